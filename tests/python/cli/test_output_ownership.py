"""Outputs that cannot be turned against the user: a command writes only regular files, new names and
folders yoyogait made; device nodes, FIFOs, sockets and its own inputs are refused even with --force;
nothing is written through a link; a forged or stale list of a report's files deletes nothing of the
user's; two outputs of one command are never the same file."""

from __future__ import annotations

import contextlib
import hashlib
import os
import stat
from pathlib import Path

import pytest

from builders import identity, make_special, stepping_walk, write_trc
from yoyogait import _files
from yoyogait import evaluation as ev
from yoyogait.cli import main
from yoyogait.errors import InputError, OutputError
from yoyogait.live.live import CsvRecord

MARKER = _files.MARKER


@pytest.fixture(scope="module")
def walks(tmp_path_factory) -> Path:
    """A folder with one short TRC walk (fast to estimate and evaluate)."""
    folder = tmp_path_factory.mktemp("walks")
    rec, _ = stepping_walk(step_hz=1.8)
    write_trc(folder / "walk.trc", rec)
    return folder


def one_error(capsys) -> str:
    """The single line a failed command printed on stderr (it must be one, starting 'yoyogait: error: ')."""
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1, err
    assert err[0].startswith("yoyogait: error: ") and "Traceback" not in err[0]
    return err[0]


SPECIAL_KINDS = ("null", "fifo", "socket")

WRITERS = {
    "estimate": lambda walk, out, force: ["estimate", walk, "--out", out, "--figure", "none", *force],
    "estimate --figure": lambda walk, out, force: ["estimate", walk, "--out", "x.csv", "--figure", out, *force],
    "estimate --online": lambda walk, out, force: ["estimate", walk, "--online", "--out", out, *force],
    "tune": lambda walk, out, force: ["tune", str(Path(walk).parent), "--out", out, "--trials", "1", "--no-cv", *force],
}


@pytest.mark.parametrize("kind", SPECIAL_KINDS)
@pytest.mark.parametrize("command", WRITERS)
def test_force_never_replaces_a_device_fifo_or_socket(walks, tmp_path, capsys, monkeypatch, command, kind):
    """An output path that is a character device, a FIFO or a socket is refused in one line, with or
    without --force, and the node stays as it was."""
    monkeypatch.chdir(tmp_path)
    node = make_special(tmp_path / f"node.{kind}", kind)
    before = identity(node)
    for force in ([], ["--force"]):
        assert main(WRITERS[command](str(walks / "walk.trc"), str(node), force)) == 2
        line = one_error(capsys)
        assert "not a regular file" in line and str(node) in line
        assert identity(node) == before
    assert sorted(p.name for p in tmp_path.iterdir()) == [node.name]


@pytest.mark.parametrize("kind", SPECIAL_KINDS)
def test_live_record_never_replaces_a_device_fifo_or_socket(tmp_path, kind):
    """live --record onto a device node, a FIFO or a socket is refused (also with --force); the node stays."""
    node = make_special(tmp_path / f"node.{kind}", kind)
    before = identity(node)
    for force in (False, True):
        with pytest.raises(OutputError, match="not a regular file"):
            CsvRecord(node, force=force)
    assert identity(node) == before
    assert [p.name for p in tmp_path.iterdir()] == [node.name]


@pytest.mark.parametrize("kind", SPECIAL_KINDS)
def test_a_report_folder_that_is_a_special_file_is_refused(walks, tmp_path, capsys, kind):
    """evaluate --out onto a device node, FIFO or socket is refused with one line even with --force."""
    node = make_special(tmp_path / f"node.{kind}", kind)
    before = identity(node)
    assert main(["evaluate", str(walks), "--out", str(node), "--force", "--no-figures", "-j", "1"]) == 2
    assert "--out" in one_error(capsys)
    assert identity(node) == before


def test_atomic_file_refuses_a_special_file_whoever_calls_it(tmp_path):
    """The library's own writer (also EstimatorConfig.save) refuses a FIFO as its target."""
    node = make_special(tmp_path / "fifo", "fifo")
    with pytest.raises(OutputError, match="not a regular file"):
        _files.atomic_file(node, lambda p: p.write_text("x"))
    assert stat.S_ISFIFO(os.lstat(node).st_mode) and [p.name for p in tmp_path.iterdir()] == ["fifo"]


