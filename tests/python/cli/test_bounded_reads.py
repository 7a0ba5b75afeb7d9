"""Reads that are bounded: a configuration file or a manifest is read only if it is a regular file under
its size limit, parsed to a bounded depth, and every problem is one line of bounded length naming the
file, the entry and the field; a bad manifest entry is skipped like a missing file, repeated entries are
evaluated once, report names are unique per recording and escaped in index.md."""

from __future__ import annotations

import json
import os
import re
import subprocess
import sys
import time
from pathlib import Path

import pytest

from builders import make_special, stepping_walk, write_trc
from yoyogait import EstimatorConfig
from yoyogait import evaluation as ev
from yoyogait.cli import main
from yoyogait.errors import InputError

LINE_MAX = 1000
"""The longest error line a bad file may give (characters; a long value is shortened)."""


@pytest.fixture(scope="module")
def walk(tmp_path_factory) -> Path:
    """One short TRC walk."""
    folder = tmp_path_factory.mktemp("walk")
    rec, _ = stepping_walk(step_hz=1.8)
    write_trc(folder / "walk.trc", rec)
    return folder / "walk.trc"


def run_cli(*argv: str, timeout_s: float = 60.0) -> subprocess.CompletedProcess:
    """yoyogait in a subprocess, killed after ``timeout_s`` (a read that blocks or never ends fails the test
    instead of hanging it)."""
    try:
        return subprocess.run(
            [sys.executable, "-m", "yoyogait", *argv], capture_output=True, text=True, timeout=timeout_s
        )
    except subprocess.TimeoutExpired:
        pytest.fail(f"yoyogait {' '.join(argv)} did not finish within {timeout_s} s")


def check_one_line(proc: subprocess.CompletedProcess, *names: str) -> str:
    """The run failed with exit 2 and one bounded stderr line naming each of ``names``."""
    lines = proc.stderr.strip().splitlines()
    assert proc.returncode == 2, proc.stderr[-2000:]
    assert len(lines) == 1 and lines[0].startswith("yoyogait: error: "), proc.stderr[-2000:]
    assert len(lines[0]) <= LINE_MAX + 100, len(lines[0])
    for name in names:
        assert name in lines[0], lines[0]
    return lines[0]


# --------------------------------------------------------------------------------------- configurations


def deep_toml(kind: str, depth: int) -> str:
    if kind == "arrays":
        return "x = " + "[" * depth + "]" * depth + "\n"
    if kind == "inline tables":
        return "x = " + "{a = " * depth + "1" + "}" * depth + "\n"
    return "x." + ".".join("a" for _ in range(depth)) + " = 1\n"  # dotted keys


@pytest.mark.parametrize("kind", ["arrays", "inline tables", "dotted keys"])
def test_a_deeply_nested_configuration_is_one_line(walk, tmp_path, kind):
    """A TOML file nested 100,000 deep (arrays, inline tables, dotted keys) is one line naming the file and
    the depth limit, at once."""
    cfg = tmp_path / "deep.toml"
    cfg.write_text(deep_toml(kind, 100_000))
    proc = run_cli("estimate", str(walk), "--config", str(cfg), "--out", str(tmp_path / "o.csv"), "--figure", "none")
    line = check_one_line(proc, str(cfg))
    assert "nested" in line and "Traceback" not in proc.stderr
    assert not (tmp_path / "o.csv").exists()


@pytest.mark.parametrize("kind", ["zero", "urandom", "null", "fifo", "socket"])
def test_a_configuration_that_is_not_a_regular_file_is_refused_at_once(walk, tmp_path, kind):
    """--config a device node (like /dev/zero, /dev/urandom, /dev/null), a FIFO with no writer or a socket:
    one line naming the file, within seconds (nothing read from it, nothing waited for)."""
    node = make_special(tmp_path / f"cfg.{kind}", kind)
    t0 = time.monotonic()
    proc = run_cli(
        "estimate", str(walk), "--config", str(node), "--out", str(tmp_path / "o.csv"), "--figure", "none", timeout_s=30
    )
    assert time.monotonic() - t0 < 30
    line = check_one_line(proc, str(node))
    assert "not a regular file" in line


def test_a_configuration_over_the_size_limit_is_refused_at_once(walk, tmp_path):
    """A 100 MB configuration (a sparse file) is refused by its size before it is read: one line naming the
    file and the limit."""
    cfg = tmp_path / "huge.toml"
    with open(cfg, "wb") as fh:
        fh.truncate(100_000_000)
    t0 = time.monotonic()
    proc = run_cli("estimate", str(walk), "--config", str(cfg), "--out", str(tmp_path / "o.csv"), "--figure", "none")
    assert time.monotonic() - t0 < 30
    line = check_one_line(proc, str(cfg))
    assert "1 MiB" in line


