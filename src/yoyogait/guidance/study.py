"""The comparison: every feedback source on the same guided walks, and the one table side by side."""

from __future__ import annotations

import math
from collections.abc import Callable, Sequence
from dataclasses import dataclass, field

import numpy as np

from ..synthetic import SUBJECTS, SyntheticSubject
from .metrics import METRIC_KEYS, run_metrics
from .paths import BUILTIN_WALKS, GuidePath, builtin_walk
from .simulation import GuidanceConfig, GuidanceRun, simulate
from .sources import SOURCE_NAMES, check_sources

__all__ = [
    "GuidanceStudy",
    "run_study",
    "TABLE_COLUMNS",
    "table_rows",
    "table_csv",
    "table_markdown",
    "runs_csv",
    "target_checks",
]

MIN_GAIN = 0.01
"""A source improves on another when it reduces a metric by more than this fraction."""

TABLE_COLUMNS: tuple[tuple[str, str, int], ...] = (
    ("lag_s", "lag (s)", 3),
    ("force_osc_step_n", "force osc. step+2x (N RMS)", 3),
    ("force_osc_vs_raw", "vs raw", 2),
    ("force_osc_stride_n", "force osc. stride (N RMS)", 3),
    ("robot_accel_rms_mps2", "robot acc. (m/s^2 RMS)", 3),
    ("robot_jerk_rms_mps3", "robot jerk (m/s^3 RMS)", 1),
    ("path_error_rms_m", "path err. RMS (m)", 3),
    ("path_error_max_m", "path err. max (m)", 3),
    ("overshoot_m", "overshoot (m)", 2),
    ("time_to_goal_s", "time to goal (s)", 2),
    ("force_start_peak_n", "start peak (N)", 2),
    ("force_stop_peak_n", "stop peak (N)", 2),
    ("force_turn_peak_n", "turn peak (N)", 2),
    ("slack_s", "slack (s)", 2),
    ("source_osc_mps", "source osc. (m/s RMS)", 3),
)
"""(key, header, decimals) of the table: the mean over the walks of each metric per source."""


@dataclass
class GuidanceStudy:
    """Runs and metrics of every (walk, walker, source); all SYNTHETIC."""

    sources: tuple[str, ...]
    walks: tuple[str, ...]
    walkers: tuple[str, ...]
    seed: int
    config: GuidanceConfig
    runs: list[GuidanceRun] = field(default_factory=list)
    metrics: list[dict[str, float]] = field(default_factory=list)


def run_study(
    paths: Sequence[GuidePath] | None = None,
    subjects: Sequence[SyntheticSubject] | None = None,
    sources: Sequence[str] = SOURCE_NAMES,
    *,
    seed: int = 0,
    config: GuidanceConfig | None = None,
    progress: Callable[[str], None] | None = None,
) -> GuidanceStudy:
    """Simulate every source on every walk of every walker (default: the built-in walks, the
    synthetic lab's three walkers, every source)."""
    cfg = config if config is not None else GuidanceConfig()
    paths = list(paths) if paths is not None else [builtin_walk(n) for n in BUILTIN_WALKS]
    subjects = list(subjects) if subjects is not None else list(SUBJECTS)
    names = check_sources(sources)
    study = GuidanceStudy(names, tuple(p.name for p in paths), tuple(s.name for s in subjects), int(seed), cfg)
    for path in paths:
        for subject in subjects:
            for name in names:
                if progress is not None:
                    progress(f"{path.name} / {subject.name} / {name}")
                run = simulate(path, subject, name, seed=seed, config=cfg)
                study.runs.append(run)
                study.metrics.append(run_metrics(run))
    return study


def _mean(values) -> float:
    a = np.asarray([v for v in values if math.isfinite(v)], float)
    return float(a.mean()) if a.size else math.nan


def table_rows(study: GuidanceStudy) -> list[dict]:
    """One row per source: the mean of each metric over the walks, and the force oscillation
    relative to ``raw`` (when raw was run)."""
    rows = []
    for name in study.sources:
        ms = [m for r, m in zip(study.runs, study.metrics) if r.source == name]
        row: dict = {"source": name, "runs": len(ms)}
        for key in METRIC_KEYS:
            row[key] = _mean(m[key] for m in ms)
        rows.append(row)
    raw = next((r for r in rows if r["source"] == "raw"), None)
    for row in rows:
        ref = raw["force_osc_step_n"] if raw is not None else math.nan
        row["force_osc_vs_raw"] = row["force_osc_step_n"] / ref if ref and math.isfinite(ref) else math.nan
    return rows


def _fmt(value, decimals: int) -> str:
    if isinstance(value, float) and not math.isfinite(value):
        return "n/a"
    return f"{value:.{decimals}f}"


