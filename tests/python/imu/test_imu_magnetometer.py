"""The optional magnetometer of the IMU estimator on the SYNTHETIC IMU lab: absolute heading, gating."""

from __future__ import annotations

import dataclasses

import numpy as np
import pytest

from yoyogait import ImuConfig, ImuOnlineEstimator
from yoyogait.synthetic import SUBJECTS
from yoyogait.synthetic_imu import make_imu_walk

BIAS_RAD_S = np.deg2rad([1.0, 1.0, 1.0])


def _heading_error_deg(res, walk, from_s: float = 10.0) -> np.ndarray:
    err = np.angle(np.exp(1j * (res["heading_rad"] - walk.forward_heading_rad)))
    return np.rad2deg(np.abs(err[walk.recording.time_s >= from_s]))


def _walk(walk_type: str = "4-figure-eight", **kw):
    return make_imu_walk(
        SUBJECTS[0],
        walk_type,
        magnetometer=True,
        tilt_pitch_deg=20.0,
        tilt_roll_deg=10.0,
        gyro_bias_rad_s=BIAS_RAD_S,
        **kw,
    )


def _run(walk, mag=True, config=None):
    r = walk.recording
    return ImuOnlineEstimator(config).run(r.time_s, r.acc_mps2, r.gyr_rad_s, walk.mag_ut if mag else None)


@pytest.mark.parametrize("walk_type", ["1-straight", "3-rectangle", "4-figure-eight"])
def test_heading_is_absolute_with_a_magnetometer(walk_type):
    """With the magnetometer the heading is within 10 deg of magnetic north (median 5): turns, 1 deg/s gyro bias."""
    walk = _walk(walk_type)
    res = _run(walk)
    err = _heading_error_deg(res, walk)
    assert res["heading_absolute"].all()
    assert np.median(err) < 5.0 and err.max() < 10.0


def test_without_magnetometer_the_heading_is_relative_and_drifts():
    """Without it the heading is not absolute and drifts with the vertical gyro bias (more than with it)."""
    walk = _walk("1-straight")
    res = _run(walk, mag=False)
    assert not res["heading_absolute"].any()
    rel = np.angle(np.exp(1j * (res["heading_rad"] - walk.forward_heading_rad)))
    drift = np.rad2deg(np.abs(np.angle(np.exp(1j * (rel[-1] - rel[0])))))
    with_mag = _heading_error_deg(_run(walk), walk)[-1]
    assert drift > 10.0 > with_mag


def test_a_disturbed_field_is_not_used():
    """A 30 uT disturbance for 5 s (iron nearby) is rejected by the norm check: the heading stays within 10 deg."""
    walk = _walk("1-straight", mag_disturbance_ut=(0.0, 30.0, 0.0), mag_disturbance_s=(12.0, 17.0))
    gated = _heading_error_deg(_run(walk), walk)
    ungated = _heading_error_deg(_run(walk, config=ImuConfig(mag_norm_tolerance=10.0)), walk)
    assert gated.max() < 10.0 < ungated.max()


def test_no_magnetometer_gives_what_the_three_argument_update_gives():
    """A NaN magnetometer, or mag_kp_per_s 0, gives sample for sample what update(t, acc, gyr) gives."""
    walk = _walk("1-straight", duration_s=12.0)
    r = walk.recording
    base = _run(walk, mag=False)
    nan = ImuOnlineEstimator().run(r.time_s, r.acc_mps2, r.gyr_rad_s, np.full_like(walk.mag_ut, np.nan))
    off = _run(walk, config=dataclasses.replace(ImuConfig(), mag_kp_per_s=0.0))
    for name in base.column_names():
        assert np.array_equal(base[name], nan[name], equal_nan=True), name
        assert np.array_equal(base[name], off[name], equal_nan=True), name
    est = ImuOnlineEstimator()
    rows = [est.update(t, a, g, m) for t, a, g, m in zip(r.time_s, r.acc_mps2, r.gyr_rad_s, walk.mag_ut)]
    assert np.array_equal([e.heading_rad for e in rows], _run(walk)["heading_rad"])


def test_mag_of_the_wrong_shape_is_an_error_naming_it():
    """mag with 2 values, or not N x 3 in run(), is an error naming mag."""
    est = ImuOnlineEstimator()
    with pytest.raises(ValueError, match="mag"):
        est.update(0.0, [9.81, 0, 0], [0, 0, 0], [1.0, 2.0])
    with pytest.raises(ValueError, match="mag"):
        est.run(np.arange(3.0), np.zeros((3, 3)), np.zeros((3, 3)), np.zeros((2, 3)))
