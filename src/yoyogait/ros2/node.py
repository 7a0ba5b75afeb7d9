"""The ROS 2 node: motion-capture topics in, gait estimates out, each stamped with its input frame (docs/ros2.md).

One frame of the input (a ``PoseStamped``, the ``PointStamped`` of every marker topic for one stamp
(:mod:`.assembly`), or a ``mocap4r2_msgs/Markers``) goes through the frame handling shared with
``live`` (:class:`yoyogait.estimators.frame_gate.FrameGate`) and :class:`OnlineEstimator.update`, then out
(a ``sensor_msgs/Imu`` sample likewise through :class:`ImuOnlineEstimator.update`, without the predicted velocity):

=============================  ====================================  =============================================
topic (relative to the node)   type                                  what
=============================  ====================================  =============================================
``~/walking_velocity``         geometry_msgs/TwistWithCovarianceSt.  oscillation-free walking velocity (walk_a, walk_b)
``~/velocity``                 geometry_msgs/TwistWithCovarianceSt.  the front-end's current velocity (vh_a, vh_b, vz)
``~/predicted_velocity``       geometry_msgs/TwistWithCovarianceSt.  the velocity ``predict_horizon_s`` ahead
``~/gait_state``               std_msgs/Float64MultiArray            every field, ``layout.dim[i].label`` names data[i]
``/diagnostics``               diagnostic_msgs/DiagnosticArray       rates, dropped frames, latency, walking (~1 Hz)
=============================  ====================================  =============================================

Bad input (a NaN, a stamp of zero or from the future, a topic of another type or that never
publishes, a unit or up axis that fails the plausibility check of files) is one log line naming the
topic, once per topic and kind, and a count in the diagnostics; the node keeps running.
"""

from __future__ import annotations

import dataclasses
import gc
import math
import signal
import statistics
import sys
import threading
import time
from collections import deque
from collections.abc import Callable, Sequence
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np

from .. import _guard
from ..errors import InputError, YoyogaitError
from ..estimators.config import OnlineConfig
from ..estimators.frame_gate import DROP, RESTART, FrameCounts, FrameGate
from ..estimators.imu import ImuConfig, ImuOnlineEstimator
from ..estimators.imu import why_not_valid as imu_why_not_valid
from ..estimators.online import OnlineEstimator, config_for_point, why_not_valid
from ..io.imu_read import check_imu_plausible
from ..io.imu_recording import ImuRecording
from ..io.plausibility import check_plausible
from ..io.recording import AXES, Recording
from ..pipeline import points
from . import messages
from ._ros import markers_type, ros
from .assembly import FrameAssembler

__all__ = ["NODE_NAME", "PARAMETERS", "NodeCounts", "GaitNode", "run_node", "main", "startup_line", "summary_line"]

NODE_NAME = "yoyogait"

#: The node's parameters: name -> (default, what it is). An empty string or list is "not given".
PARAMETERS: dict[str, tuple[Any, str]] = {
    "pose_topic": ("", "geometry_msgs/PoseStamped of one rigid body (pelvis, tether handle)"),
    "point_topics": ([], "geometry_msgs/PointStamped topics, one per marker, averaged as the pelvis points are"),
    "markers_topic": ("", "mocap4r2_msgs/Markers (needs mocap4r2_msgs importable)"),
    "marker_names": ([], "the Markers' markers to follow by name (default: the pelvis, found by name)"),
    "foot_topics": ([], "with point_topics: two PointStamped topics, one per foot (heels or ankles), in the frames"),
    "foot_names": ([], "with markers_topic: the Markers' two foot markers (heels or ankles), in the frames"),
    "imu_topic": ("", "sensor_msgs/Imu of one IMU at the lower back (m/s^2 with gravity, rad/s: REP 145)"),
    "forward_axis": ("x", "IMU input: the sensor axis pointing forward, x y z -x -y -z (REP 103: x)"),
    "sensor_height_m": (0.0, "IMU input: the sensor's height above the floor standing [m] (0: the configuration's)"),
    "up_axis": ("z", "the input frame's up axis (x, y or z; ROS: z)"),
    "length_unit_m": (1.0, "metres per input length unit (ROS: 1)"),
    "time_source": ("header", "header (header.stamp) or arrival (the node's clock at arrival)"),
    "qos": ("reliable", "input QoS: reliable, or sensor_data (best effort, as mocap drivers publish)"),
    "queue_depth": (100, "messages kept per input and output topic (keep last)"),
    "predict_horizon_s": (0.2, "horizon of ~/predicted_velocity [s]"),
    "config_file": ("", "TOML settings of the online estimator (docs/configuration.md)"),
    "assembly_window_s": (0.05, "a point frame waits this long for its last marker, then goes incomplete [s]"),
    "reacquire_after_s": (2.0, "silence or jump of the input time after which the estimator starts over [s]"),
    "max_future_s": (0.5, "stamps further ahead of the node's clock are dropped [s]"),
    "silent_warning_s": (5.0, "an input topic silent this long gets one line [s]"),
    "plausibility_s": (3.0, "input time after which the frames so far get the plausibility check of files [s]"),
    "diagnostics_period_s": (1.0, "period of /diagnostics [s]"),
}
_CHOICES = {
    "up_axis": AXES,
    "time_source": ("header", "arrival"),
    "qos": ("reliable", "sensor_data"),
    "forward_axis": ("x", "y", "z", "-x", "-y", "-z"),
}
_INPUTS = ("pose_topic", "point_topics", "markers_topic", "imu_topic")
_POSE = "geometry_msgs/msg/PoseStamped"
_POINT = "geometry_msgs/msg/PointStamped"
_MARKERS = "mocap4r2_msgs/msg/Markers"
_IMU = "sensor_msgs/msg/Imu"
_IMU_AXES = (0, 1, 2)  # IMU input: the outputs' x is the forward direction at the start, z up


