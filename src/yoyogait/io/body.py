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
from .marker_sets import MARKER_SETS_ENV, SIDES, _roles, marker_knowledge, normalise_name, pelvis_names
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
    "up_axis_evidence",
    "UpAxisEvidence",
    "check_declared_up_axis",
    "resolve_up_axis",
    "axis_index",
]


@dataclass(frozen=True)
class PointChoice:
    """Named points to follow, averaged when there are several."""

    names: tuple[str, ...]
    kind: str  # "pelvis markers", "root joint", "hip joints", "hand", "named"

    @property
    def label(self) -> str:
        """How the choice reads in a report, e.g. 'pelvis centre of LASI, RASI, SACR'."""
        joined = ", ".join(self.names)
        if self.kind == "pelvis markers":
            return f"pelvis centre of {joined}"
        if self.kind == "root joint":
            return f"root joint {joined}"
        if self.kind == "hip joints":
            return f"pelvis centre of the hip joints {joined}"
        if self.kind == "hand":
            return f"hand {joined}" if len(self.names) == 1 else f"hand, centre of {joined}"
        return joined if len(self.names) == 1 else f"centre of {joined}"

    @property
    def is_hand(self) -> bool:
        """A hand (found, or every named point a hand or wrist point by the marker-set table): its rise
        and fall in place are gestures, not gait (OnlineConfig.gait_in_place)."""
        if self.kind == "hand":
            return True
        k = marker_knowledge()
        return self.kind == "named" and all(any(r[0] == "hand" for r in _roles(n, k)) for n in self.names)


