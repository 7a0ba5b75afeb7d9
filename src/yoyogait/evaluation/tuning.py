"""Tuning a documented subset of the default estimator's parameters on a data set, with Optuna.

The objective of a configuration on some recordings is a weighted sum, over metrics of
:func:`yoyogait.evaluation.metrics.evaluate`, of the median over those recordings divided by the
same median for the default configuration: 1.0 is as good as the default, lower is better.

Leave-one-group-out cross-validation (a group is a manifest folder, the subject column of Table I)
measures how well tuned parameters carry over to a lab they were not tuned on: for each group, a
study tunes on the other groups and its best configuration is scored on the held-out group. With a
single group there is no other lab to hold out, so the recordings themselves are split into
:data:`K_FOLDS` folds (seeded): each fold is scored with the configuration tuned on the others,
which says how tuning carries over to recordings it did not see (from the same lab, so it is the
weaker test; the result says which was done). With a single recording nothing can be held out and
the result says so (``cross_validation``). A final study on all recordings gives the configuration
written out; its objective is measured on the recordings it was tuned on, and is labelled so.
Studies are seeded (``seed``) and, with a storage file, resumable: a study that exists there
continues up to ``n_trials``.

The velocities, references and walking parts are computed once per recording; a trial only runs
the estimator and scores it.
"""

from __future__ import annotations

import dataclasses
import math
from collections.abc import Callable
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np
import tomli_w

from ..errors import InputError
from ..estimators.config import EstimatorConfig
from ..estimators.registry import preset_runner
from .metrics import METRIC_KEYS
from .parallel import TaskFailure, run_tasks
from .running import ItemResult, run_item, score

__all__ = [
    "SEARCH_SPACE",
    "DEFAULT_WEIGHTS",
    "TUNE_EXTRA",
    "TuneResult",
    "tune",
    "objective_of",
    "config_toml",
    "parse_weights",
    "SECTION",
    "K_FOLDS",
]

K_FOLDS = 5
"""Folds of the k-fold cross-validation over recordings (fewer with fewer recordings)."""

TUNE_EXTRA = "yoyogait[tune]"

SECTION = "gait_filter"
"""The section of :class:`EstimatorConfig` that holds every tuned parameter (the default estimator's)."""

SEARCH_SPACE: dict[str, tuple[float, float, bool]] = {
    # name: (low, high, log scale); all inside what EstimatorConfig validation accepts.
    # densities: (0.01 m/s)^2 to (0.2 m/s)^2 at 25 Hz (R = density / dt)
    "meas_vx_density_m2_per_s": (4e-6, 1.6e-3, True),
    "meas_vz_density_m2_per_s": (4e-6, 1.6e-3, True),
    "q_phasor_m2_per_s3": (1e-4, 2e-2, True),
    "q_phase_rad2_per_s": (0.005, 0.5, True),
    "q_omega_rad2_per_s3": (0.005, 0.5, True),
    "q_speed_m2_per_s3": (1e-4, 1e-2, True),
    "q_harmonic_m2_per_s3": (1e-4, 1e-2, True),
    "gate_sigma": (3.0, 8.0, False),
    "radii_tau_s": (0.5, 5.0, False),
}
"""The parameters tuned (fields of the ``gait_filter`` section), with their ranges: the noise levels
of the gait filter, its innovation gate and the low-pass of the radii. The structure (bank, detector
thresholds, bounds) is left alone."""

DEFAULT_WEIGHTS: dict[str, float] = {
    "vx_sq_err_mean_1e-2": 1.0,
    "vz_sq_err_mean_1e-2": 1.0,
    "f_err_median_hz": 1.0,
    "speed_err_median_mps": 1.0,
}
"""Metric -> weight of the objective (each metric's median relative to the default's)."""


@dataclass
class TuneResult:
    """What :func:`tune` found."""

    best_params: dict
    best_objective: float
    config: EstimatorConfig
    folds: list = field(default_factory=list)  # (held-out group or fold, objective there, its recordings)
    weights: dict = field(default_factory=dict)
    n_trials: int = 0
    cross_validation: str = ""  # what was held out: "leave-one-group-out", "k-fold over recordings", or why none
    n_training: int = 0  # recordings the written configuration was tuned (and its objective measured) on


