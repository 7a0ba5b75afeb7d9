"""Behaviour of the synthetic gait lab: truth against the Yoyo-model, walk types, artefacts."""

from __future__ import annotations

import numpy as np
import pytest

from yoyogait import synthetic as sy
from yoyogait.errors import InputError
from yoyogait.io import Recording
from yoyogait.model import yoyo_model

S1 = sy.SUBJECTS[0]


def clean(walk_type, subject=S1, **kwargs):
    """A walk without marker noise or dropouts (all other realism kept)."""
    return sy.make_walk(subject, walk_type, noise_m=0.0, dropouts=False, **kwargs)


def point(walk, name):
    return walk.recording.point(name)


def steady(truth, margin_s=3.0):
    """Walking samples at least ``margin_s`` away from a start, stop or the ends."""
    t = truth.time_s
    ok = truth.walking.copy()
    edges = t[np.flatnonzero(np.diff(truth.walking.astype(int))) + 1]
    for e in np.concatenate([edges, [t[0], t[-1]]]):
        ok &= np.abs(t - e) > margin_s
    return ok


def dominant_frequency_hz(t, y):
    """Peak of the DFT of ``y`` (mean removed), zero-padded for resolution."""
    y = y - np.mean(y)
    n = 16 * len(y)
    spec = np.abs(np.fft.rfft(y * np.hanning(len(y)), n))
    freqs = np.fft.rfftfreq(n, t[1] - t[0])
    band = freqs > 0.3
    return freqs[band][np.argmax(spec[band])]


def test_pelvis_velocity_follows_eq_3_4_with_phase_offset():
    """Noise-free pelvis velocity along the path is eq. 3-4 with pi added to the forward cosine."""
    w = clean("1-straight", harmonic2_ratio=0.0)
    tr = w.truth
    omega = 2 * np.pi * tr.step_frequency_hz
    vx_expected = S1.R_m * omega + S1.r_m * omega * np.cos(tr.theta_rad + np.pi)
    vz_expected = -S1.r_m * omega * np.sin(tr.theta_rad)
    np.testing.assert_allclose(tr.vx_path_mps, vx_expected, atol=1e-12)
    np.testing.assert_allclose(tr.vz_mps, vz_expected, atol=1e-12)
    # The markers move with these velocities: a straight walk goes along +x.
    centre = point(w, "PELVIS")
    dt = tr.time_s[1] - tr.time_s[0]
    inner = slice(1, -1)
    np.testing.assert_allclose(np.gradient(centre[:, 0], dt)[inner], vx_expected[inner], atol=2e-3)
    np.testing.assert_allclose(np.gradient(centre[:, 2], dt)[inner], vz_expected[inner], atol=2e-3)


def test_model_pure_walk_is_the_package_yoyo_model():
    """With offset, harmonic and sway off, the pelvis centre is yoyo_model's x and z exactly."""
    w = sy.make_model_walk(S1, "2-fast-slow-fast")
    tr = w.truth
    ref = yoyo_model(tr.time_s, S1.R_m, S1.r_m, tr.step_frequency_hz, S1.z0_m, phase_rad=tr.theta_rad[0])
    centre = point(w, "PELVIS")
    np.testing.assert_allclose(centre[:, 0], ref.x_m - ref.x_m[0], atol=1e-9)
    np.testing.assert_allclose(centre[:, 1], 0.0, atol=1e-12)
    np.testing.assert_allclose(centre[:, 2], ref.z_m, atol=1e-9)
    np.testing.assert_allclose(tr.vx_path_mps, ref.vx_mps, atol=1e-9)
    np.testing.assert_allclose(tr.vz_mps, ref.vz_mps, atol=1e-9)


@pytest.mark.parametrize("offset_rad, sign", [(np.pi, -1.0), (0.0, 1.0)])
def test_phase_offset_sets_where_forward_velocity_peaks(offset_rad, sign):
    """Offset pi: forward velocity is highest where the pelvis is lowest; offset 0: where highest."""
    w = clean("1-straight", harmonic2_ratio=0.0, phase_offset_rad=offset_rad)
    tr = w.truth
    m = steady(tr)
    corr = np.corrcoef(tr.vx_path_mps[m] - tr.speed_mps[m], point(w, "PELVIS")[m, 2])[0, 1]
    assert sign * corr > 0.99


