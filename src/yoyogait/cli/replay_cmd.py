"""``yoyogait replay FILE --name NAME``: a recording played into an LSL marker stream (an IMU file into an IMU
stream)."""

from __future__ import annotations

import click

from .. import io
from ..errors import about_file
from ..io.imu_read import is_imu_file, read_imu
from ..live.replay import replay, replay_imu
from .imu_cmd import imu_options, refuse_other_kind
from .options import POSITIVE, read_overrides


@click.command("replay")
@click.argument("file", type=click.Path(dir_okay=False))
@click.option("--name", required=True, metavar="NAME", help="Name of the LSL stream (type Mocap; IMU for an IMU file).")
@click.option(
    "--speed", type=POSITIVE, metavar="X", default=1.0, show_default=True, help="Playback speed (2: twice as fast)."
)
@click.option("--loop", is_flag=True, help="Start over at the end (after a 1 s pause), until interrupted.")
@click.option(
    "--up-axis", type=click.Choice(["x", "y", "z"]), default=None, help="Up axis (default: the file's, else detected)."
)
@click.option(
    "--length-unit-m",
    type=POSITIVE,
    metavar="METRES",
    default=None,
    help="Metres per length unit of the file (default: the file's; BVH: inferred from the pelvis height).",
)
@click.option(
    "--capture-rate-hz",
    "--rate-hz",  # the old name, kept as an alias
    "rate_hz",
    type=POSITIVE,
    metavar="HZ",
    default=None,
    help="Capture rate of a file that has none [Hz] (--rate-hz: the old name).",
)
@click.option(
    "--wait-for-consumer",
    "wait_s",
    type=POSITIVE,
    metavar="SECONDS",
    default=None,
    help="Wait up to this many seconds for a consumer before the first frame (error when none comes).",
)
@imu_options
@click.pass_context
def command(
    ctx, file, name, speed, loop, up_axis, length_unit_m, rate_hz, wait_s, acc_unit, gyr_unit, sensor_height_m, trial,
    sensor,
):  # fmt: skip
    """Play a motion-capture FILE (C3D, TRC, BVH, CSV) into an LSL marker stream NAME.

    Channels <point>_x/_y/_z in metres (NaN where missing) and time_s (the file's time), at the
    file's rate times --speed; up axis, unit and point names in the stream's description
    (docs/live.md). An IMU file (Mobilise-D data.mat, an IMU CSV, an Xsens .txt, a Movella DOT .csv,
    an APDM .h5) is played into an IMU stream: acc_x/_y/_z in m/s^2, gyr_x/_y/_z in rad/s and time_s, the sensor
    height in its description.
    """
    imu = is_imu_file(file)
    refuse_other_kind(ctx, file, imu)
    if imu:
        with about_file(file):
            imu = read_imu(
                file,
                acc_unit=acc_unit,
                gyr_unit=gyr_unit,
                rate_hz=rate_hz,
                sensor_height_m=sensor_height_m,
                trial=trial,
                sensor=sensor,
            )

        def imu_ready():
            click.echo(f"replaying {imu.source}: IMU, {imu.n_samples} samples as {name!r}", err=True)

        stats = replay_imu(imu, name, speed=speed, loop=loop, wait_for_consumer_s=wait_s, on_ready=imu_ready)
        click.echo(f"pushed {stats.frames} samples in {stats.wall_s:.1f} s", err=True)
        return
    rec = io.read(file, **read_overrides(up_axis=up_axis, length_unit_m=length_unit_m, rate_hz=rate_hz))

    def ready():
        click.echo(
            f"replaying {rec.source}: {len(rec.point_names)} points, {rec.n_frames} frames as {name!r}", err=True
        )

    stats = replay(rec, name, speed=speed, loop=loop, up_axis=up_axis, wait_for_consumer_s=wait_s, on_ready=ready)
    click.echo(f"pushed {stats.frames} frames in {stats.wall_s:.1f} s", err=True)
