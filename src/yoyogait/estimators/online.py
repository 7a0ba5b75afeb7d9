"""The online estimator: motion-capture frames in, gait estimates out, nothing from the future.

``OnlineEstimator`` wraps the C++ ``yoyogait::OnlineEstimator`` (docs/online.md): per frame, the
causal centre of the chosen points, its velocity by a constant-acceleration Kalman filter, the
heading, forward and vertical velocity, and the default gait estimator fed every 40 ms with the
mean velocity of the interval.  Unlike :func:`yoyogait.pipeline.gait_velocities` (the paper's
offline pipeline: centred Savitzky-Golay, spline gap filling, resampling), no output at time t
depends on a frame after t.

Threads: one estimator serves one caller at a time.  ``update``, ``predict``, ``run`` and ``reset``
take a flag in C++ (set and cleared there, so that no exception, not even one raised by a signal
handler, can leave it set); a call made while another thread is inside one of them raises
:class:`ConcurrentUseError` instead of waiting or corrupting the state.  Use one estimator per
thread, or serialise the calls yourself.
"""

from __future__ import annotations

import dataclasses
import math
from collections.abc import Sequence
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from .. import _core
from .._files import atomic_file
from ..errors import InputError, YoyogaitError
from ..io.recording import AXES, Recording
from ..pipeline import events, points
from .config import OnlineConfig
from .records import fields_of

__all__ = [
    "ONLINE_CSV_COLUMNS",
    "ONLINE_ESTIMATE_COLUMNS",
    "OnlineConfig",
    "OnlineEstimator",
    "OnlineResult",
    "OnlineStatus",
    "InvalidReason",
    "ConcurrentUseError",
    "MAX_POINTS",
    "MAX_FEET",
    "MAX_BELT_SPEED_MPS",
    "config_for_point",
    "why_not_valid",
    "reason_words",
]

OnlineStatus = _core.OnlineStatus
#: The bits of ``invalid_reason`` (docs/online.md, "Validity").
InvalidReason = _core.InvalidReason
"""What ``update`` did with a frame: USED, ALL_MISSING, TIME_NOT_INCREASING, GAP_RESTART, NON_FINITE."""


def reason_words(reason) -> str:
    """A reason (InvalidReason, ImuReason) as lower-case words: MODEL_NOT_HOLDING -> "model not holding"."""
    return reason.name.lower().replace("_", " ")


def why_not_valid(invalid_reason: int) -> str:
    """The reasons of an ``invalid_reason`` by name, in lower-case words ("acquiring, model not
    holding"); "" when there is none (valid)."""
    bits = int(invalid_reason)
    return ", ".join(reason_words(r) for r in InvalidReason if bits & int(r))


MAX_POINTS = 16
#: The most foot points an estimator takes (for a treadmill's belt).
MAX_FEET = 4
#: The highest known belt speed accepted [m/s].
MAX_BELT_SPEED_MPS = 10.0


def check_belt_speed(speed_mps: float | None, what: str = "belt speed") -> None:
    """InputError naming ``what`` unless ``speed_mps`` is None or a belt speed in [0, MAX_BELT_SPEED_MPS] m/s."""
    if speed_mps is not None and not (
        isinstance(speed_mps, (int, float)) and math.isfinite(speed_mps) and 0.0 <= speed_mps <= MAX_BELT_SPEED_MPS
    ):
        raise InputError(f"{what} must be a speed in m/s in [0, {MAX_BELT_SPEED_MPS:g}], not {speed_mps!r}")


class ConcurrentUseError(YoyogaitError, RuntimeError):
    """An OnlineEstimator was called from a second thread while a call was running."""


# The errors the native per-frame calls raise.
_core.set_online_errors(InputError, ConcurrentUseError)


#: The fields of the native OnlineEstimate as its C++ table declares them (YOYOGAIT_ONLINE_ESTIMATE_FIELDS,
#: include/yoyogait/online/online_estimate.hpp): name, type, unit, doc, in the table's order.
ONLINE_ESTIMATE_FIELDS = fields_of("OnlineEstimate")


def column_of(field_name: str) -> str:
    """The column of a record field in every per-frame table: the record's ``t_s`` is ``time_s``, as the
    time of every table of the package; the others keep their names."""
    return "time_s" if field_name == "t_s" else field_name


#: One column per field of OnlineEstimate, in the table's order (``OnlineResult``, the LSL estimate stream).
ONLINE_ESTIMATE_COLUMNS: tuple[str, ...] = tuple(column_of(f.name) for f in ONLINE_ESTIMATE_FIELDS)

