"""APDM (Opal, Mobility Lab, Motion Studio) HDF5 files, formats 3 to 5 (the ``apdm`` extra: h5py;
docs/imu.md, section 4)."""

from __future__ import annotations

from pathlib import Path

import numpy as np

from ..errors import InputError
from .imu_checks import ACC_UNITS, GYR_UNITS, option_flag, pick_sensor, reading, unit_scale
from .imu_recording import GRAVITY_MPS2, ImuRecording

__all__ = ["APDM_ACC_UNITS", "APDM_GYR_UNITS", "choose_sensor", "read_apdm_h5"]

APDM_ACC_UNITS = {"m/s^2": 1.0, "m/s2": 1.0, "m/s/s": 1.0, "g": GRAVITY_MPS2}
APDM_GYR_UNITS = {"rad/s": 1.0, "rad/sec": 1.0, "deg/s": np.pi / 180.0, "deg/sec": np.pi / 180.0}


def _text(value) -> str:
    if isinstance(value, bytes):
        value = value.decode("utf-8", errors="replace")
    elif isinstance(value, np.ndarray):
        value = value.reshape(-1)[0] if value.size else ""
        return _text(value)
    return str(value).strip().strip("\x00").strip()


def _apdm_sensors(f, p: Path) -> tuple[int, dict[str, dict]]:
    """(format version, {sensor id: {label, acc, gyr, time, rate, acc_unit, gyr_unit}}) of an open APDM file:
    format 5 (``/Sensors/<id>``) or 3/4 (``/<case id>/Calibrated``, the root's ``CaseIdList``, ``MonitorLabelList``)."""
    import h5py  # the apdm extra

    version_attr = f.attrs.get("FileFormatVersion", f.attrs.get("File_Format_Version"))
    try:
        version = int(float(_text(version_attr))) if version_attr is not None else 0
    except ValueError:
        version = 0
    sensors: dict[str, dict] = {}
    if "Sensors" in f and isinstance(f["Sensors"], h5py.Group):
        for sid, g in f["Sensors"].items():
            if not isinstance(g, h5py.Group) or "Accelerometer" not in g:
                continue
            conf = g["Configuration"].attrs if "Configuration" in g else {}
            sensors[str(sid)] = {
                "label": _text(conf.get("Label 0", "")),
                "acc": g["Accelerometer"],
                "gyr": g.get("Gyroscope"),
                "time": g.get("Time"),
                "rate": conf.get("Sample Rate"),
            }
        return version or 5, sensors
    listed = f.attrs.get("CaseIdList", f["CaseIdList"][()] if "CaseIdList" in f else None)
    if listed is not None:
        # Formats 3 and 4 list the cases and their labels as attributes of the root (older writers: datasets).
        ids = [_text(v) for v in np.asarray(listed).reshape(-1)]
        said = f.attrs.get("MonitorLabelList", f["MonitorLabelList"][()] if "MonitorLabelList" in f else [])
        labels = [_text(v) for v in np.asarray(said).reshape(-1)]
        for i, case in enumerate(ids):
            if case not in f or "Calibrated" not in f[case] or "Accelerometers" not in f[case]["Calibrated"]:
                continue
            g, cal = f[case], f[case]["Calibrated"]
            sensors[case] = {
                "label": labels[i] if i < len(labels) else "",
                "acc": cal["Accelerometers"],
                "gyr": cal.get("Gyroscopes"),
                "time": g.get("Time"),
                "rate": g.attrs.get("SampleRate"),
            }
        return version or 4, sensors
    raise InputError(f"{p}: no /Sensors group (APDM format 5) nor /CaseIdList (formats 3, 4): not an APDM .h5 file")


def choose_sensor(sensors: dict[str, dict], sensor, p: Path) -> str:
    present = ", ".join(f"{s['label'] or '(no label)'} ({sid})" for sid, s in sensors.items())
    if not sensors:
        raise InputError(f"{p}: no sensor with an accelerometer in the file")
    chosen = pick_sensor({sid: (s["label"], sid) for sid, s in sensors.items()}, sensor)
    if chosen is not None:
        return chosen
    if sensor is not None:
        raise InputError(f"{p}: no sensor {sensor!r} (sensor=, --sensor); the file has {present}")
    raise InputError(
        f"{p}: no lower-back sensor by label (Lumbar, Lower Back, Sacrum, ...); choose one with sensor= (--sensor): "
        f"the file has {present}"
    )


