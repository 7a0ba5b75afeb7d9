"""What a person's body looks like in a recording: which named points are the pelvis, the hands and
the feet (the marker-set table, ``marker_sets.json``), the centre of several markers without jumps
when one drops out, and the up axis from the body's geometry.

Readers use these (a BVH root, a file's up axis), so they live with the readers; the pipeline
builds on them (:mod:`yoyogait.pipeline.points`).
"""

from __future__ import annotations

import re
import warnings
from collections.abc import Sequence
from contextlib import contextmanager
from dataclasses import dataclass

import numpy as np

from ..errors import InputError
from .marker_sets import MARKER_SETS_ENV, SIDES, _roles, marker_knowledge, pelvis_names
from .recording import AXES, Recording

__all__ = [
    "PointChoice",
    "find_pelvis",
    "find_hand",
    "find_feet",
    "find_foot_groups",
    "side_of",
    "robust_centre",
    "detect_up_axis",
    "resolve_up_axis",
    "axis_index",
]


@dataclass(frozen=True)
class PointChoice:
    """Named points to follow, averaged when there are several."""

    names: tuple[str, ...]
    kind: str  # "pelvis markers", "root joint", "hand", "named"

    @property
    def label(self) -> str:
        """How the choice reads in a report, e.g. 'pelvis centre of LASI, RASI, SACR'."""
        joined = ", ".join(self.names)
        if self.kind == "pelvis markers":
            return f"pelvis centre of {joined}"
        if self.kind == "root joint":
            return f"root joint {joined}"
        if self.kind == "hand":
            return f"hand {joined}" if len(self.names) == 1 else f"hand, centre of {joined}"
        return joined if len(self.names) == 1 else f"centre of {joined}"


def find_pelvis(names: Sequence[str]) -> PointChoice:
    """The pelvis markers found by name (marker-set table), else a root joint; InputError if neither."""
    found, kind = pelvis_names(names)
    if found:
        return PointChoice(tuple(found), kind)
    raise InputError(
        "no pelvis-like point (ASIS/PSIS/sacrum markers or a Hips/pelvis/root joint) among: "
        + (", ".join(names) or "(no points)")
        + "; name one with --point, or add your marker set to a file named by $"
        + MARKER_SETS_ENV
    )


def side_of(name: str) -> str | None:
    """ "left" or "right" if the name is a hand or foot point of that side, or has a side as a separate word
    (``L_Marker``, ``Marker.R``, ``LeftThing``); else None."""
    k = marker_knowledge()
    sides = {r[1] for r in _roles(name, k) if r[1]}
    if len(sides) == 1:
        return sides.pop()
    bare = name.rsplit(":", 1)[-1]
    words = [w.lower() for w in re.split(r"[^A-Za-z0-9]+|(?<=[a-z])(?=[A-Z])", bare) if w]
    found = {side for side, tokens in k.sides.items() for t in tokens if words and t in (words[0], words[-1])}
    return found.pop() if len(found) == 1 else None


def find_hand(names: Sequence[str], side: str = "right") -> PointChoice:
    """The hand of ``side``: a hand joint or finger marker, else its wrist markers (averaged)."""
    side = _check_side(side)
    k = marker_knowledge()
    found: dict[int, list[str]] = {}
    for n in names:
        ranks = [r[2] for r in _roles(n, k) if r[0] == "hand" and r[1] == side]
        if ranks:
            found.setdefault(min(ranks), []).append(n)
    if not found:
        raise InputError(f"no {side} hand or wrist point among: {', '.join(names) or '(no points)'}")
    return PointChoice(tuple(found[min(found)]), "hand")


def find_foot_groups(
    names: Sequence[str], visibility: dict | None = None, min_visible_fraction: float = 0.5
) -> dict[str, list[str]]:
    """The points of each foot, by side: heel first, then ankle (or a skeleton's foot joint), then toe.

    With ``visibility`` (name -> fraction of frames where the point is seen),
    points seen in fewer than ``min_visible_fraction`` of the frames go to the
    end of their foot's list (some files name heel markers that were never
    seen); a point never seen is left out.
    """
    k = marker_knowledge()
    groups: dict[str, list[tuple[int, int, str]]] = {}
    for order, n in enumerate(names):
        ranks = {(r[1], r[2]) for r in _roles(n, k) if r[0] == "foot" and r[1] in SIDES}
        sides = {side for side, _ in ranks}
        if len(sides) == 1:
            side = sides.pop()
            groups.setdefault(side, []).append((min(rank for _, rank in ranks), order, n))
    out = {}
    for side in SIDES:
        found = sorted(groups.get(side, []))
        if visibility is not None:
            seen = [c for c in found if visibility.get(c[2], 0.0) >= min_visible_fraction]
            rare = sorted(
                (c for c in found if 0 < visibility.get(c[2], 0.0) < min_visible_fraction),
                key=lambda c: -visibility.get(c[2], 0.0),
            )
            found = seen + rare
        if found:
            out[side] = [c[2] for c in found]
    return out


