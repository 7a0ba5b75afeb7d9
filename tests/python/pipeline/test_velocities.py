"""The velocity pipeline (gap filling, SG differentiation, 25 Hz, forward definitions) and the DFT check."""

from __future__ import annotations

import numpy as np
import pytest

import yoyogait
from yoyogait.errors import InputError
from yoyogait.io import Recording
from yoyogait.model import yoyo_model
from yoyogait.pipeline import spectral

STEP_HZ = 1.8


def pelvis_walk(rate_hz=100.0, duration_s=6.0, sway_m=0.0, forward_offset_rad=0.0, R_m=0.11, r_m=0.02):
    """One-point recording of a Yoyo-model pelvis walking along +x, z up, with optional lateral sway.

    ``forward_offset_rad`` shifts the forward oscillation (pi: forward slowest
    where the pelvis is highest, as in an inverted pendulum).
    """
    t = np.arange(int(duration_s * rate_hz)) / rate_hz
    theta = 2 * np.pi * STEP_HZ * t
    x = R_m * theta + r_m * np.sin(theta + forward_offset_rad)
    y = sway_m * np.sin(theta / 2)  # sway at stride frequency
    z = 0.95 + r_m * np.cos(theta)
    pos = np.column_stack([x, y, z])[:, None, :]
    return Recording(pos, ["PELVIS"], t, rate_hz=rate_hz, up_axis="z", source="synthetic")


def test_short_gaps_are_filled_and_long_ones_stay_missing():
    """Gaps up to max_gap_s are interpolated; longer gaps stay NaN (never zero)."""
    rec = pelvis_walk()
    rec.positions_m[200:215] = np.nan  # 0.15 s
    rec.positions_m[400:450] = np.nan  # 0.5 s
    v = yoyogait.gait_velocities(rec, point="PELVIS")
    _, vz_true = _truth(v.time_s)
    short = (v.time_s >= 1.9) & (v.time_s <= 2.3)
    assert np.all(np.isfinite(v.vz[short]))
    assert np.max(np.abs(v.vz[short] - vz_true[short])) < 0.01
    assert np.all(np.isnan(v.vz[(v.time_s > 4.05) & (v.time_s < 4.45)]))
    filled = yoyogait.gait_velocities(rec, point="PELVIS", max_gap_s=0.6)
    assert np.all(np.isfinite(filled.vz[(v.time_s > 4.05) & (v.time_s < 4.45)]))


