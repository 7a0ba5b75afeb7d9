"""Xsens exports: MT Manager / Awinda ``.txt`` and Movella DOT ``.csv`` (docs/imu.md, section 4)."""

from __future__ import annotations

import re
from pathlib import Path

import numpy as np

from ..errors import InputError
from .imu_checks import ACC_UNITS, GYR_UNITS, head_lines, median_rate_hz, reading, unit_scale
from .imu_recording import ImuRecording

__all__ = ["dot_layout", "read_dot", "read_dot_csv", "read_xsens_txt", "xsens_txt_header"]

#: The calibrated channels of Xsens exports (MT Manager and Movella DOT name them alike).
_XSENS_CHANNELS = ("Acc_X", "Acc_Y", "Acc_Z", "Gyr_X", "Gyr_Y", "Gyr_Z")


#: The rate in an export's preamble: MT Manager's ``// Update Rate: 100.0Hz``, or a line such as
#: ``Acquisition frequency: 100 Hz`` that other tools (and published data sets) write before the header.
_RATE_LINE = re.compile(r"(?:update rate|frequency|sampl\w* rate)\s*[:=]?\s*([0-9]+(?:\.[0-9]*)?)\s*hz", re.IGNORECASE)


def xsens_txt_header(path) -> int | None:
    """The line index of an Xsens text export's column header (the first line among the first 50 with a
    ``PacketCounter`` cell; any lines before it are its preamble), None without one."""
    lines = head_lines(path)
    return next((i for i, line in enumerate(lines) if "PacketCounter" in line.replace(",", " ").split()), None)


def read_xsens_txt(path, *, acc_unit=None, gyr_unit=None, rate_hz=None) -> ImuRecording:
    """An Xsens MT Manager / Awinda text export: a preamble (MT Manager's ``//`` comment lines with
    ``// Update Rate: 100.0Hz``, or other text such as ``Acquisition frequency: 100 Hz``), then a
    tab-separated header with ``PacketCounter``, ``Acc_X``..``Acc_Z``, ``Gyr_X``..``Gyr_Z`` (MT
    Manager's units: m/s^2 and rad/s unless ``acc_unit``/``gyr_unit`` say otherwise)."""
    p = Path(path)
    rate = float(rate_hz) if rate_hz else None
    first = xsens_txt_header(p)
    header: list[str] | None = None
    rows, lines = [], []  # the samples' cells and their line numbers (1-based, for a message)
    with open(p, encoding="utf-8-sig", errors="replace") as f:
        for i, line in enumerate(f):
            s = line.strip()
            if first is None or i < first:  # the preamble
                m = _RATE_LINE.search(s)
                if m and rate is None:
                    rate = float(m.group(1))
                continue
            if not s or s.startswith("//"):
                continue
            parts = s.split("\t") if "\t" in s else s.split()
            if header is None:
                header = [h.strip() for h in parts]
                continue
            rows.append(parts)
            lines.append(i + 1)
    if header is None or "PacketCounter" not in header:
        raise InputError(f"{p}: no PacketCounter header line: not an Xsens MT Manager export")
    need = list(_XSENS_CHANNELS)
    missing = [n for n in need if n not in header]
    if missing:
        raise InputError(f"{p}: the export lacks {', '.join(missing)} (export calibrated data)")
    if rate is None:
        raise InputError(
            f"{p}: no rate before the header (// Update Rate: 100Hz): give the sample rate with rate_hz "
            "(--capture-rate-hz)"
        )
    cols = [header.index(n) for n in ["PacketCounter", *need]]
    table = np.full((len(rows), len(cols)), np.nan)
    for k, r in enumerate(rows):
        for j, c in enumerate(cols):
            if c < len(r) and r[c] != "":
                try:
                    table[k, j] = float(r[c])
                except ValueError:
                    raise InputError(f"{p}: line {lines[k]}: {header[c]} {r[c]!r} is not a number") from None
    if table.shape[0] < 2:
        raise InputError(f"{p}: fewer than two samples")
    counter = np.unwrap(table[:, 0], period=65536.0)
    # The counter numbers packets: one that comes twice (a wireless retransmission; in published Awinda
    # recordings) is one sample, its later copy dropped. A counter going back is still refused.
    first_copy = np.concatenate([[True], np.diff(counter) != 0])
    metadata: dict = {"layout": "xsens"}
    if not first_copy.all():
        metadata["repeated_packets"] = int(np.count_nonzero(~first_copy))
        table, counter = table[first_copy], counter[first_copy]
    acc_scale = unit_scale(acc_unit, ACC_UNITS, "acc_unit", p) or 1.0
    gyr_scale = unit_scale(gyr_unit, GYR_UNITS, "gyr_unit", p) or 1.0
    time_s = (counter - counter[0]) / rate
    return reading(p, time_s, table[:, 1:4] * acc_scale, table[:, 4:7] * gyr_scale, rate, gyr_scale, metadata)