def find_feet(
    names: Sequence[str], visibility: dict | None = None, min_visible_fraction: float = 0.5
) -> dict[str, str]:
    """One foot point per side that has one: the first of :func:`find_foot_groups` (heel, else ankle, else toe)."""
    return {side: group[0] for side, group in find_foot_groups(names, visibility, min_visible_fraction).items()}


def robust_centre(positions: np.ndarray, min_visible_fraction: float = 0.5):
    """Centre of several markers (frames x k x 3) that does not jump when one drops out.

    On frames where every marker is visible the centre is their mean.  Each
    marker's offset from that centre is interpolated in time across the
    frames where some marker is missing (held at the ends), and the centre
    there is the mean of ``marker - offset`` over the markers that are
    visible.  Markers seen in fewer than ``min_visible_fraction`` of the
    frames where any of them is seen are left out, so that a rarely seen
    marker does not stretch the offsets over long stretches.

    Returns the centre (frames x 3, NaN where no marker is visible) and the
    indices of the markers used.
    """
    positions = np.asarray(positions, dtype=float)
    if positions.ndim != 3 or positions.shape[2] != 3:
        raise ValueError("positions must be frames x markers x 3")
    visible = np.all(np.isfinite(positions), axis=2)
    any_visible = visible.any(axis=1)
    used = [
        j for j in range(positions.shape[1]) if visible[:, j].sum() >= min_visible_fraction * max(1, any_visible.sum())
    ]
    if not used:
        used = list(range(positions.shape[1]))
    while True:
        full = visible[:, used].all(axis=1)
        if full.any() or len(used) == 1:
            break
        used.remove(min(used, key=lambda j: visible[:, j].sum()))  # no frame shows them all
    p = positions[:, used, :]
    if len(used) == 1:
        return p[:, 0, :].copy(), used
    frames = np.arange(p.shape[0])
    centre_full = p[full].mean(axis=1)  # nfull x 3
    offsets = p[full] - centre_full[:, None, :]  # nfull x k x 3
    carried = np.empty_like(p)
    for j in range(p.shape[1]):
        for a in range(3):
            carried[:, j, a] = np.interp(frames, frames[full], offsets[:, j, a])
    estimates = p - carried
    with np.errstate(invalid="ignore"):
        count = np.isfinite(estimates[:, :, 0]).sum(axis=1)
        centre = np.nansum(estimates, axis=1) / np.where(count > 0, count, 1)[:, None]
    centre[count == 0] = np.nan
    return centre, used


def axis_index(axis: str) -> int:
    """0, 1, 2 for "x", "y", "z"."""
    a = str(axis).lower()
    if a not in AXES:
        raise InputError(f"up_axis must be one of x, y, z, not {axis!r}")
    return AXES.index(a)


def detect_up_axis(rec: Recording) -> str:
    """The axis along which the pelvis stands high above the lowest point, steadily.

    For each axis, h(t) = pelvis(t) - lowest point(t) (lowest over all points
    of the frame, i.e. the feet).  Along the up axis h is large (0.8-1.1 m)
    and steady; along a horizontal axis it is small and swings with every
    step.  The score is median(h) / (std(h) + 5% of the body's size), which
    does not depend on the length unit.  With the pelvis alone (no point
    below it) it falls back to the axis along which the pelvis moves least.
    """
    try:
        choice = find_pelvis(rec.point_names)
        pelvis, _ = robust_centre(rec.points(choice.names))
    except InputError:
        with _quiet():
            pelvis = np.nanmean(rec.positions_m, axis=1)
    pos = rec.positions_m
    with _quiet():
        lowest = np.nanmin(pos, axis=1)  # frames x 3
        extent = np.nanmax(pos, axis=1) - lowest
        size = float(np.nanmedian(np.nanmax(extent, axis=1)))
        h = pelvis - lowest
        ok = np.all(np.isfinite(h), axis=1)
    if ok.sum() >= 2 and np.isfinite(size) and size > 0:
        h = h[ok]
        median = np.median(h, axis=0)
        if np.max(median) > 0.2 * size:  # some point lies well below the pelvis
            score = median / (np.std(h, axis=0) + 0.05 * size)
            return AXES[int(np.argmax(score))]
    with _quiet():
        spread = np.nanstd(pelvis, axis=0)
    if not np.all(np.isfinite(spread)):
        raise InputError(f"{rec.source or 'recording'}: cannot detect the up axis (no usable point); pass up_axis=")
    return AXES[int(np.argmin(spread))]


def resolve_up_axis(rec: Recording, up_axis: str | None = None) -> tuple[str, str]:
    """The up axis and where it came from: "override", "file" or "detected"."""
    if up_axis is not None:
        return AXES[axis_index(up_axis)], "override"
    if rec.up_axis is not None:
        return AXES[axis_index(rec.up_axis)], rec.metadata.get("up_axis_from", "file")
    return detect_up_axis(rec), "detected"


def _check_side(side: str) -> str:
    s = str(side).lower()
    if s in ("l", "left"):
        return "left"
    if s in ("r", "right"):
        return "right"
    raise InputError(f"side must be 'left' or 'right', not {side!r}")


@contextmanager
def _quiet():
    """Silence numpy's all-NaN-slice warnings where NaN is the expected answer."""
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", RuntimeWarning)
        yield
