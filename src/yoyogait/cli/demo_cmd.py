"""``yoyogait demo``: the paper preset and the default side by side on the built-in synthetic lab."""

from __future__ import annotations

from pathlib import Path

import click

from .evaluate_cmd import CONFIG_OPTION, run_evaluation


@click.command()
@click.option(
    "--out",
    type=click.Path(),
    default="yoyogait-demo",
    show_default=True,
    help="Folder for the report (replaced only with --force).",
)
@click.option("--force", is_flag=True, help="Replace an existing report folder.")
@click.option("--estimators", default="paper,default", show_default=True, help="Presets and baselines to compare.")
@CONFIG_OPTION
def demo(out, force, estimators, config_files):
    """Evaluate the estimators on the built-in SYNTHETIC gait lab (3 subjects x 5 walks) and print Table I."""
    run_evaluation("synthetic", Path(out), estimators, force, True, 0, config_files)
