"""A marker stream through the online estimator, into an estimate stream, a CSV and a status line.

:func:`run_live` resolves the marker stream by name, reads its layout (:mod:`.layout`), picks the
points to follow (the pelvis found by name as for files, or ``point``), and feeds every frame to
:class:`yoyogait.estimators.online.OnlineEstimator`. Each estimate is published as one sample,
stamped with its input frame's LSL timestamp (docs/live.md lists the channels).

Real conditions:

* frames whose time does not increase (duplicated, out of order, late past a newer one) are
  dropped and counted (``dropped_not_increasing``); frames missing from the source's nominal
  rate (never sent, or dropped by the bounded inlet buffer when this consumer falls behind) are
  counted (``missing_frames``);
* the inlet buffer holds at most ``max_buffer_s`` seconds of frames (liblsl drops the oldest
  beyond it); nothing here keeps a history, so memory does not grow with time;
* the source stopping: with ``exit_on_end`` the run ends; otherwise liblsl reconnects when the
  stream comes back, and after a silence longer than ``reacquire_after_s`` (or a jump back in
  time by more than that) the estimator starts over and re-acquires (``restarts``). Shorter
  gaps are bridged by the estimator itself (its front-end restarts after 0.25 s without a
  point, the gait filter keeps its state).
"""

from __future__ import annotations

import functools
import math
import os
import threading
import time
from collections.abc import Callable, Sequence
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any, TextIO

import numpy as np

from .._files import check_output_file, commit, give_default_mode, temporary_beside
from ..errors import InputError
from ..estimators.online import ONLINE_ESTIMATE_FIELDS, OnlineConfig, OnlineEstimator, column_of
from ..io.recording import Recording
from ..pipeline import points
from ._lsl import pylsl
from .layout import MarkerLayout, read_layout

ESTIMATE_STREAM_TYPE = "GaitEstimate"

#: The estimate stream's channels, in order: (name with its unit, attribute of the native estimate), one
#: per field of the C++ table of OnlineEstimate (its ``t_s`` is the ``time_s`` channel).
ESTIMATE_CHANNELS: tuple[tuple[str, str], ...] = tuple((column_of(f.name), f.name) for f in ONLINE_ESTIMATE_FIELDS)
ESTIMATE_COLUMNS = tuple(name for name, _ in ESTIMATE_CHANNELS)
_ATTRIBUTES = tuple(attr for _, attr in ESTIMATE_CHANNELS)


def estimate_row(estimate: Any) -> list[float]:
    """One estimate as the estimate stream's channel values (floats, in ESTIMATE_COLUMNS order)."""
    return [float(getattr(estimate, a)) for a in _ATTRIBUTES]


@dataclass
class LiveCounters:
    """What a live run saw; every count since the start."""

    frames: int = 0  # frames received
    estimates: int = 0  # estimates produced (one per frame used)
    dropped_not_increasing: int = 0  # duplicated, out-of-order or late frames, dropped
    missing_frames: int = 0  # frames absent by the nominal rate (not sent, or dropped by the full buffer)
    restarts: int = 0  # the source came back after a silence or jumped back: the estimator started over
    source_ended: bool = False
    latency_s: list[float] = field(default_factory=list, repr=False)  # recent receive latencies (status line)


@dataclass
class LiveSetup:
    """What the run resolved before the first frame."""

    source: str
    layout: MarkerLayout
    choice: points.PointChoice
    up_axis: str
    length_unit_m: float
    nominal_rate_hz: float


def resolve_source(name: str, timeout_s: float) -> Any:
    """The StreamInfo of the LSL stream called ``name``; InputError when none appears in time."""
    lsl = pylsl()
    found = lsl.resolve_byprop("name", name, 1, timeout_s)
    if not found:
        raise InputError(f"no LSL stream named {name!r} found within {timeout_s:g} s (is the source running?)")
    return found[0]


