"""Xsens MVN exports in MVNX (XML, version 3 and 4).

An MVNX file declares the subject's segments (``Pelvis`` first) and, per
segment, its anatomical points (``pHipOrigin``, ``pLeftASI``,
``pLeftHeelFoot``, ...) as fixed offsets in the segment's frame
(``pos_b``).  Each recorded frame (``type="normal"``) holds every segment's
position (metres) and orientation (quaternion w, x, y, z).  The recording has
every segment origin as a point (named as the segment) and every anatomical
point, placed by its segment's position and orientation (a point listed by
two segments, a joint, is taken from the first).  MVN's global frame is
Z up, X forward at the start (the MVNX convention), so the up axis is "z".
Times are the frames' ``time`` attribute (ms from the start).
"""

from __future__ import annotations

import xml.etree.ElementTree as ET

import numpy as np

from ..errors import InputError
from .recording import Recording, check_readable

__all__ = ["read_mvnx"]


def read_mvnx(path, *, length_unit_m: float | None = None, rate_hz: float | None = None) -> Recording:
    """Read the segment origins and anatomical points of an MVNX file."""
    p = check_readable(path)
    # Streamed: a long MVN take is hundreds of MB of XML; each frame is dropped once read.
    root_tag = None
    version = None
    subject: dict | None = None
    segment_names: list[str] = []
    anatomical: list[tuple[str, int, np.ndarray]] = []  # (point, segment index, offset in the segment frame)
    times: list[float] = []
    positions: list[np.ndarray] = []
    orientations: list[np.ndarray] = []
    try:
        for event, elem in ET.iterparse(p, events=("start", "end")):
            tag = elem.tag.rsplit("}", 1)[-1]
            if event == "start":
                if root_tag is None:
                    root_tag, version = tag, elem.get("version")
                    if tag != "mvnx":
                        raise InputError(f"{p}: an XML file but not an MVNX export (its root is <{tag}>)")
                elif tag == "subject" and subject is None:
                    subject = dict(elem.attrib)
                continue
            if tag == "segment":
                _add_segment(elem, segment_names, anatomical)
            elif tag == "frame":
                _add_frame(p, elem, len(segment_names), times, positions, orientations)
                elem.clear()
    except ET.ParseError as exc:
        raise InputError(f"{p}: not a readable MVNX (XML) file: {exc}") from None
    if subject is None:
        raise InputError(f"{p}: the MVNX file holds no <subject>")
    if not segment_names:
        raise InputError(f"{p}: the MVNX subject declares no segments")
    if not positions:
        raise InputError(f"{p}: the MVNX file holds no recorded frames (only calibration poses)")

    seg_pos = np.asarray(positions)
    seg_rot = _rotation_matrices(np.asarray(orientations))  # frames x segments x 3 x 3
    points = [seg_pos] + [(seg_pos[:, i, :] + seg_rot[:, i] @ offset)[:, None, :] for _, i, offset in anatomical]
    scale_m = float(length_unit_m) if length_unit_m is not None else 1.0
    file_rate = float(subject.get("frameRate", "nan"))
    rate = float(rate_hz) if rate_hz is not None else (file_rate if file_rate > 0 else None)
    t = np.asarray(times) / 1000.0
    if rate_hz is not None or not np.all(np.isfinite(t)):
        if not rate:
            raise InputError(f"{p}: the MVNX file has neither frame times nor a frameRate; pass --capture-rate-hz")
        t = np.arange(len(positions)) / rate
    return Recording(
        positions_m=np.concatenate(points, axis=1) * scale_m,
        point_names=segment_names + [name for name, _, _ in anatomical],
        time_s=t - t[0],
        rate_hz=rate,
        up_axis="z",
        source=str(p),
        metadata={
            "format": "mvnx",
            "length_unit_m": scale_m,
            "length_unit_from": "override" if length_unit_m is not None else "metres (MVNX)",
            "up_axis_from": "MVNX convention: Z up",
            "mvnx_version": version,
            "configuration": subject.get("configuration"),
        },
    )


def _add_segment(segment, names: list, anatomical: list) -> None:
    """A declared segment: its name, and its anatomical points not declared before (a joint is in two)."""
    names.append(segment.get("label", f"segment{len(names) + 1}"))
    seen = set(names) | {name for name, _, _ in anatomical}
    for point in segment.iter():
        if point.tag.rsplit("}", 1)[-1] != "point":
            continue
        label = point.get("label")
        pos_b = next((c for c in point if c.tag.rsplit("}", 1)[-1] == "pos_b"), None)
        if not label or label in seen or pos_b is None or not pos_b.text:
            continue
        seen.add(label)
        anatomical.append((label, len(names) - 1, np.array(pos_b.text.split(), dtype=float)))


def _add_frame(p, frame, n_seg: int, times: list, positions: list, orientations: list) -> None:
    """A recorded frame's segment positions and orientations (calibration frames are skipped)."""
    if frame.get("type", "normal") != "normal":
        return  # identity and T-pose calibration frames
    parts = {c.tag.rsplit("}", 1)[-1]: c.text for c in frame}
    pos, ori = parts.get("position"), parts.get("orientation")
    if pos is None or ori is None:
        raise InputError(f"{p}: MVNX frame {frame.get('index')} lacks segment positions or orientations")
    try:
        xyz = np.array(pos.split(), dtype=float)
        quat = np.array(ori.split(), dtype=float)
    except ValueError:
        raise InputError(f"{p}: MVNX frame {frame.get('index')} holds a value that is not a number") from None
    if xyz.size != 3 * n_seg or quat.size != 4 * n_seg:
        raise InputError(
            f"{p}: MVNX frame {frame.get('index')} gives {xyz.size // 3} segment positions for {n_seg} segments"
        )
    times.append(float(frame.get("time", "nan")))
    positions.append(xyz.reshape(n_seg, 3))
    orientations.append(quat.reshape(n_seg, 4))


def _rotation_matrices(q: np.ndarray) -> np.ndarray:
    """Rotation matrices (... x 3 x 3) of unit quaternions (... x 4, scalar first)."""
    q = q / np.linalg.norm(q, axis=-1, keepdims=True)
    w, x, y, z = np.moveaxis(q, -1, 0)
    return np.stack(
        [
            np.stack([1 - 2 * (y * y + z * z), 2 * (x * y - w * z), 2 * (x * z + w * y)], axis=-1),
            np.stack([2 * (x * y + w * z), 1 - 2 * (x * x + z * z), 2 * (y * z - w * x)], axis=-1),
            np.stack([2 * (x * z - w * y), 2 * (y * z + w * x), 1 - 2 * (x * x + y * y)], axis=-1),
        ],
        axis=-2,
    )
