"""Vicon Nexus CSV exports: every section, in the order Nexus writes them.

A Nexus export is a run of sections, each opened by its title on a line of
its own and closed by a blank line; the file may start with blank or
comma-only lines, and the sections come in any order::

    ,,,,                                  <- (some exports start with blank or comma-only lines)
    Events                                <- title
    Subject,Context,Name,Time (s),Description
    S08,Left,Foot Strike,1.23,The instant the heel strikes the ground
    <blank>
    Gait Cycle Parameters
    Subject,Context,Name,Value,Units
    S08,Left,Cadence,112.5,steps/min
    <blank>
    Devices                               <- analog data (force plates, EMG): not read
    1000
    ...
    Trajectories
    100                                   <- capture rate, Hz
    ,,S08:LASI,,,S08:RASI,,,| S08:LASI |  <- Subject:Marker over the X column of each marker
    Frame,Sub Frame,X,Y,Z,X,Y,Z,Magnitude <- (X', X'' ... for velocities; a "| name |" column is a magnitude)
    ,,mm,mm,mm,mm,mm,mm,mm                <- units of this section
    1,0,667.12,305.799,175.209,...        <- an empty cell is a gap

The marker positions come from the ``Trajectories`` section (X, Y, Z
columns; velocity, acceleration and magnitude columns are left out), in the
unit of its own units line.  ``Devices``, ``Model Outputs``, ``Joints`` and
``Segments`` hold analog data or model outputs, not marker positions; a
file with no Trajectories section is refused with a message naming what it
holds.  The ``Events`` section (foot strikes and foot offs, with their side
and time) goes to ``metadata["events"]`` as ``(side, name, time_s)``, the
``Gait Cycle Parameters`` to ``metadata["gait_cycle_parameters"]``; the
evaluation uses the foot strikes as its reference when they are there.

With the markers of several people (``Anna:LASI``, ``Ben:LASI``: subjects
with pelvis markers), one is read: ``subject=``, else the first named;
``metadata["subjects"]`` lists them all.  Objects (a subject without pelvis
markers, such as a box) stay beside the person.  Nexus states no up axis; Vicon
labs are Z up, which is used unless the body clearly says another axis
(:func:`yoyogait.io.body.check_declared_up_axis`).
"""

from __future__ import annotations

import csv as _csv
import re

import numpy as np

from ..errors import InputError
from .marker_sets import pelvis_names
from .recording import Recording, gait_event, number_row, read_text
from .recording import length_unit_m as unit_of

__all__ = ["read_nexus_csv", "is_nexus_csv", "SECTIONS", "nexus_sections"]

#: Section titles a Nexus CSV export may hold.
SECTIONS = (
    "Trajectories",
    "Devices",
    "Model Outputs",
    "Joints",
    "Segments",
    "Events",
    "Gait Cycle Parameters",
    "Subjects",
)
_MAGNITUDE = re.compile(r"^\|.*\|$")


def is_nexus_csv(first_line: str) -> bool:
    """True if a CSV's first line with content is a Nexus section title (``Trajectories,,,``)."""
    cells = [c.strip().strip('"') for c in first_line.split(",")]
    return bool(cells) and cells[0] in SECTIONS and not any(cells[1:])


def _is_title(row: list[str]) -> bool:
    return bool(row) and row[0].strip().strip('"') in SECTIONS and not any(c.strip() for c in row[1:])


def _is_blank(row: list[str]) -> bool:
    return not any(c.strip() for c in row)


def nexus_sections(rows: list[list[str]]) -> dict[str, tuple[int, int]]:
    """Section title -> (first row after the title, row after its last row), for the first of each title.

    A section runs to the next title; the blank lines inside it (Nexus ends
    every section with one, and some exports separate header and data by
    one) are kept for the section's own reader to skip or stop at.
    """
    starts = [(i, r[0].strip().strip('"')) for i, r in enumerate(rows) if _is_title(r)]
    out: dict[str, tuple[int, int]] = {}
    for k, (i, title) in enumerate(starts):
        end = starts[k + 1][0] if k + 1 < len(starts) else len(rows)
        out.setdefault(title, (i + 1, end))
    return out