def test_a_long_value_gives_a_short_error_line(walk, tmp_path):
    """A field set to an array of 100,000 numbers (under the size limit): the error names the file and the
    field and is one line of bounded length, the value shortened."""
    cfg = tmp_path / "long.toml"
    cfg.write_text("[gait_filter]\ngate_sigma = [" + ", ".join("1" for _ in range(100_000)) + "]\n")
    proc = run_cli("estimate", str(walk), "--config", str(cfg), "--out", str(tmp_path / "o.csv"), "--figure", "none")
    check_one_line(proc, str(cfg), "gate_sigma")


def test_from_file_keeps_working_for_a_good_configuration(tmp_path):
    """A configuration as save() writes it reads back equal (the bounded reader changes nothing else)."""
    cfg = EstimatorConfig()
    cfg.gait_filter.gate_sigma = 4.0
    cfg.save(tmp_path / "mine.toml")
    assert EstimatorConfig.from_file(tmp_path / "mine.toml") == cfg
    with pytest.raises(InputError, match="no such file"):
        EstimatorConfig.from_file(tmp_path / "absent.toml")


# --------------------------------------------------------------------------------------------- manifests


def write_manifest(path: Path, entries) -> Path:
    path.write_text(json.dumps({"recordings": entries}))
    return path


def test_a_deeply_nested_manifest_is_one_line(tmp_path):
    """A manifest nested 100,000 deep: one line naming the manifest and the depth limit, no traceback."""
    m = tmp_path / "deep.json"
    m.write_text('{"recordings": ' + "[" * 100_000 + "]" * 100_000 + "}")
    proc = run_cli("evaluate", str(m), "--out", str(tmp_path / "r"))
    line = check_one_line(proc, str(m))
    assert "nested" in line and not (tmp_path / "r").exists()


@pytest.mark.parametrize("kind", ["zero", "fifo", "socket"])
def test_a_manifest_that_is_not_a_regular_file_is_refused_at_once(tmp_path, kind):
    """A manifest .json that is a device node, a FIFO or a socket: one line naming it, within seconds."""
    node = make_special(tmp_path / "m.json", kind)
    proc = run_cli("evaluate", str(node), "--out", str(tmp_path / "r"), timeout_s=30)
    assert "not a regular file" in check_one_line(proc, str(node))


def test_a_manifest_over_the_size_limit_is_refused_at_once(tmp_path):
    """A 100 MB manifest (sparse) is refused by its size: one line naming it and the limit."""
    m = tmp_path / "m.json"
    with open(m, "wb") as fh:
        fh.truncate(100_000_000)
    proc = run_cli("evaluate", str(m), "--out", str(tmp_path / "r"))
    assert "64 MiB" in check_one_line(proc, str(m))


BAD_ENTRIES = [
    ({"path": "walk.trc", "length_unit_m": "abc"}, "length_unit_m"),
    ({"path": "walk.trc", "length_unit_m": -1}, "length_unit_m"),
    ({"path": "walk.trc", "vertical_axis": "q"}, "vertical_axis"),
    ({"path": "walk.trc", "pelvis": 5}, "pelvis"),
    ({"path": "walk.trc", "feet": "LHEE"}, "feet"),
    ({"path": "walk.trc", "walk": ["a"]}, "walk"),
    ({"path": 5}, "path"),
    ({"path": ""}, "path"),
    ("walk.trc", "entry"),
]


def test_bad_entries_are_reported_and_skipped_the_rest_evaluated(walk, tmp_path, capsys):
    """Each bad entry (a wrong length_unit_m, vertical_axis, pelvis, feet, walk or path) is one problem
    naming the entry's index, its path and the field; the good entry is still evaluated."""
    (tmp_path / "walk.trc").write_bytes(walk.read_bytes())
    entries = [{"path": "walk.trc"}] + [e for e, _ in BAD_ENTRIES]
    m = write_manifest(tmp_path / "m.json", entries)
    items, problems = ev.manifest_items(m)
    assert [it.name for it in items] == ["walk.trc"]
    assert len(problems) == len(BAD_ENTRIES)
    for k, ((entry, field), (name, message)) in enumerate(zip(BAD_ENTRIES, problems), start=1):
        text = f"{name}: {message}"
        assert f"entry {k}" in text and field in text and "\n" not in text, text
        if isinstance(entry, dict) and isinstance(entry.get("path"), str) and entry["path"]:
            assert entry["path"] in text
    assert main(["evaluate", str(m), "--out", str(tmp_path / "r"), "--no-figures", "-j", "1"]) == 1
    err = capsys.readouterr().err
    assert "Traceback" not in err and err.count("not evaluated") == len(BAD_ENTRIES)
    assert (tmp_path / "r" / "index.md").is_file()


def test_repeated_entries_are_evaluated_once_and_reported_once(walk, tmp_path):
    """The same file listed three times (also as ./walk.trc) is evaluated once; the repeats are one problem."""
    (tmp_path / "walk.trc").write_bytes(walk.read_bytes())
    m = write_manifest(tmp_path / "m.json", [{"path": "walk.trc"}, {"path": "./walk.trc"}, {"path": "walk.trc"}])
    items, problems = ev.manifest_items(m)
    assert len(items) == 1
    assert len(problems) == 1 and "entry 0" in problems[0][0] and "entries 1, 2" in problems[0][1]
    missing = write_manifest(tmp_path / "m2.json", [{"path": "gone.trc"}] * 5)
    items, problems = ev.manifest_items(missing)
    assert items == [] and len(problems) == 1


