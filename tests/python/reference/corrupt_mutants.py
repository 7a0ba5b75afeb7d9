"""Corrupt copies of real recordings (motion capture and a lower-back IMU), and what ``yoyogait inspect`` and
``estimate`` make of them.

Shared by tests/python/io/test_corrupt_files.py (a few dozen mutants) and bench/corrupt.py (hundreds).
Mutant ``i`` is fully determined by ``(seed, i)``: its source file is ``SOURCES[i % len(SOURCES)]``
and its mutation is drawn from that format's operators with ``numpy.random.default_rng((seed, i))``.

Each mutant goes through ``yoyogait.cli.main`` in-process, as ``inspect --json FILE`` and as
``estimate FILE --out CSV [--figure PNG]``, and every run is classified:

* ``traceback``: an exception escaped ``main`` or "Traceback" appeared on stderr;
* ``bad message``: a failure whose stderr is not exactly one ``yoyogait: error:`` line naming the file;
* ``partial output``: a failed estimate that left its CSV, its figure or a temporary file, or a
  successful one that left a temporary file or lacks an output;
* ``absurd``: a success whose median speed is not below :data:`MAX_SPEED_MPS` or whose step frequency
  lies outside :data:`STEP_FREQUENCY_HZ` (or is NaN);
* ``ok``: a one-line error, or a plausible result.
"""

from __future__ import annotations

import contextlib
import io
import json
import re
import struct
import time
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

#: A plausible walking result: median speed below this [m/s] ...
MAX_SPEED_MPS = 3.0
#: ... and a step frequency in this band [Hz].
STEP_FREQUENCY_HZ = (0.5, 3.5)

#: Real recordings to corrupt (relative to the datasets folder); "velocities.csv" is written from the
#: first TRC's velocities by :func:`write_velocity_csv`.
SOURCES = (
    "c3d_org_samples/sample26_Qualisys_Walking_Hybrid_1_1.c3d",
    "opensim_models/Rajagopal_motion_capture_walk.trc",
    "bandai_namco_motion/dataset-1_walk_normal_001.bvh",
    "velocities.csv",
    "c3d_org_samples/MAC_Walk1.c3d",
    "addbiomechanics/Camargo2021_levelground_ccw_fast_01_01.trc",
    "c3d_org_samples/sample03_gait-raw.c3d",  # DEC floats, integer data
    "cmu_bvh11/131_01.bvh",
    "imu_mobgap/example_data/data_csv/HA/001/TimeMeasure1_Test5_Trial1.csv",  # a lower-back IMU: the mobgap CSV
    "imu_mobgap/example_data/data/lab/HA/002/data.mat",  # ... and a Mobilise-D data.mat
)


def source_format(source: str) -> str:
    """The mutation operators' format of a source: its extension, "imucsv" for an IMU CSV."""
    return "imucsv" if source.startswith("imu_mobgap/") and source.endswith(".csv") else source.rsplit(".", 1)[1]


def is_imu(source: str) -> bool:
    """Whether a source is an IMU recording (inspect and estimate report per sample, as docs/imu.md)."""
    return source.startswith("imu_mobgap/")


CATEGORIES = ("ok", "traceback", "bad message", "partial output", "absurd")


@dataclass
class Mutant:
    index: int
    source: str
    operator: str
    detail: str
    path: Path


@dataclass
class Outcome:
    mutant: Mutant
    command: str
    category: str
    code: int | None
    message: str
    seconds: float


@dataclass
class Tally:
    outcomes: list = field(default_factory=list)

    def count(self, category: str) -> int:
        return sum(o.category == category for o in self.outcomes)

    def bad(self) -> list:
        return [o for o in self.outcomes if o.category != "ok"]


def write_velocity_csv(datasets_dir: Path, path: Path) -> Path:
    """A velocity CSV (time_s, vx, vz at 100 Hz) of a real walk: the Rajagopal TRC's pelvis velocities."""
    import yoyogait

    rec = yoyogait.read(Path(datasets_dir) / "opensim_models/Rajagopal_motion_capture_walk.trc")
    vel = yoyogait.gait_velocities(rec, rate_hz=100.0)
    ok = np.isfinite(vel.vx) & np.isfinite(vel.vz)
    rows = "".join(f"{t:.2f},{x:.4f},{z:.4f}\n" for t, x, z in zip(vel.time_s[ok], vel.vx[ok], vel.vz[ok]))
    path.write_text("time_s,vx,vz\n" + rows)
    return path


