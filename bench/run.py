"""Benchmark of the estimator: ns per sample for the native step loop, Python run(), Python step()
in a loop, and the plain-numpy reference, measured in one run on one signal.

    python bench/run.py [--samples N] [--repeats R]

Prints a Markdown table of medians and ratios. A benchmark, not a test: run it on a quiet machine.
"""

from __future__ import annotations

import argparse
import os
import platform
import re
import shutil
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT / "tests" / "python"))

import yoyogait  # noqa: E402
from reference_ekf import reference_paper_estimator  # noqa: E402


def signal(n: int, seed: int = 0):
    """A noisy Yoyo-model walk at 25 Hz with a slowly varying step frequency."""
    t = np.arange(n) * 0.04
    m = yoyogait.yoyo_model(t, 0.12, 0.025, 1.8 + 0.3 * np.sin(2 * np.pi * t / 60.0))
    rng = np.random.default_rng(seed)
    return m.vx_mps + 0.05 * rng.standard_normal(n), m.vz_mps + 0.05 * rng.standard_normal(n)


def native_step_ns(vx, vz, repeats: int) -> float:
    cmake = shutil.which("cmake") or "cmake"
    build = ROOT / "build" / "bench"
    gen = ["-G", "Ninja"] if shutil.which("ninja") else []
    subprocess.run([cmake, "-S", ROOT, "-B", build, *gen, "-DYOYOGAIT_BUILD_BENCH=ON", "-DCMAKE_BUILD_TYPE=Release"],
                   check=True, capture_output=True)
    subprocess.run([cmake, "--build", build, "--target", "bench_step"], check=True, capture_output=True)
    exe = next(build.rglob("bench_step"))
    with tempfile.TemporaryDirectory() as tmp:
        path = Path(tmp) / "signal.f64"
        np.concatenate([vx, vz]).astype(np.float64).tofile(path)
        out = subprocess.run([exe, path, str(repeats)], check=True, capture_output=True, text=True).stdout
    return float(re.search(r"cpp_step_ns_median=([\d.]+)", out).group(1))


def median_ns(fn, n_samples: int, repeats: int) -> float:
    times = []
    for _ in range(repeats):
        t0 = time.perf_counter_ns()
        fn()
        times.append((time.perf_counter_ns() - t0) / n_samples)
    return statistics.median(times)


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--samples", type=int, default=200_000)
    ap.add_argument("--repeats", type=int, default=21)
    args = ap.parse_args()
    vx, vz = signal(args.samples)
    cfg = yoyogait.EstimatorConfig.paper()

    cpp = native_step_ns(vx, vz, args.repeats)
    py_run = median_ns(lambda: yoyogait.GaitEstimator(cfg).run(vx, vz), args.samples, args.repeats)
    n_step = min(args.samples, 50_000)
    sx, sz = vx[:n_step].tolist(), vz[:n_step].tolist()

    def step_loop():
        est = yoyogait.GaitEstimator(cfg)
        step = est.step
        for a, b in zip(sx, sz):
            step(a, b)

    py_step = median_ns(step_loop, n_step, max(5, args.repeats // 3))
    n_ref = min(args.samples, 3_000)
    ref = median_ns(lambda: reference_paper_estimator(vx[:n_ref], vz[:n_ref]), n_ref, 3)

    print(f"yoyogait {yoyogait.__version__} benchmark, paper preset, {args.samples} samples, "
          f"{args.repeats} repeats; {platform.processor() or platform.machine()}, {os.cpu_count()} cores, "
          f"Python {platform.python_version()}")
    print()
    print("| path | ns per sample (median) | ratio to C++ step | target |")
    print("|---|---:|---:|---|")
    print(f"| C++ `Estimator::step` loop | {cpp:.1f} | 1.00 | <= 40 ns |")
    print(f"| Python `GaitEstimator.run` | {py_run:.1f} | {py_run / cpp:.2f} | <= 1.3x C++ |")
    print(f"| Python `GaitEstimator.step` loop | {py_step:.1f} | {py_step / cpp:.1f} | <= 1000 ns |")
    print(f"| numpy reference (tests/python/reference_ekf.py) | {ref:.0f} | {ref / cpp:.0f} | - |")


if __name__ == "__main__":
    main()
