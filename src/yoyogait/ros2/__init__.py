"""Gait estimated from ROS 2 motion-capture topics, estimates published as standard messages (docs/ros2.md).

* :mod:`.node`: the node (``yoyogait ros2``, ``python -m yoyogait.ros2 --ros-args -p name:=value``):
  ``PoseStamped``, ``PointStamped`` per marker, ``mocap4r2_msgs/Markers`` or ``sensor_msgs/Imu`` in;
  walking, current and predicted velocity (``TwistWithCovarianceStamped``), the gait state (a labelled
  ``Float64MultiArray``) and health (``DiagnosticArray``) out.
* :mod:`.assembly`: frames of k points from point messages that arrive one by one.
* :mod:`.messages`: the velocity vectors and covariances in the input frame, the gait state's labels, the
  per-frame messages as serialized bytes.

rclpy and the message packages are the optional extra ``yoyogait[ros2]`` (wheels from PyPI), imported
where they are used (:mod:`._ros`). pylsl is not needed.
"""

from __future__ import annotations
