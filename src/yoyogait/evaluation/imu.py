"""Evaluation of the lower-back IMU estimator against the reference systems of a data set.

Per walking bout of a reference system (``ImuRecording.references``: INDIP, Stereophoto), like
with like: the reference's cadence and stride time of a bout are means over its strides (initial
contact k to k + 2, those the reference measured: not the ones over a contact it missed or
counted twice) of 120 / stride duration and of the stride duration (that is how the Mobilise-D
standards define ``Cadence`` and ``Stride_Duration``; the two differ from each other where the
cadence changes within a bout).  The online estimate is taken over the same strides: a
stride counts when the estimate is valid over at least half of it, its cadence is the mean of
60 f and its stride time 2 / the mean of f over the stride's valid samples, and the bout's values
are the means over the strides that count, against the reference's means over those same
strides.  The speed is the mean over those strides against the bout's ``WalkingSpeed`` (the
reference's per-stride speeds are not read).  A bout in which no stride counts is missed (NaN
error, listed).

Coverage and confidently-wrong time follow the online evaluation's definitions
(:mod:`yoyogait.evaluation.metrics`): over every sample inside the reference's bouts, valid or
not, the share within 2 reported standard deviations of the reference (the step frequency of the
strides under way; the bout's speed), and the share that is valid and off by more than 0.15 Hz
or 0.15 m/s and more than 2 standard deviations.

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
from ..estimators.imu import ImuReason, ImuResult, estimator_for
from ..estimators.oscillator import run_oscillator
from ..io.imu_read import read_mobilised_trials
from ..io.imu_recording import ImuBout, ImuRecording
from . import figures as plots
from . import metrics
from .online import WRONG_F_HZ, WRONG_SPEED_MPS

__all__ = [
    "BoutRow",
    "bout_strides",
    "coverage",
    "evaluate_recording",
    "imu_figure",
    "imu_recordings",
    "reference_at",
    "run_mobgap",
    "startup",
    "summary",
]

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
    strides: int = 0  # the reference's strides the values are taken over
    ref_strides: int = 0  # the reference's strides in the bout
    #: The reference's own stride speeds over the strides the values are taken over (NaN without them).
    ref_stride_speed_mps: float = math.nan

    @property
    def cadence_error_spm(self) -> float:
        return self.cadence_spm - self.ref_cadence_spm

    @property
    def speed_error_mps(self) -> float:
        return self.speed_mps - self.ref_speed_mps

    @property
    def stride_speed_error_mps(self) -> float:
        """The speed against the reference's over the same strides (as the cadence is scored), where
        ``speed_error_mps`` takes the bout's: its mean over every stride it measured."""
        return self.speed_mps - self.ref_stride_speed_mps

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


def bout_strides(bout: ImuBout) -> tuple[np.ndarray, np.ndarray]:
    """The reference's strides of a bout, (start_s, end_s): those it measured (``ImuBout.strides_s``,
    the strides its cadence is the mean over), else initial contact k to k + 2, both known."""
    if bout.strides_s.size:
        return bout.strides_s[:, 0].copy(), bout.strides_s[:, 1].copy()
    ic = np.asarray(bout.contact_times_s, dtype=float).reshape(-1)
    if ic.size < 3:
        return np.zeros(0), np.zeros(0)
    a, e = ic[:-2], ic[2:]
    with np.errstate(invalid="ignore"):
        ok = np.isfinite(a) & np.isfinite(e) & (e > a)
    return a[ok], e[ok]


