"""The per-sample records, as their C++ tables declare them: ``Estimate`` and ``Innovation``
(include/yoyogait/estimate.hpp), ``OnlineEstimate`` (include/yoyogait/online/online_estimate.hpp).

Each field is declared once there (type, name with its unit, doc); the native structs, the bindings'
properties and batch columns, :class:`~yoyogait.estimators.results.EstimateResult`,
:class:`~yoyogait.estimators.online.OnlineResult`, the CSV and stream columns and docs/records.md
follow the tables (a test holds the Python classes and the doc to them).
"""

from __future__ import annotations

from dataclasses import dataclass

from .. import _core

__all__ = ["RECORDS", "RecordField", "fields_of", "records_markdown"]


@dataclass(frozen=True)
class RecordField:
    """One field of a record."""

    name: str
    type: str  # "float", "bool", "uint8" (codes, counts), "float[k]" (a state vector), "derived" (computed when read)
    unit: str
    scope: str  # "all", or "gait": only the gait filter carries something new (the paper's is a constant)
    doc: str


RECORDS: dict[str, tuple[RecordField, ...]] = {
    name: tuple(RecordField(**dict(f)) for f in fields) for name, fields in _core.record_schema().items()
}
"""Every record by name, its fields in the table's order."""


def fields_of(record: str) -> tuple[RecordField, ...]:
    """The fields of one record (``Estimate``, ``Innovation``, ``OnlineEstimate``, ``ImuEstimate``)."""
    return RECORDS[record]


_TITLES = {
    "Estimate": "`Estimate`: what both estimators report after each sample (`GaitEstimator.step`, the "
    "arrays of `EstimateResult`)",
    "Innovation": "`Innovation`: the diagnostics of a step (`diagnostics=True`)",
    "OnlineEstimate": "`OnlineEstimate`: what the online estimator reports per frame (`OnlineEstimator.update`, "
    "the arrays of `OnlineResult`, the LSL estimate stream; the field `t_s` is the column `time_s`)",
    "ImuEstimate": "`ImuEstimate`: what the lower-back IMU estimator reports per sample (`ImuOnlineEstimator.update`, "
    "the arrays of `ImuResult`, the IMU estimate stream; the field `t_s` is the column `time_s`)",
}


def records_markdown() -> str:
    """docs/records.md: every field of every record with its type, unit, scope and doc."""
    lines = [
        "# Records",
        "",
        "<!-- Generated from the C++ tables (include/yoyogait/estimate.hpp, online/online_estimate.hpp,",
        "     imu/imu_estimate.hpp) by",
        "     python -c 'import sys, yoyogait.estimators.records as r; sys.stdout.write(r.records_markdown())' \\",
        "     > docs/records.md",
        "     and checked by tests/python/estimators/test_records.py. -->",
        "",
        "Every per-sample record is declared once, as a table in the C++ core; the C++ struct, the Python",
        "properties and arrays, the CSV and stream columns follow it under the same names. Scope `gait`: only",
        "the default estimator (the gait filter) carries something of its own there; the paper's value is a",
        "constant (`vx_hat_h2_mps` = `vx_hat_mps`, `std_scale` 1, `walking` true, `acquiring` false).",
    ]
    for record, fields in RECORDS.items():
        lines += ["", f"## {_TITLES.get(record, record)}", "", "| field | type | unit | scope | what it is |"]
        lines.append("|---|---|---|---|---|")
        for f in fields:
            doc = f.doc.replace("|", "\\|")
            lines.append(f"| `{f.name}` | {f.type} | {f.unit or '-'} | {f.scope} | {doc} |")
    return "\n".join(lines) + "\n"
