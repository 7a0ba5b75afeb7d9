"""Figures of the estimate, like the paper's Fig. 3 (parameters) and Fig. 4 (velocities).

Figures are built on matplotlib's object API with the Agg canvas, never
pyplot, so that making them needs no display and leaves no global state
behind (safe in tests, scripts and servers).  Inputs are plain arrays, or an
estimator result object with the fields ``vx_hat_mps``, ``vz_hat_mps``, ``R_m``,
``r_m``, ``step_frequency_hz``, ``A0_mps``, ``A1_mps`` (and ``state``).
Figures of synthetic data always say so: in their title, in a boxed label and in a
diagonal watermark across the figure.  Layout is fixed margins, not constrained layout
(which costs most of a figure's drawing time).

Drawing many figures of one kind (a report): pass the figure of the previous call as ``into``.
Its axes, ticks, labels and text caches are kept and only the data, legends and marks are drawn
anew, which takes about half the time of a new figure; the pixels are the same.

matplotlib is imported when the first figure is made, not with this module: the commands that draw
nothing start without it.
"""

from __future__ import annotations

import functools
import math
import textwrap
from pathlib import Path
from typing import TYPE_CHECKING

import numpy as np

from ..errors import InputError
from ..estimators.online import InvalidReason, reason_words
from ..pipeline.signals import moving_mean, runs
from . import metrics as _metrics

if TYPE_CHECKING:
    from matplotlib.figure import Figure

__all__ = [
    "parameter_figure",
    "velocity_figure",
    "estimate_figure",
    "online_figure",
    "validity_strip",
    "validity_rows",
    "distribution_figure",
    "recording_title",
    "recording_conditions",
    "figure_title",
    "mark_synthetic",
]

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


def recording_conditions(recording=None, velocities=None) -> tuple[str, ...]:
    """The conditions a figure's title names: "treadmill" (the velocities' treadmill check found one)
    and "markerless" (the recording says so in ``metadata["markerless"]``, or its points are
    OpenCap's video keypoints, ``*_study``)."""
    out = []
    treadmill = getattr(velocities, "treadmill", None)
    if treadmill is not None and getattr(treadmill, "detected", False):
        out.append("treadmill")
    meta = getattr(recording, "metadata", None) or {}
    names = getattr(recording, "point_names", None) or []
    if meta.get("markerless") or any(str(n).lower().endswith("_study") for n in names):
        out.append("markerless")
    return tuple(out)


def figure_title(velocities=None, what: str = "", conditions=()) -> str:
    """The title a figure gets from the API when none is given: the file, the point followed, the
    conditions (:func:`recording_conditions`) and ``what`` (e.g. the estimator)."""
    source = getattr(velocities, "source", "") or "recording"
    name = Path(source).name if source else "recording"
    point = getattr(velocities, "point", "")
    conditions = tuple(conditions) or recording_conditions(None, velocities)
    text = f"{name}: {point}" if point else name
    if what:
        text += f" [{what}]"
    return _with_conditions(text, conditions)


def _with_conditions(title: str, conditions) -> str:
    """``title (treadmill, markerless)``, each condition once."""
    new = [c for c in dict.fromkeys(conditions or ()) if c and c not in title]
    return f"{title} ({', '.join(new)})" if new else title


#: Characters of a figure title that fit the width of a figure (a longer one is shortened at a word).
TITLE_MAX_CHARS = 110


def _title(title: str, synthetic: bool) -> str:
    if synthetic and "synthetic" not in title.lower():
        title = f"Synthetic data: {title}" if title else "Synthetic data"
    return textwrap.shorten(title, TITLE_MAX_CHARS, placeholder=" ...") if len(title) > TITLE_MAX_CHARS else title


def _given(explicit, result, name: str):
    """The explicit array, else ``result.<name>`` (one spelling: the record tables'), as floats; None if neither."""
    value = explicit if explicit is not None else None if result is None else getattr(result, name, None)
    return None if value is None else np.asarray(value, dtype=float)


def _check(t, **arrays):
    for name, a in arrays.items():
        if a is not None and a.shape != t.shape:
            raise InputError(f"{name} has shape {a.shape}, expected {t.shape} like time_s")


_MARK_GID = "yoyogait-synthetic-mark"
"""The id of the SYNTHETIC marks, by which a reused figure loses them."""


def mark_synthetic(fig: Figure) -> None:
    """A boxed SYNTHETIC DATA label in the bottom right corner and a faint diagonal watermark."""
    width_in, height_in = fig.get_size_inches()
    fig.text(
        0.5,
        0.5,
        "SYNTHETIC",
        rotation=float(np.degrees(np.arctan2(height_in, width_in))),
        fontsize=6.5 * float(np.hypot(width_in, height_in)),  # about 3/4 of the diagonal
        rotation_mode="anchor",
        weight="bold",
        color="tab:red",
        alpha=0.09,
        ha="center",
        va="center",
        zorder=0,
        gid=_MARK_GID,
    )
    fig.text(  # bottom right: the one corner no title, legend or axis label reaches
        0.995,
        0.005,
        "SYNTHETIC DATA",
        fontsize=9,
        weight="bold",
        color="darkred",
        ha="right",
        va="bottom",
        bbox=dict(boxstyle="round,pad=0.3", facecolor="#fde0dc", edgecolor="tab:red"),
        gid=_MARK_GID,
    )


