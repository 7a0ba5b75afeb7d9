"""Online estimator: native ns per frame and an online evaluation against the offline pipeline.

    python bench/online.py [--rates 30,60,100,120,200,250] [--no-real] [--timing-only] [--reference-only]
                           [--python-cost]

* ns per frame of the C++ ``OnlineEstimator::update`` (front-end and estimator), built here with
  the system compiler at -O3 (bench/bench_online.cpp), median of rounds.
* ``--python-cost`` (alone): the per-frame cost of ``yoyogait.OnlineEstimator.update`` called from a
  Python loop against the C++ update of the same frames in the same process (``run``, the loop in
  C++), at 30, 60, 100 and 250 Hz: CPU time of this thread (time.thread_time_ns, so that time the
  thread waits for a core does not count), rounds alternating the two; the ratio Python / C++ per
  round, its median and worst (target: <= 2).
* Over the shared manifest and the synthetic lab at the native capture rate, and over the
  synthetic lab generated at each rate of ``--rates``: the step-frequency error (median absolute,
  Hz) within the first 3 s of walking and after them (reference: the synthetic truth, on real data
  the cadence from gait events, as in the evaluation); the lag of the online v_z behind the offline
  centred Savitzky-Golay velocity (cross-correlation, ms); the reconstruction errors of vx_hat_mps and
  vz_hat_mps at the frames' own times (mean squared, 1e-2 (m/s)^2, walking after 3 s): against a
  synthetic walk's own velocities, on real data against the offline velocities computed at the
  capture rate (v_x along the heading). The offline default estimator's figures on the same
  samples are given beside them. A benchmark, not a test.
* Every rate of ``--rates`` against the same walks at ``--reference-hz`` (25) input: the synthetic
  lab rendered once at a rate all of them divide and decimated, the real recordings against every
  k-th of their frames; medians and a one-sided paired Wilcoxon test per figure
  (``--reference-only``: this comparison alone).
"""

from __future__ import annotations

import argparse
import dataclasses
import functools
import subprocess
import tempfile
from pathlib import Path

import numpy as np
from scipy import stats

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


def decimation_factor(rate_hz: float, reference_hz: float) -> int:
    """The integer factor that brings ``rate_hz`` closest to ``reference_hz`` (1: no reduction)."""
    return max(1, int(round(rate_hz / reference_hz)))


def every_kth_frame(rec, k: int):
    """The recording with every k-th frame (the same walk seen by a slower camera)."""
    if k == 1:
        return rec
    rate_hz = None if rec.rate_hz is None else rec.rate_hz / k
    return dataclasses.replace(rec, positions_m=rec.positions_m[::k], time_s=rec.time_s[::k], rate_hz=rate_hz)


def _load_every_kth_frame(load, k):
    return every_kth_frame(load(), k)


def decimated_item(item, k: int):
    """The item with every k-th frame of its recording."""
    return dataclasses.replace(item, load=functools.partial(_load_every_kth_frame, item.load, k))


