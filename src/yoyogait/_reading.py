"""Reading the small files that steer a run (estimator configurations, manifests, marker sets) so that no
file can hang it, exhaust its memory or flood its error output.

A file is read only if it is a regular file (a device node like /dev/zero, a FIFO or a socket is
refused before anything is read from it, and opening never waits for a writer) and no larger than
its limit (:data:`CONFIG_MAX_BYTES`, :data:`MANIFEST_MAX_BYTES`); it is parsed only if it nests no
deeper than :data:`DEPTH_MAX` (checked before the parser runs, so the parser never recurses deeply,
and again on the parsed value).  Every problem is an :class:`InputError` naming the file, in one
line of at most :data:`LINE_MAX` characters: values in it are shortened (:func:`shorten`).
"""

from __future__ import annotations

import importlib
import json
import os
import re
import reprlib
import stat
import sys
from pathlib import Path
from typing import Any

import numpy as np

from ._files import kind_of
from .errors import InputError

tomllib = importlib.import_module("tomllib" if sys.version_info >= (3, 11) else "tomli")

__all__ = [
    "CONFIG_MAX_BYTES",
    "MANIFEST_MAX_BYTES",
    "DEPTH_MAX",
    "LINE_MAX",
    "VALUE_MAX",
    "read_bounded",
    "read_toml",
    "read_json",
    "shorten",
    "clip",
    "one_line",
    "size_text",
]

CONFIG_MAX_BYTES = 2**20
"""The largest estimator configuration read: 1 MiB (one written by yoyogait is about 2 kB)."""

MANIFEST_MAX_BYTES = 64 * 2**20
"""The largest manifest read: 64 MiB (about a million entries)."""

DEPTH_MAX = 64
"""The deepest nesting of tables and arrays (TOML) or objects and arrays (JSON) that is parsed."""

LINE_MAX = 1000
"""The longest error line about a file, in characters."""

VALUE_MAX = 80
"""The longest value quoted in an error, in characters (the rest is elided)."""


def size_text(n_bytes: int) -> str:
    """'1 MiB', '64 MiB', '512 kiB', '300 bytes'."""
    for unit, size in (("GiB", 2**30), ("MiB", 2**20), ("kiB", 2**10)):
        if n_bytes >= size and n_bytes % size == 0:
            return f"{n_bytes // size} {unit}"
    return f"{n_bytes} bytes"


_REPR = reprlib.Repr()
_REPR.maxlist = _REPR.maxdict = _REPR.maxtuple = _REPR.maxset = 10
_REPR.maxstring = _REPR.maxother = VALUE_MAX
_REPR.maxlevel = 4  # a deeply nested value is shown as [[[...]]], never walked to its bottom


def shorten(value: Any, limit: int = VALUE_MAX) -> str:
    """repr(value) on one line, elided beyond ``limit`` characters (never built whole for a long value)."""
    text = " ".join(_REPR.repr(value).split())
    if len(text) <= limit:
        return text
    return text[: limit - 3] + "..."


