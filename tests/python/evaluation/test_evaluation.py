"""Evaluation toolkit: data sets, Table I, report writing, and the evaluate/estimate/demo commands."""

from __future__ import annotations

import csv
import json
import math
import subprocess
import sys

import numpy as np
import pytest

from builders import write_trc
from yoyogait import evaluation as ev
from yoyogait.cli import main


@pytest.fixture(scope="module")
def lab_evaluation():
    items = ev.synthetic_items()
    return ev.evaluate(items, ("paper",), dataset="synthetic", synthetic=True)


def test_pooling_equals_statistics_of_the_union():
    """Pooled mean and std of groups equal those of all their samples together."""
    rng = np.random.default_rng(0)
    groups = [rng.normal(m, s, n) for m, s, n in ((1.0, 0.5, 100), (3.0, 2.0, 40), (0.0, 0.1, 7))]
    pooled = ev.tables._pool([(g.size, g.mean(), g.std()) for g in groups])
    union = np.concatenate(groups)
    assert pooled == pytest.approx((union.mean(), union.std()), rel=1e-12)


def test_table_one_has_a_cell_per_walk_component_and_subject(lab_evaluation):
    """Table I on the lab: 5 walk types x (v_x, v_z) rows, 3 subject columns, every cell finite."""
    subjects, rows = ev.table_one(lab_evaluation, "paper")
    assert len(subjects) == 3 and all("synthetic" in s for s in subjects)
    assert len(rows) == 10 and [r[1] for r in rows] == ["vx", "vz"] * 5
    for _, _, cells in rows:
        assert all(c is not None and math.isfinite(c[0]) and math.isfinite(c[1]) and c[1] >= 0 for c in cells)
    md = ev.table_one_markdown(lab_evaluation, "paper").splitlines()
    assert len(md) == 12 and all(line.count("|") == 5 for line in md)


def test_table_cell_matches_the_recordings_metric(lab_evaluation):
    """A Table I cell with one recording equals that recording's mean and std of the squared error."""
    subjects, rows = ev.table_one(lab_evaluation, "paper")
    walk, comp, cells = rows[0]
    r = next(r for r in lab_evaluation.items if r.item.walk == walk and r.item.subject == subjects[0])
    m = r.metrics["paper"]
    assert cells[0] == pytest.approx((m["vx_sq_err_mean_1e-2"], m["vx_sq_err_std_1e-2"]))
    # And the metric is the paper's: mean of (vx_hat_mps - vx)^2 over the walking part, times 100.
    res, vel = r.results["paper"], r.velocities
    w = r.walking & np.isfinite(vel.vx)
    assert m["vx_sq_err_mean_1e-2"] == pytest.approx(100 * np.mean((res.vx_hat_mps[w] - vel.vx[w]) ** 2), rel=1e-9)


def test_report_is_complete_and_never_overwritten_without_force(lab_evaluation, tmp_path):
    """The report holds Table I (md, csv), a CSV row per recording, two PNGs per recording and an index;
    it is replaced only with force, and then only the files yoyogait wrote."""
    out = tmp_path / "report"
    ev.write_report(lab_evaluation, out)
    assert (out / "table1_paper.md").stat().st_size > 0
    rows = list(csv.DictReader(open(out / "recordings.csv")))
    assert len(rows) == 15 and all(r["estimator"] == "paper" for r in rows)
    assert all(math.isfinite(float(r["vz_sq_err_mean_1e-2"])) for r in rows)
    pngs = sorted((out / "figures").glob("*.png"))
    assert len(pngs) == 30 and all(p.stat().st_size > 5000 for p in pngs)
    index = (out / "index.md").read_text()
    assert "SYNTHETIC" in index and all(f"figures/{p.name}" in index for p in pngs)
    (out / "mine.txt").write_text("mine")
    with pytest.raises(OSError, match="--force"):
        ev.write_report(lab_evaluation, out, figures=False)
    assert (out / "mine.txt").read_text() == "mine" and len(list((out / "figures").glob("*.png"))) == 30
    ev.write_report(lab_evaluation, out, figures=False, force=True)
    assert (out / "mine.txt").read_text() == "mine"  # the user's file stays
    assert not (out / "figures").exists()  # the old report's figures went with it
    assert [p.name for p in tmp_path.iterdir()] == ["report"]  # no temporary folder left


def test_interrupted_report_leaves_nothing(lab_evaluation, tmp_path, monkeypatch):
    """A failure while writing leaves neither the output folder nor a temporary one."""

    def boom(*a, **k):
        raise KeyboardInterrupt

    monkeypatch.setattr(ev.report, "_figures", boom)
    with pytest.raises(KeyboardInterrupt):
        ev.write_report(lab_evaluation, tmp_path / "report")
    assert list(tmp_path.iterdir()) == []


def test_evaluate_command_on_synthetic_lab(tmp_path, capsys):
    """`yoyogait evaluate` writes the report and prints Table I for each estimator."""
    out = tmp_path / "ev"
    assert main(["evaluate", "synthetic", "--out", str(out), "--estimators", "paper", "--no-figures"]) == 0
    text = capsys.readouterr().out
    assert "Table I, estimator 'paper'" in text and "SYNTHETIC" in text
    assert (out / "recordings.csv").is_file() and not (out / "figures").exists()
    assert main(["evaluate", "synthetic", "--out", str(out), "--estimators", "paper"]) == 2
    assert "use --force" in capsys.readouterr().err


