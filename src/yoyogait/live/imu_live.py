"""An LSL stream of a lower-back IMU through the online IMU estimator, into an estimate stream, a CSV and a
status line (docs/live.md, "An IMU stream").

:func:`run_live_imu` resolves the stream by name, reads its layout (:mod:`.imu_layout`: the acc and gyro
channels by label, their units), and feeds every sample to :class:`yoyogait.ImuOnlineEstimator`. Each
estimate is published as one sample of the IMU estimate stream (its channels: the fields of the IMU
record table, ``t_s`` as ``time_s``), stamped with its input sample's LSL timestamp.

The unruly-source handling is the marker path's (:mod:`.live`, :class:`~yoyogait.estimators.frame_gate.FrameGate`):
late or repeated stamps dropped and counted, samples missing by the nominal rate counted, a bounded
inlet buffer, a source that stops and comes back resolved again with its layout read again, twins, and
``stop`` within 0.1 s in every state. On top, the units are checked against physics as the files' are:
over the first half second the median norm of the acceleration must be about 9.81 m/s^2 (a stream in g
said to be in m/s^2 reads 1), and the angular rate must stay below what a walk produces (15 rad/s; a
stream in deg/s said to be in rad/s exceeds it as soon as the person walks): else the run ends with one
line naming the stream and the option that fixes it.
"""

from __future__ import annotations

import dataclasses
import functools
import math
import operator
import threading
from collections.abc import Callable, Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np

from ..errors import InputError
from ..estimators.config import ImuConfig
from ..estimators.imu import IMU_ESTIMATE_FIELDS, ImuOnlineEstimator, csv_formats
from ..io.imu_recording import GRAVITY_MPS2
from ._lsl import pylsl
from .imu_layout import IMU_TYPES, ImuLayout, read_imu_layout
from .live import (
    _INTEGER_FORMATS,
    CsvRecord,
    ImuSourceFound,
    LiveCounters,
    _format_name,
    _Stopped,
    check_rate,
    check_run_options,
    connect_and_pump,
    resolve_all,
    run_live,
)

IMU_ESTIMATE_STREAM_TYPE = "GaitEstimate"

#: The IMU estimate stream's channels, in order: (name, attribute of the native ImuEstimate), one per field
#: of the C++ table of ImuEstimate (its ``t_s`` is the ``time_s`` channel).
IMU_CHANNELS: tuple[tuple[str, str], ...] = tuple(("time_s" if n == "t_s" else n, n) for n, _, _ in IMU_ESTIMATE_FIELDS)
IMU_COLUMNS = tuple(name for name, _ in IMU_CHANNELS)
_ATTRIBUTES = tuple(attr for _, attr in IMU_CHANNELS)
_UNITS = {("time_s" if n == "t_s" else n): unit for n, unit, _ in IMU_ESTIMATE_FIELDS}

#: Over the first UNIT_CHECK_S (and at least UNIT_CHECK_SAMPLES samples) the acceleration's median norm is
#: checked; the angular rate's bound is checked throughout.
UNIT_CHECK_S = 0.5
UNIT_CHECK_SAMPLES = 20
MAX_WALKING_RATE_RAD_S = 15.0


_FIELDS_OF = operator.attrgetter(*_ATTRIBUTES)


def imu_row(estimate: Any) -> list[float]:
    """One ImuEstimate as the IMU estimate stream's channel values (floats, in IMU_COLUMNS order)."""
    return [float(v) for v in _FIELDS_OF(estimate)]


def imu_estimate_stream_info(name: str) -> Any:
    """StreamInfo of the IMU estimate stream: irregular rate (one sample per input sample), double64."""
    lsl = pylsl()
    info = lsl.StreamInfo(
        name,
        IMU_ESTIMATE_STREAM_TYPE,
        len(IMU_COLUMNS),
        lsl.IRREGULAR_RATE,
        lsl.cf_double64,
        f"yoyogait-live-imu-{name}",
    )
    desc = info.desc()
    desc.append_child("acquisition").append_child_value("manufacturer", "yoyogait").append_child_value(
        "model", "ImuOnlineEstimator"
    )
    channels = desc.append_child("channels")
    for column in IMU_COLUMNS:
        channels.append_child("channel").append_child_value("label", column).append_child_value("unit", _UNITS[column])
    return info


