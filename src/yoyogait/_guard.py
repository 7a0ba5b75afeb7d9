"""What keeps a run's outputs safe: interrupts that always stop it, and a lock on its output folder.

Interrupts.  Python raises KeyboardInterrupt wherever the main thread happens to be when SIGINT
arrives; when that is a finaliser or a weakref callback (tqdm's ``WeakSet._remove``, say),
Python prints "Exception ignored in ..." and the run goes on as if nothing happened.
:func:`handle_interrupts` installs handlers for SIGINT and SIGTERM that raise
:class:`Interrupted` (a KeyboardInterrupt) *and* remember the signal, and every commit point
(:func:`check_interrupted`, called before an output is renamed into place) raises again if one was
swallowed (and Python's "Exception ignored" report of it is not shown).  So an interrupted run
never commits an output, and the CLI exits with 128 + the signal number (130, 143) whatever
happened in between.  :func:`signals_deferred` holds the
signals back while a commit or a clean-up must not be cut in half.

Lock.  :func:`output_lock` takes an exclusive ``flock`` on ``.<name>.lock`` beside an output
folder, without waiting: a second run on the same output fails at once.  The kernel releases the
lock when its process dies, however it dies, so a stale lock file never blocks anyone.
"""

from __future__ import annotations

import contextlib
import errno
import fcntl
import os
import signal
import stat
import sys
import threading
from collections.abc import Iterator
from pathlib import Path

from .errors import InputError

__all__ = [
    "Interrupted",
    "handle_interrupts",
    "check_interrupted",
    "interrupted_by",
    "signals_deferred",
    "output_lock",
]

SIGNALS = (signal.SIGINT, signal.SIGTERM)

_received: int | None = None  # the first interrupting signal of this run
_owner = 0  # the process that installed the handlers (forked workers inherit them)
_deferring = 0  # depth of signals_deferred blocks
_pending = False  # a signal arrived inside one: raise when the outermost ends


class Interrupted(KeyboardInterrupt):
    """The run was stopped by a signal (``signum``: SIGINT or SIGTERM)."""

    def __init__(self, signum: int = signal.SIGINT):
        super().__init__(signal.Signals(signum).name)
        self.signum = int(signum)


def _handler(signum, frame) -> None:
    global _received, _pending
    if os.getpid() != _owner:
        # A forked worker process: its parent handles the run; it ends as by default (a pool
        # terminates its workers with SIGTERM, which must not become an exception in them).
        signal.signal(signum, signal.SIG_DFL)
        os.kill(os.getpid(), signum)
        return
    if _received is None:
        _received = int(signum)
    if _deferring:
        _pending = True
        return
    raise Interrupted(signum)


def interrupted_by() -> int | None:
    """The signal that interrupted this run, or None."""
    return _received


def check_interrupted() -> None:
    """Raise :class:`Interrupted` if a signal arrived, even one whose exception was swallowed."""
    if _received is not None:
        raise Interrupted(_received)


@contextlib.contextmanager
def handle_interrupts() -> Iterator[None]:
    """SIGINT and SIGTERM raise :class:`Interrupted` and are remembered, for the block's duration
    (read :func:`interrupted_by` inside the block).

    Does nothing outside the main thread (where Python allows no signal handler); the previous
    handlers come back afterwards.
    """
    global _received, _pending, _owner
    if threading.current_thread() is not threading.main_thread():
        yield
        return
    _received, _pending, _owner = None, False, os.getpid()
    previous = {s: signal.getsignal(s) for s in SIGNALS}
    previous_hook = sys.unraisablehook

    def unraisable(args) -> None:
        # An Interrupted raised in a finaliser is ignored by Python, which would print its traceback:
        # it is remembered, and the next commit point stops the run, so there is nothing to show.
        if not isinstance(args.exc_value, Interrupted):
            previous_hook(args)

    sys.unraisablehook = unraisable
    for s in SIGNALS:
        signal.signal(s, _handler)
    try:
        yield
    finally:
        for s, h in previous.items():
            signal.signal(s, h if h is not None else signal.SIG_DFL)
        sys.unraisablehook = previous_hook
        _received, _pending = None, False  # library calls after the run owe nothing to its interrupt


