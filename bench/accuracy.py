"""Accuracy of the default estimator against its targets, measured with `yoyogait evaluate`'s machinery.

    python bench/accuracy.py [--manifest ../shared/datasets/manifest.json] [--out DIR]

Evaluates paper, default, the adaptive oscillator and the sliding-DFT bound on the real recordings of
the manifest and on the synthetic lab, and prints one Markdown table per data set with each target,
the measured value and whether it is met. The numbers in the README come from this script.
"""

from __future__ import annotations

import argparse
import sys
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[1]

from yoyogait import evaluation as ev  # noqa: E402
from yoyogait.evaluation import metrics  # noqa: E402

ESTIMATORS = ("paper", "default", "oscillator", "sliding-dft")


def _values(evaluation, est, key):
    return np.array([r.metrics[est].get(key, np.nan) for r in evaluation.items], dtype=float)


def _med(evaluation, est, key):
    v = _values(evaluation, est, key)
    return float(np.nanmedian(v)) if np.isfinite(v).any() else float("nan")


def _row(target, value, ok):
    return f"| {target} | {value} | {'met' if ok else '**missed**'} |"


def real_targets(e) -> list[str]:
    rows = ["| target (real recordings) | measured | |", "|---|---|---|"]
    vx_p, vx_d = _med(e, "paper", "vx_sq_err_mean_1e-2"), _med(e, "default", "vx_sq_err_mean_1e-2")
    worse = [
        r.item.name
        for r in e.items
        if r.metrics["default"]["vx_sq_err_mean_1e-2"] > r.metrics["paper"]["vx_sq_err_mean_1e-2"]
    ]
    rows.append(
        _row(
            "v_x error median <= 1/30 of paper's", f"{vx_d:.3g} vs {vx_p:.3g} (1/{vx_p / vx_d:.0f})", vx_d <= vx_p / 30
        )
    )
    rows.append(_row("no recording with v_x error worse than paper's", f"{len(worse)} worse {worse[:3]}", not worse))
    vz_p, vz_d = _med(e, "paper", "vz_sq_err_mean_1e-2"), _med(e, "default", "vz_sq_err_mean_1e-2")
    rows.append(
        _row("v_z error median <= 1/4 of paper's", f"{vz_d:.3g} vs {vz_p:.3g} (1/{vz_p / vz_d:.1f})", vz_d <= vz_p / 4)
    )
    f_d, f_o = _med(e, "default", "f_err_median_hz"), _med(e, "oscillator", "f_err_median_hz")
    n_f = int(np.isfinite(_values(e, "default", "f_err_median_hz")).sum())
    rows.append(
        _row(
            "step frequency error after 3 s of walking, median <= 0.05 Hz",
            f"{f_d:.4f} Hz over {n_f} recordings with > 3 s of walking",
            f_d <= 0.05,
        )
    )
    neg = np.nanmax(_values(e, "default", "f_wrong_sign_fraction"))
    rows.append(_row("no negative frequency", f"largest negative fraction {neg:.3g}", neg == 0))
    rows.append(_row("step frequency better than the oscillator", f"{f_d:.4f} vs {f_o:.4f} Hz", f_d < f_o))
    for comp in ("vx", "vz"):
        key = f"pred200ms_{comp}_sq_err_mean_1e-2"
        d, p, o = (_med(e, est, key) for est in ("default", "paper", "oscillator"))
        rows.append(
            _row(
                f"0.2 s-ahead {comp} error below paper's and the oscillator's",
                f"{d:.3g} vs {p:.3g} and {o:.3g}",
                d < p and d < o,
            )
        )
    return rows


