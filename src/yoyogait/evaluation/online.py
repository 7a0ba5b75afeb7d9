"""Online evaluation: what a user of :class:`yoyogait.OnlineEstimator` sees, frame by frame.

Each recording is replayed at its capture rate through the causal pipeline
(:class:`~yoyogait.estimators.online.OnlineEstimator`: causal centre, Kalman differentiator,
heading, the default gait filter). The estimates are scored at the capture frame times against
what the person did:

* velocities: the paper's offline pipeline (:func:`yoyogait.gait_velocities`, centred
  Savitzky-Golay) on the same recording, computed at its capture rate so that the frame times are
  its grid times (``vx_signed``: along the walking heading, as the online ``vx`` is; the walking
  part and the oscillator's input stay on the 25 Hz grid);
* step frequency, speed and walking: the foot-contact reference
  (:func:`~yoyogait.evaluation.running.real_reference`) on real data, the truth on synthetic walks;
* gait phase: the foot contacts (gait events on real data, the truth's heel strikes on synthetic walks).

Beside it the adaptive oscillator (:mod:`yoyogait.estimators.oscillator`) runs on the offline
velocities at 25 Hz (its validated rate; the offline velocities are not causal, so this favours it)
and is scored the same way on that grid. Definitions of every column: docs/online.md, "Online
evaluation".
"""

from __future__ import annotations

import functools
import math
from dataclasses import dataclass
from types import SimpleNamespace

import numpy as np

from .. import synthetic as synth
from ..errors import InputError
from ..estimators.online import OnlineConfig, OnlineEstimator
from ..estimators.oscillator import oscillate
from ..pipeline import events
from ..pipeline.velocities import gait_velocities
from . import metrics
from .datasets import Item, synthetic_item
from .parallel import TaskFailure
from .running import (
    DEFAULT_WALKING_PART,
    RATE_HZ,
    Evaluation,
    ItemResult,
    check_walking_part,
    evaluate_items,
    outcome,
    real_reference,
)
from .tables import with_trusted_part

__all__ = [
    "ONLINE_ESTIMATORS",
    "ONLINE_METRIC_KEYS",
    "FIRST_S",
    "OnlineEvaluation",
    "evaluate_online",
    "evaluate_item_online",
    "run_item_online",
    "step_walk_items",
    "lag_s",
    "circular_std_pct",
    "phase_at",
    "settle_time_s",
    "HONESTY_KEYS",
    "validity",
]

ONLINE_ESTIMATORS = ("online", "oscillator")
"""Rows per recording: the online estimator, and the adaptive oscillator beside it."""

FIRST_S = 3.0
"""The start of walking scored on its own: the first 3 s after the first walking sample."""

STARTUP_TOLERANCE_HZ = 0.1
CADENCE_TOLERANCE_HZ = 0.05
SPEED_TOLERANCE_MPS = 0.05
HOLD_S = 2.0
"""A settling time counts once the error stays within its tolerance for this long (or to the end)."""
MAX_LAG_S = 0.2
PREDICT_AHEAD_S = 0.2
"""Horizon of the scored prediction (the ``pred200ms_*`` columns) [s]."""
"""Cross-correlation search range; below half a step period (~0.27 s at 1.8 Hz), so no cycle slip."""

ONLINE_EXTRA_KEYS: tuple[str, ...] = (
    "rate_hz",
    "f_err_whole_median_hz",
    "f_err_first3s_median_hz",
    "vx_sq_err_first3s_mean_1e-2",
    "vz_sq_err_first3s_mean_1e-2",
    "vx_sq_err_after3s_mean_1e-2",
    "vz_sq_err_after3s_mean_1e-2",
    "speed_err_first3s_median_mps",
    "speed_err_after3s_median_mps",
    "latency_vz_ms",
    "latency_vz_input_ms",
    "phase_at_contact_circstd_pct",
    "phase_contacts_n",
    "startup_time_s",
    "startup_from_cadence_s",
    "cadence_step_time_s",
    "speed_step_time_s",
)
WRONG_F_HZ = 0.15
WRONG_SPEED_MPS = 0.15
"""Errors above these, flagged valid and above 2 standard deviations, are confidently wrong."""

