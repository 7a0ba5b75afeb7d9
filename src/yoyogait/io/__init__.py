"""Readers of motion-capture files into :class:`Recording`.

:func:`read` picks the reader by the file's extension and, for ``.csv``, by
its first line:

=============  ===============================================  =============================================
``.c3d``       Vicon, Qualisys, Motion Analysis, Codamotion     :func:`yoyogait.io.c3d.read_c3d`
``.trc``       OpenSim, AddBiomechanics, Cortex, pyomeca        :func:`yoyogait.io.trc.read_trc`
``.bvh``       animation pipelines, Xsens, CMU, Bandai Namco    :func:`yoyogait.io.bvh.read_bvh`
``.tsv``       Qualisys Track Manager 3D export                 :func:`yoyogait.io.qtm.read_qtm_tsv`
``.mvnx``      Xsens MVN                                        :func:`yoyogait.io.mvnx.read_mvnx`
``.mot/.sto``  OpenSim coordinates (pelvis_tx/ty/tz)            :func:`yoyogait.io.opensim.read_opensim`
``.csv``       Vicon Nexus (a section title: ``Trajectories``)  :func:`yoyogait.io.nexus.read_nexus_csv`
``.csv``       OptiTrack Motive (first line ``Format Version``) :func:`yoyogait.io.motive.read_motive_csv`
``.csv``       anything else, in the layout of docs/input.md    :func:`yoyogait.io.csv.read_csv`
``.txt``       marker table (``Time``, ``R.ASISX``, ...)         :func:`yoyogait.io.marker_table.read_marker_table`
``.txt/.json`` DeepMimic motion clip (``"Frames"``)             :func:`yoyogait.io.deepmimic.read_deepmimic`
=============  ===============================================  =============================================

``.csv`` is told apart by its first line with content (Nexus exports may
start with blank or comma-only lines).  ``.txt`` and ``.json`` are read
only when their content is one of the layouts above (:data:`TEXT_DIALECTS`);
any other ``.txt`` or ``.json`` is refused in one line saying what is read.

Every reader returns positions in metres with NaN for a missing sample, never
zero.  Bad input raises :class:`yoyogait.errors.InputError` with one sentence
saying what is wrong.
"""

from __future__ import annotations

import importlib
import inspect
import warnings

import numpy as np

from ..errors import InputError
from .body import check_declared_up_axis
from .motion_bids import channels_file
from .plausibility import check_plausible
from .recording import AXES, Recording, check_coordinates, check_rate, check_readable, check_time

__all__ = ["Recording", "read", "READERS"]

#: Extension -> (module, function) of its reader.
READERS = {
    ".c3d": ("c3d", "read_c3d"),
    ".trc": ("trc", "read_trc"),
    ".bvh": ("bvh", "read_bvh"),
    ".csv": ("csv", "read_csv"),
    ".tsv": ("qtm", "read_qtm_tsv"),  # or Motion-BIDS, when a _channels.tsv stands beside it (io/motion_bids.py)
    ".mvnx": ("mvnx", "read_mvnx"),
    ".mot": ("opensim", "read_opensim"),
    ".sto": ("opensim", "read_opensim"),
}
#: CSV dialects told apart by the first line: (module, test, reader); else yoyogait's own layout.
CSV_DIALECTS = (
    ("nexus", "is_nexus_csv", "read_nexus_csv"),
    ("motive", "is_motive_csv", "read_motive_csv"),
)
#: Text files read by content, not extension: extension -> ((module, test, reader), ...); each test
#: takes the file's first 4 kB.  A .txt or .json that none of them claims is refused.
TEXT_DIALECTS = {
    ".txt": (
        ("deepmimic", "is_deepmimic", "read_deepmimic"),
        ("marker_table", "is_marker_table", "read_marker_table"),
    ),
    ".json": (("deepmimic", "is_deepmimic", "read_deepmimic"),),
}
#: Files people have that are not motion capture yoyogait reads: extension -> what to do instead.
NOT_READ = {
    ".npz": "AMASS/SMPL parameters: export the body's joint positions to a CSV (docs/input.md)",
    ".fbx": "FBX animation: export it as BVH",
    ".json": "JSON that is not a DeepMimic motion clip (a body-tracking export or a manifest?): "
    "export positions to a CSV (docs/input.md)",
    ".txt": "a text file that is neither a marker table (Time, then NameX, NameY, NameZ columns) "
    "nor a DeepMimic motion clip",
    ".xlsx": "a spreadsheet: save it as CSV",
}


