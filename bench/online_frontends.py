"""Design study of the online front-end's differentiator: three causal candidates, measured.

Candidates (per axis, any frame times):
  cv   constant-velocity Kalman filter, white-acceleration noise density q [m^2/s^3]
  ca   constant-acceleration Kalman filter, white-jerk noise density q [m^2/s^5]
  poly causal quadratic least-squares fit over the last W seconds, derivative at the newest frame

Measured: lag of v_z behind the offline centred Savitzky-Golay velocity (cross-correlation, parabolic
peak), RMS difference to it after removing that lag, gain at 2 Hz (overshoot), white-noise gain
(output std for 1 mm position noise). Usage: python bench/online_frontends.py [--real N]
"""

from __future__ import annotations

import argparse
import json
from pathlib import Path

import numpy as np

from yoyogait import synthetic
from yoyogait.pipeline import points
from yoyogait.pipeline.velocities import savgol_velocity, savgol_window_samples


def kalman(t, x, order, q, r):
    """Causal Kalman differentiator of x (n x d); order 2 (cv) or 3 (ca). NaN rows: prediction only."""
    n, d = x.shape
    s = np.zeros((order, d))
    P = np.diag([r * r] + [1e2] * (order - 1))
    out = np.full((n, d), np.nan)
    started = False
    t_prev = t[0]
    for k in range(n):
        ok = np.all(np.isfinite(x[k]))
        if not started:
            if ok:
                s[0] = x[k]
                started = True
                t_prev = t[k]
                out[k] = 0.0
            continue
        dt = t[k] - t_prev
        t_prev = t[k]
        if order == 2:
            F = np.array([[1, dt], [0, 1]])
            Q = q * np.array([[dt**3 / 3, dt**2 / 2], [dt**2 / 2, dt]])
        else:
            F = np.array([[1, dt, dt * dt / 2], [0, 1, dt], [0, 0, 1]])
            Q = q * np.array(
                [[dt**5 / 20, dt**4 / 8, dt**3 / 6], [dt**4 / 8, dt**3 / 3, dt**2 / 2], [dt**3 / 6, dt**2 / 2, dt]]
            )
        s = F @ s
        P = F @ P @ F.T + Q
        if ok:
            S = P[0, 0] + r * r
            K = P[:, 0] / S
            s = s + np.outer(K, x[k] - s[0])
            P = P - np.outer(K, P[0, :])
        out[k] = s[1]
    return out


def poly(t, x, window_s):
    """Causal quadratic LS fit over the last window_s seconds; derivative at the newest frame."""
    n, d = x.shape
    out = np.full((n, d), np.nan)
    ok = np.all(np.isfinite(x), axis=1)
    j0 = 0
    for k in range(n):
        if not ok[k]:
            continue
        while t[k] - t[j0] > window_s + 1e-9:
            j0 += 1
        idx = np.flatnonzero(ok[j0 : k + 1]) + j0
        if len(idx) < 4:
            continue
        tau = t[idx] - t[k]
        A = np.column_stack([np.ones_like(tau), tau, tau * tau])
        coef, *_ = np.linalg.lstsq(A, x[idx], rcond=None)
        out[k] = coef[1]
    return out


def lag_s(est, ref, rate_hz, max_lag_s=0.15):
    """Delay of est behind ref by cross-correlation (parabolic refinement of the peak) [s]."""
    ok = np.isfinite(est) & np.isfinite(ref)
    a = np.where(ok, est - np.mean(est[ok]), 0.0)
    b = np.where(ok, ref - np.mean(ref[ok]), 0.0)
    m = int(round(max_lag_s * rate_hz))
    lags = np.arange(-m, m + 1)
    c = np.array([np.dot(a[max(0, L) : len(a) + min(0, L)], b[max(0, -L) : len(b) + min(0, -L)]) for L in lags])
    i = int(np.argmax(c))
    if 0 < i < len(c) - 1:
        den = c[i - 1] - 2 * c[i] + c[i + 1]
        off = 0.5 * (c[i - 1] - c[i + 1]) / den if den != 0 else 0.0
    else:
        off = 0.0
    return (lags[i] + off) / rate_hz