def choose_points(layout: MarkerLayout, source: str, point: str | Sequence[str] | None) -> points.PointChoice:
    """The points to follow among the stream's, as for files; InputError saying they must be named."""
    names = list(layout.point_names)
    stand_in = Recording(np.empty((0, len(names), 3)), names, np.empty(0), source=f"stream {source!r}")
    try:
        return points.choose_point(stand_in, point)
    except InputError as exc:
        if point is not None:
            raise
        shown = ", ".join(names[:12]) + (f", ... ({len(names) - 12} more)" if len(names) > 12 else "")
        raise InputError(
            f"stream {source!r}: no pelvis point found by name (ASIS/PSIS/sacrum markers or a Hips/pelvis/root "
            f"joint): pelvis points must be named (labelled markers), or chosen with --point; "
            f"the stream's points: {shown}"
        ) from exc


def setup_from_info(
    info: Any,
    *,
    point: str | Sequence[str] | None = None,
    up_axis: str | None = None,
    length_unit_m: float | None = None,
) -> LiveSetup:
    """Layout, points, up axis and unit of a marker stream; InputError saying what is missing."""
    source = info.name()
    layout = read_layout(info, length_unit_m=length_unit_m, up_axis=up_axis)
    if layout.up_axis is None:
        raise InputError(f"stream {source!r} does not say which axis is up; pass --up-axis")
    if layout.length_unit_m is None:
        raise InputError(f"stream {source!r} does not say its length unit; pass --length-unit-m (0.001 for mm)")
    choice = choose_points(layout, source, point)
    return LiveSetup(source, layout, choice, layout.up_axis, layout.length_unit_m, float(info.nominal_srate()))


def describe_source(name: str, timeout_s: float) -> list[str]:
    """What ``live`` would make of the marker stream ``name``: its layout, unit, up axis and pelvis."""
    lsl = pylsl()
    info = lsl.StreamInlet(resolve_source(name, timeout_s)).info(timeout_s)
    layout = read_layout(info)
    rate = info.nominal_srate()
    lines = [
        f"stream {name!r}: type {info.type()!r}, {info.channel_count()} channels, "
        + (f"{rate:g} Hz" if rate > 0 else "irregular rate")
        + f", from {info.hostname() or 'unknown host'}",
        f"points ({len(layout.point_names)}): {', '.join(layout.point_names)}",
        "length unit: "
        + (f"{layout.length_unit_m:g} m" if layout.length_unit_m else "not stated (pass --length-unit-m)"),
        f"up axis: {layout.up_axis or 'not stated (pass --up-axis)'}",
        "time: " + ("the time_s channel" if layout.time_channel is not None else "the LSL timestamps"),
    ]
    try:
        lines.append(f"followed by default: {choose_points(layout, name, None).label}")
    except InputError as exc:
        lines.append(f"followed by default: none ({exc})")
    return lines


def estimate_stream_info(name: str, setup: LiveSetup | None = None) -> Any:
    """StreamInfo of the estimate stream: irregular rate (one sample per input frame), double64."""
    lsl = pylsl()
    info = lsl.StreamInfo(
        name, ESTIMATE_STREAM_TYPE, len(ESTIMATE_COLUMNS), lsl.IRREGULAR_RATE, lsl.cf_double64, f"yoyogait-live-{name}"
    )
    desc = info.desc()
    desc.append_child("acquisition").append_child_value("manufacturer", "yoyogait").append_child_value(
        "model", "OnlineEstimator"
    )
    channels = desc.append_child("channels")
    for column in ESTIMATE_COLUMNS:
        channels.append_child("channel").append_child_value("label", column).append_child_value(
            "unit", _unit_of(column)
        )
    return info


def _unit_of(column: str) -> str:
    for suffix, unit in (("_mps", "m/s"), ("_hz", "Hz"), ("_rad", "rad"), ("_s", "s")):
        if column.endswith(suffix):
            return unit
    return {"gait_phase": "cycles"}.get(column, "")