def test_stride_averaged_forward_speed_is_R_omega():
    """The forward velocity (with harmonic and variability) averages over a stride to R * omega."""
    w = sy.make_walk(S1, "1-straight")
    tr = w.truth
    stride = int(round(2.0 / S1.step_frequency_hz * w.recording.rate_hz))
    averaged = np.convolve(tr.vx_path_mps, np.ones(stride) / stride, mode="same")
    m = steady(tr)
    np.testing.assert_allclose(averaged[m], tr.speed_mps[m], atol=0.01)
    np.testing.assert_allclose(tr.speed_mps, tr.R_m * tr.omega_rad_s)


def test_one_step_covers_2_pi_R():
    """Distance along the path between successive heel strikes is one Yoyo step, 2 pi R."""
    w = clean("3-rectangle")
    tr = w.truth
    dist = np.concatenate([[0.0], np.cumsum(0.5 * (tr.vx_path_mps[1:] + tr.vx_path_mps[:-1]) * np.diff(tr.time_s))])
    at_contacts = np.interp(tr.contact_times_s, tr.time_s, dist)
    np.testing.assert_allclose(np.diff(at_contacts), 2 * np.pi * S1.R_m, rtol=2e-3)


def test_same_seed_same_walk_other_seed_other_noise():
    """A seed fixes the walk exactly; another seed changes noise and dropouts."""
    a = sy.make_walk(sy.SUBJECTS[1], "4-figure-eight", seed=3)
    b = sy.make_walk(sy.SUBJECTS[1], "4-figure-eight", seed=3)
    c = sy.make_walk(sy.SUBJECTS[1], "4-figure-eight", seed=4)
    assert np.array_equal(a.recording.positions_m, b.recording.positions_m, equal_nan=True)
    assert np.array_equal(a.truth.step_frequency_hz, b.truth.step_frequency_hz)
    assert not np.array_equal(a.recording.positions_m, c.recording.positions_m, equal_nan=True)


def test_fast_slow_fast_step_frequency():
    """Walk 2 steps fast, then clearly slower, then fast again; the speed follows."""
    tr = clean("2-fast-slow-fast").truth
    t, f = tr.time_s, tr.step_frequency_hz
    d = t[-1]
    first = f[(t > 0.15 * d) & (t < 0.28 * d)]
    middle = f[(t > 0.45 * d) & (t < 0.6 * d)]
    last = f[t > 0.8 * d]
    assert first.min() > 1.05 * S1.step_frequency_hz
    assert middle.max() < 0.9 * S1.step_frequency_hz
    assert last.min() > 1.05 * S1.step_frequency_hz
    assert np.median(tr.speed_mps[t > 0.8 * d]) > 1.2 * np.median(tr.speed_mps[(t > 0.45 * d) & (t < 0.6 * d)])


def test_rectangle_turns_left_a_quarter_turn_per_corner():
    """Walk 3 only turns left; straight sides are quarter turns apart; one lap back at the start is 2 pi."""
    w = clean("3-rectangle")
    tr = w.truth
    assert np.all(np.diff(tr.heading_rad) >= -1e-12)
    rate = np.gradient(tr.heading_rad, tr.time_s)
    straight = tr.walking & (np.abs(rate) < 1e-9)
    quarters = (tr.heading_rad[straight] - tr.heading_rad[0]) / (np.pi / 2)
    np.testing.assert_allclose(quarters, np.round(quarters), atol=1e-9)
    assert len(np.unique(np.round(quarters))) >= 8  # two laps of four sides
    centre = point(w, "PELVIS")[:, :2]
    near_start = np.linalg.norm(centre - centre[0], axis=1) < 0.1
    later = near_start & (tr.time_s > 5.0)
    assert later.any()
    turned = tr.heading_rad[later] - tr.heading_rad[0]
    laps = np.round(turned / (2 * np.pi))
    assert laps.min() >= 1
    np.testing.assert_allclose(turned, 2 * np.pi * laps, atol=0.05)


