"""The baselines: the adaptive frequency oscillator and the offline sliding DFT."""

from __future__ import annotations

import numpy as np
import pytest

from yoyogait import yoyo_model
from yoyogait.estimators.oscillator import AdaptiveOscillator, OscillatorConfig, run_oscillator
from yoyogait.estimators.sliding_dft import sliding_dft

T = 0.04


def walk(seconds=30.0, f_hz=1.9, R_m=0.11, r_m=0.02, offset=np.pi, noise=0.01, seed=0):
    """Eq. 3-4 at 25 Hz with the forward oscillation shifted by ``offset`` (real data: pi)."""
    t = np.arange(int(seconds / T)) * T
    m = yoyo_model(t, R_m, r_m, f_hz)
    w = 2 * np.pi * f_hz
    vx = R_m * w + r_m * w * np.cos(m.theta_rad + offset)
    rng = np.random.default_rng(seed)
    return t, vx + noise * rng.standard_normal(t.size), m.vz_mps + noise * rng.standard_normal(t.size)


@pytest.mark.parametrize("f_hz", [1.3, 1.9, 2.3])
def test_oscillator_locks_on_the_step_frequency(f_hz):
    """Started at 1.8 Hz, the oscillator's frequency settles within 2 % of the step frequency."""
    t, vx, vz = walk(f_hz=f_hz)
    res = run_oscillator(t, vx, vz)
    late = t > 20
    assert np.all(np.abs(res.step_frequency_hz[late] - f_hz) < 0.02 * f_hz)
    assert np.median(np.abs(res.speed_mps[late] - 0.11 * 2 * np.pi * f_hz)) < 0.05


def test_oscillator_skips_missing_samples_and_streams_like_the_batch():
    """NaN samples leave the oscillator finite, and step() in a loop equals run_oscillator()."""
    t, vx, vz = walk(seconds=10)
    vx[50:60] = np.nan
    vz[55:70] = np.nan
    res = run_oscillator(t, vx, vz, predict_ahead_s=(0.2,))
    osc = AdaptiveOscillator()
    streamed = [osc.step(a, b, None if i == 0 else T) for i, (a, b) in enumerate(zip(vx, vz))]
    np.testing.assert_allclose(
        np.array(streamed), np.column_stack([res.vx_hat_mps, res.vz_hat_mps]), rtol=0, atol=1e-12
    )
    assert np.all(np.isfinite(res.vx_hat_mps)) and np.all(np.isfinite(res.step_frequency_hz))


def test_oscillator_rejects_bad_config():
    """Bounds in the wrong order or no harmonic are errors."""
    with pytest.raises(ValueError):
        OscillatorConfig(f_min_hz=3.0, f_max_hz=1.0)
    with pytest.raises(ValueError):
        OscillatorConfig(n_harmonics=0)


def test_sliding_dft_recovers_frequency_speed_and_radii():
    """Away from the ends, the sliding DFT gives f within 0.5 %, speed within 1 %, R within 3 % and r within 6 %."""
    t, vx, vz = walk(f_hz=1.7, noise=0.02)
    res = sliding_dft(t, vx, vz)
    mid = (t > 3) & (t < t[-1] - 3)
    assert np.all(np.abs(res.step_frequency_hz[mid] - 1.7) < 0.005 * 1.7)
    assert np.all(np.abs(res.speed_mps[mid] - 0.11 * 2 * np.pi * 1.7) < 0.01 * 1.17)
    assert np.all(np.abs(res.R_m[mid] - 0.11) < 0.03 * 0.11)
    # 0.02 m/s noise on a 4 s window: amplitude std ~1.3 % of 0.21 m/s, so extremes near 4 %.
    assert np.all(np.abs(res.r_m[mid] - 0.02) < 0.06 * 0.02)


def test_sliding_dft_takes_the_subharmonic_of_a_double_bump():
    """When v_z rises twice per step (strong 2nd harmonic), the step frequency is the fundamental."""
    t, vx, vz = walk(f_hz=1.2, noise=0.005)
    theta = 2 * np.pi * 1.2 * t
    vz = 0.03 * np.sin(theta) + 0.05 * np.sin(2 * theta + 0.3)
    res = sliding_dft(t, vx, vz)
    mid = (t > 3) & (t < t[-1] - 3)
    assert np.all(np.abs(res.step_frequency_hz[mid] - 1.2) < 0.02)


def test_sliding_dft_leaves_long_gaps_unknown():
    """Samples whose window is mostly missing are NaN, not invented."""
    t, vx, vz = walk()
    vx[200:400] = np.nan
    vz[200:400] = np.nan
    res = sliding_dft(t, vx, vz)
    assert np.isnan(res.step_frequency_hz[300])
    assert np.isfinite(res.step_frequency_hz[100])
