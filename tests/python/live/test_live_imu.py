"""live on an LSL stream of a lower-back IMU, on this machine only (tests/conftest.py confines LSL to 127.0.0.1):
replay of a real recording, the stream's labels and units, unruly sources, and bad input in one line."""

from __future__ import annotations

import gc
import os
import re
import subprocess
import sys
import threading
import time
from pathlib import Path

import numpy as np
import pytest
from live_helpers import LiveThread, unique

from yoyogait.cli import main
from yoyogait.errors import InputError
from yoyogait.estimators.config import ImuConfig
from yoyogait.estimators.imu import ImuOnlineEstimator, ImuReason, estimator_for
from yoyogait.io.imu_read import read_imu
from yoyogait.io.imu_recording import GRAVITY_MPS2
from yoyogait.live.imu_layout import imu_stream_info, is_imu_info, read_imu_layout
from yoyogait.live.imu_live import (
    AUTO_PEEK_S,
    IMU_COLUMNS,
    ImuLiveOptions,
    UnitCheck,
    imu_row,
    imu_setup_from_info,
    run_live_source,
)
from yoyogait.live.layout import marker_stream_info
from yoyogait.live.replay import replay_imu
from yoyogait.synthetic_imu import make_imu_walk

pylsl = pytest.importorskip("pylsl")

MOBGAP_CSV = "imu_mobgap/example_data/data_csv/HA/001/TimeMeasure1_Test5_Trial1.csv"
DEG = np.pi / 180.0


def imu_info(name, labels, units, *, rate_hz=100.0, kind="IMU", source_id=None):
    """An IMU StreamInfo as another system might send it: labelled channels with units."""
    info = pylsl.StreamInfo(name, kind, len(labels), rate_hz, pylsl.cf_double64, source_id or name)
    channels = info.desc().append_child("channels")
    for label, unit in zip(labels, units):
        ch = channels.append_child("channel").append_child_value("label", label)
        if unit:
            ch.append_child_value("unit", unit)
    return info


LABELS = ["acc_x", "acc_y", "acc_z", "gyr_x", "gyr_y", "gyr_z"]
UNITS = ["m/s^2"] * 3 + ["rad/s"] * 3


def reference_rows(times, acc, gyr, config=None):
    """What a fresh ImuOnlineEstimator gives for these samples, as IMU estimate-stream rows."""
    est = ImuOnlineEstimator(config)
    return np.array([imu_row(est.update(t, a, g)) for t, a, g in zip(times, acc, gyr)])


class SourceThread(LiveThread):
    """LiveThread over run_live_source (markers or IMU, as the stream says)."""

    def __init__(self, source: str, **options):
        self.rows = []
        self.stamps = []
        self.counters = None
        self.error = None
        self._stop = threading.Event()

        def collect(row, stamp):
            self.rows.append(row)
            self.stamps.append(stamp)

        def body():
            try:
                self.counters = run_live_source(source, on_estimate=collect, stop=self._stop, **options)
            except BaseException as exc:  # reported by stop()
                self.error = exc

        self.thread = threading.Thread(target=body, daemon=True)
        self.thread.start()


