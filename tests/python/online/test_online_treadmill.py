"""Treadmills online: the belt speed from the stance feet or given, and a treadmill walk without either not valid."""

from __future__ import annotations

from dataclasses import fields
from types import SimpleNamespace

import numpy as np
import pytest

from yoyogait import synthetic
from yoyogait import synthetic_conditions as sc
from yoyogait.cli import main
from yoyogait.cli.estimate_cmd import belt_line
from yoyogait.errors import InputError
from yoyogait.estimators import OnlineEstimator
from yoyogait.estimators.online import InvalidReason
from yoyogait.evaluation.datasets import manifest_items
from yoyogait.evaluation.online import evaluate_item_online
from yoyogait.io import Recording

PELVIS = ["LASI", "RASI", "LPSI", "RPSI"]
HEELS = list(synthetic.HEEL_MARKERS)
BELT_MPS = 1.2
STEADY_AFTER_S = 5.0  # the belt has reached its speed (1 s standing, 1.5 s ramp) and the estimate has followed


@pytest.fixture(scope="module")
def treadmill():
    return sc.treadmill_walk(belt_speed=BELT_MPS, duration_s=14.0)


def _steady(walk, res):
    t = np.asarray(res.time_s)
    return t >= STEADY_AFTER_S, np.interp(t, walk.truth.time_s, walk.truth.speed_mps)


def test_feet_give_the_walking_speed_on_a_treadmill_within_5_cm_per_s(treadmill):
    """With the heels in the frames the online speed after the start is within 0.05 m/s of the truth (median), valid."""
    res = OnlineEstimator(PELVIS, "z", feet=HEELS).run(treadmill.recording)
    steady, truth = _steady(treadmill, res)
    assert np.median(np.abs(res.speed_mps[steady] - truth[steady])) <= 0.05
    assert np.median(np.abs(res.belt_speed_mps[steady] - BELT_MPS)) <= 0.05
    assert res.valid[steady].mean() >= 0.8
    # The belt's uncertainty is the walking speed's too: the reported std covers the error.
    err = np.abs(res.speed_mps[steady] - truth[steady])
    assert np.mean(err <= 2.0 * res.speed_std_mps[steady]) >= 0.9


def test_known_belt_speed_without_feet_gives_the_walking_speed(treadmill):
    """set_belt_speed_mps, no feet: the speed after the start is within 0.05 m/s of the truth; the record says so."""
    est = OnlineEstimator(PELVIS, "z")
    est.set_belt_speed_mps(BELT_MPS)
    assert est.belt_speed_mps == BELT_MPS
    res = est.run(treadmill.recording)
    steady, truth = _steady(treadmill, res)
    assert np.median(np.abs(res.speed_mps[steady] - truth[steady])) <= 0.05
    assert np.all(res.belt_speed_mps == BELT_MPS) and np.all(res.belt_speed_std_mps == 0)
    est.set_belt_speed_mps(None)
    assert est.belt_speed_mps is None


def test_treadmill_walk_without_feet_or_belt_is_never_valid_while_walking(treadmill):
    """Neither feet nor a belt speed: once the travel window has filled, no walking frame is valid (NOT_MOVING)."""
    res = OnlineEstimator(PELVIS, "z").run(treadmill.recording)
    steady = (np.asarray(res.time_s) >= STEADY_AFTER_S) & res.walking
    assert steady.any()
    assert not res.valid[steady].any()
    assert np.all(res.invalid_reason[steady] & int(InvalidReason.NOT_MOVING))
    assert np.all(res.belt_speed_mps == 0)


def test_heels_overground_change_nothing():
    """Overground the stance feet stand still: with the heels in the frames every output equals the run without them."""
    walk = synthetic.make_walk(synthetic.SUBJECTS[0], "1-straight", duration_s=12.0)
    without = OnlineEstimator(PELVIS, "z").run(walk.recording)
    with_feet = OnlineEstimator(PELVIS, "z", feet=HEELS).run(walk.recording)
    for f in fields(without):
        assert np.array_equal(getattr(without, f.name), getattr(with_feet, f.name), equal_nan=True), f.name


