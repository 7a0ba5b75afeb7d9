"""A marker stream through the online estimator, into an estimate stream, a CSV and a status line.

:func:`run_live` resolves the marker stream by name, reads its layout (:mod:`.layout`), picks the
points to follow (the pelvis found by name as for files, or ``point``), and feeds every frame to
:class:`yoyogait.estimators.online.OnlineEstimator`. Each estimate is published as one sample,
stamped with its input frame's LSL timestamp (docs/live.md lists the channels).

Real conditions (the frame handling is :class:`yoyogait.estimators.frame_gate.FrameGate`, shared
with the ROS 2 node):

* frames whose time does not increase (duplicated, out of order, late past a newer one) are
  dropped and counted (``dropped_not_increasing``); a single frame whose time jumps (100 s back,
  1e306 ahead) is dropped and counted (``dropped_jumps``); frames missing from the source's nominal
  rate (never sent, or dropped by the bounded inlet buffer when this consumer falls behind) are
  counted (``missing_frames``), frames that come faster than it (a burst) too (``burst_frames``);
* the inlet buffer holds at most ``max_buffer_s`` seconds of frames (liblsl drops the oldest
  beyond it); nothing here keeps a history, so memory does not grow with time;
* the source stopping: with ``exit_on_end`` the run ends; otherwise the stream is resolved by name
  again until it comes back, and its layout is read again (a source may come back relabelled, with
  its channels shifted or another channel count: ``reconnects``); the estimator starts over
  (``restarts``), as after a silence longer than ``reacquire_after_s``. Shorter gaps are bridged by
  the estimator itself (its front-end restarts after 0.25 s without a point, the gait filter keeps
  its state);
* several streams of one name: each is tried, the newest first; the first whose layout is usable
  is followed, and a line says so;
* ``stop`` (set by SIGINT or SIGTERM in the CLI) ends the run within 0.1 s in every state, waiting
  for the source included.
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
from typing import Any, Protocol, TextIO

import numpy as np

from .._files import check_output_file, commit, give_default_mode, temporary_beside
from ..errors import InputError
from ..estimators.frame_gate import DROP, RESTART, FrameCounts, FrameGate
from ..estimators.online import (
    MAX_BELT_SPEED_MPS,
    ONLINE_ESTIMATE_FIELDS,
    OnlineConfig,
    OnlineEstimator,
    check_belt_speed,
    column_of,
    config_for_point,
)
from ..io.recording import Recording
from ..pipeline import points
from ._lsl import pylsl
from .imu_layout import describe_imu, is_imu_info
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


#: The highest nominal rate taken for a motion-capture stream [Hz], and the most frames a buffer holds.
MAX_NOMINAL_RATE_HZ = 100_000.0
MAX_BUFFER_FRAMES = 10_000_000
#: The longest --max-buffer-s [s].
MAX_BUFFER_S = 3600.0
_INTEGER_FORMATS = ("cf_int8", "cf_int16", "cf_int32", "cf_int64")


@dataclass
class LiveCounters(FrameCounts):
    """What a live run saw; every count since the start (the frame counts: :class:`FrameCounts`)."""

    reconnects: int = 0  # the source came back as a new stream (its layout read again)
    connected: bool = False  # the source was found and its layout read (else the run was stopped before)
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
    uid: str = ""  # the LSL stream's unique id (a source that comes back is a new one)

    def same_layout(self, other: LiveSetup) -> bool:
        """The same channels for the same points."""
        a, b = self.layout, other.layout
        return (
            a.channel_count == b.channel_count
            and a.point_names == b.point_names
            and a.time_channel == b.time_channel
            and np.array_equal(a.position_channels, b.position_channels)
            and self.choice.names == other.choice.names
        )


class _Stopped(Exception):
    """``stop`` was set while waiting."""


class ImuSourceFound(Exception):
    """The source is an IMU stream, not markers (run_live with ``detect_imu``): run the IMU path instead."""


def resolve_all(name: str, timeout_s: float, stop: threading.Event | None = None, twins_s: float = 0.5) -> list[Any]:
    """Every StreamInfo of the LSL streams called ``name``, the newest first. A background resolver is polled
    every 0.1 s (``stop`` ends the wait: _Stopped); once one stream is seen, ``twins_s`` more for others of the
    same name. InputError when none appears within ``timeout_s``."""
    lsl = pylsl()
    deadline = time.monotonic() + timeout_s
    resolver = lsl.ContinuousResolver(prop="name", value=name, forget_after=5.0)
    try:
        found: list[Any] = []
        seen_at = None
        while True:
            if stop is not None and stop.is_set():
                raise _Stopped
            now = time.monotonic()
            found = list(resolver.results())
            if found and seen_at is None:
                seen_at = now
            if seen_at is not None and now - seen_at >= twins_s:
                break
            if not found and now >= deadline:
                raise InputError(f"no LSL stream named {name!r} found within {timeout_s:g} s (is the source running?)")
            time.sleep(0.02 if seen_at is None and now - (deadline - timeout_s) < 0.2 else 0.1)
    finally:
        del resolver
    unique = {info.uid(): info for info in found}
    return sorted(unique.values(), key=lambda i: i.created_at(), reverse=True)


def resolve_source(name: str, timeout_s: float) -> Any:
    """The StreamInfo of the LSL stream called ``name`` (the newest); InputError when none appears in time."""
    return resolve_all(name, timeout_s, twins_s=0)[0]


def _sliced(call: Callable[[float], Any], timeout_s: float, stop: threading.Event | None, what: str) -> Any:
    """``call(slice_s)`` until it returns, in slices of 0.1 s; _Stopped when ``stop`` is set, InputError
    naming ``what`` at the timeout."""
    lsl = pylsl()
    deadline = time.monotonic() + timeout_s
    while True:
        if stop is not None and stop.is_set():
            raise _Stopped
        left = deadline - time.monotonic()
        if left <= 0:
            raise InputError(f"{what}: could not connect within {timeout_s:g} s")
        try:
            return call(min(0.1, left))
        except lsl.util.TimeoutError:
            continue
        except lsl.util.LostError as exc:
            raise InputError(f"{what}: the stream went away while connecting ({exc})") from None


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
    check_rate(info)
    layout = read_layout(info, length_unit_m=length_unit_m, up_axis=up_axis)
    if layout.up_axis is None:
        raise InputError(f"stream {source!r} does not say which axis is up; pass --up-axis")
    if layout.length_unit_m is None:
        raise InputError(f"stream {source!r} does not say its length unit; pass --length-unit-m (0.001 for mm)")
    choice = choose_points(layout, source, point)
    fmt = _format_name(info.channel_format())
    if layout.time_channel is not None and fmt in _INTEGER_FORMATS:
        raise InputError(
            f"stream {source!r}: its time_s channel is in an integer format ({fmt[3:]}), "
            "which cannot hold frame times (frames of one second would share one time); send float32 or double64 "
            "channels, or no time_s channel (the LSL timestamps are used then)"
        )
    return LiveSetup(source, layout, choice, layout.up_axis, layout.length_unit_m, float(info.nominal_srate()))


def check_rate(info: Any) -> None:
    """InputError unless the stream's nominal rate is one of motion capture (or irregular)."""
    rate = info.nominal_srate()
    if not (math.isfinite(rate) and 0 <= rate <= MAX_NOMINAL_RATE_HZ):
        raise InputError(
            f"stream {info.name()!r} states a nominal rate of {rate:g} Hz: not a motion-capture rate "
            f"(expected 0, irregular, to {MAX_NOMINAL_RATE_HZ:g} Hz); fix the source's nominal_srate"
        )


