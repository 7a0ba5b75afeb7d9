"""The command line on IMU files: inspect, estimate (a row per sample), evaluate per reference bout; bad input."""

from __future__ import annotations

import csv

import numpy as np
import pytest

from builders import write_trc
from yoyogait.cli import main
from yoyogait.io.imu_read import read_imu
from yoyogait.io.imu_recording import GRAVITY_MPS2
from yoyogait.synthetic import SUBJECTS, make_walk
from yoyogait.synthetic_imu import make_imu_walk

MOBGAP = "imu_mobgap/example_data"


def _csv(path, scale=1.0):
    rec = make_imu_walk(duration_s=10.0).recording
    cols = ["time_s", "acc_x_mps2", "acc_y_mps2", "acc_z_mps2", "gyr_x_rad_s", "gyr_y_rad_s", "gyr_z_rad_s"]
    np.savetxt(path, np.column_stack([rec.time_s, rec.acc_mps2 * scale, rec.gyr_rad_s]), delimiter=",",
               header=",".join(cols), comments="")  # fmt: skip
    return rec


def test_inspect_a_mobgap_csv(datasets_dir, capsys):
    """inspect on a mobgap CSV reports the rate, gravity, sensor height and a cadence, exit 0."""
    code = main(["inspect", str(datasets_dir / MOBGAP / "data_csv/HA/001/TimeMeasure1_Test5_Trial1.csv")])
    out, err = capsys.readouterr()
    assert code == 0, err
    assert "100 Hz" in out and "gravity" in out and "0.964 m" in out and "steps/min" in out


def test_inspect_counts_valid_time_at_the_files_rate_and_names_rows_of_zeros(tmp_path, capsys):
    """inspect on a 120 Hz file that states no rate, its first row all zeros: the rate from its times,
    the valid seconds at that rate (not at 100 Hz), and the row of zeros named."""
    import json

    rec = make_imu_walk(duration_s=10.0, rate_hz=120.0).recording
    rec.acc_mps2[0] = 0.0
    rec.gyr_rad_s[0] = 0.0
    cols = ["time_s", "acc_x_mps2", "acc_y_mps2", "acc_z_mps2", "gyr_x_rad_s", "gyr_y_rad_s", "gyr_z_rad_s"]
    p = tmp_path / "walk120.csv"
    np.savetxt(p, np.column_stack([rec.time_s, rec.acc_mps2, rec.gyr_rad_s]), delimiter=",", header=",".join(cols),
               comments="")  # fmt: skip
    assert main(["inspect", str(p), "--json"]) == 0
    report = json.loads(capsys.readouterr().out)
    back = read_imu(p)
    from yoyogait.estimators.imu import estimator_for

    valid = estimator_for(back).run_recording(back)["valid"].astype(bool)
    assert report["rate_hz"] == pytest.approx(120.0) and report["zero_rows"] == 1
    assert abs(report["valid_s"] - np.count_nonzero(valid) / 120.0) < 1e-9 and report["valid_s"] > 3.0
    assert main(["inspect", str(p)]) == 0
    out = capsys.readouterr().out
    assert "120 Hz" in out and "zero rows      1 (all six channels exactly 0" in out


def test_estimate_writes_one_row_per_sample(tmp_path, capsys, monkeypatch):
    """estimate on an IMU CSV writes one row per input sample with every field, valid while walking."""
    monkeypatch.chdir(tmp_path)
    rec = _csv(tmp_path / "walk.csv")
    assert main(["estimate", "walk.csv"]) == 0
    with open(tmp_path / "walk.csv.imu.csv") as f:
        rows = list(csv.DictReader(f))
    assert len(rows) == rec.n_samples
    assert {"time_s", "step_frequency_hz", "speed_mps", "valid", "reason"} <= set(rows[0])
    assert rows[-1]["valid"] == "1"


