"""The lower-back IMU estimator against its targets (docs/imu.md): prints the targets table.

    python bench/imu.py [--data DIR] [--no-mobgap] [--no-timing] [--no-synthetic] [--peer-cache FILE]

* Real data (``DIR``, default $YOYOGAIT_DATASETS/imu_mobgap/example_data/data/lab): per walking bout
  of each reference system (INDIP, Stereophoto), the median absolute cadence (steps/min), walking
  speed (m/s) and stride time (s) error of the online IMU estimator, beside mobgap's offline
  pipeline (when installed) and the adaptive oscillator fed the IMU front-end's velocities.
* SYNTHETIC IMU lab: each subject straight, sensor tilts 0, 10, 20 deg (forward, half as much
  sideways) and gyro biases 0 and 1 deg/s on every axis: the median relative step-frequency error
  and the median speed error from 3 s of walking on; the worst over the grid.
* ns per sample of the C++ ``ImuOnlineEstimator::update`` at 100 Hz (bench/bench_imu.cpp, -O3),
  median of rounds.

A benchmark, not a test: the figures are measured, the targets fixed beforehand.
"""

from __future__ import annotations

import argparse
import json
import math
import os
import subprocess
import tempfile
from pathlib import Path

import numpy as np

from yoyogait.estimators.imu import estimator_for
from yoyogait.evaluation import imu as ev
from yoyogait.synthetic import SUBJECTS
from yoyogait.synthetic_imu import make_imu_walk

ROOT = Path(__file__).resolve().parents[1]


def _mark(ok: bool) -> str:
    return "met" if ok else "NOT met"


