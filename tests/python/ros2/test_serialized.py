"""The node's messages written as bytes from templates: rclpy's serialization of the same messages (up to the
alignment bytes, which CDR leaves undefined and rclpy does not clear)."""

from __future__ import annotations

import numpy as np
from ros2_helpers import require_ros

from yoyogait.ros2 import messages

rclpy = require_ros()
from geometry_msgs.msg import PoseStamped, TwistWithCovarianceStamped  # noqa: E402
from rclpy.serialization import deserialize_message, serialize_message  # noqa: E402
from std_msgs.msg import Float64MultiArray, MultiArrayDimension  # noqa: E402


def test_twist_bytes_equal_rclpy_serialization_for_any_frame_id():
    """TwistWithCovarianceStamped from the template: as long as rclpy's and read back equal to the message, for
    frame ids of many lengths mod 8."""
    rng = np.random.default_rng(3)
    to_bytes = messages.StampedTwistBytes(TwistWithCovarianceStamped, serialize_message)
    for frame_id in ("", "m", "mocap", "world_frame", "a/b/c/d/e/f/g", "mocap"):
        linear = tuple(float(v) for v in rng.normal(size=3))
        cov = [float(v) for v in rng.normal(size=36)]
        sec, nanosec = int(rng.integers(0, 2**31 - 1)), int(rng.integers(0, 10**9))
        msg = TwistWithCovarianceStamped()
        msg.header.stamp.sec, msg.header.stamp.nanosec, msg.header.frame_id = sec, nanosec, frame_id
        msg.twist.twist.linear.x, msg.twist.twist.linear.y, msg.twist.twist.linear.z = linear
        msg.twist.covariance = cov
        raw = to_bytes(sec, nanosec, frame_id, linear, cov)
        assert len(raw) == len(serialize_message(msg)), frame_id
        assert deserialize_message(raw, TwistWithCovarianceStamped) == msg, frame_id


def test_gait_state_bytes_equal_rclpy_serialization():
    """The labelled gait state from the template: as long as rclpy's, its labels and values read back."""
    labels = messages.GAIT_STATE_LABELS
    msg = Float64MultiArray()
    msg.layout.dim = [MultiArrayDimension(label=label, size=1, stride=1) for label in labels]
    to_bytes = messages.GaitStateBytes(msg, serialize_message)
    row = [float(v) for v in np.random.default_rng(4).normal(size=len(labels))]
    msg.data = row
    raw = to_bytes(row)
    assert len(raw) == len(serialize_message(msg))
    back = deserialize_message(raw, Float64MultiArray)
    assert [d.label for d in back.layout.dim] == list(labels) and list(back.data) == row


def test_pose_read_from_bytes_equals_the_message():
    """Stamp, frame id and position read from a serialized PoseStamped equal the message's; other encodings None."""
    for frame_id in ("", "mocap", "world", "natnet_frame_1"):
        msg = PoseStamped()
        msg.header.stamp.sec, msg.header.stamp.nanosec, msg.header.frame_id = 1_700_000_000, 123_456_789, frame_id
        msg.pose.position.x, msg.pose.position.y, msg.pose.position.z = 0.25, -1.5, 0.98
        msg.pose.orientation.w = 1.0
        got = messages.pose_of(serialize_message(msg))
        assert got == (1_700_000_000, 123_456_789, frame_id.encode(), 0.25, -1.5, 0.98)
    assert messages.pose_of(b"\x00\x00" + serialize_message(msg)[2:]) is None  # big-endian CDR