def read(
    path,
    *,
    length_unit_m: float | None = None,
    up_axis: str | None = None,
    capture_rate_hz: float | None = None,
    plausibility: bool = True,
    rate_hz: float | None = None,
    **options,
) -> Recording:
    """Read a motion-capture file into a :class:`Recording`.

    The reader is chosen by extension (see :data:`READERS`).  The overrides
    stand in for what a file lacks, and win over what it says:

    * ``length_unit_m``: metres per file length unit (BVH has none; without it
      the BVH reader infers it from the standing pelvis height);
    * ``up_axis``: "x", "y" or "z" (else the file's own, else detected later);
    * ``capture_rate_hz``: the capture rate (a CSV without a time column needs it); ``rate_hz`` is its
      old name, still taken with a DeprecationWarning (the rate the pipeline resamples to is
      ``gait_velocities``' ``rate_hz``).

    With ``plausibility`` (the default) the result is checked against what a
    person is and does (:func:`yoyogait.io.plausibility.check_plausible`): a
    body off by a length-unit factor, a stated up axis that puts the pelvis
    on the floor, or a pelvis faster than anyone can walk is an InputError
    naming the likely cause and the option that fixes it.

    Other keyword ``options`` go to the reader.
    """
    p = check_readable(path)
    ext = p.suffix.lower()
    text_reader = _text_dialect(p) if ext in TEXT_DIALECTS else None
    if ext not in READERS and text_reader is None:
        hint = f" ({NOT_READ[ext]})" if ext in NOT_READ else ""
        raise InputError(
            f"{p}: unknown file type {p.suffix or '(no extension)'!r}{hint}; readable: {', '.join(sorted(READERS))}"
        )
    if up_axis is not None and str(up_axis).lower() not in AXES:
        raise InputError(f"up_axis must be one of x, y, z, not {up_axis!r}")
    if length_unit_m is not None and not (np.isfinite(length_unit_m) and length_unit_m > 0):
        raise InputError(f"length_unit_m must be a positive number, not {length_unit_m!r}")
    if rate_hz is not None:
        if capture_rate_hz is not None:
            raise InputError("give capture_rate_hz (rate_hz is its old name), not both")
        warnings.warn("io.read(rate_hz=...) is now capture_rate_hz=...", DeprecationWarning, stacklevel=2)
        capture_rate_hz = rate_hz
    rate_hz = capture_rate_hz  # the readers' own argument
    if rate_hz is not None and not (np.isfinite(rate_hz) and rate_hz > 0):
        raise InputError(f"capture_rate_hz must be a positive number, not {rate_hz!r}")
    if rate_hz is not None:
        check_rate(rate_hz, p, "capture_rate_hz override")

    if text_reader is not None:
        module, function = text_reader
    elif ext == ".tsv" and channels_file(p) is not None:  # a _channels.tsv beside it: Motion-BIDS, not QTM
        module, function = "motion_bids", "read_motion_bids"
    else:
        module, function = READERS[ext] if ext != ".csv" else _csv_dialect(p)
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
    check_declared_up_axis(rec)
    if plausibility:
        check_plausible(rec)
    return rec


def _csv_dialect(p) -> tuple[str, str]:
    """(module, reader) for a CSV file: Nexus or Motive by their first line with content, else yoyogait's layout."""
    first = ""
    try:
        with open(p, encoding="utf-8-sig", errors="replace") as f:
            for _, line in zip(range(50), f):
                if line.strip().strip(",").strip():
                    first = line
                    break
    except OSError as exc:
        raise InputError(f"{p}: cannot read ({exc.strerror})") from None
    for module, test, function in CSV_DIALECTS:
        if getattr(importlib.import_module(f".{module}", __name__), test)(first):
            return module, function
    return READERS[".csv"]


def _text_dialect(p) -> tuple[str, str] | None:
    """(module, reader) for a .txt or .json file whose content one of :data:`TEXT_DIALECTS` claims, else None."""
    try:
        with open(p, encoding="utf-8-sig", errors="replace") as f:
            head = f.read(4096)
    except OSError as exc:
        raise InputError(f"{p}: cannot read ({exc.strerror})") from None
    for module, test, function in TEXT_DIALECTS[p.suffix.lower()]:
        if getattr(importlib.import_module(f".{module}", __name__), test)(head):
            return module, function
    return None


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
    dialects = [*CSV_DIALECTS, *(d for ds in TEXT_DIALECTS.values() for d in ds)]
    for module, function in [*READERS.values(), *((m, f) for m, _, f in dialects)]:
        if name == function:
            return getattr(importlib.import_module(f".{module}", __name__), function)
    raise AttributeError(f"module {__name__!r} has no attribute {name!r}")
