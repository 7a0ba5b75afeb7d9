"""Gait events: foot contacts, steps, step frequency over time and walking/standing, on walks with known steps."""

from __future__ import annotations

import numpy as np
import pytest

import yoyogait
from builders import stepping_walk
from yoyogait.errors import InputError
from yoyogait.io import Recording
from yoyogait.pipeline import events


def matched(found, truth, tolerance_s=0.1):
    """True contacts each found once within ``tolerance_s``; the one that ends the walk may be missed.

    When a walk ends, the last foot is placed beside the other and is never
    again ahead of the pelvis, so that last contact has no peak to find.
    """
    ok = [np.min(np.abs(found - c)) < tolerance_s for c in truth]
    return all(ok[:-1]) and len(found) in (len(truth) - 1, len(truth))


def test_contacts_and_step_frequency_of_a_straight_walk():
    """Every step of a straight walk is found, feet alternating, and the mean step frequency is the true one."""
    rec, truth = stepping_walk()
    ev = events.detect_gait_events(rec)
    assert ev.feet == {"left": "LHEE", "right": "RHEE"}
    assert matched(ev.contacts_s, truth)  # heel strike timing within 0.1 s
    assert all(a != b for a, b in zip(ev.contact_sides, ev.contact_sides[1:]))
    assert ev.mean_step_frequency_hz == pytest.approx(1.8, abs=0.02)
    assert np.allclose(ev.step_frequency_hz, 1.8, atol=0.05)


def test_walking_and_standing_are_told_apart():
    """Walking covers gait initiation (2.0 s) to termination (7.0 s), standing before and after does not."""
    rec, truth = stepping_walk(stand_before_s=2.0, walk_s=5.0, stand_after_s=2.0)
    ev = events.detect_gait_events(rec)
    assert len(ev.walking_segments_s) == 1
    start, end = ev.walking_segments_s[0]
    assert 2.0 - 0.1 <= start <= 2.0 + 0.1 < truth[0]
    assert 7.0 - 0.2 <= end <= 7.0 + 0.2
    mask = ev.walking_mask(rec.time_s)
    assert not mask[rec.time_s < 1.5].any() and not mask[rec.time_s > 7.5].any()
    assert mask[(rec.time_s > 3) & (rec.time_s < 6)].all()


def test_step_frequency_over_time_follows_a_change():
    """The step frequency over time shows a change from 2.0 to 1.5 Hz half way through the walk."""
    rec, _ = stepping_walk(step_hz=2.0, later_step_hz=1.5, walk_s=8.0)
    ev = events.detect_gait_events(rec)
    f = ev.step_frequency_at(rec.time_s)
    early = (rec.time_s > 3.0) & (rec.time_s < 5.5)
    late = (rec.time_s > 7.0) & (rec.time_s < 9.5)
    assert np.nanmedian(f[early]) == pytest.approx(2.0, abs=0.05)
    assert np.nanmedian(f[late]) == pytest.approx(1.5, abs=0.05)
    assert np.all(np.isnan(f[rec.time_s < 1.5]))


def test_treadmill_walk_has_steps_without_forward_motion():
    """On a treadmill (the pelvis stays in place) the steps are still found at the right frequency."""
    rec, truth = stepping_walk(treadmill=True, stand_before_s=0.5, stand_after_s=0.5)
    ev = events.detect_gait_events(rec)
    assert ev.mean_step_frequency_hz == pytest.approx(1.8, abs=0.02)
    assert abs(len(ev.contacts_s) - len(truth)) <= 1


def test_curved_walk_uses_the_turning_heading():
    """On a circle of 2.5 m radius the contacts are found with the heading turning along."""
    rec, truth = stepping_walk(radius_m=2.5, walk_s=6.0)
    ev = events.detect_gait_events(rec)
    assert matched(ev.contacts_s, truth)
    assert ev.mean_step_frequency_hz == pytest.approx(1.8, abs=0.02)


def test_a_missed_contact_counts_as_a_stride_of_two_steps():
    """When one contact is lost (marker occluded), the stride around it still counts two steps."""
    rec, truth = stepping_walk()
    lost = truth[2]  # step 3: a right-foot contact (odd steps are right)
    hidden = np.abs(rec.time_s - lost) < 0.3
    rec.positions_m[hidden, rec.index_of("RHEE")] = np.nan
    ev = events.detect_gait_events(rec)
    assert matched(ev.contacts_s, np.delete(truth, 2))
    assert np.min(np.abs(ev.contacts_s - lost)) > 0.3
    assert ev.mean_step_frequency_hz == pytest.approx(1.8, abs=0.03)
    assert len(ev.walking_segments_s) == 1


