"""Data sets to evaluate on: the built-in synthetic lab, a folder of recordings, or a manifest.

A data set is a list of :class:`Item` (a recording to load, its subject and walk
type, and the ground truth where there is one).  The manifest follows the schema of
``shared/datasets/manifest.json`` (see the README).
"""

from __future__ import annotations

import dataclasses
import functools
import math
import os
import tempfile
from collections.abc import Callable
from dataclasses import dataclass
from pathlib import Path, PurePosixPath

from .. import _reading, io, synthetic
from ..errors import InputError
from ..io.recording import Recording
from ..synthetic import SyntheticTruth

__all__ = ["Item", "READABLE", "synthetic_items", "manifest_items", "folder_items", "resolve_dataset", "shipped"]

READABLE = tuple(io.READERS)


@dataclass
class Item:
    """One recording of a data set, not loaded yet."""

    name: str  # file name (or the synthetic walk's name)
    subject: str  # a column of Table I
    walk: str  # a row group of Table I
    load: Callable[[], Recording]
    truth: SyntheticTruth | None = None  # for synthetic walks
    pelvis: list | None = None  # points to average for the pelvis centre (else found by name)
    feet: list | dict | None = None  # foot points: {"left": [...], "right": [...]} or a list (sides from the names)
    up_axis: str | None = None
    synthetic: bool = False


def _recording_of(walk) -> Recording:
    # A named function rather than a lambda: items stay picklable (for worker processes).
    return walk.recording


def synthetic_item(walk) -> Item:
    """An item of one synthetic walk (SYNTHETIC data), with its truth."""
    return Item(
        name=walk.name,
        subject=walk.subject.name,
        walk=walk.walk_type,
        load=functools.partial(_recording_of, walk),
        truth=walk.truth,
        pelvis=list(synthetic.PELVIS_MARKERS),
        feet=list(synthetic.HEEL_MARKERS),
        up_axis="z",
        synthetic=True,
    )


def synthetic_items(seed: int = 0, rate_hz: float = 100.0) -> list[Item]:
    """The built-in synthetic lab: 3 virtual subjects x 5 walk types (SYNTHETIC data)."""
    items = [synthetic_item(walk) for walk in synthetic.default_lab(seed=seed, rate_hz=rate_hz)]
    return items