def test_replayed_real_imu_recording_live_record_equals_estimate_of_the_file(datasets_dir, tmp_path):
    """A real lower-back recording (mobgap CSV, 100 Hz) replayed as an IMU stream and estimated by live (auto-
    detected): the subscriber gets every sample's estimate in order, equal to the per-sample run of the file; the
    --record CSV is character for character what `yoyogait estimate FILE` writes."""
    path = datasets_dir / MOBGAP_CSV
    rec = read_imu(path)
    source, estimates = unique("imu"), unique("imu-gait")
    record = tmp_path / "live.csv"
    # The source is there before live starts, so that auto knows it at once: an IMU source that appears later
    # is first waited for as markers, with the marker estimate stream (docs/live.md).
    ready = threading.Event()
    player = threading.Thread(
        target=lambda: replay_imu(rec, source, speed=5, wait_for_consumer_s=30, on_ready=ready.set), daemon=True
    )
    player.start()
    assert ready.wait(15) and pylsl.resolve_byprop("name", source, 1, 15), "the source did not appear"
    live = subprocess.Popen(
        [sys.executable, "-m", "yoyogait", "live", "--source", source, "--publish", estimates, "--record", record,
         "--exit-on-end", "--timeout", "30", "--max-buffer-s", "60"],
        env=dict(os.environ),
        stderr=subprocess.PIPE,
        text=True,
    )  # fmt: skip
    try:
        found = pylsl.resolve_byprop("name", estimates, 1, 30)
        assert found, "the estimate stream did not appear"
        inlet = pylsl.StreamInlet(found[0], max_buflen=120, recover=False)
        assert inlet.info(10).channel_count() == len(IMU_COLUMNS)
        inlet.open_stream(10)
        rows = []
        try:
            while len(rows) < rec.n_samples:
                sample, _ = inlet.pull_sample(timeout=15)
                if sample is None:
                    break
                rows.append(sample)
        except pylsl.util.LostError:
            pass
        player.join(30)
        assert live.wait(30) == 0, live.stderr.read()
        err = live.stderr.read()
    finally:
        if live.poll() is None:
            live.kill()
    assert f"live: {source!r} at 100 Hz, an IMU (acc in m/s^2, gyr in rad/s, sensor height 0.964 m)" in err, err
    assert f"live: {rec.n_samples} frames, {rec.n_samples} estimates; dropped (time not increasing) 0" in err, err
    expected = estimator_for(rec).run_recording(rec)
    want = np.column_stack([np.asarray(expected[c], dtype=float) for c in IMU_COLUMNS])
    got = np.array(rows)
    assert got.shape == want.shape
    np.testing.assert_array_equal(got, want)
    assert 0.2 < want[:, IMU_COLUMNS.index("valid")].mean() < 1.0  # a walk, valid part of the time
    offline = tmp_path / "offline.csv"
    assert main(["estimate", str(path), "--out", str(offline)]) == 0
    assert record.read_text() == offline.read_text()


def test_labels_and_units_of_other_systems_are_read_g_and_deg_s_converted():
    """An IMU stream of another system (type unset, labels LumbarAccX.., units g and deg/s, a magnetometer): detected
    as an IMU by its labels, converted to m/s^2 and rad/s; every sample's estimate is that of the converted
    samples."""
    rec = make_imu_walk(duration_s=4.0).recording
    name = unique("other")
    labels = [f"Lumbar{k}{a}" for k in ("Acc", "Gyro", "Mag") for a in "XYZ"]
    info = imu_info(name, labels, ["g"] * 3 + ["deg/s"] * 3 + ["uT"] * 3, kind="")
    assert is_imu_info(info)
    layout = read_imu_layout(info)
    assert (layout.acc_scale, layout.gyr_scale) == (GRAVITY_MPS2, DEG) and layout.mag_channels is not None
    outlet = pylsl.StreamOutlet(info)
    live = SourceThread(name, resolve_timeout_s=10, max_buffer_s=10)
    assert outlet.wait_for_consumers(10)
    acc_g, gyr_deg = rec.acc_mps2 / GRAVITY_MPS2, rec.gyr_rad_s / DEG
    base = pylsl.local_clock()
    for k in range(rec.n_samples):
        outlet.push_sample([*acc_g[k], *gyr_deg[k], 20.0, 0.0, -40.0], base + rec.time_s[k])
    live.wait_for(rec.n_samples)
    live.settle(0.3)
    counters = live.stop()
    assert counters.estimates == rec.n_samples
    np.testing.assert_array_equal(
        np.array(live.rows), reference_rows(base + rec.time_s, acc_g * GRAVITY_MPS2, gyr_deg * DEG)
    )


