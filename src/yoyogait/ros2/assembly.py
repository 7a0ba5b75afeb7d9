"""Frames of k points from messages that arrive one point at a time (one ``PointStamped`` topic per marker).

A frame is the k points of one stamp. :class:`FrameAssembler` keeps the stamps not yet complete
(at most ``max_pending``) and hands out a frame, in stamp order:

* as soon as every point of its stamp has arrived;
* or, incomplete (NaN for the points that did not come, as a marker the camera lost), when a newer
  stamp completes, when it is older than ``window_s`` by arrival (:meth:`expire`, called by a
  timer), or when more than ``max_pending`` stamps wait;

A point for a stamp already handed out (late, out of order) or a second point of one topic for one
stamp (repeated) is dropped and counted. With ``by_arrival`` (the drivers that do not stamp), the
stamp is ignored: a frame is the points since the last frame, closed when a topic sends its second
point, when all k have come, or after ``window_s``; its time is the arrival of its first point.
"""

from __future__ import annotations

import math
from collections.abc import Hashable
from dataclasses import dataclass, field

import numpy as np

__all__ = ["FrameAssembler", "AssembledFrame"]


@dataclass
class AssembledFrame:
    """One frame: its key (the stamp), time [s], the points (k x 3, NaN where absent) and the first arrival."""

    key: Hashable
    t_s: float
    positions: np.ndarray
    first_arrival_s: float
    seen: np.ndarray = field(repr=False)

    @property
    def complete(self) -> bool:
        return bool(self.seen.all())


class FrameAssembler:
    """Points in (``add``), frames out, in order of their stamps."""

    def __init__(self, n_points: int, window_s: float = 0.05, max_pending: int = 32, by_arrival: bool = False):
        if n_points < 1:
            raise ValueError("a frame has at least one point")
        if not (math.isfinite(window_s) and window_s > 0):
            raise ValueError(f"window_s must be a positive number of seconds, not {window_s!r}")
        self.n_points = n_points
        self.window_s = float(window_s)
        self.max_pending = max(1, int(max_pending))
        self.by_arrival = by_arrival
        self._pending: dict[Hashable, AssembledFrame] = {}
        self._last_out_t = -math.inf
        self._serial = 0
        self.late_points = 0  # points of a stamp already handed out, dropped
        self.repeated_points = 0  # a second point of one topic for one stamp, dropped
        self.incomplete_frames = 0  # frames handed out with points missing

    def add(self, index: int, key: Hashable, t_s: float, point: np.ndarray, arrival_s: float) -> list[AssembledFrame]:
        """Point ``index`` (0..k-1) of the stamp ``key`` (time ``t_s``); the frames now ready, in order."""
        out: list[AssembledFrame] = []
        if self.by_arrival:
            open_frame = next(iter(self._pending.values()), None)
            if open_frame is not None and open_frame.seen[index]:
                out.extend(self._pop_until(open_frame.key))
                open_frame = None
            if open_frame is None:
                self._serial += 1
                key, t_s = self._serial, arrival_s
            else:
                key = open_frame.key
        elif t_s <= self._last_out_t:
            self.late_points += 1
            return out
        frame = self._pending.get(key)
        if frame is None:
            empty = np.full((self.n_points, 3), np.nan)
            frame = AssembledFrame(key, t_s, empty, arrival_s, np.zeros(self.n_points, bool))
            self._pending[key] = frame
        if frame.seen[index]:
            self.repeated_points += 1
            return out
        frame.positions[index] = point
        frame.seen[index] = True
        if frame.complete:
            out.extend(self._pop_until(key))
        elif len(self._pending) > self.max_pending:
            oldest = min(self._pending.values(), key=lambda f: f.t_s)
            out.extend(self._pop_until(oldest.key))
        return out

    def expire(self, now_s: float) -> list[AssembledFrame]:
        """The frames waiting longer than ``window_s`` since their first point (and those before them)."""
        old = [f for f in self._pending.values() if now_s - f.first_arrival_s > self.window_s]
        if not old:
            return []
        return self._pop_until(max(old, key=lambda f: f.t_s).key)

    def _pop_until(self, key: Hashable) -> list[AssembledFrame]:
        """The frame ``key`` and every frame stamped before it, in stamp order."""
        limit = self._pending[key].t_s
        ready = sorted((f for f in self._pending.values() if f.t_s <= limit), key=lambda f: f.t_s)
        for f in ready:
            del self._pending[f.key]
            if not f.complete:
                self.incomplete_frames += 1
        self._last_out_t = max(self._last_out_t, limit)
        return ready
