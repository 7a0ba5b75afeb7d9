"""Figures of a guidance study: paths, cable force over time and its spectrum, velocities (SYNTHETIC)."""

from __future__ import annotations

from pathlib import Path

import numpy as np

from .metrics import WALKING_SPEED_MPS
from .simulation import GuidanceRun

__all__ = ["paths_figure", "force_figure", "velocity_figure", "FIGURE_SOURCES"]

FIGURE_SOURCES = ("raw", "lowpass-1hz", "yoyogait", "yoyogait-predicted", "truth")
"""The sources drawn (those of the study among them); the others are in the table."""

_COLOURS = {
    "none": "tab:gray",
    "raw": "tab:red",
    "lowpass-0.5hz": "tab:pink",
    "lowpass-1hz": "tab:orange",
    "lowpass-2hz": "tab:brown",
    "yoyogait": "tab:blue",
    "yoyogait-gated": "tab:cyan",
    "yoyogait-predicted": "tab:purple",
    "truth": "black",
}


def _figure(width_in: float, height_in: float):
    from matplotlib.backends.backend_agg import FigureCanvasAgg
    from matplotlib.figure import Figure

    fig = Figure(figsize=(width_in, height_in), dpi=110)
    FigureCanvasAgg(fig)
    return fig


def _mark(fig) -> None:
    fig.text(
        0.995,
        0.005,
        "SYNTHETIC DATA (simulation)",
        fontsize=8,
        weight="bold",
        color="darkred",
        ha="right",
        va="bottom",
        bbox=dict(boxstyle="round,pad=0.3", facecolor="#fde0dc", edgecolor="tab:red"),
    )


def _save(fig, path: Path) -> None:
    fig.savefig(path, format="png")


def _chosen(runs: list[GuidanceRun]) -> list[GuidanceRun]:
    by = {r.source: r for r in runs}
    return [by[s] for s in FIGURE_SOURCES if s in by] or runs[:4]


def paths_figure(runs: list[GuidanceRun], title: str, path: Path) -> None:
    """Plan view: the path, the walker's guided point per source and the robot's track (yoyogait's, else
    the first); below it, each source's distance from the path over time."""
    fig = _figure(8.0, 8.0)
    plan, error = fig.subplots(2, 1, gridspec_kw=dict(height_ratios=[1.6, 1.0], hspace=0.3))
    p = runs[0].path
    plan.plot(p.xy_m[:, 0], p.xy_m[:, 1], "o-", color="0.75", lw=6, alpha=0.6, label="path", zorder=1)
    for r in _chosen(runs):
        colour = _COLOURS.get(r.source)
        plan.plot(r.guided_m[:, 0], r.guided_m[:, 1], color=colour, lw=1.1, label=f"walker, {r.source}")
        error.plot(r.time_s, 100.0 * p.distance(r.guided_m, extend_ends=True), color=colour, lw=0.9, label=r.source)
    robot = next((r for r in runs if r.source == "yoyogait"), runs[0])
    plan.plot(robot.robot_m[:, 0], robot.robot_m[:, 1], ":", color="tab:green", lw=1.2, label=f"robot, {robot.source}")
    plan.set_aspect("equal", adjustable="datalim")
    plan.set_xlabel("x (m)")
    plan.set_ylabel("y (m)")
    plan.grid(alpha=0.3)
    plan.legend(fontsize=7, loc="best")
    plan.set_title(title, fontsize=9)
    error.set_xlabel("time (s)")
    error.set_ylabel("walker's distance from\nthe path, sideways (cm)")
    error.grid(alpha=0.3)
    error.legend(fontsize=7, ncol=5, loc="upper left")
    _mark(fig)
    _save(fig, path)


def force_figure(runs: list[GuidanceRun], title: str, path: Path) -> None:
    """Cable tension over time per source, and the spectrum of the horizontal force while walking,
    with the walker's mean step frequency and its double marked."""
    fig = _figure(9.0, 7.0)
    top, bottom = fig.subplots(2, 1, gridspec_kw=dict(height_ratios=[1.2, 1.0], hspace=0.35))
    f_step = np.nan
    for r in _chosen(runs):
        colour = _COLOURS.get(r.source)
        top.plot(r.time_s, r.tension_n, color=colour, lw=0.7, label=r.source)
        walking = (np.linalg.norm(r.intent_v_mps, axis=1) > WALKING_SPEED_MPS) & (r.time_s >= r.config.start_s)
        fh = r.force_n[walking, :2]
        if len(fh) > 256:
            fs = r.config.rate_hz
            from scipy import signal  # scipy.signal takes about a second to import: only where it is used

            freq, pxx = signal.welch(fh - fh.mean(axis=0), fs=fs, nperseg=512, axis=0)
            bottom.semilogy(freq, np.sqrt(pxx.sum(axis=1)), color=colour, lw=0.9, label=r.source)
            f_step = float(np.mean(r.cadence_hz[walking]))
    top.set_ylabel("cable tension (N)")
    top.set_xlabel("time (s)")
    top.grid(alpha=0.3)
    top.legend(fontsize=7, ncol=5, loc="upper right")
    top.set_title(title, fontsize=9)
    if np.isfinite(f_step):
        for k in (0.5, 1, 2):
            bottom.axvline(k * f_step, color="0.5", ls="--", lw=0.8)
            bottom.text(k * f_step, 1.0, f" {k:g}x step", transform=bottom.get_xaxis_transform(), fontsize=7, va="top")
    bottom.set_xlim(0, 8)
    bottom.set_xlabel("frequency (Hz)")
    bottom.set_ylabel("horizontal force, amplitude\nspectral density (N/sqrt(Hz))")
    bottom.grid(alpha=0.3, which="both")
    _mark(fig)
    _save(fig, path)


def velocity_figure(runs: list[GuidanceRun], title: str, path: Path) -> None:
    """The speed each source gave the controller against the intended speed; the raw hand speed behind."""
    fig = _figure(9.0, 4.8)
    ax = fig.add_subplot(111)
    truth = next((r for r in runs if r.source == "truth"), runs[0])
    for r in _chosen(runs):
        if r.source == "truth":
            continue
        ax.plot(
            r.time_s,
            np.linalg.norm(r.source_v_mps, axis=1),
            color=_COLOURS.get(r.source),
            lw=0.8,
            alpha=0.5 if r.source == "raw" else 1.0,
            label=f"{r.source} (as the controller saw it)",
        )
    ax.plot(
        truth.time_s,
        np.linalg.norm(truth.intent_v_mps, axis=1),
        color="black",
        lw=1.4,
        ls="--",
        label=f"intended ({truth.source} run)",
    )
    ax.set_xlabel("time (s)")
    ax.set_ylabel("horizontal speed (m/s)")
    ax.grid(alpha=0.3)
    ax.legend(fontsize=7, loc="upper right")
    ax.set_title(title, fontsize=9)
    _mark(fig)
    _save(fig, path)
