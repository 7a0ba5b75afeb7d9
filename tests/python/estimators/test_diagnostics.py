"""Diagnostics of both estimators, as FilterPy exposes them: per-step innovations and NIS."""

from __future__ import annotations

import math

import numpy as np
import pytest
from test_default_estimator import _hard_scenario

import reference_default as ref
import yoyogait
from reference_ekf import reference_paper_estimator
from yoyogait import EstimatorConfig, GaitEstimator, _core

T = 0.04
DIAG = ("innovation_vx_mps", "innovation_vz_mps", "nis")


def _noisy_walk(n=3000, seed=1):
    rng = np.random.default_rng(seed)
    t = np.arange(n) * T
    m = yoyogait.yoyo_model(t, 0.12, 0.025, 1.8 + 0.3 * np.sin(2 * np.pi * t / 60.0))
    vx = m.vx_mps + 0.08 * rng.standard_normal(n)
    vz = m.vz_mps + 0.05 * rng.standard_normal(n)
    vx[[i for i in (100, 101, 2000) if i < n]] = np.nan
    return t, vx, vz


def _model_walk(seed, noise_mps=0.05, seconds=60.0):
    """A walk drawn from the default filter's own stochastic model (as in the coverage test of
    test_default_estimator.py): cadence random walk at q_omega, 2 % step-time jitter, 10 % amplitude
    variation, a second harmonic, and white measurement noise of noise_mps on both channels."""
    rng = np.random.default_rng(seed)
    n = int(seconds / T)
    t = np.arange(n) * T
    w = 2 * np.pi * 1.8 + np.concatenate([[0.0], np.cumsum(np.sqrt(0.05 * T) * rng.standard_normal(n - 1))])
    w = np.clip(w, 2 * np.pi * 1.2, 2 * np.pi * 2.4)
    theta = np.concatenate([[0.0], np.cumsum(0.5 * (w[1:] + w[:-1]) * T)]) + rng.uniform(0, 2 * np.pi)
    theta += np.cumsum(np.sqrt(0.03 * T) * rng.standard_normal(n))
    k = int(2.0 / T)
    a1 = 0.02 * w * (1 + 0.1 * np.convolve(rng.standard_normal(n + k), np.ones(k) / np.sqrt(k), "valid")[:n])
    R = 1.3 / (2 * np.pi * 1.8)
    noise = noise_mps * rng.standard_normal((2, n))
    vx = np.abs(R * w + a1 * np.cos(theta + np.pi) + 0.25 * a1 * np.cos(2 * theta + 1.0) + noise[0])
    vz = -a1 * np.sin(theta) + 0.25 * a1 * np.cos(2 * theta + 2.0) + noise[1]
    return t, vx, vz


def test_paper_innovations_and_nis_equal_the_numpy_reference():
    """Paper: innovation = z - H x- at the prediction and NIS = y^T S^-1 y, as the numpy reference
    computes them (1e-9), NaN where a sample was not used."""
    _, vx, vz = _noisy_walk()
    res = GaitEstimator(EstimatorConfig.paper()).run(vx, vz, diagnostics=True)
    r = reference_paper_estimator(vx, vz)
    np.testing.assert_allclose(res.innovation_vx_mps, r["innovation"][:, 0], rtol=1e-9, atol=1e-12)
    np.testing.assert_allclose(res.innovation_vz_mps, r["innovation"][:, 1], rtol=1e-9, atol=1e-12)
    np.testing.assert_allclose(res.nis, r["nis"], rtol=1e-8, atol=1e-12)
    assert np.isnan(res.nis[[100, 101, 2000]]).all() and np.isfinite(np.delete(res.nis, [100, 101, 2000])).all()


def test_default_innovations_and_nis_equal_the_numpy_reference():
    """Default: the innovation of each channel and the NIS equal the numpy reference's (1e-9) over the
    hard walk (bank, stops, gaps, NaN, outliers, jitter): rejected outliers too, NaN for unused channels."""
    s = _hard_scenario()
    dt = np.diff(s["t"], prepend=np.nan)
    r = ref.run_reference(s["vx"], s["vz"], dt, ref.config_from(EstimatorConfig().to_native()))
    res = GaitEstimator().run(s["vx"], s["vz"], time_s=s["t"], diagnostics=True)
    for name in DIAG:
        got, want = getattr(res, name), r[name]
        assert np.array_equal(np.isnan(got), np.isnan(want)), name
        np.testing.assert_allclose(got, want, rtol=1e-9, atol=1e-9, err_msg=name)
    outlier = res.status == int(_core.Status.REJECTED_OUTLIER)
    assert outlier.sum() >= 10 and np.all(res.nis[outlier] > 25.0)  # the gate: nu^2 > 5^2 S on a channel
    standing = ~res.walking
    assert standing.any() and np.isnan(res.innovation_vz_mps[standing]).all()