HONESTY_KEYS: tuple[str, ...] = tuple(
    f"{name}{part}_fraction"
    for name in ("f_cover2std", "speed_cover2std", "confidently_wrong", "valid")
    for part in ("", "_first3s", "_after3s")
) + (
    "frontend_speed_max_mps",
    "f_std_valid_median_hz",
    "f_err_valid_p95_hz",
    "speed_std_valid_median_mps",
    "speed_err_valid_p95_mps",
)
"""The honesty columns (online only; NaN for the oscillator, which reports no spread): per part of the
walking time (whole, first 3 s, after them) the 2-std coverage of step frequency and speed, the share
confidently wrong, the share valid; the front-end's highest horizontal speed while walking; the
sharpness (:func:`~yoyogait.evaluation.metrics.sharpness`) over the valid walking time: the median
reported std of step frequency and speed beside the 95th percentile of their errors."""

ONLINE_METRIC_KEYS: tuple[str, ...] = metrics.METRIC_KEYS + ONLINE_EXTRA_KEYS + HONESTY_KEYS
"""Columns of an online evaluation's ``recordings.csv``: every offline metric, then the online ones.

``f_err_median_hz`` is after the first 3 s of walking (as offline), ``f_err_first3s_median_hz``
within them, ``f_err_whole_median_hz`` over the whole walking part; ``latency_vz_ms``: lag of
``vz_hat_mps`` behind the offline v_z; ``latency_vz_input_ms``: the same for the front-end's v_z
(online only); ``phase_at_contact_circstd_pct``: circular standard deviation of the gait phase at
the foot contacts, % of a step; ``startup_time_s`` (from the first walking frame),
``startup_from_cadence_s`` (from the end of the walk's start-up ramp, where it reaches its cadence),
``cadence_step_time_s``, ``speed_step_time_s``: settling times on synthetic walks (inf: never, NaN:
not defined); then
:data:`HONESTY_KEYS`.
"""


# ---------------------------------------------------------------------------
# Metrics.


def lag_s(estimate, reference, rate_hz: float, *, max_lag_s: float = MAX_LAG_S) -> float:
    """Delay of ``estimate`` behind ``reference`` [s]: the shift maximising their cross-correlation.

    Both on one uniform grid at ``rate_hz``, NaN where unknown (left out). Positive: the
    estimate comes later. The correlation at each shift is the mean product of the
    mean-removed signals over the samples both know; the peak is refined by a parabola
    through its neighbours. NaN with fewer than 20 common samples.
    """
    est = np.asarray(estimate, dtype=float)
    ref = np.asarray(reference, dtype=float)
    if est.shape != ref.shape or est.ndim != 1:
        raise InputError("estimate and reference must be one-dimensional and of the same length")
    ok = np.isfinite(est) & np.isfinite(ref)
    if ok.sum() < 20 or not rate_hz > 0:
        return float("nan")
    a = np.where(np.isfinite(est), est - np.mean(est[ok]), 0.0)
    b = np.where(np.isfinite(ref), ref - np.mean(ref[ok]), 0.0)
    fa, fb = np.isfinite(est).astype(float), np.isfinite(ref).astype(float)
    m = max(1, int(round(max_lag_s * rate_hz)))
    n = est.size
    shifts = np.arange(-m, m + 1)
    corr = np.full(shifts.size, -np.inf)
    for j, k in enumerate(shifts):  # est[i] against ref[i - k]
        if abs(k) >= n:
            continue
        ea, rb = (a[k:], b[: n - k]) if k >= 0 else (a[: n + k], b[-k:])
        ca, cb = (fa[k:], fb[: n - k]) if k >= 0 else (fa[: n + k], fb[-k:])
        count = float(np.dot(ca, cb))
        if count >= 20:
            corr[j] = float(np.dot(ea, rb)) / count
    i = int(np.argmax(corr))
    if not np.isfinite(corr[i]):
        return float("nan")
    off = 0.0
    if 0 < i < shifts.size - 1 and np.isfinite(corr[i - 1]) and np.isfinite(corr[i + 1]):
        den = corr[i - 1] - 2.0 * corr[i] + corr[i + 1]
        off = 0.5 * (corr[i - 1] - corr[i + 1]) / den if den < 0 else 0.0
    return float((shifts[i] + off) / rate_hz)


def circular_std_pct(phase) -> float:
    """Circular standard deviation of phases given in cycles (1 = one step), in % of a cycle.

    ``sqrt(-2 ln R) / (2 pi) * 100`` with R the length of the mean phasor: ~ the standard
    deviation for a narrow spread, insensitive to the wrap at 0/1. NaN with fewer than 3 phases.
    """
    p = np.asarray(phase, dtype=float)
    p = p[np.isfinite(p)]
    if p.size < 3:
        return float("nan")
    r = float(np.abs(np.mean(np.exp(2j * np.pi * p))))
    return float(np.sqrt(-2.0 * np.log(min(max(r, 1e-300), 1.0))) / (2.0 * np.pi) * 100.0)