def find_pelvis(names: Sequence[str]) -> PointChoice:
    """The pelvis markers found by name (marker-set table), else a root joint; InputError if neither."""
    found, kind = pelvis_names(names)
    if found:
        return PointChoice(tuple(found), kind)
    raise InputError(
        "no pelvis-like point (ASIS/PSIS/sacrum markers, a Hips/pelvis/root joint or left and right hip joints) among: "
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


#: Pelvis height above the feet (the lowest points) of a standing or walking adult, metres.
PELVIS_BAND_M = (0.7, 1.3)
#: Step frequencies of walking and running (the band where the pelvis bounces), Hz.
STEP_BAND_HZ = (1.0, 3.5)
#: Head, neck and shoulder points (normalised names): above the pelvis when the person stands or sits.
_HEAD = re.compile(
    r"head|^[lr]?[fbt]hd$|^c7$|^t1$|^nose$|^[lr]?ear$|forehead|^vertex$|^clav|^ster|acro|shoulder|^[lr]sho$"
)


@dataclass
class UpAxisEvidence:
    """What the body says about the up axis: one score per axis and the cues behind it.

    ``scores`` adds, per axis, the cues that hold along it (each 0-2 points):
    the pelvis stands 0.7-1.3 m above the lowest points (``pelvis_height_m``),
    the feet lie 0.5 m or more below the pelvis and the head and shoulders
    0.25 m or more above it (named foot points; head, neck, sternum,
    clavicle and shoulder points), the pelvis height is steady (``steadiness``), and the pelvis
    bounces at a step frequency without drifting (``bounce``: the share of
    its velocity's power in :data:`STEP_BAND_HZ` at twice the lateral's
    frequency, its position within 0.25 m).  ``axis`` is the best-scoring
    axis; ``margin`` its lead over the next (below 1.5 the body does not
    decide).  ``cues`` are the lines ``inspect`` prints.
    """

    axis: str
    scores: dict[str, float]
    margin: float
    cues: list[str]

    @property
    def decisive(self) -> bool:
        return self.margin >= 1.5

    def summary(self) -> str:
        """One line: the axis, its lead, and the cues that hold along it."""
        held = "; ".join(self.cues) if self.cues else "no cue beyond the pelvis's spread"
        return f"{self.axis} ({'clear' if self.decisive else 'weak'}: {held})"


def up_axis_evidence(rec: Recording) -> UpAxisEvidence:
    """The up axis from a person's geometry, with the evidence (:class:`UpAxisEvidence`).

    Works in metres (every reader's unit); the height cues need points below
    the pelvis, the bounce cue needs a few steps.  Without any of them it
    falls back to the axis along which the pelvis moves least.
    """
    pos = rec.positions_m
    try:
        choice = find_pelvis(rec.point_names)
        pelvis, _ = robust_centre(rec.points(choice.names))
        prefixes = {n.rsplit(":", 1)[0] for n in choice.names if ":" in n}
        if len(prefixes) == 1:  # the person's own points (Subject:Marker), not the objects beside them
            prefix = prefixes.pop() + ":"
            own = [i for i, n in enumerate(rec.point_names) if n.startswith(prefix)]
            pos = pos[:, own, :]
    except InputError:
        with _quiet():
            pelvis = np.nanmean(rec.positions_m, axis=1)
    scores = dict.fromkeys(AXES, 0.0)
    cues: dict[str, list[str]] = {a: [] for a in AXES}
    with _quiet():
        lowest = np.nanmin(pos, axis=1)  # frames x 3
        h = pelvis - lowest
        ok = np.all(np.isfinite(h), axis=1)
        extent = np.nanmax(pos, axis=1) - lowest
        size = float(np.nanmedian(np.nanmax(extent, axis=1)))
    if pos.shape[1] > 1 and ok.sum() >= 2 and np.isfinite(size) and size > 0:
        median = np.median(h[ok], axis=0)
        spread = np.std(h[ok], axis=0)
        lo, hi = PELVIS_BAND_M
        for k, a in enumerate(AXES):
            if lo <= median[k] <= hi:
                scores[a] += 2.0
                cues[a].append(f"pelvis {median[k]:.2f} m above the lowest point")
            elif 0.4 <= median[k] <= 1.6:
                scores[a] += 1.0
                cues[a].append(f"pelvis {median[k]:.2f} m above the lowest point")
        steady = median / (spread + 0.05 * size)
        best = int(np.argmax(steady))
        if median[best] > 0.2 * size:
            scores[AXES[best]] += 1.0
            cues[AXES[best]].append("pelvis height steady")
    for what, names, sign in (
        ("feet", [n for g in find_foot_groups(rec.point_names).values() for n in g], -1.0),
        ("head and shoulders", [n for n in rec.point_names if _HEAD.search(normalise_name(n))], 1.0),
    ):
        if not names:
            continue
        with _quiet():
            rel = np.nanmedian(np.nanmean(rec.points(names), axis=1) - pelvis, axis=0) * sign
        for k, a in enumerate(AXES):
            if np.isfinite(rel[k]) and rel[k] > (0.5 if what == "feet" else 0.25):
                scores[a] += 2.0 if what == "feet" else 1.5
                where = "below" if what == "feet" else "above"
                cues[a].append(f"{what} {rel[k]:.2f} m {where} the pelvis")
    bounce = _bounce_axis(rec, pelvis)
    if bounce is not None:
        a, f_hz = bounce
        scores[a] += 1.0
        cues[a].append(f"pelvis bounces at {f_hz:.2f} Hz")
    if max(scores.values()) == 0.0:
        with _quiet():
            spread_p = np.nanstd(pelvis, axis=0)
        if not np.all(np.isfinite(spread_p)):
            raise InputError(f"{rec.source or 'recording'}: cannot detect the up axis (no usable point); pass up_axis=")
        a = AXES[int(np.argmin(spread_p))]
        return UpAxisEvidence(a, scores, 0.0, ["the pelvis moves least along it"])
    order = sorted(AXES, key=lambda a: -scores[a])
    return UpAxisEvidence(order[0], scores, scores[order[0]] - scores[order[1]], cues[order[0]])


def _bounce_axis(rec: Recording, pelvis: np.ndarray) -> tuple[str, float] | None:
    """The axis along which the pelvis bounces at a step frequency without drifting, and that frequency."""
    t = np.asarray(rec.time_s, dtype=float)
    ok = np.all(np.isfinite(pelvis), axis=1)
    if ok.sum() < 10 or t[-1] - t[0] < 2.0:
        return None
    rate = 50.0
    grid = np.arange(t[0], t[-1], 1.0 / rate)
    p = np.column_stack([np.interp(grid, t[ok], pelvis[ok, k]) for k in range(3)])
    v = np.gradient(p, axis=0) * rate
    n = len(grid)
    freqs = np.fft.rfftfreq(8 * n, 1.0 / rate)
    best: tuple[str, float, float] | None = None
    peaks = {}
    for k, a in enumerate(AXES):
        x = v[:, k] - np.mean(v[:, k])
        power = np.abs(np.fft.rfft(x * np.hanning(n), 8 * n)) ** 2
        total = power[(freqs >= 0.3) & (freqs <= 6.0)].sum()
        band = (freqs >= STEP_BAND_HZ[0]) & (freqs <= STEP_BAND_HZ[1])
        if total <= 0 or not band.any():
            continue
        share = power[band].sum() / total
        peaks[a] = float(freqs[band][np.argmax(power[band])])
        excursion = float(np.percentile(p[:, k], 95) - np.percentile(p[:, k], 5))
        if excursion <= 0.25 and share >= 0.5 and (best is None or share > best[2]):
            best = (a, peaks[a], share)
    return None if best is None else (best[0], best[1])


def detect_up_axis(rec: Recording) -> str:
    """The up axis from the body's geometry: the axis of :func:`up_axis_evidence`."""
    return up_axis_evidence(rec).axis


def check_declared_up_axis(rec: Recording) -> Recording:
    """Set the up axis of a recording whose format declares one by convention, checked against the body.

    ``metadata["up_axis_declared"]`` (a format's convention, e.g. Motive's Y
    up) is used unless the body clearly says another axis; a file that
    states its axis (``rec.up_axis``) keeps it.  Either way a disagreement
    with clear evidence is one warning naming ``--up-axis``; the evidence
    goes to ``metadata["up_axis_evidence"]``.
    """
    declared = rec.metadata.get("up_axis_declared")
    stated = rec.up_axis
    if rec.positions_m.shape[1] == 0 or (declared is None and stated is None):
        return rec
    if rec.metadata.get("up_axis_from") == "override":
        return rec
    try:
        ev = up_axis_evidence(rec)
    except InputError:
        ev = None
    if ev is not None:
        rec.metadata["up_axis_evidence"] = ev
    where = rec.source or "recording"
    if stated is not None:
        if ev is not None and ev.decisive and ev.axis != stated:
            warnings.warn(
                f"{where}: the file states up axis {stated}, the body says {ev.summary()}; "
                f"pass --up-axis {ev.axis} if the body is right",
                stacklevel=2,
            )
        return rec
    by = rec.metadata.get("up_axis_declared_by", "the format's convention")
    if ev is not None and ev.decisive and ev.axis != declared:
        rec.up_axis = ev.axis
        rec.metadata["up_axis_from"] = f"detected; {by} says {declared}"
        warnings.warn(
            f"{where}: {by} says up axis {declared}, the body says {ev.summary()}; using {ev.axis}, "
            f"pass --up-axis {declared} if the convention holds",
            stacklevel=2,
        )
    else:
        rec.up_axis = declared
        rec.metadata["up_axis_from"] = by
    return rec


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
