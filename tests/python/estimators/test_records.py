"""The per-sample records are declared once (the C++ tables): the native objects, the Python result
classes, the CSV and stream columns and docs/records.md all follow them under the same names."""

from __future__ import annotations

import dataclasses
from pathlib import Path

import numpy as np

from yoyogait import EstimatorConfig, GaitEstimator, OnlineEstimator, _core
from yoyogait.estimators.online import ONLINE_CSV_COLUMNS, ONLINE_ESTIMATE_COLUMNS, OnlineResult
from yoyogait.estimators.records import RECORDS, records_markdown
from yoyogait.estimators.results import EstimateResult
from yoyogait.live.live import ESTIMATE_COLUMNS

ROOT = Path(__file__).resolve().parents[3]


def test_every_estimate_field_is_a_result_array_and_a_native_property_under_its_table_name():
    """Each Estimate table field is an EstimateResult field (derived: a property) and a native Estimate property."""
    result_fields = {f.name for f in dataclasses.fields(EstimateResult)}
    native = GaitEstimator(EstimatorConfig()).step(1.0, 0.0)
    for f in RECORDS["Estimate"]:
        if f.type == "derived":
            assert isinstance(getattr(EstimateResult, f.name), property), f.name
        else:
            assert f.name in result_fields, f.name
        assert hasattr(native, f.name), f.name
    for f in RECORDS["Innovation"]:
        assert f.name in result_fields, f.name


def test_a_batch_run_returns_exactly_the_table_fields_of_its_scope():
    """run() gives every table field for the gait filter; for the paper those of scope all (the rest are constants)."""
    vx, vz = np.full(50, 1.2), np.zeros(50)
    for preset, scopes in (("default", {"all", "gait"}), ("paper", {"all"})):
        res = GaitEstimator(EstimatorConfig.preset(preset)).run(vx, vz, diagnostics=True)
        for f in RECORDS["Estimate"]:
            if f.type != "derived":
                value = getattr(res, f.name)
                assert value is not None or f.scope not in scopes, (preset, f.name)
        for f in RECORDS["Innovation"]:
            assert getattr(res, f.name).shape == (50,), f.name


def test_online_result_columns_are_the_online_estimate_table():
    """OnlineResult has one array per OnlineEstimate field (t_s: time_s), then the predictions; stream and CSV alike."""
    names = [f.name for f in dataclasses.fields(OnlineResult)]
    assert names[: len(ONLINE_ESTIMATE_COLUMNS)] == list(ONLINE_ESTIMATE_COLUMNS)
    assert names[len(ONLINE_ESTIMATE_COLUMNS) :] == [
        "predict_ahead_s",
        "pred_vx_mps",
        "pred_vz_mps",
        "pred_vx_std_mps",
        "pred_vz_std_mps",
    ]
    assert ESTIMATE_COLUMNS == ONLINE_ESTIMATE_COLUMNS
    assert set(ONLINE_CSV_COLUMNS) <= set(ONLINE_ESTIMATE_COLUMNS)
    e = OnlineEstimator(["p"]).update(0.0, [0.0, 0.0, 1.0])
    for f in RECORDS["OnlineEstimate"]:
        assert hasattr(e, f.name), f.name


def test_the_schema_names_carry_units_and_a_doc():
    """Every float field of every record either names its unit in its name or is dimensionless, and has a doc."""
    suffixes = ("_mps", "_m", "_s", "_hz", "_rad", "_rad_s", "_mps2", "_rad_s2")
    dimensionless = {"std_scale", "nis", "gait_phase", "state", "gait_state"}
    for record, fields in RECORDS.items():
        for f in fields:
            assert len(f.doc) > 5, (record, f.name)
            if f.type.startswith("float") or f.type == "derived":
                assert f.name.endswith(suffixes) or f.name in dimensionless, (record, f.name)
    assert set(RECORDS) == set(_core.record_schema())


def test_records_doc_is_generated_from_the_tables():
    """docs/records.md is exactly what records_markdown() generates from the C++ tables."""
    assert (ROOT / "docs" / "records.md").read_text() == records_markdown(), (
        "regenerate docs/records.md (see the comment at its top)"
    )


def test_the_imu_record_is_the_imu_estimators_table():
    """ImuEstimate in the schema lists the fields the IMU estimator's table gives, in order, each an attribute
    of the native estimate."""
    from yoyogait.estimators.imu import IMU_ESTIMATE_FIELDS, ImuOnlineEstimator

    names = [f.name for f in RECORDS["ImuEstimate"]]
    assert names == [n for n, _, _ in IMU_ESTIMATE_FIELDS]
    e = ImuOnlineEstimator().update(0.0, [0.0, 0.0, 9.81], [0.0, 0.0, 0.0])
    for name in names:
        assert hasattr(e, name), name