def test_figure_eight_turns_both_ways_and_crosses_itself():
    """Walk 4 alternates left and right loops of more than half a turn; its heading does not accumulate."""
    w = clean("4-figure-eight")
    tr = w.truth
    rate = np.gradient(tr.heading_rad, tr.time_s)
    turning = np.sign(rate[np.abs(rate) > 1e-6])
    switches = np.count_nonzero(np.diff(turning) != 0)
    assert switches >= 4  # at least two left and two right loops
    span = tr.heading_rad.max() - tr.heading_rad.min()
    assert np.pi < span < 2 * np.pi
    assert abs(tr.heading_rad[-1] - tr.heading_rad[0]) <= span
    # The track crosses itself: it passes the crossing point in two different directions.
    centre = point(w, "PELVIS")[:, :2]
    at_cross = np.linalg.norm(centre - centre[0], axis=1) < 0.1
    directions = np.mod(tr.heading_rad[at_cross & tr.walking], 2 * np.pi)
    assert np.ptp(np.cos(directions)) + np.ptp(np.sin(directions)) > 0.5


def test_heading_is_the_direction_of_travel():
    """On the curved walks the horizontal pelvis velocity points along the true heading (up to sway)."""
    for walk_type in ("3-rectangle", "4-figure-eight"):
        w = clean(walk_type)
        tr = w.truth
        v = np.gradient(point(w, "PELVIS")[:, :2], tr.time_s, axis=0)
        m = steady(tr)
        direction = np.arctan2(v[m, 1], v[m, 0])
        diff = np.angle(np.exp(1j * (direction - tr.heading_rad[m])))
        assert np.max(np.abs(diff)) < 0.2


@pytest.mark.parametrize("subject", sy.SUBJECTS, ids=lambda s: s.name)
def test_stop_and_go_stands_still(subject):
    """Walk 5 stands still for seconds mid-walk: zero truth velocity, both heels down, markers fixed up to noise."""
    w = sy.make_walk(subject, "5-stop-and-go", dropouts=False)
    tr = w.truth
    t = tr.time_s
    standing = ~tr.walking & (t > 5.0)
    assert np.ptp(t[standing]) > 3.0
    assert tr.walking[t < t[standing][0]].any() and tr.walking[t > t[standing][-1]].any()
    for name in ("step_frequency_hz", "speed_mps", "vx_path_mps", "vz_mps"):
        assert np.all(getattr(tr, name)[standing] == 0.0), name
    assert np.ptp(tr.pelvis_centre_m[standing], axis=0).max() == 0.0
    positions = w.recording.positions_m[standing]
    assert np.nanstd(positions, axis=0).max() < 2.0 * w.options["noise_m"]
    for heel in sy.HEEL_MARKERS:
        z = point(w, heel)[standing, 2]
        np.testing.assert_allclose(np.mean(z), subject.heel_height_m, atol=1e-3)


def test_sway_at_half_the_step_frequency():
    """The pelvis sways sideways at stride frequency (f/2) and bobs vertically at step frequency (f)."""
    w = sy.make_walk(S1, "1-straight", dropouts=False)
    tr = w.truth
    m = steady(tr, margin_s=1.0)
    centre = point(w, "PELVIS")
    f_mean = np.mean(tr.step_frequency_hz[m])
    resolution = 1.0 / np.ptp(tr.time_s[m])
    f_sway = dominant_frequency_hz(tr.time_s[m], centre[m, 1])
    f_vert = dominant_frequency_hz(tr.time_s[m], centre[m, 2])
    assert abs(f_sway - f_mean / 2) < resolution
    assert abs(f_vert - f_mean) < resolution


