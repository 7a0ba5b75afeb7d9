"""Writing outputs so that an interrupted run leaves nothing half-written."""

from __future__ import annotations

import os
import tempfile
from pathlib import Path


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
        os.replace(tmp, path)
    except BaseException:
        tmp.unlink(missing_ok=True)
        raise
