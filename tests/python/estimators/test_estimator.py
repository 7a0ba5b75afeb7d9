"""The paper's estimator through the Python API: exactness, convergence, gating, forms, bad input."""

from __future__ import annotations

import dataclasses

import numpy as np
import pytest

import yoyogait
from reference_ekf import reference_paper_estimator
from yoyogait import EstimatorConfig, GaitEstimator, _core
from yoyogait.estimators import Status

T = 0.04


def yoyo_walk(seconds=30.0, f_hz=1.8, R_m=0.115, r_m=0.02, noise=0.0, seed=0):
    t = np.arange(1, int(round(seconds / T)) + 1) * T
    m = yoyogait.yoyo_model(t, R_m, r_m, f_hz)
    rng = np.random.default_rng(seed)
    return t, m.vx_mps + noise * rng.standard_normal(t.size), m.vz_mps + noise * rng.standard_normal(t.size)


def test_native_matches_numpy_reference_to_1e12():
    """The native core equals an independent numpy implementation of eq. 5-14 to 1e-12 over 10,000 noisy samples."""
    rng = np.random.default_rng(42)
    t = np.arange(10_000) * T
    f = 1.8 + 0.3 * np.sin(2 * np.pi * t / 120.0)
    m = yoyogait.yoyo_model(t, 0.12, 0.025, f)
    vx = m.vx_mps + 0.1 * rng.standard_normal(t.size)
    vz = m.vz_mps + 0.05 * rng.standard_normal(t.size)
    vx[[500, 501, 7000]] = np.nan  # prediction-only samples take the same path in both
    ref = reference_paper_estimator(vx, vz)
    res = GaitEstimator(EstimatorConfig.paper()).run(vx, vz)
    np.testing.assert_allclose(res.state, ref["state"], rtol=0, atol=1e-12)
    np.testing.assert_allclose(res.R_hat_mps, ref["R_hat"], rtol=0, atol=1e-12)
    np.testing.assert_allclose(res.r_hat_mps, ref["r_hat"], rtol=0, atol=1e-12)
    np.testing.assert_allclose(res.vx_hat_mps, ref["vx_hat_mps"], rtol=0, atol=1e-12)
    np.testing.assert_allclose(res.vz_hat_mps, ref["vz_hat_mps"], rtol=0, atol=1e-12)
    assert np.all(res.parameters_updated[:10] == 0)
    assert res.parameters_updated.sum() > 5000  # the comparison covered the update branch of eq. 11-12


def test_paper_preset_converges_on_clean_yoyo_walk():
    """On eq. 3-4 at 25 Hz (1.8 Hz, R = 0.115 m, r = 0.02 m) f is within 1 % and R_m, r_m within 5 % after 10 s."""
    t, vx, vz = yoyo_walk()
    res = GaitEstimator(EstimatorConfig.paper()).run(vx, vz)
    after = t >= 10.0
    assert np.all(np.abs(res.step_frequency_hz[after] - 1.8) <= 0.018)
    assert np.all(np.abs(res.R_m[after] - 0.115) <= 0.05 * 0.115)
    assert np.all(np.abs(res.r_m[after] - 0.02) <= 0.05 * 0.02)
    np.testing.assert_allclose(res.omega_rad_s, res.state[:, 2] / T)
    np.testing.assert_allclose(res.speed_mps, res.R_m * res.omega_rad_s, rtol=1e-12)


def test_physical_units_follow_from_the_papers():
    """Paper preset: R_m = T R_hat, r_m = T r_hat, f = x3 / (2 pi T) and A1 = |(x1, x2)| on every sample."""
    _, vx, vz = yoyo_walk(10.0, noise=0.05)
    res = GaitEstimator(EstimatorConfig.paper()).run(vx, vz)
    assert res.parameters_updated.any(), "the comparison must cover samples where eq. 11-12 updated R_hat"
    np.testing.assert_allclose(res.R_m, T * res.R_hat_mps, rtol=1e-15)
    np.testing.assert_allclose(res.r_m, T * res.r_hat_mps, rtol=1e-15)
    np.testing.assert_allclose(res.step_frequency_hz, res.state[:, 2] / (2 * np.pi * T), rtol=1e-15)
    np.testing.assert_allclose(res.A1_mps, np.hypot(res.state[:, 0], res.state[:, 1]), rtol=1e-14)


