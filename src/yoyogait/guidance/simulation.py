"""The closed loop: a walker, a cable, an admittance-controlled aerial robot and its controller.

Models (docs/guidance.md; Tognon, Alami and Siciliano, IEEE T-RO 37(3), 2021, and the
human-state-aware follow-up):

* cable: massless, pulls only when taut, ``f_c = k_c (|l_c| - l0) l_c / |l_c|`` for
  ``|l_c| > l0``, else 0, with ``l_c = p_R - p_H`` (robot minus hand); ``+f_c`` acts on the
  hand, ``-f_c`` on the robot (:func:`cable_force`);
* robot: a point mass at a fixed height above the handle's rest height (its altitude loop is
  not simulated), admittance-controlled in the floor plane,
  ``M_A dv_R/dt = -B_A v_R - f_c,h + u_A``, its speed limited to ``max_speed_mps``;
* controller: ``u_A = K_H e_R + f_c^r + B_A v_H_hat``: ``e_R`` from the robot to its reference
  point (on the path, a cable's horizontal length ahead of the walker's progress), ``f_c^r`` the
  reference force along the path (nominal force times the path's pace), ``v_H_hat`` the human
  velocity from the feedback source (:mod:`yoyogait.guidance.sources`), zero for ``none``;
* the walker: :mod:`yoyogait.guidance.walker`.

Time: the physics is integrated with semi-implicit Euler at ``physics_dt_s`` (2 ms); the motion
capture samples the handle at ``rate_hz`` (100 Hz) with white noise, and the controller runs on
each frame (its command held between frames).  Deterministic for a seed; SYNTHETIC.
"""

from __future__ import annotations

import math
import zlib
from dataclasses import dataclass, field

import numpy as np

from ..errors import InputError
from ..synthetic import SyntheticSubject
from .paths import GuidePath
from .sources import make_source
from .walker import GuidedWalker, HumanModel

__all__ = ["GuidanceConfig", "GuidanceRun", "simulate", "cable_force"]

_STALLED_MPS = 0.02


@dataclass(frozen=True)
class GuidanceConfig:
    """Every parameter of the simulation (docs/guidance.md, sec. 3, gives their sources)."""

    robot_mass_kg: float = 0.8
    """``M_A``, the admittance's virtual mass (T-RO 2021: 0.8 I; the follow-up: 5 I) [kg]."""
    robot_damping_ns_per_m: float = 2.4
    """``B_A``, the admittance's damping (T-RO 2021: 2.4 I) [N s/m]."""
    position_gain_n_per_m: float = 1.8
    """``K_H``: ``B_A^2 / (4 M_A)``, the robot's position loop critically damped [N/m]."""
    max_speed_mps: float = 2.0
    """The robot's speed limit [m/s]."""
    cable_rest_length_m: float = 1.0
    """``l0`` (T-RO 2021: a 1 m cable) [m]."""
    cable_stiffness_n_per_m: float = 300.0
    """``k_c``: the cable and the arm holding it in series (hand endpoint stiffness) [N/m]."""
    cable_damping_ns_per_m: float = 10.0
    """Damping of the arm holding the handle, while the cable is taut (hand endpoint viscosity) [N s/m]."""
    robot_height_m: float = 0.5
    """The robot's height above the handle's rest height [m]."""
    human: HumanModel = field(default_factory=HumanModel)
    latency_s: float = 0.05
    """Sensing and actuation latency of the human velocity (a delay line) [s]."""
    rate_hz: float = 100.0
    """Motion-capture frame rate, and the controller's [Hz]."""
    physics_dt_s: float = 0.002
    """Integration step [s]."""
    mocap_noise_m: float = 0.001
    """White noise of the measured handle position, per axis [m]."""
    start_s: float = 1.0
    """The guidance starts after this long [s]."""
    force_ramp_s: float = 1.0
    """The reference force rises over this long at a start [s]."""
    stop_trigger_m: float = 1.6
    """A stop (or the goal) is commanded when the walker is this far from it along the path; from
    there the reference force fades in proportion to the distance left [m]."""
    goal_radius_m: float = 0.5
    """The goal is reached within this distance of the guided point (about an arm's length) [m]."""
    after_goal_s: float = 3.0
    """The simulation runs this long after the goal is reached [s]."""
    max_duration_s: float = 120.0

    def __post_init__(self):
        positive = (
            "robot_mass_kg",
            "robot_damping_ns_per_m",
            "max_speed_mps",
            "cable_rest_length_m",
            "cable_stiffness_n_per_m",
            "rate_hz",
            "physics_dt_s",
            "force_ramp_s",
            "max_duration_s",
        )
        for name in positive:
            value = getattr(self, name)
            if not (isinstance(value, (int, float)) and math.isfinite(value) and value > 0):
                raise InputError(f"{name} must be a finite number > 0, got {value!r}")
        if not 0.0 <= self.latency_s <= 0.5:
            raise InputError(f"--latency-s must be in [0, 0.5] s, got {self.latency_s!r}")
        if not 0.0 <= self.robot_height_m < self.cable_rest_length_m:
            raise InputError("robot_height_m must be in [0, cable_rest_length_m)")
        if self.position_gain_n_per_m < 0 or self.mocap_noise_m < 0:
            raise InputError("position_gain_n_per_m and mocap_noise_m must be >= 0")
        steps = 1.0 / (self.rate_hz * self.physics_dt_s)
        if abs(steps - round(steps)) > 1e-9:
            raise InputError("physics_dt_s must divide the frame interval 1 / rate_hz")

    @property
    def horizontal_cable_m(self) -> float:
        """The cable's horizontal length when just taut [m]."""
        return math.sqrt(self.cable_rest_length_m**2 - self.robot_height_m**2)


