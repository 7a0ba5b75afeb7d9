"""Evaluation of the lower-back IMU estimator against the reference systems of a data set.

Per walking bout of a reference system (``ImuRecording.references``: INDIP, Stereophoto), the
cadence (steps/min), walking speed (m/s) and stride time (s) of each estimator are the means of
its valid estimates inside the bout; the error is that minus the reference's value.  A bout in
which an estimator has no valid estimate counts as missed (NaN error, listed).

Estimators: ``yoyogait-imu`` (:class:`ImuOnlineEstimator`, online), ``oscillator-imu`` (the
adaptive oscillator fed the IMU front-end's vertical and forward velocity, 25 Hz means), and
``mobgap`` (Mobilise-D's offline pipeline, the optional extra ``yoyogait[mobgap]``) when it is
installed and the recording is one of its example data set.
"""

from __future__ import annotations

import dataclasses
import math
import warnings
from pathlib import Path
from typing import Any

import numpy as np

from ..errors import InputError
from ..estimators.config import ImuConfig
from ..estimators.imu import ImuResult, estimator_for
from ..estimators.oscillator import run_oscillator
from ..io.imu_read import read_mobilised_trials
from ..io.imu_recording import ImuBout, ImuRecording

__all__ = ["BoutRow", "imu_recordings", "evaluate_recording", "summary", "imu_figure", "run_mobgap"]

ESTIMATORS = ("yoyogait-imu", "oscillator-imu", "mobgap")


@dataclasses.dataclass
class BoutRow:
    """One estimator on one reference bout."""

    recording: str
    reference: str
    bout: int
    estimator: str
    start_s: float
    end_s: float
    ref_cadence_spm: float
    ref_speed_mps: float
    ref_stride_time_s: float
    cadence_spm: float
    speed_mps: float
    stride_time_s: float

    @property
    def cadence_error_spm(self) -> float:
        return self.cadence_spm - self.ref_cadence_spm

    @property
    def speed_error_mps(self) -> float:
        return self.speed_mps - self.ref_speed_mps

    @property
    def stride_time_error_s(self) -> float:
        return self.stride_time_s - self.ref_stride_time_s


def imu_recordings(root) -> list[ImuRecording]:
    """Every trial of every Mobilise-D ``data.mat`` under ``root`` (the imu_mobgap data set)."""
    root = Path(root)
    files = sorted(root.rglob("data.mat"))
    if not files:
        raise InputError(f"{root}: no Mobilise-D data.mat below it (the imu_mobgap data set?)")
    out: list[ImuRecording] = []
    for f in files:
        out.extend(read_mobilised_trials(f))
    return out


def _bout_means(time_s, f_hz, speed, valid, bout: ImuBout) -> tuple[float, float, float]:
    m = (time_s >= bout.start_s) & (time_s <= bout.end_s) & valid & (f_hz > 0)
    if not np.any(m):
        return math.nan, math.nan, math.nan
    f = float(np.mean(f_hz[m]))
    return 60.0 * f, float(np.mean(speed[m])), 2.0 / f


