"""The online evaluation: its metrics (lag, circular spread, settling), one replay per recording, and the CLI."""

from __future__ import annotations

import csv
import math
from types import SimpleNamespace

import numpy as np
import pytest

from builders import write_trc
from yoyogait import synthetic as sy
from yoyogait.cli import main
from yoyogait.evaluation import evaluate_online, running
from yoyogait.evaluation import online as on
from yoyogait.evaluation.datasets import synthetic_item
from yoyogait.evaluation.tables import median_and_worst

REQUIRED_COLUMNS = ("latency_vz_ms", "f_err_first3s_median_hz", "f_err_median_hz", "phase_at_contact_circstd_pct")


@pytest.fixture(scope="module")
def short_walks():
    straight = sy.make_walk(sy.SUBJECTS[1], "1-straight", duration_s=9.0, rate_hz=100.0, seed=3)
    step = sy.make_step_walk(sy.SUBJECTS[0], duration_s=11.0, step_at_s=6.0, rate_hz=120.0, seed=3)
    return evaluate_online([synthetic_item(straight), synthetic_item(step)], dataset="short", synthetic=True)


def test_lag_recovers_a_known_shift():
    """lag_s finds a 37 ms delay (between samples at 100 Hz) of a noisy gait-like signal, and its sign."""
    rate = 100.0
    t = np.arange(0, 20, 1 / rate)
    rng = np.random.default_rng(1)

    def vz(tt):
        return 0.15 * np.sin(2 * np.pi * 1.8 * tt) + 0.04 * np.sin(2 * np.pi * 3.6 * tt + 0.7)

    ref = vz(t) + rng.normal(0, 0.005, t.size)
    late = vz(t - 0.037) + rng.normal(0, 0.005, t.size)
    late[300:340] = np.nan  # a gap is left out, not read as zero
    assert on.lag_s(late, ref, rate) == pytest.approx(0.037, abs=0.0015)
    assert on.lag_s(ref, late, rate) == pytest.approx(-0.037, abs=0.0015)


def test_circular_std_of_constant_and_of_a_known_spread():
    """circular_std_pct: ~0 for phases at one value (also across the 0/1 wrap), ~4 % for a 4 % wrapped normal."""
    assert on.circular_std_pct(np.full(50, 0.73)) == pytest.approx(0.0, abs=1e-5)
    assert on.circular_std_pct(np.mod(np.array([0.999, 0.0, 0.001] * 10), 1.0)) < 0.1
    rng = np.random.default_rng(2)
    spread = np.mod(0.98 + rng.normal(0.0, 0.04, 4000), 1.0)  # centred on the wrap
    assert on.circular_std_pct(spread) == pytest.approx(4.0, abs=0.2)
    assert math.isnan(on.circular_std_pct([0.1, 0.2]))


def test_phase_at_interpolates_across_the_wrap():
    """phase_at goes the short way round between two samples (0.95 -> 0.05 passes 0, not 0.5)."""
    out = on.phase_at([0.0, 1.0], [0.95, 0.05], [0.5, 0.25, 2.0])
    assert out[0] == pytest.approx(0.0, abs=1e-12) and out[1] == pytest.approx(0.975)
    assert math.isnan(out[2])


def test_settle_time_needs_the_error_to_stay_within():
    """settle_time_s: the first time after which |error| stays within for the hold time; inf if never."""
    t = np.arange(0, 10, 0.01)
    err = np.where(t < 3.0, 1.0, 0.01)
    late = err.copy()
    late[(t > 6.0) & (t < 6.1)] = 1.0  # a relapse after the hold time does not count
    assert on.settle_time_s(t, late, 0.05, 1.0) == pytest.approx(3.0 - 1.0, abs=0.011)
    err[(t > 4.0) & (t < 4.1)] = 1.0  # a relapse within the hold time restarts the count
    assert on.settle_time_s(t, err, 0.05, 1.0) == pytest.approx(4.1 - 1.0, abs=0.011)
    assert on.settle_time_s(t, np.ones_like(t), 0.05, 1.0) == math.inf