def real(data: Path, peer: bool, peer_cache: Path | None = None) -> list[str]:
    rows = []
    cover: list = []
    starts: list = []
    note = ""
    cached = json.loads(peer_cache.read_text()) if peer_cache is not None and peer_cache.is_file() else {}
    for rec in ev.imu_recordings(data):
        bouts = None
        if peer:
            try:
                bouts = cached[rec.source] if rec.source in cached else ev.run_mobgap(rec)
                cached[rec.source] = bouts
            except ImportError:
                note, peer = "mobgap not installed: its column is empty", False
        r, res = ev.evaluate_recording(rec, None, bouts)
        rows += r
        for ref, c in ev.coverage(rec, res).items():
            cover.append((rec.source.split("lab/")[-1], ref, c))
        starts += ev.startup(rec, res)
    if peer_cache is not None and cached:
        peer_cache.write_text(json.dumps(cached))
    summ = {(d["reference"], d["estimator"]): d for d in ev.summary(rows)}
    out = ["## Real data: median absolute error over the reference's walking bouts", ""]
    if note:
        out += [note, ""]
    out += [
        "| reference | quantity | yoyogait IMU (online) | mobgap (offline) | oscillator (IMU v_z) | target | |",
        "|---|---|---|---|---|---|---|",
    ]
    for ref in sorted({k[0] for k in summ}):
        y = summ[(ref, "yoyogait-imu")]
        m = summ.get((ref, "mobgap"))
        o = summ[(ref, "oscillator-imu")]

        def cell(d, key):
            return f"{d[key]:.3f}" if d is not None and math.isfinite(d[key]) else "-"

        for key, label, limit, slack, unit in (
            ("median_abs_cadence_error_spm", "cadence", 2.0, 0.0, "steps/min"),
            ("median_abs_speed_error_mps", "speed", 0.10, 0.02, "m/s"),
            ("median_abs_stride_time_error_s", "stride time", 0.03, None, "s"),
        ):
            ok = y[key] <= limit
            target = f"<= {limit:g} {unit}"
            if slack is not None and m is not None:
                ok = ok and y[key] <= m[key] + slack
                target += " and <= mobgap" + (f" + {slack:g}" if slack else "")
            out.append(
                f"| {ref} | {label} | {cell(y, key)} | {cell(m, key)} | {cell(o, key)} | {target} | {_mark(ok)} |"
            )
    out.append("")
    refs = sorted({k[0] for k in summ})
    out.append(
        "Bouts: "
        + ", ".join(
            f"{r}: {summ[(r, 'yoyogait-imu')]['bouts']} (yoyogait missed {summ[(r, 'yoyogait-imu')]['missed']}"
            + (f", mobgap {summ[(r, 'mobgap')]['missed']}" if (r, "mobgap") in summ else "")
            + ")"
            for r in refs
        )
        + f"; strides counted by yoyogait: {sum(x.strides for x in rows if x.estimator == 'yoyogait-imu')} of "
        f"{sum(x.ref_strides for x in rows if x.estimator == 'yoyogait-imu')}."
    )
    out.append("")
    out.append(
        "The medians are over the bouts scored; a missed bout (no stride valid over half of it) has no error "
        "and is left out of them. Counted as an error larger than any instead: "
        + ", ".join(
            f"{r} cadence {summ[(r, 'yoyogait-imu')]['median_missed_worst_abs_cadence_error_spm']:.3f}, "
            f"stride time {summ[(r, 'yoyogait-imu')]['median_missed_worst_abs_stride_time_error_s']:.3f}"
            for r in refs
        )
        + ". Missed: "
        + (
            "; ".join(
                f"{x.recording.split('lab/')[-1]} {x.reference} bout {x.bout} ({x.start_s:.1f}-{x.end_s:.1f} s)"
                for x in rows
                if x.estimator == "yoyogait-imu" and not math.isfinite(x.cadence_spm)
            )
            or "none"
        )
        + "."
    )
    out.append("")
    out.append(
        "The speed's target is scored against the bout's walking speed, the reference's mean over every stride it "
        "measured, as mobgap's bouts are; the cadence is scored over the strides the estimate is valid over. The "
        "speed scored like the cadence, against the reference's own speeds of those strides (for information; "
        "the target stays as above): "
        + ", ".join(
            f"{r} {summ[(r, 'yoyogait-imu')]['median_abs_stride_speed_error_mps']:.3f} m/s "
            f"(worst {summ[(r, 'yoyogait-imu')]['max_abs_stride_speed_error_mps']:.3f}; against the bout's "
            f"{summ[(r, 'yoyogait-imu')]['median_abs_speed_error_mps']:.3f})"
            for r in refs
        )
        + "."
    )
    out += ["", "## Real data: the calibration participant (HA/001) and the held-out ones apart", "",
            "| participants | reference | bouts scored (missed) | cadence | stride time | speed |",
            "|---|---|---|---|---|---|"]  # fmt: skip
    for label, pick in (("HA/001 (calibration)", True), ("HA/002, MS/001 (held out)", False)):
        part = [x for x in rows if x.estimator == "yoyogait-imu" and ("/HA/001/" in x.recording) == pick]
        for d in ev.summary(part):
            out.append(f"| {label} | {d['reference']} | {d['scored']} ({d['missed']}) "
                       f"| {d['median_abs_cadence_error_spm']:.3f} | {d['median_abs_stride_time_error_s']:.3f} "
                       f"| {d['median_abs_speed_error_mps']:.3f} |")  # fmt: skip
    out += ["", "## Real data: 2-std coverage and confidently-wrong time (every sample inside the bouts)", "",
            "| recording | reference | samples | valid | cadence within 2 std | speed within 2 std "
            "| confidently wrong | f std while valid [Hz] | f error while valid, 95th pct. [Hz] "
            "| speed std while valid [m/s] | speed error while valid, 95th pct. [m/s] |",
            "|---|---|---|---|---|---|---|---|---|---|---|"]  # fmt: skip
    for name, ref, c in cover:
        out.append(f"| {name} | {ref} | {c['samples']} | {100 * c['valid']:.0f} % | {100 * c['cadence_2std']:.0f} % "
                   f"| {100 * c['speed_2std']:.0f} % | {100 * c['confidently_wrong']:.1f} % "
                   f"| {c['f_std_valid_hz']:.3f} | {c['f_err_valid_p95_hz']:.3f} "
                   f"| {c['speed_std_valid_mps']:.3f} | {c['speed_err_valid_p95_mps']:.3f} |")  # fmt: skip
    cov = [min(c["cadence_2std"], c["speed_2std"]) for _, _, c in cover]
    wrong = [c["confidently_wrong"] for _, _, c in cover]
    out += ["", f"Worst recording: coverage {100 * min(cov):.0f} % (target >= 90 %: {_mark(min(cov) >= 0.9)}), "
            f"confidently wrong {100 * max(wrong):.1f} % (target <= 1 %: {_mark(max(wrong) <= 0.01)})."]  # fmt: skip
    out += ["", "## Real data: start-up (each recording's first bout: from standing), in steps from the first contact",
            "", "| recording | reference | bout start [s] | to valid | to valid and within 5 % of the cadence |",
            "|---|---|---|---|---|"]  # fmt: skip
    for s in starts:
        out.append(f"| {s['recording'].split('lab/')[-1]} | {s['reference']} | {s['start_s']:.2f} "
                   f"| {s['valid_steps']:.1f} | {s['within5_steps']:.1f} |")  # fmt: skip
    v = np.array([s["valid_steps"] for s in starts])
    w = np.array([s["within5_steps"] for s in starts])
    out += ["", f"Median (worst) to valid {np.nanmedian(v):.1f} ({np.nanmax(v):.1f}) steps, to within 5 % "
            f"{np.nanmedian(w):.1f} ({np.nanmax(w):.1f}) steps "
            f"(target <= 2 steps: {_mark(np.nanmedian(w) <= 2)})."]  # fmt: skip
    return out


