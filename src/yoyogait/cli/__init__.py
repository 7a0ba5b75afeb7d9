"""The ``yoyogait`` command line: a thin layer over the library.

Each subcommand lives in its own module and is registered here.  Errors meant
for the user become one line on stderr and a non-zero exit, never a traceback.
"""

from __future__ import annotations

import sys

import click

from ..errors import YoyogaitError
from . import demo_cmd, estimate_cmd, evaluate_cmd, inspect_cmd, live_cmd, replay_cmd, tune_cmd
from .options import cli_message


@click.group(context_settings={"help_option_names": ["-h", "--help"]})
@click.version_option(package_name="yoyogait")
def cli() -> None:
    """Estimate walking gait (step frequency, speed, Yoyo-model) from motion capture."""


def _register() -> None:
    cli.add_command(demo_cmd.demo)
    for module in (inspect_cmd, estimate_cmd, evaluate_cmd, replay_cmd, live_cmd, tune_cmd):
        cli.add_command(module.command)


def main(argv=None) -> int:
    """Entry point of the ``yoyogait`` script."""
    _register()
    try:
        rv = cli.main(args=argv, prog_name="yoyogait", standalone_mode=False)
    except click.exceptions.Abort:
        click.echo("yoyogait: interrupted", err=True)
        return 130
    except click.UsageError as exc:  # one line naming the option, not click's usage block
        where = exc.ctx.command_path if exc.ctx is not None else "yoyogait"
        click.echo(f"yoyogait: error: {exc.format_message()} (see '{where} --help')", err=True)
        return exc.exit_code
    except click.ClickException as exc:
        click.echo(f"yoyogait: error: {exc.format_message()}", err=True)
        return exc.exit_code
    except (YoyogaitError, ValueError, OSError) as exc:
        click.echo(f"yoyogait: error: {cli_message(str(exc))}", err=True)
        return 2
    except KeyboardInterrupt:
        click.echo("yoyogait: interrupted", err=True)
        return 130
    return rv if isinstance(rv, int) else 0


if __name__ == "__main__":  # pragma: no cover
    sys.exit(main())
