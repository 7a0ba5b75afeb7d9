"""Live streaming over Lab Streaming Layer, on this machine only (tests/conftest.py confines LSL to 127.0.0.1)."""

from __future__ import annotations

import gc
import os
import subprocess
import sys
import threading
import time
from io import StringIO

import numpy as np
import pytest
from live_helpers import (
    PELVIS,
    LiveThread,
    marker_info,
    pelvis_frames,
    pelvis_labels,
    short_walk,
    unique,
    write_csv,
)

from yoyogait import OnlineEstimator, io
from yoyogait.cli import main
from yoyogait.errors import InputError
from yoyogait.estimators.imu import ImuReason
from yoyogait.estimators.online import InvalidReason
from yoyogait.live.imu_live import IMU_COLUMNS
from yoyogait.live.live import ESTIMATE_COLUMNS, LiveCounters, estimate_row, setup_from_info
from yoyogait.live.replay import LOOP_PAUSE_S, replay
from yoyogait.live.status import StatusLine

pylsl = pytest.importorskip("pylsl")


def reference_rows(times, frames, points=PELVIS):
    """What a fresh OnlineEstimator gives for these frames, as estimate-stream rows."""
    est = OnlineEstimator(list(points), "z", 1.0)
    return np.array([estimate_row(est.update(t, f.reshape(len(points), 3))) for t, f in zip(times, frames)])


def yoyogait_cmd(*args):
    return [sys.executable, "-m", "yoyogait", *map(str, args)]


def test_replay_live_subscriber_gets_every_frames_estimate_in_order_equal_to_the_offline_run(tmp_path):
    """replay -> live -> subscriber: per frame, in order, bit for bit the offline run; --record = estimate --online."""
    rec = short_walk(6.0)
    path = tmp_path / "walk.csv"
    write_csv(rec, path)
    source, estimates = unique("walk"), unique("gait")
    record = tmp_path / "live.csv"
    env = dict(os.environ)
    live = subprocess.Popen(
        yoyogait_cmd("live", "--source", source, "--publish", estimates, "--record", record, "--exit-on-end"),
        env=env,
        stderr=subprocess.PIPE,
        text=True,
    )
    try:
        found = pylsl.resolve_byprop("name", estimates, 1, 20)
        assert found, "the estimate stream did not appear"
        inlet = pylsl.StreamInlet(found[0], max_buflen=60, recover=False)
        inlet.open_stream(10)
        # The replayer in a thread (its command is the same call): one interpreter start less.
        player = threading.Thread(
            target=lambda: replay(io.read(path), source, speed=4, wait_for_consumer_s=20), daemon=True
        )
        player.start()
        rows, stamps = [], []
        try:
            while len(rows) < rec.n_frames:
                sample, stamp = inlet.pull_sample(timeout=15)
                if sample is None:
                    break
                rows.append(sample)
                stamps.append(stamp)
        except pylsl.util.LostError:
            pass
        player.join(20)
        assert live.wait(20) == 0, live.stderr.read()
    finally:
        if live.poll() is None:
            live.kill()
    got = np.array(rows)
    assert got.shape == (rec.n_frames, len(ESTIMATE_COLUMNS))
    assert np.all(np.diff(stamps) > 0)
    expected_result = OnlineEstimator.for_recording(rec).run(rec)
    expected = np.column_stack([np.asarray(getattr(expected_result, c), dtype=float) for c in ESTIMATE_COLUMNS])
    np.testing.assert_array_equal(got[:, 0], rec.time_s)
    np.testing.assert_array_equal(got, expected)
    offline = tmp_path / "offline.csv"
    assert main(["estimate", str(path), "--online", "--out", str(offline)]) == 0
    assert record.read_text() == offline.read_text()  # live --record writes what estimate --online writes


