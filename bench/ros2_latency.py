"""The ROS 2 node at 250 Hz on loopback, beside ``live`` and the C++ stdin bridge, in one run (not a test).

    python bench/ros2_latency.py [--duration 20] [--rate 250]

1. ``yoyogait ros2 --pose-topic ...`` as a subprocess; this process publishes a SYNTHETIC walk's pelvis
   centre as ``PoseStamped`` (reliable QoS) at ``--rate``, stamped with the system clock just before
   ``publish``, and receives ``~/walking_velocity`` (raw: its stamp read from the bytes, so that the
   consumer's own message building is not timed as the node's). Latency of a frame: from that stamp to the receipt of
   its estimate, on one clock. Lost: frames without an estimate. CPU of the node: user + system time
   from /proc between the first and the last frame, over that wall time (100 % = one core).
2. ``yoyogait live`` at the same rate and duration, as bench/live_latency.py measures it (LSL).
3. ``examples/cpp/online_stdin`` (the C++ bridge, no Python), built here with the system compiler: the
   same frames as CSV lines on its stdin at the same rate, one line out per frame; its CPU likewise.
4. ``OnlineEstimator.update`` from Python against the C++ update (bench/online.py --python-cost, one rate).

Targets: node median <= 1 ms, p99 <= 5 ms, no estimate lost; Python update <= 2x the C++ update.
ROS 2 is confined to this machine (ROS_AUTOMATIC_DISCOVERY_RANGE=LOCALHOST) in a random domain 100-200.
"""

from __future__ import annotations

import argparse
import os
import random
import shutil
import struct
import subprocess
import sys
import tempfile
import threading
import time
import uuid
from pathlib import Path

import numpy as np

from live_latency import CFG, proc_cpu_s, run_rate
from online import python_cost

ROOT = Path(__file__).resolve().parents[1]


def walk_centre(rate_hz: float, duration_s: float):
    """SYNTHETIC: the pelvis centre of the synthetic lab's straight walk (metres, z up)."""
    from yoyogait import synthetic

    rec = synthetic.make_walk(
        synthetic.get_subject("synthetic-S1"), "1-straight", duration_s=duration_s, rate_hz=rate_hz
    ).recording
    pelvis = rec.points(["LASI", "RASI", "LPSI", "RPSI"])
    centre = np.nanmean(pelvis, axis=1)
    return rec.time_s, np.where(np.isfinite(centre), centre, np.nanmean(centre, axis=0))


def paced(n: int, rate_hz: float, send, marks: dict, pid: int) -> None:
    """``send(k)`` for k < n at ``rate_hz`` (absolute schedule); CPU marks of ``pid`` at the first and last."""
    start = time.perf_counter() + 0.1
    for k in range(n):
        due = start + k / rate_hz
        while True:
            left = due - time.perf_counter()
            if left <= 0:
                break
            # Sleep until 0.3 ms before the due time, then yield: the estimates' subscriber (a thread of this
            # process) needs the interpreter lock to note their arrival.
            time.sleep(left - 0.0003 if left > 0.0005 else 0)
        if k == 0:
            marks["cpu0"], marks["wall0"] = proc_cpu_s(pid), time.perf_counter()
        send(k)
        if k == n - 1:
            marks["cpu1"], marks["wall1"] = proc_cpu_s(pid), time.perf_counter()


