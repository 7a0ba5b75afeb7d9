"""One command-line vocabulary: the same input options everywhere, errors as one line naming the
option, outputs that never leak a temporary name, and --force that touches only what yoyogait wrote."""

from __future__ import annotations

import csv
import re

import numpy as np
import pytest
from click.testing import CliRunner

from builders import write_trc
from yoyogait import evaluation as ev
from yoyogait import synthetic
from yoyogait._files import MARKER, written_files
from yoyogait.cli import _register, cli, main
from yoyogait.cli.evaluate_cmd import with_overrides
from yoyogait.cli.options import ESTIMATOR_NAMES, cli_message

INPUT_OPTIONS = ("--point", "--feet", "--up-axis", "--length-unit-m", "--capture-rate-hz")


def run(capsys, *args):
    code = main([str(a) for a in args])
    out, err = capsys.readouterr()
    return code, out, err


def one_error_line(err: str) -> str:
    lines = [line for line in err.strip().splitlines() if not line.startswith("Evaluating ")]  # evaluate's progress
    assert len(lines) == 1 and lines[0].startswith("yoyogait: error: "), err
    assert "Usage:" not in err and "Traceback" not in err
    return lines[0]


@pytest.fixture(scope="module")
def stop_and_go_trc(tmp_path_factory):
    walk = synthetic.make_walk(synthetic.SUBJECTS[0], "5-stop-and-go", duration_s=25.0)
    return write_trc(tmp_path_factory.mktemp("walks") / "stopgo.trc", walk.recording), walk


@pytest.fixture(scope="module")
def small_evaluation():
    return ev.evaluate(ev.synthetic_items()[:1], ("default",), dataset="synthetic", synthetic=True)


@pytest.mark.parametrize("command", ["inspect", "estimate", "evaluate"])
def test_every_command_that_reads_recordings_has_the_same_input_options(command):
    """inspect, estimate and evaluate all list --point, --feet, --up-axis, --length-unit-m and --capture-rate-hz."""
    _register()
    result = CliRunner().invoke(cli, [command, "--help"])
    assert result.exit_code == 0
    for option in INPUT_OPTIONS:
        assert option in result.output, (command, option)
    for old in ("--up ", "--unit ", "--rate "):
        assert old not in result.output


def test_help_lists_the_choices_of_preset_and_estimators():
    """--preset shows its choices in --help, and --estimators names every estimator."""
    _register()
    runner = CliRunner()
    assert "[paper|default|oscillator|sliding-dft]" in runner.invoke(cli, ["estimate", "--help"]).output
    text = " ".join(runner.invoke(cli, ["evaluate", "--help"]).output.split())
    assert all(name in text for name in ESTIMATOR_NAMES)


def test_library_argument_names_become_option_names():
    """Messages naming a library argument name the option instead."""
    assert (
        cli_message("x.csv: no time column and no rate; pass capture_rate_hz=")
        == "x.csv: no time column and no rate; use --capture-rate-hz"
    )
    assert (
        cli_message("length_unit_m must be a positive number, not -1")
        == "--length-unit-m must be a positive number, not -1"
    )
    assert cli_message("no unit; pass length_unit_m=") == "no unit; use --length-unit-m"
    assert cli_message("cannot detect the up axis; pass up_axis=") == "cannot detect the up axis; use --up-axis"
    assert cli_message("at least min_usable_s=1.5 s are needed") == "at least 1.5 s are needed"
    assert cli_message("point= must name at least one point") == "--point must name at least one point"
    assert cli_message("the option rate_hz_file stays") == "the option rate_hz_file stays"
    assert cli_message("no pelvis-like point; the point is missing") == "no pelvis-like point; the point is missing"


def test_a_missing_rate_names_the_option(tmp_path, capsys):
    """A CSV without time or rate: one line naming --capture-rate-hz; with it (or old --rate-hz), it reads."""
    path = tmp_path / "walk.csv"
    rows = "".join(f"{0.01 * i},0,{0.9 + 0.02 * np.sin(i / 5)}\n" for i in range(500))
    path.write_text("PELVIS_x,PELVIS_y,PELVIS_z\n" + rows)
    code, out, err = run(capsys, "inspect", path)
    assert code == 2 and out == ""
    line = one_error_line(err)
    assert "--capture-rate-hz" in line and "rate_hz" not in line
    for option in ("--capture-rate-hz", "--rate-hz"):
        code, out, _ = run(capsys, "inspect", path, option, 100)
        assert code == 0 and "100 Hz" in out, option