def read_nexus_csv(
    path, *, length_unit_m: float | None = None, rate_hz: float | None = None, subject: str | None = None
) -> Recording:
    """Read the marker trajectories (and the events) of a Vicon Nexus CSV export."""
    p, text = read_text(path, encoding="utf-8-sig")
    rows = list(_csv.reader(text.splitlines()))
    sections = nexus_sections(rows)
    if "Trajectories" not in sections:
        held = ", ".join(sections) or "no section"
        raise InputError(
            f"{p}: Vicon Nexus CSV export with {held} but no Trajectories section (no marker positions); "
            "export the trial again with Trajectories ticked, or export a C3D"
        )
    start, end = sections["Trajectories"]
    header = [i for i in range(start, end) if not _is_blank(rows[i])]
    if len(header) < 3:
        raise InputError(f"{p}: the Nexus Trajectories section stops inside its header (rate, names, Frame)")
    rate_line, names_line, axes_line = header[:3]
    file_rate = _float(rows[rate_line][0])
    names_row, axes_row = rows[names_line], rows[axes_line]
    if not axes_row or axes_row[0].strip().lower() != "frame":
        raise InputError(
            f"{p}: line {axes_line + 1}: the Nexus Trajectories header must be 'Frame,Sub Frame,X,Y,Z,...', "
            f"not {','.join(axes_row[:5])!r}"
        )
    first_data = axes_line + 1
    units_row: list[str] = []
    if first_data < end and rows[first_data] and not rows[first_data][0].strip() and not _is_blank(rows[first_data]):
        units_row = rows[first_data]  # ",,mm,mm,mm": the units line (absent in old exports)
        first_data += 1
    while first_data < end and _is_blank(rows[first_data]):
        first_data += 1  # a blank line between the header and the data

    columns, skipped = _marker_columns(names_row, axes_row, p, axes_line + 1)
    subjects = list(dict.fromkeys(n.split(":", 1)[0] for n, _ in columns if ":" in n))
    metadata: dict = {"format": "nexus-csv", "sections": list(sections)}
    people = [s for s in subjects if _has_pelvis([n for n, _ in columns if n.startswith(s + ":")])]
    if len(people) > 1 or subject is not None:
        chosen = subject if subject is not None else people[0]
        if chosen not in subjects:
            raise InputError(
                f"{p}: no subject {chosen!r} in the Nexus Trajectories; subjects: {', '.join(subjects) or '(none)'}"
            )
        others = set(people if chosen in people else subjects) - {chosen}
        columns = [(n, c) for n, c in columns if n.split(":", 1)[0] not in others]  # objects stay
        metadata["subjects"], metadata["subject"] = subjects, chosen
    if skipped:
        metadata["columns_left_out"] = skipped
    if not columns:
        raise InputError(f"{p}: the Nexus Trajectories section names no marker with X, Y, Z columns")

    units = {u.strip() for _, c in columns for u in units_row[c : c + 3] if u.strip()} if units_row else set()
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
    metadata["up_axis_declared"], metadata["up_axis_declared_by"] = "z", "the Vicon convention (Z up)"

    data, line_numbers = [], []
    width = max(len(axes_row), max(c for _, c in columns) + 3)
    for number in range(first_data, end):
        cells = rows[number]
        if _is_blank(cells):
            break  # the blank line that ends the section
        cells = cells + [""] * (width - len(cells))  # Nexus drops trailing empty cells
        picked = [cells[0]] + [cells[c + k] for _, c in columns for k in range(3)]
        data.append(number_row(picked, p, number + 1))
        line_numbers.append(number + 1)
    if not data:
        raise InputError(f"{p}: the Nexus Trajectories section holds no frames")
    table = np.asarray(data, dtype=float)

    rate = float(rate_hz) if rate_hz is not None else file_rate
    if not rate or rate <= 0:
        raise InputError(
            f"{p}: line {rate_line + 1}: the Nexus Trajectories section gives no rate after its title; "
            "pass --capture-rate-hz"
        )
    frames = table[:, 0]
    if not np.all(np.isfinite(frames)):
        raise InputError(f"{p}: the Nexus Frame column has empty cells")
    if "Events" in sections:
        events = _events(rows, sections["Events"], p, metadata.get("subject"))
        if events:
            # Nexus event times are in seconds from the trial's first frame (frame 1); shift to this time axis.
            offset_s = (frames[0] - 1.0) / rate
            metadata["events"] = [(side, name, t - offset_s) for side, name, t in events]
    if "Gait Cycle Parameters" in sections:
        params = _parameters(rows, sections["Gait Cycle Parameters"], metadata.get("subject"))
        if params:
            metadata["gait_cycle_parameters"] = params
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