def test_a_microcontrollers_short_labels_are_an_imu_stream():
    """A stream labelled ax, ay, az, gx, gy, gz (a microcontroller's sketch; type unset) is an IMU's, its channels
    in order, with the units its channels state."""
    info = imu_info(unique("mcu"), ["ax", "ay", "az", "gx", "gy", "gz"], ["g"] * 3 + ["deg/s"] * 3, kind="")
    assert is_imu_info(info)
    layout = read_imu_layout(info)
    assert (layout.acc_scale, layout.gyr_scale) == (GRAVITY_MPS2, DEG)
    assert tuple(layout.acc_channels) == (0, 1, 2) and tuple(layout.gyr_channels) == (3, 4, 5)


def test_repeated_and_late_samples_are_dropped_counted_and_leave_the_estimates_unchanged():
    """A repeated and a late IMU sample are dropped and counted; the estimates equal those of the clean sequence."""
    rec = make_imu_walk(duration_s=3.0).recording
    name = unique("imu-order")
    outlet = pylsl.StreamOutlet(imu_info(name, LABELS, UNITS))
    live = SourceThread(name, input_kind="imu", resolve_timeout_s=10, max_buffer_s=10)
    assert outlet.wait_for_consumers(10)
    base = pylsl.local_clock()
    order = list(range(100)) + [99, 100, 101, 100] + list(range(102, rec.n_samples))
    for k in order:
        outlet.push_sample([*rec.acc_mps2[k], *rec.gyr_rad_s[k]], base + rec.time_s[k])
    live.wait_for(rec.n_samples)
    live.settle(0.3)
    counters = live.stop()
    assert counters.dropped_not_increasing == 2 and counters.estimates == rec.n_samples
    np.testing.assert_array_equal(np.array(live.rows), reference_rows(base + rec.time_s, rec.acc_mps2, rec.gyr_rad_s))


def test_source_that_stops_and_comes_back_relabelled_is_read_again_from_scratch():
    """The IMU source goes away and comes back with its gyro and acc channels swapped: live reconnects, says the
    layout changed, and the new samples' estimates equal a fresh run's."""
    rec = make_imu_walk(duration_s=2.0).recording
    name = unique("imu-back")
    half = rec.n_samples // 2
    notes: list[str] = []
    outlet = pylsl.StreamOutlet(imu_info(name, LABELS, UNITS, source_id=name))
    live = SourceThread(name, input_kind="imu", resolve_timeout_s=10, max_buffer_s=10, on_note=notes.append)
    assert outlet.wait_for_consumers(10)
    base = pylsl.local_clock()
    for k in range(half):
        outlet.push_sample([*rec.acc_mps2[k], *rec.gyr_rad_s[k]], base + rec.time_s[k])
    live.wait_for(half)
    del outlet
    gc.collect()
    swapped = LABELS[3:] + LABELS[:3]
    outlet = pylsl.StreamOutlet(imu_info(name, swapped, UNITS[3:] + UNITS[:3], source_id=name))
    assert outlet.wait_for_consumers(15), "live did not reconnect"
    base2 = pylsl.local_clock()
    for k in range(rec.n_samples):
        outlet.push_sample([*rec.gyr_rad_s[k], *rec.acc_mps2[k]], base2 + rec.time_s[k])
    live.wait_for(half + rec.n_samples)
    live.settle(0.3)
    counters = live.stop()
    assert counters.reconnects == 1 and counters.restarts == 1
    assert any("came back with another layout" in n for n in notes), notes
    got = np.array(live.rows)
    assert len(got) == half + rec.n_samples
    np.testing.assert_array_equal(got[half:], reference_rows(base2 + rec.time_s, rec.acc_mps2, rec.gyr_rad_s))


