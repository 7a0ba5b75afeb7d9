"""Guide paths: waypoints in the floor plane, the pace between them and the stops at them.

A path file is a CSV with a header line and one waypoint a line (lines starting with ``#`` are
comments)::

    x_m,y_m,pace,stop_s
    0,0,1.0,0
    10,0,1.35,0
    20,0,0.7,3
    30,0,,

``x_m``, ``y_m`` (required): the waypoint in metres; the walk starts at the first one, heading to
the second, and ends at the last.  ``pace`` (optional, default 1): the guiding force from this
waypoint on, as a multiple of the nominal one (0.2-2; a person guided by the force walks faster or
slower with it).  ``stop_s`` (optional, default 0): a stop at this waypoint for that many seconds
before the guidance goes on.  Empty cells take the default.  The path between waypoints is
straight; consecutive waypoints must be at least 0.5 m apart.
"""

from __future__ import annotations

import csv
import math
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from ..errors import InputError

__all__ = ["GuidePath", "read_path", "BUILTIN_WALKS", "builtin_walk", "MIN_SEGMENT_M", "PACE_RANGE"]

MIN_SEGMENT_M = 0.5
"""Shortest distance between consecutive waypoints [m]."""
PACE_RANGE = (0.2, 2.0)
"""Allowed pace multipliers."""
MAX_STOP_S = 60.0
MAX_WAYPOINTS = 1000
MAX_COORD_M = 1e4


