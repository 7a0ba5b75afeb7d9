"""Honest stds and validity online: the stds cover turns and stops; a clean walk is valid soon."""

from __future__ import annotations

import numpy as np
import pytest

from yoyogait import synthetic as sy
from yoyogait import synthetic_conditions as sc
from yoyogait.estimators import OnlineEstimator
from yoyogait.estimators.online import InvalidReason

PELVIS = ["LASI", "RASI", "LPSI", "RPSI"]


def _run(walk):
    res = OnlineEstimator(PELVIS, "z").run(walk.recording)
    return res, walk.truth.at(res.time_s)


def _confidently_wrong(res, truth) -> np.ndarray:
    es = np.abs(res.speed_mps - truth.speed_mps)
    ef = np.abs(np.abs(res.step_frequency_hz) - truth.step_frequency_hz)
    wrong = ((es > 0.15) & (es > 2 * res.speed_std_mps)) | ((ef > 0.15) & (ef > 2 * res.step_frequency_std_hz))
    return res.valid.astype(bool) & wrong


@pytest.mark.parametrize("subject", sy.SUBJECTS, ids=lambda s: s.name)
def test_tight_turns_are_confidently_wrong_on_at_most_1_percent_of_the_walking(subject):
    """SYNTHETIC turns of 0.35 m radius: the speed the heading's lag loses is in its std (<= 1 % confidently wrong)."""
    res, truth = _run(sc.turns_walk(subject))
    walking = np.asarray(truth.walking, dtype=bool)
    assert _confidently_wrong(res, truth)[walking].mean() <= 0.01


@pytest.mark.parametrize("subject", sy.SUBJECTS, ids=lambda s: s.name)
def test_speed_std_covers_most_of_every_stop(subject):
    """SYNTHETIC stand-walk-stop bouts: over each stopping ramp the speed is within 2 std on >= 3/4 of the frames."""
    walk = sc.bouts_walk(subject)
    res, truth = _run(walk)
    t = np.asarray(res.time_s)
    md = walk.recording.metadata
    ramp_s = 0.8  # bouts_walk's default ramp
    stops = np.zeros(t.shape, dtype=bool)
    for start, length in zip(md["bout_starts_s"], md["bouts_s"]):
        stops |= (t >= start + length - ramp_s) & (t <= start + length)
    stops &= np.asarray(truth.walking, dtype=bool)
    covered = np.abs(res.speed_mps - truth.speed_mps) <= 2 * res.speed_std_mps
    assert covered[stops].mean() >= 0.75


def test_clean_walk_is_valid_within_the_bank_window_and_a_second_of_walking():
    """A clean walk at 1.3 m/s, 1.8 steps/s: valid within bank_window_s (1.5 s) + valid_after_s (1 s) of walking."""
    t = np.arange(2000) / 100.0
    th = 2 * np.pi * 1.8 * t
    off = np.array([[0.075, -0.125], [0.075, 0.125], [-0.075, -0.125], [-0.075, 0.125]])
    p = np.zeros((len(t), 4, 3))
    p[:, :, 0] = (1.3 * t - 0.012 * np.sin(th))[:, None] + off[:, 0]
    p[:, :, 1] = off[:, 1]
    p[:, :, 2] = (1.0 + 0.012 * np.cos(th))[:, None]
    res = OnlineEstimator(PELVIS, "z", length_unit_m=1.0).run(t, p)
    first_walking = t[np.flatnonzero(res.walking)[0]]
    assert t[np.flatnonzero(res.valid)[0]] - first_walking <= 2.5


def test_walking_round_a_tight_circle_is_moving():
    """Round a circle of 0.5 m radius at 1.3 m/s (2 s: a 0.5 m chord, a 2.6 m arc): never NOT_MOVING after 5 s."""
    t = np.arange(2500) / 100.0
    radius_m, speed_mps, f_hz = 0.5, 1.3, 1.8
    phi = speed_mps * t / radius_m
    th = 2 * np.pi * f_hz * t
    centre = np.stack([radius_m * np.sin(phi), radius_m * (1 - np.cos(phi)), 1.0 + 0.012 * np.cos(th)], axis=1)
    fwd = np.stack([np.cos(phi), np.sin(phi)], axis=1)
    left = np.stack([-np.sin(phi), np.cos(phi)], axis=1)
    p = np.zeros((len(t), 4, 3))
    for k, (df, dl) in enumerate([(0.075, -0.125), (0.075, 0.125), (-0.075, -0.125), (-0.075, 0.125)]):
        p[:, k, :2] = centre[:, :2] + df * fwd + dl * left
        p[:, k, 2] = centre[:, 2]
    res = OnlineEstimator(PELVIS, "z", length_unit_m=1.0).run(t, p)
    late = res.walking & (t >= 5.0)
    assert late.any()
    assert not np.any(res.invalid_reason[late] & int(InvalidReason.NOT_MOVING))
