"""Evaluation of estimators over a data set, the way the paper did (Table I, Fig. 3-4) and more.

A data set is a list of :class:`Item` (a recording to load, its subject and
walk type, and the ground truth where there is one): the built-in synthetic
lab, a folder of recordings, or a manifest in the schema of
``shared/datasets/manifest.json`` (see the README).  Each item goes through the
paper's pipeline (:func:`yoyogait.gait_velocities` at 25 Hz), every estimator
runs on the same velocities, and :func:`yoyogait.metrics.evaluate` scores it
against the truth (synthetic) or the gait events (real data).
"""

from __future__ import annotations

import csv
import functools
import io as _io
import json
import math
import os
import shutil
import tempfile
from dataclasses import dataclass, field
from pathlib import Path
from typing import Callable

import numpy as np

from ._files import give_default_mode
from .errors import InputError

__all__ = [
    "Item", "ItemResult", "Evaluation", "synthetic_items", "manifest_items", "folder_items",
    "resolve_dataset", "estimators", "evaluate_item", "evaluate", "table_one", "write_report",
    "DEFAULT_ESTIMATORS", "PREDICTION_HORIZONS_S",
]

RATE_HZ = 25.0  # the paper's resampling rate (Sec. IV-A)
PREDICTION_HORIZONS_S = (0.04, 0.2)  # one step at 25 Hz, and 0.2 s
READABLE = (".c3d", ".trc", ".bvh", ".csv")
DEFAULT_ESTIMATORS = ("paper", "default")


@dataclass
class Item:
    """One recording of a data set, not loaded yet."""

    name: str  # file name (or the synthetic walk's name)
    subject: str  # a column of Table I
    walk: str  # a row group of Table I
    load: Callable[[], object]  # -> Recording
    truth: object | None = None  # SyntheticTruth for synthetic walks
    pelvis: list | None = None  # points to average for the pelvis centre (else found by name)
    feet: list | None = None  # points for foot contacts (else found by name)
    up_axis: str | None = None
    synthetic: bool = False


@dataclass
class ItemResult:
    """An item's velocities, reference and, per estimator, its result and metrics."""

    item: Item
    velocities: object
    reference_step_frequency_hz: np.ndarray
    reference_speed_mps: np.ndarray
    walking: np.ndarray
    dft_step_frequency_hz: float
    results: dict = field(default_factory=dict)  # estimator -> result
    metrics: dict = field(default_factory=dict)  # estimator -> metric dict


@dataclass
class Evaluation:
    """Everything :func:`evaluate` found, and what it could not evaluate."""

    estimators: tuple
    items: list  # ItemResult
    failures: list  # (item name, message)
    dataset: str
    synthetic: bool

    def rows(self) -> list[dict]:
        """One flat row per recording and estimator (the per-recording CSV)."""
        out = []
        for r in self.items:
            for est in self.estimators:
                out.append({"recording": r.item.name, "subject": r.item.subject, "walk": r.item.walk,
                            "estimator": est, "synthetic": r.item.synthetic, **r.metrics[est]})
        return out


# --------------------------------------------------------------------------- data sets

def synthetic_items(seed: int = 0, rate_hz: float = 100.0) -> list[Item]:
    """The built-in synthetic lab: 3 virtual subjects x 5 walk types (SYNTHETIC data)."""
    from . import synthetic

    items = []
    for walk in synthetic.default_lab(seed=seed, rate_hz=rate_hz):
        items.append(Item(
            name=walk.name, subject=walk.subject.name, walk=walk.walk_type,
            load=(lambda w=walk: w.recording), truth=walk.truth,
            pelvis=list(synthetic.PELVIS_MARKERS), feet=list(synthetic.HEEL_MARKERS), up_axis="z",
            synthetic=True))
    return items


