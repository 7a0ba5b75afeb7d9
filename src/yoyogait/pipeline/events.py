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
count as two steps of half its length; a contact that splits one typical
step into two short ones (a doubled contact) is dropped.  A run of at
least ``min_steps`` steps each lasting ``min_step_s``-``max_step_s`` is
walking (down to 0.4 steps/s: 0.3 m/s walking); the walk is widened by a
step either side (gait initiation before the first contact seen,
termination after the last).  The rest is standing (or shuffling).
Without feet, walking is where the pelvis moves faster than
``walking_speed_mps`` for at least ``min_walk_s``.

The foot points are heel first (then ankle, then toe), so contacts are heel
strikes wherever a heel marker is seen.  A file's own gait events (a C3D
``EVENT`` group, a Nexus ``Events`` section: ``metadata["events"]``) are
the reference where they hold enough foot strikes
(:func:`file_gait_events`).

Every reference carries a quality (:func:`reference_quality`): how many
steps it has, how well the left and the right foot's strides agree, and how
well its cadence agrees with the DFT of the vertical velocity over the same
walk; a reference that fails one of these is not trusted.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from ..errors import InputError
from ..io.recording import AXES, Recording
from . import points, spectral
from .signals import fill_short_gaps, moving_mean, runs, walking_heading

__all__ = [
    "GaitEvents",
    "ReferenceQuality",
    "detect_gait_events",
    "file_gait_events",
    "reference_events",
    "reference_quality",
    "feet_of",
    "foot_groups_of",
    "walking_mask",
    "walking_from_speed",
    "MIN_TRUSTED_STEPS",
    "MAX_LEFT_RIGHT_HZ",
    "MAX_DFT_DISAGREEMENT_HZ",
]

#: The longest step that is still walking (0.4 steps/s: about 0.3 m/s).
MAX_STEP_S = 2.5
#: A reference is trusted with at least this many steps ...
MIN_TRUSTED_STEPS = 4
#: ... the step frequencies of the left and the right foot's strides within this ...
MAX_LEFT_RIGHT_HZ = 0.1
#: ... and its cadence within this of the DFT of the vertical velocity over the same walk.
MAX_DFT_DISAGREEMENT_HZ = 0.05


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
    origin: str = "foot contacts"  # "foot contacts" (from the foot points) or "file events"
    dropped_contacts: int = 0  # contacts dropped as doubled

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

    def step_frequency_at(self, time_s, *, stride_average: bool = False) -> np.ndarray:
        """The step frequency of the step under way at each time (NaN when standing).

        With ``stride_average`` each step's time is first replaced by 0.5 * its own + 0.25 * each
        neighbour's (where the neighbours are back-to-back steps): left-right asymmetry makes step
        times alternate at a constant cadence, and this takes the alternation out while following
        a changing cadence.  Built from the steps, a missed contact (a stride, two half steps) or a
        doubled one (dropped) does not halve or double the frequency.
        """
        t = np.asarray(time_s, dtype=float)
        out = np.full(t.shape, np.nan)
        step = self.step_time_s
        if stride_average and len(step) >= 2:
            prev_ok = np.concatenate([[False], self.step_start_s[1:] == self.step_end_s[:-1]])
            next_ok = np.concatenate([self.step_start_s[1:] == self.step_end_s[:-1], [False]])
            prev = np.concatenate([[np.nan], step[:-1]])
            nxt = np.concatenate([step[1:], [np.nan]])
            both = prev_ok & next_ok
            step = np.where(
                both,
                0.5 * step + 0.25 * (np.nan_to_num(prev) + np.nan_to_num(nxt)),
                np.where(
                    prev_ok,
                    0.5 * (step + np.nan_to_num(prev)),
                    np.where(next_ok, 0.5 * (step + np.nan_to_num(nxt)), step),
                ),
            )
        for start, end, dt in zip(self.step_start_s, self.step_end_s, step):
            out[(t >= start) & (t <= end)] = 1.0 / dt
        return out

    def side_step_frequency_hz(self, side: str) -> float:
        """Twice the stride frequency of one foot (its consecutive contacts 2-5 steps' median apart); NaN
        without two strides."""
        c = np.asarray([t for t, s in zip(self.contacts_s, self.contact_sides) if s == side], dtype=float)
        if len(c) < 3 or not len(self.step_start_s):
            return float("nan")
        typical = float(np.median(self.step_time_s))
        stride = np.diff(c)
        stride = stride[(stride >= 1.5 * typical) & (stride <= 2.5 * typical)]
        return 2.0 / float(np.median(stride)) if len(stride) >= 2 else float("nan")


