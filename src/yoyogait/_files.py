"""Writing outputs so that an interrupted run leaves nothing half-written, and --force touches only
what yoyogait wrote.

Output files.  An output path must be a new name, a regular file (replaced only with --force) or a
symbolic link (replaced only with --force, and then the link itself, never its target).  A device
node, a FIFO, a socket or a folder is refused with or without --force (:func:`check_output_file`),
and so is a path that names one of the command's inputs, or another output of the same command
(:func:`check_distinct`).  The temporary file is made beside the name given (never in a link's
target folder), under a new name (``O_EXCL``, so never through a link), and the target is checked
again just before the rename: a new name is linked into place without replacing anything that
appeared meanwhile.

Report folders.  A folder yoyogait writes (a report) holds a marker file, :data:`MARKER`, listing
every file it wrote there with the SHA-256 of what it wrote, in the format of ``sha256sum``
(``<64 hex digits>  <relative path>`` a line), so ``sha256sum -c .yoyogait-report`` checks it.
Replacing the folder replaces and removes only listed files that are still what yoyogait wrote:
regular files inside the folder, reached without following a symbolic link, whose content has the
listed hash.  Anything else is the user's and stays, even when the list names it (a forged or stale
list); a file of the user's at a name the new report needs, or a link or special file on the way
to it, stops the install before anything is changed.  Every path inside the folder is opened
relative to a descriptor of its parent with ``O_NOFOLLOW``, so no link inside the folder is ever
followed on write.  A folder that exists without the marker is not yoyogait's: it is filled only
when empty, and otherwise refused, with or without --force.  A list without hashes (written by an
older yoyogait) names files that are never replaced or removed.

Limits: the checks cannot make a rename atomic with the check before it; a file swapped in between
the check and the rename (a window of microseconds, by someone who can write the folder) can still
be replaced.  A list forged with the correct hash of a user's file is indistinguishable from
yoyogait's own.
"""

from __future__ import annotations

import contextlib
import errno
import hashlib
import os
import re
import shutil
import stat
import tempfile
from collections.abc import Callable, Iterable, Iterator
from pathlib import Path

from ._guard import check_interrupted, signals_deferred
from .errors import OutputError

MARKER = ".yoyogait-report"
"""The file, in a folder yoyogait wrote, that lists what yoyogait wrote there (sha256sum format)."""

MARKER_MAX_BYTES = 256 * 2**20
"""The largest list of a report's files that is read (256 MiB: about two million files)."""

_LINE = re.compile(r"^([0-9a-f]{64})  (.+)$")
_DIR_FLAGS = os.O_RDONLY | os.O_DIRECTORY | os.O_CLOEXEC
_NOFOLLOW_DIR = _DIR_FLAGS | os.O_NOFOLLOW
_READ_FLAGS = os.O_RDONLY | os.O_NOFOLLOW | os.O_NONBLOCK | os.O_NOCTTY | os.O_CLOEXEC


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


def kind_of(mode: int) -> str:
    """'a regular file', 'a folder', 'a symbolic link', 'a character device', 'a FIFO', ... for a st_mode."""
    for test, name in (
        (stat.S_ISREG, "a regular file"),
        (stat.S_ISDIR, "a folder"),
        (stat.S_ISLNK, "a symbolic link"),
        (stat.S_ISCHR, "a character device"),
        (stat.S_ISBLK, "a block device"),
        (stat.S_ISFIFO, "a FIFO"),
        (stat.S_ISSOCK, "a socket"),
    ):
        if test(mode):
            return name
    return "a special file"


def _lstat(path) -> os.stat_result | None:
    try:
        return os.lstat(path)
    except FileNotFoundError:
        return None


# ------------------------------------------------------------------------------------------ output files


def _key(path) -> tuple[str, str]:
    """The file a path names, its last component not followed: (real parent folder, name)."""
    p = Path(path).absolute()
    return os.path.realpath(p.parent), p.name


def same_file(a, b) -> bool:
    """Whether writing path ``a`` (its last link not followed) would replace the file ``b`` reads."""
    if _key(a) == _key(b):
        return True
    st_a = _lstat(a)
    try:
        st_b = os.stat(b)
    except OSError:
        return False
    return st_a is not None and not stat.S_ISLNK(st_a.st_mode) and os.path.samestat(st_a, st_b)