def manifest_items(path) -> tuple[list[Item], list[tuple[str, str]]]:
    """Items of a manifest (schema of shared/datasets/manifest.json); paths are relative to it.

    Returns the items whose file exists and (name, problem) for each that does not.
    """
    from . import io

    path = Path(path)
    try:
        doc = json.loads(path.read_text())
    except (OSError, UnicodeDecodeError) as exc:
        raise InputError(f"cannot read manifest {path}: {exc}") from None
    except json.JSONDecodeError as exc:
        raise InputError(f"manifest {path} is not valid JSON: {exc.msg} at line {exc.lineno}") from None
    entries = doc.get("recordings") if isinstance(doc, dict) else None
    if not isinstance(entries, list):
        raise InputError(f"manifest {path} has no list 'recordings'")
    items, missing = [], []
    for n, entry in enumerate(entries):
        if not isinstance(entry, dict) or not isinstance(entry.get("path"), str):
            missing.append((f"entry {n}", "has no 'path'"))
            continue
        file = path.parent / entry["path"]
        if not file.is_file():
            missing.append((entry["path"], f"file not found: {file}"))
            continue
        overrides = {}
        if entry.get("length_unit_m") is not None:
            overrides["length_unit_m"] = float(entry["length_unit_m"])
        if entry.get("vertical_axis"):
            overrides["up_axis"] = entry["vertical_axis"]
        items.append(Item(
            name=Path(entry["path"]).name, subject=Path(entry["path"]).parent.name or "recordings",
            walk=entry.get("walk") or "unknown",
            load=(lambda f=file, o=overrides: io.read(f, **o)),
            pelvis=entry.get("pelvis"), feet=entry.get("feet"), up_axis=entry.get("vertical_axis")))
    return items, missing


def folder_items(path) -> list[Item]:
    """Every readable recording (C3D, TRC, BVH, CSV) below a folder; pelvis and feet found by name."""
    from . import io

    path = Path(path)
    files = sorted(p for p in path.rglob("*") if p.is_file() and p.suffix.lower() in READABLE)
    if not files:
        raise InputError(f"no recordings ({', '.join(READABLE)}) in folder {path}")
    return [Item(name=f.name, subject=f.parent.name, walk="unknown", load=(lambda f=f: io.read(f)))
            for f in files]


def resolve_dataset(spec: str | None, seed: int = 0) -> tuple[list[Item], list[tuple[str, str]], bool]:
    """(items, problems, synthetic) for 'synthetic' (or None), a folder, or a manifest .json."""
    if spec is None or spec == "synthetic":
        return synthetic_items(seed=seed), [], True
    path = Path(spec)
    if path.is_dir():
        manifest = path / "manifest.json"
        if manifest.is_file():
            items, missing = manifest_items(manifest)
            return items, missing, False
        return folder_items(path), [], False
    if path.suffix.lower() == ".json":
        if not path.is_file():
            raise InputError(f"manifest not found: {path}")
        items, missing = manifest_items(path)
        return items, missing, False
    if not path.exists():
        raise InputError(f"data set not found: {spec} (give 'synthetic', a folder or a manifest .json)")
    raise InputError(f"not a data set: {spec} (give 'synthetic', a folder or a manifest .json)")


# --------------------------------------------------------------------------- estimators

def _preset_runner(name: str):
    from .estimator import EstimatorConfig, GaitEstimator

    def run(vel):
        cfg = EstimatorConfig.preset(name)
        return GaitEstimator(cfg).run(vel.vx, vel.vz, predict_ahead_s=PREDICTION_HORIZONS_S, time_s=vel.time_s)
    return run


@functools.cache
def estimators() -> dict[str, Callable]:
    """Estimators by name: the presets of EstimatorConfig, then the baselines."""
    from .estimator import PRESETS

    out = {name: _preset_runner(name) for name in PRESETS}
    try:
        from . import baselines
    except ImportError:
        return out
    out.update(baselines.RUNNERS)
    return out


def check_estimators(names) -> tuple:
    names = tuple(names)
    unknown = [n for n in names if n not in estimators()]
    if unknown:
        raise InputError(f"unknown estimator(s) {', '.join(unknown)}; known: {', '.join(estimators())}")
    if not names:
        raise InputError("no estimator to evaluate")
    return names


# --------------------------------------------------------------------------- one item

def _stride_mean(values: np.ndarray, rate_hz: float, window_s: float) -> np.ndarray:
    """Centred moving mean over ``window_s`` that ignores NaN (the stride-averaged speed); NaN where
    under 80 % of the window is known."""
    from .velocities import moving_mean

    n = max(1, int(round(window_s * rate_hz)))
    known = np.convolve(np.isfinite(values).astype(float), np.ones(n), mode="same")
    return np.where(known >= 0.8 * n, moving_mean(values, n), np.nan)


