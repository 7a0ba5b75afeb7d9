"""``yoyogait estimate FILE``: estimates over time as CSV, and a figure."""

from __future__ import annotations

from pathlib import Path

import click
import numpy as np

from .. import io
from .._files import atomic_files, check_outputs
from .._sample_time import RESAMPLE_RATE_HZ
from ..errors import InputError, about_file
from ..estimators.config import PRESETS, EstimatorConfig, OnlineConfig
from ..estimators.online import InvalidReason, OnlineEstimator, check_belt_speed, reason_words
from ..estimators.registry import estimators, noise_adapted, preset_runner
from ..evaluation import figures as plots
from ..pipeline import events
from ..pipeline.treadmill import detect_treadmill
from ..pipeline.velocities import check_point_motion, gait_velocities
from .imu_cmd import estimate_imu, imu_options, is_imu_file, refuse_other_kind
from .options import (
    belt_speed_option,
    check_points,
    estimator_config_option,
    force_option,
    input_options,
    preset_option,
    read_overrides,
)


def foot_contacts(recording, feet, up_axis):
    """Contact times [s] from the file's gait events or the feet (given or found by name); None when there are
    none."""
    ev = reference_events(recording, feet, up_axis)
    return ev.contacts_s if ev is not None and len(ev.contacts_s) >= 2 else None


def reference_events(recording, feet, up_axis):
    """The gait events of the reference (:func:`yoyogait.pipeline.events.reference_events`); None without
    any."""
    if recording.velocities is not None:
        return None
    if feet is None and not events.feet_of(recording) and not recording.metadata.get("events"):
        return None
    try:
        return events.reference_events(recording, feet, up_axis=up_axis)
    except InputError:
        return None