def test_feet_are_required_and_checked():
    """Without foot points events are an InputError; a named foot that does not exist lists the points."""
    rec, _ = stepping_walk()
    pelvis_only = Recording(rec.positions_m[:, :3], rec.point_names[:3], rec.time_s, up_axis="z")
    with pytest.raises(InputError, match="no foot point"):
        events.detect_gait_events(pelvis_only)
    with pytest.raises(InputError, match="no point 'LTOE'"):
        events.detect_gait_events(rec, feet={"left": "LTOE"})


def test_velocities_mark_walking_from_steps_or_else_from_speed():
    """GaitVelocities.walking comes from the steps when there are feet, from the pelvis speed when there are not."""
    rec, truth = stepping_walk()
    with_feet = yoyogait.gait_velocities(rec)
    pelvis_only = Recording(rec.positions_m[:, :3], rec.point_names[:3], rec.time_s, up_axis="z")
    from_speed = yoyogait.gait_velocities(pelvis_only)
    for v in (with_feet, from_speed):
        assert not v.walking[v.time_s < 1.5].any() and not v.walking[v.time_s > 7.6].any()
        assert v.walking[(v.time_s > 3) & (v.time_s < 6)].all()
    speed_mask = events.walking_from_speed(np.r_[np.zeros(50), np.ones(100), np.zeros(50)], 25.0)
    assert not speed_mask[:40].any() and speed_mask[60:140].all() and not speed_mask[160:].any()


def _with_toes(rec):
    """The walk with a toe marker 0.2 m ahead of each heel."""
    heels = rec.points(["LHEE", "RHEE"])
    toes = heels + np.array([0.2, 0.0, 0.0])
    pos = np.concatenate([rec.positions_m, toes], axis=1)
    return Recording(pos, rec.point_names + ["LTOE", "RTOE"], rec.time_s, rate_hz=rec.rate_hz, up_axis="z")


@pytest.mark.parametrize(
    "feet",
    [
        ["LHEE", "RHEE", "LTOE", "RTOE"],
        {"left": ["LTOE", "LHEE"], "right": ["RHEE", "RTOE"]},
        {"l": "LHEE", "r": "RHEE"},
    ],
)
def test_heel_and_toe_of_a_side_are_one_foot(feet):
    """Heel and toe of one side are one foot (list with sides from names, or a dict): one contact series per side,
    the heel used, and the cadence is the true 1.8 Hz, not doubled."""
    rec, truth = stepping_walk()
    rec = _with_toes(rec)
    assert events.foot_groups_of(rec, feet)["left"][0] == "LHEE"
    ev = events.detect_gait_events(rec, feet=feet)
    assert ev.feet == {"left": "LHEE", "right": "RHEE"}
    assert matched(ev.contacts_s, truth)
    assert ev.mean_step_frequency_hz == pytest.approx(1.8, abs=0.02)


def test_a_listed_foot_without_a_side_is_an_error():
    """A foot point whose name tells no side cannot make a per-side contact series: the error says how to fix it."""
    rec, _ = stepping_walk()
    with pytest.raises(InputError, match="feet=SACR: cannot tell which foot .SACR.*left"):
        events.detect_gait_events(rec, feet=["LHEE", "SACR"])


def test_manifest_feet_as_a_list_or_by_side(tmp_path):
    """A manifest gives feet as a list or as {"left": [...], "right": [...]}; both reach the events as given."""
    from yoyogait.evaluation.datasets import manifest_items

    (tmp_path / "a.csv").write_text("time_s,vx,vz\n0,1,0\n0.1,1,0\n")
    (tmp_path / "manifest.json").write_text(
        '{"recordings": [{"path": "a.csv", "feet": ["LHEE", "RHEE", "LTOE", "RTOE"]},'
        ' {"path": "a.csv", "feet": {"left": ["LHEE", "LTOE"], "right": ["RHEE"]}},'
        ' {"path": "a.csv", "feet": "LHEE"}]}'
    )
    items, problems = manifest_items(tmp_path / "manifest.json")
    assert items[0].feet == ["LHEE", "RHEE", "LTOE", "RTOE"]
    assert items[1].feet == {"left": ["LHEE", "LTOE"], "right": ["RHEE"]}
    assert len(problems) == 1 and problems[0][0] == "entry 2 (a.csv)"
    assert problems[0][1].startswith('\'feet\' must be a list of names or {"left": [...], "right": [...]}')