def test_saturated_upside_down_gap_and_rest_through_live_are_flagged_or_estimated_as_the_files_are():
    """Online through live, as for a file: a clipping accelerometer gives SATURATED, a 0.5 s gap GAP, a sensor at
    rest is never valid, one worn upside down is valid once walking; each sample's estimate equals the file run's."""
    walk = make_imu_walk(duration_s=10.0).recording
    clipped = make_imu_walk(duration_s=10.0, acc_range_mps2=11.0).recording
    upside = make_imu_walk(duration_s=10.0, upside_down=True).recording
    keep = (walk.time_s < 5.0) | (walk.time_s >= 5.5)
    n = walk.n_samples
    rest = (walk.time_s, np.tile([GRAVITY_MPS2, 0.0, 0.0], (n, 1)), np.zeros((n, 3)), None)
    cases = {
        "saturated": (clipped.time_s, clipped.acc_mps2, clipped.gyr_rad_s, ImuConfig(acc_saturation_mps2=11.0)),
        "upside down": (upside.time_s, upside.acc_mps2, upside.gyr_rad_s, None),
        "gap": (walk.time_s[keep], walk.acc_mps2[keep], walk.gyr_rad_s[keep], None),
        "rest": rest,
    }
    results = {}
    for case, (t, acc, gyr, config) in cases.items():
        name = unique("imu-" + case.replace(" ", "-"))
        outlet = pylsl.StreamOutlet(imu_info(name, LABELS + ["time_s"], UNITS + ["s"]))
        live = SourceThread(
            name, input_kind="imu", imu=ImuLiveOptions(config=config), resolve_timeout_s=10, max_buffer_s=30
        )
        assert outlet.wait_for_consumers(10)
        for k in range(len(t)):
            outlet.push_sample([*acc[k], *gyr[k], t[k]])
        live.wait_for(len(t))
        live.settle(0.3)
        live.stop()
        del outlet
        rows = np.array(live.rows)
        np.testing.assert_array_equal(rows, reference_rows(t, acc, gyr, config), err_msg=case)
        results[case] = rows
    reason, valid, time_s = (IMU_COLUMNS.index(c) for c in ("reason", "valid", "time_s"))
    settled = results["saturated"][:, time_s] >= 3.0
    assert np.all(results["saturated"][settled, reason] == int(ImuReason.SATURATED))
    k = int(np.searchsorted(results["gap"][:, time_s], 5.5))
    assert results["gap"][k, reason] == int(ImuReason.GAP) and not results["gap"][k, valid]
    assert not results["rest"][:, valid].any()
    assert results["upside down"][-1, valid] == 1


def _cli_on_stream(name, info, samples, args=(), timeout_s=20.0):
    """``yoyogait live --source name ...`` in a subprocess against a stream that sends ``samples`` at 100 Hz; its
    exit code and stderr."""
    outlet = pylsl.StreamOutlet(info)
    proc = subprocess.Popen(
        [sys.executable, "-m", "yoyogait", "live", "--source", name, "--timeout", "20", *map(str, args)],
        env=dict(os.environ),
        stderr=subprocess.PIPE,
        text=True,
    )
    try:
        # live may refuse the stream without ever consuming it: wait for a consumer or for live's end
        deadline = time.monotonic() + 20
        while not outlet.have_consumers() and proc.poll() is None and time.monotonic() < deadline:
            time.sleep(0.05)
        if samples is not None and outlet.have_consumers():
            base = pylsl.local_clock()
            for k, s in enumerate(samples):
                if proc.poll() is not None:
                    break
                outlet.push_sample(list(s), base + k / 100.0)
                if k % 50 == 0:
                    time.sleep(0.05)
        code = proc.wait(timeout_s)
    finally:
        if proc.poll() is None:
            proc.kill()
        del outlet
    return code, proc.stderr.read()