def table_markdown(study: GuidanceStudy) -> str:
    """The table (Markdown): sources as rows, the metrics side by side."""
    rows = table_rows(study)
    head = ["source", *(h for _, h, _ in TABLE_COLUMNS)]
    lines = ["| " + " | ".join(head) + " |", "|" + "---|" * len(head)]
    for row in rows:
        cells = [f"`{row['source']}`", *(_fmt(row[k], d) for k, _, d in TABLE_COLUMNS)]
        lines.append("| " + " | ".join(cells) + " |")
    return "\n".join(lines)


def table_csv(study: GuidanceStudy) -> str:
    """The table as CSV (full precision, ``repr`` of each mean: the same seed gives the same bytes)."""
    keys = ["source", "runs", *(k for k, _, _ in TABLE_COLUMNS)]
    rows = table_rows(study)
    out = [",".join(keys)]
    for row in rows:
        out.append(",".join(str(row[k]) if k in ("source", "runs") else repr(float(row[k])) for k in keys))
    return "\n".join(out) + "\n"


def runs_csv(study: GuidanceStudy) -> str:
    """One row per (walk, walker, source) with every metric."""
    keys = ["walk", "walker", "source", "seed", "latency_s", *METRIC_KEYS]
    out = [",".join(keys)]
    for run, m in zip(study.runs, study.metrics):
        cells = [run.walk, run.walker, run.source, str(run.seed), repr(run.latency_s)]
        cells += [repr(float(m[k])) for k in METRIC_KEYS]
        out.append(",".join(c.replace(",", ";") for c in cells))
    return "\n".join(out) + "\n"


def target_checks(study: GuidanceStudy) -> list[tuple[str, bool | None, str]]:
    """The targets of docs/guidance.md on this study: (target, met (None: not measurable here), the numbers)."""
    rows = {r["source"]: r for r in table_rows(study)}
    out: list[tuple[str, bool | None, str]] = []
    yo, raw = rows.get("yoyogait"), rows.get("raw")
    if yo is not None and raw is not None:
        ratio = yo["force_osc_step_n"] / raw["force_osc_step_n"]
        out.append(
            (
                "yoyogait's step-frequency force oscillation <= 1/3 of raw's",
                bool(ratio <= 1.0 / 3.0),
                f"{yo['force_osc_step_n']:.3f} N vs {raw['force_osc_step_n']:.3f} N: ratio {ratio:.2f}",
            )
        )
        out.append(
            (
                "path error (RMS) no worse than raw's",
                bool(yo["path_error_rms_m"] <= raw["path_error_rms_m"]),
                f"{yo['path_error_rms_m']:.3f} m vs {raw['path_error_rms_m']:.3f} m",
            )
        )
    lows = [r for name, r in rows.items() if name.startswith("lowpass-")]
    if yo is not None and lows:
        peers = [r for r in lows if r["lag_s"] <= yo["lag_s"] + 1e-9]
        if peers:
            best = min(peers, key=lambda r: r["force_osc_step_n"])
            met = bool(yo["force_osc_step_n"] < best["force_osc_step_n"])
            text = (
                f"best low-pass with lag <= {yo['lag_s']:.3f} s: {best['source']} ({best['force_osc_step_n']:.3f} N, "
                f"lag {best['lag_s']:.3f} s) vs yoyogait {yo['force_osc_step_n']:.3f} N"
            )
        else:
            best = min(lows, key=lambda r: r["force_osc_step_n"])
            met = True
            text = (
                f"no low-pass has a lag <= yoyogait's {yo['lag_s']:.3f} s (shortest: "
                f"{min(r['lag_s'] for r in lows):.3f} s); the best low-pass overall, {best['source']}: "
                f"{best['force_osc_step_n']:.3f} N at lag {best['lag_s']:.3f} s "
                f"vs yoyogait {yo['force_osc_step_n']:.3f} N"
            )
        out.append(("yoyogait beats the best low-pass at equal or lower lag", met, text))
    pred = rows.get("yoyogait-predicted")
    if yo is not None and pred is not None:  # an improvement is a reduction by more than MIN_GAIN
        better_f = pred["force_osc_step_n"] < (1.0 - MIN_GAIN) * yo["force_osc_step_n"]
        better_p = pred["path_error_rms_m"] < (1.0 - MIN_GAIN) * yo["path_error_rms_m"]
        out.append(
            (
                f"with {study.config.latency_s:g} s latency, the prediction improves force oscillation or path error "
                f"(by more than {MIN_GAIN:.0%})",
                bool(better_f or better_p) if study.config.latency_s > 0 else None,
                f"force {pred['force_osc_step_n']:.4f} vs {yo['force_osc_step_n']:.4f} N, path error "
                f"{pred['path_error_rms_m']:.4f} vs {yo['path_error_rms_m']:.4f} m, lag {pred['lag_s']:.3f} vs "
                f"{yo['lag_s']:.3f} s",
            )
        )
    return out
