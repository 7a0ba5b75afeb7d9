"""The Yoyo-model (eq. 1-4) in Python and C++."""

import numpy as np

from yoyogait import _core, yoyo_model


def test_python_and_native_models_agree():
    """yoyo_model and the C++ yoyo_trajectory give the same positions and velocities for a varying step frequency."""
    t = np.linspace(0.0, 20.0, 4001)
    f = 1.6 + 0.4 * np.sin(t / 3.0)
    py = yoyo_model(t, 0.12, 0.025, f, z0_m=0.95, phase_rad=0.4)
    cc = _core.yoyo_trajectory(0.12, 0.025, 0.95, t, f, 0.4)
    for name in ("theta_rad", "x_m", "z_m", "vx_mps", "vz_mps"):
        np.testing.assert_allclose(cc[name], getattr(py, name), rtol=0, atol=1e-9, err_msg=name)


def test_velocities_are_derivatives_of_positions():
    """v_x and v_z of eq. 3-4 are the time derivatives of x and z of eq. 1-2, also when f, R and r vary."""
    t = np.linspace(0.0, 10.0, 20001)
    for R, r, f in (
        (0.115, 0.02, 1.8),
        (np.linspace(0.1, 0.13, t.size), np.linspace(0.02, 0.03, t.size), 1.5 + 0.05 * t),
    ):
        m = yoyo_model(t, R, r, f)
        np.testing.assert_allclose(np.gradient(m.x_m, t)[2:-2], m.vx_mps[2:-2], atol=2e-5)
        np.testing.assert_allclose(np.gradient(m.z_m, t)[2:-2], m.vz_mps[2:-2], atol=2e-5)


def test_mean_forward_speed_is_R_omega():
    """Over whole steps the mean forward velocity is R omega = 2 pi f R."""
    t = np.arange(0, 5.0, 0.0005)  # 10 whole steps at 2 Hz
    m = yoyo_model(t, 0.11, 0.02, 2.0)
    assert abs(m.vx_mps.mean() - 2 * np.pi * 2.0 * 0.11) < 1e-3
