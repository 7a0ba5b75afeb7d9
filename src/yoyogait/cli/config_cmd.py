"""``yoyogait config``: the effective configuration as TOML (a preset, or a file applied to the defaults)."""

from __future__ import annotations

import click

from ..errors import InputError
from ..estimators.config import PRESETS, effective_toml
from .options import config_file_option


@click.command("config")
@click.option(
    "--preset",
    type=click.Choice(tuple(PRESETS)),
    default=None,
    help="The estimator of this preset [default: default].",
)
@config_file_option("A configuration file (TOML) to apply to the defaults, as --config does for the other commands.")
def command(preset, config_file):
    """Print the effective configuration as TOML: every field of the estimator and the [online] table
    of the online front-end (docs/configuration.md). Save it, edit it and pass it back with --config."""
    if preset is not None and config_file is not None:
        raise InputError("give --preset or --config, not both")
    click.echo(effective_toml(preset, config_file), nl=False)
