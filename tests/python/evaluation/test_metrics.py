"""Metrics on signals with answers that can be worked out by hand."""

from __future__ import annotations

import math
from types import SimpleNamespace

import numpy as np
import pytest

from yoyogait import synthetic as sy
from yoyogait.errors import InputError
from yoyogait.evaluation import metrics as mt

NAN = float("nan")


def test_constant_error_of_a_tenth_mps_is_one_unit():
    """A 0.1 m/s error everywhere is a squared error of 1 in 10^-2 (m/s)^2, with zero spread."""
    measured = np.linspace(-1, 1, 50)
    s = mt.squared_error_stats(measured, measured + 0.1)
    assert s.mean_1e_2 == pytest.approx(1.0)
    assert s.std_1e_2 == pytest.approx(0.0, abs=1e-12)
    assert s.n_samples == 50


def test_squared_error_mean_and_std_by_hand_ignoring_nan():
    """Errors 0.1, 0.2, 0.3 m/s (a NaN sample left out): mean and std of 0.01, 0.04, 0.09 (m/s)^2, x100."""
    measured = np.array([0.0, 1.0, 2.0, NAN, 5.0])
    estimated = np.array([0.1, 1.2, NAN, 7.0, 4.7])
    s = mt.squared_error_stats(measured, estimated)
    sq = [0.01, 0.04, 0.09]
    mean = sum(sq) / 3
    std = math.sqrt(sum((x - mean) ** 2 for x in sq) / 3)
    assert s.n_samples == 3
    assert s.mean_1e_2 == pytest.approx(100 * mean)
    assert s.std_1e_2 == pytest.approx(100 * std)


def test_squared_error_of_a_sinusoid_is_half_its_square_amplitude():
    """An error a sin(wt) over whole periods has mean square a^2/2."""
    t = np.arange(0, 10, 0.01)
    measured = np.cos(t)
    s = mt.squared_error_stats(measured, measured + 0.2 * np.sin(2 * np.pi * t))
    assert s.mean_1e_2 == pytest.approx(100 * 0.2**2 / 2, rel=1e-9)


def test_mask_leaves_out_samples():
    """Samples outside the mask (e.g. standing) do not count."""
    measured = np.zeros(4)
    estimated = np.array([0.1, 0.1, 5.0, 0.1])
    s = mt.squared_error_stats(measured, estimated, mask=[True, True, False, True])
    assert s.n_samples == 3
    assert s.mean_1e_2 == pytest.approx(1.0)


def test_nothing_to_compare_gives_nan():
    """All-NaN input gives NaN statistics and zero samples, not zero error."""
    s = mt.squared_error_stats([NAN, NAN], [1.0, NAN])
    assert math.isnan(s.mean_1e_2) and math.isnan(s.std_1e_2) and s.n_samples == 0


def test_mismatched_lengths_are_refused():
    """Arrays of different lengths are an input error, not silently truncated."""
    with pytest.raises(InputError):
        mt.squared_error_stats(np.zeros(3), np.zeros(4))
    with pytest.raises(InputError):
        mt.squared_error_stats(np.zeros(3), np.zeros(3), mask=[True, False])


def test_velocity_error_scores_each_component():
    """velocity_error reports v_x and v_z separately (Table I rows)."""
    vx, vz = np.ones(10), np.zeros(10)
    e = mt.velocity_error(vx, vz, vx + 0.3, vz - 0.1)
    assert e.vx.mean_1e_2 == pytest.approx(9.0)
    assert e.vz.mean_1e_2 == pytest.approx(1.0)


def test_prediction_error_skips_samples_without_prediction():
    """Predictions are compared sample by sample; NaN (no prediction yet) is left out."""
    vx, vz = np.arange(6.0), np.zeros(6)
    pvx = np.array([NAN, NAN, 2.2, 3.2, 4.2, 5.2])
    pvz = np.array([NAN, NAN, 0.1, -0.1, 0.1, -0.1])
    e = mt.prediction_error(vx, vz, pvx, pvz)
    assert e.vx.n_samples == 4 and e.vx.mean_1e_2 == pytest.approx(4.0)
    assert e.vz.mean_1e_2 == pytest.approx(1.0)


