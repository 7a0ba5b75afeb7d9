"""The IMU estimator on arbitrary input (Hypothesis): it never raises, its outputs are finite where they are
numbers, a valid estimate is in range, and a run equals its samples one by one."""

from __future__ import annotations

import math

import numpy as np
from hypothesis import given, settings
from hypothesis import strategies as st

from yoyogait import ImuConfig, ImuOnlineEstimator
from yoyogait.estimators.imu import IMU_ESTIMATE_FIELDS, ImuReason
from yoyogait.io.imu_recording import GRAVITY_MPS2
from yoyogait.synthetic_imu import make_imu_walk

WALK = make_imu_walk(duration_s=8.0).recording
CONFIG = ImuConfig()
#: Fields that are not numbers at every sample: the stds before the estimator is fed (infinite), the time to
#: the next step while no phase is known (NaN).
MAY_BE_INF = {"step_frequency_std_hz", "speed_std_mps"}
MAY_BE_NAN = {"next_step_in_s"}

VALUES = st.sampled_from(
    [0.0, -0.0, 1.0, -1.0, GRAVITY_MPS2, 1e3, -1e3, 1e12, 1e300, 1e-300, math.nan, math.inf, -math.inf]
)


@st.composite
def sequences(draw):
    """Runs of samples: a stretch of a SYNTHETIC walk, a constant vector (zeros, gravity, extremes, NaN, inf), or
    a walk with its acceleration scaled (a unit error, saturation); times regular, repeated, backwards, short of
    samples or jumping."""
    t, acc, gyr = [], [], []
    now = 0.0
    for _ in range(draw(st.integers(1, 6))):
        kind = draw(st.sampled_from(["walk", "constant", "scaled"]))
        n = draw(st.integers(1, 300))
        start = draw(st.integers(0, WALK.n_samples - n))
        if kind == "constant":
            a = np.tile([draw(VALUES), draw(VALUES), draw(VALUES)], (n, 1))
            g = np.tile([draw(VALUES), draw(VALUES), draw(VALUES)], (n, 1))
        else:
            a = WALK.acc_mps2[start : start + n].copy()
            g = WALK.gyr_rad_s[start : start + n].copy()
            if kind == "scaled":
                a *= draw(st.sampled_from([1 / GRAVITY_MPS2, 10.0, -1.0, 1e6]))
        # 0.05 and 0.2: samples lost, bridged; 0.5 and 5: a gap that restarts.
        step = draw(st.sampled_from([0.01, 0.01, 0.01, 0.0, -0.01, 0.05, 0.2, 0.5, 5.0]))
        for k in range(n):
            now += step if k == 0 else 0.01
            t.append(now)
        acc.append(a)
        gyr.append(g)
    return np.asarray(t), np.vstack(acc), np.vstack(gyr)


@settings(max_examples=40, deadline=None)
@given(sequences())
def test_any_input_gives_finite_outputs_and_valid_only_in_range(seq):
    """Any samples (NaN, infinities, extremes, zeros, unit errors, repeated, backward or jumping times): run()
    returns, every output is finite but the stds (infinite until fed) and the time to the next step (NaN while no
    phase is known); a valid estimate has reason OK, a step frequency in the range, a speed in [0, max_speed_mps]
    and finite stds; and run() equals update() sample by sample."""
    t, acc, gyr = seq
    res = ImuOnlineEstimator(CONFIG).run(t, acc, gyr)
    for name, _, _ in IMU_ESTIMATE_FIELDS:
        column = np.asarray(res["time_s" if name == "t_s" else name], dtype=float)
        if name in MAY_BE_NAN:
            assert not np.isinf(column).any(), name
        elif name in MAY_BE_INF:
            assert not np.isnan(column).any() and np.all(column >= 0), name
        else:
            assert np.all(np.isfinite(column)), name
    valid = res["valid"].astype(bool)
    assert np.all(res["reason"][valid] == int(ImuReason.OK)) and np.all(res["reason"][~valid] != int(ImuReason.OK))
    f_lo, f_hi = CONFIG.estimator.gait_filter.f_min_hz, CONFIG.estimator.gait_filter.f_max_hz
    assert np.all((res["step_frequency_hz"][valid] >= f_lo) & (res["step_frequency_hz"][valid] <= f_hi))
    assert np.all((res["speed_mps"][valid] >= 0) & (res["speed_mps"][valid] <= CONFIG.max_speed_mps))
    assert np.all(np.isfinite(res["step_frequency_std_hz"][valid])) and np.all(np.isfinite(res["speed_std_mps"][valid]))
    one = ImuOnlineEstimator(CONFIG)
    for k in range(len(t)):
        e = one.update(t[k], acc[k], gyr[k])
        assert e.valid == bool(valid[k]) and int(e.reason) == int(res["reason"][k])
        assert (e.step_frequency_hz == res["step_frequency_hz"][k]) and (e.speed_mps == res["speed_mps"][k])
