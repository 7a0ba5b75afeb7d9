"""What the node publishes, as numbers: the velocity vectors in the input frame, their 6 x 6 covariances, and
the labels of the gait state (docs/ros2.md).

Axes. The estimator's horizontal axes a, b are the two axes of the input frame other than the up
axis, in increasing order (z up: a = x, b = y); its heading is the angle from a towards b. A
velocity along the heading ``v`` and up ``vz`` is ``v (cos h e_a + sin h e_b) + vz e_up`` in the
input frame.

Covariances (row-major 6 x 6 of ``TwistWithCovariance``: linear x, y, z, then angular x, y, z):
``var_along u u^T + var_across w w^T + var_up e e^T`` in the linear block, where u is the heading
direction, w the horizontal direction across it and e the up axis; a variance the estimator does not
observe (across the heading, the angular rates, a standard deviation that is not finite yet) is
:data:`UNOBSERVED_VARIANCE`. Each block is symmetric and positive semi-definite by construction.
"""

from __future__ import annotations

import math

from ..estimators.online import ONLINE_ESTIMATE_COLUMNS, ONLINE_ESTIMATE_FIELDS
from ..io.recording import AXES

__all__ = [
    "UNOBSERVED_VARIANCE",
    "GAIT_STATE_LABELS",
    "horizontal_axes",
    "velocity_vector",
    "velocity_covariance",
    "gait_state_row",
]

#: The variance of what is not observed [(m/s)^2, (rad/s)^2]: large, as ROS consumers (robot_localization) expect.
UNOBSERVED_VARIANCE = 1.0e6

#: The gait state's fields, in order: every column of the online estimate's record table (its ``t_s`` is
#: ``time_s``), then the gait estimator's radii R and r and the predicted velocity at the node's horizon.
GAIT_STATE_LABELS: tuple[str, ...] = ONLINE_ESTIMATE_COLUMNS + (
    "R_m",
    "r_m",
    "predict_ahead_s",
    "pred_vx_mps",
    "pred_vz_mps",
    "pred_vx_std_mps",
    "pred_vz_std_mps",
)
_ATTRIBUTES = tuple(f.name for f in ONLINE_ESTIMATE_FIELDS)


def horizontal_axes(up_axis: str) -> tuple[int, int, int]:
    """Indices (a, b, up) in x, y, z of the estimator's horizontal axes and the up axis."""
    up = AXES.index(up_axis)
    a, b = (k for k in range(3) if k != up)
    return a, b, up


def velocity_vector(axes: tuple[int, int, int], v_a: float, v_b: float, v_up: float) -> tuple[float, float, float]:
    """(x, y, z) in the input frame of a velocity given along a, b and up."""
    out = [0.0, 0.0, 0.0]
    out[axes[0]], out[axes[1]], out[axes[2]] = v_a, v_b, v_up
    return out[0], out[1], out[2]


def _variance(std: float) -> float:
    return std * std if math.isfinite(std) and std >= 0 else UNOBSERVED_VARIANCE


def velocity_covariance(
    axes: tuple[int, int, int], heading_rad: float, std_along: float, std_up: float = math.inf
) -> list[float]:
    """The row-major 6 x 6 covariance of a velocity known along the heading to ``std_along`` and up to
    ``std_up`` [m/s] (inf: not observed); across the heading and every angular rate not observed.

    The linear block is ``var_along u u^T + var_across w w^T + var_up e e^T`` written out (u = (c, s),
    w = (-s, c) in the a, b plane): each off-diagonal entry is computed once and written to both places."""
    big = UNOBSERVED_VARIANCE
    if math.isfinite(heading_rad):
        c, s = math.cos(heading_rad), math.sin(heading_rad)
        along = _variance(std_along)
    else:
        c, s, along = 1.0, 0.0, big
    a, b, up = axes
    cov = [0.0] * 36
    cov[6 * a + a] = along * c * c + big * s * s
    cov[6 * b + b] = along * s * s + big * c * c
    cov[6 * a + b] = cov[6 * b + a] = (along - big) * c * s
    cov[6 * up + up] = _variance(std_up)
    cov[21] = cov[28] = cov[35] = big
    return cov


def gait_state_row(estimate, radii: tuple[float, float], horizon_s: float, prediction) -> list[float]:
    """The gait state's values in :data:`GAIT_STATE_LABELS` order."""
    row = [float(getattr(estimate, a)) for a in _ATTRIBUTES]
    row += [float(radii[0]), float(radii[1]), float(horizon_s)]
    row += [
        float(prediction.vx_mps),
        float(prediction.vz_mps),
        float(prediction.vx_std_mps),
        float(prediction.vz_std_mps),
    ]
    return row