def test_step_frequency_median_and_p90():
    """Errors 0, 0.1, ..., 0.9 Hz: median 0.45 Hz, 90th percentile 0.81 Hz (linear interpolation)."""
    t = np.arange(10.0)
    ref = np.full(10, 1.8)
    est = ref + np.arange(10) / 10
    fe = mt.step_frequency_error(t, est[::-1], ref)
    assert fe.median_abs_hz == pytest.approx(0.45)
    assert fe.p90_abs_hz == pytest.approx(0.81)
    assert fe.wrong_sign_fraction == 0.0
    assert fe.n_samples == 10


def test_step_frequency_sign_is_scored_apart():
    """A mirrored (negative) estimate has zero magnitude error but counts as wrong sign."""
    t = np.arange(8.0)
    ref = np.full(8, 2.0)
    est = np.array([-2.0, -2.0, 2.0, 2.0, 2.0, 2.0, 2.0, 2.0])
    fe = mt.step_frequency_error(t, est, ref)
    assert fe.median_abs_hz == 0.0 and fe.p90_abs_hz == 0.0
    assert fe.wrong_sign_fraction == pytest.approx(2 / 8)
    signed = mt.step_frequency_error(t, est, ref, signed=True)
    assert signed.median_abs_hz == 0.0 and signed.p90_abs_hz == pytest.approx(4.0)  # errors of -2 - 2 Hz


def test_step_frequency_mask_and_skip():
    """Standing samples (mask) and the first skip_s seconds of walking are left out."""
    t = np.arange(0.0, 10.0, 1.0)
    ref = np.full(10, 2.0)
    est = ref.copy()
    est[:2] = 9.0  # standing: masked out
    est[2:4] = 3.0  # first 2 s of walking: skipped
    walking = t >= 2.0
    fe = mt.step_frequency_error(t, est, ref, mask=walking, skip_s=2.0)
    assert fe.n_samples == 6 and fe.median_abs_hz == 0.0 and fe.p90_abs_hz == 0.0
    fe_all = mt.step_frequency_error(t, est, ref, mask=walking)
    assert fe_all.n_samples == 8 and fe_all.p90_abs_hz == pytest.approx(1.0)


def test_convergence_time_on_a_constructed_signal():
    """Error 1 Hz until 3 s, 0.05 Hz after with a 0.2 Hz blip at 5 s: converged 5.1 s, counted from 1 s."""
    t = np.round(np.arange(0.0, 10.0, 0.1), 10)
    err = np.where(t < 3.0, 1.0, 0.05)
    err[np.isclose(t, 5.0)] = 0.2
    walking = t >= 1.0
    assert mt.convergence_time_s(t, err, 0.1, walking) == pytest.approx(5.1 - 1.0)
    fe = mt.step_frequency_error(t, 2.0 + err, np.full(t.size, 2.0), mask=walking)
    assert fe.converge_time_s == pytest.approx(4.1)


def test_convergence_edge_cases():
    """Within from the start is 0; bad at the end is inf; nothing to evaluate is NaN; NaN samples skipped."""
    t = np.arange(5.0)
    assert mt.convergence_time_s(t, np.zeros(5), 0.1) == 0.0
    assert mt.convergence_time_s(t, [0, 0, 0, 0, 1.0], 0.1) == math.inf
    assert math.isnan(mt.convergence_time_s(t, np.full(5, NAN), 0.1))
    assert math.isnan(mt.convergence_time_s(t, np.zeros(5), 0.1, mask=np.zeros(5, bool)))
    assert mt.convergence_time_s(t, [1.0, 1.0, 0.0, NAN, 0.0], 0.1) == 2.0


def test_speed_error_median_and_rms():
    """Speed errors 0.1, -0.2, 0.3 m/s (NaN left out): median |e| 0.2, RMS sqrt(0.14/3)."""
    ref = np.full(4, 1.3)
    est = ref + np.array([0.1, -0.2, 0.3, NAN])
    se = mt.speed_error(est, ref)
    assert se.n_samples == 3
    assert se.median_abs_mps == pytest.approx(0.2)
    assert se.rms_mps == pytest.approx(math.sqrt(0.14 / 3))


def test_parameter_error_after_settling():
    """Before settle_s the estimate is ignored; after it an R of 0.11 for 0.10 is 0.01 m and 10 %."""
    t = np.arange(0.0, 20.0, 0.5)
    est = np.where(t < 5.0, 2.0, 0.11)
    pe = mt.parameter_error(t, est, np.full(t.size, 0.10), settle_s=5.0)
    assert pe.median_abs_m == pytest.approx(0.01)
    assert pe.rms_m == pytest.approx(0.01)
    assert pe.median_rel == pytest.approx(0.1)
    assert pe.n_samples == np.count_nonzero(t >= 5.0)
    late = mt.parameter_error(t, est, 0.10, mask=t >= 2.0, settle_s=5.0)  # settles from the mask's start
    assert late.n_samples == np.count_nonzero(t >= 7.0)


