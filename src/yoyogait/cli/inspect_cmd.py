"""``yoyogait inspect FILE``: what a motion-capture file holds and what the velocity pipeline makes of it."""

from __future__ import annotations

import json

import click
import numpy as np

from ..errors import InputError, about_file
from ..io import read
from ..pipeline import events, points, spectral
from ..pipeline.velocities import MIN_USABLE_S, gait_velocities
from .imu_cmd import imu_options, inspect_imu, is_imu_file, refuse_other_kind
from .options import belt_speed_option, input_options, read_overrides


def inspect_file(
    path: str,
    *,
    point=None,
    feet=None,
    up_axis=None,
    length_unit_m=None,
    rate_hz=None,
    forward: str = "norm",
    belt_speed_mps: float | None = None,
) -> dict:
    """Everything ``inspect`` prints, as a dict (computed before anything is printed)."""
    with about_file(path):
        return _inspect(
            path,
            point=point,
            feet=feet,
            up_axis=up_axis,
            length_unit_m=length_unit_m,
            rate_hz=rate_hz,
            forward=forward,
            belt_speed_mps=belt_speed_mps,
        )


def _inspect(path: str, *, point, feet, up_axis, length_unit_m, rate_hz, forward: str, belt_speed_mps) -> dict:
    rec = read(path, **read_overrides(up_axis=up_axis, length_unit_m=length_unit_m, rate_hz=rate_hz))
    # Inspect describes a recording too short for the offline estimator as well: it says so instead.
    velocities = gait_velocities(
        rec, point=point, up_axis=up_axis, forward=forward, feet=feet, belt_speed_mps=belt_speed_mps,
        min_usable_s=0.0,
    )  # fmt: skip
    usable_s = float(velocities.finite.sum()) / velocities.rate_hz
    treadmill = velocities.treadmill
    if rec.velocities is not None:  # ready velocities: vz is the vertical one by the CSV layout
        up_axis_from = "the velocity columns: vz is vertical"
    else:
        up_axis_from = points.resolve_up_axis(rec, up_axis)[1]
    evidence = None
    if rec.positions_m.shape[1]:
        try:
            ev = rec.metadata.get("up_axis_evidence") or points.up_axis_evidence(rec)
        except InputError:
            ev = None
        if ev is not None:
            evidence = {"axis": ev.axis, "scores": ev.scores, "decisive": ev.decisive, "summary": ev.summary()}
    report: dict = {
        "file": rec.source,
        "format": rec.format,
        "rate_hz": rec.rate_hz,
        "frames": rec.n_frames,
        "duration_s": rec.duration_s,
        "length_unit": rec.metadata.get("length_unit_from", ""),
        "time_unit": rec.metadata.get("time_unit"),
        "points": list(rec.point_names),
        "up_axis": velocities.up_axis,
        "up_axis_from": up_axis_from,
        "up_axis_evidence": evidence,
        "point": velocities.point,
        "pelvis": None,
        "hand": None,
        "feet": {},
        "foot_points": {},
        "walking_s": velocities.walking_s,
        "usable_velocity_s": usable_s,
        "too_short_note": None
        if usable_s >= MIN_USABLE_S
        else (
            f"{usable_s:.2f} s of usable velocity, shorter than the {MIN_USABLE_S:g} s the offline estimator "
            "needs (estimate and evaluate refuse it); estimate --online replays it frame by frame"
        ),
        "walking_from": "",
        "mean_speed_mps": None,
        "mean_signed_speed_mps": None,
        "step_frequency_hz": None,
        "events_step_frequency_hz": None,
        "steps": 0,
        "dft": None,
        "treadmill": None
        if treadmill is None
        else {
            "detected": treadmill.detected,
            "belt_speed_mps": treadmill.belt_speed_mps,
            "belt_from": treadmill.belt_from,
            "pelvis_range_m": treadmill.pelvis_range_m,
            "in_place": treadmill.in_place,
            "stance_foot_speed_mps": treadmill.stance_foot_speed_mps,
            "summary": treadmill.reason,
        },
    }
    if rec.velocities is None:  # a followed point other than the pelvis, no hand: not errors for inspect
        try:
            report["pelvis"] = points.find_pelvis(rec.point_names).label
        except InputError:
            pass
        try:
            report["hand"] = list(points.find_hand(rec.point_names).names)
        except InputError:
            pass
        report["foot_points"] = events.foot_groups_of(rec, feet)
        report["feet"] = {side: group[0] for side, group in report["foot_points"].items()}
    report["walking_from"] = "pelvis speed" if rec.velocities is None else "the given speed"
    report["reference"] = None
    ev = None
    if report["pelvis"] and (report["feet"] or rec.metadata.get("events")):
        ev = events.reference_events(rec, feet, up_axis=velocities.up_axis)
    if ev is not None:
        report["steps"] = int(len(ev.step_start_s))
        if len(ev.step_start_s):
            report["events_step_frequency_hz"] = ev.mean_step_frequency_hz
        if len(ev.contacts_s):
            report["walking_from"] = "foot contacts" if ev.origin == "foot contacts" else "the file's gait events"
        q = events.reference_quality(ev, velocities.time_s, velocities.vz, velocities.rate_hz)
        report["reference"] = {**q.as_row(), "summary": q.summary()}

    walking = velocities.walking & velocities.finite
    if walking.any():
        report["mean_speed_mps"] = float(np.mean(velocities.vx[walking]))
        report["mean_signed_speed_mps"] = float(np.mean(velocities.vx_signed[walking]))
    try:
        check = spectral.dft_check(velocities)
    except InputError as exc:  # too little walking for a DFT: say so instead of failing
        report["dft_note"] = str(exc).split(": ", 1)[-1]
    else:
        report["step_frequency_hz"] = check.step_frequency_hz
        report["dft"] = {
            "step_frequency_hz": check.step_frequency_hz,
            "vertical_frequency_hz": check.vertical_frequency_hz,
            "forward_frequency_hz": check.forward_frequency_hz,
            "phase_offset_deg": check.phase_offset_deg,
            "offset_sign": check.offset_sign,
            "model_offset_deg": check.model_offset_deg,
            "verdict": check.verdict,
            "start_s": check.start_s,
            "end_s": check.end_s,
            "summary": check.summary(),
        }
    # Cadence as clinicians give it, beside the Hz values (which stay as they are).
    for hz, per_min in (
        ("step_frequency_hz", "step_frequency_steps_per_min"),
        ("events_step_frequency_hz", "events_cadence_steps_per_min"),
    ):
        report[per_min] = None if report[hz] is None else 60.0 * float(report[hz])
    return report


