"""``yoyogait tune``: tune the default estimator's noise levels, gate and radii low-pass on a data set."""

from __future__ import annotations

from pathlib import Path

import click

from .. import evaluation as ev
from .._files import atomic_file, check_distinct, check_output_file
from ..errors import InputError
from ..evaluation import tuning
from .evaluate_cmd import echo_problems


def _inputs(dataset) -> list[Path]:
    """The files tuning reads that an output must not replace: a manifest (given, or in the folder)."""
    if dataset in (None, "synthetic"):
        return []
    path = Path(dataset)
    return [path / "manifest.json"] if path.is_dir() else [path]


@click.command("tune")
@click.argument("dataset", required=False, default="synthetic")
@click.option(
    "--out",
    type=click.Path(dir_okay=False),
    metavar="TOML",
    default="yoyogait-tuned.toml",
    show_default=True,
    help="The tuned configuration (replaced only with --force).",
)
@click.option("--trials", type=int, default=50, show_default=True, help="Trials per study.")
@click.option("--seed", type=int, default=0, show_default=True, help="Seed of the sampler (and of the synthetic lab).")
@click.option(
    "--storage",
    type=click.Path(dir_okay=False),
    metavar="FILE",
    default=None,
    help="SQLite file of the studies: a run with the same file continues them.",
)
@click.option(
    "--weight",
    "weights",
    multiple=True,
    metavar="METRIC=W",
    help="Weight of a metric in the objective (repeatable); default: "
    + ", ".join(f"{k}={w:g}" for k, w in tuning.DEFAULT_WEIGHTS.items())
    + ".",
)
@click.option("--no-cv", is_flag=True, help="Skip the leave-one-group-out cross-validation.")
@click.option("--jobs", "-j", type=int, default=None, help="Worker processes that prepare the recordings.")
@click.option("--force", is_flag=True, help="Replace an existing --out file.")
def command(dataset, out, trials, seed, storage, weights, no_cv, jobs, force):
    """Tune the default estimator on DATASET ('synthetic', a folder, or a manifest .json).

    The objective is the weighted mean of the recordings' median metrics, each relative to the
    default configuration's (1 = as good, lower is better). Leave-one-group-out cross-validation
    (a group is a manifest folder) reports how tuning on the other groups does on each one; with one
    group, a 5-fold split of the recordings does it instead. The configuration tuned on all of them
    is written to --out as TOML; its objective is on the recordings it was tuned on. Needs
    yoyogait[tune].
    """
    out = Path(out)
    check_distinct((("--out", out), ("--storage", storage)))
    check_output_file(out, "--out", force, inputs=_inputs(dataset))
    if storage is not None and Path(storage).exists() and not Path(storage).is_file():
        raise InputError(f"--storage {storage}: not a regular file (an SQLite file of the studies)")
    w = tuning.parse_weights(weights)
    jobs = ev.default_jobs() if jobs is None else jobs
    if jobs < 1:
        raise InputError(f"--jobs must be at least 1, not {jobs}")
    items, problems, synthetic = ev.resolve_dataset(dataset, seed=seed)
    echo_problems("skipped", problems)
    label = "SYNTHETIC data" if synthetic else str(dataset)
    click.echo(
        f"Tuning the default estimator on {len(items)} recordings ({label}), {trials} trials per study", err=True
    )

    def progress(study, number, value):
        click.echo(f"  {study}: trial {number}: objective {value:.4g}", err=True)

    result = tuning.tune(
        items,
        n_trials=trials,
        seed=seed,
        weights=w,
        storage=storage,
        cross_validate=not no_cv,
        jobs=jobs,
        on_trial=progress,
    )
    text = tuning.config_toml(result)
    atomic_file(out, lambda p: p.write_text(text))
    click.echo(f"cross-validation: {result.cross_validation}")
    for group, value, n in result.folds:
        click.echo(f"held out {group} ({n} recordings): objective {value:.4g} (tuned on the others)")
    click.echo(
        f"objective on the {result.n_training} training recordings (tuned on them, not held out): "
        f"{result.best_objective:.4g} (default: 1)"
    )
    for key, value in sorted(result.best_params.items()):
        click.echo(f"  {key} = {value:.4g}")
    click.echo(f"Configuration: {out}")
