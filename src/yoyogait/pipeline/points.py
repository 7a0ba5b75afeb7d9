"""Which point of a recording to follow, and which axis is up.

* The **pelvis centre** (the default, the closest marker-based stand-in for the
  centre of mass the Yoyo-model describes): the average of the pelvis
  markers found by name (ASIS, PSIS, sacrum and pelvis clusters in their
  common spellings), else a root joint (Hips, pelvis, root).  The names are
  data, not code: ``io/marker_sets.json`` (Plug-in Gait, IOR, ISB, Xsens,
  OpenCap, MoCap Toolbox, Qualisys, OptiTrack), extended by the files named
  in ``$YOYOGAIT_MARKER_SETS`` or given to :func:`add_marker_sets`.
* The **hand** (the paper follows the hand that holds the tether): a hand
  joint or finger marker, else the wrist markers of that side averaged.
* The **feet** (for gait events), grouped by side: heel, ankle and toe of one
  side are one foot; its heel is used, else its ankle, else its toe.
* The **up axis**: the override, else the file's, else detected from the
  data (:func:`detect_up_axis`).

Averaging markers that drop out one at a time would make the centre jump at
every drop-out by the missing marker's offset; :func:`robust_centre` instead
carries each marker's offset from the centre across its gaps.
"""

from __future__ import annotations

import contextvars
from contextlib import contextmanager
from dataclasses import dataclass

import numpy as np

from ..errors import InputError
from ..io.body import (
    PointChoice,
    UpAxisEvidence,
    axis_index,
    detect_up_axis,
    find_feet,
    find_foot_groups,
    find_hand,
    find_pelvis,
    resolve_up_axis,
    robust_centre,
    side_of,
    up_axis_evidence,
)
from ..io.marker_sets import (
    FOOT_KINDS,
    HAND_KINDS,
    MARKER_SETS_ENV,
    SIDES,
    add_marker_sets,
    marker_knowledge,
    normalise_name,
)
from ..io.recording import Recording

__all__ = [
    "PointChoice",
    "PointTrajectory",
    "reusing_trajectories",
    "normalise_name",
    "find_pelvis",
    "find_hand",
    "find_feet",
    "find_foot_groups",
    "side_of",
    "add_marker_sets",
    "marker_knowledge",
    "MARKER_SETS_ENV",
    "FOOT_KINDS",
    "HAND_KINDS",
    "SIDES",
    "choose_point",
    "point_trajectory",
    "robust_centre",
    "detect_up_axis",
    "up_axis_evidence",
    "UpAxisEvidence",
    "resolve_up_axis",
    "axis_index",
]


@dataclass
class PointTrajectory:
    """The followed point over time: frames x 3 in metres, NaN where unknown."""

    positions_m: np.ndarray
    choice: PointChoice
    used_names: tuple[str, ...]  # the markers the centre was built from (may drop a rarely seen one)

    @property
    def label(self) -> str:
        if self.used_names != self.choice.names:
            dropped = [n for n in self.choice.names if n not in self.used_names]
            return f"{self.choice.label} (without {', '.join(dropped)}: too rarely visible)"
        return self.choice.label


def choose_point(rec: Recording, point=None, *, hand_side: str = "right") -> PointChoice:
    """What to follow: None or "pelvis" (the pelvis centre), "hand", a point name or a list of names."""
    try:
        if point is None or (isinstance(point, str) and point.lower() == "pelvis" and "pelvis" not in rec.point_names):
            return find_pelvis(rec.point_names)
        if isinstance(point, str) and point.lower() == "hand" and "hand" not in rec.point_names:
            return find_hand(rec.point_names, hand_side)
    except InputError as exc:  # say which file
        raise InputError(f"{rec.source}: {exc}" if rec.source else str(exc)) from None
    names = (point,) if isinstance(point, str) else tuple(point)
    if not names:
        raise InputError("point= must name at least one point")
    for n in names:
        rec.index_of(n)  # InputError listing the available points
    return PointChoice(names, "named")


