"""The one recording type every reader produces."""

from __future__ import annotations

import re
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
        return all_xyz(np.isfinite(self.positions_m))


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


#: Sample rates a recording may have [Hz]: motion capture runs at 10-2000 Hz; outside this range the
#: rate (or a BVH frame time) is a corrupt number, and resampling from it would be meaningless.
RATE_RANGE_HZ = (1.0, 10000.0)

#: Farthest a coordinate may lie from the origin once in metres: no capture volume is 10 km wide,
#: so a larger value is a corrupt number or a wrong length unit.
MAX_COORDINATE_M = 1.0e4

#: Fastest a followed point or a given velocity may move [m/s]: no person moves at 50 m/s, so a
#: faster sample is a corrupt value (a jump of a marker), not gait.
MAX_SPEED_MPS = 50.0

#: The timestamps may span at most this many times the duration their samples cover (n x the
#: median period), plus :data:`TIME_SPAN_SLACK_S`; beyond that a timestamp is bogus, and the
#: resampled grid would be mostly an empty gap (a 1e10 s timestamp would ask for terabytes).
TIME_SPAN_FACTOR = 10.0
TIME_SPAN_SLACK_S = 60.0


def check_rate(rate_hz: float, where, what: str = "sample rate") -> float:
    """``rate_hz`` as a float if it lies in :data:`RATE_RANGE_HZ`, else InputError naming ``what``."""
    lo, hi = RATE_RANGE_HZ
    rate = float(rate_hz)
    if not (np.isfinite(rate) and lo <= rate <= hi):
        raise InputError(f"{where}: the {what} is {rate:g} Hz; a recording's rate must lie in {lo:g}-{hi:g} Hz")
    return rate


def check_time(time_s: np.ndarray, where, line_numbers=None) -> None:
    """InputError unless the timestamps are finite, increase strictly and span a sane time.

    ``line_numbers`` (one per sample) makes the message name the file's line; else it names the
    frame (counted from 1).  A repeated or decreasing timestamp names both rows; a time span far
    larger than the samples cover (:data:`TIME_SPAN_FACTOR`) names the largest jump.
    """
    t = np.asarray(time_s, dtype=float)

    def at(k: int) -> str:
        return f"line {line_numbers[k]}" if line_numbers is not None else f"frame {k + 1}"

    bad = np.flatnonzero(~np.isfinite(t))
    if bad.size:
        raise InputError(f"{where}: {at(int(bad[0]))}: the timestamp is {t[bad[0]]}, not a finite number")
    if len(t) < 2:
        return
    dt = np.diff(t)
    back = np.flatnonzero(dt <= 0)
    if back.size:
        k = int(back[0])
        how = "repeats" if dt[k] == 0 else "goes back from"
        raise InputError(
            f"{where}: {at(k + 1)}: time {how} {t[k]:g} s ({at(k)})"
            + ("" if dt[k] == 0 else f" to {t[k + 1]:g} s")
            + "; timestamps must increase"
        )
    period = float(np.median(dt))
    covered = len(t) * period
    span = float(t[-1] - t[0])
    if span > TIME_SPAN_FACTOR * covered + TIME_SPAN_SLACK_S:
        k = int(np.argmax(dt))
        raise InputError(
            f"{where}: {at(k + 1)}: time jumps from {t[k]:g} s to {t[k + 1]:g} s; the {len(t)} samples cover "
            f"{covered:.3g} s but their timestamps span {span:.3g} s (a bogus timestamp?)"
        )


def all_xyz(mask: np.ndarray) -> np.ndarray:
    """``mask.all(axis=-1)`` for a mask of x, y, z triples: the same, several times faster than numpy's
    reduction over an axis of 3."""
    if mask.shape[-1] != 3:
        return np.all(mask, axis=-1)
    return mask[..., 0] & mask[..., 1] & mask[..., 2]


def check_coordinates(positions_m: np.ndarray, names, where, line_numbers=None) -> None:
    """InputError if a coordinate (in metres) lies beyond :data:`MAX_COORDINATE_M` from the origin."""
    pos = np.asarray(positions_m, dtype=float)
    with np.errstate(invalid="ignore"):
        far = np.abs(pos) > MAX_COORDINATE_M
    if far.any():
        f, p, a = (int(i[0]) for i in np.nonzero(far))
        row = f"line {line_numbers[f]}" if line_numbers is not None else f"frame {f + 1}"
        name = names[p] if p < len(names) else f"point {p + 1}"
        raise InputError(
            f"{where}: {row}: point {name!r} has {'xyz'[a]} = {pos[f, p, a]:.4g} m, more than "
            f"{MAX_COORDINATE_M:g} m from the origin (a corrupt value, or a wrong length unit: pass length_unit_m=)"
        )


def uniform_time(n_frames: int, rate_hz: float, start_s: float = 0.0) -> np.ndarray:
    """Timestamps of ``n_frames`` samples at ``rate_hz`` from ``start_s``."""
    return start_s + np.arange(n_frames, dtype=float) / float(rate_hz)


def positive_float(text) -> float | None:
    """``text`` as a number > 0 (a rate, a frame count in a header), else None."""
    try:
        value = float(text)
    except (TypeError, ValueError):
        return None
    return value if value > 0 else None


def unique_names(names) -> list[str]:
    """Names made unique: a repeated name gets ``#2``, ``#3`` (as the C3D reader does)."""
    seen: dict[str, int] = {}
    out = []
    for n in names:
        k = seen.get(n, 0) + 1
        seen[n] = k
        out.append(n if k == 1 else f"{n}#{k}")
    return out


def gait_event(label: str, context: str = "") -> tuple[str, str]:
    """(side, kind) of a gait event as files name it: side "left", "right" or ""; kind "foot strike",
    "foot off" or the label in lower case.

    Vicon writes label "Foot Strike" with context "Left"; Motion Analysis writes context "LHS" (left
    heel strike) or "RTO" (right toe off) with an empty label; others write "Left Foot Strike",
    "RHS", "L_IC" (initial contact), "R FO".
    """
    text = f"{label} {context}".strip()
    words = [w for w in re.split(r"[^A-Za-z]+|(?<=[a-z])(?=[A-Z])", text) if w]
    low = [w.lower() for w in words]
    side = ""
    for w in low:
        if w in ("left", "l") or (len(w) == 3 and w[0] == "l" and w[1:] in ("hs", "fs", "to", "fo", "ic")):
            side = "left"
            break
        if w in ("right", "r") or (len(w) == 3 and w[0] == "r" and w[1:] in ("hs", "fs", "to", "fo", "ic")):
            side = "right"
            break
    joined = " ".join(low)
    tags = {w[-2:] if len(w) == 3 and w[0] in "lr" else w for w in low}
    if "strike" in joined or "contact" in joined or tags & {"hs", "fs", "ic"}:
        kind = "foot strike"
    elif "off" in low or tags & {"to", "fo"} or "toe off" in joined:
        kind = "foot off"
    else:
        kind = (label or context).strip().lower()
    return side, kind
