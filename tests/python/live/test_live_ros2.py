"""``yoyogait live --ros2-topic``: estimates on a ROS 2 topic (runs where the ros2 extra is installed)."""

from __future__ import annotations

import os
import threading
import time

import numpy as np
import pytest
from live_helpers import marker_info, pelvis_frames, pelvis_labels, short_walk, unique

from yoyogait import OnlineEstimator
from yoyogait.cli import main
from yoyogait.live.live import ESTIMATE_COLUMNS, estimate_row

# lark, under the rosidl runtime that rclpy.init loads, imports modules deprecated in Python 3.11 (ROS's own).
pytestmark = pytest.mark.filterwarnings("ignore::DeprecationWarning:lark.*")

pylsl = pytest.importorskip("pylsl")
rclpy = pytest.importorskip("rclpy", reason="the ros2 extra (rclpy, std_msgs) is not installed")
std_msgs = pytest.importorskip("std_msgs.msg", reason="the ros2 extra (rclpy, std_msgs) is not installed")


@pytest.fixture
def ros_localhost(ros_machine_only):
    """rclpy started on this machine only, in the test run's own domain (tests/conftest.py)."""
    rclpy.init()
    yield
    rclpy.shutdown()


def test_live_publishes_every_estimate_on_the_ros2_topic_as_a_float64_multiarray(ros_localhost):
    """live --ros2-topic: one Float64MultiArray per frame, its data the estimate channels in order."""
    rec = short_walk(1.0)
    frames = pelvis_frames(rec)
    source, topic = unique("ros"), f"/yoyogait_test_{os.getpid()}"
    received = []
    node = rclpy.create_node("yoyogait_test_subscriber")
    # A history deeper than the frames: a keep-last reader as deep as the walk drops the oldest
    # estimate when all of them arrive before the callbacks run (seen once on a loaded machine).
    node.create_subscription(std_msgs.Float64MultiArray, topic, lambda m: received.append(m), 10 * rec.n_frames)
    outlet = pylsl.StreamOutlet(marker_info(pylsl, source, pelvis_labels()))
    done = {}
    args = ["live", "--source", source, "--ros2-topic", topic, "--exit-on-end", "--max-buffer-s", "10"]
    live = threading.Thread(target=lambda: done.update(code=main(args)), daemon=True)
    live.start()
    assert outlet.wait_for_consumers(15)
    end = time.monotonic() + 15
    while node.count_publishers(topic) == 0 and time.monotonic() < end:
        rclpy.spin_once(node, timeout_sec=0.05)
    time.sleep(2.0)  # discovery seen from the subscriber; give the publisher side time to match it too
    base = pylsl.local_clock()
    for k in range(rec.n_frames):  # at the capture's rate, as a mocap system sends them
        while pylsl.local_clock() < base + rec.time_s[k]:
            rclpy.spin_once(node, timeout_sec=0.001)
        outlet.push_sample(frames[k].tolist(), base + rec.time_s[k])
    end = time.monotonic() + 15
    while len(received) < rec.n_frames and time.monotonic() < end:
        rclpy.spin_once(node, timeout_sec=0.05)
    del outlet
    live.join(15)
    node.destroy_node()
    assert done.get("code") == 0
    got_times = [m.data[0] for m in received]
    assert len(received) == rec.n_frames, f"missing: {sorted(set(base + rec.time_s) - set(got_times))[:5]}"
    assert received[0].layout.dim[0].label == "estimate" and received[0].layout.dim[0].size == len(ESTIMATE_COLUMNS)
    est = OnlineEstimator(["LASI", "RASI", "LPSI", "RPSI"], "z", 1.0)
    expected = [estimate_row(est.update(base + t, f.reshape(4, 3))) for t, f in zip(rec.time_s, frames)]
    np.testing.assert_array_equal(np.array([m.data for m in received]), np.array(expected))