def test_a_dangling_link_as_out_needs_force_and_then_only_the_link_is_replaced(walks, tmp_path, capsys):
    """--out a symlink to nothing: refused without --force; with --force the link itself becomes the CSV,
    nothing appears at (or beside) its target."""
    elsewhere = tmp_path / "elsewhere"
    elsewhere.mkdir()
    link = tmp_path / "out.csv"
    link.symlink_to(elsewhere / "target.csv")
    argv = ["estimate", str(walks / "walk.trc"), "--out", str(link), "--figure", "none"]
    assert main(argv) == 2
    assert "--force" in one_error(capsys) and link.is_symlink()
    assert main([*argv, "--force"]) == 0
    capsys.readouterr()
    assert not link.is_symlink() and link.is_file() and link.read_text().startswith("time_s,")
    assert list(elsewhere.iterdir()) == []


def test_a_link_to_a_file_as_out_replaces_the_link_not_its_target(walks, tmp_path, capsys):
    """--out a symlink to a user's file, with --force: the link is replaced, the file it pointed to stays."""
    precious = tmp_path / "precious.csv"
    precious.write_text("mine")
    link = tmp_path / "out.csv"
    link.symlink_to(precious)
    assert main(["estimate", str(walks / "walk.trc"), "--out", str(link), "--figure", "none", "--force"]) == 0
    capsys.readouterr()
    assert precious.read_text() == "mine" and not link.is_symlink() and link.read_text().startswith("time_s,")


def test_out_equal_to_figure_is_refused(walks, tmp_path, capsys):
    """estimate --out X --figure X (also spelled differently) is refused in one line and writes nothing."""
    for figure in ("both.png", "./sub/../both.png"):
        (tmp_path / "sub").mkdir(exist_ok=True)
        argv = ["estimate", str(walks / "walk.trc"), "--out", str(tmp_path / "both.png")]
        assert main([*argv, "--figure", str(tmp_path / figure), "--force"]) == 2
        line = one_error(capsys)
        assert "--out" in line and "--figure" in line and "same file" in line
        assert sorted(p.name for p in tmp_path.iterdir()) == ["sub"]


def test_out_equal_to_an_input_is_refused_even_with_force(walks, tmp_path, capsys):
    """--out naming the recording (directly, through a hard link, or --config's file) is refused with
    --force too, and the input stays byte for byte."""
    walk = tmp_path / "walk.trc"
    walk.write_bytes((walks / "walk.trc").read_bytes())
    hard = tmp_path / "hard.trc"
    os.link(walk, hard)
    config = tmp_path / "mine.toml"
    config.write_text("[gait_filter]\ngate_sigma = 4.0\n")
    before = walk.read_bytes(), config.read_bytes()
    cases = [
        ["estimate", str(walk), "--out", str(walk), "--figure", "none"],
        ["estimate", str(walk), "--out", str(hard), "--figure", "none"],
        ["estimate", str(walk), "--out", "x.csv", "--figure", str(walk)],
        ["estimate", str(walk), "--online", "--out", str(walk)],
        ["estimate", str(walk), "--config", str(config), "--out", str(config), "--figure", "none"],
    ]
    for argv in cases:
        assert main([*argv, "--force"]) == 2, argv
        assert "input" in one_error(capsys)
        assert (walk.read_bytes(), config.read_bytes()) == before
    assert sorted(p.name for p in tmp_path.iterdir()) == ["hard.trc", "mine.toml", "walk.trc"]


def test_tune_out_equal_to_its_storage_or_data_set_is_refused(walks, tmp_path, capsys):
    """tune --out equal to --storage, or to the manifest it tunes on, is refused before any trial."""
    storage = tmp_path / "s.db"
    manifest = tmp_path / "m.json"
    manifest.write_text('{"recordings": [{"path": "%s"}]}' % (walks / "walk.trc"))
    before = manifest.read_bytes()
    assert main(["tune", str(manifest), "--out", str(storage), "--storage", str(storage), "--trials", "1"]) == 2
    assert "same file" in one_error(capsys) and not storage.exists()
    assert main(["tune", str(manifest), "--out", str(manifest), "--trials", "1", "--force"]) == 2
    assert "input" in one_error(capsys) and manifest.read_bytes() == before


def _report(walks: Path, out: Path, capsys, *extra: str) -> int:
    code = main(["evaluate", str(walks), "--out", str(out), "--estimators", "paper", "-j", "1", *extra])
    capsys.readouterr()
    return code


