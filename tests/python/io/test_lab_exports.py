"""Vicon Nexus CSV in the shapes Nexus writes it, the tab-separated marker tables of the Fukuchi et al. data sets,
and DeepMimic motion clips: files written here in each documented layout."""

from __future__ import annotations

import json

import numpy as np
import pytest

import yoyogait.io as yio
from builders import stepping_walk
from yoyogait.errors import InputError

MARKERS = ("LASI", "RASI", "SACR", "LHEE", "RHEE")


def _walk_mm():
    """A stepping walk (z up) in mm, frames x 5 x 3, and its contact times."""
    rec, contacts = stepping_walk(stand_before_s=0.5, walk_s=4.0, stand_after_s=0.5)
    return rec.positions_m * 1000.0, contacts


def _trajectories(pos, names, *, subject="S08", magnitude=False, units=True, rate=100, extra_subject=None):
    cols = []
    head, axes, unit = ["", ""], ["Frame", "Sub Frame"], ["", ""]
    groups = [(subject, pos)] + ([(extra_subject, pos + 2000.0)] if extra_subject else [])
    for who, p in groups:
        for k, n in enumerate(names):
            head += [f"{who}:{n}", "", ""]
            axes += ["X", "Y", "Z"]
            unit += ["mm"] * 3
            cols.append(p[:, k, :])
            if magnitude:
                head += [f"| {who}:{n} |"]
                axes += ["Magnitude"]
                unit += ["mm"]
                cols.append(np.linalg.norm(p[:, k, :], axis=1)[:, None])
    lines = ["Trajectories" + "," * (len(head) - 1), str(rate) + "," * (len(head) - 1), ",".join(head), ",".join(axes)]
    if units:
        lines.append(",".join(unit))
    table = np.hstack(cols)
    for f, row in enumerate(table):
        lines.append(f"{f + 1},0," + ",".join(f"{v:.3f}" for v in row))
    return lines + [""]


def _events(contacts, subject="S08"):
    lines = ["Events", "Subject,Context,Name,Time (s),Description"]
    for k, t in enumerate(contacts):
        side = "Left" if k % 2 == 0 else "Right"
        lines.append(f"{subject},{side},Foot Strike,{t + 0.01:.3f},The instant the heel strikes the ground")
    return lines + [""]


def _gait_cycle(subject="S08"):
    return [
        "Gait Cycle Parameters",
        "Subject,Context,Name,Value,Units",
        f"{subject},Left,Cadence,108.0,steps/min",
        f"{subject},Right,Walking Speed,1.2,m/s",
        "",
    ]


def _devices():
    return ["Devices", "1000", ",,Force Plate 1,,", "Frame,Sub Frame,Fx,Fy,Fz", ",,N,N,N", "1,0,1,2,3", "1,1,1,2,3", ""]


@pytest.mark.parametrize(
    "lead",
    [[], ["", ""], [",,,,,", ",,,,,"]],
    ids=["no lead", "two empty lines", "two comma-only lines"],
)
@pytest.mark.parametrize(
    "order",
    [("traj",), ("events", "gcp", "devices", "traj"), ("devices", "traj", "events"), ("gcp", "traj", "devices")],
    ids=["trajectories only", "events first", "events last", "parameters first"],
)
def test_nexus_csv_sections_in_any_order_after_blank_lines(tmp_path, lead, order):
    """Every section order, after blank or comma-only lines: the same markers, in metres, at the file's rate."""
    pos, contacts = _walk_mm()
    parts = {"traj": _trajectories(pos, MARKERS), "events": _events(contacts), "gcp": _gait_cycle()}
    parts["devices"] = _devices()
    path = tmp_path / "trial.csv"
    path.write_text("\n".join(lead + [line for name in order for line in parts[name]]))
    rec = yio.read(path)
    assert rec.format == "nexus-csv" and rec.rate_hz == 100.0 and rec.n_frames == len(pos)
    assert rec.point_names == [f"S08:{n}" for n in MARKERS]
    assert rec.point("S08:LASI")[10] == pytest.approx(pos[10, 0] / 1000.0, abs=1e-6)
    if "events" in order:
        strikes = [t for _, name, t in rec.metadata["events"] if name == "foot strike"]
        assert strikes == pytest.approx(contacts + 0.01, abs=1e-3)
    if "gcp" in order:
        assert ("left", "Cadence", 108.0, "steps/min") in rec.metadata["gait_cycle_parameters"]


def test_nexus_csv_magnitude_columns_are_left_out(tmp_path):
    """'| name |' magnitude columns after each marker are left out (and listed), the positions read."""
    pos, _ = _walk_mm()
    path = tmp_path / "mag.csv"
    path.write_text("\n".join(_trajectories(pos, MARKERS, magnitude=True)))
    rec = yio.read(path)
    assert rec.point_names == [f"S08:{n}" for n in MARKERS]
    assert rec.metadata["columns_left_out"] == [f"| S08:{n} |" for n in MARKERS]
    assert rec.point("S08:RHEE")[50] == pytest.approx(pos[50, 4] / 1000.0, abs=1e-6)


