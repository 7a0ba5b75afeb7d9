"""End-to-end latency and CPU of ``yoyogait live``, on this machine over loopback (not a test).

    python bench/live_latency.py [--duration 60] [--rates 100,250] [--imu]

For each rate: a SYNTHETIC walk of ``--duration`` seconds is replayed (yoyogait.live.replay, in
this process) into a marker stream (``--imu``: the SYNTHETIC lower-back IMU of that walk into an IMU
stream, estimated by the IMU path); ``yoyogait live --source ... --publish ...`` runs as a
subprocess; a subscriber (this process) receives the estimates. Latency of a frame: from just
before the replayer's push (its LSL timestamp, which the estimate carries) to the arrival of its
estimate at the subscriber, on one clock. CPU of live: user + system time from /proc/<pid>/stat
between the first and the last frame, over that wall time (100 % = one core). Also live's
resident memory at the first and the last frame (a bounded loop does not grow).

Targets: median <= 1 ms, p99 <= 5 ms, live under 5 % of one core at 250 Hz.
LSL is confined to 127.0.0.1 and to this run by an lsl_api.cfg written here (LSLAPICFG).
"""

from __future__ import annotations

import argparse
import os
import subprocess
import sys
import tempfile
import threading
import time
import uuid
from pathlib import Path

import numpy as np

CFG = (
    "[ports]\nIPv6 = disable\n"
    "[multicast]\nResolveScope = machine\nListenAddress = 127.0.0.1\nAddressesOverride = {{127.0.0.1}}\n"
    "[lab]\nKnownPeers = {{127.0.0.1}}\nSessionID = yoyogait-bench-{session}\n"
    "[log]\nlevel = -3\n"
)


def proc_cpu_s(pid: int) -> float:
    """User + system CPU seconds of a process (fields 14 and 15 of /proc/<pid>/stat)."""
    fields = Path(f"/proc/{pid}/stat").read_text().rsplit(")", 1)[1].split()
    return (int(fields[11]) + int(fields[12])) / os.sysconf("SC_CLK_TCK")


def proc_rss_mb(pid: int) -> float:
    for line in Path(f"/proc/{pid}/status").read_text().splitlines():
        if line.startswith("VmRSS:"):
            return int(line.split()[1]) / 1024
    return float("nan")


def run_rate(rate_hz: float, duration_s: float, imu: bool = False) -> dict:
    import pylsl

    from yoyogait import synthetic
    from yoyogait.live.replay import replay, replay_imu
    from yoyogait.synthetic_imu import make_imu_walk

    if imu:
        rec = make_imu_walk(duration_s=duration_s, rate_hz=rate_hz).recording
        n_frames = rec.n_samples
        play = replay_imu
    else:
        rec = synthetic.make_walk(
            synthetic.get_subject("synthetic-S1"), "1-straight", duration_s=duration_s, rate_hz=rate_hz
        ).recording
        n_frames = rec.n_frames
        play = replay
    tag = uuid.uuid4().hex[:8]
    source, estimates = f"bench-walk-{tag}", f"bench-gait-{tag}"
    kind = ["--input", "imu"] if imu else []  # the estimate stream made before the source appears
    live = subprocess.Popen(
        [sys.executable, "-m", "yoyogait", "live", "--source", source, "--publish", estimates, "--exit-on-end", *kind],
        stderr=subprocess.PIPE,
        text=True,
    )
    try:
        found = pylsl.resolve_byprop("name", estimates, 1, 30)
        if not found:
            raise SystemExit(f"the estimate stream did not appear: {live.stderr.read() if live.poll() else ''}")
        inlet = pylsl.StreamInlet(found[0], max_buflen=60, recover=False)
        inlet.open_stream(10)
        pushes: list[float] = []
        marks: dict[str, float] = {}

        def on_push(k: int, stamp: float) -> None:
            if k == 0:
                marks["cpu0"], marks["wall0"], marks["rss0"] = (
                    proc_cpu_s(live.pid),
                    time.perf_counter(),
                    proc_rss_mb(live.pid),
                )
            elif k == n_frames - 1:
                marks["cpu1"], marks["wall1"], marks["rss1"] = (
                    proc_cpu_s(live.pid),
                    time.perf_counter(),
                    proc_rss_mb(live.pid),
                )
            pushes.append(stamp)

        player = threading.Thread(
            target=lambda: play(rec, source, wait_for_consumer_s=30, on_push=on_push), daemon=True
        )
        player.start()
        arrivals, stamps = [], []
        try:
            while len(arrivals) < n_frames:
                sample, stamp = inlet.pull_sample(timeout=10)
                now = pylsl.local_clock()
                if sample is None:
                    break
                arrivals.append(now)
                stamps.append(stamp)
        except pylsl.util.LostError:
            pass
        player.join(30)
        live.wait(30)
    finally:
        if live.poll() is None:
            live.kill()
    latency_ms = 1e3 * (np.array(arrivals) - np.array(stamps))
    wall = marks["wall1"] - marks["wall0"]
    return {
        "rate_hz": rate_hz,
        "frames": n_frames,
        "estimates": len(arrivals),
        "in_order": bool(np.all(np.diff(stamps) > 0)) and stamps == pushes[: len(stamps)],
        "median_ms": float(np.median(latency_ms)),
        "p99_ms": float(np.percentile(latency_ms, 99)),
        "max_ms": float(np.max(latency_ms)),
        "cpu_percent": 100.0 * (marks["cpu1"] - marks["cpu0"]) / wall,
        "rss_mb": (marks["rss0"], marks["rss1"]),
    }


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--duration", type=float, default=60.0, help="seconds of walk per rate")
    parser.add_argument("--rates", default="100,250", help="capture rates [Hz], comma-separated")
    parser.add_argument("--imu", action="store_true", help="a lower-back IMU stream through the IMU path")
    args = parser.parse_args()
    # The replayer's thread and the subscriber share this interpreter: a short GIL switch interval
    # keeps the subscriber from waiting up to 5 ms for the replayer to yield (live runs alone).
    sys.setswitchinterval(1e-4)
    with tempfile.TemporaryDirectory() as tmp:
        cfg = Path(tmp) / "lsl_api.cfg"
        cfg.write_text(CFG.format(session=uuid.uuid4().hex))
        os.environ["LSLAPICFG"] = str(cfg)  # before pylsl is first used, here and in the subprocess
        rows = [run_rate(float(r), args.duration, args.imu) for r in args.rates.split(",")]
    what = "an IMU stream" if args.imu else "a marker stream"
    print(f"yoyogait live on {what}, end to end over loopback, {args.duration:g} s per rate ({os.cpu_count()} cores)\n")
    print(
        "| rate | frames | estimates (in order) | latency median | p99 | max | live CPU (one core) "
        "| live RSS first/last frame |"
    )
    print("|---:|---:|---:|---:|---:|---:|---:|---:|")
    for r in rows:
        print(
            f"| {r['rate_hz']:g} Hz | {r['frames']} | {r['estimates']} ({'yes' if r['in_order'] else 'NO'}) "
            f"| {r['median_ms']:.3f} ms | {r['p99_ms']:.3f} ms | {r['max_ms']:.2f} ms | {r['cpu_percent']:.2f} % "
            f"| {r['rss_mb'][0]:.1f} / {r['rss_mb'][1]:.1f} MB |"
        )
    print("\ntargets: median <= 1 ms, p99 <= 5 ms, live < 5 % of one core at 250 Hz")


if __name__ == "__main__":
    main()
