"""The configuration: one declaration (the C++ tables) behind the Python dataclasses, ranges on every
field, TOML files, and the generated docs/configuration.md."""

from __future__ import annotations

import dataclasses
import math
from pathlib import Path

import numpy as np
import pytest

import yoyogait
from yoyogait import EstimatorConfig, GaitEstimator, _core
from yoyogait.estimators.config import (
    IMU_SECTION,
    ONLINE_SECTION,
    SCHEMA,
    SECTIONS,
    GaitFilterConfig,
    ImuConfig,
    OnlineConfig,
    PaperConfig,
    schema_markdown,
)
from yoyogait.estimators.records import RECORDS

ESTIMATOR_SCHEMA = [spec for spec in SCHEMA if spec.section not in (ONLINE_SECTION, IMU_SECTION)]
ONLINE_SCHEMA = [spec for spec in SCHEMA if spec.section == ONLINE_SECTION]

ROOT = Path(__file__).resolve().parents[3]
PY_TYPES = {"float": float, "int": int, "bool": bool, "float_list": tuple, "str": str}


def _with(cfg: EstimatorConfig, spec, value) -> EstimatorConfig:
    """cfg with one field (shared or in its section) set to value, unchecked."""
    if not spec.section:
        return dataclasses.replace(cfg, **{spec.name: value})
    section = dataclasses.replace(getattr(cfg, spec.section), **{spec.name: value})
    return dataclasses.replace(cfg, **{spec.section: section})


def _walk(seconds=6.0, seed=0):
    """A short noisy Yoyo-model walk at 25 Hz with a NaN and an outlier."""
    t = np.arange(1, int(seconds / 0.04) + 1) * 0.04
    m = yoyogait.yoyo_model(t, 0.12, 0.02, 1.8)
    rng = np.random.default_rng(seed)
    vx = m.vx_mps + 0.03 * rng.standard_normal(t.size)
    vz = m.vz_mps + 0.03 * rng.standard_normal(t.size)
    vx[40] = np.nan
    vz[90] += 2.0
    return t, vx, vz


#: Every float output of an estimate (from its record table) and the predictions.
FLOAT_OUTPUTS = (*(f.name for f in RECORDS["Estimate"] if f.type.startswith("float") and f.scope == "all"),
                 "vx_hat_h2_mps", "vz_hat_h2_mps", "std_scale", "vx_pred", "vz_pred")  # fmt: skip


def test_python_dataclasses_agree_with_the_cpp_tables_field_by_field():
    """Each section's dataclass has the C++ table's fields in its order, with its type, default and doc."""
    raw = _core.config_schema()
    tables = {
        section: [d for d in raw if d["section"] == section] for section in ("", *SECTIONS, ONLINE_SECTION, IMU_SECTION)
    }
    classes = {"": EstimatorConfig, "paper_estimator": PaperConfig, "gait_filter": GaitFilterConfig}
    classes[ONLINE_SECTION] = OnlineConfig
    classes[IMU_SECTION] = ImuConfig
    for section, cls in classes.items():
        own = [f for f in dataclasses.fields(cls) if f.name not in (*SECTIONS, "estimator")]
        assert [f.name for f in own] == [d["name"] for d in tables[section]], section
        defaults = cls()
        for f, d in zip(own, tables[section]):
            assert f.type == PY_TYPES[d["type"]].__name__, f.name
            assert getattr(defaults, f.name) == d["default"], f.name
            assert f.metadata["schema"].doc == d["doc"] and len(d["doc"]) > 10, f.name
            assert f.metadata["schema"].unit == d["unit"], f.name
    assert [f.name for f in dataclasses.fields(EstimatorConfig)][-2:] == list(SECTIONS)


