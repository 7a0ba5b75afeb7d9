"""Small signal helpers shared by the pipeline's stages: runs of a mask, NaN-aware moving means,
gap filling, resampling and the walking heading."""

from __future__ import annotations

import numpy as np

__all__ = ["runs", "moving_mean", "nearest_true", "fill_short_gaps", "resample", "walking_heading"]


def runs(mask: np.ndarray) -> list[tuple[int, int]]:
    """(start, stop) of each run of True in a bool array."""
    m = np.concatenate([[False], np.asarray(mask, dtype=bool), [False]])
    edges = np.flatnonzero(np.diff(m.astype(np.int8)))
    return list(zip(edges[::2].tolist(), edges[1::2].tolist()))


def moving_mean(values: np.ndarray, n: int) -> np.ndarray:
    """Centred mean over ``n`` samples that skips NaN (NaN only where the whole window is)."""
    v = np.asarray(values, dtype=float)
    v2 = v.reshape(len(v), -1)
    ok = np.isfinite(v2)
    kernel = np.ones(max(1, min(int(n), len(v))))  # a window longer than the series: 'same' would lengthen it
    sums = np.column_stack([np.convolve(np.where(ok[:, c], v2[:, c], 0.0), kernel, "same") for c in range(v2.shape[1])])
    counts = np.column_stack([np.convolve(ok[:, c].astype(float), kernel, "same") for c in range(v2.shape[1])])
    with np.errstate(invalid="ignore", divide="ignore"):
        out = np.where(counts > 0, sums / counts, np.nan)
    return out.reshape(v.shape)


def nearest_true(mask: np.ndarray) -> np.ndarray:
    """For every index, the nearest index where ``mask`` is True (mask must have one)."""
    idx = np.flatnonzero(mask)
    at = np.arange(len(mask))
    right = np.clip(np.searchsorted(idx, at), 0, len(idx) - 1)
    left = np.clip(right - 1, 0, len(idx) - 1)
    return np.where(np.abs(idx[left] - at) <= np.abs(idx[right] - at), idx[left], idx[right])


def fill_short_gaps(values: np.ndarray, rate_hz: float, max_gap_s: float, kind: str = "cubic") -> np.ndarray:
    """Fill NaN gaps of at most ``max_gap_s`` that have samples on both sides.

    ``kind="cubic"``: a cubic spline through all known samples (positions
    change smoothly); ``"linear"``: straight lines (velocities given as they
    are).  Gaps at the ends and longer gaps stay NaN.
    """
    x = np.array(values, dtype=float)
    flat = x.reshape(len(x), -1)
    ok = np.all(np.isfinite(flat), axis=1)
    gaps = [(a, b) for a, b in runs(~ok) if a > 0 and b < len(x) and (b - a) / rate_hz <= max_gap_s + 1e-9]
    if not gaps or ok.sum() < 2:
        return x
    idx = np.flatnonzero(ok)
    fill = np.concatenate([np.arange(a, b) for a, b in gaps])
    if kind == "cubic" and len(idx) >= 4:
        from scipy.interpolate import CubicSpline  # scipy.interpolate brings much of scipy: only where it is used

        flat[fill] = CubicSpline(idx, flat[idx], axis=0)(fill)
    else:
        for c in range(flat.shape[1]):
            flat[fill, c] = np.interp(fill, idx, flat[idx, c])
    return flat.reshape(x.shape)


def resample(time_s: np.ndarray, values: np.ndarray, rate_hz: float, max_gap_s: float | None = None):
    """Linear resampling to a ``rate_hz`` grid from the first sample; NaN next to NaN.

    With ``max_gap_s``, the grid points inside a step between two timestamps longer than that
    are NaN too: a gap in time is a gap, which interpolation must not bridge.
    """
    t = np.asarray(time_s, dtype=float)
    v = np.asarray(values, dtype=float)
    n_out = int(np.floor((t[-1] - t[0]) * rate_hz + 1e-9)) + 1
    t_out = t[0] + np.arange(n_out) / rate_hz
    v2 = v.reshape(len(v), -1)
    ok = np.all(np.isfinite(v2), axis=1)
    out = np.empty((n_out, v2.shape[1]))
    known = np.interp(t_out, t, ok.astype(float)) > 1 - 1e-9
    for c in range(v2.shape[1]):
        out[:, c] = np.interp(t_out, t, np.where(ok, v2[:, c], 0.0))
    out[~known] = np.nan
    if max_gap_s is not None and len(t) > 1:
        i = np.clip(np.searchsorted(t, t_out, side="right") - 1, 0, len(t) - 2)
        in_gap = (t[i + 1] - t[i] > max_gap_s + 1e-9) & (t_out > t[i]) & (t_out < t[i + 1])
        out[in_gap] = np.nan
    return t_out, out.reshape((n_out,) + v.shape[1:])


def walking_heading(v_h: np.ndarray, rate_hz: float, window_s: float, min_speed_mps: float = 0.1) -> np.ndarray | None:
    """Unit walking direction (n x 2) from horizontal velocity (n x 2); None if it never moves.

    The direction of the velocity averaged over ``window_s`` (about a
    stride, so that the sway cancels); where that average is slower than
    ``min_speed_mps`` the nearest heading is held.
    """
    n = max(1, int(round(window_s * rate_hz)))
    mean = moving_mean(v_h, n)
    speed = np.hypot(mean[:, 0], mean[:, 1])
    good = np.isfinite(speed) & (speed >= min_speed_mps)
    if not good.any():
        return None
    heading = mean[nearest_true(good)]
    return heading / np.hypot(heading[:, 0], heading[:, 1])[:, None]
