"""The IMU stream's channel layout: what ``replay`` writes for an IMU file and what ``live`` accepts.

yoyogait's IMU stream (type ``IMU``, ``double64``) has, per sample, ``acc_x``, ``acc_y``, ``acc_z``
(specific force, m/s^2), ``gyr_x``, ``gyr_y``, ``gyr_z`` (angular rate, rad/s), in the sensor's frame,
then ``time_s``: the sample's time in the recording (``live`` uses it as the estimator's clock). The
``desc`` holds the channels (``label``, ``type`` ``Acc``/``Gyr``/``Time``, ``unit``) and a ``setup``
element with ``sensor_height_m`` when the file gave it.

Streams from other systems are read by their channel labels, ``[PREFIX_]KIND_AXIS`` with KIND one of
acc/accel/accelerometer/acceleration, gyr/gyro/gyroscope/angvel/angular_velocity, mag/magnetometer
(optional, not used) and AXIS x, y or z, separated by ``_``, ``.``, ``:``, ``-``, a space or nothing
(``AccX``, ``Lumbar:Gyro_Y``, ``accel.z``, ``LumbarAccX``; a microcontroller's ``ax``.. ``gz`` as the whole
label), or by a channel ``type`` of that form. Units come from
the channels' ``unit`` (``m/s^2``, ``g``; ``rad/s``, ``deg/s``, ...); a stream that does not state them
needs ``--acc-unit`` and ``--gyr-unit``, which also override what it states.
"""

from __future__ import annotations

import math
import re
from dataclasses import dataclass
from typing import Any

from ..errors import InputError
from ..io.imu_checks import option_flag
from ..io.imu_recording import GRAVITY_MPS2
from ._lsl import child_text, children, pylsl

IMU_STREAM_TYPE = "IMU"
TIME_CHANNEL = "time_s"

#: Stream types taken as an IMU's (lower case).
IMU_TYPES = ("imu", "inertial", "ins", "ahrs", "accgyro")

_KINDS = {
    "acc": ("acc", "accel", "accelerometer", "acceleration", "linearacceleration", "specificforce"),
    "gyr": ("gyr", "gyro", "gyroscope", "angvel", "angularvelocity", "angularrate"),
    "mag": ("mag", "magnetometer", "magneticfield"),
}
_KIND_OF = {name: kind for kind, names in _KINDS.items() for name in names}
_LABEL = re.compile(
    r"^.*?(?P<kind>" + "|".join(sorted(_KIND_OF, key=len, reverse=True)) + r")[\s_.:\-]?(?P<axis>[xyz])$",
    re.IGNORECASE,
)

#: Unit names (lower case, spaces removed) -> m/s^2 per unit, rad/s per unit.
ACC_UNIT_NAMES = {
    "m/s^2": 1.0,
    "m/s2": 1.0,
    "m/s/s": 1.0,
    "m/s²": 1.0,
    "mps2": 1.0,
    "meterspersecondsquared": 1.0,
    "metrespersecondsquared": 1.0,
    "g": GRAVITY_MPS2,
    "gravity": GRAVITY_MPS2,
}
GYR_UNIT_NAMES = {
    "rad/s": 1.0,
    "rad_s": 1.0,
    "rad/sec": 1.0,
    "radianspersecond": 1.0,
    "rps": 1.0,
    "deg/s": math.pi / 180.0,
    "deg_s": math.pi / 180.0,
    "deg/sec": math.pi / 180.0,
    "°/s": math.pi / 180.0,
    "dps": math.pi / 180.0,
    "degreespersecond": math.pi / 180.0,
}
#: The options' unit names (--acc-unit, --gyr-unit).
OPTION_UNITS = {"mps2": 1.0, "g": GRAVITY_MPS2, "rad_s": 1.0, "deg_s": math.pi / 180.0}

EXPECTED = (
    "channels labelled acc_x, acc_y, acc_z (m/s^2 or g) and gyr_x, gyr_y, gyr_z (rad/s or deg/s), "
    "units in desc/channels/channel/unit"
)


@dataclass(frozen=True)
class ImuLayout:
    """Where the accelerometer's and the gyro's axes are in a sample of an IMU stream, and their units."""

    acc_channels: tuple[int, ...]  # 3 channel indices (x, y, z)
    gyr_channels: tuple[int, ...]  # 3 channel indices
    channel_count: int
    acc_scale: float  # m/s^2 per unit of the stream
    gyr_scale: float  # rad/s per unit
    acc_unit: str  # as the stream (or the option) says it
    gyr_unit: str
    time_channel: int | None = None  # the recording's time (yoyogait's replay), else None
    mag_channels: tuple[int, ...] | None = None  # present, not used
    sensor_height_m: float | None = None  # setup/sensor_height_m, None when the stream does not say


