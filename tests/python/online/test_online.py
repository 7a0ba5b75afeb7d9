"""The online estimator (yoyogait.OnlineEstimator): causality, streaming = batch, threads, bad input."""

from __future__ import annotations

import threading
from dataclasses import fields

import numpy as np
import pytest

from yoyogait import _core, io, synthetic
from yoyogait.errors import InputError
from yoyogait.estimators import ConcurrentUseError, OnlineConfig, OnlineEstimator, OnlineStatus
from yoyogait.evaluation.online import lag_s

# Recordings of the shared data set with partial and total marker gaps.
GAPPY = (
    "c3d_org_samples/sample01_Eb015pr.c3d",
    "c3d_org_samples/sample10_TYPE-3.c3d",
    "c3d_org_samples/sample26_Qualisys_Walking_Hybrid_1_3.c3d",
    "addbiomechanics/Camargo2021_levelground_ccw_fast_01_01.trc",
)


def _entry(manifest, path):
    return next(e for e in manifest["recordings"] if e["path"] == path)


def _arrays(result):
    return {f.name: getattr(result, f.name) for f in fields(result)}


def _equal_upto(a, b, n):
    """Rows [0, n) of two results equal bit for bit (NaN equal to NaN)."""
    return all(np.array_equal(a[k][:n], b[k][:n], equal_nan=True) for k in a)


@pytest.mark.parametrize("path", GAPPY)
def test_no_output_depends_on_a_later_frame(datasets_dir, manifest, path):
    """Changing every input after time t (positions and timestamps) changes no output at or before t, bit for bit."""
    entry = _entry(manifest, path)
    rec = io.read(datasets_dir / path, up_axis=entry["vertical_axis"])
    names = entry["pelvis"]
    t = np.array(rec.time_s, dtype=float)
    p = rec.points(names)
    assert np.isnan(p).any(), "the recording should have gaps"
    base = _arrays(OnlineEstimator(names, entry["vertical_axis"]).run(t, p))
    rng = np.random.default_rng(0)
    for cut in np.linspace(0.2, 0.9, 4):
        k = int(cut * len(t))
        t2, p2 = t.copy(), p.copy()
        p2[k + 1 :] = rng.normal(0.0, 1.0, p2[k + 1 :].shape)
        p2[k + 1 :: 7] = np.nan
        t2[k + 1 :] = t2[k] + np.cumsum(rng.uniform(-0.01, 0.05, len(t) - k - 1))
        changed = _arrays(OnlineEstimator(names, entry["vertical_axis"]).run(t2, p2))
        assert _equal_upto(base, changed, k + 1), f"{path}: output at or before frame {k} changed"
        assert not _equal_upto(base, changed, len(t)), "the change after t should show somewhere"


def test_update_run_and_chunks_agree():
    """Frame-by-frame update, one run and a run in chunks give the same estimates bit for bit."""
    walk = synthetic.default_lab(rate_hz=100.0)[1]
    rec = walk.recording
    whole = OnlineEstimator.for_recording(rec).run(rec)
    est = OnlineEstimator.for_recording(rec)
    p = rec.points(list(est.point_names))
    step = np.array([est.update(t, p[i]).vz_hat_mps for i, t in enumerate(rec.time_s)])
    assert np.array_equal(step, whole.vz_hat_mps)
    est = OnlineEstimator.for_recording(rec)
    parts = [est.run(rec.time_s[a:b], p[a:b]) for a, b in ((0, 700), (700, 701), (701, len(rec.time_s)))]
    for name in ("step_frequency_hz", "speed_mps", "vx_mps", "gait_phase", "status"):
        assert np.array_equal(np.concatenate([getattr(r, name) for r in parts]), getattr(whole, name))


