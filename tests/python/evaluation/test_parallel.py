"""Evaluation in worker processes: the same report as a serial run, failures and crashes reported by
name, Ctrl-C ending the workers, and the figure modes."""

from __future__ import annotations

import csv
import dataclasses
import functools
import json
import multiprocessing
import os
import signal
import time
from pathlib import Path

import pytest

from yoyogait import evaluation as ev
from yoyogait.cli import main
from yoyogait.evaluation import parallel

CHOSEN = (
    "c3d_org_samples/sample09_PlugInC3D.c3d",
    "c3d_org_samples/MAC_Walk1.c3d",
    "opensim_models/Rajagopal_motion_capture_walk.trc",
    "bandai_namco_motion/dataset-2_walk-turn-left_normal_001.bvh",
    "c3d_org_samples/sample26_Qualisys_Capture0004.c3d",
)


@pytest.fixture(scope="module")
def small_manifest(manifest, datasets_dir, tmp_path_factory) -> Path:
    """A manifest of five short real recordings of three formats, with absolute paths."""
    chosen = [r for r in manifest["recordings"] if r["path"] in CHOSEN]
    assert len(chosen) == len(CHOSEN)
    folder = tmp_path_factory.mktemp("small")
    doc = {"recordings": [{**r, "path": str((datasets_dir / r["path"]).resolve())} for r in chosen]}
    (folder / "manifest.json").write_text(json.dumps(doc))
    return folder / "manifest.json"


def report_files(folder: Path) -> dict:
    """Every file of a report except the PNGs, by name, as bytes."""
    return {p.relative_to(folder).as_posix(): p.read_bytes() for p in sorted(folder.rglob("*")) if p.suffix != ".png"}


def test_two_jobs_write_the_same_report_as_one(small_manifest, tmp_path):
    """Tables, the per-recording CSV and the index are byte for byte those of a serial run."""
    items, _, _ = ev.resolve_dataset(str(small_manifest))
    serial = ev.evaluate(items, ("paper", "default"), jobs=1)
    parallel_ = ev.evaluate(items, ("paper", "default"), jobs=2)
    assert [r.item.name for r in parallel_.items] == [i.name for i in items]
    a = ev.write_report(serial, tmp_path / "serial", figures="none")
    b = ev.write_report(parallel_, tmp_path / "parallel", figures="none")
    assert report_files(a) == report_files(b)
    assert len(list(csv.DictReader(open(b / "recordings.csv")))) == 2 * len(items)


def test_failing_and_crashing_recordings_are_reported_and_the_rest_finish(small_manifest, tmp_path):
    """A recording that fails and one whose worker process dies are each reported by name with a
    message; the others give what a serial run gives, in the order of the items."""
    items, _, _ = ev.resolve_dataset(str(small_manifest))
    broken = tmp_path / "broken.c3d"
    broken.write_bytes(b"not a c3d file at all")
    bad = ev.Item(name="broken.c3d", subject="x", walk="straight", load=functools.partial(ev.datasets.io.read, broken))
    crash = dataclasses.replace(items[0], name="crash.c3d", load=functools.partial(os._exit, 3))
    mixed = [items[0], crash, items[1], bad, *items[2:]]
    result = ev.evaluate(mixed, ("paper",), jobs=2)
    failed = dict(result.failures)
    assert list(failed) == ["crash.c3d", "broken.c3d"]
    assert "worker process ended" in failed["crash.c3d"]
    assert "broken.c3d" in failed["broken.c3d"]
    serial = ev.evaluate(items, ("paper",), jobs=1)
    a = ev.write_report(serial, tmp_path / "serial", figures="none")
    b = ev.write_report(result, tmp_path / "parallel", figures="none")
    assert (a / "recordings.csv").read_bytes() == (b / "recordings.csv").read_bytes()


def _interrupt(signum, frame):
    raise KeyboardInterrupt


def test_ctrl_c_ends_the_worker_processes():
    """An interrupt while tasks run cancels the rest and leaves no worker process behind, at once."""
    previous = signal.signal(signal.SIGALRM, _interrupt)
    start = time.perf_counter()
    try:
        signal.setitimer(signal.ITIMER_REAL, 0.5)
        with pytest.raises(KeyboardInterrupt):
            parallel.run_tasks(time.sleep, [(30.0,)] * 4, jobs=2)
    finally:
        signal.setitimer(signal.ITIMER_REAL, 0)
        signal.signal(signal.SIGALRM, previous)
    assert time.perf_counter() - start < 10
    assert multiprocessing.active_children() == []


