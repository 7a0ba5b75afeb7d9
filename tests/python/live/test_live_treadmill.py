"""Treadmills live (foot points, a belt speed that changes while running), a hand followed (LSL on this host only)."""

from __future__ import annotations

import time

import numpy as np
import pytest
from live_helpers import PELVIS, LiveThread, marker_info, pelvis_frames, pelvis_labels, replay_frames, unique

from yoyogait import OnlineEstimator
from yoyogait import synthetic_conditions as sc
from yoyogait.cli import main
from yoyogait.live.live import BeltSpeedStream, estimate_row

pylsl = pytest.importorskip("pylsl")

HEELS = ("LHEE", "RHEE")


def test_live_feet_and_a_changing_belt_speed_give_the_estimates_of_the_same_frames_offline():
    """live with feet and a belt-speed callback: per frame, what OnlineEstimator gives for the same feet and speeds."""
    rec = sc.treadmill_walk(duration_s=3.0).recording
    points = PELVIS + HEELS
    frames = pelvis_frames(rec, points)
    name = unique("treadmill")
    calls: list[int] = []

    def belt_speed():  # unknown for the first 100 frames, then 1.2 m/s, then 1.0 m/s
        calls.append(1)
        n = len(calls)
        return None if n <= 100 else 1.2 if n <= 200 else 1.0

    outlet = pylsl.StreamOutlet(marker_info(pylsl, name, pelvis_labels(points)))
    live = LiveThread(name, resolve_timeout_s=10, max_buffer_s=10, feet=HEELS, belt_speed=belt_speed)
    base = replay_frames(pylsl, outlet, live, rec.time_s, frames)
    est = OnlineEstimator(list(PELVIS), "z", 1.0, feet=HEELS)
    expected = []
    for k in range(rec.n_frames):
        if k in (100, 200):
            est.set_belt_speed_mps(1.2 if k == 100 else 1.0)
        expected.append(estimate_row(est.update(base + rec.time_s[k], frames[k].reshape(len(points), 3))))
    got = np.array(live.rows)
    np.testing.assert_array_equal(got, np.array(expected))
    belt = got[:, [i for i, c in enumerate(live_columns()) if c == "belt_speed_mps"][0]]
    assert belt[150] == 1.2 and belt[-1] == 1.0


def live_columns():
    from yoyogait.live.live import ESTIMATE_COLUMNS

    return ESTIMATE_COLUMNS


def test_belt_speed_stream_gives_the_newest_sample_and_none_for_what_is_not_a_speed():
    """BeltSpeedStream: the newest value of the stream's first channel; a negative or NaN value is unknown (None)."""
    name = unique("belt")
    outlet = pylsl.StreamOutlet(pylsl.StreamInfo(name, "BeltSpeed", 1, 0, pylsl.cf_double64, name))
    reader = BeltSpeedStream(name, timeout_s=10)
    assert outlet.wait_for_consumers(10)

    def read_until(expected, timeout_s=5.0):
        end = time.monotonic() + timeout_s
        value = reader()
        while value != expected and time.monotonic() < end:
            time.sleep(0.02)
            value = reader()
        return value

    assert reader() is None  # nothing sent yet
    outlet.push_sample([0.8])
    outlet.push_sample([1.1])
    assert read_until(1.1) == 1.1
    outlet.push_sample([-1.0])
    assert read_until(None) is None


def test_live_refuses_two_belt_speeds_in_one_line(capsys):
    """live --belt-speed-mps with --belt-speed-source: exit 2 with one line naming both."""
    assert main(["live", "--source", unique("x"), "--belt-speed-mps", "1", "--belt-speed-source", "b"]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and "--belt-speed-mps" in err[0] and "--belt-speed-source" in err[0]


def test_live_following_the_hand_reports_arm_gestures_as_not_walking():
    """live --point hand: per frame what for_recording(rec, "hand") gives (a hand must travel); gestures <= 5 %."""
    rec = sc.arm_gestures(duration_s=12.0).recording
    points = (*PELVIS, "RWRI")
    frames = pelvis_frames(rec, points)
    name = unique("gestures")
    outlet = pylsl.StreamOutlet(marker_info(pylsl, name, pelvis_labels(points)))
    live = LiveThread(name, resolve_timeout_s=10, max_buffer_s=30, point="hand")  # 12 s pushed at once
    base = replay_frames(pylsl, outlet, live, rec.time_s, frames)
    est = OnlineEstimator.for_recording(rec, "hand")
    assert not est.config.gait_in_place
    hand = frames[:, -3:].reshape(-1, 1, 3)
    expected = [estimate_row(est.update(base + rec.time_s[k], hand[k])) for k in range(rec.n_frames)]
    got = np.array(live.rows)
    np.testing.assert_array_equal(got, np.array(expected))
    walking = got[:, live_columns().index("walking")]
    assert walking.mean() <= 0.05
