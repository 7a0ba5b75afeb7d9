"""The frame handling every live input shares (FrameGate): drops, jumps, restarts, bursts and missing frames."""

from __future__ import annotations

import math

from yoyogait.estimators.frame_gate import DROP, RESTART, USE, FrameGate


def _feed(gate, frames):
    return [gate.admit(t, a) for t, a in frames]


def test_repeated_late_and_non_finite_times_are_dropped_and_counted():
    """A repeated time, one older than the last used, NaN and inf: DROP each, counted as not increasing."""
    gate = FrameGate(100.0)
    got = _feed(gate, [(0.0, 0.0), (0.01, 0.01), (0.01, 0.02), (0.005, 0.03), (math.nan, 0.04), (math.inf, 0.05)])
    assert got == [USE, USE, DROP, DROP, DROP, DROP]
    assert gate.counts.dropped_not_increasing == 4 and gate.counts.estimates == 2


def test_one_wild_stamp_is_dropped_without_restart_and_a_confirmed_jump_back_restarts():
    """1e306 or 100 s back once: dropped (dropped_jumps), nothing reset; two frames agreeing on a jump back: RESTART."""
    gate = FrameGate(100.0, reacquire_after_s=2.0)
    frames = [(0.00, 0.00), (0.01, 0.01), (1e306, 0.02), (0.02, 0.03), (-99.97, 0.04), (0.03, 0.05)]
    assert _feed(gate, frames) == [USE, USE, DROP, USE, DROP, USE]
    assert gate.counts.dropped_jumps == 2 and gate.counts.restarts == 0 and gate.counts.missing_frames == 0
    assert _feed(gate, [(-50.0, 0.06), (-49.99, 0.07)]) == [DROP, RESTART]
    assert gate.counts.restarts == 1


def test_a_silence_restarts_and_a_confirmed_forward_jump_goes_on_counting_what_it_lost():
    """Silent for more than reacquire_after_s: RESTART; 10 s of frames lost in a buffer: USE, counted missing."""
    gate = FrameGate(100.0, reacquire_after_s=2.0)
    assert _feed(gate, [(0.0, 0.0), (0.01, 0.01), (5.0, 3.5)]) == [USE, USE, RESTART]
    gate = FrameGate(100.0, reacquire_after_s=2.0)
    assert _feed(gate, [(0.0, 0.0), (0.01, 0.01), (10.0, 0.02), (10.01, 0.03)]) == [USE, USE, DROP, USE]
    c = gate.counts
    assert c.restarts == 0 and c.dropped_jumps == 1 and c.missing_frames + c.dropped_jumps + c.estimates == 1002


def test_frames_faster_than_half_the_nominal_period_are_counted_as_a_burst():
    """At a nominal 100 Hz, frames 1 ms apart are bursts; 20 ms apart leave one frame missing."""
    gate = FrameGate(100.0)
    _feed(gate, [(0.0, 0.0), (0.001, 0.0), (0.002, 0.0), (0.022, 0.02)])
    assert gate.counts.burst_frames == 2 and gate.counts.missing_frames == 1


def test_huge_gaps_between_finite_times_count_without_overflow():
    """Times 1e300 apart (both finite, confirmed) count a bounded number of missing frames instead of raising."""
    gate = FrameGate(1e6, reacquire_after_s=1e308)
    _feed(gate, [(-1e300, 0.0), (1e300, 0.001)])
    assert gate.counts.estimates == 2 and gate.counts.missing_frames <= 10**9