def test_before_the_first_estimator_sample_the_reconstruction_is_the_measured_velocity(datasets_dir):
    """Until the estimator is first fed, vx_hat_mps/vz_hat_mps (and predict) are the front-end velocities, not 0."""
    rec = io.read(datasets_dir / "c3d_org_samples" / "sample26_Qualisys_Capture0002.c3d")
    res = OnlineEstimator.for_recording(rec).run(rec)
    before = np.cumsum(res.estimator_fed) == 0
    assert 10 < before.sum() < len(before)
    assert np.array_equal(res.vx_hat_mps[before], res.vx_mps[before])
    assert np.array_equal(res.vz_hat_mps[before], res.vz_mps[before])
    assert np.array_equal(res.pred_vx_mps[before, -1], res.vx_mps[before])
    assert np.all(np.isinf(res.pred_vx_std_mps[before]))
    assert np.all(res.vx_mps[before][1:] > 0.9)  # the walker is already walking at 1.2-1.4 m/s


@pytest.mark.parametrize("rate_hz", [30.0, 100.0, 250.0])
def test_reconstruction_is_timed_to_the_frame(rate_hz):
    """vz_hat_mps describes the velocity at the frame's time: within 3 ms of the truth at any capture rate."""
    walk = synthetic.default_lab(rate_hz=rate_hz)[0]
    res = OnlineEstimator.for_recording(walk.recording).run(walk.recording)
    vz = np.interp(res.time_s, walk.truth.time_s, walk.truth.vz_mps)
    locked = res.time_s > 8.0
    lag = lag_s(np.where(locked, res.vz_hat_mps, np.nan), np.where(locked, vz, np.nan), rate_hz)
    assert abs(lag) < 0.003


def test_synthetic_walk_step_frequency_and_speed():
    """On a synthetic straight walk at 100 Hz the step frequency is within 0.05 Hz and the speed within 0.1 m/s
    of the truth once the walker has walked 3 s."""
    walk = synthetic.default_lab(rate_hz=100.0)[0]
    res = OnlineEstimator.for_recording(walk.recording).run(walk.recording)
    truth = walk.truth
    f_true = np.interp(res.time_s, truth.time_s, truth.step_frequency_hz)
    v_true = np.interp(res.time_s, truth.time_s, truth.speed_mps)
    walking_from = res.time_s[np.argmax(f_true > 0.5)]
    late = res.time_s > walking_from + 3.0
    assert np.max(np.abs(res.step_frequency_hz[late] - f_true[late])) < 0.05
    assert np.median(np.abs(res.speed_mps[late] - v_true[late])) < 0.1


def test_second_thread_gets_a_clear_error():
    """While one thread is inside run(), a call from another thread raises ConcurrentUseError at once."""
    n = 400_000
    t = np.arange(n) / 200.0
    p = np.zeros((n, 1, 3))
    p[:, 0, 0] = 1.2 * t
    est = OnlineEstimator(["PELVIS"], "z")
    errors, done = [], threading.Event()

    def long_run():
        try:
            est.run(t, p)
        finally:
            done.set()

    worker = threading.Thread(target=long_run)
    worker.start()
    while not done.is_set():
        try:
            est.update(1e9, np.zeros(3))
        except ConcurrentUseError as exc:
            errors.append(str(exc))
            break
    worker.join()
    assert errors and "another thread" in errors[0]
    est.update(2e9, np.zeros(3))  # usable again once the first call has returned


def test_bad_input_is_a_status_or_a_clear_error():
    """Bad frames give a status; wrong shapes and settings raise InputError naming the problem."""
    est = OnlineEstimator(["A", "B"], "y", length_unit_m=0.001)
    assert est.update(0.0, [[0, 900, 0], [100, 900, 0]]).status == OnlineStatus.USED
    assert est.update(0.0, [[0, 900, 0], [100, 900, 0]]).status == OnlineStatus.TIME_NOT_INCREASING
    assert est.update(0.01, np.full((2, 3), np.nan)).status == OnlineStatus.ALL_MISSING
    assert est.update(0.02, np.full((2, 3), np.inf)).status == OnlineStatus.NON_FINITE
    assert est.update(float("nan"), np.zeros((2, 3))).status == OnlineStatus.NON_FINITE
    # A jump ahead beyond max_time_jump_s is held back until two more frames follow it.
    assert est.update(900.0, [[0, 900, 0], [100, 900, 0]]).status == OnlineStatus.TIME_JUMP
    assert est.update(900.01, [[0, 900, 0], [100, 900, 0]]).status == OnlineStatus.TIME_JUMP
    assert est.update(900.02, [[0, 900, 0], [100, 900, 0]]).status == OnlineStatus.GAP_RESTART
    with pytest.raises(InputError, match="2 x 3"):
        est.update(1000.0, np.zeros(3))
    with pytest.raises(InputError, match="up_axis"):
        OnlineEstimator(["A"], "w")
    with pytest.raises(InputError, match="heading_tau_s"):
        OnlineEstimator(["A"], "z", config=OnlineConfig(heading_tau_s=0.0))
    with pytest.raises(InputError, match="1 to 16"):
        OnlineEstimator([f"P{i}" for i in range(17)], "z")


