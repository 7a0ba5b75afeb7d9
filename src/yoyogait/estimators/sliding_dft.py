"""The sliding-DFT baseline: an offline, non-causal bound, with the estimators' result type.

* ``sliding-dft``: an offline, non-causal bound.  Around every sample, a
  centred window of the vertical velocity gives the step frequency (the peak
  of its DFT, refined on a fine grid), and a least-squares fit of
  ``v_x = A0 + a cos(wt) + b sin(wt)``, ``v_z = c cos(wt) + d sin(wt)`` over
  the same window gives the bias, the oscillation and the reconstruction.  It
  sees the future, so no causal filter can be expected to beat it.  Where the
  spectrum has a peak near half the strongest one (the pelvis rises twice per
  step in slow walks), that one is the step frequency, as in
  :func:`yoyogait.spectral.step_frequency`.

:class:`SlidingDft` holds the parameters; its ``run`` returns an
:class:`~yoyogait.estimators.results.EstimateResult`.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from .._sample_time import SAMPLE_TIME_S
from .results import PREDICTION_HORIZONS_S, EstimateResult, result_from_fit

__all__ = ["SlidingDft", "sliding_dft"]

TWO_PI = 2.0 * np.pi


def sliding_dft(
    time_s,
    vx,
    vz,
    *,
    window_s: float = 4.0,
    min_hz: float = 0.5,
    max_hz: float = 4.0,
    resolution_hz: float = 0.01,
    predict_ahead_s=PREDICTION_HORIZONS_S,
) -> EstimateResult:
    """The offline sliding-DFT estimate on a uniform grid (see the module doc).

    Samples whose window holds fewer than half known values get NaN.
    """
    t = np.asarray(time_s, dtype=float)
    vx = np.asarray(vx, dtype=float)
    vz = np.asarray(vz, dtype=float)
    n = t.size
    T = float(np.median(np.diff(t))) if n > 1 else SAMPLE_TIME_S
    half = max(2, int(round(window_s / (2 * T))))
    freqs = np.arange(min_hz, max_hz + resolution_hz / 2, resolution_hz)
    offsets = np.arange(-half, half + 1)
    idx = np.clip(np.arange(n)[:, None] + offsets[None, :], 0, n - 1)
    inside = (np.arange(n)[:, None] + offsets[None, :] >= 0) & (np.arange(n)[:, None] + offsets[None, :] < n)
    wx, wz = vx[idx], vz[idx]
    known = inside & np.isfinite(wx) & np.isfinite(wz)
    enough = known.sum(axis=1) >= offsets.size // 2
    wz0 = np.where(known, wz, 0.0)
    wz0 = np.where(known, wz0 - wz0.sum(1, keepdims=True) / np.maximum(known.sum(1, keepdims=True), 1), 0.0)
    tau = offsets * T  # time relative to the window's centre
    hann = 0.5 + 0.5 * np.cos(np.pi * offsets / (half + 1))
    basis = np.exp(-1j * TWO_PI * freqs[None, :] * tau[:, None])  # (window, freqs)
    power = np.abs((wz0 * hann) @ basis) ** 2
    k = np.argmax(power, axis=1)
    # As yoyogait.spectral.step_frequency: in slow walks the pelvis rises twice per step, so a peak
    # near half the strongest one, at least half as tall in magnitude, is the step frequency.
    f_top = freqs[k]
    near_half = (freqs[None, :] >= np.maximum(min_hz, 0.85 * f_top / 2)[:, None]) & (
        freqs[None, :] <= (1.15 * f_top / 2)[:, None]
    )
    is_peak = np.zeros(power.shape, dtype=bool)
    is_peak[:, 1:-1] = (power[:, 1:-1] >= power[:, :-2]) & (power[:, 1:-1] > power[:, 2:])
    candidate = np.where(near_half & is_peak, power, -np.inf)
    k_half = np.argmax(candidate, axis=1)
    rows = np.arange(n)
    k = np.where(candidate[rows, k_half] >= 0.25 * power[rows, k], k_half, k)
    # Parabolic refinement of the peak on the grid.
    km, kp = np.clip(k - 1, 0, freqs.size - 1), np.clip(k + 1, 0, freqs.size - 1)
    p0, pm, pp = power[rows, k], power[rows, km], power[rows, kp]
    denom = pm - 2 * p0 + pp
    shift = np.where((denom < 0) & (k > 0) & (k < freqs.size - 1), 0.5 * (pm - pp) / np.where(denom == 0, 1, denom), 0)
    f = freqs[k] + shift * resolution_hz
    omega = TWO_PI * f
    # Least squares of [1, cos, sin] over the window, weighted by 'known'.
    c = np.cos(omega[:, None] * tau[None, :])
    s = np.sin(omega[:, None] * tau[None, :])
    m = known.astype(float)
    ones = m
    G = np.stack(
        [
            np.stack([(ones).sum(1), (c * m).sum(1), (s * m).sum(1)], -1),
            np.stack([(c * m).sum(1), (c * c * m).sum(1), (c * s * m).sum(1)], -1),
            np.stack([(s * m).sum(1), (c * s * m).sum(1), (s * s * m).sum(1)], -1),
        ],
        1,
    )
    G += 1e-9 * np.eye(3)
    wx0 = np.where(known, wx, 0.0)
    wz1 = np.where(known, wz, 0.0)
    bx = np.stack([wx0.sum(1), (c * wx0).sum(1), (s * wx0).sum(1)], -1)
    bz = np.stack([wz1.sum(1), (c * wz1).sum(1), (s * wz1).sum(1)], -1)
    px = np.linalg.solve(G, bx[..., None])[..., 0]
    pz = np.linalg.solve(G, bz[..., None])[..., 0]
    a0, ax, bxs = px[:, 0], px[:, 1], px[:, 2]
    az, bzs = pz[:, 1], pz[:, 2]
    vx_hat_mps = a0 + ax
    vz_hat_mps = pz[:, 0] + az
    horizons = tuple(float(h) for h in predict_ahead_s)
    vx_pred = np.empty((n, len(horizons)))
    vz_pred = np.empty((n, len(horizons)))
    for j, h in enumerate(horizons):
        ch, sh = np.cos(omega * h), np.sin(omega * h)
        vx_pred[:, j] = a0 + ax * ch + bxs * sh
        vz_pred[:, j] = pz[:, 0] + az * ch + bzs * sh
    bad = ~enough
    for arr in (omega, a0, vx_hat_mps, vz_hat_mps, az, bzs):
        arr[bad] = np.nan
    vx_pred[bad] = np.nan
    vz_pred[bad] = np.nan
    # In the paper's state, v_z = -x2: the oscillation's phasor at the sample is (x1, x2) with x2 = -v_z part.
    return result_from_fit(omega, a0, ax, -az, vx_hat_mps, vz_hat_mps, T, vx_pred, vz_pred, horizons, t)


@dataclass(frozen=True)
class SlidingDft:
    """The sliding-DFT baseline's parameters; :meth:`run` computes (the parameters stay apart from results)."""

    window_s: float = 4.0
    """Length of the centred window [s]."""
    min_hz: float = 0.5
    """Lowest step frequency searched [Hz]."""
    max_hz: float = 4.0
    """Highest step frequency searched [Hz]."""
    resolution_hz: float = 0.01
    """Grid step of the frequency search [Hz]."""

    def run(self, time_s, vx, vz, *, predict_ahead_s=PREDICTION_HORIZONS_S) -> EstimateResult:
        """Estimates at every sample of a uniform grid (see :func:`sliding_dft`)."""
        return sliding_dft(
            time_s,
            vx,
            vz,
            window_s=self.window_s,
            min_hz=self.min_hz,
            max_hz=self.max_hz,
            resolution_hz=self.resolution_hz,
            predict_ahead_s=predict_ahead_s,
        )
