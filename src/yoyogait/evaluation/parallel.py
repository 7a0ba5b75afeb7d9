"""Per-recording tasks run in worker processes or on a Dask cluster, results in the order of the tasks.

:func:`run_tasks` calls one picklable function on each task, in this process (one job), in a
``ProcessPoolExecutor`` of its own (several jobs), or through any ``concurrent.futures.Executor``
given to it, such as the one :func:`dask_executor` makes for a Dask cluster.  Results come back in
the order of the tasks whatever the order they finish in, so a parallel run gives what a serial
one gives.  A task that raises, or whose worker process dies, becomes a :class:`TaskFailure` with
its message; the other tasks still finish.
"""

from __future__ import annotations

import concurrent.futures as cf
import contextlib
import gc
import multiprocessing
import os
import signal
import threading
import time
from collections.abc import Callable, Iterator, Sequence
from concurrent.futures.process import BrokenProcessPool
from contextlib import contextmanager
from dataclasses import dataclass

from tqdm import tqdm

from ..errors import InputError

__all__ = ["TaskFailure", "default_jobs", "process_pool", "run_tasks", "dask_executor", "DASK_EXTRA"]

DASK_EXTRA = "yoyogait[distributed]"
"""The optional extra that brings Dask distributed."""

_PRELOAD = [
    "yoyogait.evaluation.running",
    "yoyogait.evaluation.report",
    "matplotlib.figure",
    "matplotlib.backends.backend_agg",
]
"""Modules a fork server imports once, so that each worker it forks starts with them loaded."""


@dataclass(frozen=True)
class TaskFailure:
    """A task that raised, or whose worker process ended before answering."""

    message: str


def default_jobs() -> int:
    """The number of cores this process may run on."""
    try:
        return max(1, len(os.sched_getaffinity(0)))
    except AttributeError:  # not on Linux
        return max(1, os.cpu_count() or 1)


def _start_worker(forked: bool) -> None:
    # Ctrl-C reaches the whole process group: the parent handles it and ends the workers, which
    # would otherwise each print a traceback.
    signal.signal(signal.SIGINT, signal.SIG_IGN)
    if forked:
        # What a forked worker inherits (the parent's objects, such as the results of an evaluation)
        # is left out of its garbage collector's passes, which would walk all of it again and again.
        # Forked workers end without finalising the interpreter, so nothing frozen is reported left over.
        gc.freeze()


def _openmp_loaded() -> bool:
    """GNU OpenMP in this process (scikit-learn's, once mobgap's pipeline has run here): its thread pool,
    which Python's threading does not count, ends a forked child ("fork() called from a process already
    using GNU OpenMP")."""
    try:
        with open("/proc/self/maps", encoding="utf-8", errors="replace") as maps:
            return "libgomp" in maps.read()
    except OSError:  # not on Linux: no fork context is chosen there by default either
        return False


def _context():
    methods = multiprocessing.get_all_start_methods()
    # fork starts workers at once with everything imported, but is unsafe once other threads run
    # (a lock one of them held stays held in the child) or OpenMP's; then a fork server.
    if "fork" in methods and threading.active_count() == 1 and not _openmp_loaded():
        return multiprocessing.get_context("fork")
    if "forkserver" in methods:
        ctx = multiprocessing.get_context("forkserver")
        ctx.set_forkserver_preload(_PRELOAD)
        return ctx
    return multiprocessing.get_context("spawn")


def process_pool(jobs: int) -> cf.ProcessPoolExecutor:
    """A pool of ``jobs`` worker processes that leave Ctrl-C to their parent."""
    ctx = _context()
    forked = ctx.get_start_method() in ("fork", "forkserver")
    return cf.ProcessPoolExecutor(
        max_workers=max(1, jobs), mp_context=ctx, initializer=_start_worker, initargs=(forked,)
    )


def _end_workers(pool: cf.ProcessPoolExecutor) -> None:
    """Cancel what has not started and end the pool's worker processes now (on Ctrl-C or an error)."""
    terminate = getattr(pool, "terminate_workers", None)  # Python >= 3.14
    if terminate is not None:
        terminate()
        return
    # The pool's own dict of workers, not a copy: its manager thread replaces a worker that dies
    # (CPython's _adjust_process_count) and adds the replacement there, until it notices the end.
    processes = getattr(pool, "_processes", None) or {}
    manager = getattr(pool, "_executor_manager_thread", None)
    pool.shutdown(wait=False, cancel_futures=True)
    deadline = time.monotonic() + 5.0
    while time.monotonic() < deadline:
        alive = [p for p in list(processes.values()) if p.is_alive()]
        for p in alive:
            p.terminate()
        for p in alive:
            p.join(timeout=1.0)
        if not alive and (manager is None or not manager.is_alive()):
            break
        time.sleep(0.01)


def _failure(exc: BaseException) -> TaskFailure:
    text = str(exc).strip()
    return TaskFailure(f"{type(exc).__name__}: {text}" if text else type(exc).__name__)


class _Progress(tqdm):
    # No monitor thread: worker processes are forked from this one, which is safe only while it
    # runs no other thread.
    monitor_interval = 0