def phase_at(time_s, phase, at_s) -> np.ndarray:
    """Phase (cycles, [0, 1)) at the times ``at_s``, interpolated along the shorter way round
    between the two samples around each time; NaN outside ``time_s`` or next to an unknown phase."""
    t = np.asarray(time_s, dtype=float)
    p = np.asarray(phase, dtype=float)
    at = np.asarray(at_s, dtype=float)
    out = np.full(at.shape, np.nan)
    i = np.searchsorted(t, at, side="right") - 1
    inside = (i >= 0) & (i < t.size - 1)
    i0 = i[inside]
    p0, p1 = p[i0], p[i0 + 1]
    w = (at[inside] - t[i0]) / (t[i0 + 1] - t[i0])
    d = np.mod(p1 - p0 + 0.5, 1.0) - 0.5
    out[inside] = np.mod(p0 + w * d, 1.0)
    return out


def settle_time_s(time_s, error, tolerance: float, t0_s: float, *, t_end_s: float = np.inf, hold_s: float = HOLD_S):
    """Time from ``t0_s`` until |error| is within ``tolerance`` and stays so for ``hold_s``.

    Only samples in [t0_s, t_end_s] with a finite error count; the hold is cut at ``t_end_s``.
    0 if within from ``t0_s``; inf if never; NaN if no sample to evaluate.
    """
    t = np.asarray(time_s, dtype=float)
    err = np.asarray(error, dtype=float)
    keep = (t >= t0_s) & (t <= t_end_s) & np.isfinite(err)
    if not keep.any():
        return float("nan")
    tk, bad = t[keep], np.abs(err[keep]) > tolerance
    last = tk[-1]
    # Candidate starts: the first sample and every sample after a bad one.
    starts = np.flatnonzero(~bad & np.concatenate(([True], bad[:-1])))
    bad_times = tk[bad]
    for s in starts:
        ts = tk[s]
        nxt = np.searchsorted(bad_times, ts, side="left")
        next_bad = bad_times[nxt] if nxt < bad_times.size else np.inf
        if next_bad > min(ts + hold_s, last):
            return float(ts - t0_s)
    return float("inf")


# ---------------------------------------------------------------------------
# One recording.


@dataclass
class _Refs:
    """References on one time grid."""

    t: np.ndarray
    rate_hz: float
    vx: np.ndarray
    vz: np.ndarray
    walking: np.ndarray
    f_ref: np.ndarray
    speed_ref: np.ndarray
    quality: events.ReferenceQuality = events.NO_REFERENCE  # real data: whether the reference can be trusted


def _velocities_at_capture_rate(recording, point, up_axis, vel):
    """The offline velocities of ``vel`` (the paper's pipeline at 25 Hz) computed at the recording's
    capture rate instead, or ``vel`` where that cannot be done. The online estimates are scored at the
    frames' own times: on this grid a frame's time is a grid time (or close to one, for a rendering on
    another clock), while the 25 Hz grid interpolated there adds an error of its own (on the shared
    recordings the v_x reconstruction after the first 3 s read 0.256 instead of 0.200, 1e-2 (m/s)^2)."""
    t = np.asarray(recording.time_s, dtype=float)
    dt = np.diff(t)
    dt = dt[np.isfinite(dt) & (dt > 0)]
    if dt.size == 0:
        return vel
    rate_hz = 1.0 / float(np.median(dt))
    if abs(rate_hz - float(vel.rate_hz)) < 1e-6 * rate_hz:
        return vel
    try:
        return gait_velocities(recording, point=point, rate_hz=rate_hz, up_axis=up_axis)
    except InputError:
        return vel


def _interp(t, tp, y):
    return np.interp(t, tp, np.asarray(y, dtype=float), left=np.nan, right=np.nan)


