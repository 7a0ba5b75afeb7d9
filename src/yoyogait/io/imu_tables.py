"""IMU tables read by their column names: yoyogait's IMU CSV, mobgap's, a generic one, a microcontroller's
log, a ROS ``sensor_msgs/Imu`` topic written to CSV; and the time columns every table reader knows (docs/imu.md,
section 4; the marker CSV reads its time with :func:`time_in_seconds` too)."""

from __future__ import annotations

import json
import math
import re
from pathlib import Path

import numpy as np

from ..errors import InputError
from .imu_checks import (
    ACC_UNITS,
    GYR_UNITS,
    head_lines,
    median_rate_hz,
    option_flag,
    pick_sensor,
    reading,
    unit_scale,
)
from .imu_recording import GRAVITY_MPS2, ImuRecording

__all__ = ["TIME_COLUMN_NAMES", "first_data_header", "is_imu_header", "read_imu_csv", "time_in_seconds"]

AXES = ("x", "y", "z")
#: Each axis with mobgap's body-frame name for it (``to_body_frame``: x -> is, y -> ml, z -> pa, a renaming).
_AXIS_NAMES = {"x": "(?:x|is)", "y": "(?:y|ml)", "z": "(?:z|pa)"}
_MOBGAP_HEADER = ["samples", "acc_x", "acc_y", "acc_z", "gyr_x", "gyr_y", "gyr_z"]

#: An IMU column (lower case): the sensor's name when the table has one before it (``pelvis_ACCEL_x``,
#: ``LowerBack_Acc_X``), acc/accel or gyr/gyro, the axis, and a unit when given (``acc_x_g``,
#: ``gyr_x[deg/s]``, ``acc_x (m/s^2)``); the short names of microcontroller logs, ``ax``.. ``gz``; or
#: sensor_msgs/Imu's fields as ROS tools write them to CSV (``field.linear_acceleration.x``,
#: ``angular_velocity.z``; PlotJuggler's export ``/imu/data/linear_acceleration/x``, the topic taken
#: as the sensor's name), in REP 145's units unless the column says otherwise.
_IMU_KINDS = {"acc": r"acc(?:el)?|(?P<ros>linear_acceleration)", "gyr": r"gyr(?:o)?|(?P<ros>angular_velocity)"}
_IMU_COLUMN = {
    (kind, a): re.compile(
        rf"^(?:(?:(?P<sensor>.+?)[_ .:/\-])?(?:{_IMU_KINDS[kind]})[_ .:/]?{_AXIS_NAMES[a]}|{kind[0]}{a}(?![a-z0-9]))"
        rf"(?:[_ ]?[\[(]?(?P<unit>[a-z0-9/^_]+?)[\])]?)?$"
    )
    for kind in ("acc", "gyr")
    for a in AXES
}
#: sensor_msgs/Imu's units (REP 145), and the prefix ``rostopic echo -p`` puts before every field.
_ROS_UNITS = {"acc": "m/s^2", "gyr": "rad/s"}
_ROS_PREFIX = "field"
#: Time columns of a generic IMU CSV and their unit in seconds, the first found taken (a ROS message's
#: header stamp before the time it was recorded; PlotJuggler's ``__time``, in seconds); ``timestamp``
#: alone: see _timestamp_unit.
TIME_COLUMNS_S = {
    "time_s": 1.0, "time": 1.0, "t": 1.0, "t_s": 1.0, "timestamp_s": 1.0,
    "field.header.stamp": 1e-9, "%time": 1e-9, "__time": 1.0,
    "time_ms": 1e-3, "timestamp_ms": 1e-3, "t_ms": 1e-3, "millis": 1e-3,
    "time_us": 1e-6, "timestamp_us": 1e-6, "t_us": 1e-6, "micros": 1e-6,
    "time_ns": 1e-9, "timestamp_ns": 1e-9,
}  # fmt: skip
#: A ``timestamp`` column without a unit is in the one of these whose sample rate lies in TIMESTAMP_RATES_HZ
#: (a range under a factor of 1000 wide, so that at most one fits).
TIMESTAMP_UNITS_S = {"s": 1.0, "ms": 1e-3, "us": 1e-6, "ns": 1e-9}
TIMESTAMP_RATES_HZ = (4.0, 4000.0)
#: Every time column a table may have (lower case), in the order they are looked for.
TIME_COLUMN_NAMES = (*TIME_COLUMNS_S, "timestamp")


