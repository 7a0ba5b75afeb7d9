"""Helpers of the ROS 2 node tests: rclpy or a visible reason, the node and a test node spun on loopback."""

from __future__ import annotations

import os
import platform
import threading
import time
from collections.abc import Callable

import pytest

#: Where PyPI has the ROS 2 wheels (the ros2 extra installs them there; docs/ros2.md).
WHEELS_EXIST = platform.system() == "Linux" and platform.machine() == "x86_64"


def require_ros():
    """rclpy and the messages; skip with the reason where the wheels do not exist, fail under CI where they do."""
    try:
        import rclpy  # noqa: F401
        from geometry_msgs.msg import PointStamped  # noqa: F401
    except (ImportError, OSError, RuntimeError) as exc:
        reason = f"the ros2 extra (rclpy and the message packages) is not importable: {exc}"
        if WHEELS_EXIST and os.environ.get("CI"):
            pytest.fail(reason + "; pip install '.[test]' installs it on Linux x86_64")
        pytest.skip(reason + (" (pip install '.[ros2]')" if WHEELS_EXIST else " (no PyPI wheels for this platform)"))
    import rclpy

    return rclpy


class Loopback:
    """A context of its own with the node under test and a test node, spun by one executor in a thread."""

    def __init__(self, rclpy, parameters: dict, node_name: str = "yoyogait_test"):
        from rclpy.context import Context
        from rclpy.executors import SingleThreadedExecutor

        from yoyogait.ros2.node import GaitNode

        self.rclpy = rclpy
        self.context = Context()
        rclpy.init(context=self.context, signal_handler_options=rclpy.signals.SignalHandlerOptions.NO)
        self.gait = GaitNode(parameters, node_name=node_name, context=self.context)
        self.test = rclpy.create_node("yoyogait_test_peer", context=self.context)
        self.executor = SingleThreadedExecutor(context=self.context)
        self.executor.add_node(self.gait.node)
        self.executor.add_node(self.test)
        self._stop = threading.Event()
        self.thread = threading.Thread(target=self._spin, daemon=True)
        self.thread.start()

    def _spin(self):
        while not self._stop.is_set() and self.context.ok():
            self.executor.spin_once(timeout_sec=0.02)

    def qos(self, depth: int = 100):
        from rclpy.qos import HistoryPolicy, QoSProfile, ReliabilityPolicy

        return QoSProfile(depth=depth, reliability=ReliabilityPolicy.RELIABLE, history=HistoryPolicy.KEEP_LAST)

    def collect(self, msg_type, topic: str) -> list:
        got: list = []
        self.test.create_subscription(msg_type, topic, got.append, self.qos(1000))
        return got

    def wait(self, condition: Callable[[], bool], timeout_s: float = 10.0) -> bool:
        end = time.monotonic() + timeout_s
        while not condition() and time.monotonic() < end:
            time.sleep(0.005)
        return condition()

    def close(self):
        self._stop.set()
        self.thread.join(5)
        self.executor.shutdown()
        self.gait.destroy()
        self.test.destroy_node()
        self.rclpy.shutdown(context=self.context)
