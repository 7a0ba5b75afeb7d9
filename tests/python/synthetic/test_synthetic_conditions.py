"""The SYNTHETIC renderings of real-world conditions: their noise, their truth, their labels."""

from __future__ import annotations

import numpy as np
import pytest

from yoyogait import synthetic as sy
from yoyogait import synthetic_conditions as sc
from yoyogait.errors import InputError

S1 = sy.SUBJECTS[0]


@pytest.fixture(scope="module")
def clean_walk():
    return sy.make_walk(S1, "1-straight", rate_hz=100.0, duration_s=20.0, noise_m=0.0, dropouts=False)


@pytest.fixture(scope="module")
def rendered():
    return {c: sc.render(c, S1) for c in sc.CONDITIONS}


def _steady(truth, margin_s=3.0):
    t = truth.time_s
    edges = t[np.flatnonzero(np.diff(truth.walking.astype(int))) + 1]
    ok = truth.walking.copy()
    for e in np.concatenate([edges, [t[0], t[-1]]]):
        ok &= np.abs(t - e) > margin_s
    return ok


def test_markerless_jitter_has_the_requested_standard_deviation(clean_walk):
    """Without swaps and dropouts, the markerless noise has the requested standard deviation (2 cm) and zero mean."""
    rec = sc.markerless_noise(
        clean_walk.recording, jitter_m=0.02, seed=1, swaps_per_min=0, dropouts_per_min=0, frame_dropout_probability=0
    )
    err = rec.positions_m - clean_walk.recording.positions_m
    assert np.isfinite(err).all()
    assert np.std(err) == pytest.approx(0.02, rel=0.05)
    assert abs(np.mean(err)) < 0.002
    assert rec.metadata["markerless_jitter_m"] == 0.02 and "SYNTHETIC" in rec.source


def test_markerless_slow_share_moves_the_jitter_from_frame_to_frame_into_slow_errors(clean_walk):
    """With slow_share 1 the jitter keeps its size but changes little from one frame to the next; with 0 it is white."""
    kw = dict(jitter_m=0.02, seed=1, swaps_per_min=0, dropouts_per_min=0, frame_dropout_probability=0)
    steps = {}
    for share in (0.0, 1.0):
        rec = sc.markerless_noise(clean_walk.recording, slow_share=share, slow_tau_s=0.5, **kw)
        err = rec.positions_m - clean_walk.recording.positions_m
        assert np.std(err) == pytest.approx(0.02, rel=0.15)
        steps[share] = np.std(np.diff(err, axis=0))
    assert steps[0.0] == pytest.approx(0.02 * np.sqrt(2), rel=0.05) and steps[1.0] < 0.2 * steps[0.0]


def test_markerless_noise_is_seeded_and_the_seed_matters(clean_walk):
    """The same seed gives the same rendering, another seed another one."""
    a = sc.markerless_noise(clean_walk.recording, seed=3)
    b = sc.markerless_noise(clean_walk.recording, seed=3)
    c = sc.markerless_noise(clean_walk.recording, seed=4)
    np.testing.assert_array_equal(a.positions_m, b.positions_m)
    assert not np.array_equal(np.nan_to_num(a.positions_m), np.nan_to_num(c.positions_m))


def test_markerless_swaps_exchange_left_and_right_tracks(clean_walk):
    """With swaps, some frames hold RASI's position under LASI's name (and the other way round)."""
    rec = sc.markerless_noise(
        clean_walk.recording, jitter_m=0.0, seed=2, swaps_per_min=30, dropouts_per_min=0, frame_dropout_probability=0
    )
    assert rec.metadata["markerless_swaps_n"] > 0
    lasi, rasi = rec.point("LASI"), rec.point("RASI")
    clean_l, clean_r = clean_walk.recording.point("LASI"), clean_walk.recording.point("RASI")
    swapped = np.all(lasi == clean_r, axis=1)
    assert swapped.any() and np.array_equal(swapped, np.all(rasi == clean_l, axis=1))
    assert not np.all(lasi == clean_l, axis=1)[swapped].any()


def test_markerless_dropouts_are_nan_never_zero(clean_walk):
    """Dropouts leave points missing (NaN), whole frames too, and never at zero."""
    rec = sc.markerless_noise(clean_walk.recording, seed=5, dropouts_per_min=20, frame_dropout_probability=0.02)
    missing = np.isnan(rec.positions_m).any(axis=2)
    assert 0 < missing.mean() < 0.3 and missing.all(axis=1).any()
    assert not np.any(rec.positions_m == 0.0)


def test_markerless_rate_takes_every_kth_frame(clean_walk):
    """rate_hz 50 of a 100 Hz recording keeps every second frame; the rate says so."""
    rec = sc.markerless_noise(clean_walk.recording, rate_hz=50.0, jitter_m=0.0, swaps_per_min=0)
    assert rec.rate_hz == pytest.approx(50.0)
    np.testing.assert_array_equal(rec.time_s, clean_walk.recording.time_s[::2])


