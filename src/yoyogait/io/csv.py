"""CSV files in yoyogait's documented layout (docs/input.md).

Two layouts, told apart by the header row:

Positions::

    # length_unit_m: 0.001        <- optional "# key: value" lines before the header
    # up_axis: z
    time_s,LASI_x,LASI_y,LASI_z,RASI_x,RASI_y,RASI_z
    0.00,512.1,1033.0,941.2,,,
    0.01,513.4,1033.1,941.0,700.2,1020.4,940.1

Ready velocities (m/s), e.g. from another pipeline or an IMU::

    time_s,vx,vz
    0.00,1.21,0.05

* The time column is ``time_s``, ``time`` or ``t`` in seconds, or one of the other
  names :data:`yoyogait.io.imu_tables.TIME_COLUMN_NAMES` lists (``time_ms``, a ROS
  stamp in ns, a bare ``timestamp`` by its intervals); without one, give
  ``# rate_hz:`` or ``rate_hz=``.
* A ROS topic as ``rostopic echo -p`` writes it: a pose's or transform's position is
  a point (``field.pose.position.x`` is ``pose``), a quaternion (x, y, z with a w) none,
  and columns that are neither points, times nor velocities are not parsed (text).
* A point is three columns ``<name>_x``, ``<name>_y``, ``<name>_z`` (``.x``
  and ``:x`` and upper case X/Y/Z work too), in any order; a unit after the
  axis (``pelvis_x_m``, ``LASI_x_mm``, ``_cm``) is the length unit.
* Lengths are metres unless ``# length_unit_m:``, ``length_unit_m=`` or the
  columns' unit says otherwise (velocities are then that unit per second).
* An empty cell, ``nan`` or ``NaN`` is a missing sample.
* Two header rows, the point names and under them ``x``, ``y``, ``z`` (what pandas writes for a
  table with a (point, axis) column index, as gaitmap's example motion capture), are read as
  ``<name>_x`` ...; a first column without a name there is the table's row index, not a time.
* The separator is a comma; a header with semicolons or tabs and no comma
  switches to that.
"""

from __future__ import annotations

import csv as _csv
import re

import numpy as np

from ..errors import InputError
from .imu_tables import TIME_COLUMN_NAMES, is_imu_header, time_in_seconds
from .recording import (
    AXES,
    MAX_SPEED_MPS,
    Recording,
    check_coordinates,
    check_rate,
    check_time,
    number_row,
    read_text,
    uniform_time,
)

__all__ = ["read_csv"]

VELOCITY_COLUMNS = {"vx": ("vx", "vx_mps"), "vz": ("vz", "vz_mps")}
_POINT_COLUMN = re.compile(r"^(?P<name>.+?)[_.:](?P<axis>[xyzXYZ])(?:_(?P<unit>(?i:mm|cm|m)))?$")
#: The w of a quaternion's x, y, z, w columns; a ROS message's point, named without rostopic's ``field.`` and
#: the ``position`` / ``translation`` of a pose or transform (``field.pose.position`` is ``pose``).
_QUATERNION_W = re.compile(r"^(?P<name>.+?)[_.:][wW]$")
_ROS_POSITION = re.compile(r"^(?:field\.)?(?P<name>.+?)(?:\.position|\.translation)?$")
#: The length units a point column may name after its axis, in metres.
COLUMN_UNITS_M = {"m": 1.0, "cm": 0.01, "mm": 0.001}


