"""Synthetic gait lab: motion-capture-like walks generated from the Yoyo-model.

Real recordings give no ground truth for step frequency, forward speed or the
Yoyo-model radii, so the package carries its own seeded, deterministic data
set in which these are known exactly.  Each walk is a :class:`Recording` (the
type every file reader produces), so it flows through the same pipeline as a
real file, and a :class:`SyntheticTruth` travels with it.

How a walk is built (all SI units, up axis z):

* The step frequency ``f(t)`` follows the walk type (constant, fast-slow-fast,
  stop-and-go) with a small, slow natural variability.  The Yoyo angle
  ``theta`` is its integral (:func:`yoyogait.model.integrate_phase`); one turn
  of ``theta`` is one step, ``omega = 2 pi f``.
* Along the path, the pelvis centre follows eq. 1-4 of the paper
  (:func:`yoyogait.model.yoyo_model`) with two departures seen in real data:
  a phase offset ``phase_offset_rad`` added to the forward oscillation (real
  pelvis data have the forward velocity peaking where the pelvis is lowest,
  i.e. an offset of pi; 0 gives the model as written) and a second harmonic.
* The path is a planar curve parametrised by arc length; the pelvis travels
  ``s(t) = x(t)`` along it, and its heading turns the body frame.  The pelvis
  sways sideways at stride frequency (half the step frequency), rotates and
  tilts a little, and carries four markers (LASI, RASI, LPSI, RPSI) whose mean
  is the pelvis centre, plus the centre itself (PELVIS).  A wrist marker
  (RWRI) is held roughly fixed in front and to the right of the body.
* Heel markers (LHEE, RHEE) really step: a heel strike happens each time
  ``theta`` passes ``pi`` (mod ``2 pi``), where the pelvis is lowest, feet
  alternating; each foot stays fixed on the floor in stance and swings a
  stride forward along a smooth arc.  Everything is a function of ``theta``,
  so when the step frequency drops to zero the whole body, feet included,
  stands still.
* Marker noise (about 1 mm) and dropouts (NaN, never zero): a marker occluded
  for 0.1-1 s now and then, and single frames at random.
"""

from __future__ import annotations

import zlib
from dataclasses import dataclass, field, replace

import numpy as np

from .errors import InputError
from .io.recording import Recording
from .model import integrate_phase, yoyo_model

__all__ = [
    "SyntheticSubject",
    "SyntheticTruth",
    "SyntheticWalk",
    "SUBJECTS",
    "WALK_TYPES",
    "DEFAULT_DURATION_S",
    "PELVIS_MARKERS",
    "HAND_MARKER",
    "HEEL_MARKERS",
    "POINT_NAMES",
    "make_walk",
    "make_model_walk",
    "make_step_walk",
    "step_walks",
    "STEP_WALK_TYPE",
    "default_lab",
    "get_subject",
    "with_parameters",
    "straight_path",
    "rectangle_path",
    "figure_eight_path",
    "turns_path",
]

WALK_TYPES: tuple[str, ...] = (
    "1-straight",
    "2-fast-slow-fast",
    "3-rectangle",
    "4-figure-eight",
    "5-stop-and-go",
)
"""The paper's four walk types plus a stop-and-go walk."""

DEFAULT_DURATION_S: dict[str, float] = {
    "1-straight": 35.0,
    "2-fast-slow-fast": 40.0,
    "3-rectangle": 35.0,
    "4-figure-eight": 35.0,
    "5-stop-and-go": 40.0,
}

PELVIS_MARKERS: tuple[str, ...] = ("LASI", "RASI", "LPSI", "RPSI")
PELVIS_CENTRE = "PELVIS"
HAND_MARKER = "RWRI"
HEEL_MARKERS: tuple[str, ...] = ("LHEE", "RHEE")
POINT_NAMES: tuple[str, ...] = (PELVIS_CENTRE, *PELVIS_MARKERS, HAND_MARKER, *HEEL_MARKERS)

# Pelvis markers in the body frame (forward, left, up) about the pelvis centre,
# metres.  Symmetric, so that their mean is exactly the centre.
_PELVIS_OFFSETS_M = np.array(
    [
        [0.09, 0.12, -0.02],  # LASI
        [0.09, -0.12, -0.02],  # RASI
        [-0.09, 0.045, 0.02],  # LPSI
        [-0.09, -0.045, 0.02],  # RPSI
    ]
)