def test_mirror_pairs_find_left_and_right_by_name():
    """Left/right pairs are found in the naming styles of the shared recordings; unpaired names are left alone."""
    names = ["LASI", "RASI", "L.Heel", "R.Heel", "Foot_L", "Foot_R", "LeftToe", "RightToe", "X:LPSI", "X:RPSI"]
    names += ["l_heel", "r_heel", "LTOE", "Hips", "SACR"]
    pairs = {(names[i], names[j]) for i, j in sc.mirror_pairs(names)}
    assert pairs == {
        ("LASI", "RASI"),
        ("L.Heel", "R.Heel"),
        ("Foot_L", "Foot_R"),
        ("LeftToe", "RightToe"),
        ("X:LPSI", "X:RPSI"),
        ("l_heel", "r_heel"),
    }


@pytest.mark.parametrize("rate_hz", [30.0, 60.0])
def test_markerless_walk_keeps_the_clean_walks_truth(rate_hz):
    """A markerless lab walk has the capture rate asked for and the truth of the same walk without noise."""
    walk = sc.markerless_walk(S1, rate_hz=rate_hz, seed=0)
    clean = sy.make_walk(S1, "1-straight", rate_hz=rate_hz, seed=0, noise_m=0.0, dropouts=False)
    assert walk.recording.rate_hz == pytest.approx(rate_hz) and walk.walk_type == f"markerless-{rate_hz:g}hz"
    np.testing.assert_array_equal(walk.truth.step_frequency_hz, clean.truth.step_frequency_hz)
    err = walk.recording.positions_m - clean.recording.positions_m
    assert np.nanstd(err[~np.isnan(err).any(axis=2)]) > 0.01  # centimetre jitter (swaps make it larger)


def test_treadmill_keeps_the_pelvis_in_place_and_moves_the_stance_feet_back(rendered):
    """On the treadmill the pelvis stays within 15 cm of one place; the stance heel moves back at the belt speed."""
    walk = rendered["treadmill"]
    belt = walk.recording.metadata["belt_speed_mps"]
    pelvis = walk.recording.point("PELVIS")
    steady = _steady(walk.truth)
    assert np.nanmax(np.abs(pelvis[steady, 0] - np.nanmedian(pelvis[steady, 0]))) < 0.15
    assert np.median(walk.truth.speed_mps[steady]) == pytest.approx(belt, rel=0.03)
    clean = sc.treadmill_walk(S1, noise_m=0.0, dropouts=False).recording
    heel = clean.point("LHEE")
    vx = np.gradient(heel[:, 0], clean.time_s)
    stance = steady & (heel[:, 2] < S1.heel_height_m + 1e-6)
    assert np.median(vx[stance]) == pytest.approx(-belt, rel=0.03)
    np.testing.assert_allclose(sc.belt_speed_mps(walk)[steady], belt)


def test_stand_walk_stop_bouts_last_3_to_6_s_with_standing_between(rendered):
    """The bouts walk for 3-6 s each (within half a step), with at least 2 s standing between them."""
    truth = rendered["stand-walk-stop"].truth
    t, w = truth.time_s, truth.walking
    edges = np.flatnonzero(np.diff(w.astype(int)))
    starts, stops = t[edges[::2] + 1], t[edges[1::2]]
    assert len(starts) == len(stops) == 5
    lengths = stops - starts
    assert np.all((lengths > 3.0 - 0.3) & (lengths < 6.0 + 0.3))
    assert np.all(starts[1:] - stops[:-1] >= 2.0)


def test_turns_walk_turns_round_on_a_tight_circle(rendered):
    """The turns rendering turns by pi in its U-turn on a circle of 0.35 m: heading rate / speed = 1 / 0.35."""
    truth = rendered["turns"].truth
    steady = _steady(truth)
    heading = truth.heading_rad
    assert heading[steady].max() - heading[steady].min() > np.pi - 0.1
    rate = np.gradient(heading, truth.time_s) / np.maximum(truth.speed_mps, 1e-6)
    curvature = np.abs(rate[steady])
    assert np.percentile(curvature, 95) == pytest.approx(1 / 0.35, rel=0.15)


def test_very_slow_walk_is_walking_at_0_3_mps_and_0_5_steps_per_s(rendered):
    """The very slow rendering walks (truth) at 0.3 m/s and 0.5 steps/s."""
    truth = rendered["very-slow"].truth
    steady = _steady(truth)
    assert truth.walking.mean() > 0.9
    assert np.median(truth.step_frequency_hz[steady]) == pytest.approx(0.5, rel=0.03)
    assert np.median(truth.speed_mps[steady]) == pytest.approx(0.3, rel=0.03)


