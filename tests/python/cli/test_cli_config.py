"""`--config FILE` on the command line: estimate and evaluate with a configuration from a TOML file."""

from __future__ import annotations

import csv

import numpy as np
import pytest

from builders import write_trc
from yoyogait import EstimatorConfig, synthetic
from yoyogait.cli import main


@pytest.fixture(scope="module")
def walk_dir(tmp_path_factory):
    """A folder with one short synthetic walk as TRC and a configuration file."""
    d = tmp_path_factory.mktemp("walk")
    walk = synthetic.make_walk(synthetic.SUBJECTS[0], "1-straight", duration_s=12.0)
    write_trc(d / "w.trc", walk.recording)
    cfg = EstimatorConfig()
    cfg.gait_filter.gate_sigma = 4.0
    cfg.save(d / "mine.toml")
    return d


def test_estimate_with_config_file(walk_dir, tmp_path, capsys, monkeypatch):
    """`estimate --config FILE` runs the configured estimator; with --preset too, or a bad file: one error line."""
    monkeypatch.chdir(tmp_path)
    assert main(["estimate", str(walk_dir / "w.trc"), "--config", str(walk_dir / "mine.toml"), "--figure", "none"]) == 0
    data = np.genfromtxt(tmp_path / "w.trc.estimate.csv", delimiter=",", names=True)
    assert data.size > 250 and np.all(np.isfinite(data["step_frequency_hz"]))
    capsys.readouterr()
    both = ["estimate", str(walk_dir / "w.trc"), "--preset", "paper", "--config", str(walk_dir / "mine.toml")]
    assert main([*both, "--force"]) == 2
    assert "not both" in capsys.readouterr().err
    bad = tmp_path / "bad.toml"
    bad.write_text("[gait_filter]\ngate_max_consecutive_s = 18446744073709551616\n")
    assert main(["estimate", str(walk_dir / "w.trc"), "--config", str(bad), "--out", "x.csv"]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and "bad.toml" in err[0] and "gait_filter.gate_max_consecutive_s" in err[0]
    assert not (tmp_path / "x.csv").exists()


def test_evaluate_with_config_file_adds_an_estimator(walk_dir, tmp_path):
    """`evaluate --config FILE` evaluates the file's configuration beside the presets, named by the file's stem."""
    out = tmp_path / "report"
    argv = ["evaluate", str(walk_dir), "--out", str(out), "--estimators", "paper", "--no-figures"]
    assert main([*argv, "--config", str(walk_dir / "mine.toml")]) == 0
    rows = list(csv.DictReader(open(out / "recordings.csv")))
    assert sorted({r["estimator"] for r in rows}) == ["mine", "paper"]


def test_config_prints_the_effective_configuration_that_reads_back(walk_dir, tmp_path, capsys):
    """`yoyogait config` prints every field and the [online] table as TOML; read back by --config it prints the same."""
    assert main(["config", "--config", str(walk_dir / "mine.toml")]) == 0
    text = capsys.readouterr().out
    assert "gate_sigma = 4.0" in text and "[online]" in text and "heading_tau_s = 0.5" in text
    saved = tmp_path / "effective.toml"
    saved.write_text(text)
    assert main(["config", "--config", str(saved)]) == 0
    assert capsys.readouterr().out == text
    assert main(["config", "--preset", "paper"]) == 0
    assert 'algorithm = "paper"' in capsys.readouterr().out
    assert main(["config", "--preset", "paper", "--config", str(saved)]) == 2
    assert "not both" in capsys.readouterr().err


def test_online_commands_take_the_online_table_of_a_config_file(walk_dir, tmp_path, capsys, monkeypatch):
    """`estimate --online --config` runs the front-end the file's [online] table sets (a change shows in the CSV)."""
    monkeypatch.chdir(tmp_path)
    tuned = tmp_path / "slow_heading.toml"
    tuned.write_text("[online]\nheading_tau_s = 2.0\nmeas_position_std_m = 0.01\n")
    trc = str(walk_dir / "w.trc")
    assert main(["estimate", "--online", trc, "--out", "plain.csv"]) == 0
    assert main(["estimate", "--online", trc, "--config", str(tuned), "--out", "tuned.csv"]) == 0
    plain = np.genfromtxt(tmp_path / "plain.csv", delimiter=",", names=True)
    changed = np.genfromtxt(tmp_path / "tuned.csv", delimiter=",", names=True)
    assert plain.dtype.names == changed.dtype.names and plain.size == changed.size
    assert not np.allclose(plain["vx_mps"], changed["vx_mps"], equal_nan=True)
    capsys.readouterr()
    bad = tmp_path / "bad_online.toml"
    bad.write_text("[online]\nmax_gap_s = 0.0\n")
    assert main(["estimate", "--online", trc, "--config", str(bad), "--out", "x.csv"]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and "bad_online.toml" in err[0] and "online.max_gap_s" in err[0]
    assert not (tmp_path / "x.csv").exists()