# Foot timing, in Yoyo angle: heel strike of step k at theta = pi + 2 pi k
# (the pelvis is lowest there, eq. 2); the foot of step k lifts off at the
# next heel strike plus the double support, so stance is (2 pi + delta) / 4 pi
# of a stride (60 %).
_DOUBLE_SUPPORT_RAD = 0.4 * np.pi
# theta where a walk starts or stops: the middle of a double support, so that
# both feet are on the floor while standing.
_REST_THETA_RAD = np.pi + 0.5 * _DOUBLE_SUPPORT_RAD


@dataclass(frozen=True)
class SyntheticSubject:
    """A virtual walker: Yoyo-model parameters and the details real gait adds.

    ``R_m`` and ``r_m`` are the radii of eq. 1-4 (forward speed ``R_m * omega``,
    one step ``2 pi R_m`` long), ``z0_m`` the pelvis height, and
    ``step_frequency_hz`` the preferred step frequency.  ``harmonic2_ratio``
    is the amplitude of the second harmonic of the forward and vertical
    velocity relative to the fundamental ``r omega``.
    """

    name: str
    R_m: float
    r_m: float
    z0_m: float
    step_frequency_hz: float
    sway_m: float = 0.025
    harmonic2_ratio: float = 0.2
    harmonic2_phase_rad: float = 0.6
    pelvis_yaw_rad: float = 0.07
    pelvis_roll_rad: float = 0.05
    hand_offset_m: tuple[float, float, float] = (0.30, -0.20, 0.05)
    hand_swing_m: float = 0.03
    step_width_m: float = 0.14
    heel_height_m: float = 0.06
    heel_lead_m: float = 0.28
    foot_clearance_m: float = 0.10

    @property
    def speed_mps(self) -> float:
        """Forward speed at the preferred step frequency, ``R omega``."""
        return 2.0 * np.pi * self.step_frequency_hz * self.R_m

    @property
    def step_length_m(self) -> float:
        """Distance covered by one step (one turn of theta), ``2 pi R``."""
        return 2.0 * np.pi * self.R_m


SUBJECTS: tuple[SyntheticSubject, ...] = (
    SyntheticSubject(
        "synthetic-S1", R_m=0.115, r_m=0.022, z0_m=0.95, step_frequency_hz=1.80, sway_m=0.025, harmonic2_phase_rad=0.6
    ),
    SyntheticSubject(
        "synthetic-S2",
        R_m=0.127,
        r_m=0.028,
        z0_m=1.00,
        step_frequency_hz=1.68,
        sway_m=0.030,
        harmonic2_ratio=0.25,
        harmonic2_phase_rad=-0.4,
        hand_offset_m=(0.32, -0.22, 0.08),
        step_width_m=0.16,
    ),
    SyntheticSubject(
        "synthetic-S3",
        R_m=0.104,
        r_m=0.017,
        z0_m=0.90,
        step_frequency_hz=1.98,
        sway_m=0.020,
        harmonic2_ratio=0.15,
        harmonic2_phase_rad=1.2,
        hand_offset_m=(0.27, -0.18, 0.02),
        step_width_m=0.12,
    ),
)
"""The three virtual subjects of the built-in lab (speeds 1.30, 1.34, 1.29 m/s)."""