def test_evaluate_rejects_empty_folder_and_unknown_estimator(tmp_path, capsys):
    """An empty folder or an unknown estimator is one error line and exit 2, with nothing written."""
    empty = tmp_path / "empty"
    empty.mkdir()
    assert main(["evaluate", str(empty), "--out", str(tmp_path / "o")]) == 2
    assert "no recordings" in capsys.readouterr().err
    assert main(["evaluate", "--estimators", "paper,nope", "--out", str(tmp_path / "o")]) == 2
    assert "unknown estimator" in capsys.readouterr().err
    assert not (tmp_path / "o").exists()


def test_manifest_with_missing_files_reports_each_and_evaluates_the_rest(tmp_path, capsys):
    """Missing manifest entries are each reported, the others evaluated, and the exit code is 1."""
    from yoyogait import synthetic

    walk = synthetic.make_walk(synthetic.SUBJECTS[0], "1-straight", duration_s=12.0)
    write_trc(tmp_path / "walk.trc", walk.recording)
    manifest = {
        "recordings": [
            {
                "path": "walk.trc",
                "format": "trc",
                "vertical_axis": "z",
                "pelvis": list(synthetic.PELVIS_MARKERS),
                "feet": list(synthetic.HEEL_MARKERS),
                "walk": "straight",
            },
            {"path": "gone1.c3d", "format": "c3d", "walk": "straight"},
            {"path": "sub/gone2.bvh", "format": "bvh", "walk": "turn"},
        ]
    }
    (tmp_path / "m.json").write_text(json.dumps(manifest))
    out = tmp_path / "out"
    assert main(["evaluate", str(tmp_path / "m.json"), "--out", str(out), "--estimators", "paper", "--no-figures"]) == 1
    err = capsys.readouterr().err
    assert "gone1.c3d" in err and "gone2.bvh" in err
    rows = list(csv.DictReader(open(out / "recordings.csv")))
    assert [r["recording"] for r in rows] == ["walk.trc"]
    assert "gone1.c3d" in (out / "index.md").read_text()


def test_estimate_command_writes_csv_and_figure_once(tmp_path, capsys, monkeypatch):
    """`yoyogait estimate` writes the estimates as CSV and a figure, and refuses to overwrite without --force."""
    from yoyogait import synthetic

    walk = synthetic.make_walk(synthetic.SUBJECTS[1], "1-straight", duration_s=15.0)
    write_trc(tmp_path / "w.trc", walk.recording)
    monkeypatch.chdir(tmp_path)
    assert main(["estimate", "w.trc", "--preset", "paper"]) == 0
    data = np.genfromtxt(tmp_path / "w.trc.estimate.csv", delimiter=",", names=True)
    assert data.size > 300 and np.all(np.isfinite(data["step_frequency_hz"]))
    assert np.all(np.diff(data["time_s"]) > 0)
    assert (tmp_path / "w.trc.estimate.png").stat().st_size > 5000
    capsys.readouterr()
    assert main(["estimate", "w.trc", "--preset", "paper"]) == 2
    assert "use --force" in capsys.readouterr().err
    assert main(["estimate", "w.trc", "--preset", "paper", "--force"]) == 0
    assert sorted(p.name for p in tmp_path.iterdir()) == ["w.trc", "w.trc.estimate.csv", "w.trc.estimate.png"]


def test_estimate_missing_file_is_one_line(tmp_path):
    """A missing file gives one error line, no traceback, exit 2, and no output file."""
    proc = subprocess.run(
        [sys.executable, "-m", "yoyogait", "estimate", str(tmp_path / "nope.c3d")],
        capture_output=True,
        text=True,
        cwd=tmp_path,
    )
    assert proc.returncode == 2 and "Traceback" not in proc.stderr
    assert len(proc.stderr.strip().splitlines()) == 1
    assert list(tmp_path.iterdir()) == []


def test_evaluate_on_three_real_recordings(manifest, datasets_dir, tmp_path):
    """evaluate on three real recordings of the shared manifest: tables well formed, numbers finite, figures written."""
    chosen = [
        r
        for r in manifest["recordings"]
        if r["path"]
        in (
            "c3d_org_samples/sample09_PlugInC3D.c3d",
            "opensim_models/Rajagopal_motion_capture_walk.trc",
            "bandai_namco_motion/dataset-1_walk_normal_001.bvh",
        )
    ]
    assert len(chosen) == 3
    sub = tmp_path / "data"
    sub.mkdir()
    m = {"recordings": [{**r, "path": str((datasets_dir / r["path"]).resolve())} for r in chosen]}
    (sub / "manifest.json").write_text(json.dumps(m))
    items, missing, synthetic = ev.resolve_dataset(str(sub / "manifest.json"))
    assert not missing and not synthetic and len(items) == 3
    result = ev.evaluate(items, ("paper",))
    assert not result.failures
    for r in result.items:
        m = r.metrics["paper"]
        for key in ("vx_sq_err_mean_1e-2", "vz_sq_err_mean_1e-2", "pred200ms_vx_sq_err_mean_1e-2"):
            assert math.isfinite(m[key]), (r.item.name, key)
    out = ev.write_report(result, tmp_path / "report")
    assert len(list((out / "figures").glob("*.png"))) == 6
    assert len(list(csv.DictReader(open(out / "recordings.csv")))) == 3


def test_outputs_get_the_users_default_permissions(lab_evaluation, tmp_path):
    """Reports and files written through a temporary name end with the permissions the umask gives, not private ones."""
    import os

    from yoyogait._files import atomic_file

    mask = os.umask(0o022)
    try:
        out = ev.write_report(lab_evaluation, tmp_path / "report", figures=False)
        atomic_file(tmp_path / "x.csv", lambda p: p.write_text("a\n"))
    finally:
        os.umask(mask)
    assert out.stat().st_mode & 0o777 == 0o755
    assert (out / "recordings.csv").stat().st_mode & 0o777 == 0o644
    assert (tmp_path / "x.csv").stat().st_mode & 0o777 == 0o644
