"""DeepMimic motion clips: JSON with one row per frame, the root (pelvis) first.

The layout DeepMimic (Peng et al. 2018) and the projects built on it use for
reference motions (``data/motions/humanoid3d_walk.txt``; ``.txt`` or
``.json``)::

    {
    "Loop": "wrap",
    "Frames":
    [
    [0.0333, 0.0000, 0.8475, 0.0000, 0.9987, 0.0141, -0.0007, -0.0494, ...],
    ...                   <- duration of the frame (s), root position x, y, z (m), root rotation w, x, y, z,
    ]                        then the joints' rotations
    }

The root is the humanoid's pelvis, so the clip becomes one point, ``root``
(in metres), timed by the frame durations.  The clips are Y up (the
character stands on the x-z plane), which the reader declares as the
file's up axis by convention; with a single point the body's geometry can
check it only by the pelvis's bounces (:func:`yoyogait.io.body.detect_up_axis`).

A clip with ``"Loop": "wrap"`` is one gait cycle or two, whose last frame
(duration 0) is the first pose of the next cycle.  DeepMimic plays such a
clip over and over, each cycle starting where the root left the last one;
the reader does the same up to :data:`LOOPED_DURATION_S` (the horizontal
displacement carried over; the heading kept), and says so in
``metadata["looped_cycles"]``.
With one point there are no feet, so an evaluation has no foot-contact
reference on such a clip.
"""

from __future__ import annotations

import json

import numpy as np

from ..errors import InputError
from .recording import Recording, check_rate, read_text

__all__ = ["read_deepmimic", "is_deepmimic"]

CONVENTION_UP_AXIS = "y"
#: A wrapping clip shorter than this is played again until it is this long.
LOOPED_DURATION_S = 10.0


def is_deepmimic(head: str) -> bool:
    """True if the text is a JSON object whose first keys include ``"Frames"`` (a DeepMimic clip)."""
    text = head.lstrip("\ufeff \t\r\n")
    return text.startswith("{") and '"Frames"' in text[:2000]


def read_deepmimic(path, *, length_unit_m: float | None = None, rate_hz: float | None = None) -> Recording:
    """Read the root (pelvis) trajectory of a DeepMimic motion clip."""
    p, text = read_text(path, encoding="utf-8-sig")
    try:
        clip = json.loads(text)
    except json.JSONDecodeError as exc:
        raise InputError(f"{p}: a DeepMimic clip must be JSON: line {exc.lineno}: {exc.msg}") from None
    frames = clip.get("Frames") if isinstance(clip, dict) else None
    if not isinstance(frames, list) or not frames:
        raise InputError(f'{p}: the DeepMimic clip has no "Frames" list')
    rows = []
    for k, f in enumerate(frames):
        if not isinstance(f, list) or len(f) < 4 or not all(isinstance(v, (int, float)) for v in f[:4]):
            raise InputError(
                f"{p}: DeepMimic frame {k + 1} must start with a duration and the root's x, y, z (numbers)"
            )
        rows.append([float(v) for v in f[:4]])
    table = np.asarray(rows, dtype=float)
    metadata: dict = {"format": "deepmimic", "loop": clip.get("Loop")}
    if clip.get("Loop") == "wrap" and len(rows) > 2 and rate_hz is None:
        table, metadata["looped_cycles"] = _looped(table, CONVENTION_UP_AXIS)
    durations = table[:, 0]
    if rate_hz is not None:
        rate = float(rate_hz)
        time_s = np.arange(len(rows)) / rate
    else:
        if not np.all(np.isfinite(durations[:-1])) or np.any(durations[:-1] <= 0):
            bad = int(np.argmax(~(durations[:-1] > 0)))
            raise InputError(
                f"{p}: DeepMimic frame {bad + 1} has a duration of {durations[bad]:g} s; pass --capture-rate-hz"
            )
        time_s = np.concatenate([[0.0], np.cumsum(durations[:-1])])
        rate = check_rate(1.0 / float(np.median(durations[:-1])) if len(rows) > 1 else 30.0, p, "frame rate")
    scale_m = float(length_unit_m) if length_unit_m is not None else 1.0
    metadata["length_unit_m"] = scale_m
    metadata["length_unit_from"] = "override" if length_unit_m is not None else "m (DeepMimic clips are in metres)"
    metadata["up_axis_declared"] = CONVENTION_UP_AXIS
    metadata["up_axis_declared_by"] = "the DeepMimic convention (Y up)"
    return Recording(
        positions_m=table[:, None, 1:4] * scale_m,
        point_names=["root"],
        time_s=time_s,
        rate_hz=round(rate, 6),
        up_axis=None,
        source=str(p),
        metadata=metadata,
    )


def _looped(table: np.ndarray, up_axis: str) -> tuple[np.ndarray, int]:
    """The clip played until :data:`LOOPED_DURATION_S`, each cycle moved on by the last one's displacement."""
    cycle_s = float(np.sum(table[:-1, 0]))
    if not np.isfinite(cycle_s) or cycle_s <= 0 or cycle_s >= LOOPED_DURATION_S:
        return table, 1
    n = int(np.ceil(LOOPED_DURATION_S / cycle_s))
    shift = table[-1, 1:4] - table[0, 1:4]
    shift["xyz".index(up_axis)] = 0.0  # the root's height does not accumulate
    parts = []
    for k in range(n):
        part = table[:-1].copy()
        part[:, 1:4] += k * shift
        parts.append(part)
    last = table[-1:].copy()
    last[:, 1:4] += (n - 1) * shift
    return np.vstack([*parts, last]), n
