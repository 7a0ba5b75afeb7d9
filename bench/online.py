"""Online estimator: native ns per frame and an online evaluation against the offline pipeline.

    python bench/online.py [--rates 30,60,100,120,200,250] [--no-real] [--timing-only]

* ns per frame of the C++ ``OnlineEstimator::update`` (front-end and estimator), built here with
  the system compiler at -O3 (bench/bench_online.cpp), median of rounds.
* Over the shared manifest and the synthetic lab at the native capture rate, and over the
  synthetic lab generated at each rate of ``--rates``: the step-frequency error (median absolute,
  Hz) within the first 3 s of walking and after them (reference: the synthetic truth, on real data
  the cadence from gait events, as in the evaluation); the lag of the online v_z behind the offline
  centred Savitzky-Golay velocity (cross-correlation, ms); the reconstruction errors of vx_hat and
  vz_hat against the offline velocities (mean squared, 1e-2 (m/s)^2, walking after 3 s; v_x against
  the offline velocity along the heading). The offline default estimator's figures on the same
  samples are given beside them. A benchmark, not a test.
"""

from __future__ import annotations

import argparse
import subprocess
import tempfile
from pathlib import Path

import numpy as np

from yoyogait.estimators import EstimatorConfig, GaitEstimator, OnlineConfig, OnlineEstimator
from yoyogait.evaluation.datasets import manifest_items, synthetic_items
from yoyogait.evaluation.running import real_reference
from yoyogait.pipeline import points
from yoyogait.pipeline.velocities import gait_velocities, savgol_velocity, savgol_window_samples

ROOT = Path(__file__).resolve().parents[1]


def lag_s(est, ref, rate_hz, max_lag_s=0.15):
    """Delay of est behind ref by cross-correlation, parabolic refinement of the peak [s]."""
    ok = np.isfinite(est) & np.isfinite(ref)
    if ok.sum() < 20:
        return np.nan
    a = np.where(ok, est - np.mean(est[ok]), 0.0)
    b = np.where(ok, ref - np.mean(ref[ok]), 0.0)
    m = int(round(max_lag_s * rate_hz))
    lags = np.arange(-m, m + 1)
    c = np.array([np.dot(a[max(0, k) : len(a) + min(0, k)], b[max(0, -k) : len(b) + min(0, -k)]) for k in lags])
    i = int(np.argmax(c))
    off = 0.0
    if 0 < i < len(c) - 1:
        den = c[i - 1] - 2 * c[i] + c[i + 1]
        off = 0.5 * (c[i - 1] - c[i + 1]) / den if den != 0 else 0.0
    return (lags[i] + off) / rate_hz


def evaluate(item, config=None):
    rec = item.load()
    names = list(item.pelvis) if item.pelvis else list(points.choose_point(rec).names)
    up, _ = points.resolve_up_axis(rec, item.up_axis)
    vel = gait_velocities(rec, point=names, up_axis=up)
    t = vel.time_s
    if item.truth is not None:
        tr = item.truth.at(t)
        f_ref, walking = tr.step_frequency_hz, np.asarray(tr.walking, dtype=bool)
    else:
        f_ref, _, walking = real_reference(rec, vel, item)
    walking = walking & np.isfinite(vel.vx) & np.isfinite(vel.vz)
    if not walking.any():
        return None
    t_walk = t[np.flatnonzero(walking)[0]]
    early = walking & (t < t_walk + 3.0)
    late = walking & (t >= t_walk + 3.0)
    res = OnlineEstimator(names, up, config=config).run(rec)
    # The online estimate in force at each grid time: the last frame at or before it.
    idx = np.clip(np.searchsorted(res.time_s, t, side="right") - 1, 0, len(res.time_s) - 1)
    f_on = res.step_frequency_hz[idx]
    off = GaitEstimator().run(vel.vx_signed, vel.vz, time_s=t)

    def med(err, m):
        e = np.abs(err[m])
        e = e[np.isfinite(e)]
        return float(np.median(e)) if len(e) else np.nan

    def mse(a, b, m):
        d = (a - b)[m]
        d = d[np.isfinite(d)]
        return float(np.mean(d**2)) * 100 if len(d) else np.nan

    # Lag of v_z at the capture rate against the offline centred SG velocity of the same centre.
    rate = 1.0 / float(np.median(np.diff(rec.time_s)))
    centre, _ = points.robust_centre(rec.points(names))
    k = "xyz".index(up)
    vz_sg = savgol_velocity(centre, rate, savgol_window_samples(0.25, rate, 3), 3)[:, k]
    walk_frames = np.interp(rec.time_s, t, walking.astype(float)) > 0.5
    lag = lag_s(np.where(walk_frames, res.vz_mps, np.nan), np.where(walk_frames, vz_sg, np.nan), rate)
    return dict(
        name=item.name,
        rate_hz=rate,
        f_late=med(f_on - f_ref, late),
        f_early=med(f_on - f_ref, early),
        f_late_off=med(off.step_frequency_hz - f_ref, late),
        f_early_off=med(off.step_frequency_hz - f_ref, early),
        lag_ms=1e3 * lag,
        latency_ms=1e3 * float(np.median(res.input_latency_s)),
        vz_mse=mse(res.vz_hat_mps[idx], vel.vz, late),
        vx_mse=mse(res.vx_hat_mps[idx], vel.vx_signed, late),
        vz_mse_off=mse(off.vz_hat_h2, vel.vz, late),
        vx_mse_off=mse(off.vx_hat_h2, vel.vx_signed, late),
    )


