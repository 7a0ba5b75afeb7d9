"""The paper's velocity pipeline (Sec. IV-A): positions -> forward and vertical velocity at 25 Hz.

1. Follow one point: the pelvis centre by default (:mod:`yoyogait.pipeline.points`).
2. Fill gaps of at most ``max_gap_s`` (0.2 s) with a cubic spline through the
   samples around them; longer gaps stay NaN, because a spline across a
   missing step would invent one.
3. Differentiate with a Savitzky-Golay filter (``scipy.signal.savgol_filter``,
   ``deriv=1``) whose window is given in seconds, so that the smoothing is the
   same whatever the capture rate.  The default 0.25 s, cubic, keeps 99 % of a
   2 Hz step oscillation and 86 % of its 4 Hz harmonic and falls to ~10 % by
   8 Hz, which also makes it the anti-alias filter for step 4.
4. Resample to ``rate_hz`` (25 Hz, the paper's T = 0.04 s) by linear
   interpolation; a sample next to a NaN stays NaN.
5. Forward velocity ``vx`` = 2-norm of the two horizontal components, as the
   paper does.  That norm cannot go below zero and folds lateral sway into
   the forward speed, so ``vx_signed`` (always computed) is the horizontal
   velocity along the walking heading (the direction of the horizontal
   velocity averaged over ``heading_window_s``); ``forward="heading"`` makes
   it ``vx``.  Vertical velocity ``vz`` is the up-axis component.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from .. import _table
from .._sample_time import RESAMPLE_RATE_HZ
from ..errors import InputError
from ..io.recording import AXES, MAX_SPEED_MPS, Recording, check_time
from . import events, points
from .signals import fill_short_gaps, resample, runs, walking_heading
from .treadmill import Treadmill, detect_treadmill

__all__ = [
    "GaitVelocities",
    "gait_velocities",
    "check_point_motion",
    "fill_short_gaps",
    "savgol_velocity",
    "resample",
    "runs",
    "savgol_window_samples",
    "walking_heading",
]

FORWARD_DEFINITIONS = ("norm", "heading")


@dataclass
class GaitVelocities:
    """Forward and vertical velocity of one point, resampled to ``rate_hz``.

    ``vx``/``vz`` are m/s, NaN where the source had a gap longer than
    ``max_gap_s``.  ``vx`` follows ``forward``: "norm" (the paper's 2-norm of
    the horizontal velocity) or "heading" (signed, along the walking
    heading); ``vx_signed`` is always the latter.  ``walking`` marks the
    samples where the person walks (from gait events when the recording has
    feet, else from the horizontal speed).
    """

    time_s: np.ndarray
    vx: np.ndarray
    vz: np.ndarray
    rate_hz: float
    point: str
    up_axis: str
    forward: str
    vx_signed: np.ndarray
    walking: np.ndarray
    source: str = ""
    settings: dict = field(default_factory=dict)
    treadmill: Treadmill | None = (
        None  # the treadmill check (its belt is in vx when detected); None for given velocities
    )
    #: The gait events found for ``walking`` (with the up axis used here; their ``feet`` say which
    #: points), None when none were; kept so that they need not be detected again.
    gait_events: events.GaitEvents | None = field(default=None, repr=False, compare=False)

    def __repr__(self) -> str:
        n = len(self.time_s)
        duration_s = float(self.time_s[-1] - self.time_s[0]) if n > 1 else 0.0
        return (
            f"GaitVelocities({self.source or 'recording'}: {n} samples at {self.rate_hz:g} Hz, {duration_s:.2f} s, "
            f"{self.point}, up {self.up_axis}, forward {self.forward}, walking {self.walking_s:.2f} s, "
            f"usable {self.usable_s:.2f} s)"
        )

    def to_columns(self) -> dict[str, np.ndarray]:
        """Named columns, units in every name: time_s, vx_mps, vz_mps, vx_signed_mps, walking."""
        return {
            "time_s": np.asarray(self.time_s, dtype=float),
            "vx_mps": np.asarray(self.vx, dtype=float),
            "vz_mps": np.asarray(self.vz, dtype=float),
            "vx_signed_mps": np.asarray(self.vx_signed, dtype=float),
            "walking": np.asarray(self.walking, dtype=bool),
        }

    def to_dataframe(self):
        """:meth:`to_columns` as a pandas DataFrame (needs the extra ``yoyogait[pandas]``)."""
        return _table.to_dataframe(self.to_columns())

    def to_csv(self, path):
        """Write :meth:`to_columns` as CSV to ``path`` (through a temporary file); returns the path."""
        return _table.write_csv(path, self.to_columns())

    @property
    def finite(self) -> np.ndarray:
        """True where both velocities are known."""
        return np.isfinite(self.vx) & np.isfinite(self.vz)

    @property
    def usable_s(self) -> float:
        """Seconds of samples with both velocities known."""
        return float(self.finite.sum()) / self.rate_hz

    @property
    def walking_s(self) -> float:
        """Seconds of walking with both velocities known."""
        return float((self.walking & self.finite).sum()) / self.rate_hz

    def walking_part(self) -> slice:
        """The longest stretch of consecutive samples that are walking and known (maybe empty)."""
        spans = runs(self.walking & self.finite)
        if not spans:
            return slice(0, 0)
        start, stop = max(spans, key=lambda s: s[1] - s[0])
        return slice(start, stop)


MIN_USABLE_S = 1.5
"""Seconds of known velocity the offline estimator and the DFT check need (about three steps)."""


@points.reusing_trajectories()  # the pelvis centre serves the point, the treadmill check and the gait events
def gait_velocities(
    recording: Recording,
    point=None,
    rate_hz: float = RESAMPLE_RATE_HZ,
    *,
    window_s: float = 0.25,
    polyorder: int = 3,
    max_gap_s: float = 0.2,
    forward: str = "norm",
    up_axis: str | None = None,
    heading_window_s: float = 1.0,
    min_usable_s: float = MIN_USABLE_S,
    hand_side: str = "right",
    belt_speed_mps: float | None = None,
    feet=None,
) -> GaitVelocities:
    """Forward and vertical velocity of ``point`` at ``rate_hz``, by the paper's pipeline.

    ``rate_hz``: the rate the velocities are resampled to (default 1 / the estimator's
    ``sample_time_s``, the paper's 25 Hz), not the capture rate (``io.read``'s ``capture_rate_hz``).

    ``point``: None or "pelvis" (the pelvis centre), "hand", a point name or a
    list of names to average.  ``window_s``/``polyorder``: the Savitzky-Golay
    differentiator.  ``max_gap_s``: the longest gap filled by interpolation.
    ``forward``: "norm" (paper) or "heading" (signed).  ``up_axis``: override
    the file's or the detected one.  ``min_usable_s``: fewer seconds of known
    velocity than this raise InputError ("shorter than the filter needs"),
    because neither the DFT check nor the estimator can lock onto a step
    frequency from less than about three steps (1.5 s at a normal cadence).
    On a treadmill (detected: :mod:`yoyogait.pipeline.treadmill`) the belt's
    velocity is added to the horizontal velocity, so that ``vx`` is the walking
    speed; ``belt_speed_mps`` gives the belt speed (and marks the recording a
    treadmill walk) instead of the stance feet.
    ``feet``: foot points for the walking part (else found by name).
    """
    if forward not in FORWARD_DEFINITIONS:
        raise InputError(f"forward must be one of {', '.join(FORWARD_DEFINITIONS)}, not {forward!r}")
    if not (rate_hz > 0 and window_s > 0 and max_gap_s >= 0):
        raise InputError("rate_hz and window_s must be positive and max_gap_s not negative")
    where = recording.source or "recording"
    settings = dict(
        window_s=window_s,
        polyorder=polyorder,
        max_gap_s=max_gap_s,
        heading_window_s=heading_window_s,
        min_usable_s=min_usable_s,
    )

    treadmill = None
    if recording.velocities is not None:  # a CSV of ready velocities
        if belt_speed_mps is not None:
            raise InputError(f"{where}: holds ready velocities; a belt speed applies to positions only")
        up = "z"
        label = f"velocities from {where}"
        t = np.asarray(recording.time_s, dtype=float)
        check_time(t, where)
        given = np.column_stack([recording.velocities["vx"], recording.velocities["vz"]])
        rate_in = _rate(t, where)
        given = fill_short_gaps(given, rate_in, max_gap_s, kind="linear")
        _check_speed(t, np.hypot(given[:, 0], given[:, 1]), label, where)
        t_out, v_out = resample(t, given, rate_hz, max_gap_s=max_gap_s)
        vx, vz = v_out[:, 0], v_out[:, 1]
        v_h = np.column_stack([vx, np.zeros_like(vx)])
        forward_used = "file"
        vx_signed = vx.copy()
    else:
        up, _ = points.resolve_up_axis(recording, up_axis)
        trajectory = points.point_trajectory(recording, point, hand_side=hand_side)
        label = trajectory.label
        t, p = _uniform(np.asarray(recording.time_s, dtype=float), trajectory.positions_m, where, max_gap_s)
        rate_in = _rate(t, where)
        p = fill_short_gaps(p, rate_in, max_gap_s)
        _check_jumps(t, p, label, where)
        window = savgol_window_samples(window_s, rate_in, polyorder)
        v = savgol_velocity(p, rate_in, window, polyorder)
        t_out, v_out = resample(t, v, rate_hz)
        k = AXES.index(up)
        horizontal = [a for a in range(3) if a != k]
        v_h = v_out[:, horizontal]
        treadmill = detect_treadmill(recording, up, feet=feet, belt_speed_mps=belt_speed_mps)
        if treadmill.detected:  # the belt carries the person: add its velocity to the point's own
            v_h = v_h + treadmill.belt_velocity()
        vz = v_out[:, k]
        vx_signed = v_h_along_heading(v_h, rate_hz, heading_window_s)
        vx = np.hypot(v_h[:, 0], v_h[:, 1]) if forward == "norm" else vx_signed
        forward_used = forward

    usable_s = float((np.isfinite(vx) & np.isfinite(vz)).sum()) / rate_hz
    if usable_s < min_usable_s:
        raise InputError(
            f"{where}: recording shorter than the filter needs: {usable_s:.2f} s of usable velocity "
            f"({label}), at least min_usable_s={min_usable_s:g} s are needed"
        )

    walking, gait_events = events.walking_mask_and_events(
        recording, t_out, speed_mps=np.hypot(v_h[:, 0], v_h[:, 1]), rate_hz=rate_hz, up_axis=up, feet=feet
    )
    return GaitVelocities(
        time_s=t_out,
        vx=vx,
        vz=vz,
        rate_hz=float(rate_hz),
        point=label,
        up_axis=up,
        forward=forward_used,
        vx_signed=vx_signed,
        walking=walking,
        source=where,
        settings=settings,
        treadmill=treadmill,
        gait_events=gait_events,
    )


def savgol_window_samples(window_s: float, rate_hz: float, polyorder: int) -> int:
    """The odd number of samples that spans ``window_s`` (2 floor(n/2) + 1), at least polyorder + 2.

    The small tolerance keeps a rate read as 199.9999999 Hz from changing the window.
    """
    n = 2 * int(np.floor(window_s * rate_hz / 2 + 1e-6)) + 1
    return max(n, polyorder + 2 + (polyorder % 2))


def savgol_velocity(positions: np.ndarray, rate_hz: float, window: int, polyorder: int) -> np.ndarray:
    """Savitzky-Golay first derivative of each stretch without NaN; NaN elsewhere.

    A stretch shorter than the window has no derivative (NaN): the filter
    needs a full window to fit its polynomial.
    """
    from scipy.signal import savgol_filter  # scipy.signal takes about a second to import: only where it is used

    x = np.asarray(positions, dtype=float)
    out = np.full_like(x, np.nan)
    ok = np.all(np.isfinite(x.reshape(len(x), -1)), axis=1)
    for start, stop in runs(ok):
        if stop - start >= window:
            out[start:stop] = savgol_filter(
                x[start:stop], window, polyorder, deriv=1, delta=1.0 / rate_hz, axis=0, mode="interp"
            )
    return out


def v_h_along_heading(v_h: np.ndarray, rate_hz: float, heading_window_s: float) -> np.ndarray:
    """Horizontal velocity (n x 2) projected on the walking heading: the signed forward speed.

    A recording that never moves (a treadmill) uses its main axis of motion instead.
    """
    heading = walking_heading(v_h, rate_hz, heading_window_s)
    if heading is None:
        ok = np.all(np.isfinite(v_h), axis=1)
        if ok.sum() < 2:
            return np.full(len(v_h), np.nan)
        _, _, vt = np.linalg.svd(v_h[ok] - v_h[ok].mean(axis=0), full_matrices=False)
        axis = vt[0] if np.sum(v_h[ok] @ vt[0]) >= 0 else -vt[0]
        heading = np.broadcast_to(axis, v_h.shape)
    return np.sum(v_h * heading, axis=1)


def _check_speed(time_s: np.ndarray, speed_mps: np.ndarray, label: str, where: str) -> None:
    """InputError if the point moves faster than any person can: a corrupt sample, not gait."""
    with np.errstate(invalid="ignore"):
        fast = np.flatnonzero(speed_mps > MAX_SPEED_MPS)
    if fast.size:
        k = int(fast[np.argmax(speed_mps[fast])])
        raise InputError(
            f"{where}: {label} moves at {speed_mps[k]:.4g} m/s at {time_s[k]:.3f} s, faster than any person "
            f"({MAX_SPEED_MPS:g} m/s): a corrupt sample or a wrong length unit"
        )


def check_point_motion(recording: Recording, point=None, *, max_gap_s: float = 0.2, hand_side: str = "right") -> None:
    """InputError if ``point`` (as :func:`gait_velocities` takes it) moves faster than any person between two
    known samples: the check :func:`gait_velocities` makes, for the paths that do not run it (``estimate --online``)."""
    if recording.velocities is not None:
        return
    where = recording.source or "recording"
    trajectory = points.point_trajectory(recording, point, hand_side=hand_side)
    t, p = _uniform(np.asarray(recording.time_s, dtype=float), trajectory.positions_m, where, max_gap_s)
    p = fill_short_gaps(p, _rate(t, where), max_gap_s)
    _check_jumps(t, p, trajectory.label, where)


def _check_jumps(time_s: np.ndarray, positions_m: np.ndarray, label: str, where: str) -> None:
    """InputError if the point moves faster than any person between two consecutive known samples.

    The check is on the raw differences, before any smoothing: a jump that lasts (or a glitch longer
    than the two frames :func:`yoyogait.pipeline.points.drop_spikes` leaves out) is then a clear
    error, where after the Savitzky-Golay filter it would be a plausible-looking bump that throws the
    estimator off.  (The fastest pelvis of the 53 real recordings moves 10 m/s between two frames, a
    marker dropping out of the centre; the limit is 50 m/s.)
    """
    known = np.flatnonzero(np.all(np.isfinite(positions_m), axis=1))
    if known.size < 2:
        return
    step_m = np.linalg.norm(np.diff(positions_m[known], axis=0), axis=1)
    speed = step_m / np.diff(time_s[known])
    k = int(np.argmax(speed))
    if speed[k] > MAX_SPEED_MPS:
        a, b = known[k], known[k + 1]
        raise InputError(
            f"{where}: {label} jumps {step_m[k]:.3g} m between {time_s[a]:.3f} s and {time_s[b]:.3f} s "
            f"({speed[k]:.3g} m/s; no person moves faster than {MAX_SPEED_MPS:g} m/s): a corrupt sample "
            "or a wrong length unit"
        )


def _rate(time_s: np.ndarray, where: str = "recording") -> float:
    if len(time_s) < 2:
        raise InputError(f"{where}: a recording of one frame has no velocity")
    return 1.0 / float(np.median(np.diff(time_s)))


def _uniform(time_s: np.ndarray, positions: np.ndarray, where: str = "recording", max_gap_s: float = 0.2):
    """Positions on a uniform time grid (the SG filter assumes one); untouched when already uniform.

    A step between timestamps longer than ``max_gap_s`` stays a gap (NaN), and the timestamps must
    span a time their samples can fill (:func:`yoyogait.io.recording.check_time`), so that the grid
    stays about as long as the input.
    """
    if len(time_s) < 2:
        raise InputError(f"{where}: a recording of one frame has no velocity")
    check_time(time_s, where)
    dt = np.diff(time_s)
    step = float(np.median(dt))
    if np.all(np.abs(dt - step) <= 1e-3 * step):
        return time_s, positions
    return resample(time_s, positions, 1.0 / step, max_gap_s=max_gap_s)
