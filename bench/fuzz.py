"""Fuzz both presets of the estimator with random input sequences and count what must never happen.

    python bench/fuzz.py [--sequences N] [--seed S] [--presets paper default] [--walk-fraction F]

Each sequence runs through a fresh native estimator in one batch (``GaitEstimator.run`` with the
covariance after every step), and every step is checked:

* the covariance has a negative diagonal entry;
* the covariance has an eigenvalue below -1e-9 of its largest (not positive semi-definite);
* the covariance is not symmetric or not finite;
* a reported standard deviation is NaN, or any other output is not finite;
* the status is wrong: non-finite (a NaN/inf channel, or a NaN/inf/negative time step) beats
  out-of-range (|v| > max_abs_velocity_mps) beats outlier; a usable sample is UPDATED or
  REJECTED_OUTLIER (paper: UPDATED), or REJECTED_NUMERICAL after a restart (counted apart).

Two families of sequences (sequence i is reproducible from --seed and i, see ``sequence``):

* ``runs`` (the default 1 - F of them): 2-8 runs of 1-50 samples, each run a pair of values drawn
  from zero, small noise, walking speeds, integers, in-range values up to 1000 m/s (and exactly at
  the limit), out-of-range values up to 1e308, tiny values, NaN and infinities, or a short
  sinusoid; the default also gets irregular, repeated, backward, huge and non-finite timestamps;
* ``walk`` (F = 3 % by default): realistic walking (|v| <= 3.2 m/s, 0.7-2.5 Hz, stops) broken by
  NaN dropouts of 20-200 s (the long dropouts that make the paper's covariance grow).

Prints a table of counts per preset and family, the first failing sequences of each kind, and the
wall time. A check, not a benchmark: the wall time is mostly numpy's eigenvalues.
"""

from __future__ import annotations

import argparse
import math
import sys
import time
from collections import defaultdict

import numpy as np

from yoyogait import EstimatorConfig, GaitEstimator, Status
from yoyogait.estimators.records import RECORDS

PRESETS = ("paper", "default")
T = 0.04
V_MAX = EstimatorConfig().max_abs_velocity_mps
CHECKS = (
    "negative_diagonal",
    "eigenvalue_below_-1e-9",
    "asymmetric_or_nonfinite_cov",
    "nan_std",
    "nonfinite_output",
    "wrong_status",
    "numerical_restart",
)
#: Every float output of an estimate and the two states, from the record table (docs/records.md).
OUTPUTS = tuple(f.name for f in RECORDS["Estimate"] if f.type.startswith("float"))


def draw_value(rng: np.random.Generator) -> float:
    """One value of a run: the kinds of numbers a motion-capture pipeline can hand over."""
    kind = rng.choice(10, p=[0.16, 0.10, 0.18, 0.10, 0.10, 0.04, 0.10, 0.08, 0.04, 0.10])
    sign = 1.0 if rng.random() < 0.5 else -1.0
    if kind == 0:
        return 0.0
    if kind == 1:
        return float(rng.normal(0.0, 0.05))
    if kind == 2:
        return float(rng.uniform(-3.2, 3.2))
    if kind == 3:
        return float(rng.integers(-20, 21))
    if kind == 4:
        return sign * float(rng.uniform(100.0, V_MAX))
    if kind == 5:
        return sign * float(rng.choice([V_MAX, 999.90625, math.nextafter(V_MAX, math.inf), 114.0]))
    if kind == 6:
        return sign * 10.0 ** float(rng.uniform(3.0, 308.0))
    if kind == 7:
        return math.nan
    if kind == 8:
        return sign * math.inf
    return sign * 10.0 ** float(rng.uniform(-323.0, -300.0))