@dataclass
class ImuLiveOptions:
    """What the IMU path takes besides the stream: unit overrides (mps2, g / rad_s, deg_s), the sensor height
    (over the stream's setup/sensor_height_m), the estimator's settings, the record's columns and formats."""

    acc_unit: str | None = None
    gyr_unit: str | None = None
    sensor_height_m: float | None = None
    config: ImuConfig | None = None
    record_columns: Sequence[str] = IMU_COLUMNS
    record_formats: Sequence[str] | None = None


@dataclass
class ImuLiveSetup:
    """What the run resolved before the first sample of an IMU stream."""

    source: str
    layout: ImuLayout
    nominal_rate_hz: float
    config: ImuConfig
    uid: str = ""

    @property
    def sensor_height_m(self) -> float:
        """The inverted pendulum's length the estimator uses."""
        return float(self.config.sensor_height_m)

    def same_layout(self, other: ImuLiveSetup) -> bool:
        """The same channels, units and time base."""
        a, b = self.layout, other.layout
        return (
            a.channel_count == b.channel_count
            and a.acc_channels == b.acc_channels
            and a.gyr_channels == b.gyr_channels
            and a.time_channel == b.time_channel
            and (a.acc_scale, a.gyr_scale) == (b.acc_scale, b.gyr_scale)
        )


def imu_setup_from_info(info: Any, options: ImuLiveOptions | None = None) -> ImuLiveSetup:
    """Layout, units and the estimator's settings of an IMU stream; InputError saying what is missing."""
    opts = options if options is not None else ImuLiveOptions()
    if opts.sensor_height_m is not None and not (
        math.isfinite(opts.sensor_height_m) and 0.1 < opts.sensor_height_m <= 3.0
    ):
        raise InputError(f"--sensor-height-m must be in (0.1, 3] m, not {opts.sensor_height_m!r}")
    check_rate(info)
    layout = read_imu_layout(info, acc_unit=opts.acc_unit, gyr_unit=opts.gyr_unit, sensor_height_m=opts.sensor_height_m)
    fmt = _format_name(info.channel_format())
    if layout.time_channel is not None and fmt in _INTEGER_FORMATS:
        raise InputError(
            f"stream {info.name()!r}: its time_s channel is in an integer format ({fmt[3:]}), which cannot hold "
            "sample times; send float32 or double64 channels, or no time_s channel (the LSL timestamps are used then)"
        )
    config = opts.config if opts.config is not None else ImuConfig()
    if layout.sensor_height_m is not None:
        config = dataclasses.replace(config, sensor_height_m=float(layout.sensor_height_m))
    return ImuLiveSetup(info.name(), layout, float(info.nominal_srate()), config)


