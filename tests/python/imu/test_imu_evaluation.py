"""The IMU evaluation's metrics: per reference stride like with like, coverage over every sample, start-up."""

from __future__ import annotations

import math

import numpy as np
import pytest

from yoyogait.estimators.imu import ImuResult
from yoyogait.evaluation import imu as ev
from yoyogait.io.imu_read import read_mobilised_trials
from yoyogait.io.imu_recording import ImuBout, ImuRecording

MOBGAP = "imu_mobgap/example_data"


def _bout(contacts, speed=1.0) -> ImuBout:
    c = np.asarray(contacts, dtype=float)
    d = c[2:] - c[:-2]
    return ImuBout(float(c[0]), float(c[-1]), float(np.mean(120.0 / d)), speed, float(np.mean(d)), c)


def _result(t, f_hz, speed, valid, f_std=0.05, speed_std=0.05) -> ImuResult:
    n = t.size
    cols = {
        "time_s": t,
        "step_frequency_hz": np.broadcast_to(np.asarray(f_hz, dtype=float), (n,)).copy(),
        "step_frequency_std_hz": np.full(n, f_std),
        "speed_mps": np.broadcast_to(np.asarray(speed, dtype=float), (n,)).copy(),
        "speed_std_mps": np.full(n, speed_std),
        "valid": np.broadcast_to(np.asarray(valid, dtype=bool), (n,)).copy(),
    }
    return ImuResult(columns=cols)


def test_a_cadence_change_within_a_bout_compares_like_with_like():
    """An estimate that follows the strides' cadence has almost no cadence or stride-time error, although
    its time average differs from the strides' average cadence when the cadence changes within the bout."""
    steps = np.r_[np.full(6, 0.5), np.full(6, 0.8)]  # 120 then 75 steps/min
    contacts = np.r_[1.0, 1.0 + np.cumsum(steps)]
    b = _bout(contacts)
    rec = ImuRecording(np.arange(0.0, 12.0, 0.01), np.zeros((1200, 3)), np.zeros((1200, 3)))
    rec.references = {"R": [b]}
    t = rec.time_s
    f = np.nan_to_num(ev.reference_at(rec, "R", t)[0])  # the strides under way
    cad, _, stride, ref_cad, ref_stride, n, nref, _ = ev._bout_values(t, f, np.ones(t.size), np.ones(t.size, bool), b)
    assert n == nref == contacts.size - 2
    assert ref_cad == pytest.approx(b.cadence_spm) and ref_stride == pytest.approx(b.stride_time_s)
    assert abs(cad - ref_cad) < 1.0 and abs(stride - ref_stride) < 0.02
    # The old metric: the time average of the cadence over the bout against the strides' average.
    assert abs(60.0 * np.mean(f[(t >= b.start_s) & (t <= b.end_s)]) - b.cadence_spm) > 3.0


def test_strides_not_valid_are_left_out_and_the_reference_follows():
    """Strides where the estimate is not valid are left out on both sides; none valid: the bout is missed."""
    contacts = np.arange(1.0, 8.0, 0.5)
    b = _bout(contacts)
    t = np.arange(0.0, 9.0, 0.01)
    half = t > 4.0
    out = ev._bout_values(t, np.full(t.size, 2.0), np.ones(t.size), half, b)
    assert 0 < out[5] < out[6]
    none = ev._bout_values(t, np.full(t.size, 2.0), np.ones(t.size), np.zeros(t.size, bool), b)
    assert none[5] == 0 and math.isnan(none[0])


def test_the_speed_over_the_strides_scored_is_against_the_references_speeds_of_those_strides():
    """A walk slow in its first half and fast in its second, valid over the second only: against the
    reference's own speeds of the strides scored the error is 0, against the bout's mean speed it is not;
    a bout without stride speeds has none."""
    contacts = np.arange(1.0, 8.0, 0.5)
    b = _bout(contacts)
    b.strides_s = np.column_stack([contacts[:-2], contacts[2:]])
    b.stride_speeds_mps = np.where(b.strides_s[:, 0] < 4.0, 0.6, 1.2)
    b.speed_mps = float(np.mean(b.stride_speeds_mps))
    t = np.arange(0.0, 9.0, 0.01)
    speed = np.where(t < 4.0, 0.6, 1.2)
    out = ev._bout_values(t, np.full(t.size, 2.0), speed, t >= 4.05, b)  # the stride from 3.5 s: not half valid
    row = ev.BoutRow("r", "R", 0, "yoyogait-imu", b.start_s, b.end_s, out[3], b.speed_mps, out[4], out[0], out[1],
                     out[2], out[5], out[6], out[7])  # fmt: skip
    assert row.stride_speed_error_mps == pytest.approx(0.0, abs=1e-12) and row.speed_error_mps > 0.2
    b.stride_speeds_mps = np.zeros(0)
    assert math.isnan(ev._bout_values(t, np.full(t.size, 2.0), speed, t >= 4.05, b)[7])


