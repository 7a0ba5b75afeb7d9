"""Readers of lower-back IMU files into :class:`ImuRecording` (docs/imu.md).

=====================  ==========================================================  ========================
``data.mat``           Mobilise-D MATLAB format (acc in g, gyr in deg/s)            :func:`read_mobilised_mat`
``.csv`` (mobgap)      ``samples,acc_x..acc_z,gyr_x..gyr_z``: g, deg/s, 100 Hz       :func:`read_imu_csv`
``.csv`` (yoyogait)    ``time_s,acc_x_mps2..,gyr_x_rad_s..``: units in the header   :func:`read_imu_csv`
``.csv`` (generic)     ``acc_x..`` (or ``acc_is, acc_ml, acc_pa``), ``gyr_x..`` with   :func:`read_imu_csv`
                       ``acc_unit``/``gyr_unit``; after a sensor's name or not
                       (``pelvis_ACCEL_x``; ``sensor`` chooses)
``.txt`` (Xsens)       MT Manager export: ``PacketCounter Acc_X ... Gyr_Z``         :func:`read_xsens_txt`
``.csv`` (Movella DOT) ``DeviceTag:,..`` lines, ``PacketCounter,SampleTimeFine,..``    :func:`read_dot_csv`
``.h5`` (APDM/Opal)    ``/Sensors/<id>/Accelerometer`` (v5), ``/<case>/Calibrated``   :func:`read_apdm_h5`
=====================  ==========================================================  ========================

Every reader checks the units against physics (:func:`check_imu_plausible`): the accelerometer
must read about 9.81 m/s^2 where the sensor is still, the gyro must not read in deg/s where rad/s
was said; a failure is one line naming the option that fixes it.
"""

from __future__ import annotations

import json
import re
from pathlib import Path

import numpy as np
import scipy.io

from ..errors import InputError
from .imu_recording import GRAVITY_MPS2, ImuBout, ImuRecording
from .motion_bids import channel_types, component_of
from .motion_bids import load as load_motion_bids

__all__ = [
    "ACC_UNITS",
    "GYR_UNITS",
    "check_imu_plausible",
    "clipped_ranges",
    "is_imu_file",
    "is_imu_header",
    "read_imu",
    "read_imu_csv",
    "read_mobilised_mat",
    "read_apdm_h5",
    "read_mobilised_trials",
    "read_xsens_txt",
    "read_dot_csv",
    "LOWER_BACK_LABELS",
]

#: Accelerometer units: name -> m/s^2 per unit.
ACC_UNITS = {"mps2": 1.0, "m/s^2": 1.0, "g": GRAVITY_MPS2}
#: Angular-rate units: name -> rad/s per unit.
GYR_UNITS = {"rad_s": 1.0, "rad/s": 1.0, "deg_s": np.pi / 180.0, "deg/s": np.pi / 180.0}

_AXES = ("x", "y", "z")
#: Each axis with mobgap's body-frame name for it (``to_body_frame``: x -> is, y -> ml, z -> pa, a renaming).
_AXIS_NAMES = {"x": "(?:x|is)", "y": "(?:y|ml)", "z": "(?:z|pa)"}
#: The calibrated channels of Xsens exports (MT Manager and Movella DOT name them alike).
_XSENS_CHANNELS = ("Acc_X", "Acc_Y", "Acc_Z", "Gyr_X", "Gyr_Y", "Gyr_Z")
_MOBGAP_HEADER = ["samples", "acc_x", "acc_y", "acc_z", "gyr_x", "gyr_y", "gyr_z"]


def _unit(value, table: dict, option: str, where) -> float:
    if value is None:
        return 0.0
    key = str(value).strip().lower()
    if key not in table:
        raise InputError(f"{where}: {option} must be one of {', '.join(sorted(table))}, not {value!r}")
    return table[key]


