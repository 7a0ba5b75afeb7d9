"""``yoyogait live --source NAME``: gait estimated live from an LSL marker stream or a lower-back IMU stream."""

from __future__ import annotations

import signal
import sys
import threading
from pathlib import Path

import click

from .._guard import Interrupted
from ..errors import InputError
from ..estimators.config import ImuConfig, OnlineConfig
from ..estimators.online import ONLINE_CSV_COLUMNS, csv_formats
from ..live.imu_live import IMU_COLUMNS, INPUT_KINDS, ImuLiveOptions, ImuLiveSetup, run_live_source
from ..live.live import BeltSpeedStream, describe_source
from ..live.ros2 import Ros2Publisher
from ..live.status import StatusLine
from .imu_cmd import IMU_OPTIONS
from .options import MARKER_OPTIONS, POSITIVE, config_file_option, refuse_options, split_names


@click.command("live")
@click.option("--source", required=True, metavar="NAME", help="Name of the LSL marker or IMU stream to estimate from.")
@click.option(
    "--input",
    "input_kind",
    type=click.Choice(INPUT_KINDS),
    default="auto",
    show_default=True,
    help="What the source is: markers, a lower-back IMU, or auto (an IMU by the stream's type IMU or its "
    "acc/gyr channel labels).",
)
@click.option(
    "--publish", default=None, metavar="NAME", help="Name of the LSL estimate stream to publish (docs/live.md)."
)
@click.option(
    "--record",
    type=click.Path(dir_okay=False),
    default=None,
    help="CSV of the estimates (the columns of estimate --online).",
)
@click.option("--force", is_flag=True, help="Overwrite an existing --record file.")
@click.option(
    "--point",
    metavar="NAME[,NAME...]",
    default=None,
    callback=split_names,
    help="Point to follow: 'pelvis' (default: the pelvis centre, found by name), 'hand', "
    "or point names separated by commas (averaged).",
)
@click.option(
    "--feet",
    metavar="NAME,NAME",
    default=None,
    callback=split_names,
    help="Foot points of the stream, one per foot (heels or ankles): their steps check the estimate's cadence "
    "(a markerless stream is valid only with them); on a treadmill, the belt speed from the stance feet.",
)
@click.option("--belt-speed-mps", type=float, default=None, metavar="M/S", help="Treadmill belt speed (known, fixed).")
@click.option(
    "--belt-speed-source",
    default=None,
    metavar="NAME",
    help="LSL stream of the treadmill's belt speed (first channel, m/s; it may change at any time).",
)
@click.option("--up-axis", type=click.Choice(["x", "y", "z"]), default=None, help="Up axis (default: the stream's).")
@click.option(
    "--length-unit-m",
    type=POSITIVE,
    metavar="METRES",
    default=None,
    help="Metres per length unit of the stream (default: the stream's).",
)
@click.option("--duration", type=POSITIVE, metavar="SECONDS", default=None, help="Stop after this many seconds.")
@click.option("--exit-on-end", is_flag=True, help="Stop when the source stream ends (else wait for it to come back).")
@click.option(
    "--timeout",
    type=POSITIVE,
    metavar="SECONDS",
    default=10.0,
    show_default=True,
    help="Seconds to wait for the source.",
)
@click.option(
    "--max-buffer-s",
    type=POSITIVE,
    metavar="SECONDS",
    default=1.0,
    show_default=True,
    help="Frames kept when falling behind [s].",
)
@click.option(
    "--list-points",
    is_flag=True,
    help="Print the source's points, unit and up axis (an IMU stream: its channels, units, sensor height), and exit.",
)
@config_file_option(
    "Settings of the online estimator: a TOML file with the estimator's fields and an [online] table "
    "(an IMU stream: its [imu] table; docs/configuration.md)."
)
@click.option(
    "--acc-unit",
    type=click.Choice(["mps2", "g"]),
    default=None,
    help="IMU stream: unit of the acceleration channels (default: the channels' unit).",
)
@click.option(
    "--gyr-unit",
    type=click.Choice(["rad_s", "deg_s"]),
    default=None,
    help="IMU stream: unit of the angular-rate channels (default: the channels' unit).",
)
@click.option(
    "--sensor-height-m",
    type=POSITIVE,
    metavar="METRES",
    default=None,
    help="IMU stream: the sensor's height standing (default: the stream's setup/sensor_height_m, else [imu]).",
)
@click.option(
    "--ros2-topic",
    default=None,
    metavar="TOPIC",
    help="Also publish on this ROS 2 topic (yoyogait[ros2]; docs/live.md).",
)
@click.pass_context
def command(
    ctx, source, input_kind, publish, record, force, point, feet, belt_speed_mps, belt_speed_source, up_axis,
    length_unit_m, duration, exit_on_end, timeout, max_buffer_s, list_points, config_file, acc_unit, gyr_unit,
    sensor_height_m, ros2_topic,
):  # fmt: skip
    """Estimate gait live from the LSL stream SOURCE (markers, or a lower-back IMU): publish, record and show
    the estimates.

    --feet NAME,NAME: the feet's steps check the cadence (a markerless stream is valid only with them). On
    a treadmill: --feet (the belt speed from the stance feet), --belt-speed-mps (known) or
    --belt-speed-source NAME (an LSL stream of the belt speed, which may change); without any of them a
    treadmill walk is marked not valid (not moving).
    """
    config = OnlineConfig.from_file(config_file) if config_file is not None and input_kind != "imu" else None
    imu_config = ImuConfig.from_file(config_file) if config_file is not None and input_kind != "markers" else None
    if input_kind == "imu" and ros2_topic:
        raise InputError("--ros2-topic: publishes the marker path's estimates; not available with an IMU stream")
    if input_kind == "imu" and (feet or belt_speed_mps is not None or belt_speed_source is not None):
        raise InputError("--feet, --belt-speed-mps, --belt-speed-source: for a marker stream, not an IMU stream")
    if belt_speed_mps is not None and belt_speed_source is not None:
        raise InputError("give --belt-speed-mps or --belt-speed-source, not both")
    if belt_speed_source is not None and belt_speed_source == source:
        raise InputError(f"--belt-speed-source {belt_speed_source!r}: the marker stream is not a belt speed")
    if list_points:
        for line in describe_source(source, timeout):
            click.echo(line)
        return
    # SIGINT and SIGTERM end the run at once in every state (waiting for the source included): the
    # summary line, the record completed with the rows so far, then exit 130 or 143.
    stop = threading.Event()
    received: list[int] = []

    def on_signal(signum, frame):
        received.append(signum)
        stop.set()

    in_main = threading.current_thread() is threading.main_thread()  # signals can only be caught there
    previous = {s: signal.signal(s, on_signal) for s in (signal.SIGINT, signal.SIGTERM)} if in_main else {}
    status = StatusLine(sys.stderr) if sys.stderr.isatty() else None
    sink = None

    def setup(s):
        outputs = [f"publishing LSL {publish!r}"] if publish else []
        if ros2_topic:
            outputs.append(f"ROS 2 topic {ros2_topic!r}")
        if record:
            outputs.append(f"recording {record}")
        if isinstance(s, ImuLiveSetup):
            if status is not None:
                status.columns = IMU_COLUMNS
            what = (
                f"an IMU (acc in {s.layout.acc_unit}, gyr in {s.layout.gyr_unit}, "
                f"sensor height {s.sensor_height_m:g} m)"
            )
        else:
            # The IMU options on a marker stream would be ignored: refused, named.
            refuse_options(ctx, f"stream {source!r} is a marker stream", IMU_OPTIONS, "IMU streams")
            what = f"following {s.choice.label}, up {s.up_axis}"
        click.echo(
            f"live: {s.source!r} at {s.nominal_rate_hz:g} Hz, {what}; "
            + (", ".join(outputs) if outputs else "no output but the status line (see --publish, --record)"),
            err=True,
        )

    def imu_found():
        # A marker stream's options on an IMU stream would be ignored: refused, named, as for a file.
        refuse_options(ctx, f"stream {source!r} is an IMU stream", MARKER_OPTIONS, "marker streams")
        if ros2_topic:
            raise InputError(
                f"stream {source!r} is an IMU stream: --ros2-topic publishes the marker path's estimates only"
            )

    try:
        if ros2_topic:
            sink = Ros2Publisher(ros2_topic)
        belt_input = BeltSpeedStream(belt_speed_source, timeout, stop) if belt_speed_source is not None else None
        if status is not None:  # on a terminal, so that the wait is not mistaken for a hang
            click.echo(f"live: looking for the LSL stream {source!r} (up to {timeout:g} s)", err=True)
        counters = run_live_source(
            source,
            input_kind=input_kind,
            markers=dict(
                point=point,
                up_axis=up_axis,
                length_unit_m=length_unit_m,
                record_columns=ONLINE_CSV_COLUMNS,
                record_formats=csv_formats(ONLINE_CSV_COLUMNS),
                config=config,
                on_estimate=sink.publish if sink is not None else None,
                feet=feet,
                belt_speed_mps=belt_speed_mps,
                belt_speed=belt_input,
            ),
            imu=ImuLiveOptions(
                acc_unit=acc_unit, gyr_unit=gyr_unit, sensor_height_m=sensor_height_m, config=imu_config
            ),
            on_imu=imu_found,
            publish=publish,
            resolve_timeout_s=timeout,
            duration_s=duration,
            exit_on_end=exit_on_end,
            record=Path(record) if record else None,
            force=force,
            max_buffer_s=max_buffer_s,
            on_setup=setup,
            on_status=status.show if status is not None else None,
            on_note=lambda line: click.echo(line, err=True),
            stop=stop,
        )
    finally:
        if status is not None:
            status.close()
        if sink is not None:
            sink.close()
        for s, h in previous.items():
            signal.signal(s, h)
    click.echo(
        f"live: {counters.frames} frames, {counters.estimates} estimates; dropped (time not increasing) "
        f"{counters.dropped_not_increasing}, dropped (time jumped) {counters.dropped_jumps}, missing by the "
        f"nominal rate {counters.missing_frames}, in bursts {counters.burst_frames}, restarts {counters.restarts}"
        + (f", reconnects {counters.reconnects}" if counters.reconnects else "")
        + ("; the source ended" if counters.source_ended else ""),
        err=True,
    )
    if record and counters.connected:
        click.echo(f"wrote {record}", err=True)
    if received:
        raise Interrupted(received[0])
