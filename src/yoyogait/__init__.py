"""yoyogait: online estimation of walking gait with the Yoyo-model.

Data flow one way, one sub-package per stage (docs/architecture.md):
file -> :mod:`yoyogait.io` (a :class:`Recording`) -> :mod:`yoyogait.pipeline`
(:func:`gait_velocities`) -> :mod:`yoyogait.estimators` (:class:`GaitEstimator`)
-> estimates -> :mod:`yoyogait.evaluation` (metrics, tables, figures).  Names
are imported on first use, so ``import yoyogait.io`` does not load the native core.
"""

from __future__ import annotations

import importlib

__version__ = "0.1.0"

_SUBMODULES = ("io", "pipeline", "estimators", "evaluation", "synthetic", "model", "cli", "errors")

_LAZY = {
    "GaitEstimator": "estimators",
    "EstimatorConfig": "estimators",
    "EstimateResult": "estimators",
    "Status": "estimators",
    "OnlineEstimator": "estimators",
    "OnlineConfig": "estimators",
    "ImuOnlineEstimator": "estimators",
    "ImuConfig": "estimators",
    "ImuResult": "estimators",
    "ImuRecording": "io.imu_recording",
    "PRESETS": "estimators",
    "yoyo_model": "model",
    "YoyoTrajectory": "model",
    "gait_velocities": "pipeline",
    "GaitVelocities": "pipeline",
    "dft_check": "pipeline",
    "detect_gait_events": "pipeline",
    "Recording": "io",
    "read": "io",
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
