"""Results and recordings print as one short line and export as CSV or a pandas DataFrame."""

from __future__ import annotations

import sys

import numpy as np
import pytest

import yoyogait
from yoyogait import synthetic


@pytest.fixture(scope="module")
def walk_and_result():
    walk = synthetic.make_walk(synthetic.SUBJECTS[0], "5-stop-and-go", duration_s=20.0)
    vel = yoyogait.gait_velocities(walk.recording)
    res = yoyogait.GaitEstimator().run(vel.vx, vel.vz, time_s=vel.time_s)
    return walk, vel, res


def test_reprs_are_one_short_line_without_arrays(walk_and_result):
    """Recording, GaitVelocities and EstimateResult print shape, rate, duration and points, not their arrays."""
    walk, vel, res = walk_and_result
    for obj, facts in (
        (walk.recording, ["2001 frames", "100 Hz", "20.00 s", "8 points", "PELVIS"]),
        (vel, ["501 samples", "25 Hz", "20.00 s", "pelvis centre", "walking"]),
        (res, ["501 samples", "20.00 s", "step frequency", "Hz", "speed", "m/s"]),
    ):
        text = repr(obj)
        assert "\n" not in text and "array(" not in text and len(text) < 300, text
        assert all(fact in text for fact in facts), (text, facts)


def test_status_is_exported():
    """yoyogait.Status names the codes of the status column."""
    assert int(yoyogait.Status.UPDATED) == 0 and "Status" in dir(yoyogait)


def test_csv_and_dataframe_hold_the_same_columns(walk_and_result, tmp_path):
    """to_csv writes exactly the columns of to_dataframe, with the values, units in the names."""
    pd = pytest.importorskip("pandas")
    _, vel, res = walk_and_result
    frame = res.to_dataframe(vel)
    assert list(frame.columns[:4]) == ["time_s", "vx_mps", "vz_mps", "walking"]
    assert frame["walking"].dtype == bool and len(frame) == len(vel.time_s)
    np.testing.assert_array_equal(frame["step_frequency_hz"], res.step_frequency_hz)
    path = res.to_csv(tmp_path / "e.csv", velocities=vel)
    back = pd.read_csv(path)
    assert list(back.columns) == list(frame.columns)
    np.testing.assert_allclose(back["speed_mps"], res.speed_mps, rtol=1e-5, atol=1e-9)
    np.testing.assert_array_equal(back["walking"].astype(bool), vel.walking)
    alone = res.to_dataframe()  # without the velocities: the result's own time and columns
    assert "vx_mps" not in alone.columns and alone["time_s"].iloc[-1] == pytest.approx(vel.time_s[-1])
    v = pd.read_csv(vel.to_csv(tmp_path / "v.csv"))
    assert list(v.columns) == ["time_s", "vx_mps", "vz_mps", "vx_signed_mps", "walking"]
    assert list(vel.to_dataframe().columns) == list(v.columns)


def test_without_pandas_the_error_names_the_extra(walk_and_result, monkeypatch):
    """to_dataframe without pandas raises ImportError saying to install yoyogait[pandas]."""
    _, vel, res = walk_and_result
    monkeypatch.setitem(sys.modules, "pandas", None)
    for call in (res.to_dataframe, vel.to_dataframe):
        with pytest.raises(ImportError, match=r"yoyogait\[pandas\]"):
            call()


def test_velocities_of_another_length_are_refused(walk_and_result):
    """A result paired with velocities of another length is an input error, not a misaligned table."""
    _, vel, res = walk_and_result
    short = yoyogait.GaitEstimator().run(vel.vx[:100], vel.vz[:100])
    with pytest.raises(ValueError, match="samples"):
        short.to_columns(vel)
