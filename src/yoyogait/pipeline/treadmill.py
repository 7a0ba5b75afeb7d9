"""Treadmill walking: told from the data, and the walking speed it hides.

On a treadmill the pelvis stays in place in the lab, so its velocity holds
only the body's own sway and drift (0.15 m/s for a person walking at
1.1 m/s), not the walking speed.  The belt carries each foot backwards while
it stands on it: the feet in stance move at the belt's velocity, where
overground they stand still.  So a recording is a treadmill walk when the
pelvis stays within a small area while the stance feet (the frames where a
foot is within 2 cm of its lowest height) move, consistently in one
direction, faster than ``min_belt_mps``.  The belt speed is the length of the
median stance-foot velocity, the walking direction its opposite, and the
walking speed is the belt speed plus the pelvis's own motion along that
direction: :func:`yoyogait.gait_velocities` adds the belt's velocity to the
point's horizontal velocity.  ``belt_speed_mps=`` (``--belt-speed-mps``)
gives the belt speed when the feet cannot (or should not) be trusted.
"""

from __future__ import annotations

import warnings
from dataclasses import dataclass
from typing import Any

import numpy as np

from ..errors import InputError
from ..io.recording import AXES, Recording
from . import events, points

__all__ = ["Treadmill", "detect_treadmill"]


@dataclass
class Treadmill:
    """What the treadmill check found (speeds in m/s, directions in the two horizontal axes)."""

    detected: bool
    belt_speed_mps: float | None  # None when not a treadmill
    belt_from: str  # "stance feet", "override" or ""
    forward: tuple[float, float] | None  # walking direction (unit vector over the horizontal axes)
    horizontal_axes: tuple[str, str]
    pelvis_net_speed_mps: float  # how fast the pelvis travels over the recording
    pelvis_range_m: float  # the largest horizontal distance between two pelvis positions
    stance_foot_speed_mps: float | None  # median speed of the feet in stance (NaN without feet)
    reason: str  # one sentence for reports
    pelvis_stays: bool = False  # the pelvis stays in place (a treadmill, or standing or stepping in place)

    @property
    def in_place(self) -> bool:
        """The pelvis stays in place and the feet in stance do too: standing or stepping in place."""
        return self.pelvis_stays and not self.detected and self.stance_foot_speed_mps is not None

    def belt_velocity(self) -> np.ndarray:
        """The belt's contribution to the walking velocity (over the horizontal axes): speed times direction."""
        if not self.detected or self.belt_speed_mps is None or self.forward is None:
            return np.zeros(2)
        return self.belt_speed_mps * np.asarray(self.forward)

    def summary(self) -> str:
        return self.reason


def detect_treadmill(
    recording: Recording,
    up_axis: str | None = None,
    *,
    feet=None,
    belt_speed_mps: float | None = None,
    min_belt_mps: float = 0.3,
    max_pelvis_range_m: float = 1.0,
    max_pelvis_net_mps: float = 0.2,
    stance_band_m: float = 0.02,
) -> Treadmill:
    """Whether ``recording`` is treadmill walking, and the belt speed (from the stance feet, or ``belt_speed_mps``)."""
    if belt_speed_mps is not None and not (np.isfinite(belt_speed_mps) and belt_speed_mps >= 0):
        raise InputError(f"--belt-speed-mps must be a speed in m/s (0 or more), not {belt_speed_mps!r}")
    up, _ = points.resolve_up_axis(recording, up_axis)
    k = AXES.index(up)
    horizontal = [a for a in range(3) if a != k]
    names = (AXES[horizontal[0]], AXES[horizontal[1]])
    t = np.asarray(recording.time_s, dtype=float)
    rate = 1.0 / float(np.median(np.diff(t))) if len(t) > 1 else 1.0
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", RuntimeWarning)
        try:
            pelvis = points.point_trajectory(recording, None).positions_m[:, horizontal]
        except InputError:
            pelvis = np.nanmean(recording.positions_m, axis=1)[:, horizontal]
        seen = np.all(np.isfinite(pelvis), axis=1)
        span = pelvis[seen]
        pelvis_range = float(np.max(np.ptp(span, axis=0))) if len(span) > 1 else 0.0
        duration = float(t[seen][-1] - t[seen][0]) if seen.sum() > 1 else 0.0
        net = float(np.linalg.norm(span[-1] - span[0]) / duration) if duration > 0 else 0.0
        stance = _stance_velocities(recording, feet, k, horizontal, rate, stance_band_m)
    stays = pelvis_range <= max_pelvis_range_m and net <= max_pelvis_net_mps
    if stance is None:
        median_vector, stance_speed = None, float("nan")
    else:
        median_vector = np.median(stance, axis=0)
        stance_speed = float(np.median(np.linalg.norm(stance, axis=1)))
    belt_like = (
        median_vector is not None
        and stance_speed >= min_belt_mps
        and float(np.linalg.norm(median_vector)) >= 0.7 * stance_speed  # one direction, not scuffing about
    )
    common: dict[str, Any] = dict(
        horizontal_axes=names,
        pelvis_net_speed_mps=net,
        pelvis_range_m=pelvis_range,
        stance_foot_speed_mps=None if stance is None else stance_speed,
        pelvis_stays=bool(stays),
    )
    if belt_speed_mps is not None:
        if median_vector is not None and np.linalg.norm(median_vector) > 0:
            forward = -median_vector / np.linalg.norm(median_vector)
            direction = "opposite to the stance feet"
        else:
            forward, direction = np.array([1.0, 0.0]), f"along +{names[0]} (no stance feet to tell the direction)"
        return Treadmill(
            True,
            float(belt_speed_mps),
            "override",
            (float(forward[0]), float(forward[1])),
            reason=f"treadmill, belt {belt_speed_mps:.2f} m/s (--belt-speed-mps), walking {direction}",
            **common,
        )
    if stays and belt_like:
        assert median_vector is not None
        belt = float(np.linalg.norm(median_vector))
        forward = -median_vector / belt
        return Treadmill(
            True,
            belt,
            "stance feet",
            (float(forward[0]), float(forward[1])),
            reason=(
                f"treadmill: the pelvis stays within {pelvis_range:.2f} m while the feet in stance move back at "
                f"{belt:.2f} m/s (the belt); walking speed = belt + the pelvis's own motion"
            ),
            **common,
        )
    if stays and stance is None:
        reason = f"the pelvis stays within {pelvis_range:.2f} m and there are no feet to tell a treadmill"
    elif stays:
        reason = (
            f"the pelvis stays within {pelvis_range:.2f} m but the feet in stance move at only "
            f"{stance_speed:.2f} m/s: standing or stepping in place, not a treadmill"
        )
    else:
        reason = "overground: the pelvis travels"
    return Treadmill(False, None, "", None, reason=reason, **common)


def _stance_velocities(recording, feet, k, horizontal, rate, band_m):
    """Horizontal velocities (n x 2) of every foot over the frames where it is within ``band_m`` of its lowest."""
    groups = events.feet_of(recording, feet) if recording.point_names else {}
    found = []
    for name in groups.values():
        p = recording.point(name)
        if np.isfinite(p).all(axis=1).sum() < 3:
            continue
        low = np.nanpercentile(p[:, k], 5)
        v = np.gradient(p, axis=0) * rate
        stance = (p[:, k] < low + band_m) & np.all(np.isfinite(v), axis=1)
        if stance.sum() >= 3:
            found.append(v[stance][:, horizontal])
    return np.vstack(found) if found else None
