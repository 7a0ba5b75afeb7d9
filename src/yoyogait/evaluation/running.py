"""Running estimators over a data set: each item through the paper's pipeline, every estimator on
the same velocities, each scored against the truth (synthetic) or the gait events (real data).

Each item goes through the paper's pipeline (:func:`yoyogait.gait_velocities` at 25 Hz), every
estimator runs on the same velocities, and :func:`yoyogait.evaluation.metrics.evaluate` scores it.
"""

from __future__ import annotations

import time
from dataclasses import dataclass, field
from typing import Any

import numpy as np

from .._sample_time import RESAMPLE_RATE_HZ
from ..errors import InputError
from ..estimators.registry import check_estimators, estimators
from ..estimators.results import PREDICTION_HORIZONS_S
from ..pipeline import events
from ..pipeline.signals import moving_mean
from ..pipeline.velocities import gait_velocities
from . import metrics
from .datasets import Item
from .figures import recording_conditions
from .parallel import TaskFailure, run_tasks, split_outcomes

__all__ = [
    "ItemResult",
    "Evaluation",
    "evaluate_item",
    "run_item",
    "score",
    "evaluate",
    "real_reference",
    "RATE_HZ",
    "DEFAULT_ESTIMATORS",
    "STAGES",
]

RATE_HZ = RESAMPLE_RATE_HZ  # 1 / the estimator's sample_time_s: the paper's 25 Hz (Sec. IV-A)
DEFAULT_ESTIMATORS = ("paper", "default")
STAGES = ("read", "velocities", "events", "estimators", "metrics")
"""The stages of one item, as timed in :attr:`ItemResult.timings_s` (wall time, seconds)."""


@dataclass
class ItemResult:
    """An item's velocities, reference and, per estimator, its result and metrics."""

    item: Item
    velocities: object
    reference_step_frequency_hz: np.ndarray
    reference_speed_mps: np.ndarray
    walking: np.ndarray
    dft_step_frequency_hz: float
    reference_quality: events.ReferenceQuality = events.NO_REFERENCE  # real data: how far the reference holds
    conditions: tuple = ()  # "treadmill", "markerless": named in the figures' titles
    results: dict = field(default_factory=dict)  # estimator -> result
    metrics: dict = field(default_factory=dict)  # estimator -> metric dict
    timings_s: dict = field(default_factory=dict)  # stage (STAGES) -> wall time spent on it [s]


@dataclass
class Evaluation:
    """Everything :func:`evaluate` found, and what it could not evaluate."""

    estimators: tuple
    items: list  # ItemResult
    failures: list  # (item name, message)
    dataset: str
    synthetic: bool
    figure_failures: list = field(default_factory=list)  # (figure, message), filled by write_report
    figure_time_s: float = 0.0  # time spent drawing figures, summed over the processes that drew them

    def rows(self) -> list[dict]:
        """One flat row per recording and estimator (the per-recording CSV)."""
        out = []
        for r in self.items:
            for est in self.estimators:
                reference: dict[str, Any] = (
                    {"reference_origin": "synthetic truth", "reference_trusted": True}
                    if r.item.truth is not None
                    else r.reference_quality.as_row()
                )
                if r.item.truth is None:
                    reference["reference_cadence_steps_per_min"] = 60.0 * r.reference_quality.cadence_hz
                out.append(
                    {
                        "recording": r.item.name,
                        "subject": r.item.subject,
                        "walk": r.item.walk,
                        "estimator": est,
                        "synthetic": r.item.synthetic,
                        **r.metrics[est],
                        "cadence_steps_per_min": _cadence_steps_per_min(r, est),
                        **reference,
                    }
                )
        return out


def _cadence_steps_per_min(r: ItemResult, est: str) -> float:
    """The estimator's cadence as clinicians give it: 60 x the median |step frequency| while walking
    (steps/min; NaN without an estimate there)."""
    result = r.results.get(est)
    f = getattr(result, "step_frequency_hz", None)
    if f is None:
        return float("nan")
    f = np.abs(np.asarray(f, dtype=float))
    walk = np.asarray(r.walking, dtype=bool)
    if f.shape != walk.shape:
        return float("nan")
    f = f[walk & np.isfinite(f)]
    return 60.0 * float(np.median(f)) if f.size else float("nan")


def _stride_mean(values: np.ndarray, rate_hz: float, window_s: float) -> np.ndarray:
    """Centred moving mean over ``window_s`` that ignores NaN (the stride-averaged speed); NaN where
    under 80 % of the window is known."""
    n = max(1, int(round(window_s * rate_hz)))
    known = np.convolve(np.isfinite(values).astype(float), np.ones(n), mode="same")
    return np.where(known >= 0.8 * n, moving_mean(values, n), np.nan)