def test_run_tasks_keeps_the_order_of_the_tasks():
    """Results come back in the order of the tasks, not of completion; a raising task is a TaskFailure."""
    delays = [0.3, 0.0, 0.2, 0.0, -1.0]
    out = parallel.run_tasks(time.sleep, [(d,) for d in delays], jobs=2)
    assert out[:4] == [None] * 4
    assert isinstance(out[4], parallel.TaskFailure) and "ValueError" in out[4].message


def test_figures_in_parallel_and_the_summary_mode(small_manifest, tmp_path):
    """Two jobs draw the same figure files as one; 'summary' draws the distributions and the best and
    worst recording of each estimator, and the index links every PNG."""
    items, _, _ = ev.resolve_dataset(str(small_manifest))
    result = ev.evaluate(items, ("paper", "default"), jobs=2)
    few = ev.evaluate(items[:2], ("default",), jobs=1)
    one = ev.write_report(few, tmp_path / "one", figures="all", jobs=1)
    two = ev.write_report(few, tmp_path / "two", figures="all", jobs=2)
    assert not few.figure_failures, few.figure_failures
    names = sorted(p.name for p in (one / "figures").glob("*.png"))
    assert names == sorted(p.name for p in (two / "figures").glob("*.png"))
    assert len(names) == 2 * 2
    assert (one / "index.md").read_bytes() == (two / "index.md").read_bytes()
    summary = ev.write_report(result, tmp_path / "summary", figures="summary", jobs=2)
    pngs = sorted((summary / "figures").glob("*.png"))
    assert (summary / "figures" / "distributions.png").stat().st_size > 5000
    assert 3 <= len(pngs) <= 1 + 2 * 2 * 2
    index = (summary / "index.md").read_text()
    assert all(f"figures/{p.name}" in index for p in pngs)
    assert "best" in index and "worst" in index
    assert not result.figure_failures


def test_figure_mode_defaults_by_size():
    """Above SUMMARY_ABOVE recordings the default is 'summary', else 'all'; False is 'none'."""
    assert ev.report.figure_mode(None, ev.report.SUMMARY_ABOVE) == "all"
    assert ev.report.figure_mode(None, ev.report.SUMMARY_ABOVE + 1) == "summary"
    assert ev.report.figure_mode(True, 5) == "all" and ev.report.figure_mode(False, 5) == "none"
    with pytest.raises(ValueError, match="figures must be one of"):
        ev.report.figure_mode("some", 5)


def test_evaluate_command_jobs_and_figure_options(small_manifest, tmp_path, capsys):
    """--jobs 2 --figures summary writes the summary figures; --no-figures is --figures none; a bad
    --jobs or contradicting options are one error line."""
    out = tmp_path / "ev"
    args = ["evaluate", str(small_manifest), "--estimators", "default", "--jobs", "2"]
    assert main([*args, "--out", str(out), "--figures", "summary"]) == 0
    assert (out / "figures" / "distributions.png").is_file()
    out2 = tmp_path / "ev2"
    assert main([*args, "--out", str(out2), "--no-figures"]) == 0
    assert not (out2 / "figures").exists()
    assert (out / "recordings.csv").read_bytes() == (out2 / "recordings.csv").read_bytes()
    capsys.readouterr()
    assert main(["evaluate", str(small_manifest), "--out", str(tmp_path / "x"), "--jobs", "0"]) == 2
    assert "--jobs must be at least 1" in capsys.readouterr().err
    assert main(["evaluate", "--out", str(tmp_path / "x"), "--no-figures", "--figures", "all"]) == 2
    assert "contradicts" in capsys.readouterr().err
    assert not (tmp_path / "x").exists()


def test_scheduler_without_dask_names_the_extra(monkeypatch):
    """Without Dask installed, --scheduler is one error naming the extra to install."""
    monkeypatch.setitem(__import__("sys").modules, "distributed", None)
    with pytest.raises(ValueError, match=r"yoyogait\[distributed\]"):
        with parallel.dask_executor("tcp://127.0.0.1:8786"):
            pass