def _bout_values(time_s, f_hz, speed, valid, bout: ImuBout, min_valid: float = 0.5):
    """(cadence, speed, stride time, reference cadence, reference stride time, strides counted,
    strides, reference speed over the strides counted) of an estimate over the reference's strides
    of a bout (the module's text)."""
    a, e = bout_strides(bout)
    ok = np.asarray(valid, dtype=bool) & (np.asarray(f_hz) > 0)
    speeds = bout.stride_speeds_mps if bout.stride_speeds_mps.size == a.size else np.full(a.size, math.nan)
    cad, spd, stride, ref_cad, ref_stride, ref_spd = [], [], [], [], [], []
    for s0, s1, ref_v in zip(a, e, speeds):
        i0, i1 = np.searchsorted(time_s, [s0, s1])
        if i1 <= i0:
            continue
        m = ok[i0:i1]
        if m.mean() < min_valid:
            continue
        f = float(np.mean(f_hz[i0:i1][m]))
        cad.append(60.0 * f)
        stride.append(2.0 / f)
        spd.append(float(np.mean(speed[i0:i1][m])))
        ref_cad.append(120.0 / (s1 - s0))
        ref_stride.append(s1 - s0)
        ref_spd.append(float(ref_v))
    if not cad:
        return (math.nan,) * 5 + (0, a.size, math.nan)
    return (float(np.mean(cad)), float(np.mean(spd)), float(np.mean(stride)), float(np.mean(ref_cad)),
            float(np.mean(ref_stride)), len(cad), a.size, float(np.mean(ref_spd)))  # fmt: skip


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
            for name, tt, f, v, ok in (
                ("yoyogait-imu", t, result["step_frequency_hz"], result["speed_mps"], result["valid"]),
                ("oscillator-imu", osc_t, osc_f, osc_v, np.ones(osc_t.size, bool)),
            ):
                c, sp, st, rc, rs, n, nref, rv = _bout_values(tt, f, v, ok, b)
                row = {**base, "ref_cadence_spm": rc, "ref_stride_time_s": rs}
                rows.append(BoutRow(estimator=name, cadence_spm=c, speed_mps=sp, stride_time_s=st, strides=n,
                                    ref_strides=nref, ref_stride_speed_mps=rv, **row))  # fmt: skip
            if mobgap is not None:
                # The peer's values are per its own walking bouts: against the reference's whole bout.
                c, v, s = _peer_bout(mobgap, b)
                n = bout_strides(b)[0].size
                rows.append(BoutRow(estimator="mobgap", cadence_spm=c, speed_mps=v, stride_time_s=s, strides=n,
                                    ref_strides=n, **base))  # fmt: skip
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
    """Per reference and estimator: bouts, missed, scored, median and worst |error| of cadence, speed,
    stride time over the scored bouts (a missed bout, with no stride that counts, has no error: it is
    left out of the median and counted in ``missed``), and the median with each missed bout counted
    as an error larger than any (``median_missed_worst_abs_*``: what the misses hide)."""
    out = []
    refs = sorted({r.reference for r in rows})
    ests = [e for e in ESTIMATORS if any(r.estimator == e for r in rows)]
    for ref in refs:
        for est in ests:
            sel = [r for r in rows if r.reference == ref and r.estimator == est]
            d: dict = {"reference": ref, "estimator": est, "bouts": len(sel)}
            d["missed"] = sum(1 for r in sel if not math.isfinite(r.cadence_spm))
            d["scored"] = d["bouts"] - d["missed"]
            for key in ("cadence_error_spm", "speed_error_mps", "stride_speed_error_mps", "stride_time_error_s"):
                e_all = np.abs(np.array([getattr(r, key) for r in sel], dtype=float))
                e = e_all[np.isfinite(e_all)]
                d[f"median_abs_{key}"] = float(np.median(e)) if e.size else math.nan
                d[f"max_abs_{key}"] = float(np.max(e)) if e.size else math.nan
                worst = np.where(np.isfinite(e_all), e_all, math.inf)
                d[f"median_missed_worst_abs_{key}"] = float(np.median(worst)) if worst.size else math.nan
            out.append(d)
    return out


#: Times from this on are a clock that counts from an epoch (a ROS stamp): the figure counts from the first sample.
EPOCH_CLOCK_S = 1e5


