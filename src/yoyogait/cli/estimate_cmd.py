"""``yoyogait estimate FILE``: estimates over time as CSV, and a figure."""

from __future__ import annotations

from pathlib import Path

import click
import numpy as np

from .. import io
from .._files import atomic_files
from ..errors import InputError, about_file
from ..estimators.registry import check_estimators, estimators
from ..evaluation import figures as plots
from ..pipeline.velocities import gait_velocities

COLUMNS = (
    "time_s",
    "vx_mps",
    "vz_mps",
    "vx_hat_mps",
    "vz_hat_mps",
    "step_frequency_hz",
    "step_frequency_std_hz",
    "speed_mps",
    "speed_std_mps",
    "R_m",
    "r_m",
    "A0_mps",
    "A1_mps",
    "x1",
    "x2",
    "x3_rad_per_sample",
    "x4_mps",
    "status",
)


@click.command("estimate")
@click.argument("file", type=click.Path(dir_okay=False))
@click.option("--preset", default="default", show_default=True, help="Estimator preset or baseline.")
@click.option("--point", default=None, help="Point to track: 'pelvis' (default), 'hand', or a point name.")
@click.option("--up", "up_axis", type=click.Choice(["x", "y", "z"]), default=None, help="Up axis of the file.")
@click.option("--unit", "length_unit_m", type=float, default=None, help="Metres per length unit (BVH, CSV).")
@click.option("--rate", "rate_hz", type=float, default=None, help="Sample rate of a file without one [Hz].")
@click.option(
    "--out",
    type=click.Path(dir_okay=False),
    default=None,
    help="CSV to write [default: FILE's name + .estimate.csv, here].",
)
@click.option(
    "--figure",
    type=click.Path(dir_okay=False),
    default=None,
    help="PNG to write [default: FILE's name + .estimate.png, here]; 'none' for no figure.",
)
@click.option("--force", is_flag=True, help="Overwrite existing outputs.")
def command(file, preset, point, up_axis, length_unit_m, rate_hz, out, figure, force):
    """Estimate gait over time from a motion-capture FILE (C3D, TRC, BVH, CSV)."""
    check_estimators([preset])
    stem = Path(file).name
    out = Path(out or f"{stem}.estimate.csv")
    fig = None if figure == "none" else Path(figure or f"{stem}.estimate.png")
    for target in (out, fig):
        if target is not None and target.exists() and not force:
            raise InputError(f"{target} exists; use --force to overwrite it")
    overrides = {k: v for k, v in (("up_axis", up_axis), ("length_unit_m", length_unit_m), ("rate_hz", rate_hz)) if v}
    with about_file(file):
        recording = io.read(file, **overrides)
        vel = gait_velocities(recording, point=point, up_axis=up_axis)
        res = estimators()[preset](vel)
    state = res.state
    table = np.column_stack(
        [
            vel.time_s,
            vel.vx,
            vel.vz,
            res.vx_hat,
            res.vz_hat,
            res.step_frequency_hz,
            res.step_frequency_std_hz,
            res.speed_mps,
            res.speed_std_mps,
            res.R_m,
            res.r_m,
            res.A0_mps,
            res.A1_mps,
            state,
            res.status,
        ]
    )
    f = np.abs(res.step_frequency_hz[vel.walking]) if vel.walking.any() else np.abs(res.step_frequency_hz)
    summary = (
        f"{stem}: {len(vel.time_s)} samples at {vel.rate_hz:g} Hz of {vel.point}; "
        f"median step frequency {np.median(f):.2f} Hz, median speed {np.nanmedian(res.speed_mps):.2f} m/s"
    )
    writers = {
        out: lambda p: np.savetxt(
            p,
            table,
            delimiter=",",
            header=",".join(COLUMNS),
            comments="",
            fmt=["%.4f"] + ["%.6g"] * (len(COLUMNS) - 2) + ["%d"],
        )
    }
    if fig is not None:
        title = f"{stem} [{preset}]"
        writers[fig] = lambda p: plots.parameter_figure(vel.time_s, res, title=title, measured_vz_mps=vel.vz, path=p)
    # Both or neither: the figure is drawn before the CSV is renamed into place.
    atomic_files(writers)
    click.echo(summary)
    click.echo(f"wrote {out}" + (f" and {fig}" if fig else ""))
