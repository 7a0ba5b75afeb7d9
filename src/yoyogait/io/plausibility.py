"""Is this a person?  The size and speed of what a reader produced, against what people are and do.

A wrong length unit scales everything: a TRC whose header says ``m`` but
holds millimetres puts the pelvis 950 m above the floor and walks it at
1200 m/s; ``cm`` for millimetres gives 9.5 m and a plausible-looking speed.
A wrong up axis puts the pelvis a few centimetres "above" the feet.  These
checks run on every recording :func:`yoyogait.io.read` returns and turn such
a file into one :class:`~yoyogait.errors.InputError` that names the likely
cause and the option that fixes it (``--length-unit-m``, ``--up-axis``,
``--capture-rate-hz``).  What is merely unusual (a seated subject, a file with
objects beside the person) passes: only a body whose size is off by a unit
factor, or a pelvis that moves faster than anyone can, is refused.

Measures (medians over the recording, so that marker gaps and swaps do not
decide): the body size (largest extent of the points of a frame), the
pelvis height above the lowest point of the frame along the up axis, and
the pelvis's horizontal speed over 0.5 s.
"""

from __future__ import annotations

import warnings

import numpy as np

from ..errors import InputError
from .marker_sets import pelvis_names
from .recording import AXES, LENGTH_UNITS_M, Recording

__all__ = ["check_plausible", "body_measures", "BODY_SIZE_M", "PELVIS_HEIGHT_M", "MAX_SPEED_MPS", "SPRINT_SPEED_MPS"]

#: Median largest extent of a frame's points: a few markers on one segment to a person with lab objects.
BODY_SIZE_M = (0.05, 4.0)
#: Pelvis above the lowest point (the feet) of a standing or walking person: a small child to a tall adult.
PELVIS_HEIGHT_M = (0.4, 1.4)
#: Median horizontal pelvis speed: faster than any person sustains.
MAX_SPEED_MPS = 8.0
#: Up to this a body of the right size is a sprinter (the fastest reach about 12 m/s), not a wrong rate alone.
SPRINT_SPEED_MPS = 13.0
_TYPICAL_PELVIS_M = 0.95
_TYPICAL_SIZE_M = 1.6


def body_measures(rec: Recording, up_axis: str | None = None) -> dict:
    """Median body size (m), pelvis height per axis (m), horizontal speed (m/s) and the pelvis used."""
    pos = rec.positions_m
    names, _ = pelvis_names(rec.point_names)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", RuntimeWarning)
        if names:
            pelvis = np.nanmean(rec.points(names), axis=1)
        else:
            pelvis = np.nanmean(pos, axis=1)
        extent = np.nanmax(pos, axis=1) - np.nanmin(pos, axis=1)
        size = float(np.nanmedian(np.nanmax(extent, axis=1))) if pos.shape[1] > 1 else float("nan")
        height = np.nanmedian(pelvis - np.nanmin(pos, axis=1), axis=0) if names and pos.shape[1] > 1 else None
        t = np.asarray(rec.time_s, dtype=float)
        lag = max(1, int(np.searchsorted(t - t[0], 0.5))) if len(t) > 1 else 0
        speed = float("nan")
        if lag and len(t) > lag:
            k = AXES.index(up_axis) if up_axis in AXES else None
            axes = [a for a in range(3) if a != k]
            step = pelvis[lag:, axes] - pelvis[:-lag, axes]
            speed = float(np.nanmedian(np.linalg.norm(step, axis=1) / (t[lag:] - t[:-lag])))
    return {
        "size_m": size,
        "pelvis_height_m": None if height is None else {a: float(h) for a, h in zip(AXES, height)},
        "speed_mps": speed,
        "pelvis": names,
    }


