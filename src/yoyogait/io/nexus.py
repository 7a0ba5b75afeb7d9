"""Vicon Nexus CSV exports (the "Trajectories" section).

Nexus writes one block per section, separated by a blank line::

    Trajectories
    100                                  <- capture rate, Hz
    ,,Daphnee:ASISr,,,Daphnee:ASISl,,,   <- Subject:Marker over the X column of each marker
    Frame,Sub Frame,X,Y,Z,X,Y,Z          <- (X', X'' ... when velocities were exported too)
    ,,mm,mm,mm,mm,mm,mm                  <- units
    1,0,667.12,305.799,175.209,...       <- an empty cell is a gap

Other sections (``Devices``, ``Model Outputs``, ``Joints``, ``Segments``)
hold analog data or model angles, not marker positions; a file with none of
its markers in a Trajectories section is refused with a message naming what
it holds.  Nexus states no up axis (Vicon labs are Z up, but the file does
not say so), so it is detected.
"""

from __future__ import annotations

import csv as _csv

import numpy as np

from ..errors import InputError
from .recording import Recording, number_row, read_text
from .recording import length_unit_m as unit_of

__all__ = ["read_nexus_csv", "is_nexus_csv", "SECTIONS"]

#: Section titles a Nexus CSV export may hold.
SECTIONS = ("Trajectories", "Devices", "Model Outputs", "Joints", "Segments", "Events")


def is_nexus_csv(first_line: str) -> bool:
    """True if a CSV's first line is a Nexus section title (``Trajectories,,,``)."""
    cell = first_line.split(",", 1)[0].strip().strip('"')
    return cell in SECTIONS


def read_nexus_csv(path, *, length_unit_m: float | None = None, rate_hz: float | None = None) -> Recording:
    """Read the marker trajectories of a Vicon Nexus CSV export."""
    p, text = read_text(path, encoding="utf-8-sig")
    lines = text.splitlines()
    rows = list(_csv.reader(lines))
    titles = {i: r[0].strip() for i, r in enumerate(rows) if r and r[0].strip() in SECTIONS}
    if "Trajectories" not in titles.values():
        held = ", ".join(dict.fromkeys(titles.values())) or "no section"
        raise InputError(
            f"{p}: Vicon Nexus CSV export with {held} but no Trajectories section (no marker positions); "
            "export the trial again with Trajectories ticked, or export a C3D"
        )
    start = next(i for i, title in titles.items() if title == "Trajectories")
    if start + 3 >= len(rows):
        raise InputError(f"{p}: the Nexus Trajectories section stops inside its 4-line header")
    file_rate = _float(rows[start + 1][0] if rows[start + 1] else "")
    names_row, axes_row = rows[start + 2], rows[start + 3]
    if not axes_row or axes_row[0].strip().lower() != "frame":
        raise InputError(f"{p}: line {start + 4}: the Nexus Trajectories header must be 'Frame,Sub Frame,X,Y,Z,...'")
    first_data = start + 4
    units_row: list[str] = []
    if first_data < len(rows) and rows[first_data] and not rows[first_data][0].strip():
        units_row = rows[first_data]  # ",,mm,mm,mm": the units line (absent in old exports)
        first_data += 1

    columns: list[tuple[str, int]] = []
    for c, cell in enumerate(names_row):
        name = cell.strip()
        if not name:
            continue
        axes = [a.strip().upper() for a in axes_row[c : c + 3]]
        if axes != ["X", "Y", "Z"]:
            raise InputError(f"{p}: line {start + 4}: marker {name!r} is not followed by X, Y, Z columns")
        columns.append((name, c))
    if not columns:
        raise InputError(f"{p}: the Nexus Trajectories section names no marker")

    units = {u.strip() for c in columns for u in units_row[c[1] : c[1] + 3] if u.strip()} if units_row else set()
    metadata: dict = {"format": "nexus-csv", "sections": list(dict.fromkeys(titles.values()))}
    if length_unit_m is not None:
        scale_m, metadata["length_unit_from"] = float(length_unit_m), "override"
    elif len(units) == 1:
        unit = units.pop()
        scale_m, metadata["length_unit_from"] = unit_of(unit, str(p)), f"Nexus units line = {unit}"
    elif units:
        raise InputError(f"{p}: the Nexus markers are in different units ({', '.join(sorted(units))})")
    else:
        scale_m, metadata["length_unit_from"] = 0.001, "mm (no units line; the Nexus default)"
    metadata["length_unit_m"] = scale_m

    data = []
    for number in range(first_data, len(rows)):
        cells = rows[number]
        if not any(c.strip() for c in cells) or cells[0].strip() in SECTIONS:
            break  # the blank line that ends the section
        cells = cells + [""] * (len(axes_row) - len(cells))  # Nexus drops trailing empty cells
        picked = [cells[0]] + [cells[c + k] for _, c in columns for k in range(3)]
        data.append(number_row(picked, p, number + 1))
    if not data:
        raise InputError(f"{p}: the Nexus Trajectories section holds no frames")
    table = np.asarray(data, dtype=float)

    rate = float(rate_hz) if rate_hz is not None else file_rate
    if not rate or rate <= 0:
        raise InputError(f"{p}: the Nexus Trajectories section gives no rate on its second line; pass --rate-hz")
    frames = table[:, 0]
    if not np.all(np.isfinite(frames)):
        raise InputError(f"{p}: the Nexus Frame column has empty cells")
    positions = table[:, 1:].reshape(len(data), len(columns), 3) * scale_m
    return Recording(
        positions_m=positions,
        point_names=[name for name, _ in columns],
        time_s=(frames - frames[0]) / rate,
        rate_hz=rate,
        up_axis=None,
        source=str(p),
        metadata=metadata,
    )


def _float(text: str) -> float | None:
    try:
        return float(text)
    except (TypeError, ValueError):
        return None