def test_replay_sends_positions_in_metres_nan_for_missing_the_file_time_and_paces_frames():
    """replay's frames hold every point's x, y, z (NaN where missing) and time_s, no faster than the file's rate."""
    rec = short_walk(2.0)
    assert np.isnan(rec.positions_m).any()
    name = unique("replay")
    speed = 4.0
    done = {}
    player = threading.Thread(
        target=lambda: done.update(stats=replay(rec, name, speed=speed, wait_for_consumer_s=10)), daemon=True
    )
    player.start()
    found = pylsl.resolve_byprop("name", name, 1, 10)
    inlet = pylsl.StreamInlet(found[0], max_buflen=60, recover=False)
    info = inlet.info(5)
    setup = setup_from_info(info)
    assert setup.layout.point_names == tuple(rec.point_names)
    assert (setup.up_axis, setup.length_unit_m, setup.nominal_rate_hz) == ("z", 1.0, pytest.approx(rec.rate_hz))
    inlet.open_stream(5)
    frames, stamps = [], []
    try:
        while True:
            sample, stamp = inlet.pull_sample(timeout=5)
            if sample is None:
                break
            frames.append(sample)
            stamps.append(stamp)
    except pylsl.util.LostError:
        pass
    player.join(10)
    frames = np.array(frames)
    assert done["stats"].frames == rec.n_frames == len(frames)
    np.testing.assert_array_equal(frames[:, :-1], rec.positions_m.reshape(rec.n_frames, -1))
    np.testing.assert_array_equal(frames[:, -1], rec.time_s)
    # Paced, not pushed at once: the span covers the file's at that speed. (Every frame leaves at or
    # after its due time, but the first may leave late, by a scheduler's milliseconds on a loaded
    # machine, which shortens the span by as much: 5 % of it is allowed.)
    assert stamps[-1] - stamps[0] >= 0.95 * (rec.time_s[-1] - rec.time_s[0]) / speed


def test_duplicated_and_out_of_order_frames_are_dropped_counted_and_leave_the_estimates_unchanged():
    """A repeated and a late frame are dropped and counted; the estimates equal those of the clean sequence."""
    rec = short_walk(1.5)
    frames = pelvis_frames(rec)
    name = unique("order")
    outlet = pylsl.StreamOutlet(marker_info(pylsl, name, pelvis_labels()))
    live = LiveThread(name, resolve_timeout_s=10, max_buffer_s=10)
    assert outlet.wait_for_consumers(10)
    base = pylsl.local_clock()
    order = list(range(60)) + [59, 60, 61, 60] + list(range(62, rec.n_frames))
    for k in order:
        outlet.push_sample(frames[k].tolist(), base + rec.time_s[k])
    live.wait_for(rec.n_frames)
    live.settle(0.3)
    counters = live.stop()
    assert counters.dropped_not_increasing == 2
    assert counters.frames == len(order) and counters.estimates == rec.n_frames
    got = np.array(live.rows)
    assert np.all(np.diff(got[:, 0]) > 0)
    np.testing.assert_array_equal(got, reference_rows(base + rec.time_s, frames))


def test_source_that_stops_and_comes_back_is_reacquired_from_scratch():
    """After the source's silence the estimator starts over: the new frames' estimates equal a fresh run's."""
    rec = short_walk(2.0)
    frames = pelvis_frames(rec)
    name = unique("restart")
    half = rec.n_frames // 2
    outlet = pylsl.StreamOutlet(marker_info(pylsl, name, pelvis_labels(), source_id=name))
    live = LiveThread(name, resolve_timeout_s=10, reacquire_after_s=0.5, max_buffer_s=10)
    assert outlet.wait_for_consumers(10)
    base = pylsl.local_clock()
    for k in range(half):
        outlet.push_sample(frames[k].tolist(), base + rec.time_s[k])
    live.wait_for(half)
    del outlet
    gc.collect()
    time.sleep(0.8)
    outlet = pylsl.StreamOutlet(marker_info(pylsl, name, pelvis_labels(), source_id=name))
    assert outlet.wait_for_consumers(15), "live did not reconnect"
    base2 = pylsl.local_clock()  # the source's clock restarted too: its times start again from 0
    for k in range(rec.n_frames):
        outlet.push_sample(frames[k].tolist(), base2 + rec.time_s[k])
    live.wait_for(half + rec.n_frames)
    live.settle(0.3)
    counters = live.stop()
    assert counters.restarts == 1
    assert counters.estimates == half + rec.n_frames
    got = np.array(live.rows)
    np.testing.assert_array_equal(got[:half], reference_rows(base + rec.time_s[:half], frames[:half]))
    np.testing.assert_array_equal(got[half:], reference_rows(base2 + rec.time_s, frames))