def _fmt(value, unit: str, digits: int = 2) -> str:
    return "n/a" if value is None else f"{value:.{digits}f} {unit}"


@click.command(name="inspect")
@click.argument("file", type=click.Path(dir_okay=False))
@input_options
@click.option(
    "--forward",
    type=click.Choice(["norm", "heading"]),
    default="norm",
    show_default=True,
    help="Forward velocity: 2-norm of the horizontal velocity (paper) or signed along the heading.",
)
@belt_speed_option
@click.option("--all-points", is_flag=True, help="List every point name.")
@click.option("--json", "as_json", is_flag=True, help="Print the report as JSON.")
@imu_options
@click.pass_context
def command(
    ctx, file, point, feet, up_axis, length_unit_m, rate_hz, forward, belt_speed_mps, all_points, as_json,
    acc_unit, gyr_unit, sensor_height_m, trial, sensor,
) -> None:  # fmt: skip
    """Print a recording's rate, duration, points, chosen pelvis and up axis, walking time,
    mean speed, dominant step frequency and the DFT check of the Yoyo-model. An IMU file (Mobilise-D
    data.mat, an IMU CSV, an Xsens .txt, a Movella DOT .csv, an APDM .h5): its rate, units, gravity
    and the online IMU estimate."""
    imu = is_imu_file(file)
    refuse_other_kind(ctx, file, imu)
    if imu:
        return inspect_imu(file, acc_unit=acc_unit, gyr_unit=gyr_unit, rate_hz=rate_hz,
                           sensor_height_m=sensor_height_m, trial=trial, sensor=sensor, as_json=as_json)  # fmt: skip
    report = inspect_file(
        file,
        point=point,
        feet=feet,
        up_axis=up_axis,
        length_unit_m=length_unit_m,
        rate_hz=rate_hz,
        forward=forward,
        belt_speed_mps=belt_speed_mps,
    )
    if as_json:
        click.echo(json.dumps(report, indent=1, default=float))
        return
    names = report["points"]
    shown = names if all_points or len(names) <= 12 else names[:12] + [f"... ({len(names) - 12} more)"]
    rate = f"{report['rate_hz']:g} Hz" if report["rate_hz"] else "irregular"
    lines = [
        ("file", f"{report['file']} ({report['format'].upper()})"),
        (
            "rate",
            f"{rate}, {report['frames']} frames, {report['duration_s']:.2f} s"
            + (f" ({report['time_unit']}, by its intervals)" if report["time_unit"] else ""),
        ),
        ("length unit", report["length_unit"]),
        ("points", f"{len(names)}: {', '.join(shown)}" if names else "none (ready velocities)"),
        ("up axis", f"{report['up_axis']} ({report['up_axis_from']})"),
    ]
    if report["up_axis_evidence"] is not None:
        lines.append(("body says", report["up_axis_evidence"]["summary"]))
    if names:
        lines.append(("pelvis", report["pelvis"] or "none found"))
    if report["point"] != report["pelvis"]:
        lines.append(("followed", report["point"]))
    if names:
        lines.append(("hand", ", ".join(report["hand"]) if report["hand"] else "none found"))
        feet = ", ".join(
            f"{side} {group[0]}" + (f" (with {', '.join(group[1:])})" if len(group) > 1 else "")
            for side, group in report["foot_points"].items()
        )
        lines.append(("feet", feet or "none found"))
    if report["treadmill"] is not None and (
        report["treadmill"]["detected"] or "stays" in report["treadmill"]["summary"]
    ):
        lines.append(("treadmill", report["treadmill"]["summary"]))
    walking = f"{report['walking_s']:.2f} s (from {report['walking_from']})"
    tm = report["treadmill"]
    if tm is not None and tm["in_place"] and report["walking_s"] > 0:
        # Steps (or foot motions) without walking over ground: a sit-to-stand's feet, steps in place.
        walking += f", in place: the pelvis stays within {tm['pelvis_range_m']:.2f} m"
    lines.append(("walking", walking))
    speed = _fmt(report["mean_speed_mps"], "m/s")
    if report["mean_signed_speed_mps"] is not None and forward == "norm":
        speed += f" (2-norm; {report['mean_signed_speed_mps']:.2f} m/s signed along the heading)"
    lines.append(("mean speed", speed + (" while walking" if report["mean_speed_mps"] is not None else "")))
    step = _fmt(report["step_frequency_hz"], "Hz")
    step += (
        f" = {report['step_frequency_steps_per_min']:.0f} steps/min (DFT of the vertical velocity)"
        if report["step_frequency_hz"] is not None
        else f" ({report.get('dft_note', '')})"
    )
    if report["events_step_frequency_hz"] is not None:
        origin = (report["reference"] or {}).get("reference_origin", "foot contacts")
        step += (
            f"; {origin}: {report['events_step_frequency_hz']:.2f} Hz = "
            f"{report['events_cadence_steps_per_min']:.0f} steps/min over {report['steps']} steps"
        )
    lines.append(("step frequency", step))
    if report["reference"] is not None:
        lines.append(("reference", report["reference"]["summary"]))
    if report["dft"]:
        d = report["dft"]
        lines.append(
            (
                "DFT peaks",
                f"vertical {d['vertical_frequency_hz']:.2f} Hz, forward "
                f"{d['forward_frequency_hz']:.2f} Hz over {d['start_s']:.2f}-{d['end_s']:.2f} s",
            )
        )
        lead = "forward leads vertical" if d["phase_offset_deg"] >= 0 else "forward lags vertical"
        lines.append(
            (
                "phase offset",
                f"{d['phase_offset_deg']:+.0f} deg (forward - vertical, {d['offset_sign']}: "
                f"{lead}); Yoyo-model {d['model_offset_deg']:+.0f} deg: {d['verdict']}",
            )
        )
    if report["too_short_note"]:
        lines.append(("note", report["too_short_note"]))
    width = max(len(k) for k, _ in lines) + 2
    for key, value in lines:
        click.echo(f"{key:<{width}}{value}")
