"""Honesty of the online estimate: is it right, or does it say that it may not be?

    python bench/online_honesty.py [--datasets DIR] [--no-real] [--jobs 2] [--per-recording] [--seed 0]
        [--estimator-period-s 0.0085]

Every recording is replayed frame by frame through OnlineEstimator
(:func:`yoyogait.evaluation.online.evaluate_item_online`) and scored over its whole walking part,
its first seconds included:

* the shared manifest (``--datasets``, default ``$YOYOGAIT_DATASETS`` or ../shared/datasets), as recorded;
* the SYNTHETIC renderings of :mod:`yoyogait.synthetic_conditions` (markerless capture at 30 and
  60 Hz, treadmill, stand-walk-stop bouts, tight turns, very slow walking; sit-to-stand, brisk chair
  stands, standing sway, turning on the spot, shuffling and arm gestures, which are not walking), each
  for the three built-in subjects,
  and the standing sway with markerless noise at 30 Hz; the arm gestures and the stand-walk-stop,
  turns and very slow walks also following the hand (the point a tether or handle is held by);
* the shared recordings re-rendered as a markerless capture would give them (SYNTHETIC noise,
  :func:`~yoyogait.synthetic_conditions.markerless_noise`: 2 cm jitter, swaps, dropouts, every k-th
  frame towards 60 Hz), scored against the clean recording's references.

Printed, as Markdown (the manifest over every recording and over those whose reference is trusted),
the median AND the worst recording of: the 2-std coverage of step frequency
and speed, the confidently-wrong share of walking (error above 0.15 Hz or 0.15 m/s while valid and
more than 2 std), the valid share of steady walking (after the first 3 s); on the markerless
re-renderings the step-frequency error after 3 s and the front-end's highest horizontal speed while
walking; on the treadmill renderings (and the manifest's treadmill recordings) the online speed error
without feet or belt, with the heels in the frames (the belt from the stance feet) and with the belt
speed given;
on the not-walking renderings the share of their time reported as walking; the sharpness of the
stds while valid (their median beside the 95th percentile of the errors then); for reference, the
valid share of the walking at least 3 s into its bout (a bout starts after 1 s or more of
standing). The targets are printed beside them, fixed here. "valid" is the online result's
``valid`` where it has one, else ``walking`` (:func:`yoyogait.evaluation.online.validity`). A
benchmark, not a test.
"""

from __future__ import annotations

import argparse
import dataclasses
import functools
import math
import os
import sys
import time
from pathlib import Path

import numpy as np

from online_targets import online_config  # a script beside this one
from yoyogait import synthetic as sy
from yoyogait import synthetic_conditions as sc
from yoyogait.errors import InputError
from yoyogait.evaluation.datasets import manifest_items, synthetic_item
from yoyogait.evaluation.online import evaluate_item_online, validity
from yoyogait.evaluation.parallel import TaskFailure, run_tasks
from yoyogait.evaluation.tables import trusted

ROOT = Path(__file__).resolve().parents[1]
MARKERLESS_RATE_HZ = 60.0
STANDING_MARKERLESS = "SYNTHETIC standing-sway, markerless noise at 30 Hz"
TREADMILL_FEET = "SYNTHETIC treadmill, heels in the frames"
TREADMILL_KNOWN = "SYNTHETIC treadmill, belt speed given"
TREADMILL_REAL_FEET = "manifest treadmill recordings, heels in the frames"
MANIFEST_FEET = "manifest, heels in the frames (the recordings with feet)"
MARKERLESS_FEET = "markerless re-rendering, heels in the frames (the recordings with feet)"
MARKERLESS_FEET_TRUSTED = "markerless re-rendering, heels in the frames, trusted references"
MARKERLESS_SYNTHETIC_FEET = "SYNTHETIC markerless 30 and 60 Hz, heels in the frames"
MANIFEST_TRUSTED = "manifest, trusted references"
GESTURES_HAND = "SYNTHETIC arm-gestures, following the hand"
WALKS_HAND = "SYNTHETIC stand-walk-stop, turns, very-slow, following the hand"