def test_coverage_counts_every_sample_inside_the_bouts():
    """An invalid estimate with a small std counts against coverage; an infinite std is covered; a valid
    estimate 0.3 Hz off with a small std is confidently wrong."""
    contacts = np.arange(1.0, 9.0, 0.5)  # 2 Hz
    rec = ImuRecording(np.arange(0.0, 10.0, 0.01), np.zeros((1000, 3)), np.zeros((1000, 3)))
    rec.references = {"R": [_bout(contacts)]}
    t = rec.time_s
    f = np.where(t < 5.0, 1.0, 2.0)
    off = ev.coverage(rec, _result(t, f, 1.0, t >= 5.0))["R"]
    assert 0.4 < off["cadence_2std"] < 0.6 and off["confidently_wrong"] == 0.0
    inf = ev.coverage(rec, _result(t, f, 1.0, t >= 5.0, f_std=np.inf))["R"]
    assert inf["cadence_2std"] == 1.0
    wrong = ev.coverage(rec, _result(t, 2.3, 1.0, True))["R"]
    assert wrong["confidently_wrong"] > 0.9 and wrong["cadence_2std"] == 0.0


def test_sharpness_is_taken_over_the_valid_samples_inside_the_bouts():
    """The IMU sharpness: the median std and the 95th-percentile error over the valid samples only."""
    contacts = np.arange(1.0, 9.0, 0.5)  # 2 Hz
    rec = ImuRecording(np.arange(0.0, 10.0, 0.01), np.zeros((1000, 3)), np.zeros((1000, 3)))
    rec.references = {"R": [_bout(contacts)]}
    t = rec.time_s
    f = np.where(t < 5.0, 1.0, 2.1)  # 1 Hz off before 5 s, 0.1 Hz after
    c = ev.coverage(rec, _result(t, f, 1.0, t >= 5.0, f_std=0.2))["R"]
    assert c["f_std_valid_hz"] == 0.2 and c["f_err_valid_p95_hz"] == pytest.approx(0.1)
    assert c["speed_std_valid_mps"] == 0.05


def test_startup_in_steps_from_the_first_contact():
    """Valid 1.2 s after the first contact of a 2 Hz walk: 2.4 steps; within 5 % at the same time."""
    contacts = np.arange(2.0, 9.0, 0.5)
    rec = ImuRecording(np.arange(0.0, 10.0, 0.01), np.zeros((1000, 3)), np.zeros((1000, 3)))
    rec.references = {"R": [_bout(contacts)]}
    t = rec.time_s
    (s,) = ev.startup(rec, _result(t, 2.0, 1.0, t >= 3.2))
    assert s["valid_steps"] == pytest.approx(2.4, abs=0.03) and s["within5_steps"] == pytest.approx(2.4, abs=0.03)


@pytest.mark.parametrize("participant", ["HA/001", "HA/002", "MS/001"])
def test_reference_strides_reproduce_the_mobilised_cadence_stride_time_and_speed(datasets_dir, participant):
    """The reference strides of every bout give its Mobilise-D Cadence, mean Stride_Duration and
    WalkingSpeed (the mean of their Stride_Speed), also on the daily-living course, where a standard
    leaves out the strides over a contact it missed or counted twice (INDIP's in samples,
    Stereophoto's in seconds)."""
    left_out = 0
    for rec in read_mobilised_trials(datasets_dir / MOBGAP / f"data/lab/{participant}/data.mat"):
        for bouts in rec.references.values():
            for b in bouts:
                a, e = ev.bout_strides(b)
                assert np.mean(120.0 / (e - a)) == pytest.approx(b.cadence_spm, abs=0.05)
                assert np.mean(e - a) == pytest.approx(b.stride_time_s, abs=0.005)
                assert b.stride_speeds_mps.size == a.size
                assert np.mean(b.stride_speeds_mps) == pytest.approx(b.speed_mps, abs=0.005)
                assert np.all((a >= b.start_s - 0.01) & (e <= b.end_s + 0.01))
                left_out += b.contact_times_s.size - 2 - a.size
    assert left_out > 0  # every participant's course has such strides


