"""Writing outputs so that an interrupted run leaves nothing half-written."""

from __future__ import annotations

import ctypes
import errno
import os
import shutil
import tempfile
from collections.abc import Callable
from pathlib import Path

from ._guard import check_interrupted, signals_deferred


def _umask() -> int:
    mask = os.umask(0)
    os.umask(mask)
    return mask


def give_default_mode(path: Path) -> None:
    """The permissions a plainly created file or folder would have (mkstemp/mkdtemp make them private)."""
    os.chmod(path, (0o777 if path.is_dir() else 0o666) & ~_umask())


def atomic_file(path: Path, write) -> None:
    """write(tmp_path) then rename onto ``path``; the temporary file keeps the extension (for writers
    that go by it, like matplotlib) and is removed if anything fails."""
    path = Path(path)
    fd, name = tempfile.mkstemp(prefix=f".{path.stem}.tmp.", suffix=path.suffix, dir=path.resolve().parent)
    os.close(fd)
    tmp = Path(name)
    try:
        write(tmp)
        give_default_mode(tmp)
        with signals_deferred():
            check_interrupted()  # an interrupt swallowed on the way still stops the commit
            os.replace(tmp, path)
    except BaseException:
        with signals_deferred():
            tmp.unlink(missing_ok=True)
        raise


def _temp_beside(path: Path) -> Path:
    fd, name = tempfile.mkstemp(prefix=f".{path.stem}.tmp.", suffix=path.suffix, dir=path.resolve().parent)
    os.close(fd)
    return Path(name)


def atomic_files(writers: dict[Path, Callable[[Path], object]]) -> None:
    """Several outputs that appear together or not at all: each ``write(tmp_path)`` runs first
    (temporary names beside the targets, as :func:`atomic_file`), and only when all have
    succeeded are they renamed into place.  On any failure, the temporary files and every
    target already renamed by this call are removed."""
    temps: list[Path] = []
    done: list[Path] = []
    try:
        for path, write in writers.items():
            tmp = _temp_beside(Path(path))
            temps.append(tmp)
            write(tmp)
            give_default_mode(tmp)
        with signals_deferred():
            check_interrupted()
            for path, tmp in zip(writers, temps):
                os.replace(tmp, path)
                done.append(Path(path))
    except BaseException:
        with signals_deferred():
            for p in temps + done:
                p.unlink(missing_ok=True)
        raise


_RENAME_EXCHANGE = 2  # linux/fs.h
_AT_FDCWD = -100


def _exchange(a: Path, b: Path) -> bool:
    """Swap two paths in one step (Linux renameat2 RENAME_EXCHANGE); False where unsupported."""
    try:
        renameat2 = ctypes.CDLL(None, use_errno=True).renameat2
    except (OSError, AttributeError):
        return False
    rc = renameat2(_AT_FDCWD, os.fsencode(a), _AT_FDCWD, os.fsencode(b), _RENAME_EXCHANGE)
    if rc == 0:
        return True
    err = ctypes.get_errno()
    if err in (errno.ENOSYS, errno.EINVAL, errno.EOPNOTSUPP):
        return False
    raise OSError(err, os.strerror(err), str(b))


def replace_folder(new: Path, out: Path) -> None:
    """Put the finished folder ``new`` at ``out``, replacing an existing ``out`` in one step.

    Where the system can swap two paths atomically, ``out`` is never missing nor half-replaced;
    elsewhere the old one is moved aside and removed after the new one is in place.  Signals
    wait until the old folder is gone, so neither is left behind.
    """
    new, out = Path(new), Path(out)
    with signals_deferred():
        check_interrupted()
        if not out.exists():
            os.replace(new, out)
            return
        if _exchange(new, out):
            shutil.rmtree(new, ignore_errors=True)  # ``new`` now holds the old folder
            return
        old = Path(tempfile.mkdtemp(prefix=f".{out.name}.", suffix=".old", dir=out.resolve().parent))
        os.replace(out, old / out.name)
        os.replace(new, out)
        shutil.rmtree(old, ignore_errors=True)