@click.command("estimate")
@click.argument("file", type=click.Path(dir_okay=False))
@input_options
@preset_option
@estimator_config_option(multiple=False)
@click.option(
    "--out",
    type=click.Path(dir_okay=False),
    default=None,
    help="CSV to write [default: FILE's name + .estimate.csv, here].",
)
@click.option(
    "--figure",
    type=click.Path(dir_okay=False),
    default=None,
    help="PNG to write [default: FILE's name + .estimate.png, here; with --online or an IMU file: only "
    "when given]; 'none' for no figure.",
)
@belt_speed_option
@force_option(
    "Overwrite the --out and --figure files if they exist (a link is replaced itself; never a device, "
    "FIFO, socket or an input: docs/files.md)."
)
@click.option(
    "--online",
    is_flag=True,
    help="Replay FILE frame by frame through the online estimator (a CSV; a figure only with --figure).",
)
@imu_options
@click.pass_context
def command(
    ctx,
    file,
    point,
    feet,
    up_axis,
    length_unit_m,
    rate_hz,
    preset,
    config_file,
    out,
    figure,
    belt_speed_mps,
    force,
    online,
    acc_unit,
    gyr_unit,
    sensor_height_m,
    trial,
    sensor,
):
    """Estimate gait over time from a motion-capture FILE (C3D, TRC, BVH, CSV).

    The CSV has one row per 25 Hz sample: time_s, the measured vx_mps, vz_mps, walking (1: the
    person walks, from foot contacts or speed), the reconstruction vx_hat_mps, vz_hat_mps,
    step_frequency_hz and speed_mps with their standard deviations, R_m, r_m, A0_mps, A1_mps, the
    state x1_mps, x2_mps, x3_rad_per_sample, x4_mps, estimator_walking (0: the estimator holds its
    last walking values) and status (0: the sample was used).

    --online replays FILE frame by frame through the online estimator (nothing from the future;
    the default estimator, or the one --config FILE sets with its [online] table): one
    row per capture frame with time_s, vx_mps, vz_mps, vx_hat_mps, vz_hat_mps, step_frequency_hz,
    step_frequency_std_hz, speed_mps, speed_std_mps, heading_rad, gait_phase, walking, status (0
    used, 1 no point seen, 2 timestamp not increasing, 3 restart after a gap, 4 non-finite),
    input_latency_s and next_step_in_s (time to the next lowest point of the pelvis, NaN while
    standing or while no phase is known), valid, invalid_reason and belt_speed_mps; --out defaults
    to FILE's name + .online.csv. With --figure PNG also a figure (written with the CSV or neither):
    v_z, step frequency and speed with their 2-std bands, solid where valid, and a strip of when the
    estimate is valid and why not.
    --feet NAME,NAME puts those foot points (one per foot: heels or ankles) into the frames: their
    steps check the estimate's cadence (a markerless capture is valid only with them), and on a
    treadmill the belt speed is estimated from the stance feet. --belt-speed-mps gives the belt speed;
    without either a treadmill walk is marked not valid (not moving: the pelvis stays in place).

    An IMU file (Mobilise-D data.mat, an IMU CSV, an Xsens .txt, a Movella DOT .csv, an APDM .h5) is
    estimated online by nature: one row per sample, every field of the IMU estimate (docs/imu.md),
    --out defaulting to FILE's name + .imu.csv; --config FILE's [imu] table configures it; a figure
    (cadence and speed over time with their 2-std bands, against the file's reference bouts where it
    has them) only with --figure FILE. The options of marker files (--point, --feet, --up-axis,
    --length-unit-m, --preset, --belt-speed-mps) are refused for it, as the IMU options for a marker file.
    """
    imu = is_imu_file(file)
    refuse_other_kind(ctx, file, imu)
    if imu:
        return estimate_imu(file, out=out, figure=figure, force=force, config_file=config_file, acc_unit=acc_unit,
                            gyr_unit=gyr_unit, rate_hz=rate_hz, sensor_height_m=sensor_height_m,
                            trial=trial, sensor=sensor)  # fmt: skip
    if online:
        return online_estimate(
            file, point, up_axis, length_unit_m, rate_hz, preset, out, figure, force, config_file,
            feet=feet, belt_speed_mps=belt_speed_mps,
        )  # fmt: skip
    run = estimators()[preset]
    config = EstimatorConfig.preset(preset) if preset in PRESETS else None
    resample_hz = RESAMPLE_RATE_HZ
    if config_file is not None:
        if ctx.get_parameter_source("preset") == click.core.ParameterSource.COMMANDLINE:
            raise InputError("give --preset or --config, not both")
        config = EstimatorConfig.from_file(config_file)
        run = preset_runner(config)
        resample_hz = 1.0 / config.sample_time_s  # the velocities come at the estimator's sample time
        preset = Path(config_file).name
    stem = Path(file).name
    out = Path(out or f"{stem}.estimate.csv")
    fig = None if figure == "none" else Path(figure or f"{stem}.estimate.png")
    check_outputs((("--out", out), ("--figure", fig)), force, inputs=(file, config_file))
    overrides = read_overrides(up_axis=up_axis, length_unit_m=length_unit_m, rate_hz=rate_hz)
    with about_file(file):
        recording = io.read(file, **overrides)
        check_points(recording, point, feet)
        vel = gait_velocities(
            recording, point=point, rate_hz=resample_hz, up_axis=up_axis, feet=feet, belt_speed_mps=belt_speed_mps
        )
        res = run(vel)
        noise_line = noise_adapted(config, vel)[1] if config is not None else ""
        ev = reference_events(recording, feet, vel.up_axis) if fig is not None else None
    walked = vel.walking.any()
    f = res.step_frequency_hz[vel.walking] if walked else res.step_frequency_hz
    medians = f"median step frequency {np.nanmedian(f):.2f} Hz, median speed {np.nanmedian(res.speed_mps):.2f} m/s"
    # No walking found (no steps, no travel): the estimator's figures are not a walker's; say so.
    gait = medians if walked else f"no walking found in the recording (steps, travel); over all samples {medians}"
    summary = f"{stem}: {len(vel.time_s)} samples at {vel.rate_hz:g} Hz of {vel.point}; {gait}"
    writers = {out: lambda p: res.to_csv(p, velocities=vel)}
    if fig is not None:
        cadence = ev.step_frequency_at(vel.time_s, stride_average=True) if ev is not None else None
        quality = events.reference_quality(ev, vel.time_s, vel.vz, vel.rate_hz)
        synthetic = bool(recording.metadata.get("synthetic"))
        writers[fig] = lambda p: plots.estimate_figure(
            vel,
            res,
            reference_step_frequency_hz=cadence,
            contacts_s=ev.contacts_s if ev is not None else None,
            reference_quality=quality,
            conditions=plots.recording_conditions(recording, vel),
            title=f"{stem} [{preset}]: {vel.point}",
            synthetic=synthetic,
            path=p,
        )
    # Both or neither: the figure is drawn before the CSV is renamed into place.
    atomic_files(writers)
    click.echo(summary)
    if noise_line:
        click.echo(noise_line)
    if vel.treadmill is not None and vel.treadmill.detected:
        click.echo(vel.treadmill.reason)
    click.echo(f"wrote {out}" + (f" and {fig}" if fig else ""))