def _oscillator(result: ImuResult):
    """The adaptive oscillator on the IMU front-end's velocities, as 25 Hz means of the samples."""
    t = result.time_s
    k = 4 if len(t) > 8 and abs(np.median(np.diff(t)) - 0.01) < 1e-6 else 1
    n = (len(t) // k) * k
    tt = t[:n].reshape(-1, k)[:, -1]
    vx = result["vx_mps"][:n].reshape(-1, k).mean(1)
    vz = result["vz_mps"][:n].reshape(-1, k).mean(1)
    r = run_oscillator(tt, vx, vz)
    return tt, np.asarray(r.step_frequency_hz), np.asarray(r.speed_mps)


def evaluate_recording(rec: ImuRecording, config: ImuConfig | None = None, mobgap=None):
    """(rows, result): a BoutRow per estimator and reference bout, and the IMU estimator's run.
    ``mobgap``: the peer's walking bouts [(start_s, end_s, cadence_spm, speed_mps, stride_time_s)]
    or None."""
    result = estimator_for(rec, config).run_recording(rec)
    t = result.time_s
    osc_t, osc_f, osc_v = _oscillator(result)
    rows = []
    for ref, bouts in rec.references.items():
        for i, b in enumerate(bouts):
            base: dict[str, Any] = dict(
                recording=rec.source,
                reference=ref,
                bout=i,
                start_s=b.start_s,
                end_s=b.end_s,
                ref_cadence_spm=b.cadence_spm,
                ref_speed_mps=b.speed_mps,
                ref_stride_time_s=b.stride_time_s,
            )
            c, v, s = _bout_means(t, result["step_frequency_hz"], result["speed_mps"], result["valid"], b)
            rows.append(BoutRow(estimator="yoyogait-imu", cadence_spm=c, speed_mps=v, stride_time_s=s, **base))
            c, v, s = _bout_means(osc_t, osc_f, osc_v, np.ones(osc_t.size, bool), b)
            rows.append(BoutRow(estimator="oscillator-imu", cadence_spm=c, speed_mps=v, stride_time_s=s, **base))
            if mobgap is not None:
                c, v, s = _peer_bout(mobgap, b)
                rows.append(BoutRow(estimator="mobgap", cadence_spm=c, speed_mps=v, stride_time_s=s, **base))
    return rows, result


def _peer_bout(peer, b: ImuBout):
    """The peer's values on a reference bout: its bouts weighted by their overlap with it."""
    w, c, v, s = [], [], [], []
    for start, end, cad, speed, stride in peer:
        overlap = min(end, b.end_s) - max(start, b.start_s)
        if overlap > 0:
            w.append(overlap)
            c.append(cad)
            v.append(speed)
            s.append(stride)
    if not w:
        return math.nan, math.nan, math.nan
    wa = np.asarray(w)

    def avg(x):
        x = np.asarray(x, dtype=float)
        ok = np.isfinite(x)
        return float(np.sum(wa[ok] * x[ok]) / np.sum(wa[ok])) if ok.any() else math.nan

    return avg(c), avg(v), avg(s)


def run_mobgap(rec: ImuRecording):
    """Mobilise-D's pipeline (mobgap, offline) on a recording of its example data set: its walking
    bouts as (start_s, end_s, cadence_spm, speed_mps, stride_time_s). ImportError without mobgap."""
    with warnings.catch_warnings():  # the peer's own warnings (scikit-learn versions of its models)
        warnings.simplefilter("ignore")
        return _run_mobgap(rec)


def _run_mobgap(rec: ImuRecording):
    from mobgap.data import GenericMobilisedDataset
    from mobgap.pipeline import MobilisedPipelineHealthy, MobilisedPipelineImpaired

    meta = rec.metadata
    mat = Path(rec.source.split(":")[0])
    cohort = mat.parent.parent.name
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        ds = GenericMobilisedDataset(
            [mat],
            test_level_names=["time_measure", "test", "trial"],
            parent_folders_as_metadata=["cohort", "participant_id"],
            measurement_condition="laboratory",
            reference_system="INDIP",
        )
        dp = ds.get_subset(test=meta["test"], trial=meta["trial"])
        pipe = MobilisedPipelineImpaired() if cohort == "MS" else MobilisedPipelineHealthy()
        p = pipe.safe_run(dp)
    wb = p.per_wb_parameters_
    fs = float(rec.rate_hz or 100.0)
    out = []
    for _, row in wb.iterrows():
        cad = float(row.get("cadence_spm", math.nan))
        out.append(
            (
                float(row["start"]) / fs,
                float(row["end"]) / fs,
                cad,
                float(row.get("walking_speed_mps", math.nan)),
                float(row.get("stride_duration_s", 120.0 / cad if cad > 0 else math.nan)),
            )
        )
    return out


def summary(rows: list[BoutRow]) -> list[dict]:
    """Per reference and estimator: bouts, missed, median and worst |error| of cadence, speed, stride time."""
    out = []
    refs = sorted({r.reference for r in rows})
    ests = [e for e in ESTIMATORS if any(r.estimator == e for r in rows)]
    for ref in refs:
        for est in ests:
            sel = [r for r in rows if r.reference == ref and r.estimator == est]
            d: dict = {"reference": ref, "estimator": est, "bouts": len(sel)}
            d["missed"] = sum(1 for r in sel if not math.isfinite(r.cadence_spm))
            for key in ("cadence_error_spm", "speed_error_mps", "stride_time_error_s"):
                e = np.abs([getattr(r, key) for r in sel])
                e = e[np.isfinite(e)]
                d[f"median_abs_{key}"] = float(np.median(e)) if e.size else math.nan
                d[f"max_abs_{key}"] = float(np.max(e)) if e.size else math.nan
            out.append(d)
    return out


def imu_figure(rec: ImuRecording, result: ImuResult, path, mobgap=None) -> None:
    """Cadence and speed over time against the reference bouts and initial contacts (and the peer's bouts)."""
    from matplotlib.backends.backend_agg import FigureCanvasAgg
    from matplotlib.figure import Figure

    fig = Figure(figsize=(11, 6.5))
    FigureCanvasAgg(fig)
    ax1, ax2, ax3 = fig.subplots(3, 1, sharex=True)
    t = result.time_s
    valid = result["valid"].astype(bool)
    cad = np.where(valid, 60.0 * result["step_frequency_hz"], np.nan)
    spd = np.where(valid, result["speed_mps"], np.nan)
    ax1.plot(t, result["vz_mps"], lw=0.6, color="0.4", label="vertical velocity (IMU front-end)")
    colours = {"INDIP": "tab:green", "Stereophoto": "tab:purple"}
    for ref, bouts in rec.references.items():
        for j, b in enumerate(bouts):
            col = colours.get(ref, "tab:gray")
            for ax in (ax1, ax2, ax3):
                ax.axvspan(b.start_s, b.end_s, color=col, alpha=0.08)
            ax1.plot(b.contact_times_s, np.full(b.contact_times_s.size, 0.0 if ref == "INDIP" else 0.05), "|",
                     color=col, ms=8, label=f"{ref} initial contacts" if j == 0 else None)  # fmt: skip
            ax2.plot(
                [b.start_s, b.end_s], [b.cadence_spm] * 2, color=col, lw=2.5, label=f"{ref} bout" if j == 0 else None
            )
            ax3.plot(
                [b.start_s, b.end_s], [b.speed_mps] * 2, color=col, lw=2.5, label=f"{ref} bout" if j == 0 else None
            )
    if mobgap:
        for j, (s, e, c, v, _) in enumerate(mobgap):
            ax2.plot([s, e], [c, c], color="tab:orange", lw=1.5, ls="--", label="mobgap (offline)" if j == 0 else None)
            ax3.plot([s, e], [v, v], color="tab:orange", lw=1.5, ls="--", label="mobgap (offline)" if j == 0 else None)
    ax2.plot(t, cad, color="tab:blue", lw=1.0, label="yoyogait IMU online (valid)")
    sd = 60.0 * result["step_frequency_std_hz"]
    ax2.fill_between(t, cad - 2 * sd, cad + 2 * sd, color="tab:blue", alpha=0.2, lw=0)
    ax3.plot(t, spd, color="tab:blue", lw=1.0, label="yoyogait IMU online (valid)")
    ss = result["speed_std_mps"]
    ax3.fill_between(t, spd - 2 * ss, spd + 2 * ss, color="tab:blue", alpha=0.2, lw=0)
    ax1.set_ylabel("v_z [m/s]")
    ax2.set_ylabel("cadence [steps/min]")
    ax3.set_ylabel("speed [m/s]")
    ax3.set_xlabel("time [s]")
    ax2.set_ylim(40, 160)
    ax3.set_ylim(0, 2.0)
    for ax in (ax1, ax2, ax3):
        ax.legend(loc="upper right", fontsize=7, ncol=3)
        ax.grid(alpha=0.3)
    label = "SYNTHETIC " if rec.synthetic else ""
    fig.suptitle(
        f"{label}{rec.source.split('example_data/')[-1]}: reference bouts vs online IMU estimate (band: 2 std)",
        fontsize=9,
    )
    fig.subplots_adjust(left=0.07, right=0.98, top=0.94, bottom=0.07, hspace=0.12)
    fig.savefig(path, dpi=90)


def coverage(rec: ImuRecording, result: ImuResult) -> dict[str, dict[str, float]]:
    """Per reference system, over the valid online estimates inside its walking bouts (the bout's
    mean as the truth): the fraction within 2 standard deviations of the reference (cadence, speed),
    and the confidently-wrong fraction (valid, and more than 3 standard deviations off in either)."""
    t = result.time_s
    valid = result["valid"].astype(bool)
    out = {}
    for ref, bouts in rec.references.items():
        ref_cad = np.full(t.size, np.nan)
        ref_spd = np.full(t.size, np.nan)
        for b in bouts:
            m = (t >= b.start_s) & (t <= b.end_s)
            ref_cad[m], ref_spd[m] = b.cadence_spm, b.speed_mps
        m = valid & np.isfinite(ref_cad)
        if not m.any():
            out[ref] = {"samples": 0, "cadence_2std": math.nan, "speed_2std": math.nan, "confidently_wrong": math.nan}
            continue
        ec = np.abs(60.0 * result["step_frequency_hz"][m] - ref_cad[m])
        sc = 60.0 * result["step_frequency_std_hz"][m]
        es = np.abs(result["speed_mps"][m] - ref_spd[m])
        ss = result["speed_std_mps"][m]
        out[ref] = {
            "samples": int(m.sum()),
            "cadence_2std": float(np.mean(ec <= 2 * sc)),
            "speed_2std": float(np.mean(es <= 2 * ss)),
            "confidently_wrong": float(np.mean((ec > 3 * sc) | (es > 3 * ss))),
        }
    return out
