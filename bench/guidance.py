"""Tethered guidance: the comparison table and its targets, at several latencies (SYNTHETIC).

    python bench/guidance.py [--latencies 0.05,0.1] [--robot-mass-kg 0.8] [--seed 0] [--no-repeat]

For each latency: every feedback source on the built-in walks (pace changes, stops, turns) of the
synthetic lab's three walkers, with the same controller gains (docs/guidance.md); the table (means
over the 9 walks) and the targets:

* yoyogait's step-frequency cable-force oscillation <= 1/3 of the raw velocity's, and below the best
  low-pass's at equal or lower lag, with a path error no worse than raw's;
* with a 50-100 ms latency, the prediction improves the force oscillation or the path error over
  the unpredicted estimate;
* deterministic: the first latency is run twice and the tables compared byte for byte.

``--robot-mass-kg 5`` runs the follow-up's virtual mass instead (``K_H = B_A^2 / (4 M_A)`` again:
the position loop stays critically damped). A benchmark, not a test: it reports what it measures,
met or not.
"""

from __future__ import annotations

import argparse
import dataclasses
import sys
import time

from yoyogait.guidance.simulation import GuidanceConfig
from yoyogait.guidance.study import run_study, table_csv, table_markdown, target_checks


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--latencies", default="0.05,0.1", help="latencies [s], comma-separated")
    ap.add_argument("--robot-mass-kg", type=float, default=0.8, help="M_A (T-RO 2021: 0.8; the follow-up: 5)")
    ap.add_argument("--seed", type=int, default=0)
    ap.add_argument("--no-repeat", action="store_true", help="skip the determinism check")
    args = ap.parse_args(argv)
    latencies = [float(v) for v in args.latencies.split(",") if v.strip()]
    base = GuidanceConfig()
    base = dataclasses.replace(
        base,
        robot_mass_kg=args.robot_mass_kg,
        position_gain_n_per_m=base.robot_damping_ns_per_m**2 / (4.0 * args.robot_mass_kg),
    )
    missed = 0
    first_csv = None
    for latency in latencies:
        config = dataclasses.replace(base, latency_s=latency)
        start = time.perf_counter()
        study = run_study(seed=args.seed, config=config)
        seconds = time.perf_counter() - start
        print(
            f"\n## Latency {latency:g} s, M_A {config.robot_mass_kg:g} kg, K_H {config.position_gain_n_per_m:.3g} N/m "
            f"(SYNTHETIC; {len(study.runs)} runs in {seconds:.1f} s)\n"
        )
        print(table_markdown(study))
        print()
        for target, met, text in target_checks(study):
            state = "not measurable" if met is None else ("met" if met else "MISSED")
            missed += met is False
            print(f"- {target}: {state} ({text})")
        if first_csv is None:
            first_csv = table_csv(study)
    if not args.no_repeat and latencies:
        config = dataclasses.replace(base, latency_s=latencies[0])
        again = table_csv(run_study(seed=args.seed, config=config))
        same = again == first_csv
        missed += not same
        print(
            f"\n- deterministic (seed {args.seed}, latency {latencies[0]:g} s, the table twice): "
            f"{'met: identical bytes' if same else 'MISSED: the tables differ'}"
        )
    print(f"\n{missed} target check(s) missed")
    return 0


if __name__ == "__main__":
    sys.exit(main())
