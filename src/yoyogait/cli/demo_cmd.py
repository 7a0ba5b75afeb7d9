"""``yoyogait demo``: the estimator on a synthetic Yoyo-model walk, and what it found."""

from __future__ import annotations

import click
import numpy as np


@click.command()
@click.option("--preset", default="paper", show_default=True, help="Estimator preset.")
@click.option("--seconds", default=30.0, show_default=True, type=click.FloatRange(min=5.0), help="Walk length.")
def demo(preset: str, seconds: float) -> None:
    """Run the estimator on a synthetic walk (Yoyo-model, eq. 3-4, at 25 Hz) and print what it found."""
    from ..estimator import EstimatorConfig, GaitEstimator
    from ..model import yoyo_model

    cfg = EstimatorConfig.preset(preset)
    T = cfg.sample_time_s
    truth = {"step_frequency_hz": 1.8, "R_m": 0.115, "r_m": 0.02}
    t = np.arange(1, int(seconds / T) + 1) * T
    walk = yoyo_model(t, truth["R_m"], truth["r_m"], truth["step_frequency_hz"])
    rng = np.random.default_rng(0)
    vx = walk.vx_mps + 0.02 * rng.standard_normal(t.size)
    vz = walk.vz_mps + 0.02 * rng.standard_normal(t.size)
    res = GaitEstimator(cfg).run(vx, vz)
    late = t >= t[-1] - 5.0
    click.echo(f"SYNTHETIC walk (Yoyo-model, {seconds:g} s at {1 / T:g} Hz, noise 0.02 m/s), preset '{preset}'")
    click.echo(f"{'quantity':<22}{'truth':>10}{'estimate (last 5 s)':>22}")
    for name, unit in (("step_frequency_hz", "Hz"), ("R_m", "m"), ("r_m", "m")):
        est = float(np.mean(getattr(res, name)[late]))
        click.echo(f"{name:<22}{truth[name]:>10.4f}{est:>22.4f}")
    speed = truth["R_m"] * 2 * np.pi * truth["step_frequency_hz"]
    click.echo(f"{'speed_mps':<22}{speed:>10.4f}{float(np.mean(res.speed_mps[late])):>22.4f}")
    err_vx = 100 * np.mean((res.vx_hat - vx) ** 2)
    err_vz = 100 * np.mean((res.vz_hat - vz) ** 2)
    click.echo(f"mean squared error of the reconstruction (1e-2 (m/s)^2): vx {err_vx:.3f}, vz {err_vz:.3f}")
