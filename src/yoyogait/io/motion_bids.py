"""Motion-BIDS: the BIDS extension for motion data (OpenNeuro's datasets; Jeung et al., Sci Data 2024).

Layout: ``<prefix>_motion.tsv`` (tab-separated, no header row, one column per channel) with beside it
``<prefix>_channels.tsv`` (one row per column, in order: ``name``, ``component`` (``x``, ``y``, ``z``,
``n/a``), ``type`` (``POS``, ``ORNT``, ``LATENCY``, ...), ``tracked_point``, ``units``, optionally
``sampling_frequency``) and ``<prefix>_motion.json`` (``SamplingFrequency``). Some tools write
``<prefix>.tsv`` and ``<prefix>_channels.tsv`` (the rate in the channels); both are read.

Every tracked point with ``POS`` channels for x, y and z is a point, named by its channels' name less
the component (``LHEE_PosX`` -> ``LHEE``: the marker-set names match), else by its ``tracked_point``.
``n/a`` (or an empty cell) is missing. The length unit is each channel's ``units`` (m, cm, mm); time is
a ``LATENCY`` channel in seconds where there is one, else frame / rate. The up axis is not in the
files: it is detected from the body.
"""

from __future__ import annotations

import json
import re
from pathlib import Path

import numpy as np

from ..errors import InputError
from .apdm import APDM_ACC_UNITS, APDM_GYR_UNITS, choose_sensor
from .imu_checks import ACC_UNITS, GYR_UNITS, option_flag, reading, unit_scale
from .imu_recording import ImuRecording
from .recording import Recording, number_row, read_text, uniform_time, unique_names

__all__ = ["read_motion_bids", "channels_file", "channel_types", "load", "component_of"]

_UNITS_M = {"m": 1.0, "cm": 0.01, "mm": 0.001}
_MISSING = {"n/a", "", "nan", "NaN"}


def channels_file(path) -> Path | None:
    """The ``_channels.tsv`` beside a Motion-BIDS data file, or None: ``<prefix>_motion.tsv`` or
    ``<prefix>.tsv`` -> ``<prefix>_channels.tsv``."""
    p = Path(path)
    stem = p.name[: -len(".tsv")] if p.name.lower().endswith(".tsv") else p.stem
    prefix = stem[: -len("_motion")] if stem.endswith("_motion") else stem
    if prefix.endswith("_channels"):
        return None
    candidate = p.with_name(f"{prefix}_channels.tsv")
    return candidate if candidate.is_file() else None


def _table(path: Path) -> tuple[list[str], list[dict[str, str]]]:
    _, text = read_text(path, encoding="utf-8-sig")
    lines = [line for line in text.splitlines() if line.strip()]
    if not lines:
        raise InputError(f"{path}: empty channels table")
    header = [h.strip().lower() for h in lines[0].split("\t")]
    if "name" not in header:
        raise InputError(f"{path}: a channels table needs a 'name' column; it has {', '.join(header)}")
    rows = [dict(zip(header, (c.strip() for c in line.split("\t")))) for line in lines[1:]]
    return header, rows


def _rate(channels: list[dict[str, str]], json_path: Path, where: str) -> float | None:
    rates = {r.get("sampling_frequency", "") for r in channels} - _MISSING
    if len(rates) > 1:
        raise InputError(f"{where}: the channels give different sampling frequencies ({', '.join(sorted(rates))})")
    if rates:
        try:
            return float(rates.pop())
        except ValueError:
            raise InputError(f"{where}: sampling_frequency is not a number") from None
    if json_path.is_file():
        try:
            value = json.loads(json_path.read_text(encoding="utf-8-sig")).get("SamplingFrequency")
        except (ValueError, AttributeError, OSError) as exc:
            raise InputError(f"{json_path}: not a readable JSON sidecar ({exc})") from None
        if isinstance(value, (int, float)) and not isinstance(value, bool):
            return float(value)
    return None


def _point_name(channel: str, component: str) -> str:
    """``LHEE_PosX`` -> ``LHEE``; ``pelvis_x`` -> ``pelvis``: the name less the component (and ``pos``)."""
    m = re.match(rf"^(.*?)[_\-. ]?(?:pos(?:ition)?)?[_\-. ]?{re.escape(component)}$", channel, re.IGNORECASE)
    return m.group(1) if m and m.group(1) else channel


def channel_types(path) -> set[str]:
    """The channel types (upper case) of the Motion-BIDS data file at ``path`` (empty without a channels table)."""
    channels_path = channels_file(path)
    if channels_path is None:
        return set()
    try:
        return {r.get("type", "").upper() for r in _table(channels_path)[1]}
    except InputError:
        return set()


def load(path, rate_hz: float | None = None):
    """(channels, data: samples x channels, rate or None, channels file, time from a LATENCY channel or None) of a
    Motion-BIDS data file: the readers' common part (this module's and the IMU one's)."""
    p = Path(path)
    channels_path = channels_file(p)
    if channels_path is None:
        raise InputError(f"{p}: no _channels.tsv beside it: not a Motion-BIDS file")
    _, channels = _table(channels_path)
    prefix = channels_path.name[: -len("_channels.tsv")]
    rate = float(rate_hz) if rate_hz else _rate(channels, p.with_name(f"{prefix}_motion.json"), str(channels_path))
    data = _data(p, len(channels), channels_path.name)
    latency = next((k for k, ch in enumerate(channels) if ch.get("type", "").upper() == "LATENCY"), None)
    time_s = None
    if latency is not None and np.all(np.isfinite(data[:, latency])):
        unit_s = {"ms": 1e-3, "us": 1e-6}.get(channels[latency].get("units", "s").strip().lower(), 1.0)
        time_s = (data[:, latency] - data[0, latency]) * unit_s
    elif rate:
        time_s = uniform_time(data.shape[0], rate)
    else:
        raise InputError(
            f"{p}: no sampling frequency ({channels_path.name}, {prefix}_motion.json) and no LATENCY channel; "
            "pass capture_rate_hz (--capture-rate-hz)"
        )
    return channels, data, rate, channels_path, time_s


