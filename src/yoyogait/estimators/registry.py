"""Estimators by name, each a function of :class:`~yoyogait.pipeline.velocities.GaitVelocities`.

The presets of :class:`~yoyogait.estimators.config.EstimatorConfig` (``paper``,
``default``) and the baselines (``oscillator``, ``sliding-dft``), so that the
evaluation and the command line run any of them alike.
"""

from __future__ import annotations

from collections.abc import Callable, Mapping
from pathlib import Path

from ..errors import InputError
from .config import PRESETS, EstimatorConfig
from .gait_estimator import GaitEstimator
from .oscillator import OscillatorBaseline
from .results import PREDICTION_HORIZONS_S, EstimateResult
from .sliding_dft import SlidingDft

__all__ = ["estimators", "check_estimators", "config_estimators", "preset_runner", "BASELINES"]

BASELINES = {"oscillator": OscillatorBaseline(), "sliding-dft": SlidingDft()}
"""The baselines under their names: an adaptive oscillator (causal) and a sliding DFT (offline bound)."""


def preset_runner(config: EstimatorConfig) -> Callable[[object], EstimateResult]:
    """A function that runs a fresh estimator of ``config`` over velocities."""

    def run(vel) -> EstimateResult:
        return GaitEstimator(config).run(vel.vx, vel.vz, predict_ahead_s=PREDICTION_HORIZONS_S, time_s=vel.time_s)

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