@dataclass(frozen=True)
class GuidePath:
    """A polyline of waypoints with a pace from each waypoint on and a stop at each (SYNTHETIC walks).

    ``xy_m`` (n x 2), ``pace`` (n), ``stop_s`` (n); ``name`` says where it came from.
    """

    name: str
    xy_m: np.ndarray
    pace: np.ndarray
    stop_s: np.ndarray

    def __post_init__(self):
        xy = np.asarray(self.xy_m, dtype=float)
        n = len(xy)
        if xy.ndim != 2 or xy.shape[1] != 2 or n < 2:
            raise InputError(f"{self.name}: a path needs at least 2 waypoints (x_m, y_m)")
        if n > MAX_WAYPOINTS:
            raise InputError(f"{self.name}: at most {MAX_WAYPOINTS} waypoints, got {n}")
        if not np.all(np.isfinite(xy)) or np.any(np.abs(xy) > MAX_COORD_M):
            raise InputError(f"{self.name}: waypoints must be finite and within {MAX_COORD_M:g} m")
        seg = np.hypot(*np.diff(xy, axis=0).T)
        short = np.flatnonzero(seg < MIN_SEGMENT_M)
        if short.size:
            raise InputError(
                f"{self.name}: waypoints {short[0] + 1} and {short[0] + 2} are {seg[short[0]]:.3g} m apart "
                f"(at least {MIN_SEGMENT_M} m)"
            )
        pace = np.asarray(self.pace, dtype=float)
        stop = np.asarray(self.stop_s, dtype=float)
        if pace.shape != (n,) or stop.shape != (n,):
            raise InputError(f"{self.name}: pace and stop_s need one value per waypoint")
        if not np.all((pace >= PACE_RANGE[0]) & (pace <= PACE_RANGE[1])):
            raise InputError(f"{self.name}: pace must be in [{PACE_RANGE[0]}, {PACE_RANGE[1]}]")
        if not np.all((stop >= 0) & (stop <= MAX_STOP_S)):
            raise InputError(f"{self.name}: stop_s must be in [0, {MAX_STOP_S:g}] s")
        object.__setattr__(self, "xy_m", xy)
        object.__setattr__(self, "pace", pace)
        object.__setattr__(self, "stop_s", stop)

    @property
    def cumulative_m(self) -> np.ndarray:
        """Arc length at each waypoint [m]."""
        return np.concatenate([[0.0], np.cumsum(np.hypot(*np.diff(self.xy_m, axis=0).T))])

    @property
    def length_m(self) -> float:
        return float(self.cumulative_m[-1])

    def point(self, s_m: float) -> tuple[float, float, float, float]:
        """Point (x, y) and unit tangent (tx, ty) at arc length ``s_m``; beyond the ends, the first
        and last segments continue straight."""
        cum = self.cumulative_m
        i = int(np.clip(np.searchsorted(cum, s_m, side="right") - 1, 0, len(cum) - 2))
        a, b = self.xy_m[i], self.xy_m[i + 1]
        d = b - a
        seg = math.hypot(d[0], d[1])
        tx, ty = d[0] / seg, d[1] / seg
        u = s_m - cum[i]
        return a[0] + u * tx, a[1] + u * ty, tx, ty

    def project(self, x: float, y: float, s_hint_m: float, window_m: float = 3.0) -> float:
        """Arc length of the point of the path nearest to (x, y) among those within ``window_m``
        ahead of or behind ``s_hint_m`` (so that a path that comes back near itself is followed in order)."""
        cum = self.cumulative_m
        best_s, best_d = s_hint_m, math.inf
        lo, hi = s_hint_m - window_m, s_hint_m + window_m
        for i in range(len(cum) - 1):
            if cum[i + 1] < lo or cum[i] > hi:
                continue
            a, b = self.xy_m[i], self.xy_m[i + 1]
            d = b - a
            seg2 = float(d @ d)
            u = ((x - a[0]) * d[0] + (y - a[1]) * d[1]) / seg2
            u = min(max(u, 0.0), 1.0)
            px, py = a[0] + u * d[0], a[1] + u * d[1]
            dist = math.hypot(x - px, y - py)
            s = cum[i] + u * math.sqrt(seg2)
            if dist < best_d - 1e-12 and lo <= s <= hi:
                best_s, best_d = s, dist
        return best_s

    def distance(self, xy, *, extend_ends: bool = False) -> np.ndarray:
        """Distance of each point (m x 2) to the polyline [m]; ``extend_ends``: the first and last
        segments continue straight beyond the ends (the distance sideways, not along)."""
        p = np.atleast_2d(np.asarray(xy, dtype=float))
        a = self.xy_m[:-1][None]
        d = np.diff(self.xy_m, axis=0)[None]
        lo = np.zeros(d.shape[1])
        hi = np.ones(d.shape[1])
        if extend_ends:
            lo[0], hi[-1] = -np.inf, np.inf
        u = np.clip(np.sum((p[:, None] - a) * d, axis=2) / np.sum(d * d, axis=2), lo, hi)
        near = a + u[..., None] * d
        return np.min(np.hypot(*(p[:, None] - near).transpose(2, 0, 1)), axis=1)

    def pace_at(self, s_m: float, blend_m: float = 1.0) -> float:
        """The pace at arc length ``s_m``: each segment's, changing smoothly (raised cosine) over
        ``blend_m`` centred on the waypoint where it changes."""
        cum = self.cumulative_m
        pace = float(self.pace[0])
        for i in range(1, len(cum) - 1):
            step = float(self.pace[i] - self.pace[i - 1])
            if step:
                u = min(max((s_m - cum[i]) / blend_m + 0.5, 0.0), 1.0)
                pace += step * (0.5 - 0.5 * math.cos(math.pi * u))
        return pace

    def corners(self, min_turn_rad: float = math.radians(30)) -> list[tuple[float, float]]:
        """(arc length, turn angle) of each inner waypoint where the path turns by more than ``min_turn_rad``."""
        d = np.diff(self.xy_m, axis=0)
        heading = np.arctan2(d[:, 1], d[:, 0])
        turns = np.angle(np.exp(1j * np.diff(heading)))
        cum = self.cumulative_m
        return [(float(cum[i + 1]), float(t)) for i, t in enumerate(turns) if abs(t) > min_turn_rad]

    def stops(self) -> list[tuple[float, float]]:
        """(arc length, seconds) of each inner waypoint with a stop."""
        cum = self.cumulative_m
        return [(float(cum[i]), float(self.stop_s[i])) for i in range(1, len(cum) - 1) if self.stop_s[i] > 0]


