"""Acquisition of the online estimator: the start-up bank follows a start's rising cadence."""

from __future__ import annotations

import dataclasses

import numpy as np

from yoyogait.estimators.config import EstimatorConfig, GaitFilterConfig, OnlineConfig
from yoyogait.evaluation.datasets import synthetic_items
from yoyogait.evaluation.online import evaluate_item_online


def _first3s_errors(bank_q_omega: float) -> np.ndarray:
    gf = dataclasses.replace(GaitFilterConfig(), bank_q_omega_rad2_per_s3=bank_q_omega)
    cfg = dataclasses.replace(OnlineConfig(), estimator=EstimatorConfig(gait_filter=gf))
    return np.array(
        [evaluate_item_online(it, cfg).metrics["online"]["f_err_first3s_median_hz"] for it in synthetic_items()]
    )


def test_bank_frequency_walk_follows_the_start_ramp():
    """On the SYNTHETIC lab's starts (cadence rising from 0 over 1.5 s), a larger frequency random walk of the
    bank's members (0.25, five times the steady q_omega) gives a lower median step-frequency error in the first
    3 s than the steady q_omega (the default, which the IMU estimator needs)."""
    steady = GaitFilterConfig().q_omega_rad2_per_s3
    assert GaitFilterConfig().bank_q_omega_rad2_per_s3 == steady
    assert np.median(_first3s_errors(5.0 * steady)) < np.median(_first3s_errors(steady))