def runs_sequence(rng: np.random.Generator, timestamps: bool):
    """2-8 runs of constant (or noisy, or sinusoidal) values; irregular timestamps for the default."""
    vx, vz = [], []
    for _ in range(int(rng.integers(2, 9))):
        n = int(rng.integers(1, 51))
        a, b = draw_value(rng), draw_value(rng)
        mode = rng.random()
        if mode < 0.6:
            x, z = np.full(n, a), np.full(n, b)
        elif mode < 0.8:  # noisy values around the run's pair
            with np.errstate(over="ignore", invalid="ignore"):
                x = a + rng.normal(0, 0.1, n) * max(1e-3, min(abs(a), 1e300) if math.isfinite(a) else 1.0)
                z = b + rng.normal(0, 0.1, n) * max(1e-3, min(abs(b), 1e300) if math.isfinite(b) else 1.0)
        else:  # a sinusoid of random size and frequency
            k = np.arange(n)
            w = rng.uniform(0.05, 0.8)
            amp = 10.0 ** rng.uniform(-3, 3)
            x = a if math.isfinite(a) else 0.0
            x = x + amp * np.cos(w * k)
            z = -amp * np.sin(w * k)
        vx.append(x)
        vz.append(z)
    vx, vz = np.concatenate(vx), np.concatenate(vz)
    time_s = None
    if timestamps:
        n = vx.size
        dt = np.full(n, T)
        pick = rng.random(n)
        dt[pick < 0.2] = T * rng.uniform(0.5, 1.5, int((pick < 0.2).sum()))
        for lo, hi, value in (
            (0.2, 0.23, 0.0),
            (0.23, 0.25, 1e-6),
            (0.25, 0.27, 1.0),
            (0.27, 0.29, 2.0),
            (0.29, 0.30, 100.0),
            (0.30, 0.32, -0.01),
            (0.32, 0.325, 1e6),
        ):
            dt[(pick >= lo) & (pick < hi)] = value
        time_s = np.cumsum(dt)
        bad = rng.random(n)
        time_s[bad < 0.02] = np.nan
        time_s[(bad >= 0.02) & (bad < 0.025)] = np.inf
    return vx, vz, time_s


def walk_sequence(rng: np.random.Generator, timestamps: bool):
    """Walking (|v| <= 3.2 m/s) and standing broken by NaN dropouts of 20-200 s."""
    parts_x, parts_z = [], []
    for _ in range(int(rng.integers(1, 4))):
        n = int(rng.integers(2, int(60 / T)))
        f = rng.uniform(0.7, 2.5)
        speed = rng.uniform(0.0, 2.0) if rng.random() < 0.85 else 0.0
        amp = rng.uniform(0.0, 0.3) * (speed > 0)
        theta = 2 * np.pi * f * T * np.arange(n) + rng.uniform(0, 2 * np.pi)
        rel = np.pi if rng.random() < 0.7 else 0.0  # real walking or the Yoyo relation
        x = np.clip(np.abs(speed + amp * np.cos(theta + rel) + rng.normal(0, 0.03, n)), 0, 3.2)
        z = np.clip(-amp * np.sin(theta) + rng.normal(0, 0.03, n), -3.2, 3.2)
        parts_x.append(x)
        parts_z.append(z)
        gap = int(rng.uniform(20.0, 200.0) / T)
        which = rng.random()
        parts_x.append(np.full(gap, np.nan) if which < 0.8 else rng.normal(1.0, 0.1, gap))
        parts_z.append(np.full(gap, np.nan) if which < 0.8 or which > 0.9 else np.zeros(gap))
        if which >= 0.8:  # one channel missing only
            (parts_x if which < 0.9 else parts_z)[-1][:] = np.nan
    tail = int(rng.integers(1, int(10 / T)))
    f = rng.uniform(0.7, 2.5)
    theta = 2 * np.pi * f * T * np.arange(tail)
    parts_x.append(np.abs(1.2 + 0.2 * np.cos(theta + np.pi)))
    parts_z.append(-0.2 * np.sin(theta))
    vx, vz = np.concatenate(parts_x), np.concatenate(parts_z)
    time_s = None
    if timestamps:
        time_s = np.cumsum(T * (1.0 + rng.uniform(-0.2, 0.2, vx.size)))
    return vx, vz, time_s


def sequence(seed: int, index: int, walk_fraction: float, timestamps: bool):
    """(family, vx, vz, time_s) of sequence ``index``: reproducible from (seed, index)."""
    rng = np.random.default_rng([seed, index])
    if rng.random() < walk_fraction:
        return ("walk", *walk_sequence(rng, timestamps))
    return ("runs", *runs_sequence(rng, timestamps))


def expected_status(vx: np.ndarray, vz: np.ndarray, time_s, paper: bool) -> np.ndarray:
    """The status that the input alone decides: NON_FINITE, then OUT_OF_RANGE; -1 for a usable sample."""
    out = np.full(vx.size, -1)
    with np.errstate(invalid="ignore"):
        rng_bad = (np.abs(vx) > V_MAX) | (np.abs(vz) > V_MAX)
        out[rng_bad] = int(Status.REJECTED_OUT_OF_RANGE)
        bad = ~np.isfinite(vx) | ~np.isfinite(vz)
        if time_s is not None and not paper:
            dt = np.empty(vx.size)
            dt[0] = T
            dt[1:] = np.diff(time_s)
            bad |= ~(np.isfinite(dt) & (dt >= 0))
    out[bad] = int(Status.REJECTED_NON_FINITE)
    return out