def _cell(row: dict, key: str, default: float, where: str) -> float:
    text = (row.get(key) or "").strip()
    if not text:
        return default
    try:
        value = float(text)
    except ValueError:
        raise InputError(f"{where}: {key} {text!r} is not a number") from None
    if not math.isfinite(value):
        raise InputError(f"{where}: {key} must be finite, got {text}")
    return value


def read_path(path) -> GuidePath:
    """A :class:`GuidePath` from a CSV file (the format above); InputError naming the file and line."""
    path = Path(path)
    try:
        text = path.read_text()
    except UnicodeDecodeError:
        raise InputError(f"{path}: not a text file (a path file is a CSV of waypoints x_m,y_m)") from None
    except OSError as exc:
        raise InputError(f"{path}: cannot read: {exc.strerror or exc}") from None
    lines = [(i + 1, line) for i, line in enumerate(text.splitlines()) if line.strip() and not line.startswith("#")]
    if not lines:
        raise InputError(f"{path}: empty; a path file is a CSV with the header x_m,y_m and one waypoint a line")
    reader = csv.DictReader([line for _, line in lines])
    fields = [f.strip() for f in (reader.fieldnames or [])]
    reader.fieldnames = fields
    missing = [k for k in ("x_m", "y_m") if k not in fields]
    if missing:
        raise InputError(f"{path}: the header must name x_m and y_m (optional: pace, stop_s); got {','.join(fields)}")
    unknown = [k for k in fields if k not in ("x_m", "y_m", "pace", "stop_s")]
    if unknown:
        raise InputError(f"{path}: unknown column {unknown[0]!r} (known: x_m, y_m, pace, stop_s)")
    xy, pace, stop = [], [], []
    for (lineno, _), row in zip(lines[1:], reader):
        where = f"{path}, line {lineno}"
        if None in row:
            raise InputError(f"{where}: more cells than the header has columns")
        if not (row.get("x_m") or "").strip() or not (row.get("y_m") or "").strip():
            raise InputError(f"{where}: x_m and y_m are required")
        xy.append((_cell(row, "x_m", math.nan, where), _cell(row, "y_m", math.nan, where)))
        pace.append(_cell(row, "pace", 1.0, where))
        stop.append(_cell(row, "stop_s", 0.0, where))
    try:
        return GuidePath(path.name, np.array(xy, dtype=float).reshape(-1, 2), np.array(pace), np.array(stop))
    except InputError as exc:
        raise InputError(f"{path}: {str(exc).split(': ', 1)[-1]}") from None


BUILTIN_WALKS: dict[str, tuple[list[tuple[float, float]], list[float], list[float]]] = {
    # A straight walk whose pace changes: nominal, faster, slower (cadence and speed change with it).
    "pace-changes": ([(0.0, 0.0), (8.0, 0.0), (16.0, 0.0), (24.0, 0.0)], [1.0, 1.35, 0.7, 0.7], [0, 0, 0, 0]),
    # A straight walk with two stops of 3 s.
    "stop-and-go": ([(0.0, 0.0), (7.0, 0.0), (14.0, 0.0), (20.0, 0.0)], [1.0, 1.0, 1.0, 1.0], [0, 3.0, 3.0, 0]),
    # Right-angle turns, left and right.
    "turns": ([(0.0, 0.0), (7.0, 0.0), (7.0, 5.0), (13.0, 5.0), (13.0, 0.0)], [1.0] * 5, [0.0] * 5),
}
"""The built-in SYNTHETIC guided walks: waypoints, pace and stops."""


def builtin_walk(name: str) -> GuidePath:
    """One of :data:`BUILTIN_WALKS` as a :class:`GuidePath`."""
    if name not in BUILTIN_WALKS:
        raise InputError(f"no built-in walk {name!r}; available: {', '.join(BUILTIN_WALKS)}")
    xy, pace, stop = BUILTIN_WALKS[name]
    return GuidePath(f"synthetic {name}", np.array(xy, dtype=float), np.array(pace, float), np.array(stop, float))