def test_a_figures_folder_replaced_by_a_link_is_never_written_through(walks, tmp_path, capsys):
    """A report's figures/ replaced by a symlink to the user's folder: evaluate --force does not write,
    replace or delete anything there (it refuses in one line)."""
    out = tmp_path / "report"
    assert _report(walks, out, capsys) == 0
    names = sorted(p.name for p in (out / "figures").iterdir())
    victim = tmp_path / "victim"
    victim.mkdir()
    for name in names:
        (victim / name).write_text("the user's own")
    for p in (out / "figures").iterdir():
        p.unlink()
    (out / "figures").rmdir()
    (out / "figures").symlink_to(victim)
    assert main(["evaluate", str(walks), "--out", str(out), "--estimators", "paper", "-j", "1", "--force"]) == 2
    assert "figures" in one_error(capsys)
    assert {p.name: p.read_text() for p in victim.iterdir()} == {n: "the user's own" for n in names}
    assert (out / "figures").is_symlink()


@pytest.mark.parametrize("listing", ["names", "wrong hashes"])
def test_a_forged_list_deletes_nothing_of_the_users(walks, tmp_path, capsys, listing):
    """A .yoyogait-report edited to list the user's thesis.docx and data.csv (names alone, or with made-up
    hashes): --force neither deletes nor replaces them."""
    out = tmp_path / "report"
    assert _report(walks, out, capsys, "--no-figures") == 0
    (out / "thesis.docx").write_text("years of work")
    (out / "data.csv").write_text("the only copy")
    with open(out / MARKER, "a") as fh:
        for name in ("thesis.docx", "data.csv"):
            fh.write(f"{name}\n" if listing == "names" else f"{'0' * 64}  {name}\n")
    assert _report(walks, out, capsys, "--no-figures", "--force") == 0
    assert (out / "thesis.docx").read_text() == "years of work"
    assert (out / "data.csv").read_text() == "the only copy"
    assert "thesis.docx" not in _files.written_files(out)


def test_a_stale_list_neither_replaces_nor_deletes_a_file_the_user_changed(walks, tmp_path, capsys):
    """Files of an old report that the user has since rewritten are the user's: --force refuses to replace
    one the new report needs (one line, nothing changed) and keeps one it no longer needs."""
    out = tmp_path / "report"
    assert _report(walks, out, capsys) == 0
    figure = sorted((out / "figures").iterdir())[0]
    figure.write_text("my annotated figure")
    assert _report(walks, out, capsys, "--no-figures", "--force") == 0  # the figures are not needed now
    assert figure.read_text() == "my annotated figure"
    (out / "index.md").write_text("my notes")
    assert main(["evaluate", str(walks), "--out", str(out), "--estimators", "paper", "--force", "--no-figures"]) == 2
    line = one_error(capsys)
    assert "index.md" in line and "--out" in line
    assert (out / "index.md").read_text() == "my notes" and figure.read_text() == "my annotated figure"


def test_a_user_file_at_a_name_the_report_writes_is_not_replaced(walks, tmp_path, capsys):
    """A file the list does not name, at a name the new report writes (recordings.csv), is refused, not replaced."""
    out = tmp_path / "report"
    assert _report(walks, out, capsys, "--no-figures") == 0
    lines = [line for line in (out / MARKER).read_text().splitlines() if not line.endswith("recordings.csv")]
    (out / MARKER).write_text("\n".join(lines) + "\n")
    (out / "recordings.csv").write_text("my own table")
    assert main(["evaluate", str(walks), "--out", str(out), "--estimators", "paper", "--force", "--no-figures"]) == 2
    assert "recordings.csv" in one_error(capsys)
    assert (out / "recordings.csv").read_text() == "my own table"


def test_the_list_records_a_sha256_of_every_file(walks, tmp_path, capsys):
    """The marker lists each file with the sha256 of what yoyogait wrote (the format of sha256sum)."""
    out = tmp_path / "report"
    assert _report(walks, out, capsys) == 0
    lines = (out / MARKER).read_text().splitlines()
    assert len(lines) >= 5
    for line in lines:
        digest, name = line.split("  ", 1)
        assert hashlib.sha256((out / name).read_bytes()).hexdigest() == digest