def manifest_items(path) -> tuple[list[Item], list[tuple[str, str]]]:
    """Items of a manifest (schema of shared/datasets/manifest.json); paths are relative to it.

    The manifest is read bounded (a regular file of at most :data:`yoyogait._reading.MANIFEST_MAX_BYTES`,
    nested at most :data:`yoyogait._reading.DEPTH_MAX` deep; else InputError).  Returns the items whose
    file exists and whose fields are usable, and (name, problem) for each entry that is not: a missing
    file, or a field of the wrong type or value, named by the entry's index, path and the field.  An
    entry that repeats an earlier one (the same file, the same settings) is evaluated once and reported
    once.  Item names are unique: the file name, the path when two files share a name, and the entry
    index when one file is listed with different settings.
    """
    path = Path(path)
    doc = _reading.read_json(path, _reading.MANIFEST_MAX_BYTES, "manifest")
    entries = doc.get("recordings") if isinstance(doc, dict) else None
    if not isinstance(entries, list):
        raise InputError(f"manifest {path} has no list 'recordings'")
    found: list[tuple[int, str, Path, dict]] = []  # (index, path as given, file, item fields)
    missing: list[tuple[str, str]] = []
    folder = str(path.parent)
    first_of: dict[tuple, int] = {}  # (file, settings) -> the entry evaluated
    repeats: dict[int, list[int]] = {}
    missing_at: dict[int, int] = {}  # entry -> its index in missing
    order: list[int] = []  # the entry of each problem
    for n, entry in enumerate(entries):
        name, problem, fields = _entry(n, entry, path, folder)
        if problem is not None:
            missing.append((name, problem))
            order.append(n)
            continue
        assert fields is not None
        file = fields.pop("file")
        # The settings in _entry's fixed order; a list or a mapping by its text, to be hashable.
        key = (
            os.path.normpath(file),
            *(v if v is None or isinstance(v, (str, float)) else repr(v) for v in fields.values()),
        )
        if key in first_of:
            repeats.setdefault(first_of[key], []).append(n)
            continue
        first_of[key] = n
        if not os.path.isfile(file):
            missing_at[n] = len(missing)
            missing.append((name, f"file not found: {_reading.clip(file, 200)}"))
            order.append(n)
            continue
        found.append((n, entry["path"], Path(file), fields))
    for n, again in repeats.items():  # one line for an entry and all its repeats
        listed = ", ".join(str(k) for k in again[:5]) + (f" and {len(again) - 5} more" if len(again) > 5 else "")
        also = f"listed again as entr{'y' if len(again) == 1 else 'ies'} {listed}"
        if n in missing_at:
            name, message = missing[missing_at[n]]
            missing[missing_at[n]] = (name, f"{message} ({also})")
        else:
            missing.append((f"entry {n} ({_reading.clip(entries[n]['path'], 120)})", f"{also}: evaluated once"))
            order.append(n)
    missing = [problem for _, problem in sorted(zip(order, missing), key=lambda pair: pair[0])]  # by entry
    names = _unique_names([(n, given, file) for n, given, file, _ in found])
    items = []
    for (_, given, file, fields), name in zip(found, names):
        overrides = {k: fields[k] for k in ("length_unit_m", "up_axis") if fields.get(k) is not None}
        items.append(
            Item(
                name=name,
                subject=PurePosixPath(given).parent.name or "recordings",
                walk=fields["walk"] or "unknown",
                load=functools.partial(io.read, file, **overrides),
                pelvis=fields["pelvis"],
                feet=fields["feet"],
                up_axis=fields["up_axis"],
            )
        )
    return items, missing


def _unique_names(files: list[tuple[int, str, Path]]) -> list[str]:
    """A name per (entry index, path as given, file): the file name, the normalised path when two
    files share a file name, the path and the entry index when the same path is listed twice."""
    by_name: dict[str, int] = {}
    by_path: dict[str, int] = {}
    rel = [os.path.normpath(given).replace(os.sep, "/") for _, given, _ in files]
    for (_, _, file), r in zip(files, rel):
        by_name[file.name] = by_name.get(file.name, 0) + 1
        by_path[r] = by_path.get(r, 0) + 1
    out = []
    for (n, _, file), r in zip(files, rel):
        if by_path[r] > 1:
            out.append(f"{r} [entry {n}]")
        elif by_name[file.name] > 1:
            out.append(r)
        else:
            out.append(file.name)
    return out


_AXES = ("x", "y", "z")


def _entry(n: int, entry, manifest: Path, folder: str) -> tuple[str, str | None, dict | None]:
    """(name, problem, fields) of manifest entry ``n``: a problem names the entry and the field."""
    if not isinstance(entry, dict):
        return f"entry {n}", f"must be an object with a 'path', not {_reading.shorten(entry)} (in {manifest})", None
    given = entry.get("path")
    if not isinstance(given, str) or not given.strip() or "\0" in given:
        return f"entry {n}", f"'path' must be a file name, not {_reading.shorten(given)} (in {manifest})", None
    name = f"entry {n} ({_reading.clip(given, 120)})"

    def bad(field: str, must: str) -> tuple[str, str, None]:
        return name, f"'{field}' must be {must}, not {_reading.shorten(entry.get(field))} (in {manifest})", None

    unit = entry.get("length_unit_m")
    if unit is not None:
        if isinstance(unit, bool) or not isinstance(unit, (int, float)) or not math.isfinite(unit) or unit <= 0:
            return bad("length_unit_m", "a positive number of metres or null")
        unit = float(unit)
    axis = entry.get("vertical_axis")
    if axis is not None and axis != "" and axis not in _AXES:
        return bad("vertical_axis", "x, y or z")
    pelvis = entry.get("pelvis")
    if pelvis is not None and not (isinstance(pelvis, str) or _names(pelvis)):
        return bad("pelvis", "a point name or a list of names")
    feet = entry.get("feet")
    if feet is not None and not (
        _names(feet) or (isinstance(feet, dict) and set(feet) <= {"left", "right"} and all(map(_names, feet.values())))
    ):
        return name, '\'feet\' must be a list of names or {"left": [...], "right": [...]}' + f" (in {manifest})", None
    walk = entry.get("walk")
    if walk is not None and not isinstance(walk, str):
        return bad("walk", "a text")
    fields = {
        "file": os.path.join(folder, given),
        "length_unit_m": unit,
        "up_axis": axis or None,
        "pelvis": pelvis,
        "feet": feet,
        "walk": walk,
    }
    return name, None, fields