# (column, label, target, higher is better)
HONESTY = (
    ("f_cover2std_fraction", "f within 2 std", 0.90, True),
    ("speed_cover2std_fraction", "speed within 2 std", 0.90, True),
    ("confidently_wrong_fraction", "confidently wrong", 0.01, False),
    ("valid_after3s_fraction", "valid after 3 s", 0.80, True),
)


def _markerless(load, seed: int):
    return sc.markerless_noise(load(), seed=seed, rate_hz=MARKERLESS_RATE_HZ)


def markerless_item(item, seed: int):
    """The item with its recording re-rendered as a markerless capture (SYNTHETIC noise)."""
    return dataclasses.replace(
        item, name=f"{item.name} + markerless", load=functools.partial(_markerless, item.load, seed)
    )


def score(item, reference=None, options=None) -> dict:
    """One recording's online columns, and the walking and valid shares of its whole time and of its
    walking time (the reference's walking on the frames). ``options``: evaluate_item_online's treadmill
    inputs (feet, belt_speed_mps)."""
    options = dict(options or {})
    config = online_config(options.pop("estimator_period_s", None))
    r = evaluate_item_online(item, config, reference=reference, **options)
    res = r.results["online"]
    t = np.asarray(res.time_s, dtype=float)
    ref_walk = np.interp(t, r.velocities.time_s, r.walking.astype(float), left=0, right=0) > 0.5
    walking, valid = np.asarray(res.walking, dtype=bool), validity(res)
    row = dict(r.metrics["online"])
    row["walking_share_all"] = float(walking.mean()) if walking.size else math.nan
    row["valid_share_all"] = float(valid.mean()) if valid.size else math.nan
    row["walking_share_of_walking"] = float(walking[ref_walk].mean()) if ref_walk.any() else math.nan
    bout = bout_after_s(t, ref_walk, 3.0)
    row["valid_bout_after3s_fraction"] = float(valid[bout].mean()) if bout.any() else math.nan
    row["reference_trusted"] = trusted(r)
    return row


def bout_after_s(t, walking, after_s: float, min_stop_s: float = 1.0):
    """The walking frames at least after_s into their bout: a bout starts after min_stop_s or more
    of not walking (a shorter pause continues it)."""
    out = np.zeros_like(walking, dtype=bool)
    idx = np.flatnonzero(walking)
    if idx.size == 0:
        return out
    start = t[idx[0]]
    for prev, i in zip(np.r_[idx[0], idx[:-1]], idx):
        if t[i] - t[prev] >= min_stop_s:
            start = t[i]
        out[i] = t[i] >= start + after_s
    return out


def task(group: str, item, reference, options=None):
    try:
        return group, item.name, score(item, reference, options), ""
    except (InputError, ValueError) as exc:
        return group, item.name, None, str(exc)


def median_worst(rows, key, higher_is_better):
    vals = [(r[key], n) for n, r in rows if not math.isnan(r[key])]
    if not vals:
        return "n/a", "n/a", 0
    v = np.array([x for x, _ in vals])
    i = int(np.argmin(v) if higher_is_better else np.argmax(v))
    return f"{np.median(v):.3g}", f"{v[i]:.3g} ({short(vals[i][1])})", len(vals)


def short(name: str, width: int = 44) -> str:
    return name if len(name) <= width else name[: width - 3] + "..."


def verdict(rows, key, target, higher_is_better):
    vals = np.array([r[key] for _, r in rows if not math.isnan(r[key])])
    if vals.size == 0:
        return "no value"
    worst = vals.min() if higher_is_better else vals.max()
    ok = worst >= target if higher_is_better else worst <= target
    bad = int(np.sum(vals < target) if higher_is_better else np.sum(vals > target))
    return "met" if ok else f"MISSED on {bad} of {vals.size}"


