"""The lower-back IMU estimator: accelerometer and rate gyro in, gait estimates out, online.

``ImuOnlineEstimator`` wraps the C++ ``yoyogait::ImuOnlineEstimator`` (docs/imu.md): per sample
the orientation relative to gravity (Mahony's filter), the drift-free vertical velocity and forward
oscillation (high-pass and leaky integration of the gravity-free acceleration), the heading from
the rate gyro (relative), and the default gait estimator fed every 40 ms with (inverted-pendulum
speed + forward oscillation, vertical velocity).  With a magnetometer (``mag``, optional) the
heading is absolute, from magnetic north.  No output at time t depends on a sample after t.
"""

from __future__ import annotations

import dataclasses
import functools
import threading
from dataclasses import dataclass, field

import numpy as np

from .. import _core
from ..errors import InputError
from ..io.imu_recording import ImuRecording
from .config import ImuConfig
from .online import ConcurrentUseError, reason_words

__all__ = [
    "IMU_ESTIMATE_FIELDS", "ImuConfig", "ImuOnlineEstimator", "ImuReason", "ImuResult", "csv_formats", "why_not_valid",
]  # fmt: skip

ImuReason = _core.ImuReason
"""Why an estimate is not valid: OK, NON_FINITE, TIME_NOT_INCREASING, SATURATED, GAP, GRAVITY,
ACQUIRING, NOT_WALKING, IRREGULAR, UNCERTAIN, SPEED_IMPLAUSIBLE (include/yoyogait/imu/imu_estimate.hpp)."""

#: The fields of ImuEstimate as its C++ table declares them: (name, unit, doc), in the table's order.
IMU_ESTIMATE_FIELDS: tuple[tuple[str, str, str], ...] = tuple(tuple(f) for f in _core.imu_estimate_fields())


@dataclass
class ImuResult:
    """One row per input sample: ``columns`` maps each field of ImuEstimate (``t_s`` as ``time_s``)
    to an array; ``source`` names the recording, ``synthetic`` says whether it was SYNTHETIC."""

    columns: dict[str, np.ndarray]
    source: str = ""
    synthetic: bool = False
    config: ImuConfig = field(default_factory=ImuConfig)

    def __getitem__(self, name: str) -> np.ndarray:
        return self.columns[name]

    @property
    def time_s(self) -> np.ndarray:
        """The samples' times."""
        return self.columns["time_s"]

    def __len__(self) -> int:
        return int(self.columns["time_s"].shape[0])

    @property
    def cadence_spm(self) -> np.ndarray:
        """Cadence in steps per minute, 60 times the step frequency."""
        return 60.0 * self.columns["step_frequency_hz"]

    def column_names(self) -> list[str]:
        """The columns in the record table's order (``time_s`` first)."""
        return ["time_s" if n == "t_s" else n for n, _, _ in IMU_ESTIMATE_FIELDS]


@functools.cache
def _integer_columns() -> frozenset[str]:
    # Which fields are flags or enumerations: as the native estimate types them.
    probe = _core.ImuOnlineEstimator().update(0.0, np.array([0.0, 0.0, 9.81]), np.zeros(3))
    return frozenset(("time_s" if n == "t_s" else n) for n, _, _ in IMU_ESTIMATE_FIELDS
                     if not isinstance(getattr(probe, n), float))  # fmt: skip


def csv_formats(columns) -> list[str]:
    """printf formats of the IMU record's columns as ``yoyogait estimate`` and ``live --record`` write
    them: the time to the microsecond (a recording's clock may count from its epoch), flags and
    reasons as integers, the rest to 6 significant digits."""
    integers = _integer_columns()
    return ["%.6f" if c == "time_s" else "%d" if c in integers else "%.6g" for c in columns]


_REASON_CODES = frozenset(int(r) for r in ImuReason)


def why_not_valid(reason: int) -> str:
    """An IMU estimate's ``reason`` by name, in lower-case words ("not walking"); "" when valid (OK);
    the number itself when it is no ImuReason."""
    code = int(reason)
    if code not in _REASON_CODES:
        return str(code)
    return "" if code == int(ImuReason.OK) else reason_words(ImuReason(code))


def _three(name: str, value) -> np.ndarray:
    a = np.ascontiguousarray(value, dtype=float).reshape(-1)
    if a.shape != (3,):
        raise InputError(f"{name} must hold 3 values (x, y, z), got {a.size}")
    return a


class ImuOnlineEstimator:
    """Online gait estimates from one lower-back IMU (specific force in m/s^2, angular rate in
    rad/s, in the sensor's frame). ``config``: an :class:`ImuConfig` (``[imu]`` of a TOML file)."""

    def __init__(self, config: ImuConfig | None = None):
        self.config = ImuConfig() if config is None else config
        self._native = _core.ImuOnlineEstimator(self.config.to_native())
        self._lock = threading.Lock()

    def _locked(self):
        if not self._lock.acquire(blocking=False):
            raise ConcurrentUseError("ImuOnlineEstimator is in use by another thread; use one per thread")
        return self._lock

    def update(self, t_s: float, acc, gyr, mag=None):
        """One sample; returns the native ImuEstimate (fields as in IMU_ESTIMATE_FIELDS). ``mag``: the
        magnetic field in the sensor frame (any unit), optional: the heading becomes absolute."""
        a, g = _three("acc", acc), _three("gyr", gyr)
        m = None if mag is None else _three("mag", mag)
        lock = self._locked()
        try:
            return self._native.update(float(t_s), a, g) if m is None else self._native.update(float(t_s), a, g, m)
        finally:
            lock.release()

    def run(self, time_s, acc, gyr, mag=None, *, source: str = "", synthetic: bool = False) -> ImuResult:
        """Every sample through ``update``, in C++; one row per sample (``mag``: N x 3 or None)."""
        t = np.ascontiguousarray(time_s, dtype=float).reshape(-1)
        a = np.ascontiguousarray(acc, dtype=float)
        g = np.ascontiguousarray(gyr, dtype=float)
        m = None if mag is None else np.ascontiguousarray(mag, dtype=float)
        if a.shape != (t.size, 3) or g.shape != (t.size, 3):
            raise InputError(f"acc and gyr must be {t.size} x 3 like time_s, got {a.shape} and {g.shape}")
        if m is not None and m.shape != (t.size, 3):
            raise InputError(f"mag must be {t.size} x 3 like time_s, got {m.shape}")
        lock = self._locked()
        try:
            cols = self._native.run(t, a, g, m)
        finally:
            lock.release()
        columns = {k: np.asarray(v) for k, v in cols.items()}
        return ImuResult(columns=columns, source=source, synthetic=synthetic, config=self.config)

    def run_recording(self, recording: ImuRecording) -> ImuResult:
        """``run`` over a recording (its sensor height replaces the configured one when it has one)."""
        return self.run(
            recording.time_s,
            recording.acc_mps2,
            recording.gyr_rad_s,
            source=recording.source,
            synthetic=recording.synthetic,
        )

    def reset(self) -> None:
        """Back to the state before the first sample."""
        lock = self._locked()
        try:
            self._native.reset()
        finally:
            lock.release()


def estimator_for(recording: ImuRecording, config: ImuConfig | None = None) -> ImuOnlineEstimator:
    """An estimator for a recording: its sensor height (when it gives one) as the pendulum length."""
    cfg = ImuConfig() if config is None else config
    if recording.sensor_height_m is not None:
        cfg = dataclasses.replace(cfg, sensor_height_m=float(recording.sensor_height_m))
    return ImuOnlineEstimator(cfg)