@pytest.mark.parametrize(
    "args, option",
    [
        (["estimate", "{tmp}"], "FILE"),
        (["inspect", "{tmp}"], "FILE"),
        (["estimate", "{walk}", "--out", "{tmp}"], "--out"),
        (["estimate", "{walk}", "--length-unit-m", "-1"], "--length-unit-m"),
        (["inspect", "{walk}", "--capture-rate-hz", "0"], "--capture-rate-hz"),
        (["estimate", "{walk}", "--preset", "bogus"], "--preset"),
        (["estimate", "{walk}", "--up-axis", "q"], "--up-axis"),
        (["estimate", "{walk}", "--point", "NOPE"], "--point"),
        (["estimate", "{walk}", "--feet", "LHEE,NOPE"], "--feet"),
        (["evaluate", "synthetic", "--estimators", "paper,bogus"], "--estimators"),
        (["evaluate", "synthetic", "--length-unit-m", "1"], "--length-unit-m"),
    ],
)
def test_bad_options_are_one_line_naming_the_option(tmp_path, capsys, stop_and_go_trc, args, option):
    """A folder as FILE, a folder as --out, a bad value or name: one line naming the option, exit 2, nothing written."""
    walk, _ = stop_and_go_trc
    argv = [a.format(tmp=tmp_path, walk=walk) for a in args]
    code, out, err = run(
        capsys, *argv, *([] if argv[0] == "inspect" else ["--out", tmp_path / "o"] * ("--out" not in argv))
    )
    assert code == 2
    assert option in one_error_line(err)
    assert not (tmp_path / "o").exists()


def test_a_failed_write_names_the_output_and_leaks_no_temporary_name(tmp_path, capsys, stop_and_go_trc):
    """Writing into a folder that does not exist: one line naming --out's file and why; nothing left behind."""
    walk, _ = stop_and_go_trc
    target = tmp_path / "missing" / "x.csv"
    code, _, err = run(capsys, "estimate", walk, "--out", target, "--figure", "none")
    line = one_error_line(err)
    assert code == 2 and str(target) in line and "No such file or directory" in line
    assert ".tmp" not in line and not re.search(r"\.x\.", line)
    # A figure that cannot be drawn in the asked format: its path and matplotlib's reason, no temporary
    # file, and no CSV without its figure (both or neither).
    code, _, err = run(capsys, "estimate", walk, "--out", tmp_path / "x.csv", "--figure", tmp_path / "x.nope")
    line = one_error_line(err)
    assert code == 2 and str(tmp_path / "x.nope") in line and ".tmp." not in line
    assert sorted(p.name for p in tmp_path.iterdir()) == []


def test_existing_outputs_need_force(tmp_path, capsys, stop_and_go_trc):
    """An existing --out or --figure is refused in one line naming the option; --force replaces it."""
    walk, _ = stop_and_go_trc
    out, fig = tmp_path / "e.csv", tmp_path / "e.png"
    fig.write_text("user's")
    code, _, err = run(capsys, "estimate", walk, "--out", out, "--figure", fig)
    assert code == 2 and "--figure" in one_error_line(err) and fig.read_text() == "user's" and not out.exists()
    assert run(capsys, "estimate", walk, "--out", out, "--figure", fig, "--force")[0] == 0
    assert fig.read_bytes()[:4] == b"\x89PNG"