def test_every_field_outside_its_range_is_a_value_error_naming_it():
    """Just outside each end of each numeric field's range is rejected with ValueError naming section.field."""
    for spec in SCHEMA:
        if spec.type not in ("float", "int"):
            continue
        below = math.nextafter(spec.min, -math.inf) if spec.min_inclusive else spec.min
        above = math.nextafter(spec.max, math.inf) if spec.max_inclusive else spec.max
        if spec.type == "int":
            below, above = int(spec.min) - 1, int(spec.max) + 1
        for value in (below, above):
            if math.isinf(value):
                continue
            with pytest.raises(ValueError, match=rf"{spec.path}\b"):
                if spec.section == ONLINE_SECTION:
                    OnlineConfig(**{spec.name: value}).validate()
                elif spec.section == IMU_SECTION:
                    ImuConfig(**{spec.name: value}).validate()
                else:
                    GaitEstimator(_with(EstimatorConfig(), spec, value))


@pytest.mark.parametrize("value", [2**63, 2**64, 2**100, -1, 1.5, True, "3"])
def test_integer_fields_reject_bad_values_with_value_error(value):
    """An integer field given 2**64 (or a negative, a float, a bool, a string) raises ValueError, not TypeError."""
    for spec in ESTIMATOR_SCHEMA:
        if spec.type == "int":
            with pytest.raises(ValueError, match=spec.path):
                _with(EstimatorConfig(), spec, value).validate()


def _sweep_values(default):
    scaled = [default * k for k in (1e-9, 1e-6, 1e-3, 1e3, 1e6, 1e9)]
    return scaled + [5e-324, 1e300, 1.8e308, -default, -1e300, 0.0, math.inf, math.nan]


def test_every_float_field_over_absurd_values_gives_an_error_or_finite_estimates():
    """Each float field at 1e-9..1e9 times its default and at the extremes (5e-324, 1e300, 1.8e308,
    negative, inf, NaN) either raises ValueError or gives finite estimates on a short walk, both presets."""
    t, vx, vz = _walk()
    accepted = rejected = 0
    for spec in ESTIMATOR_SCHEMA:
        if spec.type == "float":
            values = _sweep_values(spec.default)
        elif spec.type == "float_list":
            values = [tuple(v * k for v in spec.default) for k in (1e-9, 1e-3, 1e3, 1e9)] + [(5e-324,), (1.8e308,)]
        elif spec.type == "int":
            values = [0, 1, int(spec.max), int(spec.max) + 1, 2**63, 2**64]
        else:
            continue
        for value in values:
            for preset in ("paper", "default"):
                cfg = _with(EstimatorConfig.preset(preset), spec, value)
                try:
                    est = GaitEstimator(cfg)
                except ValueError:
                    rejected += 1
                    continue
                accepted += 1
                res = est.run(vx, vz, time_s=t, predict_ahead_s=(0.04, 0.2))
                for name in FLOAT_OUTPUTS:
                    assert np.all(np.isfinite(getattr(res, name))), (spec.path, value, preset, name)
                if preset == "default":
                    assert np.all(np.isfinite(res.gait_state)), (spec.path, value)
                    assert np.all(np.isfinite(est.covariance)), (spec.path, value)
    assert accepted > 500 and rejected > 500  # both branches are exercised


def test_dict_and_toml_round_trips(tmp_path):
    """to_dict/from_dict and save/from_file give back an equal configuration; a partial file keeps the defaults."""
    cfg = EstimatorConfig.paper()
    cfg.paper_estimator.q_bias_mps2 = 2e-3
    cfg.gait_filter = dataclasses.replace(cfg.gait_filter, bank_f_hz=(1.0, 2.0), gate_max_consecutive_s=0.36)
    assert EstimatorConfig.from_dict(cfg.to_dict()) == cfg
    path = tmp_path / "cfg.toml"
    cfg.save(path)
    assert EstimatorConfig.from_file(path) == cfg
    with pytest.raises(ValueError, match="exists"):
        cfg.save(path)
    cfg.save(path, force=True)
    partial = tmp_path / "partial.toml"
    partial.write_text("[gait_filter]\ngate_sigma = 4\nbank_f_hz = [1.0, 1.5, 2.0]\n")
    loaded = EstimatorConfig.from_file(partial)
    assert loaded.gait_filter.gate_sigma == 4.0 and loaded.gait_filter.bank_f_hz == (1.0, 1.5, 2.0)
    assert loaded.algorithm == "gait_filter" and loaded.paper_estimator == PaperConfig()
    assert GaitEstimator(loaded).run(*_walk()[1:]).step_frequency_hz.size == 150