def run(cand, t, x):
    kind, p = cand
    if kind == "cv":
        return kalman(t, x, 2, p, 0.001)
    if kind == "ca":
        return kalman(t, x, 3, p, 0.001)
    return poly(t, x, p)


def gain_2hz(cand, rate_hz):
    t = np.arange(0, 10, 1 / rate_hz)
    x = (0.02 / (2 * np.pi * 2)) * np.sin(2 * np.pi * 2 * t)[:, None]  # v amplitude 0.02 m/s
    v = run(cand, t, x)[:, 0]
    tail = t > 5
    return float(np.sqrt(2) * np.std(v[tail]) / 0.02)


def noise_gain(cand, rate_hz, seed=1):
    t = np.arange(0, 10, 1 / rate_hz)
    x = np.random.default_rng(seed).normal(0, 0.001, (len(t), 1))
    v = run(cand, t, x)[:, 0]
    return float(np.std(v[t > 2]))


def compare(cand, t, centre, up, rate_hz):
    ref = savgol_velocity(centre, rate_hz, savgol_window_samples(0.25, rate_hz, 3), 3)[:, up]
    est = run(cand, t, centre)[:, up]
    L = lag_s(est, ref, rate_hz)
    shift = int(round(L * rate_hz))
    e = est[shift:] - ref[: len(ref) - shift] if shift >= 0 else est - ref
    ok = np.isfinite(e)
    return L, float(np.sqrt(np.mean(e[ok] ** 2))) if ok.any() else np.nan


CANDIDATES = [("cv", 1.0), ("cv", 10.0), ("ca", 100.0), ("ca", 1000.0), ("ca", 5000.0), ("poly", 0.08), ("poly", 0.12)]


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--real", type=int, default=6, help="real recordings from the manifest to use")
    ap.add_argument("--datasets", default=str(Path(__file__).resolve().parents[2] / "shared" / "datasets"))
    args = ap.parse_args()
    rows = []
    for rate in (30, 100, 250):
        walk = synthetic.make_walk(synthetic.SUBJECTS[0], "1-straight", rate_hz=rate, duration_s=20.0, dropouts=False)
        rec = walk.recording
        centre, _ = points.robust_centre(rec.points(list(synthetic.PELVIS_MARKERS)))
        for cand in CANDIDATES:
            L, rms = compare(cand, rec.time_s, centre, 2, rate)
            rows.append(
                (f"synthetic {rate} Hz", f"{cand[0]} {cand[1]:g}", L, rms, gain_2hz(cand, rate), noise_gain(cand, rate))
            )
    from yoyogait.evaluation.datasets import manifest_items

    items, _ = manifest_items(Path(args.datasets) / "manifest.json")
    for item in items[: args.real]:
        rec = item.load()
        if item.pelvis is None:
            continue
        centre, _ = points.robust_centre(rec.points(item.pelvis))
        rate = 1.0 / float(np.median(np.diff(rec.time_s)))
        up = "xyz".index(item.up_axis or "z")
        for cand in CANDIDATES:
            L, rms = compare(cand, rec.time_s, centre, up, rate)
            rows.append(
                (
                    f"{item.name} {rate:.0f} Hz",
                    f"{cand[0]} {cand[1]:g}",
                    L,
                    rms,
                    gain_2hz(cand, rate),
                    noise_gain(cand, rate),
                )
            )
    print(f"{'recording':50s} {'candidate':10s} {'lag ms':>7s} {'rms m/s':>8s} {'gain2Hz':>8s} {'noise m/s':>9s}")
    for r in rows:
        print(f"{r[0]:50s} {r[1]:10s} {1e3 * r[2]:7.1f} {r[3]:8.4f} {r[4]:8.3f} {r[5]:9.4f}")
    Path("build").mkdir(exist_ok=True)
    Path("build/online_frontends.json").write_text(json.dumps(rows))


if __name__ == "__main__":
    main()
