"""The guided walker: a person who walks where the cable pulls, with the gait of the synthetic lab.

Human model (docs/guidance.md, sec. 2).  As in Tognon, Alami and Siciliano (IEEE T-RO 37(3),
2021) and its human-state-aware follow-up, the person's walking intent is a mass-damper driven
by the horizontal cable force at the hand::

    M_H dv_I/dt = -B_H v_I + f_c,h

``v_I`` is the intended walking velocity in the floor plane (no oscillation).  ``B_H`` is set so
that the nominal guiding force gives the walker's preferred speed (``B_H = F_nominal / v_pref``)
and ``M_H = tau_H B_H`` with ``tau_H`` the time a person takes to change pace (about two steps).

Gait on the intent (the synthetic lab's walker, :mod:`yoyogait.synthetic`):

* cadence from speed at a constant walk ratio (step length / cadence; Sekiya and Nagasaki 1998):
  ``f = f_pref sqrt(v / v_pref)``, step length ``v / f``; the Yoyo angle ``theta`` integrates
  ``2 pi f``;
* the centre of mass: the intent position plus the Yoyo model's forward oscillation (eq. 1, with
  the lab's phase offset pi and second harmonic), vertical oscillation (eq. 2), and sideways sway
  at stride frequency; amplitudes scale with ``v / v_pref`` (a standing person does not sway);
* the heading: it follows the direction of ``v_I`` with a 0.2 s time constant, turning at most
  3 rad/s (a person turning on the spot), held below 0.05 m/s;
* the hand that holds the handle: the lab's wrist, in front of and beside the body, rotating with
  the heading, with its small arm swing.  The arm is rigid: the hand carries the whole trunk
  oscillation to the cable (docs/guidance.md, sec. 5: what is not modelled).

Everything here is SYNTHETIC.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

from ..synthetic import SyntheticSubject

__all__ = ["HumanModel", "GuidedWalker", "PHASE_OFFSET_RAD"]

PHASE_OFFSET_RAD = math.pi
"""Offset of the forward oscillation, as in the synthetic lab's realistic walks."""
_HEADING_MIN_SPEED_MPS = 0.05
_TURN_TAU_S = 0.2
"""The heading follows the walking direction with this time constant [s] ..."""
_MAX_TURN_RATE_RAD_S = 3.0
"""... and at most this fast (a quarter turn on the spot in about half a second) [rad/s]."""
_MAX_PACE_RATIO = 2.0
_MAX_AMPLITUDE_RATIO = 1.5


@dataclass(frozen=True)
class HumanModel:
    """The person's response to the cable force (the mass-damper on the walking intent)."""

    nominal_force_n: float = 5.0
    """The guiding force at which the walker walks at its preferred speed [N]."""
    time_constant_s: float = 0.8
    """``M_H / B_H``: how fast the pace follows a change of force [s]."""

    def damping_ns_per_m(self, subject: SyntheticSubject) -> float:
        """``B_H`` for ``subject``: the nominal force over the preferred speed [N s/m]."""
        return self.nominal_force_n / subject.speed_mps

    def mass_kg(self, subject: SyntheticSubject) -> float:
        """``M_H = tau_H B_H``: the apparent mass [kg]."""
        return self.time_constant_s * self.damping_ns_per_m(subject)