def time_in_seconds(name: str, values: np.ndarray, where) -> tuple[np.ndarray, str | None]:
    """A time column's values in seconds: by its name (TIME_COLUMNS_S), or a bare ``timestamp`` by its
    intervals (_timestamp_unit); and the unit so inferred, None where the name gave it."""
    scale = TIME_COLUMNS_S.get(name.strip().lower())
    if scale is not None:
        return values * scale, None
    unit = _timestamp_unit(values, where)
    return values * TIMESTAMP_UNITS_S[unit], unit


def _imu_sensors(header: list[str]) -> dict[str, dict[tuple[str, str], tuple[int, str | None]]]:
    """The sensors of a CSV header with an accelerometer and a gyro column for each axis: sensor name
    ('' when the columns carry none) -> (kind, axis) -> (column, unit or None); the first column of each."""
    found: dict[str, dict[tuple[str, str], tuple[int, str | None]]] = {}
    for i, h in enumerate(header):
        name = h.strip().lower()
        for key, pattern in _IMU_COLUMN.items():
            m = pattern.match(name)
            if m:
                unit = m["unit"] or (_ROS_UNITS[key[0]] if m["ros"] else None)
                sensor = "" if m["sensor"] == _ROS_PREFIX else m["sensor"] or ""
                found.setdefault(sensor, {}).setdefault(key, (i, unit))
                break
    return {sensor: cols for sensor, cols in found.items() if len(cols) == len(_IMU_COLUMN)}


def is_imu_header(header: list[str]) -> bool:
    """True for a CSV header with accelerometer and gyro columns (x, y, z each, or mobgap's body-frame
    is, ml, pa; after a sensor's name or not)."""
    return bool(_imu_sensors(header))


def _header_of(path: Path) -> tuple[int, list[str], str | None] | None:
    """(its line's index, its cells, the separator: a tab, a comma, or None for spaces) of a table's header,
    its first line within the first 50 that is neither blank nor a comment (``#``, ``//``); None if there
    is none or the file cannot be read."""
    for i, line in enumerate(head_lines(path)):
        s = line.strip()
        if not s or s.startswith(("#", "//")):
            continue
        sep = "\t" if "\t" in s else ("," if "," in s else None)
        return i, [c.strip() for c in (s.split(sep) if sep else s.split())], sep
    return None


def first_data_header(path: Path) -> list[str] | None:
    """The cells of a table's header (:func:`_header_of`), None without one."""
    found = _header_of(path)
    return None if found is None else found[1]