def test_estimate_of_a_ros_export_keeps_its_epoch_clock_to_the_microsecond(tmp_path, capsys, monkeypatch):
    """A sensor_msgs/Imu topic as `rostopic echo -p` writes it (ns stamps since the epoch, a frame_id text column,
    REP 145 units) is read without unit options, and estimate's time column keeps every sample's own time."""
    monkeypatch.chdir(tmp_path)
    rec = make_imu_walk(duration_s=6.0).recording
    stamps = 1_700_000_000 * 10**9 + np.round(rec.time_s * 1e9).astype(np.int64)
    fields = ["angular_velocity.x", "angular_velocity.y", "angular_velocity.z"] + [
        "linear_acceleration.x", "linear_acceleration.y", "linear_acceleration.z"]  # fmt: skip
    lines = [",".join(["%time", "field.header.seq", "field.header.stamp", "field.header.frame_id"]
                      + [f"field.{n}" for n in fields] + ["field.linear_acceleration_covariance0"])]  # fmt: skip
    for i, (ns, g, a) in enumerate(zip(stamps, rec.gyr_rad_s, rec.acc_mps2)):
        lines.append(
            ",".join(
                [str(ns + 2_000_000), str(i), str(ns), "imu_link", *map(str, g.tolist()), *map(str, a.tolist()), "0"]
            )
        )
    (tmp_path / "imu.csv").write_text("\n".join(lines) + "\n")
    assert main(["estimate", "imu.csv", "--out", "est.csv"]) == 0
    with open(tmp_path / "est.csv") as f:
        times = np.array([float(r["time_s"]) for r in csv.DictReader(f)])
    np.testing.assert_allclose(times - 1.7e9, rec.time_s, atol=2e-6)
    back = read_imu(tmp_path / "imu.csv")
    np.testing.assert_allclose(back.acc_mps2, rec.acc_mps2) and np.testing.assert_allclose(
        back.gyr_rad_s, rec.gyr_rad_s
    )


def test_a_plotjuggler_export_of_an_imu_topic_reads_beside_other_topics(tmp_path, capsys, monkeypatch):
    """A sensor_msgs/Imu topic as PlotJuggler exports it to CSV (`__time` in s, `/imu/data/linear_acceleration/x`..,
    the topic as the sensor's name, REP 145 units) beside another topic whose rows leave the IMU's cells empty:
    read without options, every IMU sample and only those, and estimated."""
    monkeypatch.chdir(tmp_path)
    rec = make_imu_walk(duration_s=8.0).recording
    topic = "/imu/data"
    cols = ["__time"] + [f"{topic}/{k}/{a}" for k in ("angular_velocity", "linear_acceleration") for a in "xyz"]
    lines = [",".join(cols + [f"{topic}/header/stamp", "/odom/twist/twist/linear/x"])]
    for i, (t, g, a) in enumerate(zip(1.7e9 + rec.time_s, rec.gyr_rad_s, rec.acc_mps2)):
        lines.append(",".join([f"{t:.6f}", *map(repr, g.tolist()), *map(repr, a.tolist()), f"{t:.6f}", ""]))
        if i % 3 == 0:  # the odometry's row between two IMU samples
            lines.append(",".join([f"{t + 0.004:.6f}"] + [""] * 7 + ["0.5"]))
    (tmp_path / "layout.csv").write_text("\n".join(lines) + "\n")
    back = read_imu(tmp_path / "layout.csv")
    assert back.metadata["sensor"] == topic and back.n_samples == rec.n_samples
    np.testing.assert_allclose(back.acc_mps2, rec.acc_mps2) and np.testing.assert_allclose(
        back.gyr_rad_s, rec.gyr_rad_s
    )
    np.testing.assert_allclose(back.time_s - 1.7e9, rec.time_s, atol=2e-6)
    assert main(["estimate", "layout.csv", "--out", "est.csv"]) == 0
    with open(tmp_path / "est.csv") as f:
        assert sum(r["valid"] == "1" for r in csv.DictReader(f)) > 300


