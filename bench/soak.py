"""Soak test: 24 h of synthetic stop-and-go walking with dropouts at 25 Hz, through one estimator.

    python bench/soak.py [--hours H] [--preset default|paper] [--seed S] [--chunk-s C]

The walk is the Yoyo model (eq. 3-4) with the real-data phase relation (forward oscillation in
anti-phase), a second harmonic and noise: bouts of 30 s to 10 min at 1.5-2.1 Hz with a slow
cadence variability, each ended by a stop (1 s slowing down, 2-60 s standing, 1 s starting again
at the next bout's cadence); NaN dropouts of 0.1-3 s about every 2 minutes, of 20-120 s about
every 3 hours, and single NaN samples about every minute. 24 h are 2.16 million samples, generated
and run in chunks (``run`` continues across them) so that memory stays flat.

Reports: non-finite outputs and covariances that are not positive semi-definite (eigenvalue below
-1e-9 of the largest); the step-frequency and speed errors per hour on settled walking (5 s after
each onset and after each dropout of 1 s or more) and their drift from the first hour to the last;
the re-acquisition time after each stop (from the walking onset until f is within 5 % of the
cadence for 1 s); the resident memory at the start, after the first hour and at the end; the wall
time. A check, not a test.
"""

from __future__ import annotations

import argparse
import os
import resource
import sys
import time

import numpy as np

from yoyogait import EstimatorConfig, GaitEstimator

FS_HZ = 25.0
DT_S = 1.0 / FS_HZ
R_M, r_M, H2_RATIO, NOISE_MPS = 0.12, 0.02, 0.25, 0.015


def rss_mib() -> float:
    """Resident set size of this process now [MiB]."""
    with open("/proc/self/statm") as f:
        return int(f.read().split()[1]) * os.sysconf("SC_PAGE_SIZE") / 2**20


class Schedule:
    """The day's plan: walking bouts and stops, cadences, dropouts (all times in s)."""

    def __init__(self, duration_s: float, rng: np.random.Generator):
        starts, cadence, stand = [], [], []
        t = 0.0
        while t < duration_s:
            starts.append(t)
            cadence.append(rng.uniform(1.5, 2.1))
            walk = rng.uniform(30.0, 600.0)
            stand.append(rng.uniform(2.0, 60.0))
            t += walk + 1.0 + stand[-1] + 1.0  # walk, slow down, stand, start again
        self.bout_start = np.array(starts)  # the start of each bout's steady walking
        self.bout_f = np.array(cadence)
        self.bout_end = np.append(self.bout_start[1:] - 2.0 - np.array(stand[:-1]), np.inf)  # slowing starts
        self.stand_s = np.array(stand)
        self.var_period = rng.uniform(20.0, 60.0, len(starts))
        self.var_phase = rng.uniform(0, 2 * np.pi, len(starts))

        def events(rate_hz, lo, hi):
            n = rng.poisson(rate_hz * duration_s)
            s = np.sort(rng.uniform(0, duration_s, n))
            return s, s + rng.uniform(lo, hi, n)

        short, long_ = events(1 / 120, 0.1, 3.0), events(1 / 10800, 20.0, 120.0)
        self.drop_start = np.concatenate([short[0], long_[0]])
        self.drop_end = np.concatenate([short[1], long_[1]])
        order = np.argsort(self.drop_start)
        self.drop_start, self.drop_end = self.drop_start[order], self.drop_end[order]
        n1 = rng.poisson(duration_s / 60)
        self.single = np.sort(rng.uniform(0, duration_s, n1))

    def truth(self, t: np.ndarray):
        """Cadence f(t) [Hz], gain(t) in [0, 1] (0: standing) and the walking onsets' index."""
        b = np.searchsorted(self.bout_start, t, side="right") - 1  # the bout whose steady walk began last
        b = np.maximum(b, 0)
        t_in = t - self.bout_start[b]
        f = self.bout_f[b] * (1.0 + 0.02 * np.sin(2 * np.pi * t_in / self.var_period[b] + self.var_phase[b]))
        gain = np.ones_like(t)
        end = self.bout_end[b]
        slowing = (t >= end) & (t < end + 1.0)
        gain[slowing] = 1.0 - (t[slowing] - end[slowing])
        gain[t >= end + 1.0] = 0.0
        # The next bout's start-up (1 s before its steady walk) at its cadence.
        nb = np.minimum(b + 1, len(self.bout_start) - 1)
        starting = (t >= self.bout_start[nb] - 1.0) & (t < self.bout_start[nb]) & (nb > b)
        gain[starting] = t[starting] - (self.bout_start[nb][starting] - 1.0)
        f[starting] = self.bout_f[nb][starting]
        # The first bout has no start-up: it walks from t = 0.
        return f, gain

    def dropped(self, t: np.ndarray) -> np.ndarray:
        """True where the sample is missing (NaN)."""
        k = np.searchsorted(self.drop_start, t, side="right") - 1
        out = (k >= 0) & (t < self.drop_end[np.maximum(k, 0)])
        near = np.searchsorted(self.single, t)
        for j in (near - 1, near):
            j = np.clip(j, 0, max(len(self.single) - 1, 0))
            if len(self.single):
                out |= np.abs(self.single[j] - t) < 0.5 * DT_S
        return out

    def since_long_dropout_s(self, t: np.ndarray) -> np.ndarray:
        """Seconds since the end of the last dropout of 1 s or more (inf before the first)."""
        longer = (self.drop_end - self.drop_start) >= 1.0
        ends = np.sort(self.drop_end[longer])
        k = np.searchsorted(ends, t, side="right") - 1
        return np.where(k >= 0, t - ends[np.maximum(k, 0)], np.inf)