def real_reference(recording, vel, item: Item):
    """(step frequency, stride-averaged speed, walking) on the velocity grid, from gait events.

    The step frequency is the cadence from the foot contacts with left-right alternation averaged
    out (:func:`yoyogait.metrics.step_frequency_from_contacts` with ``stride_average``).
    """
    from . import events, metrics

    t = vel.time_s
    walking = np.asarray(vel.walking, dtype=bool)
    f_ref = np.full(t.shape, np.nan)
    try:
        ev = events.detect_gait_events(recording, feet=item.feet, up_axis=vel.up_axis)
    except InputError:
        ev = None
    if ev is not None and len(ev.contacts_s) >= 2:
        f_ref = metrics.step_frequency_from_contacts(ev.contacts_s, t, stride_average=True)
        in_walk = np.zeros(t.shape, dtype=bool)
        for a, b in np.asarray(ev.walking_segments_s).reshape(-1, 2):
            in_walk |= (t >= a) & (t <= b)
        if in_walk.any():
            walking = in_walk & np.isfinite(vel.vx) & np.isfinite(vel.vz)
    # Stride = two steps; 1.1 s is a stride at 1.8 Hz, used where no step frequency is known.
    f_typ = np.nanmedian(f_ref) if np.isfinite(f_ref).any() else 1.8
    speed = _stride_mean(vel.vx, vel.rate_hz, 2.0 / f_typ)
    return f_ref, speed, walking


def evaluate_item(item: Item, names=DEFAULT_ESTIMATORS, *, rate_hz: float = RATE_HZ) -> ItemResult:
    """Load one item, take its velocities by the paper's pipeline, run and score every estimator."""
    from . import metrics
    from .velocities import gait_velocities

    recording = item.load()
    point = item.pelvis if item.pelvis else None
    vel = gait_velocities(recording, point=point, rate_hz=rate_hz, up_axis=item.up_axis)
    t = vel.time_s
    if item.truth is not None:
        tr = item.truth.at(t)
        f_ref, speed_ref = tr.step_frequency_hz, tr.speed_mps
        walking = np.asarray(tr.walking, dtype=bool) & np.isfinite(vel.vx) & np.isfinite(vel.vz)
    else:
        f_ref, speed_ref, walking = real_reference(recording, vel, item)
    if not walking.any():
        walking = np.isfinite(vel.vx) & np.isfinite(vel.vz)
    dft = metrics.dft_step_frequency_hz(t[walking], vel.vz[walking]) if walking.sum() > 10 else float("nan")
    out = ItemResult(item, vel, f_ref, speed_ref, walking, dft)
    for name in names:
        res = estimators()[name](vel)
        out.results[name] = res
        out.metrics[name] = metrics.evaluate(
            t, vel.vx, vel.vz, res, truth=item.truth, walking=walking,
            reference_step_frequency_hz=f_ref, reference_speed_mps=speed_ref,
            predicted_1step=res.aligned_prediction(PREDICTION_HORIZONS_S[0]),
            predicted_200ms=res.aligned_prediction(PREDICTION_HORIZONS_S[1]),
            skip_s=3.0)
    return out


def evaluate(items, names=DEFAULT_ESTIMATORS, *, progress: bool = False, dataset: str = "",
             synthetic: bool = False, failures=None) -> Evaluation:
    """Evaluate every item; an item that cannot be read or processed is reported, not fatal."""
    names = check_estimators(names)
    failures = list(failures or [])
    done = []
    iterator = items
    if progress:
        from tqdm import tqdm

        iterator = tqdm(items, desc="evaluating", unit="recording", leave=False, disable=None)
    for item in iterator:
        try:
            done.append(evaluate_item(item, names))
        except InputError as exc:
            failures.append((item.name, str(exc)))
    return Evaluation(names, done, failures, dataset, synthetic)


# --------------------------------------------------------------------------- tables

def _pool(stats) -> tuple[float, float]:
    """Mean and standard deviation of the union of groups given as (n, mean, std)."""
    stats = [(n, m, s) for n, m, s in stats if n and n > 0 and math.isfinite(m) and math.isfinite(s)]
    if not stats:
        return float("nan"), float("nan")
    total = sum(n for n, _, _ in stats)
    mean = sum(n * m for n, m, _ in stats) / total
    second = sum(n * (s * s + m * m) for n, m, s in stats) / total
    return mean, math.sqrt(max(second - mean * mean, 0.0))