class UnitCheck:
    """The units against physics, sample by sample: the acceleration's median norm over the first
    UNIT_CHECK_S must be about 9.81 m/s^2; more than 1 % of the samples (and at least 10) beyond
    MAX_WALKING_RATE_RAD_S means deg/s said as rad/s. InputError naming the stream and the option."""

    def __init__(self, setup: ImuLiveSetup):
        self.setup = setup
        self._norms: list[float] = []
        self._acc_checked = False
        self._first_t: float | None = None
        self._samples = 0
        self._fast = 0

    def check(self, t_s: float, acc_mps2: Sequence[float], gyr_rad_s: Sequence[float]) -> None:
        # Plain floats: this runs for every sample (numpy on 3 values costs ten times more).
        name, layout = self.setup.source, self.setup.layout
        self._samples += 1
        ax, ay, az = acc_mps2
        if not self._acc_checked and math.isfinite(ax) and math.isfinite(ay) and math.isfinite(az):
            if self._first_t is None:
                self._first_t = t_s
            self._norms.append(math.sqrt(ax * ax + ay * ay + az * az))
            if len(self._norms) >= UNIT_CHECK_SAMPLES and t_s - self._first_t >= UNIT_CHECK_S:
                g = float(np.median(self._norms))
                self._acc_checked, self._norms = True, []  # checked once
                said = f"read as {layout.acc_unit}" if layout.acc_unit else ""
                if 0.5 < g < 2.0:
                    raise InputError(
                        f"stream {name!r}: the acceleration's median norm over the first {UNIT_CHECK_S:g} s is {g:.2f} "
                        f"m/s^2 ({said}), not 9.81 at rest: in g? pass --acc-unit g"
                    )
                if not (0.6 * GRAVITY_MPS2 < g < 1.4 * GRAVITY_MPS2):
                    raise InputError(
                        f"stream {name!r}: the acceleration's median norm over the first {UNIT_CHECK_S:g} s is "
                        f"{g:.3g} m/s^2 ({said}), not about 9.81: pass --acc-unit (mps2 or g)"
                    )
        fastest = max(abs(gyr_rad_s[0]), abs(gyr_rad_s[1]), abs(gyr_rad_s[2]))
        if fastest > MAX_WALKING_RATE_RAD_S and math.isfinite(fastest):
            self._fast += 1
            if self._fast >= 10 and self._fast > 0.01 * self._samples:
                said = f" read as {layout.gyr_unit}" if layout.gyr_unit else ""
                beyond = (
                    f"stream {name!r}: the angular rate{said} exceeds {MAX_WALKING_RATE_RAD_S:g} rad/s in "
                    f"{self._fast} of {self._samples} samples"
                )
                if abs(layout.gyr_scale - math.pi / 180.0) < 1e-12:  # read in deg/s already: the sensor's own rate
                    raise InputError(
                        f"{beyond}, beyond a lower back's in any walk: a sensor on a foot or a leg? yoyogait "
                        "estimates from one at the lower back"
                    )
                raise InputError(f"{beyond}, beyond any walk: in deg/s? pass --gyr-unit deg_s")


def run_live_imu(
    source: str,
    *,
    publish: str | None = None,
    imu: ImuLiveOptions | None = None,
    resolve_timeout_s: float = 10.0,
    duration_s: float | None = None,
    exit_on_end: bool = False,
    record: Path | None = None,
    force: bool = False,
    max_buffer_s: float = 1.0,
    reacquire_after_s: float = 2.0,
    on_setup: Callable[[ImuLiveSetup], None] | None = None,
    on_estimate: Callable[[list[float], float], None] | None = None,
    on_status: Callable[[LiveCounters, list[float]], None] | None = None,
    on_note: Callable[[str], None] | None = None,
    status_interval_s: float = 0.5,
    stop: threading.Event | None = None,
) -> LiveCounters:
    """Estimate gait live from the IMU stream ``source`` until ``duration_s``, its end (with ``exit_on_end``)
    or ``stop``, as :func:`yoyogait.live.live.run_live` does for a marker stream; ``imu``: units, sensor
    height, settings and the record's columns (:class:`ImuLiveOptions`). Returns the counters."""
    opts = imu if imu is not None else ImuLiveOptions()
    check_run_options(source, publish, max_buffer_s, duration_s)
    if opts.sensor_height_m is not None and not (
        math.isfinite(opts.sensor_height_m) and 0.1 < opts.sensor_height_m <= 3.0
    ):
        raise InputError(f"--sensor-height-m must be in (0.1, 3] m, not {opts.sensor_height_m!r}")
    formats = opts.record_formats if opts.record_formats is not None else csv_formats(opts.record_columns)
    recorder = (
        CsvRecord(record, opts.record_columns, formats, force, channels=IMU_COLUMNS) if record is not None else None
    )
    return connect_and_pump(
        source, imu_estimate_stream_info(publish) if publish else None, recorder,
        functools.partial(imu_setup_from_info, options=opts), _ImuPath(),
        resolve_timeout_s=resolve_timeout_s, duration_s=duration_s, exit_on_end=exit_on_end, max_buffer_s=max_buffer_s,
        reacquire_after_s=reacquire_after_s, stop=stop, on_setup=on_setup, on_estimate=on_estimate,
        on_status=on_status, on_note=on_note, status_interval_s=status_interval_s,
    )  # fmt: skip


