"""OptiTrack Motive CSV exports (format version 1.2x).

Layout::

    Format Version,1.23,Take Name,walk,...,Export Frame Rate,120,...,Length Units,Millimeters,...
    <blank>
    ,Type,Rigid Body,Rigid Body,...,Bone,...,Marker,Marker,Marker
    ,Name,RB1,RB1,...,Skeleton:Hip,...,Skeleton:WaistLFront,...
    ,ID,1,1,...
    ,,Rotation,Rotation,Rotation,Rotation,Position,Position,Position,Mean Marker Error,...
    Frame,Time (Seconds),X,Y,Z,W,X,Y,Z,,...
    0,0.000000,...

Every marker, rigid body and skeleton bone with Position X, Y, Z columns
becomes a point (named as in the Name row); rotations and marker errors are
left out.  The length unit is the header's ``Length Units`` (Motive's
default is metres).  An export with rotations only, or with no asset at all,
is refused with a message that says so.  Motive's up axis is an export
setting the file does not state; Y up is Motive's convention, used unless the
body clearly says another axis (:func:`yoyogait.io.body.check_declared_up_axis`).
"""

from __future__ import annotations

import csv as _csv

import numpy as np

from ..errors import InputError
from .recording import Recording, number_row, positive_float, read_text, unique_names

__all__ = ["read_motive_csv", "is_motive_csv"]

MOTIVE_UNITS_M = {"meters": 1.0, "centimeters": 0.01, "millimeters": 0.001}


def is_motive_csv(first_line: str) -> bool:
    """True if a CSV's first line is Motive's ``Format Version,...`` header."""
    return first_line.lstrip('\ufeff"').startswith("Format Version")


def read_motive_csv(path, *, length_unit_m: float | None = None, rate_hz: float | None = None) -> Recording:
    """Read the positions of markers, rigid bodies and skeleton bones of a Motive CSV export."""
    p, text = read_text(path, encoding="utf-8-sig")
    rows = list(_csv.reader(text.splitlines()))
    first = rows[0]
    header = {first[i].strip(): first[i + 1].strip() for i in range(0, len(first) - 1, 2)}
    version = header.get("Format Version", "?")
    frame_row = next((i for i, r in enumerate(rows[:12]) if r and r[0].strip() == "Frame"), None)
    if frame_row is None:
        raise InputError(
            f"{p}: Motive CSV (format {version}) without its 'Frame,Time' header row in the first 12 lines"
        )
    by_label = {r[1].strip(): r for r in rows[1:frame_row] if len(r) > 1 and r[1].strip() in ("Type", "Name")}
    kinds = rows[frame_row - 1]
    axes = rows[frame_row]
    types, names = by_label.get("Type", []), by_label.get("Name", [])
    n_cols = len(axes)

    def cell(row: list[str], c: int) -> str:
        return row[c].strip() if c < len(row) else ""

    columns: list[tuple[str, str, int]] = []  # (name, type, first column)
    rotations = 0
    for c in range(2, n_cols):
        kind = cell(kinds, c)
        if kind == "Rotation":
            rotations += 1
        if kind == "Position" and cell(axes, c).upper() == "X":
            if [cell(kinds, c + k) for k in range(3)] != ["Position"] * 3 or [
                cell(axes, c + k).upper() for k in range(3)
            ] != ["X", "Y", "Z"]:
                raise InputError(f"{p}: Motive position of {cell(names, c)!r} is not three X, Y, Z columns")
            columns.append((cell(names, c) or f"point{len(columns) + 1}", cell(types, c), c))
    if not columns:
        if rotations:
            raise InputError(
                f"{p}: Motive CSV export (format {version}) with rotations only, no positions; "
                "export again with Position ticked for markers, rigid bodies or bones"
            )
        raise InputError(
            f"{p}: Motive CSV export (format {version}) with no marker, rigid-body or skeleton columns "
            "(only Frame and Time); export again with markers or assets selected"
        )

    metadata: dict = {
        "format": "motive-csv",
        "header": header,
        "point_types": {name: kind for name, kind, _ in columns},
    }
    if length_unit_m is not None:
        scale_m, metadata["length_unit_from"] = float(length_unit_m), "override"
    elif "Length Units" in header:
        unit = header["Length Units"]
        if unit.lower() not in MOTIVE_UNITS_M:
            raise InputError(f"{p}: unknown Motive Length Units {unit!r}; pass --length-unit-m")
        scale_m, metadata["length_unit_from"] = MOTIVE_UNITS_M[unit.lower()], f"Length Units = {unit}"
    else:
        scale_m, metadata["length_unit_from"] = 1.0, "metres (no Length Units in the header; the Motive default)"
    metadata["length_unit_m"] = scale_m
    metadata["up_axis_declared"], metadata["up_axis_declared_by"] = "y", "the Motive convention (Y up)"

    data = []
    wanted = [0, 1] + [c + k for _, _, c in columns for k in range(3)]
    for number in range(frame_row + 1, len(rows)):
        cells = rows[number]
        if not any(x.strip() for x in cells):
            continue
        if len(cells) > n_cols:
            raise InputError(f"{p}: line {number + 1} holds {len(cells)} columns, the Motive header {n_cols}")
        cells = cells + [""] * (n_cols - len(cells))
        data.append(number_row([cells[c] for c in wanted], p, number + 1))
    if not data:
        raise InputError(f"{p}: the Motive CSV holds no frames")
    table = np.asarray(data, dtype=float)

    file_rate = positive_float(header.get("Export Frame Rate")) or positive_float(header.get("Capture Frame Rate"))
    rate = float(rate_hz) if rate_hz is not None else file_rate
    time_s = table[:, 1]
    if rate_hz is not None or not np.all(np.isfinite(time_s)):
        if not rate:
            raise InputError(f"{p}: the Motive CSV has neither times nor a frame rate; pass --capture-rate-hz")
        time_s = (table[:, 0] - table[0, 0]) / rate
    elif rate and np.max(np.abs(time_s - time_s[0] - (table[:, 0] - table[0, 0]) / rate)) <= 0.6e-3:
        # Motive prints times to the millisecond: at 360 Hz they step 3, 3, 2 ms; the frame numbers are exact.
        time_s = time_s[0] + (table[:, 0] - table[0, 0]) / rate
    positions = table[:, 2:].reshape(len(data), len(columns), 3) * scale_m
    return Recording(
        positions_m=positions,
        point_names=unique_names(name for name, _, _ in columns),
        time_s=time_s,
        rate_hz=rate,
        up_axis=None,
        source=str(p),
        metadata=metadata,
    )
