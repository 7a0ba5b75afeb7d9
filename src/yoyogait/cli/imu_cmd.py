"""The IMU side of ``inspect``, ``estimate`` and ``evaluate``: one lower-back IMU file or data set."""

from __future__ import annotations

import csv
import dataclasses
import json
import math
import tempfile
from pathlib import Path

import click
import numpy as np

from .._files import atomic_files, check_output_folder, check_outputs, install_folder
from ..errors import InputError, about_file
from ..estimators.config import ImuConfig
from ..estimators.imu import ImuReason, csv_formats, estimator_for
from ..evaluation import imu as ev
from ..evaluation.parallel import TaskFailure, run_tasks
from ..io.imu_read import is_imu_file, read_imu
from .options import MARKER_OPTIONS, refuse_options

__all__ = [
    "IMU_OPTIONS",
    "refuse_other_kind",
    "imu_options",
    "is_imu_file",
    "inspect_imu",
    "estimate_imu",
    "evaluate_imu",
    "is_imu_dataset",
]

#: The parameters of :func:`imu_options`: for an IMU file only (a marker file refuses them).
IMU_OPTIONS = ("acc_unit", "gyr_unit", "sensor_height_m", "trial", "sensor")


def refuse_other_kind(ctx: click.Context, file, imu: bool) -> None:
    """InputError naming the options given for ``file`` that only the other kind of file takes (``imu``:
    the file is an IMU's): the marker options for an IMU file, the IMU options for a marker file."""
    if imu:
        refuse_options(ctx, file, MARKER_OPTIONS, "motion-capture files")
    else:
        refuse_options(ctx, file, IMU_OPTIONS, "IMU files")


def imu_options(f):
    """--acc-unit, --gyr-unit, --sensor-height-m, --trial and --sensor (IMU files only)."""
    f = click.option("--sensor", default=None, metavar="LABEL",
                     help="APDM .h5, Motion-BIDS .tsv, an IMU CSV whose columns name sensors: the sensor, by label or "
                          "id (default: the one labelled Lumbar, Lower Back, Sacrum, Pelvis, ...).")(f)  # fmt: skip
    f = click.option("--trial", default=None, metavar="TEST/TRIAL",
                     help="Mobilise-D data.mat: the trial, e.g. Test11/Trial1 (default: the first).")(f)  # fmt: skip
    f = click.option("--sensor-height-m", type=float, default=None,
                     help="IMU files: the sensor's height standing (the inverted pendulum's length).")(f)  # fmt: skip
    f = click.option("--gyr-unit", type=click.Choice(["rad_s", "deg_s"]), default=None,
                     help="IMU files: unit of the angular rate columns when the file does not say.")(f)  # fmt: skip
    f = click.option("--acc-unit", type=click.Choice(["mps2", "g"]), default=None,
                     help="IMU files: unit of the acceleration columns when the file does not say.")(f)  # fmt: skip
    return f


def _read(file, acc_unit, gyr_unit, rate_hz, sensor_height_m, trial=None, sensor=None):
    with about_file(file):
        return read_imu(
            file,
            acc_unit=acc_unit,
            gyr_unit=gyr_unit,
            rate_hz=rate_hz,
            sensor_height_m=sensor_height_m,
            trial=trial,
            sensor=sensor,
        )


def _estimator(rec, config=None):
    """The estimator for a recording; a sensor range the file shows clipped (a plateau at an axis's extreme)
    becomes the saturation level, so that those samples are not used (reason SATURATED)."""
    cfg = ImuConfig() if config is None else config
    clipped = rec.metadata.get("clipped", {})
    if "acc" in clipped:
        cfg = dataclasses.replace(cfg, acc_saturation_mps2=min(cfg.acc_saturation_mps2, clipped["acc"][0]))
    if "gyr" in clipped:
        cfg = dataclasses.replace(cfg, gyr_saturation_rad_s=min(cfg.gyr_saturation_rad_s, clipped["gyr"][0]))
    return estimator_for(rec, cfg)


def _clipped_lines(rec) -> list[str]:
    units = {"acc": ("the accelerometer", "m/s^2"), "gyr": ("the gyro", "rad/s")}
    return [
        f"{units[k][0]} clipped at {level:.4g} {units[k][1]} ({n} samples): its range; those samples and "
        "the next second are not valid (SATURATED)"
        for k, (level, n) in rec.metadata.get("clipped", {}).items()
    ]


def _sensor_name(metadata: dict) -> str:
    """The sensor read, with its id where the file gives one beside its label (APDM)."""
    name, sid = str(metadata["sensor"]), metadata.get("sensor_id")
    return name if sid is None or str(sid) == name else f"{name} ({sid})"