#: A sample further than this from the median of the five around it (each coordinate's), beyond what
#: the fastest point followed moves in a frame (SPIKE_SPEED_MPS), is a spike, not motion [m]: none of
#: the 53 shared recordings' pelvis markers has one; a one-frame glitch (a coordinate read as 0) is one.
SPIKE_M = 0.1
#: The fastest a followed point (a pelvis, a hand) moves [m/s]: at the ends of a recording the median of
#: the three samples there lies a frame's travel away.
SPIKE_SPEED_MPS = 5.0


def drop_spikes(positions: np.ndarray, frame_s: float, limit_m: float = SPIKE_M) -> np.ndarray:
    """The markers' positions (frames x k x 3) with spikes missing (NaN): samples further than
    ``limit_m`` plus a frame's travel (``frame_s`` apart) from the median of the five samples around
    them (a Hampel filter with a physical limit). A glitch of one or two frames is then a gap the centre
    bridges, not a step that the velocity's filter spreads into a burst; a lasting step (a marker that
    moves for good) is left as it is: the median follows it."""
    p = np.array(positions, dtype=float, copy=True)
    if p.ndim != 3 or p.shape[0] < 3:
        return p
    threshold_m = limit_m + SPIKE_SPEED_MPS * max(float(frame_s), 0.0)
    # Where no two samples of a window are further apart than threshold / sqrt(3), no coordinate's median is
    # further than that from a sample, nor the 3-D median than the threshold: nothing to drop (the common case,
    # a few operations instead of the windows' sort).
    reach = threshold_m / np.sqrt(3.0)
    with np.errstate(invalid="ignore"):
        if not any(np.any(np.linalg.norm(p[k:] - p[:-k], axis=2) > reach) for k in (1, 2, 3, 4)):
            return p
    pad = np.full((2,) + p.shape[1:], np.nan)
    window = np.lib.stride_tricks.sliding_window_view(np.concatenate([pad, p, pad]), 5, axis=0)
    # The median of each window's known values: NaN sorts last, so of n known values the middle ones are at
    # (n - 1) // 2 and n // 2 (nanmedian gives the same, at many times the cost on short recordings).
    ordered = np.sort(window, axis=-1)
    n = np.count_nonzero(~np.isnan(ordered), axis=-1)
    lo = np.take_along_axis(ordered, np.maximum((n - 1) // 2, 0)[..., None], axis=-1)[..., 0]
    hi = np.take_along_axis(ordered, (n // 2)[..., None], axis=-1)[..., 0]
    median = np.where(n > 0, 0.5 * (lo + hi), np.nan)
    with np.errstate(invalid="ignore"):
        off = np.linalg.norm(p - median, axis=2) > threshold_m
    p[off] = np.nan
    return p


#: Centres found inside :func:`reusing_trajectories`: (id of the recording, names) -> (recording, centre, used).
_CENTRES: contextvars.ContextVar[dict | None] = contextvars.ContextVar("yoyogait_centres", default=None)


@contextmanager
def reusing_trajectories():
    """Inside the block, :func:`point_trajectory` finds the centre of the same points of the same
    recording once: for a pipeline that asks for one recording's pelvis several times (velocities,
    treadmill, gait events). The recordings must not change inside the block."""
    token = _CENTRES.set({}) if _CENTRES.get() is None else None
    try:
        yield
    finally:
        if token is not None:
            _CENTRES.reset(token)


def point_trajectory(rec: Recording, point=None, *, hand_side: str = "right") -> PointTrajectory:
    """The chosen point's trajectory (frames x 3, metres), several points averaged by :func:`robust_centre`."""
    choice = point if isinstance(point, PointChoice) else choose_point(rec, point, hand_side=hand_side)
    centres = _CENTRES.get()
    key = (id(rec), tuple(choice.names))
    if centres is not None and key in centres:
        _, centre, used = centres[key]
        centre = centre.copy()
    else:
        frame_s = float(np.median(np.diff(rec.time_s))) if len(rec.time_s) > 1 else 0.0
        centre, used = robust_centre(drop_spikes(rec.points(choice.names), frame_s))
        if centres is not None:  # the recording is kept so that its id is not reused inside the block
            centres[key] = (rec, centre.copy(), list(used))
    return PointTrajectory(centre, choice, tuple(choice.names[i] for i in used))