@dataclass
class SyntheticTruth:
    """Ground truth of a synthetic walk, one value per recording frame.

    ``speed_mps`` is the stride-averaged forward speed, ``R_m * omega``: the
    bias of eq. 3, which the forward velocity averages to over a stride.
    ``vx_path_mps`` and ``vz_mps`` are the noise-free pelvis-centre velocities
    along the path and vertically (eq. 3-4 with the phase offset and the
    second harmonic; the sideways sway is not in them).  ``walking`` is False
    where the step frequency is zero (standing).  Heel strikes are given per
    foot in ``left_contact_times_s`` and ``right_contact_times_s``.
    """

    time_s: np.ndarray
    step_frequency_hz: np.ndarray
    speed_mps: np.ndarray
    R_m: np.ndarray
    r_m: np.ndarray
    walking: np.ndarray
    heading_rad: np.ndarray
    theta_rad: np.ndarray
    vx_path_mps: np.ndarray
    vz_mps: np.ndarray
    pelvis_centre_m: np.ndarray
    left_contact_times_s: np.ndarray
    right_contact_times_s: np.ndarray
    phase_offset_rad: float
    z0_m: float

    @property
    def omega_rad_s(self) -> np.ndarray:
        """Yoyo angular velocity, ``2 pi * step_frequency_hz``."""
        return 2.0 * np.pi * self.step_frequency_hz

    @property
    def contact_times_s(self) -> np.ndarray:
        """All heel strikes, both feet, in time order."""
        return np.sort(np.concatenate([self.left_contact_times_s, self.right_contact_times_s]))

    def at(self, time_s) -> SyntheticTruth:
        """The truth on another time grid (e.g. the estimator's 25 Hz samples).

        Continuous quantities are interpolated linearly; ``walking`` is True
        where the interpolated step frequency is above zero.  Outside the
        recording the values are NaN (``walking`` False).
        """
        t = np.asarray(time_s, dtype=float)

        def interp(y):
            return np.interp(t, self.time_s, y, left=np.nan, right=np.nan)

        f = interp(self.step_frequency_hz)
        return SyntheticTruth(
            time_s=t,
            step_frequency_hz=f,
            speed_mps=interp(self.speed_mps),
            R_m=interp(self.R_m),
            r_m=interp(self.r_m),
            walking=np.nan_to_num(f, nan=0.0) > 0.0,
            heading_rad=interp(self.heading_rad),
            theta_rad=interp(self.theta_rad),
            vx_path_mps=interp(self.vx_path_mps),
            vz_mps=interp(self.vz_mps),
            pelvis_centre_m=np.stack([interp(c) for c in self.pelvis_centre_m.T], axis=1),
            left_contact_times_s=self.left_contact_times_s.copy(),
            right_contact_times_s=self.right_contact_times_s.copy(),
            phase_offset_rad=self.phase_offset_rad,
            z0_m=self.z0_m,
        )


@dataclass
class SyntheticWalk:
    """A synthetic recording and its ground truth."""

    recording: Recording
    truth: SyntheticTruth
    subject: SyntheticSubject
    walk_type: str
    seed: int
    options: dict = field(default_factory=dict)

    @property
    def name(self) -> str:
        """E.g. ``synthetic-S1 walk 3-rectangle``; always says synthetic."""
        who = self.subject.name if "synthetic" in self.subject.name.lower() else f"synthetic {self.subject.name}"
        return f"{who} walk {self.walk_type}"


# ---------------------------------------------------------------------------
# Paths: planar curves parametrised by arc length.


class _Path:
    """A planar path made of straight and circular pieces, repeated periodically.

    ``at(s)`` gives position (n x 2) and unwrapped heading at arc length ``s``
    (any real value: the path repeats before its start and after its end).
    """

    def __init__(self, start_xy, start_heading_rad, pieces):
        self.pieces = [(float(length), float(curv)) for length, curv in pieces]
        lengths = np.array([p[0] for p in self.pieces])
        self.period_m = float(lengths.sum())
        self.s0 = np.concatenate([[0.0], np.cumsum(lengths)[:-1]])
        xy = [np.asarray(start_xy, dtype=float)]
        psi = [float(start_heading_rad)]
        for length, curv in self.pieces:
            p, h = _advance(xy[-1], psi[-1], length, curv)
            xy.append(p)
            psi.append(h)
        self.xy0 = np.array(xy[:-1])
        self.psi0 = np.array(psi[:-1])
        self.turn_per_period_rad = psi[-1] - psi[0]
        self.drift_per_period_m = xy[-1] - xy[0]

    def at(self, s):
        s = np.asarray(s, dtype=float)
        lap = np.floor(s / self.period_m)
        u = s - lap * self.period_m
        i = np.clip(np.searchsorted(self.s0, u, side="right") - 1, 0, len(self.pieces) - 1)
        du = u - self.s0[i]
        curv = np.array([p[1] for p in self.pieces])[i]
        xy, psi = _advance(self.xy0[i], self.psi0[i], du, curv)
        xy = xy + lap[..., None] * self.drift_per_period_m
        return xy, psi + lap * self.turn_per_period_rad


def _advance(xy, psi, length, curv):
    """Point and heading after ``length`` metres at constant curvature ``curv``."""
    xy = np.asarray(xy, dtype=float)
    psi = np.asarray(psi, dtype=float)
    length = np.asarray(length, dtype=float)
    curv = np.asarray(curv, dtype=float)
    psi1 = psi + curv * length
    straight = np.abs(curv) < 1e-12
    safe = np.where(straight, 1.0, curv)
    dx = np.where(straight, length * np.cos(psi), (np.sin(psi1) - np.sin(psi)) / safe)
    dy = np.where(straight, length * np.sin(psi), (np.cos(psi) - np.cos(psi1)) / safe)
    return xy + np.stack([dx, dy], axis=-1), psi1