def source_bytes(datasets_dir: Path, source: str, workdir: Path) -> bytes:
    if source == "velocities.csv":
        target = workdir / "velocities.csv"
        if not target.exists():
            write_velocity_csv(datasets_dir, target)
        return target.read_bytes()
    return (Path(datasets_dir) / source).read_bytes()


# ---- mutation operators: (data, rng) -> (new data, detail) ------------------------------------------

BOGUS_NUMBERS = ("1e308", "-1e308", "nan", "inf", "1e10", "1e5", "-1", "0", "1e-30", "")


def _truncate(data: bytes, rng) -> tuple[bytes, str]:
    cut = int(rng.integers(1, len(data)))
    return data[:cut], f"truncated at byte {cut} of {len(data)}"


def _flip_bytes(data: bytes, rng) -> tuple[bytes, str]:
    b = bytearray(data)
    n = int(rng.integers(1, 9))
    at = rng.integers(0, len(b), n)
    for i in at:
        b[i] ^= int(rng.integers(1, 256))
    return bytes(b), f"{n} bytes flipped at {sorted(at.tolist())[:4]}..."


def _zero_block(data: bytes, rng) -> tuple[bytes, str]:
    b = bytearray(data)
    size = int(rng.choice([16, 64, 512, 4096]))
    at = int(rng.integers(0, max(1, len(b) - size)))
    b[at : at + size] = bytes(min(size, len(b) - at))
    return bytes(b), f"{size} bytes zeroed at {at}"


def _c3d_header_number(data: bytes, rng) -> tuple[bytes, str]:
    b = bytearray(data)
    proc = b[512 * (b[0] - 1) + 3] if b[0] >= 1 and len(b) > 512 * b[0] else 84
    order = ">" if proc == 86 else "<"
    word = str(rng.choice(["points", "first_frame", "last_frame", "scale", "data_start", "rate", "analog"]))
    offsets = {"points": 2, "analog": 4, "first_frame": 6, "last_frame": 8, "data_start": 16}
    if word in offsets:
        value = int(rng.choice([0, 1, 2, 0xFFFF, 0x7FFF, int(rng.integers(0, 0x10000))]))
        b[offsets[word] : offsets[word] + 2] = struct.pack(order + "H", value)
    else:  # the point scale (bytes 12-15) or the frame rate (20-23), as IEEE floats in the file's byte order
        value = float(rng.choice([0.0, -0.0, np.nan, np.inf, -np.inf, 1e30, -1e-30, 1e9]))
        at = 12 if word == "scale" else 20
        b[at : at + 4] = struct.pack(order + "f", value)
    return bytes(b), f"header {word} = {value}"


def _c3d_data_float(data: bytes, rng) -> tuple[bytes, str]:
    """Bogus numbers in the data section: 4-byte floats (or 2-byte integers) at random places."""
    b = bytearray(data)
    start = (struct.unpack("<H", b[16:18])[0] - 1) * 512
    start = min(max(start, 512), len(b) - 8)
    n = int(rng.integers(1, 20))
    value = float(rng.choice([1e30, -1e30, np.nan, np.inf, 3e38, 1e6]))
    for at in rng.integers(start, len(b) - 4, n):
        at -= (at - start) % 4
        b[at : at + 4] = struct.pack("<f", value)
    return bytes(b), f"{n} data floats set to {value}"


def _pelvis_columns(names: list[str]) -> list[int]:
    """Indices of the pelvis points among ``names`` (as yoyogait finds them), else the first three."""
    from yoyogait.errors import InputError
    from yoyogait.pipeline.points import find_pelvis

    try:
        chosen = find_pelvis(names).names
    except InputError:
        return list(range(min(3, len(names))))
    return [names.index(n) for n in chosen if n in names]


