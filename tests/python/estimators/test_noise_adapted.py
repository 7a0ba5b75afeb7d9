"""The offline estimator's measurement noise follows the noise the velocities show (registry.noise_adapted)."""

from __future__ import annotations

import numpy as np
import pytest

from builders import camera_walk
from yoyogait import synthetic as sy
from yoyogait.estimators.config import EstimatorConfig
from yoyogait.estimators.registry import noise_adapted, preset_runner
from yoyogait.pipeline.velocities import gait_velocities


def test_a_laboratory_walk_changes_nothing():
    """On a clean SYNTHETIC lab walk the configuration is returned as it is, with no line."""
    walk = sy.make_walk(sy.SUBJECTS[0], "1-straight", seed=0)
    vel = gait_velocities(walk.recording)
    config = EstimatorConfig.default()
    used, line = noise_adapted(config, vel)
    assert used is config and line == ""


def test_depth_jitter_raises_the_forward_noise_only_and_says_so():
    """Centimetres of depth jitter raise meas_vx_density (not meas_vz) and the line names v_x."""
    _, rec = camera_walk(0, 0.025)
    vel = gait_velocities(rec)
    config = EstimatorConfig.default()
    used, line = noise_adapted(config, vel)
    assert used.gait_filter.meas_vx_density_m2_per_s > config.gait_filter.meas_vx_density_m2_per_s
    assert used.gait_filter.meas_vz_density_m2_per_s == config.gait_filter.meas_vz_density_m2_per_s
    assert line.startswith("input noise") and "vx" in line and "vz" not in line


def test_the_paper_estimator_is_left_as_published():
    """The paper's preset is never changed, however noisy the input."""
    _, rec = camera_walk(1, 0.05)
    config = EstimatorConfig.paper()
    assert noise_adapted(config, gait_velocities(rec)) == (config, "")


@pytest.mark.parametrize("seed", [0, 1, 2, 3])
def test_depth_jitter_estimate_is_right_and_covered(seed):
    """With 4 cm depth jitter (SYNTHETIC) the default run's step frequency after 3 s of walking is
    within 0.05 Hz (median) and within 2 std 90 % of the time, its speed within 2 std 90 % too (with
    the configured noise as given, the speed's coverage is 69-78 % on these walks)."""
    walk, rec = camera_walk(seed, 0.04)
    vel = gait_velocities(rec)
    res = preset_runner(EstimatorConfig.default())(vel)
    truth = walk.truth.at(vel.time_s)
    start = vel.time_s[np.argmax(truth.walking)]
    m = truth.walking & (vel.time_s > start + 3.0)
    f_err = np.abs(res.step_frequency_hz[m] - truth.step_frequency_hz[m])
    s_err = np.abs(res.speed_mps[m] - truth.speed_mps[m])
    assert np.median(f_err) < 0.05
    assert np.mean(f_err <= 2 * res.step_frequency_std_hz[m]) >= 0.9
    assert np.mean(s_err <= 2 * res.speed_std_mps[m]) >= 0.9
