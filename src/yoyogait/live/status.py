"""The one-line live status on a terminal: rate, step frequency, speed, validity, latency."""

from __future__ import annotations

import time
from collections.abc import Sequence
from typing import TextIO

import numpy as np

from ..estimators.imu import why_not_valid as imu_why_not_valid
from ..estimators.online import why_not_valid
from .live import ESTIMATE_COLUMNS, LiveCounters


class StatusLine:
    """Rewrites one line of ``stream`` (a terminal) in place. ``columns``: the estimate rows' channel names
    (the marker path's by default; the IMU path's are set once its stream is found)."""

    def __init__(self, stream: TextIO, columns: Sequence[str] = ESTIMATE_COLUMNS):
        self.stream = stream
        self.columns = tuple(columns)
        self._last_time = time.monotonic()
        self._last_frames = 0
        self._width = 0

    def show(self, counters: LiveCounters, row: list[float]) -> None:
        now = time.monotonic()
        rate = (counters.frames - self._last_frames) / max(now - self._last_time, 1e-9)
        self._last_time, self._last_frames = now, counters.frames
        latency = counters.latency_s
        latency_ms = f"{1e3 * float(np.median(latency)):.2f} ms" if latency else "-"
        at = self.columns.index
        valid = ""
        if "valid" in self.columns:  # what a controller gates on, and why not, by name
            valid = "valid | " if row[at("valid")] else f"not valid ({self._why(row)}) | "
        text = (
            f"{rate:6.1f} frames/s | step {row[at('step_frequency_hz')]:4.2f} Hz | "
            f"speed {row[at('speed_mps')]:4.2f} m/s | "
            f"{'walking ' if row[at('walking')] else 'standing'} | {valid}latency {latency_ms} | "
            f"dropped {counters.dropped_not_increasing} missing {counters.missing_frames}"
        )
        self.stream.write("\r" + text.ljust(self._width))
        self.stream.flush()
        self._width = len(text)

    def _why(self, row: list[float]) -> str:
        """Why not valid, by name: the IMU path's one reason, the marker path's set of bits."""
        at = self.columns.index
        if "reason" in self.columns:
            return imu_why_not_valid(int(row[at("reason")])) or "-"
        return why_not_valid(int(row[at("invalid_reason")])) or "-"

    def close(self) -> None:
        if self._width:
            self.stream.write("\n")
            self.stream.flush()