def test_exit_on_end_returns_when_the_source_goes_away():
    """With exit_on_end, live returns once the source's outlet is gone, having estimated every frame."""
    rec = short_walk(1.0)
    frames = pelvis_frames(rec)
    name = unique("end")
    outlet = pylsl.StreamOutlet(marker_info(pylsl, name, pelvis_labels()))
    live = LiveThread(name, resolve_timeout_s=10, exit_on_end=True, max_buffer_s=10)
    assert outlet.wait_for_consumers(10)
    base = pylsl.local_clock()
    for k in range(rec.n_frames):
        outlet.push_sample(frames[k].tolist(), base + rec.time_s[k])
    live.wait_for(rec.n_frames)
    del outlet
    gc.collect()
    live.thread.join(10)
    assert not live.thread.is_alive()
    counters = live.stop()
    assert counters.source_ended and counters.estimates == rec.n_frames


def test_slow_consumer_keeps_a_bounded_buffer_and_counts_the_frames_it_lost():
    """A consumer stalled while 20 s of frames arrive keeps about max_buffer_s of them and counts the rest missing."""
    rate_hz, n = 100.0, 2000
    rec = short_walk(n / rate_hz - 0.01, rate_hz)
    frames = pelvis_frames(rec)
    name = unique("slow")
    outlet = pylsl.StreamOutlet(marker_info(pylsl, name, pelvis_labels(), rate_hz=rate_hz))
    stalled = []

    def stall(row, stamp):
        if not stalled:
            stalled.append(True)
            time.sleep(1.5)

    live = LiveThread(name, resolve_timeout_s=10, max_buffer_s=1.0, on_estimate=stall)
    assert outlet.wait_for_consumers(10)
    base = pylsl.local_clock()
    outlet.push_sample(frames[0].tolist(), base)
    live.wait_for(1)  # live is now stalled in its first estimate while the rest arrives
    for k in range(1, rec.n_frames):
        outlet.push_sample(frames[k].tolist(), base + rec.time_s[k])
    time.sleep(2.0)
    live.settle(0.5)
    counters = live.stop()
    assert counters.estimates <= 1 + 2 * rate_hz * 1.0  # about max_buffer_s of frames kept ...
    # ... and every one lost counted (the first frame after the jump is held back as a possible wild stamp)
    assert counters.estimates + counters.missing_frames + counters.dropped_jumps == rec.n_frames
    assert live.rows[-1][0] == base + rec.time_s[-1]  # the newest frames are the ones kept
    assert np.all(np.diff(np.array(live.rows)[:, 0]) > 0)


# ------------------------------------------------------------------ layouts (StreamInfo only, no network)


def test_layout_reads_yoyogait_and_other_systems_labels_units_and_xdf_fields():
    """Labels NAME_x, NAME.X, NAME X, NAMEX, Subject:NAME_x and XDF marker/type fields are read; mm give 0.001."""
    for labels in (
        [f"{p}_{a}" for p in PELVIS for a in "xyz"],
        [f"{p}.{a.upper()}" for p in PELVIS for a in "xyz"],
        [f"{p} {a.upper()}" for p in PELVIS for a in "xyz"],
        [f"{p}{a.upper()}" for p in PELVIS for a in "xyz"],
    ):
        setup = setup_from_info(marker_info(pylsl, "s", ["Frame"] + labels, unit="millimeters"))
        assert setup.layout.point_names == PELVIS
        assert setup.length_unit_m == 0.001
        np.testing.assert_array_equal(setup.layout.position_channels, np.arange(1, 13).reshape(4, 3))
    setup = setup_from_info(marker_info(pylsl, "v", [f"Walker:{p}_{a}" for p in PELVIS for a in "xyz"], unit="mm"))
    assert setup.choice.names == tuple(f"Walker:{p}" for p in PELVIS) and setup.length_unit_m == 0.001
    info = pylsl.StreamInfo("q", "Mocap", 6, 100.0, pylsl.cf_float32, "q")
    channels = info.desc().append_child("channels")
    for axis in "ZYX":  # any order: the type says which axis
        channels.append_child("channel").append_child_value("marker", "SACR").append_child_value(
            "type", f"Position{axis}"
        ).append_child_value("label", f"c{axis}").append_child_value("unit", "m")
    for axis in "XYZ":
        channels.append_child("channel").append_child_value("label", f"Body_q{axis.lower()}x")
    setup = setup_from_info(info, up_axis="y")
    assert setup.layout.point_names == ("SACR",)
    np.testing.assert_array_equal(setup.layout.position_channels, [[2, 1, 0]])
    assert (setup.up_axis, setup.length_unit_m) == ("y", 1.0)


