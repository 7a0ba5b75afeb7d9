"""``yoyogait evaluate``: estimators side by side over a data set, with Table I, CSVs and figures."""

from __future__ import annotations

import contextlib
import dataclasses
import functools
import os
from pathlib import Path

import click

from .. import evaluation as ev
from .. import io
from .._files import check_output_folder
from .._guard import output_lock
from .._reading import one_line
from ..errors import InputError
from ..estimators.config import OnlineConfig
from ..estimators.registry import config_estimators
from ..evaluation import parallel
from .imu_cmd import evaluate_imu, is_imu_dataset
from .options import (
    ESTIMATOR_NAMES,
    MARKER_OPTIONS,
    check_points,
    estimator_config_option,
    estimators_option,
    force_option,
    input_options,
    read_overrides,
    refuse_options,
)

#: What an IMU data set (Mobilise-D data.mat files) does not use: the marker path's input options and
#: the marker evaluation's estimators, Dask cluster and synthetic lab (--jobs it takes).
IMU_DATASET_REFUSED = (
    *MARKER_OPTIONS,
    "rate_hz",
    "estimators",
    "scheduler",
    "ship_files",
    "seed",
    "online",
    "online_feet",
)


def resolve_jobs(jobs: int | None) -> int:
    """--jobs: None for every core; fewer than one is one line naming the option."""
    jobs = parallel.default_jobs() if jobs is None else jobs
    if jobs < 1:
        raise InputError(f"--jobs must be at least 1, not {jobs}")
    return jobs


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


def _load_checked(load, point, feet):
    """load(), then an InputError naming --point or --feet if the recording lacks those points."""
    recording = load()
    check_points(recording, point, feet)
    return recording


def with_overrides(items, *, point=None, feet=None, up_axis=None, length_unit_m=None, rate_hz=None):
    """The items with the command line's input options applied to every one (they win over a manifest's)."""
    reading = read_overrides(up_axis=up_axis, length_unit_m=length_unit_m, rate_hz=rate_hz)
    out = []
    for item in items:
        changes: dict = {}
        if point is not None:
            changes["pelvis"] = point  # a name, "pelvis", "hand", or names to average
        if feet is not None:
            changes["feet"] = list(feet)
        if up_axis is not None:
            changes["up_axis"] = up_axis
        if reading:
            load = item.load
            if not isinstance(load, functools.partial) or load.func is not io.read:
                raise InputError(
                    "--up-axis, --length-unit-m and --capture-rate-hz apply to files, not to the synthetic lab"
                )
            changes["load"] = functools.partial(io.read, *load.args, **{**load.keywords, **reading})
        if point is not None or feet is not None:
            changes["load"] = functools.partial(_load_checked, changes.get("load", item.load), point, feet)
        out.append(dataclasses.replace(item, **changes))
    return out


def _evaluate_and_write(
    dataset, out, names, configs, force, figures, seed, overrides, jobs, scheduler, ship_files, online=False,
    online_config=None, online_feet=False,
):  # fmt: skip
    """The evaluation of :func:`run_evaluation`, its printout, and then its report."""
    items, problems, synthetic = ev.resolve_dataset(dataset, seed=seed)
    if not items and problems:
        raise InputError(f"no recording could be evaluated ({len(problems)}): " + first_few(problems))
    if online:  # the online estimator and the oscillator; the synthetic lab gains its cadence-step walks
        names, items = ev.ONLINE_ESTIMATORS, items + (ev.step_walk_items(seed=seed) if synthetic else [])
    if overrides:
        items = with_overrides(items, **overrides)
    mode = ev.report.figure_mode(figures, len(items))
    label = "SYNTHETIC data (yoyogait's Yoyo-model gait lab)" if synthetic else str(dataset)
    with contextlib.ExitStack() as stack:
        executor = None
        where = f"{jobs} process{'es' if jobs > 1 else ''}"
        if scheduler:
            executor = stack.enter_context(parallel.dask_executor(scheduler))
            where = f"the Dask cluster at {scheduler}"
            if ship_files:
                items = [ev.datasets.shipped(item) for item in items]
        click.echo(f"Evaluating {', '.join(names)} on {len(items)} recordings ({where}): {label}", err=True)
        run = (
            functools.partial(ev.evaluate_online, config=online_config, feet=online_feet)
            if online
            else functools.partial(ev.evaluate, names=names, configs=configs)
        )
        result = run(
            items,
            progress=True,
            dataset=str(dataset or "synthetic"),
            synthetic=synthetic,
            failures=problems,
            jobs=jobs,
            executor=executor,
        )
    if not result.items:
        raise InputError(f"no recording could be evaluated ({len(result.failures)}): " + first_few(result.failures))
    click.echo(f"\n{label}\n")
    if online:  # the online columns, honesty included, median and worst recording
        click.echo(result.summary_table() + "\n")
    click.echo(ev.summary_markdown(result))
    for name in names:
        click.echo(f"\nTable I, estimator '{name}': mean (± std) squared error, 1e-2 (m/s)^2\n")
        click.echo(ev.table_one_markdown(result, name))
    for r in result.items:  # a treadmill walk's speed includes the belt: say so
        treadmill = getattr(r.velocities, "treadmill", None)
        if treadmill is not None and treadmill.detected:
            click.echo(f"{r.item.name}: {treadmill.reason}")
    # Last: the report is moved into place once everything else is done (an interrupt before it
    # leaves nothing; SIGINT/SIGTERM wait while it is moved).
    ev.write_report(result, out, force=force, figures=mode, progress=True, jobs=jobs)
    return result