def test_parameters_hold_while_frequency_below_gate():
    """While x3 <= mu_w (a 0.3 Hz sway at 1 m/s), R_hat and r_hat keep their last value (eq. 11-12)."""
    _, vx, vz = yoyo_walk(20.0)
    _, slow_vx, slow_vz = yoyo_walk(40.0, f_hz=0.3, R_m=0.5, r_m=0.1)
    res = GaitEstimator(EstimatorConfig.paper()).run(np.concatenate([vx, slow_vx]), np.concatenate([vz, slow_vz]))
    closed = res.state[:, 2] <= 0.1
    assert closed[-500:].all(), "the slow sway must bring x3 below mu_w"
    assert np.all(res.state[-500:, 3] > 0.1), "while A0 stays above mu_A0"
    changed = np.diff(res.R_hat_mps) != 0
    assert not np.any((changed | (np.diff(res.r_hat_mps) != 0)) & closed[1:])
    assert not np.any(res.parameters_updated & closed)
    assert np.any(changed[: vx.size])


def test_parameters_hold_while_standing():
    """While the person stands, A0 falls to mu_A0 or below and R_hat, r_hat hold (eq. 11-12)."""
    _, vx, vz = yoyo_walk(20.0)
    stand = np.zeros(250)
    res = GaitEstimator(EstimatorConfig.paper()).run(np.concatenate([vx, stand]), np.concatenate([vz, stand]))
    closed = (res.state[:, 2] <= 0.1) | (res.state[:, 3] <= 0.1)
    assert closed[-200:].all()
    assert not np.any((np.diff(res.R_hat_mps) != 0) & closed[1:])
    assert res.R_hat_mps[-1] == res.R_hat_mps[-200]


def test_streaming_batch_and_chunked_agree_bit_for_bit():
    """step() in a loop, one run() and run() in uneven chunks give identical results."""
    _, vx, vz = yoyo_walk(20.0, noise=0.08, seed=3)
    vx[100] = np.nan
    batch = GaitEstimator().run(vx, vz)
    est = GaitEstimator()
    streamed = [est.step(a, b) for a, b in zip(vx, vz)]
    assert np.array_equal(np.array([e.state for e in streamed]), batch.state)
    assert np.array_equal(np.array([e.vx_hat_mps for e in streamed]), batch.vx_hat_mps)
    assert np.array_equal(np.array([e.R_m for e in streamed]), batch.R_m)
    est = GaitEstimator()
    edges = [0, 1, 7, 100, 101, 333, vx.size]
    chunks = [est.run(vx[a:b], vz[a:b]) for a, b in zip(edges[:-1], edges[1:])]
    for name in ("state", "vx_hat_mps", "vz_hat_mps", "R_m", "r_m", "step_frequency_hz", "status"):
        assert np.array_equal(np.concatenate([getattr(c, name) for c in chunks]), getattr(batch, name)), name


@pytest.mark.parametrize("preset", ["paper", "default"])
def test_run_results_survive_later_runs_that_reuse_memory(preset):
    """A kept result is never overwritten by later runs; a run into reused memory equals a fresh one."""
    _, vx, vz = yoyo_walk(60.0, noise=0.05, seed=5)
    cfg = EstimatorConfig.preset(preset)
    kept = GaitEstimator(cfg).run(vx, vz)
    kept_copy = {k: np.array(getattr(kept, k), copy=True) for k in ("state", "vx_hat_mps", "R_m", "status")}
    for seed in range(3):  # freed results hand their memory to the next run
        _, wx, wz = yoyo_walk(60.0, noise=0.2, seed=10 + seed)
        other = GaitEstimator(cfg).run(wx, wz)
        del other
    again = GaitEstimator(cfg).run(vx, vz)
    for name, value in kept_copy.items():
        assert np.array_equal(getattr(kept, name), value), name
        assert np.array_equal(getattr(again, name), value), name
    assert not np.shares_memory(kept.vx_hat_mps, again.vx_hat_mps)