def reacquisition_s(r, est) -> list[tuple[float, float]]:
    """Per resumption of walking (synthetic stop-and-go): the time until |f error| <= 0.1 Hz and stays
    so (the convergence metric of yoyogait.metrics), counted (a) from the first sample where the true
    step frequency is above zero, which includes the lab's gait-initiation ramp up from 0 Hz, and
    (b) from the first sample where it reaches 95 % of the segment's median cadence."""
    tr = r.item.truth.at(r.velocities.time_s)
    t = r.velocities.time_s
    f_true = np.nan_to_num(tr.step_frequency_hz)
    walking = f_true > 0
    edges = np.flatnonzero(np.diff(walking.astype(int)) == 1) + 1
    ends = np.flatnonzero(np.diff(walking.astype(int)) == -1) + 1
    out = []
    resumptions = edges if walking[0] else edges[1:]  # the lab's walks start standing
    for start in resumptions:
        end = next((e for e in ends if e > start), t.size)
        seg = slice(start, end)
        err = np.abs(r.results[est].step_frequency_hz[seg]) - f_true[seg]
        onset = metrics.convergence_time_s(t[seg], err, 0.1)
        at_cadence = start + int(np.argmax(f_true[seg] >= 0.95 * np.median(f_true[seg])))
        out.append((onset, onset - (t[at_cadence] - t[start])))
    return out


def synthetic_targets(e) -> list[str]:
    rows = ["| target (synthetic lab, after 5 s of walking) | measured, worst walk | |", "|---|---|---|"]
    f_rel = []
    for r in e.items:
        tr = r.item.truth.at(r.velocities.time_s)
        ok = r.walking & (r.velocities.time_s > 5.0)
        rel = (
            np.abs(np.abs(r.results["default"].step_frequency_hz[ok]) - tr.step_frequency_hz[ok])
            / tr.step_frequency_hz[ok]
        )
        f_rel.append(float(np.nanmedian(rel)))
    worst = max(f_rel)
    rows.append(_row("step frequency within 1 % (median per walk)", f"{100 * worst:.2f} %", worst <= 0.01))
    R = np.nanmax(_values(e, "default", "R_err_median_rel_fraction"))
    rows.append(_row("R within 5 % (median per walk)", f"{100 * R:.2f} %", R <= 0.05))
    s = np.nanmax(_values(e, "default", "speed_err_median_mps"))
    rows.append(_row("stride-averaged speed within 0.03 m/s (median per walk)", f"{s:.4f} m/s", s <= 0.03))
    times = [x for r in e.items if r.item.walk == "5-stop-and-go" for x in reacquisition_s(r, "default")]
    rows.append(
        _row(
            "re-acquisition within 2 s of walking resuming (to within 0.1 Hz, staying), from the onset",
            ", ".join(f"{a:.2f} s" for a, _ in times) or "n/a",
            bool(times) and max(a for a, _ in times) <= 2.0,
        )
    )
    rows.append(
        _row(
            "... the same, counted from when the cadence is reached (end of the gait-initiation ramp)",
            ", ".join(f"{b:.2f} s" for _, b in times) or "n/a",
            bool(times) and max(b for _, b in times) <= 2.0,
        )
    )
    return rows


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--manifest", default=str(ROOT.parent / "shared" / "datasets" / "manifest.json"))
    ap.add_argument("--out", default=None, help="also write the full reports into this folder")
    args = ap.parse_args()
    lab, _, _ = ev.resolve_dataset("synthetic")
    syn = ev.evaluate(lab, ESTIMATORS, dataset="synthetic", synthetic=True, progress=True)
    print("## Synthetic lab (SYNTHETIC data)\n")
    print(ev.summary_markdown(syn) + "\n")
    print("\n".join(synthetic_targets(syn)) + "\n")
    if Path(args.manifest).is_file():
        items, missing, _ = ev.resolve_dataset(args.manifest)
        real = ev.evaluate(items, ESTIMATORS, dataset=args.manifest, failures=missing, progress=True)
        print(f"## Real recordings ({len(real.items)} of {len(items) + len(missing)} evaluated)\n")
        print(ev.summary_markdown(real) + "\n")
        print("\n".join(real_targets(real)) + "\n")
        for name, msg in real.failures:
            print(f"- not evaluated: {name}: {msg}")
        if args.out:
            ev.write_report(real, Path(args.out) / "real", force=True, figures=False)
    else:
        print(f"(no manifest at {args.manifest}: real-data targets not measured)", file=sys.stderr)
    if args.out:
        ev.write_report(syn, Path(args.out) / "synthetic", force=True, figures=False)


if __name__ == "__main__":
    main()