def online_estimate(
    file, point, up_axis, length_unit_m, rate_hz, preset, out, figure, force, config_file=None, *, feet=None,
    belt_speed_mps=None,
):  # fmt: skip
    """``estimate --online``: one CSV row per capture frame from yoyogait.OnlineEstimator (ONLINE_CSV_COLUMNS;
    status: 0 used, 1 no point seen, 2 timestamp not increasing, 3 restart after a gap, 4 non-finite, 5 time jump).
    ``feet``: foot points in the frames (a treadmill's belt from the stance feet); ``belt_speed_mps``: a known
    belt speed."""
    if preset != "default":
        raise InputError(f"--online runs the default estimator; --preset {preset} is not available online")
    stem = Path(file).name
    out = Path(out or f"{stem}.online.csv")
    fig = None if figure in (None, "none") else Path(figure)
    check_outputs((("--out", out), ("--figure", fig)), force, inputs=(file, config_file))
    check_belt_speed(belt_speed_mps, "--belt-speed-mps")
    config = OnlineConfig.from_file(config_file) if config_file is not None else None
    overrides = read_overrides(up_axis=up_axis, length_unit_m=length_unit_m, rate_hz=rate_hz)
    with about_file(file):
        recording = io.read(file, **overrides)
        check_points(recording, point, feet)
        check_point_motion(recording, point)  # the check `estimate` makes (offline pipeline), here too
        est = OnlineEstimator.for_recording(recording, point, up_axis=up_axis, config=config, feet=feet)
        if belt_speed_mps is not None:
            est.set_belt_speed_mps(belt_speed_mps)
        res = est.run(recording)
    writers = {out: res.to_csv}
    if fig is not None:
        title = f"{stem}: {', '.join(est.point_names)}" + (f"; feet {', '.join(est.feet)}" if est.feet else "")
        writers[fig] = lambda p: plots.online_figure(
            res,
            conditions=plots.recording_conditions(recording),
            title=title,
            synthetic=bool(recording.metadata.get("synthetic")),
            path=p,
        )
    # Both or neither: the figure is drawn before the CSV is renamed into place.
    atomic_files(writers)
    walking = np.asarray(res.walking, dtype=bool)
    gait = (
        f"median step frequency while walking {np.median(res.step_frequency_hz[walking]):.2f} Hz"
        if walking.any()
        else "never walking"
    )
    click.echo(
        f"{stem}: {len(res)} frames of {', '.join(est.point_names)} replayed online; {gait}, "
        f"front-end latency {1e3 * float(np.median(res.input_latency_s)):.1f} ms"
    )
    click.echo(validity_line(res))
    if not est.feet and noisy_like(res):
        names = ",".join(_feet_in_file(recording)) or "NAME,NAME"
        click.echo(
            "the input is too noisy for the pelvis alone (a markerless capture?): give --feet "
            f"{names} (heels or ankles) to check the estimates on the feet's steps"
        )
    if est.feet or belt_speed_mps is not None:
        click.echo(belt_line(res, est.feet, belt_speed_mps))
    elif treadmill_like(res):
        click.echo(in_place_line(recording, est.up_axis))
    click.echo(f"wrote {out}" + (f" and {fig}" if fig else ""))


