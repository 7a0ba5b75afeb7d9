"""The command line's entry point and its demo."""

import subprocess
import sys

from yoyogait.cli import main


def test_demo_reports_the_synthetic_walk_it_recovered(capsys):
    """`yoyogait demo` says the data are synthetic and recovers the step frequency and R of the walk."""
    assert main(["demo"]) == 0
    out = capsys.readouterr().out
    assert "SYNTHETIC" in out
    row = next(line for line in out.splitlines() if line.startswith("step_frequency_hz"))
    truth, estimate = map(float, row.split()[1:3])
    assert abs(estimate - truth) < 0.02 * truth
    row = next(line for line in out.splitlines() if line.startswith("R_m"))
    truth, estimate = map(float, row.split()[1:3])
    assert abs(estimate - truth) < 0.05 * truth


def test_bad_option_is_one_line_and_nonzero():
    """An unknown preset gives one error line on stderr, no traceback, and exit code 2."""
    proc = subprocess.run([sys.executable, "-m", "yoyogait", "demo", "--preset", "nope"],
                          capture_output=True, text=True)
    assert proc.returncode == 2
    assert "Traceback" not in proc.stderr
    assert proc.stderr.strip().count("\n") == 0 and "unknown preset" in proc.stderr
