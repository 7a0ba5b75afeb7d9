"""The online front-end follows the input noise, rejects outliers and tells gait from single transients."""

from __future__ import annotations

import numpy as np
import pytest

from builders import camera_walk
from yoyogait import synthetic as sy
from yoyogait import synthetic_conditions as sc
from yoyogait.estimators import OnlineConfig, OnlineEstimator

NAMES = ["LASI", "RASI", "LPSI", "RPSI"]
OFFSETS = np.array([[0.075, -0.125], [0.075, 0.125], [-0.075, -0.125], [-0.075, 0.125]])


def pelvis(rate_hz=100.0, dur_s=20.0, speed_mps=1.3, f_hz=1.8, noise_m=0.0, seed=0):
    """Four pelvis markers (m, z up) of a walker along x, with white noise per coordinate."""
    rng = np.random.default_rng(seed)
    t = np.arange(int(dur_s * rate_hz)) / rate_hz
    th = 2 * np.pi * f_hz * t
    p = np.zeros((len(t), 4, 3))
    p[:, :, 0] = (speed_mps * t - 0.012 * np.sin(th))[:, None] + OFFSETS[None, :, 0]
    p[:, :, 1] = OFFSETS[None, :, 1]
    p[:, :, 2] = (1.0 + 0.012 * np.cos(th))[:, None]
    return t, p + rng.normal(0.0, noise_m, p.shape)


def run(t, p, **online):
    return OnlineEstimator(NAMES, "z", config=OnlineConfig(**online)).run(t, p)


def test_input_noise_is_estimated_within_a_third():
    """With 2 cm white noise per marker (1 cm on the mean of four), input_noise_m lies within 1/3 of 1 cm after 3 s."""
    t, p = pelvis(rate_hz=60.0, noise_m=0.02)
    r = run(t, p)
    noise = np.median(r.input_noise_m[t > 3.0])
    assert abs(noise - 0.01) < 0.01 / 3


def test_clean_input_is_served_as_without_adaptation():
    """At 0.2 mm noise (below meas_position_std_m) the adaptive front-end gives the estimates of the fixed one."""
    t, p = pelvis(noise_m=0.0002)
    a, b = run(t, p), run(t, p, adapt_to_noise=False)
    assert np.array_equal(a.step_frequency_hz, b.step_frequency_hz)
    assert np.array_equal(a.speed_mps, b.speed_mps)


def test_centimetre_jitter_gives_the_step_frequency_not_a_noise_peak():
    """SYNTHETIC markerless capture at 60 Hz (2 cm jitter, swaps, dropouts): f within 0.1 Hz of the truth after 5 s."""
    walk = sc.render("markerless-60hz", sy.SUBJECTS[0])
    rec = walk.recording
    r = OnlineEstimator.for_recording(rec, None).run(rec)
    t = np.asarray(r.time_s)
    f_true = np.interp(t, walk.truth.time_s, walk.truth.step_frequency_hz)
    late = (t > 5.0) & (f_true > 0)
    assert np.median(np.abs(r.step_frequency_hz[late] - f_true[late])) < 0.1


def test_a_single_frame_outlier_is_not_differentiated():
    """One frame of every marker 10 cm aside mid-walk: the front-end's v_z stays within 0.3 m/s of its neighbours."""
    t, p = pelvis()
    p[1000, :, 2] += 0.1
    r = run(t, p)
    assert np.max(np.abs(r.vz_mps[995:1010])) < 0.3


def test_sit_to_stand_is_not_walking():
    """SYNTHETIC sit-to-stand (three rises and sits): walking at most 5 % of the time."""
    walk = sc.render("sit-to-stand", sy.SUBJECTS[0])
    r = OnlineEstimator.for_recording(walk.recording, None).run(walk.recording)
    assert np.mean(r.walking) <= 0.05


def test_brisk_chair_stands_are_not_walking():
    """SYNTHETIC chair-stand (six brisk rises and sits, extrema within 2.5 s): walking at most 5 % of the time."""
    walk = sc.render("chair-stand", sy.SUBJECTS[0])
    r = OnlineEstimator.for_recording(walk.recording, None).run(walk.recording)
    assert np.mean(r.walking) <= 0.05 and not np.any(r.valid)


def test_walking_is_still_walking_after_its_first_steps():
    """A clean walk is reported walking on at least 95 % of its frames after the first 2 s."""
    t, p = pelvis()
    r = run(t, p)
    assert np.mean(r.walking[t > 2.0]) >= 0.95


def _walking_f_error_after_3s(walk) -> float:
    rec = walk.recording
    r = OnlineEstimator.for_recording(rec, None).run(rec)
    t = np.asarray(r.time_s)
    tr = walk.truth.at(t)
    walking = np.asarray(tr.walking, dtype=bool)
    after = walking & (t >= t[np.flatnonzero(walking)[0]] + 3.0)
    return float(np.median(np.abs(r.step_frequency_hz[after] - tr.step_frequency_hz[after])))


def test_markerless_renderings_give_the_step_frequency_within_the_issue_target():
    """Every SYNTHETIC markerless rendering (30, 60 Hz, 3 subjects): median f error after 3 s of walking <= 0.04 Hz."""
    for condition in ("markerless-30hz", "markerless-60hz"):
        for subject in sy.SUBJECTS:
            err = _walking_f_error_after_3s(sc.render(condition, subject))
            assert err <= 0.04, (condition, subject.name, err)


