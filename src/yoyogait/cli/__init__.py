"""The ``yoyogait`` command line: a thin layer over the library.

Each subcommand lives in its own module and is registered here.  Errors meant
for the user become one line on stderr and a non-zero exit, never a traceback.
SIGINT and SIGTERM stop any command with 130 and 143 and leave no output
(:mod:`yoyogait._guard`); numpy's RuntimeWarnings (NaN where NaN is expected)
are not shown, other warnings are shown as one line each after a command that
succeeded.
"""

from __future__ import annotations

import signal
import sys
import warnings

import click

from .._guard import Interrupted, handle_interrupts, interrupted_by
from .._reading import one_line
from ..errors import YoyogaitError


class _Stopped(BaseException):
    """Carries an interrupt past click, which would print a blank line for a KeyboardInterrupt."""

    def __init__(self, signum: int):
        super().__init__(signum)
        self.signum = signum


class _Group(click.Group):
    def invoke(self, ctx):
        try:
            return super().invoke(ctx)
        except KeyboardInterrupt as exc:
            raise _Stopped(exc.signum if isinstance(exc, Interrupted) else int(signal.SIGINT)) from None


@click.group(cls=_Group, context_settings={"help_option_names": ["-h", "--help"]})
@click.version_option(package_name="yoyogait")
def cli() -> None:
    """Estimate walking gait (step frequency, speed, Yoyo-model) from motion capture."""


def _register() -> None:
    # Imported here, not at the top: the commands bring numpy, scipy and the core (seconds on a loaded
    # machine), and main() imports them under its interrupt guard, so Ctrl-C then is a clean 130 too.
    from . import (
        config_cmd,
        demo_cmd,
        estimate_cmd,
        evaluate_cmd,
        guide_cmd,
        inspect_cmd,
        live_cmd,
        replay_cmd,
        ros2_cmd,
        tune_cmd,
    )

    cli.add_command(demo_cmd.demo)
    for module in (
        inspect_cmd, estimate_cmd, evaluate_cmd, replay_cmd, live_cmd, ros2_cmd, tune_cmd, config_cmd, guide_cmd,
    ):  # fmt: skip
        cli.add_command(module.command)


def main(argv=None) -> int:
    """Entry point of the ``yoyogait`` script."""
    with handle_interrupts(), warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("default")
        warnings.simplefilter("ignore", RuntimeWarning)
        code = _run(argv)
        signum = interrupted_by()
    if signum is not None or code in (130, 143):
        # Also when the interrupt's exception was swallowed on the way (nothing was committed then).
        signum = signum if signum is not None else code - 128
        click.echo(f"yoyogait: interrupted ({signal.Signals(signum).name})", err=True)
        return 128 + signum
    if code == 0:
        for message in dict.fromkeys(f"{w.category.__name__}: {w.message}" for w in caught):
            click.echo(f"yoyogait: warning: {message}", err=True)
    return code


def _run(argv) -> int:
    try:
        _register()
        rv = cli.main(args=argv, prog_name="yoyogait", standalone_mode=False)
    except _Stopped as stop:
        return 128 + stop.signum
    except click.exceptions.Abort:
        return 130
    except KeyboardInterrupt as exc:
        return 128 + (exc.signum if isinstance(exc, Interrupted) else int(signal.SIGINT))
    except click.UsageError as exc:  # one line naming the option, not click's usage block
        where = exc.ctx.command_path if exc.ctx is not None else "yoyogait"
        click.echo(f"yoyogait: error: {exc.format_message()} (see '{where} --help')", err=True)
        return exc.exit_code
    except click.ClickException as exc:
        click.echo(f"yoyogait: error: {exc.format_message()}", err=True)
        return exc.exit_code
    except (YoyogaitError, ValueError, OSError) as exc:
        from .options import cli_message

        click.echo(f"yoyogait: error: {cli_message(_one_line(exc))}", err=True)
        return 2
    return rv if isinstance(rv, int) else 0


def _one_line(exc: BaseException) -> str:
    """The message on one line, at most 2000 characters whatever it quotes."""
    text = one_line(str(exc), 2000)
    return text or type(exc).__name__


if __name__ == "__main__":  # pragma: no cover
    sys.exit(main())
