"""``yoyogait estimate FILE``: estimates over time as CSV, and a figure."""

from __future__ import annotations

from pathlib import Path

import click
import numpy as np

from .. import io
from .._files import atomic_file
from ..errors import InputError
from ..estimators.online import OnlineEstimator
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
@click.option("--online", is_flag=True, help="Replay FILE frame by frame through the online estimator (CSV only).")
def command(file, preset, point, up_axis, length_unit_m, rate_hz, out, figure, force, online):
    """Estimate gait over time from a motion-capture FILE (C3D, TRC, BVH, CSV)."""
    if online:
        return online_estimate(file, preset, point, up_axis, length_unit_m, rate_hz, out, figure, force)
    check_estimators([preset])
    stem = Path(file).name
    out = Path(out or f"{stem}.estimate.csv")
    fig = None if figure == "none" else Path(figure or f"{stem}.estimate.png")
    for target in (out, fig):
        if target is not None and target.exists() and not force:
            raise InputError(f"{target} exists; use --force to overwrite it")
    overrides = {k: v for k, v in (("up_axis", up_axis), ("length_unit_m", length_unit_m), ("rate_hz", rate_hz)) if v}
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
    atomic_file(
        out,
        lambda p: np.savetxt(
            p,
            table,
            delimiter=",",
            header=",".join(COLUMNS),
            comments="",
            fmt=["%.4f"] + ["%.6g"] * (len(COLUMNS) - 2) + ["%d"],
        ),
    )
    if fig is not None:
        title = f"{stem} [{preset}]"
        atomic_file(fig, lambda p: plots.parameter_figure(vel.time_s, res, title=title, measured_vz_mps=vel.vz, path=p))
    f = np.abs(res.step_frequency_hz[vel.walking]) if vel.walking.any() else np.abs(res.step_frequency_hz)
    click.echo(
        f"{stem}: {len(vel.time_s)} samples at {vel.rate_hz:g} Hz of {vel.point}; "
        f"median step frequency {np.median(f):.2f} Hz, median speed {np.nanmedian(res.speed_mps):.2f} m/s"
    )
    click.echo(f"wrote {out}" + (f" and {fig}" if fig else ""))


ONLINE_COLUMNS = (
    "time_s",
    "vx_mps",
    "vz_mps",
    "vx_hat_mps",
    "vz_hat_mps",
    "step_frequency_hz",
    "step_frequency_std_hz",
    "speed_mps",
    "speed_std_mps",
    "heading_rad",
    "gait_phase",
    "walking",
    "status",
    "input_latency_s",
)
#: printf formats of ONLINE_COLUMNS (``live --record`` writes the same).
ONLINE_FORMATS = ("%.6f",) + ("%.6g",) * 10 + ("%d", "%d", "%.6g")


def online_estimate(file, preset, point, up_axis, length_unit_m, rate_hz, out, figure, force):
    """``estimate --online``: one CSV row per capture frame from yoyogait.OnlineEstimator."""
    if preset != "default":
        raise InputError(f"--online runs the default estimator; --preset {preset} is not available online")
    if figure not in (None, "none"):
        raise InputError("--online writes no figure; leave out --figure")
    stem = Path(file).name
    out = Path(out or f"{stem}.online.csv")
    if out.exists() and not force:
        raise InputError(f"{out} exists; use --force to overwrite it")
    overrides = {k: v for k, v in (("up_axis", up_axis), ("length_unit_m", length_unit_m), ("rate_hz", rate_hz)) if v}
    recording = io.read(file, **overrides)
    est = OnlineEstimator.for_recording(recording, point, up_axis=up_axis)
    res = est.run(recording)
    table = np.column_stack([getattr(res, c).astype(float) for c in ONLINE_COLUMNS])
    fmt = list(ONLINE_FORMATS)
    atomic_file(
        out, lambda p: np.savetxt(p, table, delimiter=",", header=",".join(ONLINE_COLUMNS), comments="", fmt=fmt)
    )
    walking = res.walking
    f = res.step_frequency_hz[walking] if walking.any() else res.step_frequency_hz
    click.echo(
        f"{stem}: {len(res)} frames of {', '.join(est.point_names)} replayed online; "
        f"median step frequency while walking {np.median(f):.2f} Hz, "
        f"front-end latency {1e3 * float(np.median(res.input_latency_s)):.1f} ms"
    )
    click.echo(f"wrote {out}")