def bench_node(rate_hz: float, duration_s: float) -> dict:
    import rclpy
    from geometry_msgs.msg import PoseStamped, TwistWithCovarianceStamped
    from rclpy.qos import HistoryPolicy, QoSProfile, ReliabilityPolicy

    _, centre = walk_centre(rate_hz, duration_s)
    topic = f"/bench_{uuid.uuid4().hex[:8]}/pose"
    node_proc = subprocess.Popen(
        [sys.executable, "-m", "yoyogait", "ros2", "--pose-topic", topic, "--up-axis", "z"],
        stderr=subprocess.DEVNULL,
    )
    rclpy.init()
    node = rclpy.create_node("yoyogait_bench")
    qos = QoSProfile(depth=1000, reliability=ReliabilityPolicy.RELIABLE, history=HistoryPolicy.KEEP_LAST)
    pub = node.create_publisher(PoseStamped, topic, qos)
    received: list[tuple[int, int]] = []
    stamp = struct.Struct("<iI")  # header.stamp, right after the 4-byte CDR encapsulation

    def on_estimate(raw: bytes) -> None:
        sec, nanosec = stamp.unpack_from(raw, 4)
        received.append((time.time_ns(), sec * 10**9 + nanosec))

    node.create_subscription(TwistWithCovarianceStamped, "/yoyogait/walking_velocity", on_estimate, qos, raw=True)
    from yoyogait.ros2.node import make_executor

    executor = make_executor()
    executor.add_node(node)
    stop = threading.Event()
    spinner = threading.Thread(target=lambda: [executor.spin_once(0.01) for _ in iter(stop.is_set, True)], daemon=True)
    spinner.start()
    try:
        end = time.monotonic() + 60
        while time.monotonic() < end and (
            pub.get_subscription_count() == 0 or node.count_publishers("/yoyogait/walking_velocity") == 0
        ):
            time.sleep(0.05)
        time.sleep(1.0)
        sent: list[int] = []
        msg = PoseStamped()
        msg.header.frame_id = "mocap"

        def send(k: int) -> None:
            ns = time.time_ns()
            msg.header.stamp.sec, msg.header.stamp.nanosec = ns // 10**9, ns % 10**9
            msg.pose.position.x, msg.pose.position.y, msg.pose.position.z = (float(v) for v in centre[k])
            pub.publish(msg)
            sent.append(ns)

        marks: dict = {}
        paced(len(centre), rate_hz, send, marks, node_proc.pid)
        end = time.monotonic() + 5
        while len(received) < len(sent) and time.monotonic() < end:
            time.sleep(0.01)
    finally:
        stop.set()
        spinner.join(2)
        node.destroy_node()
        rclpy.shutdown()
        node_proc.terminate()
        node_proc.wait(10)
    by_stamp = dict((s, t) for t, s in received)
    latency_ms = np.array([(by_stamp[s] - s) / 1e6 for s in sent if s in by_stamp])
    stamps = [s for _, s in received]
    return {
        "frames": len(sent),
        "estimates": len(received),
        "lost": len(set(sent) - set(by_stamp)),
        "in_order": stamps == sorted(stamps),
        "median_ms": float(np.median(latency_ms)),
        "p99_ms": float(np.percentile(latency_ms, 99)),
        "max_ms": float(np.max(latency_ms)),
        "cpu_percent": 100.0 * (marks["cpu1"] - marks["cpu0"]) / (marks["wall1"] - marks["wall0"]),
    }