def _unreadable(source: str, info: Any) -> str:
    """The line for a stream liblsl cannot open: its description does not parse (liblsl names it "(invalid: ...)")."""
    said = info.name()
    why = f" ({said.strip('()')})" if said.startswith("(invalid") else ""
    return (
        f"stream {source!r}: its description could not be read{why}: a nominal rate or channel count out of "
        f"range? (expected a rate of 0 to {MAX_NOMINAL_RATE_HZ:g} Hz)"
    )


def _format_name(code: int) -> str:
    lsl = pylsl()
    for name in ("cf_float32", "cf_double64", "cf_string", *_INTEGER_FORMATS):
        if getattr(lsl, name, None) == code:
            return name
    return f"format {code}"


def describe_source(name: str, timeout_s: float) -> list[str]:
    """What ``live`` would make of the marker stream ``name``: its layout, unit, up axis and pelvis."""
    lsl = pylsl()
    info = lsl.StreamInlet(resolve_source(name, timeout_s)).info(timeout_s)
    if is_imu_info(info):
        return describe_imu(info)
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
        channels: Sequence[str] = ESTIMATE_COLUMNS,
    ):
        self.path = Path(path)
        unknown = [c for c in columns if c not in channels]
        if unknown:
            raise InputError(f"no estimate channel {', '.join(unknown)}; channels: {', '.join(channels)}")
        self._index = [list(channels).index(c) for c in columns]
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
    on_note: Callable[[str], None] | None = None,
    status_interval_s: float = 0.5,
    stop: threading.Event | None = None,
    config: OnlineConfig | None = None,
    detect_imu: bool = False,
    feet: Sequence[str] | None = None,
    belt_speed_mps: float | None = None,
    belt_speed: Callable[[], float | None] | None = None,
) -> LiveCounters:
    """Estimate gait live from the marker stream ``source`` until ``duration_s``, its end (with
    ``exit_on_end``) or ``stop``. Returns the counters.

    Feet and treadmills (docs/online.md, "Feet", "Treadmills"): ``feet`` names foot points of the stream
    (one per foot, heels or ankles) that go into the frames after the followed points (their steps
    check the cadence; on a treadmill, the belt from the stance feet); ``belt_speed_mps`` a
    known belt speed; ``belt_speed()``, called before each frame, the belt speed at that frame (None:
    unknown), e.g. :class:`BeltSpeedStream` or a treadmill controller's reading: it may change at any time.

    ``publish``: name of the estimate stream (created first, before the source is resolved, so a
    subscriber can connect before the first estimate); ``record``: CSV of the estimates (the channels
    ``record_columns`` in ``record_formats``);
    ``on_estimate(row, timestamp)`` after each estimate; ``on_status(counters, last_row)`` every
    ``status_interval_s``; ``on_note(line)`` for what the run handled on its own (twin streams, a
    source that came back with another layout). ``stop`` ends the run at once in every state.
    """
    check_run_options(source, publish, max_buffer_s, duration_s)
    check_belt_speed(belt_speed_mps, "--belt-speed-mps")
    recorder = CsvRecord(record, record_columns, record_formats, force) if record is not None else None
    make_setup = functools.partial(
        _marker_setup, point=point, up_axis=up_axis, length_unit_m=length_unit_m, detect_imu=detect_imu
    )
    path = _MarkerPath(config, _Belt(tuple(feet or ()), belt_speed_mps, belt_speed))
    return connect_and_pump(
        source, estimate_stream_info(publish) if publish else None, recorder, make_setup, path,
        resolve_timeout_s=resolve_timeout_s, duration_s=duration_s, exit_on_end=exit_on_end, max_buffer_s=max_buffer_s,
        reacquire_after_s=reacquire_after_s, stop=stop, on_setup=on_setup, on_estimate=on_estimate,
        on_status=on_status, on_note=on_note, status_interval_s=status_interval_s,
    )  # fmt: skip


