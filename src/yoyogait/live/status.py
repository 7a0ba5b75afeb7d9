"""The one-line live status on a terminal: rate, step frequency, speed, latency."""

from __future__ import annotations

import time
from typing import TextIO

import numpy as np

from .live import ESTIMATE_COLUMNS, LiveCounters

_F = ESTIMATE_COLUMNS.index("step_frequency_hz")
_V = ESTIMATE_COLUMNS.index("speed_mps")
_W = ESTIMATE_COLUMNS.index("walking")


class StatusLine:
    """Rewrites one line of ``stream`` (a terminal) in place."""

    def __init__(self, stream: TextIO):
        self.stream = stream
        self._last_time = time.monotonic()
        self._last_frames = 0
        self._width = 0

    def show(self, counters: LiveCounters, row: list[float]) -> None:
        now = time.monotonic()
        rate = (counters.frames - self._last_frames) / max(now - self._last_time, 1e-9)
        self._last_time, self._last_frames = now, counters.frames
        latency = counters.latency_s
        latency_ms = f"{1e3 * float(np.median(latency)):.2f} ms" if latency else "-"
        text = (
            f"{rate:6.1f} frames/s | step {row[_F]:4.2f} Hz | speed {row[_V]:4.2f} m/s | "
            f"{'walking ' if row[_W] else 'standing'} | latency {latency_ms} | "
            f"dropped {counters.dropped_not_increasing} missing {counters.missing_frames}"
        )
        self.stream.write("\r" + text.ljust(self._width))
        self.stream.flush()
        self._width = len(text)

    def close(self) -> None:
        if self._width:
            self.stream.write("\n")
            self.stream.flush()