def test_config_mirrors_the_native_struct():
    """OnlineConfig has exactly the native struct's fields, with the same defaults."""
    native = _core.OnlineConfig()
    names = {f.name for f in fields(OnlineConfig)}
    native_names = {n for n in dir(native) if not n.startswith("_") and n != "validate"}
    assert names == native_names
    py = OnlineConfig()
    for name in names - {"estimator"}:
        assert getattr(py, name) == getattr(native, name), name


def test_estimate_online_writes_one_row_per_frame(datasets_dir, tmp_path, capsys):
    """`estimate FILE --online` writes a finite CSV row per frame (stds once fed, next step while walking)."""
    import csv

    from yoyogait.cli import main

    path = datasets_dir / "c3d_org_samples" / "sample10_TYPE-3.c3d"
    out = tmp_path / "online.csv"
    assert main(["estimate", str(path), "--online", "--out", str(out)]) == 0
    rows = list(csv.DictReader(open(out)))
    assert len(rows) == io.read(path).n_frames
    needed = "time_s vx_mps vz_mps vx_hat_mps vz_hat_mps step_frequency_hz step_frequency_std_hz speed_mps"
    needed += " speed_std_mps heading_rad gait_phase walking status"
    assert set(needed.split()) <= set(rows[0])
    # Every value finite, but the stds, which are infinite until the estimator has had its first sample.
    stds = {"step_frequency_std_hz", "speed_std_mps"}
    assert all(np.isfinite(float(v)) for r in rows for k, v in r.items() if k != "next_step_in_s" and k not in stds)
    assert all(not np.isnan(float(r[k])) for r in rows for k in stds)
    assert all(np.isfinite(float(r[k])) for r in rows if r["walking"] == "1" for k in stds)
    next_step = np.array([float(r["next_step_in_s"]) for r in rows])
    walking = np.array([r["walking"] == "1" for r in rows])
    assert walking.any() and np.array_equal(np.isfinite(next_step), walking)
    f_hz = np.array([float(r["step_frequency_hz"]) for r in rows])
    # The next step comes within about one step period (the frequency's rate may stretch it a little).
    assert np.all(next_step[walking] >= 0) and np.all(next_step[walking] * f_hz[walking] <= 1.2)
    assert {int(r["status"]) for r in rows} >= {int(OnlineStatus.USED), int(OnlineStatus.ALL_MISSING)}
    before = out.read_bytes()
    assert main(["estimate", str(path), "--online", "--out", str(out)]) != 0
    assert out.read_bytes() == before
    assert "--force" in capsys.readouterr().err


def test_for_recording_finds_the_pelvis_and_runs_a_recording(datasets_dir):
    """for_recording finds a BVH's root joint and the file's up axis; run(recording) equals run(time, positions)."""
    rec = io.read(datasets_dir / "bandai_namco_motion" / "dataset-2_walk_normal_001.bvh", length_unit_m=0.01)
    est = OnlineEstimator.for_recording(rec)
    assert est.point_names == ("Hips",) and est.up_axis == "y"
    a = est.run(rec)
    b = OnlineEstimator.for_recording(rec).run(rec.time_s, rec.points(["Hips"]))
    assert np.array_equal(a.step_frequency_hz, b.step_frequency_hz) and np.array_equal(a.vz_mps, b.vz_mps)
    walking = a.walking
    assert walking.mean() > 0.5 and 1.2 < np.median(a.step_frequency_hz[walking]) < 2.4
