"""The Mobilise-D ``data.mat`` format: every trial's lower-back sensor with the reference systems' walking
bouts and the strides they measured (docs/imu.md, sections 4 and 6)."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import scipy.io

from ..errors import InputError
from .imu_checks import check_imu_plausible, finish_reading
from .imu_recording import GRAVITY_MPS2, ImuBout, ImuRecording

__all__ = ["read_mobilised_mat", "read_mobilised_trials"]


def read_mobilised_trials(path) -> list[ImuRecording]:
    """Every trial of a Mobilise-D ``data.mat`` (lower-back sensor ``SU.LowerBack``), with the
    reference systems' walking bouts (``Standards.<system>.MicroWB``) and the sensor height of the
    ``infoForAlgo.mat`` beside it."""
    p = Path(path)
    try:
        data = scipy.io.loadmat(p, simplify_cells=True)["data"]
    except Exception as exc:  # noqa: BLE001 (scipy's parser raises many kinds on a damaged file: TypeError, zlib.error, ...)
        raise InputError(f"{p}: not a Mobilise-D data.mat ({exc})") from None
    height = _mobilised_height(p.parent / "infoForAlgo.mat")
    out = []
    for tm, tests in data.items():
        if not isinstance(tests, dict):
            continue
        for test, trials in tests.items():
            if not isinstance(trials, dict):
                continue
            for trial, content in trials.items():
                try:
                    lb = content["SU"]["LowerBack"]
                except (KeyError, TypeError):
                    continue
                try:
                    rate, acc, gyr, refs = _mobilised_trial(lb, content)
                except (KeyError, TypeError, ValueError, IndexError, AttributeError) as exc:
                    where = f"{p}: trial {tm}/{test}/{trial}"
                    raise InputError(f"{where}: its lower-back data cannot be read ({exc})") from None
                rec = ImuRecording(
                    time_s=np.arange(acc.shape[0]) / rate,
                    acc_mps2=acc,
                    gyr_rad_s=gyr,
                    rate_hz=rate,
                    source=f"{p}:{tm}/{test}/{trial}",
                    sensor_height_m=height,
                    references=refs,
                    metadata={"layout": "mobilised", "test": test, "trial": trial, "participant": p.parent.name},
                )
                finish_reading(rec, np.pi / 180.0)
                check_imu_plausible(rec)
                out.append(rec)
    if not out:
        raise InputError(f"{p}: no lower-back sensor (SU.LowerBack) in any trial")
    return out


def _mobilised_trial(lb, content) -> tuple[float, np.ndarray, np.ndarray, dict[str, list[ImuBout]]]:
    """(rate, acc in m/s^2, gyr in rad/s, the reference systems' bouts) of one trial's ``SU.LowerBack``."""
    rate = float(lb["Fs"]["Acc"]) if isinstance(lb.get("Fs"), dict) else float(lb.get("Fs", 100.0))
    # The format stores the accelerometer in g (mobgap's loader scales it by 9.81 too).
    acc = np.asarray(lb["Acc"], dtype=float) * GRAVITY_MPS2
    gyr = np.asarray(lb["Gyr"], dtype=float) * np.pi / 180.0
    refs = {}
    for system, std in (content.get("Standards") or {}).items():
        bouts = _bouts(std.get("MicroWB"), std.get("Fs"))
        if bouts:
            refs[system] = bouts
    return rate, acc, gyr, refs


def read_mobilised_mat(path, *, trial=None) -> ImuRecording:
    """One trial of a Mobilise-D ``data.mat``: ``trial`` as ``Test5/Trial1`` (default: the first)."""
    trials = read_mobilised_trials(path)
    if trial is None:
        return trials[0]
    names = [f"{r.metadata['test']}/{r.metadata['trial']}" for r in trials]
    if trial not in names:
        raise InputError(f"{path}: no trial {trial!r}; the file has {', '.join(names)} (trial=, --trial)")
    return trials[names.index(trial)]


def _mobilised_height(info: Path) -> float | None:
    if not info.is_file():
        return None
    try:
        tm = scipy.io.loadmat(info, simplify_cells=True)["infoForAlgo"]
        value = float(next(iter(tm.values()))["SensorHeight"])
    except (KeyError, ValueError, TypeError, StopIteration, OSError):
        return None
    return value / 100.0 if value > 3.0 else value  # the format gives centimetres


def _bouts(micro, rate_hz=None) -> list[ImuBout]:
    if micro is None:
        return []
    items = [micro] if isinstance(micro, dict) else list(micro)
    out = []
    for b in items:
        try:
            stride = np.asarray(b.get("Stride_Duration", []), dtype=float).reshape(-1)
            ic = np.asarray(b.get("InitialContact_Event", []), dtype=float).reshape(-1)
            strides, known = _measured(b.get("Stride_InitialContacts"), stride, rate_hz)
            speeds = np.asarray(b.get("Stride_Speed", []), dtype=float).reshape(-1)
            speeds = speeds[known] if speeds.size == stride.size and strides.size else np.zeros(0)
            out.append(
                ImuBout(
                    start_s=float(b["Start"]),
                    end_s=float(b["End"]),
                    cadence_spm=float(b["Cadence"]),
                    speed_mps=float(b["WalkingSpeed"]),
                    stride_time_s=float(np.nanmean(stride)) if stride.size else float("nan"),
                    contact_times_s=ic,
                    strides_s=strides,
                    stride_speeds_mps=speeds,
                )
            )
        except (KeyError, TypeError, ValueError):
            continue
    return out


def _measured(contacts, duration_s: np.ndarray, rate_hz) -> tuple[np.ndarray, np.ndarray]:
    """The strides a Mobilise-D standard measured: its ``Stride_InitialContacts`` (N x 2) where its
    ``Stride_Duration`` is known (NaN marks a stride over a missed or doubled contact, left out of
    its ``Cadence``), in seconds, and which of its strides they are (a mask over the N). The
    standards store them in seconds or in samples at their ``Fs``; the scale is the one whose strides
    last their ``Stride_Duration``. Empty when neither does."""
    none = np.zeros((0, 2)), np.zeros(duration_s.size, dtype=bool)
    try:
        c = np.asarray(contacts, dtype=float)
    except (TypeError, ValueError):  # absent or not numbers: the strides from the contacts instead
        return none
    if c.size % 2 or c.size // 2 != duration_s.size:
        return none
    c = c.reshape(-1, 2)
    known = np.isfinite(duration_s) & np.all(np.isfinite(c), axis=1)
    if not known.any():
        return none
    scales = [1.0] + ([1.0 / float(rate_hz)] if rate_hz and float(rate_hz) > 0 else [])
    for scale in scales:
        if np.max(np.abs((c[known, 1] - c[known, 0]) * scale - duration_s[known])) < 1e-3:
            return c[known] * scale, known
    return none