#: The walking part a real reference scores: "gait" from gait initiation to termination (a step before
#: the first contact and after the last: :func:`yoyogait.pipeline.events.reference_events`), or
#: "half-step", half a step either side of the contacts, the walking part the online targets were
#: first measured on (docs/online.md, section 7).
WALKING_PARTS = ("gait", "half-step")
#: The walking part scored unless asked otherwise.
DEFAULT_WALKING_PART = WALKING_PARTS[0]


def check_walking_part(walking_part: str) -> None:
    """ValueError unless ``walking_part`` is one of :data:`WALKING_PARTS`."""
    if walking_part not in WALKING_PARTS:
        raise ValueError(f"walking_part must be one of {', '.join(WALKING_PARTS)}, not {walking_part!r}")


def real_reference(recording, vel, item: Item, *, walking_part: str = DEFAULT_WALKING_PART):
    """(step frequency, stride-averaged speed, walking, quality) on the velocity grid, from gait events.

    The events are the file's own where it holds enough foot strikes, else the foot contacts
    (:func:`yoyogait.pipeline.events.reference_events`); the gait events ``vel`` holds serve when they
    were found from the same foot points.  The step frequency is the cadence of the steps with
    left-right alternation averaged out (:meth:`~yoyogait.pipeline.events.GaitEvents.step_frequency_at`
    with ``stride_average``): a missed contact (a stride) or a doubled one does not halve or double it.
    The quality (:func:`yoyogait.pipeline.events.reference_quality`) says whether it can be trusted.
    ``walking_part``: one of :data:`WALKING_PARTS`.
    """
    check_walking_part(walking_part)
    t = vel.time_s
    walking = np.asarray(vel.walking, dtype=bool)
    f_ref = np.full(t.shape, np.nan)
    found = getattr(vel, "gait_events", None)
    own = events.file_gait_events(recording)
    usable = own is None or len(own.step_start_s) < events.MIN_TRUSTED_STEPS - 1
    if usable and found is not None and len(found.step_start_s) and found.feet == events.feet_of(recording, item.feet):
        ev = found
    else:
        ev = events.reference_events(recording, item.feet, up_axis=vel.up_axis)
    quality = events.reference_quality(ev, t, vel.vz, vel.rate_hz)
    if ev is not None and len(ev.step_start_s) >= 1:
        f_ref = ev.step_frequency_at(t, stride_average=True)
        in_walk = np.zeros(t.shape, dtype=bool)
        for a, b in _walking_segments(ev, walking_part):
            in_walk |= (t >= a) & (t <= b)
        if in_walk.any():
            walking = in_walk & np.isfinite(vel.vx) & np.isfinite(vel.vz)
    # Stride = two steps; 1.1 s is a stride at 1.8 Hz, used where no step frequency is known.
    f_typ = np.nanmedian(f_ref) if np.isfinite(f_ref).any() else 1.8
    speed = _stride_mean(vel.vx, vel.rate_hz, 2.0 / f_typ)
    return f_ref, speed, walking, quality


def _walking_segments(ev, walking_part: str) -> np.ndarray:
    """The events' walking stretches (k x 2), or, for "half-step", each narrowed to half a mean step
    either side of its first and last contact."""
    segments = np.asarray(ev.walking_segments_s, dtype=float).reshape(-1, 2)
    if walking_part == DEFAULT_WALKING_PART:
        return segments
    starts, ends = np.asarray(ev.step_start_s, dtype=float), np.asarray(ev.step_end_s, dtype=float)
    out = []
    for a, b in segments:
        inside = (starts >= a) & (ends <= b)
        if inside.any():
            half = 0.5 * float(np.mean(ends[inside] - starts[inside]))
            out.append((max(a, starts[inside].min() - half), min(b, ends[inside].max() + half)))
    return np.asarray(out, dtype=float).reshape(-1, 2)