COLS = (
    ("f_late", "f err >3 s", "{:.3f}"),
    ("f_early", "f err <3 s", "{:.3f}"),
    ("f_late_off", "offline >3 s", "{:.3f}"),
    ("f_early_off", "offline <3 s", "{:.3f}"),
    ("lag_ms", "v_z lag ms", "{:.1f}"),
    ("latency_ms", "reported ms", "{:.1f}"),
    ("vz_mse", "v_z recon", "{:.2f}"),
    ("vx_mse", "v_x recon", "{:.2f}"),
    ("vz_mse_off", "offline v_z", "{:.2f}"),
    ("vx_mse_off", "offline v_x", "{:.2f}"),
)


def summary(label, rows, agg=np.median):
    cells = []
    for key, _, fmt in COLS:
        vals = [r[key] for r in rows if np.isfinite(r[key])]
        cells.append(fmt.format(agg(vals)) if vals else "-")
    return f"| {label} | {len(rows)} | " + " | ".join(cells) + " |"


def header():
    return "| data | n | " + " | ".join(c[1] for c in COLS) + " |\n|" + "---|" * (len(COLS) + 2)


def timing(rounds=7):
    with tempfile.TemporaryDirectory() as tmp:
        exe = Path(tmp) / "bench_online"
        subprocess.run(
            [
                "c++",
                "-O3",
                "-std=c++17",
                "-DNDEBUG",
                f"-I{ROOT / 'include'}",
                str(ROOT / "bench" / "bench_online.cpp"),
                "-o",
                str(exe),
            ],
            check=True,
        )
        out = [
            subprocess.run(
                [str(exe), str(rounds), "0.04", str(rate)], check=True, capture_output=True, text=True
            ).stdout
            for rate in (30, 100, 250)
        ]
    return "".join(out).strip()


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--rates", default="30,60,100,120,200,250")
    ap.add_argument("--no-real", action="store_true")
    ap.add_argument("--timing-only", action="store_true")
    ap.add_argument("--per-recording", action="store_true", help="a row per recording as well")
    ap.add_argument("--antialias-hz", type=float, default=None, help="override OnlineConfig.antialias_hz")
    ap.add_argument(
        "--estimator-period-s",
        type=float,
        default=None,
        help="override the estimator's sample_time_s (0.001: every frame)",
    )
    ap.add_argument("--datasets", default=str(ROOT.parent / "shared" / "datasets"))
    args = ap.parse_args()
    print(timing())
    if args.timing_only:
        return
    config = OnlineConfig() if args.antialias_hz is None else OnlineConfig(antialias_hz=args.antialias_hz)
    if args.estimator_period_s is not None:
        config.estimator = EstimatorConfig(sample_time_s=args.estimator_period_s)
    print()
    print(header())
    groups = []
    if not args.no_real:
        items, _ = manifest_items(Path(args.datasets) / "manifest.json")
        groups.append(("real (manifest), native rate", items))
    groups.append(("synthetic lab, 100 Hz", synthetic_items(rate_hz=100.0)))
    for rate in [float(r) for r in args.rates.split(",") if r]:
        groups.append((f"synthetic lab, {rate:g} Hz", synthetic_items(rate_hz=rate)))
    for label, items in groups:
        rows = []
        for item in items:
            try:
                r = evaluate(item, config)
            except Exception as exc:  # a recording the pipeline cannot use is reported, not fatal
                print(f"  skipped {item.name}: {exc}")
                continue
            if r is not None:
                rows.append(r)
        print(summary(label + " (median)", rows), flush=True)
        print(summary(label + " (mean)", rows, np.mean), flush=True)
        if args.per_recording:
            for r in rows:
                print(summary(f"  {r['name']} {r['rate_hz']:.0f} Hz", [r]))


if __name__ == "__main__":
    main()
