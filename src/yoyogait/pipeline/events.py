"""Gait events from the feet: contacts, steps, step frequency over time, walking or standing.

This is the reference the estimator's step frequency is scored against, so
it uses nothing the estimator uses (no pelvis velocity spectrum), only where
the feet are relative to the pelvis.

Contacts follow Zeni et al. (2008, Gait & Posture 27:710): a foot strikes
the ground when it is furthest ahead of the pelvis along the walking
heading.  That works overground, on curved paths (the heading follows the
pelvis) and on a treadmill (where the heading is the feet's main axis of
motion relative to the pelvis, pointed so that feet move backwards during
the longer stance phase).  With heel points this is heel strike; with ankle
or toe points it comes a little later in the step, which leaves step times
unchanged.

Steps are the intervals between consecutive contacts.  Two consecutive
contacts of the same foot (the other foot's was missed) are a stride and
count as two steps of half its length.  A run of at least ``min_steps``
steps each lasting ``min_step_s``-``max_step_s`` is walking; the rest is
standing (or shuffling).  Without feet, walking is where the pelvis moves
faster than ``walking_speed_mps`` for at least ``min_walk_s``.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np
from scipy.signal import find_peaks

from ..errors import InputError
from ..io.recording import AXES, Recording
from . import points
from .signals import fill_short_gaps, moving_mean, runs, walking_heading

__all__ = ["GaitEvents", "detect_gait_events", "feet_of", "foot_groups_of", "walking_mask", "walking_from_speed"]


@dataclass
class GaitEvents:
    """Foot contacts and steps of one recording (times in seconds of the recording's clock)."""

    contacts_s: np.ndarray  # every contact, sorted
    contact_sides: tuple[str, ...]  # "left" or "right" for each contact
    step_start_s: np.ndarray  # each step's first contact
    step_end_s: np.ndarray  # each step's next contact
    walking_segments_s: np.ndarray  # k x 2: each walking stretch, its steps plus half a step either side
    feet: dict = field(default_factory=dict)  # side -> point name used
    source: str = ""

    @property
    def step_time_s(self) -> np.ndarray:
        return self.step_end_s - self.step_start_s

    @property
    def step_frequency_hz(self) -> np.ndarray:
        """1 / step time of each step."""
        return 1.0 / self.step_time_s

    @property
    def walking_time_s(self) -> float:
        return (
            float(np.sum(self.walking_segments_s[:, 1] - self.walking_segments_s[:, 0]))
            if len(self.walking_segments_s)
            else 0.0
        )

    @property
    def mean_step_frequency_hz(self) -> float:
        """Steps per second over the steps taken (NaN without steps)."""
        total = float(np.sum(self.step_time_s))
        return len(self.step_start_s) / total if total > 0 else float("nan")

    def walking_mask(self, time_s) -> np.ndarray:
        """True at the times inside a walking stretch."""
        t = np.asarray(time_s, dtype=float)
        mask = np.zeros(t.shape, dtype=bool)
        for start, end in self.walking_segments_s:
            mask |= (t >= start) & (t <= end)
        return mask

    def step_frequency_at(self, time_s) -> np.ndarray:
        """The step frequency of the step under way at each time (NaN when standing)."""
        t = np.asarray(time_s, dtype=float)
        out = np.full(t.shape, np.nan)
        for start, end, f in zip(self.step_start_s, self.step_end_s, self.step_frequency_hz):
            out[(t >= start) & (t <= end)] = f
        return out


def detect_gait_events(
    recording: Recording,
    feet=None,
    *,
    up_axis: str | None = None,
    min_step_s: float = 0.25,
    max_step_s: float = 1.5,
    min_steps: int = 2,
    min_excursion_m: float = 0.05,
    max_gap_s: float = 0.2,
    heading_window_s: float = 1.0,
) -> GaitEvents:
    """Foot contacts and steps from foot points (heel, ankle, toe, foot).

    ``feet``: {"left": name or names, "right": ...} or a list of names (sides
    told by the names; one contact series per side); found by name when None.
    ``min_excursion_m``: how far a foot must swing ahead and back relative to
    the pelvis for a contact to count.  Steps outside
    ``min_step_s``-``max_step_s`` break a walking stretch.
    """

    where = recording.source or "recording"
    feet = feet_of(recording, feet)
    if not feet:
        raise InputError(f"{where}: no foot point (heel, ankle, toe, foot) found; pass feet=")
    up, _ = points.resolve_up_axis(recording, up_axis)
    k = AXES.index(up)
    horizontal = [a for a in range(3) if a != k]
    t = np.asarray(recording.time_s, dtype=float)
    rate = 1.0 / float(np.median(np.diff(t)))

    pelvis = fill_short_gaps(points.point_trajectory(recording, None).positions_m, rate, max_gap_s)[:, horizontal]
    relative = {
        side: fill_short_gaps(recording.point(name), rate, max_gap_s)[:, horizontal] - pelvis
        for side, name in feet.items()
    }
    heading = walking_heading(np.gradient(pelvis, axis=0) * rate, rate, heading_window_s)
    if heading is None:  # the pelvis stays in place: a treadmill
        heading = np.broadcast_to(_feet_axis(relative, rate), pelvis.shape)

    contact_list: list[float] = []
    side_list: list[str] = []
    for side, rel in relative.items():
        ahead = np.sum(rel * heading, axis=1)
        for start, stop in runs(np.isfinite(ahead)):
            peaks, _ = find_peaks(
                ahead[start:stop], distance=max(1, int(2 * min_step_s * rate)), prominence=min_excursion_m
            )
            contact_list.extend(t[start + peaks])
            side_list.extend([side] * len(peaks))
    order = np.argsort(contact_list, kind="stable")
    contacts = np.asarray(contact_list, dtype=float)[order]
    sides = tuple(np.asarray(side_list, dtype=object)[order]) if len(order) else ()

    starts, ends = _steps(contacts, sides, both_feet=len(feet) == 2, min_step_s=min_step_s, max_step_s=max_step_s)
    segments = _segments(starts, ends, min_steps)
    keep = np.zeros(len(starts), dtype=bool)
    for a, b in segments:
        keep |= (starts >= a) & (ends <= b)
    return GaitEvents(
        contacts_s=contacts,
        contact_sides=sides,
        step_start_s=starts[keep],
        step_end_s=ends[keep],
        walking_segments_s=_widen(segments, starts, ends, t[0], t[-1]),
        feet=dict(feet),
        source=where,
    )


def walking_mask(
    recording: Recording,
    time_s,
    *,
    speed_mps=None,
    rate_hz: float | None = None,
    up_axis: str | None = None,
    walking_speed_mps: float = 0.15,
    min_walk_s: float = 1.0,
    feet=None,
) -> np.ndarray:
    """Walking (True) or standing per time in ``time_s``.

    From gait events when the recording has feet (``feet``, else found by name)
    and a pelvis and some foot contact is found; else from ``speed_mps``
    (horizontal speed on the ``time_s`` grid, see :func:`walking_from_speed`).
    """
    return walking_mask_and_events(
        recording,
        time_s,
        speed_mps=speed_mps,
        rate_hz=rate_hz,
        up_axis=up_axis,
        walking_speed_mps=walking_speed_mps,
        min_walk_s=min_walk_s,
        feet=feet,
    )[0]


def walking_mask_and_events(
    recording: Recording,
    time_s,
    *,
    speed_mps=None,
    rate_hz: float | None = None,
    up_axis: str | None = None,
    walking_speed_mps: float = 0.15,
    min_walk_s: float = 1.0,
    feet=None,
) -> tuple[np.ndarray, GaitEvents | None]:
    """:func:`walking_mask`, and the gait events it found on the way (:func:`detect_gait_events` with
    ``feet`` and ``up_axis``; None when it did not look for them or found none), so that a caller
    needing them does not detect them again."""

    t = np.asarray(time_s, dtype=float)
    events = None
    if recording.velocities is None and feet is not None:
        feet_of(recording, feet)  # InputError naming a foot point that is not there
    if recording.velocities is None and (feet is not None or points.find_feet(recording.point_names)):
        try:
            events = detect_gait_events(recording, feet=feet, up_axis=up_axis)
        except InputError:
            events = None
        if events is not None and len(events.contacts_s) > 0:
            return events.walking_mask(t), events
    if speed_mps is None or rate_hz is None:
        return np.zeros(t.shape, dtype=bool), events
    return walking_from_speed(speed_mps, rate_hz, walking_speed_mps, min_walk_s), events


def walking_from_speed(
    speed_mps, rate_hz: float, walking_speed_mps: float = 0.15, min_walk_s: float = 1.0
) -> np.ndarray:
    """True where the speed averaged over ``min_walk_s`` exceeds ``walking_speed_mps`` for ``min_walk_s``."""
    n = max(1, int(round(min_walk_s * rate_hz)))
    mean = moving_mean(np.asarray(speed_mps, dtype=float), n)
    fast = np.nan_to_num(mean, nan=0.0) >= walking_speed_mps
    out = np.zeros(len(fast), dtype=bool)
    for a, b in runs(fast):
        if b - a >= n:
            out[a:b] = True
    return out


def feet_of(recording: Recording, feet=None) -> dict[str, str]:
    """The point of each foot used for contacts: side -> name (the first of :func:`foot_groups_of`)."""
    return {side: group[0] for side, group in foot_groups_of(recording, feet).items()}


def foot_groups_of(recording: Recording, feet=None) -> dict[str, list[str]]:
    """The points of each foot, by side, best first (heel, ankle, toe; well seen before rarely seen).

    ``feet``: None (found by name), ``{"left": [...], "right": [...]}`` (a name
    or a list per side), or a list of names whose sides are told by their names
    (heel, toe and ankle of one side are one foot).  A listed name whose side
    cannot be told is an error: a contact series needs a side.
    """
    names = recording.point_names
    visibility = dict(zip(names, recording.visible().mean(axis=0))) if names else {}
    if feet is None:
        return points.find_foot_groups(names, visibility)
    if isinstance(feet, dict):
        given = {}
        for side, value in feet.items():
            listed = [value] if isinstance(value, str) else [n for n in (value or []) if n]
            if listed:
                given[_side_key(side)] = listed
    else:
        listed = [feet] if isinstance(feet, str) else list(feet)
        given = {}
        for name in listed:
            side = points.side_of(name)
            if side is None:
                raise InputError(
                    f"feet={name}: cannot tell which foot {name!r} belongs to, its name says neither left nor right; "
                    'give heel, ankle or toe points named by side (LHEE, R_Heel) or {"left": [...], "right": [...]}'
                )
            given.setdefault(side, []).append(name)
    for group in given.values():
        for name in group:
            recording.index_of(name)  # InputError listing the points there are
    out = {}
    for side, group in given.items():
        ranked = points.find_foot_groups(group, visibility).get(side, []) if side in points.SIDES else []
        ranked = [n for n in ranked if n in group]
        rest = sorted((n for n in group if n not in ranked), key=lambda n: -visibility.get(n, 0.0))
        out[side] = ranked + rest
    return out


def _side_key(side) -> str:
    s = str(side).lower()
    return "left" if s in ("l", "left") else "right" if s in ("r", "right") else str(side)


def _feet_axis(relative: dict[str, np.ndarray], rate_hz: float) -> np.ndarray:
    """Main horizontal axis of the feet's motion relative to the pelvis, pointing forward.

    Forward is where the feet move the faster way: they swing forward quickly
    and drift back during the longer stance, so the median relative velocity
    along the forward axis is negative.
    """
    stacked = np.vstack([r for r in relative.values()])
    ok = np.all(np.isfinite(stacked), axis=1)
    if ok.sum() < 3:
        return np.array([1.0, 0.0])
    _, _, vt = np.linalg.svd(stacked[ok] - stacked[ok].mean(axis=0), full_matrices=False)
    axis = vt[0]
    velocity = np.vstack([np.gradient(r, axis=0) * rate_hz for r in relative.values()]) @ axis
    return -axis if np.nanmedian(velocity) > 0 else axis


def _steps(contacts, sides, *, both_feet: bool, min_step_s: float, max_step_s: float):
    """Step intervals from consecutive contacts; a stride (same foot twice) counts as two half steps."""
    starts, ends = [], []
    for i in range(len(contacts) - 1):
        a, b = contacts[i], contacts[i + 1]
        n = 1 if (both_feet and sides[i] != sides[i + 1]) else 2
        if not min_step_s <= (b - a) / n <= max_step_s:
            continue
        if n == 1:
            starts.append(a)
            ends.append(b)
        else:
            mid = 0.5 * (a + b)
            starts += [a, mid]
            ends += [mid, b]
    return np.asarray(starts, dtype=float), np.asarray(ends, dtype=float)


def _widen(segments, starts, ends, t_first: float, t_last: float) -> np.ndarray:
    """Each walking stretch widened by half a step at either end (k x 2).

    The walk goes on for part of a step before the first contact seen and
    after the last one; half a mean step, kept inside the recording and
    clear of the neighbouring stretch, is that part.
    """
    out: list[tuple[float, float]] = []
    for i, (a, b) in enumerate(segments):
        inside = (starts >= a) & (ends <= b)
        half = 0.5 * float(np.mean(ends[inside] - starts[inside]))
        lo = max(t_first, a - half, out[-1][1] if out else -np.inf)
        hi = min(t_last, b + half, segments[i + 1][0] if i + 1 < len(segments) else np.inf)
        out.append((lo, hi))
    return np.asarray(out, dtype=float).reshape(-1, 2)


def _segments(starts, ends, min_steps: int) -> list[tuple[float, float]]:
    """Stretches of back-to-back steps, at least ``min_steps`` long."""
    segments = []
    i = 0
    while i < len(starts):
        j = i
        while j + 1 < len(starts) and starts[j + 1] == ends[j]:
            j += 1
        if j - i + 1 >= min_steps:
            segments.append((float(starts[i]), float(ends[j])))
        i = j + 1
    return segments