def run_evaluation(
    dataset,
    out,
    estimators,
    force,
    figures,
    seed,
    overrides=None,
    config_files=(),
    *,
    jobs=None,
    scheduler=None,
    ship_files=False,
    online=False,
    online_feet=False,
):
    """Evaluate, print the summary and Table I, write the report; returns the evaluation.

    ``config_files``: estimator configurations (TOML) evaluated too, each named by its file's stem.
    ``figures``: a mode of :data:`yoyogait.evaluation.report.FIGURE_MODES`, True/False, or None
    (by the size of the data set). ``jobs``: worker processes (None: every core). ``scheduler``:
    the address of a Dask scheduler that evaluates the recordings instead (figures are drawn here).
    ``online``: the online evaluation (:func:`yoyogait.evaluation.evaluate_online`); ``online_feet``:
    with it, each recording's foot points in the frames.
    The whole run holds the lock on ``out``: a second run on it fails at once.
    """
    online_config = None
    if online_feet and not online:
        raise InputError("--online-feet goes with --online")
    if online:
        if len(config_files) > 1:
            raise InputError("--online takes one --config (the online estimator's settings), not several")
        online_config = OnlineConfig.from_file(config_files[0]) if config_files else None
        configs = {}
    else:
        configs = config_estimators(config_files)
    names = ev.check_estimators(tuple(dict.fromkeys(estimator_list(estimators) + tuple(configs))), configs)
    jobs = resolve_jobs(jobs)
    if ship_files and not scheduler:
        raise InputError("--ship-files goes with --scheduler")
    if dataset not in (None, "synthetic") and os.path.lexists(out) and os.path.lexists(dataset):
        if os.path.samefile(out, dataset) or Path(dataset).absolute().parent.samefile(out):
            raise InputError(
                f"--out {out}: holds the data set {dataset}; give another folder (refused even with --force)"
            )
    expected = ev.report.REPORT_NAMES
    check_output_folder(out, force, "--out", expected)
    with output_lock(out):
        check_output_folder(out, force, "--out", expected)  # again: a run that just finished may have written it
        result = _evaluate_and_write(
            dataset, out, names, configs, force, figures, seed, overrides, jobs, scheduler, ship_files, online,
            online_config, online_feet,
        )  # fmt: skip
    click.echo(f"\nReport: {out / 'index.md'}")
    echo_problems("not evaluated", result.failures, out / "not_evaluated.csv")
    echo_problems("figure not drawn", result.figure_failures, out / "index.md")
    return result


PROBLEMS_SHOWN = 20
"""At most this many problems of one kind are printed (the report lists them all)."""


def first_few(problems, n: int = 3) -> str:
    """The first ``n`` problems on one line, and how many more."""
    text = "; ".join(f"{name}: {message}" for name, message in problems[:n])
    return text + (f"; and {len(problems) - n} more" if len(problems) > n else "")


