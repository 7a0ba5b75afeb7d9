"""Which frames of a live source reach the online estimator: the real-condition handling that every live
input (an LSL marker stream, ROS 2 topics) shares.

:class:`FrameGate` looks at each frame's time (the source's stamp) and its arrival time (this machine's
monotonic clock) and says whether to use it, drop it, or start the estimator over first:

* a time that is not finite, or does not increase (a repeated, out-of-order or late frame), is
  dropped and counted (``dropped_not_increasing``);
* a time that jumps (back, or forward by more than its arrival moved) by more than
  ``reacquire_after_s`` is held as a candidate and dropped (``dropped_jumps``): one wild stamp (a
  sample 100 s in the past, a time of 1e306) neither resets the estimator nor blocks the frames after
  it. When the next frame continues from the candidate, the source did jump: back (it restarted, its
  clock was reset), the estimator starts over (``restarts``); forward (frames lost on the way, say a
  consumer that fell behind a bounded buffer), the estimator goes on and bridges the gap;
* after a silence of more than ``reacquire_after_s`` (by arrival) the estimator starts over
  (``restarts``): the source came back;
* with a nominal rate, the frames absent between two used frames are counted (``missing_frames``),
  and frames closer than half a period to the previous one (a burst: a source that sends a backlog at
  once) are counted (``burst_frames``).

Nothing is kept but the last frame, so memory does not grow with time.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

__all__ = ["FrameCounts", "FrameGate", "USE", "DROP", "RESTART"]

DROP = 0
USE = 1
RESTART = 2  # start the estimator over, then use the frame

#: Counted as missing between two frames at most (a gap longer than this is a restart anyway).
_MAX_MISSING_PER_GAP = 10**9


@dataclass
class FrameCounts:
    """What a live input saw; every count since the start."""

    frames: int = 0  # frames received
    estimates: int = 0  # frames used (one estimate each)
    dropped_not_increasing: int = 0  # repeated, out-of-order, late or non-finite times, dropped
    dropped_jumps: int = 0  # times that jumped by more than reacquire_after_s, dropped (one restart if confirmed)
    missing_frames: int = 0  # frames absent by the nominal rate
    burst_frames: int = 0  # frames closer than half the nominal period to the previous one
    restarts: int = 0  # the estimator started over (a silence, or a confirmed jump)


class FrameGate:
    """The decision for each frame (``admit``), counted in ``counts``."""

    def __init__(self, nominal_rate_hz: float = 0.0, reacquire_after_s: float = 2.0, counts: FrameCounts | None = None):
        if not (math.isfinite(reacquire_after_s) and reacquire_after_s > 0):
            raise ValueError(f"reacquire_after_s must be a positive number of seconds, not {reacquire_after_s!r}")
        rate = float(nominal_rate_hz)
        self.period_s = 1.0 / rate if math.isfinite(rate) and rate > 0 else 0.0
        self.reacquire_after_s = float(reacquire_after_s)
        self.counts = counts if counts is not None else FrameCounts()
        self.reset()

    def reset(self) -> None:
        """Forget the last frame (the next one starts afresh, as the first)."""
        self._last_t = -math.inf
        self._last_arrival: float | None = None
        self._candidate: tuple[float, float] | None = None  # (time, arrival) of a jump not yet confirmed

    def admit(self, t_s: float, arrival_s: float) -> int:
        """USE, DROP or RESTART (start the estimator over, then use) for a frame at ``t_s`` arrived at
        ``arrival_s``; counts it."""
        c = self.counts
        c.frames += 1
        if not math.isfinite(t_s):
            c.dropped_not_increasing += 1
            return DROP
        restart = False
        lost = 0
        last_arrival, self._last_arrival = self._last_arrival, arrival_s
        if self._last_t > -math.inf:
            assert last_arrival is not None
            if arrival_s - last_arrival > self.reacquire_after_s:
                restart = True  # the source was silent and came back
            else:
                moved_s = max(0.0, arrival_s - last_arrival)
                jump_s = t_s - self._last_t
                if jump_s < -self.reacquire_after_s or jump_s > moved_s + self.reacquire_after_s:
                    candidate, self._candidate = self._candidate, (t_s, arrival_s)
                    follows = (
                        candidate is not None
                        and 0.0 < t_s - candidate[0] <= (arrival_s - candidate[1]) + self.reacquire_after_s
                    )
                    if not follows:
                        c.dropped_jumps += 1
                        return DROP
                    # Two frames agree: the source's time did jump. Back: start over. Forward: go on; the
                    # candidate, dropped, is not counted missing as well.
                    restart = jump_s < 0
                    lost = 1
        self._candidate = None
        if restart:
            self._last_t = -math.inf
            if c.estimates > 0:
                c.restarts += 1
        if not t_s > self._last_t:
            c.dropped_not_increasing += 1
            return DROP
        if self.period_s and self._last_t > -math.inf:
            gap = (t_s - self._last_t) / self.period_s
            if gap < 0.5:
                c.burst_frames += 1
            elif math.isfinite(gap):
                c.missing_frames += max(0, min(_MAX_MISSING_PER_GAP, round(gap) - 1 - lost))
        self._last_t = t_s
        c.estimates += 1
        return RESTART if restart else USE