def _never_valid_why(why: dict[str, float]) -> str:
    """What a recording never valid most likely is, from the shares of its reasons."""
    if why.get("GRAVITY", 0.0) >= 0.25:  # the median norm passed the readers' check: the low-passed one strays
        return "the acceleration's low-passed norm strays from 9.81 m/s^2 while it moves: a sensor on a foot or a limb?"
    if why and max(why, key=lambda k: why[k]) == "ACQUIRING":
        return "walking too short or too irregular to lock on"
    return "a sensor at rest, a walk too short"


def inspect_imu(
    file, *, acc_unit=None, gyr_unit=None, rate_hz=None, sensor_height_m=None, trial=None, sensor=None, as_json=False
) -> None:
    """Print an IMU recording's rate, duration, units, gravity, and what the online estimator finds."""
    rec = _read(file, acc_unit, gyr_unit, rate_hz, sensor_height_m, trial, sensor)
    res = _estimator(rec).run_recording(rec)
    valid = res["valid"].astype(bool)
    dt = np.diff(rec.time_s)
    nominal_s = 1.0 / rec.rate_hz if rec.rate_hz else float(np.median(dt))
    gaps = dt[dt > 1.5 * nominal_s]
    max_gap_s = ImuConfig().max_gap_s  # the estimator's (inspect runs the defaults)
    restarts = int(np.count_nonzero(gaps > max_gap_s))
    reasons = np.asarray(res["reason"])[~valid]
    why = {ImuReason(int(r)).name: float(np.count_nonzero(reasons == r)) / len(res) for r in np.unique(reasons)}
    g = float(np.nanmedian(np.linalg.norm(rec.acc_mps2, axis=1)))
    report = {
        "file": str(file),
        "format": f"IMU ({rec.metadata.get('layout', '?')})",
        "synthetic": rec.synthetic,
        "rate_hz": rec.rate_hz,
        "time_unit": rec.metadata.get("time_unit"),
        "samples": rec.n_samples,
        "duration_s": rec.duration_s,
        "gravity_mps2": g,
        "max_abs_acc_mps2": float(np.nanmax(np.abs(rec.acc_mps2))),
        "max_abs_gyr_rad_s": float(np.nanmax(np.abs(rec.gyr_rad_s))),
        "sensor_height_m": rec.sensor_height_m,
        "valid_s": float(np.count_nonzero(valid) * nominal_s),
        "median_cadence_spm": float(np.median(res.cadence_spm[valid])) if valid.any() else None,
        "median_speed_mps": float(np.median(res["speed_mps"][valid])) if valid.any() else None,
        "references": {k: len(v) for k, v in rec.references.items()},
        "not_valid": why,
        "zero_rows": int(rec.metadata.get("zero_rows", 0)),
        "repeated_packets": int(rec.metadata.get("repeated_packets", 0)),
        "gaps": int(gaps.size),
        "gap_restarts": restarts,
        "longest_gap_s": float(gaps.max()) if gaps.size else 0.0,
        "clipped": {k: {"range": level, "samples": n} for k, (level, n) in rec.metadata.get("clipped", {}).items()},
    }
    if as_json:
        click.echo(json.dumps(report, indent=1, default=float))
        return
    height = f"{rec.sensor_height_m:.3f} m" if rec.sensor_height_m else "not given (default 0.95 m; --sensor-height-m)"
    lines = [
        ("file", f"{file} ({report['format']})" + (" SYNTHETIC" if rec.synthetic else "")),
        *([("sensor", _sensor_name(rec.metadata))] if "sensor" in rec.metadata else []),
        (
            "rate",
            (f"{rec.rate_hz:g} Hz, {rec.n_samples} samples, {rec.duration_s:.2f} s" if rec.rate_hz else "irregular")
            + (f" ({rec.metadata['time_unit']}, by its intervals)" if "time_unit" in rec.metadata else ""),
        ),
        ("gravity", f"{g:.2f} m/s^2 (median norm of the acceleration)"),
        ("range", f"|acc| <= {report['max_abs_acc_mps2']:.1f} m/s^2, |gyr| <= {report['max_abs_gyr_rad_s']:.2f} rad/s"),
        ("sensor height", height),
        ("valid", f"{report['valid_s']:.2f} s of valid online estimates (walking)"),
    ]
    if not valid.any():
        lines.append(("walking", "none found: the estimate never became valid (" + _never_valid_why(why) + ")"))
    if why:
        shown = ", ".join(
            f"{k} {100 * v:.0f} %" if v >= 0.01 else f"{k} {100 * v:.1g} %"
            for k, v in sorted(why.items(), key=lambda kv: -kv[1])
        )
        lines.append(("not valid", f"{shown} of the samples"))
    if rec.metadata.get("zero_rows"):
        lines.append(
            ("zero rows", f"{rec.metadata['zero_rows']} (all six channels exactly 0: no measurement, ignored)")
        )
    if rec.metadata.get("repeated_packets"):
        n = rec.metadata["repeated_packets"]
        lines.append(("repeated", f"{n} packet{'s' if n > 1 else ''} received twice (the later copy dropped)"))
    if gaps.size:
        what = (
            f"{gaps.size - restarts} up to {max_gap_s:g} s bridged (by the model while walking), "
            f"{restarts} longer: the front-end restarts after each (GAP)"
        )
        lines.append(("gaps", f"{gaps.size} (longest {gaps.max():.2f} s): {what}"))
    for line in _clipped_lines(rec):
        lines.append(("saturated", line))
    if report["median_cadence_spm"] is not None:
        lines.append(("cadence", f"{report['median_cadence_spm']:.1f} steps/min (median while valid)"))
        lines.append(("speed", f"{report['median_speed_mps']:.2f} m/s (median while valid, inverted pendulum)"))
    if rec.references:
        lines.append(("references", ", ".join(f"{k} ({n} walking bouts)" for k, n in report["references"].items())))
    width = max(len(k) for k, _ in lines)
    for k, v in lines:
        click.echo(f"{k:<{width}}  {v}")


