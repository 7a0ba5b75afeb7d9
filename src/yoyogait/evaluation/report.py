"""The report of an evaluation: tables, the per-recording CSV, figures and an index, written
atomically into one folder."""

from __future__ import annotations

import csv
import shutil
import tempfile
from pathlib import Path

from tqdm import tqdm

from .._files import check_output_folder, install_folder, why
from .._guard import check_interrupted, signals_deferred
from ..errors import OutputError
from . import figures as plots
from . import metrics
from .running import Evaluation
from .tables import summary_markdown, table_one_csv, table_one_markdown

__all__ = ["write_report"]


def _slug(text: str) -> str:
    keep = "".join(c if c.isalnum() or c in "-_." else "_" for c in text)
    return keep.strip("_") or "recording"


def write_report(
    evaluation: Evaluation, out_dir, *, force: bool = False, figures: bool = True, progress: bool = False
) -> Path:
    """Write tables, CSVs, figures and an index into ``out_dir``.

    Written into a temporary folder beside it and moved into place at the end, so an
    interrupted run leaves no half-written report.  ``out_dir`` may be new or empty; a
    report yoyogait wrote there before is replaced only with ``force``, and then only the
    files it lists in its marker (``.yoyogait-report``): the user's other files stay.  A
    non-empty folder without the marker is refused.
    """
    out = Path(out_dir)
    check_output_folder(out, force)
    parent = out.resolve().parent
    try:
        parent.mkdir(parents=True, exist_ok=True)
        tmp = Path(tempfile.mkdtemp(prefix=f".{out.name}.", suffix=".tmp", dir=parent))
    except OSError as exc:
        raise OutputError(f"cannot write the report {out}: {why(exc)}") from None
    try:
        _write(evaluation, tmp, figures=figures, progress=progress)
        install_folder(tmp, out)
    except OutputError:
        raise
    except OSError as exc:
        raise OutputError(f"cannot write the report {out}: {why(exc, tmp)}") from None
    finally:
        with signals_deferred():  # a second signal does not cut the clean-up short
            shutil.rmtree(tmp, ignore_errors=True)
    return out


def _write(ev: Evaluation, folder: Path, *, figures: bool, progress: bool) -> None:
    label = "SYNTHETIC data (yoyogait's Yoyo-model gait lab)" if ev.synthetic else f"data set {ev.dataset}"
    md = [f"# yoyogait evaluation: {label}", ""]
    md += [f"Recordings evaluated: {len(ev.items)}; estimators: {', '.join(ev.estimators)}.", ""]
    if ev.failures:
        md += ["Not evaluated:", ""] + [f"- `{n}`: {m}" for n, m in ev.failures] + [""]
    md += ["## Summary", "", summary_markdown(ev), ""]
    for est in ev.estimators:
        md += [
            f"## Table I, estimator `{est}`",
            "",
            "Mean (± standard deviation) of the squared error of the reconstructed velocity "
            "(eq. 13-14) against the measured one over the walking part, in 10^-2 (m/s)^2.",
            "",
            table_one_markdown(ev, est),
            "",
        ]
        (folder / f"table1_{est}.md").write_text(table_one_markdown(ev, est) + "\n")
        (folder / f"table1_{est}.csv").write_text(table_one_csv(ev, est))
    rows = ev.rows()
    keys = ["recording", "subject", "walk", "estimator", "synthetic"] + list(metrics.METRIC_KEYS)
    with open(folder / "recordings.csv", "w", newline="") as fh:
        w = csv.DictWriter(fh, fieldnames=keys, extrasaction="ignore")
        w.writeheader()
        for row in rows:
            w.writerow({k: (f"{v:.6g}" if isinstance(v, float) else v) for k, v in row.items()})
    if figures:
        md += ["## Figures", ""] + _figures(ev, folder, progress=progress)
    (folder / "index.md").write_text("\n".join(md) + "\n")


def _figures(ev: Evaluation, folder: Path, *, progress: bool) -> list[str]:
    figdir = folder / "figures"
    figdir.mkdir()
    lines = []
    iterator = ev.items
    if progress:
        iterator = tqdm(ev.items, desc="figures", unit="recording", leave=False, disable=None)
    for r in iterator:
        check_interrupted()
        vel = r.velocities
        links = []
        for est in ev.estimators:
            res = r.results[est]
            stem = _slug(f"{r.item.name}_{est}")
            title = f"{r.item.name} [{est}]"
            truth = r.item.truth
            plots.parameter_figure(
                vel.time_s,
                res,
                dft_step_frequency_hz=r.dft_step_frequency_hz,
                truth=truth,
                reference_time_s=None if truth is not None else vel.time_s,
                reference_step_frequency_hz=None if truth is not None else r.reference_step_frequency_hz,
                title=title,
                synthetic=r.item.synthetic,
                path=figdir / f"{stem}_parameters.png",
            )
            plots.velocity_figure(
                vel.time_s,
                vel.vx,
                vel.vz,
                res,
                title=title,
                synthetic=r.item.synthetic,
                path=figdir / f"{stem}_velocities.png",
            )
            links.append(
                f"[{est}: parameters](figures/{stem}_parameters.png), [velocities](figures/{stem}_velocities.png)"
            )
        lines.append(f"- `{r.item.name}` ({r.item.subject}, {r.item.walk}): " + "; ".join(links))
    return lines
