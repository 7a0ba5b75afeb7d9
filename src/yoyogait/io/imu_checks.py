"""What every IMU reader ends with: the units it may be told, the sensor it picks among several, the
samples and units checked against physics, the sensor ranges the file shows clipped (docs/imu.md, section 4)."""

from __future__ import annotations

import re

import numpy as np

from ..errors import InputError
from .imu_recording import GRAVITY_MPS2, ImuRecording

__all__ = [
    "ACC_UNITS",
    "GYR_UNITS",
    "LOWER_BACK_LABELS",
    "check_imu_plausible",
    "clipped_ranges",
    "finish_reading",
    "head_lines",
    "label_key",
    "median_rate_hz",
    "pick_sensor",
    "reading",
    "unit_scale",
]

#: Accelerometer units: name -> m/s^2 per unit.
ACC_UNITS = {"mps2": 1.0, "m/s^2": 1.0, "g": GRAVITY_MPS2}
#: Angular-rate units: name -> rad/s per unit.
GYR_UNITS = {"rad_s": 1.0, "rad/s": 1.0, "deg_s": np.pi / 180.0, "deg/s": np.pi / 180.0}


#: Monitor labels of a lower-back sensor (lower case, spaces and underscores removed), tried in order.
LOWER_BACK_LABELS = ("lumbar", "lowerback", "sacrum", "sacral", "pelvis", "l5", "l4l5", "waist", "lowback")


def option_flag(option: str) -> str:
    """The command line's flag of a reader option: ``acc_unit`` -> ``--acc-unit``."""
    return "--" + option.replace("_", "-")


def head_lines(path, n: int = 50) -> list[str]:
    """The first ``n`` lines of a text file, where a reader looks for its header (fewer at the file's
    end; none when it cannot be read)."""
    try:
        with open(path, encoding="utf-8-sig", errors="replace") as f:
            return [line for _, line in zip(range(n), f)]
    except OSError:
        return []


def unit_scale(value, table: dict, option: str, where) -> float:
    """The scale of a unit the user gave (``value``, a key of ``table``) to the SI unit; 0.0 when none was
    given (the caller's default then); InputError naming ``option`` and the units it takes."""
    if value is None:
        return 0.0
    key = str(value).strip().lower()
    if key not in table:
        raise InputError(f"{where}: {option} must be one of {', '.join(sorted(table))}, not {value!r}")
    return table[key]


def label_key(label: str) -> str:
    """A sensor label as it is compared: lower case, without spaces, underscores or hyphens."""
    return re.sub(r"[\s_\-]+", "", label.lower())


def pick_sensor(names: dict[str, tuple[str, ...]], sensor) -> str | None:
    """Which sensor of a file to read, the one rule of every reader with several: ``names`` maps each
    sensor's key to the names it answers to, its label first (then its id). ``sensor`` given: the one
    answering to it; else the first labelled as the lower back (:data:`LOWER_BACK_LABELS`, in their
    order), else the only one. None when none is (the caller says why, naming what the file has)."""
    if sensor is not None:
        want = label_key(str(sensor))
        return next((k for k, ns in names.items() if any(label_key(n) == want for n in ns)), None)
    for label in LOWER_BACK_LABELS:
        for k, ns in names.items():
            if ns and label_key(ns[0]) == label:
                return k
    return next(iter(names)) if len(names) == 1 else None


def finish_reading(rec: ImuRecording, gyr_scale: float) -> None:
    """Every reader's last step: the unit the angular rate was read in (``gyr_scale``: to rad/s) kept
    for the plausibility check's message; a sample whose six channels read exactly 0 is no
    measurement (a sensor always feels gravity; a DOT export's first packet is such a row): missing
    (NaN), which the estimator ignores. Then the timestamps and the rate are checked."""
    rec.metadata["gyr_unit_read"] = "deg/s" if abs(gyr_scale - np.pi / 180.0) < 1e-12 else "rad/s"
    zero = np.all(rec.acc_mps2 == 0.0, axis=1) & np.all(rec.gyr_rad_s == 0.0, axis=1)
    if zero.any():
        rec.acc_mps2[zero] = np.nan
        rec.gyr_rad_s[zero] = np.nan
        rec.metadata["zero_rows"] = int(zero.sum())
    _check_samples(rec)


def reading(source, time_s, acc_mps2, gyr_rad_s, rate_hz, gyr_scale: float, metadata: dict, **more) -> ImuRecording:
    """A reader's record, finished (:func:`finish_reading`): the samples in SI units (``gyr_scale``: the unit
    the angular rate was read in, to rad/s), ``more`` the other fields of :class:`ImuRecording`."""
    rec = ImuRecording(time_s=time_s, acc_mps2=acc_mps2, gyr_rad_s=gyr_rad_s, rate_hz=rate_hz, source=str(source),
                       metadata=metadata, **more)  # fmt: skip
    finish_reading(rec, gyr_scale)
    return rec


def median_rate_hz(time_s) -> float | None:
    """The nominal rate of timestamps without a stated one: 1 / their median interval (None if not positive)."""
    dt = np.diff(np.asarray(time_s, dtype=float))
    return float(1.0 / np.median(dt)) if dt.size and np.median(dt) > 0 else None