def generate(schedule: Schedule, t: np.ndarray, theta0: float, rng: np.random.Generator):
    """(vx, vz, f, gain, theta_end) for the samples at t, the Yoyo phase continuing from theta0."""
    f, gain = schedule.truth(t)
    w = 2 * np.pi * f * (gain > 0)
    theta = theta0 + np.cumsum(w * DT_S)
    amp = r_M * 2 * np.pi * f * gain
    vx = R_M * 2 * np.pi * f * gain + amp * np.cos(theta + np.pi) + H2_RATIO * amp * np.cos(2 * theta + 0.7)
    vz = -amp * np.sin(theta) + H2_RATIO * amp * np.cos(2 * theta + 2.1)
    vx = np.abs(vx + NOISE_MPS * rng.standard_normal(t.size))
    vz = vz + NOISE_MPS * rng.standard_normal(t.size)
    gone = schedule.dropped(t)
    vx[gone] = np.nan
    vz[gone] = np.nan
    return vx, vz, f, gain, float(theta[-1])


def reacquisition_s(gain, f_est, f_true, onsets, tol=0.05, hold_s=1.0, window_s=20.0):
    """Per onset index: seconds until f is within tol of the cadence for hold_s (NaN: not within window_s)."""
    ok = np.abs(f_est / f_true - 1) < tol
    hold = int(round(hold_s * FS_HZ))
    # Whether the hold_s starting at each index are all ok: a sliding count of ok samples.
    csum = np.concatenate([[0], np.cumsum(ok)])
    held = np.zeros(ok.size, bool)
    held[: ok.size - hold + 1] = (csum[hold:] - csum[:-hold]) == hold
    out = []
    for k0 in onsets:
        good = np.flatnonzero(held[k0 : k0 + int(window_s * FS_HZ)])
        out.append(good[0] / FS_HZ if good.size else np.nan)
    return out