def table_one(evaluation: Evaluation, estimator: str):
    """Table I: rows (walk type, component), columns subjects; cells (mean, std) in 1e-2 (m/s)^2.

    A cell with several recordings pools their samples.
    """
    subjects = sorted({r.item.subject for r in evaluation.items})
    walks = sorted({r.item.walk for r in evaluation.items})
    rows = []
    for walk in walks:
        for comp in ("vx", "vz"):
            cells = []
            for subj in subjects:
                group = [r.metrics[estimator] for r in evaluation.items if r.item.walk == walk and r.item.subject == subj]
                cells.append(_pool([(m["n_samples"], m[f"{comp}_sq_err_mean_1e-2"], m[f"{comp}_sq_err_std_1e-2"])
                                    for m in group]) if group else None)
            rows.append((walk, comp, cells))
    return subjects, rows


def _cell(c) -> str:
    if c is None:
        return ""
    mean, std = c
    if not math.isfinite(mean):
        return "n/a"
    return f"{_num(mean)} (±{_num(std)})"


def _num(v: float) -> str:
    if v >= 100:
        return f"{v:.0f}"
    if v >= 10:
        return f"{v:.1f}"
    return f"{v:.2f}" if v >= 0.1 else f"{v:.3f}"


def table_one_markdown(evaluation: Evaluation, estimator: str) -> str:
    subjects, rows = table_one(evaluation, estimator)
    head = "| walk type & component | " + " | ".join(subjects) + " |"
    lines = [head, "|---|" + "---:|" * len(subjects)]
    for walk, comp, cells in rows:
        label = f"{walk}: v_x error" if comp == "vx" else "  v_z error"
        lines.append(f"| {label} | " + " | ".join(_cell(c) for c in cells) + " |")
    return "\n".join(lines)


def table_one_csv(evaluation: Evaluation, estimator: str) -> str:
    subjects, rows = table_one(evaluation, estimator)
    buf = _io.StringIO()
    w = csv.writer(buf)
    w.writerow(["walk", "component"] + [f"{s} mean_1e-2" for s in subjects] + [f"{s} std_1e-2" for s in subjects])
    for walk, comp, cells in rows:
        w.writerow([walk, comp] + [("" if c is None else f"{c[0]:.6g}") for c in cells]
                   + [("" if c is None else f"{c[1]:.6g}") for c in cells])
    return buf.getvalue()


SUMMARY_KEYS = (
    ("vx_sq_err_mean_1e-2", "v_x sq. error (1e-2 (m/s)^2)"),
    ("vz_sq_err_mean_1e-2", "v_z sq. error (1e-2 (m/s)^2)"),
    ("f_err_median_hz", "step freq. error median (Hz)"),
    ("f_wrong_sign_fraction", "negative-frequency fraction"),
    ("speed_err_median_mps", "speed error median (m/s)"),
    ("pred200ms_vx_sq_err_mean_1e-2", "0.2 s-ahead v_x error (1e-2 (m/s)^2)"),
    ("pred200ms_vz_sq_err_mean_1e-2", "0.2 s-ahead v_z error (1e-2 (m/s)^2)"),
)


def summary_markdown(evaluation: Evaluation) -> str:
    """Median over recordings of the main metrics, one column per estimator."""
    lines = ["| median over recordings | " + " | ".join(evaluation.estimators) + " |",
             "|---|" + "---:|" * len(evaluation.estimators)]
    for key, label in SUMMARY_KEYS:
        vals = []
        for est in evaluation.estimators:
            v = np.array([r.metrics[est].get(key, np.nan) for r in evaluation.items], dtype=float)
            vals.append(f"{np.nanmedian(v):.3g}" if np.isfinite(v).any() else "n/a")
        lines.append(f"| {label} | " + " | ".join(vals) + " |")
    return "\n".join(lines)


# --------------------------------------------------------------------------- report

def _slug(text: str) -> str:
    keep = "".join(c if c.isalnum() or c in "-_." else "_" for c in text)
    return keep.strip("_") or "recording"