@dataclass
class NodeCounts(FrameCounts):
    """What the node saw (the frame counts: :class:`FrameCounts`) and what it refused before the gate."""

    zero_stamps: int = 0  # messages stamped 0 (a driver that does not stamp: time_source arrival)
    future_stamps: int = 0  # messages stamped more than max_future_s ahead of the node's clock
    non_finite: int = 0  # messages with a NaN or inf coordinate (estimated with that point missing)
    late_points: int = 0  # point messages of a stamp already estimated (point_topics)
    repeated_points: int = 0  # a second message of one point topic for one stamp (point_topics)
    incomplete_frames: int = 0  # point frames estimated without every marker (assembly_window_s)
    latency_s: deque = field(default_factory=lambda: deque(maxlen=1000), repr=False)  # clock - stamp at receipt


def _seconds(stamp: Any) -> float:
    return stamp.sec + stamp.nanosec * 1e-9


def _why_not_valid(estimate) -> str:
    """Why the last estimate is not valid, by name ("" when valid or when there is none yet: no input)."""
    if estimate is None or estimate.valid:
        return ""
    if hasattr(estimate, "invalid_reason"):  # marker input: a set of InvalidReason bits
        return why_not_valid(int(estimate.invalid_reason))
    return imu_why_not_valid(int(estimate.reason))


