"""The online evaluation against its targets: medians over the shared manifest and the synthetic lab.

    python bench/online_targets.py [--datasets ../shared/datasets] [--no-real] [--jobs 2] [--per-recording]
        [--estimator-period-s 0.0085]

Every recording goes through :func:`yoyogait.evaluation.online.evaluate_item_online` (replayed frame by
frame at its capture rate through OnlineEstimator; the adaptive oscillator beside it on the offline
velocities at 25 Hz). The synthetic lab is the built-in 3 x 5 walks plus the three cadence/speed-step
walks (SYNTHETIC data), at 100 Hz. Prints one Markdown table: per target, the median over recordings
of the online estimator and of the oscillator, on the manifest and on the synthetic lab, and whether
the online estimator meets it. A benchmark, not a test; the targets are fixed here and never tuned.
"""

from __future__ import annotations

import argparse
import functools
import math
from concurrent.futures import ProcessPoolExecutor
from pathlib import Path

import numpy as np

from yoyogait import OnlineConfig
from yoyogait.errors import InputError
from yoyogait.estimators.config import EstimatorConfig
from yoyogait.evaluation.datasets import manifest_items, synthetic_items
from yoyogait.evaluation.online import evaluate_item_online, step_walk_items
from yoyogait.evaluation.running import DEFAULT_WALKING_PART, WALKING_PARTS

ROOT = Path(__file__).resolve().parents[1]

# (column, label, target, also below the oscillator's, data it applies to: "both" or "synthetic", abs)
TARGETS = (
    ("f_err_median_hz", "step freq. error after the first 3 s of walking, Hz", 0.03, True, "both", False),
    ("f_err_first3s_median_hz", "step freq. error in the first 3 s of walking, Hz", 0.05, True, "both", False),
    ("vz_sq_err_mean_1e-2", "v_z reconstruction vs offline velocity, 1e-2 (m/s)^2", 0.25, False, "both", False),
    ("vx_sq_err_mean_1e-2", "v_x reconstruction vs offline velocity, 1e-2 (m/s)^2", 0.5, False, "both", False),
    ("pred200ms_vx_sq_err_mean_1e-2", "0.2 s-ahead v_x, 1e-2 (m/s)^2", 2.5, False, "both", False),
    ("pred200ms_vz_sq_err_mean_1e-2", "0.2 s-ahead v_z, 1e-2 (m/s)^2", 0.5, False, "both", False),
    (
        "latency_vz_ms",
        "lag of v_z_hat behind the offline v_z, ms: median of the absolute lag (signed median)",
        10.0,
        False,
        "both",
        True,
    ),
    ("cadence_step_time_s", "cadence step 1.6 -> 2.0 Hz: within 0.05 Hz after, s", 1.0, False, "synthetic", False),
    ("speed_step_time_s", "speed step 1.2 -> 1.5 m/s: within 0.05 m/s after, s", 0.4, False, "synthetic", False),
    ("startup_time_s", "start-up: within 0.1 Hz after walking starts, s", 1.0, False, "synthetic", False),
    (
        "startup_from_cadence_s",
        "start-up: within 0.1 Hz after the walk reaches its cadence (the lab's 1.5 s ramp from standing), s",
        1.0,
        False,
        "synthetic",
        False,
    ),
    (
        "phase_at_contact_circstd_pct",
        "gait phase at foot contacts, circular std, % of a step",
        5.0,
        True,
        "both",
        False,
    ),
)


# Shown beside the targets, without one: the split of the reconstruction errors and the front-end's own lag.
INFO = (
    ("f_err_whole_median_hz", "step freq. error over the whole walking part, Hz"),
    ("vz_sq_err_first3s_mean_1e-2", "v_z reconstruction, first 3 s of walking, 1e-2 (m/s)^2"),
    ("vz_sq_err_after3s_mean_1e-2", "v_z reconstruction, after the first 3 s, 1e-2 (m/s)^2"),
    ("vx_sq_err_first3s_mean_1e-2", "v_x reconstruction, first 3 s of walking, 1e-2 (m/s)^2"),
    ("vx_sq_err_after3s_mean_1e-2", "v_x reconstruction, after the first 3 s, 1e-2 (m/s)^2"),
    ("speed_err_median_mps", "speed error, median, m/s"),
    ("latency_vz_input_ms", "lag of the front-end's v_z (before the estimator), ms (signed median)"),
)


def online_config(estimator_period_s=None):
    """The online settings: the defaults, or with the estimator fed every ``estimator_period_s``."""
    if estimator_period_s is None:
        return None
    config = OnlineConfig()
    config.estimator = EstimatorConfig(sample_time_s=estimator_period_s)
    return config


