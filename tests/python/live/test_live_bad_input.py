"""live under malformed or unruly LSL sources: each case one line or a count, never a traceback or silence."""

from __future__ import annotations

import gc
import os
import pty
import select
import signal
import subprocess
import sys
import time

import numpy as np
import pytest
from live_helpers import PELVIS, LiveThread, marker_info, pelvis_frames, pelvis_labels, short_walk, unique

from yoyogait import OnlineEstimator
from yoyogait.cli import main
from yoyogait.errors import InputError
from yoyogait.live.live import estimate_row, run_live, setup_from_info

pylsl = pytest.importorskip("pylsl")


def reference_rows(times, frames, points=PELVIS):
    """What a fresh OnlineEstimator gives for these frames, as estimate-stream rows."""
    est = OnlineEstimator(list(points), "z", 1.0)
    return np.array([estimate_row(est.update(t, f.reshape(len(points), 3))) for t, f in zip(times, frames)])


def test_one_frame_stamped_1e307_or_100_s_back_is_dropped_counted_and_resets_nothing():
    """A single wild stamp (1e307, 100 s in the past) is dropped and counted; no OverflowError, no restart, the
    other frames' estimates equal those of the clean sequence."""
    rec = short_walk(1.0)
    frames = pelvis_frames(rec)
    name = unique("wild")
    outlet = pylsl.StreamOutlet(marker_info(pylsl, name, pelvis_labels()))
    live = LiveThread(name, resolve_timeout_s=10, max_buffer_s=10)
    assert outlet.wait_for_consumers(10)
    base = pylsl.local_clock()
    for k in range(rec.n_frames):
        if k == 30:
            outlet.push_sample(frames[k].tolist(), 1e307)
        if k == 60:
            outlet.push_sample(frames[k].tolist(), base + rec.time_s[k] - 100.0)
        outlet.push_sample(frames[k].tolist(), base + rec.time_s[k])
    live.wait_for(rec.n_frames)
    live.settle(0.3)
    counters = live.stop()
    assert counters.dropped_jumps == 2 and counters.restarts == 0
    assert counters.estimates == rec.n_frames
    np.testing.assert_array_equal(np.array(live.rows), reference_rows(base + rec.time_s, frames))


def test_a_burst_of_frames_faster_than_the_nominal_rate_is_counted():
    """Frames pushed at once, stamped on arrival, at a nominal 100 Hz: each closer than half a period is counted."""
    name = unique("burst")
    outlet = pylsl.StreamOutlet(marker_info(pylsl, name, pelvis_labels(), rate_hz=100.0))
    live = LiveThread(name, resolve_timeout_s=10, max_buffer_s=10)
    assert outlet.wait_for_consumers(10)
    frame = pelvis_frames(short_walk(0.1))[0].tolist()
    for _ in range(300):
        outlet.push_sample(frame)  # stamped now: 300 frames within a few milliseconds
    live.wait_for(300)
    live.settle(0.3)
    counters = live.stop()
    assert counters.estimates + counters.dropped_not_increasing == 300
    assert counters.burst_frames >= 0.9 * (counters.estimates - 1)