def evaluate(item, config=None, decimate_to_hz=None):
    """One walk's figures; ``decimate_to_hz``: the online estimator is fed every k-th frame only
    (k = :func:`decimation_factor`, what a camera at 1/k of the rate would have delivered; None when
    k would be 1), everything it is scored against unchanged."""
    rec = item.load()
    decimate = 1 if decimate_to_hz is None else decimation_factor(rec.rate_hz, decimate_to_hz)
    if decimate_to_hz is not None and decimate < 2:
        return None
    names = list(item.pelvis) if item.pelvis else list(points.choose_point(rec).names)
    up, _ = points.resolve_up_axis(rec, item.up_axis)
    vel = gait_velocities(rec, point=names, up_axis=up)
    t = vel.time_s
    if item.truth is not None:
        tr = item.truth.at(t)
        f_ref, walking = tr.step_frequency_hz, np.asarray(tr.walking, dtype=bool)
    else:
        f_ref, _, walking, _ = real_reference(rec, vel, item)
    walking = walking & np.isfinite(vel.vx) & np.isfinite(vel.vz)
    if not walking.any():
        return None
    t_walk = t[np.flatnonzero(walking)[0]]
    early = walking & (t < t_walk + 3.0)
    late = walking & (t >= t_walk + 3.0)
    res = OnlineEstimator(names, up, config=config).run(every_kth_frame(rec, decimate))
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

    def at_frames(y):
        return np.interp(res.time_s, t, np.asarray(y, dtype=float), left=np.nan, right=np.nan)

    late_frames = at_frames(late.astype(float)) > 0.5
    # What the walker did at the frames' own times: a SYNTHETIC walk's own velocities, else the offline
    # velocities at the capture rate (whose grid holds every frame, also of every k-th frame). The
    # 25 Hz offline grid interpolated to a 30 Hz frame's time adds an error of its own: on the
    # SYNTHETIC lab the 30 Hz input's v_z recon read 0.060 against 0.049 at 25 Hz that way, while
    # against the walks' own v_z it is 0.028 against 0.037.
    if item.truth is not None:
        tf = item.truth.at(res.time_s)
        vz_at, vx_at = np.asarray(tf.vz_mps, dtype=float), np.asarray(tf.vx_path_mps, dtype=float)
    else:
        native = gait_velocities(rec, point=names, up_axis=up, rate_hz=1.0 / float(np.median(np.diff(rec.time_s))))
        vz_at = np.interp(res.time_s, native.time_s, native.vz, left=np.nan, right=np.nan)
        vx_at = np.interp(res.time_s, native.time_s, native.vx_signed, left=np.nan, right=np.nan)

    # Lag of v_z at the capture rate against the offline centred SG velocity of the same centre.
    rate = 1.0 / float(np.median(np.diff(rec.time_s)))
    centre, _ = points.robust_centre(rec.points(names))
    k = "xyz".index(up)
    vz_sg = savgol_velocity(centre, rate, savgol_window_samples(0.25, rate, 3), 3)[:, k]
    vz_sg, frame_t, rate = vz_sg[::decimate], rec.time_s[::decimate], rate / decimate
    walk_frames = np.interp(frame_t, t, walking.astype(float)) > 0.5
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
        # The reconstructions at the frames' own times, against the offline velocities interpolated
        # there (as the online evaluation scores them): holding a frame's output until a 25 Hz grid
        # time would add up to a frame interval of age at rates the grid does not divide.
        vz_mse=mse(res.vz_hat_mps, vz_at, late_frames),
        vx_mse=mse(res.vx_hat_mps, vx_at, late_frames),
        vz_mse_off=mse(off.vz_hat_h2_mps, vel.vz, late),
        vx_mse_off=mse(off.vx_hat_h2_mps, vel.vx_signed, late),
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
                [str(exe), str(rounds), "0.04", str(rate), *mode], check=True, capture_output=True, text=True
            ).stdout
            for mode in ((), ("treadmill",))
            for rate in (30, 100, 250)
        ]
    return "".join(out).strip()


def centre_frames(rate_hz: float, duration_s: float):
    """SYNTHETIC: the pelvis centre of the synthetic lab's straight walk (metres, z up): times, n x 3."""
    from yoyogait import synthetic

    rec = synthetic.make_walk(
        synthetic.get_subject("synthetic-S1"), "1-straight", duration_s=duration_s, rate_hz=rate_hz
    ).recording
    centre = np.nanmean(rec.points(["LASI", "RASI", "LPSI", "RPSI"]), axis=1)
    return rec.time_s, np.where(np.isfinite(centre), centre, np.nanmean(centre, axis=0))


