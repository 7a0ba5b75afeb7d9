"""The command line's entry point and its demo."""

import csv
import subprocess
import sys

from yoyogait.cli import main


def test_demo_evaluates_both_presets_on_the_synthetic_lab(tmp_path, capsys):
    """`yoyogait demo` prints Table I of 'paper' and 'default' on SYNTHETIC data and writes the report."""
    assert main(["demo", "--out", str(tmp_path / "demo")]) == 0
    out = capsys.readouterr().out
    assert "SYNTHETIC" in out
    assert "Table I, estimator 'paper'" in out and "Table I, estimator 'default'" in out
    rows = list(csv.DictReader(open(tmp_path / "demo" / "recordings.csv")))
    assert {r["estimator"] for r in rows} == {"paper", "default"} and len(rows) == 30
    assert len(list((tmp_path / "demo" / "figures").glob("*.png"))) == 60


def test_bad_option_is_one_line_and_nonzero():
    """An unknown estimator gives one error line on stderr, no traceback, and exit code 2."""
    proc = subprocess.run(
        [sys.executable, "-m", "yoyogait", "demo", "--estimators", "nope"], capture_output=True, text=True
    )
    assert proc.returncode == 2
    assert "Traceback" not in proc.stderr
    assert proc.stderr.strip().count("\n") == 0 and "unknown estimator" in proc.stderr
