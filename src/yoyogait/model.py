"""The Yoyo-model of walking (eq. 1-4 of the paper).

The pelvis (centre of mass) moves like a point on a cylinder of radius ``r``
fixed inside a cylinder of radius ``R`` that rolls forward:

    x(t) = R theta(t) + r sin(theta(t))          (eq. 1)
    z(t) = z0 + r cos(theta(t))                   (eq. 2)
    v_x  = R omega + r omega cos(theta)           (eq. 3)
    v_z  = -r omega sin(theta)                    (eq. 4)

with ``omega = d theta / dt``.  One turn of theta is one step, so
``omega = 2 pi * step_frequency_hz``.  The step frequency may vary over time;
theta is then its integral (trapezoidal rule on the given time grid), which is
what makes eq. 3-4 the exact derivatives of eq. 1-2 as the time step shrinks.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

__all__ = ["YoyoTrajectory", "yoyo_model", "integrate_phase"]


@dataclass(frozen=True)
class YoyoTrajectory:
    """Positions and velocities of the Yoyo-model on a time grid (SI units)."""

    time_s: np.ndarray
    theta_rad: np.ndarray
    omega_rad_s: np.ndarray
    x_m: np.ndarray
    z_m: np.ndarray
    vx_mps: np.ndarray
    vz_mps: np.ndarray


def integrate_phase(time_s, omega_rad_s, phase_rad: float = 0.0) -> np.ndarray:
    """theta(t) = phase + integral of omega, trapezoidal on the grid ``time_s``."""
    t = np.asarray(time_s, dtype=float)
    w = np.broadcast_to(np.asarray(omega_rad_s, dtype=float), t.shape)
    if t.ndim != 1:
        raise ValueError("time_s must be one-dimensional")
    return phase_rad + _cumtrapz(w, t)


def yoyo_model(time_s, R_m, r_m, step_frequency_hz, z0_m: float = 1.0, phase_rad: float = 0.0) -> YoyoTrajectory:
    """Evaluate eq. 1-4 on ``time_s``.

    ``R_m``, ``r_m`` and ``step_frequency_hz`` may be scalars or arrays of the
    same length as ``time_s`` (a parameter that changes over time); ``phase_rad``
    is theta at the first sample.
    """
    t = np.asarray(time_s, dtype=float)
    if t.ndim != 1:
        raise ValueError("time_s must be one-dimensional")
    if t.size > 1 and np.any(np.diff(t) <= 0):
        raise ValueError("time_s must be strictly increasing")
    R = np.broadcast_to(np.asarray(R_m, dtype=float), t.shape)
    r = np.broadcast_to(np.asarray(r_m, dtype=float), t.shape)
    omega = np.broadcast_to(2.0 * np.pi * np.asarray(step_frequency_hz, dtype=float), t.shape)
    theta = integrate_phase(t, omega, phase_rad)
    vx = R * omega + r * omega * np.cos(theta)  # eq. 3
    vz = -r * omega * np.sin(theta)  # eq. 4
    constant = t.size == 0 or (np.all(R == R[0]) and np.all(r == r[0]))
    if constant:
        x = R * theta + r * np.sin(theta)  # eq. 1
        z = z0_m + r * np.cos(theta)  # eq. 2
    else:
        # Parameters that change over time: positions are the integrals of eq. 3-4,
        # so that v_x and v_z stay the exact derivatives of x and z.
        x = r[0] * np.sin(theta[0]) + _cumtrapz(vx, t)
        z = z0_m + r[0] * np.cos(theta[0]) + _cumtrapz(vz, t)
    return YoyoTrajectory(t, theta, np.array(omega), x, z, vx, vz)


def _cumtrapz(y: np.ndarray, t: np.ndarray) -> np.ndarray:
    out = np.zeros_like(t)
    out[1:] = np.cumsum(0.5 * (y[1:] + y[:-1]) * np.diff(t))
    return out
