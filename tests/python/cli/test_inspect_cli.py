"""``yoyogait inspect FILE``: the report on a good file, one error line and exit 2 on a bad one."""

from __future__ import annotations

import json
import subprocess
import sys

import pytest

from builders import write_walk_c3d
from yoyogait.cli import main

ezc3d = pytest.importorskip("ezc3d")


def run(capsys, *args):
    code = main(["inspect", *map(str, args)])
    out, err = capsys.readouterr()
    return code, out, err


def test_inspect_reports_rate_points_pelvis_axis_walking_speed_and_step_frequency(tmp_path, capsys):
    """inspect prints rate, duration, points, pelvis, up axis, walking time, mean speed and step frequency."""
    path = write_walk_c3d(tmp_path / "walk.c3d", stand_before_s=1.0, walk_s=6.0, stand_after_s=1.0)
    code, out, err = run(capsys, path)
    assert code == 0 and err == ""
    assert "100 Hz, 800 frames, 7.99 s" in out
    assert "5: LASI, RASI, SACR, LHEE, RHEE" in out
    assert "pelvis centre of LASI, RASI, SACR" in out
    assert "z (file)" in out
    assert "left LHEE, right RHEE" in out
    walking_s = float(out.split("walking")[1].split()[0])
    assert 5.5 < walking_s < 7.0
    speed = float(out.split("mean speed")[1].split()[0])
    assert speed == pytest.approx(0.7 * 1.8, abs=0.1)  # step length x step frequency
    step = float(out.split("step frequency")[1].split()[0])
    assert step == pytest.approx(1.8, abs=0.05)
    assert "Yoyo-model -90 deg" in out


def test_foot_contacts_without_travel_are_said_to_be_in_place(tmp_path, capsys):
    """A SYNTHETIC chair-stand test (feet that move, a pelvis that does not travel): the walking line says the
    contacts are in place, beside the pelvis's range; a walk over ground's does not."""
    from builders import write_trc
    from yoyogait import synthetic_conditions as sc

    path = tmp_path / "chair_stand.trc"
    write_trc(path, sc.render("chair-stand").recording)
    code, out, _ = run(capsys, path)
    line = next(x for x in out.splitlines() if x.startswith("walking"))
    assert code == 0 and "(from foot contacts), in place: the pelvis stays within 0.2" in line, line
    walk = write_walk_c3d(tmp_path / "walk.c3d", walk_s=6.0)
    code, out, _ = run(capsys, walk)
    assert code == 0 and "in place" not in out


def test_inspect_json_and_overrides(tmp_path, capsys):
    """--json gives the same facts machine-readably; --up-axis and --point override the choices."""
    path = write_walk_c3d(tmp_path / "walk.c3d")
    code, out, _ = run(capsys, path, "--json", "--point", "LASI,RASI", "--up-axis", "z")
    report = json.loads(out)
    assert code == 0
    assert report["point"] == "centre of LASI, RASI"
    assert report["up_axis"] == "z" and report["up_axis_from"] == "override"
    assert report["dft"]["step_frequency_hz"] == pytest.approx(1.8, abs=0.05)
    assert report["dft"]["offset_sign"] in ("positive", "negative")


def _bad_files(tmp_path):
    good = write_walk_c3d(tmp_path / "good.c3d")
    truncated = tmp_path / "truncated.c3d"
    truncated.write_bytes(good.read_bytes()[:-3000])
    corrupt = tmp_path / "corrupt.c3d"
    corrupt.write_bytes(b"\x01P" + bytes(range(256)) * 20)
    empty = tmp_path / "empty.trc"
    empty.write_bytes(b"")
    unknown = tmp_path / "walk.mp4"
    unknown.write_bytes(b"\x00\x00")
    no_pelvis = tmp_path / "knees.csv"
    no_pelvis.write_text("time_s,LKNE_x,LKNE_y,LKNE_z\n" + "".join(f"{i / 100},0,0,0.5\n" for i in range(400)))
    return {
        "missing": ([tmp_path / "nothere.c3d"], "no such file"),
        "empty": ([empty], "empty"),
        "truncated": ([truncated], "truncated"),
        "corrupt": ([corrupt], "not a readable C3D"),
        "unknown extension": ([unknown], "unknown file type"),
        "no such point": ([good, "--point", "LWRI"], "no point 'LWRI'.*available: LASI, RASI, SACR, LHEE, RHEE"),
        "no pelvis": ([no_pelvis], "no pelvis-like point.*LKNE"),
    }


@pytest.mark.parametrize(
    "case", ["missing", "empty", "truncated", "corrupt", "unknown extension", "no such point", "no pelvis"]
)
def test_bad_input_is_one_error_line_and_exit_2(tmp_path, capsys, case):
    """Each bad input prints exactly one line saying what is wrong, no traceback, and exits with 2."""
    import re

    args, message = _bad_files(tmp_path)[case]
    code, out, err = run(capsys, *args)
    assert code == 2 and out == ""
    lines = err.strip().splitlines()
    assert len(lines) == 1 and lines[0].startswith("yoyogait: error: ")
    assert re.search(message, lines[0]), lines[0]


def test_a_recording_too_short_for_the_offline_estimator_is_described_with_a_note(tmp_path, capsys):
    """A 1 s walk is inspected (exit 0: the online estimator takes it); a note says the offline one needs 1.5 s."""
    short = write_walk_c3d(tmp_path / "short.c3d", stand_before_s=0.0, walk_s=1.0, stand_after_s=0.0)
    code, out, err = run(capsys, short)
    assert code == 0 and err == ""
    assert "pelvis centre of LASI, RASI, SACR" in out
    note = out.split("note")[1]
    assert "s of usable velocity, shorter than the 1.5 s the offline estimator needs" in note
    assert "estimate --online replays it" in note
    code, out, _ = run(capsys, write_walk_c3d(tmp_path / "long.c3d"))
    assert code == 0 and "\nnote" not in out


def test_entry_point_prints_no_traceback(tmp_path):
    """Through the real command line, a corrupt file gives one stderr line and exit status 2."""
    bad = tmp_path / "bad.bvh"
    bad.write_text("HIERARCHY\nROOT Hips\n{\n OFFSET 0 0\n")
    proc = subprocess.run([sys.executable, "-m", "yoyogait", "inspect", str(bad)], capture_output=True, text=True)
    assert proc.returncode == 2
    assert "Traceback" not in proc.stderr and len(proc.stderr.strip().splitlines()) == 1


def test_inspect_on_a_real_recording_names_the_manifest_pelvis(manifest, datasets_dir, capsys):
    """On a real Qualisys trial, inspect finds the manifest's pelvis markers and up axis by itself."""
    entry = next(r for r in manifest["recordings"] if r["path"].endswith("Walking_Hybrid_1_1.c3d"))
    code, out, _ = run(capsys, datasets_dir / entry["path"])
    assert code == 0
    assert f"pelvis centre of {', '.join(entry['pelvis'])}" in out
    assert f"{entry['vertical_axis']} (detected)" in out