def _data(p: Path, n_channels: int, channels_name: str) -> np.ndarray:
    _, text = read_text(p, encoding="utf-8-sig")
    rows = []
    for number, line in enumerate(text.splitlines(), start=1):
        if not line.strip():
            continue
        cells = line.split("\t")
        if len(cells) != n_channels:
            raise InputError(
                f"{p}: line {number} holds {len(cells)} values, but {channels_name} lists {n_channels} channels"
            )
        rows.append(number_row(["" if c.strip() in _MISSING else c for c in cells], p, number))
    if not rows:
        raise InputError(f"{p}: no data rows")
    return np.asarray(rows, dtype=float)


def component_of(channel: dict[str, str]) -> str:
    """A channel's axis, x, y or z: its ``component``, else the last letter of its name ('' if neither)."""
    component = channel.get("component", "").lower()
    if component not in ("x", "y", "z"):
        component = channel.get("name", "")[-1:].lower()
    return component if component in ("x", "y", "z") else ""


def read_motion_bids(path, *, length_unit_m: float | None = None, rate_hz: float | None = None) -> Recording:
    """Read the point positions of a Motion-BIDS ``*_motion.tsv`` (with its ``_channels.tsv`` and
    ``_motion.json`` beside it)."""
    p = Path(path)
    channels, data, rate, channels_path, time_s = load(p, rate_hz)
    # The points: POS channels grouped by their point, x, y and z each.
    points: dict[str, dict[str, int]] = {}
    scales: dict[str, float] = {}
    for k, ch in enumerate(channels):
        if ch.get("type", "").upper() != "POS":
            continue
        component = component_of(ch)
        if not component:
            continue
        name = _point_name(ch.get("name", ""), component) or ch.get("tracked_point", "") or f"point{k}"
        unit = ch.get("units", "m").strip().lower() or "m"
        if length_unit_m is None and unit not in _UNITS_M:
            raise InputError(
                f"{channels_path}: channel {ch.get('name', k)!r} in {unit!r}; pass length_unit_m (--length-unit-m)"
            )
        points.setdefault(name, {})[component] = k
        scales[name] = float(length_unit_m) if length_unit_m is not None else _UNITS_M.get(unit, 1.0)
    complete = [n for n, axes in points.items() if set(axes) == {"x", "y", "z"}]
    if not complete:
        kinds = sorted({ch.get("type", "?") for ch in channels})
        raise InputError(
            f"{p}: no point with POS channels for x, y and z ({channels_path.name} has {', '.join(kinds)})"
        )
    positions = np.stack([data[:, [points[n][a] for a in "xyz"]] * scales[n] for n in complete], axis=1)
    units = {ch.get("units", "") for ch in channels if ch.get("type", "").upper() == "POS"}
    return Recording(
        positions,
        unique_names(complete),
        time_s,
        rate_hz=rate,
        up_axis=None,
        source=str(p),
        metadata={
            "format": "motion_bids",
            "length_unit_m": scales[complete[0]],
            "length_unit_from": "override" if length_unit_m is not None else f"units {', '.join(sorted(units))}",
            "tracked_points": {n: channels[points[n]["x"]].get("tracked_point", "") for n in complete},
        },
    )


# ------------------------------------------------------------------------------------------- IMU

_BIDS_ACC_UNITS = {**APDM_ACC_UNITS, "m s^-2": 1.0, "m*s^-2": 1.0}
_BIDS_GYR_UNITS = {**APDM_GYR_UNITS, "rad s^-1": 1.0, "deg s^-1": np.pi / 180.0, "°/s": np.pi / 180.0}


def read_motion_bids_imu(path, *, sensor=None, acc_unit=None, gyr_unit=None, rate_hz=None) -> ImuRecording:
    """An IMU of a Motion-BIDS ``*_motion.tsv`` (io/motion_bids.py): the tracked point with ACCEL and GYRO
    channels for x, y and z that is at the lower back by its label (as the APDM reader chooses), or the only
    one, or ``sensor`` (--sensor); units from each channel's ``units`` (m/s^2 or g, rad/s or deg/s) unless
    ``acc_unit`` / ``gyr_unit`` say otherwise."""
    p = Path(path)
    channels, data, rate, channels_path, time_s = load(p, rate_hz)
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
    chosen = sensors[choose_sensor(sensors, sensor, p)]
    scales = []
    for kind, table, override, option in (
        ("ACCEL", _BIDS_ACC_UNITS, acc_unit, "acc_unit"),
        ("GYRO", _BIDS_GYR_UNITS, gyr_unit, "gyr_unit"),
    ):
        if override is not None:
            scales.append(unit_scale(override, ACC_UNITS if kind == "ACCEL" else GYR_UNITS, option, p))
            continue
        units = chosen["units"][kind]
        if len(units) != 1 or next(iter(units)) not in table:
            said = ", ".join(sorted(units))
            raise InputError(f"{channels_path}: {kind} channels in {said!r}; pass {option} ({option_flag(option)})")
        scales.append(table[next(iter(units))])
    acc = data[:, [chosen["ACCEL"][a] for a in "xyz"]] * scales[0]
    gyr = data[:, [chosen["GYRO"][a] for a in "xyz"]] * scales[1]
    about = {"layout": "motion_bids", "sensor": chosen["label"], "sensor_id": chosen["label"]}
    return reading(p, time_s, acc, gyr, rate, scales[1], about)
