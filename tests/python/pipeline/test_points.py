"""Choosing the point to follow (pelvis centre, hand, feet) and the up axis."""

from __future__ import annotations

import numpy as np
import pytest

from yoyogait.errors import InputError
from yoyogait.io import Recording
from yoyogait.pipeline import points


@pytest.mark.parametrize(
    "names, expected",
    [
        (["LASI", "RASI", "LPSI", "RPSI", "LKNE"], ["LASI", "RASI", "LPSI", "RPSI"]),
        (["R_ASIS", "L_ASIS", "SACRUM", "R_HEEL"], ["R_ASIS", "L_ASIS", "SACRUM"]),
        (["R.ASIS", "L.ASIS", "V.Sacral", "R.Heel"], ["R.ASIS", "L.ASIS", "V.Sacral"]),
        (["R.ASIS", "L.ASIS", "R.PSIS", "S2", "L.PSIS", "R.Toe"], ["R.ASIS", "L.ASIS", "R.PSIS", "S2", "L.PSIS"]),
        (["RASI", "LASI", "VSAC", "RWRI"], ["RASI", "LASI", "VSAC"]),
        (["IS070607:LASI", "IS070607:RASI", "IS070607:LHEE"], ["IS070607:LASI", "IS070607:RASI"]),
        (["r_asis", "sacrum", "l_asis", "l_heel"], ["r_asis", "sacrum", "l_asis"]),
        (["LASIS", "RASIS", "LPSIS", "RPSIS"], ["LASIS", "RASIS", "LPSIS", "RPSIS"]),
        (["PV1", "PV2", "PV3", "pv4", "RFT1"], ["PV1", "PV2", "PV3", "pv4"]),
        (["L.Sac.Wand", "R.Sac.Wand", "L.ASIS", "R.ASIS", "PELO", "VPEL"], ["L.ASIS", "R.ASIS"]),
    ],
)
def test_pelvis_markers_are_found_in_their_common_spellings(names, expected):
    """ASIS/PSIS/sacrum/pelvis-cluster markers are found by name in the spellings of Vicon, Qualisys, OpenSim, MAC."""
    choice = points.find_pelvis(names)
    assert choice.kind == "pelvis markers"
    assert list(choice.names) == expected


@pytest.mark.parametrize(
    "names, root",
    [
        (["joint_Root", "Hips", "Spine", "Hand_R"], "Hips"),
        (["mixamorig:Hips", "mixamorig:Spine"], "mixamorig:Hips"),
        (["Pelvis", "L5", "RightUpperLeg"], "Pelvis"),
        (["root", "lfemur", "rfemur"], "root"),
    ],
)
def test_root_joint_is_the_pelvis_of_a_skeleton(names, root):
    """Without pelvis markers, a Hips/pelvis/root joint is the pelvis."""
    choice = points.find_pelvis(names)
    assert choice.kind == "root joint" and choice.names == (root,)


def test_no_pelvis_like_point_is_an_error_listing_the_points():
    """A file without pelvis markers or a root joint gives an error that lists what there is."""
    with pytest.raises(InputError, match="no pelvis-like point.*LKNE, RKNE"):
        points.find_pelvis(["LKNE", "RKNE"])


@pytest.mark.parametrize(
    "names, side, expected",
    [
        (["RWRI", "LWRI", "RASI"], "right", ("RWRI",)),
        (["R.Wrist.Med", "R.Wrist.Lat", "L.Wrist.Med"], "right", ("R.Wrist.Med", "R.Wrist.Lat")),
        (["R_wrist_radius", "R_wrist_ulna", "L_wrist_radius"], "right", ("R_wrist_radius", "R_wrist_ulna")),
        (["RFIN", "RLW", "RMW", "LFIN"], "right", ("RFIN",)),
        (["RightWrist", "rhand", "RFingers"], "right", ("rhand",)),
        (["Hand_L", "Hand_R"], "left", ("Hand_L",)),
    ],
)
def test_hand_is_a_hand_point_else_the_wrist_markers(names, side, expected):
    """The hand of a side: a hand joint or finger marker first, else its wrist markers averaged."""
    assert points.find_hand(names, side).names == expected


def test_feet_prefer_a_heel_that_is_actually_seen():
    """Feet: heel first, but a heel marker seen in too few frames gives way to the ankle."""
    names = ["LHEE", "RHEE", "LANK", "RANK", "LTOE", "RTOE"]
    assert points.find_feet(names) == {"left": "LHEE", "right": "RHEE"}
    seen = {"LHEE": 0.0, "RHEE": 0.9, "LANK": 0.95, "RANK": 0.95, "LTOE": 1.0, "RTOE": 1.0}
    assert points.find_feet(names, seen) == {"left": "LANK", "right": "RHEE"}
    assert points.find_feet(["Foot_L", "Toes_L", "Foot_R"]) == {"left": "Foot_L", "right": "Foot_R"}