def _legend_above(ax, **kwargs) -> None:
    """The legend in one row just above the axes: it never hides data."""
    handles, labels = ax.get_legend_handles_labels()
    if handles:
        ax.legend(
            handles,
            labels,
            loc="lower left",
            bbox_to_anchor=(0.0, 1.0),
            ncol=kwargs.pop("ncol", len(handles)),
            fontsize="small",
            frameon=False,
            borderaxespad=0.1,
            handlelength=1.6,
            columnspacing=1.2,
            **kwargs,
        )


def _shade_standing(ax, t, walking, label: bool = True) -> None:
    """Grey bands where the person stands (not walking)."""
    if walking is None:
        return
    standing = ~np.asarray(walking, dtype=bool)
    first = True
    for a, b in runs(standing):
        ax.axvspan(
            t[a], t[min(b, len(t) - 1)], color="0.88", lw=0, zorder=0, label="standing" if first and label else None
        )
        first = False


def _split_standing(y, walking):
    """(y while walking, y while standing), each NaN elsewhere and joined at the transitions."""
    y = np.asarray(y, dtype=float)
    if walking is None:
        return y, None
    walk = np.asarray(walking, dtype=bool)
    if walk.shape != y.shape or walk.all():
        return y, None
    stand = ~walk
    # each part reaches one sample into the other, so that the line does not break at a transition
    walk_ext = walk | np.concatenate([walk[1:], [False]]) | np.concatenate([[False], walk[:-1]])
    stand_ext = stand | np.concatenate([stand[1:], [False]]) | np.concatenate([[False], stand[:-1]])
    return np.where(walk_ext, y, np.nan), np.where(stand_ext, y, np.nan)


def _plot_estimate(ax, t, y, walking, *, color, lw=1.2, label=None, prior_label: bool = True) -> None:
    """An estimate drawn as what it is: solid while walking, grey dashed while standing (where the
    estimator holds its last walking values or its prior: no measurement of the gait there)."""
    walk, stand = _split_standing(y, walking)
    ax.plot(t, walk, color=color, lw=lw, label=label)
    if stand is not None and np.isfinite(stand).any():
        ax.plot(t, stand, color="0.55", lw=lw, ls="--", label="held while standing" if prior_label else None)


def _reference_style(quality, truth: bool) -> tuple[str, dict]:
    """The label and line style of a reference step frequency, by its quality."""
    if truth:
        return "truth", dict(color=_REF, lw=1.0, ls="--")
    if quality is None:
        return "reference (foot contacts)", dict(color=_REF, lw=1.0, ls="--")
    origin = getattr(quality, "origin", "foot contacts")
    if getattr(quality, "trusted", False):
        return f"reference ({origin}, trusted)", dict(color=_REF, lw=1.0, ls="--")
    return f"reference ({origin}), not trusted", dict(color="tab:brown", lw=1.0, ls=":", alpha=0.8)


def _reference_note(ax, quality, f_ref) -> None:
    """A note in the panel: why the reference is not trusted, or that there is none."""
    has = f_ref is not None and np.isfinite(np.asarray(f_ref, dtype=float)).any()
    if has and (quality is None or getattr(quality, "trusted", False)):
        return
    if not has:
        why = getattr(quality, "reason", "") if quality is not None else ""
        text = "no reference step frequency" + (f": {why}" if why else " (no foot contacts)")
    else:
        text = f"reference not trusted: {quality.reason}"
    ax.text(
        0.01,
        0.04,
        text,
        transform=ax.transAxes,
        fontsize="small",
        color="tab:brown",
        ha="left",
        va="bottom",
        bbox=dict(boxstyle="round,pad=0.2", facecolor="white", edgecolor="none", alpha=0.8),
    )


DPI = 100
"""Resolution of saved figures (an 8 in wide figure is 800 pixels)."""

_YLABEL_GAP_IN = 0.62
"""Distance of the y labels from their axes, in inches."""


def _align_ylabels(fig: Figure) -> None:
    """The y labels at one fixed distance from their axes: aligned like ``fig.align_ylabels()``
    without measuring every tick label of every axes at each draw (a quarter of a figure's time)."""
    width_in = fig.get_size_inches()[0]
    for ax in fig.axes:
        ax_width_in = width_in * ax.get_position().width
        if ax_width_in > 0:
            ax.yaxis.set_label_coords(-_YLABEL_GAP_IN / ax_width_in, 0.5)


def load_matplotlib() -> None:
    """Import what drawing figures needs (about a quarter of a second, once per process): worker
    processes forked afterwards start with it."""
    import matplotlib.backends.backend_agg  # noqa: F401
    import matplotlib.figure  # noqa: F401
    import PIL.PngImagePlugin  # noqa: F401


def _new_figure(kind: str, width_in: float, height_in: float) -> Figure:
    from matplotlib.backends.backend_agg import FigureCanvasAgg
    from matplotlib.figure import Figure

    fig = Figure(figsize=(width_in, height_in), dpi=DPI, label=kind)
    FigureCanvasAgg(fig)
    return fig


