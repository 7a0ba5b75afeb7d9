"""An independent, plain-numpy implementation of the paper's estimator (eq. 5-14).

Written from the paper with general matrices (np.sin/np.cos, full F P F^T,
np.linalg.inv of S, (I - K H) P) and none of the native core's shortcuts, so
that agreement with it checks the core's algebra.  Also used by the benchmark.

With the core's covariance guard (docs/paper_estimator.md, "Covariance guard"),
written independently: variances bounded after the prediction (rows and columns
scaled), and a covariance that is not positive definite after the step (here:
Cholesky fails) recomputed in the Joseph form from the prediction (itself made
positive definite first if it is not), then projected onto the matrices whose
eigenvalues are at least 1e-12 of the largest.  Walking data never reach either.
"""

from __future__ import annotations

import numpy as np

H = np.array([[1.0, 0.0, 0.0, 1.0], [0.0, -1.0, 0.0, 0.0]])  # eq. 9
MIN_RELATIVE_EIGENVALUE = 1e-12


def positive_definite(P) -> bool:
    """True when P is finite and its Cholesky factorization exists."""
    if not np.all(np.isfinite(P)):
        return False
    try:
        np.linalg.cholesky(P)
    except np.linalg.LinAlgError:
        return False
    return True


def nearest_positive_definite(P, P0):
    """Eigenvalues raised to 1e-12 of the largest; P0 when there is no positive eigenvalue."""
    if not np.all(np.isfinite(P)):
        return P0.copy()
    lam, vec = np.linalg.eigh(P)
    if not lam[-1] > 0:
        return P0.copy()
    lam = np.maximum(lam, MIN_RELATIVE_EIGENVALUE * lam[-1])
    out = (vec * lam) @ vec.T
    return 0.5 * (out + out.T)


def bound_variances(P, max_var, P0):
    """Rows and columns scaled so that no variance exceeds its bound; P0 if P is not finite."""
    if not np.all(np.isfinite(P)):
        return P0.copy()
    d = np.where(np.diag(P) > max_var, np.sqrt(max_var / np.diag(P)), 1.0)
    return P * np.outer(d, d)


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
    v_max=1000.0,
):
    """Run eq. 5-14 over the samples; returns dict of arrays (state, R_hat, r_hat, vx_hat_mps, vz_hat_mps, the
    covariance P after each sample, and the diagnostics: innovation (N, 2) = z - H x- at the
    prediction, nis = y^T S^-1 y; NaN where unused)."""
    N = len(vx)
    x = np.array([r0 * w0, 0.0, w0, R0 * w0])
    P = np.eye(4) * P0
    P_start = P.copy()
    Qm = np.diag(Q)
    Vm = np.diag(V)
    # Popoviciu: velocities within +-v_max, the frequency within +-pi rad/sample.
    max_var = np.array([v_max**2, v_max**2, np.pi**2, v_max**2])
    covariances = np.empty((N, 4, 4))
    states = np.empty((N, 4))
    R_hist = np.empty(N + 1)
    r_hist = np.empty(N + 1)
    R_hist[0], r_hist[0] = R0, r0
    vx_hat_mps = np.empty(N)
    vz_hat_mps = np.empty(N)
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
        if np.any(np.diag(P) > max_var) or not np.all(np.isfinite(P)):
            P = bound_variances(P, max_var, P_start)
        z = np.array([vx[k - 1], vz[k - 1]])
        if np.all(np.isfinite(z)) and np.all(np.abs(z) <= v_max):
            x_pred, P_pred = x, P
            S = H @ P @ H.T + Vm
            S_inv = np.linalg.inv(S)
            K = P @ H.T @ S_inv
            y = z - H @ x
            innovation[k - 1] = y
            nis[k - 1] = y @ S_inv @ y
            x = x + K @ y
            P = (np.eye(4) - K @ H) @ P
            if not positive_definite(P):
                # The guard: the Joseph form of the same update, from a positive definite prediction.
                if not positive_definite(P_pred):
                    P_pred = nearest_positive_definite(P_pred, P_start)
                S = H @ P_pred @ H.T + Vm
                K = P_pred @ H.T @ np.linalg.inv(S)
                x = x_pred + K @ (z - H @ x_pred)
                A = np.eye(4) - K @ H
                P = A @ P_pred @ A.T + K @ Vm @ K.T
                P = 0.5 * (P + P.T)
        if not positive_definite(P):
            P = nearest_positive_definite(P, P_start)
        covariances[k - 1] = P
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
        vx_hat_mps[k - 1] = R_hist[k] * x[2] + r_hist[k] * x[2] * x[0] / A1
        vz_hat_mps[k - 1] = -r_hist[k] * x[2] * x[1] / A1
    return {
        "state": states,
        "R_hat": R_hist[1:],
        "r_hat": r_hist[1:],
        "vx_hat_mps": vx_hat_mps,
        "vz_hat_mps": vz_hat_mps,
        "innovation": innovation,
        "nis": nis,
        "P": covariances,
    }