def check_output_file(path, option: str = "--out", force: bool = False, inputs: Iterable = ()) -> None:
    """OutputError unless ``path`` may be written: a new name, or with ``force`` a regular file or a
    symbolic link (the link is replaced, never its target).  A folder, a device node, a FIFO or a
    socket is refused even with ``force``, and so is a path naming one of ``inputs``."""
    path = Path(path)
    for source in inputs:
        if source is not None and same_file(path, source):
            raise OutputError(f"{option} {path}: is the input {source}; give another name (refused even with --force)")
    try:
        st = _lstat(path)
    except OSError as exc:
        raise OutputError(f"{option} {path}: cannot use it: {why(exc)}") from None
    if st is None:
        return
    if stat.S_ISLNK(st.st_mode):
        if not force:
            raise OutputError(
                f"{option} {path}: exists (a symbolic link); use --force to replace the link (its target stays)"
            )
        return
    if stat.S_ISDIR(st.st_mode):
        raise OutputError(f"{option} {path}: is a folder; give a file name")
    if not stat.S_ISREG(st.st_mode):
        raise OutputError(
            f"{option} {path}: is {kind_of(st.st_mode)}, not a regular file; yoyogait writes only regular files "
            "(refused even with --force)"
        )
    if not force:
        raise OutputError(f"{option} {path}: exists; use --force to overwrite it")


def check_distinct(outputs: Iterable[tuple[str, str | os.PathLike | None]]) -> None:
    """OutputError when two outputs of one command, (option, path) pairs, name the same file."""
    seen: list[tuple[str, Path]] = []
    for option, path in outputs:
        if path is None:
            continue
        for other_option, other in seen:
            if same_file(path, other) or same_file(other, path):
                raise OutputError(f"{other_option} {other} and {option} {path} are the same file; give two names")
        seen.append((option, Path(path)))


def check_outputs(
    outputs: Iterable[tuple[str, str | os.PathLike | None]], force: bool = False, inputs: Iterable = ()
) -> None:
    """The checks of a command's output files, (option, path) pairs (None: not written): no two the
    same (:func:`check_distinct`), each one writable (:func:`check_output_file`)."""
    outputs = tuple(outputs)
    inputs = tuple(inputs)
    check_distinct(outputs)
    for option, path in outputs:
        if path is not None:
            check_output_file(path, option, force, inputs)


def temporary_beside(path: Path) -> tuple[int, Path]:
    """A new private file beside ``path`` (in the folder the name is in, never a link's target folder),
    keeping its extension: (descriptor, name)."""
    path = Path(path).absolute()
    fd, name = tempfile.mkstemp(prefix=f".{path.stem}.tmp.", suffix=path.suffix, dir=path.parent)
    return fd, Path(name)


def commit(tmp: Path, path: Path, absent: bool) -> None:
    """Move the finished ``tmp`` to ``path``.  ``absent``: ``path`` did not exist when the run checked it;
    then it is linked into place, never replacing what appeared meanwhile.  Otherwise it is checked
    again (a regular file or a symbolic link) and replaced by a rename (a link itself is replaced)."""
    path = Path(path)
    if absent:
        try:
            os.link(tmp, path, follow_symlinks=False)
        except FileExistsError:
            raise OutputError(f"cannot write {path}: it appeared while yoyogait was writing; left as it is") from None
        except OSError as exc:
            if exc.errno not in (errno.EPERM, errno.EOPNOTSUPP, errno.ENOTSUP, errno.EXDEV, errno.EMLINK):
                raise
        else:
            tmp.unlink()
            return
    st = _lstat(path)
    if st is not None and not (stat.S_ISREG(st.st_mode) or stat.S_ISLNK(st.st_mode)):
        raise OutputError(f"cannot write {path}: is {kind_of(st.st_mode)}, not a regular file; left as it is")
    if st is not None and absent:
        raise OutputError(f"cannot write {path}: it appeared while yoyogait was writing; left as it is")
    os.replace(tmp, path)


def _refuse_special(path: Path) -> bool:
    """OutputError if ``path`` is something no writer may replace; whether it is absent."""
    st = _lstat(path)
    if st is not None and not (stat.S_ISREG(st.st_mode) or stat.S_ISLNK(st.st_mode)):
        raise OutputError(
            f"cannot write {path}: is {kind_of(st.st_mode)}, not a regular file; yoyogait writes only regular files"
        )
    return st is None


