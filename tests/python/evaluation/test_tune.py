"""`yoyogait tune`: a configuration that validates and loads, leave-one-group-out folds, the same
result for the same seed, and studies that continue from their storage file."""

from __future__ import annotations

import json
import math

import pytest

from yoyogait import evaluation as ev
from yoyogait.cli import main
from yoyogait.estimators.config import EstimatorConfig
from yoyogait.evaluation import tuning

optuna = pytest.importorskip("optuna", reason="Optuna is not installed (yoyogait[tune])")

CHOSEN = (
    "c3d_org_samples/MAC_Walk1.c3d",
    "c3d_org_samples/sample09_PlugInC3D.c3d",
    "opensim_models/Rajagopal_motion_capture_walk.trc",
    "bandai_namco_motion/dataset-2_walk-turn-left_normal_001.bvh",
)


@pytest.fixture(scope="module")
def three_groups(manifest, datasets_dir, tmp_path_factory):
    """Four short real recordings from three folders (three groups)."""
    chosen = [r for r in manifest["recordings"] if r["path"] in CHOSEN]
    folder = tmp_path_factory.mktemp("tune")
    doc = {"recordings": [{**r, "path": str((datasets_dir / r["path"]).resolve())} for r in chosen]}
    (folder / "manifest.json").write_text(json.dumps(doc))
    return folder / "manifest.json"


def test_tune_writes_a_loadable_configuration_with_one_fold_per_group(three_groups, tmp_path, capsys):
    """The TOML loads into an EstimatorConfig that validates, with the tuned values in their ranges;
    one held-out fold per folder is reported."""
    out = tmp_path / "tuned.toml"
    args = ["tune", str(three_groups), "--out", str(out), "--trials", "2", "--jobs", "1"]
    assert main(args) == 0
    text = capsys.readouterr().out
    assert text.count("held out ") == 3 and "cross-validation: leave-one-group-out" in text
    assert "objective on the 4 training recordings (tuned on them, not held out)" in text
    config = EstimatorConfig.from_file(out)
    config.validate()
    section = getattr(config, tuning.SECTION)
    for name, (low, high, _) in tuning.SEARCH_SPACE.items():
        assert low <= getattr(section, name) <= high, name
    assert main(args) == 2  # exists: not replaced without --force


def test_same_seed_same_result_and_storage_resumes(three_groups, tmp_path):
    """Two runs with one seed find the same parameters; a run on the same storage continues the
    studies up to the new number of trials instead of starting over."""
    items, _, _ = ev.resolve_dataset(str(three_groups))
    a = tuning.tune(items, n_trials=2, seed=3, cross_validate=False)
    b = tuning.tune(items, n_trials=2, seed=3, cross_validate=False)
    assert a.best_params == b.best_params and a.best_objective == b.best_objective
    db = tmp_path / "studies.db"
    tuning.tune(items, n_trials=2, seed=3, cross_validate=False, storage=db)
    tuning.tune(items, n_trials=3, seed=3, cross_validate=False, storage=db)
    study = optuna.load_study(study_name="yoyogait-tune-all", storage=f"sqlite:///{db}")
    assert len(study.trials) == 3


def test_objective_is_one_for_the_baseline_and_weights_are_checked():
    """The objective of the baseline's own medians is 1; a bad --weight is one error."""
    medians = {"vx_sq_err_mean_1e-2": 0.2, "f_err_median_hz": 0.03}
    assert tuning.objective_of(medians, medians, {"vx_sq_err_mean_1e-2": 1.0, "f_err_median_hz": 2.0}) == 1.0
    better = {"vx_sq_err_mean_1e-2": 0.1, "f_err_median_hz": 0.03}
    assert math.isclose(
        tuning.objective_of(better, medians, {"vx_sq_err_mean_1e-2": 1.0, "f_err_median_hz": 1.0}), 0.75
    )
    assert tuning.parse_weights(["f_err_median_hz=3"])["f_err_median_hz"] == 3.0
    with pytest.raises(ValueError, match="--weight"):
        tuning.parse_weights(["nonsense=1"])


def _one_group(manifest, datasets_dir, tmp_path, paths):
    chosen = [r for r in manifest["recordings"] if r["path"] in paths]
    doc = {"recordings": [{**r, "path": str((datasets_dir / r["path"]).resolve())} for r in chosen]}
    (tmp_path / "manifest.json").write_text(json.dumps(doc))
    return tmp_path / "manifest.json"


def test_one_group_is_cross_validated_over_its_recordings(manifest, datasets_dir, tmp_path, capsys):
    """One folder of three recordings: a 3-fold split of the recordings, said so, each fold held out once."""
    paths = [r["path"] for r in manifest["recordings"] if r["path"].startswith("bandai_namco_motion/")][:3]
    path = _one_group(manifest, datasets_dir, tmp_path, paths)
    out = tmp_path / "tuned.toml"
    assert main(["tune", str(path), "--out", str(out), "--trials", "1", "--jobs", "1"]) == 0
    text = capsys.readouterr().out
    assert "cross-validation: k-fold over recordings (3 folds; one group, bandai_namco_motion" in text
    assert text.count("held out fold") == 3 and text.count("(1 recordings)") == 3
    assert "# cross-validation: k-fold over recordings" in out.read_text()


def test_one_recording_cannot_be_cross_validated_and_says_so(manifest, datasets_dir, tmp_path, capsys):
    """One recording: no fold, one line saying why, and the objective labelled as on the training recording."""
    path = _one_group(manifest, datasets_dir, tmp_path, ["c3d_org_samples/MAC_Walk1.c3d"])
    out = tmp_path / "tuned.toml"
    assert main(["tune", str(path), "--out", str(out), "--trials", "1", "--jobs", "1"]) == 0
    text = capsys.readouterr().out
    assert "cross-validation: none: one recording in one group (c3d_org_samples), nothing to hold out" in text
    assert "held out" not in text.replace("not held out", "")
    assert "objective on the 1 training recordings (tuned on them, not held out)" in text