def cable_force(
    robot_m,
    hand_m,
    rest_length_m: float,
    stiffness_n_per_m: float,
    damping_ns_per_m: float = 0.0,
    stretch_rate_mps: float = 0.0,
) -> tuple[float, float, float]:
    """The force of the cable on the hand (3) [N]: ``t l / |l|`` with ``l = robot - hand`` and the
    tension ``t = k_c (|l| - l0) + c d|l|/dt`` when taut (``|l| > l0``), never below zero (a cable
    cannot push); zero when slack.  The robot feels the opposite force."""
    lx, ly, lz = robot_m[0] - hand_m[0], robot_m[1] - hand_m[1], robot_m[2] - hand_m[2]
    d = math.sqrt(lx * lx + ly * ly + lz * lz)
    if d <= rest_length_m:
        return 0.0, 0.0, 0.0
    tension = stiffness_n_per_m * (d - rest_length_m) + damping_ns_per_m * stretch_rate_mps
    if tension <= 0.0:
        return 0.0, 0.0, 0.0
    k = tension / d
    return k * lx, k * ly, k * lz


@dataclass
class GuidanceRun:
    """One guided walk with one source: per-frame arrays (SYNTHETIC) and what happened."""

    source: str
    walker: str
    walk: str
    seed: int
    latency_s: float
    time_s: np.ndarray
    guided_m: np.ndarray  # n x 2: the walker's guided point (hand offset, no oscillation)
    centre_m: np.ndarray  # n x 3
    hand_m: np.ndarray  # n x 3, true
    handle_measured_m: np.ndarray  # n x 3, what the motion capture gives
    robot_m: np.ndarray  # n x 3
    robot_v_mps: np.ndarray  # n x 2
    force_n: np.ndarray  # n x 3, on the hand
    slack: np.ndarray  # n, bool
    source_v_mps: np.ndarray  # n x 2: what the controller used
    intent_v_mps: np.ndarray  # n x 2: of the guided point (the handle without its oscillation)
    theta_rad: np.ndarray
    cadence_hz: np.ndarray
    reference_force_n: np.ndarray  # |f_c^r|
    starts_s: list[float]
    stops_s: list[float]
    turns_s: list[float]
    goal_s: float  # NaN: not reached
    path: GuidePath
    config: GuidanceConfig

    @property
    def tension_n(self) -> np.ndarray:
        return np.linalg.norm(self.force_n, axis=1)