#: The columns of an online estimate CSV (``estimate --online``, ``live --record``), in order.
ONLINE_CSV_COLUMNS = (
    "time_s",
    "vx_mps",
    "vz_mps",
    "vx_hat_mps",
    "vz_hat_mps",
    "step_frequency_hz",
    "step_frequency_std_hz",
    "speed_mps",
    "speed_std_mps",
    "heading_rad",
    "gait_phase",
    "walking",
    "status",
    "input_latency_s",
    "next_step_in_s",
    "valid",
    "invalid_reason",
    "belt_speed_mps",
)


def csv_formats(columns) -> list[str]:
    """printf formats of per-frame columns, from the record table's types: the time to the microsecond,
    other floats to 6 significant digits, flags, codes and counts as integers."""
    types = {column_of(f.name): f.type for f in ONLINE_ESTIMATE_FIELDS}
    return ["%.6f" if c == "time_s" else "%.6g" if types[c] == "float" else "%d" for c in columns]


@dataclass
class OnlineResult:
    """One row per frame of ``OnlineEstimator.run``: the fields of the native OnlineEstimate as arrays, in the
    order of its table (docs/records.md; a test holds them to it), then the predictions."""

    time_s: np.ndarray
    vx_mps: np.ndarray
    vz_mps: np.ndarray
    vh_a_mps: np.ndarray
    vh_b_mps: np.ndarray
    heading_rad: np.ndarray
    walk_a_mps: np.ndarray
    walk_b_mps: np.ndarray
    vx_hat_mps: np.ndarray
    vz_hat_mps: np.ndarray
    step_frequency_hz: np.ndarray
    step_frequency_std_hz: np.ndarray
    speed_mps: np.ndarray
    speed_std_mps: np.ndarray
    gait_phase: np.ndarray
    next_step_in_s: np.ndarray
    """Time to the next step (gait_phase 0.75, the pelvis low point) [s]; NaN while not walking or no phase is known."""
    input_latency_s: np.ndarray
    estimate_age_s: np.ndarray
    status: np.ndarray
    estimator_status: np.ndarray
    walking: np.ndarray
    estimator_fed: np.ndarray
    points_seen: np.ndarray
    valid: np.ndarray
    """The estimate can be used as it is (``invalid_reason`` 0)."""
    invalid_reason: np.ndarray
    """Why not: a set of :class:`InvalidReason` bits."""
    input_noise_m: np.ndarray
    belt_speed_mps: np.ndarray
    """The treadmill belt speed in ``speed_mps`` (known, or from the stance feet; 0 overground)."""
    belt_speed_std_mps: np.ndarray
    predict_ahead_s: np.ndarray = field(default_factory=lambda: np.zeros(0))
    """The horizons of the predictions (m) [s]."""
    pred_vx_mps: np.ndarray = field(default_factory=lambda: np.zeros((0, 0)))
    """n x m: v_x predicted at each frame for time_s + predict_ahead_s[j] (``OnlineEstimator.predict``)."""
    pred_vz_mps: np.ndarray = field(default_factory=lambda: np.zeros((0, 0)))
    pred_vx_std_mps: np.ndarray = field(default_factory=lambda: np.zeros((0, 0)))
    """n x m: their standard deviations (inf before the estimator is fed)."""
    pred_vz_std_mps: np.ndarray = field(default_factory=lambda: np.zeros((0, 0)))

    def __len__(self) -> int:
        return len(self.time_s)

    def to_csv(self, path, columns=ONLINE_CSV_COLUMNS):
        """Write ``columns`` (default :data:`ONLINE_CSV_COLUMNS`, what ``estimate --online`` writes) as
        CSV to ``path``, through a temporary file; returns the path."""
        table = np.column_stack([getattr(self, c).astype(float) for c in columns])
        header, fmt = ",".join(columns), csv_formats(columns)
        atomic_file(Path(path), lambda p: np.savetxt(p, table, delimiter=",", header=header, comments="", fmt=fmt))
        return Path(path)


def config_for_point(choice: points.PointChoice, config: OnlineConfig | None = None) -> OnlineConfig:
    """``config`` (default: the defaults) for following ``choice``: ``gait_in_place`` false for a hand
    (:attr:`~yoyogait.pipeline.points.PointChoice.is_hand`), whose rise and fall in place are gestures."""
    config = config if config is not None else OnlineConfig()
    return dataclasses.replace(config, gait_in_place=False) if choice.is_hand else config


