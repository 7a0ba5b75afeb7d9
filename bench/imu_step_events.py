"""The lower-back IMU estimator on a data set that none of the project's tests or calibrations use:
Voisard et al.'s reference data set for healthy gait with IMUs (IPOL 2023, article 497; the folder
``GaitData`` of github.com/CyrilVoisard/ipol_dataset_1, AGPL-3.0; not shipped with yoyogait).

    python bench/imu_step_events.py --data PATH/TO/GaitData [--jobs 2] [--sensor-height-ratio 0.60] [--no-mobgap]

110 trials of 19 healthy adults: standing, 10 m of walking, a U-turn, 10 m back, stopping; an Xsens
Awinda sensor at L5 (``N-K_lb.txt``, read by ``yoyogait.read_imu`` as any user's file) and, per trial,
the footstep events of the two foot sensors (``N-K.json``, checked by hand), the trial's and the
U-turn's boundaries and the participant's height. Printed:

* cadence per stride (two consecutive events of one foot) and per trial (the mean over the straight
  strides the estimate is valid over at least half of, as bench/imu.py scores a bout): the median and
  the worst absolute error in steps/min; strides that overlap the U-turn apart (the data set marks no
  event inside the turn: one "stride" spans it);
* per trial, inside the straight walking (samples with a straight stride under way, the reference the
  mean of 2 / duration of those strides, as ``yoyogait.evaluation.imu.reference_at``): the valid
  share, the step frequency's 2-std coverage over the valid samples and the confidently-wrong share
  (valid, off by more than 0.15 Hz and by more than 2 std);
* start-up: steps from the first footstep to the first valid sample;
* the median speed while valid on the straights beside 20 m over the trial's time less the U-turn's
  (the data set's own walking speed is 20 m over the whole trial): an approximate reference that
  includes the start and the stop, so a steady speed reads above it;
* with mobgap installed (``pip install 'yoyogait[mobgap]'``; ``--no-mobgap`` leaves it out), its
  offline pipeline for healthy walkers as the peer, as bench/imu.py runs it: the samples put on the
  packet counter's 100 Hz grid (the few lost packets interpolated), acc in m/s^2 and gyr in deg/s as
  mobgap takes them; its walking bouts' cadence and speed weighted by their overlap with the trial,
  against the trial's reference (the mean over all its straight strides).

The sensor height is ``--sensor-height-ratio`` times the participant's height (0.60: SensorHeight over
Height of the three Mobilise-D participants of imu_mobgap reads 0.58-0.62); 0.95 m where a trial gives
no height. A benchmark, not a test: the figures are measured, the targets those of docs/imu.md.
"""

from __future__ import annotations

import argparse
import dataclasses
import json
import math
from concurrent.futures import ProcessPoolExecutor
from pathlib import Path

import numpy as np

from yoyogait import ImuConfig, ImuOnlineEstimator
from yoyogait.evaluation import metrics
from yoyogait.evaluation.imu import reference_at
from yoyogait.evaluation.online import WRONG_F_HZ  # the confidently-wrong tolerance (docs/evaluation.md)
from yoyogait.io.imu_read import read_imu
from yoyogait.io.imu_recording import ImuBout

RATE_HZ = 100.0  # the events are sample indices of the 100 Hz recordings


def _strides(meta: dict, t0: float, t1: float, u0: float, u1: float) -> list[tuple[float, float, bool]]:
    """(start_s, end_s, overlaps the U-turn) of every stride inside the trial [t0, t1]: two consecutive
    events of one foot (the files also hold the steps taken after the trial, up to seconds later)."""
    out = []
    for foot in ("LeftFootEvents", "RightFootEvents"):
        ev = np.asarray(meta.get(foot, []), dtype=float).reshape(-1, 2) / RATE_HZ
        for a, b in zip(ev[:-1, 0], ev[1:, 0]):
            if t0 <= a < b <= t1 + 1e-9:
                out.append((a, b, not (b <= u0 or a >= u1)))
    return out