def rectangle_path(width_m: float = 6.0, height_m: float = 3.5, corner_radius_m: float = 0.8) -> _Path:
    """Counter-clockwise rectangle with rounded corners, centred on the origin.

    Starts in the middle of the lower long side heading +x; turns left by a
    quarter turn at each corner, ``2 pi`` per lap.
    """
    a = width_m - 2 * corner_radius_m
    b = height_m - 2 * corner_radius_m
    k = 1.0 / corner_radius_m
    quarter = 0.5 * np.pi * corner_radius_m
    pieces = [
        (a / 2, 0.0),
        (quarter, k),
        (b, 0.0),
        (quarter, k),
        (a, 0.0),
        (quarter, k),
        (b, 0.0),
        (quarter, k),
        (a / 2, 0.0),
    ]
    return _Path((0.0, -height_m / 2), 0.0, pieces)


def figure_eight_path(centre_distance_m: float = 1.8, loop_radius_m: float = 1.0) -> _Path:
    """Figure of eight around two posts at (+-d, 0), crossing at the origin.

    A left loop around the right post, a right loop around the left post,
    joined by straight lines through the origin.  Each loop turns by
    ``pi + 2 asin(radius / d)``; over one figure the turns cancel.
    """
    d, rho = centre_distance_m, loop_radius_m
    alpha = np.arcsin(rho / d)
    leg = np.sqrt(d * d - rho * rho)
    beta = np.pi + 2 * alpha
    pieces = [(leg, 0.0), (rho * beta, 1 / rho), (2 * leg, 0.0), (rho * beta, -1 / rho), (leg, 0.0)]
    return _Path((0.0, 0.0), -alpha, pieces)


def turns_path(leg_m: float = 4.0, radius_m: float = 0.35) -> _Path:
    """Straight legs joined by tight turns: a left U-turn, a right quarter turn, a left quarter turn.

    ``leg_m`` between turns, each turn on a circle of ``radius_m`` (0.35 m: a turn at walking pace
    in a corridor). Starts at the origin heading +x.
    """
    k = 1.0 / radius_m
    pieces = [
        (leg_m, 0.0),
        (np.pi * radius_m, k),
        (leg_m, 0.0),
        (0.5 * np.pi * radius_m, -k),
        (leg_m, 0.0),
        (0.5 * np.pi * radius_m, k),
    ]
    return _Path((0.0, 0.0), 0.0, pieces)


def straight_path() -> _Path:
    """A straight line from the origin along +x."""
    return _Path((0.0, 0.0), 0.0, [(100.0, 0.0)])


def _path_for(walk_type: str) -> _Path:
    if walk_type == "3-rectangle":
        return rectangle_path()
    if walk_type == "4-figure-eight":
        return figure_eight_path()
    return straight_path()


# ---------------------------------------------------------------------------
# Step frequency profiles.


def _smoothstep(t, t0, duration):
    """0 before ``t0``, 1 after ``t0 + duration``, raised cosine in between."""
    u = np.clip((np.asarray(t, dtype=float) - t0) / max(duration, 1e-9), 0.0, 1.0)
    return 0.5 * (1.0 - np.cos(np.pi * u))


def _variability(t, rng, amount):
    """Slow, smooth, zero-mean variability of unit standard deviation times ``amount``."""
    k = 6
    freqs = rng.uniform(0.02, 0.15, k)
    phases = rng.uniform(0, 2 * np.pi, k)
    xi = np.sqrt(2.0 / k) * np.cos(2 * np.pi * freqs[None, :] * t[:, None] + phases[None, :]).sum(axis=1)
    return 1.0 + amount * xi


def _step_frequency_profile(walk_type, subject, t, rng, *, start_standing_s, ramp_s, jitter):
    """Step frequency (Hz) of the walk type on ``t``, zero while standing."""
    f0 = subject.step_frequency_hz
    duration = t[-1] if t.size else 0.0
    var = _variability(t, rng, jitter)
    start = _smoothstep(t, start_standing_s, ramp_s) if start_standing_s > 0 else np.ones_like(t)
    if walk_type == "2-fast-slow-fast":
        fast, slow, transition = 1.12, 0.80, 4.0
        t1, t2 = 0.30 * duration, 0.62 * duration
        level = fast + (slow - fast) * _smoothstep(t, t1, transition) + (fast - slow) * _smoothstep(t, t2, transition)
        return f0 * level * start * var
    if walk_type == "5-stop-and-go":
        stand_s = 4.0
        t_stop = max(0.3 * duration, start_standing_s + ramp_s + 2.0)

        def profile(t_down):
            env = start - _smoothstep(t, t_down, ramp_s) + _smoothstep(t, t_down + ramp_s + stand_s, ramp_s)
            return f0 * env * var

        # Move the start of the slow-down so that theta comes to rest in a
        # double support (both feet on the floor), then stand still.
        t_down = t_stop
        for _ in range(4):
            f = profile(t_down)
            theta = integrate_phase(t, 2 * np.pi * f, _REST_THETA_RAD)
            i_rest = np.searchsorted(t, t_down + ramp_s + 0.5 * stand_s)
            theta_rest = theta[min(i_rest, t.size - 1)]
            target = _REST_THETA_RAD + 2 * np.pi * np.round((theta_rest - _REST_THETA_RAD) / (2 * np.pi))
            f_here = max(np.interp(t_down, t, f), 0.2 * f0)
            t_down += (target - theta_rest) / (2 * np.pi * f_here)
        return profile(t_down)
    return f0 * start * var


