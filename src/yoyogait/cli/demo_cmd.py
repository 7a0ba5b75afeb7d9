"""``yoyogait demo``: the paper preset and the default side by side on the built-in synthetic lab."""

from __future__ import annotations

from pathlib import Path

import click

from .evaluate_cmd import REPORT_FORCE_HELP, run_evaluation
from .options import estimator_config_option, estimators_option, force_option


@click.command()
@estimators_option()
@click.option(
    "--out",
    type=click.Path(file_okay=False),
    metavar="FOLDER",
    default="yoyogait-demo",
    show_default=True,
    help="Folder for the report: new, empty, or a report of yoyogait's (with --force).",
)
@force_option(REPORT_FORCE_HELP)
@estimator_config_option(multiple=True)
def demo(estimators, out, force, config_files):
    """Evaluate the estimators on the built-in SYNTHETIC gait lab (3 subjects x 5 walks) and print Table I."""
    run_evaluation("synthetic", Path(out), estimators, force, True, 0, config_files=config_files)
