"""The report folder of a guidance study, written atomically (the conventions of the evaluation's report).

Everything is written into a temporary folder beside ``out`` and moved into place at the end
(:func:`yoyogait._files.install_folder`): an interrupted run leaves nothing half-written; a folder
yoyogait wrote before is replaced only with ``force``, and then only the files its marker lists.
"""

from __future__ import annotations

import re
from pathlib import Path

from .._files import write_folder
from . import figures
from .study import GuidanceStudy, runs_csv, table_csv, table_markdown, target_checks

__all__ = ["write_guidance_report"]


def _slug(text: str) -> str:
    return re.sub(r"[^A-Za-z0-9._-]+", "_", text).strip("_") or "walk"


def write_guidance_report(study: GuidanceStudy, out_dir, *, force: bool = False, draw: bool = True) -> Path:
    """table.csv, table.md, runs.csv, figures/ and report.md into ``out_dir`` (SYNTHETIC)."""
    return write_folder(out_dir, lambda tmp: _write(study, tmp, draw), force=force)


def _write(study: GuidanceStudy, folder: Path, draw: bool) -> None:
    cfg = study.config
    table = table_markdown(study)
    (folder / "table.md").write_text(table + "\n")
    (folder / "table.csv").write_text(table_csv(study))
    (folder / "runs.csv").write_text(runs_csv(study))
    md = [
        "# Tethered guidance: SYNTHETIC simulation",
        "",
        "A person (the synthetic gait lab's walker) guided along a path by a tethered aerial robot under "
        "admittance control; each feedback source gives the controller the human velocity "
        "(docs/guidance.md). Everything here is SYNTHETIC: simulated walkers, simulated motion capture.",
        "",
        f"- walks: {', '.join(study.walks)}",
        f"- walkers: {', '.join(study.walkers)}",
        f"- seed {study.seed}; latency {cfg.latency_s:g} s (a delay line on the human velocity; `truth` undelayed)",
        f"- robot: M_A {cfg.robot_mass_kg:g} kg, B_A {cfg.robot_damping_ns_per_m:g} N s/m, "
        f"K_H {cfg.position_gain_n_per_m:g} N/m, speed limit {cfg.max_speed_mps:g} m/s; "
        f"cable {cfg.cable_rest_length_m:g} m, "
        f"k_c {cfg.cable_stiffness_n_per_m:g} N/m, arm damping {cfg.cable_damping_ns_per_m:g} N s/m",
        f"- human: nominal force {cfg.human.nominal_force_n:g} N, time constant {cfg.human.time_constant_s:g} s; "
        f"physics step {cfg.physics_dt_s * 1000:g} ms (semi-implicit Euler), motion capture and controller "
        f"{cfg.rate_hz:g} Hz",
        "",
        "## The table",
        "",
        "Mean over the walks of each metric, per source (table.csv; per walk: runs.csv).",
        "",
        table,
        "",
        "## Targets",
        "",
    ]
    for target, met, text in target_checks(study):
        state = "not measurable here" if met is None else ("met" if met else "MISSED")
        md.append(f"- {target}: **{state}** ({text})")
    md.append("")
    if draw:
        figures_dir = folder / "figures"
        figures_dir.mkdir()
        md += ["## Figures", "", f"The first walker ({study.walkers[0]}) on each walk.", ""]
        for walk in study.walks:
            runs = [r for r in study.runs if r.walk == walk and r.walker == study.walkers[0]]
            if not runs:
                continue
            stem = _slug(walk)
            title = f"SYNTHETIC: {walk}, {study.walkers[0]}, latency {cfg.latency_s:g} s"
            figures.paths_figure(runs, title + ": paths", figures_dir / f"{stem}_paths.png")
            figures.force_figure(runs, title + ": cable force", figures_dir / f"{stem}_force.png")
            figures.velocity_figure(runs, title + ": velocities", figures_dir / f"{stem}_velocities.png")
            md.append(
                f"- {walk}: [paths](figures/{stem}_paths.png), [cable force and spectrum](figures/{stem}_force.png), "
                f"[velocities](figures/{stem}_velocities.png)"
            )
        md.append("")
    (folder / "report.md").write_text("\n".join(md))