def honesty_table(groups) -> list[str]:
    head = " | ".join(f"{label} median | worst" for _, label, _, _ in HONESTY)
    rule = "; ".join(f"{label} {'>=' if hb else '<='} {t:g}" for _, label, t, hb in HONESTY)
    lines = [
        "Over the whole walking part including its first seconds (valid: after 3 s). "
        f"Targets on every recording: {rule}.",
        "",
        f"| recordings | n | {head} | targets |",
        "|---|---:|" + "---:|---|" * len(HONESTY) + "---|",
    ]
    for gname, rows in groups:
        if not rows:
            continue
        cells, verdicts = [], []
        for key, label, target, hb in HONESTY:
            med, worst, _ = median_worst(rows, key, hb)
            cells += [med, worst]
            v = verdict(rows, key, target, hb)
            if v != "met":
                verdicts.append(f"{label}: {v}")
        lines.append(f"| {gname} | {len(rows)} | " + " | ".join(cells) + f" | {'; '.join(verdicts) or 'met'} |")
    return lines


def simple_table(title, groups, columns) -> list[str]:
    head = " | ".join(f"{label} median | worst" for _, label, _, _ in columns)
    lines = [title, "", f"| recordings | n | {head} |", "|---|---:|" + "---:|---|" * len(columns)]
    for gname, rows in groups:
        if not rows:
            continue
        cells = []
        for key, _, _, hb in columns:
            med, worst, _ = median_worst(rows, key, hb)
            cells += [med, worst]
        lines.append(f"| {gname} | {len(rows)} | " + " | ".join(cells) + " |")
    tgt = "; ".join(f"{label}: {t}" for _, label, t, _ in columns if t)
    return lines + ([f"\nTargets: {tgt}."] if tgt else [])


