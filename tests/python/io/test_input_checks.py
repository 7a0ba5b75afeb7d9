"""Inputs checked before any work: timestamps, time gaps, C3D header numbers, absurd values and rates.

Each bad input is one error line naming the file (and the line where there is one), with nothing
in front of it and no output left behind.
"""

from __future__ import annotations

import re
import struct
import tracemalloc

import numpy as np
import pytest
from test_io_readers import write_bvh

import yoyogait
from builders import write_trc_positions as write_trc
from builders import write_walk_c3d
from yoyogait.cli import main
from yoyogait.errors import InputError
from yoyogait.pipeline.signals import resample


def velocity_csv(path, n=500, rate_hz=100.0, times=None):
    """A velocity CSV of a 1.8 Hz walk at 1.2 m/s; ``times`` replaces the time column."""
    t = np.arange(n) / rate_hz if times is None else np.asarray(times, dtype=float)
    rows = "".join(
        f"{float(ti)!r},{1.2 + 0.1 * np.sin(2 * np.pi * 1.8 * k / rate_hz):.4f},"
        f"{0.1 * np.cos(2 * np.pi * 1.8 * k / rate_hz):.4f}\n"
        for k, ti in enumerate(t)
    )
    path.write_text("time_s,vx,vz\n" + rows)
    return path


def one_error_line(capsys, args) -> str:
    """Run the CLI; assert exit 2 and exactly one stderr line (no warning in front); return it."""
    code = main([str(a) for a in args])
    out, err = capsys.readouterr()
    lines = err.strip().splitlines()
    assert code == 2 and len(lines) == 1 and lines[0].startswith("yoyogait: error: "), err
    return lines[0]


@pytest.mark.parametrize(
    "times, message",
    [
        ([0.0, 0.0, 0.0], r"rep\.csv: line 3: time repeats 0 s \(line 2\)"),
        ([0.0, 0.01, 0.02, 0.015, 0.03], r"rep\.csv: line 5: time goes back from 0\.02 s \(line 4\) to 0\.015 s"),
        ([0.0, 0.01, float("nan")], r"rep\.csv: the time column"),
    ],
)
def test_timestamps_that_repeat_or_go_back_name_the_line(tmp_path, capsys, times, message):
    """A repeated or decreasing timestamp is an error naming the file and the lines (was a ZeroDivisionError)."""
    path = velocity_csv(tmp_path / "rep.csv", n=len(times), times=times)
    assert re.search(message, one_error_line(capsys, ["inspect", path]))
    assert re.search(message, one_error_line(capsys, ["estimate", path, "--out", tmp_path / "o.csv"]))
    assert not (tmp_path / "o.csv").exists()


@pytest.mark.parametrize("bogus", [1e5, 1e6, 1e10])
def test_a_bogus_timestamp_is_refused_without_allocating_across_it(tmp_path, capsys, bogus):
    """A last timestamp of 1e5-1e10 s after 5 s of samples is an error naming its line, found without
    allocating the grid it would span (was 1.8 TiB, or 2.5 M rows of a linearly filled 27 h gap)."""
    times = np.arange(500) / 100.0
    times[-1] = bogus
    path = velocity_csv(tmp_path / "bogus.csv", times=times)
    tracemalloc.start()
    try:
        line = one_error_line(capsys, ["estimate", path, "--out", tmp_path / "o.csv", "--figure", "none"])
        peak = tracemalloc.get_traced_memory()[1]
    finally:
        tracemalloc.stop()
    assert re.search(r"bogus\.csv: line 501: time jumps from 4\.98 s to .* \(a bogus timestamp\?\)", line), line
    assert peak < 50e6
    assert not (tmp_path / "o.csv").exists()


def test_a_gap_in_time_stays_nan_and_is_never_filled(tmp_path, capsys):
    """Rows missing for 1 s (longer than the 0.2 s that is filled) leave NaN at every grid time inside the gap."""
    times = np.arange(1000) / 100.0
    keep = (times < 4.0) | (times >= 5.0)
    path = velocity_csv(tmp_path / "gap.csv", times=times[keep])
    out = tmp_path / "gap_estimate.csv"
    assert main(["estimate", str(path), "--out", str(out), "--figure", "none"]) == 0
    table = np.genfromtxt(out, delimiter=",", names=True)
    inside = (table["time_s"] > 3.99 + 1e-9) & (table["time_s"] < 5.0 - 1e-9)
    assert inside.sum() == 25 and np.all(np.isnan(table["vx_mps"][inside]))
    assert np.all(np.isfinite(table["vx_mps"][~inside]))


def test_resample_leaves_steps_longer_than_the_limit_empty():
    """resample(max_gap_s) gives NaN strictly inside a longer step between timestamps, values elsewhere."""
    t = np.array([0.0, 0.1, 0.2, 1.2, 1.3])
    t_out, v = resample(t, t * 2, 10.0, max_gap_s=0.2)
    inside = (t_out > 0.2 + 1e-9) & (t_out < 1.2 - 1e-9)
    assert np.all(np.isnan(v[inside])) and np.allclose(v[~inside], 2 * t_out[~inside])


def test_inspect_of_a_velocity_csv_reports_speed_and_step_frequency(tmp_path, capsys):
    """inspect of a valid velocity CSV works (was 'zero-size array to reduction operation fmin')."""
    path = velocity_csv(tmp_path / "v.csv", n=1000)
    assert main(["inspect", str(path)]) == 0
    out = capsys.readouterr().out
    assert float(out.split("mean speed")[1].split()[0]) == pytest.approx(1.2, abs=0.02)
    assert float(out.split("step frequency")[1].split()[0]) == pytest.approx(1.8, abs=0.05)
    assert "vz is vertical" in out