def _vectors(ds, what: str, n: int | None, p: Path) -> np.ndarray:
    a = np.asarray(ds[()], dtype=float)
    if a.ndim == 2 and a.shape[1] != 3 and a.shape[0] == 3:
        a = a.T  # stored 3 x N
    if a.ndim != 2 or a.shape[1] != 3 or (n is not None and a.shape[0] != n):
        raise InputError(f"{p}: {what} is {'x'.join(map(str, a.shape))}, expected N x 3 (N samples, x y z)")
    return a


def _apdm_unit(ds, table: dict, override, option: str, default: float, p: Path) -> float:
    if override is not None:
        units = ACC_UNITS if option == "acc_unit" else GYR_UNITS
        return unit_scale(override, units, option, p)
    said = _text(ds.attrs.get("Units", ds.attrs.get("Unit", ""))) if ds is not None else ""
    if not said:
        return default
    key = said.lower().replace(" ", "").replace("\u00b2", "^2")
    if key not in table:
        raise InputError(f"{p}: unit {said!r} of {ds.name} not understood; pass {option} ({option_flag(option)})")
    return table[key]


def read_apdm_h5(path, *, sensor=None, acc_unit=None, gyr_unit=None, rate_hz=None) -> ImuRecording:
    """An APDM (Opal, Mobility Lab, Motion Studio) HDF5 file: format 5 (``/Sensors/<id>/Accelerometer``,
    ``Gyroscope``, ``Time`` in microseconds, ``/Sensors/<id>/Configuration`` attributes ``Label 0`` and
    ``Sample Rate``) or formats 3 and 4 (``/<case id>/Calibrated/Accelerometers``, ``Gyroscopes``,
    ``/<case id>/Time``, the root's attributes ``CaseIdList`` and ``MonitorLabelList``, the case's
    ``SampleRate``). The sensor: the
    one labelled as the lower back (:data:`LOWER_BACK_LABELS`), the only one, or ``sensor`` (label or id).
    Units: the datasets' ``Units`` attribute, else APDM's m/s^2 and rad/s."""
    try:
        import h5py  # the apdm extra
    except ImportError:
        raise InputError(f"{path}: reading APDM .h5 files needs h5py: pip install 'yoyogait[apdm]'") from None
    p = Path(path)
    try:
        f = h5py.File(p, "r")
    except OSError as exc:
        raise InputError(f"{p}: not an HDF5 file ({str(exc).splitlines()[0]})") from None
    with f:
        version, sensors = _apdm_sensors(f, p)
        sid = choose_sensor(sensors, sensor, p)
        s = sensors[sid]
        name = s["label"] or sid
        if s["gyr"] is None:
            raise InputError(f"{p}: sensor {name!r} has no gyroscope data (Gyroscope / Calibrated/Gyroscopes)")
        acc = _vectors(s["acc"], f"sensor {name!r}: its accelerometer", None, p)
        gyr = _vectors(s["gyr"], f"sensor {name!r}: its gyroscope", acc.shape[0], p)
        acc = acc * _apdm_unit(s["acc"], APDM_ACC_UNITS, acc_unit, "acc_unit", 1.0, p)
        gyr_scale = _apdm_unit(s["gyr"], APDM_GYR_UNITS, gyr_unit, "gyr_unit", 1.0, p)
        gyr = gyr * gyr_scale
        try:
            rate = float(rate_hz) if rate_hz else (float(_text(s["rate"])) if s["rate"] is not None else None)
        except ValueError:
            rate = None
        if s["time"] is not None:
            stamps = np.asarray(s["time"][()], dtype=np.float64).reshape(-1)
            if stamps.shape[0] != acc.shape[0]:
                raise InputError(f"{p}: sensor {name!r}: {stamps.shape[0]} times for {acc.shape[0]} samples")
            time_s = (stamps - stamps[0]) * 1e-6  # microseconds since 1970
        elif rate:
            time_s = np.arange(acc.shape[0]) / rate
        else:
            raise InputError(
                f"{p}: sensor {name!r} has neither Time nor a sample rate; pass rate_hz (--capture-rate-hz)"
            )
    return reading(
        p, time_s, acc, gyr, rate, gyr_scale, {"layout": f"apdm v{version}", "sensor": name, "sensor_id": sid}
    )