def _pelvis_markers(n_frames, rate_hz=100.0, turn_deg_per_s=30.0):
    """Four pelvis markers of a pelvis walking forward and turning (frames x 4 x 3) and the true centre."""
    t = np.arange(n_frames) / rate_hz
    yaw = np.radians(turn_deg_per_s) * t
    centre = np.column_stack([1.2 * t, 0.1 * np.sin(2 * np.pi * 0.9 * t), 0.95 + 0.02 * np.cos(2 * np.pi * 1.8 * t)])
    local = np.array([[0.1, 0.12, 0.02], [0.1, -0.12, 0.02], [-0.1, 0.05, 0.0], [-0.1, -0.05, 0.0]])
    local -= local.mean(axis=0)
    c, s = np.cos(yaw), np.sin(yaw)
    world = np.stack(
        [
            c[:, None] * local[:, 0] - s[:, None] * local[:, 1],
            s[:, None] * local[:, 0] + c[:, None] * local[:, 1],
            np.broadcast_to(local[:, 2], (n_frames, 4)),
        ],
        axis=-1,
    )
    return centre[:, None, :] + world, centre


def test_pelvis_centre_does_not_jump_when_a_marker_drops_out():
    """A marker lost for 0.5 s (and one lost for single frames) moves the centre by < 2 mm; a plain mean jumps by cm."""
    markers, truth = _pelvis_markers(400)
    markers[150:200, 0] = np.nan  # LASI occluded for 0.5 s while the pelvis turns
    markers[::37, 2] = np.nan  # single-frame drop-outs
    centre, used = points.robust_centre(markers)
    assert used == [0, 1, 2, 3]
    assert np.nanmax(np.linalg.norm(centre - truth, axis=1)) < 0.002
    plain = np.nanmean(markers, axis=1)
    assert np.nanmax(np.linalg.norm(plain - truth, axis=1)) > 0.02  # what the carried offsets avoid


def test_pelvis_centre_is_nan_only_where_no_marker_is_seen():
    """The centre is known whenever one marker is, and NaN (not zero) when none is."""
    markers, _ = _pelvis_markers(100)
    markers[40:45] = np.nan
    markers[60:70, :3] = np.nan
    centre, _ = points.robust_centre(markers)
    assert np.all(np.isnan(centre[40:45])) and np.all(np.isfinite(np.delete(centre, range(40, 45), axis=0)))


def test_trajectories_reused_inside_the_block_are_the_same_and_private(monkeypatch):
    """Inside reusing_trajectories a recording's pelvis centre is computed once, each caller gets its own copy
    equal to a fresh computation; outside the block nothing is kept."""
    markers, _ = _pelvis_markers(120)
    markers[30:50, 1] = np.nan
    rec = Recording(markers, ["LASI", "RASI", "LPSI", "RPSI"], np.arange(120) / 100.0, 100.0)
    fresh = points.point_trajectory(rec)
    calls = []
    original = points.robust_centre
    monkeypatch.setattr(points, "robust_centre", lambda p: calls.append(1) or original(p))
    with points.reusing_trajectories():
        first = points.point_trajectory(rec)
        first.positions_m[:] = 0.0  # a caller changing its copy
        second = points.point_trajectory(rec, ["LASI", "RASI", "LPSI", "RPSI"])
    assert len(calls) == 1
    assert np.array_equal(second.positions_m, fresh.positions_m, equal_nan=True)
    assert second.used_names == fresh.used_names and second.choice.kind == "named"
    points.point_trajectory(rec)
    assert len(calls) == 2


def test_rarely_seen_marker_is_left_out_of_the_centre():
    """A marker seen in under half the frames does not take part (its offsets would be stretched too far)."""
    markers, truth = _pelvis_markers(200, turn_deg_per_s=0.0)
    markers[:150, 3] = np.nan
    centre, used = points.robust_centre(markers)
    assert used == [0, 1, 2]
    assert np.allclose(centre - truth, centre[0] - truth[0], atol=0.002)  # a constant offset only


