"""Cadence in steps/min where clinicians read it (inspect, the evaluation's recordings.csv), the Hz values kept."""

from __future__ import annotations

import csv
import json

import pytest

from builders import stepping_walk, write_trc
from yoyogait.cli import main


@pytest.fixture(scope="module")
def walk_folder(tmp_path_factory):
    """Two stepping walks at 1.8 steps/s (108 steps/min) as TRC files."""
    folder = tmp_path_factory.mktemp("cadence")
    for k in range(2):
        rec, _ = stepping_walk(step_hz=1.8, stand_before_s=1.0, walk_s=8.0, stand_after_s=1.0)
        write_trc(folder / f"walk{k}.trc", rec)
    return folder


def test_inspect_gives_steps_per_min_beside_hz(walk_folder, capsys):
    """inspect prints and returns the step frequency in Hz and, beside it, 60 x that in steps/min."""
    assert main(["inspect", "--json", str(walk_folder / "walk0.trc")]) == 0
    report = json.loads(capsys.readouterr().out)
    assert report["step_frequency_hz"] == pytest.approx(1.8, abs=0.03)
    assert report["step_frequency_steps_per_min"] == pytest.approx(60 * report["step_frequency_hz"])
    assert report["events_cadence_steps_per_min"] == pytest.approx(60 * report["events_step_frequency_hz"])
    assert main(["inspect", str(walk_folder / "walk0.trc")]) == 0
    line = next(x for x in capsys.readouterr().out.splitlines() if x.startswith("step frequency"))
    assert f"= {60 * report['step_frequency_hz']:.0f} steps/min" in line and "Hz" in line


def test_recordings_csv_has_cadence_columns_and_keeps_the_hz_ones(walk_folder, tmp_path):
    """recordings.csv: cadence_steps_per_min (the estimate) and reference_cadence_steps_per_min, 60 x Hz."""
    out = tmp_path / "report"
    assert main(["evaluate", str(walk_folder), "--estimators", "default", "--out", str(out), "--figures", "none"]) == 0
    rows = list(csv.DictReader(open(out / "recordings.csv")))
    assert len(rows) == 2
    for row in rows:
        assert float(row["cadence_steps_per_min"]) == pytest.approx(108.0, abs=2.0)
        assert float(row["reference_cadence_steps_per_min"]) == pytest.approx(60 * float(row["reference_cadence_hz"]))
        assert "f_err_median_hz" in row and "reference_cadence_hz" in row