@pytest.mark.parametrize("condition", sc.NOT_WALKING)
def test_not_walking_renderings_have_a_truth_of_not_walking(rendered, condition):
    """Sit-to-stand, sway, turning on the spot and shuffling: walking False and step frequency 0 throughout."""
    walk = rendered[condition]
    assert not walk.truth.walking.any()
    assert np.all(walk.truth.step_frequency_hz == 0.0) and np.all(walk.truth.speed_mps == 0.0)
    assert walk.recording.positions_m.shape[0] == walk.truth.time_s.size


def test_chair_stand_rises_and_sits_within_a_slow_steps_time(rendered):
    """The chair-stand pelvis rises and sits six times, 0.3-0.5 m each, its turns less than 2.5 s apart."""
    z = rendered["chair-stand"].truth.pelvis_centre_m[:, 2]
    t = rendered["chair-stand"].truth.time_s
    up = z > 0.5 * (0.55 + S1.z0_m)
    rises = np.flatnonzero(np.diff(up.astype(int)) == 1)
    falls = np.flatnonzero(np.diff(up.astype(int)) == -1)
    assert rises.size == 6 and falls.size == 6
    assert 0.3 <= z.max() - z.min() <= 0.5
    crossings = np.sort(np.r_[rises, falls])
    assert np.max(np.diff(t[crossings])) < 2.5


def test_sit_to_stand_rises_from_the_seat_to_standing_height(rendered):
    """The sit-to-stand pelvis goes from the seat height (0.55 m) to standing height, three times."""
    z = rendered["sit-to-stand"].truth.pelvis_centre_m[:, 2]
    assert z.min() == pytest.approx(0.55, abs=0.005) and z.max() == pytest.approx(S1.z0_m, abs=0.01)
    up = z > 0.5 * (0.55 + S1.z0_m)
    assert np.count_nonzero(np.diff(up.astype(int)) == 1) == 3


def test_standing_and_turning_on_the_spot_stay_in_place(rendered):
    """Standing sway and turning on the spot keep the pelvis within 10 cm horizontally; the turn turns 2 pi."""
    for condition in ("standing-sway", "turn-on-the-spot"):
        p = rendered[condition].recording.point("PELVIS")
        assert np.nanmax(np.hypot(p[:, 0], p[:, 1])) < 0.1, condition
    heading = rendered["turn-on-the-spot"].truth.heading_rad
    assert heading.max() - heading.min() == pytest.approx(2 * np.pi, abs=1e-6)
    heel = rendered["turn-on-the-spot"].recording.point("LHEE")
    assert np.nanmax(heel[:, 2]) > S1.heel_height_m + 0.03  # it steps


def test_shuffling_moves_slowly_in_short_steps(rendered):
    """Shuffling advances slower than 0.15 m/s on average, with the heels at most 2 cm off the floor (plus noise)."""
    walk = rendered["shuffling"]
    rec = walk.recording
    p = rec.point("PELVIS")
    ok = np.isfinite(p[:, 0])
    assert (p[ok, 0][-1] - p[ok, 0][0]) / rec.duration_s < 0.15
    assert np.nanmax(rec.point("LHEE")[:, 2]) < S1.heel_height_m + 0.02 + 0.005


def test_every_rendering_is_labelled_synthetic(rendered):
    """Every rendering's name, source and description say synthetic; its walk type is the condition."""
    for condition, walk in rendered.items():
        assert "synthetic" in walk.name.lower() and walk.walk_type == condition
        assert walk.recording.metadata["synthetic"] is True
        assert "SYNTHETIC" in walk.recording.metadata["description"]
        assert walk.recording.source.startswith("synthetic:")


def test_renderings_are_deterministic_for_a_seed():
    """The same condition, subject and seed give the same recording."""
    for condition in ("markerless-30hz", "sit-to-stand", "turn-on-the-spot"):
        a, b = sc.render(condition, S1, seed=7), sc.render(condition, S1, seed=7)
        np.testing.assert_array_equal(a.recording.positions_m, b.recording.positions_m)


def test_unknown_condition_and_bad_settings_are_refused():
    """An unknown condition, a negative jitter and too short a bout are one clear InputError each."""
    with pytest.raises(InputError, match="unknown synthetic condition"):
        sc.render("moonwalk")
    walk = sc.render("standing-sway")
    with pytest.raises(InputError, match="jitter_m"):
        sc.markerless_noise(walk.recording, jitter_m=-1.0)
    with pytest.raises(InputError, match="bout"):
        sc.bouts_walk(S1, bouts_s=(1.0,))
    with pytest.raises(InputError, match="not a treadmill"):
        sc.belt_speed_mps(walk)


def test_make_walk_with_the_straight_path_given_is_the_default_walk():
    """make_walk(path=straight_path()) gives the same walk as without a path (the option changes nothing else)."""
    a = sy.make_walk(S1, "1-straight", duration_s=6.0, seed=2)
    b = sy.make_walk(S1, "1-straight", duration_s=6.0, seed=2, path=sy.straight_path())
    np.testing.assert_array_equal(a.recording.positions_m, b.recording.positions_m)