def python_cost(rate_hz: float, rounds: int = 15, duration_s: float = 20.0) -> dict:
    """ns per frame of ``OnlineEstimator.update`` from a Python loop (one point, a 1 x 3 float64 frame per
    call as a live source hands it over; and ``update_point`` with the three numbers) against the C++
    loop (``run``) over the same frames, alternating in each round; the ratios per round."""
    import time

    t, centre = centre_frames(rate_hz, duration_s)
    times = [float(v) for v in t]
    frames = [np.ascontiguousarray(c.reshape(1, 3)) for c in centre]
    coords = [tuple(float(v) for v in c) for c in centre]
    stacked = np.ascontiguousarray(centre[:, None, :])
    none = np.zeros(0)
    clock = time.thread_time_ns
    cpp, py, point = [], [], []
    for _ in range(rounds):
        est = OnlineEstimator(["pelvis"], "z", 1.0)
        start = clock()
        est._impl.run(t, stacked, none)
        cpp.append((clock() - start) / len(t))
        update = OnlineEstimator(["pelvis"], "z", 1.0).update
        start = clock()
        for t_s, frame in zip(times, frames):
            update(t_s, frame)
        py.append((clock() - start) / len(t))
        update_point = OnlineEstimator(["pelvis"], "z", 1.0).update_point
        start = clock()
        for t_s, (x, y, z) in zip(times, coords):
            update_point(t_s, x, y, z)
        point.append((clock() - start) / len(t))
    ratio = np.array(py) / np.array(cpp)
    ratio_point = np.array(point) / np.array(cpp)
    return {
        "rate_hz": rate_hz,
        "frames": len(t),
        "cpp_ns": float(np.median(cpp)),
        "python_ns": float(np.median(py)),
        "point_ns": float(np.median(point)),
        "ratio_median": float(np.median(ratio)),
        "ratio_worst": float(np.max(ratio)),
        "point_ratio_median": float(np.median(ratio_point)),
        "point_ratio_worst": float(np.max(ratio_point)),
    }


def print_python_cost(rates=(30.0, 60.0, 100.0, 250.0), rounds: int = 15) -> None:
    print(
        "OnlineEstimator.update from Python against the C++ update (one point, SYNTHETIC walk of 20 s, "
        f"{rounds} alternating rounds, thread CPU time; target <= 2x)\n"
    )
    print("| rate | C++ ns/frame | Python update ns | ratio median | worst | update_point ns | ratio median | worst |")
    print("|---|---:|---:|---:|---:|---:|---:|---:|")
    for rate in rates:
        r = python_cost(rate, rounds)
        print(
            f"| {rate:g} Hz | {r['cpp_ns']:.0f} | {r['python_ns']:.0f} | {r['ratio_median']:.2f} | "
            f"{r['ratio_worst']:.2f} | {r['point_ns']:.0f} | {r['point_ratio_median']:.2f} | "
            f"{r['point_ratio_worst']:.2f} |",
            flush=True,
        )


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--python-cost", action="store_true", help="only the Python against C++ update cost")
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
    ap.add_argument(
        "--reference-hz",
        type=float,
        default=25.0,
        help="compare every rate with the same walks at this input rate (0: no comparison)",
    )
    ap.add_argument("--reference-only", action="store_true", help="only the comparison with the reference input rate")
    ap.add_argument("--datasets", default=str(ROOT.parent / "shared" / "datasets"))
    args = ap.parse_args()
    if args.python_cost:
        print_python_cost()
        return
    if not args.reference_only:
        print(timing())
    if args.timing_only:
        return
    config = OnlineConfig() if args.antialias_hz is None else OnlineConfig(antialias_hz=args.antialias_hz)
    if args.estimator_period_s is not None:
        config.estimator = EstimatorConfig(sample_time_s=args.estimator_period_s)
    print()
    print(header())
    groups = []
    real_items = []
    if not args.no_real:
        real_items, _ = manifest_items(Path(args.datasets) / "manifest.json")
        groups.append(("real (manifest), native rate", real_items))
    rates = [float(r) for r in args.rates.split(",") if r]
    if not args.reference_only:
        groups.append(("synthetic lab, 100 Hz", synthetic_items(rate_hz=100.0)))
        for rate in rates:
            groups.append((f"synthetic lab, {rate:g} Hz", synthetic_items(rate_hz=rate)))
    results = {}
    for label, items in groups:
        rows = evaluate_all(items, config)
        results[label] = rows
        print_group(label, rows, args.per_recording)
    if args.reference_hz > 0:
        reference_comparison(args, config, results, real_items, rates)


def evaluate_all(items, config, decimate_to_hz=None):
    """Rows of ``evaluate`` for the items (a recording the pipeline cannot use is reported, not fatal)."""
    rows = []
    for item in items:
        try:
            r = evaluate(item, config, decimate_to_hz)
        except Exception as exc:
            print(f"  skipped {item.name}: {exc}")
            continue
        if r is not None:
            rows.append(r)
    return rows


