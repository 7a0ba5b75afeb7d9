"""The estimator's sample time, from its one declaration (``sample_time_s`` in the C++ table of
include/yoyogait/config.hpp): the rate the paper's pipeline resamples to, the time step of the
baselines and the one-sample prediction horizon all follow it. Every stage may read it."""

from __future__ import annotations

from . import _core

SAMPLE_TIME_S: float = float(next(f["default"] for f in _core.config_schema() if f["name"] == "sample_time_s"))
"""T, the estimator's default time between samples [s] (0.04: the paper's 25 Hz)."""

RESAMPLE_RATE_HZ: float = 1.0 / SAMPLE_TIME_S
"""The rate the paper's pipeline resamples the velocities to, 1 / T [Hz]."""
