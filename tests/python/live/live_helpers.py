"""Helpers of the live-streaming tests: a short synthetic walk on disk, crafted marker streams."""

from __future__ import annotations

import threading
import time
import uuid

import numpy as np

from yoyogait import synthetic
from yoyogait.io.recording import Recording

PELVIS = ("LASI", "RASI", "LPSI", "RPSI")


def unique(prefix: str) -> str:
    """A stream name no other test (or run) uses."""
    return f"{prefix}-{uuid.uuid4().hex[:10]}"


def short_walk(duration_s: float = 6.0, rate_hz: float = 100.0) -> Recording:
    """A few seconds of the SYNTHETIC lab's straight walk (z up, metres, a few dropouts)."""
    subject = synthetic.get_subject("synthetic-S1")
    return synthetic.make_walk(subject, "1-straight", duration_s=duration_s, rate_hz=rate_hz).recording


def write_csv(rec: Recording, path) -> None:
    """``rec`` as a point CSV (docs/input.md), every value written exactly (repr)."""
    header = ["time_s"] + [f"{n}_{a}" for n in rec.point_names for a in "xyz"]
    lines = ["# up_axis: z", ",".join(header)]
    for f in range(rec.n_frames):
        values = rec.positions_m[f].ravel()
        cells = [repr(float(rec.time_s[f]))] + ["" if np.isnan(v) else repr(float(v)) for v in values]
        lines.append(",".join(cells))
    path.write_text("\n".join(lines) + "\n")


def marker_info(pylsl, name, labels, *, rate_hz=100.0, unit="meters", up_axis="z", source_id=None, fmt=None):
    """A marker StreamInfo as another system might send it: labelled channels, a unit, an up axis."""
    info = pylsl.StreamInfo(
        name, "Mocap", len(labels), rate_hz, pylsl.cf_double64 if fmt is None else fmt, source_id or name
    )
    desc = info.desc()
    if labels and labels[0] is not None:
        channels = desc.append_child("channels")
        for label in labels:
            ch = channels.append_child("channel").append_child_value("label", label)
            if unit:
                ch.append_child_value("unit", unit)
    if up_axis:
        desc.append_child("setup").append_child_value("up_axis", up_axis)
    return info


def pelvis_labels(points=PELVIS):
    return [f"{p}_{a}" for p in points for a in "xyz"]


def pelvis_frames(rec: Recording, points=PELVIS) -> np.ndarray:
    """Frames x (3 per point) of ``rec``'s points, in the order of :func:`pelvis_labels`."""
    return rec.points(list(points)).reshape(rec.n_frames, -1)


class LiveThread:
    """run_live in a thread, its estimates collected; ``stop()`` ends it and returns the counters."""

    def __init__(self, source: str, **options):
        from yoyogait.live.live import run_live

        self.rows: list[list[float]] = []
        self.stamps: list[float] = []
        self.counters = None
        self.error: BaseException | None = None
        self._stop = threading.Event()
        hook = options.pop("on_estimate", None)

        def collect(row, stamp):
            self.rows.append(row)
            self.stamps.append(stamp)
            if hook is not None:
                hook(row, stamp)

        def body():
            try:
                self.counters = run_live(source, on_estimate=collect, stop=self._stop, **options)
            except BaseException as exc:  # reported by stop()
                self.error = exc

        self.thread = threading.Thread(target=body, daemon=True)
        self.thread.start()

    def wait_for(self, n: int, timeout_s: float = 10.0) -> None:
        end = time.monotonic() + timeout_s
        while len(self.rows) < n and time.monotonic() < end and self.thread.is_alive():
            time.sleep(0.01)

    def settle(self, quiet_s: float = 0.5, timeout_s: float = 10.0) -> None:
        """Wait until no estimate has come for ``quiet_s``."""
        end = time.monotonic() + timeout_s
        count = -1
        while time.monotonic() < end and self.thread.is_alive():
            if len(self.rows) == count:
                return
            count = len(self.rows)
            time.sleep(quiet_s)

    def stop(self, timeout_s: float = 10.0):
        self._stop.set()
        self.thread.join(timeout_s)
        if self.error is not None:
            raise self.error
        return self.counters


def replay_frames(pylsl, outlet, live: LiveThread, time_s, frames) -> float:
    """Once ``live`` has connected to ``outlet``, push every frame at the LSL clock now plus its time,
    wait for the estimates and stop the run; returns that clock (the frames' time zero)."""
    assert outlet.wait_for_consumers(10)
    base = pylsl.local_clock()
    for t_s, frame in zip(time_s, frames):
        outlet.push_sample(np.ravel(frame).tolist(), base + t_s)
    live.wait_for(len(frames))
    live.settle(0.3)
    live.stop()
    return base
