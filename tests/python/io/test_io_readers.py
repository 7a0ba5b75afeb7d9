"""The readers: what each format's conventions become in a Recording, and bad files."""

from __future__ import annotations

import numpy as np
import pytest

import yoyogait.io as yio
from builders import write_trc_positions as write_trc
from yoyogait.errors import InputError
from yoyogait.io.bvh import CANDIDATE_UNITS_M

ezc3d = pytest.importorskip("ezc3d")


# ----------------------------------------------------------------------------- writers


def write_c3d(path, positions_mm, names, *, rate_hz=100.0, units="mm", residuals=None, extra=None):
    """A C3D file through ezc3d's own writer (positions frames x points x 3)."""
    c = ezc3d.c3d()
    n_frames, n_points, _ = positions_mm.shape
    data = np.ones((4, n_points, n_frames))
    data[:3] = np.transpose(positions_mm, (2, 1, 0))
    c["parameters"]["POINT"]["RATE"]["value"] = [rate_hz]
    c["parameters"]["POINT"]["LABELS"]["value"] = list(names)
    if units is not None:
        c.add_parameter("POINT", "UNITS", [units])
    for key, value in (extra or {}).items():
        c.add_parameter("POINT", key, value)
    c["data"]["points"] = data
    if residuals is not None:
        c["data"]["meta_points"] = {
            "residuals": residuals.T[None, :, :].astype(float),
            "camera_masks": np.zeros((7, n_points, n_frames), dtype=bool),
        }
    c.write(str(path))
    return path


BVH_TWO_JOINTS = """HIERARCHY
ROOT Hips
{{
  OFFSET 0 0 0
  CHANNELS 6 Xposition Yposition Zposition {root_order}
  JOINT Chest
  {{
    OFFSET 0 {chest} 0
    CHANNELS 3 {chest_order}
    End Site
    {{
      OFFSET 0 {head} 0
    }}
  }}
  JOINT LeftFoot
  {{
    OFFSET 0 {foot} 0
    CHANNELS 3 Zrotation Xrotation Yrotation
  }}
}}
MOTION
Frames: {frames}
Frame Time: {frame_time}
{motion}
"""


def write_bvh(
    path,
    root_xyz,
    *,
    root_order="Zrotation Xrotation Yrotation",
    root_angles=None,
    chest_order="Zrotation Yrotation Xrotation",
    chest_angles=None,
    unit=0.01,
    frame_time=0.01,
):
    """A three-joint BVH (Hips, Chest with an End Site, LeftFoot) in file units of ``unit`` m."""
    n = len(root_xyz)
    root_angles = np.zeros((n, 3)) if root_angles is None else root_angles
    chest_angles = np.zeros((n, 3)) if chest_angles is None else chest_angles
    rows = [" ".join(f"{v:.9f}" for v in (*root_xyz[i], *root_angles[i], *chest_angles[i], 0, 0, 0)) for i in range(n)]
    text = BVH_TWO_JOINTS.format(
        root_order=root_order,
        chest_order=chest_order,
        chest=0.5 / unit,
        head=0.3 / unit,
        foot=-0.9 / unit,
        frames=n,
        frame_time=frame_time,
        motion="\n".join(rows),
    )
    path.write_text(text)
    return path


# ----------------------------------------------------------------------------- C3D


def test_c3d_units_zero_and_negative_residual_become_missing(tmp_path):
    """C3D: mm become metres; an exact-zero point and a negative residual are NaN, not zero."""
    n = 40
    pos = np.zeros((n, 2, 3))
    pos[:, 0] = [100.0, 200.0, 950.0]
    pos[:, 1] = [-50.0, 20.0, 80.0]
    pos[5, 0] = 0.0  # the occluded-marker convention of several systems
    residuals = np.zeros((n, 2))
    residuals[9, 1] = -1.0  # the C3D convention for an invalid sample
    rec = yio.read(write_c3d(tmp_path / "a.c3d", pos, ["LASI", "LHEE"], residuals=residuals))
    assert rec.positions_m.shape == (n, 2, 3)
    assert np.allclose(rec.point("LASI")[0], [0.1, 0.2, 0.95])
    assert np.all(np.isnan(rec.point("LASI")[5]))
    assert np.all(np.isnan(rec.point("LHEE")[9]))
    assert np.isfinite(rec.positions_m).sum() == (n * 2 - 2) * 3
    assert rec.rate_hz == 100.0 and rec.time_s[1] == pytest.approx(0.01)


