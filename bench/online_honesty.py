"""Whether the online estimates are right or say that they may not be: per recording, over its walking part.

    python bench/online_honesty.py [--datasets ../shared/datasets] [--no-real] [--jobs 2] [--per-recording]
                                   [--set max_mean_nis=8 ...]   (online settings other than the defaults)

Every recording is replayed frame by frame through OnlineEstimator (its defaults) and compared, at each
frame, with the references of the online evaluation (yoyogait.evaluation.online: the truth of the
SYNTHETIC lab, the offline references of the shared manifest). Per recording, over the frames where the
reference says walking:

- ``cov_f``, ``cov_speed``: 2-std coverage, the fraction of frames with |error| <= 2 std (whole walking part);
- ``wrong``: the confidently-wrong fraction, frames that are ``valid`` with an error above 0.15 Hz (f) or
  0.15 m/s (speed) larger than 2 std;
- ``valid_steady``: the fraction of frames valid after the first 3 s of each walking bout;
- ``wrong_first3s``: the confidently-wrong fraction within the first 3 s of each bout.

Prints one Markdown table: the median and the worst recording of each, against the targets (coverage
>= 90 %, wrong <= 1 % on every recording, valid >= 80 % of steady walking). A benchmark, not a test.
"""

from __future__ import annotations

import argparse
import math
from concurrent.futures import ProcessPoolExecutor
from pathlib import Path

import numpy as np

from yoyogait.errors import InputError
from yoyogait.estimators.config import OnlineConfig
from yoyogait.estimators.online import OnlineEstimator
from yoyogait.evaluation.datasets import manifest_items, synthetic_items
from yoyogait.evaluation.online import RATE_HZ, _references, step_walk_items
from yoyogait.pipeline import gait_velocities

ROOT = Path(__file__).resolve().parents[1]
F_WRONG_HZ, SPEED_WRONG_MPS, STEADY_AFTER_S = 0.15, 0.15, 3.0

# (column, label, target, "min" (worst is the smallest) or "max")
TARGETS = (
    ("cov_f", "2-std coverage of f, %", 90.0, "min"),
    ("cov_speed", "2-std coverage of speed, %", 90.0, "min"),
    ("wrong", "confidently wrong, % of walking", 1.0, "max"),
    ("wrong_first3s", "confidently wrong in the first 3 s of walking, %", 1.0, "max"),
    ("valid_steady", "valid, % of walking after 3 s", 80.0, "min"),
)


def _since_bout_start(t: np.ndarray, walking: np.ndarray) -> np.ndarray:
    """Per frame: time since the start of its walking bout (inf outside walking)."""
    out = np.full(len(t), np.inf)
    start = None
    for i, w in enumerate(walking):
        if w:
            start = t[i] if start is None else start
            out[i] = t[i] - start
        else:
            start = None
    return out


def score(item, overrides=None) -> dict:
    """The honesty figures of one item (percentages), with the online settings ``overrides``."""
    recording = item.load()
    point = item.pelvis if item.pelvis else None
    vel = gait_velocities(recording, point=point, rate_hz=RATE_HZ, up_axis=item.up_axis)
    config = OnlineConfig.from_dict({"online": dict(overrides)}) if overrides else None
    est = OnlineEstimator.for_recording(recording, point, up_axis=vel.up_axis, config=config)
    res = est.run(recording, predict_ahead_s=())
    t = np.asarray(res.time_s, dtype=float)
    dt = np.diff(t)
    if not np.any(dt > 0):
        raise InputError(f"{item.name}: fewer than two frames with increasing times")
    ref = _references(recording, vel, item, t, 1.0 / float(np.median(dt[dt > 0])))
    walking = ref.walking & np.isfinite(ref.f_ref) & np.isfinite(ref.speed_ref)
    if not walking.any():
        raise InputError(f"{item.name}: no walking with references")
    err_f = np.abs(res.step_frequency_hz - ref.f_ref)
    err_s = np.abs(res.speed_mps - ref.speed_ref)
    cov_f = err_f <= 2.0 * res.step_frequency_std_hz
    cov_s = err_s <= 2.0 * res.speed_std_mps
    valid = res.valid.astype(bool)
    wrong = valid & (((err_f > F_WRONG_HZ) & ~cov_f) | ((err_s > SPEED_WRONG_MPS) & ~cov_s))
    since = _since_bout_start(t, walking)
    steady, first = walking & (since >= STEADY_AFTER_S), walking & (since < STEADY_AFTER_S)

    def pct(x, m):
        return 100.0 * float(np.mean(x[m])) if m.any() else math.nan

    return {
        "cov_f": pct(cov_f, walking),
        "cov_speed": pct(cov_s, walking),
        "wrong": pct(wrong, walking),
        "wrong_first3s": pct(wrong, first),
        "valid_steady": pct(valid, steady),
    }


def _one(args):
    item, overrides = args
    try:
        return item.name, score(item, overrides), ""
    except (InputError, ValueError) as exc:
        return item.name, None, str(exc)


def run(items, jobs, overrides=None):
    work = [(i, overrides) for i in items]
    if jobs > 1:
        with ProcessPoolExecutor(jobs) as pool:
            return list(pool.map(_one, work))
    return [_one(w) for w in work]


def table(name: str, rows) -> list[str]:
    done = [(n, m) for n, m, _ in rows if m is not None]
    lines = [f"### {name}: {len(done)} recordings", "", "| figure | target | median | worst | worst recording | met |"]
    lines.append("|---|---|---|---|---|---|")
    for key, label, target, kind in TARGETS:
        vals = [(m[key], n) for n, m in done if not math.isnan(m[key])]
        if not vals:
            continue
        med = float(np.median([v for v, _ in vals]))
        worst, who = (min if kind == "min" else max)(vals)
        ok = worst >= target if kind == "min" else worst <= target
        sign = ">=" if kind == "min" else "<="
        lines.append(f"| {label} | {sign} {target:g} | {med:.1f} | {worst:.1f} | {who} | {'yes' if ok else 'no'} |")
    for n, _, why in rows:
        if why:
            lines.append(f"\nnot scored: {n}: {why}")
    return lines + [""]


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--datasets", type=Path, default=ROOT.parent / "shared" / "datasets")
    ap.add_argument("--no-real", action="store_true")
    ap.add_argument("--jobs", type=int, default=1)
    ap.add_argument("--per-recording", action="store_true")
    ap.add_argument("--set", action="append", default=[], metavar="NAME=VALUE", help="an online setting")
    args = ap.parse_args()
    overrides = tuple((k, float(v)) for k, v in (s.split("=", 1) for s in args.set))
    groups = [("SYNTHETIC lab", synthetic_items() + step_walk_items())]
    if not args.no_real and args.datasets.is_dir():
        groups.append(("shared manifest", manifest_items(args.datasets / "manifest.json")[0]))
    for name, items in groups:
        rows = run(items, args.jobs, overrides)
        print("\n".join(table(name, rows)))
        if args.per_recording:
            keys = [k for k, *_ in TARGETS]
            print("| recording | " + " | ".join(keys) + " |")
            print("|---|" + "---|" * len(keys))
            for n, m, _ in rows:
                if m is not None:
                    print(f"| {n} | " + " | ".join(f"{m[k]:.1f}" for k in keys) + " |")
            print()


if __name__ == "__main__":
    main()