class CsvRecord:
    """Estimates appended to a CSV as they come; written under a temporary name, renamed on close.

    ``columns``: the estimate-stream channels to write, each with its printf format in ``formats``
    (default: every channel, every digit).
    """

    def __init__(
        self,
        path: Path,
        columns: Sequence[str] = ESTIMATE_COLUMNS,
        formats: Sequence[str] | None = None,
        force: bool = False,
    ):
        self.path = Path(path)
        unknown = [c for c in columns if c not in ESTIMATE_COLUMNS]
        if unknown:
            raise InputError(f"no estimate channel {', '.join(unknown)}; channels: {', '.join(ESTIMATE_COLUMNS)}")
        self._index = [ESTIMATE_COLUMNS.index(c) for c in columns]
        self._formats = list(formats) if formats is not None else ["%r"] * len(columns)
        check_output_file(self.path, "--record", force)
        self._absent = not os.path.lexists(self.path)
        fd, self._tmp = temporary_beside(self.path)  # a new name: never a link's target
        self._file: TextIO | None = os.fdopen(fd, "w", encoding="utf-8")
        self._file.write(",".join(columns) + "\n")
        self.rows = 0

    def write(self, row: Sequence[float]) -> None:
        assert self._file is not None
        self._file.write(",".join(f % row[i] for f, i in zip(self._formats, self._index)) + "\n")
        self.rows += 1

    def close(self) -> None:
        """Complete the file (every row so far) under its name."""
        if self._file is not None:
            self._file.close()
            self._file = None
            try:
                give_default_mode(self._tmp)
                commit(self._tmp, self.path, self._absent)
            except BaseException:
                self._tmp.unlink(missing_ok=True)
                raise

    def discard(self) -> None:
        if self._file is not None:
            self._file.close()
            self._file = None
            self._tmp.unlink(missing_ok=True)


def run_live(
    source: str,
    *,
    publish: str | None = None,
    point: str | Sequence[str] | None = None,
    up_axis: str | None = None,
    length_unit_m: float | None = None,
    resolve_timeout_s: float = 10.0,
    duration_s: float | None = None,
    exit_on_end: bool = False,
    record: Path | None = None,
    record_columns: Sequence[str] = ESTIMATE_COLUMNS,
    record_formats: Sequence[str] | None = None,
    force: bool = False,
    max_buffer_s: float = 1.0,
    reacquire_after_s: float = 2.0,
    on_setup: Callable[[LiveSetup], None] | None = None,
    on_estimate: Callable[[list[float], float], None] | None = None,
    on_status: Callable[[LiveCounters, list[float]], None] | None = None,
    status_interval_s: float = 0.5,
    stop: threading.Event | None = None,
    config: OnlineConfig | None = None,
) -> LiveCounters:
    """Estimate gait live from the marker stream ``source`` until ``duration_s``, its end (with
    ``exit_on_end``) or ``stop``. Returns the counters.

    ``publish``: name of the estimate stream (created first, before the source is resolved, so a
    subscriber can connect before the first estimate); ``record``: CSV of the estimates (the channels
    ``record_columns`` in ``record_formats``);
    ``on_estimate(row, timestamp)`` after each estimate; ``on_status(counters, last_row)`` every
    ``status_interval_s``.
    """
    lsl = pylsl()
    if publish is not None and publish == source:
        raise InputError(f"--publish {publish!r}: the estimate stream needs a name other than the source's")
    if not (math.isfinite(max_buffer_s) and max_buffer_s > 0):
        raise InputError(f"--max-buffer-s must be a positive number, not {max_buffer_s!r}")
    if duration_s is not None and not (math.isfinite(duration_s) and duration_s > 0):
        raise InputError(f"--duration must be a positive number of seconds, not {duration_s!r}")
    recorder = CsvRecord(record, record_columns, record_formats, force) if record is not None else None
    try:
        outlet = lsl.StreamOutlet(estimate_stream_info(publish), 1, 10) if publish else None
        info = resolve_source(source, resolve_timeout_s)
        # max_buflen is in seconds for a stream with a nominal rate, in hundreds of samples otherwise.
        rate = info.nominal_srate()
        buflen = max(1, math.ceil(max_buffer_s if rate > 0 else max_buffer_s * 10))
        inlet = lsl.StreamInlet(info, max_buflen=buflen, recover=not exit_on_end, processing_flags=0)
        try:
            full_info = inlet.info(resolve_timeout_s)
            setup = setup_from_info(full_info, point=point, up_axis=up_axis, length_unit_m=length_unit_m)
            if on_setup is not None:
                on_setup(setup)
            inlet.open_stream(resolve_timeout_s)
        except (lsl.util.TimeoutError, lsl.util.LostError) as exc:
            raise InputError(f"stream {source!r}: could not connect within {resolve_timeout_s:g} s ({exc})") from None
        counters = _loop(
            inlet, outlet, recorder, setup, functools.partial(OnlineEstimator, config=config), duration_s,
            reacquire_after_s, stop,
            on_estimate, on_status, status_interval_s,
        )  # fmt: skip
    except BaseException:
        if recorder is not None:
            # A live run interrupted keeps what it recorded (whole rows); a failed setup leaves nothing.
            if recorder.rows > 0:
                recorder.close()
            else:
                recorder.discard()
        raise
    if recorder is not None:
        recorder.close()
    return counters


