"""The cadence-change detector of the default estimator (gait/cadence_change.hpp, default_estimator.md sec. 2.8)."""

from __future__ import annotations

import dataclasses

import numpy as np
import pytest
from test_default_estimator import make_walk

from yoyogait import EstimatorConfig, GaitEstimator
from yoyogait.estimators.online import OnlineConfig, OnlineEstimator
from yoyogait.evaluation import online as on


def _without_detector() -> EstimatorConfig:
    cfg = EstimatorConfig()
    cfg.gait_filter = dataclasses.replace(cfg.gait_filter, cadence_change_adapt=False)
    return cfg


@pytest.fixture(scope="module")
def step_walks():
    return on.step_walk_items(seed=0)


def test_cadence_step_settles_within_1_25_s_online(step_walks):
    """Synthetic 1.6 -> 2.0 Hz step walks replayed online: f within 0.05 Hz (held 2 s) <= 1.25 s after the step."""
    times = [on.evaluate_item_online(item).metrics["online"]["cadence_step_time_s"] for item in step_walks]
    assert max(times) <= 1.25, times


def test_without_the_detector_the_cadence_step_takes_longer(step_walks, monkeypatch):
    """The same walks with cadence_change_adapt off settle after > 1.5 s: the gain above is the detector's."""
    original = OnlineEstimator.for_recording.__func__

    def without(cls, rec, point=None, *, up_axis=None, config=None):
        return original(cls, rec, point, up_axis=up_axis, config=OnlineConfig(estimator=_without_detector()))

    monkeypatch.setattr(OnlineEstimator, "for_recording", classmethod(without))
    times = [on.evaluate_item_online(item).metrics["online"]["cadence_step_time_s"] for item in step_walks]
    assert min(times) > 1.5, times


@pytest.mark.parametrize("seed", range(5))
def test_steady_walk_with_step_timing_variability_never_triggers(seed):
    """A steady walk with the model's step-timing variability (0.05 rad^2/s) never triggers: f equals f without it."""
    s = make_walk(40.0, f_hz=1.8, seed=seed, phase_jitter_rad2_per_s=0.05, amp_jitter=0.1)
    with_it = GaitEstimator().run(s["vx"], s["vz"], time_s=s["t"]).step_frequency_hz
    without = GaitEstimator(_without_detector()).run(s["vx"], s["vz"], time_s=s["t"]).step_frequency_hz
    assert np.array_equal(with_it, without)
