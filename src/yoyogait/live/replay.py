"""A recording played into an LSL marker stream (an IMU recording into an IMU stream: :func:`replay_imu`), at
its capture rate (or ``speed`` times it).

Each frame is pushed when its time comes (the recording's timestamps, divided by ``speed``),
stamped with the LSL clock at the push, and carries the recording's own time in the ``time_s``
channel (layout: :mod:`yoyogait.live.layout`). With ``loop`` the recording starts over after a
pause of :data:`LOOP_PAUSE_S` (longer than a consumer's gap limit, so that the jump back to the
start reads as a gap and not as a flight across the room), and ``time_s`` keeps increasing.
"""

from __future__ import annotations

import threading
import time
from collections.abc import Callable
from dataclasses import dataclass
from typing import Any

import numpy as np

from ..errors import InputError
from ..io.imu_recording import ImuRecording
from ..io.recording import Recording
from ..pipeline.points import resolve_up_axis
from ._lsl import pylsl
from .imu_layout import imu_stream_info
from .layout import marker_stream_info

#: Pause between passes of a looped replay [s].
LOOP_PAUSE_S = 1.0
#: Time the stream stays open after the last frame [s].
LINGER_S = 0.3


@dataclass
class ReplayStats:
    """What a replay pushed."""

    frames: int = 0
    passes: int = 0
    wall_s: float = 0.0


def replay(
    rec: Recording,
    name: str,
    *,
    speed: float = 1.0,
    loop: bool = False,
    up_axis: str | None = None,
    source_id: str = "",
    wait_for_consumer_s: float | None = None,
    stop: threading.Event | None = None,
    on_push: Callable[[int, float], None] | None = None,
    on_ready: Callable[[], None] | None = None,
) -> ReplayStats:
    """Play ``rec`` into a marker stream called ``name`` until its end (or ``stop``; forever with ``loop``).

    ``wait_for_consumer_s``: wait up to that long for a consumer before the first frame (InputError
    when none comes). ``on_push(frame_index, lsl_timestamp)`` is called after every push;
    ``on_ready()`` once the stream exists.
    """
    if not (np.isfinite(speed) and speed > 0):
        raise InputError(f"--speed must be a positive number, not {speed!r}")
    if rec.velocities is not None or not rec.point_names:
        raise InputError(f"{rec.source or 'recording'}: holds velocities, not point positions; nothing to replay")
    lsl = pylsl()
    up, _ = resolve_up_axis(rec, up_axis)
    t = np.asarray(rec.time_s, dtype=float)
    rate_hz = rec.rate_hz or (1.0 / float(np.median(np.diff(t))) if len(t) > 1 else 0.0)
    n_points = len(rec.point_names)
    # One contiguous row per frame: x, y, z of every point, then the recording's time.
    frames = np.empty((rec.n_frames, 3 * n_points + 1))
    frames[:, :-1] = rec.positions_m.reshape(rec.n_frames, 3 * n_points)
    info = marker_stream_info(
        name, rec.point_names, rate_hz, up, source_id=source_id or f"yoyogait-replay-{name}", source_file=rec.source
    )
    outlet = lsl.StreamOutlet(info, chunk_size=1, max_buffered=10)
    if on_ready is not None:
        on_ready()
    stats = ReplayStats()
    if wait_for_consumer_s is not None and not outlet.wait_for_consumers(wait_for_consumer_s):
        raise InputError(f"stream {name!r}: no consumer connected within {wait_for_consumer_s:g} s")
    return _play(outlet, frames, t, speed, loop, stats, stop, on_push)


def _play(
    outlet: Any,
    frames: np.ndarray,
    t: np.ndarray,
    speed: float,
    loop: bool,
    stats: ReplayStats,
    stop: threading.Event | None,
    on_push: Callable[[int, float], None] | None,
) -> ReplayStats:
    """Push each row of ``frames`` when its time ``t`` comes (divided by ``speed``), its last channel set to the
    time (shifted by a pass's period when looping)."""
    lsl = pylsl()
    period_s = float(t[-1] - t[0]) + LOOP_PAUSE_S
    start_wall = time.perf_counter()
    start = lsl.local_clock()
    while True:
        offset_s = stats.passes * period_s
        for k in range(frames.shape[0]):
            due = start + (t[k] - t[0] + offset_s) / speed
            while True:
                if stop is not None and stop.is_set():
                    stats.wall_s = time.perf_counter() - start_wall
                    return stats
                wait_s = due - lsl.local_clock()
                if wait_s <= 0:
                    break
                time.sleep(min(wait_s, 0.1))  # short enough to notice ``stop``
            frames[k, -1] = t[k] + offset_s
            row = frames[k].tolist()
            stamp = lsl.local_clock()
            outlet.push_sample(row, stamp)
            stats.frames += 1
            if on_push is not None:
                on_push(k, stamp)
        stats.passes += 1
        if not loop:
            break
    # Give the last frames time to leave before the outlet closes with the function.
    time.sleep(LINGER_S)
    stats.wall_s = time.perf_counter() - start_wall
    return stats


def replay_imu(
    rec: ImuRecording,
    name: str,
    *,
    speed: float = 1.0,
    loop: bool = False,
    source_id: str = "",
    wait_for_consumer_s: float | None = None,
    stop: threading.Event | None = None,
    on_push: Callable[[int, float], None] | None = None,
    on_ready: Callable[[], None] | None = None,
) -> ReplayStats:
    """Play an IMU recording into an IMU stream called ``name`` (:mod:`.imu_layout`: acc in m/s^2, gyr in
    rad/s, time_s; the sensor height in its setup), as :func:`replay` plays markers."""
    if not (np.isfinite(speed) and speed > 0):
        raise InputError(f"--speed must be a positive number, not {speed!r}")
    if rec.n_samples < 2:
        raise InputError(f"{rec.source or 'recording'}: fewer than two samples; nothing to replay")
    lsl = pylsl()
    t = np.asarray(rec.time_s, dtype=float)
    rate_hz = rec.rate_hz or 1.0 / float(np.median(np.diff(t)))
    frames = np.empty((rec.n_samples, 7))
    frames[:, 0:3] = rec.acc_mps2
    frames[:, 3:6] = rec.gyr_rad_s
    info = imu_stream_info(
        name,
        rate_hz,
        sensor_height_m=rec.sensor_height_m,
        source_id=source_id or f"yoyogait-replay-{name}",
        source_file=rec.source,
    )
    outlet = lsl.StreamOutlet(info, chunk_size=1, max_buffered=10)
    if on_ready is not None:
        on_ready()
    if wait_for_consumer_s is not None and not outlet.wait_for_consumers(wait_for_consumer_s):
        raise InputError(f"stream {name!r}: no consumer connected within {wait_for_consumer_s:g} s")
    return _play(outlet, frames, t, speed, loop, ReplayStats(), stop, on_push)
