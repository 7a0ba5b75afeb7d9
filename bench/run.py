"""Benchmark of both presets of the estimator: ns per sample for the native step loop (generic and
-march=native builds), Python run(), Python step() in a loop, and the plain-numpy reference
implementations, measured in one run on one signal.

    python bench/run.py [--samples N] [--rounds R] [--baseline REV]

Prints a Markdown table of medians (and the C++ minimum, the least disturbed by other load) and
the ratios default / paper. With --baseline REV, the native step loop is also built against the
include/ of the git revision REV (same compiler, same flags) and timed in the same rounds, and a
second table gives before (REV) and after (this tree) for both presets. A benchmark, not a test.
The machine's speed drifts (a shared virtual machine: up to 30 % within minutes), so every path is
timed in each of R rounds, one after the other, and the medians are taken over all rounds: all
paths see the same load, and a ratio compares like with like.
"""

from __future__ import annotations

import os

# Idle BLAS worker threads spin on this 2-core class of machine and disturb the timings.
os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")
os.environ.setdefault("OMP_NUM_THREADS", "1")

import argparse  # noqa: E402
import io
import platform  # noqa: E402
import re
import shutil
import statistics
import subprocess
import sys
import tarfile
import tempfile
import time
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT / "tests" / "python" / "reference"))

import yoyogait  # noqa: E402
from reference_default import run_reference  # noqa: E402
from reference_ekf import reference_paper_estimator  # noqa: E402

PRESETS = ("paper", "default")


def signal(n: int, seed: int = 0):
    """A noisy Yoyo-model walk at 25 Hz with a slowly varying step frequency."""
    t = np.arange(n) * 0.04
    m = yoyogait.yoyo_model(t, 0.12, 0.025, 1.8 + 0.3 * np.sin(2 * np.pi * t / 60.0))
    rng = np.random.default_rng(seed)
    return m.vx_mps + 0.05 * rng.standard_normal(n), m.vz_mps + 0.05 * rng.standard_normal(n)


def baseline_include(rev: str) -> tuple[str, Path]:
    """(commit, directory holding include/) of the git revision rev, extracted under build/bench."""
    proc = subprocess.run(
        ["git", "-C", ROOT, "rev-parse", "--verify", "--quiet", f"{rev}^{{commit}}"], capture_output=True, text=True
    )
    if proc.returncode != 0:
        sys.exit(f"bench/run.py: --baseline {rev}: not a commit of this repository")
    sha = proc.stdout.strip()
    dest = ROOT / "build" / "bench" / f"baseline-{sha[:12]}"
    if not (dest / "include").is_dir():
        tar = subprocess.run(
            ["git", "-C", ROOT, "archive", "--format=tar", sha, "include"], check=True, capture_output=True
        ).stdout
        dest.parent.mkdir(parents=True, exist_ok=True)
        tmp = tempfile.mkdtemp(dir=dest.parent)  # complete or absent: extracted, then renamed
        try:
            with tarfile.open(fileobj=io.BytesIO(tar)) as t:
                t.extractall(tmp)
            os.replace(tmp, dest)
        finally:
            shutil.rmtree(tmp, ignore_errors=True)
    return sha, dest / "include"


def build_native(baseline: Path | None = None) -> dict:
    """{build: path} of bench/bench_step.cpp (Release): "generic" (the compiler's default target,
    -O3) and, where the compiler has it, "native" (-O3 -march=native: this machine's instruction
    set, e.g. AVX2 and FMA). With baseline (an include/ directory) also "generic-baseline" and
    "native-baseline": the same loop, built the same way, against those headers."""
    cmake = shutil.which("cmake") or "cmake"
    build = ROOT / "build" / "bench"
    gen = ["-G", "Ninja"] if shutil.which("ninja") else []
    subprocess.run(
        [
            cmake,
            "-S",
            ROOT,
            "-B",
            build,
            *gen,
            "-DYOYOGAIT_BUILD_BENCH=ON",
            "-DCMAKE_BUILD_TYPE=Release",
            f"-DYOYOGAIT_BENCH_BASELINE_INCLUDE={baseline or ''}",
        ],
        check=True,
        capture_output=True,
    )
    subprocess.run([cmake, "--build", build, "--parallel", "2"], check=True, capture_output=True)
    names = {"generic": "bench_step", "native": "bench_step_native"}
    if baseline is not None:
        names.update({"generic-baseline": "bench_step_baseline", "native-baseline": "bench_step_native_baseline"})
    exes = {name: next(build.rglob(exe), None) for name, exe in names.items()}
    return {name: exe for name, exe in exes.items() if exe is not None}