def test_nan_sample_is_prediction_only_and_flagged():
    """A NaN or infinite sample skips the update and is flagged; the state stays finite."""
    _, vx, vz = yoyo_walk(5.0, noise=0.05)
    vx[[10, 20]] = np.nan
    vz[30] = np.inf
    res = GaitEstimator(EstimatorConfig.paper()).run(vx, vz)
    assert set(np.flatnonzero(res.status == int(Status.REJECTED_NON_FINITE))) == {10, 20, 30}
    assert np.all(np.isfinite(res.state))
    ok = GaitEstimator(EstimatorConfig.paper()).run(vx[:10], vz[:10])
    predicted = _core.transition(ok.state[-1].tolist())
    np.testing.assert_array_equal(res.state[10], predicted)


def _min_eigenvalues(cov):
    return np.linalg.eigvalsh(cov)[:, 0]


def test_covariance_stays_positive_definite_on_the_five_sample_reproducer():
    """(0, 0), (-3, 999.90625), (0, NaN), (0, 0), (0, 0) (before the guard: P44 = -0.0038 and a NaN
    speed std at the last sample): P is positive definite and every std finite after each sample."""
    res = GaitEstimator(EstimatorConfig.paper()).run([0, -3, 0, 0, 0], [0, 999.90625, np.nan, 0, 0], covariance=True)
    assert np.all(_min_eigenvalues(res.covariance) > 0)
    assert np.all(np.isfinite(res.speed_std_mps)) and np.all(np.isfinite(res.step_frequency_std_hz))
    assert np.array_equal(res.covariance, res.covariance.transpose(0, 2, 1))


def test_covariance_stays_positive_definite_across_long_dropouts():
    """2,501 NaN samples, 30 of a 1.4 Hz walk, 5,025 NaN, 2 more, for 96 walks (speed 1 or 1.5 m/s,
    r 0.012 or 0.025 m, 24 phases; 3 of them lost positive definiteness before the guard): P stays
    positive definite and both standard deviations finite."""
    w = 2 * np.pi * 1.4
    th0 = w * T * np.arange(32)
    nan = lambda n: np.full(n, np.nan)  # noqa: E731
    for speed in (1.0, 1.5):
        for r in (0.012, 0.025):
            for phase in np.linspace(0, 2 * np.pi, 24, endpoint=False):
                vx = speed + r * w * np.cos(th0 + phase)
                vz = -r * w * np.sin(th0 + phase)
                res = GaitEstimator(EstimatorConfig.paper()).run(
                    np.concatenate([nan(2501), vx[:30], nan(5025), vx[30:]]),
                    np.concatenate([nan(2501), vz[:30], nan(5025), vz[30:]]),
                    covariance=True,
                )
                assert np.all(_min_eigenvalues(res.covariance) > 0), (speed, r, phase)
                assert np.all(np.isfinite(res.step_frequency_std_hz)) and np.all(np.isfinite(res.speed_std_mps))


def test_variance_bounds_match_the_reference_over_a_long_dropout():
    """Over 20 s of walking and 15,000 NaN samples the variances reach their bounds (pi^2 for x3,
    1000^2 for x2) in the native core and in the numpy reference alike (to 1e-9 of the largest entry)."""
    _, vx, vz = yoyo_walk(20.0, noise=0.05, seed=8)
    vx = np.concatenate([vx, np.full(15000, np.nan)])
    vz = np.concatenate([vz, np.full(15000, np.nan)])
    ref = reference_paper_estimator(vx, vz)
    res = GaitEstimator(EstimatorConfig.paper()).run(vx, vz, covariance=True)
    scale = np.abs(ref["P"]).max(axis=(1, 2))
    assert np.all(np.abs(res.covariance - ref["P"]).max(axis=(1, 2)) <= 1e-9 * scale)
    np.testing.assert_allclose(res.state, ref["state"], rtol=0, atol=1e-9)
    assert res.covariance[-1, 2, 2] == np.pi**2 and res.covariance[-1, 1, 1] == 1e6
    assert np.all(_min_eigenvalues(res.covariance) > 0)