#: An IMU column (lower case): the sensor's name when the table has one before it (``pelvis_ACCEL_x``,
#: ``LowerBack_Acc_X``), acc/accel or gyr/gyro, the axis, and a unit when given (``acc_x_g``,
#: ``gyr_x[deg/s]``, ``acc_x (m/s^2)``); the short names of microcontroller logs, ``ax``.. ``gz``; or
#: sensor_msgs/Imu's fields as ROS tools write them to CSV (``field.linear_acceleration.x``,
#: ``angular_velocity.z``), in REP 145's units unless the column says otherwise.
_IMU_KINDS = {"acc": r"acc(?:el)?|(?P<ros>linear_acceleration)", "gyr": r"gyr(?:o)?|(?P<ros>angular_velocity)"}
_IMU_COLUMN = {
    (kind, a): re.compile(
        rf"^(?:(?:(?P<sensor>.+?)[_ .:\-])?(?:{_IMU_KINDS[kind]})[_ .:]?{_AXIS_NAMES[a]}|{kind[0]}{a}(?![a-z0-9]))"
        rf"(?:[_ ]?[\[(]?(?P<unit>[a-z0-9/^_]+?)[\])]?)?$"
    )
    for kind in ("acc", "gyr")
    for a in _AXES
}
#: sensor_msgs/Imu's units (REP 145), and the prefix ``rostopic echo -p`` puts before every field.
_ROS_UNITS = {"acc": "m/s^2", "gyr": "rad/s"}
_ROS_PREFIX = "field"
#: Time columns of a generic IMU CSV and their unit in seconds, the first found taken (a ROS message's
#: header stamp before the time it was recorded); ``timestamp`` alone: see _timestamp_unit.
TIME_COLUMNS_S = {
    "time_s": 1.0, "time": 1.0, "t": 1.0, "t_s": 1.0, "timestamp_s": 1.0,
    "field.header.stamp": 1e-9, "%time": 1e-9,
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


def _first_data_header(path: Path) -> list[str] | None:
    try:
        with open(path, encoding="utf-8-sig", errors="replace") as f:
            for _ in range(50):
                line = f.readline()
                if not line:
                    return None
                s = line.strip()
                if not s or s.startswith(("#", "//")):
                    continue
                sep = "\t" if "\t" in s else ("," if "," in s else None)
                return [c.strip() for c in (s.split(sep) if sep else s.split())]
    except OSError:
        return None
    return None


def is_imu_file(path) -> bool:
    """True for a file the IMU readers read: a Mobilise-D data.mat, an IMU CSV, an Xsens .txt export,
    an APDM .h5."""
    p = Path(path)
    ext = p.suffix.lower()
    if ext in (".mat", ".h5"):
        return True
    if ext == ".tsv":  # Motion-BIDS with accelerometer and gyro channels (and no positions)
        types = channel_types(p)
        return {"ACCEL", "GYRO"} <= types and "POS" not in types
    if ext in (".csv", ".txt"):
        header = _first_data_header(p)
        return (header is not None and (is_imu_header(header) or "PacketCounter" in header)) or (
            ext == ".csv" and _dot_layout(p) is not None
        )
    return False


def read_imu(
    path, *, acc_unit=None, gyr_unit=None, rate_hz=None, sensor_height_m=None, trial=None, sensor=None
) -> ImuRecording:
    """Read an IMU file (see the module's table); the options override what the file says or lacks
    (``sensor``: the sensor of a multi-sensor APDM file, by label or id)."""
    p = Path(path)
    if not p.is_file():
        raise InputError(f"{p}: no such file")
    ext = p.suffix.lower()
    if ext == ".mat":
        rec = read_mobilised_mat(p, trial=trial)
    elif ext == ".txt" and "PacketCounter" in (_first_data_header(p) or []):
        rec = read_xsens_txt(p, acc_unit=acc_unit, gyr_unit=gyr_unit, rate_hz=rate_hz)
    elif ext == ".txt" and is_imu_header(_first_data_header(p) or []):  # a log of IMU columns, as a CSV
        rec = read_imu_csv(p, acc_unit=acc_unit, gyr_unit=gyr_unit, rate_hz=rate_hz, sensor=sensor)
    elif ext == ".txt":
        rec = read_xsens_txt(p, acc_unit=acc_unit, gyr_unit=gyr_unit, rate_hz=rate_hz)
    elif ext == ".csv" and (layout := _dot_layout(p)) is not None:
        rec = _read_dot(p, layout, acc_unit=acc_unit, gyr_unit=gyr_unit, rate_hz=rate_hz)
    elif ext == ".csv":
        rec = read_imu_csv(p, acc_unit=acc_unit, gyr_unit=gyr_unit, rate_hz=rate_hz, sensor=sensor)
    elif ext == ".h5":
        rec = read_apdm_h5(p, sensor=sensor, acc_unit=acc_unit, gyr_unit=gyr_unit, rate_hz=rate_hz)
    elif ext == ".tsv":
        rec = read_motion_bids_imu(p, sensor=sensor, acc_unit=acc_unit, gyr_unit=gyr_unit, rate_hz=rate_hz)
    else:
        raise InputError(f"{p}: not an IMU file yoyogait reads (.mat, .csv, .txt, .h5, a Motion-BIDS .tsv)")
    if sensor is not None and not (ext in (".h5", ".tsv") or rec.metadata.get("layout") in ("yoyogait", "generic")):
        raise InputError(
            f"{p}: sensor= (--sensor) chooses among the sensors of an APDM .h5, a Motion-BIDS .tsv or an IMU CSV "
            "whose columns carry sensor names only"
        )
    if sensor_height_m is not None:
        if not (np.isfinite(sensor_height_m) and 0.1 < sensor_height_m <= 3.0):
            raise InputError(f"sensor_height_m must be in (0.1, 3] m, not {sensor_height_m!r}")
        rec.sensor_height_m = float(sensor_height_m)
    check_imu_plausible(rec)
    clipped = clipped_ranges(rec)
    if clipped:
        rec.metadata["clipped"] = clipped
    return rec


# ----------------------------------------------------------------------------------------- CSV


def read_imu_csv(path, *, acc_unit=None, gyr_unit=None, rate_hz=None, sensor=None) -> ImuRecording:
    """An IMU CSV: the mobgap layout (``samples`` column, g and deg/s at 100 Hz, a
    ``participant_metadata.json`` beside the cohort folders for the sensor height), yoyogait's
    (``time_s``, units in the column names ``acc_x_mps2``/``acc_x_g``, ``gyr_x_rad_s``/``gyr_x_deg_s``)
    or a generic one (``acc_x``.. and ``gyr_x``.. with ``acc_unit``, ``gyr_unit`` and a time column
    or ``rate_hz``). Columns may carry a sensor's name before them (``pelvis_ACCEL_x``): with several
    sensors the lower back's is read (by name: Lumbar, Pelvis, ...) or ``sensor``'s."""
    p = Path(path)
    header = _first_data_header(p)
    if header is None or not is_imu_header(header):
        raise InputError(f"{p}: no acc_x, acc_y, acc_z and gyr_x, gyr_y, gyr_z columns: not an IMU table")
    lower = [h.lower() for h in header]
    metadata: dict = {}
    sensor_height = None
    rate: float | None
    tcol: int | None
    if lower[: len(_MOBGAP_HEADER)] == _MOBGAP_HEADER:
        metadata["layout"] = "mobgap"
        acc_scale = _unit(acc_unit, ACC_UNITS, "acc_unit", p) or GRAVITY_MPS2
        gyr_scale = _unit(gyr_unit, GYR_UNITS, "gyr_unit", p) or np.pi / 180.0
        tcol = 0
        acc_cols = [lower.index(f"acc_{a}") for a in _AXES]
        gyr_cols = [lower.index(f"gyr_{a}") for a in _AXES]
        sensor_height = _mobgap_sensor_height(p)
    else:
        sensors = _imu_sensors(header)
        chosen = _choose_csv_sensor(sensors, sensor, p)
        if chosen:
            metadata["sensor"] = chosen
        acc_cols, acc_scale = _columns(sensors[chosen], "acc", ACC_UNITS, acc_unit, "acc_unit", p)
        gyr_cols, gyr_scale = _columns(sensors[chosen], "gyr", GYR_UNITS, gyr_unit, "gyr_unit", p)
        tcol = next((lower.index(n) for n in TIME_COLUMN_NAMES if n in lower), None)
        if tcol is None and not rate_hz:
            raise InputError(f"{p}: no time column (time_s); give the sample rate with rate_hz (--capture-rate-hz)")
        metadata["layout"] = "yoyogait" if "time_s" in lower else "generic"
    # Only the columns used are read: a ROS export's frame_id, a log's text columns stay out.
    used = ([] if tcol is None else [tcol]) + acc_cols + gyr_cols
    first = _header_line(p)
    with open(p, encoding="utf-8-sig", errors="replace") as f:
        line = next((text for i, text in enumerate(f) if i == first), "")
    delimiter = "\t" if "\t" in line else "," if "," in line else None  # a log's tabs or spaces as in its header
    try:
        table = np.loadtxt(p, delimiter=delimiter, skiprows=first + 1, ndmin=2, comments="#", usecols=used)
    except ValueError as exc:
        raise InputError(f"{p}: not a numeric table after the header ({exc})") from None
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
        rate = float(rate_hz) if rate_hz else _median_rate_hz(time_s)
    else:
        rate = float(rate_hz)
        time_s = np.arange(table.shape[0]) / rate
    rec = ImuRecording(
        time_s=time_s,
        acc_mps2=table[:, acc_cols] * acc_scale,
        gyr_rad_s=table[:, gyr_cols] * gyr_scale,
        rate_hz=rate,
        source=str(p),
        sensor_height_m=sensor_height,
        metadata=metadata,
    )
    _finish(rec, gyr_scale)
    return rec


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


def _header_line(p: Path) -> int:
    with open(p, encoding="utf-8-sig", errors="replace") as f:
        for i, line in enumerate(f):
            s = line.strip()
            if s and not s.startswith(("#", "//")):
                return i
    return 0


def _choose_csv_sensor(sensors: dict, sensor, p: Path) -> str:
    """The sensor of an IMU CSV's columns (_imu_sensors): ``sensor``'s, the only one, or the lower back's by name."""
    chosen = _pick_sensor({n: (n,) if n else () for n in sensors}, sensor)  # no name: only as the only one
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


def _columns(sensor_cols, kind, units, override, option, where) -> tuple[list[int], float]:
    """The columns of x, y, z of one kind of a sensor (_imu_sensors) and the scale of their unit."""
    flag = "--" + option.replace("_", "-")
    cols, scales = [], set()
    for a in _AXES:
        i, unit = sensor_cols[(kind, a)]
        cols.append(i)
        if unit:
            if unit not in units:
                raise InputError(f"{where}: unknown unit {unit!r} in the {kind} {a} column; pass {option} ({flag})")
            scales.add(units[unit])
    if override is not None:
        return cols, _unit(override, units, option, where)
    if len(scales) == 1:
        return cols, scales.pop()
    if len(scales) > 1:
        raise InputError(f"{where}: the {kind} columns disagree on their unit; pass {option} ({flag})")
    raise InputError(
        f"{where}: the {kind} columns carry no unit; pass {option} ({flag}) "
        f"{' or '.join(sorted(set(units) - {'m/s^2', 'rad/s', 'deg/s'}))}"
    )


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


# ------------------------------------------------------------------------------------- Mobilise-D


def read_mobilised_trials(path) -> list[ImuRecording]:
    """Every trial of a Mobilise-D ``data.mat`` (lower-back sensor ``SU.LowerBack``), with the
    reference systems' walking bouts (``Standards.<system>.MicroWB``) and the sensor height of the
    ``infoForAlgo.mat`` beside it."""
    p = Path(path)
    try:
        data = scipy.io.loadmat(p, simplify_cells=True)["data"]
    except Exception as exc:  # noqa: BLE001 (scipy's parser raises many kinds on a damaged file: TypeError, zlib.error, ...)
        raise InputError(f"{p}: not a Mobilise-D data.mat ({exc})") from None
    height = _mobilised_height(p.parent / "infoForAlgo.mat")
    out = []
    for tm, tests in data.items():
        if not isinstance(tests, dict):
            continue
        for test, trials in tests.items():
            if not isinstance(trials, dict):
                continue
            for trial, content in trials.items():
                try:
                    lb = content["SU"]["LowerBack"]
                except (KeyError, TypeError):
                    continue
                try:
                    rate, acc, gyr, refs = _mobilised_trial(lb, content)
                except (KeyError, TypeError, ValueError, IndexError, AttributeError) as exc:
                    where = f"{p}: trial {tm}/{test}/{trial}"
                    raise InputError(f"{where}: its lower-back data cannot be read ({exc})") from None
                rec = ImuRecording(
                    time_s=np.arange(acc.shape[0]) / rate,
                    acc_mps2=acc,
                    gyr_rad_s=gyr,
                    rate_hz=rate,
                    source=f"{p}:{tm}/{test}/{trial}",
                    sensor_height_m=height,
                    references=refs,
                    metadata={"layout": "mobilised", "test": test, "trial": trial, "participant": p.parent.name},
                )
                _finish(rec, np.pi / 180.0)
                check_imu_plausible(rec)
                out.append(rec)
    if not out:
        raise InputError(f"{p}: no lower-back sensor (SU.LowerBack) in any trial")
    return out


def _mobilised_trial(lb, content) -> tuple[float, np.ndarray, np.ndarray, dict[str, list[ImuBout]]]:
    """(rate, acc in m/s^2, gyr in rad/s, the reference systems' bouts) of one trial's ``SU.LowerBack``."""
    rate = float(lb["Fs"]["Acc"]) if isinstance(lb.get("Fs"), dict) else float(lb.get("Fs", 100.0))
    # The format stores the accelerometer in g (mobgap's loader scales it by 9.81 too).
    acc = np.asarray(lb["Acc"], dtype=float) * GRAVITY_MPS2
    gyr = np.asarray(lb["Gyr"], dtype=float) * np.pi / 180.0
    refs = {}
    for system, std in (content.get("Standards") or {}).items():
        bouts = _bouts(std.get("MicroWB"), std.get("Fs"))
        if bouts:
            refs[system] = bouts
    return rate, acc, gyr, refs


def read_mobilised_mat(path, *, trial=None) -> ImuRecording:
    """One trial of a Mobilise-D ``data.mat``: ``trial`` as ``Test5/Trial1`` (default: the first)."""
    trials = read_mobilised_trials(path)
    if trial is None:
        return trials[0]
    names = [f"{r.metadata['test']}/{r.metadata['trial']}" for r in trials]
    if trial not in names:
        raise InputError(f"{path}: no trial {trial!r}; the file has {', '.join(names)} (trial=, --trial)")
    return trials[names.index(trial)]


def _mobilised_height(info: Path) -> float | None:
    if not info.is_file():
        return None
    try:
        tm = scipy.io.loadmat(info, simplify_cells=True)["infoForAlgo"]
        value = float(next(iter(tm.values()))["SensorHeight"])
    except (KeyError, ValueError, TypeError, StopIteration, OSError):
        return None
    return value / 100.0 if value > 3.0 else value  # the format gives centimetres


def _bouts(micro, rate_hz=None) -> list[ImuBout]:
    if micro is None:
        return []
    items = [micro] if isinstance(micro, dict) else list(micro)
    out = []
    for b in items:
        try:
            stride = np.asarray(b.get("Stride_Duration", []), dtype=float).reshape(-1)
            ic = np.asarray(b.get("InitialContact_Event", []), dtype=float).reshape(-1)
            out.append(
                ImuBout(
                    start_s=float(b["Start"]),
                    end_s=float(b["End"]),
                    cadence_spm=float(b["Cadence"]),
                    speed_mps=float(b["WalkingSpeed"]),
                    stride_time_s=float(np.nanmean(stride)) if stride.size else float("nan"),
                    contact_times_s=ic,
                    strides_s=_measured_strides(b.get("Stride_InitialContacts"), stride, rate_hz),
                )
            )
        except (KeyError, TypeError, ValueError):
            continue
    return out


def _measured_strides(contacts, duration_s: np.ndarray, rate_hz) -> np.ndarray:
    """The strides a Mobilise-D standard measured: its ``Stride_InitialContacts`` (N x 2) where its
    ``Stride_Duration`` is known (NaN marks a stride over a missed or doubled contact, left out of
    its ``Cadence``), in seconds. The standards store them in seconds or in samples at their ``Fs``;
    the scale is the one whose strides last their ``Stride_Duration``. Empty when neither does."""
    none = np.zeros((0, 2))
    try:
        c = np.asarray(contacts, dtype=float)
    except (TypeError, ValueError):  # absent or not numbers: the strides from the contacts instead
        return none
    if c.size % 2 or c.size // 2 != duration_s.size:
        return none
    c = c.reshape(-1, 2)
    known = np.isfinite(duration_s) & np.all(np.isfinite(c), axis=1)
    if not known.any():
        return none
    scales = [1.0] + ([1.0 / float(rate_hz)] if rate_hz and float(rate_hz) > 0 else [])
    for scale in scales:
        if np.max(np.abs((c[known, 1] - c[known, 0]) * scale - duration_s[known])) < 1e-3:
            return c[known] * scale
    return none


# ------------------------------------------------------------------------------------------ Xsens


def read_xsens_txt(path, *, acc_unit=None, gyr_unit=None, rate_hz=None) -> ImuRecording:
    """An Xsens MT Manager / Awinda text export: ``//`` comment lines (``// Update Rate: 100.0Hz``),
    a tab-separated header with ``PacketCounter``, ``Acc_X``..``Acc_Z``, ``Gyr_X``..``Gyr_Z``
    (MT Manager's units: m/s^2 and rad/s unless ``acc_unit``/``gyr_unit`` say otherwise)."""
    p = Path(path)
    rate = float(rate_hz) if rate_hz else None
    header, rows = None, []
    with open(p, encoding="utf-8-sig", errors="replace") as f:
        for line in f:
            s = line.strip()
            if not s:
                continue
            if s.startswith("//"):
                m = re.search(r"Update Rate:\s*([0-9.]+)\s*Hz", s)
                if m and rate is None:
                    rate = float(m.group(1))
                continue
            parts = s.split("\t") if "\t" in s else s.split()
            if header is None:
                header = [h.strip() for h in parts]
                continue
            rows.append(parts)
    if header is None or "PacketCounter" not in header:
        raise InputError(f"{p}: no PacketCounter header line: not an Xsens MT Manager export")
    need = list(_XSENS_CHANNELS)
    missing = [n for n in need if n not in header]
    if missing:
        raise InputError(f"{p}: the export lacks {', '.join(missing)} (export calibrated data)")
    if rate is None:
        raise InputError(f"{p}: no '// Update Rate' line; give the sample rate with rate_hz (--capture-rate-hz)")
    cols = [header.index(n) for n in ["PacketCounter", *need]]
    try:
        table = np.array([[float(r[c]) if c < len(r) and r[c] != "" else np.nan for c in cols] for r in rows])
    except ValueError as exc:
        raise InputError(f"{p}: a value is not a number ({exc})") from None
    if table.shape[0] < 2:
        raise InputError(f"{p}: fewer than two samples")
    counter = np.unwrap(table[:, 0], period=65536.0)
    acc_scale = _unit(acc_unit, ACC_UNITS, "acc_unit", p) or 1.0
    gyr_scale = _unit(gyr_unit, GYR_UNITS, "gyr_unit", p) or 1.0
    rec = ImuRecording(
        time_s=(counter - counter[0]) / rate,
        acc_mps2=table[:, 1:4] * acc_scale,
        gyr_rad_s=table[:, 4:7] * gyr_scale,
        rate_hz=rate,
        source=str(p),
        metadata={"layout": "xsens"},
    )
    _finish(rec, gyr_scale)
    return rec


# ------------------------------------------------------------------------------------ Movella DOT

#: SampleTimeFine of a Movella DOT export: microseconds in an unsigned 32-bit counter.
_DOT_TICK_S = 1e-6
_DOT_WRAP = 2.0**32


def _dot_layout(p: Path) -> tuple[int, list[str], dict[str, str]] | None:
    """(line index of the column header, its names, the ``Key:,value`` lines before it) of a Movella
    (Xsens) DOT CSV export, whose column header holds PacketCounter and SampleTimeFine; else None."""
    meta: dict[str, str] = {}
    try:
        with open(p, encoding="utf-8-sig", errors="replace") as f:
            for i, line in enumerate(f):
                if i >= 60:
                    return None
                cells = [c.strip() for c in line.strip().split(",")]
                if "PacketCounter" in cells and "SampleTimeFine" in cells:
                    return i, cells, meta
                if cells and cells[0].endswith(":"):
                    meta[cells[0][:-1].strip()] = cells[1] if len(cells) > 1 else ""
    except OSError:
        return None
    return None


def read_dot_csv(path, *, acc_unit=None, gyr_unit=None, rate_hz=None) -> ImuRecording:
    """A Movella (Xsens) DOT CSV export: ``sep=,`` and ``Key:,value`` lines (``OutputRate:,60Hz``),
    then ``PacketCounter,SampleTimeFine,...`` with ``Acc_X``..``Acc_Z`` and ``Gyr_X``..``Gyr_Z``
    (the DOT's units: m/s^2 and deg/s unless ``acc_unit``/``gyr_unit`` say otherwise). The time is
    SampleTimeFine (microseconds, unwrapped at 2^32). An export of orientation and free acceleration
    only (no angular rate) is refused in one line."""
    p = Path(path)
    layout = _dot_layout(p)
    if layout is None:
        raise InputError(f"{p}: no PacketCounter,SampleTimeFine header line: not a Movella DOT export")
    return _read_dot(p, layout, acc_unit=acc_unit, gyr_unit=gyr_unit, rate_hz=rate_hz)


def _read_dot(p: Path, layout, *, acc_unit=None, gyr_unit=None, rate_hz=None) -> ImuRecording:
    """read_dot_csv over the layout :func:`_dot_layout` found (its header scanned once)."""
    line, header, meta = layout
    need = list(_XSENS_CHANNELS)
    missing = [n for n in need if n not in header]
    if missing:
        has = ", ".join(h for h in header if h not in ("PacketCounter", "SampleTimeFine", "Status") and h) or "nothing"
        raise InputError(
            f"{p}: a Movella DOT export of {has}: it lacks {', '.join(missing)}; export a measurement mode "
            "with the calibrated acceleration and angular rate (orientation and free acceleration alone are "
            "not read)"
        )
    cols = [header.index(n) for n in ["SampleTimeFine", *need]]
    rows = []
    with open(p, encoding="utf-8-sig", errors="replace") as f:
        for i, text in enumerate(f):
            if i <= line or not text.strip():
                continue
            cells = text.strip().split(",")
            try:
                rows.append([float(cells[c]) if c < len(cells) and cells[c].strip() else np.nan for c in cols])
            except ValueError as exc:
                raise InputError(f"{p}: line {i + 1}: a value is not a number ({exc})") from None
    table = np.array(rows, dtype=float).reshape(-1, len(cols))
    if table.shape[0] < 2:
        raise InputError(f"{p}: fewer than two samples")
    missing_tick = np.flatnonzero(~np.isfinite(table[:, 0]))
    if missing_tick.size:
        raise InputError(
            f"{p}: sample {missing_tick[0]} (after the header) has no SampleTimeFine, and {missing_tick.size - 1} more"
        )
    ticks = np.unwrap(table[:, 0], period=_DOT_WRAP)
    time_s = (ticks - ticks[0]) * _DOT_TICK_S
    rate: float | None = float(rate_hz) if rate_hz else None
    m = re.match(r"\s*([0-9.]+)\s*Hz", meta.get("OutputRate", ""), re.IGNORECASE)
    if rate is None and m:
        rate = float(m.group(1))
    if rate is None:  # no OutputRate line (an SDK's own export): the ticks' median interval
        rate = _median_rate_hz(time_s)
    acc_scale = _unit(acc_unit, ACC_UNITS, "acc_unit", p) or 1.0
    gyr_scale = _unit(gyr_unit, GYR_UNITS, "gyr_unit", p) or np.pi / 180.0
    rec = ImuRecording(
        time_s=time_s,
        acc_mps2=table[:, 1:4] * acc_scale,
        gyr_rad_s=table[:, 4:7] * gyr_scale,
        rate_hz=rate,
        source=str(p),
        metadata={"layout": "movella_dot", **({"device_tag": meta["DeviceTag"]} if "DeviceTag" in meta else {})},
    )
    _finish(rec, gyr_scale)
    return rec


# ------------------------------------------------------------------------------------------- APDM

#: Monitor labels of a lower-back sensor (lower case, spaces and underscores removed), tried in order.
LOWER_BACK_LABELS = ("lumbar", "lowerback", "sacrum", "sacral", "pelvis", "l5", "l4l5", "waist", "lowback")

_APDM_ACC_UNITS = {"m/s^2": 1.0, "m/s2": 1.0, "m/s/s": 1.0, "g": GRAVITY_MPS2}
_APDM_GYR_UNITS = {"rad/s": 1.0, "rad/sec": 1.0, "deg/s": np.pi / 180.0, "deg/sec": np.pi / 180.0}


def _text(value) -> str:
    if isinstance(value, bytes):
        value = value.decode("utf-8", errors="replace")
    elif isinstance(value, np.ndarray):
        value = value.reshape(-1)[0] if value.size else ""
        return _text(value)
    return str(value).strip().strip("\x00").strip()


def _label_key(label: str) -> str:
    return re.sub(r"[\s_\-]+", "", label.lower())


def _apdm_sensors(f, p: Path) -> tuple[int, dict[str, dict]]:
    """(format version, {sensor id: {label, acc, gyr, time, rate, acc_unit, gyr_unit}}) of an open APDM file:
    format 5 (``/Sensors/<id>``) or 3/4 (``/<case id>/Calibrated``, the root's ``CaseIdList``, ``MonitorLabelList``)."""
    import h5py  # the apdm extra

    version_attr = f.attrs.get("FileFormatVersion", f.attrs.get("File_Format_Version"))
    try:
        version = int(float(_text(version_attr))) if version_attr is not None else 0
    except ValueError:
        version = 0
    sensors: dict[str, dict] = {}
    if "Sensors" in f and isinstance(f["Sensors"], h5py.Group):
        for sid, g in f["Sensors"].items():
            if not isinstance(g, h5py.Group) or "Accelerometer" not in g:
                continue
            conf = g["Configuration"].attrs if "Configuration" in g else {}
            sensors[str(sid)] = {
                "label": _text(conf.get("Label 0", "")),
                "acc": g["Accelerometer"],
                "gyr": g.get("Gyroscope"),
                "time": g.get("Time"),
                "rate": conf.get("Sample Rate"),
            }
        return version or 5, sensors
    listed = f.attrs.get("CaseIdList", f["CaseIdList"][()] if "CaseIdList" in f else None)
    if listed is not None:
        # Formats 3 and 4 list the cases and their labels as attributes of the root (older writers: datasets).
        ids = [_text(v) for v in np.asarray(listed).reshape(-1)]
        said = f.attrs.get("MonitorLabelList", f["MonitorLabelList"][()] if "MonitorLabelList" in f else [])
        labels = [_text(v) for v in np.asarray(said).reshape(-1)]
        for i, case in enumerate(ids):
            if case not in f or "Calibrated" not in f[case] or "Accelerometers" not in f[case]["Calibrated"]:
                continue
            g, cal = f[case], f[case]["Calibrated"]
            sensors[case] = {
                "label": labels[i] if i < len(labels) else "",
                "acc": cal["Accelerometers"],
                "gyr": cal.get("Gyroscopes"),
                "time": g.get("Time"),
                "rate": g.attrs.get("SampleRate"),
            }
        return version or 4, sensors
    raise InputError(f"{p}: no /Sensors group (APDM format 5) nor /CaseIdList (formats 3, 4): not an APDM .h5 file")


def _choose_sensor(sensors: dict[str, dict], sensor, p: Path) -> str:
    present = ", ".join(f"{s['label'] or '(no label)'} ({sid})" for sid, s in sensors.items())
    if not sensors:
        raise InputError(f"{p}: no sensor with an accelerometer in the file")
    chosen = _pick_sensor({sid: (s["label"], sid) for sid, s in sensors.items()}, sensor)
    if chosen is not None:
        return chosen
    if sensor is not None:
        raise InputError(f"{p}: no sensor {sensor!r} (sensor=, --sensor); the file has {present}")
    raise InputError(
        f"{p}: no lower-back sensor by label (Lumbar, Lower Back, Sacrum, ...); choose one with sensor= (--sensor): "
        f"the file has {present}"
    )


def _pick_sensor(names: dict[str, tuple[str, ...]], sensor) -> str | None:
    """Which sensor of a file to read, the one rule of every reader with several: ``names`` maps each
    sensor's key to the names it answers to, its label first (then its id). ``sensor`` given: the one
    answering to it; else the first labelled as the lower back (:data:`LOWER_BACK_LABELS`, in their
    order), else the only one. None when none is (the caller says why, naming what the file has)."""
    if sensor is not None:
        want = _label_key(str(sensor))
        return next((k for k, ns in names.items() if any(_label_key(n) == want for n in ns)), None)
    for label in LOWER_BACK_LABELS:
        for k, ns in names.items():
            if ns and _label_key(ns[0]) == label:
                return k
    return next(iter(names)) if len(names) == 1 else None


# ------------------------------------------------------------------------------------ Motion-BIDS

_BIDS_ACC_UNITS = {**_APDM_ACC_UNITS, "m s^-2": 1.0, "m*s^-2": 1.0}
_BIDS_GYR_UNITS = {**_APDM_GYR_UNITS, "rad s^-1": 1.0, "deg s^-1": np.pi / 180.0, "°/s": np.pi / 180.0}


def read_motion_bids_imu(path, *, sensor=None, acc_unit=None, gyr_unit=None, rate_hz=None) -> ImuRecording:
    """An IMU of a Motion-BIDS ``*_motion.tsv`` (io/motion_bids.py): the tracked point with ACCEL and GYRO
    channels for x, y and z that is at the lower back by its label (as the APDM reader chooses), or the only
    one, or ``sensor`` (--sensor); units from each channel's ``units`` (m/s^2 or g, rad/s or deg/s) unless
    ``acc_unit`` / ``gyr_unit`` say otherwise."""
    p = Path(path)
    channels, data, rate, channels_path, time_s = load_motion_bids(p, rate_hz)
    found: dict[str, dict] = {}
    for k, ch in enumerate(channels):
        kind, axis = ch.get("type", "").upper(), component_of(ch)
        if kind in ("ACCEL", "GYRO") and axis:
            point = ch.get("tracked_point", "") or "(no tracked point)"
            entry = found.setdefault(point, {"label": point, "ACCEL": {}, "GYRO": {}, "units": {}})
            entry[kind][axis] = k
            entry["units"].setdefault(kind, set()).add(ch.get("units", "").strip().lower())
    sensors = {name: e for name, e in found.items() if len(e["ACCEL"]) == 3 and len(e["GYRO"]) == 3}
    if not sensors:
        raise InputError(f"{p}: no tracked point with ACCEL and GYRO channels for x, y and z ({channels_path.name})")
    chosen = sensors[_choose_sensor(sensors, sensor, p)]
    scales = []
    for kind, table, override, option in (
        ("ACCEL", _BIDS_ACC_UNITS, acc_unit, "acc_unit"),
        ("GYRO", _BIDS_GYR_UNITS, gyr_unit, "gyr_unit"),
    ):
        if override is not None:
            scales.append(_unit(override, ACC_UNITS if kind == "ACCEL" else GYR_UNITS, option, p))
            continue
        units = chosen["units"][kind]
        if len(units) != 1 or next(iter(units)) not in table:
            flag = "--" + option.replace("_", "-")
            said = ", ".join(sorted(units))
            raise InputError(f"{channels_path}: {kind} channels in {said!r}; pass {option} ({flag})")
        scales.append(table[next(iter(units))])
    acc = data[:, [chosen["ACCEL"][a] for a in "xyz"]] * scales[0]
    gyr = data[:, [chosen["GYRO"][a] for a in "xyz"]] * scales[1]
    rec = ImuRecording(
        time_s=time_s,
        acc_mps2=acc,
        gyr_rad_s=gyr,
        rate_hz=rate,
        source=str(p),
        metadata={"layout": "motion_bids", "sensor": chosen["label"], "sensor_id": chosen["label"]},
    )
    _finish(rec, scales[1])
    return rec


def _vectors(ds, what: str, n: int | None, p: Path) -> np.ndarray:
    a = np.asarray(ds[()], dtype=float)
    if a.ndim == 2 and a.shape[1] != 3 and a.shape[0] == 3:
        a = a.T  # stored 3 x N
    if a.ndim != 2 or a.shape[1] != 3 or (n is not None and a.shape[0] != n):
        raise InputError(f"{p}: {what} is {'x'.join(map(str, a.shape))}, expected N x 3 (N samples, x y z)")
    return a


def _apdm_unit(ds, table: dict, override, option: str, default: float, p: Path) -> float:
    if override is not None:
        units = ACC_UNITS if option == "acc_unit" else GYR_UNITS
        return _unit(override, units, option, p)
    said = _text(ds.attrs.get("Units", ds.attrs.get("Unit", ""))) if ds is not None else ""
    if not said:
        return default
    key = said.lower().replace(" ", "").replace("\u00b2", "^2")
    if key not in table:
        flag = "--" + option.replace("_", "-")
        raise InputError(f"{p}: unit {said!r} of {ds.name} not understood; pass {option} ({flag})")
    return table[key]


def read_apdm_h5(path, *, sensor=None, acc_unit=None, gyr_unit=None, rate_hz=None) -> ImuRecording:
    """An APDM (Opal, Mobility Lab, Motion Studio) HDF5 file: format 5 (``/Sensors/<id>/Accelerometer``,
    ``Gyroscope``, ``Time`` in microseconds, ``/Sensors/<id>/Configuration`` attributes ``Label 0`` and
    ``Sample Rate``) or formats 3 and 4 (``/<case id>/Calibrated/Accelerometers``, ``Gyroscopes``,
    ``/<case id>/Time``, the root's attributes ``CaseIdList`` and ``MonitorLabelList``, the case's
    ``SampleRate``). The sensor: the
    one labelled as the lower back (:data:`LOWER_BACK_LABELS`), the only one, or ``sensor`` (label or id).
    Units: the datasets' ``Units`` attribute, else APDM's m/s^2 and rad/s."""
    try:
        import h5py  # the apdm extra
    except ImportError:
        raise InputError(f"{path}: reading APDM .h5 files needs h5py: pip install 'yoyogait[apdm]'") from None
    p = Path(path)
    try:
        f = h5py.File(p, "r")
    except OSError as exc:
        raise InputError(f"{p}: not an HDF5 file ({str(exc).splitlines()[0]})") from None
    with f:
        version, sensors = _apdm_sensors(f, p)
        sid = _choose_sensor(sensors, sensor, p)
        s = sensors[sid]
        name = s["label"] or sid
        if s["gyr"] is None:
            raise InputError(f"{p}: sensor {name!r} has no gyroscope data (Gyroscope / Calibrated/Gyroscopes)")
        acc = _vectors(s["acc"], f"sensor {name!r}: its accelerometer", None, p)
        gyr = _vectors(s["gyr"], f"sensor {name!r}: its gyroscope", acc.shape[0], p)
        acc = acc * _apdm_unit(s["acc"], _APDM_ACC_UNITS, acc_unit, "acc_unit", 1.0, p)
        gyr_scale = _apdm_unit(s["gyr"], _APDM_GYR_UNITS, gyr_unit, "gyr_unit", 1.0, p)
        gyr = gyr * gyr_scale
        try:
            rate = float(rate_hz) if rate_hz else (float(_text(s["rate"])) if s["rate"] is not None else None)
        except ValueError:
            rate = None
        if s["time"] is not None:
            stamps = np.asarray(s["time"][()], dtype=np.float64).reshape(-1)
            if stamps.shape[0] != acc.shape[0]:
                raise InputError(f"{p}: sensor {name!r}: {stamps.shape[0]} times for {acc.shape[0]} samples")
            time_s = (stamps - stamps[0]) * 1e-6  # microseconds since 1970
        elif rate:
            time_s = np.arange(acc.shape[0]) / rate
        else:
            raise InputError(
                f"{p}: sensor {name!r} has neither Time nor a sample rate; pass rate_hz (--capture-rate-hz)"
            )
    rec = ImuRecording(
        time_s=time_s,
        acc_mps2=acc,
        gyr_rad_s=gyr,
        rate_hz=rate,
        source=str(p),
        metadata={"layout": f"apdm v{version}", "sensor": name, "sensor_id": sid},
    )
    _finish(rec, gyr_scale)
    return rec


# ------------------------------------------------------------------------------------ plausibility


def _finish(rec: ImuRecording, gyr_scale: float) -> None:
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


def _median_rate_hz(time_s) -> float | None:
    """The nominal rate of timestamps without a stated one: 1 / their median interval (None if not positive)."""
    dt = np.diff(np.asarray(time_s, dtype=float))
    return float(1.0 / np.median(dt)) if dt.size and np.median(dt) > 0 else None


def _check_samples(rec: ImuRecording) -> None:
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
