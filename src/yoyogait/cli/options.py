"""The command line's one vocabulary: options shared by every command, and error lines that name them.

Every command that reads recordings takes the same input options, declared once here
(:func:`input_options`); ``estimate`` picks one estimator with ``--preset``, ``evaluate`` and
``demo`` compare several with ``--estimators``; every command that writes takes ``--out`` and
``--force``.  The library names its arguments (``length_unit_m=``); :func:`cli_message` turns
those names into the options that set them, so an error line tells the user what to type.
"""

from __future__ import annotations

import re

import click

from ..errors import InputError
from ..estimators.config import PRESETS
from ..estimators.registry import BASELINES
from ..pipeline import events, points

ESTIMATOR_NAMES = (*PRESETS, *BASELINES)
"""Every estimator the commands can run: the presets, then the baselines."""

#: Library argument -> the option that sets it (None: an internal setting, its name is dropped).
OPTION_OF_ARGUMENT = {
    "length_unit_m": "--length-unit-m",
    "up_axis": "--up-axis",
    "capture_rate_hz": "--capture-rate-hz",
    "rate_hz": "--capture-rate-hz",
    "point": "--point",
    "feet": "--feet",
    "min_usable_s": None,
}

_NAMES = "|".join(OPTION_OF_ARGUMENT)
_PASS = re.compile(rf"\bpass ({_NAMES})=")
_ASSIGN = re.compile(rf"(?<![\w-])({_NAMES})=")
# Only names that cannot be English words ("point", "feet" can) as the subject of a sentence.
_SUBJECT = re.compile(rf"(?<![\w-])({'|'.join(n for n in OPTION_OF_ARGUMENT if '_' in n)}) (must|is|has)\b")


def cli_message(message: str) -> str:
    """``message`` with the library's argument names replaced by the command-line options.

    "pass length_unit_m=" -> "use --length-unit-m"; "up_axis must ..." -> "--up-axis must ...";
    "min_usable_s=1.5 s" -> "1.5 s".
    """

    def option(name: str) -> str:
        return OPTION_OF_ARGUMENT[name] or ""

    message = _PASS.sub(lambda m: f"use {option(m[1])}" if option(m[1]) else "", message)

    def assign(m: re.Match) -> str:
        value_follows = m.end() < len(message) and not message[m.end()].isspace()
        return (option(m[1]) + (" " if value_follows else "")) if option(m[1]) else ""

    message = _ASSIGN.sub(assign, message)
    message = _SUBJECT.sub(lambda m: f"{option(m[1]) or m[1]} {m[2]}", message)
    return message


def _split_names(ctx, param, value):
    """'A, B' -> ['A', 'B'] (averaged or used together); one name stays a string; None stays None."""
    if value is None:
        return None
    names = [n.strip() for n in value.split(",") if n.strip()]
    if not names:
        raise click.BadParameter("give at least one point name", ctx=ctx, param=param)
    return names if len(names) > 1 or param.name == "feet" else names[0]


_POSITIVE = click.FloatRange(min=0.0, min_open=True)
#: Shared with the streaming commands (replay, live).
POSITIVE = _POSITIVE
split_names = _split_names

_INPUT_OPTIONS = (
    # --config FILE belongs here, first: one place that gives every command the same settings file
    # (its values are the defaults the options below override).
    click.option(
        "--point",
        metavar="NAME[,NAME...]",
        default=None,
        callback=_split_names,
        help="Point to follow: 'pelvis' (default: the pelvis centre, found by name), 'hand', "
        "or point names separated by commas (averaged).",
    ),
    click.option(
        "--feet",
        metavar="NAME,NAME",
        default=None,
        callback=_split_names,
        help="Foot points for contacts and the walking part, separated by commas "
        "(default: found by name: heel, ankle, toe, foot).",
    ),
    click.option(
        "--up-axis",
        type=click.Choice(["x", "y", "z"]),
        default=None,
        help="Up axis (default: the file's, else detected).",
    ),
    click.option(
        "--length-unit-m",
        type=_POSITIVE,
        metavar="METRES",
        default=None,
        help="Metres per length unit of the file (default: the file's; BVH: inferred from the pelvis height).",
    ),
    click.option(
        "--capture-rate-hz",
        "--rate-hz",  # the old name, kept as an alias
        "rate_hz",
        type=_POSITIVE,
        metavar="HZ",
        default=None,
        help="Capture rate of a file that has none [Hz] (--rate-hz: the old name).",
    ),
)