# ---------------------------------------------------------------------------
# The walk.


def _forward_position(theta, subject, phase_offset_rad, h2):
    """Distance along the path as a function of theta (eq. 1 with offset and 2nd harmonic)."""
    R, r = subject.R_m, subject.r_m
    return (
        R * theta
        + r * np.sin(theta + phase_offset_rad)
        + 0.5 * h2 * r * np.sin(2 * theta + subject.harmonic2_phase_rad + phase_offset_rad)
    )


def _rot_z(psi):
    c, s = np.cos(psi), np.sin(psi)
    out = np.zeros(psi.shape + (3, 3))
    out[..., 0, 0], out[..., 0, 1] = c, -s
    out[..., 1, 0], out[..., 1, 1] = s, c
    out[..., 2, 2] = 1.0
    return out


def _rot_x(phi):
    c, s = np.cos(phi), np.sin(phi)
    out = np.zeros(phi.shape + (3, 3))
    out[..., 0, 0] = 1.0
    out[..., 1, 1], out[..., 1, 2] = c, -s
    out[..., 2, 1], out[..., 2, 2] = s, c
    return out


def _heel(theta, is_right, subject, path, s_of_theta):
    """Heel marker (n x 3): fixed on the floor in stance, smooth arc in swing."""
    parity = 0 if is_right else 1
    m = np.floor((theta - np.pi) / (2 * np.pi)).astype(int)  # last heel strike, either foot
    k = np.where((m - parity) % 2 == 0, m, m - 1)  # last heel strike of this foot
    u = theta - (np.pi + 2 * np.pi * k)  # in [0, 4 pi)
    swing_start = 2 * np.pi + _DOUBLE_SUPPORT_RAD
    p = np.clip((u - swing_start) / (2 * np.pi - _DOUBLE_SUPPORT_RAD), 0.0, 1.0)
    side = -0.5 if is_right else 0.5

    def landing(kk):
        sigma = s_of_theta(np.pi + 2 * np.pi * kk) + subject.heel_lead_m
        xy, psi = path.at(sigma)
        normal = np.stack([-np.sin(psi), np.cos(psi)], axis=-1)
        return xy + side * subject.step_width_m * normal

    a, b = landing(k), landing(k + 2)
    q = p * p * p * (10 - 15 * p + 6 * p * p)  # minimum-jerk progress
    xy = a + q[:, None] * (b - a)
    z = subject.heel_height_m + subject.foot_clearance_m * np.sin(np.pi * p) ** 2
    return np.column_stack([xy, z])


def _contact_times(time_s, theta, parity):
    """Times at which theta passes pi + 2 pi k for the steps k of one foot."""
    if theta.size < 2:
        return np.empty(0)
    k_first = int(np.ceil((theta[0] - np.pi) / (2 * np.pi)))
    k_last = int(np.floor((theta[-1] - np.pi) / (2 * np.pi)))
    ks = [k for k in range(k_first, k_last + 1) if (k - parity) % 2 == 0]
    targets = np.pi + 2 * np.pi * np.array(ks, dtype=float)
    targets = targets[targets > theta[0]]
    i1 = np.searchsorted(theta, targets, side="left")
    i0 = i1 - 1
    w = (targets - theta[i0]) / (theta[i1] - theta[i0])
    return time_s[i0] + w * (time_s[i1] - time_s[i0])