def read_csv(path, *, length_unit_m: float | None = None, rate_hz: float | None = None) -> Recording:
    """Read a CSV of point positions or of ready velocities."""
    p, text = read_text(path, encoding="utf-8-sig")
    lines = text.splitlines()

    settings: dict[str, str] = {}
    first = 0
    while first < len(lines) and (not lines[first].strip() or lines[first].lstrip().startswith("#")):
        key, sep, value = lines[first].lstrip("# \t").partition(":")
        if sep:
            settings[key.strip().lower()] = value.strip()
        first += 1
    if first >= len(lines):
        raise InputError(f"{p}: the CSV file has no header row")
    header_line = lines[first]
    delimiter = "," if "," in header_line else ";" if ";" in header_line else "\t" if "\t" in header_line else ","
    header = [h.strip() for h in next(_csv.reader([header_line], delimiter=delimiter))]
    if first + 1 < len(lines):
        axes_row = [h.strip() for h in next(_csv.reader([lines[first + 1]], delimiter=delimiter))]
        merged = _two_row_header(header, axes_row)
        if merged is not None:
            header = merged
            first += 1

    _refuse_inertial(header, p)
    # Cells of the columns read are numbers; others (a ROS export's frame_id, a note) are not parsed.
    lower_names = [h.lower() for h in header]
    velocity_names = {n for names in VELOCITY_COLUMNS.values() for n in names}
    read = [
        bool(_POINT_COLUMN.match(h)) or n in TIME_COLUMN_NAMES or n in velocity_names
        for h, n in zip(header, lower_names)
    ]

    rows = []
    line_numbers = []
    body = [(n, line) for n, line in enumerate(lines[first + 1 :], start=first + 2) if line.strip()]
    for (number, _line), cells in zip(body, _csv.reader([line for _, line in body], delimiter=delimiter)):
        if len(cells) != len(header):
            if number == body[-1][0] and len(cells) < len(header) and not text.endswith("\n"):
                raise InputError(
                    f"{p}: truncated CSV file: the last line stops after {len(cells)} of {len(header)} columns"
                )
            raise InputError(f"{p}: line {number} holds {len(cells)} columns, the header {len(header)}")
        rows.append(number_row([c if r else "nan" for c, r in zip(cells, read)], p, number))
        line_numbers.append(number)
    if not rows:
        raise InputError(f"{p}: the CSV file holds no data rows")
    table = np.asarray(rows, dtype=float)

    metadata: dict = {"format": "csv", "settings": settings}
    in_file = _setting_float(settings, "length_unit_m", p)
    named = _column_unit(header, p)
    if in_file is not None and named is not None and abs(in_file - named[0]) > 1e-12 * named[0]:
        raise InputError(
            f"{p}: '# length_unit_m: {settings['length_unit_m']}' but the columns are in {named[1]} "
            f"({named[2]}); give one of them (--length-unit-m overrides both)"
        )
    if length_unit_m is not None:
        unit, source = float(length_unit_m), "override"
    elif in_file is not None:
        unit, source = in_file, "# length_unit_m"
    elif named is not None:
        unit, source = named[0], f"the columns' unit ({named[2]})"
    else:
        unit, source = 1.0, "metres (the CSV default)"
    metadata["length_unit_m"] = unit
    metadata["length_unit_from"] = source

    lower = [h.lower() for h in header]
    # The columns first: a file without usable ones is told so before it is asked for a rate.
    velocity_cols = {
        key: next((lower.index(c) for c in names if c in lower), None) for key, names in VELOCITY_COLUMNS.items()
    }
    if all(c is not None for c in velocity_cols.values()):
        metadata["velocities_mps"] = {key: table[:, c] * unit for key, c in velocity_cols.items()}
        for key, v in metadata["velocities_mps"].items():
            with np.errstate(invalid="ignore"):
                fast = np.flatnonzero(np.abs(v) > MAX_SPEED_MPS)
            if fast.size:
                k = int(fast[0])
                raise InputError(
                    f"{p}: line {line_numbers[k]}: {key} = {v[k]:.4g} m/s, faster than any person "
                    f"({MAX_SPEED_MPS:g} m/s): a corrupt value or a wrong length unit"
                )
        positions = np.empty((len(rows), 0, 3))
        names: list[str] = []
    else:
        names, positions = _points(header, table, p)
        positions *= unit
        check_coordinates(positions, names, p, line_numbers)

    time_col = next((lower.index(c) for c in TIME_COLUMN_NAMES if c in lower), None)
    file_rate = _setting_float(settings, "rate_hz", p)
    rate = float(rate_hz) if rate_hz is not None else file_rate
    if rate is not None:
        rate = check_rate(rate, p, "capture_rate_hz override" if rate_hz is not None else "'# rate_hz'")
    if time_col is not None and rate_hz is None:
        time_s, inferred = time_in_seconds(header[time_col], table[:, time_col], p)
        if inferred is not None:
            metadata["time_unit"] = f"{header[time_col]} in {inferred}"
        if not np.all(np.isfinite(time_s)):
            raise InputError(f"{p}: the time column {header[time_col]!r} has empty or invalid cells")
        check_time(time_s, p, line_numbers)
    elif rate:
        time_s = uniform_time(len(rows), rate)
    else:
        raise InputError(
            f"{p}: the CSV has no time column ({', '.join(TIME_COLUMN_NAMES[:3])}, ...) and no rate; "
            "pass capture_rate_hz="
        )

    up_axis = settings.get("up_axis")
    if up_axis is not None and up_axis.lower() not in AXES:
        raise InputError(f"{p}: '# up_axis: {up_axis}' must be x, y or z")

    if rate is None and len(time_s) > 1:
        rate = check_rate(1.0 / float(np.median(np.diff(time_s))), p, "rate of the timestamps")
    return Recording(
        positions_m=positions,
        point_names=names,
        time_s=time_s,
        rate_hz=rate,
        up_axis=up_axis.lower() if up_axis else None,
        source=str(p),
        metadata=metadata,
    )