def atomic_file(path: Path, write) -> None:
    """write(tmp_path) then rename onto ``path``; the temporary file keeps the extension (for writers
    that go by it, like matplotlib) and is removed if anything fails.  A failure is an
    :class:`OutputError` naming ``path`` and the reason (never the temporary name).  ``path`` must
    be new, a regular file or a symbolic link (replaced itself; see :func:`check_output_file`)."""
    atomic_files({Path(path): write})


def atomic_files(writers: dict[Path, Callable[[Path], object]]) -> None:
    """Several outputs that appear together or not at all: each ``write(tmp_path)`` runs first
    (temporary names beside the targets, as :func:`atomic_file`), and only when all have
    succeeded are they moved into place (:func:`commit`).  On any failure, the temporary files and
    every target already moved by this call are removed; an ordinary failure is an
    :class:`OutputError` naming the output."""
    temps: list[Path] = []
    done: list[Path] = []
    current = None
    try:
        check_distinct(("output", p) for p in writers)
        absent = {Path(p): _refuse_special(Path(p)) for p in writers}
        for path, write in writers.items():
            current = Path(path)
            fd, name = temporary_beside(current)
            os.close(fd)
            temps.append(name)
            write(name)
            give_default_mode(name)
        with signals_deferred():
            check_interrupted()
            for path, tmp in zip(writers, temps):
                current = Path(path)
                commit(tmp, current, absent[current])
                done.append(current)
    except BaseException as exc:
        with signals_deferred():
            for p in temps + done:
                p.unlink(missing_ok=True)
        if isinstance(exc, Exception) and not isinstance(exc, OutputError):
            raise OutputError(f"cannot write {current}: {why(exc, *temps)}") from None
        raise


# ------------------------------------------------------------------------------------------ report folders


def _valid_name(name: str) -> bool:
    """A relative path that stays inside its folder: no absolute path, no '..', '.', empty part or NUL."""
    if not name or "\0" in name or name.startswith("/") or "\n" in name:
        return False
    return all(part not in ("", ".", "..") for part in name.split("/"))


def _read_marker_fd(folder_fd: int, where: str) -> dict[str, set[str | None]] | None:
    """name -> the hashes the list gives it (None for a line without one); None if there is no marker.
    OutputError if the marker is not a regular file (a link, a FIFO, ...) or is too large."""
    try:
        fd = os.open(MARKER, _READ_FLAGS, dir_fd=folder_fd)
    except FileNotFoundError:
        return None
    except OSError as exc:
        if exc.errno == errno.ELOOP:
            raise OutputError(
                f"{where}/{MARKER}: is a symbolic link, not a regular file; this is not a report yoyogait can replace"
            ) from None
        raise OutputError(f"{where}/{MARKER}: cannot read: {why(exc)}") from None
    try:
        st = os.fstat(fd)
        if not stat.S_ISREG(st.st_mode):
            raise OutputError(
                f"{where}/{MARKER}: is {kind_of(st.st_mode)}, not a regular file; "
                "this is not a report yoyogait can replace"
            )
        if st.st_size > MARKER_MAX_BYTES:
            raise OutputError(f"{where}/{MARKER}: larger than {MARKER_MAX_BYTES >> 20} MiB; not read")
        with os.fdopen(os.dup(fd), "rb") as fh:
            data = fh.read(MARKER_MAX_BYTES + 1)
    finally:
        os.close(fd)
    listed: dict[str, set[str | None]] = {}
    for line in data.decode("utf-8", errors="replace").splitlines():
        m = _LINE.match(line)
        name, digest = (m[2], m[1]) if m else (line.strip(), None)
        if _valid_name(name):
            listed.setdefault(name, set()).add(digest)
    return listed


def read_marker(folder) -> dict[str, set[str | None]] | None:
    """The files ``folder``'s marker lists, each with the hashes it gives (None: a line without one);
    None if the folder has no marker.  OutputError if the marker is a link or not a regular file."""
    try:
        fd = os.open(folder, _DIR_FLAGS)
    except OSError as exc:
        raise OutputError(f"{folder}: cannot open the folder: {why(exc)}") from None
    try:
        return _read_marker_fd(fd, str(folder))
    finally:
        os.close(fd)


