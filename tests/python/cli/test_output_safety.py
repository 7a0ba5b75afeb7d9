"""Outputs that cannot be lost: one run at a time per output folder, interrupts that always stop a run
with nothing left behind, and --force that replaces a report in one step."""

from __future__ import annotations

import os
import signal
import subprocess
import sys
import time
from pathlib import Path

import pytest

from builders import stepping_walk, write_trc
from yoyogait import _files, _guard
from yoyogait.cli import main
from yoyogait.errors import InputError


@pytest.fixture(scope="module")
def walks(tmp_path_factory) -> Path:
    """A tiny data set: a folder of three TRC walks (fast to evaluate)."""
    folder = tmp_path_factory.mktemp("walks")
    for k, step_hz in enumerate((1.6, 1.8, 2.0)):
        rec, _ = stepping_walk(step_hz=step_hz)
        write_trc(folder / f"walk{k}.trc", rec)
    return folder


def _evaluate(walks: Path, out: Path, *extra: str) -> subprocess.Popen:
    argv = [sys.executable, "-m", "yoyogait", "evaluate", str(walks), "--out", str(out), "--estimators", "paper"]
    return subprocess.Popen([*argv, *extra], stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)


def test_a_second_run_on_a_locked_output_fails_at_once(walks, tmp_path, capsys):
    """While another run holds the output's lock, evaluate fails at once with one line and writes nothing."""
    out = tmp_path / "report"
    with _guard.output_lock(out) as lock:
        assert lock.exists()
        t0 = time.monotonic()
        assert main(["evaluate", str(walks), "--out", str(out), "--no-figures"]) == 2
        assert time.monotonic() - t0 < 5
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and "another yoyogait run is writing this output" in err[0] and str(out) in err[0]
    assert list(tmp_path.iterdir()) == []  # and the lock file went with the lock


def test_the_lock_of_a_killed_run_does_not_block(tmp_path):
    """A run killed with SIGKILL while holding the lock leaves a lock file that the next run simply takes."""
    out = tmp_path / "report"
    holder = subprocess.Popen(
        [
            sys.executable,
            "-c",
            "import sys, time\nfrom yoyogait._guard import output_lock\n"
            f"with output_lock({str(out)!r}):\n    print('locked', flush=True)\n    time.sleep(60)\n",
        ],
        stdout=subprocess.PIPE,
        text=True,
    )
    try:
        assert holder.stdout.readline().strip() == "locked"
        with pytest.raises(InputError, match="another yoyogait run"):
            with _guard.output_lock(out):
                pass
    finally:
        holder.kill()
        holder.wait()
    assert (tmp_path / ".report.lock").exists()  # SIGKILL left it
    with _guard.output_lock(out):
        pass
    assert list(tmp_path.iterdir()) == []


def test_two_concurrent_runs_on_the_same_output_exactly_one_succeeds(walks, tmp_path):
    """Two evaluate processes started together on one --out: one writes the report, the other fails with
    one line; nothing else is left."""
    out = tmp_path / "report"
    runs = [_evaluate(walks, out, "--no-figures") for _ in range(2)]
    results = [(p.wait(timeout=120), *p.communicate()) for p in runs]
    codes = sorted(code for code, _, _ in results)
    assert codes == [0, 2], results
    _, _, err = next(r for r in results if r[0] == 2)
    lines = err.strip().splitlines()
    assert "another yoyogait run" in lines[-1] or "use --force" in lines[-1], err
    assert "Traceback" not in err and lines[-1].startswith("yoyogait: error: ")
    assert sorted(p.name for p in tmp_path.iterdir()) == ["report"]
    assert (out / "index.md").is_file() and (out / "recordings.csv").is_file()