def read_imu_csv(path, *, acc_unit=None, gyr_unit=None, rate_hz=None, sensor=None) -> ImuRecording:
    """An IMU CSV: the mobgap layout (``samples`` column, g and deg/s at 100 Hz, a
    ``participant_metadata.json`` beside the cohort folders for the sensor height), yoyogait's
    (``time_s``, units in the column names ``acc_x_mps2``/``acc_x_g``, ``gyr_x_rad_s``/``gyr_x_deg_s``)
    or a generic one (``acc_x``.. and ``gyr_x``.. with ``acc_unit``, ``gyr_unit`` and a time column
    or ``rate_hz``). Columns may carry a sensor's name before them (``pelvis_ACCEL_x``): with several
    sensors the lower back's is read (by name: Lumbar, Pelvis, ...) or ``sensor``'s."""
    p = Path(path)
    found = _header_of(p)
    if found is None or not is_imu_header(found[1]):
        raise InputError(f"{p}: no acc_x, acc_y, acc_z and gyr_x, gyr_y, gyr_z columns: not an IMU table")
    first, header, delimiter = found  # a log's tabs or spaces as in its header
    lower = [h.lower() for h in header]
    metadata: dict = {}
    sensor_height = None
    rate: float | None
    tcol: int | None
    if lower[: len(_MOBGAP_HEADER)] == _MOBGAP_HEADER:
        metadata["layout"] = "mobgap"
        acc_scale = unit_scale(acc_unit, ACC_UNITS, "acc_unit", p) or GRAVITY_MPS2
        gyr_scale = unit_scale(gyr_unit, GYR_UNITS, "gyr_unit", p) or np.pi / 180.0
        tcol = 0
        acc_cols = [lower.index(f"acc_{a}") for a in AXES]
        gyr_cols = [lower.index(f"gyr_{a}") for a in AXES]
        sensor_height = _mobgap_sensor_height(p)
    else:
        sensors = _imu_sensors(header)
        chosen = _choose_csv_sensor(sensors, sensor, p)
        if chosen:
            metadata["sensor"] = chosen
        acc_cols, acc_said = _columns(sensors[chosen], "acc", ACC_UNITS, acc_unit, "acc_unit", p)
        gyr_cols, gyr_said = _columns(sensors[chosen], "gyr", GYR_UNITS, gyr_unit, "gyr_unit", p)
        tcol = next((lower.index(n) for n in TIME_COLUMN_NAMES if n in lower), None)
        # What the user must give, all of it in one line (not one option per run).
        missing = [
            f"the {kind} columns carry no unit: pass {option} ({option_flag(option)}) {' or '.join(_plain(units))}"
            for kind, scale, option, units in (
                ("acc", acc_said, "acc_unit", ACC_UNITS),
                ("gyr", gyr_said, "gyr_unit", GYR_UNITS),
            )
            if scale is None
        ]
        if tcol is None and not rate_hz:
            missing.append("no time column (time_s): give the sample rate with rate_hz (--capture-rate-hz)")
        if missing or acc_said is None or gyr_said is None:
            raise InputError(f"{p}: " + "; ".join(missing))
        acc_scale, gyr_scale = acc_said, gyr_said
        metadata["layout"] = "yoyogait" if "time_s" in lower else "generic"
    # Only the columns used are read: a ROS export's frame_id, a log's text columns stay out.
    used = ([] if tcol is None else [tcol]) + acc_cols + gyr_cols

    def load(**converters):
        return np.loadtxt(p, delimiter=delimiter, skiprows=first + 1, ndmin=2, comments="#", usecols=used, **converters)

    try:
        try:
            table = load()
        except ValueError:  # empty cells? (a cell per Python call: only then)
            table = load(converters=_number)
    except ValueError as exc:
        raise InputError(f"{p}: not a numeric table after the header ({exc})") from None
    # An export of several topics at their own rates (PlotJuggler's) leaves this sensor's cells empty on
    # the other topics' rows: those rows are not samples of it.
    complete = ~np.isnan(table).any(axis=1)
    if not complete.all():
        metadata["rows_without_a_sample"] = int((~complete).sum())
        table = table[complete]
    if table.shape[0] < 2:
        raise InputError(f"{p}: fewer than two samples")
    k = 0 if tcol is None else 1
    acc_cols, gyr_cols = list(range(k, k + 3)), list(range(k + 3, k + 6))
    if metadata["layout"] == "mobgap":
        rate = float(rate_hz) if rate_hz else 100.0
        time_s = table[:, 0] / rate
    elif tcol is not None:
        time_s, unit = time_in_seconds(header[tcol], table[:, 0], p)
        if unit is not None:
            metadata["time_unit"] = f"{header[tcol]} in {unit}"
        rate = float(rate_hz) if rate_hz else median_rate_hz(time_s)
    else:
        rate = float(rate_hz)
        time_s = np.arange(table.shape[0]) / rate
    acc, gyr = table[:, acc_cols] * acc_scale, table[:, gyr_cols] * gyr_scale
    return reading(p, time_s, acc, gyr, rate, gyr_scale, metadata, sensor_height_m=sensor_height)