def test_dropouts_are_nan_runs_not_zeros():
    """Occluded markers are NaN (never 0), in runs of 0.1-1 s as well as single frames."""
    w = sy.make_walk(S1, "3-rectangle", seed=1)
    p = w.recording.positions_m
    missing = np.isnan(p)
    assert missing.any()
    assert not np.any(p[~missing] == 0.0)
    assert np.array_equal(missing[..., 0], missing[..., 2])  # a point is missing whole
    runs = []
    for j in range(p.shape[1]):
        edges = np.diff(np.concatenate([[0], missing[:, j, 0].astype(int), [0]]))
        runs.extend(np.flatnonzero(edges == -1) - np.flatnonzero(edges == 1))
    rate = w.recording.rate_hz
    assert max(runs) >= 0.1 * rate and max(runs) <= 1.0 * rate + 1
    assert min(runs) == 1
    assert not np.isnan(sy.make_walk(S1, "3-rectangle", seed=1, dropouts=False).recording.positions_m).any()


def test_heel_strikes_alternate_at_step_frequency():
    """Heel strikes alternate left/right, one per step (1/f apart), with the pelvis at its lowest."""
    w = clean("1-straight")
    tr = w.truth
    left, right = tr.left_contact_times_s, tr.right_contact_times_s
    times = np.concatenate([left, right])
    is_left = np.concatenate([np.ones(left.size, bool), np.zeros(right.size, bool)])
    order = np.argsort(times)
    times, is_left = times[order], is_left[order]
    assert times.size > 40
    assert np.all(is_left[1:] != is_left[:-1])
    mid = 0.5 * (times[1:] + times[:-1])
    f_mid = np.interp(mid, tr.time_s, tr.step_frequency_hz)
    walking = np.interp(mid, tr.time_s, steady(tr).astype(float)) == 1.0
    np.testing.assert_allclose(np.diff(times)[walking], 1.0 / f_mid[walking], rtol=0.01)
    # The Yoyo angle is pi (mod 2 pi), where z = z0 + r cos(theta) is lowest.
    theta = np.interp(times, tr.time_s, tr.theta_rad)
    np.testing.assert_allclose(np.cos(theta), -1.0, atol=1e-4)


def test_heels_rest_in_stance_and_swing_a_stride():
    """Each heel is fixed on the floor from its strike to the other heel's strike, then moves a stride."""
    w = clean("1-straight")
    tr = w.truth
    t = tr.time_s
    for heel, own, other in (
        ("LHEE", tr.left_contact_times_s, tr.right_contact_times_s),
        ("RHEE", tr.right_contact_times_s, tr.left_contact_times_s),
    ):
        p = point(w, heel)
        for a, b in zip(own[:-1], own[1:]):
            nxt = other[(other > a) & (other < b)]
            assert nxt.size == 1
            stance = (t > a) & (t < nxt[0])
            assert np.ptp(p[stance], axis=0).max() < 1e-9
            np.testing.assert_allclose(p[stance, 2], S1.heel_height_m, atol=1e-9)
            i_a, i_b = np.searchsorted(t, [a, b])
            moved = p[i_b, 0] - p[i_a, 0]
            f = np.interp(0.5 * (a + b), t, tr.step_frequency_hz)
            if np.interp(0.5 * (a + b), t, steady(tr).astype(float)) == 1.0:
                np.testing.assert_allclose(moved, 2 * 2 * np.pi * S1.R_m, atol=0.02)
                assert p[i_a:i_b, 2].max() > S1.heel_height_m + 0.5 * S1.foot_clearance_m
                assert f > 0


def test_pelvis_markers_average_to_the_centre():
    """The four pelvis markers are placed so their mean is the pelvis centre, while turning and rocking."""
    w = clean("4-figure-eight")
    idx = [w.recording.point_names.index(n) for n in sy.PELVIS_MARKERS]
    mean = w.recording.positions_m[:, idx, :].mean(axis=1)
    np.testing.assert_allclose(mean, point(w, "PELVIS"), atol=1e-12)
    np.testing.assert_allclose(point(w, "PELVIS"), w.truth.pelvis_centre_m, atol=1e-12)


