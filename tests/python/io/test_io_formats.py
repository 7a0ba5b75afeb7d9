"""Readers of vendor exports (Nexus CSV, Motive CSV, QTM TSV, MVNX, OpenSim .mot/.sto, comma TRC): real samples
from ../shared/datasets/formats and small files written here in each program's documented layout."""

from __future__ import annotations

import numpy as np
import pytest

import yoyogait.io as yio
from yoyogait.errors import InputError

# ----------------------------------------------------------------------------- real samples


def test_nexus_csv_sample_reads_the_trajectories_section(formats_dir):
    """The Nexus sample: 51 Subject:Marker points at 100 Hz in mm, gaps NaN, picked by content as a .csv."""
    rec = yio.read(formats_dir / "vicon_nexus_csv" / "pyomeca_markers.csv")
    assert rec.format == "nexus-csv" and rec.rate_hz == 100.0
    assert len(rec.point_names) == 51 and rec.n_frames == 580
    assert "Daphnee:ASISr" in rec.point_names and rec.point_names[0] == "boite:gauche_ext"
    assert rec.metadata["length_unit_m"] == 0.001
    assert rec.point("Daphnee:ASISl")[0] == pytest.approx([0.753439, 0.0759487, 0.187759])
    assert rec.time_s[1] - rec.time_s[0] == pytest.approx(0.01)


def test_comma_trc_sample_is_parsed_and_its_cut_is_reported(formats_dir):
    """The comma-separated TRC sample is parsed (93 rows of 51 markers) and reported cut short of its 652 frames."""
    with pytest.raises(InputError, match="announces 652 frames, the file holds 93"):
        yio.read(formats_dir / "trc_comma" / "pyomeca_markers.trc")


def test_motive_csv_sample_without_assets_says_so(formats_dir):
    """The Motive sample (format 1.23) holds only Frame and Time columns: the error names the format and why."""
    with pytest.raises(InputError, match=r"Motive CSV export \(format 1.23\) with no marker, rigid-body or skeleton"):
        yio.read(formats_dir / "optitrack_motive_csv" / "test_default.csv")


def test_mvnx_sample_places_segments_and_anatomical_points(formats_dir):
    """The MVNX sample: 23 segments plus their points at 60 Hz, Z up; pHipOrigin sits on the Pelvis origin and each
    anatomical point keeps its fixed distance to its segment."""
    rec = yio.read(formats_dir / "xsens_mvnx" / "test_mocap.mvnx")
    assert rec.format == "mvnx" and rec.rate_hz == 60.0 and rec.n_frames == 112 and rec.up_axis == "z"
    assert rec.point_names[:2] == ["Pelvis", "L5"] and {"pLeftASI", "pSacrum", "pLeftHeelFoot"} <= set(rec.point_names)
    assert np.allclose(rec.point("pHipOrigin"), rec.point("Pelvis"))
    distance = np.linalg.norm(rec.point("pLeftHeelFoot") - rec.point("LeftFoot"), axis=1)
    assert np.ptp(distance) < 1e-5 and distance[0] > 0.05
    assert rec.time_s[-1] == pytest.approx(1.850)


def test_opensim_ik_sample_gives_the_pelvis_and_marker_positions(formats_dir):
    """The OpenSim IK sample: pelvis from pelvis_tx/ty/tz (m, Y up), model markers as points, angles in radians."""
    rec = yio.read(formats_dir / "opensim_mot" / "subject01_walk1_ik.mot")
    assert rec.format == "opensim" and rec.up_axis == "y" and rec.n_frames == 73
    assert rec.point_names[0] == "pelvis" and {"R.ASIS", "L.Heel"} <= set(rec.point_names)
    assert rec.point("pelvis")[0] == pytest.approx([0.60175322, 1.04544757, -0.02167535])
    assert rec.metadata["in_degrees"]
    assert rec.metadata["coordinates_rad"]["pelvis_tilt"][0] == pytest.approx(np.radians(5.18756704))


