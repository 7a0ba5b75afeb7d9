"""yoyogait: online estimation of walking gait with the Yoyo-model.

Data flow one way: file -> :class:`~yoyogait.io.Recording` ->
:func:`gait_velocities` -> :class:`GaitEstimator` -> estimates -> metrics and
figures.  Names are imported on first use, so ``import yoyogait.io`` does not
load the native core.
"""

from __future__ import annotations

import importlib

__version__ = "0.1.0"

_LAZY = {
    "GaitEstimator": "estimator",
    "EstimatorConfig": "estimator",
    "EstimateResult": "estimator",
    "yoyo_model": "model",
    "YoyoTrajectory": "model",
    "gait_velocities": "velocities",
    "GaitVelocities": "velocities",
    "Recording": "io",
    "read": "io",
    "YoyogaitError": "errors",
    "InputError": "errors",
}

__all__ = sorted(_LAZY) + ["__version__"]


def __getattr__(name: str):
    module = _LAZY.get(name)
    if module is None:
        raise AttributeError(f"module 'yoyogait' has no attribute {name!r}")
    value = getattr(importlib.import_module(f".{module}", __name__), name)
    globals()[name] = value
    return value


def __dir__():
    return __all__