def _time_panels(into: Figure | None, kind: str, height_in: float, ylabels, **adjust) -> tuple[Figure, bool]:
    """``into`` emptied for reuse (:func:`_reused`), else a new 8 in wide ``kind`` figure of panels
    stacked over a shared time axis, one per label of ``ylabels``; and whether it is new."""
    fig = _reused(into, kind)
    if fig is not None:
        return fig, False
    fig = _new_figure(kind, 8.0, height_in)
    fig.subplots_adjust(left=0.1, right=0.97, **adjust)
    axes = fig.subplots(len(ylabels), 1, sharex=True)
    for ax, label in zip(axes, ylabels):
        ax.set_ylabel(label)
        ax.grid(True, alpha=0.3)
    axes[-1].set_xlabel("time (s)")
    return fig, True


def _reused(into: Figure | None, kind: str) -> Figure | None:
    """``into`` (drawn by an earlier call of the ``kind`` figure) emptied of its data, legends and
    SYNTHETIC marks, as a new one would be before them; None when ``into`` is None."""
    if into is None:
        return None
    from matplotlib.figure import Figure

    if not isinstance(into, Figure) or into.get_label() != kind:
        raise InputError(f"into: not a figure drawn by {kind}_figure")
    for ax in into.axes:
        for artist in (*ax.lines, *ax.collections, *ax.patches, *ax.texts):
            artist.remove()
        legend = ax.get_legend()
        if legend is not None:
            legend.remove()
        ax.relim()  # the data limits of a new axes: none, until data are added
        ax.set_prop_cycle(None)
        # The limits of a new axes, autoscaled to the data at the draw (each axes of the figure is
        # reset, so the shared ones need not hear of it).
        ax.set_xlim(0.0, 1.0, emit=False, auto=True)
        ax.set_ylim(0.0, 1.0, emit=False, auto=True)
    for text in [t for t in into.texts if t.get_gid() == _MARK_GID]:
        text.remove()
    return into


@functools.cache
def _png_info():
    """The text chunk matplotlib's own PNGs have."""
    import matplotlib
    from PIL import PngImagePlugin

    info = PngImagePlugin.PngInfo()
    info.add_text("Software", f"Matplotlib version{matplotlib.__version__}, https://matplotlib.org/")
    return info


def _save(fig: Figure, path: Path) -> None:
    """``fig.savefig(path, dpi=DPI)``; a PNG of an opaque figure as RGB at zlib level 1 instead of RGBA
    at level 6: the same pixels, in about half the encoding time (a sixth of a figure's), and no larger."""
    from matplotlib.backends.backend_agg import FigureCanvasAgg
    from matplotlib.colors import to_rgba
    from PIL import Image

    canvas = fig.canvas
    opaque = to_rgba(fig.get_facecolor())[3] == 1.0
    if path.suffix.lower() != ".png" or not opaque or fig.dpi != DPI or not isinstance(canvas, FigureCanvasAgg):
        fig.savefig(path, dpi=DPI)
        return
    canvas.draw()
    width, height = canvas.get_width_height()
    rgba = Image.frombuffer("RGBA", (width, height), canvas.buffer_rgba(), "raw", "RGBA", 0, 1)
    rgba.convert("RGB").save(path, format="png", compress_level=1, dpi=(DPI, DPI), pnginfo=_png_info())