def test_dft_step_frequency_finds_the_peak_between_bins():
    """The DFT average frequency of a noisy 1.83 Hz sinusoid with gaps is found to 0.01 Hz."""
    rng = np.random.default_rng(0)
    t = np.arange(0.0, 30.0, 0.04)
    vz = 0.2 * np.sin(2 * np.pi * 1.83 * t) + 0.05 * np.sin(2 * np.pi * 3.66 * t) + rng.normal(0, 0.05, t.size)
    vz[100:130] = NAN
    assert mt.dft_step_frequency_hz(t, vz) == pytest.approx(1.83, abs=0.01)


def test_step_frequency_from_contacts_by_hand():
    """Strikes at 0, 0.5, 1.0, 1.6, 4.0 s: 2, 2, 1/0.6 Hz, then a gap (NaN); NaN outside."""
    contacts = [1.0, 0.0, 0.5, 1.6, 4.0]
    t = np.array([-0.1, 0.2, 0.7, 1.2, 2.0, 4.5])
    f = mt.step_frequency_from_contacts(contacts, t)
    np.testing.assert_allclose(f, [NAN, 2.0, 2.0, 1 / 0.6, NAN, NAN])


def test_stride_average_removes_left_right_alternation():
    """Alternating step intervals (0.5, 0.6 s) at a constant cadence give 1/0.55 Hz inside with stride_average."""
    contacts = np.cumsum([0.0] + [0.5, 0.6] * 10)
    t = np.linspace(contacts[1] + 0.01, contacts[-2] - 0.01, 200)
    raw = mt.step_frequency_from_contacts(contacts, t)
    avg = mt.step_frequency_from_contacts(contacts, t, stride_average=True)
    assert np.ptp(raw) > 0.3
    np.testing.assert_allclose(avg, 1 / 0.55, rtol=1e-12)


def test_synthetic_contacts_give_the_true_step_frequency():
    """Step frequency from the synthetic heel strikes matches the truth (they are timed from theta)."""
    tr = sy.make_walk(sy.SUBJECTS[1], "2-fast-slow-fast").truth
    f = mt.step_frequency_from_contacts(tr.contact_times_s, tr.time_s)
    ok = np.isfinite(f)
    assert ok.mean() > 0.9
    assert np.median(np.abs(f[ok] - tr.step_frequency_hz[ok])) < 0.01


def _perfect_result(truth, t):
    """An estimator output equal to the truth, on grid t."""
    tr = truth.at(t)
    return SimpleNamespace(
        vx_hat_mps=tr.vx_path_mps,
        vz_hat_mps=tr.vz_mps,
        step_frequency_hz=tr.step_frequency_hz,
        speed_mps=tr.speed_mps,
        R_m=tr.R_m,
        r_m=tr.r_m,
        omega_rad_s=2 * np.pi * tr.step_frequency_hz,
    )


def test_evaluate_has_every_key_and_zero_error_for_a_perfect_estimate():
    """evaluate() returns all METRIC_KEYS; estimates equal to the truth score zero error everywhere."""
    truth = sy.make_walk(sy.SUBJECTS[0], "5-stop-and-go").truth
    t = np.arange(0.0, truth.time_s[-1], 0.04)
    tr = truth.at(t)
    result = _perfect_result(truth, t)
    out = mt.evaluate(t, tr.vx_path_mps, tr.vz_mps, result, truth=truth, predicted_1step=(tr.vx_path_mps, tr.vz_mps))
    assert tuple(out) == mt.METRIC_KEYS
    for key in (
        "vx_sq_err_mean_1e-2",
        "vz_sq_err_mean_1e-2",
        "f_err_median_hz",
        "f_err_p90_hz",
        "speed_err_rms_mps",
        "R_err_median_abs_m",
        "r_err_median_rel_fraction",
        "pred1_vx_sq_err_mean_1e-2",
        "f_wrong_sign_fraction",
        "f_converge_time_s",
    ):
        assert out[key] == pytest.approx(0.0, abs=1e-12), key
    assert math.isnan(out["pred200ms_vz_sq_err_mean_1e-2"])  # not given
    assert out["walking_s"] == pytest.approx(np.sum(np.diff(t)[tr.walking[:-1]]))
    assert out["walking_s"] < t[-1] - 3.0  # the standing part is not walking


