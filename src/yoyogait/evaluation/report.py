"""The report of an evaluation: tables, the per-recording CSV, figures and an index, written
atomically into one folder."""

from __future__ import annotations

import contextlib
import csv
import gc
import math
import os
import threading
import time
from pathlib import Path

import numpy as np

from .._files import write_folder
from ..errors import InputError
from . import figures as plots
from . import metrics
from .parallel import TaskFailure, run_tasks
from .running import Evaluation
from .tables import md_code, md_text, summary_markdown, table_one_csv, table_one_markdown

__all__ = ["write_report", "FIGURE_MODES", "SUMMARY_ABOVE", "figure_mode", "RANK_KEY"]

FIGURE_MODES = ("all", "summary", "none")
#: The reference's columns of recordings.csv (:meth:`~yoyogait.pipeline.events.ReferenceQuality.as_row`).
REFERENCE_COLUMNS = (
    "reference_origin",
    "reference_trusted",
    "reference_steps",
    "reference_cadence_hz",
    "reference_cadence_steps_per_min",
    "reference_left_right_hz",
    "reference_dft_hz",
    "reference_dft_disagreement_hz",
    "reference_dropped_contacts",
    "reference_gaps",
    "reference_reason",
)
"""Which figures a report has: every recording's, the cross-recording ones with the worst and best
recordings only, or none."""

SUMMARY_ABOVE = 36
"""Above this many recordings a report has the summary figures unless asked for all."""

RANK_KEY = "vx_sq_err_mean_1e-2"
"""The metric that ranks recordings from best to worst: Table I's v_x error."""

DISTRIBUTION_KEYS = (
    ("vx_sq_err_mean_1e-2", "v_x sq. error (1e-2 (m/s)^2)"),
    ("vz_sq_err_mean_1e-2", "v_z sq. error (1e-2 (m/s)^2)"),
    ("f_err_median_hz", "step freq. error median (Hz)"),
    ("speed_err_median_mps", "speed error median (m/s)"),
)
"""The metrics whose distribution over recordings the summary figure shows."""


def figure_mode(figures, n_recordings: int) -> str:
    """The figure mode for a report: ``figures`` as given (a mode, or True/False), else by size."""
    if figures is None or figures is True:
        return "summary" if n_recordings > SUMMARY_ABOVE else "all"
    if figures is False:
        return "none"
    if figures not in FIGURE_MODES:
        raise InputError(f"figures must be one of {', '.join(FIGURE_MODES)}, not {figures!r}")
    return figures


REPORT_NAMES = ("index.md", "recordings.csv", "figures/")
"""Names every report may write (checked before an evaluation starts: a conflict is known at once)."""

LISTED_MAX = 50
"""At most this many recordings that could not be evaluated are listed in index.md (all of them are in
``not_evaluated.csv``)."""


def _slug(text: str) -> str:
    keep = "".join(c if c.isalnum() or c in "-_." else "_" for c in text)
    return keep.strip("_.")[:120] or "recording"


def _stems(ev: Evaluation) -> dict[int, str]:
    """A file stem per recording (by id), unique in the report even when two names slug alike."""
    out: dict[int, str] = {}
    used: set[str] = set()
    for r in ev.items:
        base = stem = _slug(r.item.name)
        k = 2
        while stem.lower() in used:
            stem, k = f"{base}-{k}", k + 1
        used.add(stem.lower())
        out[id(r)] = stem
    return out


