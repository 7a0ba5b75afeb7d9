"""The metrics measure what they say: the oscillation at the gait's harmonics, the lag, the path error sideways."""

from __future__ import annotations

import math

import numpy as np
import pytest

from yoyogait.guidance import GuidePath
from yoyogait.guidance.metrics import _lag_s, harmonic_rms


def _gait(seconds: float = 30.0, rate_hz: float = 100.0):
    t = np.arange(int(seconds * rate_hz)) / rate_hz
    f = 1.7 + 0.3 * np.sin(2 * np.pi * t / 20.0)  # the cadence changes
    theta = 2 * np.pi * np.cumsum(f) / rate_hz
    return t, theta


@pytest.mark.parametrize("k, amplitude", [(1, 2.0), (2, 0.5), (0.5, 1.0)])
def test_harmonic_rms_finds_the_amplitude_at_its_harmonic(k, amplitude):
    """A sinusoid of amplitude A at k theta on a constant offset has RMS A / sqrt(2) at k, and about none at other k."""
    t, theta = _gait()
    values = 5.0 + amplitude * np.cos(k * theta + 0.4)
    inner = (t > 3) & (t < 27)
    assert harmonic_rms(t, values, theta, (k,), inner) == pytest.approx(amplitude / math.sqrt(2), rel=0.02)
    other = 3 if k != 3 else 1
    assert harmonic_rms(t, values, theta, (other,), inner) < 0.02 * amplitude


def test_the_lag_is_the_delay_of_the_slow_part():
    """A signal delayed by 0.3 s with a strong step oscillation on it has a lag of 0.3 s."""
    t, theta = _gait()
    slow = np.column_stack([1.0 + 0.4 * np.tanh((t - 10.0) / 1.5), 0.2 * np.sin(2 * np.pi * t / 12.0)])
    delayed = np.column_stack([np.interp(t - 0.3, t, slow[:, j]) for j in range(2)])
    delayed[:, 0] += 0.3 * np.cos(theta)
    assert _lag_s(t, delayed, slow, t > 1.0) == pytest.approx(0.3, abs=0.011)


def test_the_path_error_is_sideways_beyond_the_goal():
    """Past the goal on the extended path the error is zero (ends extended); beside the path it is the offset."""
    path = GuidePath("l", np.array([[0.0, 0.0], [4.0, 0.0], [4.0, 3.0]]), np.ones(3), np.zeros(3))
    points = np.array([[4.0, 4.0], [4.2, 4.0], [2.0, -0.3]])
    assert np.allclose(path.distance(points, extend_ends=True), [0.0, 0.2, 0.3])
    assert path.distance(points)[0] == pytest.approx(1.0)