def in_place_line(recording, up_axis: str) -> str:
    """What to say of a walk whose pelvis stays in place: with feet in the file that stay too, that
    it steps or bobs in place; else that it may be a treadmill, and the feet or belt speed to give."""
    feet = _feet_in_file(recording)
    if feet:
        treadmill = detect_treadmill(recording, up_axis, feet=feet)
        if treadmill.in_place:
            return (
                f"the pelvis stays in place while the estimator says walking, and so do the feet in stance "
                f"({', '.join(feet)} at {treadmill.stance_foot_speed_mps:.2f} m/s): stepping or bobbing "
                "in place, not a treadmill; its speed is marked not valid"
            )
    return (
        "the pelvis stays in place while the estimator says walking (a treadmill?): its speed is marked "
        f"not valid; give --feet {','.join(feet) or 'NAME,NAME'} (heels) or --belt-speed-mps for the walking speed"
    )


def _feet_in_file(recording) -> list[str]:
    """The recording's foot points found by name, one per foot; empty unless both are found."""
    found = events.feet_of(recording) if recording.point_names else {}
    return list(found.values()) if len(found) == 2 else []


def noisy_like(res) -> bool:
    """Whether most of the walking frames are marked INPUT_NOISY."""
    return _walking_share_flagged(res, InvalidReason.INPUT_NOISY) > 0.5


def treadmill_like(res) -> bool:
    """Whether most of the walking frames are marked not moving (the pelvis stays in place: a treadmill)."""
    return _walking_share_flagged(res, InvalidReason.NOT_MOVING) > 0.5


def _walking_share_flagged(res, reason) -> float:
    """The share of the walking frames whose invalid_reason has ``reason`` (0 without walking)."""
    walking = np.asarray(res.walking, dtype=bool)
    if not walking.any():
        return 0.0
    flagged = (np.asarray(res.invalid_reason, dtype=int) & int(reason)) != 0
    return float(flagged[walking].mean())


def belt_line(res, feet, belt_speed_mps) -> str:
    """One line on the treadmill belt: given, or found from the stance feet (the share of frames, its median)."""
    if belt_speed_mps is not None:
        return f"treadmill belt {belt_speed_mps:.2f} m/s (--belt-speed-mps) added to the pelvis's own speed"
    belt = np.asarray(res.belt_speed_mps, dtype=float)
    on = belt > 0
    if not on.any():
        return (
            f"no treadmill belt found from the stance feet ({', '.join(feet)}): overground; "
            "their steps check the cadence"
        )
    # The frames counted, not a rounded share: a belt on 1 of 331 frames is not "0 %" of a treadmill walk.
    where = f"on {int(on.sum())} of {on.size} frames ({100.0 * on.mean():.1f} %)"
    return (
        f"treadmill belt found from the stance feet ({', '.join(feet)}) {where}, "
        f"median {float(np.median(belt[on])):.2f} m/s, added to the pelvis's own speed there"
    )


def validity_line(res) -> str:
    """One line on what the validity checks found: the share of valid frames, the most frequent reason
    when not valid, the input noise (docs/online.md, "Validity")."""
    valid = np.asarray(res.valid, dtype=bool)
    reasons = np.asarray(res.invalid_reason, dtype=int)
    noise_mm = 1e3 * float(np.median(res.input_noise_m)) if len(res) else 0.0
    line = f"estimates valid {100.0 * valid.mean() if len(res) else 0.0:.0f} % of the time"
    if (~valid).any():
        counts = {reason_words(r): int(np.sum((reasons & int(r)) != 0)) for r in InvalidReason}
        line += f" (not valid mostly: {max(counts, key=lambda name: counts[name])})"
    return line + f"; input noise {noise_mm:.1f} mm"