def _c3d_pelvis_cells(data: bytes, rng) -> tuple[bytes, str]:
    """Bogus values in the pelvis markers' cells over a stretch of frames (where they matter most)."""
    import tempfile

    import ezc3d

    with tempfile.NamedTemporaryFile(suffix=".c3d") as f:
        f.write(data)
        f.flush()
        c = ezc3d.c3d(f.name)
    labels = [s.strip() for s in c["parameters"]["POINT"]["LABELS"]["value"]]
    b = bytearray(data)
    proc = b[512 * (b[0] - 1) + 3]
    order = ">" if proc == 86 else "<"
    words = struct.unpack(order + "12H", bytes(b[:24]))
    n_points, n_analog, first, last, data_block = words[1], words[2], words[3], words[4], words[8]
    is_float = c["parameters"]["POINT"]["SCALE"]["value"][0] < 0
    size = 4 if is_float else 2
    frame_values = 4 * n_points + n_analog
    n_frames = last - first + 1
    point = int(rng.choice(_pelvis_columns(labels[:n_points])))
    f0 = int(rng.integers(0, n_frames))
    count = int(rng.choice([1, 3, 10, 50]))
    axes = [int(rng.integers(0, 3))] if rng.random() < 0.5 else [0, 1, 2]
    if is_float:
        value = float(rng.choice([3e38, -3e38, np.inf, np.nan, 1e6, 1e4, 0.0]))
        packed = struct.pack(order + "f", value)
    else:
        value = int(rng.choice([32767, -32768, 0]))
        packed = struct.pack(order + "h", value)
    start = (data_block - 1) * 512
    for frame in range(f0, min(n_frames, f0 + count)):
        for a in axes:
            at = start + (frame * frame_values + 4 * point + a) * size
            b[at : at + size] = packed
    return bytes(b), f"point {labels[point]!r} axes {axes} = {value} on frames {f0}-{f0 + count - 1}"


def _text_pelvis_cells(fmt):
    """TRC: bogus values in a pelvis marker's cells; BVH: in the root's channels; over a stretch of lines."""

    def op(data: bytes, rng) -> tuple[bytes, str]:
        lines = _lines(data)
        lo, hi = _data_line_range(lines, fmt)
        sep = _cell_separator(fmt)
        if fmt == "trc":
            names = [c.strip() for c in lines[3].split("\t")[2:] if c.strip()]
            marker = int(rng.choice(_pelvis_columns(names)))
            columns = [2 + 3 * marker + a for a in range(3)]
        else:
            columns = list(range(6))  # the root's position and rotation channels
        chosen = [int(rng.choice(columns))] if rng.random() < 0.5 else columns[:3]
        value = str(rng.choice(["1e308", "-1e308", "1e30", "1e6", "1e4", "nan", "inf", "0", ""]))
        k0 = int(rng.integers(lo, max(lo + 1, hi - 1)))
        count = int(rng.choice([1, 3, 10, 50]))
        for k in range(k0, min(hi, k0 + count)):
            cells = lines[k].split(sep)
            if len(cells) <= max(chosen):
                continue
            for c in chosen:
                cells[c] = value
            lines[k] = sep.join(cells)
        return _join(lines), f"columns {chosen} = {value!r} on lines {k0 + 1}-{k0 + count}"

    return op


def _lines(data: bytes) -> list[str]:
    return data.decode("utf-8", errors="replace").split("\n")


def _join(lines: list[str]) -> bytes:
    return "\n".join(lines).encode()


def _imu_header(data: bytes, rng) -> tuple[bytes, str]:
    """An IMU CSV's header row: a column dropped or renamed, a unit that is not the data's, or none."""
    lines = _lines(data)
    choice = str(
        rng.choice(
            [
                "samples,acc_x,acc_y,acc_z,gyr_x,gyr_y",
                "samples,acc_x_mps2,acc_y_mps2,acc_z_mps2,gyr_x,gyr_y,gyr_z",
                "samples,acc_x,acc_y,acc_z,gyr_x_rad_s,gyr_y_rad_s,gyr_z_rad_s",
                "time_s,acc_x_g,acc_y_g,acc_z_g,gyr_x_deg_s,gyr_y_deg_s,gyr_z_deg_s",
                "samples,acc_x,acc_y,acc_z,acc_x,gyr_y,gyr_z",
                "samples;acc_x;acc_y;acc_z;gyr_x;gyr_y;gyr_z",
                "",
                "#",
            ]
        )
    )
    lines[0] = choice
    return _join(lines), f"IMU CSV header {choice!r}"