def test_online_evaluation_of_two_short_walks_gives_every_column_where_defined(short_walks):
    """On a straight walk and a cadence-step walk every new column is finite where defined (NaN elsewhere)."""
    assert [r.item.walk for r in short_walks.items] == ["1-straight", sy.STEP_WALK_TYPE]
    straight, step = (r.metrics for r in short_walks.items)
    step_only = {"cadence_step_time_s", "speed_step_time_s"}
    online_only = {"latency_vz_input_ms"}
    for key in on.ONLINE_EXTRA_KEYS + REQUIRED_COLUMNS:
        assert math.isfinite(step["online"][key]), key
        assert math.isfinite(straight["online"][key]) != (key in step_only), key
        assert math.isfinite(step["oscillator"][key]) != (key in online_only), key
    assert step["online"]["rate_hz"] == pytest.approx(120.0)
    assert step["oscillator"]["rate_hz"] == pytest.approx(25.0)
    # The synthetic estimate is close to the truth after the start: these are not placeholders.
    assert step["online"]["f_err_median_hz"] < 0.05 and abs(step["online"]["latency_vz_ms"]) < 30


def test_startup_from_cadence_counts_from_the_end_of_the_start_up_ramp(short_walks):
    """startup_from_cadence_s is the start-up time measured from the ramp's end (ramp_s after the first
    step), not from the first walking frame: the two differ by the ramp where both settle after it."""
    for r in short_walks.items:
        ramp_s = r.item.load().metadata["ramp_s"]
        for est in ("online", "oscillator"):
            m = r.metrics[est]
            assert m["startup_time_s"] > ramp_s, (r.item.walk, est)  # nobody follows a ramp from 0 Hz
            assert m["startup_from_cadence_s"] == pytest.approx(m["startup_time_s"] - ramp_s, abs=0.05)


def test_evaluate_online_through_the_cli_writes_the_named_columns(tmp_path, capsys):
    """`yoyogait evaluate FOLDER --online` on two TRC files writes recordings.csv with the online columns."""
    data = tmp_path / "data"
    data.mkdir()
    for subject, seed in ((sy.SUBJECTS[0], 4), (sy.SUBJECTS[2], 5)):
        walk = sy.make_walk(subject, "1-straight", duration_s=9.0, rate_hz=100.0, seed=seed)
        write_trc(data / f"{subject.name}.trc", walk.recording)
    out = tmp_path / "report"
    assert main(["evaluate", str(data), "--online", "--out", str(out)]) == 0
    printed = capsys.readouterr().out
    assert "online" in printed and "confidently wrong, share of walking" in printed
    with open(out / "recordings.csv", newline="") as fh:
        rows = list(csv.DictReader(fh))
    assert [r["estimator"] for r in rows] == ["online", "oscillator"] * 2
    for key in REQUIRED_COLUMNS:
        assert key in rows[0] and all(math.isfinite(float(r[key])) for r in rows), key
    assert "online evaluation" in (out / "index.md").read_text()
    online_rows = [r for r in rows if r["estimator"] == "online"]
    for key in ("f_cover2std_fraction", "speed_cover2std_fraction", "confidently_wrong_fraction", "valid_fraction"):
        assert all(0.0 <= float(r[key]) <= 1.0 for r in online_rows), key


def test_online_200ms_prediction_is_scored_and_the_oscillators_is_not(short_walks):
    """The pred200ms columns are finite for the online estimator and NaN for the oscillator (it has no prediction)."""
    for r in short_walks.items:
        online, osc = r.metrics["online"], r.metrics["oscillator"]
        assert math.isfinite(online["pred200ms_vx_sq_err_mean_1e-2"]) and online["pred200ms_vz_sq_err_mean_1e-2"] > 0
        assert math.isnan(osc["pred200ms_vx_sq_err_mean_1e-2"]) and math.isnan(osc["pred200ms_vz_sq_err_mean_1e-2"])


def test_200ms_prediction_is_compared_with_the_velocity_0_2_s_later():
    """A prediction equal to the reference 0.2 s later scores 0; the current reference instead does not."""
    t = np.arange(0.0, 10.0, 0.01)
    vx, vz = 1.0 + 0.2 * np.sin(2 * np.pi * 1.8 * t), 0.1 * np.cos(2 * np.pi * 1.8 * t)
    ref = on._Refs(t, 100.0, vx, vz, np.ones_like(t, dtype=bool), np.full_like(t, 1.8), np.ones_like(t))
    ahead = [np.interp(t + 0.2, t, v, right=np.nan) for v in (vx, vz)]
    kw = dict(vx_hat_mps=vx, vz_hat_mps=vz, f_hat=np.full_like(t, 1.8), speed_hat=np.ones_like(t), phase=t % 1.0)
    kw.update(contacts_s=np.empty(0), synthetic=False, step_at_s=None)
    exact = on._score(ref, pred200=(*ahead, *ahead), **kw)
    stale = on._score(ref, pred200=(*ahead, vx, vz), **kw)
    assert exact["pred200ms_vx_sq_err_mean_1e-2"] == 0.0 and exact["pred200ms_vz_sq_err_mean_1e-2"] == 0.0
    assert stale["pred200ms_vz_sq_err_mean_1e-2"] > 0.1