def echo_problems(what: str, problems, where: Path | None = None) -> None:
    """One stderr line per problem, the first :data:`PROBLEMS_SHOWN`, then their count and where all are."""
    for name, message in problems[:PROBLEMS_SHOWN]:
        click.echo(f"yoyogait: {what}: {one_line(f'{name}: {message}')}", err=True)
    if len(problems) > PROBLEMS_SHOWN:
        rest = len(problems) - PROBLEMS_SHOWN
        click.echo(
            f"yoyogait: {what}: {rest} more ({len(problems)} in all" + (f"; every one in {where})" if where else ")"),
            err=True,
        )


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
@click.option(
    "--figures",
    type=click.Choice(ev.report.FIGURE_MODES),
    default=None,
    help="all: every recording's; summary: distributions over recordings and the best and worst recordings; "
    f"none. Default: summary above {ev.report.SUMMARY_ABOVE} recordings, else all.",
)
@click.option("--no-figures", is_flag=True, help="Same as --figures none.")
@click.option(
    "--jobs",
    "-j",
    type=int,
    default=None,
    help="Worker processes for the recordings and the figures. Default: every core.",
)
@click.option(
    "--scheduler",
    default=None,
    metavar="ADDRESS",
    help="Evaluate on the Dask cluster of this scheduler (e.g. tcp://host:8786); needs yoyogait[distributed] "
    "and the recordings at the same paths on the workers (or --ship-files).",
)
@click.option("--ship-files", is_flag=True, help="With --scheduler: send each file's bytes with its task.")
@click.option("--seed", default=0, show_default=True, help="Seed of the synthetic lab.")
@estimator_config_option(multiple=True)
@click.option(
    "--online",
    is_flag=True,
    help="Online evaluation: replay each recording frame by frame through "
    "OnlineEstimator (the oscillator beside it; --estimators is refused). See docs/online.md.",
)
@click.option(
    "--online-feet",
    is_flag=True,
    help="With --online: each recording's foot points (--feet, or found by name) go into the frames, "
    "as estimate --online --feet puts them: their steps check the cadence (markerless capture), and on a "
    "treadmill the belt speed comes from the stance feet. A recording without feet is reported.",
)
@click.pass_context
def command(
    ctx,
    dataset,
    point,
    feet,
    up_axis,
    length_unit_m,
    rate_hz,
    estimators,
    out,
    force,
    figures,
    no_figures,
    jobs,
    scheduler,
    ship_files,
    seed,
    config_files,
    online,
    online_feet,
):
    """Evaluate estimators on DATASET: 'synthetic' (built-in), a folder of recordings, or a manifest .json.

    A folder of Mobilise-D lower-back IMU data (data.mat files): per reference walking bout the
    cadence, speed and stride-time errors of the online IMU estimator, the oscillator and mobgap
    (the recordings in parallel: --jobs).

    Writes Table I per estimator (Markdown, CSV), one CSV row per recording and estimator,
    Fig. 3/4-style figures and an index.md into --out (recordings and figures in parallel: --jobs,
    or a Dask cluster with --scheduler; the results do not depend on how). The input options apply to
    every recording (and win over a manifest's entries). Exits 1 when some recording could not
    be evaluated (the others are still reported).
    """
    if no_figures and figures not in (None, "none"):
        raise InputError(f"--no-figures contradicts --figures {figures}")
    mode = "none" if no_figures else figures
    if dataset != "synthetic" and is_imu_dataset(dataset):
        # Options of the marker evaluation would be ignored here: refused, named.
        refuse_options(ctx, dataset, IMU_DATASET_REFUSED, "motion-capture data sets")
        if len(config_files) > 1:
            raise InputError(f"{dataset}: an IMU data set is evaluated with one --config (its [imu] table)")
        imu_config = config_files[0] if config_files else None
        jobs = resolve_jobs(jobs)
        imu = evaluate_imu(dataset, Path(out), force=force, figures=mode != "none", config_file=imu_config, jobs=jobs)
        if imu["failures"]:
            raise click.exceptions.Exit(1)
        return
    if dataset not in (None, "synthetic"):  # the seed draws the synthetic lab's walks, nothing else
        refuse_options(ctx, dataset, ("seed",), "the synthetic lab")
    if online:  # the online evaluation runs the online estimator and the oscillator: a list would be ignored
        refuse_options(ctx, "--online", ("estimators",), "the offline evaluation")
    overrides = dict(point=point, feet=feet, up_axis=up_axis, length_unit_m=length_unit_m, rate_hz=rate_hz)
    overrides = {k: v for k, v in overrides.items() if v is not None}
    result = run_evaluation(
        dataset,
        Path(out),
        estimators,
        force,
        mode,
        seed,
        overrides,
        config_files,
        jobs=jobs,
        scheduler=scheduler,
        ship_files=ship_files,
        online=online,
        online_feet=online_feet,
    )
    if result.failures or result.figure_failures:
        raise click.exceptions.Exit(1)