@dataclass(frozen=True)
class ReferenceQuality:
    """How far a foot-contact reference can be trusted.

    ``origin``: "file events" or "foot contacts"; ``steps``: steps in its walking stretches;
    ``cadence_hz``: steps per second over the steps of the stretch the DFT covers;
    ``left_right_hz``: |left - right| step frequency from each foot's strides (NaN with one foot);
    ``dft_hz``: the step frequency by the DFT of the vertical velocity over that stretch
    (:func:`yoyogait.pipeline.spectral.step_frequency`); ``dft_disagreement_hz``: |cadence - DFT|;
    ``dropped_contacts``: doubled contacts left out; ``gaps``: breaks in the steps shorter than three
    steps, where the walk went on but the contacts there make no step (the reference is NaN there, so
    those stretches are left out of every score). ``trusted`` when there are at least
    :data:`MIN_TRUSTED_STEPS` steps, the feet agree within :data:`MAX_LEFT_RIGHT_HZ` and the DFT
    within :data:`MAX_DFT_DISAGREEMENT_HZ`; ``reason`` says which failed ("" when trusted).
    """

    origin: str
    steps: int
    cadence_hz: float
    left_right_hz: float
    dft_hz: float
    dft_disagreement_hz: float
    dropped_contacts: int
    trusted: bool
    reason: str
    gaps: int = 0

    def summary(self) -> str:
        """One line: trusted or not (why), with the numbers behind it."""
        lr = "" if not np.isfinite(self.left_right_hz) else f", left-right {self.left_right_hz:.3f} Hz"
        dft = "" if not np.isfinite(self.dft_hz) else f", DFT {self.dft_hz:.2f} Hz"
        head = "trusted" if self.trusted else f"not trusted ({self.reason})"
        gaps = f", {self.gaps} gap{'s' if self.gaps != 1 else ''} left out" if self.gaps else ""
        return f"{head}: {self.origin}, {self.steps} steps, {self.cadence_hz:.2f} Hz{lr}{dft}{gaps}"

    def as_row(self) -> dict:
        """The columns of recordings.csv."""
        return {
            "reference_origin": self.origin,
            "reference_trusted": self.trusted,
            "reference_steps": self.steps,
            "reference_cadence_hz": self.cadence_hz,
            "reference_left_right_hz": self.left_right_hz,
            "reference_dft_hz": self.dft_hz,
            "reference_dft_disagreement_hz": self.dft_disagreement_hz,
            "reference_dropped_contacts": self.dropped_contacts,
            "reference_gaps": self.gaps,
            "reference_reason": self.reason,
        }


NO_REFERENCE = ReferenceQuality(
    "none", 0, float("nan"), float("nan"), float("nan"), float("nan"), 0, False, "no foot contacts"
)


