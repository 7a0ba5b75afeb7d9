"""Treadmill walking: told from the stance feet moving back while the pelvis stays, and the walking speed as the
belt speed plus the pelvis's own motion."""

from __future__ import annotations

import numpy as np
import pytest

import yoyogait
from builders import STEP_M, stepping_walk
from yoyogait.errors import InputError
from yoyogait.pipeline.treadmill import detect_treadmill

BELT_MPS = STEP_M * 1.8  # the synthetic walker's speed: step length times step frequency


def _walking_speed(rec, **kwargs):
    v = yoyogait.gait_velocities(rec, **kwargs)
    walking = v.walking & v.finite
    return v, float(np.mean(v.vx[walking])), float(np.mean(v.vx_signed[walking]))


def test_treadmill_walk_is_detected_and_its_speed_is_the_belt():
    """On a treadmill (pelvis in place) the belt is found from the stance feet (1.26 m/s) and the walking speed is
    the belt speed, as overground, instead of the pelvis's 0.0x m/s."""
    rec, _ = stepping_walk(stand_before_s=0.5, walk_s=6.0, stand_after_s=0.5, treadmill=True)
    found = detect_treadmill(rec)
    assert found.detected and found.belt_from == "stance feet"
    assert found.belt_speed_mps == pytest.approx(BELT_MPS, rel=0.05)
    assert found.forward == pytest.approx((1.0, 0.0), abs=0.05)  # opposite to the feet's backward motion
    v, speed, signed = _walking_speed(rec)
    assert v.treadmill is not None and v.treadmill.detected
    assert speed == pytest.approx(BELT_MPS, rel=0.08) and signed == pytest.approx(BELT_MPS, rel=0.08)
    overground, _ = stepping_walk(stand_before_s=0.5, walk_s=6.0, stand_after_s=0.5)
    assert not detect_treadmill(overground).detected
    assert _walking_speed(overground)[1] == pytest.approx(speed, rel=0.05)


def test_standing_still_is_not_a_treadmill():
    """A person who only stands (pelvis in place, feet still) is not a treadmill walk; the reason says so."""
    rec, _ = stepping_walk(stand_before_s=3.0, walk_s=0.0, stand_after_s=3.0)
    found = detect_treadmill(rec)
    assert not found.detected and "not a treadmill" in found.reason


def test_belt_speed_override_wins_and_is_checked():
    """--belt-speed-mps replaces the stance-feet estimate (and marks a treadmill); a negative speed is an error."""
    rec, _ = stepping_walk(stand_before_s=0.5, walk_s=6.0, stand_after_s=0.5, treadmill=True)
    v, speed, _ = _walking_speed(rec, belt_speed_mps=1.0)
    assert v.treadmill.belt_from == "override" and speed == pytest.approx(1.0, rel=0.08)
    with pytest.raises(InputError, match="belt-speed-mps"):
        detect_treadmill(rec, belt_speed_mps=-1.0)


def _write_csv(path, rec):
    """The recording in yoyogait's CSV layout (metres, z up)."""
    header = "time_s," + ",".join(f"{n}_{a}" for n in rec.point_names for a in "xyz")
    rows = [f"{t:.4f}," + ",".join(f"{v:.5f}" for v in frame.ravel()) for t, frame in zip(rec.time_s, rec.positions_m)]
    path.write_text("# up_axis: z\n" + header + "\n" + "\n".join(rows) + "\n")
    return path


def test_inspect_states_the_treadmill_and_takes_a_belt_speed(tmp_path, capsys):
    """inspect prints a treadmill line and the belt-inclusive speed; --belt-speed-mps replaces the belt."""
    from yoyogait.cli import main

    rec, _ = stepping_walk(stand_before_s=0.5, walk_s=6.0, stand_after_s=0.5, treadmill=True)
    path = _write_csv(tmp_path / "treadmill.csv", rec)
    assert main(["inspect", str(path)]) == 0
    out = capsys.readouterr().out
    assert "treadmill" in out and "move back at 1.2" in out
    speed = float(out.split("mean speed")[1].split()[0])
    assert speed == pytest.approx(BELT_MPS, rel=0.08)
    assert main(["inspect", str(path), "--belt-speed-mps", "0.9"]) == 0
    out = capsys.readouterr().out
    assert "belt 0.90 m/s (--belt-speed-mps)" in out
    assert float(out.split("mean speed")[1].split()[0]) == pytest.approx(0.9, rel=0.08)