def test_a_belt_speed_that_changes_is_followed(treadmill):
    """A known belt speed changed mid-walk (a live input): the estimate's belt_speed_mps follows it from that frame."""
    est = OnlineEstimator(PELVIS, "z")
    rec = treadmill.recording
    est.set_belt_speed_mps(1.0)
    for k in range(rec.n_frames):
        if k == 600:
            est.set_belt_speed_mps(BELT_MPS)
        e = est.update(rec.time_s[k], rec.points(PELVIS)[k])
        assert e.belt_speed_mps == (1.0 if k < 600 else BELT_MPS)


@pytest.mark.parametrize("bad", [-0.1, float("inf"), 11.0, "fast"])
def test_a_belt_speed_that_is_not_one_is_refused(bad):
    """set_belt_speed_mps refuses a negative, infinite, too high or non-numeric speed with InputError."""
    with pytest.raises(InputError, match="belt speed"):
        OnlineEstimator(PELVIS, "z").set_belt_speed_mps(bad)


def test_feet_count_and_frame_shape_are_checked():
    """More than 4 feet is refused; a frame must hold the points and the feet."""
    with pytest.raises(InputError, match="at most 4"):
        OnlineEstimator(PELVIS, "z", feet=["a", "b", "c", "d", "e"])
    est = OnlineEstimator(PELVIS, "z", feet=HEELS)
    with pytest.raises(InputError, match="6 x 3"):
        est.update(0.0, np.zeros((4, 3)))
    assert est.update(0.0, np.ones((6, 3))).points_seen == 4


def _write(rec, path):
    header = ["time_s"] + [f"{n}_{a}" for n in rec.point_names for a in "xyz"]
    table = np.column_stack([rec.time_s, rec.positions_m.reshape(rec.n_frames, -1)])
    path.write_text(
        "# up_axis: z\n"
        + ",".join(header)
        + "\n"
        + "\n".join(",".join(repr(float(v)) for v in r) for r in table)
        + "\n"
    )