@pytest.mark.parametrize("units, scale", [("m", 1.0), ("cm", 0.01), ("mm", 0.001)])
def test_c3d_length_unit_comes_from_point_units(tmp_path, units, scale):
    """C3D: POINT:UNITS sets the scale to metres."""
    pos = np.full((10, 1, 3), 2.0)
    rec = yio.read(write_c3d(tmp_path / "u.c3d", pos, ["P"], units=units))
    assert np.allclose(rec.positions_m, 2.0 * scale)


def test_c3d_without_units_assumes_mm_and_says_so(tmp_path):
    """C3D without POINT:UNITS: mm (the format's default), and the metadata says it was assumed."""
    rec = yio.read(write_c3d(tmp_path / "n.c3d", np.full((10, 1, 3), 900.0), ["P"], units=None))
    assert np.allclose(rec.positions_m, 0.9)
    assert "assumed" in rec.metadata["length_unit_from"]


def test_c3d_length_unit_override_wins(tmp_path):
    """length_unit_m= replaces what POINT:UNITS says."""
    rec = yio.read(write_c3d(tmp_path / "o.c3d", np.full((10, 1, 3), 3.0), ["P"], units="mm"), length_unit_m=0.5)
    assert np.allclose(rec.positions_m, 1.5)


def test_c3d_up_axis_from_y_screen_and_model_outputs_left_out(tmp_path):
    """C3D: Y_SCREEN '+Z' gives up axis z; angles stored as points are not positions and are dropped."""
    pos = np.ones((10, 3, 3))
    rec = yio.read(
        write_c3d(
            tmp_path / "m.c3d",
            pos,
            ["LASI", "LHipAngles", "PELO"],
            extra={"Y_SCREEN": ["+Z"], "ANGLES": ["LHipAngles"]},
        )
    )
    assert rec.up_axis == "z"
    assert rec.point_names == ["LASI", "PELO"]
    assert rec.metadata["excluded_points"] == ["LHipAngles"]


def test_c3d_repeated_labels_are_made_unique(tmp_path):
    """C3D: a label used twice (as in some MAC files) stays addressable under a unique name."""
    rec = yio.read(write_c3d(tmp_path / "d.c3d", np.ones((5, 3, 3)), ["RKNE", "RANK", "RKNE"]))
    assert rec.point_names == ["RKNE", "RANK", "RKNE#2"]


def test_c3d_truncated_file_is_an_error(tmp_path):
    """A C3D cut short is reported as truncated, not read as a shorter trial."""
    path = write_c3d(tmp_path / "t.c3d", np.ones((400, 4, 3)), ["A", "B", "C", "D"])
    data = path.read_bytes()
    path.write_bytes(data[: len(data) - 4000])
    with pytest.raises(InputError, match="truncated"):
        yio.read(path)


@pytest.mark.parametrize("content", [b"\x00" * 100, b"not a c3d file at all\n" * 40, bytes(range(256)) * 8])
def test_c3d_corrupt_file_is_an_error(tmp_path, content):
    """Bytes that are not a C3D give an InputError naming the file."""
    path = tmp_path / "bad.c3d"
    path.write_bytes(content)
    with pytest.raises(InputError, match="bad.c3d"):
        yio.read(path)


# ----------------------------------------------------------------------------- TRC


def test_trc_units_from_header_and_empty_cells_missing(tmp_path):
    """TRC: the Units field scales to metres; an empty cell is NaN; no up axis is claimed."""
    pos = np.tile(np.array([[10.0, 950.0, 20.0], [0.0, 0.0, 0.0]]), (20, 1, 1))
    rec = yio.read(write_trc(tmp_path / "a.trc", pos, ["R.ASIS", "R.Heel"], blank={(3, 0)}))
    assert np.allclose(rec.point("R.ASIS")[0], [0.01, 0.95, 0.02])
    assert np.all(np.isnan(rec.point("R.ASIS")[3]))
    assert np.allclose(rec.point("R.Heel"), 0.0)  # a real zero in a TRC is a position, not a gap
    assert rec.up_axis is None
    rec_m = yio.read(write_trc(tmp_path / "b.trc", pos / 1000, ["R.ASIS", "R.Heel"], units="m"))
    assert np.allclose(rec_m.point("R.ASIS")[0], [0.01, 0.95, 0.02])