def _data_line_range(lines: list[str], fmt: str) -> tuple[int, int]:
    if fmt == "trc":
        return 5, len(lines)
    if fmt == "bvh":
        at = next((i for i, s in enumerate(lines) if s.strip().upper().startswith("FRAME TIME")), 0)
        return at + 1, len(lines)
    return 1, len(lines)  # csv


def _cell_separator(fmt: str) -> str:
    return {"trc": "\t", "bvh": " ", "csv": ",", "imucsv": ","}[fmt]


def _bogus_cells(fmt):
    def op(data: bytes, rng) -> tuple[bytes, str]:
        lines = _lines(data)
        lo, hi = _data_line_range(lines, fmt)
        sep = _cell_separator(fmt)
        n = int(rng.integers(1, 12))
        value = str(rng.choice(BOGUS_NUMBERS))
        changed = []
        first = int(rng.integers(lo, max(lo + 1, hi - n)))
        column = None
        for k in range(first, min(hi, first + n)):
            cells = lines[k].split(sep)
            if len(cells) < 2:
                continue
            if column is None:  # the same column on consecutive lines: a bad stretch of one point
                column = int(rng.integers(1 if fmt != "bvh" else 0, len(cells)))
            cells[min(column, len(cells) - 1)] = value
            lines[k] = sep.join(cells)
            changed.append(k + 1)
        return _join(lines), f"column {column} = {value!r} on lines {changed[:3]}..."

    return op


def _bogus_time(fmt):
    def op(data: bytes, rng) -> tuple[bytes, str]:
        lines = _lines(data)
        lo, hi = _data_line_range(lines, fmt)
        sep = _cell_separator(fmt)
        col = 1 if fmt == "trc" else 0
        k = int(rng.integers(lo, max(lo + 1, hi - 1)))
        kind = str(rng.choice(["1e5", "1e10", "1e6", "repeat", "back", "-5", "nan", "swap", "last"]))
        if kind == "last":
            k = max(i for i in range(lo, hi) if lines[i].strip())
            kind = str(rng.choice(["1e5", "1e10"]))
        cells = lines[k].split(sep)
        if len(cells) <= col:
            return _join(lines), "no time cell"
        if kind == "repeat" and k > lo:
            cells[col] = lines[k - 1].split(sep)[col]
        elif kind == "back":
            cells[col] = str(float(cells[col] or 0) - 1.0) if _is_number(cells[col]) else "-1"
        elif kind == "swap" and k + 1 < hi:
            lines[k], lines[k + 1] = lines[k + 1], lines[k]
            return _join(lines), f"lines {k + 1} and {k + 2} swapped"
        else:
            cells[col] = kind
        lines[k] = sep.join(cells)
        return _join(lines), f"time on line {k + 1} = {cells[col]!r} ({kind})"

    return op


def _is_number(text: str) -> bool:
    try:
        float(text)
    except ValueError:
        return False
    return True


def _text_header(fmt):
    def op(data: bytes, rng) -> tuple[bytes, str]:
        lines = _lines(data)
        if fmt == "trc":
            cells = lines[2].split("\t")
            k = int(rng.integers(0, len(cells)))
            cells[k] = str(rng.choice(["0", "-100", "nan", "1e30", "1e9", "furlong", "", "3"]))
            lines[2] = "\t".join(cells)
            return _join(lines), f"TRC header field {k} = {cells[k]!r}"
        if fmt == "bvh":
            at = next(i for i, s in enumerate(lines) if s.strip().upper().startswith("FRAME TIME"))
            if rng.random() < 0.6:
                value = str(rng.choice(["0", "-0.01", "1e-30", "nan", "inf", "1e30", "1e-5", "100", "abc"]))
                lines[at] = f"Frame Time: {value}"
            else:
                value = str(rng.choice(["0", "-5", "99999999", "1", "abc"]))
                lines[at - 1] = f"Frames: {value}"
            return _join(lines), f"BVH header {lines[at - 1] if 'Frames' in lines[at - 1] else ''} {lines[at]}"
        # csv: the header row
        choice = str(rng.choice(["time_s,vx", "time_s,vx,vz,vx", "t,vx,vz", "vx,vz", "time_s;vx;vz", "", "#"]))
        lines[0] = choice
        return _join(lines), f"CSV header {choice!r}"

    return op


