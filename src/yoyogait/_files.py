"""Writing outputs so that an interrupted run leaves nothing half-written, and --force touches only
what yoyogait wrote.

A folder yoyogait writes (a report) holds a marker file, :data:`MARKER`, listing every file it
wrote there, one relative path a line.  Replacing the folder replaces and removes only those
files; anything else in it is the user's and stays.  A folder that exists without the marker is
not yoyogait's: it is filled only when empty, and otherwise refused, with or without --force.
"""

from __future__ import annotations

import os
import tempfile
from collections.abc import Callable
from pathlib import Path

from ._guard import check_interrupted, signals_deferred
from .errors import OutputError

MARKER = ".yoyogait-report"
"""The file, in a folder yoyogait wrote, that lists what yoyogait wrote there."""


def _umask() -> int:
    mask = os.umask(0)
    os.umask(mask)
    return mask


def give_default_mode(path: Path) -> None:
    """The permissions a plainly created file or folder would have (mkstemp/mkdtemp make them private)."""
    os.chmod(path, (0o777 if path.is_dir() else 0o666) & ~_umask())


def why(exc: BaseException, *hide: Path) -> str:
    """The reason of a failed write in a few words, without the temporary names in ``hide``."""
    text = exc.strerror if isinstance(exc, OSError) and exc.strerror else str(exc) or type(exc).__name__
    for p in hide:
        text = text.replace(str(p), "").replace(p.name, "")
    return text


def atomic_file(path: Path, write) -> None:
    """write(tmp_path) then rename onto ``path``; the temporary file keeps the extension (for writers
    that go by it, like matplotlib) and is removed if anything fails.  A failure is an
    :class:`OutputError` naming ``path`` and the reason (never the temporary name)."""
    path = Path(path)
    try:
        fd, name = tempfile.mkstemp(prefix=f".{path.stem}.tmp.", suffix=path.suffix, dir=path.resolve().parent)
    except OSError as exc:
        raise OutputError(f"cannot write {path}: {why(exc)}") from None
    os.close(fd)
    tmp = Path(name)
    try:
        write(tmp)
        give_default_mode(tmp)
        with signals_deferred():
            check_interrupted()  # an interrupt swallowed on the way still stops the commit
            os.replace(tmp, path)
    except Exception as exc:
        with signals_deferred():
            tmp.unlink(missing_ok=True)
        raise OutputError(f"cannot write {path}: {why(exc, tmp)}") from None
    except BaseException:
        with signals_deferred():
            tmp.unlink(missing_ok=True)
        raise


def atomic_files(writers: dict[Path, Callable[[Path], object]]) -> None:
    """Several outputs that appear together or not at all: each ``write(tmp_path)`` runs first
    (temporary names beside the targets, as :func:`atomic_file`), and only when all have
    succeeded are they renamed into place.  On any failure, the temporary files and every
    target already renamed by this call are removed; an ordinary failure is an
    :class:`OutputError` naming the output."""
    temps: list[Path] = []
    done: list[Path] = []
    current = None
    try:
        for path, write in writers.items():
            current = Path(path)
            fd, name = tempfile.mkstemp(
                prefix=f".{current.stem}.tmp.", suffix=current.suffix, dir=current.resolve().parent
            )
            os.close(fd)
            temps.append(Path(name))
            write(temps[-1])
            give_default_mode(temps[-1])
        with signals_deferred():
            check_interrupted()
            for path, tmp in zip(writers, temps):
                current = Path(path)
                os.replace(tmp, path)
                done.append(current)
    except BaseException as exc:
        with signals_deferred():
            for p in temps + done:
                p.unlink(missing_ok=True)
        if isinstance(exc, Exception) and not isinstance(exc, OutputError):
            raise OutputError(f"cannot write {current}: {why(exc, *temps)}") from None
        raise


def written_files(folder: Path) -> list[str] | None:
    """The files yoyogait lists in ``folder``'s marker (relative paths), None if it has no marker."""
    marker = Path(folder) / MARKER
    if not marker.is_file():
        return None
    return [line for line in marker.read_text().splitlines() if line.strip()]


def check_output_folder(out: Path, force: bool, option: str = "--out") -> None:
    """OutputError unless ``out`` may be written: absent, an empty folder, or (with ``force``) a folder
    yoyogait wrote (it has the marker)."""
    out = Path(out)
    if not out.exists():
        return
    if not out.is_dir():
        raise OutputError(f"{option} {out}: exists and is not a folder")
    if not any(out.iterdir()):
        return
    if written_files(out) is None:
        raise OutputError(
            f"{option} {out}: the folder holds files yoyogait did not write (no {MARKER}); give a new or empty folder"
        )
    if not force:
        raise OutputError(f"{option} {out}: a report exists there; use --force to replace it")


def _listed(root: Path, names) -> list[str]:
    """Only names that stay inside ``root`` (a marker is a file anyone could edit)."""
    root = root.resolve()
    out = []
    for name in names:
        p = (root / name).resolve()
        if p != root and root in p.parents:
            out.append(name)
    return out


def install_folder(tmp: Path, out: Path) -> None:
    """Move the finished folder ``tmp`` to ``out``, replacing only what yoyogait wrote there.

    ``out`` absent: one rename.  ``out`` existing (checked by :func:`check_output_folder`): each
    new file is renamed into place, then files of the old report that the new one lacks are
    removed, and the marker is written last.  Throughout, the marker lists every file of yoyogait
    in ``out``, so an interruption never leaves one unlisted; SIGINT and SIGTERM wait until the
    install is done (and a run interrupted before it never starts it).
    """
    with signals_deferred():  # SIGINT/SIGTERM cannot cut the install in half
        check_interrupted()
        _install_folder(Path(tmp), Path(out))


def _install_folder(tmp: Path, out: Path) -> None:
    new = sorted(str(p.relative_to(tmp)) for p in tmp.rglob("*") if p.is_file() and p.name != MARKER)
    for item in (tmp, *tmp.rglob("*")):
        give_default_mode(item)
    if not out.exists():
        (tmp / MARKER).write_text("".join(f"{n}\n" for n in new))
        give_default_mode(tmp / MARKER)
        os.replace(tmp, out)
        return
    old = _listed(out, written_files(out) or [])
    marker = out / MARKER
    marker.write_text("".join(f"{n}\n" for n in sorted(set(old) | set(new))))
    for name in new:
        target = out / name
        target.parent.mkdir(parents=True, exist_ok=True)
        if target.is_dir():
            raise OutputError(f"cannot write {target}: a folder is in the way")
        os.replace(tmp / name, target)
    for name in sorted(set(old) - set(new)):
        (out / name).unlink(missing_ok=True)
    for name in sorted({str(Path(n).parent) for n in old} - {"."}, key=len, reverse=True):
        try:
            (out / name).rmdir()  # only folders that became empty
        except OSError:
            pass
    marker.write_text("".join(f"{n}\n" for n in new))
    give_default_mode(marker)