def written_files(folder: Path) -> list[str] | None:
    """The files yoyogait lists in ``folder``'s marker (relative paths, sorted), None if it has no marker."""
    listed = read_marker(folder)
    return None if listed is None else sorted(listed)


def check_output_folder(out: Path, force: bool, option: str = "--out", expected: Iterable[str] = ()) -> None:
    """OutputError unless ``out`` may be written: absent, an empty folder, or (with ``force``) a folder
    yoyogait wrote (it has the marker).  ``out`` may be a symbolic link to a folder (that folder is
    written); a link to nothing, or anything but a folder, is refused.  ``expected``: names the new
    report will write (a name ending in '/' is a folder), checked now as :func:`install_folder`
    will check them, so that a conflict is known before the work is done."""
    out = Path(out)
    st = _lstat(out)
    if st is None:
        return
    if stat.S_ISLNK(st.st_mode):
        try:
            st = os.stat(out)
        except OSError:
            raise OutputError(f"{option} {out}: a symbolic link to nothing; give a folder") from None
    if not stat.S_ISDIR(st.st_mode):
        raise OutputError(f"{option} {out}: exists and is {kind_of(st.st_mode)}, not a folder")
    with os.scandir(out) as entries:
        if next(entries, None) is None:
            return
    try:
        listed = read_marker(out)
    except OutputError as exc:
        raise OutputError(f"{option} {exc}") from None
    if listed is None:
        raise OutputError(
            f"{option} {out}: the folder holds files yoyogait did not write (no {MARKER}); give a new or empty folder"
        )
    if not force:
        raise OutputError(f"{option} {out}: a report exists there; use --force to replace it")
    fd = os.open(out, _DIR_FLAGS)
    try:
        for name in expected:
            try:
                if name.endswith("/"):
                    with _parent_fd(fd, name + "x", create=False):
                        pass
                else:
                    _check_target(fd, name, listed)
            except _Conflict as exc:
                raise OutputError(
                    f"{option} {out}: {exc}; yoyogait replaces only the files it wrote, unchanged: "
                    "move it away or give a new folder"
                ) from None
    finally:
        os.close(fd)


def write_folder(out, write, *, force: bool, option: str = "--out", expected: Iterable[str] = ()) -> Path:
    """A folder of outputs written whole or not at all: checked (:func:`check_output_folder`), filled
    by ``write(tmp)`` in a temporary folder beside it, then installed (:func:`install_folder`); the
    temporary folder is removed whatever happens. Returns ``out``."""
    out = Path(out)
    check_output_folder(out, force, option, expected)
    parent = out.resolve().parent
    try:
        parent.mkdir(parents=True, exist_ok=True)
        tmp = Path(tempfile.mkdtemp(prefix=f".{out.name}.", suffix=".tmp", dir=parent))
    except OSError as exc:
        raise OutputError(f"cannot write the report {out}: {why(exc)}") from None
    try:
        write(tmp)
        install_folder(tmp, out, option)
    except OutputError:
        raise
    except OSError as exc:
        raise OutputError(f"cannot write the report {out}: {why(exc, tmp)}") from None
    finally:
        with signals_deferred():  # a second signal does not cut the clean-up short
            shutil.rmtree(tmp, ignore_errors=True)
    return out


def install_folder(tmp: Path, out: Path, option: str = "--out") -> None:
    """Move the finished folder ``tmp`` to ``out``, replacing only what yoyogait wrote there.

    ``out`` absent: one rename.  ``out`` existing (checked by :func:`check_output_folder`): first every
    name the new report needs is checked (absent, or a file yoyogait wrote there, unchanged; no link
    or special file on the way), and any conflict is an OutputError before anything changes; then
    each new file is renamed into place, files of the old report that the new one lacks (and that
    are still what yoyogait wrote) are removed, and the marker is written last.  Throughout, the
    marker lists every file of yoyogait in ``out`` with its hash, so an interruption never leaves one
    unlisted; SIGINT and SIGTERM wait until the install is done (and a run interrupted before it
    never starts it).
    """
    with signals_deferred():  # SIGINT/SIGTERM cannot cut the install in half
        check_interrupted()
        _install_folder(Path(tmp), Path(out), option)