def _references(
    recording,
    vel,
    item: Item,
    t: np.ndarray,
    rate_hz: float,
    walking_part: str = DEFAULT_WALKING_PART,
    vel_at=None,
) -> _Refs:
    """The references at the times ``t``, from ``vel``; ``vel_at``: the offline velocities that the
    returned v_x and v_z are taken from (:func:`_velocities_at_capture_rate`; the walking part and the
    real reference stay those of ``vel``), where ``vel`` has them."""
    vx = _interp(t, vel.time_s, vel.vx_signed)
    vz = _interp(t, vel.time_s, vel.vz)
    quality = events.NO_REFERENCE  # a SYNTHETIC truth: trusted by being the truth (tables.trusted)
    if item.truth is not None:
        tr = item.truth.at(t)
        f_ref, speed_ref = tr.step_frequency_hz, tr.speed_mps
        walking = np.asarray(tr.walking, dtype=bool) & np.isfinite(vx) & np.isfinite(vz)
    else:
        walk_in = _interp(t, vel.time_s, np.asarray(vel.walking, dtype=float)) > 0.5
        shim = SimpleNamespace(time_s=t, walking=walk_in, vx=vx, vz=vz, rate_hz=rate_hz, up_axis=vel.up_axis)
        f_ref, speed_ref, walking, quality = real_reference(recording, shim, item, walking_part=walking_part)
    if not walking.any():
        walking = np.isfinite(vx) & np.isfinite(vz)
    if vel_at is not None:
        known = np.isfinite(vx) & np.isfinite(vz)
        vx = np.where(known, _interp(t, vel_at.time_s, vel_at.vx_signed), np.nan)
        vz = np.where(known, _interp(t, vel_at.time_s, vel_at.vz), np.nan)
    return _Refs(t, rate_hz, vx, vz, np.asarray(walking, dtype=bool), f_ref, speed_ref, quality)


def _contacts(recording, item: Item, up_axis: str) -> np.ndarray:
    if item.truth is not None:
        return item.truth.contact_times_s
    try:
        return events.detect_gait_events(recording, feet=item.feet, up_axis=up_axis).contacts_s
    except InputError:
        return np.empty(0)