@pytest.mark.parametrize(
    "text, message",
    [
        ("gate_sigma = 3\n", r"gate_sigma \(did you mean gait_filter.gate_sigma\?\)"),
        ("[gait_filter]\ngate_sigmaa = 3\n", r"unknown estimator parameter\(s\) in \[gait_filter\]: gate_sigmaa"),
        ('[gait_filter]\ngate_sigma = "3"\n', "gait_filter.gate_sigma must be a number"),
        ("[gait_filter]\ngate_max_consecutive_s = 18446744073709551615\n", "gait_filter.gate_max_consecutive_s"),
        (
            "[paper_estimator]\nsmoothing_window_samples = 18446744073709551615\n",
            "paper_estimator.smoothing_window_samples",
        ),
        ("[gait_filter]\nspectral_buffer_s = 20.0\n", "gait_filter.spectral_buffer_s must hold 1 to 256 samples"),
        ("[paper_estimator]\nv_vx_mps2 = 0.0\n", r"paper_estimator.v_vx_mps2 = 0.0 is outside its valid range"),
        ('algorithm = "kalman"\n', "algorithm must be one of"),
        ("sample_time_s = = 1\n", "not a valid TOML file"),
        ("gait_filter = 3\n", "gait_filter must be a table"),
    ],
)
def test_bad_config_files_name_the_file_and_the_field(tmp_path, text, message):
    """A config file with an unknown, mistyped or out-of-range field raises ValueError naming the file and field."""
    path = tmp_path / "bad.toml"
    path.write_text(text)
    with pytest.raises(ValueError, match=message) as info:
        EstimatorConfig.from_file(path)
    assert str(path) in str(info.value)
    with pytest.raises(ValueError, match="no such file"):
        EstimatorConfig.from_file(tmp_path / "missing.toml")


def test_online_settings_share_the_toml_file_in_an_online_table(tmp_path):
    """OnlineConfig saves and loads the estimator fields and an [online] table; EstimatorConfig reads that file."""
    cfg = OnlineConfig(meas_position_std_m=0.004, heading_tau_s=0.8)
    cfg.estimator.gait_filter.gate_sigma = 4.0
    path = tmp_path / "online.toml"
    cfg.save(path)
    assert "[online]" in path.read_text()
    assert OnlineConfig.from_file(path) == cfg
    assert EstimatorConfig.from_file(path) == cfg.estimator
    partial = tmp_path / "partial.toml"
    partial.write_text("[online]\nmax_gap_s = 0.5\n")
    assert OnlineConfig.from_file(partial) == OnlineConfig(max_gap_s=0.5)
    bad = tmp_path / "bad.toml"
    bad.write_text("[online]\nheading_tau = 0.5\n")
    with pytest.raises(ValueError, match=r"bad.toml: unknown estimator parameter\(s\) in \[online\]: heading_tau"):
        OnlineConfig.from_file(bad)
    bad.write_text("[online]\nmax_gap_s = -1.0\n")
    with pytest.raises(ValueError, match=r"online.max_gap_s = -1.0 is outside its valid range"):
        OnlineConfig.from_file(bad)


def test_configuration_doc_is_generated_from_the_schema():
    """docs/configuration.md is exactly what schema_markdown() generates from the C++ tables."""
    doc = (ROOT / "docs" / "configuration.md").read_text()
    assert doc == schema_markdown(), "regenerate docs/configuration.md (see the comment at its top)"
    for spec in SCHEMA:
        assert f"| `{spec.name}` |" in doc