def test_standing_sway_seen_markerless_is_not_walking():
    """SYNTHETIC standing sway with markerless noise at 30 Hz, three subjects: walking at most 5 % of the time."""
    for subject in sy.SUBJECTS:
        walk = sc.render("standing-sway", subject)
        rec = sc.markerless_noise(walk.recording, seed=0, rate_hz=30.0)
        r = OnlineEstimator.for_recording(rec, None).run(rec)
        assert np.mean(r.walking) <= 0.05, subject.name


def test_the_noise_estimate_does_not_overshoot_at_the_start():
    """One point at 30 Hz, 2 cm white noise: input_noise_m never exceeds 1.5 x 2 cm (3.4 cm without the ratio bound)."""
    rng = np.random.default_rng(1)
    t, p = pelvis(rate_hz=30.0, dur_s=6.0)
    one = p.mean(axis=1, keepdims=True) + rng.normal(0.0, 0.02, (len(t), 1, 3))
    r = OnlineEstimator(["C"], "z").run(t, one)
    assert np.max(r.input_noise_m) <= 1.5 * 0.02


def test_noise_below_the_knee_changes_nothing():
    """Noise below noise_knee_m (1 mm per marker): every output as with the knee out of reach (no adaptation)."""
    t, p = pelvis(rate_hz=60.0, noise_m=0.001)
    a, b = run(t, p), run(t, p, noise_knee_m=1e100)
    for name in ("step_frequency_hz", "speed_mps", "vx_hat_mps", "walking", "valid", "input_noise_m"):
        assert np.array_equal(np.asarray(getattr(a, name)), np.asarray(getattr(b, name))), name


@pytest.mark.parametrize("seed", [0, 2, 5])
def test_depth_jitter_is_weighed_on_the_forward_channel_only(seed):
    """6 cm of depth jitter (SYNTHETIC): after 3 s of walking the step frequency is within 0.02 Hz (median)
    and within 2 std 95 % of the time: the jitter is v_x's measurement noise, v_z keeps its weight
    (with the three-axis noise on both channels seeds 2 and 5 lock 0.25-0.9 Hz off)."""
    walk, rec = camera_walk(seed, 0.06)
    r = OnlineEstimator.for_recording(rec).run(rec)
    t = np.asarray(r.time_s)
    truth = walk.truth
    m = truth.walking & (t > t[np.argmax(truth.walking)] + 3.0)
    err = np.abs(np.asarray(r.step_frequency_hz)[m] - truth.step_frequency_hz[m])
    assert np.median(err) < 0.02
    assert np.mean(err <= 2 * np.asarray(r.step_frequency_std_hz)[m]) >= 0.95


def test_arm_gestures_followed_by_the_hand_are_not_walking():
    """SYNTHETIC arm gestures (waving, pointing, pumping at 1-2.5 Hz), the hand followed, 3 subjects: walking <= 5 %."""
    for subject in sy.SUBJECTS:
        rec = sc.render("arm-gestures", subject).recording
        r = OnlineEstimator.for_recording(rec, "hand").run(rec)
        assert np.mean(r.walking) <= 0.05, subject.name


def test_a_walk_followed_by_the_hand_is_walking_once_it_travels():
    """The lab's straight walk, the hand followed (it must travel to walk): walking on >= 95 % of the frames 3 s in."""
    walk = sy.make_walk(sy.SUBJECTS[0], "1-straight")
    r = OnlineEstimator.for_recording(walk.recording, "hand").run(walk.recording)
    t = np.asarray(r.time_s)
    assert np.mean(r.walking[t > 3.0]) >= 0.95


def test_only_a_hand_must_travel_to_walk():
    """for_recording sets gait_in_place false for the hand (found or named) and keeps it for the pelvis."""
    rec = sy.make_walk(sy.SUBJECTS[0], "1-straight").recording
    assert not OnlineEstimator.for_recording(rec, "hand").config.gait_in_place
    assert not OnlineEstimator.for_recording(rec, [sy.HAND_MARKER]).config.gait_in_place
    assert OnlineEstimator.for_recording(rec).config.gait_in_place


def test_markerless_renderings_with_heels_are_valid_and_never_confidently_wrong():
    """SYNTHETIC markerless renderings (30, 60 Hz, 3 subjects): valid on less than 20 % of the walking after 3 s
    without the heels (INPUT_NOISY), on at least 80 % with them, never with an f error above 0.15 Hz beyond 2 std."""
    for condition in ("markerless-30hz", "markerless-60hz"):
        for subject in sy.SUBJECTS:
            walk = sc.render(condition, subject)
            rec = walk.recording
            without = OnlineEstimator.for_recording(rec, None).run(rec)
            r = OnlineEstimator.for_recording(rec, None, feet=True).run(rec)
            t = np.asarray(r.time_s)
            tr = walk.truth.at(t)
            walking = np.asarray(tr.walking, dtype=bool)
            after = walking & (t >= t[np.flatnonzero(walking)[0]] + 3.0)
            err = np.abs(r.step_frequency_hz - tr.step_frequency_hz)
            wrong = r.valid & after & (err > 0.15) & (err > 2 * r.step_frequency_std_hz)
            assert without.valid[after].mean() < 0.2, (condition, subject.name)
            assert r.valid[after].mean() >= 0.8, (condition, subject.name)
            assert not wrong.any(), (condition, subject.name)