def test_trc_fewer_rows_than_announced_is_truncated(tmp_path):
    """TRC with fewer frames than NumFrames is reported as truncated."""
    path = write_trc(tmp_path / "t.trc", np.ones((20, 1, 3)), ["A"], frames_announced=40)
    with pytest.raises(InputError, match="truncated"):
        yio.read(path)


def test_trc_cut_mid_line_is_truncated(tmp_path):
    """TRC whose last line stops in the middle of a frame is reported as truncated."""
    path = write_trc(tmp_path / "m.trc", np.ones((20, 2, 3)), ["A", "B"])
    text = path.read_text()
    path.write_text(text[: text.rstrip("\n").rfind("\t")])
    with pytest.raises(InputError, match="truncated"):
        yio.read(path)


def test_trc_text_in_a_number_cell_is_an_error(tmp_path):
    """TRC with a non-number cell names the line and the cell."""
    path = write_trc(tmp_path / "c.trc", np.ones((5, 1, 3)), ["A"])
    path.write_text(path.read_text().replace("1.000000000", "oops", 1))
    with pytest.raises(InputError, match="oops"):
        yio.read(path)


def test_trc_without_header_is_an_error(tmp_path):
    """A file named .trc that is not one says so."""
    path = tmp_path / "x.trc"
    path.write_text("hello\nworld\n")
    with pytest.raises(InputError, match="not a TRC"):
        yio.read(path)


# ----------------------------------------------------------------------------- BVH


def _rot(axis, deg):
    c, s = np.cos(np.radians(deg)), np.sin(np.radians(deg))
    return {
        "X": np.array([[1, 0, 0], [0, c, -s], [0, s, c]]),
        "Y": np.array([[c, 0, s], [0, 1, 0], [-s, 0, c]]),
        "Z": np.array([[c, -s, 0], [s, c, 0], [0, 0, 1]]),
    }[axis]


