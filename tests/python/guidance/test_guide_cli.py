"""yoyogait guide: bad input in one line with exit 2, the report written whole, --force touching only its files."""

from __future__ import annotations

from pathlib import Path

import pytest

from yoyogait.cli import main

SHORT = "x_m,y_m,pace,stop_s\n0,0,1,0\n3,0,,\n"


def _error_line(capsys) -> str:
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1, err
    return err[0]


@pytest.fixture
def path_file(tmp_path) -> Path:
    p = tmp_path / "path.csv"
    p.write_text(SHORT)
    return p


@pytest.mark.parametrize(
    "content, words",
    [
        ("", "empty"),
        ("x,y\n0,0\n3,0\n", "x_m and y_m"),
        ("x_m,y_m\n0,0\n", "at least 2 waypoints"),
        ("x_m,y_m\n0,0\n0.1,0\n", "apart"),
        ("x_m,y_m\n0,0\nfoo,1\n", "line 3"),
        ("x_m,y_m,pace\n0,0,5\n3,0,1\n", "pace"),
        ("x_m,y_m,speed\n0,0,1\n3,0,1\n", "unknown column"),
        ("x_m,y_m\n0,0\nnan,1\n", "finite"),
    ],
)
def test_a_bad_path_file_is_one_line_naming_the_file(tmp_path, capsys, content, words):
    """Each broken path file ends the command with exit 2 and one line naming the file and the problem."""
    p = tmp_path / "bad.csv"
    p.write_text(content)
    code = main(["guide", "--path", str(p), "--out", str(tmp_path / "out"), "--source", "raw"])
    line = _error_line(capsys)
    assert code == 2 and "bad.csv" in line and words in line, line
    assert not (tmp_path / "out").exists()


@pytest.mark.parametrize(
    "args, words",
    [
        (["--source", "raw,kalman"], "--source"),
        (["--latency-s", "0.9"], "--latency-s"),
        (["--path", "missing.csv"], "missing.csv"),
    ],
)
def test_bad_options_are_one_line(tmp_path, capsys, path_file, args, words):
    """An unknown source, a latency out of range or a missing path file: exit 2, one line naming it."""
    argv = ["guide", "--path", str(path_file), "--out", str(tmp_path / "out"), *args]
    code = main(argv)
    line = _error_line(capsys)
    assert code == 2 and words in line, line
    assert not (tmp_path / "out").exists()


def test_the_report_is_written_and_force_replaces_only_its_files(tmp_path, capsys, path_file):
    """A second run needs --force; with it the report is replaced and a user's file in the folder stays."""
    out = tmp_path / "out"
    argv = ["guide", "--path", str(path_file), "--out", str(out), "--source", "raw,yoyogait"]
    assert main(argv) == 0
    written = {p.name for p in out.rglob("*") if p.is_file()}
    assert {"table.csv", "table.md", "runs.csv", "report.md", ".yoyogait-report"} <= written
    assert any(name.endswith("_force.png") for name in written)
    assert "SYNTHETIC" in (out / "report.md").read_text()
    capsys.readouterr()
    (out / "notes.txt").write_text("mine")
    assert main(argv) == 2
    assert "--force" in _error_line(capsys)
    assert main([*argv, "--force", "--no-figures"]) == 0
    assert (out / "notes.txt").read_text() == "mine"
    assert not list(out.rglob("*.png"))  # the old figures were yoyogait's: removed with the report they belonged to
    header = (out / "table.csv").read_text().splitlines()[0]
    assert header.startswith("source,runs,lag_s,force_osc_step_n")