class OnlineEstimator:
    """Online gait estimation from motion-capture frames (docs/online.md).

    >>> est = OnlineEstimator(["LASI", "RASI", "LPSI", "RPSI"], up_axis="z", length_unit_m=0.001)
    >>> e = est.update(0.01, frame)          # frame: 4 x 3 coordinates (mm), NaN where missing
    >>> est = OnlineEstimator.for_recording(rec)   # the pelvis points of a Recording, found by name
    >>> result = est.run(rec)                # every frame, replayed in C++: an OnlineResult

    Treadmills (docs/online.md, "Treadmills"): ``feet`` names foot points (heels, at most
    :data:`MAX_FEET`) that follow the pelvis points in every frame; the belt's velocity is then
    estimated from the feet in stance and the walking speed is the belt's plus the pelvis's own.
    :meth:`set_belt_speed_mps` gives a known belt speed instead, at any time (a callback of a live loop).
    """

    def __init__(
        self,
        point_names: Sequence[str],
        up_axis: str = "z",
        length_unit_m: float = 1.0,
        config: OnlineConfig | None = None,
        *,
        feet: Sequence[str] = (),
    ):
        names = [point_names] if isinstance(point_names, str) else [str(n) for n in point_names]
        if not 1 <= len(names) <= MAX_POINTS:
            raise InputError(f"point_names must name 1 to {MAX_POINTS} points, got {len(names)}")
        foot_names = [feet] if isinstance(feet, str) else [str(n) for n in feet]
        if len(foot_names) > MAX_FEET:
            raise InputError(f"feet must name at most {MAX_FEET} points, got {len(foot_names)}")
        self.point_names: tuple[str, ...] = tuple(names)
        self.feet: tuple[str, ...] = tuple(foot_names)
        self.up_axis = AXES[points.axis_index(up_axis)]
        if not (isinstance(length_unit_m, (int, float)) and np.isfinite(length_unit_m) and length_unit_m > 0):
            raise InputError(f"length_unit_m must be a finite number > 0, got {length_unit_m!r}")
        self.length_unit_m = float(length_unit_m)
        self.config = config if config is not None else OnlineConfig()
        if not isinstance(self.config, OnlineConfig):
            raise InputError(f"config must be an OnlineConfig, got {type(self.config).__name__}")
        self._impl = _core.OnlineEstimator(
            len(names), AXES.index(self.up_axis), self.length_unit_m, self.config.to_native(), len(foot_names)
        )
        # The per-frame path: the native calls bound to this instance, no Python code per call (they
        # read the frame without an array copy, check its size, take the estimator's flag against
        # concurrent use and raise InputError / ConcurrentUseError as the methods below document).
        # The methods of the class stay as the reference of the same behaviour.
        vars(self).update(
            update=self._impl.update_frame, update_point=self._impl.update_point, predict=self._impl.predict_horizon
        )

    @classmethod
    def for_recording(cls, rec: Recording, point=None, *, up_axis: str | None = None, config=None, feet=None):
        """An estimator for ``rec``'s points: the pelvis markers found by name (``point=None``), or
        ``point`` as :func:`yoyogait.pipeline.points.choose_point` takes it; the up axis from the
        file, else detected (:func:`yoyogait.pipeline.points.resolve_up_axis`). Recordings are in metres.
        ``feet``: foot points for a treadmill's belt, as :func:`yoyogait.pipeline.events.feet_of` takes
        them (``True``: found by name); None: none. Following a hand (:attr:`PointChoice.is_hand`), the
        config's ``gait_in_place`` is set false: a hand's bobs in place are gestures."""
        choice = points.choose_point(rec, point)
        if len(choice.names) > MAX_POINTS:
            raise InputError(f"{rec.source or 'recording'}: {len(choice.names)} points, at most {MAX_POINTS}")
        up, _ = points.resolve_up_axis(rec, up_axis)
        foot_names: list[str] = []
        if feet is not None and feet is not False:
            found = events.feet_of(rec, None if feet is True else feet) if rec.point_names else {}
            if not found:
                raise InputError(f"{rec.source or 'recording'}: no foot points found (give them by name)")
            foot_names = list(found.values())
        return cls(choice.names, up, 1.0, config_for_point(choice, config), feet=foot_names)

    @staticmethod
    def _busy(what: str) -> ConcurrentUseError:
        return ConcurrentUseError(
            f"OnlineEstimator.{what} called while another thread is using this estimator; "
            "use one estimator per thread or serialise the calls"
        )

    def update(self, t_s: float, positions):
        """One frame at ``t_s`` [s]: positions of the points (k x 3, in the length unit, NaN where
        missing; an array of float64 is read in place, anything else converted). Returns the native
        OnlineEstimate; bad frames get a ``status``, never an exception. (Each instance binds the native
        call itself as ``update``: this method is what it does.)"""
        return self._impl.update_frame(t_s, positions)

    def update_point(self, t_s: float, x: float, y: float, z: float):
        """``update`` of an estimator of one point, its coordinates as numbers (no array to build)."""
        return self._impl.update_point(t_s, x, y, z)

    @property
    def max_horizon_s(self) -> float:
        """The longest horizon ``predict`` accepts [s]."""
        return float(_core.OnlineEstimator.max_horizon_s)

    def predict(self, horizon_s: float):
        """Forward and vertical velocity ``horizon_s`` [s] after the last frame, with standard
        deviations (rates of speed and cadence included; docs/online.md sec. 5): a native
        OnlinePrediction (t_s, vx_mps, vz_mps, vx_std_mps, vz_std_mps, valid). ``predict(0)`` is the
        last estimate's vx_hat_mps, vz_hat_mps; a horizon outside [0, max_horizon_s] raises InputError.
        (Bound natively per instance, as ``update``.)"""
        return self._impl.predict_horizon(horizon_s)

    def run(
        self, recording: Recording | np.ndarray, positions=None, *, predict_ahead_s: Sequence[float] = (0.2,)
    ) -> OnlineResult:
        """Every frame through ``update``, in C++, continuing from the current state.

        ``run(recording)``: the recording's frames (its points by name, metres converted to the
        length unit). ``run(time_s, positions)``: arrays (n) and (n x k x 3) in the length unit.
        ``predict_ahead_s``: after each frame, ``predict(h)`` for each h; the result's ``pred_*``
        arrays (frames x horizons).
        """
        horizons = _horizons(predict_ahead_s)
        if isinstance(recording, Recording):
            if positions is not None:
                raise InputError("run(recording) takes no positions")
            t = np.asarray(recording.time_s, dtype=np.float64)
            p = recording.points(list(self.point_names) + list(self.feet)) / self.length_unit_m
        else:
            if positions is None:
                raise InputError("run(time_s, positions) needs positions")
            t = np.asarray(recording, dtype=np.float64)
            p = np.asarray(positions, dtype=np.float64)
        if t.ndim != 1:
            raise InputError(f"time_s must be one-dimensional, got shape {t.shape}")
        k = len(self.point_names) + len(self.feet)
        if p.shape != (len(t), k, 3):
            raise InputError(f"positions must be frames x {k} x 3 = ({len(t)}, {k}, 3), got {p.shape}")
        t = np.ascontiguousarray(t)
        p = np.ascontiguousarray(p)
        try:
            out = self._impl.run(t, p, horizons)
        except _core.ConcurrentUse:
            raise self._busy("run") from None
        m = len(horizons)
        for key in ("pred_vx_mps", "pred_vz_mps", "pred_vx_std_mps", "pred_vz_std_mps"):
            out[key] = out[key].reshape(len(t), m)
        return OnlineResult(**out, predict_ahead_s=horizons)

    def set_belt_speed_mps(self, speed_mps: float | None) -> None:
        """A known treadmill belt speed [m/s] from the next frame on (it may change at any time: a
        live loop's callback); ``None`` or NaN: unknown again (the stance feet's estimate, if there are
        feet). Its direction: the stance feet's, else against ``treadmill_heading_rad``. The estimate's
        ``belt_speed_mps`` reports the speed in use."""
        if isinstance(speed_mps, float) and math.isnan(speed_mps):
            speed_mps = None
        check_belt_speed(speed_mps)
        try:
            self._impl.set_belt_speed_mps(math.nan if speed_mps is None else float(speed_mps))
        except _core.ConcurrentUse:
            raise self._busy("set_belt_speed_mps") from None

    @property
    def belt_speed_mps(self) -> float | None:
        """The known belt speed given by :meth:`set_belt_speed_mps` [m/s]; None when none is."""
        v = float(self._impl.belt_speed_mps)
        return None if math.isnan(v) else v

    def reset(self) -> None:
        """Back to the state before the first frame (a known belt speed is kept: it is an input)."""
        try:
            self._impl.reset()
        except _core.ConcurrentUse:
            raise self._busy("reset") from None

    @property
    def feet_step_frequency_hz(self) -> float | None:
        """The step frequency the first two feet show at the last frame [Hz] (their separation along
        the heading: docs/online.md, "Feet"); None while not known (fewer than two feet, the first
        steps, an unsteady rhythm)."""
        v = float(self._impl.feet_step_frequency_hz)
        return v if v > 0.0 else None

    @property
    def ignored_frames(self) -> int:
        """Frames ignored since the last reset (timestamp not finite, absurd, not increasing, or an
        unconfirmed jump ahead)."""
        return int(self._impl.ignored_frames)

    @property
    def estimate(self):
        """The gait estimator's last native Estimate (at its last sample)."""
        return self._impl.estimate


def _horizons(values) -> np.ndarray:
    """Prediction horizons as a float array; InputError unless each is in [0, max_horizon_s]."""
    try:
        h = np.ascontiguousarray(np.atleast_1d(np.asarray(values, dtype=np.float64)))
    except (TypeError, ValueError):
        raise InputError(f"prediction horizons must be numbers in seconds, got {values!r}") from None
    top = float(_core.OnlineEstimator.max_horizon_s)
    if h.ndim != 1 or not np.all((h >= 0.0) & (h <= top)):
        raise InputError(f"prediction horizons must be in [0, {top:g}] s, got {values!r}")
    return h