def test_ground_reaction_mot_is_refused_naming_what_it_holds(datasets_dir):
    """A .mot of ground-reaction forces is refused: the message says forces, no positions, and where they are."""
    with pytest.raises(InputError, match="ground-reaction forces.*no positions.*trc"):
        yio.read(datasets_dir / "addbiomechanics" / "treadmill_HBM_initial_off_treadmill_grf.mot")


# ----------------------------------------------------------------------------- files written here


def _walk(n=200, names=("LASI", "RASI", "LHEE")):
    """Smooth positions in mm, frames x points x 3."""
    t = np.arange(n)[:, None] / 100.0
    base = np.array([[100.0 * k, 50.0 * k, 900.0 - 400.0 * (k == 2)] for k in range(len(names))])
    return base[None] + np.stack([1200.0 * t, 0 * t, 20.0 * np.sin(2 * np.pi * 2 * t)], axis=2)


def _qtm_tsv(path, positions, names, *, frame_time=True, rate=100, zero=None):
    lines = [
        f"NO_OF_FRAMES\t{len(positions)}",
        "NO_OF_CAMERAS\t8",
        f"NO_OF_MARKERS\t{len(names)}",
        f"FREQUENCY\t{rate}",
        "NO_OF_ANALOG\t0",
        "ANALOG_FREQUENCY\t0",
        "DESCRIPTION\t--",
        "TIME_STAMP\t2019-11-28, 13:43:42.715\t1476252.89504471",
        "DATA_INCLUDED\t3D",
        "MARKER_NAMES\t" + "\t".join(names),
        "TRAJECTORY_TYPES\t" + "\t".join(["Measured"] * len(names)),
    ]
    if frame_time:
        lines.append("Frame\tTime\t" + "\t".join(f"{n} {a}" for n in names for a in "XYZ"))
    for f, frame in enumerate(positions):
        values = frame.copy()
        if zero is not None and f in zero:
            values[zero[f]] = 0.0
        cells = [f"{v:.3f}" for v in values.ravel()]
        lines.append("\t".join(([str(f + 1), f"{f / rate:.5f}"] if frame_time else []) + cells))
    path.write_text("\n".join(lines) + "\n")
    return path


@pytest.mark.parametrize("frame_time", [True, False])
def test_qtm_tsv_markers_in_mm_and_zero_is_missing(tmp_path, frame_time):
    """QTM 3D TSV (with or without the Frame/Time row): mm to m, a 0,0,0 marker is missing, rate from FREQUENCY."""
    names = ("LASI", "RASI", "LHEE")
    pos = _walk()
    rec = yio.read(_qtm_tsv(tmp_path / "walk.tsv", pos, names, frame_time=frame_time, zero={5: 1}))
    assert rec.format == "qtm-tsv" and rec.point_names == list(names) and rec.rate_hz == 100
    assert np.allclose(rec.point("LASI"), pos[:, 0] / 1000, atol=1e-6)
    assert np.isnan(rec.point("RASI")[5]).all() and np.isfinite(rec.point("RASI")[6]).all()
    assert rec.time_s[10] == pytest.approx(0.1)


def test_qtm_6dof_and_truncated_tsv_are_refused(tmp_path):
    """A 6DOF TSV is refused as such; a TSV shorter than NO_OF_FRAMES is truncated."""
    six = tmp_path / "bodies.tsv"
    six.write_text("NO_OF_FRAMES\t2\nFREQUENCY\t100\nDATA_INCLUDED\t6D\nBODY_NAMES\tRB1\n1\t0\t1\t2\t3\n")
    with pytest.raises(InputError, match="6DOF"):
        yio.read(six)
    path = _qtm_tsv(tmp_path / "cut.tsv", _walk(), ("LASI", "RASI", "LHEE"))
    path.write_text(path.read_text().replace("NO_OF_FRAMES\t200", "NO_OF_FRAMES\t300"))
    with pytest.raises(InputError, match="truncated QTM TSV"):
        yio.read(path)