def _names(value) -> bool:
    return isinstance(value, list) and bool(value) and all(isinstance(v, str) for v in value)


def folder_items(path) -> list[Item]:
    """Every readable recording (any extension of :data:`yoyogait.io.READERS`) below a folder; pelvis and feet
    found by name."""
    path = Path(path)
    files = sorted(p for p in path.rglob("*") if p.is_file() and p.suffix.lower() in READABLE)
    if not files:
        raise InputError(f"no recordings ({', '.join(READABLE)}) in folder {path}")
    names = _unique_names([(n, f.relative_to(path).as_posix(), f) for n, f in enumerate(files)])
    return [
        Item(name=name, subject=f.parent.name, walk="unknown", load=functools.partial(io.read, f))
        for f, name in zip(files, names)
    ]


def resolve_dataset(spec: str | None, seed: int = 0) -> tuple[list[Item], list[tuple[str, str]], bool]:
    """(items, problems, synthetic) for 'synthetic' (or None), a folder, or a manifest .json."""
    if spec is None or spec == "synthetic":
        return synthetic_items(seed=seed), [], True
    path = Path(spec)
    if path.is_dir():
        manifest = path / "manifest.json"
        if manifest.is_file():
            items, missing = manifest_items(manifest)
            return items, missing, False
        return folder_items(path), [], False
    if path.suffix.lower() == ".json":
        if not os.path.lexists(path):
            raise InputError(f"manifest not found: {path}")
        items, missing = manifest_items(path)
        return items, missing, False
    if not path.exists():
        raise InputError(f"data set not found: {spec} (give 'synthetic', a folder or a manifest .json)")
    raise InputError(f"not a data set: {spec} (give 'synthetic', a folder or a manifest .json)")


def read_shipped(data: bytes, name: str, **overrides) -> Recording:
    """Read a recording from the bytes of its file (``name`` gives the extension and the messages)."""
    with tempfile.TemporaryDirectory(prefix="yoyogait-") as folder:
        path = Path(folder) / Path(name).name
        path.write_bytes(data)
        return io.read(path, **overrides)


def shipped(item: Item) -> Item:
    """The item with its file's bytes inside it, for workers that do not see the file (Dask).

    Items that are not read from a file (the synthetic lab) already carry their data.
    """
    return dataclasses.replace(item, load=_ship(item.load))


def _ship(load):
    """``load`` with io.read(path) replaced by a read of the file's bytes, also inside a wrapping
    partial (such as one that checks the points after reading)."""
    if not isinstance(load, functools.partial) or not load.args:
        return load
    if load.func is io.read:
        path = Path(load.args[0])
        try:
            data = path.read_bytes()
        except OSError as exc:
            raise InputError(f"cannot read {path}: {exc.strerror or exc}") from None
        return functools.partial(read_shipped, data, str(path), **load.keywords)
    inner = _ship(load.args[0])
    if inner is load.args[0]:
        return load
    return functools.partial(load.func, inner, *load.args[1:], **load.keywords)