def _finish(fig: Figure, path, synthetic: bool = False, *, new: bool = True) -> Figure:
    if synthetic:
        mark_synthetic(fig)
    if new:
        _align_ylabels(fig)
    if path is not None:
        path = Path(path)
        path.parent.mkdir(parents=True, exist_ok=True)
        _save(fig, path)
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
    walking=None,
    reference_quality=None,
    conditions=(),
    title: str = "",
    synthetic: bool | None = None,
    path=None,
    into: Figure | None = None,
) -> Figure:
    """Fig. 3: step frequency, Yoyo radii and EKF bias/amplitude over time.

    Top: the signed step frequency estimate (Hz; 0 marked, so that a filter locked
    onto the negative frequency shows) with the recording's DFT average as a
    horizontal line (given, or computed from ``measured_vz_mps``) and a
    reference step frequency over time when known.  Middle: R and r (m),
    estimated and true.  Bottom: A0 and A1 (m/s).  ``truth`` (a
    :class:`~yoyogait.synthetic.SyntheticTruth`) supplies the references on
    its own time grid and marks the figure synthetic.  ``walking`` (on
    ``time_s``) shades the standing periods, where the estimate is drawn grey
    and dashed (held, not measured); the step frequency has its +-2 sigma
    band (``result.step_frequency_std_hz``).  ``reference_quality`` (a
    :class:`~yoyogait.pipeline.events.ReferenceQuality`) labels the
    reference, draws an untrusted one dotted and says why; without a
    reference on real data a note says so.  ``conditions`` ("treadmill",
    "markerless") are named in the title.  Saved as PNG to ``path`` when
    given.  ``into``: a figure an earlier call returned, drawn again with
    these data (faster than a new one, see the module's notes).
    """
    t = np.asarray(time_s, dtype=float)
    f = _given(step_frequency_hz, result, "step_frequency_hz")
    R = _given(R_m, result, "R_m")
    r = _given(r_m, result, "r_m")
    A0 = _given(A0_mps, result, "A0_mps")
    A1 = _given(A1_mps, result, "A1_mps")
    state = _given(None, result, "state")
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

    fig, new = _time_panels(
        into, "parameter", 7.5, ("step frequency (Hz)", "R, r (m)", "A0, A1 (m/s)"), top=0.9, bottom=0.07, hspace=0.32
    )
    ax_f, ax_R, ax_A = fig.axes

    if walking is not None:
        walking = np.asarray(walking, dtype=bool)
        if walking.shape != t.shape:
            raise InputError(f"walking has shape {walking.shape}, expected {t.shape} like time_s")
        for ax in (ax_f, ax_R, ax_A):
            _shade_standing(ax, t, walking, label=ax is ax_f)
    ax_f.axhline(0.0, color="0.3", lw=0.8)
    f_std = getattr(result, "step_frequency_std_hz", None) if result is not None else None
    if f is not None and f_std is not None:
        f_std = np.asarray(f_std, dtype=float)
        band = np.isfinite(f_std) & np.isfinite(f)
        if f_std.shape == t.shape and band.any():
            ax_f.fill_between(t, f - 2 * f_std, f + 2 * f_std, where=band, color=_EST, alpha=0.2, lw=0, label="±2σ")
    if f is not None:
        _plot_estimate(ax_f, t, f, walking, color=_EST, label="estimate f (signed)")
    if reference_step_frequency_hz is not None:
        label, style = _reference_style(reference_quality, truth is not None)
        ax_f.plot(
            t_ref, np.broadcast_to(np.asarray(reference_step_frequency_hz, float), t_ref.shape), label=label, **style
        )
    if truth is None and not synthetic:
        _reference_note(ax_f, reference_quality, reference_step_frequency_hz)
    if f is not None:  # the band of the first samples (P0) must not flatten the estimate
        finite_f = f[np.isfinite(f)]
        ref = np.asarray(reference_step_frequency_hz, float) if reference_step_frequency_hz is not None else None
        if finite_f.size:
            top = max(
                0.5, float(np.max(finite_f)), float(np.nanmax(ref)) if ref is not None and np.isfinite(ref).any() else 0
            )
            bottom = min(0.0, float(np.min(finite_f)))
            pad = 0.1 * (top - bottom)
            ax_f.set_ylim(bottom - pad, top + pad)
    if dft_step_frequency_hz is not None and np.isfinite(dft_step_frequency_hz):
        ax_f.axhline(
            dft_step_frequency_hz,
            color="tab:red",
            lw=1.0,
            ls=":",
            label=f"DFT average ({dft_step_frequency_hz:.2f} Hz)",
        )

    if R is not None:
        _plot_estimate(ax_R, t, R, walking, color=_EST, label="R est.")
    if r is not None:
        _plot_estimate(ax_R, t, r, walking, color=_EST2, label="r est.", prior_label=False)
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

    if A0 is not None:
        ax_A.plot(t, A0, color=_EST, lw=1.0, label="A0 (bias)")
    if A1 is not None:
        ax_A.plot(t, A1, color=_EST2, lw=1.0, label="A1 (amplitude)")

    for ax in (ax_f, ax_R, ax_A):
        _legend_above(ax)
    fig.suptitle(_title(_with_conditions(title, conditions), bool(synthetic)), y=0.985)
    return _finish(fig, path, bool(synthetic), new=new)


def velocity_figure(
    time_s,
    measured_vx_mps,
    measured_vz_mps,
    result=None,
    *,
    vx_hat_mps=None,
    vz_hat_mps=None,
    walking=None,
    conditions=(),
    title: str = "",
    synthetic: bool = False,
    path=None,
    into: Figure | None = None,
) -> Figure:
    """Fig. 4: measured against reconstructed (eq. 13-14) v_x (top) and v_z (bottom), m/s.

    ``walking`` (on ``time_s``) shades the standing periods, where the reconstruction is drawn grey
    and dashed; the reconstruction has a band of +-2 standard deviations of its residual against the
    measurement while walking (the reconstruction's uncertainty as the data show it); ``conditions``
    ("treadmill", "markerless") are named in the title.  Saved as PNG to ``path`` when given.
    ``into``: a figure an earlier call returned, drawn again with these data (faster than a new
    one, see the module's notes).
    """
    t = np.asarray(time_s, dtype=float)
    vx = np.asarray(measured_vx_mps, dtype=float)
    vz = np.asarray(measured_vz_mps, dtype=float)
    vx_hat_mps = _given(vx_hat_mps, result, "vx_hat_mps")
    vz_hat_mps = _given(vz_hat_mps, result, "vz_hat_mps")
    _check(t, measured_vx_mps=vx, measured_vz_mps=vz, vx_hat_mps=vx_hat_mps, vz_hat_mps=vz_hat_mps)

    fig, new = _time_panels(
        into, "velocity", 5.5, ("forward $v_x$ (m/s)", "vertical $v_z$ (m/s)"), top=0.86, bottom=0.1, hspace=0.3
    )
    ax_x, ax_z = fig.axes
    walk = None
    if walking is not None:
        walk = np.asarray(walking, dtype=bool)
        if walk.shape != t.shape:
            raise InputError(f"walking has shape {walk.shape}, expected {t.shape} like time_s")
    for ax, measured, estimate, name in ((ax_x, vx, vx_hat_mps, "v_x"), (ax_z, vz, vz_hat_mps, "v_z")):
        _shade_standing(ax, t, walk, label=ax is ax_x)
        ax.plot(t, measured, color="0.45", lw=1.0, label=f"measured ${name}$")
        if estimate is not None:
            residual = measured - estimate
            used = np.isfinite(residual) & (walk if walk is not None else True)
            if used.sum() > 10:
                sigma = float(np.std(residual[used]))
                ax.fill_between(
                    t,
                    estimate - 2 * sigma,
                    estimate + 2 * sigma,
                    where=np.isfinite(estimate) & (walk if walk is not None else True),
                    color=_EST,
                    alpha=0.15,
                    lw=0,
                    label=f"±2σ of the residual ({sigma:.3f} m/s)",
                )
            _plot_estimate(ax, t, estimate, walk, color=_EST, label=f"reconstructed ${name}$", prior_label=ax is ax_x)
        _legend_above(ax)
    fig.suptitle(_title(_with_conditions(title, conditions), synthetic), y=0.985)
    return _finish(fig, path, synthetic, new=new)