def _motive_csv(path, *, unit="Millimeters", positions=True):
    """Motive 1.23 export: a rigid body (rotation + position), a skeleton bone and a marker."""
    types = ["Rigid Body"] * 7 + ["Bone"] * 3 + ["Marker"] * 3
    names = ["RB1"] * 7 + ["Skeleton:Hip"] * 3 + ["Skeleton:LHeel"] * 3
    kinds = ["Rotation"] * 4 + ["Position"] * 3 + ["Position"] * 6
    axes = ["X", "Y", "Z", "W", "X", "Y", "Z"] + ["X", "Y", "Z"] * 2
    if not positions:
        types, names, kinds, axes = types[:4], names[:4], kinds[:4], axes[:4]
    rows = [
        "Format Version,1.23,Take Name,walk,Capture Frame Rate,120.000000,Export Frame Rate,120.000000,"
        f"Rotation Type,Quaternion,Length Units,{unit},Coordinate Space,Global",
        "",
        ",Type," + ",".join(types),
        ",Name," + ",".join(names),
        ",ID," + ",".join(["1"] * len(types)),
        ",," + ",".join(kinds),
        "Frame,Time (Seconds)," + ",".join(axes),
    ]
    for f in range(240):
        t = f / 120
        values = [0, 0, 0, 1, 1000 * t, 900, 0, 1000 * t + 5, 950, 10, 1000 * t - 50, 60, 20]
        if f == 3:
            values[-3:] = ["", "", ""]  # the marker unseen
        rows.append(f"{f},{t:.6f}," + ",".join(str(v) for v in values[: len(axes)]))
    path.write_text("\n".join(rows) + "\n")
    return path


def test_motive_csv_positions_of_rigid_bodies_bones_and_markers(tmp_path):
    """Motive CSV: every asset with Position columns is a point (rotations left out), Length Units applied,
    an empty cell missing; the reader is chosen by content for a .csv."""
    rec = yio.read(_motive_csv(tmp_path / "take.csv"))
    assert rec.format == "motive-csv" and rec.rate_hz == 120
    assert rec.point_names == ["RB1", "Skeleton:Hip", "Skeleton:LHeel"]
    assert rec.point("RB1")[120] == pytest.approx([1.0, 0.9, 0.0])
    assert np.isnan(rec.point("Skeleton:LHeel")[3]).all()
    assert rec.metadata["point_types"]["Skeleton:Hip"] == "Bone"


def test_motive_rotation_only_export_is_named(tmp_path):
    """A Motive export of rotations only is refused with a message that says so."""
    with pytest.raises(InputError, match="Motive CSV export .* rotations only"):
        yio.read(_motive_csv(tmp_path / "rot.csv", positions=False))


def test_nexus_csv_without_trajectories_is_named(tmp_path):
    """A Nexus CSV with only Model Outputs is refused naming the sections it holds and what to export instead."""
    path = tmp_path / "angles.csv"
    path.write_text(
        "Model Outputs,,,,\n100,,,,\n,,Sub:LHipAngles,,\nFrame,Sub Frame,X,Y,Z\n,,deg,deg,deg\n1,0,1,2,3\n\n"
    )
    with pytest.raises(InputError, match="Vicon Nexus CSV export with Model Outputs but no Trajectories"):
        yio.read(path)


def test_nexus_csv_with_devices_first_and_short_rows(tmp_path):
    """Nexus CSV: a Devices section before Trajectories is skipped; rows cut short of trailing gaps are padded."""
    path = tmp_path / "trial.csv"
    path.write_text(
        "Devices,,,,,\n1000,,,,,\n,,Force Plate,,,\nFrame,Sub Frame,Fx,Fy,Fz\n,,N,N,N\n1,0,1,2,3\n\n"
        "Trajectories,,,,,,,,\n100,,,,,,,,\n,,S:LASI,,,S:RASI,,,\nFrame,Sub Frame,X,Y,Z,X,Y,Z\n,,mm,mm,mm,mm,mm,mm\n"
        "1,0,100,200,900,400,500,900\n2,0,101,200,900\n"
    )
    rec = yio.read(path)
    assert rec.point_names == ["S:LASI", "S:RASI"] and rec.n_frames == 2
    assert rec.point("S:RASI")[0] == pytest.approx([0.4, 0.5, 0.9]) and np.isnan(rec.point("S:RASI")[1]).all()


