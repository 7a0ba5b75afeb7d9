"""TRC marker files (OpenSim, AddBiomechanics, Motion Analysis Cortex exports).

Layout (tab-separated; some tools, e.g. pyomeca, write commas instead)::

    PathFileType  4  (X/Y/Z)  name.trc
    DataRate  CameraRate  NumFrames  NumMarkers  Units  OrigDataRate ...
    100       100         238        41          mm     100 ...
    Frame#  Time  R.ASIS      L.ASIS ...
                  X1  Y1  Z1  X2  Y2  Z2 ...
    <blank line, optional>
    1       0.00  ...

The length unit comes from the ``Units`` header field (``length_unit_m=``
overrides); an empty cell is a missing sample (NaN).  TRC files carry no up
axis (OpenSim's convention is Y up, but the file does not say it), so it is
left to detection.  A file with fewer data rows than ``NumFrames`` is
reported as truncated.
"""

from __future__ import annotations

import numpy as np

from ..errors import InputError
from .recording import Recording, check_coordinates, check_rate, check_time, number_row, read_text, uniform_time
from .recording import length_unit_m as unit_of

__all__ = ["read_trc"]


def read_trc(path, *, length_unit_m: float | None = None, rate_hz: float | None = None) -> Recording:
    """Read the markers of a TRC file."""
    p, text = read_text(path)
    lines = text.splitlines()
    if len(lines) < 5 or not lines[0].startswith("PathFileType"):
        raise InputError(f"{p}: not a TRC file (it must start with a PathFileType line and a 5-line header)")

    separator = "\t" if "\t" in lines[0] else "," if "," in lines[0] else None
    keys = [c.strip() for c in _cells(lines[1], separator) if c.strip()]
    values = [c.strip() for c in _cells(lines[2], separator) if c.strip()]
    if len(values) < len(keys) or "DataRate" not in keys:
        raise InputError(f"{p}: corrupt TRC header: line 3 does not give a value for each field of line 2")
    header = dict(zip(keys, values))

    name_cells = [c.strip() for c in _cells(lines[3], separator)]
    if len(name_cells) < 3 or not name_cells[0].lower().startswith("frame"):
        raise InputError(f"{p}: corrupt TRC header: line 4 must be 'Frame#  Time  <marker names>'")
    names = [c for c in name_cells[2:] if c]
    if not names:
        raise InputError(f"{p}: the TRC file names no marker")
    n_columns = 2 + 3 * len(names)

    rows = []
    line_numbers = []
    for number, line in enumerate(lines[5:], start=6):
        cells = _cells(line, separator)
        if not any(c.strip() for c in cells):  # a blank line (",,,," in a comma-separated file)
            continue
        if len(cells) > n_columns and any(c.strip() for c in cells[n_columns:]):
            raise InputError(f"{p}: line {number} holds {len(cells)} columns, the header names {n_columns}")
        cells = cells[:n_columns] + [""] * (n_columns - len(cells))
        rows.append(number_row(cells, p, number))
        line_numbers.append(number)
    if not rows:
        raise InputError(f"{p}: the TRC file holds no frames")
    table = np.asarray(rows, dtype=float)

    announced = _int(header.get("NumFrames"))
    if announced is not None and len(rows) < announced:
        raise InputError(
            f"{p}: truncated TRC file: the header announces {announced} frames, the file holds {len(rows)} "
            "(if those rows are all there is, set NumFrames to that number)"
        )
    if not text.endswith("\n") and len(_cells(lines[-1], separator)) < n_columns:
        raise InputError(f"{p}: truncated TRC file: the last line stops in the middle of a frame")

    metadata: dict = {"format": "trc", "header": header, "separator": separator or "whitespace"}
    if length_unit_m is not None:
        scale_m = float(length_unit_m)
        metadata["length_unit_from"] = "override"
    elif "Units" in header:
        scale_m = unit_of(header["Units"], str(p))
        metadata["length_unit_from"] = f"Units = {header['Units']}"
    else:
        raise InputError(f"{p}: the TRC header gives no Units; pass length_unit_m=")
    metadata["length_unit_m"] = scale_m

    file_rate = _float(header.get("DataRate"))
    rate = float(rate_hz) if rate_hz is not None else file_rate
    time_s = table[:, 1]
    if rate_hz is not None or not np.all(np.isfinite(time_s)):
        if not rate or rate <= 0:
            raise InputError(f"{p}: the TRC file has neither times nor a DataRate; pass capture_rate_hz=")
        rate = check_rate(rate, p, "capture_rate_hz override" if rate_hz is not None else "DataRate")
        time_s = uniform_time(len(rows), rate, 0.0 if not np.isfinite(time_s[0]) else time_s[0])
    else:
        check_time(time_s, p, line_numbers)
    if rate is not None and rate > 0:
        rate = check_rate(rate, p, "capture_rate_hz override" if rate_hz is not None else "DataRate")

    positions = table[:, 2:].reshape(len(rows), len(names), 3) * scale_m
    check_coordinates(positions, names, p, line_numbers)
    return Recording(
        positions_m=positions,
        point_names=names,
        time_s=time_s,
        rate_hz=rate if rate and rate > 0 else None,
        up_axis=None,
        source=str(p),
        metadata=metadata,
    )


def _cells(line: str, separator: str | None) -> list[str]:
    # TRC is tab-separated (or comma-separated), and an empty cell between two separators is a
    # missing value; only a file whose first line has neither falls back to whitespace.
    if separator is None or separator not in line:
        return line.split("\t") if "\t" in line else line.split()
    return line.split(separator)


def _float(text) -> float | None:
    try:
        return float(text)
    except (TypeError, ValueError):
        return None


def _int(text) -> int | None:
    value = _float(text)
    return int(value) if value is not None and value >= 0 else None