def _number(cell: str) -> float:
    """A table's cell: a number, an empty cell NaN (no sample of this column on that row)."""
    return float(cell) if cell.strip() else math.nan


def _timestamp_unit(values: np.ndarray, p: Path) -> str:
    """The unit of a ``timestamp`` column that names none: the one in which its median interval is a
    sample rate within TIMESTAMP_RATES_HZ (10 per sample: ms at 100 Hz); InputError if none is."""
    dt = np.diff(values)
    dt = dt[np.isfinite(dt) & (dt > 0)]
    if dt.size:
        step = float(np.median(dt))
        lo, hi = TIMESTAMP_RATES_HZ
        for unit, scale in TIMESTAMP_UNITS_S.items():
            if lo <= 1.0 / (step * scale) < hi:
                return unit
    raise InputError(
        f"{p}: the unit of its timestamp column is unclear (a sample every {step if dt.size else float('nan'):g}); "
        "name it time_s, time_ms or time_us, or give the rate with rate_hz (--capture-rate-hz)"
    )


def _choose_csv_sensor(sensors: dict, sensor, p: Path) -> str:
    """The sensor of an IMU CSV's columns (_imu_sensors): ``sensor``'s, the only one, or the lower back's by name."""
    chosen = pick_sensor({n: (n,) if n else () for n in sensors}, sensor)  # no name: only as the only one
    if chosen is not None:
        return chosen
    named = [n for n in sensors if n]
    if sensor is not None:
        have = f"the columns name {', '.join(named)}" if named else "its columns carry no sensor names"
        raise InputError(f"{p}: no sensor {sensor!r} (sensor=, --sensor); {have}")
    raise InputError(
        f"{p}: IMU columns of several sensors ({', '.join(n or '(no name)' for n in sensors)}), none named as the "
        "lower back's (Lumbar, Pelvis, Sacrum, ...): choose one with sensor= (--sensor)"
    )


def _plain(units) -> list[str]:
    """A unit table's names to type on a command line (not the ones with a slash)."""
    return sorted(set(units) - {"m/s^2", "rad/s", "deg/s"})


def _columns(sensor_cols, kind, units, override, option, where) -> tuple[list[int], float | None]:
    """The columns of x, y, z of one kind of a sensor (_imu_sensors) and the scale of their unit
    (None: neither the columns nor ``override`` give one)."""
    flag = option_flag(option)
    cols, scales = [], set()
    for a in AXES:
        i, unit = sensor_cols[(kind, a)]
        cols.append(i)
        if unit:
            if unit not in units:
                raise InputError(f"{where}: unknown unit {unit!r} in the {kind} {a} column; pass {option} ({flag})")
            scales.add(units[unit])
    if override is not None:
        return cols, unit_scale(override, units, option, where)
    if len(scales) == 1:
        return cols, scales.pop()
    if len(scales) > 1:
        raise InputError(f"{where}: the {kind} columns disagree on their unit; pass {option} ({flag})")
    return cols, None


def _mobgap_sensor_height(p: Path) -> float | None:
    # data_csv/<cohort>/<id>/<file>.csv with data_csv/participant_metadata.json
    meta = p.parent.parent.parent / "participant_metadata.json"
    if not meta.is_file():
        return None
    try:
        info = json.loads(meta.read_text())[p.parent.parent.name][p.parent.name]
        return float(info["sensor_height_m"])
    except (KeyError, ValueError, TypeError):
        return None