def _zoom_window(t: np.ndarray, walking, span_s: float) -> tuple[float, float]:
    """A ``span_s`` window in the middle of the longest walking stretch (else of the recording)."""
    spans = runs(np.asarray(walking, dtype=bool)) if walking is not None else []
    a, b = max(spans, key=lambda s: s[1] - s[0]) if spans else (0, len(t))
    lo, hi = t[a], t[b - 1]
    mid = 0.5 * (lo + hi)
    start = max(t[0], min(mid - 0.5 * span_s, t[-1] - span_s))
    return start, min(start + span_s, t[-1])  # never past the end of a short recording


def estimate_figure(
    velocities,
    result,
    *,
    reference_step_frequency_hz=None,
    contacts_s=None,
    reference_quality=None,
    conditions=None,
    title: str = "",
    synthetic: bool = False,
    zoom_s: float = 5.0,
    path=None,
) -> Figure:
    """What ``yoyogait estimate`` draws: the estimate over a whole recording and a zoom.

    Rows, on one time axis: forward and vertical velocity, measured and reconstructed
    (eq. 13-14); the signed step frequency with its +-2 sigma band (0 marked) and the cadence
    from foot contacts (``reference_step_frequency_hz`` on the velocity grid) when known; the
    speed with its +-2 sigma band against the measured forward velocity averaged over a stride.
    Standing periods (``velocities.walking`` False) are shaded.  Bottom: ``zoom_s`` seconds in
    the middle of the longest walking stretch (inside the recording), where each step and the phase
    of the reconstruction against the measurement show, foot contacts (``contacts_s``) marked.
    While standing the step frequency and the speed are drawn grey and dashed: the estimator holds
    them there, nothing measures them.  ``reference_quality`` labels the reference (dotted and
    named "not trusted" when it is not, a note when there is none).  Without ``title`` the figure
    is titled from the velocities (:func:`figure_title`); ``conditions`` (default: from the
    velocities' treadmill check) are named in it.
    """
    vel, res = velocities, result
    t = np.asarray(vel.time_s, dtype=float)
    vx, vz = np.asarray(vel.vx, dtype=float), np.asarray(vel.vz, dtype=float)
    vx_hat_mps, vz_hat_mps = np.asarray(res.vx_hat_mps, dtype=float), np.asarray(res.vz_hat_mps, dtype=float)
    f = np.asarray(res.step_frequency_hz, dtype=float)
    f_std = np.asarray(res.step_frequency_std_hz, dtype=float)
    speed = np.asarray(res.speed_mps, dtype=float)
    speed_std = np.asarray(res.speed_std_mps, dtype=float)
    f_ref = None if reference_step_frequency_hz is None else np.asarray(reference_step_frequency_hz, dtype=float)
    _check(t, vx_hat_mps=vx_hat_mps, vz_hat_mps=vz_hat_mps, step_frequency_hz=f, speed_mps=speed, reference=f_ref)
    walking = getattr(vel, "walking", None)

    fig = _new_figure("estimate", 10.0, 11.0)
    outer = fig.add_gridspec(2, 1, height_ratios=(4.0, 1.2), left=0.08, right=0.98, top=0.93, bottom=0.05, hspace=0.2)
    rows = outer[0].subgridspec(4, 1, hspace=0.32)
    ax_x = fig.add_subplot(rows[0])
    ax_z = fig.add_subplot(rows[1], sharex=ax_x)
    ax_f = fig.add_subplot(rows[2], sharex=ax_x)
    ax_s = fig.add_subplot(rows[3], sharex=ax_x)
    for ax in (ax_x, ax_z, ax_f):
        ax.tick_params(labelbottom=False)
    zoom_row = outer[1].subgridspec(1, 2, wspace=0.22)
    zoom_x, zoom_z = fig.add_subplot(zoom_row[0, 0]), fig.add_subplot(zoom_row[0, 1])
    lo, hi = _zoom_window(t, walking, zoom_s)

    whole = hi - lo >= 0.9 * (t[-1] - t[0])  # a short recording: the zoom shows all of it, no box
    for ax in (ax_x, ax_z, ax_f, ax_s):
        _shade_standing(ax, t, walking, label=ax is ax_x)
        if not whole:
            ax.axvspan(
                lo,
                hi,
                facecolor="none",
                edgecolor="tab:purple",
                lw=1.0,
                ls="--",
                zorder=1,
                label="zoom (bottom)" if ax is ax_x else None,
            )
        ax.grid(True, alpha=0.3)
        ax.margins(x=0)

    for ax, zoom, measured, estimate, name in (
        (ax_x, zoom_x, vx, vx_hat_mps, "v_x"),
        (ax_z, zoom_z, vz, vz_hat_mps, "v_z"),
    ):
        for a in (ax, zoom):
            a.plot(t, measured, color="0.4", lw=0.9, label=f"measured ${name}$")
            # While standing the reconstruction is the model carried on without a measurement, as in Fig. 4.
            _plot_estimate(a, t, estimate, walking, color=_EST, lw=1.1, label=f"reconstructed ${name}$",
                           prior_label=a is ax_x)  # fmt: skip
    ax_x.set_ylabel("forward $v_x$ (m/s)")
    ax_z.set_ylabel("vertical $v_z$ (m/s)")

    band = np.isfinite(f_std)
    if band.any():
        ax_f.fill_between(t, f - 2 * f_std, f + 2 * f_std, where=band, color=_EST, alpha=0.25, lw=0, label="±2σ")
    ax_f.axhline(0.0, color="0.3", lw=0.8)
    _plot_estimate(ax_f, t, f, walking, color=_EST, label="estimate (signed)")
    if f_ref is not None and np.isfinite(f_ref).any():
        label, style = _reference_style(reference_quality, False)
        ax_f.plot(t, f_ref, label=label.replace("reference", "cadence", 1), **style)
    if not synthetic:
        _reference_note(ax_f, reference_quality, f_ref)
    ax_f.set_ylabel("step frequency (Hz)")
    finite_f = f[np.isfinite(f)]
    if finite_f.size:  # the band of the first samples (P0) must not flatten the estimate
        top = max(
            0.5,
            float(np.max(finite_f)),
            float(np.nanmax(f_ref)) if f_ref is not None and np.isfinite(f_ref).any() else 0.0,
        )
        bottom = min(0.0, float(np.min(finite_f)))
        pad = 0.1 * (top - bottom)
        ax_f.set_ylim(bottom - pad, top + pad)

    band = np.isfinite(speed_std)
    if band.any():
        ax_s.fill_between(
            t, speed - 2 * speed_std, speed + 2 * speed_std, where=band, color=_EST2, alpha=0.25, lw=0, label="±2σ"
        )
    # Averaged over a stride (two steps), where the oscillation cancels: the stride of the foot-contact
    # cadence, else of the estimate; 1.8 Hz when neither is known.
    cadence = f_ref if f_ref is not None and np.isfinite(f_ref).any() else f
    known = np.abs(cadence[np.isfinite(cadence) & (np.asarray(walking, bool) if walking is not None else True)])
    f_typ = float(np.clip(np.median(known), 0.6, 3.0)) if known.size else 1.8
    mean_vx = moving_mean(vx, max(1, int(round(2.0 / f_typ * vel.rate_hz))))
    ax_s.plot(t, mean_vx, color="0.4", lw=1.0, label="measured $v_x$, stride mean")
    _plot_estimate(ax_s, t, speed, walking, color=_EST2, label="speed estimate", prior_label=False)
    ax_s.set_ylabel("speed (m/s)")
    ax_s.set_xlabel("time (s)")

    contacts = np.asarray(contacts_s, dtype=float) if contacts_s is not None else np.empty(0)
    shown = contacts[(contacts >= lo) & (contacts <= hi)]
    for zoom, name in ((zoom_x, "forward $v_x$ (m/s)"), (zoom_z, "vertical $v_z$ (m/s)")):
        zoom.set_xlim(lo, hi)
        inside = (t >= lo) & (t <= hi)
        values = np.concatenate(
            [vx[inside], vx_hat_mps[inside]] if zoom is zoom_x else [vz[inside], vz_hat_mps[inside]]
        )
        values = values[np.isfinite(values)]
        if values.size:
            pad = 0.08 * (values.max() - values.min() + 1e-3)
            zoom.set_ylim(values.min() - pad, values.max() + pad)
        for k, c in enumerate(shown):
            zoom.axvline(c, color="tab:green", lw=0.8, ls=":", label="foot contact" if k == 0 else None)
        zoom.set_xlabel("time (s)")
        zoom.set_ylabel(name)
        zoom.grid(True, alpha=0.3)
        zoom.set_title(f"zoom: {lo:.1f}-{hi:.1f} s", fontsize="small", loc="right", pad=2)

    for ax in (ax_x, ax_z, ax_f, ax_s):
        _legend_above(ax)
    _legend_above(zoom_z, ncol=2)
    _legend_above(zoom_x, ncol=2)
    if conditions is None:
        conditions = recording_conditions(None, vel)
    fig.suptitle(_title(_with_conditions(title or figure_title(vel), conditions), synthetic), y=0.99)
    return _finish(fig, path, synthetic)


