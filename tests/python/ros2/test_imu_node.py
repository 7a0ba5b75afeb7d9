"""The ROS 2 node on IMU input: a real lower-back IMU recording replayed as sensor_msgs/Imu, every estimate received
in order, stamped, identical to ImuOnlineEstimator.run of the same samples; a wrong unit said in one line."""

from __future__ import annotations

import dataclasses
import time

import numpy as np
import pytest
from ros2_helpers import Loopback, require_ros

from yoyogait import ImuConfig, ImuOnlineEstimator
from yoyogait.io.imu_read import read_imu
from yoyogait.ros2.messages import IMU_GAIT_STATE_LABELS

rclpy = require_ros()
from geometry_msgs.msg import TwistWithCovarianceStamped  # noqa: E402
from sensor_msgs.msg import Imu  # noqa: E402
from std_msgs.msg import Float64MultiArray  # noqa: E402

TRIAL = "imu_mobgap/example_data/data_csv/HA/001/TimeMeasure1_Test5_Trial1.csv"
# Mobilise-D's lower-back frame (x up, y right, z forward) to REP 103's body frame (x forward, y left, z up):
# a rotation that only permutes and negates, so that the replayed samples are the file's values exactly.
TO_REP103 = np.array([[0.0, 0.0, 1.0], [0.0, -1.0, 0.0], [1.0, 0.0, 0.0]])


