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
import struct
from collections.abc import Callable
from typing import Any

from ..estimators.imu import IMU_ESTIMATE_FIELDS
from ..estimators.online import ONLINE_ESTIMATE_COLUMNS, ONLINE_ESTIMATE_FIELDS
from ..io.recording import AXES

__all__ = [
    "UNOBSERVED_VARIANCE",
    "GAIT_STATE_LABELS",
    "IMU_GAIT_STATE_LABELS",
    "imu_gait_state_row",
    "horizontal_axes",
    "velocity_vector",
    "velocity_covariance",
    "gait_state_row",
    "StampedTwistBytes",
    "GaitStateBytes",
    "pose_of",
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

#: The gait state of IMU input (``imu_topic``): every field of the IMU estimate's record table, in order
#: (its ``t_s`` is ``time_s``; docs/imu.md). The IMU estimator has no prediction and no radii.
IMU_GAIT_STATE_LABELS: tuple[str, ...] = tuple(
    "time_s" if name == "t_s" else name for name, _, _ in IMU_ESTIMATE_FIELDS
)
_IMU_ATTRIBUTES = tuple(name for name, _, _ in IMU_ESTIMATE_FIELDS)


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


def imu_gait_state_row(estimate) -> list[float]:
    """The IMU gait state's values in :data:`IMU_GAIT_STATE_LABELS` order."""
    return [float(getattr(estimate, a)) for a in _IMU_ATTRIBUTES]


# ------------------------------------------------------------------------------ serialized messages
# The per-frame messages are published as their serialized bytes (rclpy's Publisher.publish(bytes)):
# building a message object and converting it costs tens of microseconds per topic, the gait state's
# 30 labelled dimensions most (about 60 us). Each message is serialized once by rclpy as a template;
# per frame only its numbers are written over, at offsets that follow from the CDR layout of the
# type (ROS 2 serializes as OMG CDR: a 4-byte encapsulation header, little endian where it is 00 01,
# then the fields, each aligned to its size). The tests compare the bytes with rclpy's own serialization.

_STAMP = struct.Struct("<iI")  # builtin_interfaces/Time: int32 sec, uint32 nanosec, right after the header
_TWIST_DOUBLES = struct.Struct("<42d")  # TwistWithCovariance: linear, angular, covariance[36]: the message's end
_POSE_DOUBLES = struct.Struct("<3d")  # Pose.position: the first 3 of the 7 doubles that end a PoseStamped
_LENGTH = struct.Struct("<I")
_CDR_LE = b"\x00\x01"
_MAX_FRAME_IDS = 16


class StampedTwistBytes:
    """``geometry_msgs/TwistWithCovarianceStamped`` as bytes: the stamp, the frame and 42 numbers (linear,
    angular, covariance) written into a template of the type serialized by ``serialize`` (one per frame id)."""

    def __init__(self, msg_type: Any, serialize: Callable[[Any], bytes]):
        self._type, self._serialize = msg_type, serialize
        self._templates: dict[str, tuple[bytes, bytes]] = {}

    def __call__(self, sec: int, nanosec: int, frame_id: str, linear, covariance) -> bytes:
        parts = self._templates.get(frame_id)
        if parts is None:
            if len(self._templates) >= _MAX_FRAME_IDS:  # a source that changes its frame id each message
                self._templates.clear()
            msg = self._type()
            msg.header.frame_id = frame_id
            raw = self._serialize(msg)
            end = 16 + _LENGTH.unpack_from(raw, 12)[0]  # the frame id's length, its NUL included
            pad = len(raw) - _TWIST_DOUBLES.size - end  # alignment of the doubles: zeros (rclpy leaves any bytes)
            parts = self._templates[frame_id] = (raw[:4], raw[12:end] + bytes(pad))
        head, frame = parts
        return head + _STAMP.pack(sec, nanosec) + frame + _TWIST_DOUBLES.pack(*linear, 0.0, 0.0, 0.0, *covariance)


class GaitStateBytes:
    """``std_msgs/Float64MultiArray`` with the labelled layout of :data:`GAIT_STATE_LABELS` as bytes: the
    layout serialized once (``message``, its data any n numbers), the row written after it."""

    def __init__(self, message: Any, serialize: Callable[[Any], bytes]):
        n = len(message.layout.dim)
        message.data = [0.0] * n
        raw = serialize(message)
        self._head = raw[: len(raw) - 8 * n]
        self._row = struct.Struct(f"<{n}d")

    def __call__(self, row) -> bytes:
        return self._head + self._row.pack(*row)


def pose_of(raw: bytes) -> tuple[int, int, bytes, float, float, float] | None:
    """Stamp (sec, nanosec), frame id (bytes) and position of a serialized ``geometry_msgs/PoseStamped``; None
    when it is not little-endian CDR (then deserialize it)."""
    if raw[:2] != _CDR_LE or len(raw) < 16 + 56:
        return None
    sec, nanosec = _STAMP.unpack_from(raw, 4)
    (n,) = _LENGTH.unpack_from(raw, 12)
    x, y, z = _POSE_DOUBLES.unpack_from(raw, len(raw) - 56)
    return sec, nanosec, raw[16 : 16 + max(0, n - 1)], x, y, z
