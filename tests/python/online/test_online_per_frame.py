"""The per-frame calls (update, update_point, predict) as the instance binds them natively: values, inputs, errors."""

from __future__ import annotations

import numpy as np
import pytest

from yoyogait import synthetic
from yoyogait.errors import InputError
from yoyogait.estimators import OnlineEstimator

FIELDS = ("t_s", "vx_mps", "vz_mps", "step_frequency_hz", "speed_mps", "gait_phase", "status", "walking", "valid")


@pytest.fixture(scope="module")
def walk():
    rec = synthetic.default_lab(rate_hz=100.0)[0].recording
    est = OnlineEstimator.for_recording(rec)
    return rec, est.point_names, rec.points(list(est.point_names))


def _row(e):
    return tuple(getattr(e, f) for f in FIELDS)


def test_estimates_kept_by_the_caller_do_not_change_later(walk):
    """Every estimate object kept from update(), and every prediction, still holds its own frame's values
    after later frames (the refilled result objects are never ones the caller holds), equal to run()'s."""
    rec, names, p = walk
    n = 600
    whole = OnlineEstimator(names).run(rec.time_s[:n], p[:n], predict_ahead_s=(0.3,))
    est = OnlineEstimator(names)
    kept, rows, preds = [], [], []
    for i in range(n):
        e = est.update(rec.time_s[i], p[i])
        pr = est.predict(0.3)
        rows.append(_row(e))
        if i % 7 == 0:
            kept.append((i, e, _row(e)))
            preds.append((i, pr, pr.vx_mps))
    assert all(_row(e) == row for _, e, row in kept)
    assert all(pr.vx_mps == v for _, pr, v in preds)
    assert all(rows[i][4] == whole.speed_mps[i] or np.isnan(whole.speed_mps[i]) for i in range(n))
    assert all(np.array_equal(whole.pred_vx_mps[i, 0], v, equal_nan=True) for i, _, v in preds)


def test_any_array_like_frame_gives_the_same_estimate(walk):
    """A frame as float64 (k x 3 or 3k), float32, a list, a non-contiguous view or one point's numbers:
    the same estimates bit for bit."""
    rec, names, p = walk
    n = 300
    ref = OnlineEstimator(names)
    expected = [_row(ref.update(rec.time_s[i], p[i])) for i in range(n)]
    p32 = p.astype(np.float32).astype(np.float64)
    variants = {
        "flat": lambda i: p[i].ravel(),
        "list": lambda i: p[i].tolist(),
        "strided": lambda i: np.asfortranarray(p[i]),
        "float32": lambda i: p32[i].astype(np.float32),
    }
    for name, frame in variants.items():
        est = OnlineEstimator(names)
        got = [_row(est.update(rec.time_s[i], frame(i))) for i in range(n)]
        if name == "float32":  # the same values once widened: compare with the widened frames
            ref32 = OnlineEstimator(names)
            expected32 = [_row(ref32.update(rec.time_s[i], p32[i])) for i in range(n)]
            assert got == expected32
        else:
            assert got == expected, name
    centre = np.nanmean(p, axis=1)
    one, point = OnlineEstimator(["c"]), OnlineEstimator(["c"])
    for i in range(n):
        x, y, z = (float(v) for v in centre[i])
        assert _row(one.update(float(rec.time_s[i]), centre[i])) == _row(point.update_point(rec.time_s[i], x, y, z))


def test_bad_frames_raise_one_line_input_errors():
    """A frame of the wrong size, a time that is not a number, update_point on several points, a horizon
    out of range: InputError naming what was expected, and the estimator still usable."""
    est = OnlineEstimator(["A", "B"], "z")
    with pytest.raises(InputError, match=r"2 x 3 coordinates, got shape \(3,\)"):
        est.update(0.0, np.zeros(3))
    with pytest.raises(InputError, match=r"got shape \(1, 3\)"):
        est.update(0.0, [[0.0, 0.0, 0.0]])
    with pytest.raises(InputError, match="t_s must be a number"):
        est.update("soon", np.zeros((2, 3)))
    with pytest.raises(InputError, match="update_point takes one point"):
        est.update_point(0.0, 1.0, 2.0, 3.0)
    for bad in (-0.1, float("nan"), 99.0, "x"):
        with pytest.raises(InputError, match="horizon"):
            est.predict(bad)
    assert est.update(0.0, [[0.1, 0.2, 1.0], [0.3, 0.2, 1.0]]).points_seen == 2
    assert est.predict(1).horizon_s == 1.0