class GaitNode:
    """The node (``self.node``, an rclpy Node) with its subscriptions, estimator and publishers.

    ``parameters``: overrides of :data:`PARAMETERS` (the command line's ``--ros-args -p`` come from the
    context). ``context``: an rclpy context (default: the global one).
    """

    def __init__(self, parameters: dict[str, Any] | None = None, *, node_name: str = NODE_NAME, context=None):
        r = ros()
        self._r = r
        overrides = [r.Parameter(k, value=v) for k, v in (parameters or {}).items() if k in PARAMETERS]
        unknown = sorted(set(parameters or {}) - set(PARAMETERS))
        if unknown:
            raise InputError(f"unknown parameter {', '.join(unknown)}; parameters: {', '.join(PARAMETERS)}")
        self.node = r.Node(node_name, context=context, parameter_overrides=overrides)
        try:
            self._setup()
        except BaseException:
            self.node.destroy_node()
            raise

    # ----------------------------------------------------------------------------------------- setup
    def _param(self, name: str) -> Any:
        r = self._r
        default, doc = PARAMETERS[name]
        if isinstance(default, list):
            value = self.node.declare_parameter(
                name, r.Parameter.Type.STRING_ARRAY, r.ParameterDescriptor(description=doc)
            ).value
            value = [] if value is None else list(value)
        else:
            descriptor = r.ParameterDescriptor(description=doc, dynamic_typing=True)
            value = self.node.declare_parameter(name, default, descriptor).value
        if isinstance(default, float):
            if isinstance(value, bool) or not isinstance(value, (int, float)) or not math.isfinite(value):
                raise InputError(f"parameter {name}: a number, not {value!r}")
            value = float(value)
            if name == "sensor_height_m":  # 0: the configuration's
                if value < 0:
                    raise InputError(f"parameter {name}: a number >= 0, not {value!r}")
            elif value <= 0 and name != "max_future_s":
                raise InputError(f"parameter {name}: a number > 0, not {value!r}")
        elif isinstance(default, int):
            if isinstance(value, bool) or not isinstance(value, int) or value < 1:
                raise InputError(f"parameter {name}: a whole number >= 1, not {value!r}")
        elif isinstance(default, str) and not isinstance(value, str):
            raise InputError(f"parameter {name}: a string, not {value!r}")
        if name in _CHOICES and value not in _CHOICES[name]:
            raise InputError(f"parameter {name}: one of {', '.join(_CHOICES[name])}, not {value!r}")
        return value

    def _setup(self) -> None:
        r, node = self._r, self.node
        p = {name: self._param(name) for name in PARAMETERS}
        self.params = p
        given = [k for k in _INPUTS if p[k]]
        if len(given) != 1:
            raise InputError(
                "give one input: pose_topic (PoseStamped), point_topics (PointStamped per marker), markers_topic "
                f"(mocap4r2_msgs/Markers) or imu_topic (sensor_msgs/Imu); got {', '.join(given) if given else 'none'}"
            )
        self._check_feet(p)
        if p["predict_horizon_s"] > OnlineEstimator(["p"]).max_horizon_s:
            raise InputError(f"parameter predict_horizon_s: at most {OnlineEstimator(['p']).max_horizon_s:g} s")
        self.imu: ImuOnlineEstimator | None = None
        if p["imu_topic"]:
            self.imu = ImuOnlineEstimator(self._imu_config())
            self.config = None
        else:
            self.config = OnlineConfig.from_file(Path(p["config_file"])) if p["config_file"] else None
        self.by_arrival = p["time_source"] == "arrival"
        self.axes = messages.horizontal_axes(p["up_axis"])
        self.counts = NodeCounts()
        self.gate = FrameGate(0.0, p["reacquire_after_s"], self.counts)
        self.estimator: OnlineEstimator | None = None
        self.assembler: FrameAssembler | None = None
        self._said: set[tuple[str, str]] = set()
        self._last_message: dict[str, float] = {}
        self._started = time.monotonic()
        self._plausibility: list[tuple[float, np.ndarray]] | None = []
        self.implausible: str | None = None
        self.last_estimate: Any = None
        self._frame_id = ""
        depth = p["queue_depth"]
        if p["qos"] == "sensor_data":
            qos_in = r.qos.qos_profile_sensor_data
        else:
            qos_in = r.qos.QoSProfile(
                depth=depth, reliability=r.qos.ReliabilityPolicy.RELIABLE, history=r.qos.HistoryPolicy.KEEP_LAST
            )
        qos_out = r.qos.QoSProfile(
            depth=depth, reliability=r.qos.ReliabilityPolicy.RELIABLE, history=r.qos.HistoryPolicy.KEEP_LAST
        )
        for key in _INPUTS:
            for topic in p[key] if isinstance(p[key], list) else [p[key]] if p[key] else []:
                try:
                    r.validate_topic_name(topic)
                except r.rclpy.exceptions.NameValidationException as exc:
                    why = str(exc).splitlines()[0].split(": ", 1)[-1].rstrip(":")
                    raise InputError(f"parameter {key}: {topic!r} is not a topic name ({why})") from None
        self.inputs: dict[str, str] = {}  # topic -> the type expected
        if p["pose_topic"]:
            topic = p["pose_topic"]
            self._make_estimator(points.PointChoice((topic,), "named"))
            # Raw: the stamp, frame and position read from the bytes (no message object per frame).
            node.create_subscription(r.PoseStamped, topic, lambda m: self._on_pose(topic, m), qos_in, raw=True)
            self.inputs[topic] = _POSE
        elif p["point_topics"]:
            topics = p["point_topics"]
            if len(set(topics)) != len(topics):
                raise InputError(f"parameter point_topics: a topic given twice in {topics}")
            feet = p["foot_topics"]
            self._make_estimator(points.PointChoice(tuple(topics), "named"), feet)
            self.assembler = FrameAssembler(len(topics) + len(feet), p["assembly_window_s"], by_arrival=self.by_arrival)
            for k, topic in enumerate([*topics, *feet]):
                node.create_subscription(r.PointStamped, topic, self._point_callback(k, topic), qos_in)
                self.inputs[topic] = _POINT
            node.create_timer(min(0.01, p["assembly_window_s"]), self._expire)
        elif p["imu_topic"]:
            topic = p["imu_topic"]
            node.create_subscription(r.Imu, topic, lambda m: self._on_imu(topic, m), qos_in)
            self.inputs[topic] = _IMU
            self._imu_samples: list[tuple[float, tuple, tuple]] | None = []
        else:
            topic = p["markers_topic"]
            node.create_subscription(markers_type(), topic, lambda m: self._on_markers(topic, m), qos_in)
            self.inputs[topic] = _MARKERS
            self._marker_index: np.ndarray | None = None
        twist = r.TwistWithCovarianceStamped
        self.pub_walking = node.create_publisher(twist, "~/walking_velocity", qos_out)
        self.pub_velocity = node.create_publisher(twist, "~/velocity", qos_out)
        # IMU input has no prediction (ImuOnlineEstimator): no predicted velocity topic.
        self.pub_predicted = (
            None if self.imu is not None else node.create_publisher(twist, "~/predicted_velocity", qos_out)
        )
        self.pub_state = node.create_publisher(r.Float64MultiArray, "~/gait_state", qos_out)
        self.pub_diagnostics = node.create_publisher(r.DiagnosticArray, "/diagnostics", 10)
        # The per-frame messages as bytes from templates (messages.py: a message object costs far more).
        self._twist_bytes = messages.StampedTwistBytes(twist, r.serialize)
        state = r.Float64MultiArray()
        labels = messages.IMU_GAIT_STATE_LABELS if self.imu is not None else messages.GAIT_STATE_LABELS
        state.layout.dim = [r.MultiArrayDimension(label=label, size=1, stride=1) for label in labels]
        self._state_bytes = messages.GaitStateBytes(state, r.serialize)
        self._frame_bytes, self._frame_str = b"", ""
        # The node's clock in ns: the system clock as it is, unless use_sim_time (then the ROS clock).
        clock = node.get_clock()
        self._now_ns = (lambda: clock.now().nanoseconds) if node.get_parameter("use_sim_time").value else time.time_ns
        self._diag_last = (time.monotonic(), 0, 0)
        node.create_timer(p["diagnostics_period_s"], self._diagnostics)

    def _imu_config(self) -> ImuConfig:
        """The IMU estimator's settings: the configuration file's (its [imu] table), the forward axis and
        the sensor height of the parameters."""
        p = self.params
        config = ImuConfig.from_file(Path(p["config_file"])) if p["config_file"] else ImuConfig()
        axis = p["forward_axis"]
        changes: dict[str, Any] = {"forward_axis": AXES.index(axis[-1]), "forward_negative": axis.startswith("-")}
        if p["sensor_height_m"] > 0:
            changes["sensor_height_m"] = p["sensor_height_m"]
        config = dataclasses.replace(config, **changes)
        config.to_native()  # InputError naming the setting out of range
        return config

    def _make_estimator(self, choice: points.PointChoice, feet=()) -> None:
        """The estimator of the points followed, and the feet after them in each frame (docs/online.md, "Feet")."""
        p = self.params
        self.point_names = tuple(choice.names)
        self.foot_names = tuple(feet)
        config = config_for_point(choice, self.config)  # a hand must travel to walk
        self.estimator = OnlineEstimator(list(choice.names), p["up_axis"], p["length_unit_m"], config, feet=list(feet))

    @staticmethod
    def _check_feet(p: dict) -> None:
        """foot_topics goes with point_topics, foot_names with markers_topic: two distinct names each, not
        among the points followed."""
        for key, partner in (("foot_topics", "point_topics"), ("foot_names", "markers_topic")):
            feet = p[key]
            if not feet:
                continue
            if not p[partner]:
                raise InputError(f"parameter {key}: goes with {partner}")
            if len(feet) != 2 or len(set(feet)) != 2:
                raise InputError(f"parameter {key}: two distinct names, one per foot, not {feet}")
            followed = set(p[partner]) if key == "foot_topics" else set(p["marker_names"])
            if followed & set(feet):
                raise InputError(f"parameter {key}: {sorted(followed & set(feet))} also followed")

    def say(self, topic: str, kind: str, text: str, error: bool = False) -> None:
        """One line naming the topic, once per topic and kind."""
        if (topic, kind) in self._said:
            return
        self._said.add((topic, kind))
        log = self.node.get_logger()
        if error:  # rclpy wants one severity per call site
            log.error(f"topic {topic}: {text}")
        else:
            log.warning(f"topic {topic}: {text}")

    # ----------------------------------------------------------------------------------------- inputs
    def _time_of(self, topic: str, sec: int, nanosec: int, frame_id: str) -> float | None:
        """The frame time [s] of a message stamped (sec, nanosec), or None (counted, said) when its stamp is
        unusable."""
        now_s = self._now_ns() * 1e-9
        self._last_message[topic] = time.monotonic()
        if not self._frame_id:
            self._frame_id = frame_id
        if self.by_arrival:
            return now_s
        if sec == 0 and nanosec == 0:
            self.counts.zero_stamps += 1
            self.say(topic, "zero", "header.stamp is 0 (the driver does not stamp?): dropped; set time_source:=arrival")
            return None
        t_s = sec + nanosec * 1e-9
        if t_s > now_s + self.params["max_future_s"]:
            self.counts.future_stamps += 1
            self.say(
                topic,
                "future",
                f"header.stamp {t_s:.6f} s is {t_s - now_s:.3g} s ahead of this node's clock "
                f"(max_future_s {self.params['max_future_s']:g}): dropped; are the clocks synchronised?",
            )
            return None
        self.counts.latency_s.append(now_s - t_s)
        return t_s

    def _stamp(self, t_s: float, sec: int, nanosec: int, frame_id: str) -> tuple[int, int, str]:
        """The outputs' stamp and frame: the input's, or its arrival time (time_source arrival)."""
        if not self.by_arrival:
            return sec, nanosec, frame_id
        ns = round(t_s * 1e9)
        return ns // 1_000_000_000, ns % 1_000_000_000, frame_id

    def _finite(self, topic: str, xyz: np.ndarray) -> None:
        if not np.isfinite(xyz).all():
            self._non_finite(topic)

    def _non_finite(self, topic: str) -> None:
        self.counts.non_finite += 1
        self.say(topic, "nan", "a message with NaN or inf coordinates: estimated with that point missing")

    def _on_pose(self, topic: str, raw: bytes) -> None:
        pose = messages.pose_of(raw)
        if pose is None:  # not little-endian CDR: through rclpy
            msg = self._r.deserialize(raw, self._r.PoseStamped)
            h, q = msg.header, msg.pose.position
            sec, nanosec, frame, x, y, z = h.stamp.sec, h.stamp.nanosec, h.frame_id, q.x, q.y, q.z
        else:
            sec, nanosec, frame_bytes, x, y, z = pose
            if frame_bytes != self._frame_bytes:
                self._frame_bytes, self._frame_str = frame_bytes, frame_bytes.decode("utf-8", "replace")
            frame = self._frame_str
        t_s = self._time_of(topic, sec, nanosec, frame)
        if t_s is None:
            return
        if not (math.isfinite(x) and math.isfinite(y) and math.isfinite(z)):
            self._non_finite(topic)
        self.process(topic, t_s, self._stamp(t_s, sec, nanosec, frame), (x, y, z))

    def _point_callback(self, index: int, topic: str) -> Callable[[Any], None]:
        def on_point(msg: Any) -> None:
            h = msg.header
            t_s = self._time_of(topic, h.stamp.sec, h.stamp.nanosec, h.frame_id)
            if t_s is None:
                return
            assert self.assembler is not None
            key = (msg.header.stamp.sec, msg.header.stamp.nanosec)
            q = msg.point
            xyz = np.array([q.x, q.y, q.z])
            self._finite(topic, xyz)
            for frame in self.assembler.add(index, key, t_s, xyz, time.monotonic()):
                self._assembled(topic, frame)

        return on_point

    def _expire(self) -> None:
        assert self.assembler is not None
        for frame in self.assembler.expire(time.monotonic()):
            self._assembled("point_topics", frame)

    def _assembled(self, topic: str, frame: Any) -> None:
        sec, nanosec = (0, 0) if self.by_arrival else frame.key
        self.process(topic, frame.t_s, self._stamp(frame.t_s, sec, nanosec, self._frame_id), frame.positions)

    def _on_markers(self, topic: str, msg: Any) -> None:
        h = msg.header
        t_s = self._time_of(topic, h.stamp.sec, h.stamp.nanosec, h.frame_id)
        if t_s is None:
            return
        names = [m.marker_name or str(m.marker_index) for m in msg.markers]
        if self.estimator is None:
            try:
                wanted = self.params["marker_names"] or None
                stand_in = Recording(np.empty((0, len(names), 3)), names, np.empty(0), source=f"topic {topic}")
                choice = points.choose_point(stand_in, wanted)
            except InputError as exc:
                self.say(topic, "names", f"{exc}; set marker_names", error=True)
                return
            self._make_estimator(choice, self.params["foot_names"])
        index = {n: k for k, n in enumerate(names)}
        wanted = (*self.point_names, *self.foot_names)
        positions = np.full((len(wanted), 3), np.nan)
        for k, name in enumerate(wanted):
            j = index.get(name)
            if j is not None:
                q = msg.markers[j].translation
                positions[k] = (q.x, q.y, q.z)
        self._finite(topic, positions)
        self.process(topic, t_s, self._stamp(t_s, h.stamp.sec, h.stamp.nanosec, h.frame_id), positions)

    def _on_imu(self, topic: str, msg: Any) -> None:
        """One IMU sample: specific force (m/s^2, gravity included) and angular rate (rad/s), REP 145."""
        h = msg.header
        t_s = self._time_of(topic, h.stamp.sec, h.stamp.nanosec, h.frame_id)
        if t_s is None:
            return
        a, w = msg.linear_acceleration, msg.angular_velocity
        acc, gyr = (a.x, a.y, a.z), (w.x, w.y, w.z)
        if not all(math.isfinite(v) for v in (*acc, *gyr)):
            self.counts.non_finite += 1
            self.say(topic, "nan", "a sample with NaN or inf: ignored by the estimator (its reason NON_FINITE)")
        assert self.imu is not None
        verdict = self.gate.admit(t_s, time.monotonic())
        if verdict == DROP:
            return
        if verdict == RESTART:
            self.imu.reset()
        est = self.imu.update(t_s, acc, gyr)
        self.last_estimate = est
        sec, nanosec, frame = self._stamp(t_s, h.stamp.sec, h.stamp.nanosec, h.frame_id)
        # The horizontal frame of the IMU estimator: x the forward direction at the start, z up.
        heading, twist, cov = est.heading_rad, self._twist_bytes, messages.velocity_covariance
        c, s = (math.cos(heading), math.sin(heading)) if math.isfinite(heading) else (math.nan, math.nan)
        speed, vx = est.speed_mps, est.vx_mps
        # Not valid: published all the same, with the covariance of what is not observed (a consumer
        # that weighs by covariance then gives it no weight; one that reads valid, in gait_state, skips it).
        std = est.speed_std_mps if est.valid else math.inf
        self.pub_walking.publish(twist(sec, nanosec, frame, (speed * c, speed * s, 0.0), cov(_IMU_AXES, heading, std)))
        self.pub_velocity.publish(
            twist(sec, nanosec, frame, (vx * c, vx * s, est.vz_mps), cov(_IMU_AXES, heading, math.inf))
        )
        self.pub_state.publish(self._state_bytes(messages.imu_gait_state_row(est)))
        if self._imu_samples is not None:
            self._check_imu_plausible(topic, t_s, acc, gyr)

    def _check_imu_plausible(self, topic: str, t_s: float, acc: tuple, gyr: tuple) -> None:
        assert self._imu_samples is not None
        self._imu_samples.append((t_s, acc, gyr))
        if t_s - self._imu_samples[0][0] < self.params["plausibility_s"]:
            return
        t, a, g = (np.array(column, dtype=float) for column in zip(*self._imu_samples))
        self._imu_samples = None
        try:
            check_imu_plausible(ImuRecording(t, a, g, source=f"topic {topic}"))
        except InputError as exc:
            text = str(exc).replace(f"topic {topic}: ", "")
            text += " (sensor_msgs/Imu is in m/s^2 and rad/s, REP 145: convert in the driver)"
            self.implausible = text
            self.say(topic, "plausibility", text, error=True)

    # ----------------------------------------------------------------------------------------- a frame
    def process(self, topic: str, t_s: float, stamp: tuple[int, int, str], positions) -> Any:
        """One frame through the gate and the estimator; the outputs published, stamped ``stamp`` (sec,
        nanosec, frame id). ``positions``: k x 3, or one point's (x, y, z). Returns the estimate."""
        assert self.estimator is not None
        verdict = self.gate.admit(t_s, time.monotonic())
        if verdict == DROP:
            return None
        if verdict == RESTART:
            self.estimator.reset()
        if type(positions) is tuple:
            est = self.estimator.update_point(t_s, *positions)
        else:
            est = self.estimator.update(t_s, positions)
        self.last_estimate = est
        self._publish(stamp, est)
        if self._plausibility is not None:
            self._check_plausible(topic, t_s, np.reshape(positions, (-1, 3))[: len(self.point_names)])
        return est

    def _publish(self, stamp: tuple[int, int, str], est: Any) -> None:
        """The outputs of a frame, the walking velocity first (what a controller waits for), each as bytes."""
        axes, v, cov, twist = self.axes, messages.velocity_vector, messages.velocity_covariance, self._twist_bytes
        sec, nanosec, frame = stamp
        heading = est.heading_rad
        # Not valid: the estimates published with the covariance of what is not observed (a consumer that
        # weighs by covariance gives them no weight; one that reads valid, in gait_state, skips them).
        valid = bool(est.valid)
        self.pub_walking.publish(
            twist(
                sec,
                nanosec,
                frame,
                v(axes, est.walk_a_mps, est.walk_b_mps, 0.0),
                cov(axes, heading, est.speed_std_mps if valid else math.inf),
            ),
        )
        self.pub_velocity.publish(
            twist(sec, nanosec, frame, v(axes, est.vh_a_mps, est.vh_b_mps, est.vz_mps), cov(axes, heading, math.inf))
        )
        assert self.estimator is not None and self.pub_predicted is not None
        horizon_s = self.params["predict_horizon_s"]
        prediction = self.estimator.predict(horizon_s)
        c, s = (math.cos(heading), math.sin(heading)) if math.isfinite(heading) else (math.nan, math.nan)
        vx = prediction.vx_mps
        stds = (prediction.vx_std_mps, prediction.vz_std_mps) if valid else (math.inf, math.inf)
        self.pub_predicted.publish(
            twist(
                sec,
                nanosec,
                frame,
                v(axes, vx * c, vx * s, prediction.vz_mps),
                cov(axes, heading, *stds),
            )
        )
        gait = self.estimator.estimate
        self.pub_state.publish(
            self._state_bytes(messages.gait_state_row(est, (gait.R_m, gait.r_m), horizon_s, prediction))
        )

    def _check_plausible(self, topic: str, t_s: float, positions: np.ndarray) -> None:
        assert self._plausibility is not None
        self._plausibility.append((t_s, positions * self.params["length_unit_m"]))
        if t_s - self._plausibility[0][0] < self.params["plausibility_s"]:
            return
        times = np.array([t for t, _ in self._plausibility])
        frames = np.stack([f for _, f in self._plausibility])
        self._plausibility = None
        where = topic if topic in self.inputs else ", ".join(self.inputs)
        rec = Recording(frames, list(self.point_names), times, up_axis=self.params["up_axis"], source=f"topic {where}")
        rec.metadata["length_unit_m"] = self.params["length_unit_m"]
        rec.metadata["up_axis_from"] = "parameter"
        try:
            check_plausible(rec)
        except InputError as exc:
            text = str(exc).replace("--length-unit-m ", "length_unit_m:=").replace("--up-axis ", "up_axis:=")
            text = (
                text.replace("pass --capture-rate-hz", "check the stamps")
                .replace("--capture-rate-hz", "the stamps")
                .replace(f"topic {where}: ", "")
            )
            self.implausible = text
            self.say(where, "plausibility", text, error=True)

    # ----------------------------------------------------------------------------------------- health
    def _diagnostics(self) -> None:
        r, c = self._r, self.counts
        now = time.monotonic()
        self._check_topics(now)
        then, frames0, estimates0 = self._diag_last
        period = max(1e-9, now - then)
        input_rate, estimate_rate = (c.frames - frames0) / period, (c.estimates - estimates0) / period
        self._diag_last = (now, c.frames, c.estimates)
        latencies = list(c.latency_s)
        c.latency_s.clear()
        est = self.last_estimate
        walking = bool(est is not None and est.walking)
        why = _why_not_valid(est)
        status = r.DiagnosticStatus()
        status.name = f"{self.node.get_name()}: gait estimator"
        status.hardware_id = ", ".join(self.inputs)
        if self.implausible:
            status.level, status.message = r.DiagnosticStatus.ERROR, f"implausible input: {self.implausible}"
        elif est is None or estimate_rate == 0:
            status.level, status.message = r.DiagnosticStatus.WARN, "no input frames"
        else:
            status.level = r.DiagnosticStatus.OK
            status.message = (
                f"walking {est.step_frequency_hz:.2f} Hz, {est.speed_mps:.2f} m/s" if walking else "not walking"
            )
            if why:  # what a controller gating on valid sees: the estimate held back, and why
                status.message += f"; not valid: {why}"
        values = {
            "input_rate_hz": f"{input_rate:.1f}",
            "estimate_rate_hz": f"{estimate_rate:.1f}",
            "latency_median_ms": f"{1e3 * statistics.median(latencies):.3f}" if latencies else "nan",
            "latency_max_ms": f"{1e3 * max(latencies):.3f}" if latencies else "nan",
            "walking": str(walking).lower(),
            "valid": str(bool(est is not None and est.valid)).lower(),
            "not_valid_because": why,
            # OnlineStatus of marker input; ImuReason (why not valid) of IMU input
            "status": str(int(getattr(est, "status", getattr(est, "reason", 0)))) if est is not None else "",
        }
        for name in FrameCounts.__dataclass_fields__:
            values[name] = str(getattr(c, name))
        for name in ("zero_stamps", "future_stamps", "non_finite"):
            values[name] = str(getattr(c, name))
        if self.assembler is not None:
            a = self.assembler
            values.update(
                late_points=str(a.late_points),
                repeated_points=str(a.repeated_points),
                incomplete_frames=str(a.incomplete_frames),
            )
        status.values = [r.KeyValue(key=k, value=v) for k, v in values.items()]
        msg = r.DiagnosticArray()
        msg.header.stamp = self.node.get_clock().now().to_msg()
        msg.status = [status]
        self.pub_diagnostics.publish(msg)

    def _check_topics(self, now: float) -> None:
        for topic, expected in self.inputs.items():
            publishers = self.node.get_publishers_info_by_topic(topic)
            carried = sorted({info.topic_type for info in publishers} - {expected})
            if carried and len(carried) == len({info.topic_type for info in publishers}):
                self.say(topic, "type", f"carries {', '.join(carried)}, expected {expected}: nothing is read", True)
            last = self._last_message.get(topic)
            silent_s = now - (last if last is not None else self._started)
            if last is None and silent_s > self.params["silent_warning_s"]:
                n = len(publishers)
                self.say(
                    topic,
                    "silent",
                    f"no message in {silent_s:.0f} s ({n} publisher{'s' if n != 1 else ''}; expected {expected})",
                )

    def destroy(self) -> None:
        """Deliver the last estimates (reliable: acknowledged, or 1 s) and destroy the node."""
        if self.assembler is not None:
            self.counts.late_points = self.assembler.late_points
            self.counts.repeated_points = self.assembler.repeated_points
            self.counts.incomplete_frames = self.assembler.incomplete_frames
        for pub in (self.pub_walking, self.pub_velocity, self.pub_predicted, self.pub_state):
            if pub is not None:
                pub.wait_for_all_acked(self._r.rclpy.duration.Duration(seconds=1.0))
        self.node.destroy_node()


