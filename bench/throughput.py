"""Throughput of `yoyogait evaluate`: hours of recording evaluated per second of wall time.

    python bench/throughput.py [--manifest ../shared/datasets/manifest.json] [--hours 1] [--runs 3]

The C3D recordings of the manifest, repeated until they make up ``--hours`` of recording, are
evaluated (the CLI's default estimators, paper and default) and reported, as ``yoyogait evaluate``
does, with 1 and 2 worker processes and figures none and summary. Figures all (two per recording
and estimator) are drawn for the C3D recordings once each (not repeated), to measure the wall
time per figure. Each configuration runs ``--runs`` times; the medians are printed as Markdown,
with the share of each stage (read, velocities, events, estimators, metrics, figures) in the time
the processes spent on them. Wall time counts the whole run: workers starting, evaluation, tables,
figures and the report folder.
"""

from __future__ import annotations

import argparse
import dataclasses
import math
import os
import resource
import shutil
import tempfile
import time
from pathlib import Path

import numpy as np

from yoyogait import evaluation as ev
from yoyogait.evaluation.running import STAGES

ROOT = Path(__file__).resolve().parents[1]
ESTIMATORS = ev.DEFAULT_ESTIMATORS


def c3d_items(manifest: Path):
    """The C3D items of the manifest, with their durations [s] and sample rates [Hz]."""
    items, _, _ = ev.resolve_dataset(str(manifest))
    chosen = [i for i in items if i.name.lower().endswith(".c3d")]
    durations, rates = [], []
    for item in chosen:
        rec = item.load()
        durations.append(rec.positions_m.shape[0] / rec.rate_hz)
        rates.append(rec.rate_hz)
    return chosen, np.array(durations), np.array(rates)


def replicate(items, durations, hours: float):
    """The items repeated (renamed copy by copy) until they make up ``hours`` of recording."""
    copies = max(1, math.ceil(hours * 3600.0 / durations.sum()))
    out = [dataclasses.replace(item, name=f"{k:03d}_{item.name}") for k in range(copies) for item in items]
    return out, copies * durations.sum()


def cpu_s() -> float:
    """CPU time of this process and of its children that have ended (the worker processes)."""
    own, children = resource.getrusage(resource.RUSAGE_SELF), resource.getrusage(resource.RUSAGE_CHILDREN)
    return own.ru_utime + own.ru_stime + children.ru_utime + children.ru_stime


def run_once(items, jobs: int, figures: str, folder: Path) -> dict:
    """One evaluation and report as the CLI makes them; wall and CPU time, and per-stage time."""
    out = folder / f"report-{jobs}-{figures}"
    cpu0 = cpu_s()
    start = time.perf_counter()
    result = ev.evaluate(items, ESTIMATORS, jobs=jobs, dataset="bench")
    evaluated = time.perf_counter()
    cpu1 = cpu_s()
    ev.write_report(result, out, figures=figures, jobs=jobs)
    end = time.perf_counter()
    cpu2 = cpu_s()
    stages = dict.fromkeys(STAGES, 0.0)
    for r in result.items:
        for k, v in r.timings_s.items():
            stages[k] += v
    stages["figures"] = result.figure_time_s
    n_figures = len(list((out / "figures").glob("*.png"))) if (out / "figures").exists() else 0
    if result.failures or result.figure_failures:
        raise SystemExit(f"failures: {result.failures[:3]} {result.figure_failures[:3]}")
    shutil.rmtree(out)
    return {
        "wall_s": end - start,
        "evaluate_s": evaluated - start,
        "report_s": end - evaluated,
        "cpu_s": cpu2 - cpu0,
        "report_cpu_s": cpu2 - cpu1,
        "stages": stages,
        "figures": n_figures,
    }


def median_of(runs: list[dict]) -> dict:
    return {
        "wall_s": float(np.median([r["wall_s"] for r in runs])),
        "evaluate_s": float(np.median([r["evaluate_s"] for r in runs])),
        "report_s": float(np.median([r["report_s"] for r in runs])),
        "cpu_s": float(np.median([r["cpu_s"] for r in runs])),
        "report_cpu_s": float(np.median([r["report_cpu_s"] for r in runs])),
        "stages": {k: float(np.median([r["stages"][k] for r in runs])) for k in runs[0]["stages"]},
        "figures": runs[0]["figures"],
    }


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--manifest", type=Path, default=ROOT.parent / "shared" / "datasets" / "manifest.json")
    ap.add_argument("--hours", type=float, default=1.0, help="hours of recording to evaluate")
    ap.add_argument("--runs", type=int, default=3, help="runs per configuration (medians)")
    ap.add_argument("--jobs", default="1,2", help="worker counts to compare")
    args = ap.parse_args()

    items, durations, rates = c3d_items(args.manifest)
    hour_items, seconds = replicate(items, durations, args.hours)
    hours = seconds / 3600.0
    print(
        f"{len(items)} C3D recordings ({durations.sum():.1f} s, {rates.min():.0f}-{rates.max():.0f} Hz, "
        f"mean {np.average(rates, weights=durations):.0f} Hz by duration) x {len(hour_items) // len(items)} "
        f"= {len(hour_items)} recordings, {hours:.3f} h; estimators {', '.join(ESTIMATORS)}; "
        f"medians of {args.runs} runs; load average before: {os.getloadavg()[0]:.1f} on {os.cpu_count()} cores\n"
    )
    jobs_list = [int(j) for j in args.jobs.split(",")]
    rows = []
    with tempfile.TemporaryDirectory(prefix="yoyogait-bench-") as tmp:
        folder = Path(tmp)
        for figures in ("none", "summary"):
            for jobs in jobs_list:
                m = median_of([run_once(hour_items, jobs, figures, folder) for _ in range(args.runs)])
                rows.append((f"{hours:.2f} h ({len(hour_items)} rec.)", jobs, figures, m, hours))
        for jobs in jobs_list:
            m = median_of([run_once(items, jobs, "all", folder) for _ in range(args.runs)])
            rows.append((f"{durations.sum() / 3600:.3f} h ({len(items)} rec.)", jobs, "all", m, durations.sum() / 3600))

    print(f"load average after: {os.getloadavg()[0]:.1f}\n")
    print(
        "| data | jobs | figures | wall (s) | CPU (s) | h of recording / s | wall s per h of recording | "
        "figures drawn | wall per figure (s) | CPU per figure (s) | "
        + " | ".join(f"{s} %" for s in (*STAGES, "figures"))
        + " |"
    )
    print("|---|---:|---|---:|---:|---:|---:|---:|---:|---:|" + "---:|" * (len(STAGES) + 1))
    for label, jobs, figures, m, h in rows:
        total = sum(m["stages"].values()) or 1.0
        shares = " | ".join(f"{100 * m['stages'][s] / total:.1f}" for s in (*STAGES, "figures"))
        per_fig = f"{m['report_s'] / m['figures']:.3f}" if m["figures"] else "-"
        cpu_fig = f"{m['report_cpu_s'] / m['figures']:.3f}" if m["figures"] else "-"
        print(
            f"| {label} | {jobs} | {figures} | {m['wall_s']:.2f} | {m['cpu_s']:.2f} | {h / m['wall_s']:.3f} | "
            f"{m['wall_s'] / h:.2f} | {m['figures']} | {per_fig} | {cpu_fig} | {shares} |"
        )
    print(
        "\nCPU: this process and its worker processes. Per figure: the report's time (tables, figures, "
        "folder) over the figures drawn. Stage shares: of the time the processes spent in each stage "
        "(summed over workers)."
    )


if __name__ == "__main__":
    main()