def test_recording_says_synthetic_and_names_the_points():
    """Every walk is a Recording in metres, z up, whose metadata and source say synthetic."""
    w = sy.make_walk(sy.SUBJECTS[2], "5-stop-and-go", rate_hz=200.0)
    rec = w.recording
    assert isinstance(rec, Recording)
    assert rec.metadata["synthetic"] is True
    assert "synthetic" in rec.source and "synthetic" in w.name and "SYNTHETIC" in rec.metadata["description"]
    assert rec.up_axis == "z" and rec.metadata["vertical_axis"] == "z"
    assert rec.metadata["walk_type"] == "5-stop-and-go" and rec.metadata["subject"] == sy.SUBJECTS[2].name
    assert set(rec.metadata["pelvis"]) | {rec.metadata["hand"], *rec.metadata["feet"]} <= set(rec.point_names)
    assert rec.positions_m.shape == (rec.time_s.size, len(rec.point_names), 3)
    np.testing.assert_allclose(np.diff(rec.time_s), 1 / 200.0)
    assert rec.duration_s == pytest.approx(sy.DEFAULT_DURATION_S["5-stop-and-go"])
    custom = sy.make_walk(sy.with_parameters(S1, name="Bob"), "1-straight", duration_s=5.0)
    assert "synthetic" in custom.name and custom.recording.source.startswith("synthetic:")


def test_rate_does_not_change_the_gait():
    """The same walk at 100 Hz and 200 Hz has the same truth at common times."""
    a = clean("2-fast-slow-fast", rate_hz=100.0).truth
    b = clean("2-fast-slow-fast", rate_hz=200.0).truth
    np.testing.assert_allclose(b.step_frequency_hz[::2], a.step_frequency_hz, atol=1e-12)
    np.testing.assert_allclose(b.theta_rad[::2], a.theta_rad, atol=1e-3)
    np.testing.assert_allclose(b.left_contact_times_s, a.left_contact_times_s, atol=1e-3)


def test_truth_resamples_to_an_estimator_grid():
    """truth.at() gives the truth on another time grid, NaN and not walking outside the recording."""
    tr = sy.make_walk(S1, "5-stop-and-go").truth
    grid = np.arange(0.0, tr.time_s[-1] + 1.0, 0.04)
    at = tr.at(grid)
    inside = grid <= tr.time_s[-1]
    common = np.isin(np.round(tr.time_s, 9), np.round(grid, 9))
    np.testing.assert_allclose(at.step_frequency_hz[inside], tr.step_frequency_hz[common])
    np.testing.assert_array_equal(at.walking[inside], tr.walking[common])
    assert np.isnan(at.speed_mps[~inside]).all() and not at.walking[~inside].any()
    assert at.pelvis_centre_m.shape == (grid.size, 3)


def test_default_lab_is_three_subjects_by_five_walks():
    """The built-in lab holds every subject on every walk type, 30-40 s each."""
    lab = sy.default_lab(seed=0)
    assert len(lab) == len(sy.SUBJECTS) * len(sy.WALK_TYPES) == 15
    assert {(w.subject.name, w.walk_type) for w in lab} == {(s.name, k) for s in sy.SUBJECTS for k in sy.WALK_TYPES}
    for w in lab:
        assert 30.0 <= w.recording.duration_s <= 40.0
        assert w.truth.phase_offset_rad == pytest.approx(np.pi)
    pure = sy.default_lab(pure=True)
    assert all(w.truth.phase_offset_rad == 0.0 for w in pure)
    assert not any(np.isnan(w.recording.positions_m).any() for w in pure)


def test_subject_speeds_and_radii_are_human():
    """Built-in subjects walk at 1.2-1.45 m/s with R, r, z0 and step frequency in human ranges."""
    for s in sy.SUBJECTS:
        assert s.speed_mps >= 1.2 and s.speed_mps <= 1.45
        assert 0.09 <= s.R_m <= 0.15 and 0.01 <= s.r_m <= 0.03
        assert 0.85 <= s.z0_m <= 1.05 and 1.6 <= s.step_frequency_hz <= 2.1


def test_bad_arguments_are_input_errors():
    """Unknown walk types and non-positive rates are refused with a message."""
    with pytest.raises(InputError, match="walk type"):
        sy.make_walk(S1, "6-moonwalk")
    with pytest.raises(InputError, match="rate_hz"):
        sy.make_walk(S1, "1-straight", rate_hz=0.0)
    with pytest.raises(InputError, match="R_m"):
        sy.make_walk(sy.with_parameters(S1, r_m=0.2), "1-straight")