def _c3d_with_header(tmp_path, name, offset, fmt, value):
    path = write_walk_c3d(tmp_path / name)
    data = bytearray(path.read_bytes())
    data[offset : offset + struct.calcsize(fmt)] = struct.pack(fmt, value)
    path.write_bytes(bytes(data))
    return path


@pytest.mark.parametrize(
    "offset, fmt, value, message",
    [
        (12, "<f", 0.0, "point scale factor is 0; it must be a non-zero number"),
        (12, "<f", float("nan"), "point scale factor is nan"),
        (12, "<f", float("inf"), "point scale factor is inf"),
        (12, "<f", 0.1, "disagree on whether the data are floats or integers"),
        (16, "<H", 0, "the data start at block 0, but the parameters end at block"),
        (16, "<H", 60000, "the data start at block 60000"),
    ],
)
def test_c3d_header_scale_and_data_start_are_checked(tmp_path, capsys, offset, fmt, value, message):
    """A C3D whose header scale is 0/NaN/inf or of the wrong sign, or whose data start inside the header
    or past the end, is refused (was accepted: speeds of 5-168 m/s, velocities of 1e-12)."""
    path = _c3d_with_header(tmp_path, "hdr.c3d", offset, fmt, value)
    line = one_error_line(capsys, ["inspect", path])
    assert str(path) in line and message in line, line


def test_absurd_coordinates_are_an_error_naming_point_and_line(tmp_path, capsys):
    """1e308 in the pelvis cells of a TRC is an error naming the point and the line (was a speed of 0.00)."""
    from builders import stepping_walk

    rec, _ = stepping_walk()
    pos = np.nan_to_num(rec.positions_m)
    pos[300:310, 0, 0] = 1e308
    path = write_trc(tmp_path / "huge.trc", pos, rec.point_names, units="m")
    line = one_error_line(capsys, ["inspect", path])
    assert re.search(r"huge\.trc: line 307: point 'LASI' has x = 1e\+308 m, more than 10000 m", line), line


def test_a_velocity_faster_than_any_person_is_an_error(tmp_path, capsys):
    """A velocity CSV with vx = 400 m/s on one row is an error naming its line."""
    path = velocity_csv(tmp_path / "fast.csv")
    lines = path.read_text().splitlines()
    lines[100] = "0.99,400,0"
    path.write_text("\n".join(lines) + "\n")
    assert re.search(
        r"fast\.csv: line 101: vx = 400 m/s, faster than any person", one_error_line(capsys, ["inspect", path])
    )


def test_a_point_that_jumps_is_an_error_not_a_speed(tmp_path):
    """A pelvis that jumps 1 km for a few frames gives an error naming the jump, not an absurd speed."""
    from builders import stepping_walk

    rec, _ = stepping_walk()
    rec.positions_m[400:405, :3, 0] += 1000.0
    rec.source = "jump.c3d"
    with pytest.raises(InputError, match=r"jump\.c3d: pelvis .* jumps 1e\+03 m between 3\.990 s and 4\.000 s"):
        yoyogait.gait_velocities(rec)


@pytest.mark.parametrize("frame_time", ["1e-30", "0", "-0.01", "nan", "1e30", "5"])
def test_bvh_frame_time_must_be_positive_and_sane(tmp_path, capsys, frame_time):
    """A BVH frame time that is not positive or gives a rate outside 1-10000 Hz is one error line
    (was 'cannot reshape array of size 50 into shape (1,2)' for 1e-30)."""
    n = 300
    root = np.column_stack([np.arange(n) * 1.0, np.full(n, 95.0), np.zeros(n)])
    path = write_bvh(tmp_path / "ft.bvh", root)
    path.write_text(path.read_text().replace("Frame Time: 0.01", f"Frame Time: {frame_time}"))
    line = one_error_line(capsys, ["inspect", path])
    assert "ft.bvh" in line and ("frame time" in line.lower() or "rate of 'Frame Time" in line), line


def test_bvh_absurd_channel_leaves_no_output(tmp_path, capsys):
    """1e308 in the root channels of a BVH is one error line; estimate leaves neither CSV nor figure."""
    n = 300
    root = np.column_stack([np.arange(n) * 1.0, np.full(n, 95.0), np.zeros(n)])
    root[100:110, 0] = 1e308
    path = write_bvh(tmp_path / "big.bvh", root)
    out, fig = tmp_path / "x.csv", tmp_path / "x.png"
    line = one_error_line(capsys, ["estimate", path, "--out", out, "--figure", fig])
    assert "big.bvh: line" in line and "1e+308" in line
    assert sorted(p.name for p in tmp_path.iterdir()) == ["big.bvh"]


def test_messages_without_a_file_name_get_it(tmp_path, capsys):
    """An error raised deep in the pipeline without the file's name gets it in front (here: one frame)."""
    path = velocity_csv(tmp_path / "one.csv", n=1)
    assert "one.csv" in one_error_line(capsys, ["estimate", path, "--out", tmp_path / "o.csv"])


def test_estimate_writes_both_outputs_or_neither(tmp_path, capsys, monkeypatch):
    """When the figure fails after the CSV is ready, neither the CSV nor a temporary file is left."""
    from yoyogait.cli import estimate_cmd

    def broken(*args, **kwargs):
        raise ValueError("Axis limits cannot be NaN or Inf")

    monkeypatch.setattr(estimate_cmd.plots, "estimate_figure", broken)
    path = velocity_csv(tmp_path / "v.csv", n=1000)
    out, fig = tmp_path / "x.csv", tmp_path / "x.png"
    assert main(["estimate", str(path), "--out", str(out), "--figure", str(fig)]) == 2
    capsys.readouterr()
    assert sorted(p.name for p in tmp_path.iterdir()) == ["v.csv"]