@contextlib.contextmanager
def signals_deferred() -> Iterator[None]:
    """SIGINT and SIGTERM wait until the block ends (a commit or a clean-up is never cut in half).

    The handler only notes a signal that arrives meanwhile, and :class:`Interrupted` is raised when
    the outermost such block ends (unless the block is already ending with an exception; the
    signal is remembered either way, so the next commit point stops the run).  A flag rather than
    a signal mask, because Python runs the handler in the main thread even when another thread
    (tqdm's monitor, say) took the signal.
    """
    global _deferring, _pending
    _deferring += 1
    raise_now = False
    try:
        yield
    finally:
        _deferring -= 1
        if _deferring == 0 and _pending:
            _pending = False
            raise_now = True
    if raise_now:
        raise Interrupted(_received if _received is not None else signal.SIGINT)


@contextlib.contextmanager
def output_lock(out) -> Iterator[Path]:
    """Hold an exclusive lock on output ``out`` (a folder or file) for the block, or fail at once.

    The lock is ``flock`` on ``.<name>.lock`` beside ``out`` (its parent folders are made, and
    removed again if the block fails and they are still empty).  A second holder gets InputError
    right away.  The lock file is removed on release; one left by a killed run is simply locked
    again (the kernel dropped the dead run's lock).
    """
    out = Path(out)
    parent = out.absolute().parent
    made = _make_parents(parent)
    lock = parent / f".{out.name}.lock"
    fd = -1
    try:
        while True:
            fd = _open_lock(lock, out)
            try:
                fcntl.flock(fd, fcntl.LOCK_EX | fcntl.LOCK_NB)
            except BlockingIOError:
                os.close(fd)
                fd = -1
                raise InputError(
                    f"{out}: another yoyogait run is writing this output (it holds {lock}); "
                    "wait for it to finish or choose another --out"
                ) from None
            # The run that held it may have removed the file meanwhile: then lock the new one.
            try:
                same = os.path.samestat(os.fstat(fd), os.stat(lock))
            except FileNotFoundError:
                same = False
            if same:
                break
            os.close(fd)
            fd = -1
        os.ftruncate(fd, 0)
        os.write(fd, f"{os.getpid()}\n".encode())
        yield lock
    except BaseException:
        with signals_deferred():
            _release(lock, fd)
            fd = -1
            for folder in reversed(made):
                with contextlib.suppress(OSError):
                    folder.rmdir()
        raise
    else:
        with signals_deferred():
            _release(lock, fd)


def _open_lock(lock: Path, out: Path) -> int:
    """The lock file opened for writing, never through a link nor onto a device, FIFO or socket."""
    flags = os.O_RDWR | os.O_CREAT | os.O_CLOEXEC | os.O_NOFOLLOW | os.O_NONBLOCK | os.O_NOCTTY
    try:
        fd = os.open(lock, flags, 0o666)
    except OSError as exc:
        if exc.errno == errno.ELOOP:
            raise InputError(
                f"{out}: its lock file {lock} is a symbolic link; yoyogait does not follow it (remove the link)"
            ) from None
        raise InputError(f"{out}: cannot open its lock file {lock}: {exc.strerror or exc}") from None
    if not stat.S_ISREG(os.fstat(fd).st_mode):
        os.close(fd)
        raise InputError(f"{out}: its lock file {lock} is not a regular file; remove it")
    return fd


def _release(lock: Path, fd: int) -> None:
    if fd < 0:
        return
    lock.unlink(missing_ok=True)  # while still locked, so nobody locks a file about to vanish
    os.close(fd)


def _make_parents(folder: Path) -> list[Path]:
    """Make ``folder`` and its missing parents; the ones made, outermost first."""
    missing = []
    f = folder
    while not f.exists():
        missing.append(f)
        f = f.parent
    folder.mkdir(parents=True, exist_ok=True)
    return list(reversed(missing))