def _bar(total: int, desc: str | None):
    if not desc:
        return contextlib.nullcontext(_NoBar())
    return _Progress(total=total, desc=desc, unit="recording", leave=False, disable=None)


class _NoBar:
    def update(self, n: int = 1) -> None:
        pass


def run_tasks(
    fn: Callable,
    tasks: Sequence[tuple],
    *,
    jobs: int = 1,
    executor: cf.Executor | None = None,
    progress: str | None = None,
) -> list:
    """``[fn(*task) for task in tasks]``, in that order, run on ``jobs`` processes or ``executor``.

    With one job and no executor everything runs in this process. An entry is a
    :class:`TaskFailure` where ``fn`` raised or its worker died. ``progress``, when given, is the
    label of a progress bar. On Ctrl-C (or any exception here) the tasks not started are cancelled,
    the pool's workers are ended, and the exception goes on.
    """
    tasks = list(tasks)
    if not tasks:
        return []
    if executor is None and (jobs <= 1 or len(tasks) == 1):
        out: list = []
        with _bar(len(tasks), progress) as bar:
            for task in tasks:
                try:
                    out.append(fn(*task))
                except Exception as exc:  # reported by name, as a worker's would be
                    out.append(_failure(exc))
                bar.update()
        return out
    own = executor is None
    pool = process_pool(min(jobs, len(tasks))) if executor is None else executor
    results: list = [None] * len(tasks)
    try:
        with _bar(len(tasks), progress) as bar:
            broken = _collect(pool, fn, tasks, range(len(tasks)), results, bar)
            if own:
                pool.shutdown(wait=True)
                # Which task ended the worker is unknown: run the unfinished ones one at a time in a
                # fresh one-worker pool, so that a crash is pinned on the task that causes it.
                for i in broken:
                    _isolated(fn, tasks[i], i, results)
                    bar.update()
            else:
                for i in broken:
                    results[i] = TaskFailure("worker process ended unexpectedly")
    except BaseException:
        if isinstance(pool, cf.ProcessPoolExecutor) and own:
            _end_workers(pool)
        raise
    finally:
        if own:
            pool.shutdown(wait=True, cancel_futures=True)
    return results


def split_outcomes(items: Sequence, outcomes: Sequence, failures: list) -> list:
    """The outcomes that succeeded, in order; a :class:`TaskFailure` appends (item name, message) to
    ``failures`` instead."""
    done = []
    for item, outcome in zip(items, outcomes):
        if isinstance(outcome, TaskFailure):
            failures.append((item.name, outcome.message))
        else:
            done.append(outcome)
    return done


def _collect(pool: cf.Executor, fn, tasks, indices, results, bar) -> list[int]:
    """Submit tasks[i] for i in indices, fill results; the indices lost to a broken pool, in order."""
    futures: dict = {}
    try:
        for i in indices:
            futures[pool.submit(fn, *tasks[i])] = i
    except BrokenProcessPool:
        pass  # submitting after a worker died: the rest are retried below
    broken = [i for i in indices if i not in futures.values()]
    try:
        for future in cf.as_completed(futures):
            i = futures[future]
            try:
                results[i] = future.result()
            except BrokenProcessPool:
                broken.append(i)
                continue
            except cf.CancelledError:
                results[i] = TaskFailure("cancelled")
            except Exception as exc:
                results[i] = _failure(exc)
            bar.update()
    except BaseException:
        for future in futures:
            future.cancel()
        raise
    return sorted(broken)


def _isolated(fn, task, i: int, results: list) -> None:
    pool = process_pool(1)
    try:
        results[i] = pool.submit(fn, *task).result()
    except BrokenProcessPool:
        results[i] = TaskFailure("its worker process ended unexpectedly (crashed or killed)")
    except Exception as exc:
        results[i] = _failure(exc)
    except BaseException:
        _end_workers(pool)
        raise
    finally:
        pool.shutdown(wait=True, cancel_futures=True)


@contextmanager
def dask_executor(address: str, *, timeout_s: float = 5.0) -> Iterator[cf.Executor]:
    """A ``concurrent.futures`` executor that runs tasks on the Dask scheduler at ``address``.

    The workers need yoyogait installed and, unless files are shipped with their tasks, the
    recordings at the same paths. InputError (one line) when Dask is not installed or the
    scheduler does not answer within ``timeout_s``.
    """
    try:
        from distributed import Client
        from distributed.comm.addressing import parse_address, parse_host_port
    except ImportError:
        raise InputError(f"--scheduler needs Dask distributed: pip install '{DASK_EXTRA}'") from None
    try:
        # Checked first: a client made from a malformed address fails half-made and then blocks on exit.
        parse_host_port(parse_address(address)[1])
    except (ValueError, TypeError) as exc:
        raise InputError(f"not a Dask scheduler address: {address} ({exc}); e.g. tcp://host:8786") from None
    try:
        client = Client(address, timeout=timeout_s, set_as_default=False)
    except Exception as exc:  # OSError, TimeoutError, ValueError for a malformed address
        detail = str(exc).strip().splitlines()[0] if str(exc).strip() else type(exc).__name__
        raise InputError(f"cannot reach the Dask scheduler at {address}: {detail}") from None
    try:
        yield client.get_executor(pure=False)
    finally:
        client.close()
