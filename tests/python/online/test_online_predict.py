"""Predictions of the online estimator: horizon 0, accuracy ahead on a clean walk, stds, next-step time."""

from __future__ import annotations

import numpy as np
import pytest

from yoyogait import synthetic
from yoyogait.errors import InputError
from yoyogait.estimators import OnlineEstimator

HORIZONS_S = (0.0, 0.2, 0.5, 1.0)
# 1 mm of white position noise gives 0.059 m/s of velocity noise per frame at 100 Hz (docs/online.md
# sec. 2); the estimator's input is the mean over 4 frames: ~0.03 m/s per sample. A prediction 0.5 s
# ahead at constant cadence should be no noisier than one input sample.
INPUT_NOISE_MPS = 0.059 / np.sqrt(4.0)


@pytest.fixture(scope="module")
def clean_walk():
    """A model-pure straight walk at constant cadence (1 mm marker noise, no dropouts), 100 Hz."""
    subject = synthetic.SUBJECTS[0]
    walk = synthetic.make_model_walk(
        subject, "1-straight", rate_hz=100.0, duration_s=20.0, dropouts=False, noise_m=0.001, frequency_jitter=0.0
    )
    res = OnlineEstimator.for_recording(walk.recording).run(walk.recording, predict_ahead_s=HORIZONS_S)
    return walk, res


def test_prediction_at_horizon_zero_is_the_reconstruction(clean_walk):
    """predict(0) after each frame equals that frame's vx_hat_mps, vz_hat_mps bit for bit."""
    _, res = clean_walk
    assert np.array_equal(res.pred_vx_mps[:, 0], res.vx_hat_mps)
    assert np.array_equal(res.pred_vz_mps[:, 0], res.vz_hat_mps)


def test_half_second_prediction_matches_the_truth(clean_walk):
    """At constant cadence, after 8 s, the 0.5 s-ahead v_x and v_z have an RMS error below one input sample's noise."""
    walk, res = clean_walk
    t, tr = res.time_s, walk.truth
    j = HORIZONS_S.index(0.5)
    use = (t > 8.0) & (t + 0.5 < tr.time_s[-1])
    for pred, true in ((res.pred_vx_mps, tr.vx_path_mps), (res.pred_vz_mps, tr.vz_mps)):
        err = pred[use, j] - np.interp(t[use] + 0.5, tr.time_s, true)
        assert np.sqrt(np.mean(err**2)) < INPUT_NOISE_MPS


def test_far_forecast_tends_to_the_mean(clean_walk):
    """While walking, the 1 s-ahead v_z oscillates less (RMS) than the 0.2 s-ahead: the phase coherence falls."""
    _, res = clean_walk
    w = res.walking & (res.time_s > 8.0)
    rms = [np.sqrt(np.mean(res.pred_vz_mps[w, HORIZONS_S.index(h)] ** 2)) for h in (0.2, 1.0)]
    assert rms[1] < rms[0]


def test_stds_grow_with_the_horizon(clean_walk):
    """While walking, the predicted stds of v_x and v_z increase strictly with the horizon at every frame."""
    _, res = clean_walk
    w = res.walking & np.isfinite(res.pred_vx_std_mps[:, 0])
    assert w.sum() > 1000
    for std in (res.pred_vx_std_mps[w], res.pred_vz_std_mps[w]):
        assert np.all(np.diff(std, axis=1) > 0.0)


def test_next_step_counts_down_and_wraps_once_per_step(clean_walk):
    """After 8 s the time to the next step falls by the frame interval (up to the estimator's phase corrections,
    within 3 % of a step) and wraps up once per step."""
    _, res = clean_walk
    t, n = res.time_s, res.next_step_in_s
    use = t > 8.0
    assert np.all(np.isfinite(n[use]))
    f = float(np.median(res.step_frequency_hz[use]))
    assert np.all((n[use] >= 0.0) & (n[use] < 1.0 / f + 0.02))
    d = np.diff(n[use])
    dt = np.diff(t[use])
    down = d < 0
    dev = np.abs(d[down] + dt[down])
    assert np.max(dev) < 0.03 / f and np.quantile(dev, 0.95) < 0.005
    span_s = float(t[use][-1] - t[use][0])
    assert abs(int(np.sum(~down)) - span_s * f) <= 1.0
    assert np.all(d[~down] > 0.8 / f)


def test_next_step_is_nan_while_standing(clean_walk):
    """Before walking (the first second is standing) no next step is predicted."""
    _, res = clean_walk
    assert np.all(np.isnan(res.next_step_in_s[res.time_s < 0.9]))


def test_predict_matches_run_and_rejects_bad_horizons():
    """predict(h) after update() equals run()'s prediction for that frame; a horizon outside [0, max] raises."""
    walk = synthetic.default_lab(rate_hz=100.0)[0]
    rec = walk.recording
    whole = OnlineEstimator.for_recording(rec).run(rec, predict_ahead_s=(0.3,))
    est = OnlineEstimator.for_recording(rec)
    p = rec.points(list(est.point_names))
    k = 900
    for i in range(k + 1):
        est.update(rec.time_s[i], p[i])
    pr = est.predict(0.3)
    assert pr.valid and pr.vx_mps == whole.pred_vx_mps[k, 0] and pr.vz_std_mps == whole.pred_vz_std_mps[k, 0]
    assert pr.t_s == pytest.approx(rec.time_s[k] + 0.3)
    for bad in (-0.1, float("nan"), est.max_horizon_s + 1.0):
        with pytest.raises(InputError, match="horizon"):
            est.predict(bad)
    fresh = OnlineEstimator.for_recording(rec).predict(0.2)
    assert not fresh.valid and np.isinf(fresh.vx_std_mps)