def estimate_imu(file, *, out=None, figure=None, force=False, config_file=None, acc_unit=None, gyr_unit=None,
                 rate_hz=None, sensor_height_m=None, trial=None, sensor=None) -> None:  # fmt: skip
    """The online IMU estimate of FILE as CSV, one row per sample (every field of ImuEstimate), and with
    ``figure`` (a path; None or 'none': no figure) cadence and speed over time against the file's reference
    bouts where it has them."""
    config = ImuConfig.from_file(config_file) if config_file is not None else None
    target = Path(out or f"{Path(file).name}.imu.csv")
    fig = None if figure in (None, "none") else Path(figure)
    check_outputs((("--out", target), ("--figure", fig)), force, inputs=(file, config_file))
    rec = _read(file, acc_unit, gyr_unit, rate_hz, sensor_height_m, trial, sensor)
    res = _estimator(rec, config).run_recording(rec)
    names = res.column_names()

    def write(p):
        with open(p, "w", newline="", encoding="utf-8") as f:
            if rec.synthetic:
                f.write("# SYNTHETIC data (yoyogait.synthetic_imu)\n")
            w = csv.writer(f)
            w.writerow(names)
            cols = [res[n] for n in names]
            formats = csv_formats(names)
            for i in range(len(res)):
                w.writerow([fmt % c[i] for fmt, c in zip(formats, cols)])

    writers = {target: write}
    if fig is not None:
        writers[fig] = lambda p: ev.imu_figure(rec, res, p)
    # Both or neither: the figure is drawn before the CSV is renamed into place.
    atomic_files(writers)
    valid = res["valid"].astype(bool)
    wrote = f"{target} and {fig}" if fig else f"{target}"
    click.echo(f"wrote {wrote}: {len(res)} samples, {valid.mean() * 100:.0f} % valid")
    for line in _clipped_lines(rec):
        click.echo(f"{file}: {line}", err=True)


def is_imu_dataset(dataset) -> bool:
    """A folder with Mobilise-D data.mat files below it."""
    p = Path(dataset)
    return p.is_dir() and next(p.rglob("data.mat"), None) is not None


MOBGAP_ABSENT = "mobgap is not installed (pip install 'yoyogait[mobgap]'): its column is left out"


def evaluate_imu_recording(rec, config, peer: bool, figure_path):
    """One recording of an IMU evaluation (a top-level function: it runs in worker processes): its bout
    rows, and what became of the peer: None (it ran or was not asked for), MOBGAP_ABSENT, or the line
    saying how it failed (the peer's own failure is reported, not ours)."""
    peer_bouts, peer_note = None, None
    if peer:
        try:
            peer_bouts = ev.run_mobgap(rec)
        except ImportError:
            peer_note = MOBGAP_ABSENT
        except Exception as exc:
            peer_note = f"mobgap failed on {rec.source}: {type(exc).__name__}: {str(exc).splitlines()[0][:200]}"
    rows, res = ev.evaluate_recording(rec, config, peer_bouts)
    if figure_path is not None:
        ev.imu_figure(rec, res, figure_path, peer_bouts)
    return rows, peer_note


