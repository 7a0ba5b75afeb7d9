"""Qualisys Track Manager (QTM) 3D TSV exports.

Layout (tab-separated; QTM 2.x and later)::

    NO_OF_FRAMES    1000
    NO_OF_CAMERAS   8
    NO_OF_MARKERS   3
    FREQUENCY       100
    NO_OF_ANALOG    0
    ANALOG_FREQUENCY    0
    DESCRIPTION     --
    TIME_STAMP      2019-11-28, 13:43:42.715    1476252.895
    DATA_INCLUDED   3D
    MARKER_NAMES    LASI    RASI    SACR
    TRAJECTORY_TYPES    Measured    Measured    Gap-filled
    Frame   Time    LASI X  LASI Y  LASI Z  RASI X  ...
    1       0.00000 512.100 1033.000 941.200 ...

Positions are millimetres (QTM's TSV unit).  Older exports have no
``Frame  Time`` row: the data rows then hold X, Y, Z per marker only, and
time comes from ``FREQUENCY``.  QTM writes a marker it did not see as
0, 0, 0 (or leaves the cells empty): both become missing.  A 6DOF or
skeleton TSV (``DATA_INCLUDED 6D``, ``BODY_NAMES``) holds rigid bodies, not
markers, and is refused with a message that says so.  QTM's up axis is a
project setting the file does not state; Z, QTM's default, is used unless the
body clearly says another axis (:func:`yoyogait.io.body.check_declared_up_axis`).
"""

from __future__ import annotations

import numpy as np

from ..errors import InputError
from .recording import Recording, number_row, positive_float, read_text, uniform_time, unique_names

__all__ = ["read_qtm_tsv"]


def read_qtm_tsv(path, *, length_unit_m: float | None = None, rate_hz: float | None = None) -> Recording:
    """Read the marker trajectories of a QTM 3D TSV export."""
    p, text = read_text(path, encoding="utf-8-sig")
    lines = text.splitlines()
    header: dict[str, list[str]] = {}
    first_data = None
    for number, line in enumerate(lines):
        cells = line.rstrip("\r\n").split("\t")
        key = cells[0].strip()
        if key and key.replace("_", "").isalpha() and key.isupper():
            header[key] = [c.strip() for c in cells[1:]]
            continue
        first_data = number
        break
    if "MARKER_NAMES" not in header:
        if "BODY_NAMES" in header or header.get("DATA_INCLUDED", [""])[0].upper() == "6D":
            raise InputError(f"{p}: QTM 6DOF TSV export (rigid bodies, no markers); export the 3D data instead")
        if "NO_OF_FRAMES" in header:
            included = " ".join(header.get("DATA_INCLUDED", [])).strip()
            if included and included.upper() != "3D":
                raise InputError(
                    f"{p}: QTM TSV export of {included} data (DATA_INCLUDED {included}), no marker positions; "
                    "export the 3D data instead"
                )
            raise InputError(f"{p}: QTM TSV export without a MARKER_NAMES line (skeleton or analog data?)")
        raise InputError(f"{p}: not a QTM TSV export (it must start with NO_OF_FRAMES ... MARKER_NAMES lines)")
    names = [n for n in header["MARKER_NAMES"] if n]
    if not names:
        raise InputError(f"{p}: the QTM MARKER_NAMES line names no marker")
    if first_data is None:
        raise InputError(f"{p}: the QTM TSV export holds no frames")

    columns = lines[first_data].split("\t")
    has_frame_time = columns[0].strip().lower() == "frame"
    if has_frame_time:
        first_data += 1
        if len(columns) < 2 + 3 * len(names):
            raise InputError(
                f"{p}: line {first_data}: {len(columns)} columns for {len(names)} markers (Frame, Time, X Y Z each)"
            )
    offset = 2 if has_frame_time else 0
    n_columns = offset + 3 * len(names)

    rows = []
    for number, line in enumerate(lines[first_data:], start=first_data + 1):
        if not line.strip():
            continue
        cells = line.split("\t")
        if len(cells) > n_columns and any(c.strip() for c in cells[n_columns:]):
            raise InputError(f"{p}: line {number} holds {len(cells)} columns, MARKER_NAMES gives {n_columns}")
        cells = cells[:n_columns] + [""] * (n_columns - len(cells))
        rows.append(number_row(cells, p, number))
    if not rows:
        raise InputError(f"{p}: the QTM TSV export holds no frames")
    table = np.asarray(rows, dtype=float)
    announced = positive_float(header.get("NO_OF_FRAMES", [""])[0])
    if announced is not None and len(rows) < announced:
        raise InputError(f"{p}: truncated QTM TSV: NO_OF_FRAMES announces {int(announced)}, the file holds {len(rows)}")

    metadata: dict = {"format": "qtm-tsv", "header": header}
    if length_unit_m is not None:
        scale_m, metadata["length_unit_from"] = float(length_unit_m), "override"
    else:
        scale_m, metadata["length_unit_from"] = 0.001, "mm (the unit of every QTM TSV export)"
    metadata["length_unit_m"] = scale_m
    metadata["up_axis_declared"], metadata["up_axis_declared_by"] = "z", "the Qualisys convention (Z up)"

    positions = table[:, offset:].reshape(len(rows), len(names), 3)
    positions[np.all(positions == 0.0, axis=2)] = np.nan  # QTM's "not seen"
    file_rate = positive_float(header.get("FREQUENCY", [""])[0])
    rate = float(rate_hz) if rate_hz is not None else file_rate
    if has_frame_time and rate_hz is None and np.all(np.isfinite(table[:, 1])):
        time_s = table[:, 1]
        if rate and np.max(np.abs(time_s - uniform_time(len(rows), rate, time_s[0]))) < 0.1 / rate:
            time_s = uniform_time(len(rows), rate, time_s[0])  # QTM rounds its times to 10 us
    elif rate:
        time_s = uniform_time(len(rows), rate)
    else:
        raise InputError(f"{p}: the QTM TSV has neither a Time column nor a FREQUENCY; pass --capture-rate-hz")
    return Recording(
        positions_m=positions * scale_m,
        point_names=unique_names(names),
        time_s=time_s,
        rate_hz=rate,
        up_axis=None,
        source=str(p),
        metadata=metadata,
    )