#: An inertial sensor's column: acc, accel, gyr, gyro, mag or magn as a word of the name, first
#: (``acc_x``) or after a sensor's name (``pelvis_ACCEL_x``).
_INERTIAL_COLUMN = re.compile(r"(?:^|[_ .:\-])(?:acc|accel|gyr|gyro|mag|magn)(?:[_ .:\-]?[xyz]\b|[_ .:\-])")


def _two_row_header(names: list[str], axes: list[str]) -> list[str] | None:
    """The columns ``<name>_<axis>`` of a header in two rows (point names, then x, y, z under each; a
    leading column unnamed in both is the row index: ``index``), or None unless ``axes`` is such a row."""
    if len(axes) != len(names) or not any(axes):
        return None
    merged = []
    for name, axis in zip(names, axes):
        if not name and not axis:
            merged.append("index")
        elif name and axis.lower() in AXES:
            merged.append(f"{name}_{axis.lower()}")
        else:
            return None
    return merged


def _refuse_inertial(header: list[str], where) -> None:
    """An IMU table (accelerometer and gyroscope columns, no point positions) is not motion capture."""
    lower = [h.lower() for h in header]
    inertial = [h for h in lower if _INERTIAL_COLUMN.search(h)]
    has_points = any(h.endswith(("_x", ".x", " x")) and not _INERTIAL_COLUMN.search(h) for h in lower)
    if len(inertial) >= 3 and not has_points:
        columns = ", ".join(header[lower.index(h)] for h in inertial[:6])
        if is_imu_header(header):
            how = "read it with yoyogait.io.imu_read.read_imu (the CLI does; docs/imu.md)"
        else:  # the CLI took it for motion capture: say what the IMU readers need
            how = "an IMU table needs acc and gyr columns for each axis: x, y, z or is, ml, pa (docs/imu.md)"
        raise InputError(f"{where}: an IMU recording ({columns}), not point positions: {how}")


def _column_unit(header: list[str], where) -> tuple[float, str, str] | None:
    """(metres per unit, the unit, a column naming it) of point columns that name a unit after their
    axis (``pelvis_x_m``); None when none does. Columns in different units are refused."""
    named: dict[str, str] = {}
    for h in header:
        m = _POINT_COLUMN.match(h)
        if m and m["unit"]:
            named.setdefault(m["unit"].lower(), h)
    if len(named) > 1:
        shown = ", ".join(f"{h} ({u})" for u, h in named.items())
        raise InputError(f"{where}: point columns in different length units: {shown}; give them in one")
    if not named:
        return None
    ((name, column),) = named.items()
    return COLUMN_UNITS_M[name], name, column


def _points(header: list[str], table: np.ndarray, where) -> tuple[list[str], np.ndarray]:
    """Point names (in order of first appearance) and their positions from the x/y/z columns. A group
    with a w column too is a quaternion, not a point; a ROS pose's position (``field.pose.position.x``,
    as ``rostopic echo -p`` writes a geometry_msgs/PoseStamped) is the point ``pose``, a PointStamped's
    ``point``, a TransformStamped's ``transform``."""
    columns: dict[str, dict[str, int]] = {}
    quaternions = {m["name"] for h in header if (m := _QUATERNION_W.match(h))}
    for i, h in enumerate(header):
        m = _POINT_COLUMN.match(h)
        if m and m["name"] not in quaternions:
            name = _ROS_POSITION.sub(r"\g<name>", m["name"])
            columns.setdefault(name, {})[m["axis"].lower()] = i
    incomplete = [n for n, axes in columns.items() if set(axes) != set(AXES)]
    if incomplete:
        raise InputError(f"{where}: point {incomplete[0]!r} lacks an x, y or z column")
    if not columns:
        shown = ", ".join(header[:8]) + (", ..." if len(header) > 8 else "")
        raise InputError(
            f"{where}: no point columns (<name>_x, <name>_y, <name>_z) and no velocity columns (vx, vz) in the header "
            f"(it has {shown}; an IMU table needs acc and gyr columns)"
        )
    names = list(columns)
    idx = [[columns[n][a] for a in AXES] for n in names]
    return names, table[:, idx]


def _setting_float(settings: dict, key: str, where) -> float | None:
    if key not in settings:
        return None
    try:
        value = float(settings[key])
    except ValueError:
        raise InputError(f"{where}: '# {key}: {settings[key]}' is not a number") from None
    if not value > 0:
        raise InputError(f"{where}: '# {key}' must be positive")
    return value
