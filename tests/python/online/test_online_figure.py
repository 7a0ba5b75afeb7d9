"""The figure of an online estimate: `estimate --online --figure`, `evaluate --online`'s report."""

from __future__ import annotations

import numpy as np
import pytest
from PIL import Image

from builders import write_two_walks
from yoyogait import OnlineEstimator, io
from yoyogait.cli import main
from yoyogait.estimators.online import InvalidReason
from yoyogait.evaluation import figures as plots


@pytest.fixture(scope="module")
def walks(tmp_path_factory):
    """A folder with two short synthetic walks as TRC files, one with stops."""
    return write_two_walks(tmp_path_factory.mktemp("walks"))


def _png_size(path):
    with Image.open(path) as im:
        return im.size


def test_estimate_online_draws_its_figure_with_the_csv_and_only_when_asked(walks, tmp_path, monkeypatch, capsys):
    """Without --figure only the CSV; with it both; a figure that cannot be written leaves neither."""
    monkeypatch.chdir(tmp_path)
    walk = str(sorted(walks.glob("*.trc"))[0])
    assert main(["estimate", walk, "--online", "--out", "a.csv"]) == 0
    assert sorted(p.name for p in tmp_path.iterdir()) == ["a.csv"]
    assert main(["estimate", walk, "--online", "--out", "b.csv", "--figure", "b.png"]) == 0
    assert "wrote b.csv and b.png" in capsys.readouterr().out
    width, height = _png_size(tmp_path / "b.png")
    assert width >= 900 and height >= 800
    # The same path twice, or a figure that exists: one line, exit 2, and no CSV either.
    assert main(["estimate", walk, "--online", "--out", "c.png", "--figure", "c.png"]) == 2
    before = (tmp_path / "b.png").read_bytes()
    assert main(["estimate", walk, "--online", "--out", "d.csv", "--figure", "b.png"]) != 0
    assert "--force" in capsys.readouterr().err
    assert (tmp_path / "b.png").read_bytes() == before and not (tmp_path / "d.csv").exists()
    assert not (tmp_path / "c.png").exists()


def test_the_figure_draws_the_estimate_solid_only_where_it_is_valid_and_names_each_reason(walks):
    """The solid line is NaN exactly where the estimate is not valid; the strip lists walking, valid
    and every reason that occurs, and nothing else."""
    rec = io.read(sorted(walks.glob("*.trc"))[1])
    res = OnlineEstimator.for_recording(rec).run(rec)
    valid = np.asarray(res.valid, dtype=bool)
    assert valid.any() and (~valid).any()
    fig = plots.online_figure(res, title="walk")
    ax_z, ax_f, ax_s, ax_v = fig.axes
    solid = next(line for line in ax_f.lines if line.get_label() == "estimate (valid)")
    assert np.array_equal(np.isnan(solid.get_ydata()), ~valid)
    reasons = np.asarray(res.invalid_reason, dtype=int)
    occurring = {r.name.lower().replace("_", " ") for r in InvalidReason if (reasons & int(r)).any()}
    assert {t.get_text() for t in ax_v.get_yticklabels()} == {"walking", "valid"} | occurring


def test_evaluate_online_draws_each_recordings_online_figure_or_the_summary(walks, tmp_path):
    """--figures all: one online figure per recording, linked from index.md; summary: the
    distributions and the best and worst recording; the oscillator (no validity) has none."""
    out = tmp_path / "all"
    assert main(["evaluate", str(walks), "--online", "--out", str(out), "--figures", "all", "--jobs", "1"]) == 0
    figures = sorted(p.name for p in (out / "figures").iterdir())
    assert figures == sorted(f"{p.name}_online.png" for p in walks.glob("*.trc"))
    index = (out / "index.md").read_text()
    assert all(f"(figures/{name})" in index for name in figures)
    out = tmp_path / "summary"
    assert main(["evaluate", str(walks), "--online", "--out", str(out), "--figures", "summary", "--jobs", "1"]) == 0
    figures = sorted(p.name for p in (out / "figures").iterdir())
    assert "distributions.png" in figures and len(figures) == 3
    assert "`online`, worst:" in (out / "index.md").read_text()


def test_with_no_estimate_valid_the_panels_limits_follow_the_estimate_so_its_line_is_in_view(walks):
    """Nothing valid and the step frequency at 3.2 Hz while walking: the panel reaches above it (the
    valid-only limits ended at 2.8 Hz and drew the grey line out of view)."""
    import dataclasses

    rec = io.read(sorted(walks.glob("*.trc"))[0])
    res = OnlineEstimator.for_recording(rec).run(rec)
    walking = np.asarray(res.walking, dtype=bool)
    assert walking.any()
    res = dataclasses.replace(
        res,
        valid=np.zeros_like(res.valid),
        step_frequency_hz=np.where(walking, 3.2, np.asarray(res.step_frequency_hz, dtype=float)),
    )
    ax_f = plots.online_figure(res, title="walk").axes[1]
    assert ax_f.get_ylim()[1] > 3.2
