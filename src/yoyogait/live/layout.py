"""The marker stream's channel layout: what ``replay`` writes and what ``live`` accepts.

yoyogait's marker stream (type ``Mocap``, ``double64``) has, per frame, three channels per point,
labelled ``<point>_x``, ``<point>_y``, ``<point>_z``, in metres, NaN where the point is missing,
then one channel ``time_s``: the frame's time in the recording (``live`` uses it as the
estimator's clock, so a replay at any speed is estimated as the walk it records). The stream's
``desc`` holds, besides the channels (label, marker, type PositionX/Y/Z or Time, unit), a
``setup`` element with ``up_axis``, ``length_unit_m`` and the point names (``markers/marker/label``).

Streams from other systems are read by their channel labels: ``NAME_x``, ``NAME.X``, ``NAME:x``,
``NAME X`` or ``NAMEX`` (three per point), or by the XDF motion-capture fields (``marker`` or
``object`` and ``type`` PositionX/Y/Z) when the channels carry them; other channels (rotations,
frame numbers, ...) are ignored. The length unit comes from the channels' ``unit`` or
``setup/length_unit_m`` and the up axis from ``setup/up_axis``; where the stream does not say,
``live`` needs ``--length-unit-m`` and ``--up-axis``.
"""

from __future__ import annotations

import re
from collections.abc import Sequence
from dataclasses import dataclass
from typing import Any

import numpy as np

from ..errors import InputError
from ..io.recording import AXES, LENGTH_UNITS_M
from ._lsl import child_text, children, pylsl

STREAM_TYPE = "Mocap"
TIME_CHANNEL = "time_s"

#: Unit names of channels (XDF uses the long plural forms) -> metres per unit.
_UNIT_NAMES_M = {
    **LENGTH_UNITS_M,
    "millimeters": 0.001,
    "millimetres": 0.001,
    "millimeter": 0.001,
    "millimetre": 0.001,
    "centimeters": 0.01,
    "centimetres": 0.01,
    "centimeter": 0.01,
    "centimetre": 0.01,
}
_LABEL = re.compile(r"^(?P<point>.+?)[\s_.:\-]+(?P<axis>[xyz])$", re.IGNORECASE)
_LABEL_GLUED = re.compile(r"^(?P<point>.+?)(?P<axis>[XYZ])$")  # LASIX: upper-case axis, no separator
_TYPE = re.compile(r"^position[\s_]*(?P<axis>[xyz])$", re.IGNORECASE)


@dataclass(frozen=True)
class MarkerLayout:
    """Where each point's coordinates are in a frame of a marker stream."""

    point_names: tuple[str, ...]
    position_channels: np.ndarray  # points x 3 channel indices (x, y, z)
    channel_count: int
    time_channel: int | None = None  # the recording's time (yoyogait's replay), else None
    length_unit_m: float | None = None  # metres per unit, None when the stream does not say
    up_axis: str | None = None  # "x", "y", "z", None when the stream does not say

    def positions(self, sample: np.ndarray, names: Sequence[int] | None = None) -> np.ndarray:
        """Coordinates (points x 3, the stream's unit) of one frame, of the points at ``names``."""
        channels = self.position_channels if names is None else self.position_channels[list(names)]
        return np.asarray(sample, dtype=float)[channels]


def marker_stream_info(
    name: str,
    point_names: Sequence[str],
    rate_hz: float,
    up_axis: str,
    *,
    source_id: str = "",
    source_file: str = "",
) -> Any:
    """StreamInfo of yoyogait's marker stream (layout in the module docstring)."""
    lsl = pylsl()
    n = len(point_names)
    info = lsl.StreamInfo(name, STREAM_TYPE, 3 * n + 1, float(rate_hz), lsl.cf_double64, source_id or name)
    desc = info.desc()
    desc.append_child("acquisition").append_child_value("manufacturer", "yoyogait").append_child_value(
        "model", "replay"
    )
    channels = desc.append_child("channels")
    for point in point_names:
        for axis in AXES:
            ch = channels.append_child("channel")
            ch.append_child_value("label", f"{point}_{axis}")
            ch.append_child_value("marker", point)
            ch.append_child_value("type", f"Position{axis.upper()}")
            ch.append_child_value("unit", "meters")
    ch = channels.append_child("channel")
    ch.append_child_value("label", TIME_CHANNEL)
    ch.append_child_value("type", "Time")
    ch.append_child_value("unit", "seconds")
    setup = desc.append_child("setup")
    setup.append_child_value("up_axis", up_axis)
    setup.append_child_value("length_unit_m", "1")
    if source_file:
        setup.append_child_value("source_file", source_file)
    markers = setup.append_child("markers")
    for point in point_names:
        markers.append_child("marker").append_child_value("label", point)
    return info