def _seed(seed: int, subject: SyntheticSubject, path: GuidePath) -> np.random.Generator:
    words = [int(seed) & 0xFFFFFFFF, zlib.crc32(subject.name.encode()), zlib.crc32(path.name.encode())]
    return np.random.default_rng(np.random.SeedSequence(words))


def _ramp(t: float, t0: float, duration: float) -> float:
    u = min(max((t - t0) / duration, 0.0), 1.0)
    return 0.5 - 0.5 * math.cos(math.pi * u)


def simulate(
    path: GuidePath,
    subject: SyntheticSubject,
    source: str,
    *,
    seed: int = 0,
    config: GuidanceConfig | None = None,
) -> GuidanceRun:
    """One guided walk along ``path`` by ``subject`` with the feedback ``source``.

    The same seed, walker and path give the same motion-capture noise and initial gait phase for
    every source (the sources are compared on the same walks) and the same result bit for bit.
    """
    cfg = config if config is not None else GuidanceConfig()
    rng = _seed(seed, subject, path)
    frame_dt = 1.0 / cfg.rate_hz
    substeps = int(round(frame_dt / cfg.physics_dt_s))
    dt = cfg.physics_dt_s
    max_frames = int(math.ceil(cfg.max_duration_s * cfg.rate_hz))
    noise = rng.normal(0.0, cfg.mocap_noise_m, (max_frames + 1, 3)) if cfg.mocap_noise_m > 0 else None
    theta0 = float(rng.uniform(0.0, 2.0 * math.pi))
    feedback = make_source(source, latency_s=cfg.latency_s, rate_hz=cfg.rate_hz)

    x0, y0, tx, ty = path.point(0.0)
    heading0 = math.atan2(ty, tx)
    walker = GuidedWalker(subject, cfg.human, 0.0, 0.0, heading0, theta0)
    # Start with the guided point (the hand's mean position) on the path's first waypoint.
    gx, gy = walker.guided_point()
    walker.x, walker.y = x0 - gx, y0 - gy
    hand = walker.hand()
    horiz = cfg.horizontal_cable_m
    robot_z = hand[2] + cfg.robot_height_m
    rx, ry = hand[0] + horiz * tx, hand[1] + horiz * ty
    rvx = rvy = 0.0
    ma, ba, kh = cfg.robot_mass_kg, cfg.robot_damping_ns_per_m, cfg.position_gain_n_per_m
    l0, kc, cc = cfg.cable_rest_length_m, cfg.cable_stiffness_n_per_m, cfg.cable_damping_ns_per_m
    d_last: float | None = None
    length = path.length_m
    pending_stops = list(path.stops())
    corners = path.corners()

    cols: dict[str, list] = {k: [] for k in ("t", "g", "c", "h", "hm", "r", "rv", "f", "sv", "iv", "th", "cad", "fr")}
    starts, stops, turns = [cfg.start_s], [], []
    s_h = 0.0
    mode = "guiding"  # guiding, stopping, goal
    anchor = 0.0  # arc length the robot's reference holds at while stopping
    resume_at = math.inf
    force_on_t = cfg.start_s
    goal_s = math.nan
    stalled_s = 0.0
    end_at = cfg.max_duration_s
    fx = fy = fz = 0.0
    for k in range(max_frames + 1):
        t = k * frame_dt
        if t > end_at + 1e-9:
            break
        hand = walker.hand()
        measured = hand if noise is None else (hand[0] + noise[k, 0], hand[1] + noise[k, 1], hand[2] + noise[k, 2])
        # The controller: progress along the path from the measured handle (the motion capture).
        s_h = path.project(measured[0], measured[1], s_h)
        while corners and s_h >= corners[0][0]:
            turns.append(t)
            corners.pop(0)
        if mode == "guiding":
            if pending_stops and s_h >= pending_stops[0][0] - cfg.stop_trigger_m:
                anchor, hold = pending_stops.pop(0)
                mode, resume_at = "stopping", t + 2.0 + hold
                stops.append(t)
            elif s_h >= length - cfg.stop_trigger_m:
                anchor, mode = length, "goal"
                stops.append(t)
        elif mode == "stopping" and t >= resume_at:
            mode, force_on_t = "guiding", t
            starts.append(t)
        if mode == "guiding":
            level = _ramp(t, force_on_t, cfg.force_ramp_s) * path.pace_at(s_h)
            ref_s = s_h + horiz
        else:  # the force fades as the walker nears the stop: its pace dies out there
            level = min(max((anchor - s_h) / cfg.stop_trigger_m, 0.0), 1.0) * path.pace_at(anchor - 1e-9)
            ref_s = anchor + horiz
        px, py, ptx, pty = path.point(min(ref_s, length + horiz))
        f_ref = cfg.human.nominal_force_n * level
        intent = walker.guided_velocity()
        svx, svy = feedback.update(t, measured, intent)
        ux = kh * (px - rx) + f_ref * ptx + ba * svx
        uy = kh * (py - ry) + f_ref * pty + ba * svy
        if t < cfg.start_s:  # hovering, waiting
            ux = uy = 0.0

        gx, gy = walker.guided_point()
        if mode == "goal" and math.isnan(goal_s):
            ex, ey = path.xy_m[-1]
            if math.hypot(gx - ex, gy - ey) <= cfg.goal_radius_m:
                goal_s = t
                end_at = min(end_at, t + cfg.after_goal_s)
            elif walker.speed_mps < _STALLED_MPS:  # stopped short of (or past) the goal: the walk is over
                stalled_s += frame_dt
                if stalled_s >= 1.0:
                    end_at = min(end_at, t)
            else:
                stalled_s = 0.0
        cols["t"].append(t)
        cols["g"].append((gx, gy))
        cols["c"].append(walker.centre())
        cols["h"].append(hand)
        cols["hm"].append(measured)
        cols["r"].append((rx, ry, robot_z))
        cols["rv"].append((rvx, rvy))
        cols["f"].append((fx, fy, fz))
        cols["sv"].append((svx, svy))
        cols["iv"].append(intent)
        cols["th"].append(walker.theta)
        cols["cad"].append(walker.cadence_hz)
        cols["fr"].append(f_ref)

        for _ in range(substeps):
            hand = walker.hand()
            d = math.dist((rx, ry, robot_z), hand)
            rate = (d - d_last) / dt if d_last is not None else 0.0
            d_last = d
            fx, fy, fz = cable_force((rx, ry, robot_z), hand, l0, kc, cc, rate)
            ax = (-ba * rvx - fx + ux) / ma  # the robot feels -f_c
            ay = (-ba * rvy - fy + uy) / ma
            rvx += ax * dt
            rvy += ay * dt
            speed = math.hypot(rvx, rvy)
            if speed > cfg.max_speed_mps:
                rvx *= cfg.max_speed_mps / speed
                rvy *= cfg.max_speed_mps / speed
            rx += rvx * dt
            ry += rvy * dt
            walker.step(dt, fx, fy)

    def arr(key, width=None):
        a = np.asarray(cols[key], dtype=float)
        return a if width is None else a.reshape(-1, width)

    force = arr("f", 3)
    return GuidanceRun(
        source=source,
        walker=subject.name,
        walk=path.name,
        seed=int(seed),
        latency_s=cfg.latency_s,
        time_s=arr("t"),
        guided_m=arr("g", 2),
        centre_m=arr("c", 3),
        hand_m=arr("h", 3),
        handle_measured_m=arr("hm", 3),
        robot_m=arr("r", 3),
        robot_v_mps=arr("rv", 2),
        force_n=force,
        slack=np.linalg.norm(force, axis=1) == 0.0,
        source_v_mps=arr("sv", 2),
        intent_v_mps=arr("iv", 2),
        theta_rad=arr("th"),
        cadence_hz=arr("cad"),
        reference_force_n=arr("fr"),
        starts_s=starts,
        stops_s=stops,
        turns_s=turns,
        goal_s=goal_s,
        path=path,
        config=cfg,
    )
