"""Estimates on a ROS 2 topic (the optional extra ``yoyogait[ros2]``: rclpy and std_msgs).

Each estimate is one ``std_msgs/msg/Float64MultiArray`` on the topic: ``layout.dim[0]`` is
labelled ``estimate`` with size and stride the number of channels, ``data`` holds the estimate
stream's channels in their order (:data:`yoyogait.live.live.ESTIMATE_COLUMNS`, ``time_s`` first;
docs/live.md). The node is called ``yoyogait_live``; QoS: keep last 10, reliable.
"""

from __future__ import annotations

import warnings
from typing import Any

from ..errors import YoyogaitError
from .live import ESTIMATE_COLUMNS

INSTALL_HINT = "publishing on ROS 2 needs rclpy and std_msgs: pip install 'yoyogait[ros2]' (or source a ROS 2 install)"


def _ros() -> tuple[Any, Any]:
    # lark (under the rosidl runtime) imports modules deprecated in Python 3.11: ROS's warnings, not shown.
    warnings.filterwarnings("ignore", category=DeprecationWarning, module=r"lark(\..*)?$")
    try:
        import rclpy
        from std_msgs.msg import Float64MultiArray, MultiArrayDimension
    except (ImportError, OSError, RuntimeError) as exc:
        raise YoyogaitError(f"{INSTALL_HINT} ({exc})") from None
    return rclpy, (Float64MultiArray, MultiArrayDimension)


def _duration(seconds: float) -> Any:
    from rclpy.duration import Duration

    return Duration(seconds=seconds)


class Ros2Publisher:
    """Publishes estimate rows on ``topic``; ``close()`` shuts the node down."""

    def __init__(self, topic: str, node_name: str = "yoyogait_live"):
        rclpy, (array_type, dimension_type) = _ros()
        self._rclpy = rclpy
        self._owns_context = not rclpy.ok()
        if self._owns_context:
            rclpy.init()
        try:
            self.node = rclpy.create_node(node_name)
            self.publisher = self.node.create_publisher(array_type, topic, 10)
        except Exception as exc:  # an invalid topic name, a middleware that does not start
            self.close()
            raise YoyogaitError(f"ROS 2 topic {topic!r}: {exc}") from None
        self._message = array_type()
        self._message.layout.dim = [
            dimension_type(label="estimate", size=len(ESTIMATE_COLUMNS), stride=len(ESTIMATE_COLUMNS))
        ]

    def publish(self, row: list[float], stamp: float | None = None) -> None:
        """One estimate row (the estimate stream's channels); ``stamp`` is carried by ``time_s``."""
        self._message.data = row
        self.publisher.publish(self._message)

    def close(self) -> None:
        node = getattr(self, "node", None)
        if node is not None:
            publisher = getattr(self, "publisher", None)
            if publisher is not None:  # reliable delivery of the last estimates before the node goes
                publisher.wait_for_all_acked(_duration(1.0))
            node.destroy_node()
            self.node = None
        if self._owns_context and self._rclpy.ok():
            self._rclpy.shutdown()