def read_layout(info: Any, *, length_unit_m: float | None = None, up_axis: str | None = None) -> MarkerLayout:
    """The layout of a marker stream from its StreamInfo (with desc); InputError saying what is expected."""
    lsl = pylsl()
    name = info.name()
    count = info.channel_count()
    expected = "channels labelled <point>_x, <point>_y, <point>_z (marker positions)"
    if info.channel_format() == lsl.cf_string:
        raise InputError(f"stream {name!r}: holds strings; expected numeric {expected}")
    desc = info.desc()
    channel_elements = children(desc.child("channels"), "channel")
    labels = [child_text(c, "label") for c in channel_elements]
    if len(channel_elements) != count or not any(labels):
        raise InputError(f"stream {name!r}: its {count} channels carry no labels in desc/channels; expected {expected}")
    axes_of: dict[str, dict[int, int]] = {}
    time_channel = None
    units = set()
    for index, (element, label) in enumerate(zip(channel_elements, labels)):
        kind = child_text(element, "type")
        if label == TIME_CHANNEL or kind.lower() == "time":
            time_channel = index if label == TIME_CHANNEL else time_channel
            continue
        point, axis = _point_and_axis(label, kind, child_text(element, "marker") or child_text(element, "object"))
        if point is None:
            continue
        axes_of.setdefault(point, {})[axis] = index
        unit = child_text(element, "unit")
        if unit:
            units.add(unit.lower())
    complete = [(p, a) for p, a in axes_of.items() if len(a) == 3]
    if not complete:
        shown = ", ".join(labels[:12]) + (f", ... ({count - 12} more)" if count > 12 else "")
        raise InputError(f"stream {name!r}: no point has x, y and z channels; expected {expected}; got {shown}")
    position_channels = np.array([[a[0], a[1], a[2]] for _, a in complete], dtype=np.intp)

    setup = desc.child("setup")
    unit_m = length_unit_m
    if unit_m is None and child_text(setup, "length_unit_m"):
        unit_m = _positive(child_text(setup, "length_unit_m"), f"stream {name!r}: setup/length_unit_m")
    if unit_m is None and units:
        if len(units) > 1 or next(iter(units)) not in _UNIT_NAMES_M:
            raise InputError(
                f"stream {name!r}: position unit(s) {', '.join(sorted(units))} not understood; pass --length-unit-m"
            )
        unit_m = _UNIT_NAMES_M[next(iter(units))]
    up = up_axis or child_text(setup, "up_axis").lower() or None
    if up is not None and up not in AXES:
        raise InputError(f"stream {name!r}: up axis {up!r} is not x, y or z; pass --up-axis")
    return MarkerLayout(tuple(p for p, _ in complete), position_channels, count, time_channel, unit_m, up)


def _point_and_axis(label: str, kind: str, marker: str) -> tuple[str | None, int]:
    typed = _TYPE.match(kind)
    if typed and marker:
        return marker, AXES.index(typed["axis"].lower())
    for pattern in (_LABEL, _LABEL_GLUED):
        m = pattern.match(label)
        if m:
            return m["point"], AXES.index(m["axis"].lower())
    return None, 0


def _positive(text: str, where: str) -> float:
    try:
        value = float(text)
    except ValueError:
        value = float("nan")
    if not (np.isfinite(value) and value > 0):
        raise InputError(f"{where}: {text!r} is not a positive number")
    return value