def _sha256_fd(fd: int) -> str:
    h = hashlib.sha256()
    while chunk := os.read(fd, 1 << 20):
        h.update(chunk)
    return h.hexdigest()


def _new_files(tmp: Path) -> dict[str, str]:
    """Every file of the finished folder ``tmp`` (yoyogait's own), by relative path, with its sha256."""
    out: dict[str, str] = {}
    for folder, dirs, files in os.walk(tmp):
        dirs.sort()
        for name in sorted(files):
            p = Path(folder) / name
            rel = p.relative_to(tmp).as_posix()
            if rel == MARKER:
                continue
            if not _valid_name(rel):
                raise OutputError(f"cannot write {rel!r}: not a name a report can list")
            fd = os.open(p, _READ_FLAGS)
            try:
                out[rel] = _sha256_fd(fd)
            finally:
                os.close(fd)
    return out


def _marker_text(entries: Iterable[tuple[str, str]]) -> str:
    return "".join(f"{digest}  {name}\n" for name, digest in sorted(set(entries)))


class _Conflict(Exception):
    """A path inside a report folder that is not yoyogait's to replace."""


@contextlib.contextmanager
def _parent_fd(root_fd: int, name: str, create: bool) -> Iterator[int | None]:
    """A descriptor of the folder holding ``name`` (relative to ``root_fd``), every part opened without
    following a link; None if a part is missing (and not ``create``).  _Conflict on a link or a file."""
    parts = name.split("/")[:-1]
    fds: list[int] = []
    try:
        current = root_fd
        for k, part in enumerate(parts):
            try:
                current = os.open(part, _NOFOLLOW_DIR, dir_fd=current)
            except FileNotFoundError:
                if not create:
                    yield None
                    return
                os.mkdir(part, 0o777 & ~_umask(), dir_fd=current)
                current = os.open(part, _NOFOLLOW_DIR, dir_fd=current)
            except OSError as exc:
                if exc.errno in (errno.ELOOP, errno.ENOTDIR):
                    st = os.stat(part, dir_fd=current, follow_symlinks=False)
                    raise _Conflict(f"{'/'.join(parts[: k + 1])} is {kind_of(st.st_mode)}, not a folder") from None
                raise
            fds.append(current)
        yield current
    finally:
        for fd in fds:
            os.close(fd)


def _ours(dir_fd: int, base: str, digests: set[str | None]) -> tuple[os.stat_result, str] | None:
    """(lstat, sha256) of ``base`` in ``dir_fd`` if it is a regular file whose sha256 is one of ``digests``."""
    try:
        fd = os.open(base, _READ_FLAGS, dir_fd=dir_fd)
    except OSError:
        return None
    try:
        st = os.fstat(fd)
        if not stat.S_ISREG(st.st_mode):
            return None
        digest = _sha256_fd(fd)
        return (st, digest) if digest in digests else None
    finally:
        os.close(fd)


def _still(dir_fd: int, base: str, st: os.stat_result | None) -> bool:
    """Whether ``base`` is still what was checked (``st``; None: absent)."""
    try:
        now = os.stat(base, dir_fd=dir_fd, follow_symlinks=False)
    except FileNotFoundError:
        return st is None
    return st is not None and os.path.samestat(now, st) and now.st_mtime_ns == st.st_mtime_ns


def _check_target(root_fd: int, name: str, old: dict[str, set[str | None]]) -> os.stat_result | None:
    """The lstat of what ``name`` replaces (None: nothing); _Conflict if it is not yoyogait's."""
    with _parent_fd(root_fd, name, create=False) as fd:
        if fd is None:
            return None
        base = name.rsplit("/", 1)[-1]
        try:
            st = os.stat(base, dir_fd=fd, follow_symlinks=False)
        except FileNotFoundError:
            return None
        if not stat.S_ISREG(st.st_mode):
            raise _Conflict(f"{name} is {kind_of(st.st_mode)}")
        ours = _ours(fd, base, old.get(name, set()) - {None})
        if ours is None:
            raise _Conflict(f"{name} is not (or no longer) the file yoyogait wrote there")
        return ours[0]


