"""Marker tables: tab-separated text with a ``Time`` column and three columns per marker.

The layout of the public walking and running data sets of Fukuchi et al.
(2018, overground and treadmill walking, files ``WBDS01walkT01mkr.txt``;
2017, running, ``RBDS001runT25markers.txt``), exported from Cortex::

    Time    R.ASISX  R.ASISY  R.ASISZ  L.ASISX  ...    <- one header line: the marker name + X, Y or Z
    0.00    1234.56  789.01   234.56   ...             <- time in seconds, positions in mm
    0.01    1235.67  790.12   235.67   ...             <- an empty cell or NaN is a gap

The length unit is millimetres (the data sets' documentation; the
plausibility check of :func:`yoyogait.io.read` names ``--length-unit-m``
when the body's size says otherwise).  The data sets' laboratory frame has
Y vertical (X forward, Z to the right), which the reader declares as the
file's up axis; the body's geometry is checked against it
(:func:`yoyogait.io.body.check_declared_up_axis`).  A ``Time`` column that
counts frames (1, 2, 3 ...) needs the rate: ``--rate-hz``.
"""

from __future__ import annotations

import numpy as np

from ..errors import InputError
from .recording import Recording, check_rate, number_row, read_text

__all__ = ["read_marker_table", "is_marker_table"]

#: The up axis of the data sets' laboratory frame, declared by convention (not stated in the file).
CONVENTION_UP_AXIS = "y"


def _split(line: str) -> list[str]:
    return [c.strip() for c in line.rstrip("\r\n").split("\t")]


def _markers(header: list[str]) -> list[tuple[str, int]] | None:
    """(marker name, column of X) for a header ``Time, aX, aY, aZ, bX, ...``; None if it is not one."""
    if not header or header[0].lower() not in ("time", "time (s)", "frame"):
        return None
    cells = [c for c in header[1:]]
    while cells and not cells[-1]:
        cells.pop()  # a trailing tab
    if len(cells) < 3 or len(cells) % 3:
        return None
    out = []
    for k in range(0, len(cells), 3):
        x, y, z = cells[k : k + 3]
        name = x[:-1]
        if not name or (x[-1:].upper(), y[-1:].upper(), z[-1:].upper()) != ("X", "Y", "Z"):
            return None
        if y[:-1] != name or z[:-1] != name:
            return None
        out.append((name, 1 + k))
    return out


def is_marker_table(head: str) -> bool:
    """True if a text file starts with a tab-separated ``Time, NameX, NameY, NameZ, ...`` header."""
    first = head.lstrip("\ufeff").split("\n", 1)[0]
    return "\t" in first and _markers(_split(first)) is not None


def read_marker_table(path, *, length_unit_m: float | None = None, rate_hz: float | None = None) -> Recording:
    """Read a tab-separated marker table (Fukuchi et al. data sets' layout)."""
    p, text = read_text(path, encoding="utf-8-sig")
    lines = text.splitlines()
    header = _split(lines[0]) if lines else []
    markers = _markers(header)
    if markers is None:
        raise InputError(f"{p}: line 1 is not a marker-table header (Time, then NameX, NameY, NameZ per marker)")
    data, numbers = [], []
    for i, line in enumerate(lines[1:], start=2):
        if not line.strip():
            continue
        cells = _split(line)
        cells = cells + [""] * (len(header) - len(cells))
        cells = ["" if c.lower() == "nan" else c for c in cells[: len(header)]]
        data.append(number_row(cells, p, i))
        numbers.append(i)
    if not data:
        raise InputError(f"{p}: the marker table holds no frames")
    table = np.asarray(data, dtype=float)
    time = table[:, 0]
    if not np.all(np.isfinite(time)):
        raise InputError(f"{p}: line {numbers[int(np.argmax(~np.isfinite(time)))]}: the Time column has an empty cell")
    step = np.diff(time)
    counts_frames = header[0].lower() == "frame" or (
        len(step) > 0 and np.allclose(step, 1.0) and np.allclose(time, np.round(time))
    )
    metadata: dict = {"format": "marker-table"}
    if rate_hz is not None:
        rate = float(rate_hz)
        time_s = (time - time[0]) / rate if counts_frames else time - time[0]
    elif counts_frames:
        raise InputError(f"{p}: the {header[0]} column counts frames (1, 2, 3 ...) and gives no rate; pass --rate-hz")
    else:
        if len(step) == 0 or not np.all(step > 0):
            raise InputError(f"{p}: the Time column does not increase")
        rate = check_rate(1.0 / float(np.median(step)), p, "rate from the Time column")
        time_s = time - time[0]
    if length_unit_m is not None:
        scale_m, metadata["length_unit_from"] = float(length_unit_m), "override"
    else:
        scale_m, metadata["length_unit_from"] = 0.001, "mm (the marker tables' unit)"
    metadata["length_unit_m"] = scale_m
    metadata["up_axis_declared"] = CONVENTION_UP_AXIS
    metadata["up_axis_declared_by"] = "the marker tables' laboratory frame (Y vertical)"
    cols = [c + k for _, c in markers for k in range(3)]
    positions = table[:, cols].reshape(len(data), len(markers), 3) * scale_m
    return Recording(
        positions_m=positions,
        point_names=[n for n, _ in markers],
        time_s=time_s,
        rate_hz=round(rate, 6),
        up_axis=None,
        source=str(p),
        metadata=metadata,
    )