def _standing_body(up: str, n=200, rate_hz=100.0):
    """Pelvis markers, heels and a head of a person walking along the first horizontal axis."""
    markers, centre = _pelvis_markers(n, rate_hz, turn_deg_per_s=0.0)
    heels = centre[:, None, :] + np.array([[0.0, 0.1, -0.9], [0.0, -0.1, -0.9]])
    heels[:, 0, 0] += 0.3 * np.sin(2 * np.pi * 0.9 * np.arange(n) / rate_hz)
    head = centre[:, None, :] + np.array([[0.0, 0.0, 0.75]])
    xyz_up_z = np.concatenate([markers, heels, head], axis=1)
    order = {"z": [0, 1, 2], "y": [0, 2, 1], "x": [1, 2, 0]}[up]  # where forward, lateral, vertical go
    pos = np.empty_like(xyz_up_z)
    pos[..., order] = xyz_up_z
    names = ["LASI", "RASI", "LPSI", "RPSI", "LHEE", "RHEE", "HEAD"]
    return Recording(pos + 5.0, names, np.arange(n) / rate_hz)  # an offset lab origin changes nothing


@pytest.mark.parametrize("up", ["x", "y", "z"])
def test_up_axis_is_detected_whichever_axis_it_is(up):
    """The detected up axis is the one along which the pelvis stands high above the feet, steadily."""
    assert points.detect_up_axis(_standing_body(up)) == up


def test_up_axis_from_file_and_override():
    """The file's up axis is used unless overridden; without both it is detected."""
    rec = _standing_body("y")
    assert points.resolve_up_axis(rec) == ("y", "detected")
    rec.up_axis = "z"
    assert points.resolve_up_axis(rec) == ("z", "file")
    assert points.resolve_up_axis(rec, "x") == ("x", "override")
    with pytest.raises(InputError, match="up_axis"):
        points.resolve_up_axis(rec, "up")


def test_choose_point_by_name_list_or_keyword():
    """point= takes None/'pelvis', 'hand', a name or a list; an unknown name lists the available points."""
    rec = _standing_body("z")
    rec.point_names[-1] = "RWRI"
    assert points.choose_point(rec).names == ("LASI", "RASI", "LPSI", "RPSI")
    assert points.choose_point(rec, "pelvis").kind == "pelvis markers"
    assert points.choose_point(rec, "hand").names == ("RWRI",)
    assert points.choose_point(rec, ["LASI", "RASI"]).label == "centre of LASI, RASI"
    with pytest.raises(InputError, match="no point 'NOPE'.*available: LASI, RASI"):
        points.choose_point(rec, "NOPE")


# ----------------------------------------------------------------------------- marker-set table

_KNOWLEDGE = points.marker_knowledge()


def _set_names(spec) -> list[str]:
    names = list(spec.get("pelvis", [])) + list(spec.get("root", []))
    for role in ("hips", "hand", "wrist"):
        for side in ("left", "right"):
            names += spec.get(role, {}).get(side, [])
    for side in ("left", "right"):
        for kind_names in spec.get("feet", {}).get(side, {}).values():
            names += kind_names
    return list(dict.fromkeys(names))


@pytest.mark.parametrize("set_name", sorted(_KNOWLEDGE.sets))
def test_every_marker_set_of_the_table_is_recognised_from_a_file(tmp_path, set_name):
    """A CSV holding one set's names (under a subject prefix) is read; its pelvis and each foot, by side, are found."""
    import yoyogait

    spec = _KNOWLEDGE.sets[set_name]
    names = _set_names(spec) + ["LKNE", "RKNE"]
    header = "time_s," + ",".join(f"Sub:{n}_{a}" for n in names for a in "xyz")
    rows = [
        f"{f / 100:.2f}," + ",".join(f"{0.01 * f + i * 0.001:.3f},{i * 0.01:.2f},0.5" for i in range(len(names)))
        for f in range(3)
    ]
    path = tmp_path / "set.csv"
    path.write_text(header + "\n" + "\n".join(rows) + "\n")
    rec = yoyogait.read(path)
    choice = points.find_pelvis(rec.point_names)
    if spec.get("pelvis"):
        assert choice.kind == "pelvis markers"
        assert {f"Sub:{n}" for n in spec["pelvis"]} <= set(choice.names)
    elif not spec.get("root"):  # hip joints: the first of each side
        assert choice.kind == "hip joints"
        assert choice.names == tuple(f"Sub:{spec['hips'][side][0]}" for side in ("left", "right"))
    else:
        assert choice.kind == "root joint" and choice.names[0] == f"Sub:{spec['root'][0]}"
    groups = points.find_foot_groups(rec.point_names)
    for side, kinds in spec.get("feet", {}).items():
        listed = {f"Sub:{n}" for kind_names in kinds.values() for n in kind_names}
        assert listed <= set(groups[side]), f"{side}: {groups.get(side)}"
        first_kind = next(k for k in points.FOOT_KINDS if kinds.get(k))
        assert groups[side][0] in {f"Sub:{n}" for n in kinds[first_kind]}
    for side in ("left", "right"):
        if spec.get("hand", {}).get(side) or spec.get("wrist", {}).get(side):
            assert points.find_hand(rec.point_names, side).names