@pytest.mark.parametrize(
    "case, message",
    [
        (
            "gravity in g",
            r"median norm over the first 0.5 s is 1.00 m/s\^2 \(read as m/s\^2\), not 9.81 at rest: "
            r"in g\? pass --acc-unit g",
        ),  # fmt: skip
        (
            "deg/s as rad/s",
            r"exceeds 15 rad/s in \d+ of \d+ samples, beyond any walk: in deg/s\? pass --gyr-unit deg_s",
        ),
        (
            "a foot's rate in deg/s",
            r"read as deg/s exceeds 15 rad/s in \d+ of \d+ samples, beyond a lower back's in any walk: a sensor on "
            r"a foot or a leg\?",
        ),
        ("no gyro", r"no gyr_x, gyr_y, gyr_z channel; expected channels labelled acc_x"),
        (
            "no units",
            r"its acceleration channels carry no unit; pass --acc-unit \(mps2 or g\); its angular rate channels carry "
            r"no unit; pass --gyr-unit \(rad_s or deg_s\)",
        ),
    ],
)
def test_bad_imu_streams_end_live_with_one_line_naming_the_stream_and_what_was_expected(case, message, tmp_path):
    """Gravity in g or deg/s said to be m/s^2 / rad/s, a foot's rate, missing gyro channels, no units: one line naming
    the stream and what was expected (the option to pass, or where the sensor is), exit 2, no traceback."""
    walk = make_imu_walk(None, "3-rectangle", duration_s=12.0).recording
    name = unique("imu-bad")
    labels, units = LABELS, UNITS
    acc, gyr = walk.acc_mps2, walk.gyr_rad_s
    if case == "gravity in g":
        acc = acc / GRAVITY_MPS2
    elif case == "deg/s as rad/s":
        gyr = gyr / DEG
    elif case == "a foot's rate in deg/s":  # said in deg/s, and a foot's 20 rad/s
        gyr = gyr * (20.0 / np.percentile(np.abs(gyr), 99)) / DEG
        units = UNITS[:3] + ["deg/s"] * 3
    elif case == "no gyro":
        labels, units = LABELS[:3] + ["ch3", "ch4", "ch5"], UNITS
    elif case == "no units":
        units = [""] * 6
    samples = np.column_stack([acc, gyr])
    code, err = _cli_on_stream(name, imu_info(name, labels, units), samples, ["--input", "imu"])
    lines = [line for line in err.splitlines() if not line.startswith("live:")]
    assert code == 2, err
    assert len(lines) == 1 and f"stream {name!r}" in lines[0] and "Traceback" not in err, err
    assert any(re.search(message, line) for line in lines), err


def test_an_imu_stream_read_as_markers_says_to_pass_input_imu():
    """--input markers on an IMU stream: one line saying it is an IMU stream and naming --input imu."""
    name = unique("imu-as-markers")
    code, err = _cli_on_stream(name, imu_info(name, LABELS, UNITS), None, ["--input", "markers"])
    assert code == 2 and len(err.strip().splitlines()) == 1, err
    assert f"stream {name!r}: an IMU stream (type 'IMU'), not markers; pass --input imu" in err


def test_a_marker_streams_options_on_an_imu_stream_are_refused_not_ignored():
    """--feet and --belt-speed-mps on an IMU stream: one line naming the stream and both options, exit 2."""
    name = unique("imu-with-feet")
    walk = make_imu_walk(duration_s=2.0).recording
    samples = np.column_stack([walk.acc_mps2, walk.gyr_rad_s])
    code, err = _cli_on_stream(
        name, imu_info(name, LABELS, UNITS), samples, ["--feet", "LHEE,RHEE", "--belt-speed-mps", "1"]
    )
    lines = [line for line in err.splitlines() if not line.startswith("live:")]
    assert code == 2 and len(lines) == 1 and "Traceback" not in err, err
    assert f"stream {name!r} is an IMU stream: --feet, --belt-speed-mps" in lines[0], err


