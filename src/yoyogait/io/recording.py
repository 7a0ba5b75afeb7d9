"""The one recording type every reader produces."""

from __future__ import annotations

from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from ..errors import InputError

AXES = ("x", "y", "z")


@dataclass
class Recording:
    """Motion-capture points over time, in metres.

    ``positions_m`` is frames x points x 3 in the file's frame, NaN where a
    point is missing (never zero).  ``time_s`` holds the timestamp of every
    frame; ``rate_hz`` is the nominal rate when the file has one.
    ``up_axis`` is ``"x"``, ``"y"`` or ``"z"`` when the file says it, else None.
    """

    positions_m: np.ndarray
    point_names: list[str]
    time_s: np.ndarray
    rate_hz: float | None = None
    up_axis: str | None = None
    source: str = ""
    metadata: dict = field(default_factory=dict)

    def __repr__(self) -> str:
        names = list(self.point_names)
        shown = ", ".join(names[:6]) + (f", ... ({len(names) - 6} more)" if len(names) > 6 else "")
        rate = f"{self.rate_hz:g} Hz" if self.rate_hz else "irregular rate"
        what = f"{len(names)} points: {shown}" if names else "ready velocities"
        return (
            f"Recording({self.source or 'in memory'}: {self.n_frames} frames at {rate}, {self.duration_s:.2f} s, "
            f"up {self.up_axis or 'not given'}, {what})"
        )

    @property
    def n_frames(self) -> int:
        return int(self.positions_m.shape[0])

    @property
    def duration_s(self) -> float:
        return float(self.time_s[-1] - self.time_s[0]) if self.n_frames > 1 else 0.0

    def point(self, name: str) -> np.ndarray:
        """Trajectory (frames x 3) of the point called ``name``."""
        return self.positions_m[:, self.index_of(name), :]

    def index_of(self, name: str) -> int:
        """Column of ``name`` in ``positions_m``; the error lists the points there are."""

        try:
            return self.point_names.index(name)
        except ValueError:
            raise InputError(
                f"no point {name!r} in {self.source or 'the recording'}; "
                f"available: {', '.join(self.point_names) or '(none)'}"
            ) from None

    def points(self, names) -> np.ndarray:
        """Trajectories (frames x len(names) x 3) of several points, in the order given."""
        return self.positions_m[:, [self.index_of(n) for n in names], :]

    @property
    def format(self) -> str:
        """Which reader made this recording ("c3d", "trc", "bvh", "csv"), "" if none."""
        return str(self.metadata.get("format", ""))

    @property
    def velocities(self) -> dict | None:
        """Ready velocities from a velocity CSV: {"vx": ..., "vz": ...} in m/s, else None.

        Such a recording has no points; :func:`yoyogait.gait_velocities` resamples
        these instead of differentiating positions.
        """
        return self.metadata.get("velocities_mps")

    def visible(self) -> np.ndarray:
        """Bool frames x points: True where the point has a position."""
        return np.all(np.isfinite(self.positions_m), axis=2)


#: Metres per length unit, by the names files use for them.
LENGTH_UNITS_M = {
    "m": 1.0,
    "meter": 1.0,
    "meters": 1.0,
    "metre": 1.0,
    "metres": 1.0,
    "dm": 0.1,
    "cm": 0.01,
    "mm": 0.001,
    "in": 0.0254,
    "inch": 0.0254,
    "inches": 0.0254,
    "ft": 0.3048,
    "feet": 0.3048,
}


def length_unit_m(name: str, source: str = "") -> float:
    """Metres per unit for a unit name such as "mm"; InputError if unknown."""

    key = str(name).strip().lower()
    if key not in LENGTH_UNITS_M:
        raise InputError(
            f"{source or 'file'}: unknown length unit {name!r} "
            f"(known: {', '.join(sorted(set(LENGTH_UNITS_M)))}); pass length_unit_m="
        )
    return LENGTH_UNITS_M[key]


def check_readable(path) -> Path:
    """The path as a Path if it names a non-empty regular file, else InputError.

    Readers call this first so that a missing or empty file gets one clear
    sentence instead of a parser error from deep inside a library.
    """

    p = Path(path)
    if not p.exists():
        raise InputError(f"{p}: no such file")
    if not p.is_file():
        raise InputError(f"{p}: not a regular file")
    if p.stat().st_size == 0:
        raise InputError(f"{p}: the file is empty")
    return p


def read_text(path, encoding: str = "utf-8") -> tuple[Path, str]:
    """(path, its text) of a readable text file; undecodable bytes become U+FFFD, errors InputError."""

    p = check_readable(path)
    try:
        return p, p.read_text(encoding=encoding, errors="replace")
    except OSError as exc:
        raise InputError(f"{p}: cannot read ({exc.strerror})") from None


def number_row(cells, where, line_number: int) -> list[float]:
    """The cells of a text row as floats, empty cells NaN; InputError naming the first bad cell."""

    try:
        return [float(c) if c.strip() else np.nan for c in cells]
    except ValueError:
        bad = next(c for c in cells if c.strip() and not _is_float(c))
        raise InputError(f"{where}: line {line_number}: {bad.strip()!r} is not a number") from None


def _is_float(text: str) -> bool:
    try:
        float(text)
    except ValueError:
        return False
    return True


def uniform_time(n_frames: int, rate_hz: float, start_s: float = 0.0) -> np.ndarray:
    """Timestamps of ``n_frames`` samples at ``rate_hz`` from ``start_s``."""
    return start_s + np.arange(n_frames, dtype=float) / float(rate_hz)


def unique_names(names) -> list[str]:
    """Names made unique: a repeated name gets ``#2``, ``#3`` (as the C3D reader does)."""
    seen: dict[str, int] = {}
    out = []
    for n in names:
        k = seen.get(n, 0) + 1
        seen[n] = k
        out.append(n if k == 1 else f"{n}#{k}")
    return out