@pytest.mark.parametrize(
    "names, pelvis, left_foot",
    [
        (
            ["pHipOrigin", "pLeftASI", "pRightASI", "pSacrum", "pLeftHeelFoot"],
            {"pLeftASI", "pRightASI", "pSacrum"},
            "pLeftHeelFoot",
        ),
        (["Hip_FL", "Hip_FR", "Hip_BL", "Hip_BR", "LToe"], {"Hip_FL", "Hip_FR", "Hip_BL", "Hip_BR"}, "LToe"),
        (["r.ASIS_study", "L.PSIS_study", "midHip", "L_calc_study"], {"r.ASIS_study", "L.PSIS_study"}, "L_calc_study"),
        (["LIAS", "RIAS", "LIPS", "RIPS", "LCA"], {"LIAS", "RIAS", "LIPS", "RIPS"}, "LCA"),
        (["midHip", "LHeel", "RHeel"], {"midHip"}, "LHeel"),
        (["Skeleton_Hip", "Skeleton_LFoot", "Skeleton_RFoot"], {"Skeleton_Hip"}, "Skeleton_LFoot"),
        (["Skeleton 001_Hip", "Skeleton 001_LFoot"], {"Skeleton 001_Hip"}, "Skeleton 001_LFoot"),
        (["RHip", "RKnee", "RHeel", "LHip", "LKnee", "LHeel", "Neck"], {"RHip", "LHip"}, "LHeel"),
        (["nose", "left_hip", "right_hip", "left_heel", "right_heel"], {"left_hip", "right_hip"}, "left_heel"),
        (["C7", "Psis", "RxAsis", "LxAsis", "RxHeel", "LxHeel", "LxToe1"], {"Psis", "RxAsis", "LxAsis"}, "LxHeel"),
    ],
)
def test_pelvis_and_feet_of_xsens_mocap_toolbox_opencap_isb_and_skeletons(names, pelvis, left_foot):
    """Xsens, MoCap Toolbox, OpenCap, ISB names, prefixed skeleton bones, video keypoints (hip joints: their
    midpoint) and Rx/Lx side prefixes give the pelvis and the left foot."""
    assert set(points.find_pelvis(names).names) == pelvis
    assert points.find_feet(names)["left"] == left_foot


def test_joint_root_prefix_is_not_stripped_to_a_root():
    """'joint_Root' (Bandai's ground projection) is not taken for a root joint through its 'joint_' prefix."""
    with pytest.raises(InputError, match="no pelvis-like point"):
        points.find_pelvis(["joint_Root", "Spine"])


def test_users_extend_the_table_with_a_file_named_by_the_environment(tmp_path, monkeypatch):
    """A JSON file named by $YOYOGAIT_MARKER_SETS adds a lab's own names (pelvis and feet by side); a bad file is
    one clear error."""
    own = tmp_path / "lab.json"
    own.write_text(
        '{"sets": {"our lab": {"pelvis": ["WAISTF", "WAISTB"],'
        ' "feet": {"left": {"heel": ["FERSE_LI"]}, "right": {"heel": ["FERSE_RE"]}}}}}'
    )
    names = ["WAISTF", "WAISTB", "FERSE_LI", "FERSE_RE"]
    with pytest.raises(InputError):
        points.find_pelvis(names)
    monkeypatch.setenv(points.MARKER_SETS_ENV, str(own))
    assert points.find_pelvis(names).names == ("WAISTF", "WAISTB")
    assert points.find_feet(names) == {"left": "FERSE_LI", "right": "FERSE_RE"}
    bad = tmp_path / "bad.json"
    bad.write_text("{not json")
    monkeypatch.setenv(points.MARKER_SETS_ENV, str(bad))
    with pytest.raises(InputError, match="bad.json: not valid JSON"):
        points.find_pelvis(names)


def test_hip_joints_give_the_pelvis_only_where_nothing_better_is_named():
    """Left and right hip joints (video keypoints) are the pelvis only without pelvis markers or a root joint, and
    only as a pair."""
    assert points.find_pelvis(["RHip", "LHip", "midHip"]).names == ("midHip",)
    assert set(points.find_pelvis(["RHip", "LHip", "LASI", "RASI"]).names) == {"LASI", "RASI"}
    assert points.find_pelvis(["RHip", "LHip"]).kind == "hip joints"
    with pytest.raises(InputError, match="no pelvis-like point"):
        points.find_pelvis(["RHip", "RKnee"])