def imu_figure(rec: ImuRecording, result: ImuResult, path, mobgap=None):
    """Cadence and speed over time against the reference bouts and initial contacts (and the peer's
    bouts), and a strip of when the estimate is valid and why not; the figure, saved to ``path``."""
    from matplotlib.backends.backend_agg import FigureCanvasAgg
    from matplotlib.figure import Figure

    # A clock that counts from an epoch (a ROS stamp) is drawn from the first sample, said in the label.
    t_origin = float(result.time_s[0]) if abs(float(result.time_s[0])) >= EPOCH_CLOCK_S else 0.0
    t = result.time_s - t_origin
    valid = result["valid"].astype(bool)
    reason = np.asarray(result["reason"], dtype=int)
    reasons = [(r, reason == int(r)) for r in ImuReason if int(r) != int(ImuReason.OK)]
    strip = plots.validity_rows(t, result["walking"], valid, reasons)
    fig = Figure(figsize=(11, 7.2 + 0.17 * len(strip)))
    FigureCanvasAgg(fig)
    ax1, ax2, ax3, ax4 = fig.subplots(
        4, 1, sharex=True, gridspec_kw={"height_ratios": (1.0, 1.0, 1.0, 0.17 * (len(strip) + 1))}
    )
    cad = np.where(valid, 60.0 * result["step_frequency_hz"], np.nan)
    spd = np.where(valid, result["speed_mps"], np.nan)
    ax1.plot(t, result["vz_mps"], lw=0.6, color="0.4", label="vertical velocity (IMU front-end)")
    colours = {"INDIP": "tab:green", "Stereophoto": "tab:purple"}
    for ref, bouts in rec.references.items():
        for j, b in enumerate(bouts):
            col = colours.get(ref, "tab:gray")
            for ax in (ax1, ax2, ax3):
                ax.axvspan(b.start_s - t_origin, b.end_s - t_origin, color=col, alpha=0.08)
            level = np.full(b.contact_times_s.size, 0.0 if ref == "INDIP" else 0.05)
            ax1.plot(b.contact_times_s - t_origin, level, "|", color=col, ms=8,
                     label=f"{ref} initial contacts" if j == 0 else None)  # fmt: skip
            span = [b.start_s - t_origin, b.end_s - t_origin]
            ax2.plot(span, [b.cadence_spm] * 2, color=col, lw=2.5, label=f"{ref} bout" if j == 0 else None)
            ax3.plot(span, [b.speed_mps] * 2, color=col, lw=2.5, label=f"{ref} bout" if j == 0 else None)
    if mobgap:
        for j, (s, e, c, v, _) in enumerate(mobgap):
            s, e = s - t_origin, e - t_origin
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
    plots.validity_strip(ax4, strip)  # why not valid, where not
    ax4.set_xlabel(f"time [s] after {t_origin:.6f} s" if t_origin else "time [s]")
    ax4.set_xlim(float(t[0]), float(t[-1]))
    ax2.set_ylim(40, 160)
    ax3.set_ylim(0, 2.0)
    for ax in (ax1, ax2, ax3):
        ax.legend(loc="upper right", fontsize=7, ncol=3)
        ax.grid(alpha=0.3)
    label = "SYNTHETIC " if rec.synthetic else ""
    against = "reference bouts vs " if rec.references else ""
    fig.suptitle(
        f"{label}{rec.source.split('example_data/')[-1]}: {against}online IMU estimate (band: 2 std)", fontsize=9
    )
    fig.subplots_adjust(left=0.11, right=0.98, top=0.95, bottom=0.06, hspace=0.12)
    fig.savefig(path, dpi=90)
    return fig