def test_estimate_does_not_overwrite_without_force(tmp_path, capsys, monkeypatch):
    """An existing --out is left alone without --force: one line, exit non-zero; with --force it is replaced."""
    monkeypatch.chdir(tmp_path)
    _csv(tmp_path / "walk.csv")
    (tmp_path / "mine.csv").write_text("keep\n")
    code = main(["estimate", "walk.csv", "--out", "mine.csv"])
    err = capsys.readouterr().err
    assert code != 0 and len(err.strip().splitlines()) == 1 and "--force" in err
    assert (tmp_path / "mine.csv").read_text() == "keep\n"
    assert main(["estimate", "walk.csv", "--out", "mine.csv", "--force"]) == 0


def test_estimate_draws_a_figure_only_when_asked(tmp_path, capsys, monkeypatch):
    """estimate on an IMU file writes the CSV alone by default, and the CSV with a PNG under --figure."""
    monkeypatch.chdir(tmp_path)
    _csv(tmp_path / "walk.csv")
    assert main(["estimate", "walk.csv"]) == 0
    assert not list(tmp_path.glob("*.png"))
    assert main(["estimate", "walk.csv", "--out", "b.csv", "--figure", "b.png"]) == 0
    assert (tmp_path / "b.csv").is_file() and (tmp_path / "b.png").read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    assert "b.png" in capsys.readouterr().out


def test_options_of_the_other_kind_of_file_are_refused_not_ignored(tmp_path, capsys, monkeypatch):
    """A marker file's option given for an IMU file, or an IMU option for a marker file: one line naming it, exit 2."""
    monkeypatch.chdir(tmp_path)
    _csv(tmp_path / "walk.csv")
    write_trc(tmp_path / "markers.trc", make_walk(SUBJECTS[0], "1-straight", duration_s=6.0).recording)
    for argv, named in (
        (["estimate", "walk.csv", "--point", "hand"], "--point"),
        (["estimate", "walk.csv", "--feet", "LHEE,RHEE", "--belt-speed-mps", "1"], "--feet, --belt-speed-mps"),
        (["inspect", "walk.csv", "--up-axis", "y"], "--up-axis"),
        (["replay", "walk.csv", "--name", "w", "--length-unit-m", "0.001"], "--length-unit-m"),
        (["estimate", "markers.trc", "--acc-unit", "g"], "--acc-unit"),
        (["inspect", "markers.trc", "--trial", "Test5/Trial1", "--sensor-height-m", "1"], "--sensor-height-m, --trial"),
    ):
        code = main(argv)
        err = capsys.readouterr().err
        assert code == 2 and len(err.strip().splitlines()) == 1 and named in err and argv[1] in err, (argv, err)
    assert not list(tmp_path.glob("walk.csv.imu.csv"))
    assert not list(tmp_path.glob("markers.trc.estimate.*"))


def test_evaluate_refuses_the_marker_evaluations_options_for_an_imu_data_set(tmp_path, capsys):
    """evaluate on a folder of data.mat files with --point or --estimators: one line naming them, exit 2, no
    report; --jobs below 1 is one line too."""
    (tmp_path / "lab" / "HA").mkdir(parents=True)
    (tmp_path / "lab" / "HA" / "data.mat").write_bytes(b"")
    out = tmp_path / "report"
    code = main(["evaluate", str(tmp_path / "lab"), "--out", str(out), "--point", "hand", "--estimators", "paper"])
    err = capsys.readouterr().err
    assert code == 2 and len(err.strip().splitlines()) == 1 and "--point, --estimators" in err, err
    assert not out.exists()
    assert main(["evaluate", str(tmp_path / "lab"), "--out", str(out), "--jobs", "0"]) == 2
    err = capsys.readouterr().err
    assert len(err.strip().splitlines()) == 1 and "--jobs must be at least 1" in err, err
    assert not out.exists()


