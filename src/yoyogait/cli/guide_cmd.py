"""``yoyogait guide``: the tethered-guidance simulation, every feedback source side by side (SYNTHETIC)."""

from __future__ import annotations

import dataclasses
from pathlib import Path

import click

from .._files import check_output_folder
from .._guard import output_lock
from ..errors import InputError
from ..guidance import paths as guide_paths
from ..guidance.report import write_guidance_report
from ..guidance.simulation import GuidanceConfig
from ..guidance.sources import SOURCE_NAMES, check_sources
from ..guidance.study import run_study, table_markdown, target_checks
from .evaluate_cmd import REPORT_FORCE_HELP
from .options import force_option


def _source_list(value: str | None) -> tuple[str, ...]:
    if value is None:
        return SOURCE_NAMES
    return check_sources(n.strip() for n in value.split(",") if n.strip())


@click.command("guide")
@click.option(
    "--path",
    "path_file",
    type=click.Path(dir_okay=False),
    metavar="FILE",
    default=None,
    help="Waypoints to guide along: a CSV with x_m,y_m (optional pace, stop_s; docs/guidance.md). "
    "Default: the built-in walks (pace changes, stops, turns).",
)
@click.option(
    "--source",
    "sources",
    metavar="NAME[,NAME...]",
    default=None,
    help=f"Feedback sources to compare, comma-separated (default: all): {', '.join(SOURCE_NAMES)}.",
)
@click.option("--seed", type=int, default=0, show_default=True, help="Seed of the motion-capture noise and gait phase.")
@click.option(
    "--latency-s",
    type=float,
    default=GuidanceConfig.latency_s,
    show_default=True,
    metavar="S",
    help="Sensing and actuation latency of the human velocity, in [0, 0.5] s.",
)
@click.option(
    "--out",
    "out",
    type=click.Path(file_okay=False),
    metavar="FOLDER",
    required=True,
    help="Folder for the report: new, empty, or a report of yoyogait's (with --force).",
)
@force_option(REPORT_FORCE_HELP)
@click.option("--no-figures", is_flag=True, help="Only the tables and the report.")
def command(path_file, sources, seed, latency_s, out, force, no_figures):
    """Simulate a person guided along a path by a tethered aerial robot, with each feedback source
    of the human velocity in the controller, and write the comparison table (CSV, Markdown), figures
    and report.md into --out. Everything is SYNTHETIC (docs/guidance.md)."""
    names = _source_list(sources)
    if not 0.0 <= latency_s <= 0.5:
        raise InputError(f"--latency-s must be in [0, 0.5] s, got {latency_s:g}")
    config = dataclasses.replace(GuidanceConfig(), latency_s=float(latency_s))
    paths = None
    if path_file is not None:
        paths = [guide_paths.read_path(path_file)]
    out = Path(out)
    check_output_folder(out, force)
    with output_lock(out):
        check_output_folder(out, force)
        n_paths = 1 if paths is not None else len(guide_paths.BUILTIN_WALKS)
        click.echo(
            f"Simulating {len(names)} sources x {n_paths} walks x 3 walkers (SYNTHETIC, latency {latency_s:g} s)",
            err=True,
        )
        first = names[0]

        def progress(what: str) -> None:  # one line per walk and walker
            if what.endswith(f" / {first}"):
                click.echo(f"  {what[: -len(first) - 3]}", err=True)

        study = run_study(paths, sources=names, seed=seed, config=config, progress=progress)
        click.echo("\nTethered guidance, SYNTHETIC: mean over the walks per source\n")
        click.echo(table_markdown(study))
        click.echo("")
        for target, met, text in target_checks(study):
            state = "not measurable here" if met is None else ("met" if met else "MISSED")
            click.echo(f"- {target}: {state} ({text})")
        write_guidance_report(study, out, force=force, draw=not no_figures)
    click.echo(f"\nReport: {out / 'report.md'}")