def _dropouts(positions, rng, rate_hz, duration_s, names):
    """Occlude markers: 0.1-1 s gaps now and then, and single frames at random."""
    n = positions.shape[0]
    occludable = [names.index(m) for m in (*PELVIS_MARKERS, HAND_MARKER)]
    n_gaps = rng.poisson(duration_s / 8.0)
    for _ in range(n_gaps):
        j = occludable[rng.integers(len(occludable))]
        length = int(round(rng.uniform(0.1, 1.0) * rate_hz))
        i0 = int(rng.integers(0, max(n - length, 1)))
        positions[i0 : i0 + length, j, :] = np.nan
    single = rng.random(positions.shape[:2]) < 0.002
    positions[single] = np.nan
    return positions


def make_walk(
    subject: SyntheticSubject,
    walk_type: str,
    *,
    rate_hz: float = 100.0,
    duration_s: float | None = None,
    phase_offset_rad: float = np.pi,
    seed: int = 0,
    noise_m: float = 0.001,
    dropouts: bool = True,
    harmonic2_ratio: float | None = None,
    sway_m: float | None = None,
    frequency_jitter: float = 0.01,
    start_standing_s: float = 1.0,
    ramp_s: float = 1.5,
    step_frequency_profile=None,
    path: _Path | None = None,
) -> SyntheticWalk:
    """Generate one synthetic walk of ``subject`` (deterministic for a seed).

    ``walk_type`` is one of :data:`WALK_TYPES`.  ``phase_offset_rad`` is added
    to the forward oscillation of eq. 3 (pi: forward velocity peaks where the
    pelvis is lowest, as in real pelvis data; 0: the model as written).
    ``harmonic2_ratio`` and ``sway_m`` override the subject's values.
    ``frequency_jitter`` is the relative standard deviation of the slow
    natural step-frequency variability.  The walk starts standing for
    ``start_standing_s`` and reaches its pace within ``ramp_s``.
    ``step_frequency_profile``: a function of the frame times (s) giving the step frequency (Hz),
    replacing the walk type's profile (the walk type then only chooses the path).
    ``path``: the path walked (e.g. :func:`turns_path`), replacing the walk type's.
    """
    if walk_type not in WALK_TYPES:
        raise InputError(f"unknown synthetic walk type {walk_type!r}; choose one of {', '.join(WALK_TYPES)}")
    if not np.isfinite(rate_hz) or rate_hz <= 0:
        raise InputError(f"rate_hz must be positive, got {rate_hz}")
    duration_s = DEFAULT_DURATION_S[walk_type] if duration_s is None else float(duration_s)
    if not duration_s > 0:
        raise InputError(f"duration_s must be positive, got {duration_s}")
    h2 = subject.harmonic2_ratio if harmonic2_ratio is None else float(harmonic2_ratio)
    sway = subject.sway_m if sway_m is None else float(sway_m)
    if subject.r_m * (1.0 + 2.0 * abs(h2)) >= subject.R_m:
        # The slowest forward velocity is about (R - r (1 + h)) omega; keep a margin above zero.
        raise InputError("r_m (with its harmonic) must be well below R_m, or the walker would move backwards")

    rng = np.random.default_rng(
        np.random.SeedSequence([int(seed), zlib.crc32(subject.name.encode()), WALK_TYPES.index(walk_type)])
    )
    n = int(round(duration_s * rate_hz)) + 1
    t = np.arange(n) / rate_hz
    if step_frequency_profile is None:
        f = _step_frequency_profile(
            walk_type, subject, t, rng, start_standing_s=start_standing_s, ramp_s=ramp_s, jitter=frequency_jitter
        )
    else:
        f = np.asarray(step_frequency_profile(t), dtype=float)
    f = np.maximum(f, 0.0)
    omega = 2 * np.pi * f

    # Eq. 1-4: vertical as written, forward with the phase offset.
    vert = yoyo_model(t, subject.R_m, subject.r_m, f, subject.z0_m, phase_rad=_REST_THETA_RAD)
    fwd = yoyo_model(t, subject.R_m, subject.r_m, f, 0.0, phase_rad=_REST_THETA_RAD + phase_offset_rad)
    theta = vert.theta_rad
    a2 = 0.5 * h2 * subject.r_m  # second-harmonic position amplitude
    ph2 = subject.harmonic2_phase_rad
    z = vert.z_m + a2 * np.cos(2 * theta + ph2)
    vz = vert.vz_mps - 2 * a2 * omega * np.sin(2 * theta + ph2)
    vx = fwd.vx_mps + 2 * a2 * omega * np.cos(2 * theta + ph2 + phase_offset_rad)

    def s_of_theta(th):
        return _forward_position(th, subject, phase_offset_rad, h2) - _forward_position(
            _REST_THETA_RAD, subject, phase_offset_rad, h2
        )

    s = s_of_theta(theta)
    path = _path_for(walk_type) if path is None else path
    path_xy, heading = path.at(s)
    left = np.stack([-np.sin(heading), np.cos(heading)], axis=-1)

    # Sideways sway at stride frequency: towards the stance foot (right at theta = 2 pi mod 4 pi).
    stride_phase = 0.5 * theta
    lateral = sway * np.cos(stride_phase)
    centre = np.column_stack([path_xy + lateral[:, None] * left, z])

    yaw = heading + subject.pelvis_yaw_rad * np.sin(stride_phase)
    roll = subject.pelvis_roll_rad * np.cos(stride_phase)
    rot = _rot_z(yaw) @ _rot_x(roll)
    pelvis = centre[:, None, :] + np.einsum("nij,mj->nmi", rot, _PELVIS_OFFSETS_M)

    hand_local = np.array(subject.hand_offset_m)[None, :] + np.column_stack(
        [
            subject.hand_swing_m * np.sin(stride_phase + 0.3),
            np.zeros(n),
            0.3 * subject.hand_swing_m * np.sin(theta + 0.5),
        ]
    )
    hand = centre + np.einsum("nij,nj->ni", _rot_z(heading), hand_local)

    lheel = _heel(theta, False, subject, path, s_of_theta)
    rheel = _heel(theta, True, subject, path, s_of_theta)

    positions = np.stack([centre, *pelvis.transpose(1, 0, 2), hand, lheel, rheel], axis=1)
    names = list(POINT_NAMES)
    if noise_m > 0:
        positions = positions + rng.normal(0.0, noise_m, positions.shape)
    if dropouts:
        positions = _dropouts(positions, rng, rate_hz, duration_s, names)

    options = dict(
        rate_hz=float(rate_hz),
        duration_s=duration_s,
        phase_offset_rad=float(phase_offset_rad),
        noise_m=float(noise_m),
        dropouts=bool(dropouts),
        harmonic2_ratio=h2,
        sway_m=sway,
        frequency_jitter=float(frequency_jitter),
        start_standing_s=float(start_standing_s),
        ramp_s=float(ramp_s),
    )
    metadata = {
        "synthetic": True,
        "description": "SYNTHETIC walk generated by yoyogait.synthetic (Yoyo-model), not a real recording",
        "subject": subject.name,
        "walk_type": walk_type,
        "seed": int(seed),
        "pelvis": list(PELVIS_MARKERS),
        "pelvis_centre": PELVIS_CENTRE,
        "hand": HAND_MARKER,
        "feet": list(HEEL_MARKERS),
        "vertical_axis": "z",
        "length_unit_m": 1.0,
        "walk": walk_type,
        **options,
    }
    recording = Recording(
        positions_m=positions,
        point_names=names,
        time_s=t,
        rate_hz=float(rate_hz),
        up_axis="z",
        source=f"synthetic:{subject.name}/{walk_type}/seed{int(seed)}",
        metadata=metadata,
    )
    truth = SyntheticTruth(
        time_s=t,
        step_frequency_hz=f,
        speed_mps=subject.R_m * omega,
        R_m=np.full(n, subject.R_m),
        r_m=np.full(n, subject.r_m),
        walking=f > 0.0,
        heading_rad=heading,
        theta_rad=theta,
        vx_path_mps=vx,
        vz_mps=vz,
        pelvis_centre_m=centre,
        left_contact_times_s=_contact_times(t, theta, 1),
        right_contact_times_s=_contact_times(t, theta, 0),
        phase_offset_rad=float(phase_offset_rad),
        z0_m=subject.z0_m,
    )
    return SyntheticWalk(recording, truth, subject, walk_type, int(seed), options)


