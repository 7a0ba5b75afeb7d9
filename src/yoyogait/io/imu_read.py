"""Lower-back IMU files into :class:`ImuRecording` (docs/imu.md, section 4): which reader takes a file, and
the names every reader module offers, in one place.

=====================  ==========================================================  ========================
``data.mat``           Mobilise-D MATLAB format (acc in g, gyr in deg/s)            :mod:`.mobilised`
``.csv`` (mobgap)      ``samples,acc_x..acc_z,gyr_x..gyr_z``: g, deg/s, 100 Hz       :mod:`.imu_tables`
``.csv`` (yoyogait)    ``time_s,acc_x_mps2..,gyr_x_rad_s..``: units in the header   :mod:`.imu_tables`
``.csv`` (generic)     ``acc_x..`` (or ``acc_is, acc_ml, acc_pa``, or a             :mod:`.imu_tables`
                       microcontroller's ``ax..gz``), ``gyr_x..`` with
                       ``acc_unit``/``gyr_unit``; after a sensor's name or not
                       (``pelvis_ACCEL_x``; ``sensor`` chooses); also a ``.txt``
``.csv`` (ROS)         a ``sensor_msgs/Imu`` topic (``field.linear_acceleration.x``) :mod:`.imu_tables`
                       or PlotJuggler's (``__time``, ``/imu/linear_acceleration/x``)
``.txt`` (Xsens)       MT Manager export: ``PacketCounter Acc_X ... Gyr_Z`` after  :mod:`.xsens`
                       any preamble (``// Update Rate: 100.0Hz``)
``.csv`` (Movella DOT) ``DeviceTag:,..`` lines, ``PacketCounter,SampleTimeFine,..``    :mod:`.xsens`
``.h5`` (APDM/Opal)    ``/Sensors/<id>/Accelerometer`` (v5), ``/<case>/Calibrated``   :mod:`.apdm`
``.tsv`` (Motion-BIDS) a tracked point's ACCEL and GYRO channels                     :mod:`.motion_bids`
=====================  ==========================================================  ========================

Every reader checks the units against physics (:func:`check_imu_plausible`, :mod:`.imu_checks`): the
accelerometer must read about 9.81 m/s^2 where the sensor is still, the gyro must not read in deg/s
where rad/s was said; a failure is one line naming the option that fixes it.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

from ..errors import InputError
from .apdm import read_apdm_h5
from .imu_checks import ACC_UNITS, GYR_UNITS, LOWER_BACK_LABELS, check_imu_plausible, clipped_ranges
from .imu_recording import ImuRecording
from .imu_tables import TIME_COLUMN_NAMES, first_data_header, is_imu_header, read_imu_csv, time_in_seconds
from .mobilised import read_mobilised_mat, read_mobilised_trials
from .motion_bids import channel_types, read_motion_bids_imu
from .xsens import dot_layout, read_dot, read_dot_csv, read_xsens_txt, xsens_txt_header

__all__ = [
    "ACC_UNITS",
    "GYR_UNITS",
    "LOWER_BACK_LABELS",
    "TIME_COLUMN_NAMES",
    "check_imu_plausible",
    "clipped_ranges",
    "is_imu_file",
    "is_imu_header",
    "read_apdm_h5",
    "read_dot_csv",
    "read_imu",
    "read_imu_csv",
    "read_mobilised_mat",
    "read_mobilised_trials",
    "read_motion_bids_imu",
    "read_xsens_txt",
    "time_in_seconds",
]


def is_imu_file(path) -> bool:
    """True for a file the IMU readers read: a Mobilise-D data.mat, an IMU CSV, an Xsens .txt export,
    an APDM .h5."""
    p = Path(path)
    ext = p.suffix.lower()
    if ext in (".mat", ".h5"):
        return True
    if ext == ".tsv":  # Motion-BIDS with accelerometer and gyro channels (and no positions)
        types = channel_types(p)
        return {"ACCEL", "GYRO"} <= types and "POS" not in types
    if ext == ".txt" and xsens_txt_header(p) is not None:
        return True
    if ext in (".csv", ".txt"):
        header = first_data_header(p)
        return (header is not None and is_imu_header(header)) or (ext == ".csv" and dot_layout(p) is not None)
    return False


def read_imu(
    path, *, acc_unit=None, gyr_unit=None, rate_hz=None, sensor_height_m=None, trial=None, sensor=None
) -> ImuRecording:
    """Read an IMU file (see the module's table); the options override what the file says or lacks
    (``sensor``: the sensor of a multi-sensor APDM file, by label or id)."""
    p = Path(path)
    if not p.is_file():
        raise InputError(f"{p}: no such file")
    ext = p.suffix.lower()
    if ext == ".mat":
        rec = read_mobilised_mat(p, trial=trial)
    elif ext == ".txt":
        if xsens_txt_header(p) is None and is_imu_header(first_data_header(p) or []):  # IMU columns, as a CSV
            rec = read_imu_csv(p, acc_unit=acc_unit, gyr_unit=gyr_unit, rate_hz=rate_hz, sensor=sensor)
        else:
            rec = read_xsens_txt(p, acc_unit=acc_unit, gyr_unit=gyr_unit, rate_hz=rate_hz)
    elif ext == ".csv" and (layout := dot_layout(p)) is not None:
        rec = read_dot(p, layout, acc_unit=acc_unit, gyr_unit=gyr_unit, rate_hz=rate_hz)
    elif ext == ".csv":
        rec = read_imu_csv(p, acc_unit=acc_unit, gyr_unit=gyr_unit, rate_hz=rate_hz, sensor=sensor)
    elif ext == ".h5":
        rec = read_apdm_h5(p, sensor=sensor, acc_unit=acc_unit, gyr_unit=gyr_unit, rate_hz=rate_hz)
    elif ext == ".tsv":
        rec = read_motion_bids_imu(p, sensor=sensor, acc_unit=acc_unit, gyr_unit=gyr_unit, rate_hz=rate_hz)
    else:
        raise InputError(f"{p}: not an IMU file yoyogait reads (.mat, .csv, .txt, .h5, a Motion-BIDS .tsv)")
    if sensor is not None and not (ext in (".h5", ".tsv") or rec.metadata.get("layout") in ("yoyogait", "generic")):
        raise InputError(
            f"{p}: sensor= (--sensor) chooses among the sensors of an APDM .h5, a Motion-BIDS .tsv or an IMU CSV "
            "whose columns carry sensor names only"
        )
    if sensor_height_m is not None:
        if not (np.isfinite(sensor_height_m) and 0.1 < sensor_height_m <= 3.0):
            raise InputError(f"sensor_height_m must be in (0.1, 3] m, not {sensor_height_m!r}")
        rec.sensor_height_m = float(sensor_height_m)
    check_imu_plausible(rec)
    clipped = clipped_ranges(rec)
    if clipped:
        rec.metadata["clipped"] = clipped
    return rec
