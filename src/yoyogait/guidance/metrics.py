"""What a guidance designer looks at, per guided walk and per feedback source (docs/guidance.md, sec. 4).

* ``force_osc_step_n``: RMS of the horizontal cable force at the step frequency and its second
  harmonic [N].  The walker's gait phase ``theta`` is known, so each component is found by
  demodulation: the force times ``exp(-i k theta)`` through a zero-phase 4th-order Butterworth
  low-pass at 0.3 Hz, for k = 1, 2: a band-pass that follows the cadence through its changes.
  Over the walking part (speed above 0.3 m/s).
* ``force_osc_stride_n``: the same at the stride frequency (k = 1/2, the sideways sway) [N].
* ``robot_accel_rms_mps2``, ``robot_jerk_rms_mps3``: of the robot's horizontal motion, by
  differences of its velocity at the frame rate, over the guided part.
* ``path_error_rms_m``, ``path_error_max_m``: the distance of the walker's guided point (its
  hand's mean position) from the path, sideways (the path's ends extended straight: going past
  the goal is the overshoot, not a path error).
* ``overshoot_m``: the furthest the guided point went past a stop or the goal, along the path's
  direction there, before the guidance went on (or the walk ended).
* ``time_to_goal_s``: when it came within the goal radius of the last waypoint (NaN: never).
* ``force_start_peak_n``, ``force_stop_peak_n``, ``force_turn_peak_n``: the largest cable
  tension within 3 s after each start and each commanded stop, and within 1.5 s of each corner.
* ``slack_s``: time the cable was slack after it first became taut.
* ``lag_s``: the delay that best aligns the source's velocity with the intended one (least squares
  over shifts of 0-1.5 s), both low-passed at 0.5 Hz without phase shift first, so that the step
  oscillation and the noise do not count: the lag of the walking velocity's changes; NaN for ``none``.
* ``source_osc_mps``: RMS of the source's velocity at the step frequency and its harmonic.
"""

from __future__ import annotations

import math

import numpy as np

from .simulation import GuidanceRun

__all__ = ["METRIC_KEYS", "run_metrics", "harmonic_rms", "WALKING_SPEED_MPS"]

METRIC_KEYS: tuple[str, ...] = (
    "force_osc_step_n",
    "force_osc_stride_n",
    "robot_accel_rms_mps2",
    "robot_jerk_rms_mps3",
    "path_error_rms_m",
    "path_error_max_m",
    "overshoot_m",
    "time_to_goal_s",
    "force_start_peak_n",
    "force_stop_peak_n",
    "force_turn_peak_n",
    "slack_s",
    "lag_s",
    "source_osc_mps",
)

WALKING_SPEED_MPS = 0.3
"""Above this intended speed a sample counts as walking (for the oscillation metrics)."""
_DEMOD_CUTOFF_HZ = 0.3
_MAX_LAG_S = 1.5
_LAG_CUTOFF_HZ = 0.5


def harmonic_rms(time_s, values, theta_rad, harmonics, mask=None) -> float:
    """RMS [unit of ``values``] of the components of ``values`` (n, or n x m) at ``k theta`` for each
    k of ``harmonics``, summed over components and columns, over ``mask`` (default: all samples)."""
    t = np.asarray(time_s, float)
    v = np.asarray(values, float)
    v = v[:, None] if v.ndim == 1 else v
    if len(t) < 30:
        return math.nan
    fs = 1.0 / float(np.median(np.diff(t)))
    from scipy import signal  # scipy.signal takes about a second to import: only where it is used

    sos = signal.butter(4, _DEMOD_CUTOFF_HZ, fs=fs, output="sos")
    slow = signal.sosfiltfilt(sos, v, axis=0)
    fast = v - slow
    m = np.ones(len(t), bool) if mask is None else np.asarray(mask, bool)
    if not m.any():
        return math.nan
    power = 0.0
    for k in harmonics:
        carrier = np.exp(-1j * k * np.asarray(theta_rad, float))[:, None]
        z = fast * carrier
        c = signal.sosfiltfilt(sos, z.real, axis=0) + 1j * signal.sosfiltfilt(sos, z.imag, axis=0)
        power += float(np.mean(2.0 * np.abs(c[m]) ** 2, axis=0).sum())
    return math.sqrt(power)