def clip(text: str, limit: int = VALUE_MAX) -> str:
    """``text`` (a name, a path) on one line, cut to ``limit`` characters with '...' in the middle."""
    text = " ".join(str(text).split())
    if len(text) <= limit:
        return text
    keep = limit - 3
    return text[: keep - keep // 2] + "..." + text[len(text) - keep // 2 :]


def one_line(text: str, limit: int = LINE_MAX) -> str:
    """``text`` on one line, cut at ``limit`` characters (saying how many were left out)."""
    text = " ".join(str(text).split())
    if len(text) <= limit:
        return text
    note = f"... ({len(text) - limit + 40} more characters)"
    return text[: limit - len(note)] + note


def read_bounded(path, max_bytes: int, what: str) -> bytes:
    """The bytes of ``path`` if it is a regular file of at most ``max_bytes``; InputError naming it
    otherwise (a folder, a device node, a FIFO, a socket, a larger file, one that cannot be read).
    ``what`` names the kind of file in the messages ("configuration file", "manifest")."""
    path = Path(path)
    try:
        st = os.stat(path)
    except FileNotFoundError:
        raise InputError(f"{path}: no such file") from None
    except OSError as exc:
        raise InputError(f"{path}: cannot read: {exc.strerror or exc}") from None
    _check_stat(path, st, max_bytes, what)
    try:
        # O_NONBLOCK: a FIFO swapped in after the check opens at once instead of waiting for a writer.
        fd = os.open(path, os.O_RDONLY | os.O_NONBLOCK | os.O_NOCTTY | os.O_CLOEXEC)
    except OSError as exc:
        raise InputError(f"{path}: cannot read: {exc.strerror or exc}") from None
    try:
        _check_stat(path, os.fstat(fd), max_bytes, what)  # what was opened, not what was checked
        chunks, total = [], 0
        while total <= max_bytes:
            chunk = os.read(fd, min(1 << 20, max_bytes + 1 - total))
            if not chunk:
                break
            chunks.append(chunk)
            total += len(chunk)
    except BlockingIOError:
        raise InputError(f"{path}: cannot read: it gives no data now") from None
    except OSError as exc:
        raise InputError(f"{path}: cannot read: {exc.strerror or exc}") from None
    finally:
        os.close(fd)
    if total > max_bytes:
        raise InputError(f"{path}: larger than {size_text(max_bytes)}, the limit for a {what}; not read")
    return b"".join(chunks)


def _check_stat(path: Path, st: os.stat_result, max_bytes: int, what: str) -> None:
    if stat.S_ISDIR(st.st_mode):
        raise InputError(f"{path}: is a folder, not a {what}")
    if not stat.S_ISREG(st.st_mode):
        raise InputError(f"{path}: is {kind_of(st.st_mode)}, not a regular file; a {what} is read only from one")
    if st.st_size > max_bytes:
        raise InputError(
            f"{path}: larger than {size_text(max_bytes)} ({st.st_size} bytes), the limit for a {what}; not read"
        )


def _decode(data: bytes, path: Path, what: str) -> str:
    try:
        return data.decode("utf-8")
    except UnicodeDecodeError as exc:
        raise InputError(f"{path}: not a {what} (not UTF-8 text at byte {exc.start})") from None


_JSON_STRING = re.compile(rb'"[^"\\]*(?:\\.[^"\\]*)*"', re.DOTALL)
_TOML_SKIP = re.compile(
    rb"'''.*?'''"  # multi-line literal
    rb'|"""[^\\]*?(?:\\.[^\\]*?)*?"""'  # multi-line basic
    rb"|'[^'\n]*'"  # literal
    rb'|"[^"\\\n]*(?:\\.[^"\\\n]*)*"'  # basic
    rb"|#[^\n]*",  # comment
    re.DOTALL,
)
_DOTTED = re.compile(rb"(?:[A-Za-z0-9_-]*[ \t]*\.[ \t]*){%d,}" % DEPTH_MAX)
"""A key of more than DEPTH_MAX dotted parts (strings already removed: a quoted part leaves nothing)."""
_OPEN = np.zeros(256, np.int8)
_OPEN[[ord("["), ord("{")]] = 1
_OPEN[[ord("]"), ord("}")]] = -1


def _bracket_depth(code: bytes) -> int:
    """The deepest nesting of brackets and braces in ``code`` (strings and comments removed)."""
    steps = _OPEN[np.frombuffer(code, np.uint8)]
    steps = steps[steps != 0]
    return int(np.cumsum(steps, dtype=np.int64).max()) if steps.size else 0


def _value_depth(value: Any) -> int:
    """The nesting depth of dicts and lists in a parsed value (without recursion)."""
    deepest, stack = 0, [(value, 1)]
    while stack:
        v, d = stack.pop()
        if isinstance(v, dict):
            children: Any = v.values()
        elif isinstance(v, list):
            children = v
        else:
            continue
        deepest = max(deepest, d)
        if deepest > DEPTH_MAX:
            return deepest
        stack.extend((c, d + 1) for c in children if isinstance(c, (dict, list)))
    return deepest


def _too_deep(path: Path) -> InputError:
    return InputError(f"{path}: nested deeper than {DEPTH_MAX} levels (tables, arrays, dotted keys); not read")


def read_toml(path, max_bytes: int = CONFIG_MAX_BYTES, what: str = "configuration file") -> dict:
    """The TOML document of ``path``, read bounded (:func:`read_bounded`) and depth-checked."""
    path = Path(path)
    data = read_bounded(path, max_bytes, what)
    code = _TOML_SKIP.sub(b"", data)
    if _bracket_depth(code) > DEPTH_MAX or _DOTTED.search(code):
        raise _too_deep(path)
    text = _decode(data, path, what)
    try:
        values = tomllib.loads(text)
    except tomllib.TOMLDecodeError as exc:
        raise InputError(f"{path}: not a valid TOML file: {one_line(str(exc), 200)}") from None
    except RecursionError:
        raise _too_deep(path) from None
    if _value_depth(values) > DEPTH_MAX:
        raise _too_deep(path)
    return values


def read_json(path, max_bytes: int = MANIFEST_MAX_BYTES, what: str = "manifest") -> Any:
    """The JSON document of ``path``, read bounded (:func:`read_bounded`) and depth-checked."""
    path = Path(path)
    data = read_bounded(path, max_bytes, what)
    if _bracket_depth(_JSON_STRING.sub(b"", data)) > DEPTH_MAX:
        raise _too_deep(path)
    text = _decode(data, path, what)
    try:
        return json.loads(text)
    except json.JSONDecodeError as exc:
        raise InputError(f"{path}: not valid JSON: {exc.msg} at line {exc.lineno}") from None
    except RecursionError:
        raise _too_deep(path) from None