def reference_at(rec: ImuRecording, reference: str, time_s) -> tuple[np.ndarray, np.ndarray]:
    """(step frequency [Hz], speed [m/s]) of a reference system at each time: inside its bouts the
    mean of 2 / duration of the strides under way (a stride-averaged step frequency: left-right
    asymmetry averaged out) and the bout's speed; NaN outside them."""
    t = np.asarray(time_s, dtype=float)
    f_sum, f_n = np.zeros(t.size), np.zeros(t.size)
    speed = np.full(t.size, np.nan)
    for b in rec.references.get(reference, []):
        i0, i1 = np.searchsorted(t, [b.start_s, b.end_s], side="left")
        speed[i0:i1] = b.speed_mps
        for s0, s1 in zip(*bout_strides(b)):
            j0, j1 = np.searchsorted(t, [s0, s1])
            f_sum[j0:j1] += 2.0 / (s1 - s0)
            f_n[j0:j1] += 1.0
    with np.errstate(invalid="ignore", divide="ignore"):
        f = np.where(f_n > 0, f_sum / f_n, np.nan)
    return f, np.where(np.isfinite(f), speed, np.nan)


def coverage(rec: ImuRecording, result: ImuResult) -> dict[str, dict[str, float]]:
    """Per reference system, over every sample inside its walking bouts with a stride under way
    (valid or not, as the online evaluation counts): the share within 2 standard deviations of the
    reference (step frequency, speed: :func:`reference_at`), the confidently-wrong share (valid,
    and off by more than 0.15 Hz or 0.15 m/s and more than 2 standard deviations), the valid share,
    and the sharpness over the valid samples (:func:`~yoyogait.evaluation.metrics.sharpness`: the
    median reported std beside the 95th percentile of the error)."""
    t = result.time_s
    valid = result["valid"].astype(bool)
    f, f_std = result["step_frequency_hz"], result["step_frequency_std_hz"]
    v, v_std = result["speed_mps"], result["speed_std_mps"]
    out = {}
    for ref in rec.references:
        f_ref, v_ref = reference_at(rec, ref, t)
        m = np.isfinite(f_ref)
        quantities = ((f, f_std, f_ref, WRONG_F_HZ), (v, v_std, v_ref, WRONG_SPEED_MPS))
        out[ref] = {
            "samples": int(m.sum()),
            "cadence_2std": metrics.coverage_fraction(f, f_std, f_ref, m),
            "speed_2std": metrics.coverage_fraction(v, v_std, v_ref, m),
            "confidently_wrong": metrics.confidently_wrong_fraction(quantities, valid, m),
            "valid": metrics.flag_fraction(valid, m),
        }
        out[ref]["f_std_valid_hz"], out[ref]["f_err_valid_p95_hz"] = metrics.sharpness(f, f_std, f_ref, valid, m)
        out[ref]["speed_std_valid_mps"], out[ref]["speed_err_valid_p95_mps"] = metrics.sharpness(
            v, v_std, v_ref, valid, m
        )
    return out


def startup(rec: ImuRecording, result: ImuResult) -> list[dict]:
    """On the first bout of each reference (the walk starts from standing): the time from its first
    initial contact to the first valid estimate, and to the first valid estimate within 5 % of the
    reference's cadence, in the bout's steps (60 / its cadence)."""
    t = result.time_s
    valid = result["valid"].astype(bool)
    cad = 60.0 * result["step_frequency_hz"]
    out = []
    for ref, bouts in rec.references.items():
        for b in bouts[:1]:
            step_s = 60.0 / b.cadence_spm
            m = (t >= b.start_s) & (t <= b.end_s)
            first = np.flatnonzero(m & valid)
            close = np.flatnonzero(m & valid & (np.abs(cad - b.cadence_spm) <= 0.05 * b.cadence_spm))
            out.append(
                {
                    "recording": rec.source,
                    "reference": ref,
                    "start_s": b.start_s,
                    "valid_steps": (t[first[0]] - b.start_s) / step_s if first.size else math.nan,
                    "within5_steps": (t[close[0]] - b.start_s) / step_s if close.size else math.nan,
                }
            )
    return out