def make_executor(context=None) -> Any:
    """rclpy's events executor (callbacks dispatched from C++: about a fifth of the CPU per message of the
    Python single-threaded executor) where this rclpy has it, else the single-threaded executor."""
    r = ros()
    events = getattr(r.experimental, "EventsExecutor", None)
    if events is not None:
        return events(context=context)
    return r.executors.SingleThreadedExecutor(context=context)


def run_node(
    parameters: dict[str, Any] | None = None,
    ros_args: Sequence[str] = (),
    *,
    stop: threading.Event | None = None,
    duration_s: float | None = None,
    on_start: Callable[[GaitNode], None] | None = None,
) -> NodeCounts:
    """Run the node until ``stop``, ``duration_s`` or the context's shutdown; its counts.

    ``ros_args``: the command line's ROS arguments (``--ros-args -p name:=value -r from:=to ...``).
    rclpy's own signal handlers are not installed: the caller decides what a signal does (``stop``).
    """
    r = ros()
    args = ["yoyogait", *ros_args]
    try:
        r.rclpy.init(args=args, signal_handler_options=r.signals.SignalHandlerOptions.NO)
    except Exception as exc:  # malformed --ros-args, a middleware that does not start
        raise YoyogaitError(f"ROS 2 arguments {' '.join(ros_args)!r}: {' '.join(str(exc).split())}") from None
    try:
        try:
            gait = GaitNode(parameters)
        except r.rclpy.exceptions.InvalidParameterTypeException as exc:
            raise InputError(f"parameter {exc.args[-1] if exc.args else ''}: {' '.join(str(exc).split())}") from None
        executor = make_executor()
        executor.add_node(gait.node)
        # What the imports and the set-up made lives as long as the node: out of the cyclic collector's
        # way, so that a full collection (which would walk every object of numpy, scipy and rclpy) does not
        # hold up a frame.
        gc.collect()
        gc.freeze()
        if on_start is not None:
            on_start(gait)
        started = time.monotonic()
        try:
            while r.rclpy.ok():
                if stop is not None and stop.is_set():
                    break
                if duration_s is not None and time.monotonic() - started >= duration_s:
                    break
                executor.spin_once(timeout_sec=0.1)
        finally:
            executor.remove_node(gait.node)
            gait.destroy()
            # Back to the collector, so that what the node held is released before the interpreter
            # ends (frozen objects never are: nanobind would report them as leaked at exit).
            gc.unfreeze()
        return gait.counts
    finally:
        if r.rclpy.ok():
            r.rclpy.shutdown()