def write_report(
    evaluation: Evaluation,
    out_dir,
    *,
    force: bool = False,
    figures: bool | str | None = None,
    progress: bool = False,
    jobs: int = 1,
    option: str = "--out",
) -> Path:
    """Write tables, CSVs, figures and an index into ``out_dir``.

    ``figures``: "all" (two per recording and estimator), "summary" (the distribution of the main
    metrics over recordings, and the worst and best recording of each estimator), "none"; None or
    True chooses "summary" above :data:`SUMMARY_ABOVE` recordings, else "all". Figures are drawn
    in ``jobs`` worker processes. A figure that cannot be drawn is listed in the index and in
    ``evaluation.figure_failures``.

    Written into a temporary folder beside it and moved into place at the end, so an
    interrupted run leaves no half-written report.  ``out_dir`` may be new or empty; a
    report yoyogait wrote there before is replaced only with ``force``, and then only the
    files it lists in its marker (``.yoyogait-report``) that are still what it wrote (their
    SHA-256): the user's other files stay, and one at a name the report needs, or a link inside
    the folder, is refused before anything changes (:func:`yoyogait._files.install_folder`).  A
    non-empty folder without the marker is refused.  ``option`` names ``out`` in the messages.
    """
    mode = figure_mode(figures, len(evaluation.items))
    return write_folder(
        out_dir,
        lambda tmp: _write(evaluation, tmp, mode=mode, progress=progress, jobs=jobs),
        force=force,
        option=option,
        expected=REPORT_NAMES,
    )


def _write(ev: Evaluation, folder: Path, *, mode: str, progress: bool, jobs: int) -> None:
    label = "SYNTHETIC data (yoyogait's Yoyo-model gait lab)" if ev.synthetic else f"data set {ev.dataset}"
    md = [f"# {md_text(getattr(ev, 'title', 'yoyogait evaluation'))}: {md_text(label)}", ""]
    md += list(getattr(ev, "preamble", []))
    md += [f"Recordings evaluated: {len(ev.items)}; estimators: {', '.join(map(md_text, ev.estimators))}.", ""]
    if ev.failures:
        md += [f"Not evaluated: {len(ev.failures)} (every one in [not\\_evaluated.csv](not_evaluated.csv))", ""]
        md += [f"- {md_code(n)}: {md_text(m)}" for n, m in ev.failures[:LISTED_MAX]]
        if len(ev.failures) > LISTED_MAX:
            md.append(f"- and {len(ev.failures) - LISTED_MAX} more")
        md.append("")
        with open(folder / "not_evaluated.csv", "w", newline="", encoding="utf-8") as fh:
            problems = csv.writer(fh)
            problems.writerow(["recording", "problem"])
            problems.writerows(ev.failures)
    md += ["## Summary", "", summary_markdown(ev), ""]
    for est in ev.estimators:
        md += [
            f"## Table I, estimator {md_code(est)}",
            "",
            "Mean (± standard deviation) of the squared error of the reconstructed velocity "
            "(eq. 13-14) against the measured one over the walking part, in 10^-2 (m/s)^2.",
            "",
            table_one_markdown(ev, est),
            "",
        ]
        (folder / f"table1_{_slug(est)}.md").write_text(table_one_markdown(ev, est) + "\n")
        (folder / f"table1_{_slug(est)}.csv").write_text(table_one_csv(ev, est))
    rows = ev.rows()
    keys = ["recording", "subject", "walk", "estimator", "synthetic"] + list(
        getattr(ev, "metric_keys", metrics.METRIC_KEYS)
    )
    if rows and "cadence_steps_per_min" in rows[0]:
        keys.append("cadence_steps_per_min")  # the step frequency as clinicians give it; the Hz columns stay
    if rows and "reference_trusted" in rows[0]:
        keys += [k for k in REFERENCE_COLUMNS if any(k in row for row in rows)]
    with open(folder / "recordings.csv", "w", newline="") as fh:
        w = csv.DictWriter(fh, fieldnames=keys, extrasaction="ignore")
        w.writeheader()
        for row in rows:
            w.writerow({k: (f"{v:.6g}" if isinstance(v, float) else v) for k, v in row.items()})
    if mode != "none" and getattr(ev, "figures", True):
        md += ["## Figures", ""] + _figures(ev, folder, mode=mode, progress=progress, jobs=jobs)
    (folder / "index.md").write_text("\n".join(md) + "\n")