def onsets_of(gain, first, stop):
    """Indices k in [first, stop) where walking starts after a stand (gain 0, then > 0)."""
    k = np.flatnonzero((gain[1:] > 0) & (gain[:-1] == 0)) + 1
    return k[(k >= first) & (k < stop)]


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--hours", type=float, default=24.0)
    ap.add_argument("--preset", default="default", choices=("default", "paper"))
    ap.add_argument("--seed", type=int, default=0)
    ap.add_argument("--chunk-s", type=float, default=600.0, help="seconds per run() call (default 600)")
    args = ap.parse_args()
    if not (args.hours > 0 and args.chunk_s >= 1):
        print("soak.py: --hours must be > 0 and --chunk-s >= 1", file=sys.stderr)
        return 2
    rng = np.random.default_rng(args.seed)
    duration = args.hours * 3600.0
    schedule = Schedule(duration, rng)
    n_total = int(round(duration * FS_HZ))
    chunk = int(round(args.chunk_s * FS_HZ))
    est = GaitEstimator(EstimatorConfig.preset(args.preset))
    hour = int(3600 * FS_HZ)
    n_hours = int(np.ceil(n_total / hour))
    # Per hour: the errors of the hour being run, then only their statistics (memory stays flat).
    f_err: dict[int, list] = {}
    v_err: dict[int, list] = {}
    rows = {}

    def close_hours(before_h):
        for h in [h for h in f_err if h < before_h]:
            fe, ve = np.concatenate(f_err.pop(h)), np.concatenate(v_err.pop(h))
            rows[h] = (fe.size, np.median(fe), np.percentile(fe, 95), np.median(ve), np.percentile(ve, 95))

    nonfinite = not_psd = 0
    reacq = []
    theta = rng.uniform(0, 2 * np.pi)
    keep = int(20 * FS_HZ)  # the re-acquisition window, carried over between chunks
    carry = None
    onset_t: list = []
    rss_start = rss_mib()
    rss_hour1 = None
    t0 = time.perf_counter()
    for a in range(0, n_total, chunk):
        b = min(a + chunk, n_total)
        t = np.arange(a, b) * DT_S
        vx, vz, f, gain, theta = generate(schedule, t, theta, rng)
        res = est.run(vx, vz, time_s=t, covariance=True)
        outputs = (res.state, res.step_frequency_hz, res.step_frequency_std_hz, res.speed_mps, res.speed_std_mps,
                   res.vx_hat_mps, res.vz_hat_mps, res.R_m, res.r_m)  # fmt: skip
        nonfinite += int(sum((~np.isfinite(x)).reshape(len(t), -1).any(axis=1).sum() for x in outputs))
        ev = np.linalg.eigvalsh(res.covariance)
        not_psd += int((ev[:, 0] < -1e-9 * np.maximum(ev[:, -1], 0)).sum())
        f_est = np.abs(res.step_frequency_hz)
        speed_true = R_M * 2 * np.pi * f * gain
        # Settled walking: full gain, 5 s after the onset of the bout and after any dropout >= 1 s.
        b_idx = np.maximum(np.searchsorted(schedule.bout_start, t, side="right") - 1, 0)
        settled = (gain == 1) & (t - schedule.bout_start[b_idx] >= 5.0) & (schedule.since_long_dropout_s(t) >= 5.0)
        settled &= np.isfinite(vx)
        for h in np.unique(t[settled] // 3600).astype(int):
            m = settled & (t // 3600 == h)
            f_err.setdefault(h, []).append(np.abs(f_est[m] / f[m] - 1))
            v_err.setdefault(h, []).append(np.abs(res.speed_mps[m] - speed_true[m]))
        close_hours(int(t[-1] // 3600))
        # Re-acquisition: each onset with its 20 s window complete here; the last 20 s (and the
        # sample before them) go with the next chunk.
        block = (gain, f_est, f, t)
        if carry is not None:
            block = tuple(np.concatenate([c, x]) for c, x in zip(carry, block))
        limit = block[0].size - keep
        onsets = onsets_of(block[0], 1, limit)
        reacq += reacquisition_s(*block[:3], onsets)
        onset_t += list(block[3][onsets])
        carry = tuple(x[limit - 1 :] for x in block)
        if rss_hour1 is None and b >= hour:
            rss_hour1 = rss_mib()
    onsets = onsets_of(carry[0], 1, carry[0].size)
    reacq += reacquisition_s(*carry[:3], onsets)
    onset_t += list(carry[3][onsets])
    wall = time.perf_counter() - t0
    rss_end = rss_mib()
    peak = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024

    print(f"soak: {args.hours:g} h of stop-and-go walking at 25 Hz ({n_total} samples), preset {args.preset}, "
          f"seed {args.seed}, chunks of {args.chunk_s:g} s")  # fmt: skip
    print(f"bouts {len(schedule.bout_start)}, dropouts {len(schedule.drop_start)} "
          f"({int(((schedule.drop_end - schedule.drop_start) >= 20).sum())} of 20 s or more), "
          f"single NaN samples {len(schedule.single)}")  # fmt: skip
    print(f"wall time {wall:.1f} s ({1e9 * wall / n_total:.0f} ns per sample with generation and checks)")
    print(f"non-finite output rows: {nonfinite}; covariances not positive semi-definite: {not_psd}")
    hour1 = f", after the first hour {rss_hour1:.1f} MiB" if rss_hour1 is not None else ""
    print(f"resident memory: start {rss_start:.1f} MiB{hour1}, end {rss_end:.1f} MiB, peak {peak:.1f} MiB")
    print()
    print(
        "| hour | settled samples | f error median | f error p95 | speed error median [m/s] | speed error p95 [m/s] |"
    )
    print("|---:|---:|---:|---:|---:|---:|")
    close_hours(n_hours + 1)
    for h in sorted(rows):
        r = rows[h]
        print(f"| {h + 1} | {r[0]} | {100 * r[1]:.2f} % | {100 * r[2]:.2f} % | {r[3]:.4f} | {r[4]:.4f} |")
    if rows:
        first, last = rows[min(rows)], rows[max(rows)]
        print()
        print(f"drift, last hour minus first: f error median {100 * (last[1] - first[1]):+.3f} points, "
              f"p95 {100 * (last[2] - first[2]):+.3f} points; speed error median {last[3] - first[3]:+.4f} m/s, "
              f"p95 {last[4] - first[4]:+.4f} m/s")  # fmt: skip
    ra = np.array(reacq)
    found = ra[np.isfinite(ra)]
    print()
    print(f"re-acquisition after {ra.size} stops: median {np.median(found):.2f} s, p95 "
          f"{np.percentile(found, 95):.2f} s, max {found.max():.2f} s; not within 20 s: {int((~np.isfinite(ra)).sum())}"
          if found.size else f"re-acquisition after {ra.size} stops: never")  # fmt: skip
    for t_on, dt in zip(onset_t, reacq):
        if not np.isfinite(dt) or dt > 3.0:
            k = np.searchsorted(schedule.drop_start, t_on + 20.0) - 1
            lo = max(k - 3, 0)
            spans = zip(schedule.drop_start[lo : k + 1], schedule.drop_end[lo : k + 1])
            near = [(round(float(a - t_on), 1), round(float(b - a), 1)) for a, b in spans if b > t_on - 5.0]
            why = f"dropouts (start after onset, length) [s]: {near}" if near else "no dropout near"
            print(
                f"  stop ending at {t_on:.1f} s: {'not within 20 s' if not np.isfinite(dt) else f'{dt:.2f} s'}; {why}"
            )
    return 0


if __name__ == "__main__":
    sys.exit(main())
