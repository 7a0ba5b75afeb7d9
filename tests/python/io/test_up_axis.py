"""The up axis from a person's geometry (feet low, head high, the pelvis band, its bounces), a format's declared
axis checked against it, and the one warning naming --up-axis when they disagree."""

from __future__ import annotations

import warnings

import numpy as np
import pytest

import yoyogait.io as yio
from builders import stepping_walk
from yoyogait.cli import main
from yoyogait.io import body
from yoyogait.io.recording import Recording

NAMES = ("LASI", "RASI", "SACR", "LHEE", "RHEE", "LFHD", "RFHD", "LWRA", "RWRA", "LTOE", "RTOE")


def _person(up="z"):
    """A stepping walk with head, wrist and toe markers (m), z up; ``up`` permutes the axes."""
    rec, _ = stepping_walk(stand_before_s=0.5, walk_s=5.0, stand_after_s=0.5)
    pos = rec.positions_m
    pelvis = pos[:, :3].mean(axis=1)
    extra = [
        pelvis + [0.05, 0.08, 0.55],  # LFHD: the head 1.45-1.55 m
        pelvis + [0.05, -0.08, 0.55],
        pelvis + [0.0, 0.35, -0.05],  # wrists beside the hips
        pelvis + [0.0, -0.35, -0.05],
        pos[:, 3] + [0.2, 0.0, -0.03],  # toes ahead of the heels, 0.02-0.12 m
        pos[:, 4] + [0.2, 0.0, -0.03],
    ]
    all_pos = np.concatenate([pos, np.stack(extra, axis=1)], axis=1)
    order = {"z": [0, 1, 2], "y": [0, 2, 1], "x": [2, 0, 1]}[up]
    return all_pos[:, :, order], rec.time_s


def _qtm_tsv(path, pos, names, rate=100):
    lines = [
        f"NO_OF_FRAMES\t{len(pos)}",
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
        "Frame\tTime\t" + "\t".join(f"{n} {a}" for n in names for a in "XYZ"),
    ]
    for f, frame in enumerate(pos * 1000.0):
        lines.append(f"{f + 1}\t{f / rate:.5f}\t" + "\t".join(f"{v:.3f}" for v in frame.ravel()))
    path.write_text("\n".join(lines) + "\n")
    return path


def _motive_csv(path, pos, names, rate=100):
    """Motive 1.23 marker export in metres."""
    rows = [
        f"Format Version,1.23,Take Name,walk,Capture Frame Rate,{rate},Export Frame Rate,{rate},"
        "Rotation Type,Quaternion,Length Units,Meters,Coordinate Space,Global",
        "",
        ",Type," + ",".join(["Marker"] * 3 * len(names)),
        ",Name," + ",".join(f"Skeleton:{n}" for n in names for _ in range(3)),
        ",ID," + ",".join(["1"] * 3 * len(names)),
        ",," + ",".join(["Position"] * 3 * len(names)),
        "Frame,Time (Seconds)," + ",".join(["X", "Y", "Z"] * len(names)),
    ]
    for f, frame in enumerate(pos):
        rows.append(f"{f},{f / rate:.6f}," + ",".join(f"{v:.5f}" for v in frame.ravel()))
    path.write_text("\n".join(rows) + "\n")
    return path


def test_qualisys_tsv_feet_low_head_high_is_z_up(tmp_path, capsys):
    """Feet at z 0.02-0.12 m and head markers at z 1.4-1.6 m, and a static reference marker 2.5 m to the side (the
    lowest point along y, steady, which made the pelvis look 2.6 m 'above' it along y): z, with the feet and the head
    named as evidence."""
    pos, _ = _person("z")
    wall = np.broadcast_to(np.array([1.0, -2.5, 0.8]), (len(pos), 3))[:, None, :]
    pos = np.concatenate([pos, wall], axis=1)
    names = [n.replace("LFHD", "HeadL").replace("RFHD", "HeadR") for n in NAMES] + ["WallRef"]
    path = _qtm_tsv(tmp_path / "walk.tsv", pos, names)
    rec = yio.read(path)
    assert 0.0 < np.nanmin(rec.point("LHEE")[:, 2]) and np.nanmax(rec.point("LTOE")[:, 2]) < 0.15
    ev = body.up_axis_evidence(rec)
    assert ev.axis == "z" and ev.decisive
    assert any(c.startswith("feet") for c in ev.cues) and any(c.startswith("head") for c in ev.cues)
    assert main(["inspect", str(path)]) == 0
    out = capsys.readouterr().out
    assert "up axis         z (the Qualisys convention (Z up))" in out and "body says       z (clear: " in out


@pytest.mark.parametrize("up", ["x", "y", "z"])
def test_every_axis_is_found_from_the_body(up):
    """The same person with each axis up is found up along it, clearly."""
    pos, t = _person(up)
    ev = body.up_axis_evidence(Recording(pos, list(NAMES), t, rate_hz=100.0))
    assert ev.axis == up and ev.decisive


def test_pelvis_alone_is_told_by_its_bounces():
    """A lone pelvis point (a clip's root) walking along x: its step-frequency bounces say which axis is up."""
    t = np.arange(0, 8, 0.01)
    pelvis = np.column_stack([1.2 * t, 0.9 + 0.02 * np.cos(2 * np.pi * 1.8 * t), 0.03 * np.sin(np.pi * 1.8 * t)])
    ev = body.up_axis_evidence(Recording(pelvis[:, None, :], ["root"], t, rate_hz=100.0))
    assert ev.axis == "y" and any("bounces at 1.80 Hz" in c for c in ev.cues)


def test_motive_csv_y_up_by_convention(tmp_path):
    """A Motive CSV of a Y-up skeleton is read Y up, from Motive's convention, without a warning."""
    pos, _ = _person("y")
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        rec = yio.read(_motive_csv(tmp_path / "take.csv", pos, NAMES))
    assert rec.up_axis == "y" and "Motive convention" in rec.metadata["up_axis_from"]


def test_motive_csv_whose_body_is_z_up_says_so_once(tmp_path):
    """A Motive CSV whose body is clearly Z up is read Z up, with one warning naming --up-axis y."""
    pos, _ = _person("z")
    with pytest.warns(UserWarning, match=r"Motive convention .* says up axis y, the body says z .*--up-axis y") as w:
        rec = yio.read(_motive_csv(tmp_path / "take.csv", pos, NAMES))
    assert len([x for x in w if "up axis" in str(x.message)]) == 1
    assert rec.up_axis == "z" and rec.metadata["up_axis_from"].startswith("detected")


def test_stated_axis_against_the_body_warns_naming_the_option(tmp_path):
    """A file stating z whose body is y up keeps z and warns once, naming --up-axis y; --up-axis silences it."""
    pos, t = _person("y")
    path = tmp_path / "walk.csv"
    header = "# up_axis: z\ntime_s," + ",".join(f"{n}_{a}" for n in NAMES for a in "xyz")
    rows = [f"{ti:.3f}," + ",".join(f"{v:.5f}" for v in frame.ravel()) for ti, frame in zip(t, pos)]
    path.write_text(header + "\n" + "\n".join(rows) + "\n")
    with pytest.warns(UserWarning, match=r"the file states up axis z, the body says y .*pass --up-axis y"):
        rec = yio.read(path, plausibility=False)
    assert rec.up_axis == "z"
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        assert yio.read(path, up_axis="y").up_axis == "y"