def test_nexus_csv_several_subjects_reads_one(tmp_path):
    """Two subjects: the first is read unless subject= names the other; both are listed; a wrong name is refused."""
    pos, _ = _walk_mm()
    path = tmp_path / "two.csv"
    path.write_text("\n".join(_trajectories(pos, MARKERS, subject="Anna", extra_subject="Ben")))
    rec = yio.read(path)
    assert rec.metadata["subjects"] == ["Anna", "Ben"] and rec.metadata["subject"] == "Anna"
    assert rec.point_names == [f"Anna:{n}" for n in MARKERS]
    ben = yio.read(path, subject="Ben")
    assert ben.point("Ben:LASI")[0] == pytest.approx(pos[0, 0] / 1000.0 + 2.0, abs=1e-6)
    with pytest.raises(InputError, match="no subject 'Cleo' .* subjects: Anna, Ben"):
        yio.read(path, subject="Cleo")


def test_nexus_csv_units_are_those_of_the_trajectories_section(tmp_path):
    """The Trajectories units line decides (m here), whatever the units of the sections before it."""
    pos, _ = _walk_mm()
    lines = _trajectories(pos / 1000.0, MARKERS)
    lines[4] = lines[4].replace("mm", "m")
    path = tmp_path / "metres.csv"
    path.write_text("\n".join(_devices() + lines))
    rec = yio.read(path)
    assert rec.metadata["length_unit_m"] == 1.0
    assert rec.point("S08:SACR")[5] == pytest.approx(pos[5, 2] / 1000.0, abs=1e-6)


def test_nexus_csv_events_only_is_refused_naming_its_sections(tmp_path):
    """A Nexus export of events and parameters only is refused in one line naming what it holds."""
    path = tmp_path / "events.csv"
    path.write_text("\n".join(["", ""] + _events([1.0, 1.5]) + _gait_cycle()))
    with pytest.raises(InputError, match="Nexus CSV export with Events, Gait Cycle Parameters but no Trajectories"):
        yio.read(path)


# ----------------------------------------------------------------------------- marker tables (Fukuchi et al.)


def _marker_table(path, pos, names, *, time_s=True, rate=100.0):
    """Tab-separated: Time, then NameX NameY NameZ per marker (y up, as the data sets' laboratory)."""
    header = ["Time"] + [f"{n}{a}" for n in names for a in "XYZ"]
    lines = ["\t".join(header)]
    for f, frame in enumerate(pos):
        yup = frame[:, [0, 2, 1]]  # x forward, y up, z lateral
        t = f"{f / rate:.4f}" if time_s else str(f + 1)
        lines.append(t + "\t" + "\t".join("NaN" if not np.isfinite(v) else f"{v:.3f}" for v in yup.ravel()))
    path.write_text("\n".join(lines) + "\n")
    return path


def test_marker_table_reads_time_markers_and_declares_y_up(tmp_path):
    """Fukuchi-style table: names without the X/Y/Z suffix, mm to m, rate from Time, gaps NaN, y up."""
    pos, _ = _walk_mm()
    names = ("R.ASIS", "L.ASIS", "R.PSIS", "L.Heel", "R.Heel")
    pos[20, 1] = np.nan
    rec = yio.read(_marker_table(tmp_path / "WBDS01walkT01mkr.txt", pos, names))
    assert rec.format == "marker-table" and rec.point_names == list(names)
    assert rec.rate_hz == pytest.approx(100.0) and rec.n_frames == len(pos)
    assert rec.point("R.ASIS")[7] == pytest.approx(pos[7, 0, [0, 2, 1]] / 1000.0, abs=1e-6)
    assert np.isnan(rec.point("L.ASIS")[20]).all()
    assert rec.up_axis == "y" and "laboratory frame" in rec.metadata["up_axis_from"]


def test_marker_table_counting_frames_needs_the_rate(tmp_path):
    """A Time column that counts frames is refused naming --capture-rate-hz, and read with it."""
    pos, _ = _walk_mm()
    path = _marker_table(tmp_path / "frames.txt", pos, ("R.ASIS", "L.ASIS", "R.PSIS", "L.Heel", "R.Heel"), time_s=False)
    with pytest.raises(InputError, match="counts frames .* pass --capture-rate-hz"):
        yio.read(path)
    assert yio.read(path, capture_rate_hz=100.0).duration_s == pytest.approx((len(pos) - 1) / 100.0)