def _mobgap_trial(rec, height_m: float, ratio: float, t0: float, t1: float) -> tuple[float, float]:
    """(cadence [steps/min], speed [m/s]) of mobgap's healthy pipeline over the trial [t0, t1]: its walking
    bouts weighted by their overlap with it (NaN without one)."""
    import warnings

    import pandas as pd
    from mobgap.data import GaitDatasetFromData
    from mobgap.pipeline import MobilisedPipelineHealthy

    grid = np.arange(rec.time_s[0], rec.time_s[-1] + 1e-9, 1.0 / RATE_HZ)
    cols = {f"acc_{a}": np.interp(grid, rec.time_s, rec.acc_mps2[:, i]) for i, a in enumerate("xyz")}
    cols |= {f"gyr_{a}": np.degrees(np.interp(grid, rec.time_s, rec.gyr_rad_s[:, i])) for i, a in enumerate("xyz")}
    participant = {"height_m": height_m, "sensor_height_m": ratio * height_m, "cohort": "HA"}
    with warnings.catch_warnings():  # the peer's own warnings (scikit-learn versions of its models)
        warnings.simplefilter("ignore")
        ds = GaitDatasetFromData({"trial": {"LowerBack": pd.DataFrame(cols)}}, RATE_HZ, {"trial": participant},
                                 {"trial": {"measurement_condition": "laboratory"}})  # fmt: skip
        wb = MobilisedPipelineHealthy().safe_run(ds[0]).per_wb_parameters_
    w, cad, speed = [], [], []
    for _, row in wb.iterrows():
        overlap = min(float(row["end"]) / RATE_HZ, t1) - max(float(row["start"]) / RATE_HZ, t0)
        if overlap > 0:
            w.append(overlap)
            cad.append(float(row.get("cadence_spm", math.nan)))
            speed.append(float(row.get("walking_speed_mps", math.nan)))
    if not w:
        return math.nan, math.nan
    return float(np.average(cad, weights=w)), float(np.average(speed, weights=w))