def native_step_ns(exe: Path, signal_path: Path, repeats: int) -> dict:
    """{preset: (median, min)} of one invocation of bench_step (both presets interleaved)."""
    out = subprocess.run([exe, signal_path, str(repeats)], check=True, capture_output=True, text=True).stdout
    get = lambda key: float(re.search(key + r"=([\d.]+)", out).group(1))  # noqa: E731
    return {p: (get(f"cpp_step_ns_median_{p}"), get(f"cpp_step_ns_min_{p}")) for p in PRESETS}


def times_ns(fns: dict, n_samples: int, repeats: int) -> dict:
    """{name: [ns per sample, one per call]} of the callables, called alternately."""
    times = {name: [] for name in fns}
    for _ in range(repeats):
        for name, fn in fns.items():
            t0 = time.perf_counter_ns()
            fn()
            times[name].append((time.perf_counter_ns() - t0) / n_samples)
    return times


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--samples", type=int, default=200_000)
    ap.add_argument("--rounds", type=int, default=11)
    ap.add_argument(
        "--baseline",
        metavar="REV",
        help="also time the C++ step loop built against include/ of this git revision (before/after)",
    )
    args = ap.parse_args()
    baseline = baseline_include(args.baseline) if args.baseline else None
    vx, vz = signal(args.samples)
    cfg = {p: yoyogait.EstimatorConfig.preset(p) for p in PRESETS}
    time_s = np.arange(args.samples) * 0.04
    n_step = min(args.samples, 50_000)
    sx, sz = vx[:n_step].tolist(), vz[:n_step].tolist()

    def step_loop(p):
        step = yoyogait.GaitEstimator(cfg[p]).step
        for a, b in zip(sx, sz):
            step(a, b)

    exes = build_native(baseline[1] if baseline else None)
    cpp = {b: {p: ([], []) for p in PRESETS} for b in exes}  # per round: median, min
    py_run = {p: [] for p in PRESETS}
    py_run_t = {p: [] for p in PRESETS}
    py_step = {p: [] for p in PRESETS}
    with tempfile.TemporaryDirectory() as tmp:
        signal_path = Path(tmp) / "signal.f64"
        np.concatenate([vx, vz]).astype(np.float64).tofile(signal_path)
        for r in range(args.rounds):
            # Every other round in the reverse order, so that no build always runs first.
            for build, exe in list(exes.items()) if r % 2 == 0 else list(exes.items())[::-1]:
                for p, (med, low) in native_step_ns(exe, signal_path, 7).items():
                    cpp[build][p][0].append(med)
                    cpp[build][p][1].append(low)
            for p, v in times_ns(
                {p: (lambda p=p: yoyogait.GaitEstimator(cfg[p]).run(vx, vz)) for p in PRESETS}, args.samples, 5
            ).items():
                py_run[p] += v
            for p, v in times_ns(
                {p: (lambda p=p: yoyogait.GaitEstimator(cfg[p]).run(vx, vz, time_s=time_s)) for p in PRESETS},
                args.samples,
                2,
            ).items():
                py_run_t[p] += v
            for p, v in times_ns({p: (lambda p=p: step_loop(p)) for p in PRESETS}, n_step, 1).items():
                py_step[p] += v
    n_ref = min(args.samples, 3_000)
    ref = times_ns(
        {
            "paper": lambda: reference_paper_estimator(vx[:n_ref], vz[:n_ref]),
            "default": lambda: run_reference(vx[:n_ref], vz[:n_ref]),
        },
        n_ref,
        3,
    )
    med = statistics.median
    cpp = {b: {p: (med(v[0]), min(v[1])) for p, v in res.items()} for b, res in cpp.items()}
    py_run, py_run_t, py_step, ref = ({p: med(v) for p, v in d.items()} for d in (py_run, py_run_t, py_step, ref))

    print(
        f"yoyogait {yoyogait.__version__} benchmark, both presets, {args.samples} samples, {args.rounds} rounds; "
        f"{platform.processor() or platform.machine()}, {os.cpu_count()} cores, Python {platform.python_version()}"
    )
    print()
    print("| path | paper ns/sample | default ns/sample | default / paper | target |")
    print("|---|---:|---:|---:|---|")
    labels = {"generic": "C++ `Estimator::step` loop, -O3", "native": "C++ `Estimator::step` loop, -O3 -march=native"}
    for build, res in cpp.items():
        if build not in labels:
            continue
        print(
            f"| {labels[build]}, median | {res['paper'][0]:.1f} | {res['default'][0]:.1f} | "
            f"{res['default'][0] / res['paper'][0]:.2f} | paper <= 40 ns |"
        )
        print(
            f"| {labels[build]}, min | {res['paper'][1]:.1f} | {res['default'][1]:.1f} | "
            f"{res['default'][1] / res['paper'][1]:.2f} | |"
        )
    print(
        f"| Python `GaitEstimator.run` | {py_run['paper']:.1f} | {py_run['default']:.1f} | "
        f"{py_run['default'] / py_run['paper']:.2f} | <= 1.3x C++ |"
    )
    # The module is built like the generic loop (-O3, the default target), so that is its reference.
    ref_cpp = cpp["generic"]
    print(
        f"| ... ratio to the C++ step, -O3 (median) | {py_run['paper'] / ref_cpp['paper'][0]:.2f} | "
        f"{py_run['default'] / ref_cpp['default'][0]:.2f} | | <= 1.3 |"
    )
    print(
        f"| Python `GaitEstimator.run(time_s=...)` | {py_run_t['paper']:.1f} | {py_run_t['default']:.1f} | "
        f"{py_run_t['default'] / py_run_t['paper']:.2f} | |"
    )
    print(
        f"| Python `GaitEstimator.step` loop | {py_step['paper']:.1f} | {py_step['default']:.1f} | "
        f"{py_step['default'] / py_step['paper']:.2f} | <= 1000 ns |"
    )
    print(
        f"| numpy reference (tests/python/reference/reference_*.py) | {ref['paper']:.0f} | {ref['default']:.0f} | "
        f"{ref['default'] / ref['paper']:.2f} | - |"
    )
    if baseline:
        print()
        print(
            f"Before: include/ of {args.baseline} ({baseline[0][:12]}); after: this tree. The same bench_step.cpp, "
            f"compiler and flags, timed in the same {args.rounds} rounds."
        )
        print()
        print(
            "| C++ `Estimator::step` loop | preset | before median | after median | after / before | "
            "before min | after min | after / before |"
        )
        print("|---|---|---:|---:|---:|---:|---:|---:|")
        for build in ("generic", "native"):
            if build not in cpp or f"{build}-baseline" not in cpp:
                continue
            for p in PRESETS:
                (a_med, a_min), (b_med, b_min) = cpp[build][p], cpp[f"{build}-baseline"][p]
                print(
                    f"| {labels[build][len('C++ `Estimator::step` loop, ') :]} | {p} | {b_med:.1f} | {a_med:.1f} | "
                    f"{a_med / b_med:.3f} | {b_min:.1f} | {a_min:.1f} | {a_min / b_min:.3f} |"
                )


if __name__ == "__main__":
    main()
