"""Estimators by name, each a function of :class:`~yoyogait.pipeline.velocities.GaitVelocities`.

The presets of :class:`~yoyogait.estimators.config.EstimatorConfig` (``paper``,
``default``) and the baselines (``oscillator``, ``sliding-dft``), so that the
evaluation and the command line run any of them alike.
"""

from __future__ import annotations

from collections.abc import Callable, Mapping
from pathlib import Path

from ..errors import InputError
from ..pipeline.noise import velocity_noise_var
from .config import PRESETS, EstimatorConfig
from .gait_estimator import GaitEstimator
from .oscillator import OscillatorBaseline
from .results import PREDICTION_HORIZONS_S, EstimateResult
from .sliding_dft import SlidingDft

__all__ = ["estimators", "check_estimators", "config_estimators", "noise_adapted", "preset_runner", "BASELINES"]

BASELINES = {"oscillator": OscillatorBaseline(), "sliding-dft": SlidingDft()}
"""The baselines under their names: an adaptive oscillator (causal) and a sliding DFT (offline bound)."""


def noise_adapted(config: EstimatorConfig, vel) -> tuple[EstimatorConfig, str]:
    """``config`` with the gait filter's measurement noise raised to the velocity noise that ``vel``
    shows (:func:`yoyogait.pipeline.noise.velocity_noise_var`, as a density: variance x sample time)
    where that is larger, and a line saying so ("" when nothing changed). The paper's estimator is
    left as published."""
    if config.algorithm != "gait_filter":
        return config, ""
    gf = config.gait_filter
    dt = config.sample_time_s
    changes, said = {}, []
    for axis, name in (("vx", "meas_vx_density_m2_per_s"), ("vz", "meas_vz_density_m2_per_s")):
        var = velocity_noise_var(getattr(vel, axis), vel.rate_hz)
        if var * dt > getattr(gf, name):
            changes[name] = var * dt
            said.append(f"{axis} {var**0.5:.2f} m/s")
    if not changes:
        return config, ""
    line = (
        f"input noise (velocity above the gait's band): {', '.join(said)}; the estimator's measurement noise "
        "is raised to it"
    )
    return config.with_values({"gait_filter": changes}), line


def preset_runner(config: EstimatorConfig) -> Callable[[object], EstimateResult]:
    """A function that runs a fresh estimator of ``config`` over velocities, its measurement noise
    at least what the velocities show (:func:`noise_adapted`)."""

    def run(vel) -> EstimateResult:
        used, _ = noise_adapted(config, vel)
        return GaitEstimator(used).run(vel.vx, vel.vz, predict_ahead_s=PREDICTION_HORIZONS_S, time_s=vel.time_s)

    return run


def _baseline_runner(baseline) -> Callable[[object], EstimateResult]:
    def run(vel) -> EstimateResult:
        return baseline.run(vel.time_s, vel.vx, vel.vz, predict_ahead_s=PREDICTION_HORIZONS_S)

    return run


def estimators(configs: Mapping[str, EstimatorConfig] | None = None) -> dict[str, Callable[[object], EstimateResult]]:
    """Estimators by name: the presets of EstimatorConfig, the baselines, then ``configs`` (further
    configurations by name, e.g. read from files; a name may not repeat a preset or baseline)."""
    out = {name: preset_runner(make()) for name, make in PRESETS.items()}
    out.update({name: _baseline_runner(b) for name, b in BASELINES.items()})
    for name, config in (configs or {}).items():
        if name in out:
            raise InputError(f"estimator name {name!r} is taken by a preset or baseline; rename the configuration")
        out[name] = preset_runner(config)
    return out


def config_estimators(paths) -> dict[str, EstimatorConfig]:
    """Configurations read from TOML files, named by their file stems (``slow.toml``: ``slow``)."""
    out: dict[str, EstimatorConfig] = {}
    for path in paths:
        name = Path(path).stem
        if name in out:
            raise InputError(f"two configuration files are named {name!r}; give them different names")
        out[name] = EstimatorConfig.from_file(path)
    return out


def check_estimators(names, configs: Mapping[str, EstimatorConfig] | None = None) -> tuple:
    """The names as a tuple; InputError for an unknown one or none."""
    names = tuple(names)
    known = estimators(configs)
    unknown = [n for n in names if n not in known]
    if unknown:
        raise InputError(f"unknown estimator(s) {', '.join(unknown)}; known: {', '.join(known)}")
    if not names:
        raise InputError("no estimator to evaluate")
    return names