def evaluate_trial(args: tuple[Path, Path, float, bool]) -> dict:
    """The figures of one trial (the module's text)."""
    lb, meta_path, ratio, with_mobgap = args
    meta = json.loads(meta_path.read_text())
    height_cm = meta.get("Height")
    sensor_height_m = ratio * height_cm / 100.0 if isinstance(height_cm, (int, float)) and height_cm > 0 else None
    rec = read_imu(lb, sensor_height_m=sensor_height_m)
    res = ImuOnlineEstimator(ImuConfig(sensor_height_m=rec.sensor_height_m or 0.95)).run_recording(rec)
    t, f, f_std = res.time_s, res["step_frequency_hz"], res["step_frequency_std_hz"]
    valid = res["valid"].astype(bool)
    t0, t1 = (b / RATE_HZ for b in meta["TrialBoundaries"])
    u0, u1 = (b / RATE_HZ for b in meta["UTurnBoundaries"])
    strides = _strides(meta, t0, t1, u0, u1)
    rows = []
    for s0, s1, turn in strides:
        i0, i1 = np.searchsorted(t, [s0, s1])
        if i1 <= i0:
            continue
        ok = valid[i0:i1]
        est = float(np.mean(f[i0:i1][ok])) if ok.mean() >= 0.5 else math.nan
        rows.append({"turn": turn, "ref_hz": 2.0 / (s1 - s0), "est_hz": est})
    # The per-sample reference over the straight strides, as the Mobilise-D evaluation takes its own.
    straight_s = np.array([(s0, s1) for s0, s1, turn in strides if not turn]).reshape(-1, 2)
    bout = ImuBout(start_s=t0, end_s=t1, cadence_spm=math.nan, speed_mps=math.nan, stride_time_s=math.nan,
                   strides_s=straight_s)  # fmt: skip
    f_ref, _ = reference_at(dataclasses.replace(rec, references={"events": [bout]}), "events", t)
    straight = (t >= t0) & (t <= t1) & np.isfinite(f_ref)
    first = min(ev[0][0] for ev in (meta["LeftFootEvents"], meta["RightFootEvents"])) / RATE_HZ
    after = np.flatnonzero(valid & (t >= first))
    starts = np.sort([e[0] / RATE_HZ for k in ("LeftFootEvents", "RightFootEvents") for e in meta[k]])
    walking = (t >= t0) & (t <= t1) & ~((t >= u0) & (t <= u1))
    ref_speed = 20.0 / ((t1 - t0) - (u1 - u0))
    ref_cadence_spm = (
        60.0 * float(np.mean(2.0 / (straight_s[:, 1] - straight_s[:, 0]))) if straight_s.size else math.nan
    )
    peer = (math.nan, math.nan)
    if with_mobgap:
        peer = _mobgap_trial(rec, (height_cm / 100.0) if sensor_height_m else 0.95 / ratio, ratio, t0, t1)
    return {
        "trial": lb.name,
        "ref_cadence_spm": ref_cadence_spm,
        "mobgap_cadence_err": peer[0] - ref_cadence_spm,
        "mobgap_speed_err": peer[1] - ref_speed,
        "rows": rows,
        "valid": metrics.flag_fraction(valid, straight),
        "coverage": metrics.coverage_fraction(f, f_std, f_ref, straight & valid),
        "wrong": metrics.confidently_wrong_fraction([(f, f_std, f_ref, WRONG_F_HZ)], valid, straight),
        "startup_steps": float(np.count_nonzero(starts < t[after[0]]) - 1) if after.size else math.nan,
        "speed_err": float(np.median(res["speed_mps"][walking & valid]) - ref_speed)
        if (walking & valid).any()
        else math.nan,
        "ref_speed": ref_speed,
    }


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--data", required=True, type=Path, help="the data set's GaitData folder")
    ap.add_argument("--jobs", type=int, default=2)
    ap.add_argument("--sensor-height-ratio", type=float, default=0.60)
    ap.add_argument("--no-mobgap", action="store_true", help="leave the peer out")
    a = ap.parse_args()
    with_mobgap = not a.no_mobgap
    if with_mobgap:
        try:
            import mobgap  # noqa: F401
        except ImportError:
            print("mobgap is not installed (pip install 'yoyogait[mobgap]'): the peer is left out\n")
            with_mobgap = False
    trials = sorted(a.data.glob("*_lb.txt"))
    if not trials:
        raise SystemExit(f"{a.data}: no *_lb.txt (the data set's GaitData folder?)")
    jobs = [
        (lb, lb.with_name(lb.name[: -len("_lb.txt")] + ".json"), a.sensor_height_ratio, with_mobgap) for lb in trials
    ]
    with ProcessPoolExecutor(a.jobs) as pool:
        out = list(pool.map(evaluate_trial, jobs))
    print(f"# Lower-back IMU on {len(out)} trials of the IPOL healthy-gait data set (not used for any setting)\n")
    print("| strides | n (valid over half) | cadence error, median [steps/min] | 95th pct. | signed median |")
    print("|---|---:|---:|---:|---:|")
    for turn in (False, True):
        rr = [r for o in out for r in o["rows"] if r["turn"] == turn]
        e = np.array([60.0 * (r["est_hz"] - r["ref_hz"]) for r in rr])
        e = e[np.isfinite(e)]
        name = "overlapping the U-turn" if turn else "straight"
        print(f"| {name} | {len(rr)} ({e.size}) | {np.median(np.abs(e)):.2f} | {np.percentile(np.abs(e), 95):.2f} "
              f"| {np.median(e):+.2f} |")  # fmt: skip
    per_trial = []
    for o in out:
        rr = [r for r in o["rows"] if not r["turn"] and np.isfinite(r["est_hz"])]
        if rr:
            per_trial.append(60.0 * abs(np.mean([r["est_hz"] for r in rr]) - np.mean([r["ref_hz"] for r in rr])))
    pt = np.array(per_trial)
    wrong = np.array([o["wrong"] for o in out])
    cov = np.array([o["coverage"] for o in out])
    val = np.array([o["valid"] for o in out])
    st = np.array([o["startup_steps"] for o in out])
    se = np.array([o["speed_err"] for o in out])
    worst = max(out, key=lambda o: o["wrong"])
    print()
    print("| per trial | median | worst | target (docs/imu.md) |")
    print("|---|---:|---:|---|")
    print(f"| cadence error (straight strides), steps/min ({pt.size} of {len(out)} trials) | {np.median(pt):.2f} | "
          f"{pt.max():.2f} | <= 2 |")  # fmt: skip
    print(f"| step frequency within 2 std, valid samples | {100 * np.median(cov):.1f} % | {100 * cov.min():.1f} % "
          "| >= 90 % |")  # fmt: skip
    print(f"| confidently wrong, straight walking | {100 * np.median(wrong):.2f} % | {100 * wrong.max():.2f} % "
          f"({worst['trial']}; {np.count_nonzero(wrong > 0.01)} trials over 1 %) | <= 1 % |")  # fmt: skip
    print(f"| valid, straight walking | {100 * np.median(val):.0f} % | {100 * val.min():.0f} % | |")
    print(f"| start-up, steps from the first footstep to valid | {np.nanmedian(st):.0f} | {np.nanmax(st):.0f} | <= 2 |")
    print(f"| speed while valid minus 20 m / (trial - U-turn time), m/s (approximate) | {np.nanmedian(se):+.3f} | "
          f"{se[np.nanargmax(np.abs(se))]:+.3f} | |")  # fmt: skip
    if with_mobgap:
        mc = np.array([o["mobgap_cadence_err"] for o in out])
        ms = np.array([o["mobgap_speed_err"] for o in out])
        missed = int(np.count_nonzero(~np.isfinite(mc)))
        print(f"| mobgap (offline, healthy pipeline): cadence error, steps/min ({mc.size - missed} of {len(out)} "
              f"trials with a bout) | {np.nanmedian(np.abs(mc)):.2f} | {np.nanmax(np.abs(mc)):.2f} | |")  # fmt: skip
        print(f"| mobgap: speed minus 20 m / (trial - U-turn time), m/s (approximate) | {np.nanmedian(ms):+.3f} | "
              f"{ms[np.nanargmax(np.abs(ms))]:+.3f} | |")  # fmt: skip


if __name__ == "__main__":
    main()