# ------------------------------------------------------------------------------------ Movella DOT

#: SampleTimeFine of a Movella DOT export: microseconds in an unsigned 32-bit counter.
_DOT_TICK_S = 1e-6
_DOT_WRAP = 2.0**32


def dot_layout(p: Path) -> tuple[int, list[str], dict[str, str]] | None:
    """(line index of the column header, its names, the ``Key:,value`` lines before it) of a Movella
    (Xsens) DOT CSV export, whose column header holds PacketCounter and SampleTimeFine; else None."""
    meta: dict[str, str] = {}
    for i, line in enumerate(head_lines(p, 60)):
        cells = [c.strip() for c in line.strip().split(",")]
        if "PacketCounter" in cells and "SampleTimeFine" in cells:
            return i, cells, meta
        if cells and cells[0].endswith(":"):
            meta[cells[0][:-1].strip()] = cells[1] if len(cells) > 1 else ""
    return None


def read_dot_csv(path, *, acc_unit=None, gyr_unit=None, rate_hz=None) -> ImuRecording:
    """A Movella (Xsens) DOT CSV export: ``sep=,`` and ``Key:,value`` lines (``OutputRate:,60Hz``),
    then ``PacketCounter,SampleTimeFine,...`` with ``Acc_X``..``Acc_Z`` and ``Gyr_X``..``Gyr_Z``
    (the DOT's units: m/s^2 and deg/s unless ``acc_unit``/``gyr_unit`` say otherwise). The time is
    SampleTimeFine (microseconds, unwrapped at 2^32). An export of orientation and free acceleration
    only (no angular rate) is refused in one line."""
    p = Path(path)
    layout = dot_layout(p)
    if layout is None:
        raise InputError(f"{p}: no PacketCounter,SampleTimeFine header line: not a Movella DOT export")
    return read_dot(p, layout, acc_unit=acc_unit, gyr_unit=gyr_unit, rate_hz=rate_hz)


def read_dot(p: Path, layout, *, acc_unit=None, gyr_unit=None, rate_hz=None) -> ImuRecording:
    """read_dot_csv over the layout :func:`dot_layout` found (its header scanned once)."""
    line, header, meta = layout
    need = list(_XSENS_CHANNELS)
    missing = [n for n in need if n not in header]
    if missing:
        has = ", ".join(h for h in header if h not in ("PacketCounter", "SampleTimeFine", "Status") and h) or "nothing"
        raise InputError(
            f"{p}: a Movella DOT export of {has}: it lacks {', '.join(missing)}; export a measurement mode "
            "with the calibrated acceleration and angular rate (orientation and free acceleration alone are "
            "not read)"
        )
    cols = [header.index(n) for n in ["SampleTimeFine", *need]]
    rows = []
    with open(p, encoding="utf-8-sig", errors="replace") as f:
        for i, text in enumerate(f):
            if i <= line or not text.strip():
                continue
            cells = text.strip().split(",")
            try:
                rows.append([float(cells[c]) if c < len(cells) and cells[c].strip() else np.nan for c in cols])
            except ValueError as exc:
                raise InputError(f"{p}: line {i + 1}: a value is not a number ({exc})") from None
    table = np.array(rows, dtype=float).reshape(-1, len(cols))
    if table.shape[0] < 2:
        raise InputError(f"{p}: fewer than two samples")
    missing_tick = np.flatnonzero(~np.isfinite(table[:, 0]))
    if missing_tick.size:
        raise InputError(
            f"{p}: sample {missing_tick[0]} (after the header) has no SampleTimeFine, and {missing_tick.size - 1} more"
        )
    ticks = np.unwrap(table[:, 0], period=_DOT_WRAP)
    time_s = (ticks - ticks[0]) * _DOT_TICK_S
    rate: float | None = float(rate_hz) if rate_hz else None
    m = re.match(r"\s*([0-9.]+)\s*Hz", meta.get("OutputRate", ""), re.IGNORECASE)
    if rate is None and m:
        rate = float(m.group(1))
    if rate is None:  # no OutputRate line (an SDK's own export): the ticks' median interval
        rate = median_rate_hz(time_s)
    acc_scale = unit_scale(acc_unit, ACC_UNITS, "acc_unit", p) or 1.0
    gyr_scale = unit_scale(gyr_unit, GYR_UNITS, "gyr_unit", p) or np.pi / 180.0
    about = {"layout": "movella_dot", **({"device_tag": meta["DeviceTag"]} if "DeviceTag" in meta else {})}
    return reading(p, time_s, table[:, 1:4] * acc_scale, table[:, 4:7] * gyr_scale, rate, gyr_scale, about)