def check(res, vx, vz, time_s, paper: bool) -> dict:
    """{check: True} for each check the run of one sequence fails."""
    found = {}
    cov = res.covariance
    n = cov.shape[0]
    finite = np.isfinite(cov).all(axis=(1, 2))
    if not finite.all() or not np.array_equal(cov, cov.transpose(0, 2, 1)):
        found["asymmetric_or_nonfinite_cov"] = True
    diag = np.diagonal(cov, axis1=1, axis2=2)
    if (diag < 0).any():
        found["negative_diagonal"] = True
    if n and finite.any():
        ev = np.linalg.eigvalsh(cov[finite])
        if (ev[:, 0] < -1e-9 * np.maximum(ev[:, -1], 0.0)).any():
            found["eigenvalue_below_-1e-9"] = True
    if np.isnan(res.step_frequency_std_hz).any() or np.isnan(res.speed_std_mps).any():
        found["nan_std"] = True
    for name in OUTPUTS:
        value = getattr(res, name)
        if value is not None and not np.isfinite(value).all():
            found["nonfinite_output"] = True
            break
    status = np.asarray(res.status).astype(int)
    numerical = status == int(Status.REJECTED_NUMERICAL)
    if numerical.any():
        found["numerical_restart"] = True
    want = expected_status(vx, vz, time_s, paper)
    usable = want < 0
    allowed = (status == int(Status.UPDATED)) | numerical
    if not paper:
        allowed |= status == int(Status.REJECTED_OUTLIER)
    if (~usable & (status != want) & ~numerical).any() or (usable & ~allowed).any():
        found["wrong_status"] = True
    return found


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--sequences", type=int, default=100_000, help="sequences per preset (default 100000)")
    ap.add_argument("--seed", type=int, default=0)
    ap.add_argument("--presets", nargs="+", default=list(PRESETS), choices=PRESETS)
    ap.add_argument("--walk-fraction", type=float, default=0.03, help="share of realistic walks with dropouts")
    ap.add_argument("--progress", type=int, default=0, help="print a line every this many sequences (0: never)")
    args = ap.parse_args()
    if args.sequences < 1 or not 0.0 <= args.walk_fraction <= 1.0:
        print("fuzz.py: --sequences must be >= 1 and --walk-fraction in [0, 1]", file=sys.stderr)
        return 2
    print(f"fuzz: {args.sequences} sequences per preset, seed {args.seed}, walk fraction {args.walk_fraction}")
    total_failures = 0
    for preset in args.presets:
        cfg = EstimatorConfig.preset(preset)
        paper = preset == "paper"
        counts = defaultdict(int)
        examples = defaultdict(list)
        steps = defaultdict(int)
        seqs = defaultdict(int)
        t0 = time.perf_counter()
        for i in range(args.sequences):
            family, vx, vz, time_s = sequence(args.seed, i, args.walk_fraction, timestamps=not paper)
            res = GaitEstimator(cfg).run(vx, vz, time_s=time_s, covariance=True)
            seqs[family] += 1
            steps[family] += vx.size
            for name in check(res, vx, vz, time_s, paper):
                counts[(family, name)] += 1
                if len(examples[name]) < 5:
                    examples[name].append(i)
            if args.progress and (i + 1) % args.progress == 0:
                print(f"  {preset}: {i + 1} sequences, {time.perf_counter() - t0:.0f} s", flush=True)
        wall = time.perf_counter() - t0
        print()
        print(f"## preset {preset}: {sum(seqs.values())} sequences, {sum(steps.values())} steps, {wall:.1f} s")
        print()
        families = sorted(seqs)
        print("| check | " + " | ".join(f"{f} ({seqs[f]} seq, {steps[f]} steps)" for f in families) + " | all |")
        print("|---|" + "---:|" * (len(families) + 1))
        for name in CHECKS:
            row = [counts[(f, name)] for f in families]
            print(f"| {name} | " + " | ".join(str(c) for c in row) + f" | {sum(row)} |")
            if name != "numerical_restart":
                total_failures += sum(row)
        for name in CHECKS:
            if examples[name]:
                print(f"first sequences with {name}: {examples[name]} (sequence(seed={args.seed}, index, ...))")
    return 1 if total_failures else 0


if __name__ == "__main__":
    sys.exit(main())
