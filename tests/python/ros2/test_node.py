"""The ROS 2 node on loopback: a real walk replayed as PoseStamped and PointStamped, every estimate received
in order, stamped, identical to OnlineEstimator.run; bad input said in one line; the CLI's exits."""

from __future__ import annotations

import os
import signal
import subprocess
import sys
import threading
import time
import warnings

import numpy as np
import pytest
from ros2_helpers import Loopback, require_ros

from yoyogait import io
from yoyogait.estimators.online import ONLINE_ESTIMATE_COLUMNS, InvalidReason, OnlineEstimator
from yoyogait.pipeline import points
from yoyogait.ros2.messages import GAIT_STATE_LABELS

rclpy = require_ros()
from geometry_msgs.msg import PointStamped, PoseStamped, TwistWithCovarianceStamped  # noqa: E402
from std_msgs.msg import Float64MultiArray  # noqa: E402

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__)))))
WALK = "c3d_org_samples/sample26_Qualisys_Walking_Hybrid_1_1.c3d"
HORIZON_S = 0.2


@pytest.fixture(scope="module")
def walk(datasets_dir):
    """The real Qualisys walk (240 Hz, 2.8 s): its pelvis markers, up axis and integer stamps 100 s ago."""
    rec = io.read(datasets_dir / WALK)
    names = list(points.choose_point(rec, None).names)
    up, _ = points.resolve_up_axis(rec, None)
    markers = rec.points(names)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", RuntimeWarning)  # frames where every pelvis marker is lost: NaN
        centre = np.nanmean(markers, axis=1)
    base_ns = time.time_ns() - 100 * 10**9
    stamps_ns = base_ns + np.round(rec.time_s * 1e9).astype(np.int64)
    t_s = np.array([(ns // 10**9) + (ns % 10**9) * 1e-9 for ns in stamps_ns.tolist()])  # as the node reads them
    return {"names": names, "up": up, "markers": markers, "centre": centre, "stamps_ns": stamps_ns.tolist(), "t_s": t_s}


def _stamp(msg, ns: int, frame_id: str = "mocap"):
    msg.header.stamp.sec, msg.header.stamp.nanosec = ns // 10**9, ns % 10**9
    msg.header.frame_id = frame_id
    return msg


def _outputs(loop: Loopback):
    base = loop.gait.node.get_fully_qualified_name()
    return {
        "walking": loop.collect(TwistWithCovarianceStamped, f"{base}/walking_velocity"),
        "velocity": loop.collect(TwistWithCovarianceStamped, f"{base}/velocity"),
        "predicted": loop.collect(TwistWithCovarianceStamped, f"{base}/predicted_velocity"),
        "state": loop.collect(Float64MultiArray, f"{base}/gait_state"),
    }


def _connected(loop: Loopback, publishers) -> bool:
    """Every input publisher matched by the node, every output matched by the test's subscriptions."""
    g = loop.gait
    outs = (g.pub_walking, g.pub_velocity, g.pub_predicted, g.pub_state)
    return all(p.get_subscription_count() > 0 for p in publishers) and all(p.get_subscription_count() > 0 for p in outs)


def _check_against_run(out, expected, stamps_ns):
    n = len(stamps_ns)
    for key, got in out.items():
        assert len(got) == n, f"{key}: {len(got)} of {n} estimates"
    got_ns = [m.header.stamp.sec * 10**9 + m.header.stamp.nanosec for m in out["walking"]]
    assert got_ns == list(stamps_ns)  # every frame, in order, stamped with its own stamp
    assert {m.header.frame_id for m in out["walking"] + out["velocity"] + out["predicted"]} == {"mocap"}
    labels = [d.label for d in out["state"][0].layout.dim]
    assert labels == list(GAIT_STATE_LABELS) and set(ONLINE_ESTIMATE_COLUMNS) <= set(labels)
    state = np.array([m.data for m in out["state"]])
    for j, column in enumerate(ONLINE_ESTIMATE_COLUMNS):
        np.testing.assert_array_equal(state[:, j], getattr(expected, column).astype(float), err_msg=column)
    np.testing.assert_array_equal(state[:, labels.index("pred_vx_mps")], expected.pred_vx_mps[:, 0])
    walking = np.array([[m.twist.twist.linear.x, m.twist.twist.linear.y] for m in out["walking"]])
    np.testing.assert_array_equal(walking[:, 0], expected.walk_a_mps)
    np.testing.assert_array_equal(walking[:, 1], expected.walk_b_mps)
    for key in ("walking", "velocity", "predicted"):
        for m in out[key]:
            c = np.array(m.twist.covariance).reshape(6, 6)
            assert np.array_equal(c, c.T), key
            assert np.linalg.eigvalsh(c).min() >= -1e-9 * np.abs(c).max(), key
    # The walking velocity's covariance: the speed's std along the heading while valid; while not valid
    # nothing is observed (a consumer weighing by covariance gives it no weight).
    linear = [np.array(m.twist.covariance).reshape(6, 6)[:3, :3] for m in out["walking"]]
    lowest = np.array([np.linalg.eigvalsh(c)[0] for c in linear])
    valid = expected.valid.astype(bool)
    np.testing.assert_allclose(lowest[valid], expected.speed_std_mps[valid] ** 2, rtol=1e-6)
    assert np.all(lowest[~valid] >= 0.99e6)


def _point_sender(pubs, markers, stamps_ns):
    """send(k): frame k's markers, one PointStamped per publisher, stamped stamps_ns[k]."""

    def send(k):
        for j, pub in enumerate(pubs):
            msg = _stamp(PointStamped(), stamps_ns[k])
            msg.point.x, msg.point.y, msg.point.z = (float(v) for v in markers[k, j])
            pub.publish(msg)

    return send


def _replay(loop, publish_frame, n, out, window=8):
    """Frames published as fast as the node takes them (at most ``window`` ahead of its estimates)."""
    for k in range(n):
        assert loop.wait(lambda k=k: len(out["state"]) >= k - window, 10), f"stalled at frame {k}"
        publish_frame(k)
    loop.wait(lambda: len(out["state"]) >= n, 10)
    time.sleep(0.2)  # nothing more arrives


def test_pose_stamped_replay_gives_every_estimate_in_order_stamped_equal_to_the_online_run(walk):
    """The pelvis centre of a real walk as PoseStamped: one estimate per frame, in order, with its stamp and frame,
    equal to OnlineEstimator.run of the same frames; covariances symmetric and PSD."""
    from diagnostic_msgs.msg import DiagnosticArray

    centre = walk["centre"]
    loop = Loopback(rclpy, {"pose_topic": "/test/pelvis/pose", "up_axis": walk["up"], "diagnostics_period_s": 0.2})
    try:
        out = _outputs(loop)  # the consumer, connected before the source starts
        health = loop.collect(DiagnosticArray, "/diagnostics")
        pub = loop.test.create_publisher(PoseStamped, "/test/pelvis/pose", loop.qos())
        assert loop.wait(lambda: _connected(loop, [pub]), 15), "no discovery on loopback"

        def send(k):
            msg = _stamp(PoseStamped(), walk["stamps_ns"][k])
            msg.pose.position.x, msg.pose.position.y, msg.pose.position.z = (float(v) for v in centre[k])
            pub.publish(msg)

        _replay(loop, send, len(centre), out)
    finally:
        loop.close()
    estimator = OnlineEstimator(["pelvis"], walk["up"], 1.0)
    expected = estimator.run(walk["t_s"], centre[:, None, :], predict_ahead_s=[HORIZON_S])
    _check_against_run(out, expected, walk["stamps_ns"])
    assert loop.gait.counts.estimates == len(centre) and loop.gait.counts.dropped_not_increasing == 0
    # /diagnostics says whether the last estimate was valid and why not, by name.
    said = [{kv.key: kv.value for kv in m.status[0].values} | {"": m.status[0].message} for m in health]
    said = [d for d in said if d.get("estimate_rate_hz", "0.0") != "0.0"]
    assert said and all(d["valid"] in ("true", "false") for d in said)
    for d in said:
        assert (d["valid"] == "false") == bool(d["not_valid_because"])
        assert ("not valid: " + d["not_valid_because"] in d[""]) if d["not_valid_because"] else "not valid" not in d[""]
    names = {r.name.lower().replace("_", " ") for r in InvalidReason}
    assert all(set(d["not_valid_because"].split(", ")) <= names for d in said if d["not_valid_because"])


def test_point_stamped_markers_assembled_by_stamp_give_the_online_run_of_the_pelvis_markers(walk):
    """The pelvis markers of a real walk, one PointStamped topic each (NaN where the camera lost one): one frame per
    stamp, estimated as OnlineEstimator.run of the k markers."""
    names, markers = walk["names"], walk["markers"]
    topics = [f"/test/markers/{n}" for n in names]
    loop = Loopback(rclpy, {"point_topics": topics, "up_axis": walk["up"], "assembly_window_s": 2.0})
    try:
        out = _outputs(loop)
        pubs = [loop.test.create_publisher(PointStamped, t, loop.qos()) for t in topics]
        assert loop.wait(lambda: _connected(loop, pubs), 15), "no discovery on loopback"
        _replay(loop, _point_sender(pubs, markers, walk["stamps_ns"]), markers.shape[0], out)
    finally:
        loop.close()
    expected = OnlineEstimator(names, walk["up"], 1.0).run(walk["t_s"], markers, predict_ahead_s=[HORIZON_S])
    _check_against_run(out, expected, walk["stamps_ns"])
    c = loop.gait.counts
    assert c.incomplete_frames == 0 and c.late_points == 0 and c.repeated_points == 0
    assert c.non_finite == int(np.isnan(markers).any(axis=2).sum())  # every lost marker counted


def test_foot_topics_go_into_the_frames_and_make_a_markerless_walk_valid():
    """A SYNTHETIC markerless walk (60 Hz, 2 cm jitter, swaps, dropouts; 10 s): its pelvis markers and heels as
    PointStamped topics, the heels as foot_topics: estimated as OnlineEstimator.run with feet=the heels, valid on
    part of the walk (never without the heels)."""
    from yoyogait import synthetic as sy
    from yoyogait import synthetic_conditions as sc

    rec = sc.render("markerless-60hz", sy.SUBJECTS[0]).recording
    n = int(np.searchsorted(rec.time_s, 10.0))
    pelvis, heels = ["LASI", "RASI", "LPSI", "RPSI"], list(sy.HEEL_MARKERS)
    markers = rec.points(pelvis + heels)[:n]
    stamps_ns = (time.time_ns() - 100 * 10**9 + np.round(rec.time_s[:n] * 1e9).astype(np.int64)).tolist()
    t_s = np.array([(ns // 10**9) + (ns % 10**9) * 1e-9 for ns in stamps_ns])
    topics = [f"/test/feet/{name}" for name in pelvis + heels]
    params = {"point_topics": topics[:4], "foot_topics": topics[4:], "up_axis": "z", "assembly_window_s": 2.0}
    loop = Loopback(rclpy, params)
    try:
        out = _outputs(loop)
        pubs = [loop.test.create_publisher(PointStamped, t, loop.qos()) for t in topics]
        assert loop.wait(lambda: _connected(loop, pubs), 15), "no discovery on loopback"
        _replay(loop, _point_sender(pubs, markers, stamps_ns), n, out)
    finally:
        loop.close()
    expected = OnlineEstimator(pelvis, "z", 1.0, feet=heels).run(t_s, markers, predict_ahead_s=[HORIZON_S])
    _check_against_run(out, expected, stamps_ns)
    without = OnlineEstimator(pelvis, "z", 1.0).run(t_s, markers[:, :4])
    assert expected.valid.mean() > 0.2 and not without.valid.any()


def test_bad_input_is_one_line_naming_the_topic_and_the_node_keeps_running(walk, capfd):
    """NaN, a zero stamp, a stamp from the future, a topic of another type, one that never publishes, and a
    length unit off by 1000: one line each naming the topic; the frames after them are still estimated."""
    from std_msgs.msg import String

    centre_mm = walk["centre"] * 1000.0  # millimetres, the node told metres
    pose, wrong, silent = "/test/bad/pose", "/test/bad/string", "/test/bad/silent"
    loop = Loopback(
        rclpy,
        {"point_topics": [silent], "silent_warning_s": 0.5, "diagnostics_period_s": 0.2},
        node_name="yoyogait_silent",
    )
    loop2 = None
    try:
        time.sleep(1.0)  # the silent topic's line comes from the ~1 Hz health check
        loop2 = Loopback(
            rclpy,
            {"pose_topic": pose, "plausibility_s": 1.0, "diagnostics_period_s": 0.2},
            node_name="yoyogait_bad",
        )
        out = _outputs(loop2)
        pub = loop2.test.create_publisher(PoseStamped, pose, loop2.qos())
        bogus = loop2.test.create_publisher(String, wrong, loop2.qos())
        loop2.gait.inputs[wrong] = "geometry_msgs/msg/PoseStamped"  # as if the node had been told to read it
        assert loop2.wait(lambda: _connected(loop2, [pub]), 15)
        bogus.publish(String(data="not a pose"))
        now_ns = time.time_ns()

        def send(k, ns=None, xyz=None):
            msg = _stamp(PoseStamped(), walk["stamps_ns"][k] if ns is None else ns)
            msg.pose.position.x, msg.pose.position.y, msg.pose.position.z = (
                float(v) for v in (centre_mm[k] if xyz is None else xyz)
            )
            pub.publish(msg)

        send(0, ns=0)  # stamp zero
        send(0, ns=now_ns + 60 * 10**9)  # a minute ahead
        send(0, xyz=(float("nan"),) * 3)
        _replay(loop2, lambda k: send(k + 1), len(centre_mm) - 1, out)
        time.sleep(0.5)
    finally:
        if loop2 is not None:
            loop2.close()
        loop.close()
    err = capfd.readouterr().err
    for needle in (
        f"topic {pose}: header.stamp is 0",
        "ahead of this node's clock (max_future_s 0.5): dropped",
        f"topic {pose}: a message with NaN",
        f"topic {wrong}: carries std_msgs/msg/String, expected geometry_msgs/msg/PoseStamped",
        f"topic {silent}: no message in",
        f"topic {pose}: faster than a person",
    ):
        lines = [line for line in err.splitlines() if needle in line]
        assert len(lines) == 1, (needle, err[-3000:])
    assert "length_unit_m:=0.001" in err
    assert "or if the rate is wrong check the stamps" in err and "--capture-rate-hz" not in err  # no CLI options
    c = loop2.gait.counts
    lost = int(np.isnan(centre_mm[1:]).any(axis=1).sum())  # frames of the file where every pelvis marker is lost
    assert c.zero_stamps == 1 and c.future_stamps == 1 and c.non_finite == 1 + lost
    assert len(out["state"]) == len(centre_mm)  # the NaN frame and every later one estimated
    assert "Traceback" not in err


def _node_cli(*args):
    # The yoyogait this interpreter imports (the installed package, or what PYTHONPATH names).
    return subprocess.Popen([sys.executable, *args], stderr=subprocess.PIPE, stdout=subprocess.DEVNULL, text=True)


@pytest.mark.parametrize(
    "argv, signum",
    [
        (["-m", "yoyogait.ros2", "--ros-args", "-p", "pose_topic:=/test/cli/pose", "-p", "up_axis:=z"], signal.SIGINT),
        (["-m", "yoyogait", "ros2", "--pose-topic", "/test/cli/pose"], signal.SIGTERM),
    ],
)
def test_node_from_the_command_line_says_its_topics_and_stops_at_a_signal_with_128_plus_it(argv, signum):
    """python -m yoyogait.ros2 --ros-args -p ... and yoyogait ros2: SIGINT/SIGTERM end them at once, exit 130/143,
    the summary line; nothing on stderr but those lines."""
    proc = _node_cli(*argv)
    lines: list[str] = []
    reader = threading.Thread(target=lambda: lines.extend(iter(proc.stderr.readline, "")), daemon=True)
    reader.start()
    try:
        deadline = time.monotonic() + 30
        while not any("ros2: node" in x for x in lines) and time.monotonic() < deadline and proc.poll() is None:
            time.sleep(0.05)
        assert any("ros2: node /yoyogait reading /test/cli/pose (PoseStamped)" in x for x in lines), lines
        time.sleep(0.3)
        stopped = time.monotonic()
        proc.send_signal(signum)
        code = proc.wait(10)
        took_s = time.monotonic() - stopped
    finally:
        if proc.poll() is None:
            proc.kill()
    reader.join(5)
    err = "".join(lines)
    assert code == 128 + signum, err
    assert took_s < 2.0
    assert "ros2: 0 frames, 0 estimates" in err
    assert "Warning" not in err and "Traceback" not in err, err
    # Nothing else: no warning of the bindings at exit either (nanobind's leak report, say).
    assert all(x.startswith("ros2: ") or "interrupted (SIG" in x for x in lines), err


@pytest.mark.parametrize(
    "argv, message",
    [
        (["ros2", "--ros-args", "-p", "up_axis:=w"], "parameter up_axis: one of x, y, z, not 'w'"),
        (
            ["ros2", "--ros-args", "-p", "pose_topic:=/a", "-p", "length_unit_m:=abc"],
            "parameter length_unit_m: a number",
        ),
        (["ros2"], "give one input: pose_topic (PoseStamped), point_topics"),
        (["ros2", "--pose-topic", "bad topic"], "parameter pose_topic: 'bad topic' is not a topic name"),
        (["ros2", "--markers-topic", "/markers"], "mocap4r2_msgs is not importable"),
        (
            ["ros2", "--pose-topic", "/p", "--foot-topic", "/l", "--foot-topic", "/r"],
            "foot_topics: goes with point_topics",
        ),
        (["ros2", "--point-topic", "/a", "--foot-topic", "/l"], "foot_topics: two distinct names, one per foot"),
        (
            ["ros2", "--point-topic", "/a", "--foot-topic", "/a", "--foot-topic", "/r"],
            "foot_topics: ['/a'] also followed",
        ),
        (
            ["ros2", "--ros-args", "-p", "imu_topic:=/imu", "-p", "forward_axis:=w"],
            "parameter forward_axis: one of x, y, z, -x, -y, -z, not 'w'",
        ),
        (["ros2", "--imu-topic", "/imu", "--sensor-height-m", "5"], "sensor_height_m = 5.0 is outside its valid range"),
        (["ros2", "--imu-topic", "/imu", "--pose-topic", "/p"], "got pose_topic, imu_topic"),
    ],
)
def test_bad_parameters_exit_2_with_one_line_naming_them(argv, message, capsys):
    """A wrong parameter, no input or two, a malformed topic, Markers without mocap4r2_msgs, an IMU setting out of
    range: one line, exit 2."""
    from yoyogait.cli import main

    if "--markers-topic" in argv:
        pytest.importorskip("rclpy")
        try:
            import mocap4r2_msgs  # noqa: F401

            pytest.skip("mocap4r2_msgs is importable here")
        except ImportError:
            pass
    assert main(argv) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and message in err, err