def test_marker_table_with_commas_metres_and_force_columns(tmp_path):
    """Commas, '_X' suffixes, metres (told by the body's size) and force-plate columns beside the markers
    (left out and listed) read like the Fukuchi layout."""
    pos, _ = _walk_mm()
    names = ("R.ASIS", "L.ASIS", "R.PSIS", "L.Heel", "R.Heel")
    header = ["Time"] + [f"{n}_{a}" for n in names for a in "XYZ"] + ["Fx", "Fy", "Fz", "COPx", "COPy", "COPz", "My"]
    lines = [",".join(header)]
    for f, frame in enumerate(pos / 1000.0):
        values = ",".join(f"{v:.5f}" for v in frame[:, [0, 2, 1]].ravel())
        lines.append(f"{f / 100:.2f},{values},0,0,0,300,0,-203,0")
    path = tmp_path / "postureData.txt"
    path.write_text("\n".join(lines) + "\n")
    rec = yio.read(path)
    assert rec.point_names == list(names) and rec.metadata["length_unit_m"] == 1.0
    assert rec.metadata["columns_left_out"] == ["F", "COP", "My"]
    assert rec.point("L.Heel")[40] == pytest.approx(pos[40, 3, [0, 2, 1]] / 1000.0, abs=1e-5)


def test_other_text_files_are_not_taken(tmp_path):
    """A .txt that is neither a marker table nor a clip (a licence, a readme) is refused in one line naming both."""
    path = tmp_path / "LICENSE.txt"
    path.write_text("Permission is hereby granted, free of charge, to any person\n")
    with pytest.raises(InputError, match="neither a marker table .* nor a DeepMimic motion clip"):
        yio.read(path)
    other = tmp_path / "manifest.json"
    other.write_text(json.dumps({"recordings": []}))
    with pytest.raises(InputError, match="JSON that is not a DeepMimic motion clip"):
        yio.read(other)


# ----------------------------------------------------------------------------- DeepMimic clips


def _clip(path, *, loop="none", seconds=4.0, rate=30.0, speed=1.0, step_hz=1.8):
    n = int(seconds * rate) + 1
    t = np.arange(n) / rate
    frames = []
    for k, tk in enumerate(t):
        root = [speed * tk, 0.85 + 0.02 * np.cos(2 * np.pi * step_hz * tk), 0.01 * np.sin(np.pi * step_hz * tk)]
        frames.append([0.0 if k == n - 1 else 1.0 / rate, *root, 1.0, 0.0, 0.0, 0.0, 0.5, 0.5, 0.5, 0.5])
    path.write_text(json.dumps({"Loop": loop, "Frames": frames}))
    return path


def test_deepmimic_clip_is_the_root_in_metres_timed_by_durations(tmp_path):
    """A clip reads as one 'root' point in metres, timed by the frame durations, y up (the convention)."""
    rec = yio.read(_clip(tmp_path / "walk.json"))
    assert rec.format == "deepmimic" and rec.point_names == ["root"]
    assert rec.rate_hz == pytest.approx(30.0) and rec.duration_s == pytest.approx(4.0)
    assert rec.point("root")[30] == pytest.approx([1.0, 0.85 + 0.02 * np.cos(2 * np.pi * 1.8), 0.0], abs=0.011)
    assert rec.up_axis == "y"


def test_deepmimic_wrapping_clip_is_played_on(tmp_path):
    """A 1.2 s wrapping clip is repeated to 10 s, each cycle starting where the root left the last one."""
    rec = yio.read(_clip(tmp_path / "cycle.txt", loop="wrap", seconds=1.2))
    assert rec.metadata["looped_cycles"] == 9 and rec.duration_s == pytest.approx(10.8, abs=1e-6)
    x = rec.point("root")[:, 0]
    assert np.all(np.diff(x) > 0) and x[-1] == pytest.approx(10.8, abs=1e-6)


def test_deepmimic_bad_frame_is_named(tmp_path):
    """A frame without a duration and a root position is refused naming the frame."""
    path = tmp_path / "bad.json"
    path.write_text(json.dumps({"Loop": "none", "Frames": [[0.03, 0, 0.8, 0], ["x"]]}))
    with pytest.raises(InputError, match="DeepMimic frame 2 must start with a duration"):
        yio.read(path)


def test_qtm_angle_export_is_refused_saying_what_it_holds(tmp_path):
    """A QTM TSV of computed angles (DATA_INCLUDED Angle) is refused in one line naming the data it holds."""
    path = tmp_path / "left_q1.tsv"
    lines = ["NO_OF_FRAMES\t3", "NO_OF_DATA_TYPES\t1", "FREQUENCY\t100", "TIME_STAMP\t2026-01-20, 10:25:12"]
    lines += ["DATA_INCLUDED\tAngle", "DATA_TYPES\tleft_q1_XY", "", "Frame\tTime\tleft_q1_XY\t"]
    lines += [f"{k + 1}\t{k / 100:.5f}\t79.30{k}" for k in range(3)]
    path.write_text("\n".join(lines) + "\n")
    with pytest.raises(InputError, match=r"QTM TSV export of Angle data \(DATA_INCLUDED Angle\), no marker positions"):
        yio.read(path)
