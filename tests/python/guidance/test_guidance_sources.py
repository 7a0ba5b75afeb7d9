"""The feedback sources: only the past, the delay line, the filters and the gate."""

from __future__ import annotations

from types import SimpleNamespace

import numpy as np
import pytest

from yoyogait.guidance import SOURCE_NAMES, usable
from yoyogait.guidance.metrics import harmonic_rms
from yoyogait.guidance.sources import Delayed, VelocitySource, make_source
from yoyogait.synthetic import SUBJECTS, make_walk

RATE_HZ = 100.0


def _hand_frames(seconds: float = 6.0):
    walk = make_walk(SUBJECTS[0], "1-straight", duration_s=seconds, dropouts=False, rate_hz=RATE_HZ)
    rec = walk.recording
    return rec.time_s, rec.points(["RWRI"])[:, 0, :], np.column_stack([walk.truth.speed_mps, 0 * walk.truth.speed_mps])


@pytest.mark.parametrize("name", SOURCE_NAMES)
def test_a_source_sees_only_the_past(name):
    """Frames after t change nothing the source returned up to t (two walks equal up to 3 s, different after)."""
    t, hand, intent = _hand_frames()
    other = hand.copy()
    cut = int(3.0 * RATE_HZ)
    other[cut + 1 :] += np.array([0.5, -0.3, 0.1])
    intent_other = intent.copy()
    intent_other[cut + 1 :] *= 2.0
    a = make_source(name, latency_s=0.05, rate_hz=RATE_HZ)
    b = make_source(name, latency_s=0.05, rate_hz=RATE_HZ)
    out_a = np.array([a.update(t[k], hand[k], intent[k]) for k in range(len(t))])
    out_b = np.array([b.update(t[k], other[k], intent_other[k]) for k in range(len(t))])
    assert np.array_equal(out_a[: cut + 1], out_b[: cut + 1])
    if name != "none":
        assert not np.array_equal(out_a, out_b)


def test_the_delay_line_delays_by_whole_frames():
    """Delayed(source, n) returns what the source gave n frames earlier, zeros before."""

    class Counter(VelocitySource):
        def __init__(self):
            self.k = 0

        def update(self, t_s, handle_m, intent_v):
            self.k += 1
            return float(self.k), -float(self.k)

    line = Delayed(Counter(), 5)
    out = [line.update(0.0, None, None) for _ in range(12)]
    assert out[:5] == [(0.0, 0.0)] * 5 and out[5:] == [(float(k), -float(k)) for k in range(1, 8)]


def test_every_source_but_truth_is_behind_the_latency():
    """make_source puts a round(latency * rate)-frame delay line before every source except truth."""
    for name in SOURCE_NAMES:
        source = make_source(name, latency_s=0.07, rate_hz=RATE_HZ)
        if name in ("truth",):
            assert not isinstance(source, Delayed)
        else:
            assert isinstance(source, Delayed) and source.frames == 7


@pytest.mark.parametrize("name", ["lowpass-0.5hz", "lowpass-1hz", "lowpass-2hz"])
def test_a_low_pass_passes_a_constant_velocity(name):
    """A handle moving at a constant velocity comes out of the low-pass at that velocity (unit DC gain)."""
    source = make_source(name, latency_s=0.0, rate_hz=RATE_HZ)
    v = None
    for k in range(2000):
        t = k / RATE_HZ
        v = source.update(t, np.array([1.1 * t, -0.4 * t, 1.0]), (0.0, 0.0))
    assert v == pytest.approx((1.1, -0.4), abs=1e-6)


def test_the_yoyogait_source_gives_the_walking_velocity_without_the_oscillation():
    """On a synthetic hand, yoyogait's velocity oscillates far less than the raw one and is near the walking speed."""
    t, hand, intent = _hand_frames(12.0)
    walk = make_walk(SUBJECTS[0], "1-straight", duration_s=12.0, dropouts=False, rate_hz=RATE_HZ)
    walk_t, walk_theta = walk.truth.time_s, walk.truth.theta_rad
    raw = make_source("raw", latency_s=0.0, rate_hz=RATE_HZ)
    yo = make_source("yoyogait", latency_s=0.0, rate_hz=RATE_HZ)
    vr = np.array([raw.update(t[k], hand[k], intent[k]) for k in range(len(t))])
    vy = np.array([yo.update(t[k], hand[k], intent[k]) for k in range(len(t))])
    late = t > 6.0
    speed = SUBJECTS[0].speed_mps
    assert abs(np.median(vy[late, 0]) - speed) < 0.1
    theta = np.interp(t, walk_t, walk_theta)
    step_yo = harmonic_rms(t, vy, theta, (1, 2), late)
    step_raw = harmonic_rms(t, vr, theta, (1, 2), late)
    assert step_yo < 0.2 * step_raw


def test_the_gate_follows_the_valid_flag():
    """usable() is the estimate's valid flag, not its walking detector."""
    assert usable(SimpleNamespace(walking=True, valid=True))
    assert not usable(SimpleNamespace(walking=True, valid=False))