def test_gravity_in_g_is_one_line_naming_the_option(tmp_path, capsys, monkeypatch):
    """An IMU CSV whose acceleration is in g but labelled m/s^2: one line naming --acc-unit, exit 2, no output."""
    monkeypatch.chdir(tmp_path)
    _csv(tmp_path / "walk.csv", scale=1 / GRAVITY_MPS2)
    code = main(["estimate", "walk.csv"])
    err = capsys.readouterr().err
    assert code == 2 and len(err.strip().splitlines()) == 1 and "--acc-unit g" in err and "Traceback" not in err
    assert not (tmp_path / "walk.csv.imu.csv").exists()


def test_evaluate_the_imu_data_set(datasets_dir, tmp_path, capsys):
    """evaluate over the Mobilise-D folder writes bouts.csv, summary.md and a figure per recording."""
    out = tmp_path / "report"
    code = main(["evaluate", str(datasets_dir / MOBGAP / "data/lab"), "--out", str(out)])
    text = capsys.readouterr().out
    assert code == 0
    assert (out / "bouts.csv").is_file() and (out / "summary.md").is_file()
    assert len(list((out / "figures").glob("*.png"))) == 9
    assert "yoyogait-imu" in text and "INDIP" in text and "Stereophoto" in text


def _bouts_csv(folder):
    with open(folder / "bouts.csv", newline="", encoding="utf-8") as f:
        return list(csv.DictReader(f))


def test_evaluate_scores_mobgaps_pipeline_on_the_same_reference_bouts(datasets_dir, tmp_path, capsys):
    """With mobgap installed, evaluate runs its offline pipeline as the peer on every recording: a mobgap row for
    each reference bout yoyogait is scored on, errors of a walking pipeline (not of seconds read as samples),
    and its line in the summary."""
    pytest.importorskip("mobgap", reason="mobgap is not installed (yoyogait[mobgap])")
    out = tmp_path / "report"
    assert main(["evaluate", str(datasets_dir / MOBGAP / "data/lab/HA/002"), "--out", str(out), "--jobs", "1"]) == 0
    # The recordings on two processes: the same report, byte for byte.
    out2 = tmp_path / "report2"
    assert main(["evaluate", str(datasets_dir / MOBGAP / "data/lab/HA/002"), "--out", str(out2), "--jobs", "2"]) == 0
    for name in ("bouts.csv", "summary.md"):
        assert (out2 / name).read_bytes() == (out / name).read_bytes(), name
    assert sorted(p.name for p in (out2 / "figures").iterdir()) == sorted(p.name for p in (out / "figures").iterdir())
    rows = _bouts_csv(out)
    ours = [(r["recording"], r["reference"], r["bout"]) for r in rows if r["estimator"] == "yoyogait-imu"]
    peer = [r for r in rows if r["estimator"] == "mobgap"]
    assert ours and [(r["recording"], r["reference"], r["bout"]) for r in peer] == ours
    for ref in ("INDIP", "Stereophoto"):
        scored = [r for r in peer if r["reference"] == ref and np.isfinite(float(r["cadence_error_spm"] or "nan"))]
        assert scored, ref
        assert np.median([abs(float(r["cadence_error_spm"])) for r in scored]) < 10.0, scored
        assert np.median([abs(float(r["speed_error_mps"])) for r in scored]) < 0.3, scored
    summary = (out / "summary.md").read_text()
    assert "| INDIP | mobgap |" in summary and "| Stereophoto | mobgap |" in summary
    assert "mobgap failed" not in summary and "not installed" not in summary