_VALID = "tab:green"
_INVALID = "tab:red"


def validity_rows(time_s, walking, valid, reasons) -> list[tuple[str, np.ndarray, np.ndarray, str]]:
    """The rows of :func:`validity_strip`: walking, valid, then each reason that occurs; ``reasons``:
    (reason, mask) pairs (an InvalidReason bit set, an ImuReason equal)."""
    t = np.asarray(time_s, dtype=float)
    rows = [
        ("walking", t, np.asarray(walking, dtype=bool), "0.45"),
        ("valid", t, np.asarray(valid, dtype=bool), _VALID),
    ]
    return rows + [(reason_words(r), t, mask, _INVALID) for r, mask in reasons if mask.any()]


def _reason_rows(result) -> list[tuple[str, np.ndarray, np.ndarray, str]]:
    """The strip's rows of an online result (its invalid_reason bits)."""
    bits = np.asarray(result.invalid_reason, dtype=int)
    reasons = [(r, (bits & int(r)) != 0) for r in InvalidReason]
    return validity_rows(result.time_s, result.walking, result.valid, reasons)


def validity_strip(ax, rows) -> None:
    """A strip of when things hold: one horizontal bar per row, top to bottom, over the samples
    where its mask holds (each sample until the next); rows: (label, times, mask, colour)."""
    for k, (_, times, mask, colour) in enumerate(rows):
        step = times[-1] - times[-2] if times.size > 1 else 0.01
        edges = np.concatenate([times, [times[-1] + step]])
        bars = [(edges[a], edges[b] - edges[a]) for a, b in runs(mask)]
        ax.broken_barh(bars, (len(rows) - 1 - k - 0.35, 0.7), facecolors=colour, lw=0)
    ax.set_yticks(range(len(rows)))
    ax.set_yticklabels([row[0] for row in reversed(rows)], fontsize="small")
    ax.set_ylim(-0.6, len(rows) - 0.4)
    ax.grid(True, axis="x", alpha=0.3)