def test_default_innovation_is_measurement_minus_predicted_measurement():
    """Default without harmonics, walking after the bank: innovation_vx = vx - (A0 + X1) at the
    transition of the previous posterior (computed here with the transition itself)."""
    cfg = EstimatorConfig()
    cfg.gait_filter.use_harmonic = False
    gcfg = cfg.gait_filter
    t, vx, vz = _model_walk(3, seconds=20.0)
    est = GaitEstimator(cfg)
    checked = 0
    prev = None
    for k in range(t.size):
        e = est.step(vx[k], vz[k], diagnostics=True)
        if prev is not None and e.walking and not e.acquiring and prev[1]:
            a, b = math.exp(-T / gcfg.accel_tau_s), math.exp(-T / gcfg.omega_rate_tau_s)
            x = _core.gait_transition(prev[0], T, a, b)
            assert e.innovation_vx_mps == pytest.approx(vx[k] - (x[5] + x[0]), abs=1e-12), k
            checked += 1
        prev = (list(e.gait_state), e.walking and not e.acquiring)
    assert checked > 400


def test_nis_of_the_default_is_consistent_on_a_walk_from_its_own_model():
    """On walks from the filter's own stochastic model with its measurement noise (0.05 m/s), the
    mean NIS is within 20 % of 2 (the two channels) and 2-10 % of samples exceed the chi-square(2)
    95 % point; with the measurement noise stated 2x too large or too small it is not."""

    def nis(meas_std):
        cfg = EstimatorConfig()
        # the std at the nominal 25 Hz: R = density / dt
        density = meas_std**2 * cfg.sample_time_s
        cfg.gait_filter.meas_vx_density_m2_per_s = cfg.gait_filter.meas_vz_density_m2_per_s = density
        out = []
        for seed in range(2):
            t, vx, vz = _model_walk(seed)
            out.append(GaitEstimator(cfg).run(vx, vz, time_s=t, diagnostics=True).nis[t > 5.0])
        return np.concatenate(out)

    def in_band(mean_nis: float) -> bool:
        return 1.6 <= mean_nis <= 2.4  # chi-square with 2 degrees of freedom: mean 2

    consistent = nis(0.05)
    assert in_band(consistent.mean()), consistent.mean()
    outside_95 = np.mean(consistent > 5.991)
    assert outside_95 >= 0.02 and outside_95 <= 0.10, outside_95
    assert not in_band(nis(0.1).mean())
    assert not in_band(nis(0.025).mean())


@pytest.mark.parametrize("preset", ["paper", "default"])
def test_streaming_batch_and_chunked_diagnostics_agree_bit_for_bit(preset):
    """step(diagnostics=True), run(diagnostics=True) and a chunked run give the same diagnostics exactly,
    and the estimates are the same with and without diagnostics."""
    t, vx, vz = _noisy_walk(n=600)
    cfg = EstimatorConfig.preset(preset)
    full = GaitEstimator(cfg).run(vx, vz, time_s=t, diagnostics=True)
    plain = GaitEstimator(cfg).run(vx, vz, time_s=t)
    assert plain.nis is None and plain.innovation_vx_mps is None
    assert np.array_equal(full.step_frequency_hz, plain.step_frequency_hz)
    chunked = GaitEstimator(cfg)
    parts = [chunked.run(vx[a:b], vz[a:b], time_s=t[a:b], diagnostics=True) for a, b in ((0, 250), (250, 600))]
    stream = GaitEstimator(cfg)
    steps = [stream.step(vx[k], vz[k], None if k == 0 else t[k] - t[k - 1], diagnostics=True) for k in range(t.size)]
    for name in DIAG:
        a = np.asarray(getattr(full, name))
        np.testing.assert_array_equal(a, np.concatenate([getattr(p, name) for p in parts]), err_msg=name)
        np.testing.assert_array_equal(a, np.array([getattr(e, name) for e in steps]), err_msg=name)
    assert np.array_equal(full.step_frequency_hz, np.array([e.step_frequency_hz for e in steps]))