def check_plausible(rec: Recording) -> Recording:
    """InputError (one sentence: measure, likely cause, the option that fixes it) if the recording is no person."""
    if rec.velocities is not None or rec.positions_m.shape[1] == 0:
        return rec
    where = rec.source or "recording"
    up = rec.up_axis
    m = body_measures(rec, up)
    unit = float(rec.metadata.get("length_unit_m", 1.0))
    unit_from = rec.metadata.get("length_unit_from", "")
    if unit_from == "override":
        said = f"--length-unit-m {unit:g}"
    else:
        said = f"the length unit {_unit_name(unit)}" + (f" ({unit_from})" if unit_from else "")
    height = m["pelvis_height_m"]
    size = m["size_m"]

    observed: float | None = height[up] if height is not None and up is not None else None
    if np.isfinite(size) and size > 0 and not BODY_SIZE_M[0] <= size <= BODY_SIZE_M[1]:
        h = observed if observed is not None and observed > 0 else None
        if not (h is not None and PELVIS_HEIGHT_M[0] <= h <= PELVIS_HEIGHT_M[1]):  # a right pelvis: no unit error
            likely = _likely_unit(
                (h if h is not None else size) / unit, _TYPICAL_PELVIS_M if h is not None else _TYPICAL_SIZE_M
            )
            if abs(likely / unit - 1) > 1e-6:  # only a factor that some unit explains is called a unit error
                what = (
                    f"the pelvis stands {h:.4g} m above the lowest point (people: 0.6-1.2 m)"
                    if h is not None
                    else f"the body spans {size:.4g} m (people: 0.5-2 m)"
                )
                raise InputError(f"{where}: not the size of a person: {what} with {said}; {_fix(likely)}")

    by_convention = rec.metadata.get("up_axis_declared") is not None and rec.metadata.get(
        "up_axis_from"
    ) == rec.metadata.get("up_axis_declared_by")
    if height is not None and up is not None and not by_convention:  # a format's convention is a guess, not a fact
        h_up = height[up]
        if h_up < PELVIS_HEIGHT_M[0]:  # the pelvis near the floor along the stated axis, high along another
            others = {a: h for a, h in height.items() if a != up and 0.6 <= h <= 1.3 and h > 2 * h_up}
            if others:
                best = max(others, key=lambda a: others[a])
                source = rec.metadata.get("up_axis_from", "file")
                origin = "--up-axis" if source == "override" else "the file" if source == "file" else source
                raise InputError(
                    f"{where}: the up axis {up} (from {origin}) puts the pelvis {h_up:.2f} m above the lowest point, "
                    f"{best} puts it {others[best]:.2f} m: the up axis is probably {best}; pass --up-axis {best}"
                )

    speed = m["speed_mps"]
    if np.isfinite(speed) and speed > MAX_SPEED_MPS:
        body_ok = observed is not None or (np.isfinite(size) and 0.3 <= size <= 3.0)  # then the unit is not it
        likely = unit if body_ok else _likely_unit(speed / unit, 1.3)
        rate = f"{rec.rate_hz:g} Hz" if rec.rate_hz else "the file's times"
        if body_ok and speed <= SPRINT_SPEED_MPS:
            raise InputError(
                f"{where}: faster than anyone walks: the pelvis moves at a median {speed:.2f} m/s with {said} at "
                f"{rate} and a body of a person's size: a sprint (people walk at 0.5-2 m/s), and yoyogait "
                "estimates walking; if the rate is wrong pass --capture-rate-hz"
            )
        raise InputError(
            f"{where}: faster than a person: the pelvis moves at a median {speed:.2f} m/s (people walk at 0.5-2 m/s) "
            f"with {said} at {rate}; "
            + (
                f"{_fix(likely)}, or if the rate is wrong pass --capture-rate-hz"
                if likely != unit
                else "the body's size is right, so is the rate? pass --capture-rate-hz"
            )
        )
    rec.metadata["plausibility"] = {
        "size_m": size,
        "pelvis_height_m": None if height is None or up is None else height[up],
        "speed_mps": speed,
    }
    return rec


def _unit_name(unit_m: float) -> str:
    names = {1.0: "m", 0.1: "dm", 0.01: "cm", 0.001: "mm", 0.0254: "inch", 0.3048: "foot"}
    return next((n for u, n in names.items() if abs(u - unit_m) <= 1e-9 * u), f"{unit_m:g} m")


def _likely_unit(value_in_file_units: float, typical_m: float) -> float:
    """The length unit (metres per file unit) that makes ``value_in_file_units`` nearest to ``typical_m``."""
    units = sorted(set(LENGTH_UNITS_M.values()))
    return min(units, key=lambda u: abs(np.log(value_in_file_units * u / typical_m)))


def _fix(unit_m: float) -> str:
    """'the numbers look like mm: pass --length-unit-m 0.001'."""
    return f"the numbers look like {_unit_name(unit_m)}: pass --length-unit-m {unit_m:g}"