def test_the_imu_options_on_a_marker_stream_are_refused_not_ignored():
    """--acc-unit and --sensor-height-m on a marker stream: one line naming the stream and both options, exit 2."""
    name = unique("markers-with-imu-options")
    info = marker_stream_info(name, ["LASI", "RASI", "LPSI", "RPSI"], 100.0, "z")
    frames = np.zeros((100, 13))
    code, err = _cli_on_stream(name, info, frames, ["--acc-unit", "g", "--sensor-height-m", "1"])
    lines = [line for line in err.splitlines() if not line.startswith("live:")]
    assert code == 2 and len(lines) == 1 and "Traceback" not in err, err
    assert f"stream {name!r} is a marker stream: --acc-unit, --sensor-height-m" in lines[0], err


def test_list_points_describes_an_imu_stream(capsys):
    """--list-points on an IMU stream: its acc and gyro channels, their units, the time base, the sensor height."""
    name = unique("imu-list")
    outlet = pylsl.StreamOutlet(imu_stream_info(name, 100.0, sensor_height_m=0.97))
    assert main(["live", "--source", name, "--list-points", "--timeout", "5"]) == 0
    out = capsys.readouterr().out
    del outlet
    assert "an IMU stream" in out and "acceleration: acc_x, acc_y, acc_z" in out
    assert "units: acceleration m/s^2, angular rate rad/s" in out and "time: the time_s channel" in out
    assert "sensor height: 0.97 m" in out


def test_imu_setup_takes_the_options_over_the_stream():
    """--acc-unit/--gyr-unit override the channels' units, --sensor-height-m the stream's setup; bad values one line."""
    info = imu_stream_info("s", 100.0, sensor_height_m=0.9)
    setup = imu_setup_from_info(info, ImuLiveOptions(acc_unit="g", gyr_unit="deg_s", sensor_height_m=1.05))
    assert (setup.layout.acc_scale, setup.layout.gyr_scale, setup.sensor_height_m) == (GRAVITY_MPS2, DEG, 1.05)
    assert imu_setup_from_info(info).sensor_height_m == 0.9
    with pytest.raises(InputError, match=r"--sensor-height-m must be in \(0.1, 3\] m"):
        imu_setup_from_info(info, ImuLiveOptions(sensor_height_m=30.0))


def test_replay_cli_plays_an_imu_file_into_an_imu_stream(datasets_dir, capsys):
    """yoyogait replay on an IMU file makes an IMU stream (type IMU, acc/gyr/time_s, the sensor height) of its
    samples."""
    path = datasets_dir / MOBGAP_CSV
    rec = read_imu(path)
    name = unique("imu-replay")
    done = {}
    player = threading.Thread(
        target=lambda: done.update(code=main(["replay", str(path), "--name", name, "--speed", "20",
                                              "--wait-for-consumer", "20"])),
        daemon=True,
    )  # fmt: skip
    player.start()
    found = pylsl.resolve_byprop("name", name, 1, 20)
    inlet = pylsl.StreamInlet(found[0], max_buflen=60, recover=False)
    info = inlet.info(5)
    assert info.type() == "IMU" and is_imu_info(info)
    assert read_imu_layout(info).sensor_height_m == rec.sensor_height_m
    inlet.open_stream(5)
    samples = []
    try:
        while True:
            sample, _ = inlet.pull_sample(timeout=5)
            if sample is None:
                break
            samples.append(sample)
    except pylsl.util.LostError:
        pass
    player.join(20)
    assert done["code"] == 0
    got = np.array(samples)
    np.testing.assert_array_equal(got, np.column_stack([rec.acc_mps2, rec.gyr_rad_s, rec.time_s]))
    assert f"pushed {rec.n_samples} samples" in capsys.readouterr().err


def test_docs_list_the_imu_estimate_streams_channels_in_order():
    """docs/live.md lists every channel of the IMU estimate stream, in the table's order."""
    text = (Path(__file__).resolve().parents[3] / "docs" / "live.md").read_text()
    assert ", ".join(IMU_COLUMNS) + "." in " ".join(text.split())