def test_evaluate_known_offsets():
    """Offsets of 0.1 m/s, +0.2 Hz, mirrored frequency and R off by 10 % show up in the right keys."""
    truth = sy.make_walk(sy.SUBJECTS[2], "1-straight").truth
    t = np.arange(0.0, truth.time_s[-1], 0.04)
    tr = truth.at(t)
    result = _perfect_result(truth, t)
    result.vx_hat_mps = tr.vx_path_mps + 0.1
    result.step_frequency_hz = -(tr.step_frequency_hz + 0.2)
    result.R_m = 1.1 * tr.R_m
    del result.speed_mps  # falls back to R_m * |omega_rad_s|
    out = mt.evaluate(t, tr.vx_path_mps, tr.vz_mps, result, truth=truth)
    assert out["vx_sq_err_mean_1e-2"] == pytest.approx(1.0)
    assert out["vz_sq_err_mean_1e-2"] == pytest.approx(0.0)
    assert out["f_err_median_hz"] == pytest.approx(0.2)
    assert out["f_wrong_sign_fraction"] == 1.0
    assert out["f_converge_time_s"] == math.inf
    assert out["R_err_median_rel_fraction"] == pytest.approx(0.1)
    walking_speed = tr.speed_mps[tr.walking]
    assert out["speed_err_median_mps"] == pytest.approx(0.1 * np.median(walking_speed), rel=1e-6)
    assert math.isnan(out["pred1_vx_sq_err_mean_1e-2"])


def test_evaluate_without_references_leaves_nan():
    """Without truth or references only the Table I metric is computed; the rest is NaN."""
    t = np.arange(0.0, 4.0, 0.04)
    v = np.sin(t)
    out = mt.evaluate(t, v, v, vx_hat_mps=v + 0.1, vz_hat_mps=v)
    assert out["vx_sq_err_mean_1e-2"] == pytest.approx(1.0)
    assert math.isnan(out["f_err_median_hz"]) and math.isnan(out["R_err_median_abs_m"])
    assert out["samples_n"] == t.size


def test_coverage_counts_errors_within_two_stds():
    """coverage_fraction: |error| <= 2 std counts, a NaN reference is left out, a NaN estimate needs an inf std."""
    ref = np.array([1.0, 1.0, 1.0, 1.0, np.nan, 1.0, 1.0])
    est = np.array([1.1, 1.3, 0.8, 1.0, 5.0, np.nan, np.nan])
    std = np.array([0.1, 0.1, 0.1, 0.0, 0.1, np.inf, 0.1])
    # covered: 0.1 <= 0.2 yes, 0.3 no, 0.2 <= 0.2 yes, 0 <= 0 yes, (left out), NaN with inf yes, NaN no
    assert mt.coverage_fraction(est, std, ref) == pytest.approx(4 / 6)
    assert mt.coverage_fraction(est, std, ref, mask=[True, True, False, False, False, False, False]) == 0.5
    assert math.isnan(mt.coverage_fraction(est, std, ref, mask=np.zeros(7, dtype=bool)))


def test_confidently_wrong_needs_a_large_error_a_small_std_and_valid():
    """confidently_wrong_fraction: valid, error above its tolerance and above 2 std, in either quantity."""
    f_ref = np.full(6, 1.8)
    f_est = np.array([1.8, 2.1, 2.1, 2.1, 1.9, 1.8])  # errors 0, 0.3, 0.3, 0.3, 0.1, 0
    f_std = np.array([0.01, 0.01, 0.2, 0.01, 0.01, 0.01])  # sample 2: 2 std covers the error
    s_ref = np.full(6, 1.2)
    s_est = np.array([1.2, 1.2, 1.2, 1.2, 1.2, 1.5])  # sample 5: speed wrong by 0.3 m/s
    s_std = np.full(6, 0.02)
    valid = np.array([True, True, True, False, True, True])  # sample 3 is not valid
    q = ((f_est, f_std, f_ref, 0.15), (s_est, s_std, s_ref, 0.15))
    assert mt.confidently_wrong_fraction(q, valid) == pytest.approx(2 / 6)  # samples 1 and 5
    assert mt.confidently_wrong_fraction(q, np.zeros(6, dtype=bool)) == 0.0
    assert mt.flag_fraction(valid) == pytest.approx(5 / 6)
    assert mt.flag_fraction(valid, mask=[False, False, False, True, False, False]) == 0.0