def parse_weights(specs) -> dict[str, float]:
    """``["key=w", ...]`` over :data:`DEFAULT_WEIGHTS`; InputError for a bad one."""
    weights = dict(DEFAULT_WEIGHTS)
    for spec in specs or ():
        key, sep, value = str(spec).partition("=")
        try:
            w = float(value)
        except ValueError:
            w = math.nan
        if not sep or key not in METRIC_KEYS or not (math.isfinite(w) and w >= 0):
            raise InputError(f"--weight {spec}: give METRIC=WEIGHT with a metric of the report's CSV and a weight >= 0")
        weights[key] = w
    if not any(w > 0 for w in weights.values()):
        raise InputError("--weight: at least one weight must be above 0")
    return {k: w for k, w in weights.items() if w > 0}


def _prepared(items, jobs: int) -> list[ItemResult]:
    """Each item's velocities and reference, once (no estimator run)."""
    out = run_tasks(run_item, [(item, ()) for item in items], jobs=jobs, progress="preparing")
    kept = [r for r in out if not isinstance(r, TaskFailure)]
    if not kept:
        raise InputError("no recording could be prepared for tuning")
    return kept


def _metrics_of(config: EstimatorConfig, prepared: list[ItemResult]) -> list[dict]:
    runner = preset_runner(config)
    rows = []
    for r in prepared:
        copy = dataclasses.replace(r, results={}, metrics={})
        score(copy, "tuned", runner(r.velocities))
        rows.append(copy.metrics["tuned"])
    return rows


def _medians(rows: list[dict], weights: dict) -> dict:
    out = {}
    for key in weights:
        v = np.array([m.get(key, np.nan) for m in rows], dtype=float)
        out[key] = float(np.nanmedian(v)) if np.isfinite(v).any() else math.nan
    return out


def objective_of(medians: dict, baseline: dict, weights: dict) -> float:
    """Weighted sum of each metric's median relative to the baseline's (1.0: as good as it)."""
    total = 0.0
    for key, w in weights.items():
        m, b = medians.get(key, math.nan), baseline.get(key, math.nan)
        if not (math.isfinite(m) and math.isfinite(b)) or b <= 0:
            continue
        total += w * m / b
    weight_sum = sum(w for k, w in weights.items() if math.isfinite(baseline.get(k, math.nan)) and baseline[k] > 0)
    return total / weight_sum if weight_sum else math.inf


def _study(optuna, name: str, storage, seed: int):
    sampler = optuna.samplers.TPESampler(seed=seed)
    return optuna.create_study(
        study_name=name, storage=storage, sampler=sampler, direction="minimize", load_if_exists=True
    )


def _optimise(optuna, study, prepared, weights, n_trials: int, on_trial: Callable | None):
    baseline = _medians(_metrics_of(EstimatorConfig(), prepared), weights)

    def objective(trial) -> float:
        params = {
            name: trial.suggest_float(name, low, high, log=log) for name, (low, high, log) in SEARCH_SPACE.items()
        }
        config = tuned_config(params)  # validated: an InputError here would be a range it does not accept
        value = objective_of(_medians(_metrics_of(config, prepared), weights), baseline, weights)
        if on_trial:
            on_trial(study.study_name, trial.number, value)
        return value

    if not study.trials:
        # The default first: the configuration written out is never worse than it on the data tuned on.
        defaults = getattr(EstimatorConfig(), SECTION)
        study.enqueue_trial({name: getattr(defaults, name) for name in SEARCH_SPACE})
    done = sum(1 for t in study.trials if t.state == optuna.trial.TrialState.COMPLETE)
    if n_trials > done:
        study.optimize(objective, n_trials=n_trials - done)
    return study.best_trial


