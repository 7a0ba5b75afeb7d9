"""yoyogait: online estimation of walking gait with the Yoyo-model.

Data flow one way: file -> :class:`~yoyogait.io.Recording` ->
:func:`gait_velocities` -> :class:`GaitEstimator` -> estimates -> metrics and
figures.  Names are imported on first use, so ``import yoyogait.io`` does not
load the native core.
"""

from __future__ import annotations

import importlib

__version__ = "0.1.0"

_SUBMODULES = ("io", "synthetic", "metrics", "evaluation", "plots", "events", "spectral", "baselines")

_LAZY = {
    "GaitEstimator": "estimator",
    "EstimatorConfig": "estimator",
    "EstimateResult": "estimator",
    "Status": "estimator",
    "yoyo_model": "model",
    "YoyoTrajectory": "model",
    "gait_velocities": "velocities",
    "GaitVelocities": "velocities",
    "Recording": "io",
    "read": "io",
    "dft_check": "spectral",
    "detect_gait_events": "events",
    "YoyogaitError": "errors",
    "InputError": "errors",
}

__all__ = sorted(_LAZY) + ["__version__"]


def __getattr__(name: str):
    if name in _SUBMODULES:
        return importlib.import_module(f".{name}", __name__)
    module = _LAZY.get(name)
    if module is None:
        raise AttributeError(f"module 'yoyogait' has no attribute {name!r}")
    value = getattr(importlib.import_module(f".{module}", __name__), name)
    globals()[name] = value
    return value


def __dir__():
    return __all__