def synthetic() -> list[str]:
    out = ["## SYNTHETIC IMU lab: median error from 3 s of walking on", ""]
    out += [
        "| subject | tilt [deg] | gyro bias [deg/s] | step frequency error [%] | speed error [m/s] |",
        "|---|---|---|---|---|",
    ]
    worst_f = worst_v = 0.0
    for s in SUBJECTS:
        for tilt in (0.0, 10.0, 20.0):
            for bias in (0.0, 1.0):
                w = make_imu_walk(
                    s, tilt_pitch_deg=tilt, tilt_roll_deg=tilt / 2, gyro_bias_rad_s=np.deg2rad([bias] * 3)
                )
                res = estimator_for(w.recording).run_recording(w.recording)
                m = res.time_s >= 1.0 + 1.5 + 3.0
                fe = 100 * abs(float(np.median(res["step_frequency_hz"][m] / w.truth.step_frequency_hz[m] - 1)))
                ve = abs(float(np.median(res["speed_mps"][m] - w.truth.speed_mps[m])))
                worst_f, worst_v = max(worst_f, fe), max(worst_v, ve)
                out.append(f"| {s.name} | {tilt:g} | {bias:g} | {fe:.3f} | {ve:.3f} |")
    out += ["", f"Worst: step frequency {worst_f:.3f} % (target <= 1 %: {_mark(worst_f <= 1)}), "
            f"speed {worst_v:.3f} m/s (target <= 0.05 m/s: {_mark(worst_v <= 0.05)})."]  # fmt: skip
    return out


def timing() -> list[str]:
    with tempfile.TemporaryDirectory() as tmp:
        exe = Path(tmp) / "bench_imu"
        subprocess.run(["c++", "-O3", "-std=c++17", "-DNDEBUG", f"-I{ROOT / 'include'}",
                        str(ROOT / "bench" / "bench_imu.cpp"), "-o", str(exe)], check=True)  # fmt: skip
        r = json.loads(subprocess.run([str(exe)], check=True, capture_output=True, text=True).stdout)
        m = json.loads(subprocess.run([str(exe), "60000", "9", "mag"], check=True, capture_output=True,
                                      text=True).stdout)  # fmt: skip
    ok = r["median_ns"] <= 300
    return ["## C++ update at 100 Hz", "",
            f"{r['median_ns']:.0f} ns per sample (median of {r['rounds']} rounds of {r['samples']} samples; "
            f"worst round {r['max_ns']:.0f} ns); target <= 300 ns: {_mark(ok)}. With a magnetometer: "
            f"{m['median_ns']:.0f} ns (worst round {m['max_ns']:.0f} ns)."]  # fmt: skip


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    default = (
        Path(os.environ.get("YOYOGAIT_DATASETS", ROOT.parent / "shared" / "datasets"))
        / "imu_mobgap/example_data/data/lab"
    )
    ap.add_argument("--data", type=Path, default=default)
    ap.add_argument("--no-mobgap", action="store_true")
    ap.add_argument("--no-timing", action="store_true")
    ap.add_argument("--no-synthetic", action="store_true")
    ap.add_argument("--peer-cache", type=Path, default=None, help="a JSON file keeping mobgap's bouts between runs")
    args = ap.parse_args()
    lines = ["# IMU targets", ""]
    if args.data.is_dir():
        lines += real(args.data, not args.no_mobgap, args.peer_cache) + [""]
    else:
        lines += [f"(real data not found at {args.data})", ""]
    if not args.no_synthetic:
        lines += synthetic() + [""]
    if not args.no_timing:
        lines += timing()
    print("\n".join(lines))


if __name__ == "__main__":
    main()