def _score(
    ref: _Refs,
    *,
    vx_hat_mps,
    vz_hat_mps,
    f_hat,
    speed_hat,
    phase,
    contacts_s,
    synthetic: bool,
    step_at_s: float | None,
    ramp_s: float = 0.0,
    vz_input=None,
    pred200=None,
    f_std=None,
    speed_std=None,
    valid=None,
    frontend_speed=None,
) -> dict[str, float]:
    """Every column of :data:`ONLINE_METRIC_KEYS` for one estimator on one grid.

    ``pred200``: (vx_ref, vz_ref, vx_pred, vz_pred), per frame: the offline velocities at t + 0.2 s
    and the prediction made at t for t + 0.2 s; scored where the walker walks at t + 0.2 s.
    ``f_std``, ``speed_std``, ``valid`` (the reported spreads and validity) give the honesty columns,
    ``frontend_speed`` (the front-end's horizontal speed) its maximum while walking; ``ramp_s``: how long
    after the first walking frame a synthetic walk reaches its cadence (its start-up ramp)."""
    t, walk = ref.t, ref.walking
    row = {k: float("nan") for k in ONLINE_METRIC_KEYS}
    row.update(
        metrics.evaluate(
            t,
            ref.vx,
            ref.vz,
            vx_hat_mps=vx_hat_mps,
            vz_hat_mps=vz_hat_mps,
            step_frequency_hz=f_hat,
            speed_mps=speed_hat,
            walking=walk,
            reference_step_frequency_hz=ref.f_ref,
            reference_speed_mps=ref.speed_ref,
            skip_s=FIRST_S,
        )
    )
    row["rate_hz"] = ref.rate_hz
    if pred200 is not None:
        vx_at, vz_at, vx_pred, vz_pred = (np.asarray(a, dtype=float) for a in pred200)
        # Walking at the predicted time (nearest frame); NaN beyond the end leaves it out.
        walk_at = _interp(t + PREDICT_AHEAD_S, t, walk.astype(float)) > 0.5
        err = metrics.prediction_error(vx_at, vz_at, vx_pred, vz_pred, walk_at)
        for comp, stats in (("vx", err.vx), ("vz", err.vz)):
            row[f"pred200ms_{comp}_sq_err_mean_1e-2"] = stats.mean_1e_2
            row[f"pred200ms_{comp}_sq_err_std_1e-2"] = stats.std_1e_2
    if not walk.any():
        return row
    t0 = float(t[np.flatnonzero(walk)[0]])
    first = walk & (t < t0 + FIRST_S)
    after = walk & (t >= t0 + FIRST_S)
    row["f_err_whole_median_hz"] = metrics.step_frequency_error(t, f_hat, ref.f_ref, mask=walk).median_abs_hz
    row["f_err_first3s_median_hz"] = metrics.step_frequency_error(t, f_hat, ref.f_ref, mask=first).median_abs_hz
    for part, mask in (("first3s", first), ("after3s", after)):
        err = metrics.velocity_error(ref.vx, ref.vz, vx_hat_mps, vz_hat_mps, mask)
        row[f"vx_sq_err_{part}_mean_1e-2"] = err.vx.mean_1e_2
        row[f"vz_sq_err_{part}_mean_1e-2"] = err.vz.mean_1e_2
        row[f"speed_err_{part}_median_mps"] = metrics.speed_error(speed_hat, ref.speed_ref, mask).median_abs_mps
    row["latency_vz_ms"] = 1e3 * lag_s(np.where(walk, vz_hat_mps, np.nan), np.where(walk, ref.vz, np.nan), ref.rate_hz)
    if vz_input is not None:
        row["latency_vz_input_ms"] = 1e3 * lag_s(
            np.where(walk, vz_input, np.nan), np.where(walk, ref.vz, np.nan), ref.rate_hz
        )
    # Phase at the contacts of both feet while walking, after the first 3 s (acquisition apart).
    c = np.asarray(contacts_s, dtype=float)
    in_walk = _interp(c, t, walk.astype(float)) > 0.5
    c = c[in_walk & (c >= t0 + FIRST_S)]
    ph = phase_at(t, phase, c)
    row["phase_contacts_n"] = float(np.isfinite(ph).sum())
    if f_std is not None and speed_std is not None and valid is not None:
        row.update(_honesty(ref, walk, first, after, f_hat, f_std, speed_hat, speed_std, valid))
    if frontend_speed is not None:
        fs = np.asarray(frontend_speed, dtype=float)[walk]
        fs = fs[np.isfinite(fs)]
        row["frontend_speed_max_mps"] = float(fs.max()) if fs.size else float("nan")
    row["phase_at_contact_circstd_pct"] = circular_std_pct(ph)
    if synthetic:
        f_err = np.abs(np.asarray(f_hat, dtype=float)) - ref.f_ref
        # Start-up: the first walking stretch (or up to a cadence step).
        stops = np.flatnonzero(~walk & (t > t0))
        t_stop = float(t[stops[0]]) if stops.size else float(t[-1])
        if step_at_s is not None:
            t_stop = min(t_stop, step_at_s)
        row["startup_time_s"] = settle_time_s(
            t, np.where(walk, f_err, np.nan), STARTUP_TOLERANCE_HZ, t0, t_end_s=t_stop
        )
        # The start-up target counts from where the walk has reached its cadence (the ramp's end).
        if t0 + ramp_s < t_stop:
            row["startup_from_cadence_s"] = settle_time_s(
                t, np.where(walk, f_err, np.nan), STARTUP_TOLERANCE_HZ, t0 + ramp_s, t_end_s=t_stop
            )
        if step_at_s is not None:
            end = float(t[-1])
            row["cadence_step_time_s"] = settle_time_s(
                t, np.where(walk, f_err, np.nan), CADENCE_TOLERANCE_HZ, step_at_s, t_end_s=end
            )
            s_err = np.asarray(speed_hat, dtype=float) - ref.speed_ref
            row["speed_step_time_s"] = settle_time_s(
                t, np.where(walk, s_err, np.nan), SPEED_TOLERANCE_MPS, step_at_s, t_end_s=end
            )
    return row


def _honesty(ref: _Refs, walk, first, after, f_hat, f_std, speed_hat, speed_std, valid) -> dict[str, float]:
    """The coverage, confidently-wrong and valid columns over the whole walking part and its two parts."""
    f_abs = np.abs(np.asarray(f_hat, dtype=float))
    quantities = (
        (f_abs, f_std, ref.f_ref, WRONG_F_HZ),
        (speed_hat, speed_std, ref.speed_ref, WRONG_SPEED_MPS),
    )
    out = {}
    for part, mask in (("", walk), ("_first3s", first), ("_after3s", after)):
        out[f"f_cover2std{part}_fraction"] = metrics.coverage_fraction(f_abs, f_std, ref.f_ref, mask)
        out[f"speed_cover2std{part}_fraction"] = metrics.coverage_fraction(speed_hat, speed_std, ref.speed_ref, mask)
        out[f"confidently_wrong{part}_fraction"] = metrics.confidently_wrong_fraction(quantities, valid, mask)
        out[f"valid{part}_fraction"] = metrics.flag_fraction(valid, mask)
    out["f_std_valid_median_hz"], out["f_err_valid_p95_hz"] = metrics.sharpness(f_abs, f_std, ref.f_ref, valid, walk)
    out["speed_std_valid_median_mps"], out["speed_err_valid_p95_mps"] = metrics.sharpness(
        speed_hat, speed_std, ref.speed_ref, valid, walk
    )
    return out