def detect_gait_events(
    recording: Recording,
    feet=None,
    *,
    up_axis: str | None = None,
    min_step_s: float = 0.25,
    max_step_s: float = MAX_STEP_S,
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

    from scipy.signal import find_peaks  # scipy.signal takes about a second to import: only where it is used

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
    seen = [(float(t[a]), float(t[b - 1])) for a, b in runs(np.all(np.isfinite(pelvis), axis=1))]
    return _events_from_contacts(
        contact_list,
        side_list,
        both_feet=len(feet) == 2,
        min_step_s=min_step_s,
        max_step_s=max_step_s,
        min_steps=min_steps,
        t_first=float(t[0]),
        t_last=float(t[-1]),
        feet=dict(feet),
        source=where,
        origin="foot contacts",
        seen_s=seen,
    )


def _events_from_contacts(
    contact_list,
    side_list,
    *,
    both_feet,
    min_step_s,
    max_step_s,
    min_steps,
    t_first,
    t_last,
    feet,
    source,
    origin,
    seen_s=None,
) -> GaitEvents:
    order = np.argsort(contact_list, kind="stable")
    contacts = np.asarray(contact_list, dtype=float)[order]
    sides = tuple(np.asarray(side_list, dtype=object)[order]) if len(order) else ()
    contacts, sides, dropped = _drop_doubled(contacts, sides, min_step_s, max_step_s)
    starts, ends = _steps(contacts, sides, both_feet=both_feet, min_step_s=min_step_s, max_step_s=max_step_s)
    segments = _segments(starts, ends, min_steps)
    keep = np.zeros(len(starts), dtype=bool)
    for a, b in segments:
        keep |= (starts >= a) & (ends <= b)
    return GaitEvents(
        contacts_s=contacts,
        contact_sides=sides,
        step_start_s=starts[keep],
        step_end_s=ends[keep],
        walking_segments_s=_widen(segments, starts, ends, t_first, t_last, seen_s),
        feet=feet,
        source=source,
        origin=origin,
        dropped_contacts=dropped,
    )


def file_gait_events(
    recording: Recording,
    *,
    min_step_s: float = 0.25,
    max_step_s: float = MAX_STEP_S,
    min_steps: int = 2,
) -> GaitEvents | None:
    """The gait events a file holds (its foot strikes, ``metadata["events"]``), as :class:`GaitEvents`;
    None with fewer than three foot strikes of known side inside the recording."""
    t = np.asarray(recording.time_s, dtype=float)
    held = recording.metadata.get("events") or []
    strikes = [
        (float(time), side)
        for side, kind, time in held
        if kind == "foot strike" and side in points.SIDES and t[0] <= time <= t[-1]
    ]
    if len(strikes) < 3:
        return None
    sides_seen = {side for _, side in strikes}
    return _events_from_contacts(
        [c for c, _ in strikes],
        [s for _, s in strikes],
        both_feet=len(sides_seen) == 2,
        min_step_s=min_step_s,
        max_step_s=max_step_s,
        min_steps=min_steps,
        t_first=float(t[0]),
        t_last=float(t[-1]),
        feet={},
        source=recording.source or "recording",
        origin="file events",
    )


def reference_events(recording: Recording, feet=None, *, up_axis: str | None = None) -> GaitEvents | None:
    """The gait events a reference is built from: the file's own (:func:`file_gait_events`) when it holds
    enough foot strikes, else the foot contacts (:func:`detect_gait_events`) of ``feet``, or of the feet
    found by name when those give no step; None without any."""
    own = file_gait_events(recording)
    if own is not None and len(own.step_start_s) >= MIN_TRUSTED_STEPS - 1:
        return own
    found = None
    try:
        found = detect_gait_events(recording, feet=feet, up_axis=up_axis)
    except InputError:
        pass
    if feet is not None and (found is None or len(found.step_start_s) == 0):
        # the named feet give no step (a heel marker rarely seen): the feet found by name, best seen first
        try:
            found = detect_gait_events(recording, feet=None, up_axis=up_axis)
        except InputError:
            pass
    return found if found is not None else own


def reference_quality(ev: GaitEvents | None, time_s, vz_mps, rate_hz: float) -> ReferenceQuality:
    """How far the reference of ``ev`` can be trusted (:class:`ReferenceQuality`).

    ``time_s``, ``vz_mps``: the vertical velocity on a uniform grid at ``rate_hz``, whose DFT over the
    longest walking stretch of ``ev`` is set against the cadence of the steps in that stretch.
    """
    if ev is None or len(ev.contacts_s) < 2:
        return NO_REFERENCE
    steps = len(ev.step_start_s)
    if steps == 0:
        return ReferenceQuality(
            ev.origin, 0, float("nan"), float("nan"), float("nan"), float("nan"), ev.dropped_contacts, False, "no steps"
        )
    t = np.asarray(time_s, dtype=float)
    vz = np.asarray(vz_mps, dtype=float)
    segments = np.asarray(ev.walking_segments_s).reshape(-1, 2)
    a, b = max(segments, key=lambda s: s[1] - s[0])
    inside = (ev.step_start_s >= a) & (ev.step_end_s <= b)
    total = float(np.sum(ev.step_time_s[inside]))
    cadence = int(inside.sum()) / total if total > 0 else float("nan")
    # The DFT over the walking stretch, as the evaluation scores it (its steps and a step either side).
    span = (t >= a) & (t <= b) & np.isfinite(vz)
    dft = float("nan")
    if span.sum() >= max(8, int(1.5 * rate_hz)):
        try:
            dft = spectral.step_frequency(vz[span], rate_hz, min_hz=0.3, max_hz=4.0)
        except (InputError, ValueError):
            dft = float("nan")
    sides = {s for s in ev.contact_sides}
    lr = (
        abs(ev.side_step_frequency_hz("left") - ev.side_step_frequency_hz("right"))
        if sides >= {"left", "right"}
        else float("nan")
    )
    disagreement = abs(cadence - dft) if np.isfinite(dft) else float("nan")
    reasons = []
    if steps < MIN_TRUSTED_STEPS:
        reasons.append(f"{steps} steps, fewer than {MIN_TRUSTED_STEPS}")
    if np.isfinite(lr) and lr > MAX_LEFT_RIGHT_HZ:
        reasons.append(f"left and right strides differ by {lr:.2f} Hz")
    if not np.isfinite(disagreement):
        reasons.append("no DFT over its walk")
    elif disagreement > MAX_DFT_DISAGREEMENT_HZ:
        reasons.append(f"cadence {cadence:.2f} Hz, DFT of the vertical velocity {dft:.2f} Hz")
    return ReferenceQuality(
        ev.origin,
        steps,
        cadence,
        lr,
        dft,
        disagreement,
        ev.dropped_contacts,
        not reasons,
        "; ".join(reasons),
        gaps=_gaps(ev),
    )


def _gaps(ev: GaitEvents) -> int:
    """Breaks in the steps shorter than three typical steps: the walk went on but no step could be made of
    the contacts there (a missed pair, a misplaced contact)."""
    starts, ends = np.asarray(ev.step_start_s, dtype=float), np.asarray(ev.step_end_s, dtype=float)
    if len(starts) < 2:
        return 0
    typical = float(np.median(ends - starts))
    pause = starts[1:] - ends[:-1]
    return int(np.sum((pause > 1e-9) & (pause < 3.0 * typical)))


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


def _drop_doubled(contacts, sides, min_step_s: float, max_step_s: float):
    """Contacts without the doubled ones: a contact closer than half a typical step to its neighbour,
    whose removal leaves a step of typical length, is dropped (the one that keeps the feet alternating).
    Returns the contacts, their sides and how many were dropped."""
    c = list(map(float, contacts))
    s = list(sides)
    dropped = 0
    while len(c) >= 3:
        d = np.diff(c)
        ok = d[(d >= min_step_s) & (d <= max_step_s)]
        if len(ok) < 2:
            break
        typical = float(np.median(ok))
        short = [i for i in range(len(d)) if d[i] < 0.5 * typical]
        if not short:
            break
        i = short[0]  # contacts i and i + 1 are too close: drop one of them

        def cost(k: int, typical: float = typical) -> float:
            left = c[k - 1] if k > 0 else None
            right = c[k + 1] if k + 1 < len(c) else None
            if left is None or right is None:
                return 0.5  # an end contact: dropping it leaves no step to judge
            merged = right - left
            alternate = s[k - 1] != s[k + 1]
            return abs(merged / typical - 1.0) + (0.0 if alternate else 0.25)

        k = i if cost(i) <= cost(i + 1) else i + 1
        del c[k]
        del s[k]
        dropped += 1
    return np.asarray(c, dtype=float), tuple(s), dropped


def _steps(contacts, sides, *, both_feet: bool, min_step_s: float, max_step_s: float):
    """Step intervals from consecutive contacts, with the steps missed between them.

    Each interval is judged against the typical stride around it (the median of the sums of two
    neighbouring intervals between alternating feet, so that asymmetric gait, long and short steps
    in turn, is one stride): between opposite feet, an interval shorter than a stride is one step and
    one of 1.25-1.75 strides is three (two contacts missed in a row); between the same foot, one of
    0.75-1.25 strides is two steps (a missed contact).  Anything else, or a step outside
    ``min_step_s``-``max_step_s``, is not walking.  With one foot only every interval is a stride.
    """
    starts: list[float] = []
    ends: list[float] = []
    c = np.asarray(contacts, dtype=float)
    d = np.diff(c)
    if len(d) == 0:
        return np.asarray(starts), np.asarray(ends)
    alternating = np.array([both_feet and sides[i] != sides[i + 1] for i in range(len(d))])
    plain = alternating & (d >= min_step_s) & (d <= max_step_s)
    pairs = np.full(len(d), np.nan)
    for j in range(len(d) - 1):
        if plain[j] and plain[j + 1]:
            pairs[j] = d[j] + d[j + 1]
    for i in range(len(d)):
        near = pairs[max(0, i - 5) : i + 5]
        near = near[np.isfinite(near)]
        if len(near) >= 2:
            stride = float(np.median(near))
        else:
            stride = 2.0 * d[i] if alternating[i] else d[i]  # too few neighbours: take it as it is
        if not stride > 0.0:  # two contacts at one time: no interval to split
            continue
        ratio = d[i] / stride
        if alternating[i]:
            n = 1 if ratio < 1.0 else 3 if 1.25 <= ratio <= 1.75 else 0
        else:
            n = 2 if 0.75 <= ratio <= 1.25 else 0
        if n == 0 or not (min_step_s <= d[i] / n <= max_step_s):
            continue
        step = d[i] / n
        for k in range(n):
            starts.append(float(c[i] + k * step))
            ends.append(float(c[i] + (k + 1) * step))
    return np.asarray(starts, dtype=float), np.asarray(ends, dtype=float)


def _widen(segments, starts, ends, t_first: float, t_last: float, seen_s=None) -> np.ndarray:
    """Each walking stretch widened by a step at either end (k x 2).

    The walk starts (gait initiation: the first swing) about a step before
    the first contact seen, and ends (termination: the trailing foot's last
    swing) about a step after the last one; a mean step, kept inside the
    recording, inside the time the pelvis is seen (``seen_s``: its runs,
    (start, end) in s) and clear of the neighbouring stretch, is that part.
    """
    out: list[tuple[float, float]] = []
    for i, (a, b) in enumerate(segments):
        inside = (starts >= a) & (ends <= b)
        step = float(np.mean(ends[inside] - starts[inside]))
        first, last = t_first, t_last
        for run_start, run_end in seen_s or ():
            if run_start <= a <= run_end:
                first = max(first, run_start)
            if run_start <= b <= run_end:
                last = min(last, run_end)
        lo = max(first, a - step, out[-1][1] if out else -np.inf)
        hi = min(last, b + step, 0.5 * (b + segments[i + 1][0]) if i + 1 < len(segments) else np.inf)
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