def evaluate_imu(dataset, out, *, force=False, figures=True, config_file=None, peer=True, jobs: int = 1) -> dict:
    """Per reference walking bout: cadence, speed and stride-time errors of the IMU estimators
    (yoyogait online, the oscillator, mobgap when installed); bouts.csv, summary.md, a figure per recording.
    The recordings run on ``jobs`` processes (the same report whatever their number), with a progress
    bar; one that fails is listed in the report and in ``failures``, the others are still reported."""
    out = Path(out)
    check_output_folder(out, force)
    config = ImuConfig.from_file(config_file) if config_file is not None else None
    recs = ev.imu_recordings(dataset)
    where = f"{jobs} process{'es' if jobs > 1 else ''}"
    click.echo(f"Evaluating the IMU estimators on {len(recs)} recordings ({where}): {dataset}", err=True)
    rows = []
    failures: list[tuple[str, str]] = []
    notes: list[str] = []
    with tempfile.TemporaryDirectory(dir=out.parent if out.parent.exists() else None) as tmp_name:
        tmp = Path(tmp_name) / "report"
        (tmp / "figures").mkdir(parents=True)
        tasks = []
        for rec in recs:
            name = rec.source.split("lab/")[-1].replace("/data.mat:TimeMeasure1/", "_").replace("/", "_")
            tasks.append((rec, config, peer, tmp / "figures" / f"{name}.png" if figures else None))
        outcomes = run_tasks(evaluate_imu_recording, tasks, jobs=jobs, progress="evaluating")
        for rec, outcome in zip(recs, outcomes):
            if isinstance(outcome, TaskFailure):
                failures.append((rec.source, outcome.message))
                continue
            r, peer_note = outcome
            rows += r
            if peer_note is not None and peer_note not in notes:
                notes.append(peer_note)
        # mobgap absent is said once; its failures on recordings each.
        mobgap_note = MOBGAP_ABSENT if MOBGAP_ABSENT in notes else "; ".join(notes)
        with open(tmp / "bouts.csv", "w", newline="", encoding="utf-8") as f:
            w = csv.writer(f)
            keys = ["recording", "reference", "bout", "estimator", "start_s", "end_s", "ref_cadence_spm",
                    "cadence_spm", "ref_speed_mps", "ref_stride_speed_mps", "speed_mps", "ref_stride_time_s",
                    "stride_time_s", "strides", "ref_strides"]  # fmt: skip
            errors = ["cadence_error_spm", "speed_error_mps", "stride_speed_error_mps", "stride_time_error_s"]
            w.writerow(keys + errors)
            for row in rows:
                vals = [getattr(row, k) for k in keys + errors]
                vals[0] = vals[0].split("example_data/")[-1]
                w.writerow(vals)
        summ = ev.summary(rows)
        lines = ["# IMU evaluation: per reference walking bout", "",
                 f"Data set: {dataset} ({len(recs)} recordings). Median (worst) absolute error over the bouts. "
                 "yoyogait and the oscillator are scored on each bout over the strides its reference measured, where "
                 "the estimate is valid over half a stride or more (a bout with none is missed: no error, left out "
                 "of the median); mobgap's own bouts against the whole bout (docs/imu.md, section 6). The speed is "
                 "against the bout's walking speed (the reference's mean over all its strides); over the strides "
                 "scored, against the reference's own speeds of them where it gives them.",
                 ""]  # fmt: skip
        if mobgap_note:
            lines += [mobgap_note, ""]
        if failures:
            lines += [f"Not evaluated ({len(failures)}): " + "; ".join(f"{src}: {msg}" for src, msg in failures), ""]
        lines += ["| reference | estimator | bouts | missed | cadence [steps/min] | speed [m/s] "
                  "| speed over the strides scored [m/s] | stride time [s] |",
                  "|---|---|---|---|---|---|---|---|"]  # fmt: skip
        for d in summ:
            over = d["median_abs_stride_speed_error_mps"]
            lines.append(
                f"| {d['reference']} | {d['estimator']} | {d['bouts']} | {d['missed']} | "
                f"{d['median_abs_cadence_error_spm']:.2f} ({d['max_abs_cadence_error_spm']:.1f}) | "
                f"{d['median_abs_speed_error_mps']:.3f} ({d['max_abs_speed_error_mps']:.2f}) | "
                + (f"{over:.3f} ({d['max_abs_stride_speed_error_mps']:.2f}) | " if math.isfinite(over) else "- | ")
                + f"{d['median_abs_stride_time_error_s']:.3f} ({d['max_abs_stride_time_error_s']:.2f}) |"
            )
        (tmp / "summary.md").write_text("\n".join(lines) + "\n", encoding="utf-8")
        install_folder(tmp, out)
    for line in lines[4:]:
        click.echo(line)
    return {"rows": rows, "summary": summ, "note": mobgap_note, "failures": failures}


def check_imu_only_options(**given) -> None:
    """InputError for a motion-capture option given with an IMU file."""
    bad = [k for k, v in given.items() if v]
    if bad:
        raise InputError(f"{', '.join('--' + b.replace('_', '-') for b in bad)}: not used with an IMU file")