def validity(res) -> np.ndarray:
    """The per-frame flag a controller gates on: the online estimate's ``valid``."""
    return np.asarray(res.valid, dtype=bool)


def _run_oscillator(vel) -> dict[str, np.ndarray]:
    """The adaptive oscillator over the offline velocities (NaN before its first sample); its phase in cycles."""
    o = oscillate(vel.time_s, vel.vx_signed, vel.vz)
    out = {k: o[k] for k in ("vx_hat_mps", "vz_hat_mps", "gait_phase")}
    out["step_frequency_hz"] = o["omega_rad_s"] / (2.0 * math.pi)
    out["speed_mps"] = o["b0_mps"]
    for k in ("step_frequency_hz", "speed_mps", "gait_phase"):
        out[k] = np.where(o["started"], out[k], np.nan)
    return out


def evaluate_item_online(
    item: Item,
    config: OnlineConfig | None = None,
    reference: Item | None = None,
    *,
    feet: bool = False,
    belt_speed_mps: float | None = None,
    walking_part: str = DEFAULT_WALKING_PART,
) -> ItemResult:
    """Replay one item frame by frame through the online estimator (``config``: its settings, else the
    defaults) and score it, with the adaptive oscillator beside it (a top-level function: it runs in
    worker processes too).

    ``reference``: the item whose recording gives the offline velocities, the gait events and the
    walking reference (default: ``item`` itself), e.g. the clean recording of which ``item`` is a
    noisier rendering on the same clock. The oscillator runs on those reference velocities.
    ``feet``: the item's foot points go into the frames (a treadmill's belt from the stance feet);
    ``belt_speed_mps``: a known belt speed (OnlineEstimator.set_belt_speed_mps).
    ``walking_part``: the real reference's walking part scored (:data:`yoyogait.evaluation.running.WALKING_PARTS`).
    """
    check_walking_part(walking_part)  # before the replay, not after it
    recording = item.load()
    ref_item = item if reference is None else reference
    ref_recording = recording if reference is None else reference.load()
    point = item.pelvis if item.pelvis else None
    ref_point = ref_item.pelvis if ref_item.pelvis else None
    vel = gait_velocities(ref_recording, point=ref_point, rate_hz=RATE_HZ, up_axis=ref_item.up_axis)
    # The feet only when asked for: without them the call is the one it has always been.
    with_feet = {"feet": item.feet or True} if feet else {}
    estimator = OnlineEstimator.for_recording(recording, point, up_axis=vel.up_axis, config=config, **with_feet)
    if belt_speed_mps is not None:
        estimator.set_belt_speed_mps(belt_speed_mps)
    res = estimator.run(recording, predict_ahead_s=(PREDICT_AHEAD_S,))
    t = np.asarray(res.time_s, dtype=float)
    dt = np.diff(t)
    if not np.any(dt > 0):
        raise InputError(f"{item.name}: fewer than two frames with increasing times")
    rate = 1.0 / float(np.median(dt[dt > 0]))
    vel_at = _velocities_at_capture_rate(ref_recording, ref_point, vel.up_axis, vel)
    ref_frames = _references(ref_recording, vel, ref_item, t, rate, walking_part, vel_at=vel_at)
    grid = np.asarray(vel.time_s, dtype=float)
    ref_grid = _references(ref_recording, vel, ref_item, grid, float(vel.rate_hz), walking_part)
    contacts = _contacts(ref_recording, ref_item, vel.up_axis)
    step_at = ref_recording.metadata.get("cadence_step_at_s") if ref_item.synthetic else None
    # A synthetic walk that starts standing reaches its cadence ramp_s after its first step.
    meta = ref_recording.metadata
    ramp = float(meta.get("ramp_s", 0.0)) if ref_item.synthetic and meta.get("start_standing_s", 0.0) > 0 else 0.0
    synthetic = ref_item.truth is not None
    osc = _run_oscillator(vel)
    online_row = _score(
        ref_frames,
        vx_hat_mps=res.vx_hat_mps,
        vz_hat_mps=res.vz_hat_mps,
        f_hat=res.step_frequency_hz,
        speed_hat=res.speed_mps,
        phase=np.where(res.walking, res.gait_phase, np.nan),
        contacts_s=contacts,
        synthetic=synthetic,
        step_at_s=step_at,
        ramp_s=ramp,
        vz_input=res.vz_mps,
        pred200=(
            _interp(t + PREDICT_AHEAD_S, vel_at.time_s, vel_at.vx_signed),
            _interp(t + PREDICT_AHEAD_S, vel_at.time_s, vel_at.vz),
            np.where(np.isfinite(res.pred_vx_std_mps[:, 0]), res.pred_vx_mps[:, 0], np.nan),
            np.where(np.isfinite(res.pred_vz_std_mps[:, 0]), res.pred_vz_mps[:, 0], np.nan),
        ),
        f_std=res.step_frequency_std_hz,
        speed_std=res.speed_std_mps,
        valid=validity(res),
        frontend_speed=np.hypot(res.vh_a_mps, res.vh_b_mps),
    )
    osc_row = _score(
        ref_grid,
        vx_hat_mps=osc["vx_hat_mps"],
        vz_hat_mps=osc["vz_hat_mps"],
        f_hat=osc["step_frequency_hz"],
        speed_hat=osc["speed_mps"],
        phase=osc["gait_phase"],
        contacts_s=contacts,
        synthetic=synthetic,
        step_at_s=step_at,
        ramp_s=ramp,
    )
    walking = ref_grid.walking
    dft = metrics.dft_step_frequency_hz(vel.time_s[walking], vel.vz[walking]) if walking.sum() > 10 else float("nan")
    out = ItemResult(item, vel, ref_grid.f_ref, ref_grid.speed_ref, walking, dft, reference_quality=ref_grid.quality)
    out.results = {"online": res, "oscillator": osc}
    out.metrics = {"online": online_row, "oscillator": osc_row}
    return out


