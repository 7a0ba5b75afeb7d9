"""Figures of the estimate, like the paper's Fig. 3 (parameters) and Fig. 4 (velocities).

Figures are built on matplotlib's object API with the Agg canvas, never
pyplot, so that making them needs no display and leaves no global state
behind (safe in tests, scripts and servers).  Inputs are plain arrays, or an
estimator result object with the fields ``vx_hat``, ``vz_hat``, ``R_m``,
``r_m``, ``step_frequency_hz``, ``A0_mps``, ``A1_mps`` (and ``state``).
Figures of synthetic data always say so in their title.
"""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
from matplotlib.backends.backend_agg import FigureCanvasAgg
from matplotlib.figure import Figure

from ..errors import InputError
from . import metrics as _metrics

__all__ = ["parameter_figure", "velocity_figure", "distribution_figure", "recording_title"]

_EST = "tab:blue"
_EST2 = "tab:orange"
_REF = "black"


def recording_title(recording, what: str = "") -> str:
    """A figure title naming the recording, saying "synthetic" when it is."""
    meta = getattr(recording, "metadata", {}) or {}
    name = getattr(recording, "source", "") or "recording"
    if meta.get("synthetic"):
        name = f"{meta.get('subject', '')} walk {meta.get('walk_type', '')}".strip()
        if "synthetic" not in name.lower():
            name = f"synthetic {name}"
        name = f"Synthetic data: {name}"
    return f"{what} - {name}" if what else name


def _title(title: str, synthetic: bool) -> str:
    if synthetic and "synthetic" not in title.lower():
        return f"Synthetic data: {title}" if title else "Synthetic data"
    return title


def _pick(explicit, result, *names):
    if explicit is not None:
        return np.asarray(explicit, dtype=float)
    if result is not None:
        for name in names:
            value = getattr(result, name, None)
            if value is not None:
                return np.asarray(value, dtype=float)
    return None


def _check(t, **arrays):
    for name, a in arrays.items():
        if a is not None and a.shape != t.shape:
            raise InputError(f"{name} has shape {a.shape}, expected {t.shape} like time_s")


DPI = 100
"""Resolution of saved figures (an 8 in wide figure is 800 pixels)."""

_MARGINS_IN = {"left": 0.85, "right": 0.2, "top": 0.5, "bottom": 0.5}
"""Fixed figure margins in inches: room for tick labels, axis labels and the title.

A fixed layout instead of matplotlib's constrained layout, which measured every text twice per
figure and took about half of the time to make one."""


def _new_figure(width_in: float, height_in: float) -> Figure:
    fig = Figure(figsize=(width_in, height_in), dpi=DPI)
    FigureCanvasAgg(fig)
    return fig


def _layout(fig: Figure, hspace: float = 0.15, wspace: float = 0.2) -> None:
    """Place the axes within fixed margins and align the y labels at a fixed distance from the axes."""
    w, h = fig.get_size_inches()
    m = _MARGINS_IN
    fig.subplots_adjust(
        left=m["left"] / w,
        right=1 - m["right"] / w,
        top=1 - m["top"] / h,
        bottom=m["bottom"] / h,
        hspace=hspace,
        wspace=wspace,
    )
    for ax in fig.axes:
        # Fixed label coordinates align the labels across axes without measuring tick labels.
        ax.yaxis.set_label_coords(-0.62 / (w * ax.get_position().width), 0.5)


def _finish(fig: Figure, path, **spacing) -> Figure:
    _layout(fig, **spacing)
    if path is not None:
        path = Path(path)
        path.parent.mkdir(parents=True, exist_ok=True)
        fig.savefig(path, dpi=DPI)
    return fig