def test_a_rate_of_1e12_hz_or_a_buffer_of_1e300_s_is_one_line_and_exit_2(capsys):
    """A stream stating 1e12 Hz, and --max-buffer-s 1e300: one line each naming what is expected, exit 2."""
    name = unique("rate")
    outlet = pylsl.StreamOutlet(marker_info(pylsl, name, pelvis_labels(), rate_hz=1e12))
    try:
        assert main(["live", "--source", name, "--timeout", "5", "--duration", "1"]) == 2
        err = capsys.readouterr().err
        assert err.count("\n") == 1 and f"stream {name!r}: " in err
        assert "nominal rate" in err and "10000" in err, err  # liblsl itself cannot parse the rate: said as such
    finally:
        del outlet
        gc.collect()
    assert main(["live", "--source", name, "--max-buffer-s", "1e300", "--timeout", "1"]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and "--max-buffer-s must be a number of seconds in (0, 3600]" in err


def test_a_time_channel_in_int16_is_refused_in_one_line_naming_the_stream():
    """time_s in an int16 stream would give one time per second: refused, saying to send floats or no time_s."""
    info = marker_info(pylsl, "int16-time", pelvis_labels() + ["time_s"], fmt=pylsl.cf_int16)
    with pytest.raises(InputError, match=r"stream 'int16-time': its time_s channel is in an integer format \(int16\)"):
        setup_from_info(info)


def test_two_streams_of_one_name_the_usable_one_is_followed_and_said():
    """An unlabelled twin and a labelled stream of one name: the labelled one is followed, a line names both."""
    rec = short_walk(0.5)
    frames = pelvis_frames(rec)
    name = unique("twins")
    good = pylsl.StreamOutlet(marker_info(pylsl, name, pelvis_labels(), source_id=f"{name}-good"))
    time.sleep(0.2)
    twin = pylsl.StreamOutlet(marker_info(pylsl, name, [None] * 12, source_id=f"{name}-unlabelled"))  # newer
    notes: list[str] = []
    live = LiveThread(name, resolve_timeout_s=10, max_buffer_s=10, on_note=notes.append)
    assert good.wait_for_consumers(15)
    base = pylsl.local_clock()
    for k in range(rec.n_frames):
        good.push_sample(frames[k].tolist(), base + rec.time_s[k])
    live.wait_for(rec.n_frames)
    live.settle(0.3)
    counters = live.stop()
    del twin
    assert counters.estimates == rec.n_frames
    assert len(notes) == 1 and f"2 streams named {name!r}" in notes[0] and f"{name}-good" in notes[0]


@pytest.mark.parametrize("change", ["shifted", "more channels"])
def test_a_source_back_with_other_channels_is_reconnected_and_read_with_its_new_layout(change):
    """The source comes back (same source id) with its channels in another order, or with another channel count:
    live reconnects, says the layout changed, and reads the points where they now are."""
    rec = short_walk(1.0)
    frames = pelvis_frames(rec)
    name = unique("relabel")
    half = rec.n_frames // 2
    outlet = pylsl.StreamOutlet(marker_info(pylsl, name, pelvis_labels(), source_id=name))
    notes: list[str] = []
    live = LiveThread(name, resolve_timeout_s=10, reacquire_after_s=0.5, max_buffer_s=10, on_note=notes.append)
    assert outlet.wait_for_consumers(10)
    base = pylsl.local_clock()
    for k in range(half):
        outlet.push_sample(frames[k].tolist(), base + rec.time_s[k])
    live.wait_for(half)
    del outlet
    gc.collect()
    order = list(reversed(PELVIS)) if change == "shifted" else list(PELVIS) + ["RWRI"]
    new_frames = rec.points(order).reshape(rec.n_frames, -1)
    outlet = pylsl.StreamOutlet(marker_info(pylsl, name, pelvis_labels(order), source_id=name))
    assert outlet.wait_for_consumers(15), "live did not reconnect"
    base2 = pylsl.local_clock()
    for k in range(rec.n_frames):
        outlet.push_sample(new_frames[k].tolist(), base2 + rec.time_s[k])
    live.wait_for(half + rec.n_frames)
    live.settle(0.3)
    counters = live.stop()
    assert counters.reconnects == 1 and counters.restarts == 1
    assert any("came back with another layout" in n for n in notes), notes
    if change == "more channels":
        assert any("(15 channels, was 12)" in n for n in notes), notes
    got = np.array(live.rows)
    assert len(got) == half + rec.n_frames
    # the points read where they now are (the centre's sum in another order: equal to rounding)
    np.testing.assert_allclose(got[half:], reference_rows(base2 + rec.time_s, frames), rtol=1e-9, atol=1e-9)


def _read_terminal_until(fd: int, needle: str | None, within_s: float) -> str:
    """What the terminal's other end received, until `needle` was seen (or the end, for None)."""
    got, deadline = b"", time.monotonic() + within_s
    while time.monotonic() < deadline and (needle is None or needle.encode() not in got):
        ready, _, _ = select.select([fd], [], [], 0.1)
        if ready:
            try:
                chunk = os.read(fd, 4096)
            except OSError:  # the other end closed
                break
            if not chunk:
                break
            got += chunk
    return got.decode(errors="replace")


def test_sigint_while_waiting_for_the_source_stops_live_at_once_with_130_and_the_summary(tmp_path):
    """Ctrl-C while live waits (--timeout 60) for a source that never comes: exit 130 at once, the
    summary line, no record left behind, nothing else on stderr."""
    record = tmp_path / "est.csv"
    env = dict(os.environ)
    # stderr on a terminal, where live says that it is looking for the source: SIGINT is sent then, not
    # after a guessed time (the imports alone can take seconds on a loaded machine)
    master, terminal = pty.openpty()
    proc = subprocess.Popen(
        [sys.executable, "-m", "yoyogait", "live", "--source", unique("never"), "--timeout", "60", "--record", record],
        env=env,
        stderr=terminal,
    )
    os.close(terminal)
    try:
        seen = _read_terminal_until(master, "live: looking for the LSL stream", within_s=60)
        time.sleep(0.3)
        sent = time.monotonic()
        proc.send_signal(signal.SIGINT)
        code = proc.wait(10)
        took_s = time.monotonic() - sent
        seen += _read_terminal_until(master, None, within_s=2)
    finally:
        if proc.poll() is None:
            proc.kill()
        os.close(master)
    err = "\n".join(line for line in seen.replace("\r", "\n").splitlines()[1:] if line.strip())
    assert code == 130, err
    assert took_s < 3.0  # at once, not after the 60 s wait (the bound leaves room for a loaded machine)
    assert err.splitlines()[0].startswith("live: 0 frames, 0 estimates") and "interrupted (SIGINT)" in err, err
    assert "warning" not in err.lower() and "Traceback" not in err
    assert not record.exists() and not list(tmp_path.iterdir())


def test_the_start_up_line_names_every_output(tmp_path, capsys):
    """live's first line names the LSL estimate stream and the record file it writes."""
    name = unique("outputs")
    outlet = pylsl.StreamOutlet(marker_info(pylsl, name, pelvis_labels()))
    record = tmp_path / "est.csv"
    publish = unique("estimates")
    args = ["live", "--source", name, "--publish", publish, "--record", str(record), "--duration", "0.5"]
    assert main(args) == 0
    first = capsys.readouterr().err.splitlines()[0]
    del outlet
    assert f"publishing LSL {publish!r}" in first and f"recording {record}" in first


def test_run_live_stop_set_while_waiting_returns_at_once():
    """stop set while run_live waits for a source returns within 0.3 s with nothing connected."""
    import threading

    stop = threading.Event()
    threading.Timer(0.3, stop.set).start()
    started = time.monotonic()
    counters = run_live(unique("absent"), resolve_timeout_s=30, stop=stop)
    assert time.monotonic() - started < 0.9 and not counters.connected and counters.frames == 0


def test_ctrl_c_while_the_commands_are_imported_is_130_and_one_line(monkeypatch, capsys):
    """A KeyboardInterrupt while main() imports the commands (numpy, scipy, the core: seconds on a loaded
    machine) is exit 130 and the interrupted line, not a traceback."""
    import yoyogait.cli as cli

    def interrupted_import():
        raise KeyboardInterrupt

    monkeypatch.setattr(cli, "_register", interrupted_import)
    assert cli.main(["live", "--source", "x"]) == 130
    err = capsys.readouterr().err
    assert err == "yoyogait: interrupted (SIGINT)\n", err