def _delete_or_repeat_lines(fmt):
    def op(data: bytes, rng) -> tuple[bytes, str]:
        lines = _lines(data)
        lo, hi = _data_line_range(lines, fmt)
        n = int(rng.choice([1, 5, 50, 500]))
        k = int(rng.integers(lo, max(lo + 1, hi - 1)))
        if rng.random() < 0.5:
            del lines[k : k + n]
            return _join(lines), f"{n} lines deleted at {k + 1}"
        lines[k:k] = lines[k : k + n]
        return _join(lines), f"{n} lines repeated at {k + 1}"

    return op


OPERATORS = {
    "c3d": {
        "truncate": _truncate,
        "flip bytes": _flip_bytes,
        "zero block": _zero_block,
        "header number": _c3d_header_number,
        "bogus data": _c3d_data_float,
        "pelvis cells": _c3d_pelvis_cells,
    },
    **{
        fmt: {
            "truncate": _truncate,
            "flip bytes": _flip_bytes,
            "zero block": _zero_block,
            "header number": _text_header(fmt),
            "bogus time": _bogus_time(fmt) if fmt != "bvh" else _bogus_cells(fmt),
            "bogus cells": _bogus_cells(fmt),
            "lines": _delete_or_repeat_lines(fmt),
            **({"pelvis cells": _text_pelvis_cells(fmt)} if fmt != "csv" else {}),
        }
        for fmt in ("trc", "bvh", "csv")
    },
    "imucsv": {
        "truncate": _truncate,
        "flip bytes": _flip_bytes,
        "zero block": _zero_block,
        "header": _imu_header,
        "bogus time": _bogus_time("imucsv"),
        "bogus cells": _bogus_cells("imucsv"),
        "lines": _delete_or_repeat_lines("imucsv"),
    },
    "mat": {"truncate": _truncate, "flip bytes": _flip_bytes, "zero block": _zero_block},
}


