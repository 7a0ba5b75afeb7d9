"""Readers of motion-capture files into :class:`Recording`.

:func:`read` picks the reader by the file's extension:

========  ==========================================  ================================
``.c3d``  Vicon, Qualisys, Motion Analysis, Codamotion  :func:`yoyogait.io.c3d.read_c3d`
``.trc``  OpenSim, AddBiomechanics, Cortex exports      :func:`yoyogait.io.trc.read_trc`
``.bvh``  animation pipelines, Xsens, CMU, Bandai Namco :func:`yoyogait.io.bvh.read_bvh`
``.csv``  anything else, in the layout of docs/input.md :func:`yoyogait.io.csv.read_csv`
========  ==========================================  ================================

Every reader returns positions in metres with NaN for a missing sample, never
zero.  Bad input raises :class:`yoyogait.errors.InputError` with one sentence
saying what is wrong.
"""

from __future__ import annotations

import importlib
import inspect

import numpy as np

from ..errors import InputError
from .recording import AXES, Recording, check_coordinates, check_rate, check_readable, check_time

__all__ = ["Recording", "read", "READERS"]

#: Extension -> (module, function) of its reader.
READERS = {
    ".c3d": ("c3d", "read_c3d"),
    ".trc": ("trc", "read_trc"),
    ".bvh": ("bvh", "read_bvh"),
    ".csv": ("csv", "read_csv"),
}


def read(
    path, *, length_unit_m: float | None = None, up_axis: str | None = None, rate_hz: float | None = None, **options
) -> Recording:
    """Read a motion-capture file into a :class:`Recording`.

    The reader is chosen by extension (see :data:`READERS`).  The overrides
    stand in for what a file lacks, and win over what it says:

    * ``length_unit_m``: metres per file length unit (BVH has none; without it
      the BVH reader infers it from the standing pelvis height);
    * ``up_axis``: "x", "y" or "z" (else the file's own, else detected later);
    * ``rate_hz``: the sample rate (a CSV without a time column needs it).

    Other keyword ``options`` go to the reader.
    """
    p = check_readable(path)
    ext = p.suffix.lower()
    if ext not in READERS:
        raise InputError(
            f"{p}: unknown file type {p.suffix or '(no extension)'!r}; readable: {', '.join(sorted(READERS))}"
        )
    if up_axis is not None and str(up_axis).lower() not in AXES:
        raise InputError(f"up_axis must be one of x, y, z, not {up_axis!r}")
    if length_unit_m is not None and not (np.isfinite(length_unit_m) and length_unit_m > 0):
        raise InputError(f"length_unit_m must be a positive number, not {length_unit_m!r}")
    if rate_hz is not None and not (np.isfinite(rate_hz) and rate_hz > 0):
        raise InputError(f"rate_hz must be a positive number, not {rate_hz!r}")
    if rate_hz is not None:
        check_rate(rate_hz, p, "rate_hz override")

    module, function = READERS[ext]
    reader = getattr(importlib.import_module(f".{module}", __name__), function)
    kwargs = dict(length_unit_m=length_unit_m, rate_hz=rate_hz, **options)
    if up_axis is not None and "up_axis" in inspect.signature(reader).parameters:
        kwargs["up_axis"] = str(up_axis).lower()  # the BVH reader needs it to infer the unit
    try:
        inspect.signature(reader).bind(p, **kwargs)
    except TypeError as exc:
        raise InputError(f"{p}: the {ext[1:].upper()} reader does not take that option ({exc})") from None
    rec = reader(p, **kwargs)
    if up_axis is not None:
        rec.up_axis = str(up_axis).lower()
        rec.metadata["up_axis_from"] = "override"
    elif rec.up_axis is not None:
        rec.metadata.setdefault("up_axis_from", "file")
    validate(rec)
    return rec


def validate(rec: Recording) -> Recording:
    """Check the invariants every reader promises; InputError where they fail."""
    where = rec.source or "recording"
    pos = rec.positions_m
    if pos.ndim != 3 or pos.shape[2] != 3 or pos.shape[1] != len(rec.point_names):
        raise InputError(f"{where}: positions must be frames x points x 3, got {pos.shape}")
    if rec.n_frames == 0:
        raise InputError(f"{where}: the file holds no frames")
    t = np.asarray(rec.time_s, dtype=float)
    if t.shape != (rec.n_frames,) or not np.all(np.isfinite(t)):
        raise InputError(f"{where}: timestamps are missing or not finite")
    check_time(t, where)
    if rec.rate_hz is not None:
        check_rate(rec.rate_hz, where)
    if np.any(np.isinf(pos)):
        raise InputError(f"{where}: positions hold infinite values")
    check_coordinates(pos, rec.point_names, where)
    if rec.velocities is None and (pos.shape[1] == 0 or not np.any(np.isfinite(pos))):
        raise InputError(f"{where}: the file holds no valid point position")
    return rec


def __getattr__(name: str):
    # read_c3d, read_trc, ... without importing every reader up front.
    for module, function in READERS.values():
        if name == function:
            return getattr(importlib.import_module(f".{module}", __name__), function)
    raise AttributeError(f"module {__name__!r} has no attribute {name!r}")