def parameter_figure(
    time_s,
    result=None,
    *,
    step_frequency_hz=None,
    R_m=None,
    r_m=None,
    A0_mps=None,
    A1_mps=None,
    dft_step_frequency_hz: float | None = None,
    measured_vz_mps=None,
    truth=None,
    reference_time_s=None,
    reference_step_frequency_hz=None,
    true_R_m=None,
    true_r_m=None,
    title: str = "",
    synthetic: bool | None = None,
    path=None,
) -> Figure:
    """Fig. 3: step frequency, Yoyo radii and EKF bias/amplitude over time.

    Top: |step frequency| estimate (Hz) with the recording's DFT average as a
    horizontal line (given, or computed from ``measured_vz_mps``) and a
    reference step frequency over time when known.  Middle: R and r (m),
    estimated and true.  Bottom: A0 and A1 (m/s).  ``truth`` (a
    :class:`~yoyogait.synthetic.SyntheticTruth`) supplies the references on
    its own time grid and marks the figure synthetic.  Saved as PNG to
    ``path`` when given.
    """
    t = np.asarray(time_s, dtype=float)
    f = _pick(step_frequency_hz, result, "step_frequency_hz")
    R = _pick(R_m, result, "R_m")
    r = _pick(r_m, result, "r_m")
    A0 = _pick(A0_mps, result, "A0_mps")
    A1 = _pick(A1_mps, result, "A1_mps")
    state = _pick(None, result, "state")
    if state is not None and state.ndim == 2 and state.shape[1] == 4:
        A0 = state[:, 3] if A0 is None else A0  # x4 is the bias of v_x
        A1 = np.hypot(state[:, 0], state[:, 1]) if A1 is None else A1
    _check(t, step_frequency_hz=f, R_m=R, r_m=r, A0_mps=A0, A1_mps=A1)

    if truth is not None:
        reference_time_s = truth.time_s if reference_time_s is None else reference_time_s
        reference_step_frequency_hz = (
            truth.step_frequency_hz if reference_step_frequency_hz is None else reference_step_frequency_hz
        )
        true_R_m = truth.R_m if true_R_m is None else true_R_m
        true_r_m = truth.r_m if true_r_m is None else true_r_m
        synthetic = True if synthetic is None else synthetic
    t_ref = t if reference_time_s is None else np.asarray(reference_time_s, dtype=float)
    if dft_step_frequency_hz is None and measured_vz_mps is not None:
        dft_step_frequency_hz = _metrics.dft_step_frequency_hz(t, measured_vz_mps)

    fig = _new_figure(8.0, 7.5)
    ax_f, ax_R, ax_A = fig.subplots(3, 1, sharex=True)

    if f is not None:
        ax_f.plot(t, np.abs(f), color=_EST, lw=1.2, label="estimate |f|")
    if reference_step_frequency_hz is not None:
        ax_f.plot(
            t_ref,
            np.broadcast_to(np.asarray(reference_step_frequency_hz, float), t_ref.shape),
            color=_REF,
            lw=1.0,
            ls="--",
            label="reference",
        )
    if dft_step_frequency_hz is not None and np.isfinite(dft_step_frequency_hz):
        ax_f.axhline(
            dft_step_frequency_hz,
            color="tab:red",
            lw=1.0,
            ls=":",
            label=f"DFT average ({dft_step_frequency_hz:.2f} Hz)",
        )
    ax_f.set_ylabel("step frequency (Hz)")

    if R is not None:
        ax_R.plot(t, R, color=_EST, lw=1.2, label="R est.")
    if r is not None:
        ax_R.plot(t, r, color=_EST2, lw=1.2, label="r est.")
    if true_R_m is not None:
        ax_R.plot(
            t_ref,
            np.broadcast_to(np.asarray(true_R_m, float), t_ref.shape),
            color=_EST,
            lw=1.0,
            ls="--",
            label="R true",
        )
    if true_r_m is not None:
        ax_R.plot(
            t_ref,
            np.broadcast_to(np.asarray(true_r_m, float), t_ref.shape),
            color=_EST2,
            lw=1.0,
            ls="--",
            label="r true",
        )
    ax_R.set_ylabel("R, r (m)")

    if A0 is not None:
        ax_A.plot(t, A0, color=_EST, lw=1.0, label="A0 (bias)")
    if A1 is not None:
        ax_A.plot(t, A1, color=_EST2, lw=1.0, label="A1 (amplitude)")
    ax_A.set_ylabel("A0, A1 (m/s)")
    ax_A.set_xlabel("time (s)")

    for ax in (ax_f, ax_R, ax_A):
        ax.grid(True, alpha=0.3)
        if ax.get_legend_handles_labels()[0]:
            ax.legend(loc="best", fontsize="small")
    fig.suptitle(_title(title, bool(synthetic)))
    return _finish(fig, path)