def main(argv: Sequence[str] | None = None) -> int:
    """``python -m yoyogait.ros2 [--ros-args ...]``: the node until SIGINT/SIGTERM (exit 130/143)."""
    argv = list(sys.argv[1:] if argv is None else argv)
    stop = threading.Event()
    received: list[int] = []

    def on_signal(signum, frame):
        received.append(signum)
        stop.set()

    previous = {s: signal.signal(s, on_signal) for s in _guard.SIGNALS}
    code = 0
    try:
        counts = run_node(None, argv, stop=stop, on_start=lambda gait: print(startup_line(gait), file=sys.stderr))
        print(summary_line(counts), file=sys.stderr)
    except (YoyogaitError, ValueError, OSError) as exc:
        print(f"yoyogait ros2: error: {' '.join(str(exc).split())}", file=sys.stderr)
        code = 2
    finally:
        for s, h in previous.items():
            signal.signal(s, h)
    if received:
        print(f"yoyogait ros2: interrupted ({signal.Signals(received[0]).name})", file=sys.stderr)
        return 128 + received[0]
    return code


def startup_line(gait: GaitNode) -> str:
    """What the node reads and publishes, on one line (printed when it starts)."""
    p = gait.params
    inputs = ", ".join(f"{topic} ({kind.rsplit('/', 1)[-1]})" for topic, kind in gait.inputs.items())
    base = gait.node.get_fully_qualified_name()
    if gait.imu is not None:
        return (
            f"ros2: node {base} reading {inputs}, {p['time_source']} time, {p['qos']} QoS, forward "
            f"{p['forward_axis']}; publishing {base}/walking_velocity, {base}/velocity, {base}/gait_state, /diagnostics"
        )
    return (
        f"ros2: node {base} reading {inputs}, {p['time_source']} time, {p['qos']} QoS, up {p['up_axis']}, "
        f"{p['length_unit_m']:g} m per unit; publishing {base}/walking_velocity, {base}/velocity, "
        f"{base}/predicted_velocity ({p['predict_horizon_s']:g} s ahead), {base}/gait_state, /diagnostics"
    )


def summary_line(c: NodeCounts) -> str:
    """The run's counts on one line (what ``yoyogait ros2`` prints at its end)."""
    line = (
        f"ros2: {c.frames} frames, {c.estimates} estimates; dropped (time not increasing) "
        f"{c.dropped_not_increasing}, dropped (time jumped) {c.dropped_jumps}, stamped 0 {c.zero_stamps}, "
        f"from the future {c.future_stamps}, with NaN {c.non_finite}, restarts {c.restarts}"
    )
    if c.late_points or c.repeated_points or c.incomplete_frames:
        line += f"; points late {c.late_points}, repeated {c.repeated_points}, frames incomplete {c.incomplete_frames}"
    return line