def test_estimate_online_with_feet_or_a_belt_speed_and_a_hint_without(treadmill, tmp_path, capsys):
    """estimate --online: --feet and --belt-speed-mps give the belt (the CSV's belt_speed_mps); neither: a hint line."""
    path = tmp_path / "treadmill.csv"
    _write(treadmill.recording, path)
    out = tmp_path / "o.csv"
    assert main(["estimate", str(path), "--online", "--feet", "LHEE,RHEE", "--out", str(out), "--force"]) == 0
    assert "belt found from the stance feet (LHEE, RHEE)" in capsys.readouterr().out
    table = np.genfromtxt(out, delimiter=",", names=True)
    assert abs(np.median(table["belt_speed_mps"][table["time_s"] >= STEADY_AFTER_S]) - BELT_MPS) <= 0.05
    assert main(["estimate", str(path), "--online", "--belt-speed-mps", "1.2", "--out", str(out), "--force"]) == 0
    assert "belt 1.20 m/s (--belt-speed-mps)" in capsys.readouterr().out
    assert main(["estimate", str(path), "--online", "--out", str(out), "--force"]) == 0
    said = capsys.readouterr().out
    assert "(a treadmill?)" in said and "give --feet LHEE,RHEE (heels) or --belt-speed-mps" in said
    assert main(["estimate", str(path), "--online", "--belt-speed-mps", "-1", "--out", str(out), "--force"]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and "--belt-speed-mps" in err[0]


def test_real_treadmill_walk_with_heels_within_5_cm_per_s_of_the_offline_speed(datasets_dir):
    """Gait2392 (a 60 Hz treadmill walk, heels): the online speed with feet is within 0.05 m/s (median over its
    walking, the start included) of the evaluation's reference (the offline treadmill speed: belt plus pelvis)."""
    items, _ = manifest_items(datasets_dir / "manifest.json")
    item = next(i for i in items if i.name == "Gait2392_subject01_walk1.trc")
    assert item.walk == "treadmill" and item.feet
    without = evaluate_item_online(item).metrics["online"]["speed_err_median_mps"]
    with_feet = evaluate_item_online(item, feet=True).metrics["online"]["speed_err_median_mps"]
    assert with_feet <= 0.05 < without


def test_treadmill_walk_without_feet_or_belt_reports_its_speed_as_unknown(treadmill):
    """Neither feet nor a belt speed: while walking and NOT_MOVING the speed std covers the belt's walking speed."""
    res = OnlineEstimator(PELVIS, "z").run(treadmill.recording)
    steady, truth = _steady(treadmill, res)
    not_moving = steady & res.walking & ((res.invalid_reason & int(InvalidReason.NOT_MOVING)) != 0)
    assert not_moving.any()
    err = np.abs(res.speed_mps[not_moving] - truth[not_moving])
    assert np.all(err <= 2.0 * res.speed_std_mps[not_moving])


def test_treadmill_walk_is_not_moving_before_the_travel_window_fills():
    """Stepping in place from the first frame (a treadmill, no feet, no belt): NOT_MOVING already in its first 2 s."""
    t = np.arange(600) / 100.0
    th = 2 * np.pi * 1.8 * t
    p = np.zeros((len(t), 4, 3))
    p[:, :, 0] = -0.012 * np.sin(th)[:, None] + np.array([0.075, 0.075, -0.075, -0.075])
    p[:, :, 1] = np.array([-0.125, 0.125, -0.125, 0.125])
    p[:, :, 2] = 1.0 + 0.012 * np.cos(th)[:, None]
    res = OnlineEstimator(PELVIS, "z", length_unit_m=1.0).run(t, p)
    early = res.walking & (t < 2.0)
    assert early.any()
    assert np.all(res.invalid_reason[early] & int(InvalidReason.NOT_MOVING))


def test_estimate_online_says_a_walk_in_place_with_feet_that_stay_is_no_treadmill(tmp_path, capsys):
    """estimate --online on a pelvis bobbing in place at 1.8 Hz over heels that stand still (knee bends, as a
    video-keypoint demo shows): the line says bobbing in place, not a treadmill, and names no option to give."""
    t = np.arange(800) / 100.0
    bob = 0.03 * np.sin(2 * np.pi * 1.8 * t)
    pelvis = [(0.1, 0.12, 1.0), (0.1, -0.12, 1.0), (-0.1, 0.0, 1.0)]
    heels = [(-0.05, 0.1, 0.05), (-0.05, -0.1, 0.05)]
    pos = np.array([[(x, y, z + (b if z > 0.5 else 0.0)) for x, y, z in pelvis + heels] for b in bob])
    rec = Recording(pos, ["LASI", "RASI", "SACR", "LHEE", "RHEE"], t, rate_hz=100.0, up_axis="z", source="test")
    path = tmp_path / "in_place.csv"
    _write(rec, path)
    assert main(["estimate", str(path), "--online", "--out", str(tmp_path / "o.csv")]) == 0
    said = capsys.readouterr().out
    assert "stepping or bobbing in place, not a treadmill" in said and "LHEE, RHEE at 0.00 m/s" in said
    assert "a treadmill?" not in said and "give --feet" not in said


def test_belt_line_counts_the_frames_a_belt_was_found_on():
    """A belt found on 1 of 331 frames of an overground walk is said as such, not as "0 %" of the frames."""
    belt = np.zeros(331)
    belt[6] = 0.276
    line = belt_line(SimpleNamespace(belt_speed_mps=belt), ("Foot_L", "Foot_R"), None)
    assert "on 1 of 331 frames (0.3 %), median 0.28 m/s" in line