def _write_marker(root_fd: int, text: str) -> None:
    """The marker replaced in one rename (never written through a link)."""
    for _ in range(100):
        tmp_name = f".{MARKER}.tmp.{os.getpid()}.{os.urandom(4).hex()}"
        try:
            fd = os.open(
                tmp_name, os.O_WRONLY | os.O_CREAT | os.O_EXCL | os.O_NOFOLLOW | os.O_CLOEXEC, 0o600, dir_fd=root_fd
            )
            break
        except FileExistsError:
            continue
    else:  # pragma: no cover
        raise OutputError(f"cannot write {MARKER}: no free temporary name")
    try:
        with os.fdopen(fd, "w", encoding="utf-8") as fh:
            fh.write(text)
            os.fchmod(fh.fileno(), 0o666 & ~_umask())
        os.replace(tmp_name, MARKER, src_dir_fd=root_fd, dst_dir_fd=root_fd)
    except BaseException:
        with contextlib.suppress(OSError):
            os.unlink(tmp_name, dir_fd=root_fd)
        raise


def _install_folder(tmp: Path, out: Path, option: str) -> None:
    new = _new_files(tmp)
    for item in (tmp, *tmp.rglob("*")):
        give_default_mode(item)
    if _lstat(out) is None:
        (tmp / MARKER).write_text(_marker_text((n, d) for n, d in new.items()), encoding="utf-8")
        give_default_mode(tmp / MARKER)
        os.replace(tmp, out)
        return
    root_fd = os.open(out, _DIR_FLAGS)
    try:
        old = _read_marker_fd(root_fd, str(out)) or {}
        # 1. Nothing changes unless every name the new report needs is free or yoyogait's own.
        replaced: dict[str, os.stat_result | None] = {}
        conflicts: list[str] = []
        for name in new:
            try:
                replaced[name] = _check_target(root_fd, name, old)
            except _Conflict as exc:
                conflicts.append(str(exc))
        if conflicts:
            more = f" (and {len(conflicts) - 1} more)" if len(conflicts) > 1 else ""
            raise OutputError(
                f"{option} {out}: {conflicts[0]}{more}; yoyogait replaces only the files it wrote, unchanged: "
                "move them away or give a new folder"
            )
        # Old files the new report lacks, removed only if still yoyogait's.
        stale: dict[str, tuple[str, os.stat_result]] = {}
        for name, digests in old.items():
            if name in new:
                continue
            try:
                with _parent_fd(root_fd, name, create=False) as fd:
                    ours = _ours(fd, name.rsplit("/", 1)[-1], digests - {None}) if fd is not None else None
            except _Conflict:
                ours = None
            if ours is not None:
                stale[name] = (ours[1], ours[0])
        # 2. The marker lists the old files (their old hashes) and the new ones, then the files move.
        kept = [(n, d) for n in replaced if replaced[n] is not None for d in old[n] if d is not None]
        during = [*new.items(), *kept, *((n, d) for n, (d, _) in stale.items())]
        _write_marker(root_fd, _marker_text(during))
        for name in new:
            base = name.rsplit("/", 1)[-1]
            with _parent_fd(root_fd, name, create=True) as fd:
                assert fd is not None
                if not _still(fd, base, replaced[name]):
                    raise OutputError(f"{option} {out}: {name} changed while the report was written; left as it is")
                src = os.open(str((tmp / name).parent), _NOFOLLOW_DIR)
                try:
                    os.replace(base, base, src_dir_fd=src, dst_dir_fd=fd)
                finally:
                    os.close(src)
        for name, (_, st) in stale.items():
            with _parent_fd(root_fd, name, create=False) as fd:
                base = name.rsplit("/", 1)[-1]
                if fd is not None and _still(fd, base, st):
                    os.unlink(base, dir_fd=fd)
        for folder in sorted({n.rsplit("/", 1)[0] for n in stale if "/" in n}, key=len, reverse=True):
            parts = folder.split("/")
            for k in range(len(parts), 0, -1):  # only folders that became empty, innermost first
                sub = "/".join(parts[:k])
                with contextlib.suppress(OSError, _Conflict), _parent_fd(root_fd, sub, create=False) as fd:
                    if fd is not None:
                        os.rmdir(parts[k - 1], dir_fd=fd)
        _write_marker(root_fd, _marker_text(new.items()))
    finally:
        os.close(root_fd)