# ---------------------------------------------------------------------------
# A data set.


SUMMARY_ONLINE_KEYS = (
    ("f_err_first3s_median_hz", "step freq. error, first 3 s of walking (Hz)"),
    ("f_err_median_hz", "step freq. error, after 3 s (Hz)"),
    ("f_err_whole_median_hz", "step freq. error, whole walking part (Hz)"),
    ("vz_sq_err_mean_1e-2", "v_z error vs offline (1e-2 (m/s)^2)"),
    ("vx_sq_err_mean_1e-2", "v_x error vs offline (1e-2 (m/s)^2)"),
    ("latency_vz_ms", "lag of v_z_hat (ms)"),
    ("latency_vz_input_ms", "lag of the front-end v_z (ms)"),
    ("phase_at_contact_circstd_pct", "gait phase at contacts, circ. std (% of a step)"),
    ("startup_time_s", "start-up within 0.1 Hz (s)"),
    ("startup_from_cadence_s", "start-up within 0.1 Hz from reaching the cadence (s)"),
    ("cadence_step_time_s", "cadence step within 0.05 Hz (s)"),
    ("speed_step_time_s", "speed step within 0.05 m/s (s)"),
    ("f_cover2std_fraction", "step freq. within 2 std, share of walking"),
    ("speed_cover2std_fraction", "speed within 2 std, share of walking"),
    ("confidently_wrong_fraction", "confidently wrong, share of walking"),
    ("confidently_wrong_first3s_fraction", "confidently wrong, share of the first 3 s"),
    ("valid_fraction", "valid, share of walking"),
    ("valid_after3s_fraction", "valid, share of walking after 3 s"),
    ("frontend_speed_max_mps", "front-end horizontal speed, highest while walking (m/s)"),
    ("f_std_valid_median_hz", "step freq. std while valid, median (Hz)"),
    ("f_err_valid_p95_hz", "step freq. error while valid, 95th percentile (Hz)"),
    ("speed_std_valid_median_mps", "speed std while valid, median (m/s)"),
    ("speed_err_valid_p95_mps", "speed error while valid, 95th percentile (m/s)"),
)
"""The rows of the online summary: (column, label); the worst recording is the highest value except for
the columns in :data:`HIGHER_IS_BETTER` (the lowest) and :data:`BY_MAGNITUDE` (the farthest from 0)."""

ONLINE_DISTRIBUTION_KEYS = (
    ("f_err_whole_median_hz", "step freq. error, whole walking part (Hz)"),
    ("vz_sq_err_mean_1e-2", "v_z error vs offline (1e-2 (m/s)^2)"),
    ("f_cover2std_fraction", "step freq. within 2 std, share of walking"),
    ("valid_after3s_fraction", "valid, share of walking after 3 s"),
)
"""The metrics whose distribution over recordings an online report's summary figure shows."""

