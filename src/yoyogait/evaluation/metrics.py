"""Evaluation metrics of the gait estimate, each with its unit.

The paper scores the estimator by the squared error between the reconstructed
and the measured velocities (Table I).  That score alone hides what matters
for guidance (is the step frequency right, and of the right sign? how fast
does it settle? is the forward speed without oscillation right?), so the
metrics here add those.  All functions take plain arrays on one time grid,
ignore NaN samples (a missing measurement or estimate is not an error of
zero), and accept an optional boolean ``mask`` (e.g. the walking part).
:func:`evaluate` bundles them into one flat dict per recording whose keys
carry their unit, for the evaluation table.

Units: velocities in m/s; squared velocity errors in 10^-2 (m/s)^2 (the
reported number is the value in (m/s)^2 times 100, as in Table I);
frequencies in Hz; times in s; lengths in m; fractions and relative errors
are dimensionless (0.05 = 5 %).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..errors import InputError
from ..pipeline.spectral import step_frequency

__all__ = [
    "SquaredErrorStats",
    "VelocityError",
    "StepFrequencyError",
    "SpeedError",
    "ParameterError",
    "METRIC_KEYS",
    "squared_error_stats",
    "velocity_error",
    "prediction_error",
    "step_frequency_error",
    "convergence_time_s",
    "speed_error",
    "parameter_error",
    "dft_step_frequency_hz",
    "step_frequency_from_contacts",
    "coverage_fraction",
    "confidently_wrong_fraction",
    "flag_fraction",
    "sharpness",
    "evaluate",
]

SQ_SCALE = 100.0
"""(m/s)^2 -> 10^-2 (m/s)^2, the unit of Table I."""


@dataclass(frozen=True)
class SquaredErrorStats:
    """Mean and standard deviation of the squared error, in 10^-2 (m/s)^2.

    The paper's Table I header gives the standard deviation in 10^-2 m/s,
    but it is the deviation of the squared error (its caption), so both
    numbers are in 10^-2 (m/s)^2.  Population standard deviation (ddof 0).
    """

    mean_1e_2: float
    std_1e_2: float
    n_samples: int


@dataclass(frozen=True)
class VelocityError:
    """Table I metric for the forward (``vx``) and vertical (``vz``) velocity."""

    vx: SquaredErrorStats
    vz: SquaredErrorStats


@dataclass(frozen=True)
class StepFrequencyError:
    """Step frequency against a reference.

    ``median_abs_hz`` and ``p90_abs_hz``: median and 90th percentile of
    |error| in Hz; ``wrong_sign_fraction``: share of the evaluated walking
    samples whose estimate is negative (the EKF's mirror solution);
    ``converge_time_s``: time from the first walking sample after which the
    error stays within the tolerance (inf if it never does, NaN if nothing
    can be evaluated).
    """

    median_abs_hz: float
    p90_abs_hz: float
    wrong_sign_fraction: float
    converge_time_s: float
    n_samples: int


@dataclass(frozen=True)
class SpeedError:
    """Forward speed without oscillation against the stride-averaged speed, m/s."""

    median_abs_mps: float
    rms_mps: float
    n_samples: int


@dataclass(frozen=True)
class ParameterError:
    """Error of a Yoyo-model radius (R or r) after settling.

    Absolute errors in metres; ``median_rel`` is |error| / |true|
    (dimensionless, 0.05 = 5 %).
    """

    median_abs_m: float
    rms_m: float
    median_rel: float
    n_samples: int


def _arr(x, name) -> np.ndarray:
    a = np.asarray(x, dtype=float)
    if a.ndim != 1:
        raise InputError(f"{name} must be one-dimensional, got shape {a.shape}")
    return a


def _mask(mask, n) -> np.ndarray:
    if mask is None:
        return np.ones(n, dtype=bool)
    m = np.asarray(mask, dtype=bool)
    if m.shape != (n,):
        raise InputError(f"mask must have {n} samples, got shape {m.shape}")
    return m


def _same_length(*arrays_and_names):
    n = arrays_and_names[0][0].shape[0]
    for a, name in arrays_and_names:
        if a.shape[0] != n:
            raise InputError(f"{name} has {a.shape[0]} samples, expected {n}")
    return n


def squared_error_stats(measured, estimated, mask=None) -> SquaredErrorStats:
    """Table I metric: mean and std of ``(estimated - measured)^2`` in 10^-2 (m/s)^2.

    Samples where either is NaN, or outside ``mask``, are left out.
    """
    y = _arr(measured, "measured")
    e = _arr(estimated, "estimated")
    n = _same_length((y, "measured"), (e, "estimated"))
    keep = _mask(mask, n) & np.isfinite(y) & np.isfinite(e)
    if not keep.any():
        return SquaredErrorStats(np.nan, np.nan, 0)
    sq = (e[keep] - y[keep]) ** 2
    return SquaredErrorStats(float(np.mean(sq) * SQ_SCALE), float(np.std(sq) * SQ_SCALE), int(keep.sum()))


def velocity_error(measured_vx_mps, measured_vz_mps, vx_hat_mps, vz_hat_mps, mask=None) -> VelocityError:
    """Table I metric for both components (reconstruction eq. 13-14 vs measurement)."""
    return VelocityError(
        squared_error_stats(measured_vx_mps, vx_hat_mps, mask),
        squared_error_stats(measured_vz_mps, vz_hat_mps, mask),
    )


def prediction_error(measured_vx_mps, measured_vz_mps, predicted_vx_mps, predicted_vz_mps, mask=None) -> VelocityError:
    """Squared error of predicted velocities, in 10^-2 (m/s)^2.

    The predictions must already be aligned to the sample they predict (the
    value at index k is the prediction *for* sample k, made one step or
    0.2 s earlier), NaN where no prediction exists; this only compares.
    """
    return velocity_error(measured_vx_mps, measured_vz_mps, predicted_vx_mps, predicted_vz_mps, mask)


def convergence_time_s(time_s, error, tolerance, mask=None) -> float:
    """Time from the first evaluated sample until |error| stays within ``tolerance``.

    Only samples inside ``mask`` with a finite error count.  0 if it is
    within from the start, inf if the last evaluated sample is outside,
    NaN if there is no sample to evaluate.
    """
    t = _arr(time_s, "time_s")
    err = _arr(error, "error")
    n = _same_length((t, "time_s"), (err, "error"))
    m = _mask(mask, n)
    if not m.any():
        return float("nan")
    t0 = t[np.flatnonzero(m)[0]]
    valid = m & np.isfinite(err)
    idx = np.flatnonzero(valid)
    if idx.size == 0:
        return float("nan")
    bad = np.abs(err[idx]) > tolerance
    if not bad.any():
        return float(t[idx[0]] - t0)
    last_bad = np.flatnonzero(bad)[-1]
    if last_bad == idx.size - 1:
        return float("inf")
    return float(t[idx[last_bad + 1]] - t0)


def step_frequency_error(
    time_s,
    estimated_hz,
    reference_hz,
    *,
    mask=None,
    skip_s: float = 0.0,
    tolerance_hz: float = 0.1,
    signed: bool = False,
) -> StepFrequencyError:
    """Step frequency error against a reference (truth, or gait events for real data).

    By default the magnitude of the estimate is compared (the EKF has a mirror
    solution with the sign of omega flipped that reconstructs the same
    velocities; the paper plots |omega|); the sign is scored separately by
    ``wrong_sign_fraction``.  ``signed=True`` compares the signed estimate.
    ``mask`` selects the walking samples.  ``skip_s`` leaves out the first
    seconds after the first walking sample from the median, percentile and
    sign metrics (not from the convergence time, which is measured from the
    first walking sample).  Samples with NaN estimate or reference are left
    out.
    """
    t = _arr(time_s, "time_s")
    est = _arr(estimated_hz, "estimated_hz")
    ref = _arr(reference_hz, "reference_hz")
    n = _same_length((t, "time_s"), (est, "estimated_hz"), (ref, "reference_hz"))
    walking = _mask(mask, n)
    err = (est if signed else np.abs(est)) - ref
    converge = convergence_time_s(t, err, tolerance_hz, walking)
    if walking.any():
        walking = walking & (t >= t[np.flatnonzero(walking)[0]] + skip_s)
    keep = walking & np.isfinite(err)
    if not keep.any():
        return StepFrequencyError(np.nan, np.nan, np.nan, converge, 0)
    abs_err = np.abs(err[keep])
    has_est = walking & np.isfinite(est)
    wrong = float(np.mean(est[has_est] < 0)) if has_est.any() else np.nan
    return StepFrequencyError(
        float(np.median(abs_err)), float(np.percentile(abs_err, 90)), wrong, converge, int(keep.sum())
    )


def speed_error(estimated_speed_mps, reference_speed_mps, mask=None) -> SpeedError:
    """Forward speed without the oscillation (estimator's R * omega) vs the stride-averaged speed, m/s."""
    est = _arr(estimated_speed_mps, "estimated_speed_mps")
    ref = _arr(reference_speed_mps, "reference_speed_mps")
    n = _same_length((est, "estimated_speed_mps"), (ref, "reference_speed_mps"))
    keep = _mask(mask, n) & np.isfinite(est) & np.isfinite(ref)
    if not keep.any():
        return SpeedError(np.nan, np.nan, 0)
    err = est[keep] - ref[keep]
    return SpeedError(float(np.median(np.abs(err))), float(np.sqrt(np.mean(err**2))), int(keep.sum()))


def parameter_error(time_s, estimated_m, true_m, *, mask=None, settle_s: float = 5.0) -> ParameterError:
    """Error of an estimated Yoyo radius (R or r) against the truth, after ``settle_s``.

    The settling time counts from the first sample inside ``mask``; the
    estimator starts from a generic human, so the first seconds say nothing
    about its accuracy.
    """
    t = _arr(time_s, "time_s")
    est = _arr(estimated_m, "estimated_m")
    true = np.asarray(true_m, dtype=float)
    true = _arr(np.broadcast_to(true, est.shape) if true.ndim == 0 else true, "true_m")
    n = _same_length((t, "time_s"), (est, "estimated_m"), (true, "true_m"))
    m = _mask(mask, n)
    if m.any():
        m = m & (t >= t[np.flatnonzero(m)[0]] + settle_s)
    keep = m & np.isfinite(est) & np.isfinite(true)
    if not keep.any():
        return ParameterError(np.nan, np.nan, np.nan, 0)
    err = est[keep] - true[keep]
    with np.errstate(divide="ignore", invalid="ignore"):
        rel = np.abs(err) / np.abs(true[keep])
    return ParameterError(
        float(np.median(np.abs(err))), float(np.sqrt(np.mean(err**2))), float(np.median(rel)), int(keep.sum())
    )


def dft_step_frequency_hz(time_s, signal, *, fmin_hz: float = 0.5, fmax_hz: float = 4.0) -> float:
    """Average step frequency of a recording from the DFT of ``signal`` (Hz).

    The paper's reference line in Fig. 3.  Use the vertical velocity.  NaN
    samples are filled by linear interpolation; the grid must be (nearly)
    uniform.  The step frequency is :func:`yoyogait.pipeline.spectral.step_frequency`:
    the DFT peak, or the peak near half of it in slow walks where the pelvis
    rises twice per step.
    """
    t = _arr(time_s, "time_s")
    y = _arr(signal, "signal")
    _same_length((t, "time_s"), (y, "signal"))
    good = np.isfinite(y) & np.isfinite(t)
    if good.sum() < 8:
        return float("nan")
    first, last = np.flatnonzero(good)[[0, -1]]
    t, y, good = t[first : last + 1], y[first : last + 1], good[first : last + 1]
    y = np.interp(t, t[good], y[good])
    return step_frequency(y, 1.0 / float(np.median(np.diff(t))), min_hz=fmin_hz, max_hz=fmax_hz)


def step_frequency_from_contacts(
    contact_times_s, time_s, *, max_step_s: float = 1.5, stride_average: bool = False
) -> np.ndarray:
    """Reference step frequency (Hz) on ``time_s`` from heel strikes of both feet.

    Between two successive heel strikes (either foot) the step frequency is
    1 / their interval; NaN before the first and after the last strike and
    over intervals longer than ``max_step_s`` (standing, or a missed event).

    With ``stride_average`` each interval is first replaced by
    0.5 * its own + 0.25 * each neighbour's (where the neighbours are steps too):
    left-right asymmetry makes step intervals alternate (0.52, 0.58, 0.52 s...)
    at a constant cadence, and this average of a step and the two strides
    around it takes the alternation out while following a changing cadence.
    """
    c = np.sort(_arr(contact_times_s, "contact_times_s"))
    t = _arr(time_s, "time_s")
    out = np.full(t.shape, np.nan)
    if c.size < 2:
        return out
    i = np.searchsorted(c, t, side="right") - 1
    inside = (i >= 0) & (i < c.size - 1)
    interval = np.diff(c)
    step = interval <= max_step_s
    if stride_average and interval.size >= 2:
        prev = np.concatenate(([np.nan], interval[:-1]))
        prev_ok = np.concatenate(([False], step[:-1]))
        nxt = np.concatenate((interval[1:], [np.nan]))
        nxt_ok = np.concatenate((step[1:], [False]))
        both = prev_ok & nxt_ok
        smoothed = np.where(
            both,
            0.5 * interval + 0.25 * (np.where(prev_ok, prev, 0) + np.where(nxt_ok, nxt, 0)),
            np.where(
                prev_ok,
                0.5 * (interval + np.where(prev_ok, prev, 0)),
                np.where(nxt_ok, 0.5 * (interval + np.where(nxt_ok, nxt, 0)), interval),
            ),
        )
        interval = smoothed
    f = np.where(step, 1.0 / interval, np.nan)
    out[inside] = f[i[inside]]
    return out


COVERAGE_STDS = 2.0
"""An estimate covers the reference when |error| <= this many of its standard deviations."""


def _finite_or(value, n, name):
    a = np.asarray(value, dtype=float)
    if a.ndim == 0:
        a = np.full(n, float(a))
    if a.shape != (n,):
        raise InputError(f"{name} has {a.shape[0] if a.ndim else 0} samples, expected {n}")
    return a


def coverage_fraction(estimate, std, reference, mask=None, *, stds: float = COVERAGE_STDS) -> float:
    """Share of the samples in ``mask`` with a finite reference where |estimate - reference| <= ``stds``
    standard deviations (the estimate's ``std``, same unit).

    A missing estimate (NaN) is not covered unless its std is infinite (it then claims nothing);
    a NaN std covers nothing. Frames are uniform in time, so this is a share of the time too. NaN
    without a sample.
    """
    ref = _arr(reference, "reference")
    n = ref.shape[0]
    est = _finite_or(estimate, n, "estimate")
    sd = _finite_or(std, n, "std")
    keep = _mask(mask, n) & np.isfinite(ref)
    if not keep.any():
        return float("nan")
    with np.errstate(invalid="ignore"):
        err = np.abs(est - ref)
        covered = np.where(np.isfinite(err), err <= stds * sd, np.isposinf(sd))
    return float(np.mean(covered[keep]))


def confidently_wrong_fraction(quantities, valid, mask=None, *, stds: float = COVERAGE_STDS) -> float:
    """Share of the samples in ``mask`` (where any reference is finite) at which some estimate is
    confidently wrong: flagged ``valid``, its error above the tolerance, and ``stds`` standard deviations
    below the error.

    ``quantities``: (estimate, std, reference, tolerance) per quantity (e.g. step frequency with 0.15 Hz,
    speed with 0.15 m/s). A NaN std counts as 0 (a valid estimate without a spread claims to be exact);
    a missing estimate is never wrong. NaN without a sample.
    """
    v = np.asarray(valid, dtype=bool)
    n = v.shape[0]
    m = _mask(mask, n)
    known = np.zeros(n, dtype=bool)
    wrong = np.zeros(n, dtype=bool)
    for estimate, std, reference, tolerance in quantities:
        ref = _finite_or(reference, n, "reference")
        est = _finite_or(estimate, n, "estimate")
        sd = np.nan_to_num(_finite_or(std, n, "std"), nan=0.0)
        known |= np.isfinite(ref)
        with np.errstate(invalid="ignore", over="ignore"):  # an infinite std (not yet known) is never below
            err = np.abs(est - ref)
            wrong |= np.isfinite(err) & (err > tolerance) & (err > stds * sd)
    keep = m & known
    if not keep.any():
        return float("nan")
    return float(np.mean((wrong & v)[keep]))


def sharpness(estimate, std, reference, valid, mask=None) -> tuple[float, float]:
    """(median reported std, 95th percentile of |estimate - reference|) over the samples in ``mask``
    that are flagged ``valid`` and have a finite estimate, std and reference: how wide the spread is
    that a controller gating on ``valid`` is given, beside how far off it is (a calibrated Gaussian
    spread has its 2 std near that percentile). (NaN, NaN) without such a sample."""
    ref = _arr(reference, "reference")
    n = ref.shape[0]
    est = _arr(estimate, "estimate")
    sd = _arr(std, "std")
    keep = _mask(mask, n) & np.asarray(valid, dtype=bool) & np.isfinite(ref) & np.isfinite(est) & np.isfinite(sd)
    if not keep.any():
        return float("nan"), float("nan")
    return float(np.median(sd[keep])), float(np.percentile(np.abs(est[keep] - ref[keep]), 95.0))


def flag_fraction(flag, mask=None) -> float:
    """Share of the samples in ``mask`` where ``flag`` is set (e.g. the estimate valid); NaN without a sample."""
    f = np.asarray(flag, dtype=bool)
    m = _mask(mask, f.shape[0])
    return float(np.mean(f[m])) if m.any() else float("nan")


_SQ_KEYS = ("sq_err_mean_1e-2", "sq_err_std_1e-2")
METRIC_KEYS: tuple[str, ...] = (
    "samples_n",
    "walking_s",
    *(f"{c}_{k}" for c in ("vx", "vz") for k in _SQ_KEYS),
    "f_err_median_hz",
    "f_err_p90_hz",
    "f_wrong_sign_fraction",
    "f_converge_time_s",
    "speed_err_median_mps",
    "speed_err_rms_mps",
    *(f"{p}_{c}_{k}" for p in ("pred1", "pred200ms") for c in ("vx", "vz") for k in _SQ_KEYS),
    *(f"{p}_err_{k}" for p in ("R", "r") for k in ("median_abs_m", "rms_m", "median_rel_fraction")),
)
"""Keys of :func:`evaluate`, always all present (NaN when not computable).

``samples_n``: samples evaluated; ``walking_s``: walking time (s);
``vx_/vz_sq_err_mean/std_1e-2``: Table I metric, 10^-2 (m/s)^2;
``f_err_median_hz``, ``f_err_p90_hz``: |step frequency error| (Hz);
``f_wrong_sign_fraction``: share of walking samples with negative estimate;
``f_converge_time_s``: time to stay within the tolerance (s);
``speed_err_median_mps``, ``speed_err_rms_mps``: speed without oscillation (m/s);
``pred1_*``, ``pred200ms_*``: one-sample and 0.2 s-ahead prediction error,
10^-2 (m/s)^2; ``R_err_*``, ``r_err_*``: Yoyo radii errors (m, and relative: a fraction).
"""


def _of(result, name: str):
    """``result.<name>`` (one spelling: the record tables'), None without a result or the field."""
    return None if result is None else getattr(result, name, None)


def evaluate(
    time_s,
    measured_vx_mps,
    measured_vz_mps,
    result=None,
    *,
    vx_hat_mps=None,
    vz_hat_mps=None,
    step_frequency_hz=None,
    speed_mps=None,
    R_m=None,
    r_m=None,
    truth=None,
    walking=None,
    reference_step_frequency_hz=None,
    reference_speed_mps=None,
    true_R_m=None,
    true_r_m=None,
    predicted_1step=None,
    predicted_200ms=None,
    walking_only: bool = True,
    skip_s: float = 0.0,
    settle_s: float = 5.0,
    tolerance_hz: float = 0.1,
) -> dict[str, float]:
    """All metrics of one recording as one flat dict (keys: :data:`METRIC_KEYS`).

    ``time_s`` is the estimator's time grid; the measured velocities and every
    estimate are on it.  Estimates come from ``result`` (an object with
    ``vx_hat_mps``, ``vz_hat_mps``, ``step_frequency_hz``, ``speed_mps``, ``R_m``,
    ``r_m``; without ``speed_mps``, ``R_m * |omega_rad_s|``) or the explicit
    arrays, which win.  References: ``truth`` (a
    :class:`~yoyogait.synthetic.SyntheticTruth`, resampled here with its
    ``at()``) fills ``walking``, the reference step frequency and speed and
    the true radii unless given explicitly.  ``predicted_1step`` and
    ``predicted_200ms`` are ``(vx, vz)`` pairs aligned to the predicted
    sample.  With ``walking_only`` the velocity and prediction errors are
    taken over the walking samples only.
    """
    t = _arr(time_s, "time_s")
    vx = _arr(measured_vx_mps, "measured_vx_mps")
    vz = _arr(measured_vz_mps, "measured_vz_mps")
    n = _same_length((t, "time_s"), (vx, "measured_vx_mps"), (vz, "measured_vz_mps"))

    vx_hat_mps = vx_hat_mps if vx_hat_mps is not None else _of(result, "vx_hat_mps")
    vz_hat_mps = vz_hat_mps if vz_hat_mps is not None else _of(result, "vz_hat_mps")
    f_hat = step_frequency_hz if step_frequency_hz is not None else _of(result, "step_frequency_hz")
    speed_hat = speed_mps if speed_mps is not None else _of(result, "speed_mps")
    R_hat = R_m if R_m is not None else _of(result, "R_m")
    r_hat = r_m if r_m is not None else _of(result, "r_m")
    omega_hat = _of(result, "omega_rad_s")
    if speed_hat is None and R_hat is not None and omega_hat is not None:
        speed_hat = np.asarray(R_hat, dtype=float) * np.abs(np.asarray(omega_hat, dtype=float))

    if truth is not None:
        tr = truth.at(t)
        walking = tr.walking if walking is None else walking
        reference_step_frequency_hz = (
            tr.step_frequency_hz if reference_step_frequency_hz is None else reference_step_frequency_hz
        )
        reference_speed_mps = tr.speed_mps if reference_speed_mps is None else reference_speed_mps
        true_R_m = tr.R_m if true_R_m is None else true_R_m
        true_r_m = tr.r_m if true_r_m is None else true_r_m

    walk = _mask(walking, n)
    vel_mask = walk if walking_only else None
    out: dict[str, float] = {key: float("nan") for key in METRIC_KEYS}
    out["samples_n"] = float(n)
    dt = np.diff(t)
    out["walking_s"] = float(np.sum(dt[walk[:-1]])) if n > 1 else 0.0

    def put_velocity(prefix, pair):
        if pair is None or pair[0] is None or pair[1] is None:
            return
        err = velocity_error(vx, vz, pair[0], pair[1], vel_mask)
        for comp, stats in (("vx", err.vx), ("vz", err.vz)):
            out[f"{prefix}{comp}_sq_err_mean_1e-2"] = stats.mean_1e_2
            out[f"{prefix}{comp}_sq_err_std_1e-2"] = stats.std_1e_2

    put_velocity("", (vx_hat_mps, vz_hat_mps))
    put_velocity("pred1_", predicted_1step)
    put_velocity("pred200ms_", predicted_200ms)

    if f_hat is not None and reference_step_frequency_hz is not None:
        fe = step_frequency_error(
            t, f_hat, reference_step_frequency_hz, mask=walk, skip_s=skip_s, tolerance_hz=tolerance_hz
        )
        out.update(
            f_err_median_hz=fe.median_abs_hz,
            f_err_p90_hz=fe.p90_abs_hz,
            f_wrong_sign_fraction=fe.wrong_sign_fraction,
            f_converge_time_s=fe.converge_time_s,
        )
    if speed_hat is not None and reference_speed_mps is not None:
        se = speed_error(speed_hat, reference_speed_mps, walk)
        out.update(speed_err_median_mps=se.median_abs_mps, speed_err_rms_mps=se.rms_mps)
    for name, est, true in (("R", R_hat, true_R_m), ("r", r_hat, true_r_m)):
        if est is None or true is None:
            continue
        pe = parameter_error(t, est, true, mask=walk, settle_s=settle_s)
        out[f"{name}_err_median_abs_m"] = pe.median_abs_m
        out[f"{name}_err_rms_m"] = pe.rms_m
        out[f"{name}_err_median_rel_fraction"] = pe.median_rel
    return out
