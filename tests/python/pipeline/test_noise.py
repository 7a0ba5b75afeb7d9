"""The velocity noise a recording's own samples show (pipeline/noise.py)."""

from __future__ import annotations

import numpy as np

from yoyogait.pipeline.noise import velocity_noise_var

RATE_HZ = 25.0


def _gait(n: int = 500) -> np.ndarray:
    t = np.arange(n) / RATE_HZ
    return 1.3 + 0.2 * np.sin(2 * np.pi * 1.8 * t) + 0.05 * np.sin(2 * np.pi * 3.6 * t + 0.4)


def test_gait_alone_shows_no_noise():
    """A walking velocity (step frequency and its harmonic, below the cutoff) shows next to no noise."""
    assert velocity_noise_var(_gait(), RATE_HZ) < 1e-4


def test_white_noise_is_measured_within_a_third():
    """White noise added to a walking velocity is estimated within a third of its variance."""
    rng = np.random.default_rng(3)
    for sigma in (0.05, 0.3, 1.0):
        v = _gait() + rng.normal(0.0, sigma, 500)
        est = velocity_noise_var(v, RATE_HZ)
        assert 2 / 3 * sigma**2 < est < 4 / 3 * sigma**2, (sigma, est)


def test_gaps_split_the_samples_into_runs():
    """NaN gaps do not spread: the estimate over runs between gaps matches the one without them."""
    rng = np.random.default_rng(4)
    v = _gait() + rng.normal(0.0, 0.3, 500)
    gappy = v.copy()
    gappy[100:110] = np.nan
    gappy[300:303] = np.nan
    gappy[495:] = np.nan  # a run too short to filter is left out
    assert np.isfinite(velocity_noise_var(gappy, RATE_HZ))
    assert abs(velocity_noise_var(gappy, RATE_HZ) / velocity_noise_var(v, RATE_HZ) - 1) < 0.15


def test_too_few_samples_or_too_low_a_rate_give_zero():
    """Nothing to measure (short, all NaN, or a rate with no band above the cutoff) gives 0, not NaN."""
    assert velocity_noise_var(np.ones(5), RATE_HZ) == 0.0
    assert velocity_noise_var(np.full(100, np.nan), RATE_HZ) == 0.0
    assert velocity_noise_var(_gait(), 12.0) == 0.0