def check_run_options(source: str, publish: str | None, max_buffer_s: float, duration_s: float | None) -> None:
    """The options every live run takes, checked before anything is opened (InputError naming the option)."""
    if publish is not None and publish == source:
        raise InputError(f"--publish {publish!r}: the estimate stream needs a name other than the source's")
    if not (math.isfinite(max_buffer_s) and 0 < max_buffer_s <= MAX_BUFFER_S):
        raise InputError(f"--max-buffer-s must be a number of seconds in (0, {MAX_BUFFER_S:g}], not {max_buffer_s!r}")
    if duration_s is not None and not (math.isfinite(duration_s) and duration_s > 0):
        raise InputError(f"--duration must be a positive number of seconds, not {duration_s!r}")


def connect_and_pump(
    source: str,
    outlet_info: Any,
    recorder: CsvRecord | None,
    make_setup: Callable[[Any], Any],
    path: SamplePath,
    *,
    resolve_timeout_s: float | None,
    duration_s: float | None,
    exit_on_end: bool,
    max_buffer_s: float,
    reacquire_after_s: float,
    stop: threading.Event | None,
    on_setup: Callable[[Any], None] | None,
    on_estimate: Callable[[list[float], float], None] | None,
    on_status: Callable[[LiveCounters, list[float]], None] | None,
    on_note: Callable[[str], None] | None,
    status_interval_s: float,
) -> LiveCounters:
    """A live run of any source kind: the estimate stream (``outlet_info``; None: none) opened first, the
    source connected (``make_setup(info)``), then :func:`pump` with ``path`` until the end; the record
    kept with its whole rows when the run stops or fails after connecting, left out otherwise."""
    lsl = pylsl()
    note = on_note if on_note is not None else (lambda line: None)
    counters = LiveCounters()
    started = time.monotonic()
    connect = functools.partial(
        _connect, source, stop=stop, point=None, up_axis=None, length_unit_m=None, max_buffer_s=max_buffer_s,
        exit_on_end=exit_on_end, note=note, make_setup=make_setup,
    )  # fmt: skip
    try:
        outlet = lsl.StreamOutlet(outlet_info, 1, 10) if outlet_info is not None else None
        try:
            inlet, setup = connect(timeout_s=resolve_timeout_s)
        except _Stopped:
            inlet = None
        if inlet is not None:
            counters.connected = True
            if on_setup is not None:
                on_setup(setup)
            pump(
                inlet, outlet, recorder, setup, path, counters, started, duration_s, reacquire_after_s, stop,
                None if exit_on_end else functools.partial(connect, timeout_s=None), on_estimate, on_status, note,
                status_interval_s,
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
        if counters.connected:
            recorder.close()
        else:  # stopped while waiting for the source: nothing to keep
            recorder.discard()
    return counters


def _marker_setup(
    info: Any,
    *,
    point: str | Sequence[str] | None,
    up_axis: str | None,
    length_unit_m: float | None,
    detect_imu: bool,
) -> LiveSetup:
    if is_imu_info(info):
        if detect_imu:
            raise ImuSourceFound(info.name())
        raise InputError(f"stream {info.name()!r}: an IMU stream (type {info.type()!r}), not markers; pass --input imu")
    return setup_from_info(info, point=point, up_axis=up_axis, length_unit_m=length_unit_m)


def _connect(
    source: str,
    timeout_s: float | None,
    stop: threading.Event | None,
    point: str | Sequence[str] | None,
    up_axis: str | None,
    length_unit_m: float | None,
    max_buffer_s: float,
    exit_on_end: bool,
    note: Callable[[str], None],
    exclude: frozenset[str] = frozenset(),
    deadline: float | None = None,
    make_setup: Callable[[Any], Any] | None = None,
) -> tuple[Any, Any]:
    """An open inlet on the newest usable stream called ``source`` and its setup (``make_setup(info)``, by
    default the marker stream's). ``timeout_s`` None: wait (until ``deadline``, a monotonic time, if given)
    for a stream whose uid is not in ``exclude``."""
    lsl = pylsl()
    while True:
        wait_s = (
            timeout_s if timeout_s is not None else (0.5 if deadline is None else max(0.0, deadline - time.monotonic()))
        )
        try:
            infos = [i for i in resolve_all(source, wait_s, stop) if i.uid() not in exclude]
        except InputError:
            if timeout_s is not None:
                raise
            if deadline is not None and time.monotonic() >= deadline:
                raise _Stopped from None
            continue
        if not infos:
            if timeout_s is not None:
                raise InputError(f"no new LSL stream named {source!r} found within {timeout_s:g} s")
            if deadline is not None and time.monotonic() >= deadline:
                raise _Stopped
            time.sleep(0.1)
            continue
        break
    first_error: InputError | None = None
    for info in infos:
        try:
            check_rate(info)
            rate = info.nominal_srate()
            # max_buflen is in seconds for a stream with a nominal rate, in hundreds of samples otherwise.
            buflen = max(1, math.ceil(max_buffer_s if rate > 0 else max_buffer_s * 10))
            if rate * buflen > MAX_BUFFER_FRAMES:
                raise InputError(
                    f"stream {source!r}: --max-buffer-s {max_buffer_s:g} at {rate:g} Hz would hold {rate * buflen:.3g} "
                    f"frames (at most {MAX_BUFFER_FRAMES:g}); pass a smaller --max-buffer-s"
                )
            try:
                inlet = lsl.StreamInlet(info, max_buflen=buflen, recover=False, processing_flags=0)
            except RuntimeError:
                raise InputError(_unreadable(source, info)) from None
            what = f"stream {source!r}"
            full_info = _sliced(inlet.info, timeout_s if timeout_s is not None else 10.0, stop, what)
            setup: Any = (
                make_setup(full_info)
                if make_setup is not None
                else setup_from_info(full_info, point=point, up_axis=up_axis, length_unit_m=length_unit_m)
            )
            _sliced(inlet.open_stream, timeout_s if timeout_s is not None else 10.0, stop, what)
        except InputError as exc:
            if first_error is None:
                first_error = exc
            continue
        if len(infos) > 1:
            hosts = ", ".join(f"{i.hostname() or '?'} ({i.source_id() or i.uid()[:8]})" for i in infos)
            note(
                f"live: {len(infos)} streams named {source!r}: {hosts}; following the newest usable one, "
                f"{info.source_id() or info.uid()[:8]} ({info.channel_count()} channels)"
            )
        setup.uid = info.uid()
        return inlet, setup
    assert first_error is not None
    if timeout_s is None:
        note(f"live: {first_error}; waiting for another stream named {source!r}")
        return _connect(
            source, None, stop, point, up_axis, length_unit_m, max_buffer_s, exit_on_end, note,
            exclude | {i.uid() for i in infos}, deadline, make_setup,
        )  # fmt: skip
    raise first_error


class SamplePath(Protocol):
    """What one kind of source's samples become in :func:`pump`: the marker path's or the IMU's."""

    time_channel: int | None  # the channel of the frame's time, else its LSL stamp

    def start(self, setup: Any) -> None:
        """A new estimator for ``setup`` (the start, a source that came back)."""

    def reset(self) -> None:
        """Start the estimator over (the source came back after a gap)."""

    def row(self, t_s: float, sample: Sequence[float]) -> list[float]:
        """The estimate of one admitted sample, as a row of the estimate stream."""

    def layout_note(self, setup: Any) -> str:
        """Said after "read again" when a source came back with another layout."""


def pump(
    inlet: Any,
    outlet: Any,
    recorder: CsvRecord | None,
    setup: Any,
    path: SamplePath,
    counters: LiveCounters,
    started: float,
    duration_s: float | None,
    reacquire_after_s: float,
    stop: threading.Event | None,
    reconnect: Callable[..., tuple[Any, Any]] | None,
    on_estimate: Callable[[list[float], float], None] | None,
    on_status: Callable[[LiveCounters, list[float]], None] | None,
    note: Callable[[str], None],
    status_interval_s: float,
) -> None:
    """The live loop of every source kind: pull, reconnect, gate, estimate (``path``), publish, record."""
    lsl = pylsl()
    lost_error = lsl.util.LostError
    path.start(setup)
    gate = FrameGate(setup.nominal_rate_hz, reacquire_after_s, counters)
    next_status = started + status_interval_s
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
            if reconnect is None:
                counters.source_ended = True
                break
            old = setup
            deadline = None if duration_s is None else started + duration_s
            try:
                inlet, setup = reconnect(exclude=frozenset({old.uid}), deadline=deadline)
            except _Stopped:
                break
            counters.reconnects += 1
            if not setup.same_layout(old):
                note(
                    f"live: stream {setup.source!r} came back with another layout ({setup.layout.channel_count} "
                    f"channels, was {old.layout.channel_count}): read again{path.layout_note(setup)}"
                )
            path.start(setup)
            gate = FrameGate(setup.nominal_rate_hz, reacquire_after_s, counters)
            if counters.estimates > 0:
                counters.restarts += 1
            continue
        if sample is None:
            continue
        arrival = time.monotonic()
        t_s = float(sample[path.time_channel]) if path.time_channel is not None else stamp
        verdict = gate.admit(t_s, arrival)
        if verdict == DROP:
            continue
        if verdict == RESTART:
            path.reset()  # the source came back: start over rather than bridge the gap
        row = path.row(t_s, sample)
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


class _MarkerPath:
    """The marker path of :func:`pump`: the chosen points (and feet) of each frame into an OnlineEstimator."""

    def __init__(self, config: OnlineConfig | None, belt: _Belt):
        self._config, self._belt = config, belt
        self.time_channel: int | None = None

    def start(self, s: LiveSetup) -> None:
        chosen = [s.layout.point_names.index(n) for n in s.choice.names] + self._belt.feet_of(s)
        config = config_for_point(s.choice, self._config)  # a hand must travel to walk
        self.estimator = OnlineEstimator(s.choice.names, s.up_axis, s.length_unit_m, config, feet=self._belt.feet)
        self._belt.start(self.estimator)
        self._channels = s.layout.position_channels[chosen].ravel()
        self.time_channel = s.layout.time_channel

    def reset(self) -> None:
        self.estimator.reset()

    def row(self, t_s: float, sample: Sequence[float]) -> list[float]:
        positions = np.asarray(sample)[self._channels]
        self._belt.before_frame(self.estimator)
        return estimate_row(self.estimator.update(t_s, positions))

    def layout_note(self, s: LiveSetup) -> str:
        return f", following {s.choice.label}"


class _Belt:
    """The treadmill inputs of a live run: foot points, a known belt speed, a belt speed that may change."""

    def __init__(
        self,
        feet: tuple[str, ...] = (),
        speed_mps: float | None = None,
        speed: Callable[[], float | None] | None = None,
    ):
        self.feet, self._fixed, self._speed = feet, speed_mps, speed
        self._last: float | None = None

    def feet_of(self, s: LiveSetup) -> list[int]:
        """The feet's indices among the stream's points; InputError naming a missing one."""
        names = list(s.layout.point_names)
        missing = [f for f in self.feet if f not in names]
        if missing:
            raise InputError(f"stream {s.source!r}: --feet {', '.join(missing)}: not among its points")
        return [names.index(f) for f in self.feet]

    def start(self, estimator: Any) -> None:
        """A new estimator (the start, a source that came back): the known belt speed."""
        self._last = self._fixed
        if self._fixed is not None:
            estimator.set_belt_speed_mps(self._fixed)

    def before_frame(self, estimator: Any) -> None:
        """The belt speed of this frame from ``speed()``, given to the estimator when it changed."""
        if self._speed is None:
            return
        v = self._speed()
        if v is not None and not (math.isfinite(v) and 0 <= v <= MAX_BELT_SPEED_MPS):
            v = None  # not a speed: unknown
        if v != self._last:
            estimator.set_belt_speed_mps(v)
            self._last = v


class BeltSpeedStream:
    """The belt speed of a treadmill from an LSL stream (its first channel, m/s), as ``run_live``'s
    ``belt_speed``: each call takes the newest sample without waiting; a value that is not a speed
    (negative, NaN), no sample yet, or the stream gone is None (unknown)."""

    def __init__(self, name: str, timeout_s: float = 10.0, stop: threading.Event | None = None):
        lsl = pylsl()
        self.name = name
        self._lost = lsl.util.LostError
        self._value: float | None = None
        self._inlet: Any = None
        try:
            try:
                infos = resolve_all(name, timeout_s, stop)
            except InputError as exc:
                raise InputError(f"--belt-speed-source: {exc}") from None
            inlet = lsl.StreamInlet(infos[0], max_buflen=1, recover=False, processing_flags=0)
            _sliced(inlet.open_stream, timeout_s, stop, f"--belt-speed-source {name!r}")
        except _Stopped:  # stopped while waiting: the run that follows ends at once
            return
        self._inlet = inlet

    def __call__(self) -> float | None:
        if self._inlet is None:
            return None
        try:
            chunk, _ = self._inlet.pull_chunk(timeout=0.0)
        except self._lost:
            self._inlet, self._value = None, None
            return None
        if chunk:
            v = float(chunk[-1][0]) if len(chunk[-1]) else math.nan
            self._value = v if math.isfinite(v) and v >= 0 else None
        return self._value