@pytest.mark.parametrize(
    "labels, options, message",
    [
        ([None] * 12, {}, "carry no labels"),
        ([f"ch{i}" for i in range(12)], {}, "expected channels labelled <point>_x"),
        ([f"Marker{i}_{a}" for i in range(4) for a in "xyz"], {}, "pelvis points must be named"),
        ([f"Marker{i}_{a}" for i in range(4) for a in "xyz"], {"point": "Hip"}, "no point 'Hip'"),
    ],
)
def test_wrong_layouts_say_what_is_expected(labels, options, message):
    """Unlabelled, mislabelled or unnamed-marker streams raise an InputError saying what was expected."""
    with pytest.raises(InputError, match=message):
        setup_from_info(marker_info(pylsl, "bad", labels), **options)


def test_stream_without_unit_or_up_axis_asks_for_the_option():
    """A stream that does not state its unit or up axis asks for --length-unit-m / --up-axis."""
    with pytest.raises(InputError, match="--length-unit-m"):
        setup_from_info(marker_info(pylsl, "u", pelvis_labels(), unit=""))
    with pytest.raises(InputError, match="--up-axis"):
        setup_from_info(marker_info(pylsl, "u", pelvis_labels(), up_axis=""))
    setup = setup_from_info(marker_info(pylsl, "u", pelvis_labels(), unit="", up_axis=""), up_axis="y", length_unit_m=1)
    assert (setup.up_axis, setup.length_unit_m) == ("y", 1)


# ------------------------------------------------------------------ the command line


def test_live_without_a_source_exits_2_with_one_line(capsys):
    """live names the stream it could not find, in one line, and exits non-zero."""
    code = main(["live", "--source", unique("absent"), "--timeout", "0.3"])
    err = capsys.readouterr().err
    assert code == 2 and len(err.strip().splitlines()) == 1 and "no LSL stream named" in err


def test_live_on_a_stream_of_unnamed_markers_exits_2_saying_pelvis_points_must_be_named(capsys, tmp_path):
    """live on unnamed markers: one line saying the pelvis points must be named, exit 2, no --record file left."""
    name = unique("unnamed")
    outlet = pylsl.StreamOutlet(marker_info(pylsl, name, [f"M{i}_{a}" for i in range(5) for a in "xyz"]))
    out = tmp_path / "est.csv"
    code = main(["live", "--source", name, "--timeout", "5", "--record", str(out)])
    err = capsys.readouterr().err
    del outlet
    assert code == 2 and len(err.strip().splitlines()) == 1 and "pelvis points must be named" in err
    assert not out.exists() and not list(tmp_path.iterdir())


def test_replay_of_a_velocity_file_or_at_zero_speed_exits_2(tmp_path, capsys):
    """replay refuses a file without points and a non-positive speed, in one line."""
    vel = tmp_path / "v.csv"
    vel.write_text("time,vx,vz\n0,1,0\n0.04,1,0\n0.08,1,0\n")
    assert main(["replay", str(vel), "--name", unique("v")]) == 2
    assert "nothing to replay" in capsys.readouterr().err
    walk = tmp_path / "w.csv"
    write_csv(short_walk(0.5), walk)
    assert main(["replay", str(walk), "--name", unique("v"), "--speed", "0"]) == 2
    assert "--speed" in capsys.readouterr().err