def _valid_and_not(ax, t, y, std, valid, *, colour, label) -> None:
    """An online estimate: solid with its ±2σ band where it is valid, thin grey (band pale) where not."""
    y, std = np.asarray(y, dtype=float), np.asarray(std, dtype=float)
    band = np.isfinite(std) & np.isfinite(y)
    ax.fill_between(t, y - 2 * std, y + 2 * std, where=band & valid, color=colour, alpha=0.25, lw=0,
                    label="±2σ" if (band & valid).any() else None)  # fmt: skip
    ax.fill_between(t, y - 2 * std, y + 2 * std, where=band & ~valid, color="0.6", alpha=0.15, lw=0)
    ax.plot(t, np.where(valid, y, np.nan), color=colour, lw=1.2, label=f"{label} (valid)" if valid.any() else None)
    ax.plot(t, np.where(valid, np.nan, y), color="0.55", lw=0.8, label=None if valid.all() else f"{label} (not valid)")


def _limits(ax, *series, low: float, high: float, cap: float) -> None:
    """y from 0 to the largest finite value of the series (at least ``low``), padded, at most ``cap``."""
    top = high
    for v in series:
        if v is not None:
            v = np.asarray(v, dtype=float)
            v = v[np.isfinite(v)]
            if v.size:
                top = max(top, float(np.max(v)))
    ax.set_ylim(low, min(cap, 1.12 * top))