def test_estimate_csv_says_where_the_person_walks(tmp_path, capsys, stop_and_go_trc):
    """The estimate CSV has walking, estimator_walking and status columns, units in the other names, and
    walking is 0 in the middle of the stop."""
    walk, lab = stop_and_go_trc
    out = tmp_path / "e.csv"
    assert run(capsys, "estimate", walk, "--out", out, "--figure", "none")[0] == 0
    header = out.read_text().splitlines()[0].split(",")
    assert {"walking", "estimator_walking", "status"} <= set(header)
    unitless = {"walking", "estimator_walking", "status"}
    units = ("_s", "_mps", "_hz", "_m", "_rad_per_sample")
    assert all(name.endswith(units) for name in header if name not in unitless), header
    data = np.genfromtxt(out, delimiter=",", names=True)
    truth = lab.truth.at(data["time_s"])
    standing = ~np.asarray(truth.walking, dtype=bool)
    assert standing.any() and (~standing).any()
    # The detector lags the truth by up to a step at each transition; away from them they agree.
    agree = (data["walking"] == 1) == ~standing
    assert agree.mean() > 0.9
    assert set(np.unique(data["status"])) <= {0, 1, 2, 3, 4}


def test_evaluate_options_apply_to_every_recording(tmp_path, capsys, stop_and_go_trc):
    """evaluate FOLDER --point/--feet override every item's points; a foot that is not there fails each recording."""
    walk, _ = stop_and_go_trc
    items = ev.folder_items(walk.parent)
    changed = with_overrides(items, point=["LASI", "RASI"], feet=["LHEE", "RHEE"], up_axis="z", length_unit_m=1.0)
    assert changed[0].pelvis == ["LASI", "RASI"] and changed[0].feet == ["LHEE", "RHEE"]
    assert changed[0].load().up_axis == "z" and changed[0].load().metadata["up_axis_from"] == "override"
    code, _, err = run(capsys, "evaluate", walk.parent, "--feet", "LHEE,NOPE", "--out", tmp_path / "r", "--no-figures")
    assert code == 2 and "NOPE" in one_error_line(err) and not (tmp_path / "r").exists()


def test_force_replaces_only_what_yoyogait_wrote(small_evaluation, tmp_path):
    """--force replaces the files listed in .yoyogait-report and removes the old report's others; the user's stay."""
    out = tmp_path / "report"
    ev.write_report(small_evaluation, out, figures=True)
    listed = written_files(out)
    assert "index.md" in listed and any(name.startswith("figures/") for name in listed)
    (out / "notes.md").write_text("mine")
    (out / "figures" / "my_plot.png").write_text("mine too")
    ev.write_report(small_evaluation, out, figures=False, force=True)
    assert (out / "notes.md").read_text() == "mine"
    assert (out / "figures" / "my_plot.png").read_text() == "mine too"
    assert list((out / "figures").iterdir()) == [out / "figures" / "my_plot.png"]
    assert written_files(out) == sorted(p.name for p in out.iterdir() if p.name not in ("notes.md", "figures", MARKER))
    assert sorted(p.name for p in tmp_path.iterdir()) == ["report"]


def test_a_folder_yoyogait_did_not_write_is_refused_even_with_force(small_evaluation, tmp_path, capsys):
    """A non-empty folder without the marker is refused, with or without --force; an empty one is filled."""
    mine = tmp_path / "mine"
    mine.mkdir()
    (mine / "thesis.tex").write_text("keep")
    for force in (False, True):
        with pytest.raises(OSError, match="did not write"):
            ev.write_report(small_evaluation, mine, figures=False, force=force)
    assert [p.name for p in mine.iterdir()] == ["thesis.tex"]
    code, _, err = run(capsys, "evaluate", "--out", mine, "--force", "--estimators", "default", "--no-figures")
    assert code == 2 and "--out" in one_error_line(err) and [p.name for p in mine.iterdir()] == ["thesis.tex"]
    empty = tmp_path / "empty"
    empty.mkdir()
    ev.write_report(small_evaluation, empty, figures=False)
    rows = list(csv.DictReader(open(empty / "recordings.csv")))
    assert len(rows) == 1 and (empty / MARKER).is_file()


def test_a_marker_cannot_point_outside_its_folder(small_evaluation, tmp_path):
    """Names in an edited marker that leave the folder are ignored: --force deletes nothing outside it."""
    out = tmp_path / "report"
    ev.write_report(small_evaluation, out, figures=False)
    (tmp_path / "precious.txt").write_text("keep")
    with open(out / MARKER, "a") as fh:
        fh.write("../precious.txt\n" + str(tmp_path / "precious.txt") + "\n")
    ev.write_report(small_evaluation, out, figures=False, force=True)
    assert (tmp_path / "precious.txt").read_text() == "keep"
