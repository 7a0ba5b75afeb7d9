"""An independent, plain-numpy implementation of the paper's estimator (eq. 5-14).

Written from the paper with general matrices (np.sin/np.cos, full F P F^T,
np.linalg.inv of S, (I - K H) P) and none of the native core's shortcuts, so
that agreement with it checks the core's algebra.  Also used by the benchmark.
"""

from __future__ import annotations

import numpy as np

H = np.array([[1.0, 0.0, 0.0, 1.0], [0.0, -1.0, 0.0, 0.0]])  # eq. 9


def reference_paper_estimator(
    vx,
    vz,
    *,
    T=0.04,
    R0=2.0,
    r0=0.2,
    w0=0.1,
    Q=(1e-5, 1e-5, 1e-3, 1e-3),
    V=(1e-2, 1e-2),
    P0=1.0,
    n=10,
    mu_w=0.1,
    mu_A0=0.1,
):
    """Run eq. 5-14 over the samples; returns dict of arrays (state, R_hat, r_hat, vx_hat, vz_hat, and the
    diagnostics: innovation (N, 2) = z - H x- at the prediction, nis = y^T S^-1 y; NaN where unused)."""
    N = len(vx)
    x = np.array([r0 * w0, 0.0, w0, R0 * w0])
    P = np.eye(4) * P0
    Qm = np.diag(Q)
    Vm = np.diag(V)
    states = np.empty((N, 4))
    R_hist = np.empty(N + 1)
    r_hist = np.empty(N + 1)
    R_hist[0], r_hist[0] = R0, r0
    vx_hat = np.empty(N)
    vz_hat = np.empty(N)
    innovation = np.full((N, 2), np.nan)
    nis = np.full(N, np.nan)
    for k in range(1, N + 1):
        # Prediction through eq. 6 with F evaluated at the prior state.
        x1, x2, w, A0 = x
        F = np.array(
            [
                [np.cos(w), -np.sin(w), -x1 * np.sin(w) - x2 * np.cos(w), 0.0],
                [np.sin(w), np.cos(w), x1 * np.cos(w) - x2 * np.sin(w), 0.0],
                [0.0, 0.0, 1.0, 0.0],
                [0.0, 0.0, 0.0, 1.0],
            ]
        )
        x = np.array([x1 * np.cos(w) - x2 * np.sin(w), x1 * np.sin(w) + x2 * np.cos(w), w, A0])
        P = F @ P @ F.T + Qm
        z = np.array([vx[k - 1], vz[k - 1]])
        if np.all(np.isfinite(z)):
            S = H @ P @ H.T + Vm
            S_inv = np.linalg.inv(S)
            K = P @ H.T @ S_inv
            y = z - H @ x
            innovation[k - 1] = y
            nis[k - 1] = y @ S_inv @ y
            x = x + K @ y
            P = (np.eye(4) - K @ H) @ P
        states[k - 1] = x
        # Eq. 11-12.
        A1 = np.hypot(x[0], x[1])
        if k > n and x[2] > mu_w and x[3] > mu_A0:
            R_hist[k] = (R_hist[k - n : k].sum() + x[3] / x[2]) / (n + 1)
            r_hist[k] = (r_hist[k - n : k].sum() + A1 / x[2]) / (n + 1)
        else:
            R_hist[k] = R_hist[k - 1]
            r_hist[k] = r_hist[k - 1]
        # Eq. 13-14.
        vx_hat[k - 1] = R_hist[k] * x[2] + r_hist[k] * x[2] * x[0] / A1
        vz_hat[k - 1] = -r_hist[k] * x[2] * x[1] / A1
    return {
        "state": states,
        "R_hat": R_hist[1:],
        "r_hat": r_hist[1:],
        "vx_hat": vx_hat,
        "vz_hat": vz_hat,
        "innovation": innovation,
        "nis": nis,
    }
