"""The offline estimator's measurement noise follows the noise the velocities show (registry.noise_adapted)."""

from __future__ import annotations

import dataclasses

import numpy as np
import pytest

from yoyogait import synthetic as sy
from yoyogait import synthetic_conditions as sc
from yoyogait.estimators.config import EstimatorConfig
from yoyogait.estimators.registry import noise_adapted, preset_runner
from yoyogait.pipeline.velocities import gait_velocities


def _camera_walk(seed: int, depth_jitter_m: float):
    """A SYNTHETIC lab walk at 60 Hz seen as a camera sees it: 2 mm everywhere, and jitter correlated
    over 50 ms along one horizontal axis (a camera's depth), as a markerless capture's keypoints."""
    walk = sy.make_walk(sy.SUBJECTS[seed % 3], "1-straight", rate_hz=60.0, seed=seed, noise_m=0.0, dropouts=False)
    rec = walk.recording
    pos = np.array(rec.positions_m)
    rng = np.random.default_rng(seed)
    depth = [a for a in range(3) if a != "xyz".index(rec.up_axis)][0]
    pos += rng.normal(0.0, 0.002, pos.shape)
    pos[:, :, depth] += depth_jitter_m * sc._correlated(rng, pos.shape[:2], 60.0, 0.05)
    return walk, dataclasses.replace(rec, positions_m=pos)


def test_a_laboratory_walk_changes_nothing():
    """On a clean SYNTHETIC lab walk the configuration is returned as it is, with no line."""
    walk = sy.make_walk(sy.SUBJECTS[0], "1-straight", seed=0)
    vel = gait_velocities(walk.recording)
    config = EstimatorConfig.default()
    used, line = noise_adapted(config, vel)
    assert used is config and line == ""


def test_depth_jitter_raises_the_forward_noise_only_and_says_so():
    """Centimetres of depth jitter raise meas_vx_density (not meas_vz) and the line names v_x."""
    _, rec = _camera_walk(0, 0.025)
    vel = gait_velocities(rec)
    config = EstimatorConfig.default()
    used, line = noise_adapted(config, vel)
    assert used.gait_filter.meas_vx_density_m2_per_s > config.gait_filter.meas_vx_density_m2_per_s
    assert used.gait_filter.meas_vz_density_m2_per_s == config.gait_filter.meas_vz_density_m2_per_s
    assert line.startswith("input noise") and "vx" in line and "vz" not in line


def test_the_paper_estimator_is_left_as_published():
    """The paper's preset is never changed, however noisy the input."""
    _, rec = _camera_walk(1, 0.05)
    config = EstimatorConfig.paper()
    assert noise_adapted(config, gait_velocities(rec)) == (config, "")


@pytest.mark.parametrize("seed", [0, 1, 2, 3])
def test_depth_jitter_estimate_is_right_and_covered(seed):
    """With 4 cm depth jitter (SYNTHETIC) the default run's step frequency after 3 s of walking is
    within 0.05 Hz (median) and within 2 std 90 % of the time, its speed within 2 std 90 % too (with
    the configured noise as given, the speed's coverage is 69-78 % on these walks)."""
    walk, rec = _camera_walk(seed, 0.04)
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