def read_overrides(*, up_axis=None, length_unit_m=None, rate_hz=None) -> dict:
    """What the input options given on the command line ask ``io.read`` for (the ones left out: none)."""
    given = {"up_axis": up_axis, "length_unit_m": length_unit_m, "capture_rate_hz": rate_hz}
    return {k: v for k, v in given.items() if v is not None}


def input_options(f):
    """--point, --feet, --up-axis, --length-unit-m, --capture-rate-hz: how to read the recordings."""
    for decorator in reversed(_INPUT_OPTIONS):
        f = decorator(f)
    return f


def preset_option(f):
    """--preset: one estimator, from the listed choices."""
    return click.option(
        "--preset",
        type=click.Choice(ESTIMATOR_NAMES),
        default="default",
        show_default=True,
        help="Estimator: a preset (paper, default) or a baseline (oscillator, sliding-dft).",
    )(f)


def estimators_option(default: str = "paper,default"):
    """--estimators: several estimators, comma-separated, each one of the listed names."""
    return click.option(
        "--estimators",
        metavar="NAME[,NAME...]",
        default=default,
        show_default=True,
        help=f"Estimators to compare, comma-separated, from: {', '.join(ESTIMATOR_NAMES)}.",
    )


def config_file_option(help_text: str):
    """--config FILE (one configuration file, TOML, docs/configuration.md), as ``config_file``."""
    return click.option(
        "--config", "config_file", type=click.Path(dir_okay=False), metavar="FILE", default=None, help=help_text
    )


def estimator_config_option(multiple: bool):
    """--config FILE: an estimator configuration (TOML, docs/configuration.md). estimate: instead of
    --preset; evaluate, demo: one more estimator per file, named by the file's stem (repeatable)."""
    if not multiple:
        return config_file_option("Estimator configuration file (TOML, docs/configuration.md), instead of --preset.")
    return click.option(
        "--config",
        "config_files",
        type=click.Path(dir_okay=False),
        metavar="FILE",
        multiple=True,
        help="Also evaluate the estimator configured in this TOML file (docs/configuration.md), "
        "named by the file's stem; repeatable.",
    )


def belt_speed_option(f):
    """--belt-speed-mps: a treadmill's belt speed, else found from the stance feet."""
    return click.option(
        "--belt-speed-mps",
        type=float,
        default=None,
        metavar="M/S",
        help="Treadmill belt speed (else found from the stance feet).",
    )(f)


def force_option(what: str):
    return click.option("--force", is_flag=True, help=what)


def check_points(recording, point=None, feet=None) -> None:
    """InputError naming --point or --feet when the recording lacks what they ask for (or no pelvis is found)."""
    if recording.velocities is not None:  # ready velocities: no points to choose
        return
    try:
        points.choose_point(recording, point)
    except InputError as exc:
        if point is None or point == "pelvis":
            raise InputError(f"{exc}; use --point to name the points to follow") from None
        raise InputError(f"--point: {exc}") from None
    if feet is not None:
        try:
            events.feet_of(recording, feet)
        except InputError as exc:
            raise InputError(f"--feet: {exc}") from None


#: Parameters for motion-capture files only (an IMU file refuses them where a command has them).
MARKER_OPTIONS = (
    "point",
    "feet",
    "up_axis",
    "length_unit_m",
    "belt_speed_mps",
    "belt_speed_source",
    "preset",
    "forward",
    "all_points",
)


def refuse_options(ctx: click.Context, file, names, applies_to: str) -> None:
    """InputError naming the options of ``names`` (parameter names) given for ``file`` although they
    apply only to ``applies_to`` (an IMU file's units for a marker file, a marker file's points for an
    IMU file): a given option is never ignored in silence."""
    typed = (click.core.ParameterSource.COMMANDLINE, click.core.ParameterSource.ENVIRONMENT)
    given = [p.opts[0] for p in ctx.command.params if p.name in names and ctx.get_parameter_source(p.name) in typed]
    if given:
        them, it = ("it applies", "it") if len(given) == 1 else ("they apply", "them")
        raise InputError(f"{file}: {', '.join(given)}: {them} to {applies_to} only; leave {it} out")