def test_auto_waits_as_for_markers_then_takes_the_imu_path_when_an_imu_source_appears():
    """--input auto with no source yet: live waits; an IMU stream of that name appears: its samples are estimated
    by the IMU path and published on an IMU estimate stream (24 channels)."""
    rec = make_imu_walk(duration_s=1.5).recording
    name, publish = unique("imu-late"), unique("imu-late-gait")
    live = SourceThread(name, publish=publish, resolve_timeout_s=20, max_buffer_s=10)
    time.sleep(AUTO_PEEK_S + 1.0)  # past the quick look: the marker path is waiting
    outlet = pylsl.StreamOutlet(imu_info(name, LABELS, UNITS))
    assert outlet.wait_for_consumers(15)
    base = pylsl.local_clock()
    for k in range(rec.n_samples):
        outlet.push_sample([*rec.acc_mps2[k], *rec.gyr_rad_s[k]], base + rec.time_s[k])
    live.wait_for(rec.n_samples)
    live.settle(0.3)
    found = pylsl.resolve_byprop("name", publish, 1, 5)
    counters = live.stop()
    assert counters.estimates == rec.n_samples
    np.testing.assert_array_equal(np.array(live.rows), reference_rows(base + rec.time_s, rec.acc_mps2, rec.gyr_rad_s))
    assert found and {i.channel_count() for i in found} == {len(IMU_COLUMNS)}


def test_sigterm_ends_live_on_an_imu_stream_with_143_the_summary_and_a_complete_record(tmp_path):
    """SIGTERM during an IMU run: exit 143, the summary line, one CSV row per sample received."""
    rec = make_imu_walk(duration_s=1.0).recording
    name = unique("imu-term")
    outlet = pylsl.StreamOutlet(imu_info(name, LABELS, UNITS))
    record = tmp_path / "est.csv"
    live = subprocess.Popen(
        [sys.executable, "-m", "yoyogait", "live", "--source", name, "--input", "imu", "--record", record,
         "--max-buffer-s", "10"],
        env=dict(os.environ),
        stderr=subprocess.PIPE,
        text=True,
    )  # fmt: skip
    try:
        assert outlet.wait_for_consumers(30)
        base = pylsl.local_clock()
        for k in range(rec.n_samples):
            outlet.push_sample([*rec.acc_mps2[k], *rec.gyr_rad_s[k]], base + rec.time_s[k])
        time.sleep(1.0)
        live.terminate()
        assert live.wait(20) == 143
        err = live.stderr.read()
    finally:
        if live.poll() is None:
            live.kill()
    assert f"live: {rec.n_samples} frames, {rec.n_samples} estimates" in err, err
    rows = np.genfromtxt(record, delimiter=",", names=True)
    assert rows.shape[0] == rec.n_samples and rows.dtype.names == IMU_COLUMNS


def test_the_online_unit_check_on_the_real_recordings(datasets_dir):
    """On each real lower-back recording the online unit check passes with the right units, stops within its first
    half second for g said as m/s^2, and within 10 s of the walk for deg/s said as rad/s."""
    setup = imu_setup_from_info(imu_stream_info("real", 100.0))
    files = sorted((datasets_dir / "imu_mobgap/example_data/data_csv").rglob("*.csv"))
    assert len(files) == 9
    for f in files:
        rec = read_imu(f)
        for acc_scale, gyr_scale, stops_by_s in ((1.0, 1.0, None), (1 / GRAVITY_MPS2, 1.0, 0.6), (1.0, 1 / DEG, 10.0)):
            check = UnitCheck(setup)
            stopped_at = None
            try:
                for t, a, g in zip(rec.time_s, rec.acc_mps2 * acc_scale, rec.gyr_rad_s * gyr_scale):
                    check.check(t, list(a), list(g))
            except InputError:
                stopped_at = t - rec.time_s[0]
            if stops_by_s is None:
                assert stopped_at is None, f
            else:
                assert stopped_at is not None and stopped_at <= stops_by_s, (f, stopped_at)
