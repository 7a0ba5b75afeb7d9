"""``yoyogait evaluate``: estimators side by side over a data set, with Table I, CSVs and figures."""

from __future__ import annotations

import dataclasses
import functools
from pathlib import Path

import click

from .. import evaluation as ev
from .. import io
from .._files import check_output_folder
from .._guard import check_interrupted, output_lock
from ..errors import InputError
from .options import ESTIMATOR_NAMES, check_points, estimators_option, force_option, input_options


def estimator_list(value: str) -> tuple[str, ...]:
    names = tuple(n.strip() for n in value.split(",") if n.strip())
    if not names:
        raise InputError("--estimators needs at least one name")
    unknown = [n for n in names if n not in ESTIMATOR_NAMES]
    if unknown:
        raise InputError(
            f"--estimators: unknown estimator(s) {', '.join(unknown)}; known: {', '.join(ESTIMATOR_NAMES)}"
        )
    return names


class _Checked:
    """The items of a data set, with a check for a (maybe swallowed) interrupt before each."""

    def __init__(self, items):
        self.items = list(items)

    def __len__(self) -> int:
        return len(self.items)

    def __iter__(self):
        for item in self.items:
            check_interrupted()
            yield item


def _load_checked(load, point, feet):
    """load(), then an InputError naming --point or --feet if the recording lacks those points."""
    recording = load()
    check_points(recording, point, feet)
    return recording


def with_overrides(items, *, point=None, feet=None, up_axis=None, length_unit_m=None, rate_hz=None):
    """The items with the command line's input options applied to every one (they win over a manifest's)."""
    read_overrides = {k: v for k, v in (("length_unit_m", length_unit_m), ("rate_hz", rate_hz)) if v is not None}
    if up_axis is not None:
        read_overrides["up_axis"] = up_axis
    out = []
    for item in items:
        changes: dict = {}
        if point is not None:
            changes["pelvis"] = point  # a name, "pelvis", "hand", or names to average
        if feet is not None:
            changes["feet"] = list(feet)
        if up_axis is not None:
            changes["up_axis"] = up_axis
        if read_overrides:
            load = item.load
            if not isinstance(load, functools.partial) or load.func is not io.read:
                raise InputError("--up-axis, --length-unit-m and --rate-hz apply to files, not to the synthetic lab")
            changes["load"] = functools.partial(io.read, *load.args, **{**load.keywords, **read_overrides})
        if point is not None or feet is not None:
            changes["load"] = functools.partial(_load_checked, changes.get("load", item.load), point, feet)
        out.append(dataclasses.replace(item, **changes))
    return out


def run_evaluation(dataset, out, estimators, force, figures, seed, overrides=None):
    """Evaluate, print the summary and Table I, write the report; returns the evaluation.

    The whole run holds the lock on ``out`` (a second run on it fails at once), and the report is
    moved into place as the last step, after everything is printed.
    """
    names = ev.check_estimators(estimator_list(estimators))
    check_output_folder(out, force)
    with output_lock(out):
        check_output_folder(out, force)  # again: a run that just finished may have written it
        items, problems, synthetic = ev.resolve_dataset(dataset, seed=seed)
        if overrides:
            items = with_overrides(items, **overrides)
        label = "SYNTHETIC data (yoyogait's Yoyo-model gait lab)" if synthetic else str(dataset)
        click.echo(f"Evaluating {', '.join(names)} on {len(items)} recordings: {label}", err=True)
        result = ev.evaluate(
            _Checked(items),
            names,
            progress=True,
            dataset=str(dataset or "synthetic"),
            synthetic=synthetic,
            failures=problems,
        )
        if not result.items:
            raise InputError("no recording could be evaluated: " + "; ".join(f"{n}: {m}" for n, m in result.failures))
        click.echo(f"\n{label}\n")
        click.echo(ev.summary_markdown(result))
        for name in names:
            click.echo(f"\nTable I, estimator '{name}': mean (± std) squared error, 1e-2 (m/s)^2\n")
            click.echo(ev.table_one_markdown(result, name))
        for r in result.items:  # a treadmill walk's speed includes the belt: say so
            treadmill = getattr(r.velocities, "treadmill", None)
            if treadmill is not None and treadmill.detected:
                click.echo(f"{r.item.name}: {treadmill.reason}")
        ev.write_report(result, out, force=force, figures=figures, progress=True)
    click.echo(f"\nReport: {out / 'index.md'}")
    for name, message in result.failures:
        click.echo(f"yoyogait: not evaluated: {name}: {message}", err=True)
    return result


REPORT_FORCE_HELP = (
    "Replace a report yoyogait wrote in --out before: only the files listed in its .yoyogait-report; "
    "other files there stay."
)


@click.command("evaluate")
@click.argument("dataset", required=False, default="synthetic")
@input_options
@estimators_option()
@click.option(
    "--out",
    "out",
    type=click.Path(file_okay=False),
    metavar="FOLDER",
    default="yoyogait-evaluation",
    show_default=True,
    help="Folder for the report: new, empty, or a report of yoyogait's (with --force).",
)
@force_option(REPORT_FORCE_HELP)
@click.option("--no-figures", is_flag=True, help="Skip the per-recording figures.")
@click.option("--seed", default=0, show_default=True, help="Seed of the synthetic lab.")
def command(dataset, point, feet, up_axis, length_unit_m, rate_hz, estimators, out, force, no_figures, seed):
    """Evaluate estimators on DATASET: 'synthetic' (built-in), a folder of recordings, or a manifest .json.

    Writes Table I per estimator (Markdown, CSV), one CSV row per recording and estimator,
    Fig. 3/4-style figures per recording and an index.md into --out. The input options apply to
    every recording (and win over a manifest's entries). Exits 1 when some recording could not
    be evaluated (the others are still reported).
    """
    overrides = dict(point=point, feet=feet, up_axis=up_axis, length_unit_m=length_unit_m, rate_hz=rate_hz)
    overrides = {k: v for k, v in overrides.items() if v is not None}
    result = run_evaluation(dataset, Path(out), estimators, force, not no_figures, seed, overrides)
    if result.failures:
        raise click.exceptions.Exit(1)