@pytest.mark.parametrize(
    "order", ["Zrotation Xrotation Yrotation", "Xrotation Yrotation Zrotation", "Yrotation Zrotation Xrotation"]
)
def test_bvh_forward_kinematics_follows_the_channel_order(tmp_path, order):
    """BVH: joint world positions are the parent's rotation (channels in the listed order) times the offset."""
    n = 30
    root = np.column_stack([np.linspace(0, 100, n), np.full(n, 95.0), np.zeros(n)])
    angles = np.column_stack([np.linspace(0, 40, n), np.linspace(10, -20, n), np.linspace(-30, 5, n)])
    chest_angles = np.column_stack([np.full(n, 15.0), np.full(n, -25.0), np.full(n, 35.0)])
    path = write_bvh(
        tmp_path / "fk.bvh",
        root,
        root_order=order,
        root_angles=angles,
        chest_angles=chest_angles,
        chest_order="Xrotation Zrotation Yrotation",
    )
    rec = yio.read(path, length_unit_m=0.01)
    axes = [c[0] for c in order.split()]
    for i in (0, n // 2, n - 1):
        r_root = _rot(axes[0], angles[i, 0]) @ _rot(axes[1], angles[i, 1]) @ _rot(axes[2], angles[i, 2])
        r_chest = r_root @ _rot("X", 15) @ _rot("Z", -25) @ _rot("Y", 35)
        hips = root[i] * 0.01
        chest = hips + r_root @ [0, 0.5, 0]
        head = chest + r_chest @ [0, 0.3, 0]
        assert np.allclose(rec.point("Hips")[i], hips, atol=1e-9)
        assert np.allclose(rec.point("Chest")[i], chest, atol=1e-9)
        assert np.allclose(rec.point("Chest_End")[i], head, atol=1e-9)
    assert rec.point_names == ["Hips", "Chest", "Chest_End", "LeftFoot"]


@pytest.mark.parametrize("unit_name", ["m", "cm", "mm", "inch", "CMU unit (1/0.45 inch)"])
def test_bvh_unit_is_inferred_from_pelvis_height(tmp_path, unit_name):
    """BVH without length_unit_m: the unit that puts the pelvis 0.8-1.1 m above the floor is chosen, and named."""
    unit = CANDIDATE_UNITS_M[unit_name]
    n = 20
    root = np.column_stack([np.linspace(0, 1.0, n), np.full(n, 0.95), np.zeros(n)]) / unit
    rec = yio.read(write_bvh(tmp_path / "u.bvh", root, unit=unit))
    assert rec.metadata["length_unit_m"] == pytest.approx(unit)
    assert unit_name in rec.metadata["length_unit_from"]
    feet_height = rec.point("Hips")[:, 1] - rec.point("LeftFoot")[:, 1]
    assert np.allclose(feet_height, 0.9)


def test_bvh_unit_that_fits_no_person_is_an_error(tmp_path):
    """BVH whose pelvis height fits no usual unit asks for length_unit_m."""
    n = 10
    root = np.column_stack([np.zeros(n), np.full(n, 0.95), np.zeros(n)])
    path = write_bvh(tmp_path / "odd.bvh", root, unit=0.5)  # pelvis 1.8 file units above the feet
    with pytest.raises(InputError, match="length_unit_m"):
        yio.read(path)
    assert yio.read(path, length_unit_m=0.5).metadata["length_unit_from"] == "override"


def test_bvh_truncated_motion_is_an_error(tmp_path):
    """BVH with fewer frames than 'Frames:' or a cut last line is reported as truncated."""
    n = 20
    root = np.column_stack([np.zeros(n), np.full(n, 95.0), np.zeros(n)])
    path = write_bvh(tmp_path / "t.bvh", root)
    lines = path.read_text().splitlines()
    path.write_text("\n".join(lines[:-5]) + "\n")
    with pytest.raises(InputError, match="truncated"):
        yio.read(path)
    path.write_text("\n".join(lines)[:-30])
    with pytest.raises(InputError, match="truncated"):
        yio.read(path)


def test_bvh_broken_hierarchy_is_an_error(tmp_path):
    """BVH with an unknown channel or without MOTION gives one clear error."""
    n = 5
    root = np.column_stack([np.zeros(n), np.full(n, 95.0), np.zeros(n)])
    path = write_bvh(tmp_path / "b.bvh", root)
    text = path.read_text()
    path.write_text(text.replace("Zrotation Xrotation Yrotation\n  JOINT", "Zrotation Xrotation Wrotation\n  JOINT"))
    with pytest.raises(InputError, match="channel"):
        yio.read(path)
    path.write_text(text.split("MOTION")[0])
    with pytest.raises(InputError, match="MOTION"):
        yio.read(path)


# ----------------------------------------------------------------------------- CSV


def test_csv_positions_with_settings_and_gaps(tmp_path):
    """CSV: '# length_unit_m' and '# up_axis' lines apply; <name>_x/_y/_z columns make points; empty cells are NaN."""
    path = tmp_path / "p.csv"
    path.write_text(
        "# length_unit_m: 0.001\n# up_axis: z\n"
        "time_s,LASI_x,LASI_y,LASI_z,R.Heel.X,R.Heel.Y,R.Heel.Z\n"
        "0.0,100,200,950,1,2,3\n"
        "0.1,,,,1,2,3\n"
        "0.2,110,200,nan,1,2,3\n"
    )
    rec = yio.read(path)
    assert rec.point_names == ["LASI", "R.Heel"]
    assert np.allclose(rec.point("LASI")[0], [0.1, 0.2, 0.95])
    assert np.all(np.isnan(rec.point("LASI")[1])) and np.isnan(rec.point("LASI")[2, 2])
    assert rec.up_axis == "z" and np.allclose(rec.time_s, [0, 0.1, 0.2])


@pytest.mark.parametrize("suffix, scale", [("m", 1.0), ("cm", 0.01), ("mm", 0.001), ("MM", 0.001)])
def test_csv_point_columns_naming_their_unit_set_the_length_unit(tmp_path, suffix, scale):
    """CSV: a unit after the axis (pelvis_x_m, _cm, _mm) is the length unit, as yoyogait's own columns name theirs."""
    path = tmp_path / "u.csv"
    path.write_text(f"time_s,pelvis_x_{suffix},pelvis_y_{suffix},pelvis_z_{suffix}\n0.0,100,0,95\n0.01,101,0,95\n")
    rec = yio.read(path)
    assert rec.point_names == ["pelvis"] and np.allclose(rec.point("pelvis")[0], np.array([100, 0, 95]) * scale)
    assert rec.metadata["length_unit_m"] == scale and f"pelvis_x_{suffix}" in rec.metadata["length_unit_from"]


def test_csv_length_unit_override_wins_over_the_columns_unit(tmp_path):
    """CSV: length_unit_m= (--length-unit-m) overrides the unit the columns name."""
    path = tmp_path / "o.csv"
    path.write_text("time_s,A_x_mm,A_y_mm,A_z_mm\n0.0,1,2,3\n0.01,1,2,3\n")
    rec = yio.read(path, length_unit_m=1.0)
    assert np.allclose(rec.point("A")[0], [1, 2, 3]) and rec.metadata["length_unit_from"] == "override"


def test_csv_of_a_ros_pose_topic_reads_its_position_as_a_point_on_the_stamps_clock(tmp_path):
    """CSV as `rostopic echo -p` writes a geometry_msgs/PoseStamped: the position is the point `pose`, the orientation
    (x, y, z with a w) no point, the frame_id text not read, the header stamp (ns) the time in seconds."""
    path = tmp_path / "pose.csv"
    head = "%time,field.header.seq,field.header.stamp,field.header.frame_id," + ",".join(
        [f"field.pose.position.{a}" for a in "xyz"] + [f"field.pose.orientation.{a}" for a in "xyzw"]
    )
    stamps = [1_700_000_000_000_000_000 + k * 10_000_000 for k in range(3)]
    body = "".join(f"{ns + 1},{k},{ns},world,{0.012 * k},0.5,0.95,0,0,0,1\n" for k, ns in enumerate(stamps))
    path.write_text(head + "\n" + body)
    rec = yio.read(path)
    assert rec.point_names == ["pose"]
    np.testing.assert_allclose(rec.point("pose")[2], [0.024, 0.5, 0.95])
    np.testing.assert_allclose(rec.time_s - 1.7e9, [0.0, 0.01, 0.02], atol=1e-6)


def test_csv_with_a_bare_timestamp_in_milliseconds_reads_in_seconds_and_says_so(tmp_path):
    """CSV: a `timestamp` column without a unit is read in the unit its intervals make a capture rate of (ms here)."""
    path = tmp_path / "ms.csv"
    path.write_text("timestamp,A_x,A_y,A_z\n1000,0,0,1\n1010,0.01,0,1\n1020,0.02,0,1\n")
    rec = yio.read(path)
    np.testing.assert_allclose(rec.time_s, [1.0, 1.01, 1.02])
    assert rec.metadata["time_unit"] == "timestamp in ms"


def test_csv_ready_velocities(tmp_path):
    """CSV with time,vx,vz columns holds velocities and no points."""
    path = tmp_path / "v.csv"
    path.write_text("time,vx,vz\n0.0,1.2,0.1\n0.04,1.3,-0.1\n")
    rec = yio.read(path)
    assert rec.point_names == [] and rec.positions_m.shape == (2, 0, 3)
    assert np.allclose(rec.velocities["vx"], [1.2, 1.3]) and np.allclose(rec.velocities["vz"], [0.1, -0.1])


def test_csv_without_time_needs_a_rate(tmp_path):
    """CSV without a time column takes rate_hz=, and says so when it is missing."""
    path = tmp_path / "r.csv"
    path.write_text("P_x,P_y,P_z\n0,0,1\n0,0,1\n0,0,1\n")
    with pytest.raises(InputError, match="rate_hz"):
        yio.read(path)
    assert np.allclose(yio.read(path, capture_rate_hz=50).time_s, [0, 0.02, 0.04])


def test_csv_with_point_names_over_axes_reads_each_point_and_takes_the_index_for_no_time(tmp_path):
    """A header in two rows, point names over x/y/z, under an unnamed row index (pandas' (point, axis)
    columns, as gaitmap's example motion capture): the points as <name>_x ...; the index is no time."""
    path = tmp_path / "pandas.csv"
    path.write_text(",L_FCC,L_FCC,L_FCC,R_FCC,R_FCC,R_FCC\n,x,y,z,x,y,z\n0,1,2,3,4,5,6\n1,1.5,2,3,4.5,5,6\n")
    with pytest.raises(InputError, match="no time column"):
        yio.read(path)
    rec = yio.read(path, capture_rate_hz=100)
    assert rec.point_names == ["L_FCC", "R_FCC"]
    np.testing.assert_allclose(rec.positions_m[1], [[1.5, 2, 3], [4.5, 5, 6]])
    np.testing.assert_allclose(rec.time_s, [0, 0.01])


def test_coordinates_beyond_any_lab_name_the_length_unit_option(tmp_path):
    """Millimetres read as metres (x = 33 km) name the option that sets the unit."""
    path = tmp_path / "mm.csv"
    path.write_text("time,A_x,A_y,A_z\n0,33006.8,10512.2,55.7\n0.01,33006.9,10512.1,55.8\n")
    with pytest.raises(InputError, match="wrong length unit: pass length_unit_m="):
        yio.read(path)


@pytest.mark.parametrize(
    "body, message",
    [
        ("time,A_x,A_y\n0,1,2\n", "lacks"),
        ("time,foo,bar\n0,1,2\n", "no point columns"),
        ("time,A_x,A_y,A_z\n0,1,2,x\n", "not a number"),
        ("time,A_x,A_y,A_z\n0,1,2,3\n0.1,1,2", "truncated"),
        ("time,A_x,A_y,A_z\n", "no data rows"),
        (
            "time_s,A_x_m,A_y_m,A_z_m,B_x_mm,B_y_mm,B_z_mm\n0,1,2,3,4,5,6\n",
            r"different length units: A_x_m \(m\), B_x_mm",
        ),
        (
            "# length_unit_m: 0.001\ntime_s,A_x_m,A_y_m,A_z_m\n0,1,2,3\n",
            r"length_unit_m: 0.001' but the columns are in m",
        ),
    ],
)
def test_csv_bad_layout_is_an_error(tmp_path, body, message):
    """CSV that breaks the documented layout (also point columns in two units, or a '# length_unit_m' against the
    columns' unit) says what is wrong."""
    path = tmp_path / "bad.csv"
    path.write_text(body)
    with pytest.raises(InputError, match=message):
        yio.read(path)


def test_csv_without_usable_columns_says_so_before_asking_for_a_rate(tmp_path):
    """Bare x, y, z columns and no time (an accelerometer alone, as a public lower-back test recording has
    it): the one line names the columns the file has and what a table needs, not the missing rate first."""
    path = tmp_path / "acc.csv"
    path.write_text("\ufeffx,y,z\n100.8,0.71,10.5\n97.9,0.65,0.81\n")
    with pytest.raises(InputError, match=r"no point columns .* \(it has x, y, z; an IMU table needs acc and gyr"):
        yio.read(path)


# ----------------------------------------------------------------------------- read()


def test_read_missing_empty_and_unknown_files(tmp_path):
    """read(): a missing file, an empty file and an unknown extension each give one InputError."""
    with pytest.raises(InputError, match="no such file"):
        yio.read(tmp_path / "nothere.c3d")
    empty = tmp_path / "empty.trc"
    empty.write_bytes(b"")
    with pytest.raises(InputError, match="empty"):
        yio.read(empty)
    other = tmp_path / "walk.xyz"
    other.write_text("1 2 3\n")
    with pytest.raises(InputError, match="unknown file type"):
        yio.read(other)


def test_read_picks_reader_by_extension_case_insensitively_and_applies_overrides(tmp_path):
    """read(): '.TRC' is a TRC; up_axis= and rate_hz= override the file's."""
    path = write_trc(tmp_path / "UPPER.TRC", np.ones((10, 1, 3)), ["A"], rate_hz=100.0)
    rec = yio.read(path, up_axis="Y", capture_rate_hz=50.0)
    assert rec.format == "trc" and rec.up_axis == "y" and rec.metadata["up_axis_from"] == "override"
    assert rec.time_s[1] == pytest.approx(0.02)
    with pytest.raises(InputError, match="up_axis"):
        yio.read(path, up_axis="w")
    with pytest.raises(InputError, match="does not take"):
        yio.read(path, colour="red")


def test_read_takes_the_capture_rate_and_its_old_name_with_a_deprecation(tmp_path):
    """read(capture_rate_hz=) sets the rate of a file without one; rate_hz= does too, with a DeprecationWarning."""
    path = tmp_path / "walk.csv"
    path.write_text("P_x,P_y,P_z\n" + "".join(f"{0.01 * i},0,{0.9 + 0.02 * np.sin(i / 5)}\n" for i in range(300)))
    assert yio.read(path, capture_rate_hz=50.0).rate_hz == pytest.approx(50.0)
    with pytest.warns(DeprecationWarning, match="capture_rate_hz"):
        assert yio.read(path, rate_hz=50.0).rate_hz == pytest.approx(50.0)
    with pytest.raises(InputError, match="not both"):
        yio.read(path, rate_hz=50.0, capture_rate_hz=50.0)