def print_group(label, rows, per_recording=False):
    print(summary(label + " (median)", rows), flush=True)
    print(summary(label + " (mean)", rows, np.mean), flush=True)
    if per_recording:
        for r in rows:
            print(summary(f"  {r['name']} {r['rate_hz']:.0f} Hz", [r]))


# (key, label, lower is better as absolute value)
COMPARED = (
    ("f_late", "f err >3 s"),
    ("f_early", "f err <3 s"),
    ("lag_ms", "|v_z lag| ms"),
    ("vz_mse", "v_z recon"),
    ("vx_mse", "v_x recon"),
)


def compare(label, rows, reference_rows):
    """A row: each figure's median at the rate / at the reference input on the same walks, and
    whether the rate is worse: one-sided Wilcoxon signed-rank test of the paired per-walk values,
    p < 0.05 (with fewer than 6 pairs no test can say so, shown as "n < 6")."""
    by_name = {r["name"]: r for r in reference_rows}
    pairs = [(r, by_name[r["name"]]) for r in rows if r["name"] in by_name]
    cells, worse = [], []
    for key, name in COMPARED:
        ok = [(abs(r[key]), abs(q[key])) for r, q in pairs if np.isfinite(r[key]) and np.isfinite(q[key])]
        if not ok:
            cells.append("-")
            continue
        a, b = np.array(ok).T
        ma, mb = float(np.median(a)), float(np.median(b))
        if len(a) < 6:
            p = "n < 6"
        elif np.all(a == b):
            p = "p = 1"
        else:
            pv = float(stats.wilcoxon(a, b, alternative="greater").pvalue)
            p = f"p = {pv:.2f}"
            if pv < 0.05:
                worse.append(name)
        cells.append(f"{ma:.3g} / {mb:.3g} (n {len(a)}, {p})")
    verdict = "worse: " + ", ".join(worse) if worse else "no"
    return f"| {label} | {len(pairs)} | " + " | ".join(cells) + f" | {verdict} |"


def reference_comparison(args, config, results, real_items, rates):
    """Every capture rate against the same walks at the reference input rate (25 Hz)."""
    ref_hz = args.reference_hz
    print()
    print(
        f"Against {ref_hz:g} Hz input on the same walks (median at the rate / median at {ref_hz:g} Hz; "
        "worse: one-sided paired Wilcoxon test, p < 0.05):"
    )
    print()
    print(
        "| data | n | "
        + " | ".join(name for _, name in COMPARED)
        + f" | worse than {ref_hz:g} Hz |\n|"
        + "---|" * (len(COMPARED) + 3)
    )
    # The synthetic lab rendered once at a rate that every compared rate divides, then every k-th
    # frame: the same walks, the same marker noise at the frames that two rates share.
    base_hz = float(np.lcm.reduce([int(round(r)) for r in [*rates, ref_hz]]))
    base = synthetic_items(rate_hz=base_hz)
    ref_rows = evaluate_all([decimated_item(i, int(round(base_hz / ref_hz))) for i in base], config)
    for rate in rates:
        rows = evaluate_all([decimated_item(i, int(round(base_hz / rate))) for i in base], config)
        print(compare(f"synthetic lab, {rate:g} Hz (from {base_hz:g} Hz)", rows, ref_rows), flush=True)
    if real_items:
        # Each recording with every k-th frame (k = its rate / 25, rounded; recordings below
        # 1.5 x 25 Hz have no lower rate and are left out).
        dec_rows = evaluate_all(real_items, config, decimate_to_hz=ref_hz)
        native = results["real (manifest), native rate"]
        print(compare("real (manifest), native rate", native, dec_rows), flush=True)
        for lo, hi in ((45, 80), (80, 160), (160, 260)):
            sub = [r for r in native if lo <= r["rate_hz"] < hi]
            if sub:
                print(compare(f"real, {lo}-{hi} Hz", sub, dec_rows), flush=True)


if __name__ == "__main__":
    main()