def velocity_figure(
    time_s,
    measured_vx_mps,
    measured_vz_mps,
    result=None,
    *,
    vx_hat_mps=None,
    vz_hat_mps=None,
    title: str = "",
    synthetic: bool = False,
    path=None,
) -> Figure:
    """Fig. 4: measured against reconstructed (eq. 13-14) v_x (top) and v_z (bottom), m/s.

    Saved as PNG to ``path`` when given.
    """
    t = np.asarray(time_s, dtype=float)
    vx = np.asarray(measured_vx_mps, dtype=float)
    vz = np.asarray(measured_vz_mps, dtype=float)
    vx_hat = _pick(vx_hat_mps, result, "vx_hat", "vx_hat_mps")
    vz_hat = _pick(vz_hat_mps, result, "vz_hat", "vz_hat_mps")
    _check(t, measured_vx_mps=vx, measured_vz_mps=vz, vx_hat_mps=vx_hat, vz_hat_mps=vz_hat)

    fig = _new_figure(8.0, 5.5)
    ax_x, ax_z = fig.subplots(2, 1, sharex=True)
    for ax, measured, estimate, name in ((ax_x, vx, vx_hat, "v_x"), (ax_z, vz, vz_hat, "v_z")):
        ax.plot(t, measured, color="0.45", lw=1.0, label=f"measured ${name}$")
        if estimate is not None:
            ax.plot(t, estimate, color=_EST, lw=1.2, label=f"reconstructed ${name}$")
        ax.grid(True, alpha=0.3)
        ax.legend(loc="best", fontsize="small")
    ax_x.set_ylabel("forward $v_x$ (m/s)")
    ax_z.set_ylabel("vertical $v_z$ (m/s)")
    ax_z.set_xlabel("time (s)")
    fig.suptitle(_title(title, synthetic))
    return _finish(fig, path)


def distribution_figure(values: dict, *, labels: dict | None = None, title: str = "", path=None) -> Figure:
    """The distribution over recordings of some metrics, one panel per metric, one box per estimator.

    ``values``: estimator -> metric -> one value per recording (NaN where unknown, left out).
    Boxes span the quartiles around the median, whiskers reach 1.5 interquartile ranges, and every
    recording is a dot. A panel whose values are all positive has a log scale.
    """
    estimators = list(values)
    keys = list(dict.fromkeys(k for est in estimators for k in values[est]))
    labels = labels or {}
    ncols = 2 if len(keys) > 1 else 1
    nrows = max(1, math.ceil(len(keys) / ncols))
    fig = _new_figure(8.0, 2.6 * nrows + 0.8)
    axes = np.atleast_1d(fig.subplots(nrows, ncols, squeeze=False).ravel())
    positions = np.arange(len(estimators), dtype=float)
    for ax, key in zip(axes, keys):
        data = [np.asarray(values[est].get(key, []), dtype=float) for est in estimators]
        data = [d[np.isfinite(d)] for d in data]
        shown = [(p, d) for p, d in zip(positions, data) if d.size]
        if shown:
            ax.boxplot([d for _, d in shown], positions=[p for p, _ in shown], widths=0.5, showfliers=False)
            for p, d in shown:
                # Spread the dots evenly across the box by rank: deterministic, no overlap in order.
                offsets = (np.argsort(np.argsort(d)) / max(d.size - 1, 1) - 0.5) * 0.3
                ax.plot(p + offsets, d, "o", ms=2.5, alpha=0.5, color=_EST, mec="none")
            if all(d.min() > 0 for _, d in shown):
                ax.set_yscale("log")
        ax.set_xticks(positions, estimators)
        ax.set_xlim(-0.6, len(estimators) - 0.4)
        ax.set_ylabel(labels.get(key, key), fontsize="small")
        ax.grid(True, axis="y", alpha=0.3)
    for ax in axes[len(keys) :]:
        ax.set_visible(False)
    fig.suptitle(title)
    return _finish(fig, path, hspace=0.25, wspace=0.35)