def _marker_columns(names_row, axes_row, p, line: int) -> tuple[list[tuple[str, int]], list[str]]:
    """(name, column of X) of each marker with X, Y, Z columns; the names of the other columns, left out."""
    columns: list[tuple[str, int]] = []
    skipped: list[str] = []
    for c, cell in enumerate(names_row):
        name = cell.strip()
        if not name or c < 2:
            continue
        axes = [a.strip().upper() for a in axes_row[c : c + 3]]
        if _MAGNITUDE.match(name) or axes != ["X", "Y", "Z"]:
            skipped.append(name)  # a magnitude, or a marker exported as velocity or acceleration only
            continue
        columns.append((name, c))
    if not columns and skipped:
        raise InputError(f"{p}: line {line}: no Nexus Trajectories column is an X, Y, Z position ({skipped[0]!r}, ...)")
    return columns, skipped


def _has_pelvis(names: list[str]) -> bool:
    return pelvis_names(names)[1] == "pelvis markers"


def _header_index(header: list[str], *names: str) -> int | None:
    low = [h.strip().lower() for h in header]
    for n in names:
        for i, h in enumerate(low):
            if h.startswith(n):
                return i
    return None


def _events(rows, span: tuple[int, int], p, subject: str | None) -> list[tuple[str, str, float]]:
    """(side, event name, time_s) of the Events section, of ``subject`` when the file names several."""
    start, end = span
    body = [rows[i] for i in range(start, end) if not _is_blank(rows[i])]
    if not body:
        return []
    header = body[0]
    i_subject, i_side = _header_index(header, "subject"), _header_index(header, "context")
    i_name, i_time = _header_index(header, "name"), _header_index(header, "time")
    if i_name is None or i_time is None or i_side is None:
        return []
    out = []
    for r in body[1:]:
        r = r + [""] * (len(header) - len(r))
        if subject is not None and i_subject is not None and r[i_subject].strip() not in ("", subject):
            continue
        t = _float(r[i_time])
        if t is None or not np.isfinite(t):
            continue
        side, kind = gait_event(r[i_name].strip(), r[i_side].strip())
        out.append((side, kind, t))
    return sorted(out, key=lambda e: e[2])


def _parameters(rows, span: tuple[int, int], subject: str | None) -> list[tuple[str, str, float, str]]:
    """(side, name, value, unit) of the Gait Cycle Parameters section."""
    start, end = span
    body = [rows[i] for i in range(start, end) if not _is_blank(rows[i])]
    if not body:
        return []
    header = body[0]
    i_subject, i_side = _header_index(header, "subject"), _header_index(header, "context")
    i_name, i_value = _header_index(header, "name"), _header_index(header, "value")
    i_unit = _header_index(header, "unit")
    if i_name is None or i_value is None:
        return []
    out = []
    for r in body[1:]:
        r = r + [""] * (len(header) - len(r))
        if subject is not None and i_subject is not None and r[i_subject].strip() not in ("", subject):
            continue
        v = _float(r[i_value])
        if v is None:
            continue
        side = r[i_side].strip().lower() if i_side is not None else ""
        unit = r[i_unit].strip() if i_unit is not None else ""
        out.append((side, r[i_name].strip(), v, unit))
    return out


def _float(text: str) -> float | None:
    try:
        return float(text)
    except (TypeError, ValueError):
        return None