def _recording_task(r, est: str, figdir: Path, stem: str) -> tuple:
    """What drawing one recording's figures for one estimator needs, and nothing more (it is sent
    to a worker process)."""
    vel = r.velocities
    truth = r.item.truth
    spec = {
        "time_s": vel.time_s,
        "vx": vel.vx,
        "vz": vel.vz,
        "result": r.results[est],
        "dft_step_frequency_hz": r.dft_step_frequency_hz,
        "truth": truth,
        "reference_step_frequency_hz": None if truth is not None else r.reference_step_frequency_hz,
        "reference_quality": None if truth is not None else r.reference_quality,
        "walking": r.walking,
        "conditions": tuple(getattr(r, "conditions", ())),
        "title": f"{r.item.name} [{est}]",
        "synthetic": r.item.synthetic,
        "stem": str(figdir / f"{stem}_{_slug(est)}"),
    }
    return ("recording", spec)


def _online_task(r, est: str, figdir: Path, stem: str) -> tuple:
    """What drawing one recording's online figure needs (an online evaluation's item)."""
    vel = r.velocities
    truth = r.item.truth is not None
    spec = {
        "result": r.results[est],
        "reference_time_s": vel.time_s,
        "reference_vz_mps": vel.vz,
        "reference_step_frequency_hz": r.reference_step_frequency_hz,
        "reference_speed_mps": r.reference_speed_mps,
        "reference_walking": r.walking,
        "reference_quality": None if truth else r.reference_quality,
        "conditions": tuple(getattr(r, "conditions", ())),
        "title": f"{r.item.name} [{est}]",
        "synthetic": r.item.synthetic,
        "path": str(figdir / f"{stem}_{_slug(est)}.png"),
    }
    return ("online", spec)


_DRAWN: dict = {}
"""The last figure of each kind each thread of this process drew, by (process id, thread id, kind):
the next one is drawn into it (``into``), about twice as fast as a new figure. A figure made before
a fork is not used in the child (matplotlib's fonts cannot be used across a fork)."""


def _drawer() -> tuple[int, int]:
    return os.getpid(), threading.get_ident()


def draw_figures(kind: str, spec: dict) -> float:
    """Draw one task's figures into their files; the seconds it took. Run in worker processes."""
    start = time.perf_counter()
    me = _drawer()
    if kind == "recording":
        t = spec["time_s"]
        truth = spec["truth"]
        _DRAWN[me + ("parameter",)] = plots.parameter_figure(
            t,
            spec["result"],
            dft_step_frequency_hz=spec["dft_step_frequency_hz"],
            truth=truth,
            reference_time_s=None if truth is not None else t,
            reference_step_frequency_hz=spec["reference_step_frequency_hz"],
            walking=spec["walking"],
            reference_quality=spec["reference_quality"],
            conditions=spec["conditions"],
            title=spec["title"],
            synthetic=spec["synthetic"],
            path=spec["stem"] + "_parameters.png",
            into=_DRAWN.get(me + ("parameter",)),
        )
        _DRAWN[me + ("velocity",)] = plots.velocity_figure(
            t,
            spec["vx"],
            spec["vz"],
            spec["result"],
            walking=spec["walking"],
            conditions=spec["conditions"],
            title=spec["title"],
            synthetic=spec["synthetic"],
            path=spec["stem"] + "_velocities.png",
            into=_DRAWN.get(me + ("velocity",)),
        )
    elif kind == "online":
        plots.online_figure(**spec)
    elif kind == "distribution":
        plots.distribution_figure(spec["values"], labels=spec["labels"], title=spec["title"], path=spec["path"])
    else:
        raise ValueError(f"unknown figure task {kind!r}")
    return time.perf_counter() - start


@contextlib.contextmanager
def _collector_spared():
    """The objects alive now (most of them the evaluation's results) left out of the garbage
    collector's passes while figures are drawn in this process: the full passes over them took
    10-20 % of the time of a summary's figures. Nothing changes when something else froze objects."""
    if gc.get_freeze_count():
        yield
        return
    gc.freeze()
    try:
        yield
    finally:
        gc.unfreeze()


