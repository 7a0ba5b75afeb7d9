"""Marker tables: text with a ``Time`` column and three columns per marker.

The layout of the public walking and running data sets of Fukuchi et al.
(2018, overground and treadmill walking, files ``WBDS01walkT01mkr.txt``;
2017, running, ``RBDS001runT25markers.txt``) and of their lab's teaching
data, exported from Cortex::

    Time    R.ASISX  R.ASISY  R.ASISZ  L.ASISX  ...    <- one header line: the marker name + X, Y or Z
    0.00    1234.56  789.01   234.56   ...             <- time in seconds, positions in mm
    0.01    1235.67  790.12   235.67   ...             <- an empty cell or NaN is a gap

Tabs or commas; the suffix in either case, after ``_`` or ``.`` or not
(``R.ASISX``, ``FHx``, ``COG_X``).  Columns that are not a marker's X, Y
and Z (force-plate channels ``Fx``, ``COPx``, ``My`` beside the markers)
are left out and listed in ``metadata["columns_left_out"]``.

The file states no unit: millimetres, the data sets' unit, unless the
body's size says metres or centimetres (a body about a metre across reads
1000 in mm, 1 in m: ``metadata["length_unit_from"]`` says which was
taken; ``--length-unit-m`` overrides).  The data sets' laboratory frame has
Y vertical (X forward, Z to the right), which the reader declares as the
file's up axis; the body's geometry is checked against it
(:func:`yoyogait.io.body.check_declared_up_axis`).  A ``Time`` column that
counts frames (1, 2, 3 ...) needs the rate: ``--capture-rate-hz``.
"""

from __future__ import annotations

import re
import warnings

import numpy as np

from ..errors import InputError
from .recording import Recording, check_rate, number_row, read_text

__all__ = ["read_marker_table", "is_marker_table"]

#: The up axis of the data sets' laboratory frame, declared by convention (not stated in the file).
CONVENTION_UP_AXIS = "y"


_SUFFIX = re.compile(r"^(?P<name>.+?)[_.]?(?P<axis>[XYZxyz])$")
#: Force-plate channels that come in X, Y, Z triples too, but are not positions.
_NOT_POSITIONS = re.compile(r"^(f|cop|m|t|force|moment|grf)\d*$", re.IGNORECASE)
_TIME = ("time", "time (s)", "time(s)", "time_s", "t", "frame")


def _split(line: str, sep: str) -> list[str]:
    return [c.strip() for c in line.rstrip("\r\n").split(sep)]


def _separator(first: str) -> str | None:
    return "\t" if "\t" in first else "," if "," in first else None


def _markers(header: list[str]) -> tuple[list[tuple[str, int]], list[str]] | None:
    """(marker name, column of X) for a header ``Time, aX, aY, aZ, bX, ...`` and the columns left out;
    None if it is not one (no Time first, or not a single marker)."""
    if not header or header[0].lower() not in _TIME:
        return None
    cells = list(header[1:])
    while cells and not cells[-1]:
        cells.pop()  # a trailing separator
    out: list[tuple[str, int]] = []
    left: list[str] = []
    k = 0
    while k < len(cells):
        triple = [_SUFFIX.match(c) for c in cells[k : k + 3]]
        if (
            len(triple) == 3
            and all(triple)
            and len({m.group("name") for m in triple if m}) == 1
            and "".join(m.group("axis").lower() for m in triple if m) == "xyz"
        ):
            name = triple[0].group("name") if triple[0] else ""
            if _NOT_POSITIONS.match(name):
                left.append(name)
            else:
                out.append((name, 1 + k))
            k += 3
        else:
            left.append(cells[k])
            k += 1
    return (out, left) if out else None


def is_marker_table(head: str) -> bool:
    """True if a text file starts with a ``Time, NameX, NameY, NameZ, ...`` header (tabs or commas)."""
    first = head.lstrip("\ufeff").split("\n", 1)[0]
    sep = _separator(first)
    return sep is not None and _markers(_split(first, sep)) is not None


def read_marker_table(path, *, length_unit_m: float | None = None, rate_hz: float | None = None) -> Recording:
    """Read a tab-separated marker table (Fukuchi et al. data sets' layout)."""
    p, text = read_text(path, encoding="utf-8-sig")
    lines = text.splitlines()
    sep = _separator(lines[0]) if lines else None
    header = _split(lines[0], sep) if sep else []
    found = _markers(header)
    if found is None or sep is None:
        raise InputError(f"{p}: line 1 is not a marker-table header (Time, then NameX, NameY, NameZ per marker)")
    markers, left_out = found
    data, numbers = [], []
    for i, line in enumerate(lines[1:], start=2):
        if not line.strip():
            continue
        cells = _split(line, sep)
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
        raise InputError(
            f"{p}: the {header[0]} column counts frames (1, 2, 3 ...) and gives no rate; pass --capture-rate-hz"
        )
    else:
        if len(step) == 0 or not np.all(step > 0):
            raise InputError(f"{p}: the Time column does not increase")
        rate = check_rate(1.0 / float(np.median(step)), p, "rate from the Time column")
        time_s = time - time[0]
    cols = [c + k for _, c in markers for k in range(3)]
    raw = table[:, cols].reshape(len(data), len(markers), 3)
    if length_unit_m is not None:
        scale_m, metadata["length_unit_from"] = float(length_unit_m), "override"
    else:
        scale_m, metadata["length_unit_from"] = _unit_from_size(raw)
    metadata["length_unit_m"] = scale_m
    if left_out:
        metadata["columns_left_out"] = left_out
    metadata["up_axis_declared"] = CONVENTION_UP_AXIS
    metadata["up_axis_declared_by"] = "the marker tables' laboratory frame (Y vertical)"
    positions = raw * scale_m
    return Recording(
        positions_m=positions,
        point_names=[n for n, _ in markers],
        time_s=time_s,
        rate_hz=round(rate, 6),
        up_axis=None,
        source=str(p),
        metadata=metadata,
    )


def _unit_from_size(raw: np.ndarray) -> tuple[float, str]:
    """Metres per file unit from the body's size: mm (the data sets' unit) unless the points span about
    a metre as metres or centimetres would have it."""
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", RuntimeWarning)
        if raw.shape[1] > 1:
            extent = np.nanmax(np.nanmax(raw, axis=1) - np.nanmin(raw, axis=1), axis=1)
        else:  # one point: how far it goes over the recording
            extent = np.atleast_1d(np.nanmax(np.nanmax(raw[:, 0], axis=0) - np.nanmin(raw[:, 0], axis=0)))
        size = float(np.nanmedian(extent))
    if not np.isfinite(size) or size <= 0:
        return 0.001, "mm (the marker tables' unit)"
    best = min((1.0, 0.01, 0.001), key=lambda u: abs(np.log(size * u / 1.0)))
    if best == 0.001:
        return 0.001, "mm (the marker tables' unit)"
    name = "m" if best == 1.0 else "cm"
    return best, f"{name} (no unit in the file; the points span {size:.3g}, a body's size in {name})"