def test_list_points_describes_a_qualisys_like_stream(capsys):
    """--list-points on a QTM-app-like stream (marker/type fields, float32, no rate, no up axis) says what it found."""
    name = unique("qtm")
    markers = ["R_IAS", "L_IAS", "R_IPS", "L_IPS", "R_FCC"]
    info = pylsl.StreamInfo(name, "Mocap", 3 * len(markers), 0.0, pylsl.cf_float32, name)
    channels = info.desc().append_child("channels")
    for m in markers:
        for axis in "XYZ":
            ch = channels.append_child("channel").append_child_value("label", f"{m}_{axis}")
            ch.append_child_value("marker", m).append_child_value("type", f"Position{axis}")
            ch.append_child_value("unit", "meters")
    outlet = pylsl.StreamOutlet(info)
    code = main(["live", "--source", name, "--list-points", "--timeout", "5"])
    out = capsys.readouterr().out
    del outlet
    assert code == 0
    assert f"points (5): {', '.join(markers)}" in out and "length unit: 1 m" in out and "irregular rate" in out
    assert "up axis: not stated (pass --up-axis)" in out
    assert "followed by default: pelvis centre of R_IAS, L_IAS, R_IPS, L_IPS" in out  # not the foot marker


def test_sigterm_ends_live_with_exit_143_the_summary_and_a_complete_record(tmp_path):
    """SIGTERM (a launcher stopping live) ends it at once: exit 143, the summary line, one CSV row per frame."""
    rec = short_walk(1.0)
    frames = pelvis_frames(rec)
    name = unique("term")
    outlet = pylsl.StreamOutlet(marker_info(pylsl, name, pelvis_labels()))
    record = tmp_path / "est.csv"
    live = subprocess.Popen(
        yoyogait_cmd("live", "--source", name, "--record", record, "--max-buffer-s", 10),
        env=dict(os.environ),
        stderr=subprocess.PIPE,
        text=True,
    )
    try:
        assert outlet.wait_for_consumers(30)
        base = pylsl.local_clock()
        for k in range(rec.n_frames):
            outlet.push_sample(frames[k].tolist(), base + rec.time_s[k])
        time.sleep(1.0)
        live.terminate()
        assert live.wait(20) == 143
        err = live.stderr.read()
        assert f"live: {rec.n_frames} frames, {rec.n_frames} estimates" in err, err
    finally:
        if live.poll() is None:
            live.kill()
    rows = np.loadtxt(record, delimiter=",", skiprows=1)
    assert rows.shape[0] == rec.n_frames
    np.testing.assert_allclose(rows[:, 0], base + rec.time_s, rtol=0, atol=1e-6)  # written with %.6f


def test_duration_ends_live_with_exit_0_and_the_summary_line(capsys):
    """--duration S: live stops after S seconds on a silent source and exits 0 with its summary."""
    name = unique("quiet")
    outlet = pylsl.StreamOutlet(marker_info(pylsl, name, pelvis_labels()))
    started = time.monotonic()
    code = main(["live", "--source", name, "--duration", "0.5", "--timeout", "5"])
    elapsed = time.monotonic() - started
    err = capsys.readouterr().err
    del outlet
    assert code == 0 and elapsed < 5
    assert "live: 0 frames, 0 estimates" in err


def test_status_line_shows_rate_step_frequency_speed_and_latency_on_one_line():
    """The terminal status line is rewritten in place (\\r) with rate, step frequency, speed, latency, counts."""
    stream = StringIO()
    line = StatusLine(stream)
    row = [0.0] * len(ESTIMATE_COLUMNS)
    row[ESTIMATE_COLUMNS.index("step_frequency_hz")] = 1.85
    row[ESTIMATE_COLUMNS.index("speed_mps")] = 1.3
    row[ESTIMATE_COLUMNS.index("walking")] = 1.0
    counters = LiveCounters(frames=50, dropped_not_increasing=2, missing_frames=3, latency_s=[0.0004, 0.0006])
    line.show(counters, row)
    line.close()
    text = stream.getvalue()
    assert text.startswith("\r") and text.endswith("\n") and text.count("\n") == 1
    assert "step 1.85 Hz" in text and "speed 1.30 m/s" in text and "walking" in text
    assert "latency 0.50 ms" in text and "dropped 2 missing 3" in text and "frames/s" in text