class _ImuPath:
    """The IMU path of :func:`~yoyogait.live.live.pump`: each sample's acceleration and rate, in SI units
    and checked, into an ImuOnlineEstimator."""

    def __init__(self) -> None:
        self.time_channel: int | None = None

    def start(self, setup: ImuLiveSetup) -> None:
        self.estimator = ImuOnlineEstimator(setup.config)
        self._units = UnitCheck(setup)
        self._layout = setup.layout
        self.time_channel = setup.layout.time_channel

    def reset(self) -> None:
        self.estimator.reset()

    def row(self, t_s: float, sample: Sequence[float]) -> list[float]:
        layout = self._layout
        a, w = layout.acc_channels, layout.gyr_channels
        acc = [float(sample[a[0]]) * layout.acc_scale, float(sample[a[1]]) * layout.acc_scale,
               float(sample[a[2]]) * layout.acc_scale]  # fmt: skip
        gyr = [float(sample[w[0]]) * layout.gyr_scale, float(sample[w[1]]) * layout.gyr_scale,
               float(sample[w[2]]) * layout.gyr_scale]  # fmt: skip
        self._units.check(t_s, acc, gyr)
        return imu_row(self.estimator.update(t_s, acc, gyr))

    def layout_note(self, setup: ImuLiveSetup) -> str:
        return ""


#: ``input_kind``: what the source is; "auto" decides from the stream (type IMU, or acc/gyr labels).
INPUT_KINDS = ("auto", "markers", "imu")
#: How long "auto" looks for the source before it starts the marker path's wait [s]: it ends at the first
#: sight, so it costs only where the source is absent (0.3 s is short for a resolve on a loaded machine).
AUTO_PEEK_S = 1.0


def run_live_source(
    source: str,
    *,
    input_kind: str = "auto",
    imu: ImuLiveOptions | None = None,
    markers: dict[str, Any] | None = None,
    on_imu: Callable[[], None] | None = None,
    **common: Any,
) -> LiveCounters:
    """``run_live`` (``markers``: its marker-only options) or ``run_live_imu`` (``imu``) as ``input_kind`` says.
    "auto": a source already there (within AUTO_PEEK_S) of type IMU takes the IMU path at once; else the marker
    path, until the stream found is an IMU's (by type or labels), then the IMU path (its estimate stream replaces
    the marker one; ``on_imu()`` first: it may refuse with an InputError). ``common``: the options both take
    (publish, record, stop, ...)."""
    if input_kind not in INPUT_KINDS:
        raise InputError(f"--input must be one of {', '.join(INPUT_KINDS)}, not {input_kind!r}")
    if input_kind == "auto":
        # A source already there says its type at once: the right estimate stream is made from the start.
        try:
            seen = resolve_all(source, AUTO_PEEK_S, common.get("stop"), twins_s=0)
        except InputError:
            seen = []
        except _Stopped:
            return LiveCounters()
        if seen and seen[0].type().strip().lower() in IMU_TYPES:
            input_kind = "imu"
    if input_kind != "imu":
        try:
            return run_live(source, detect_imu=input_kind == "auto", **(markers or {}), **common)
        except ImuSourceFound:
            pass
    if on_imu is not None:
        on_imu()
    return run_live_imu(source, imu=imu, **common)