def write_report(evaluation: Evaluation, out_dir, *, force: bool = False, figures: bool = True,
                 progress: bool = False) -> Path:
    """Write tables, CSVs, figures and an index into ``out_dir``.

    Written into a temporary folder beside it and renamed at the end, so an
    interrupted run leaves no half-written report; an existing ``out_dir`` is
    replaced only with ``force``.
    """
    out = Path(out_dir)
    if out.exists() and not force:
        raise InputError(f"{out} exists; use --force to replace it")
    if out.exists() and not out.is_dir():
        raise InputError(f"{out} exists and is not a folder")
    parent = out.resolve().parent
    parent.mkdir(parents=True, exist_ok=True)
    tmp = Path(tempfile.mkdtemp(prefix=f".{out.name}.", suffix=".tmp", dir=parent))
    try:
        _write(evaluation, tmp, figures=figures, progress=progress)
        for item in (tmp, *tmp.rglob("*")):
            give_default_mode(item)
        if out.exists():
            old = Path(tempfile.mkdtemp(prefix=f".{out.name}.", suffix=".old", dir=parent))
            os.replace(out, old / out.name)
            os.replace(tmp, out)
            shutil.rmtree(old, ignore_errors=True)
        else:
            os.replace(tmp, out)
    except BaseException:
        shutil.rmtree(tmp, ignore_errors=True)
        raise
    return out


def _write(ev: Evaluation, folder: Path, *, figures: bool, progress: bool) -> None:
    from . import metrics

    label = "SYNTHETIC data (yoyogait's Yoyo-model gait lab)" if ev.synthetic else f"data set {ev.dataset}"
    md = [f"# yoyogait evaluation: {label}", ""]
    md += [f"Recordings evaluated: {len(ev.items)}; estimators: {', '.join(ev.estimators)}.", ""]
    if ev.failures:
        md += ["Not evaluated:", ""] + [f"- `{n}`: {m}" for n, m in ev.failures] + [""]
    md += ["## Summary", "", summary_markdown(ev), ""]
    for est in ev.estimators:
        md += [f"## Table I, estimator `{est}`", "",
               "Mean (± standard deviation) of the squared error of the reconstructed velocity "
               "(eq. 13-14) against the measured one over the walking part, in 10^-2 (m/s)^2.", "",
               table_one_markdown(ev, est), ""]
        (folder / f"table1_{est}.md").write_text(table_one_markdown(ev, est) + "\n")
        (folder / f"table1_{est}.csv").write_text(table_one_csv(ev, est))
    rows = ev.rows()
    keys = ["recording", "subject", "walk", "estimator", "synthetic"] + list(metrics.METRIC_KEYS)
    with open(folder / "recordings.csv", "w", newline="") as fh:
        w = csv.DictWriter(fh, fieldnames=keys, extrasaction="ignore")
        w.writeheader()
        for row in rows:
            w.writerow({k: (f"{v:.6g}" if isinstance(v, float) else v) for k, v in row.items()})
    if figures:
        md += ["## Figures", ""] + _figures(ev, folder, progress=progress)
    (folder / "index.md").write_text("\n".join(md) + "\n")


def _figures(ev: Evaluation, folder: Path, *, progress: bool) -> list[str]:
    from . import plots

    figdir = folder / "figures"
    figdir.mkdir()
    lines = []
    iterator = ev.items
    if progress:
        from tqdm import tqdm

        iterator = tqdm(ev.items, desc="figures", unit="recording", leave=False, disable=None)
    for r in iterator:
        vel = r.velocities
        links = []
        for est in ev.estimators:
            res = r.results[est]
            stem = _slug(f"{r.item.name}_{est}")
            title = f"{r.item.name} [{est}]"
            truth = r.item.truth
            plots.parameter_figure(
                vel.time_s, res, dft_step_frequency_hz=r.dft_step_frequency_hz, truth=truth,
                reference_time_s=None if truth is not None else vel.time_s,
                reference_step_frequency_hz=None if truth is not None else r.reference_step_frequency_hz,
                title=title, synthetic=r.item.synthetic, path=figdir / f"{stem}_parameters.png")
            plots.velocity_figure(vel.time_s, vel.vx, vel.vz, res, title=title, synthetic=r.item.synthetic,
                                  path=figdir / f"{stem}_velocities.png")
            links.append(f"[{est}: parameters](figures/{stem}_parameters.png), "
                         f"[velocities](figures/{stem}_velocities.png)")
        lines.append(f"- `{r.item.name}` ({r.item.subject}, {r.item.walk}): " + "; ".join(links))
    return lines