@pytest.mark.parametrize("signum, delay_s", [(signal.SIGINT, 0.0), (signal.SIGTERM, 0.3)])
def test_an_interrupted_evaluate_exits_nonzero_and_leaves_nothing(walks, tmp_path, signum, delay_s):
    """SIGINT or SIGTERM during evaluate ends it with 128 + the signal and one line; no report, no
    temporary folder, no lock file."""
    out = tmp_path / "report"
    proc = _evaluate(walks, out)  # with figures: a few seconds of work to interrupt
    try:
        assert proc.stderr.readline().startswith("Evaluating")
        time.sleep(delay_s)
        proc.send_signal(signum)
        _, err = proc.communicate(timeout=60)
    finally:
        proc.kill()
    assert proc.returncode == 128 + signum, err
    assert "Traceback" not in err and "Exception ignored" not in err
    assert err.strip().splitlines()[-1] == f"yoyogait: interrupted ({signal.Signals(signum).name})"
    assert list(tmp_path.iterdir()) == []


def test_an_interrupt_swallowed_by_a_finaliser_still_stops_the_run(walks, tmp_path, monkeypatch, capsys):
    """A SIGINT whose KeyboardInterrupt lands in a finaliser (and is ignored there) still ends evaluate with 130
    before the report is committed, and with one line: no "Exception ignored" traceback."""
    from yoyogait import evaluation as ev

    class Swallower:
        def __del__(self):
            os.kill(os.getpid(), signal.SIGINT)  # the handler raises here, where Python ignores it

    real = ev.evaluate

    def evaluate(*args, **kwargs):
        Swallower()  # dropped at once: __del__ runs
        return real(*args, **kwargs)

    monkeypatch.setattr(ev, "evaluate", evaluate)
    out = tmp_path / "report"
    unraisable = []
    monkeypatch.setattr(sys, "unraisablehook", unraisable.append)  # what Python would report
    assert main(["evaluate", str(walks), "--out", str(out), "--no-figures"]) == 130
    err = capsys.readouterr().err
    assert err.strip().splitlines()[-1] == "yoyogait: interrupted (SIGINT)"
    assert unraisable == [] and "Traceback" not in err
    assert list(tmp_path.iterdir()) == []


def test_a_signal_during_a_commit_waits_until_it_is_done():
    """Inside signals_deferred a SIGINT only is noted; Interrupted comes when the block ends, and the
    run remembers it."""
    steps = []
    with _guard.handle_interrupts():
        with pytest.raises(_guard.Interrupted):
            with _guard.signals_deferred():
                os.kill(os.getpid(), signal.SIGINT)
                time.sleep(0.05)  # the handler has run by now
                steps.append("finished")
        assert steps == ["finished"] and _guard.interrupted_by() == signal.SIGINT
        with pytest.raises(_guard.Interrupted):
            _guard.check_interrupted()
    assert _guard.interrupted_by() is None


def _folder(path: Path, files: dict) -> Path:
    path.mkdir()
    for name, text in files.items():
        (path / name).write_text(text)
    return path


def test_a_signal_while_force_replaces_a_report_waits_until_it_is_whole(tmp_path, monkeypatch):
    """A SIGINT that arrives while --force moves a new report over an old one is held until every file and
    the list of them are in place; then the run stops."""
    out = tmp_path / "report"
    _files.install_folder(_folder(tmp_path / "old", {"a.txt": "old", "b.txt": "old"}), out)
    new = _folder(tmp_path / "new", {"a.txt": "new", "c.txt": "new"})
    real_replace = os.replace
    moved = []

    def replace(src, dst, **dir_fds):
        if Path(dst).name == _files.MARKER:  # the list of files, rewritten before and after them
            return real_replace(src, dst, **dir_fds)
        if not moved:
            os.kill(os.getpid(), signal.SIGINT)
            time.sleep(0.05)  # the handler has run by now
        moved.append(Path(dst).name)
        real_replace(src, dst, **dir_fds)

    monkeypatch.setattr(os, "replace", replace)
    with _guard.handle_interrupts():
        with pytest.raises(_guard.Interrupted):
            _files.install_folder(new, out)
    assert moved == ["a.txt", "c.txt"]
    assert {p.name: p.read_text() for p in out.iterdir() if p.name != _files.MARKER} == {"a.txt": "new", "c.txt": "new"}
    assert _files.written_files(out) == ["a.txt", "c.txt"]