def bench_cpp_bridge(rate_hz: float, duration_s: float, build: Path) -> dict | None:
    compiler = shutil.which("c++") or shutil.which("g++") or shutil.which("clang++")
    if compiler is None:
        return None
    exe = build / "online_stdin"
    subprocess.run(
        [compiler, "-O2", "-std=c++17", "-I", str(ROOT / "include"), str(ROOT / "examples/cpp/online_stdin.cpp"),
         "-o", str(exe)],
        check=True,
    )  # fmt: skip
    t, centre = walk_centre(rate_hz, duration_s)
    proc = subprocess.Popen([str(exe), "z", "1"], stdin=subprocess.PIPE, stdout=subprocess.PIPE, text=True, bufsize=1)
    assert proc.stdin is not None and proc.stdout is not None
    out: list[tuple[float, str]] = []
    reader = threading.Thread(
        target=lambda: out.extend((time.perf_counter(), line) for line in proc.stdout), daemon=True
    )
    reader.start()
    sent: list[float] = []

    def send(k: int) -> None:
        sent.append(time.perf_counter())
        proc.stdin.write(",".join(repr(float(v)) for v in (t[k], *centre[k])) + "\n")
        proc.stdin.flush()

    marks: dict = {}
    paced(len(t), rate_hz, send, marks, proc.pid)
    proc.stdin.close()
    proc.wait(10)
    reader.join(5)
    out = out[1:]  # its header line
    latency_ms = 1e3 * (np.array([a for a, _ in out[: len(sent)]]) - np.array(sent[: len(out)]))
    return {
        "frames": len(sent),
        "estimates": len(out),
        "median_ms": float(np.median(latency_ms)),
        "p99_ms": float(np.percentile(latency_ms, 99)),
        "cpu_percent": 100.0 * (marks["cpu1"] - marks["cpu0"]) / (marks["wall1"] - marks["wall0"]),
    }


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--duration", type=float, default=20.0, help="seconds of walk")
    parser.add_argument("--rate", type=float, default=250.0, help="capture rate [Hz]")
    args = parser.parse_args()
    sys.setswitchinterval(1e-4)  # publisher and subscriber threads share this interpreter
    os.environ["ROS_AUTOMATIC_DISCOVERY_RANGE"] = "LOCALHOST"
    os.environ["ROS_DOMAIN_ID"] = str(random.SystemRandom().randint(100, 200))
    with tempfile.TemporaryDirectory() as tmp:
        cfg = Path(tmp) / "lsl_api.cfg"
        cfg.write_text(CFG.format(session=uuid.uuid4().hex))
        os.environ["LSLAPICFG"] = str(cfg)
        node = bench_node(args.rate, args.duration)
        live = run_rate(args.rate, args.duration)
        cpp = bench_cpp_bridge(args.rate, args.duration, Path(tmp))
    update = python_cost(args.rate)
    print(f"{args.rate:g} Hz, {args.duration:g} s of a SYNTHETIC walk, one run ({os.cpu_count()} cores)\n")
    print("| path | frames | estimates | lost | latency median | p99 | max | CPU (one core) |")
    print("|---|---:|---:|---:|---:|---:|---:|---:|")
    print(
        f"| ros2 node (PoseStamped, reliable) | {node['frames']} | {node['estimates']} "
        f"({'in order' if node['in_order'] else 'NOT in order'}) | {node['lost']} | {node['median_ms']:.3f} ms "
        f"| {node['p99_ms']:.3f} ms | {node['max_ms']:.2f} ms | {node['cpu_percent']:.1f} % |"
    )
    print(
        f"| live (LSL) | {live['frames']} | {live['estimates']} | {live['frames'] - live['estimates']} "
        f"| {live['median_ms']:.3f} ms | {live['p99_ms']:.3f} ms | {live['max_ms']:.2f} ms "
        f"| {live['cpu_percent']:.1f} % |"
    )
    if cpp is not None:
        print(
            f"| C++ online_stdin (pipe) | {cpp['frames']} | {cpp['estimates']} | {cpp['frames'] - cpp['estimates']} "
            f"| {cpp['median_ms']:.3f} ms | {cpp['p99_ms']:.3f} ms | | {cpp['cpu_percent']:.2f} % |"
        )
    else:
        print("| C++ online_stdin | no C++ compiler found | | | | | | |")
    print(
        f"\nOnlineEstimator.update, one point, {update['frames']} frames, thread CPU time: Python "
        f"{update['python_ns']:.0f} ns, C++ {update['cpp_ns']:.0f} ns per frame: {update['ratio_median']:.2f}x "
        f"median, {update['ratio_worst']:.2f}x worst of the rounds (target <= 2x); update_point "
        f"{update['point_ns']:.0f} ns, {update['point_ratio_median']:.2f}x"
    )
    print("targets: node median <= 1 ms, p99 <= 5 ms, no estimate lost")


if __name__ == "__main__":
    main()