@pytest.mark.parametrize("frames", [[0], [250], [250, 251], [599]], ids=["first", "middle", "two", "last"])
def test_a_glitch_of_a_frame_or_two_is_a_gap_not_a_burst(frames):
    """A coordinate read as 0 on one or two frames (the first, the last, inside) is left out as a spike:
    the velocity stays the model's, as over a gap, at 25 and at 100 Hz; a marker that moves for good is kept."""
    for rate in (25.0, 100.0):
        rec = pelvis_walk(rate_hz=rate)
        glitch = [min(k, len(rec.time_s) - 1) for k in frames] if rate == 100.0 else [k // 4 for k in frames]
        rec.positions_m[glitch, 0, 2] = 0.0
        v = yoyogait.gait_velocities(rec, point="PELVIS")
        _, vz_true = _truth(v.time_s)
        inner = (v.time_s > 0.3) & (v.time_s < 5.6)
        assert np.nanmax(np.abs(v.vz - vz_true)[inner]) < 0.02, (rate, frames)
        assert np.nanmax(np.abs(v.vz)) < 0.5, (rate, frames)
    moved = pelvis_walk()
    moved.positions_m[300:, 0, 2] += 0.3  # a marker re-placed 0.3 m higher: it moves, it is no spike
    kept = yoyogait.gait_velocities(moved, point="PELVIS")
    assert np.nanmax(kept.vz) > 1.0


def _truth(t, R_m=0.11, r_m=0.02):
    w = 2 * np.pi * STEP_HZ
    return R_m * w + r_m * w * np.cos(w * t), -r_m * w * np.sin(w * t)


def test_window_is_in_seconds_so_the_capture_rate_does_not_matter():
    """The same walk captured at 60, 120 and 240 Hz gives the same 25 Hz velocities."""
    results = [yoyogait.gait_velocities(pelvis_walk(rate)) for rate in (60.0, 120.0, 240.0)]
    n = min(len(r.vz) for r in results)
    for r in results[1:]:
        assert np.max(np.abs(r.vz[5 : n - 5] - results[0].vz[5 : n - 5])) < 0.004
    a_wide = yoyogait.gait_velocities(pelvis_walk(240.0), window_s=0.6)
    assert np.std(a_wide.vz) < 0.9 * np.std(results[2].vz)  # a longer window smooths more


def test_output_is_resampled_to_the_requested_rate():
    """Velocities come on a uniform grid at rate_hz (25 Hz by default, the paper's T = 0.04 s)."""
    v = yoyogait.gait_velocities(pelvis_walk(200.0))
    assert v.rate_hz == 25.0 and np.allclose(np.diff(v.time_s), 0.04)
    v50 = yoyogait.gait_velocities(pelvis_walk(200.0), rate_hz=50.0)
    assert np.allclose(np.diff(v50.time_s), 0.02)


def test_irregular_timestamps_are_put_on_a_uniform_grid_first():
    """Jittered timestamps (e.g. from a CSV export) still give the right velocity."""
    rec = pelvis_walk(100.0)
    jitter = np.random.default_rng(1).uniform(-0.002, 0.002, rec.n_frames)
    jitter[0] = 0.0
    t = rec.time_s + jitter
    theta = 2 * np.pi * STEP_HZ * t
    rec.positions_m[:, 0, 0] = 0.11 * theta + 0.02 * np.sin(theta)
    rec.positions_m[:, 0, 2] = 0.95 + 0.02 * np.cos(theta)
    rec.time_s = t
    v = yoyogait.gait_velocities(rec)
    vx_true, vz_true = _truth(v.time_s)
    inner = slice(10, -10)
    assert np.max(np.abs(v.vz[inner] - vz_true[inner])) < 0.01
    assert np.max(np.abs(v.vx[inner] - vx_true[inner])) < 0.01


def test_norm_folds_sway_in_and_heading_keeps_the_sign():
    """The paper's 2-norm is never negative and grows with sway; the heading option follows the signed forward speed."""
    rec = pelvis_walk(sway_m=0.03, R_m=0.03, r_m=0.04)  # forward speed 0.34 +- 0.45 m/s: it goes backwards
    norm = yoyogait.gait_velocities(rec)
    signed = yoyogait.gait_velocities(rec, forward="heading")
    vx_true, _ = _truth(norm.time_s, R_m=0.03, r_m=0.04)
    inner = slice(15, -15)
    assert norm.forward == "norm" and signed.forward == "heading"
    assert np.all(norm.vx[inner] >= 0) and np.min(signed.vx[inner]) < -0.05
    assert np.max(np.abs(signed.vx[inner] - vx_true[inner])) < 0.03
    assert np.all(norm.vx[inner] >= np.abs(signed.vx[inner]) - 1e-9)
    assert np.mean(norm.vx[inner]) > np.mean(vx_true[inner]) + 0.05  # the norm overstates the forward speed
    assert np.array_equal(norm.vx_signed, signed.vx)


def test_heading_follows_a_turn():
    """On a path that turns by 180 degrees the signed forward speed stays positive and equal to the path speed."""
    rate = 100.0
    t = np.arange(int(8 * rate)) / rate
    heading = np.pi * np.clip((t - 3) / 2, 0, 1)  # turn between 3 s and 5 s
    speed = 1.2
    x = np.cumsum(speed * np.cos(heading)) / rate
    y = np.cumsum(speed * np.sin(heading)) / rate
    z = 0.95 + 0.02 * np.cos(2 * np.pi * STEP_HZ * t)
    rec = Recording(np.column_stack([x, y, z])[:, None, :], ["PELVIS"], t, rate_hz=rate, up_axis="z")
    v = yoyogait.gait_velocities(rec, forward="heading")
    inner = slice(15, -15)
    assert np.allclose(v.vx[inner], speed, atol=0.03)


def test_recording_too_short_for_the_filter_is_an_error():
    """Fewer than min_usable_s seconds of known velocity raise a clear InputError."""
    with pytest.raises(InputError, match="shorter than the filter needs"):
        yoyogait.gait_velocities(pelvis_walk(duration_s=1.0))
    rec = pelvis_walk(duration_s=4.0)
    rec.positions_m[30:] = np.nan  # only 0.3 s of pelvis
    with pytest.raises(InputError, match="shorter than the filter needs"):
        yoyogait.gait_velocities(rec)
    assert yoyogait.gait_velocities(pelvis_walk(duration_s=1.0), min_usable_s=0.5).usable_s >= 0.5


def test_bad_options_are_errors():
    """An unknown forward definition or point name is an InputError, not a traceback."""
    with pytest.raises(InputError, match="forward"):
        yoyogait.gait_velocities(pelvis_walk(), forward="sideways")
    with pytest.raises(InputError, match="no point 'LASI'.*available: PELVIS"):
        yoyogait.gait_velocities(pelvis_walk(), point="LASI")


def test_ready_velocities_are_resampled_not_differentiated(tmp_path):
    """A CSV of vx, vz at 100 Hz comes out at 25 Hz with the same values."""
    t = np.arange(400) / 100.0
    vx, vz = _truth(t)
    path = tmp_path / "v.csv"
    path.write_text("time_s,vx,vz\n" + "\n".join(f"{a:.4f},{b:.9f},{c:.9f}" for a, b, c in zip(t, vx, vz)) + "\n")
    v = yoyogait.gait_velocities(yoyogait.read(path))
    assert np.allclose(np.diff(v.time_s), 0.04)
    vx_true, vz_true = _truth(v.time_s)
    assert np.allclose(v.vx, vx_true, atol=1e-6) and np.allclose(v.vz, vz_true, atol=1e-6)
    assert v.forward == "file"


# ------------------------------------------------------------------------------------------- DFT check


def model_velocities(offset_rad=0.0, second_harmonic=0.0, seconds=10.0, noise=0.0):
    """GaitVelocities of the Yoyo-model at 25 Hz (eq. 3-4), all walking."""
    t = np.arange(int(seconds * 25)) / 25.0
    walk = yoyo_model(t, 0.115, 0.02, STEP_HZ)
    w = 2 * np.pi * STEP_HZ
    vx = walk.vx_mps if offset_rad == 0 else 0.115 * w + 0.02 * w * np.cos(w * t + offset_rad)
    vz = walk.vz_mps + second_harmonic * np.sin(2 * w * t + 0.3)
    rng = np.random.default_rng(3)
    vx = vx + noise * rng.standard_normal(t.size)
    vz = vz + noise * rng.standard_normal(t.size)
    return yoyogait.GaitVelocities(t, vx, vz, 25.0, "model", "z", "norm", vx.copy(), np.ones(t.size, bool))


def test_dft_check_finds_the_model_step_frequency_and_minus_90_degrees():
    """On the Yoyo-model itself the DFT check finds the step frequency and the model's -90 deg offset."""
    check = spectral.dft_check(model_velocities(noise=0.02))
    assert check.step_frequency_hz == pytest.approx(STEP_HZ, abs=0.02)
    assert check.forward_frequency_hz == pytest.approx(STEP_HZ, abs=0.02)
    assert check.phase_offset_deg == pytest.approx(-90, abs=5)
    assert check.offset_sign == "negative" and check.matches_model
    assert check.verdict == "consistent" and "consistent" in check.summary()


def test_dft_check_reports_the_opposite_sign_of_an_inverted_pendulum():
    """Forward velocity lowest where the pelvis is highest shows as +90 deg, flagged as the opposite of the model."""
    check = spectral.dft_check(model_velocities(offset_rad=np.pi))
    assert check.phase_offset_deg == pytest.approx(90, abs=5)
    assert check.offset_sign == "positive" and not check.matches_model
    assert check.verdict == "opposite sign" and "opposite sign" in check.summary()


def test_step_frequency_is_the_fundamental_when_the_pelvis_rises_twice_per_step():
    """A vertical velocity whose second harmonic is the strongest peak still gives the step frequency."""
    v = model_velocities(second_harmonic=0.35)  # 1.5 x the fundamental, as in slow stylised walks
    assert spectral.dominant_frequency(v.vz, 25.0) == pytest.approx(2 * STEP_HZ, abs=0.02)
    assert spectral.step_frequency(v.vz, 25.0) == pytest.approx(STEP_HZ, abs=0.02)
    plain = model_velocities(noise=0.05)  # no real subharmonic: stays at the peak
    assert spectral.step_frequency(plain.vz, 25.0) == pytest.approx(STEP_HZ, abs=0.02)


def test_dft_check_needs_enough_walking():
    """A walking stretch shorter than min_duration_s is an InputError."""
    v = model_velocities(seconds=10.0)
    v.walking[:] = False
    v.walking[:20] = True
    with pytest.raises(InputError, match="walking"):
        spectral.dft_check(v)