def test_status_precedence_non_finite_then_out_of_range():
    """A sample with a NaN (or infinite) channel and an out-of-range one is REJECTED_NON_FINITE; one
    out of range and finite is REJECTED_OUT_OF_RANGE; step() and run() agree."""
    vx = np.array([1.0, np.nan, 1e4, np.inf, 1.0, -2e3])
    vz = np.array([0.0, 1e4, np.nan, 1e300, 1e4, 0.0])
    want = [
        Status.UPDATED,
        Status.REJECTED_NON_FINITE,
        Status.REJECTED_NON_FINITE,
        Status.REJECTED_NON_FINITE,
        Status.REJECTED_OUT_OF_RANGE,
        Status.REJECTED_OUT_OF_RANGE,
    ]
    res = GaitEstimator(EstimatorConfig.paper()).run(vx, vz)
    assert list(res.status) == [int(s) for s in want]
    est = GaitEstimator(EstimatorConfig.paper())
    assert [est.step(a, b).status for a, b in zip(vx, vz)] == want


def test_extreme_values_never_make_state_non_finite():
    """Huge samples are rejected as out of range and the state and covariance stay finite."""
    est = GaitEstimator()
    res = est.run(np.array([1e308, -1e300, 1e5, 1.0, np.nan]), np.array([-1e308, 1e300, 0.0, 0.0, 1.0]))
    assert list(res.status[:3]) == [int(Status.REJECTED_OUT_OF_RANGE)] * 3
    assert np.all(np.isfinite(res.state)) and np.all(np.isfinite(est.covariance))


@pytest.mark.parametrize(
    "change, message",
    [
        ({"sample_time_s": 0.0}, "sample_time_s"),
        ({"sample_time_s": -0.04}, "sample_time_s"),
        ({"sample_time_s": 5e-324}, "sample_time_s"),
        ({"p0_bias_mps2": 1e300}, "paper_estimator.p0_bias_mps2"),
        ({"smoothing_window_samples": 2**64}, "smoothing_window_samples"),
        ({"v_vx_mps2": 0.0}, "v_vx_mps2"),
        ({"q_omega_rad2": float("nan")}, "q_omega_rad2"),
        ({"smoothing_window_samples": -1}, "smoothing_window_samples"),
        ({"smoothing_window_samples": 1000}, "smoothing_window_samples"),
        ({"smoothing_window_samples": 2.5}, "smoothing_window_samples"),
        ({"gate_bias_mps": "high"}, "gate_bias_mps"),
    ],
)
def test_invalid_config_is_an_error_at_construction(change, message):
    """A malformed configuration raises ValueError naming the field when the estimator is built."""
    cfg = EstimatorConfig.paper()
    shared = {k: v for k, v in change.items() if k == "sample_time_s"}
    section = {k: v for k, v in change.items() if k != "sample_time_s"}
    cfg = dataclasses.replace(cfg, **shared, paper_estimator=dataclasses.replace(cfg.paper_estimator, **section))
    with pytest.raises(ValueError, match=message):
        GaitEstimator(cfg)


def test_mismatched_or_multidimensional_arrays_raise():
    """run() raises ValueError naming the problem for arrays of different lengths or wrong dimension."""
    est = GaitEstimator()
    with pytest.raises(ValueError, match="same length"):
        est.run(np.zeros(5), np.zeros(6))
    with pytest.raises(ValueError, match="vx must be one-dimensional"):
        est.run(np.zeros((5, 2)), np.zeros(5))
    with pytest.raises(ValueError, match="vz must be one-dimensional"):
        est.run(np.zeros(5), 3.0)
    assert est.sample_count == 0