def test_evaluate_without_mobgap_leaves_its_column_out_with_a_note(datasets_dir, tmp_path, monkeypatch):
    """mobgap absent: the report says so in one line and has no mobgap row; yoyogait's own rows are all there."""
    from yoyogait.evaluation import imu as ev

    def absent(rec):
        raise ImportError("No module named 'mobgap'")

    monkeypatch.setattr(ev, "run_mobgap", absent)
    out = tmp_path / "report"  # one process: the patch is in this one
    assert main(["evaluate", str(datasets_dir / MOBGAP / "data/lab/HA/002"), "--out", str(out), "--jobs", "1"]) == 0
    rows = _bouts_csv(out)
    assert rows and not any(r["estimator"] == "mobgap" for r in rows)
    assert any(r["estimator"] == "yoyogait-imu" for r in rows)
    assert "mobgap is not installed (pip install 'yoyogait[mobgap]')" in (out / "summary.md").read_text()


def test_evaluate_lists_a_recording_that_fails_and_reports_the_others(datasets_dir, tmp_path, monkeypatch, capsys):
    """One recording's evaluation raising: the report lists it under 'Not evaluated' with its message, the
    other recordings' rows are all there, and the exit status is 1."""
    from yoyogait.evaluation import imu as ev

    real = ev.evaluate_recording

    def failing(rec, config=None, mobgap=None):
        if rec.source.endswith("Test5/Trial2"):
            raise ValueError("a broken trial")
        return real(rec, config, mobgap)

    monkeypatch.setattr(ev, "evaluate_recording", failing)
    monkeypatch.setattr(ev, "run_mobgap", lambda rec: (_ for _ in ()).throw(ImportError("no mobgap")))
    out = tmp_path / "report"
    assert main(["evaluate", str(datasets_dir / MOBGAP / "data/lab/HA/002"), "--out", str(out), "--jobs", "1"]) == 1
    summary = (out / "summary.md").read_text()
    assert "Not evaluated (1): " in summary and "Test5/Trial2: ValueError: a broken trial" in summary, summary
    recordings = {r["recording"] for r in _bouts_csv(out)}
    assert recordings and not any(r.endswith("Test5/Trial2") for r in recordings)
    assert "Not evaluated (1)" in capsys.readouterr().out


def test_estimate_a_trial_of_a_data_mat(datasets_dir, tmp_path, capsys):
    """--trial picks a trial of a data.mat (one row per sample); an unknown one is one line naming --trial."""
    mat = str(datasets_dir / MOBGAP / "data/lab/HA/002/data.mat")
    out = tmp_path / "t.csv"
    assert main(["estimate", mat, "--trial", "Test5/Trial2", "--out", str(out)]) == 0
    with open(out) as f:
        assert sum(1 for _ in f) - 1 == read_imu(mat, trial="Test5/Trial2").n_samples
    code = main(["estimate", mat, "--trial", "Test12/Trial1", "--out", str(tmp_path / "u.csv")])
    err = capsys.readouterr().err
    assert code == 2 and len(err.strip().splitlines()) == 1 and "--trial" in err


def test_inspect_says_a_sensor_whose_norm_strays_while_moving_may_be_on_a_limb(tmp_path, capsys):
    """A recording never valid because its low-passed norm strays from gravity while it moves (a foot's
    swing: a 0.25 s burst of 30 m/s^2 once a stride), though its median norm passes the readers' check (the
    foot still in stance): inspect says it may be on a foot or a limb, not that it is at rest."""
    rec = make_imu_walk(duration_s=10.0).recording
    t = rec.time_s
    phase = np.mod(t, 1.1)
    acc = rec.acc_mps2.copy()
    acc[:, 2] += np.where(phase < 0.25, 30.0 * np.sin(np.pi * phase / 0.25), 0.0)
    p = tmp_path / "foot.csv"
    cols = ["time_s", "acc_x_mps2", "acc_y_mps2", "acc_z_mps2", "gyr_x_rad_s", "gyr_y_rad_s", "gyr_z_rad_s"]
    np.savetxt(p, np.column_stack([rec.time_s, acc, rec.gyr_rad_s]), delimiter=",", header=",".join(cols),
               comments="")  # fmt: skip
    assert main(["inspect", str(p)]) == 0
    out = capsys.readouterr().out
    assert "GRAVITY" in out and "a sensor on a foot or a limb?" in out, out