def test_online_reconstructions_are_scored_against_offline_velocities_at_the_capture_rate():
    """At 30 Hz the reference at a frame is the offline velocity computed on the capture grid (a frame's time
    is a grid time), not the 25 Hz grid interpolated there: it lies closer to the SYNTHETIC walk's own v_z."""
    walk = sy.make_walk(sy.SUBJECTS[0], "1-straight", duration_s=6.0, rate_hz=30.0, seed=5)
    rec, up = walk.recording, "z"
    vel = on.gait_velocities(rec, point=list(sy.PELVIS_MARKERS), rate_hz=on.RATE_HZ, up_axis=up)
    at = on._velocities_at_capture_rate(rec, list(sy.PELVIS_MARKERS), up, vel)
    assert at.rate_hz == pytest.approx(30.0) and np.allclose(at.time_s, rec.time_s[: at.time_s.size])
    t = rec.time_s[(rec.time_s > 1.0) & (rec.time_s < 5.0)]
    truth = walk.truth.at(t).vz_mps
    err_at = np.mean((np.interp(t, at.time_s, at.vz) - truth) ** 2)
    err_grid = np.mean((np.interp(t, vel.time_s, vel.vz) - truth) ** 2)
    assert err_at < 0.8 * err_grid
    assert on._velocities_at_capture_rate(rec, list(sy.PELVIS_MARKERS), up, at) is at  # already there: itself


def test_honesty_columns_are_shares_for_the_online_estimator_and_nan_for_the_oscillator(short_walks):
    """Honesty columns: shares in [0, 1] online, NaN for the oscillator (no spread); front-end top speed a walker's."""
    for r in short_walks.items:
        online, osc = r.metrics["online"], r.metrics["oscillator"]
        for key in on.HONESTY_KEYS:
            assert math.isnan(osc[key]), key
            if key.endswith("_fraction"):
                assert 0.0 <= online[key] <= 1.0, key
        assert online["frontend_speed_max_mps"] > 1.0 and online["frontend_speed_max_mps"] < 3.0
        # Clean synthetic walking after the start: not confidently wrong most of the time.
        assert online["confidently_wrong_after3s_fraction"] < 0.1


def test_clean_straight_walking_is_valid_most_of_the_time_after_3_s(short_walks):
    """On a clean SYNTHETIC straight walk, the estimates are valid on at least 80 % of the walking time after 3 s."""
    straight = next(r for r in short_walks.items if "straight" in r.item.name)
    assert straight.metrics["online"]["valid_after3s_fraction"] >= 0.8


def test_honesty_of_a_made_up_estimate_is_scored_as_defined():
    """_score on a known estimate: half the walking time outside 2 std and valid gives coverage 0.5, wrong 0.5."""
    t = np.arange(0.0, 10.0, 0.01)
    n = t.size
    vx, vz = np.ones(n), np.zeros(n)
    ref = on._Refs(t, 100.0, vx, vz, np.ones(n, dtype=bool), np.full(n, 1.8), np.ones(n))
    f_hat = np.where(t < 5.0, 1.8, 2.2)  # 0.4 Hz wrong in the second half
    kw = dict(vx_hat_mps=vx, vz_hat_mps=vz, f_hat=f_hat, speed_hat=np.ones(n), phase=t % 1.0)
    kw.update(contacts_s=np.empty(0), synthetic=False, step_at_s=None)
    row = on._score(ref, f_std=np.full(n, 0.05), speed_std=np.full(n, 0.05), valid=np.ones(n, dtype=bool), **kw)
    assert row["f_cover2std_fraction"] == pytest.approx(0.5, abs=0.01)
    assert row["speed_cover2std_fraction"] == 1.0
    assert row["confidently_wrong_fraction"] == pytest.approx(0.5, abs=0.01)
    assert row["confidently_wrong_first3s_fraction"] == 0.0 and row["valid_fraction"] == 1.0
    honest = on._score(ref, f_std=np.full(n, 0.3), speed_std=np.full(n, 0.05), valid=np.ones(n, dtype=bool), **kw)
    assert honest["f_cover2std_fraction"] == 1.0 and honest["confidently_wrong_fraction"] == 0.0
    flagged = on._score(ref, f_std=np.full(n, 0.05), speed_std=np.full(n, 0.05), valid=t < 5.0, **kw)
    assert flagged["confidently_wrong_fraction"] == 0.0 and flagged["valid_fraction"] == pytest.approx(0.5, abs=0.01)