def evaluate_item(item: Item, names=DEFAULT_ESTIMATORS, *, rate_hz: float = RATE_HZ, configs=None) -> ItemResult:
    """Load one item, take its velocities by the paper's pipeline, run and score every estimator
    (``configs``: further configurations by name, see :func:`~yoyogait.estimators.registry.estimators`).

    The wall time of each stage (:data:`STAGES`) is in the result's ``timings_s``.
    """
    clock = time.perf_counter
    timings = dict.fromkeys(STAGES, 0.0)
    t0 = clock()
    recording = item.load()
    t1 = clock()
    timings["read"] = t1 - t0
    point = item.pelvis if item.pelvis else None
    vel = gait_velocities(recording, point=point, rate_hz=rate_hz, up_axis=item.up_axis)
    t0 = clock()
    timings["velocities"] = t0 - t1
    t = vel.time_s
    quality = events.NO_REFERENCE
    if item.truth is not None:
        tr = item.truth.at(t)
        f_ref, speed_ref = tr.step_frequency_hz, tr.speed_mps
        walking = np.asarray(tr.walking, dtype=bool) & np.isfinite(vel.vx) & np.isfinite(vel.vz)
    else:
        f_ref, speed_ref, walking, quality = real_reference(recording, vel, item)
    if not walking.any():
        walking = np.isfinite(vel.vx) & np.isfinite(vel.vz)
    t1 = clock()
    timings["events"] = t1 - t0
    dft = metrics.dft_step_frequency_hz(t[walking], vel.vz[walking]) if walking.sum() > 10 else float("nan")
    conditions = recording_conditions(recording, vel)
    out = ItemResult(
        item, vel, f_ref, speed_ref, walking, dft, reference_quality=quality, conditions=conditions, timings_s=timings
    )
    runners = estimators(configs)
    t0 = clock()
    timings["metrics"] += t0 - t1
    for name in names:
        res = runners[name](out.velocities)
        t1 = clock()
        timings["estimators"] += t1 - t0
        score(out, name, res)
        t0 = clock()
        timings["metrics"] += t0 - t1
    return out


def score(out: ItemResult, name: str, res) -> None:
    """Score an estimator's result on the item (its velocities and reference) into ``out``."""
    vel: Any = out.velocities
    out.results[name] = res
    out.metrics[name] = metrics.evaluate(
        vel.time_s,
        vel.vx,
        vel.vz,
        res,
        truth=out.item.truth,
        walking=out.walking,
        reference_step_frequency_hz=out.reference_step_frequency_hz,
        reference_speed_mps=out.reference_speed_mps,
        predicted_1step=res.aligned_prediction(PREDICTION_HORIZONS_S[0]),
        predicted_200ms=res.aligned_prediction(PREDICTION_HORIZONS_S[1]),
        skip_s=3.0,
    )


def outcome(evaluate_one, item: Item, *args):
    """``evaluate_one(item, *args)``, with what stops it (an InputError) as a :class:`TaskFailure`:
    what worker processes and Dask workers run for one item of an offline or online evaluation."""
    try:
        return evaluate_one(item, *args)
    except InputError as exc:
        return TaskFailure(str(exc))


def run_item(item: Item, names=DEFAULT_ESTIMATORS, rate_hz: float = RATE_HZ, configs=None) -> ItemResult | TaskFailure:
    """:func:`evaluate_item`, with what stops it as a :class:`TaskFailure`."""
    return outcome(_evaluate_item_positional, item, names, rate_hz, configs)


def _evaluate_item_positional(item: Item, names, rate_hz: float, configs) -> ItemResult:
    return evaluate_item(item, names, rate_hz=rate_hz, configs=configs)


def evaluate_items(evaluate_one, items, args=(), *, progress: str | None, failures=None, jobs: int = 1, executor=None):
    """Every item through ``evaluate_one(item, *args)`` (a top-level function: it runs in worker
    processes or on a Dask cluster), in the order of ``items``: (the results, the failures, those
    given first). The skeleton of :func:`evaluate` and :func:`~yoyogait.evaluation.evaluate_online`."""
    failures = list(failures or [])
    items = list(items)
    outcomes = run_tasks(outcome, [(evaluate_one, item, *args) for item in items], jobs=jobs, executor=executor,
                         progress=progress)  # fmt: skip
    return split_outcomes(items, outcomes, failures), failures


def evaluate(
    items,
    names=DEFAULT_ESTIMATORS,
    *,
    progress: bool = False,
    dataset: str = "",
    synthetic: bool = False,
    failures=None,
    jobs: int = 1,
    executor=None,
    configs=None,
) -> Evaluation:
    """Evaluate every item; an item that cannot be read or processed is reported, not fatal.

    ``configs``: further configurations by name, which ``names`` may use. ``jobs`` > 1 evaluates
    the items in that many worker processes; ``executor`` (any ``concurrent.futures.Executor``,
    e.g. :func:`~yoyogait.evaluation.parallel.dask_executor`) runs them there instead. The result
    is the same either way, in the order of ``items``.
    """
    names = check_estimators(names, configs)
    for name, config in (configs or {}).items():  # every estimator runs on the same velocities
        if name in names and config.sample_time_s != 1.0 / RATE_HZ:
            raise InputError(
                f"{name}: sample_time_s = {config.sample_time_s:g} s; the estimators of one evaluation share the "
                f"velocities at {RATE_HZ:g} Hz (sample_time_s = {1.0 / RATE_HZ:g} s); evaluate it on its own"
            )
    done, failures = evaluate_items(
        _evaluate_item_positional,
        items,
        (names, RATE_HZ, configs),
        progress="evaluating" if progress else None,
        failures=failures,
        jobs=jobs,
        executor=executor,
    )
    return Evaluation(names, done, failures, dataset, synthetic)