HIGHER_IS_BETTER = frozenset(k for k in HONESTY_KEYS if "cover2std" in k or k.startswith("valid"))
BY_MAGNITUDE = frozenset(("latency_vz_ms", "latency_vz_input_ms"))
#: The rows judged against the gait-event reference: again over the trusted references (honesty
#: is measured against those), where some are not.
REFERENCE_ONLINE_KEYS = frozenset(
    k for k, _ in SUMMARY_ONLINE_KEYS if k.startswith(("f_err", "speed_err", "f_cover", "speed_cover", "confidently"))
)
"""Signed columns whose worst recording is the one farthest from 0."""


@dataclass
class OnlineEvaluation(Evaluation):
    """An :class:`~yoyogait.evaluation.running.Evaluation` of the online estimator: its own columns,
    a preamble for the report, and its own figures (the online estimate of each recording, as
    :func:`~yoyogait.evaluation.figures.online_figure` draws it; the oscillator, which reports no
    validity, has none; summary: the distributions of :data:`ONLINE_DISTRIBUTION_KEYS` and the best
    and worst recording by the step frequency's error over the whole walking part)."""

    metric_keys: tuple = ONLINE_METRIC_KEYS
    title: str = "yoyogait online evaluation"
    figure_kind: str = "online"
    figure_estimators: tuple = ("online",)
    rank_key: tuple = ("f_err_whole_median_hz", "step frequency error over the whole walking part")
    distribution_keys: tuple = ONLINE_DISTRIBUTION_KEYS

    @property
    def preamble(self) -> list[str]:
        lines = [
            "Online evaluation: every recording replayed frame by frame at its capture rate through "
            "`yoyogait.OnlineEstimator` (causal front-end and the default gait filter), scored at the frame "
            "times against the offline centred velocities of the paper's pipeline and the foot-contact "
            "reference (synthetic walks: the truth). The adaptive oscillator runs beside it on the offline "
            "velocities at 25 Hz. pred200ms columns: the online prediction made at t for t + 0.2 s against the offline "
            "velocity at t + 0.2 s (the oscillator's: n/a). Honesty rows (online only): the share of walking time "
            "the estimate is within 2 reported standard deviations, and confidently wrong (error above 0.15 Hz "
            "or 0.15 m/s while valid and more than 2 std); sharpness: over the valid walking time, the median "
            "reported std beside the 95th percentile of the error (a calibrated std has 2 std near it). "
            "Worst: the recording with the highest value (lowest for "
            "shares within 2 std and valid, farthest from 0 for lags). "
            'Definitions: docs/online.md, section "Online evaluation".',
            "",
            self.summary_table(),
            "",
        ]
        return lines

    def summary_table(self) -> str:
        """The median over recordings and the worst recording of :data:`SUMMARY_ONLINE_KEYS`, per estimator."""
        return with_trusted_part(self, SUMMARY_ONLINE_KEYS, REFERENCE_ONLINE_KEYS, HIGHER_IS_BETTER, BY_MAGNITUDE)


def step_walk_items(seed: int = 0, rate_hz: float = 100.0) -> list[Item]:
    """Synthetic walks with a cadence (and speed) step, one per built-in subject (SYNTHETIC data)."""
    return [synthetic_item(walk) for walk in synth.step_walks(seed=seed, rate_hz=rate_hz)]


def run_item_online(item: Item, config: OnlineConfig | None = None) -> ItemResult | TaskFailure:
    """:func:`evaluate_item_online`, with what stops it as a :class:`TaskFailure`."""
    return outcome(evaluate_item_online, item, config)


def evaluate_online(
    items,
    *,
    progress: bool = False,
    dataset: str = "",
    synthetic: bool = False,
    failures=None,
    jobs: int = 1,
    executor=None,
    config: OnlineConfig | None = None,
    feet: bool = False,
) -> OnlineEvaluation:
    """The online evaluation of every item; an item that cannot be read or processed is reported.

    ``jobs`` > 1: in that many worker processes; ``executor``: any ``concurrent.futures.Executor``
    (e.g. :func:`~yoyogait.evaluation.parallel.dask_executor`). Same result, in the order of ``items``.
    ``feet``: each item's foot points go into the frames (:func:`evaluate_item_online`; an item
    without them is reported).
    """
    done, failures = evaluate_items(
        functools.partial(evaluate_item_online, feet=True) if feet else evaluate_item_online,
        items,
        (config,),
        progress="evaluating online" if progress else None,
        failures=failures,
        jobs=jobs,
        executor=executor,
    )
    return OnlineEvaluation(ONLINE_ESTIMATORS, done, failures, dataset, synthetic)
