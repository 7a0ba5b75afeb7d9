"""Frames of k points from point messages that arrive one by one, and the covariances (no ROS needed)."""

from __future__ import annotations

import math

import numpy as np

from yoyogait.ros2.assembly import FrameAssembler
from yoyogait.ros2.messages import UNOBSERVED_VARIANCE, velocity_covariance


def test_a_frame_goes_out_when_its_last_point_arrives_in_stamp_order_with_late_and_repeated_points_counted():
    """Two points per stamp, interleaved: each out once complete, older first; a late and a repeated point dropped."""
    a = FrameAssembler(2, window_s=1.0)
    out = []
    out += a.add(0, 1, 0.01, np.array([1.0, 0, 0]), 0.0)
    out += a.add(0, 2, 0.02, np.array([2.0, 0, 0]), 0.0)
    out += a.add(0, 2, 0.02, np.array([9.0, 0, 0]), 0.0)  # repeated
    out += a.add(1, 1, 0.01, np.array([1.5, 0, 0]), 0.0)
    out += a.add(1, 2, 0.02, np.array([2.5, 0, 0]), 0.0)
    out += a.add(1, 1, 0.01, np.array([7.0, 0, 0]), 0.0)  # late
    assert [f.key for f in out] == [1, 2] and all(f.complete for f in out)
    np.testing.assert_array_equal(out[1].positions[:, 0], [2.0, 2.5])
    assert a.repeated_points == 1 and a.late_points == 1 and a.incomplete_frames == 0


def test_an_incomplete_frame_goes_out_with_nan_when_a_newer_completes_or_its_window_ends():
    """A marker never sent: its stamp goes out with NaN for it, before the newer complete one, or on expiry."""
    a = FrameAssembler(2, window_s=0.05)
    a.add(0, 1, 0.01, np.array([1.0, 0, 0]), 0.0)
    a.add(0, 2, 0.02, np.array([2.0, 0, 0]), 0.0)
    out = a.add(1, 2, 0.02, np.array([2.5, 0, 0]), 0.01)
    assert [f.key for f in out] == [1, 2] and np.isnan(out[0].positions[1]).all()
    a.add(0, 3, 0.03, np.array([3.0, 0, 0]), 0.02)
    assert a.expire(0.05) == [] and [f.key for f in a.expire(0.08)] == [3]
    assert a.incomplete_frames == 2


def test_covariances_are_symmetric_psd_with_the_std_along_the_heading_and_large_elsewhere():
    """For headings around the circle and each up axis: symmetric, PSD, speed_std^2 along u, 1e6 across and angular."""
    for up, axes in (("z", (0, 1, 2)), ("y", (0, 2, 1)), ("x", (1, 2, 0))):
        for h in np.linspace(-math.pi, math.pi, 13):
            c = np.array(velocity_covariance(axes, h, 0.05, 0.02)).reshape(6, 6)
            assert np.array_equal(c, c.T)
            assert np.linalg.eigvalsh(c).min() >= -1e-9 * UNOBSERVED_VARIANCE
            u = np.zeros(6)
            u[axes[0]], u[axes[1]] = math.cos(h), math.sin(h)
            assert math.isclose(u @ c @ u, 0.05**2, rel_tol=1e-6, abs_tol=1e-6), up
            assert c[axes[2], axes[2]] == 0.02**2 and c[3, 3] == c[4, 4] == c[5, 5] == UNOBSERVED_VARIANCE
    c = np.array(velocity_covariance((0, 1, 2), math.nan, math.nan)).reshape(6, 6)
    assert np.all(np.diag(c) == UNOBSERVED_VARIANCE)  # before the first estimate: nothing observed