def test_a_standards_stride_list_is_read_in_seconds_or_samples_and_only_where_it_fits():
    """Stride_InitialContacts in samples or seconds, whichever lasts the Stride_Duration; a stride with
    a NaN duration is left out; a list that fits neither, or is no numbers, is not read."""
    from yoyogait.io.mobilised import _bouts

    base = {"Start": 1.0, "End": 4.0, "Cadence": 100.0, "WalkingSpeed": 1.0, "InitialContact_Event": [1.0, 1.6, 2.2]}
    durations = [1.2, float("nan")]
    in_samples = _bouts({**base, "Stride_InitialContacts": [[100, 220], [160, 400]], "Stride_Duration": durations}, 100)
    in_seconds = _bouts({**base, "Stride_InitialContacts": [[1.0, 2.2], [1.6, 4.0]], "Stride_Duration": durations}, 100)
    for (b,) in (in_samples, in_seconds):
        np.testing.assert_allclose(b.strides_s, [[1.0, 2.2]])
    (b,) = _bouts({**base, "Stride_InitialContacts": [[1.0, 2.2], [1.6, 4.0]], "Stride_Duration": durations,
                   "Stride_Speed": [0.9, 0.4]}, 100)  # fmt: skip
    np.testing.assert_allclose(b.stride_speeds_mps, [0.9])  # the speed of the stride kept
    for wrong in ([[1.0, 2.5], [1.6, 4.0]], [["a", "b"], ["c", "d"]], [1.0, 2.2, 3.0]):
        (b,) = _bouts({**base, "Stride_InitialContacts": wrong, "Stride_Duration": durations,
                       "Stride_Speed": [0.9, 0.4]}, 100)  # fmt: skip
        assert b.strides_s.shape == (0, 2) and b.stride_speeds_mps.size == 0 and b.cadence_spm == 100.0


def test_strides_from_the_contacts_when_the_reference_lists_none():
    """Without a stride list (another source of bouts) the strides are initial contact k to k + 2."""
    b = _bout([0.0, 0.5, 1.0, 1.6, 2.1])
    a, e = ev.bout_strides(b)
    np.testing.assert_allclose(a, [0.0, 0.5, 1.0])
    np.testing.assert_allclose(e, [1.0, 1.6, 2.1])


def test_not_walking_inside_a_reference_bout_is_within_the_speed_band(datasets_dir):
    """On HA/001's daily-living course, the samples the detector calls standing inside a reference
    walking bout (slow steps, turns on the spot) have the reference speed within 2 reported std for at
    least 90 % of them (the coverage target): the std holds the pendulum speed of the vertical motion seen."""
    from yoyogait.estimators.imu import ImuReason, estimator_for

    inside = covered = 0
    for rec in read_mobilised_trials(datasets_dir / MOBGAP / "data/lab/HA/001/data.mat"):
        if rec.metadata["test"] != "Test11":
            continue
        res = estimator_for(rec).run_recording(rec)
        standing = res["reason"] == int(ImuReason.NOT_WALKING)
        for ref in rec.references:
            _, v_ref = ev.reference_at(rec, ref, res.time_s)
            m = standing & np.isfinite(v_ref)
            inside += int(m.sum())
            covered += int(np.sum(np.abs(res["speed_mps"][m] - v_ref[m]) <= 2.0 * res["speed_std_mps"][m]))
    assert inside > 50  # the course has such samples: the property is tested, not skipped
    assert covered >= 0.9 * inside


def test_a_missed_bout_is_counted_and_left_out_of_the_median():
    """A missed bout adds to missed, not to the median's bouts; the missed-as-worst median counts it above all."""

    def row(err):
        return ev.BoutRow("r", "R", 0, "yoyogait-imu", 0.0, 1.0, 100.0, 1.0, 1.2, 100.0 + err, 1.0, 1.2, 1, 1)

    d = ev.summary([row(1.0), row(2.0), row(math.nan)])[0]
    assert (d["bouts"], d["missed"], d["scored"]) == (3, 1, 2)
    assert d["median_abs_cadence_error_spm"] == pytest.approx(1.5)
    assert d["median_missed_worst_abs_cadence_error_spm"] == pytest.approx(2.0)


def test_next_step_lies_within_one_step_period_on_a_real_course(datasets_dir):
    """On HA/001's daily-living course (stops, turns, falling cadences), next_step_in_s lies in [0, 1/f)
    of the reported f on every sample that has one, as on the marker path (online::GaitPhase)."""
    from yoyogait.estimators.imu import estimator_for

    (rec,) = [r for r in read_mobilised_trials(datasets_dir / MOBGAP / "data/lab/HA/001/data.mat")
              if r.metadata["test"] == "Test11"]  # fmt: skip
    res = estimator_for(rec).run_recording(rec)
    n, f = res["next_step_in_s"], res["step_frequency_hz"]
    has = np.isfinite(n)
    assert has.sum() > 1000
    assert np.all(n[has] >= 0.0) and np.all(n[has] < 1.0 / f[has])