def _best_and_worst(ev: Evaluation, est: str, key: str = RANK_KEY) -> tuple[int, int] | None:
    """Indices of the recordings with the lowest and the highest ``key`` of ``est``."""
    values = [r.metrics[est].get(key, math.nan) for r in ev.items]
    known = [i for i, v in enumerate(values) if isinstance(v, float) and math.isfinite(v)]
    if not known:
        return None
    return min(known, key=lambda i: values[i]), max(known, key=lambda i: values[i])


def _figures(ev: Evaluation, folder: Path, *, mode: str, progress: bool, jobs: int) -> list[str]:
    figdir = folder / "figures"
    figdir.mkdir()
    tasks: list[tuple] = []
    lines: list[str] = []
    label = "SYNTHETIC data" if ev.synthetic else "recordings"
    stems = _stems(ev)
    # An online evaluation draws its own figure of the estimators that report validity; the offline
    # one two per recording and estimator, ranked by Table I's v_x error.
    online = getattr(ev, "figure_kind", "recording") == "online"
    drawn = tuple(getattr(ev, "figure_estimators", ev.estimators))
    task = _online_task if online else _recording_task
    rank_key, rank_label = getattr(ev, "rank_key", (RANK_KEY, "v_x error"))
    distribution_keys = getattr(ev, "distribution_keys", DISTRIBUTION_KEYS)

    def links(r, est: str) -> str:
        stem = f"{stems[id(r)]}_{_slug(est)}"
        if online:
            return f"[{md_text(est)} estimate](figures/{stem}.png)"
        return (
            f"[{md_text(est)}: parameters](figures/{stem}_parameters.png), [velocities](figures/{stem}_velocities.png)"
        )

    if mode == "summary":
        values = {
            est: {
                key: np.array([r.metrics[est].get(key, np.nan) for r in ev.items], float)
                for key, _ in distribution_keys
            }
            for est in ev.estimators
        }
        spec = {
            "values": values,
            "labels": dict(distribution_keys),
            "title": f"{len(ev.items)} {label}: the main metrics over recordings, per estimator",
            "path": str(figdir / "distributions.png"),
        }
        tasks.append(("distribution", spec))
        lines += [
            "Distribution over recordings of the main metrics, per estimator "
            "(box: quartiles and median; whiskers: 1.5 interquartile ranges; dots: recordings): "
            "[distributions](figures/distributions.png)",
            "",
            f"Best and worst recording of each estimator by its {rank_label} ({rank_key}):",
            "",
        ]
        for est in drawn:
            pair = _best_and_worst(ev, est, rank_key)
            if pair is None:
                lines.append(f"- {md_code(est)}: no recording with a finite {rank_label}")
                continue
            for which, i in zip(("best", "worst"), pair):
                r = ev.items[i]
                value = r.metrics[est][rank_key]
                tasks.append(task(r, est, figdir, stems[id(r)]))
                lines.append(
                    f"- {md_code(est)}, {which}: {md_code(r.item.name)} ({md_text(r.item.subject)}, {value:.3g}): "
                    + links(r, est)
                )
                if pair[0] == pair[1]:
                    break
    else:
        for r in ev.items:
            for est in drawn:
                tasks.append(task(r, est, figdir, stems[id(r)]))
            lines.append(
                f"- {md_code(r.item.name)} ({md_text(r.item.subject)}, {md_text(r.item.walk)}): "
                + "; ".join(links(r, est) for est in drawn)
            )
    plots.load_matplotlib()  # here, not in each worker process
    try:
        with _collector_spared():
            outcomes = run_tasks(draw_figures, tasks, jobs=jobs, progress="figures" if progress else None)
    finally:
        for key in [k for k in _DRAWN if k[:2] == _drawer()]:
            del _DRAWN[key]  # the figures drawn here (one job) are not kept beyond the report
    failed, seconds = [], 0.0
    for (kind, spec), outcome in zip(tasks, outcomes):
        if isinstance(outcome, TaskFailure):
            failed.append((spec.get("title") or kind, outcome.message))
        else:
            seconds += outcome
    ev.figure_failures, ev.figure_time_s = failed, seconds
    if failed:
        lines += ["", "Figures not drawn:", ""] + [f"- {md_text(n)}: {md_text(m)}" for n, m in failed]
    return lines