def test_status_line_says_whether_the_estimate_is_valid_and_why_not_by_name():
    """valid, or not valid with the reasons named (the marker path's bits; the IMU path's one reason)."""

    def shown(columns, **values):
        stream, row = StringIO(), [0.0] * len(columns)
        for name, value in values.items():
            row[columns.index(name)] = float(value)
        StatusLine(stream, columns).show(LiveCounters(frames=1), row)
        return stream.getvalue()

    bits = int(InvalidReason.ACQUIRING) | int(InvalidReason.MODEL_NOT_HOLDING)
    assert "| not valid (acquiring, model not holding) |" in shown(ESTIMATE_COLUMNS, invalid_reason=bits)
    assert "| valid |" in shown(ESTIMATE_COLUMNS, valid=1)
    assert "| not valid (not walking) |" in shown(IMU_COLUMNS, reason=int(ImuReason.NOT_WALKING))
    assert "| valid |" in shown(IMU_COLUMNS, valid=1)


def test_looped_replay_starts_over_after_a_pause_with_time_still_increasing():
    """--loop: the second pass repeats the frames, its time_s shifted by the duration plus the pause."""
    rec = short_walk(0.3)
    name = unique("loop")
    stop = threading.Event()
    player = threading.Thread(
        target=lambda: replay(rec, name, speed=5.0, loop=True, wait_for_consumer_s=10, stop=stop), daemon=True
    )
    player.start()
    inlet = pylsl.StreamInlet(pylsl.resolve_byprop("name", name, 1, 10)[0], max_buflen=60)
    inlet.open_stream(5)
    frames = []
    while len(frames) < 2 * rec.n_frames:
        sample, _ = inlet.pull_sample(timeout=5)
        assert sample is not None
        frames.append(sample)
    stop.set()
    player.join(5)
    frames = np.array(frames)
    first, second = frames[: rec.n_frames], frames[rec.n_frames :]
    np.testing.assert_array_equal(second[:, :-1], first[:, :-1])
    period = rec.time_s[-1] - rec.time_s[0] + LOOP_PAUSE_S
    np.testing.assert_allclose(second[:, -1], first[:, -1] + period, rtol=0, atol=1e-12)
    assert np.all(np.diff(frames[:, -1]) > 0)


def test_live_refuses_to_publish_under_the_source_name(capsys):
    """--publish equal to --source would make live read its own estimates: one line, exit 2."""
    assert main(["live", "--source", "same", "--publish", "same", "--timeout", "1"]) == 2
    assert "other than the source" in capsys.readouterr().err


def test_real_qualisys_walk_replayed_and_estimated_live_equals_the_offline_online_run(datasets_dir):
    """A real C3D walk (Qualisys, 240 Hz, mm) through replay and live: each frame's estimate = the offline run's."""
    rec = io.read(datasets_dir / "c3d_org_samples" / "sample26_Qualisys_Walking_Hybrid_1_2.c3d")
    name = unique("real")
    live = LiveThread(name, resolve_timeout_s=10, max_buffer_s=30)
    player = threading.Thread(target=lambda: replay(rec, name, speed=4, wait_for_consumer_s=10), daemon=True)
    player.start()
    player.join(30)
    live.wait_for(rec.n_frames)
    counters = live.stop()
    assert counters.estimates == rec.n_frames and counters.dropped_not_increasing == counters.missing_frames == 0
    result = OnlineEstimator.for_recording(rec).run(rec)
    expected = np.column_stack([np.asarray(getattr(result, c), dtype=float) for c in ESTIMATE_COLUMNS])
    np.testing.assert_array_equal(np.array(live.rows), expected)
