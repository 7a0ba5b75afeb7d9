"""``yoyogait evaluate``: estimators side by side over a data set, with Table I, CSVs and figures."""

from __future__ import annotations

from pathlib import Path

import click

from .. import evaluation as ev
from .._guard import check_interrupted, output_lock
from ..errors import InputError


def estimator_list(value: str) -> tuple[str, ...]:
    names = tuple(n.strip() for n in value.split(",") if n.strip())
    if not names:
        raise InputError("--estimators needs at least one name")
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


def run_evaluation(dataset, out, estimators, force, figures, seed):
    """Evaluate, print the summary and Table I, write the report; returns the evaluation.

    The whole run holds the lock on ``out`` (a second run on it fails at once), and the report is
    renamed into place as the last step, after everything is printed.
    """
    names = ev.check_estimators(estimator_list(estimators))
    if out.exists() and not force:
        raise InputError(f"{out} exists; use --force to replace it")
    with output_lock(out):
        if out.exists() and not force:  # written by a run that finished while this one started
            raise InputError(f"{out} exists; use --force to replace it")
        items, problems, synthetic = ev.resolve_dataset(dataset, seed=seed)
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
        ev.write_report(result, out, force=force, figures=figures, progress=True)
    click.echo(f"\nReport: {out / 'index.md'}")
    for name, message in result.failures:
        click.echo(f"yoyogait: not evaluated: {name}: {message}", err=True)
    return result


@click.command("evaluate")
@click.argument("dataset", required=False, default="synthetic")
@click.option(
    "--out",
    "out",
    type=click.Path(),
    default="yoyogait-evaluation",
    show_default=True,
    help="Folder for the report (replaced only with --force).",
)
@click.option(
    "--estimators", default="paper,default", show_default=True, help="Comma-separated presets and baselines to compare."
)
@click.option("--force", is_flag=True, help="Replace an existing report folder.")
@click.option("--no-figures", is_flag=True, help="Skip the per-recording figures.")
@click.option("--seed", default=0, show_default=True, help="Seed of the synthetic lab.")
def command(dataset, out, estimators, force, no_figures, seed):
    """Evaluate estimators on DATASET: 'synthetic' (built-in), a folder of recordings, or a manifest .json.

    Writes Table I per estimator (Markdown, CSV), one CSV row per recording and estimator,
    Fig. 3/4-style figures per recording and an index.md into --out. Exits 1 when some
    recording could not be evaluated (the others are still reported).
    """
    result = run_evaluation(dataset, Path(out), estimators, force, not no_figures, seed)
    if result.failures:
        raise click.exceptions.Exit(1)