def _one(item, walking_part=DEFAULT_WALKING_PART, estimator_period_s=None):
    try:
        r = evaluate_item_online(item, online_config(estimator_period_s), walking_part=walking_part)
    except (InputError, ValueError) as exc:  # a recording the pipeline cannot use is reported, not fatal
        return item.name, None, str(exc)
    return item.name, r.metrics, ""


def run(items, jobs, walking_part=DEFAULT_WALKING_PART, estimator_period_s=None):
    one = functools.partial(_one, walking_part=walking_part, estimator_period_s=estimator_period_s)
    if jobs > 1:
        with ProcessPoolExecutor(jobs) as pool:
            out = list(pool.map(one, items))
    else:
        out = [one(i) for i in items]
    for name, _, problem in out:
        if problem:
            print(f"  skipped {name}: {problem}")
    return [(name, m) for name, m, _ in out if m is not None]


def median(rows, est, key, absolute):
    v = np.array([m[est][key] for _, m in rows], dtype=float)
    v = v[~np.isnan(v)]
    if absolute:
        v = np.abs(v)
    return (float(np.median(v)) if v.size else float("nan")), int(v.size)


def fmt(value, n, signed=None):
    if n == 0:
        return "n/a"
    text = "inf" if math.isinf(value) else f"{value:.3g}"
    return text + (f" ({signed:+.3g})" if signed is not None else "") + f" (n={n})"


def table(groups):
    head = "| target | " + " | ".join(f"{g} online | {g} oscillator" for g, _ in groups) + " | online meets it |"
    lines = [head, "|---|" + "---:|---:|" * len(groups) + "---|"]
    for key, label, target, below_osc, scope, absolute in TARGETS:
        cells, verdicts = [], []
        for gname, rows in groups:
            if scope == "synthetic" and not gname.startswith("synthetic"):
                cells += ["-", "-"]
                continue
            on, n_on = median(rows, "online", key, absolute)
            osc, n_osc = median(rows, "oscillator", key, absolute)
            s_on = median(rows, "online", key, False)[0] if absolute else None
            s_osc = median(rows, "oscillator", key, False)[0] if absolute else None
            cells += [fmt(on, n_on, s_on), fmt(osc, n_osc, s_osc)]
            if n_on == 0:
                verdicts.append(f"{gname}: no value")
                continue
            ok = on <= target and (not below_osc or n_osc == 0 or on < osc)
            why = "" if ok else (f" ({on:.3g} > {target:g})" if on > target else f" (not below oscillator {osc:.3g})")
            verdicts.append(f"{gname}: {'met' if ok else 'MISSED' + why}")
        rule = f"<= {target:g}" + (", below the oscillator" if below_osc else "")
        lines.append(f"| {label} {rule} | " + " | ".join(cells) + " | " + "; ".join(verdicts) + " |")
    lines += ["", "| without a target | " + " | ".join(f"{g} online | {g} oscillator" for g, _ in groups) + " |"]
    lines += ["|---|" + "---:|---:|" * len(groups)]
    for key, label in INFO:
        cells = []
        for _, rows in groups:
            for est in ("online", "oscillator"):
                cells.append(fmt(*median(rows, est, key, False)))
        lines.append(f"| {label} | " + " | ".join(cells) + " |")
    return "\n".join(lines)


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--datasets", default=str(ROOT.parent / "shared" / "datasets"))
    ap.add_argument("--no-real", action="store_true")
    ap.add_argument("--jobs", type=int, default=1)
    ap.add_argument("--per-recording", action="store_true")
    ap.add_argument(
        "--walking-part",
        choices=WALKING_PARTS,
        default=DEFAULT_WALKING_PART,
        help="the real references' walking part: from gait initiation to termination (default), or half a "
        "step either side of the contacts, the part the online targets were first measured on",
    )
    ap.add_argument(
        "--estimator-period-s",
        type=float,
        default=None,
        help="feed the estimator every this long instead of the default 0.04 s (0.0085: every frame up to 176 Hz)",
    )
    args = ap.parse_args()
    period = args.estimator_period_s
    groups = []
    if not args.no_real:
        items, missing = manifest_items(Path(args.datasets) / "manifest.json")
        for name, problem in missing:
            print(f"  missing {name}: {problem}")
        groups.append(("manifest", run(items, args.jobs, args.walking_part, period)))
    groups.append(("synthetic", run(synthetic_items() + step_walk_items(), args.jobs, estimator_period_s=period)))
    for gname, rows in groups:
        print(f"{gname}: {len(rows)} recordings")
    if args.per_recording:
        keys = [t[0] for t in TARGETS]
        print("| recording | estimator | " + " | ".join(keys) + " |")
        for _, rows in groups:
            for name, m in rows:
                for est in ("online", "oscillator"):
                    print(f"| {name} | {est} | " + " | ".join(f"{m[est][k]:.3g}" for k in keys) + " |")
    print()
    print(table(groups))


if __name__ == "__main__":
    main()