def _loop(
    inlet: Any,
    outlet: Any,
    recorder: CsvRecord | None,
    setup: LiveSetup,
    estimator_type: Any,
    duration_s: float | None,
    reacquire_after_s: float,
    stop: threading.Event | None,
    on_estimate: Callable[[list[float], float], None] | None,
    on_status: Callable[[LiveCounters, list[float]], None] | None,
    status_interval_s: float,
) -> LiveCounters:
    lsl = pylsl()
    lost_error = lsl.util.LostError
    layout = setup.layout
    chosen = [layout.point_names.index(n) for n in setup.choice.names]
    channels = layout.position_channels[chosen].ravel()
    time_channel = layout.time_channel
    estimator = estimator_type(setup.choice.names, setup.up_axis, setup.length_unit_m)
    counters = LiveCounters()
    frame_period_s = 1.0 / setup.nominal_rate_hz if setup.nominal_rate_hz > 0 else 0.0
    started = time.monotonic()
    next_status = started + status_interval_s
    last_arrival = None
    last_t = -math.inf
    row: list[float] = []
    while True:
        now = time.monotonic()
        if stop is not None and stop.is_set():
            break
        if duration_s is not None and now - started >= duration_s:
            break
        wait_s = 0.1 if duration_s is None else max(0.0, min(0.1, started + duration_s - now))
        try:
            sample, stamp = inlet.pull_sample(timeout=wait_s)
        except lost_error:
            counters.source_ended = True
            break
        if sample is None:
            continue
        arrival = time.monotonic()
        counters.frames += 1
        t_s = sample[time_channel] if time_channel is not None else stamp
        silent = last_arrival is not None and arrival - last_arrival > reacquire_after_s
        jumped_back = t_s < last_t - reacquire_after_s
        if (silent or jumped_back) and counters.estimates > 0:
            estimator.reset()  # the source came back: start over rather than bridge the gap
            counters.restarts += 1
            last_t = -math.inf
        last_arrival = arrival
        if not (t_s > last_t) or not math.isfinite(t_s):
            counters.dropped_not_increasing += 1
            continue
        if frame_period_s and last_t > -math.inf:
            counters.missing_frames += max(0, round((t_s - last_t) / frame_period_s) - 1)
        last_t = t_s
        positions = np.asarray(sample)[channels]
        row = estimate_row(estimator.update(t_s, positions))
        counters.estimates += 1
        if outlet is not None:
            outlet.push_sample(row, stamp)
        if recorder is not None:
            recorder.write(row)
        if on_estimate is not None:
            on_estimate(row, stamp)
        if on_status is not None:
            counters.latency_s.append(lsl.local_clock() - stamp)
            if arrival >= next_status:
                on_status(counters, row)
                counters.latency_s.clear()
                next_status = arrival + status_interval_s
    return counters
