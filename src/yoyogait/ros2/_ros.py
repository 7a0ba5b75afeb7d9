"""rclpy and the message types, imported on first use, with one line naming the ``ros2`` extra when absent.

The rosidl runtime parses type descriptions with lark, which imports modules deprecated in Python 3.11
(``sre_parse``): those DeprecationWarnings come from ROS's own code and are not shown.
"""

from __future__ import annotations

import warnings
from types import SimpleNamespace
from typing import Any

from ..errors import YoyogaitError

INSTALL_HINT = (
    "the ROS 2 node needs rclpy and the message packages: pip install 'yoyogait[ros2]' (or source a ROS 2 install)"
)
MARKERS_HINT = (
    "mocap4r2_msgs is not importable (it is not on PyPI): source a ROS 2 workspace that has mocap4r2_msgs "
    "to read its Markers"
)

_loaded: SimpleNamespace | None = None


def ros() -> Any:
    """rclpy and the message classes the node uses (a namespace); YoyogaitError naming the extra."""
    global _loaded
    if _loaded is not None:
        return _loaded
    # lark (under the rosidl runtime) is imported later too, when rclpy starts: not only in this block.
    warnings.filterwarnings("ignore", category=DeprecationWarning, module=r"lark(\..*)?$")
    try:
        with warnings.catch_warnings():
            warnings.simplefilter("ignore", DeprecationWarning)
            import rclpy
            import rclpy.executors
            import rclpy.experimental
            import rclpy.node
            import rclpy.qos
            import rclpy.serialization
            import rclpy.signals
            from diagnostic_msgs.msg import DiagnosticArray, DiagnosticStatus, KeyValue
            from geometry_msgs.msg import PointStamped, PoseStamped, TwistWithCovarianceStamped
            from rcl_interfaces.msg import ParameterDescriptor
            from rclpy.parameter import Parameter
            from rclpy.validate_topic_name import validate_topic_name
            from sensor_msgs.msg import Imu
            from std_msgs.msg import Float64MultiArray, Header, MultiArrayDimension
    except (ImportError, OSError, RuntimeError) as exc:
        raise YoyogaitError(f"{INSTALL_HINT} ({exc})") from None
    _loaded = SimpleNamespace(
        rclpy=rclpy,
        Node=rclpy.node.Node,
        Parameter=Parameter,
        validate_topic_name=validate_topic_name,
        ParameterDescriptor=ParameterDescriptor,
        qos=rclpy.qos,
        executors=rclpy.executors,
        experimental=rclpy.experimental,
        signals=rclpy.signals,
        serialize=rclpy.serialization.serialize_message,
        deserialize=rclpy.serialization.deserialize_message,
        PoseStamped=PoseStamped,
        PointStamped=PointStamped,
        Imu=Imu,
        TwistWithCovarianceStamped=TwistWithCovarianceStamped,
        Header=Header,
        Float64MultiArray=Float64MultiArray,
        MultiArrayDimension=MultiArrayDimension,
        DiagnosticArray=DiagnosticArray,
        DiagnosticStatus=DiagnosticStatus,
        KeyValue=KeyValue,
    )
    return _loaded


def markers_type() -> Any:
    """mocap4r2_msgs/msg/Markers; YoyogaitError (one line) when the package is not importable."""
    try:
        with warnings.catch_warnings():
            warnings.simplefilter("ignore", DeprecationWarning)
            from mocap4r2_msgs.msg import Markers
    except (ImportError, OSError, RuntimeError):
        raise YoyogaitError(MARKERS_HINT) from None
    return Markers
