"""OpenSim motion and storage files (``.mot``, ``.sto``): model coordinates over time.

Layout::

    subject01_walk1_ik          <- header lines, ``key=value`` among them
    version=1
    nRows=73
    nColumns=24
    inDegrees=yes
    endheader
    time  pelvis_tx  pelvis_ty  pelvis_tz  pelvis_tilt ...   (tab- or space-separated)
    0.40  0.6018     1.0454     -0.0217    5.1876 ...

The pelvis is the model's ``pelvis_tx``, ``pelvis_ty``, ``pelvis_tz``
(metres in OpenSim's ground frame, Y up); it becomes the point ``pelvis``.
Marker positions some tools append (``R.ASIS_tx``, ``R.ASIS_ty``,
``R.ASIS_tz``) become points too, so the feet are found.  Column names
written as state paths (``/jointset/ground_pelvis/pelvis_tx/value``) work
as well.  Rotational coordinates are kept in ``metadata["coordinates_rad"]``,
converted from degrees when the header says ``inDegrees=yes``.  A file of
ground-reaction forces (``ground_force_vx`` ...) holds no position and is
refused with a message that says so.  The up axis is Y (OpenSim's ground
frame).
"""

from __future__ import annotations

import re

import numpy as np

from ..errors import InputError
from .recording import Recording, number_row, read_text, unique_names

__all__ = ["read_opensim"]

_TRANSLATION = re.compile(r"^(?P<name>.+)_t(?P<axis>[xyz])$")


def read_opensim(path, *, length_unit_m: float | None = None, rate_hz: float | None = None) -> Recording:
    """Read the pelvis position (and any marker positions) of an OpenSim .mot or .sto file."""
    p, text = read_text(path)
    lines = text.splitlines()
    end = next((i for i, line in enumerate(lines[:200]) if line.strip().lower() == "endheader"), None)
    if end is None or end + 1 >= len(lines):
        raise InputError(f"{p}: not an OpenSim .mot/.sto file (no 'endheader' line followed by column names)")
    header = {}
    for line in lines[:end]:
        key, sep, value = line.partition("=")
        if sep:
            header[key.strip()] = value.strip()
    in_degrees = header.get("inDegrees", "yes" if "# SIMM Motion File Header:" in text[:2000] else "no")
    in_degrees_flag = in_degrees.strip().lower() in ("yes", "true", "1")
    columns = [_short(c) for c in lines[end + 1].split()]
    if not columns or columns[0].lower() != "time":
        raise InputError(f"{p}: line {end + 2}: the first OpenSim column must be 'time', not {columns[:1]}")

    translations: dict[str, dict[str, int]] = {}
    for i, c in enumerate(columns):
        m = _TRANSLATION.match(c)
        if m:
            translations.setdefault(m["name"], {})[m["axis"]] = i
    points = {n: axes for n, axes in translations.items() if set(axes) == {"x", "y", "z"}}
    if not points:
        if any("force" in c.lower() for c in columns):
            raise InputError(
                f"{p}: OpenSim file of ground-reaction forces ({', '.join(columns[1:4])}, ...), no positions; "
                "read the marker file (.trc) or the inverse-kinematics .mot beside it"
            )
        raise InputError(
            f"{p}: OpenSim file without pelvis_tx/pelvis_ty/pelvis_tz or marker _tx/_ty/_tz columns "
            f"(it holds {', '.join(columns[1:6])}{', ...' if len(columns) > 6 else ''})"
        )

    rows = []
    for number, line in enumerate(lines[end + 2 :], start=end + 3):
        if not line.strip():
            continue
        cells = line.split()
        if len(cells) != len(columns):
            raise InputError(f"{p}: line {number} holds {len(cells)} values, the header names {len(columns)}")
        rows.append(number_row(cells, p, number))
    if not rows:
        raise InputError(f"{p}: the OpenSim file holds no rows")
    table = np.asarray(rows, dtype=float)
    announced = _int(header.get("nRows") or header.get("datarows"))
    if announced is not None and len(rows) < announced:
        raise InputError(f"{p}: truncated OpenSim file: nRows announces {announced}, the file holds {len(rows)}")

    # The pelvis first (the model's root); its name is what the pelvis search knows for a root joint.
    names = sorted(points, key=lambda n: (n != "pelvis", columns.index(f"{n}_tx")))
    scale_m = float(length_unit_m) if length_unit_m is not None else 1.0
    positions = np.stack([table[:, [points[n][a] for a in "xyz"]] for n in names], axis=1) * scale_m
    used = {i for axes in points.values() for i in axes.values()}
    factor = np.pi / 180.0 if in_degrees_flag else 1.0
    coordinates = {
        c: table[:, i] * factor
        for i, c in enumerate(columns)
        if i and i not in used and "force" not in c and "torque" not in c
    }
    time_s = table[:, 0]
    rate = (
        float(rate_hz) if rate_hz is not None else (1.0 / float(np.median(np.diff(time_s))) if len(rows) > 1 else None)
    )
    if rate_hz is not None:
        time_s = time_s[0] + np.arange(len(rows)) / rate_hz
    return Recording(
        positions_m=positions,
        point_names=unique_names(names),
        time_s=time_s,
        rate_hz=rate,
        up_axis="y",
        source=str(p),
        metadata={
            "format": "opensim",
            "header": header,
            "in_degrees": in_degrees_flag,
            "coordinates_rad": coordinates,
            "length_unit_m": scale_m,
            "length_unit_from": "override" if length_unit_m is not None else "metres (OpenSim)",
            "up_axis_from": "OpenSim ground frame: Y up",
        },
    )


def _short(column: str) -> str:
    # "/jointset/ground_pelvis/pelvis_tx/value" -> "pelvis_tx"
    parts = [s for s in column.split("/") if s]
    if len(parts) > 1 and parts[-1] == "value":
        return parts[-2]
    return parts[-1] if parts else column


def _int(text) -> int | None:
    try:
        return int(float(text))
    except (TypeError, ValueError):
        return None
