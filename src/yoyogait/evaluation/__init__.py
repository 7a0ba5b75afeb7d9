"""Evaluation of estimators over a data set, the way the paper did (Table I, Fig. 3-4) and more.

* :mod:`.datasets`: the synthetic lab, a folder of recordings, a manifest;
* :mod:`.running`: each recording through the pipeline and every estimator, scored;
* :mod:`.metrics`: the scores of one recording;
* :mod:`.tables`: Table I and the summary over recordings;
* :mod:`.figures`: Fig. 3/4-style figures;
* :mod:`.online`: the online evaluation (each recording frame by frame through OnlineEstimator);
* :mod:`.report`: everything written atomically into one folder;
* :mod:`.parallel`: recordings and figures in worker processes or on a Dask cluster.
"""

from __future__ import annotations

from ..estimators.registry import check_estimators, estimators
from ..estimators.results import PREDICTION_HORIZONS_S
from . import parallel
from .datasets import READABLE, Item, folder_items, manifest_items, resolve_dataset, shipped, synthetic_items
from .online import ONLINE_ESTIMATORS, ONLINE_METRIC_KEYS, OnlineEvaluation, evaluate_online, step_walk_items
from .parallel import TaskFailure, dask_executor, default_jobs
from .report import FIGURE_MODES, write_report
from .running import (
    DEFAULT_ESTIMATORS,
    RATE_HZ,
    Evaluation,
    ItemResult,
    evaluate,
    evaluate_item,
    real_reference,
    run_item,
)
from .tables import SUMMARY_KEYS, summary_markdown, table_one, table_one_csv, table_one_markdown

__all__ = [
    "DEFAULT_ESTIMATORS",
    "ONLINE_ESTIMATORS",
    "ONLINE_METRIC_KEYS",
    "OnlineEvaluation",
    "FIGURE_MODES",
    "TaskFailure",
    "dask_executor",
    "default_jobs",
    "parallel",
    "run_item",
    "shipped",
    "PREDICTION_HORIZONS_S",
    "RATE_HZ",
    "READABLE",
    "SUMMARY_KEYS",
    "Evaluation",
    "Item",
    "ItemResult",
    "check_estimators",
    "estimators",
    "evaluate",
    "evaluate_item",
    "evaluate_online",
    "folder_items",
    "manifest_items",
    "real_reference",
    "resolve_dataset",
    "step_walk_items",
    "summary_markdown",
    "synthetic_items",
    "table_one",
    "table_one_csv",
    "table_one_markdown",
    "write_report",
]