def make_mutant(datasets_dir: Path, workdir: Path, seed: int, index: int) -> Mutant:
    """Mutant ``index`` of ``seed``: a corrupt copy of one source, written into ``workdir``."""
    source = SOURCES[index % len(SOURCES)]
    fmt = source_format(source)
    rng = np.random.default_rng((seed, index))
    names = sorted(OPERATORS[fmt])
    operator = names[(index // len(SOURCES)) % len(names)]
    data, detail = OPERATORS[fmt][operator](source_bytes(datasets_dir, source, workdir), rng)
    path = workdir / f"m{index:04d}_{Path(source).name}"
    path.write_bytes(data)
    return Mutant(index, source, operator, detail, path)


# ---- running and classifying ----------------------------------------------------------------------


def _call(argv: list[str]) -> tuple[int | None, str, str, BaseException | None]:
    from yoyogait.cli import main

    out, err = io.StringIO(), io.StringIO()
    with contextlib.redirect_stdout(out), contextlib.redirect_stderr(err):
        try:
            code = main(argv)
            exc = None
        except SystemExit as e:  # click may exit for usage errors
            code, exc = (e.code if isinstance(e.code, int) else 1), None
        except Exception as e:  # noqa: BLE001 (an escaping exception is what is counted)
            code, exc = None, e
    return code, out.getvalue(), err.getvalue(), exc


def _error_problem(err: str, mutant: Mutant) -> str | None:
    lines = err.strip().splitlines()
    if "Traceback" in err:
        return "traceback"
    if len(lines) != 1 or not lines[0].startswith("yoyogait: error: "):
        return "bad message"
    if mutant.path.name not in lines[0]:
        return "bad message"
    return None


def _plausible(speed_mps: float | None, step_hz: float | None) -> bool:
    lo, hi = STEP_FREQUENCY_HZ
    speed_ok = speed_mps is not None and np.isfinite(speed_mps) and 0 <= speed_mps < MAX_SPEED_MPS
    step_ok = step_hz is None or (np.isfinite(step_hz) and lo <= step_hz <= hi)
    return bool(speed_ok and step_ok)


def run_inspect(mutant: Mutant) -> Outcome:
    t0 = time.perf_counter()
    code, out, err, exc = _call(["inspect", "--json", str(mutant.path)])
    dt = time.perf_counter() - t0
    if exc is not None:
        return Outcome(mutant, "inspect", "traceback", None, f"{type(exc).__name__}: {exc}", dt)
    if code != 0:
        problem = _error_problem(err, mutant)
        return Outcome(mutant, "inspect", problem or "ok", code, err.strip(), dt)
    report = json.loads(out)
    if is_imu(mutant.source):  # the medians while valid (None when never valid)
        cadence = report.get("median_cadence_spm")
        speed, step = report.get("median_speed_mps"), (cadence / 60.0 if cadence is not None else None)
    else:
        speed, step = report.get("mean_speed_mps"), report.get("step_frequency_hz")
    if speed is None:  # no walking found: then the whole-recording speed must still be sane; none is shown
        return Outcome(mutant, "inspect", "ok", 0, "no walking found", dt)
    category = "ok" if _plausible(speed, step) else "absurd"
    return Outcome(mutant, "inspect", category, 0, f"speed {speed} m/s, step frequency {step} Hz", dt)


_SUMMARY = re.compile(r"median step frequency (\S+) Hz, median speed (\S+) m/s")


def run_estimate(mutant: Mutant, outdir: Path, figure: bool) -> Outcome:
    outdir.mkdir(parents=True, exist_ok=True)
    csv = outdir / f"{mutant.path.stem}.estimate.csv"
    png = outdir / f"{mutant.path.stem}.estimate.png"
    before = set(outdir.iterdir())
    argv = ["estimate", str(mutant.path), "--out", str(csv), "--figure", str(png) if figure else "none"]
    t0 = time.perf_counter()
    code, out, err, exc = _call(argv)
    dt = time.perf_counter() - t0
    new = set(outdir.iterdir()) - before
    temps = [p for p in new if p not in (csv, png)]
    if exc is not None:
        return Outcome(mutant, "estimate", "traceback", None, f"{type(exc).__name__}: {exc}", dt)
    if code != 0:
        problem = "partial output" if new else _error_problem(err, mutant)
        return Outcome(mutant, "estimate", problem or "ok", code, err.strip() + f" [left: {sorted(map(str, new))}]", dt)
    expected = {csv, png} if figure else {csv}
    if temps or new != expected:
        return Outcome(mutant, "estimate", "partial output", 0, f"outputs {sorted(map(str, new))}", dt)
    if is_imu(mutant.source):  # one row per sample: what is valid must be plausible
        step, speed = _imu_valid_medians(csv)
        category = "ok" if speed is None or _plausible(speed, step) else "absurd"
    else:
        m = _SUMMARY.search(out)
        step, speed = (float(m[1]), float(m[2])) if m else (None, None)
        category = "ok" if m and _plausible(speed, step) else "absurd"
    for p in new:
        p.unlink()
    return Outcome(mutant, "estimate", category, 0, f"speed {speed} m/s, step frequency {step} Hz", dt)


def _imu_valid_medians(csv: Path) -> tuple[float | None, float | None]:
    """(step frequency, speed): the medians over an IMU estimate's valid rows; (None, None) when none is valid."""
    import pandas as pd

    rows = pd.read_csv(csv)
    valid = rows["valid"].to_numpy() == 1
    if not valid.any():
        return None, None
    return float(np.median(rows["step_frequency_hz"][valid])), float(np.median(rows["speed_mps"][valid]))


def run_mutants(
    datasets_dir: Path, workdir: Path, n: int, seed: int = 0, figure_every: int = 4, start: int = 0
) -> Tally:
    """Make mutants ``start .. start + n - 1`` and run each through inspect and estimate.

    Every ``figure_every``-th estimate also draws its figure (the figure is the slow part).
    """
    import warnings

    tally = Tally()
    workdir.mkdir(parents=True, exist_ok=True)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")  # pytest's own warning capture would otherwise see each mutant's
        for i in range(start, start + n):
            mutant = make_mutant(datasets_dir, workdir, seed, i)
            tally.outcomes.append(run_inspect(mutant))
            tally.outcomes.append(
                run_estimate(mutant, workdir / "out", figure=figure_every > 0 and i % figure_every == 0)
            )
            mutant.path.unlink()
    return tally