def test_sharpness_is_the_valid_frames_median_std_beside_their_95th_percentile_error():
    """_score's sharpness: median std and 95th-percentile error over the valid walking frames only."""
    t = np.arange(0.0, 10.0, 0.01)
    n = t.size
    vx, vz = np.ones(n), np.zeros(n)
    ref = on._Refs(t, 100.0, vx, vz, np.ones(n, dtype=bool), np.full(n, 1.8), np.full(n, 1.2))
    err = np.linspace(0.0, 0.1, n)  # f off by 0 .. 0.1 Hz along the walk
    f_std = np.where(t < 5.0, 0.02, 0.5)
    kw = dict(vx_hat_mps=vx, vz_hat_mps=vz, f_hat=1.8 + err, speed_hat=np.full(n, 1.25), phase=t % 1.0)
    kw.update(contacts_s=np.empty(0), synthetic=False, step_at_s=None)
    first_half = t < 5.0
    row = on._score(ref, f_std=f_std, speed_std=np.full(n, 0.1), valid=first_half, **kw)
    assert row["f_std_valid_median_hz"] == 0.02  # the invalid half's wide std does not count
    assert row["f_err_valid_p95_hz"] == pytest.approx(np.percentile(err[first_half], 95.0))
    assert row["speed_std_valid_median_mps"] == 0.1
    assert row["speed_err_valid_p95_mps"] == pytest.approx(0.05)
    never = on._score(ref, f_std=f_std, speed_std=np.full(n, 0.1), valid=np.zeros(n, dtype=bool), **kw)
    assert math.isnan(never["f_std_valid_median_hz"]) and math.isnan(never["f_err_valid_p95_hz"])


def test_validity_is_the_results_valid_not_its_walking():
    """validity(): a result's `valid`, whatever its walking detector says."""
    both = SimpleNamespace(walking=np.array([True, True, False]), valid=np.array([False, True, False]))
    assert on.validity(both).tolist() == [False, True, False]


def test_summary_names_the_worst_recording_beside_the_median(short_walks):
    """The online summary has a median and a worst column per estimator, the worst naming its recording."""
    med, worst, name, n = median_and_worst(short_walks, "online", "f_err_whole_median_hz")
    values = [r.metrics["online"]["f_err_whole_median_hz"] for r in short_walks.items]
    assert n == 2 and worst == max(values) and med == pytest.approx(np.median(values))
    assert name == short_walks.items[int(np.argmax(values))].item.name
    _, lowest, _, _ = median_and_worst(short_walks, "online", "valid_fraction", higher_is_better=True)
    assert lowest == min(r.metrics["online"]["valid_fraction"] for r in short_walks.items)
    lags = [r.metrics["online"]["latency_vz_ms"] for r in short_walks.items]
    _, farthest, _, _ = median_and_worst(short_walks, "online", "latency_vz_ms", by_magnitude=True)
    assert farthest == lags[int(np.argmax(np.abs(lags)))]
    text = "\n".join(short_walks.preamble)
    assert "online: worst (recording)" in text and "confidently wrong" in text


def test_the_half_step_walking_part_lies_half_a_step_beside_the_contacts_within_the_gait_one():
    """walking_part "half-step": each stretch from half a mean step before its first contact to half a step after
    its last, inside the events' gait-initiation-to-termination stretch; an unknown part is refused."""
    ev = SimpleNamespace(
        walking_segments_s=np.array([[0.4, 5.2], [8.0, 9.0]]),
        step_start_s=np.array([1.0, 1.6, 2.2, 8.5]),
        step_end_s=np.array([1.6, 2.2, 2.8, 8.9]),
    )
    np.testing.assert_array_equal(running._walking_segments(ev, "gait"), ev.walking_segments_s)
    np.testing.assert_allclose(running._walking_segments(ev, "half-step"), [[0.7, 3.1], [8.3, 9.0]])
    with pytest.raises(ValueError, match="walking_part"):
        running.real_reference(None, None, None, walking_part="from the first step")
