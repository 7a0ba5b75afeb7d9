"""evaluate's options that do not apply to the data set or mode given: refused in one line, never ignored."""

from __future__ import annotations

import pytest

from builders import write_two_walks
from yoyogait.cli import main


@pytest.fixture(scope="module")
def walks(tmp_path_factory):
    """A folder with two short synthetic walks as TRC files."""
    return write_two_walks(tmp_path_factory.mktemp("walks"))


def test_evaluate_online_refuses_an_estimator_list_it_would_ignore(walks, tmp_path, capsys):
    """--online compares the online estimator and the oscillator: --estimators is refused in one line."""
    out = tmp_path / "r"
    assert main(["evaluate", str(walks), "--online", "--estimators", "paper", "--out", str(out)]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and "--estimators" in err[0] and "--online" in err[0]
    assert not out.exists()


def test_evaluate_refuses_a_seed_for_a_data_set_of_files(walks, tmp_path, capsys):
    """--seed draws the synthetic lab: given for a folder of recordings it is refused in one line, not ignored."""
    out = tmp_path / "r"
    assert main(["evaluate", str(walks), "--seed", "3", "--out", str(out)]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and "--seed" in err[0] and "synthetic lab" in err[0]
    assert not out.exists()
