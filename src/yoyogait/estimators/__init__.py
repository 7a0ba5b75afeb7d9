"""Estimators: the native gait estimator (paper and default presets) and the baselines.

* :mod:`.config`: :class:`EstimatorConfig` and the presets;
* :mod:`.gait_estimator`: :class:`GaitEstimator` (the C++ core, streaming and batch);
* :mod:`.online`: :class:`OnlineEstimator` (frames in, estimates out, causal front-end in C++);
* :mod:`.imu`: :class:`ImuOnlineEstimator` (one lower-back IMU in, estimates out, online);
* :mod:`.results`: :class:`EstimateResult`, what every estimator returns;
* :mod:`.oscillator`, :mod:`.sliding_dft`: the baselines, as algorithm objects;
* :mod:`.registry`: every estimator by name, as the evaluation and the CLI run them.
"""

from __future__ import annotations

from .config import ALGORITHMS, PRESETS, EstimatorConfig
from .gait_estimator import GaitEstimator, Status
from .imu import ImuConfig, ImuOnlineEstimator, ImuReason, ImuResult
from .online import ConcurrentUseError, OnlineConfig, OnlineEstimator, OnlineResult, OnlineStatus
from .oscillator import AdaptiveOscillator, OscillatorBaseline, OscillatorConfig, run_oscillator
from .registry import BASELINES, check_estimators, estimators
from .results import PREDICTION_HORIZONS_S, EstimateResult
from .sliding_dft import SlidingDft, sliding_dft

__all__ = [
    "ALGORITHMS",
    "BASELINES",
    "PREDICTION_HORIZONS_S",
    "PRESETS",
    "AdaptiveOscillator",
    "ConcurrentUseError",
    "EstimateResult",
    "EstimatorConfig",
    "GaitEstimator",
    "ImuConfig",
    "ImuOnlineEstimator",
    "ImuReason",
    "ImuResult",
    "OnlineConfig",
    "OnlineEstimator",
    "OnlineResult",
    "OnlineStatus",
    "OscillatorBaseline",
    "OscillatorConfig",
    "SlidingDft",
    "Status",
    "check_estimators",
    "estimators",
    "run_oscillator",
    "sliding_dft",
]
