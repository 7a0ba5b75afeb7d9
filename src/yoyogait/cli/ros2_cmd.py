"""``yoyogait ros2``: the ROS 2 node (docs/ros2.md); ``python -m yoyogait.ros2`` is the same node."""

from __future__ import annotations

import signal
import threading

import click

from .._guard import Interrupted
from ..ros2.node import run_node, startup_line, summary_line
from .options import POSITIVE, config_file_option


@click.command(
    "ros2",
    context_settings={"ignore_unknown_options": True, "allow_interspersed_args": False},
)
@click.option("--pose-topic", default=None, metavar="TOPIC", help="geometry_msgs/PoseStamped of one rigid body.")
@click.option(
    "--point-topic",
    "point_topics",
    multiple=True,
    metavar="TOPIC",
    help="geometry_msgs/PointStamped of one marker; repeat for each marker (averaged, as the pelvis points).",
)
@click.option(
    "--foot-topic",
    "foot_topics",
    multiple=True,
    metavar="TOPIC",
    help="With --point-topic: geometry_msgs/PointStamped of one foot (heel or ankle); twice, one per foot.",
)
@click.option("--markers-topic", default=None, metavar="TOPIC", help="mocap4r2_msgs/Markers (mocap4r2_msgs needed).")
@click.option(
    "--imu-topic", default=None, metavar="TOPIC", help="sensor_msgs/Imu of one IMU at the lower back (docs/imu.md)."
)
@click.option(
    "--forward-axis",
    type=click.Choice(["x", "y", "z", "-x", "-y", "-z"]),
    default=None,
    help="IMU input: the sensor axis pointing forward [x, REP 103].",
)
@click.option(
    "--sensor-height-m", type=POSITIVE, metavar="METRES", default=None, help="IMU input: sensor height standing [0.95]."
)
@click.option("--up-axis", type=click.Choice(["x", "y", "z"]), default=None, help="Up axis of the input frame [z].")
@click.option("--length-unit-m", type=POSITIVE, metavar="METRES", default=None, help="Metres per input unit [1].")
@click.option(
    "--time-source", type=click.Choice(["header", "arrival"]), default=None, help="Frame time [header.stamp]."
)
@click.option("--qos", type=click.Choice(["reliable", "sensor_data"]), default=None, help="Input QoS [reliable].")
@click.option(
    "--predict-horizon-s", type=POSITIVE, metavar="SECONDS", default=None, help="Horizon of ~/predicted_velocity [0.2]."
)
@config_file_option("Settings of the online (or, IMU input, the [imu]) estimator: a TOML file (docs/configuration.md).")
@click.option("--duration", type=POSITIVE, metavar="SECONDS", default=None, help="Stop after this many seconds.")
@click.argument("ros_args", nargs=-1, type=click.UNPROCESSED)
def command(
    pose_topic, point_topics, foot_topics, markers_topic, imu_topic, forward_axis, sensor_height_m, up_axis,
    length_unit_m, time_source, qos, predict_horizon_s, config_file, duration, ros_args,
):  # fmt: skip
    """Estimate gait from ROS 2 motion-capture or IMU topics; publish walking, current and predicted velocity, the gait
    state and diagnostics (docs/ros2.md). ROS_ARGS: --ros-args -p name:=value -r from:=to ..."""
    options = {
        "pose_topic": pose_topic,
        "point_topics": list(point_topics) or None,
        "foot_topics": list(foot_topics) or None,
        "markers_topic": markers_topic,
        "imu_topic": imu_topic,
        "forward_axis": forward_axis,
        "sensor_height_m": sensor_height_m,
        "up_axis": up_axis,
        "length_unit_m": length_unit_m,
        "time_source": time_source,
        "qos": qos,
        "predict_horizon_s": predict_horizon_s,
        "config_file": config_file,
    }
    parameters = {k: v for k, v in options.items() if v is not None}
    if ros_args and ros_args[0] != "--ros-args":
        raise click.UsageError(f"unexpected argument {ros_args[0]!r}; ROS arguments follow --ros-args")
    stop = threading.Event()
    received: list[int] = []

    def on_signal(signum, frame):
        received.append(signum)
        stop.set()

    in_main = threading.current_thread() is threading.main_thread()
    previous = {s: signal.signal(s, on_signal) for s in (signal.SIGINT, signal.SIGTERM)} if in_main else {}

    try:
        counts = run_node(
            parameters,
            ros_args,
            stop=stop,
            duration_s=duration,
            on_start=lambda gait: click.echo(startup_line(gait), err=True),
        )
    finally:
        for s, h in previous.items():
            signal.signal(s, h)
    click.echo(summary_line(counts), err=True)
    if received:
        raise Interrupted(received[0])