def main():
    default_data = os.environ.get("YOYOGAIT_DATASETS") or str(ROOT.parent / "shared" / "datasets")
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--datasets", default=default_data)
    ap.add_argument("--no-real", action="store_true")
    ap.add_argument("--jobs", type=int, default=2)
    ap.add_argument("--seed", type=int, default=0)
    ap.add_argument("--per-recording", action="store_true")
    ap.add_argument(
        "--estimator-period-s",
        type=float,
        default=None,
        help="feed the estimator every this long instead of the default 0.04 s (0.0085: every frame up to 176 Hz)",
    )
    args = ap.parse_args()
    start = time.perf_counter()
    tasks = []
    treadmill_real = set()
    if not args.no_real:
        manifest = Path(args.datasets) / "manifest.json"
        if not manifest.is_file():
            sys.exit(f"no manifest at {manifest}: give --datasets or set YOYOGAIT_DATASETS (or --no-real)")
        items, missing = manifest_items(manifest)
        for name, problem in missing:
            print(f"  missing {name}: {problem}")
        for item in items:
            tasks.append(("manifest", item, None))
            tasks.append(("markerless re-rendering of the manifest", markerless_item(item, args.seed), item))
            if item.feet:  # overground the heels check the cadence; on a treadmill they give the belt
                tasks.append((MANIFEST_FEET, item, None, {"feet": True}))
                tasks.append((MARKERLESS_FEET, markerless_item(item, args.seed), item, {"feet": True}))
            if item.walk == "treadmill" and item.feet:
                treadmill_real.add(item.name)
    for walk in sc.condition_walks(seed=args.seed):
        tasks.append((f"SYNTHETIC {walk.walk_type}", synthetic_item(walk), None))
        if walk.walk_type.startswith("markerless"):  # the feet's steps check the lock
            tasks.append((MARKERLESS_SYNTHETIC_FEET, synthetic_item(walk), None, {"feet": True}))
        if walk.walk_type == "treadmill":  # the same walks with the heels in the frames, and with the belt given
            tasks.append((TREADMILL_FEET, synthetic_item(walk), None, {"feet": True}))
            belt = {"belt_speed_mps": float(walk.recording.metadata["belt_speed_mps"])}
            tasks.append((TREADMILL_KNOWN, synthetic_item(walk), None, belt))
        if walk.walk_type in ("arm-gestures", "stand-walk-stop", "turns", "very-slow"):  # the hand followed
            hand = dataclasses.replace(synthetic_item(walk), pelvis=[sy.HAND_MARKER])
            tasks.append((GESTURES_HAND if walk.walk_type == "arm-gestures" else WALKS_HAND, hand, None))
        if walk.walk_type == "standing-sway":  # standing seen by a markerless camera at 30 Hz
            rec = sc.markerless_noise(walk.recording, seed=args.seed, rate_hz=30.0)
            noisy = dataclasses.replace(walk, recording=rec, truth=walk.truth.at(rec.time_s))
            tasks.append((STANDING_MARKERLESS, synthetic_item(noisy), None))
    if args.estimator_period_s is not None:
        period = {"estimator_period_s": args.estimator_period_s}
        tasks = [(g, i, r, {**(rest[0] if rest else {}), **period}) for g, i, r, *rest in tasks]
    outcomes = run_tasks(task, tasks, jobs=args.jobs)
    by_group: dict[str, list] = {}
    for (group, item, *_), out in zip(tasks, outcomes):
        if isinstance(out, TaskFailure):
            print(f"  failed {item.name}: {out.message}")
            continue
        _, name, row, problem = out
        if row is None:
            print(f"  skipped {name}: {problem}")
            continue
        by_group.setdefault(group, []).append((name, row))
    walking_groups = (
        ["manifest", "markerless re-rendering of the manifest"]
        + [f"SYNTHETIC {c}" for c in sc.CONDITIONS if c not in sc.NOT_WALKING]
        + [MANIFEST_FEET, MARKERLESS_FEET, MARKERLESS_SYNTHETIC_FEET, TREADMILL_FEET, TREADMILL_KNOWN]
    )
    groups = by_group
    # Honesty is judged against the references that the reference's quality check
    # trusts (pipeline/events.py; a SYNTHETIC truth always is); the row over every recording stays.
    trusted_rows = [(n, r) for n, r in groups.get("manifest", []) if r["reference_trusted"]]
    groups[MANIFEST_TRUSTED] = trusted_rows
    walking_groups.insert(1, MANIFEST_TRUSTED)
    trusted_names = {n for n, _ in trusted_rows}
    groups[MARKERLESS_FEET_TRUSTED] = [
        (n, r) for n, r in groups.get(MARKERLESS_FEET, []) if n.removesuffix(" + markerless") in trusted_names
    ]
    walking_groups.insert(walking_groups.index(MARKERLESS_FEET) + 1, MARKERLESS_FEET_TRUSTED)
    print(f"{sum(len(r) for r in groups.values())} recordings in {time.perf_counter() - start:.0f} s\n")
    print("## Honesty (online estimate; the synthetic renderings: 3 subjects each)\n")
    print("\n".join(honesty_table([(g, groups.get(g, [])) for g in walking_groups])))
    print()
    print(
        "\n".join(
            simple_table(
                "## Sharpness: the stds a controller gating on valid is given, beside the errors then",
                [(g, groups.get(g, [])) for g in walking_groups],
                (
                    ("f_std_valid_median_hz", "f std while valid, Hz", None, False),
                    ("f_err_valid_p95_hz", "f error while valid, 95th pct., Hz", None, False),
                    ("speed_std_valid_median_mps", "speed std while valid, m/s", None, False),
                    ("speed_err_valid_p95_mps", "speed error while valid, 95th pct., m/s", None, False),
                ),
            )
        )
    )
    print("(no target: a calibrated std has 2 std near the 95th percentile of the error; worst = widest)\n")
    clean = {n: r for n, r in groups.get("manifest", [])}
    noisy = groups.get("markerless re-rendering of the manifest", [])
    pairs = [(n, r) for n, r in noisy if n.removesuffix(" + markerless") in clean]
    pairs_feet = [(n, r) for n, r in groups.get(MARKERLESS_FEET, []) if n.removesuffix(" + markerless") in clean]
    print(
        "\n".join(
            simple_table(
                "## Markerless re-renderings of the shared recordings (2 cm jitter, swaps, dropouts, towards 60 Hz)",
                [
                    ("as recorded", groups.get("manifest", [])),
                    ("markerless re-rendering", pairs),
                    ("markerless re-rendering, heels in the frames", pairs_feet),
                ],
                (
                    ("f_err_median_hz", "f error after 3 s, Hz", 0.04, False),
                    ("frontend_speed_max_mps", "front-end speed while walking, highest, m/s", 3.0, False),
                ),
            )
        )
    )
    print("(f error: median <= 0.04 Hz; front-end speed: never above 3 m/s, on every recording)\n")
    real_treadmill = [(n, r) for n, r in groups.get("manifest", []) if n in treadmill_real]
    treadmill = [
        ("SYNTHETIC treadmill, neither feet nor belt", groups.get("SYNTHETIC treadmill", [])),
        (TREADMILL_FEET, groups.get(TREADMILL_FEET, [])),
        (TREADMILL_KNOWN, groups.get(TREADMILL_KNOWN, [])),
        ("manifest treadmill recordings, neither feet nor belt", real_treadmill),
        (TREADMILL_REAL_FEET, [(n, r) for n, r in groups.get(MANIFEST_FEET, []) if n in treadmill_real]),
    ]
    print(
        "\n".join(
            simple_table(
                "## Treadmill: online speed error (without feet or belt the speed is not valid: NOT_MOVING)",
                treadmill,
                (
                    ("speed_err_median_mps", "speed error, whole walking, m/s", 0.05, False),
                    ("speed_err_after3s_median_mps", "speed error after 3 s, m/s", None, False),
                    ("valid_after3s_fraction", "valid after 3 s", None, True),
                ),
            )
        )
    )
    print("(median <= 0.05 m/s)\n")
    print(
        "\n".join(
            simple_table(
                "## Not walking: share of the time reported walking (target <= 0.05 on every recording)",
                [(f"SYNTHETIC {c}", groups.get(f"SYNTHETIC {c}", [])) for c in sc.NOT_WALKING]
                + [(g, groups.get(g, [])) for g in (STANDING_MARKERLESS, GESTURES_HAND)],
                (
                    ("walking_share_all", "walking", 0.05, False),
                    ("valid_share_all", "valid", None, False),
                ),
            )
        )
    )
    print()
    print(
        "\n".join(
            simple_table(
                "## Walking detected, share of the walking time (for reference)",
                [(g, groups.get(g, [])) for g in [*walking_groups, WALKS_HAND]],
                (("walking_share_of_walking", "walking detected", None, True),),
            )
        )
    )
    print(
        "\n".join(
            simple_table(
                "## Valid share of the walking after the first 3 s of each bout (for reference)",
                [(g, groups.get(g, [])) for g in walking_groups],
                (("valid_bout_after3s_fraction", "valid, 3 s into its bout", None, True),),
            )
        )
    )
    print(
        "(a bout starts after 1 s or more of standing; the honesty table's valid after 3 s counts from "
        "the recording's first step, so a stand-walk-stop trial's later bouts count from their first step)\n"
    )
    if args.per_recording:
        keys = [h[0] for h in HONESTY] + [
            "f_err_median_hz",
            "frontend_speed_max_mps",
            "speed_err_median_mps",
            "walking_share_all",
        ]
        print("\n| group | recording | " + " | ".join(keys) + " |")
        print("|---|---|" + "---:|" * len(keys))
        for g, rows in groups.items():
            for n, r in rows:
                print(f"| {g} | {n} | " + " | ".join(f"{r[k]:.3g}" for k in keys) + " |")


if __name__ == "__main__":
    main()