@pytest.fixture(scope="module")
def imu_walk(datasets_dir):
    """The real trial (100 Hz, about 12 s) in REP 103 axes, stamped 100 s ago in integer nanoseconds."""
    rec = read_imu(datasets_dir / TRIAL)
    acc, gyr = rec.acc_mps2 @ TO_REP103.T, rec.gyr_rad_s @ TO_REP103.T
    base_ns = time.time_ns() - 100 * 10**9
    stamps_ns = (base_ns + np.round(rec.time_s * 1e9).astype(np.int64)).tolist()
    t_s = np.array([(ns // 10**9) + (ns % 10**9) * 1e-9 for ns in stamps_ns])  # as the node reads them
    return {"acc": acc, "gyr": gyr, "stamps_ns": stamps_ns, "t_s": t_s, "height_m": rec.sensor_height_m}


def _message(ns: int, acc, gyr, frame_id: str = "imu_link") -> Imu:
    msg = Imu()
    msg.header.stamp.sec, msg.header.stamp.nanosec, msg.header.frame_id = ns // 10**9, ns % 10**9, frame_id
    msg.linear_acceleration.x, msg.linear_acceleration.y, msg.linear_acceleration.z = (float(v) for v in acc)
    msg.angular_velocity.x, msg.angular_velocity.y, msg.angular_velocity.z = (float(v) for v in gyr)
    return msg


def _run_node(parameters, samples, node_name="yoyogait_imu"):
    """The node fed ``samples`` (stamp ns, acc, gyr) at most 8 ahead of its estimates; its outputs and counts."""
    loop = Loopback(rclpy, parameters, node_name=node_name)
    try:
        base = loop.gait.node.get_fully_qualified_name()
        out = {
            "walking": loop.collect(TwistWithCovarianceStamped, f"{base}/walking_velocity"),
            "velocity": loop.collect(TwistWithCovarianceStamped, f"{base}/velocity"),
            "state": loop.collect(Float64MultiArray, f"{base}/gait_state"),
        }
        pub = loop.test.create_publisher(Imu, parameters["imu_topic"], loop.qos())
        g = loop.gait
        outputs = (g.pub_walking, g.pub_velocity, g.pub_state)
        assert loop.wait(
            lambda: pub.get_subscription_count() > 0 and all(p.get_subscription_count() > 0 for p in outputs), 15
        ), "no discovery on loopback"
        assert g.pub_predicted is None  # the IMU estimator predicts nothing: no topic
        for k, (ns, acc, gyr) in enumerate(samples):
            assert loop.wait(lambda k=k: len(out["state"]) >= k - 8, 10), f"stalled at sample {k}"
            pub.publish(_message(ns, acc, gyr))
        loop.wait(lambda: len(out["state"]) >= len(samples), 10)
        time.sleep(0.2)  # nothing more arrives
    finally:
        loop.close()
    return out, loop.gait.counts


def test_imu_replay_gives_every_estimate_in_order_stamped_equal_to_the_offline_run(imu_walk):
    """A real lower-back IMU trial as sensor_msgs/Imu: one estimate per sample, in order, with its stamp and frame,
    every gait-state field equal to ImuOnlineEstimator.run of the same samples; covariances symmetric and PSD."""
    w = imu_walk
    params = {"imu_topic": "/test/imu/data", "forward_axis": "x"}
    if w["height_m"] is not None:
        params["sensor_height_m"] = float(w["height_m"])
    out, counts = _run_node(params, list(zip(w["stamps_ns"], w["acc"], w["gyr"])))
    config = ImuConfig(forward_axis=0)
    if w["height_m"] is not None:
        config = dataclasses.replace(config, sensor_height_m=float(w["height_m"]))
    expected = ImuOnlineEstimator(config).run(w["t_s"], w["acc"], w["gyr"])
    n = len(w["stamps_ns"])
    for key, got in out.items():
        assert len(got) == n, f"{key}: {len(got)} of {n} estimates"
    for key in ("walking", "velocity"):
        assert [m.header.stamp.sec * 10**9 + m.header.stamp.nanosec for m in out[key]] == w["stamps_ns"], key
        assert {m.header.frame_id for m in out[key]} == {"imu_link"}
    labels = [d.label for d in out["state"][0].layout.dim]
    assert labels == list(IMU_GAIT_STATE_LABELS)
    state = np.array([m.data for m in out["state"]])
    for j, column in enumerate(labels):
        np.testing.assert_array_equal(state[:, j], np.asarray(expected[column], dtype=float), err_msg=column)
    assert expected["valid"].any()  # the trial is walked: the comparison covers valid estimates too
    speed, heading = expected["speed_mps"], expected["heading_rad"]
    walking = np.array([[m.twist.twist.linear.x, m.twist.twist.linear.y] for m in out["walking"]])
    np.testing.assert_array_equal(walking[:, 0], speed * np.cos(heading))
    np.testing.assert_array_equal(walking[:, 1], speed * np.sin(heading))
    for key in ("walking", "velocity"):
        for m in out[key]:
            c = np.array(m.twist.covariance).reshape(6, 6)
            assert np.array_equal(c, c.T), key
            assert np.linalg.eigvalsh(c).min() >= -1e-9 * np.abs(c).max(), key
    # The speed's std along the heading while valid; nothing observed while not valid.
    lowest = np.array(
        [np.linalg.eigvalsh(np.array(m.twist.covariance).reshape(6, 6)[:3, :3])[0] for m in out["walking"]]
    )
    valid = expected["valid"].astype(bool) & np.isfinite(heading)
    np.testing.assert_allclose(lowest[valid], expected["speed_std_mps"][valid] ** 2, rtol=1e-6)
    assert np.all(lowest[~expected["valid"].astype(bool)] >= 0.99e6)
    assert counts.estimates == n and counts.dropped_not_increasing == 0


def test_imu_in_g_is_one_line_naming_the_unit(imu_walk, capfd):
    """Specific force published in g instead of m/s^2: one error line naming the topic and REP 145; every
    sample still estimated, no traceback."""
    w = imu_walk
    n = 250
    samples = list(zip(w["stamps_ns"][:n], w["acc"][:n] / 9.80665, w["gyr"][:n]))
    out, _ = _run_node({"imu_topic": "/test/imu/in_g", "plausibility_s": 1.0}, samples, node_name="yoyogait_imu_g")
    err = capfd.readouterr().err
    lines = [line for line in err.splitlines() if "topic /test/imu/in_g:" in line and "9.81" in line]
    assert len(lines) == 1 and "REP 145" in lines[0], err[-2000:]
    assert len(out["state"]) == n and "Traceback" not in err