def tune(
    items,
    *,
    n_trials: int = 50,
    seed: int = 0,
    weights: dict | None = None,
    storage: str | Path | None = None,
    cross_validate: bool = True,
    jobs: int = 1,
    on_trial: Callable | None = None,
) -> TuneResult:
    """Tune :data:`SEARCH_SPACE` of the default estimator on ``items`` (see the module's text).

    ``storage``: an SQLite file for the studies (resumable); ``on_trial(study, number, value)`` is
    called after each trial.
    """
    try:
        import optuna
    except ImportError:
        raise InputError(f"tuning needs Optuna: pip install '{TUNE_EXTRA}'") from None
    optuna.logging.set_verbosity(optuna.logging.WARNING)
    weights = dict(weights or DEFAULT_WEIGHTS)
    if n_trials < 1:
        raise InputError(f"--trials must be at least 1, not {n_trials}")
    url = f"sqlite:///{Path(storage).resolve()}" if storage else None
    prepared = _prepared(items, jobs)
    splits, how = _splits(prepared, seed) if cross_validate else ([], "none: not asked for (--no-cv)")
    folds = []
    for name, train, held in splits:
        study = _study(optuna, f"yoyogait-tune-without-{name}", url, seed)
        best = _optimise(optuna, study, train, weights, n_trials, on_trial)
        config = tuned_config(best.params)
        baseline = _medians(_metrics_of(EstimatorConfig(), held), weights)
        value = objective_of(_medians(_metrics_of(config, held), weights), baseline, weights)
        folds.append((name, value, len(held)))
    study = _study(optuna, "yoyogait-tune-all", url, seed)
    best = _optimise(optuna, study, prepared, weights, n_trials, on_trial)
    config = tuned_config(best.params)
    return TuneResult(
        dict(best.params), float(best.value), config, folds, weights, n_trials, how, n_training=len(prepared)
    )


def _splits(prepared: list[ItemResult], seed: int) -> tuple[list, str]:
    """(name, training recordings, held-out recordings) of each fold, and what kind of cross-validation."""
    groups = sorted({r.item.subject for r in prepared})
    if len(groups) > 1:
        return [
            (g, [r for r in prepared if r.item.subject != g], [r for r in prepared if r.item.subject == g])
            for g in groups
        ], "leave-one-group-out"
    if len(prepared) < 2:
        return [], f"none: one recording in one group ({groups[0]}), nothing to hold out"
    k = min(K_FOLDS, len(prepared))
    order = np.random.default_rng(seed).permutation(len(prepared))
    out = []
    for i in range(k):
        held_idx = set(order[i::k].tolist())
        out.append(
            (
                f"fold{i + 1}of{k}",
                [r for j, r in enumerate(prepared) if j not in held_idx],
                [r for j, r in enumerate(prepared) if j in held_idx],
            )
        )
    return out, f"k-fold over recordings ({k} folds; one group, {groups[0]}: no other lab to hold out)"


def tuned_config(params: dict) -> EstimatorConfig:
    """The default configuration with ``params`` (names of :data:`SEARCH_SPACE`) set, validated."""
    return EstimatorConfig().with_values({SECTION: dict(params)})


def config_toml(result: TuneResult) -> str:
    """The tuned configuration as TOML, as :meth:`EstimatorConfig.save` writes it (every field; it
    loads with :meth:`EstimatorConfig.from_file` and ``--config``), after comments with the
    objective, weights and cross-validation."""
    lines = [
        "# yoyogait tune: the default estimator with the parameters below tuned.",
        f"# objective on the {result.n_training} training recordings it was tuned on (not held out; weighted median "
        f"metrics relative to the default, lower is better): {result.best_objective:.4g}",
        "# weights: " + ", ".join(f"{k}={w:g}" for k, w in result.weights.items()),
        f"# cross-validation: {result.cross_validation}",
    ]
    for group, value, n in result.folds:
        lines.append(f"# held out {group} ({n} recordings): objective {value:.4g} when tuned on the others")
    lines += [f"# tuned ({SECTION}): " + ", ".join(sorted(result.best_params)), ""]
    return "\n".join(lines) + "\n" + tomli_w.dumps(result.config.to_dict())