def test_python_config_mirrors_the_cpp_struct():
    """Every field of the C++ EstimatorConfig (and of its two sections) has a Python twin with the same
    default (the default estimator) and the same paper() value, and no more."""
    native, native_paper = _core.EstimatorConfig(), _core.EstimatorConfig.paper()
    default, paper = EstimatorConfig(), EstimatorConfig.paper()
    assert default.algorithm == "gait_filter" and paper.algorithm == "paper"

    def public(obj):
        return {n for n in dir(obj) if not n.startswith("_") and n not in ("paper", "validate")}

    assert public(native) == {f.name for f in dataclasses.fields(EstimatorConfig)}
    for section in ("paper_estimator", "gait_filter"):
        names = {f.name for f in dataclasses.fields(getattr(default, section))}
        assert public(getattr(native, section)) == names, section
        for name in names:
            assert getattr(getattr(native, section), name) == getattr(getattr(default, section), name), name
            assert getattr(getattr(native_paper, section), name) == getattr(getattr(paper, section), name), name
        assert getattr(paper, section) == getattr(default, section)  # paper() changes the algorithm only
    for name in ("algorithm", "sample_time_s", "max_abs_velocity_mps"):
        assert getattr(native, name) == getattr(default, name) and getattr(native_paper, name) == getattr(paper, name)


def test_prediction_ahead_is_aligned_to_the_sample_it_predicts():
    """On a converged clean walk, the 0.2 s-ahead prediction aligned to its target equals the signal."""
    t, vx, vz = yoyo_walk(30.0)
    res = GaitEstimator().run(vx, vz, predict_ahead_s=(0.04, 0.2))
    pvx, pvz = res.aligned_prediction(0.2)
    assert np.isnan(pvx[:5]).all() and np.isfinite(pvx[5:]).all()
    late = t > 20
    assert np.max(np.abs(pvx[late] - vx[late])) < 0.01
    assert np.max(np.abs(pvz[late] - vz[late])) < 0.01
    with pytest.raises(ValueError):
        res.aligned_prediction(0.5)


def test_prediction_is_aligned_by_real_time_on_irregular_samples():
    """With irregular time_s the 0.2 s-ahead prediction is placed at the time it predicts, not 5 samples later."""
    t_reg, vx, vz = yoyo_walk(30.0)
    rng = np.random.default_rng(1)
    t = np.cumsum(rng.uniform(0.02, 0.06, t_reg.size))  # 25 Hz on average, jittered
    phase = 2 * np.pi * np.cumsum(np.r_[0.0, np.diff(t)]) * 1.8
    vx, vz = 1.3 + 0.1 * np.cos(phase), 0.08 * np.sin(phase)
    res = GaitEstimator().run(vx, vz, time_s=t, predict_ahead_s=(0.2,))
    pvx, pvz = res.aligned_prediction(0.2)
    late = t > 20
    assert np.nanmax(np.abs(pvz[late] - vz[late])) < 0.02
    # Sample-count alignment (5 samples of the nominal 0.04 s) puts it at the wrong time here.
    shifted = np.full_like(vz, np.nan)
    shifted[5:] = res.vz_pred[:-5, 0]
    assert np.nanmax(np.abs(shifted[late] - vz[late])) > 0.05


def test_sample_counting_settings_are_durations():
    """spectral_buffer_s and gate_max_consecutive_s give 40 and 6 samples at 25 Hz and the same durations at 50 Hz."""
    from reference_default import DefaultConfig

    at25, at50 = DefaultConfig(), DefaultConfig(nominal_dt_s=0.02)
    assert (at25.spec_buffer_n, at25.max_consecutive_rejects) == (40, 6)
    assert (at50.spec_buffer_n, at50.max_consecutive_rejects) == (80, 12)
    cfg = EstimatorConfig()
    cfg.sample_time_s = 0.02
    GaitEstimator(cfg)  # 80 samples fit the buffer
    cfg.sample_time_s = 0.004  # 1.6 s would need 400 samples
    with pytest.raises(ValueError, match="spectral_buffer_s"):
        GaitEstimator(cfg)