def _lag_s(t, source_v, intent_v, mask) -> float:
    dt = float(np.median(np.diff(t)))
    if len(t) < 30:
        return math.nan
    from scipy import signal  # scipy.signal takes about a second to import: only where it is used

    sos = signal.butter(4, _LAG_CUTOFF_HZ, fs=1.0 / dt, output="sos")
    source_v = signal.sosfiltfilt(sos, source_v, axis=0)  # zero-phase: no shift of its own
    intent_v = signal.sosfiltfilt(sos, intent_v, axis=0)
    best, best_err = math.nan, math.inf
    n = len(t)
    for shift in range(0, int(round(_MAX_LAG_S / dt)) + 1):
        a = source_v[shift:]
        b = intent_v[: n - shift]
        mm = mask[shift:]
        if mm.sum() < 10:
            break
        err = float(np.mean(np.sum((a[mm] - b[mm]) ** 2, axis=1)))
        if err < best_err - 1e-15:
            best, best_err = shift * dt, err
    return best


def _peak(t, tension, events, before_s, after_s) -> float:
    peaks = [tension[(t >= e - before_s) & (t <= e + after_s)] for e in events]
    peaks = [p.max() for p in peaks if p.size]
    return float(max(peaks)) if peaks else math.nan


def _overshoot_m(run: GuidanceRun) -> float:
    """The furthest past each stop and the goal the guided point went before the next start (or the end)."""
    path = run.path
    cum = path.cumulative_m
    points = [(float(s_stop), i) for i, s_stop in enumerate(cum) if 0 < i < len(cum) - 1 and path.stop_s[i] > 0]
    points.append((float(cum[-1]), len(cum) - 1))
    worst = 0.0
    for trigger_s, (_, i) in zip(run.stops_s, points):
        later = [s for s in run.starts_s if s > trigger_s]
        until = later[0] if later else math.inf
        window = (run.time_s >= trigger_s) & (run.time_s <= until)
        d = path.xy_m[i] - path.xy_m[i - 1]
        along = (run.guided_m[window] - path.xy_m[i]) @ (d / np.hypot(*d))
        if along.size:
            worst = max(worst, float(along.max()))
    return worst


def run_metrics(run: GuidanceRun) -> dict[str, float]:
    """The metrics of one guided walk (the keys of :data:`METRIC_KEYS`)."""
    t = run.time_s
    cfg = run.config
    guided = t >= cfg.start_s
    walking = (np.linalg.norm(run.intent_v_mps, axis=1) > WALKING_SPEED_MPS) & guided
    fh = run.force_n[:, :2]
    out: dict[str, float] = {}
    out["force_osc_step_n"] = harmonic_rms(t, fh, run.theta_rad, (1, 2), walking)
    out["force_osc_stride_n"] = harmonic_rms(t, fh, run.theta_rad, (0.5,), walking)
    dt = float(np.median(np.diff(t)))
    acc = np.diff(run.robot_v_mps, axis=0) / dt
    jerk = np.diff(acc, axis=0) / dt
    out["robot_accel_rms_mps2"] = float(np.sqrt(np.mean(np.sum(acc[guided[1:]] ** 2, axis=1))))
    out["robot_jerk_rms_mps3"] = float(np.sqrt(np.mean(np.sum(jerk[guided[2:]] ** 2, axis=1))))
    err = run.path.distance(run.guided_m, extend_ends=True)
    out["path_error_rms_m"] = float(np.sqrt(np.mean(err[guided] ** 2)))
    out["path_error_max_m"] = float(err[guided].max())
    out["overshoot_m"] = _overshoot_m(run)
    out["time_to_goal_s"] = float(run.goal_s - cfg.start_s) if math.isfinite(run.goal_s) else math.nan
    tension = run.tension_n
    out["force_start_peak_n"] = _peak(t, tension, run.starts_s, 0.0, 3.0)
    out["force_stop_peak_n"] = _peak(t, tension, run.stops_s, 0.0, 3.0)
    out["force_turn_peak_n"] = _peak(t, tension, run.turns_s, 1.5, 1.5)
    taut = np.flatnonzero(~run.slack)
    out["slack_s"] = float(run.slack[taut[0] :].sum() * dt) if taut.size else float(len(t) * dt)
    if run.source == "none":
        out["lag_s"] = math.nan
    else:
        out["lag_s"] = _lag_s(t, run.source_v_mps, run.intent_v_mps, guided)
    out["source_osc_mps"] = harmonic_rms(t, run.source_v_mps, run.theta_rad, (1, 2), walking)
    return out
