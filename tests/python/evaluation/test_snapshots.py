"""Regression snapshot of the estimators on the real recordings, in the spirit of PX4's change indication.

Every metric of ``paper`` and ``default`` on every recording of the shared manifest is kept in
``tests/snapshots/real_metrics.csv``. A change that moves any of them beyond the tolerance below
fails here and must be explained; to accept it on purpose, regenerate the file with

    YOYOGAIT_UPDATE_SNAPSHOTS=1 pytest tests/python/evaluation/test_snapshots.py

and commit the diff with the reason.
"""

from __future__ import annotations

import csv
import math
import os
from pathlib import Path

import pytest

from yoyogait import evaluation as ev
from yoyogait.evaluation.metrics import METRIC_KEYS

SNAPSHOT = Path(__file__).resolve().parents[2] / "snapshots" / "real_metrics.csv"
ESTIMATORS = ("paper", "default")
# Beyond rounding: the pipeline and both estimators are deterministic, so anything larger is a change.
RTOL, ATOL = 1e-6, 1e-9


def _current(manifest_path: Path) -> list[dict]:
    items, missing = ev.manifest_items(manifest_path)
    assert not missing, missing
    result = ev.evaluate(items, ESTIMATORS)
    assert not result.failures, result.failures
    rows = []
    for row in result.rows():
        rows.append(
            {"path_key": f"{row['subject']}/{row['recording']}", "estimator": row["estimator"]}
            | {k: row[k] for k in METRIC_KEYS}
        )
    return rows


def _write(rows: list[dict]) -> None:
    SNAPSHOT.parent.mkdir(parents=True, exist_ok=True)
    with open(SNAPSHOT, "w", newline="") as fh:
        w = csv.DictWriter(fh, fieldnames=["path_key", "estimator", *METRIC_KEYS], lineterminator="\n")
        w.writeheader()
        for row in rows:
            w.writerow({k: (repr(float(v)) if k in METRIC_KEYS else v) for k, v in row.items()})


@pytest.fixture(scope="module")
def rows(datasets_dir) -> list[dict]:
    return _current(datasets_dir / "manifest.json")


def test_real_recording_metrics_match_the_snapshot(rows):
    """Every per-recording metric of paper and default on the shared manifest equals the committed snapshot."""
    if os.environ.get("YOYOGAIT_UPDATE_SNAPSHOTS"):
        _write(rows)
        pytest.skip(f"snapshot regenerated: {SNAPSHOT}")
    assert SNAPSHOT.is_file(), f"{SNAPSHOT} is missing; regenerate it (see this module's docstring)"
    with open(SNAPSHOT, newline="") as fh:
        kept = {(r["path_key"], r["estimator"]): r for r in csv.DictReader(fh)}
    now = {(r["path_key"], r["estimator"]): r for r in rows}
    assert sorted(now) == sorted(kept), "the recordings or estimators differ from the snapshot"
    moved = []
    for key, row in now.items():
        for metric in METRIC_KEYS:
            a, b = float(row[metric]), float(kept[key][metric])
            same = (math.isnan(a) and math.isnan(b)) or math.isclose(a, b, rel_tol=RTOL, abs_tol=ATOL)
            if not same:
                moved.append(f"{key[0]} [{key[1]}] {metric}: {b:.6g} -> {a:.6g}")
    assert not moved, f"{len(moved)} metrics moved:\n" + "\n".join(moved[:40])


def _median(rows: list[dict], estimator: str, metric: str) -> float:
    values = [float(r[metric]) for r in rows if r["estimator"] == estimator and math.isfinite(float(r[metric]))]
    assert values, (estimator, metric)
    values.sort()
    mid = len(values) // 2
    return values[mid] if len(values) % 2 else 0.5 * (values[mid - 1] + values[mid])


def test_default_beats_the_paper_on_real_recordings_by_its_targets(rows):
    """On the real recordings (medians): default v_x error <= 1/30 and v_z <= 1/4 of the paper's, step
    frequency error <= 0.05 Hz after 3 s of walking, no negative frequency, and no recording worse in v_x."""
    assert _median(rows, "default", "vx_sq_err_mean_1e-2") <= _median(rows, "paper", "vx_sq_err_mean_1e-2") / 30
    assert _median(rows, "default", "vz_sq_err_mean_1e-2") <= _median(rows, "paper", "vz_sq_err_mean_1e-2") / 4
    assert _median(rows, "default", "f_err_median_hz") <= 0.05
    by_key = {(r["path_key"], r["estimator"]): r for r in rows}
    for (path_key, est), r in by_key.items():
        if est != "default":
            continue
        assert not float(r["f_wrong_sign_fraction"]) > 0, path_key
        assert float(r["vx_sq_err_mean_1e-2"]) <= float(by_key[(path_key, "paper")]["vx_sq_err_mean_1e-2"]), path_key