def online_figure(
    result,
    *,
    reference_time_s=None,
    reference_vz_mps=None,
    reference_step_frequency_hz=None,
    reference_speed_mps=None,
    reference_walking=None,
    reference_quality=None,
    conditions=(),
    title: str = "",
    synthetic: bool = False,
    path=None,
) -> Figure:
    """What ``yoyogait estimate --online --figure`` and ``evaluate --online`` draw: an online estimate
    (:class:`~yoyogait.estimators.online.OnlineResult`) frame by frame, as a controller gating on
    ``valid`` would see it.

    Rows, on one time axis: the front-end's vertical velocity and the reconstruction at the frame
    time; the step frequency and the speed, solid with their ±2σ bands where the estimate is
    valid, grey where it is not; a strip of when the estimator says walking, when the estimate is
    valid and each reason it is not (docs/online.md, "Validity"). With references (on
    ``reference_time_s``: the offline v_z, the foot-contact cadence and stride-averaged speed, the
    reference's walking part) each row shows them too, and the strip their walking part.
    """
    t = np.asarray(result.time_s, dtype=float)
    if t.size == 0:
        raise InputError("the online result has no frames to draw")
    valid = np.asarray(result.valid, dtype=bool)
    # The y-limits follow the valid estimates (a not-valid start-up must not flatten them); with none
    # valid, the estimate while walking (else all of it), so that its line is in view.
    shown = valid if valid.any() else np.asarray(result.walking, dtype=bool)
    shown = shown if shown.any() else np.ones_like(valid)
    f_shown = np.asarray(result.step_frequency_hz, dtype=float)[shown]
    s_shown = np.asarray(result.speed_mps, dtype=float)[shown]
    # The references, on their own time axis; none without one.
    given = reference_time_s is not None
    ref_t = np.asarray(reference_time_s if given else t, dtype=float)
    ref = {
        name: np.asarray(value, dtype=float) if given and value is not None else None
        for name, value in (
            ("vz", reference_vz_mps),
            ("f", reference_step_frequency_hz),
            ("speed", reference_speed_mps),
            ("walking", reference_walking),
        )
    }
    _check(ref_t, **{k: v for k, v in ref.items() if v is not None})

    rows = _reason_rows(result)
    n_rows = len(rows) + (ref["walking"] is not None)
    fig = _new_figure("online", 10.0, 8.0 + 0.16 * n_rows)
    grid = fig.add_gridspec(4, 1, height_ratios=(1.0, 1.0, 1.0, 0.17 * (n_rows + 1)), left=0.17, right=0.98,
                            top=0.9, bottom=0.07, hspace=0.28)  # fmt: skip
    ax_z = fig.add_subplot(grid[0])
    ax_f = fig.add_subplot(grid[1], sharex=ax_z)
    ax_s = fig.add_subplot(grid[2], sharex=ax_z)
    ax_v = fig.add_subplot(grid[3], sharex=ax_z)
    for ax in (ax_z, ax_f, ax_s):
        ax.tick_params(labelbottom=False)
        ax.grid(True, alpha=0.3)
        ax.margins(x=0)

    ax_z.plot(t, np.asarray(result.vz_mps, dtype=float), color="0.6", lw=0.7, label="front-end $v_z$")
    if ref["vz"] is not None:
        ax_z.plot(ref_t, ref["vz"], color=_REF, lw=0.8, ls="--", label="offline $v_z$ (centred)")
    ax_z.plot(t, np.asarray(result.vz_hat_mps, dtype=float), color=_EST, lw=1.0, label="reconstructed $v_z$")
    ax_z.set_ylabel("vertical $v_z$ (m/s)")
    finite_vz = np.asarray(result.vz_hat_mps, dtype=float)[valid]
    finite_vz = finite_vz[np.isfinite(finite_vz)]
    if finite_vz.size:  # the front-end's start-up and noise must not flatten the gait
        half = max(0.3, 1.5 * float(np.max(np.abs(finite_vz))))
        ax_z.set_ylim(-half, half)

    _valid_and_not(ax_f, t, result.step_frequency_hz, result.step_frequency_std_hz, valid, colour=_EST,
                   label="estimate")  # fmt: skip
    if ref["f"] is not None and np.isfinite(ref["f"]).any():
        label, style = _reference_style(reference_quality, synthetic and reference_quality is None)
        ax_f.plot(ref_t, ref["f"], label=label, **style)
    ax_f.set_ylabel("step frequency (Hz)")
    _limits(ax_f, f_shown, ref["f"], low=0.0, high=2.5, cap=4.0)

    _valid_and_not(ax_s, t, result.speed_mps, result.speed_std_mps, valid, colour=_EST2, label="speed")
    if ref["speed"] is not None and np.isfinite(ref["speed"]).any():
        truth = synthetic and reference_quality is None
        ax_s.plot(
            ref_t, ref["speed"], color=_REF, lw=1.0, ls="--", label="truth" if truth else "reference (stride mean)"
        )
    ax_s.set_ylabel("speed (m/s)")
    _limits(ax_s, s_shown, ref["speed"], low=0.0, high=1.5, cap=3.5)

    if ref["walking"] is not None:
        rows.insert(0, (f"walking ({'truth' if synthetic else 'reference'})", ref_t, ref["walking"] > 0.5, _REF))
    validity_strip(ax_v, rows)
    ax_v.set_xlabel("time (s)")
    ax_v.set_xlim(float(t[0]), float(t[-1]))

    for ax in (ax_z, ax_f, ax_s):
        _legend_above(ax)
    if not synthetic and given:
        _reference_note(ax_f, reference_quality, ref["f"])
    text = _with_conditions(title or "online estimate", conditions)
    fig.suptitle(_title(f"{text}: online, frame by frame", synthetic), y=0.985)
    return _finish(fig, path, synthetic)


def distribution_figure(values: dict, *, labels: dict | None = None, title: str = "", path=None) -> Figure:
    """The distribution over recordings of some metrics, one panel per metric, one box per estimator.

    ``values``: estimator -> metric -> one value per recording (NaN where unknown, left out).
    Boxes span the quartiles around the median, whiskers reach 1.5 interquartile ranges, and every
    recording is a dot. A panel whose values are all positive and span more than a decade has a log scale.
    """
    estimators = list(values)
    keys = list(dict.fromkeys(k for est in estimators for k in values[est]))
    labels = labels or {}
    ncols = 2 if len(keys) > 1 else 1
    nrows = max(1, math.ceil(len(keys) / ncols))
    height_in = 2.6 * nrows + 0.8
    fig = _new_figure("distribution", 8.0, height_in)
    fig.subplots_adjust(
        left=0.11, right=0.98, top=1 - 0.5 / height_in, bottom=0.4 / height_in, hspace=0.25, wspace=0.35
    )
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
            low, high = min(d.min() for _, d in shown), max(d.max() for _, d in shown)
            if low > 0 and high > 10.0 * low:  # errors over decades; shares and narrow spreads stay linear
                from matplotlib.ticker import NullFormatter

                ax.set_yscale("log")
                ax.yaxis.set_minor_formatter(NullFormatter())  # labels at the decades only: none overlap
        ax.set_xticks(positions, estimators)
        ax.set_xlim(-0.6, len(estimators) - 0.4)
        ax.set_ylabel(labels.get(key, key), fontsize="small")
        ax.grid(True, axis="y", alpha=0.3)
    for ax in axes[len(keys) :]:
        ax.set_visible(False)
    fig.suptitle(title)
    return _finish(fig, path)