def test_a_marker_that_is_a_link_or_a_fifo_is_not_trusted(walks, tmp_path, capsys):
    """A .yoyogait-report that is a symlink (to a real list elsewhere) or a FIFO does not make the folder
    yoyogait's: --force refuses it in one line, at once."""
    out = tmp_path / "report"
    assert _report(walks, out, capsys, "--no-figures") == 0
    real = tmp_path / "list"
    os.replace(out / MARKER, real)
    (out / MARKER).symlink_to(real)
    assert main(["evaluate", str(walks), "--out", str(out), "--estimators", "paper", "--force", "--no-figures"]) == 2
    assert MARKER in one_error(capsys)
    (out / MARKER).unlink()
    make_special(out / MARKER, "fifo")
    assert main(["evaluate", str(walks), "--out", str(out), "--estimators", "paper", "--force", "--no-figures"]) == 2
    assert MARKER in one_error(capsys)


def test_the_lock_file_is_never_followed(walks, tmp_path, capsys):
    """A symlink where the output's lock file goes (.report.lock -> the user's file): the run refuses it in
    one line and the user's file is not truncated."""
    precious = tmp_path / "precious.txt"
    precious.write_text("keep me")
    (tmp_path / ".report.lock").symlink_to(precious)
    assert main(["evaluate", str(walks), "--out", str(tmp_path / "report"), "--no-figures", "-j", "1"]) == 2
    assert ".report.lock" in one_error(capsys)
    assert precious.read_text() == "keep me"


def test_live_record_writes_no_temporary_file_through_a_link(tmp_path):
    """A symlink where a partial recording would go does not redirect the rows: they go to a new file beside
    the output, and the link's target stays untouched."""
    precious = tmp_path / "precious.txt"
    precious.write_text("keep me")
    out = tmp_path / "rec.csv"
    (tmp_path / ".rec.csv.partial").symlink_to(precious)
    rec = CsvRecord(out, columns=("time_s",), formats=("%.3f",))
    rec.write([1.0] + [0.0] * 20)
    rec.close()
    assert precious.read_text() == "keep me" and out.read_text() == "time_s\n1.000\n"


def test_out_that_is_a_link_to_nothing_is_refused_as_a_report_folder(tmp_path, capsys):
    """evaluate --out a dangling symlink: refused in one line, with or without --force; nothing appears at
    the link's target."""
    link = tmp_path / "report"
    link.symlink_to(tmp_path / "nowhere")
    for force in ([], ["--force"]):
        assert main(["evaluate", "--out", str(link), "--estimators", "default", "--no-figures", *force]) == 2
        assert "--out" in one_error(capsys)
    assert sorted(p.name for p in tmp_path.iterdir()) == ["report"] and link.is_symlink()


def test_library_write_report_keeps_the_same_rules(tmp_path):
    """ev.write_report (the library call behind evaluate) refuses a FIFO --out and a linked figures/ too."""
    evaluation = ev.evaluate(ev.synthetic_items()[:1], ("default",), dataset="synthetic", synthetic=True)
    node = make_special(tmp_path / "fifo", "fifo")
    with pytest.raises(OutputError):
        ev.write_report(evaluation, node, figures=False, force=True)
    out = tmp_path / "report"
    ev.write_report(evaluation, out, figures=False)
    victim = tmp_path / "victim"
    victim.mkdir()
    (out / "figures").symlink_to(victim)
    with contextlib.suppress(OutputError):
        ev.write_report(evaluation, out, figures="all", force=True)
    assert list(victim.iterdir()) == []


def test_input_error_and_output_error_are_both_one_line(tmp_path):
    """The checks raise yoyogait's own errors (never a bare OSError with a temporary name)."""
    node = make_special(tmp_path / "fifo", "fifo")
    with pytest.raises((InputError, OutputError)) as info:
        _files.check_output_file(node, "--out", force=True)
    assert "\n" not in str(info.value) and ".tmp." not in str(info.value)


def test_evaluate_out_holding_the_data_set_is_refused(walks, tmp_path, capsys):
    """evaluate --out naming the data set's own folder (or the folder of its manifest) is refused, also with
    --force, before anything is evaluated."""
    data = tmp_path / "data"
    data.mkdir()
    (data / "walk.trc").write_bytes((walks / "walk.trc").read_bytes())
    (data / "manifest.json").write_text('{"recordings": [{"path": "walk.trc"}]}')
    for dataset in (data, data / "manifest.json"):
        assert main(["evaluate", str(dataset), "--out", str(data), "--force", "--no-figures"]) == 2
        assert "data set" in one_error(capsys)
    assert sorted(p.name for p in data.iterdir()) == ["manifest.json", "walk.trc"]