def _check_samples(rec: ImuRecording) -> None:
    # Timestamps finite and increasing, the rate plausible: one line naming the sample otherwise.
    where = rec.source
    t = rec.time_s
    bad = np.flatnonzero(~np.isfinite(t))
    if bad.size:
        raise InputError(f"{where}: timestamps are not finite (sample {bad[0]} of {t.size}, and {bad.size - 1} more)")
    back = np.flatnonzero(np.diff(t) <= 0)
    if back.size:
        i = int(back[0]) + 1
        raise InputError(
            f"{where}: timestamps do not increase (sample {i} of {t.size}: {t[i]:.6g} s after {t[i - 1]:.6g} s; "
            f"{back.size} such samples)"
        )
    if rec.rate_hz is not None and not (np.isfinite(rec.rate_hz) and 1.0 <= rec.rate_hz <= 10000.0):
        raise InputError(f"{where}: sample rate {rec.rate_hz!r} Hz is not plausible; pass rate_hz")


#: A plateau at an axis's extreme: at least this share of the samples (and CLIP_MIN_SAMPLES) sit exactly at it,
#: some of them CLIP_MIN_RUN in a row: the peaks of a smooth signal are single samples (an exactly periodic
#: synthetic signal reaches its maximum once per period, two equal samples where its peak falls between them).
CLIP_SHARE = 0.005
CLIP_MIN_SAMPLES = 5
CLIP_MIN_RUN = 3
#: ... and the extreme is beyond what a sensor at rest reads (a coarse quantisation repeats values there).
CLIP_MIN_ACC_MPS2 = 1.05 * GRAVITY_MPS2
CLIP_MIN_GYR_RAD_S = 2.0


def clipped_ranges(rec: ImuRecording) -> dict[str, tuple[float, int]]:
    """Where a sensor's range clipped the signal: {"acc" or "gyr": (the range, in m/s^2 or rad/s; the samples at
    it)} for the sensors one of whose axes has a plateau at its extreme |value|."""
    out: dict[str, tuple[float, int]] = {}
    for kind, values, floor in (("acc", rec.acc_mps2, CLIP_MIN_ACC_MPS2), ("gyr", rec.gyr_rad_s, CLIP_MIN_GYR_RAD_S)):
        magnitude = np.abs(values)
        for axis in range(3):
            column = magnitude[:, axis][np.isfinite(magnitude[:, axis])]
            if column.size == 0:
                continue
            top = float(column.max())
            held = column >= top
            at = int(np.count_nonzero(held))
            if (
                top >= floor
                and at >= max(CLIP_MIN_SAMPLES, CLIP_SHARE * column.size)
                and _longest_run(held) >= CLIP_MIN_RUN
            ):
                level, count = out.get(kind, (np.inf, 0))
                out[kind] = (min(level, top), count + at)
    return out


def _longest_run(flags: np.ndarray) -> int:
    """The longest run of True in a boolean array."""
    edges = np.flatnonzero(np.diff(np.concatenate(([0], flags.astype(np.int8), [0]))))
    return int(np.max(edges[1::2] - edges[::2])) if edges.size else 0


def check_imu_plausible(rec: ImuRecording) -> None:
    """Units against physics: where the sensor is still (the angular rate small, the acceleration
    steady) its specific force is gravity, 9.81 m/s^2; the rate gyro of a walking person stays
    below 10 rad/s. InputError naming the option that fixes a wrong unit."""
    where = rec.source
    acc, gyr = rec.acc_mps2, rec.gyr_rad_s
    ok = np.all(np.isfinite(acc), axis=1) & np.all(np.isfinite(gyr), axis=1)
    if ok.sum() < 2:
        raise InputError(f"{where}: no finite accelerometer and gyro sample")
    norm = np.linalg.norm(acc[ok], axis=1)
    g = float(np.median(norm))
    if 0.5 < g < 2.0:
        raise InputError(
            f"{where}: the acceleration's median norm is {g:.2f}, not 9.81 m/s^2: in g? pass acc_unit g (--acc-unit g)"
        )
    if not (0.6 * GRAVITY_MPS2 < g < 1.4 * GRAVITY_MPS2):
        raise InputError(
            f"{where}: the acceleration's median norm is {g:.3g} m/s^2, not about 9.81: pass acc_unit (mps2 or g)"
        )
    w = float(np.percentile(np.abs(gyr[ok]), 99))
    if w > 15.0 and rec.metadata.get("gyr_unit_read") == "deg/s":
        # Read as deg/s already: the rate is the sensor's own, not a unit's mistake.
        raise InputError(
            f"{where}: the angular rate reaches {w:.0f} rad/s ({np.degrees(w):.0f} deg/s), beyond a lower back's in "
            "any walk (a few rad/s): a sensor on a foot or a leg? yoyogait estimates from one at the lower back"
        )
    if w > 15.0:
        raise InputError(
            f"{where}: the angular rate reaches {w:.0f} rad/s, beyond any walk: in deg/s? "
            "pass gyr_unit deg_s (--gyr-unit deg_s)"
        )