def make_model_walk(subject: SyntheticSubject, walk_type: str, **kwargs) -> SyntheticWalk:
    """A model-pure walk: eq. 1-4 exactly as written.

    No phase offset, harmonic, sway, noise, dropouts or step-frequency
    variability unless given in ``kwargs`` (which go to :func:`make_walk`).
    """
    pure: dict = dict(
        phase_offset_rad=0.0, harmonic2_ratio=0.0, sway_m=0.0, noise_m=0.0, dropouts=False, frequency_jitter=0.0
    )
    pure.update(kwargs)
    return make_walk(subject, walk_type, **pure)


STEP_WALK_TYPE = "6-cadence-speed-step"
"""Walk type of :func:`make_step_walk` (not one of :data:`WALK_TYPES`: the built-in lab stays as it is)."""


def make_step_walk(
    subject: SyntheticSubject | None = None,
    *,
    rate_hz: float = 100.0,
    seed: int = 0,
    f_before_hz: float = 1.6,
    f_after_hz: float = 2.0,
    speed_before_mps: float = 1.2,
    step_at_s: float = 12.0,
    step_duration_s: float = 0.25,
    duration_s: float = 22.0,
    start_standing_s: float = 1.0,
    ramp_s: float = 1.5,
    **kwargs,
) -> SyntheticWalk:
    """A straight walk with a step of cadence, and with it of speed (SYNTHETIC data).

    The walker stands ``start_standing_s``, reaches ``f_before_hz`` within ``ramp_s`` (raised
    cosine), walks at it without variability, and at ``step_at_s`` changes to ``f_after_hz``
    within ``step_duration_s`` (raised cosine, about half a step). The step length ``2 pi R`` is
    set so that the speed ``R omega`` is ``speed_before_mps`` before the step; the speed then
    steps with the cadence (1.6 -> 2.0 Hz at 1.2 m/s: 1.2 -> 1.5 m/s). ``subject`` (default the
    first built-in one) gives everything else; ``kwargs`` go to :func:`make_walk`.
    The recording's metadata holds ``cadence_step_at_s`` and ``cadence_step_duration_s``.
    """
    if not (f_before_hz > 0 and f_after_hz > 0 and speed_before_mps > 0):
        raise InputError("f_before_hz, f_after_hz and speed_before_mps must be > 0")
    if not start_standing_s + ramp_s < step_at_s < step_at_s + step_duration_s < duration_s:
        raise InputError("need start_standing_s + ramp_s < step_at_s < step_at_s + step_duration_s < duration_s")
    base = SUBJECTS[0] if subject is None else subject
    walker = replace(base, R_m=speed_before_mps / (2.0 * np.pi * f_before_hz), step_frequency_hz=f_before_hz)

    def profile(t):
        start = _smoothstep(t, start_standing_s, ramp_s) if start_standing_s > 0 else np.ones_like(t)
        return start * (f_before_hz + (f_after_hz - f_before_hz) * _smoothstep(t, step_at_s, step_duration_s))

    walk = make_walk(
        walker,
        "1-straight",
        rate_hz=rate_hz,
        seed=seed,
        duration_s=duration_s,
        start_standing_s=start_standing_s,
        ramp_s=ramp_s,
        step_frequency_profile=profile,
        **kwargs,
    )
    rec = walk.recording
    metadata = {
        **rec.metadata,
        "walk_type": STEP_WALK_TYPE,
        "walk": STEP_WALK_TYPE,
        "cadence_step_at_s": float(step_at_s),
        "cadence_step_duration_s": float(step_duration_s),
    }
    rec = replace(rec, source=f"synthetic:{walker.name}/{STEP_WALK_TYPE}/seed{int(seed)}", metadata=metadata)
    options = {**walk.options, "step_at_s": float(step_at_s), "step_duration_s": float(step_duration_s)}
    return replace(walk, recording=rec, walk_type=STEP_WALK_TYPE, options=options)