#: A microcontroller's short labels, the whole label: ax, ay, az (acc), gx, gy, gz (gyr), mx.. (mag).
_SHORT_LABEL = re.compile(r"^(?P<kind>[agm])(?P<axis>[xyz])$", re.IGNORECASE)
_SHORT_KIND = {"a": "acc", "g": "gyr", "m": "mag"}


def _kind_and_axis(label: str, kind: str) -> tuple[str | None, int]:
    for text in (label, kind):
        m = _LABEL.match(text.strip().replace("angular velocity", "angvel")) if text else None
        if m:
            return _KIND_OF[m["kind"].lower()], "xyz".index(m["axis"].lower())
        short = _SHORT_LABEL.match(text.strip()) if text else None
        if short:
            return _SHORT_KIND[short["kind"].lower()], "xyz".index(short["axis"].lower())
    return None, 0


def _channels(info: Any) -> tuple[list[Any], list[str]]:
    elements = children(info.desc().child("channels"), "channel")
    return elements, [child_text(c, "label") for c in elements]


def imu_axes(info: Any) -> dict[str, dict[int, int]]:
    """{kind: {axis: channel}} of the labelled acc/gyr/mag channels of a StreamInfo (with desc)."""
    elements, labels = _channels(info)
    found: dict[str, dict[int, int]] = {}
    for index, (element, label) in enumerate(zip(elements, labels)):
        kind, axis = _kind_and_axis(label, child_text(element, "type"))
        if kind is not None:
            found.setdefault(kind, {}).setdefault(axis, index)
    return found


def is_imu_info(info: Any) -> bool:
    """True for an IMU stream: its type says so (``IMU``), or its channels are labelled acc and gyro x, y, z."""
    if info.type().strip().lower() in IMU_TYPES:
        return True
    axes = imu_axes(info)
    return len(axes.get("acc", {})) == 3 and len(axes.get("gyr", {})) == 3


def _scale(units: set[str], table: dict[str, float], override: str | None, option: str, what: str, name: str):
    flag = option_flag(option)
    if override is not None:
        if override not in OPTION_UNITS:
            raise InputError(f"{flag} must be one of {', '.join(sorted(OPTION_UNITS))}, not {override!r}")
        return OPTION_UNITS[override], override
    keys = {u.strip().lower().replace(" ", "") for u in units}
    if not keys:  # asked for by the caller, with the other kind's if it has none either
        return None, ""
    unknown = sorted(k for k in keys if k not in table)
    if unknown:
        raise InputError(f"stream {name!r}: {what} unit {', '.join(unknown)} not understood; pass {flag}")
    scales = {table[k] for k in keys}
    if len(scales) > 1:
        raise InputError(f"stream {name!r}: its {what} channels disagree on their unit ({', '.join(sorted(keys))})")
    return scales.pop(), sorted(units)[0]


