"""BVH skeleton animation (animation pipelines, Xsens/OptiTrack exports, CMU, Bandai Namco).

The hierarchy is run through forward kinematics, so every joint and every
End Site becomes a point with its world position per frame:

* a joint's translation from its parent is its OFFSET, with each component
  that has a position channel replaced by that channel (the convention of
  Blender, MotionBuilder and the CMU/Bandai files: the root's position
  channels are its absolute position);
* its rotation is the product of its rotation channels in the order they
  are listed (``Zrotation Xrotation Yrotation`` is Rz @ Rx @ Ry), degrees,
  applied in the parent frame: ``world = parent_R @ (R_local)``,
  ``p = parent_p + parent_R @ translation``;
* joints may have 3 or 6 channels (or any subset); an End Site is named
  ``<parent>_End``.

BVH has no length unit.  Give ``length_unit_m=``; without it the unit is
inferred from the standing pelvis height, which is 0.8-1.1 m for an adult
(:func:`infer_length_unit`), and ``metadata["length_unit_from"]`` says which
unit was chosen and why.  The up axis is left to detection (BVH files are Y up
by convention, but the file does not say it).
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np
from scipy.spatial.transform import Rotation

from ..errors import InputError
from .body import detect_up_axis, find_pelvis
from .recording import MAX_COORDINATE_M, Recording, check_coordinates, check_rate, read_text, uniform_time

__all__ = ["read_bvh", "infer_length_unit", "CANDIDATE_UNITS_M", "PELVIS_HEIGHT_M"]

#: Units a BVH file is written in, tried in this order when inferring it.
CANDIDATE_UNITS_M = {
    "m": 1.0,
    "cm": 0.01,
    "mm": 0.001,
    "inch": 0.0254,
    "CMU unit (1/0.45 inch)": 0.0254 / 0.45,
    "dm": 0.1,
    "foot": 0.3048,
}

#: Height of a standing adult's pelvis (hip joint centre or root) above the floor.
PELVIS_HEIGHT_M = (0.8, 1.1)


@dataclass
class _Joint:
    name: str
    parent: int
    offset: np.ndarray
    channels: list[str] = field(default_factory=list)
    first_channel: int = 0


def read_bvh(
    path, *, length_unit_m: float | None = None, rate_hz: float | None = None, up_axis: str | None = None
) -> Recording:
    """Read a BVH file into world positions of all its joints and End Sites.

    ``up_axis`` is only used to infer the length unit when the detection
    would be wrong; :func:`yoyogait.io.read` sets the recording's up axis itself.
    """
    p, text = read_text(path)
    joints, motion_lines, frames_announced, frame_time = _parse(text, str(p))

    n_channels = sum(len(j.channels) for j in joints)
    rows: list[list[float]] = []
    for number, line in motion_lines:
        cells = line.split()
        if len(cells) != n_channels:
            if len(rows) + 1 == frames_announced or number == motion_lines[-1][0]:
                raise InputError(
                    f"{p}: truncated BVH file: line {number} holds {len(cells)} of {n_channels} channel values"
                )
            raise InputError(f"{p}: line {number} holds {len(cells)} values, the hierarchy has {n_channels} channels")
        try:
            rows.append([float(c) for c in cells])
        except ValueError:
            raise InputError(f"{p}: line {number}: a channel value is not a number") from None
    if not rows:
        raise InputError(f"{p}: the BVH file holds no frames")
    if len(rows) < frames_announced:
        raise InputError(f"{p}: truncated BVH file: 'Frames: {frames_announced}' but the file holds {len(rows)}")
    motion = np.asarray(rows, dtype=float)
    if not np.all(np.isfinite(motion)):
        raise InputError(f"{p}: the BVH motion holds values that are not finite")
    # No unit (the smallest BVH is written in is the mm) makes a larger value a place in a capture volume,
    # and no rotation is given as millions of degrees: a corrupt number.
    limit = MAX_COORDINATE_M / min(CANDIDATE_UNITS_M.values())
    huge = np.flatnonzero(np.any(np.abs(motion) > limit, axis=1))
    if huge.size:
        k = int(huge[0])
        value = motion[k][np.argmax(np.abs(motion[k]))]
        raise InputError(
            f"{p}: line {motion_lines[k][0]}: a channel value of {value:.4g} is beyond any capture volume "
            "or rotation (a corrupt number)"
        )

    positions, names = _forward_kinematics(joints, motion)
    metadata: dict = {"format": "bvh", "root_joint": joints[0].name, "frame_time_s": frame_time}
    rate = check_rate(rate_hz, p, "capture_rate_hz override") if rate_hz is not None else 1.0 / frame_time

    rec = Recording(
        positions_m=positions,
        point_names=names,
        time_s=uniform_time(len(rows), rate),
        rate_hz=rate,
        up_axis=None,
        source=str(p),
        metadata=metadata,
    )
    if length_unit_m is not None:
        unit, reason = float(length_unit_m), "override"
    else:
        unit, reason = infer_length_unit(rec, up_axis=up_axis)
    rec.positions_m *= unit
    check_coordinates(rec.positions_m, names, p)
    metadata.update(length_unit_m=unit, length_unit_from=reason)
    return rec


def infer_length_unit(rec: Recording, up_axis: str | None = None) -> tuple[float, str]:
    """Metres per file unit, from the pelvis height above the floor while standing or walking.

    The pelvis is the one :func:`yoyogait.io.body.find_pelvis` picks (Hips,
    pelvis, root ...); the floor is the lowest point of the skeleton.  Each
    unit of :data:`CANDIDATE_UNITS_M` is tried, and the one that puts the
    pelvis 0.8-1.1 m above the floor wins (the nearest to 0.95 m if several
    do).  Returns the unit and a sentence saying what was inferred.
    """
    axis = up_axis or detect_up_axis(rec)
    k = "xyz".index(axis)
    pelvis = find_pelvis(rec.point_names)
    pelvis_height = rec.points(pelvis.names)[:, :, k].mean(axis=1)
    floor = np.nanmin(rec.positions_m[:, :, k], axis=1)
    height = float(np.nanmedian(pelvis_height - floor))
    if not np.isfinite(height) or height <= 0:
        raise InputError(f"{rec.source}: cannot infer the BVH length unit (no pelvis height); pass length_unit_m=")
    lo, hi = PELVIS_HEIGHT_M
    fits = [
        (abs(np.log(height * u / 0.95)), name, u) for name, u in CANDIDATE_UNITS_M.items() if lo <= height * u <= hi
    ]
    if not fits:
        raise InputError(
            f"{rec.source}: cannot infer the BVH length unit: the pelvis ({'+'.join(pelvis.names)}) is "
            f"{height:.4g} units above the floor, which no usual unit turns into {lo}-{hi} m; pass length_unit_m="
        )
    _, name, unit = min(fits)
    return unit, (f"inferred: {name} ({unit:.6g} m), which puts the pelvis {height * unit:.2f} m above the floor")


def _parse(text: str, where: str):
    """Joints (parents first), the motion lines, the announced frame count and the frame time."""
    lines = text.splitlines()
    try:
        motion_at = next(i for i, line in enumerate(lines) if line.strip().upper() == "MOTION")
    except StopIteration:
        if not text.lstrip().upper().startswith("HIERARCHY"):
            raise InputError(f"{where}: not a BVH file (it must start with HIERARCHY)") from None
        raise InputError(f"{where}: truncated BVH file: no MOTION section") from None
    if not text.lstrip().upper().startswith("HIERARCHY"):
        raise InputError(f"{where}: not a BVH file (it must start with HIERARCHY)")

    tokens = " ".join(lines[:motion_at]).replace("{", " { ").replace("}", " } ").split()
    joints: list[_Joint] = []
    stack: list[int] = []
    pending: _Joint | None = None
    n_channels = 0
    i = 1  # after HIERARCHY
    try:
        while i < len(tokens):
            tok = tokens[i]
            upper = tok.upper()
            if upper in ("ROOT", "JOINT"):
                pending = _Joint(tokens[i + 1], stack[-1] if stack else -1, np.zeros(3))
                i += 2
            elif upper == "END":  # End Site
                parent = stack[-1]
                pending = _Joint(f"{joints[parent].name}_End", parent, np.zeros(3))
                i += 2
            elif tok == "{":
                if pending is None:
                    raise InputError(f"{where}: corrupt BVH hierarchy: '{{' without a joint")
                joints.append(pending)
                stack.append(len(joints) - 1)
                pending = None
                i += 1
            elif tok == "}":
                stack.pop()
                i += 1
            elif upper == "OFFSET":
                joints[stack[-1]].offset = np.array([float(v) for v in tokens[i + 1 : i + 4]])
                i += 4
            elif upper == "CHANNELS":
                count = int(tokens[i + 1])
                channels = tokens[i + 2 : i + 2 + count]
                bad = [c for c in channels if c.lower() not in _CHANNELS]
                if bad or len(channels) != count:
                    what = (
                        f"unknown channel {bad[0]!r}" if bad else f"{count} channels announced, {len(channels)} given"
                    )
                    raise InputError(f"{where}: corrupt BVH hierarchy: {what}")
                joints[stack[-1]].channels = [c.lower() for c in channels]
                joints[stack[-1]].first_channel = n_channels
                n_channels += count
                i += 2 + count
            else:
                raise InputError(f"{where}: corrupt BVH hierarchy: unexpected {tok!r}")
    except InputError:
        raise
    except (IndexError, ValueError):  # a missing or non-numeric value
        raise InputError(
            f"{where}: corrupt BVH hierarchy near token {i} ({tokens[i] if i < len(tokens) else 'end'!r})"
        ) from None
    if stack or not joints:
        raise InputError(f"{where}: corrupt BVH hierarchy: unbalanced braces or no joint")

    header: dict[str, str] = {}
    for line in lines[motion_at + 1 : motion_at + 3]:
        key, _, value = line.partition(":")
        header[key.strip().lower()] = value.strip()
    try:
        frames = int(header["frames"])
        frame_time = float(header["frame time"])
    except (KeyError, ValueError):
        raise InputError(
            f"{where}: corrupt or truncated BVH: MOTION must be followed by 'Frames:' and 'Frame Time:'"
        ) from None
    if not frame_time > 0:
        raise InputError(f"{where}: BVH frame time must be positive, not {frame_time}")
    check_rate(1.0 / frame_time, where, f"rate of 'Frame Time: {header['frame time']}'")
    motion_lines = [(n + 1, line) for n, line in enumerate(lines[motion_at + 3 :], start=motion_at + 3) if line.strip()]
    return joints, motion_lines, frames, frame_time


_CHANNELS = {"xposition": 0, "yposition": 1, "zposition": 2, "xrotation": 0, "yrotation": 1, "zrotation": 2}


def _forward_kinematics(joints: list[_Joint], motion: np.ndarray):
    """World positions (frames x joints x 3) of every joint, parents before children."""
    n = motion.shape[0]
    world_r = np.empty((len(joints), n, 3, 3))
    world_p = np.empty((len(joints), n, 3))
    for j, joint in enumerate(joints):
        translation = np.broadcast_to(joint.offset, (n, 3)).copy()
        axes = ""
        angle_cols = []
        for c, channel in enumerate(joint.channels):
            column = motion[:, joint.first_channel + c]
            if channel.endswith("position"):
                translation[:, _CHANNELS[channel]] = column
            else:
                axes += channel[0].upper()
                angle_cols.append(column)
        if axes:
            local = Rotation.from_euler(axes, np.stack(angle_cols, axis=1), degrees=True).as_matrix()
        else:
            local = np.broadcast_to(np.eye(3), (n, 3, 3))
        if joint.parent < 0:
            world_r[j] = local
            world_p[j] = translation
        else:
            parent_r = world_r[joint.parent]
            world_r[j] = parent_r @ local
            world_p[j] = world_p[joint.parent] + np.einsum("fij,fj->fi", parent_r, translation)
    return np.ascontiguousarray(world_p.transpose(1, 0, 2)), [j.name for j in joints]
