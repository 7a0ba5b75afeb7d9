"""The recording type of the IMU readers: one inertial sensor (accelerometer and rate gyro) over time."""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from ..errors import InputError

#: Standard gravity [m/s^2].
GRAVITY_MPS2 = 9.80665


@dataclass
class ImuBout:
    """One walking bout of a reference system: its span, its mean values, its initial contacts and the
    strides it measured (``strides_s``: start and end of each, N x 2; empty when the source lists none)
    with their speeds (``stride_speeds_mps``, one per row of ``strides_s``; empty when the source gives
    none: the bout's ``speed_mps`` is their mean, as its cadence is the strides').

    A reference does not measure every stride between its contacts: where a contact is missed or
    counted twice (a turn, a pause), its stride is left out of its means; ``strides_s`` holds those
    it kept."""

    start_s: float
    end_s: float
    cadence_spm: float
    speed_mps: float
    stride_time_s: float
    contact_times_s: np.ndarray = field(default_factory=lambda: np.zeros(0))
    strides_s: np.ndarray = field(default_factory=lambda: np.zeros((0, 2)))
    stride_speeds_mps: np.ndarray = field(default_factory=lambda: np.zeros(0))


@dataclass
class ImuRecording:
    """Specific force (m/s^2) and angular rate (rad/s) of one sensor in its own frame, N x 3 each.

    ``time_s`` holds every sample's timestamp; ``rate_hz`` the nominal rate.  ``sensor_height_m`` is
    the sensor's height above the floor when standing (the inverted pendulum's length), None when the
    file does not say.  ``references`` maps a reference system's name (e.g. ``"INDIP"``) to its
    walking bouts.
    """

    time_s: np.ndarray
    acc_mps2: np.ndarray
    gyr_rad_s: np.ndarray
    rate_hz: float | None = None
    source: str = ""
    sensor_height_m: float | None = None
    references: dict[str, list[ImuBout]] = field(default_factory=dict)
    metadata: dict = field(default_factory=dict)

    def __post_init__(self) -> None:
        self.time_s = np.asarray(self.time_s, dtype=float)
        self.acc_mps2 = np.asarray(self.acc_mps2, dtype=float)
        self.gyr_rad_s = np.asarray(self.gyr_rad_s, dtype=float)
        n = self.time_s.shape[0]
        if self.acc_mps2.shape != (n, 3) or self.gyr_rad_s.shape != (n, 3):
            raise InputError(
                f"{self.source or 'IMU recording'}: acc and gyr must be {n} x 3 like the time, got "
                f"{self.acc_mps2.shape} and {self.gyr_rad_s.shape}"
            )

    @property
    def n_samples(self) -> int:
        """Number of samples."""
        return int(self.time_s.shape[0])

    @property
    def duration_s(self) -> float:
        """Last minus first timestamp (0 for fewer than two samples)."""
        return float(self.time_s[-1] - self.time_s[0]) if self.n_samples > 1 else 0.0

    @property
    def synthetic(self) -> bool:
        """True for a recording made by yoyogait.synthetic_imu."""
        return bool(self.metadata.get("synthetic", False))

    def __repr__(self) -> str:
        rate = f"{self.rate_hz:g} Hz" if self.rate_hz else "irregular rate"
        label = "SYNTHETIC " if self.synthetic else ""
        refs = f", references {', '.join(self.references)}" if self.references else ""
        return (
            f"{label}ImuRecording({self.source or 'in memory'}: {self.n_samples} samples at {rate}, "
            f"{self.duration_s:.2f} s{refs})"
        )