def read_imu_layout(
    info: Any, *, acc_unit: str | None = None, gyr_unit: str | None = None, sensor_height_m: float | None = None
) -> ImuLayout:
    """The layout of an IMU stream from its StreamInfo (with desc); InputError naming the stream and what is
    expected. ``acc_unit``/``gyr_unit`` (mps2, g / rad_s, deg_s) override the stream's units,
    ``sensor_height_m`` its setup/sensor_height_m."""
    lsl = pylsl()
    name = info.name()
    count = info.channel_count()
    if info.channel_format() == lsl.cf_string:
        raise InputError(f"stream {name!r}: holds strings; expected numeric {EXPECTED}")
    elements, labels = _channels(info)
    if len(elements) != count or not any(labels):
        raise InputError(f"stream {name!r}: its {count} channels carry no labels in desc/channels; expected {EXPECTED}")
    axes = imu_axes(info)
    missing = [f"{k}_{a}" for k in ("acc", "gyr") for i, a in enumerate("xyz") if i not in axes.get(k, {})]
    if missing:
        shown = ", ".join(labels[:12]) + (f", ... ({count - 12} more)" if count > 12 else "")
        raise InputError(f"stream {name!r}: no {', '.join(missing)} channel; expected {EXPECTED}; got {shown}")
    acc = tuple(axes["acc"][i] for i in range(3))
    gyr = tuple(axes["gyr"][i] for i in range(3))
    mag = tuple(axes["mag"][i] for i in range(3)) if len(axes.get("mag", {})) == 3 else None

    def units(channels: tuple[int, ...]) -> set[str]:
        return {u for u in (child_text(elements[int(c)], "unit") for c in channels) if u}

    acc_scale, acc_said = _scale(units(acc), ACC_UNIT_NAMES, acc_unit, "acc_unit", "acceleration", name)
    gyr_scale, gyr_said = _scale(units(gyr), GYR_UNIT_NAMES, gyr_unit, "gyr_unit", "angular rate", name)
    unitless = [
        f"its {what} channels carry no unit; pass {option_flag(option)} ({choices})"
        for scale, what, option, choices in (
            (acc_scale, "acceleration", "acc_unit", "mps2 or g"),
            (gyr_scale, "angular rate", "gyr_unit", "rad_s or deg_s"),
        )
        if scale is None
    ]
    if unitless:  # both kinds in one line, not one option per attempt
        raise InputError(f"stream {name!r}: " + "; ".join(unitless))
    time_channel = labels.index(TIME_CHANNEL) if TIME_CHANNEL in labels else None
    height = sensor_height_m
    said = child_text(info.desc().child("setup"), "sensor_height_m")
    if height is None and said:
        try:
            height = float(said)
        except ValueError:
            height = math.nan
        if not (math.isfinite(height) and 0.1 < height <= 3.0):
            raise InputError(
                f"stream {name!r}: setup/sensor_height_m {said!r} is not a height in (0.1, 3] m; pass --sensor-height-m"
            )
    return ImuLayout(acc, gyr, count, acc_scale, gyr_scale, acc_said, gyr_said, time_channel, mag, height)


def imu_stream_info(
    name: str,
    rate_hz: float,
    *,
    sensor_height_m: float | None = None,
    source_id: str = "",
    source_file: str = "",
) -> Any:
    """StreamInfo of yoyogait's IMU stream (layout in the module docstring)."""
    lsl = pylsl()
    info = lsl.StreamInfo(name, IMU_STREAM_TYPE, 7, float(rate_hz), lsl.cf_double64, source_id or name)
    desc = info.desc()
    desc.append_child("acquisition").append_child_value("manufacturer", "yoyogait").append_child_value(
        "model", "replay"
    )
    channels = desc.append_child("channels")
    for kind, unit in (("acc", "m/s^2"), ("gyr", "rad/s")):
        for axis in "xyz":
            ch = channels.append_child("channel")
            ch.append_child_value("label", f"{kind}_{axis}")
            ch.append_child_value("type", kind.capitalize())
            ch.append_child_value("unit", unit)
    ch = channels.append_child("channel")
    ch.append_child_value("label", TIME_CHANNEL)
    ch.append_child_value("type", "Time")
    ch.append_child_value("unit", "seconds")
    setup = desc.append_child("setup")
    if sensor_height_m is not None:
        setup.append_child_value("sensor_height_m", repr(float(sensor_height_m)))
    if source_file:
        setup.append_child_value("source_file", source_file)
    return info


def describe_imu(info: Any) -> list[str]:
    """What ``live`` makes of an IMU stream (``--list-points``): its channels, units, time base, sensor height."""
    rate = info.nominal_srate()
    lines = [
        f"stream {info.name()!r}: type {info.type()!r}, {info.channel_count()} channels, "
        + (f"{rate:g} Hz" if rate > 0 else "irregular rate")
        + f", from {info.hostname() or 'unknown host'}: an IMU stream",
    ]
    _, labels = _channels(info)
    axes = imu_axes(info)
    for kind, what in (("acc", "acceleration"), ("gyr", "angular rate"), ("mag", "magnetometer (not used)")):
        found = axes.get(kind, {})
        shown = ", ".join(labels[found[i]] for i in sorted(found)) if found else "none"
        lines.append(f"{what}: {shown}")
    try:
        layout = read_imu_layout(info)
        lines.append(f"units: acceleration {layout.acc_unit}, angular rate {layout.gyr_unit}")
        lines.append("time: " + ("the time_s channel" if layout.time_channel is not None else "the LSL timestamps"))
        height = f"{layout.sensor_height_m:g} m" if layout.sensor_height_m else "not stated (--sensor-height-m)"
        lines.append(f"sensor height: {height}")
    except InputError as exc:
        lines.append(f"not usable as it is: {exc}")
    return lines