def test_comma_and_tab_trc_read_the_same(tmp_path):
    """A TRC written with commas reads exactly as the same TRC with tabs."""
    pos = _walk(50)
    header = [
        "PathFileType\t4\t(X/Y/Z)\tw.trc",
        "DataRate\tCameraRate\tNumFrames\tNumMarkers\tUnits",
        "100\t100\t50\t3\tmm",
    ]
    header += ["Frame#\tTime\tLASI\t\t\tRASI\t\t\tLHEE\t\t", "\t\t" + "\t".join(f"X{i}\tY{i}\tZ{i}" for i in (1, 2, 3))]
    body = ["\t".join([str(f + 1), f"{f / 100:.2f}"] + [f"{v:.4f}" for v in pos[f].ravel()]) for f in range(50)]
    tab = tmp_path / "tab.trc"
    tab.write_text("\n".join(header + [""] + body) + "\n")
    comma = tmp_path / "comma.trc"
    comma.write_text("\n".join(line.replace("\t", ",") for line in header + [",,,,,"] + body) + "\n")
    a, b = yio.read(tab), yio.read(comma)
    assert a.point_names == b.point_names == ["LASI", "RASI", "LHEE"]
    assert np.array_equal(a.positions_m, b.positions_m) and np.array_equal(a.time_s, b.time_s)
    assert b.metadata["separator"] == ","


@pytest.mark.parametrize("degrees", ["yes", "no"])
def test_opensim_sto_state_paths_and_in_degrees_flag(tmp_path, degrees):
    """An OpenSim 4 .sto with state-path columns: pelvis from /jointset/.../pelvis_tx/value; inDegrees respected."""
    cols = ["time"] + [f"/jointset/ground_pelvis/pelvis_{c}/value" for c in ("tilt", "tx", "ty", "tz")]
    lines = ["states", "version=1", "nRows=3", "nColumns=5", f"inDegrees={degrees}", "endheader", "\t".join(cols)]
    lines += [f"{i / 100}\t10\t{i * 0.012}\t0.95\t0.0" for i in range(3)]
    path = tmp_path / "states.sto"
    path.write_text("\n".join(lines) + "\n")
    rec = yio.read(path)
    assert rec.point_names == ["pelvis"] and rec.point("pelvis")[2] == pytest.approx([0.024, 0.95, 0.0])
    expected = np.radians(10) if degrees == "yes" else 10.0
    assert rec.metadata["coordinates_rad"]["pelvis_tilt"][0] == pytest.approx(expected)


def test_mvnx_without_frames_and_foreign_xml_are_refused(tmp_path):
    """An MVNX with only calibration poses, and an XML that is not MVNX, are refused saying why."""
    ns = 'xmlns="http://www.xsens.com/mvn/mvnx"'
    only_tpose = tmp_path / "tpose.mvnx"
    only_tpose.write_text(
        f'<mvnx {ns} version="4"><subject frameRate="60"><segments><segment label="Pelvis" id="1"/></segments>'
        '<frames><frame time="0" type="tpose"><position>0 0 1</position><orientation>1 0 0 0</orientation>'
        "</frame></frames></subject></mvnx>"
    )
    with pytest.raises(InputError, match="no recorded frames"):
        yio.read(only_tpose)
    other = tmp_path / "other.mvnx"
    other.write_text("<svg/>")
    with pytest.raises(InputError, match="not an MVNX export"):
        yio.read(other)