class GuidedWalker:
    """One walker's state: intent position and velocity, Yoyo angle, heading; integrated by
    :meth:`step` (semi-implicit Euler), positions of the centre and the hand by :meth:`hand`."""

    def __init__(
        self,
        subject: SyntheticSubject,
        model: HumanModel,
        x_m: float,
        y_m: float,
        heading_rad: float,
        theta_rad: float = 0.0,
    ):
        self.subject = subject
        self.model = model
        self.b_h = model.damping_ns_per_m(subject)
        self.m_h = model.mass_kg(subject)
        self.v_pref = subject.speed_mps
        self.x, self.y = float(x_m), float(y_m)
        self.vx = self.vy = 0.0
        self.heading = float(heading_rad)
        self.theta = float(theta_rad)
        self.cadence_hz = 0.0
        self.turn_rate_rad_s = 0.0

    @property
    def speed_mps(self) -> float:
        return math.hypot(self.vx, self.vy)

    def step(self, dt_s: float, fx_n: float, fy_n: float) -> None:
        """Advance ``dt_s`` under the horizontal cable force (fx, fy) at the hand."""
        ax = (fx_n - self.b_h * self.vx) / self.m_h
        ay = (fy_n - self.b_h * self.vy) / self.m_h
        self.vx += ax * dt_s
        self.vy += ay * dt_s
        self.x += self.vx * dt_s
        self.y += self.vy * dt_s
        v = self.speed_mps
        if v > _HEADING_MIN_SPEED_MPS:  # the body turns towards the walking direction, at a human rate
            error = math.remainder(math.atan2(self.vy, self.vx) - self.heading, 2.0 * math.pi)
            self.turn_rate_rad_s = min(max(error / _TURN_TAU_S, -_MAX_TURN_RATE_RAD_S), _MAX_TURN_RATE_RAD_S)
            self.heading += self.turn_rate_rad_s * dt_s
        else:
            self.turn_rate_rad_s = 0.0
        self.cadence_hz = self.subject.step_frequency_hz * math.sqrt(min(v / self.v_pref, _MAX_PACE_RATIO))
        self.theta += 2.0 * math.pi * self.cadence_hz * dt_s

    def _scale(self) -> float:
        return min(self.speed_mps / self.v_pref, _MAX_AMPLITUDE_RATIO)

    def centre(self) -> tuple[float, float, float]:
        """The centre of mass (the pelvis centre of the synthetic lab) [m]."""
        s = self.subject
        k = self._scale()
        r = s.r_m * k
        th = self.theta
        fwd = r * math.sin(th + PHASE_OFFSET_RAD) + 0.5 * s.harmonic2_ratio * r * math.sin(
            2 * th + s.harmonic2_phase_rad + PHASE_OFFSET_RAD
        )
        lat = s.sway_m * k * math.cos(0.5 * th)
        z = s.z0_m + r * math.cos(th) + 0.5 * s.harmonic2_ratio * r * math.cos(2 * th + s.harmonic2_phase_rad)
        c, sn = math.cos(self.heading), math.sin(self.heading)
        return self.x + fwd * c - lat * sn, self.y + fwd * sn + lat * c, z

    def hand(self) -> tuple[float, float, float]:
        """The hand holding the handle [m]: centre plus the rotated hand offset and arm swing."""
        s = self.subject
        cx, cy, cz = self.centre()
        k = self._scale()
        ox = s.hand_offset_m[0] + s.hand_swing_m * k * math.sin(0.5 * self.theta + 0.3)
        oy = s.hand_offset_m[1]
        oz = s.hand_offset_m[2] + 0.3 * s.hand_swing_m * k * math.sin(self.theta + 0.5)
        c, sn = math.cos(self.heading), math.sin(self.heading)
        return cx + ox * c - oy * sn, cy + ox * sn + oy * c, cz + oz

    def guided_point(self) -> tuple[float, float]:
        """Where the hand is on average (intent position plus the hand offset, no oscillation) [m]:
        the point the guidance steers along the path."""
        s = self.subject
        c, sn = math.cos(self.heading), math.sin(self.heading)
        ox, oy = s.hand_offset_m[0], s.hand_offset_m[1]
        return self.x + ox * c - oy * sn, self.y + ox * sn + oy * c

    def guided_velocity(self) -> tuple[float, float]:
        """The velocity of the guided point: the intended velocity plus the hand offset turning with the
        body, without the oscillation [m/s]; what a perfect oscillation-free estimate of the handle gives."""
        s = self.subject
        c, sn = math.cos(self.heading), math.sin(self.heading)
        ox, oy = s.hand_offset_m[0], s.hand_offset_m[1]
        w = self.turn_rate_rad_s
        return self.vx - w * (ox * sn + oy * c), self.vy + w * (ox * c - oy * sn)