def test_same_named_files_in_two_folders_get_their_own_names_and_figures(tmp_path, capsys):
    """a/walk.trc and b/walk.trc: two recordings with folder-qualified names, each with its own figures,
    and index.md links each to its own."""
    for sub, step_hz in (("a", 1.6), ("b", 2.0)):
        (tmp_path / sub).mkdir()
        rec, _ = stepping_walk(step_hz=step_hz)
        write_trc(tmp_path / sub / "walk.trc", rec)
    m = write_manifest(tmp_path / "m.json", [{"path": "a/walk.trc"}, {"path": "b/walk.trc"}])
    items, _ = ev.manifest_items(m)
    assert len({it.name for it in items}) == 2
    folder_names = [it.name for it in ev.datasets.folder_items(tmp_path)]
    assert len(set(folder_names)) == 2
    out = tmp_path / "r"
    assert main(["evaluate", str(m), "--out", str(out), "--estimators", "paper", "-j", "1"]) == 0
    capsys.readouterr()
    figures = sorted(p.name for p in (out / "figures").iterdir())
    assert len(figures) == 4, figures
    index = (out / "index.md").read_text()
    links = [line for line in index.splitlines() if "walk.trc" in line and "figures/" in line]
    assert len(links) == 2 and links[0] != links[1]
    for line in links:
        for target in line.split("](")[1:]:
            assert (out / target.split(")")[0]).is_file()


def test_400000_missing_entries_are_summarised(walk, tmp_path):
    """400,000 entries whose files are missing: stderr and index.md give the count and the first few, not
    hundreds of megabytes; the good entry is evaluated."""
    (tmp_path / "walk.trc").write_bytes(walk.read_bytes())
    entries = [{"path": "walk.trc"}] + [{"path": f"gone/{k:06d}.trc"} for k in range(400_000)]
    m = write_manifest(tmp_path / "m.json", entries)
    out = tmp_path / "r"
    proc = run_cli("evaluate", str(m), "--out", str(out), "--estimators", "paper", "--no-figures", "-j", "1")
    assert proc.returncode == 1, proc.stderr[-2000:]
    assert len(proc.stderr) < 20_000 and "400000" in proc.stderr.replace(",", "")
    assert (out / "index.md").stat().st_size < 100_000
    only_missing = write_manifest(tmp_path / "m2.json", entries[1:])
    proc = run_cli("evaluate", str(only_missing), "--out", str(tmp_path / "r2"), "--no-figures")
    check_one_line(proc, "400000")


def test_names_cannot_inject_markdown_into_the_index(tmp_path, capsys):
    """File, folder and walk names with Markdown and HTML in them appear in index.md as text: no link, image,
    HTML tag or broken code span that the names did not come with."""
    markdown_it = pytest.importorskip("markdown_it", reason="markdown-it-py renders the index to check it")
    folder = tmp_path / "s](javascript:alert(1))"
    folder.mkdir()
    name = "w`<img src=x onerror=alert(1)>`[x](javascript:alert(2))|*b*.trc"
    rec, _ = stepping_walk(step_hz=1.8)
    write_trc(folder / name, rec)
    m = write_manifest(
        tmp_path / "m.json",
        [{"path": f"{folder.name}/{name}", "walk": "<script>alert(1)</script>|`x`"}, {"path": "gone`<b>x</b>.trc"}],
    )
    out = tmp_path / "r"
    assert main(["evaluate", str(m), "--out", str(out), "--estimators", "paper", "-j", "1"]) == 1
    capsys.readouterr()
    html = markdown_it.MarkdownIt("commonmark").enable("table").render((out / "index.md").read_text())
    for bad in ("<img", "<script", "<b>"):
        assert bad not in html, bad
    links = re.findall(r'href="([^"]*)"', html)
    assert links and all(link.startswith("figures/") or link == "not_evaluated.csv" for link in links), links
    for table in out.glob("table1_*.md"):
        rendered = markdown_it.MarkdownIt("commonmark").enable("table").render(table.read_text())
        assert "<script" not in rendered


def test_marker_sets_file_is_read_bounded_too(tmp_path):
    """$YOYOGAIT_MARKER_SETS naming a FIFO is refused in one line instead of waiting for a writer."""
    from yoyogait.pipeline import points

    node = make_special(tmp_path / "sets.json", "fifo")
    code = (
        "from yoyogait.pipeline import points\n"
        "try:\n    points.find_pelvis(['LASI', 'RASI'])\nexcept Exception as e:\n    print(type(e).__name__, e)\n"
    )
    env = {**os.environ, points.MARKER_SETS_ENV: str(node)}
    try:
        proc = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, timeout=30, env=env)
    except subprocess.TimeoutExpired:
        pytest.fail("reading a FIFO as the marker sets file blocked")
    assert "not a regular file" in proc.stdout, proc.stdout + proc.stderr