def step_walks(seed: int = 0, rate_hz: float = 100.0) -> list[SyntheticWalk]:
    """:func:`make_step_walk` for each built-in subject (their radius ratio, harmonics, sway)."""
    return [make_step_walk(subject, rate_hz=rate_hz, seed=seed) for subject in SUBJECTS]


def default_lab(seed: int = 0, rate_hz: float = 100.0, *, pure: bool = False) -> list[SyntheticWalk]:
    """The built-in synthetic data set: 3 subjects x 5 walk types.

    Realistic by default (phase offset pi, harmonic, sway, noise, dropouts);
    ``pure=True`` gives the model-pure version of every walk.
    """
    make = make_model_walk if pure else make_walk
    return [make(subject, walk_type, rate_hz=rate_hz, seed=seed) for subject in SUBJECTS for walk_type in WALK_TYPES]


def get_subject(name: str) -> SyntheticSubject:
    """The built-in subject called ``name`` (e.g. ``synthetic-S1``)."""
    for s in SUBJECTS:
        if s.name == name:
            return s
    raise InputError(f"no synthetic subject {name!r}; available: {', '.join(s.name for s in SUBJECTS)}")


def with_parameters(base: SyntheticSubject, **changes) -> SyntheticSubject:
    """A copy of ``base`` with some fields changed (e.g. another ``R_m``)."""
    return replace(base, **changes)
