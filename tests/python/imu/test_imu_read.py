"""The IMU readers: the real Mobilise-D and mobgap files, yoyogait's and a generic CSV, Xsens .txt; units checked."""

from __future__ import annotations

import numpy as np
import pytest

from yoyogait.errors import InputError
from yoyogait.io import read
from yoyogait.io.imu_read import is_imu_file, read_imu, read_mobilised_trials
from yoyogait.io.imu_recording import GRAVITY_MPS2
from yoyogait.synthetic_imu import make_imu_walk

MOBGAP = "imu_mobgap/example_data"


def _write_yoyogait_csv(path, rec, acc_scale=1.0, acc_col="acc_{}_mps2", gyr_col="gyr_{}_rad_s", gyr_scale=1.0):
    cols = ["time_s"] + [acc_col.format(a) for a in "xyz"] + [gyr_col.format(a) for a in "xyz"]
    table = np.column_stack([rec.time_s, rec.acc_mps2 * acc_scale, rec.gyr_rad_s * gyr_scale])
    np.savetxt(path, table, delimiter=",", header=",".join(cols), comments="")


def test_mobilised_mat_reads_every_trial_with_its_references(datasets_dir):
    """A Mobilise-D data.mat gives each trial at 100 Hz, gravity ~9.81 m/s^2, the sensor height, both references."""
    trials = read_mobilised_trials(datasets_dir / MOBGAP / "data/lab/HA/001/data.mat")
    assert [f"{r.metadata['test']}/{r.metadata['trial']}" for r in trials] == [
        "Test5/Trial1",
        "Test5/Trial2",
        "Test11/Trial1",
    ]
    for r in trials:
        assert r.rate_hz == 100.0 and abs(np.median(np.linalg.norm(r.acc_mps2, axis=1)) - GRAVITY_MPS2) < 0.5
        assert r.sensor_height_m == pytest.approx(0.964)
        assert set(r.references) == {"INDIP", "Stereophoto"}
        for b in r.references["INDIP"]:
            assert b.end_s > b.start_s and 60 < b.cadence_spm < 140 and 0.1 < b.speed_mps < 2.0


def test_mobgap_csv_matches_the_mat_file(datasets_dir):
    """The mobgap CSV and the data.mat of a trial hold the same signals (to the 0.03 % of the export's g)."""
    csv = read_imu(datasets_dir / MOBGAP / "data_csv/HA/001/TimeMeasure1_Test5_Trial1.csv")
    mat = read_imu(datasets_dir / MOBGAP / "data/lab/HA/001/data.mat", trial="Test5/Trial1")
    assert csv.n_samples == mat.n_samples and csv.sensor_height_m == pytest.approx(mat.sensor_height_m)
    assert np.allclose(csv.acc_mps2, mat.acc_mps2, rtol=5e-4, atol=1e-6)
    assert np.allclose(csv.gyr_rad_s, mat.gyr_rad_s, atol=1e-6)


def test_every_shared_imu_table_is_recognised(datasets_dir):
    """Each of the nine shared IMU CSVs is an IMU file and reads with plausible units."""
    files = sorted((datasets_dir / MOBGAP / "data_csv").rglob("*.csv"))
    assert len(files) == 9
    for f in files:
        assert is_imu_file(f)
        read_imu(f)


def test_unknown_trial_names_the_option(datasets_dir):
    """A trial the data.mat does not hold: one line naming the trials it has and trial=."""
    with pytest.raises(InputError, match=r"Test5/Trial1, .*trial="):
        read_imu(datasets_dir / MOBGAP / "data/lab/HA/001/data.mat", trial="Test9/Trial1")


def test_yoyogait_csv_round_trip(tmp_path):
    """A yoyogait IMU CSV (units in the header) reads back the SYNTHETIC signals exactly (to print precision)."""
    rec = make_imu_walk(duration_s=4.0).recording
    p = tmp_path / "imu.csv"
    _write_yoyogait_csv(p, rec)
    back = read_imu(p)
    assert np.allclose(back.acc_mps2, rec.acc_mps2, atol=1e-9) and np.allclose(back.gyr_rad_s, rec.gyr_rad_s, atol=1e-9)
    assert back.rate_hz == pytest.approx(100.0)


def test_header_units_g_and_deg_s_are_applied(tmp_path):
    """Columns named acc_x_g and gyr_x_deg_s are scaled to m/s^2 and rad/s."""
    rec = make_imu_walk(duration_s=4.0).recording
    p = tmp_path / "imu.csv"
    _write_yoyogait_csv(p, rec, 1 / GRAVITY_MPS2, "acc_{}_g", "gyr_{}_deg_s", 180 / np.pi)
    back = read_imu(p)
    assert np.allclose(back.acc_mps2, rec.acc_mps2, atol=1e-6) and np.allclose(back.gyr_rad_s, rec.gyr_rad_s, atol=1e-6)


def test_generic_csv_without_units_names_the_option(tmp_path):
    """acc_x.. without a unit: one line asking for acc_unit; with it, it reads."""
    rec = make_imu_walk(duration_s=4.0).recording
    p = tmp_path / "generic.csv"
    _write_yoyogait_csv(p, rec, 1.0, "acc_{}", "gyr_{}")
    with pytest.raises(InputError, match="acc_unit"):
        read_imu(p)
    back = read_imu(p, acc_unit="mps2", gyr_unit="rad_s")
    assert np.allclose(back.acc_mps2, rec.acc_mps2, atol=1e-9)


def test_mobgap_body_frame_columns_are_the_sensor_axes(tmp_path):
    """acc_is, acc_ml, acc_pa and gyr_is.. (mobgap's body frame: x -> is, y -> ml, z -> pa) read as x, y, z."""
    rec = make_imu_walk(duration_s=4.0).recording
    p = tmp_path / "body_frame.csv"
    _write_yoyogait_csv(p, rec, 1.0, "acc_{}", "gyr_{}")
    p.write_text(p.read_text().replace("_x", "_is", 2).replace("_y", "_ml", 2).replace("_z", "_pa", 2))
    assert p.read_text().startswith("time_s,acc_is,acc_ml,acc_pa,gyr_is,gyr_ml,gyr_pa\n")
    assert is_imu_file(p)
    back = read_imu(p, acc_unit="mps2", gyr_unit="rad_s")
    assert np.allclose(back.acc_mps2, rec.acc_mps2, atol=1e-9) and np.allclose(back.gyr_rad_s, rec.gyr_rad_s, atol=1e-9)


def _sensors_csv(path, rec, sensors, acc_scale=1 / GRAVITY_MPS2, gyr_scale=180 / np.pi):
    """A table as KielMAT and others write it: an index column, then sensor-named columns (``pelvis_ACCEL_x``),
    no time, g and deg/s; every sensor the SYNTHETIC lower back's signals, its gyro 0.01 rad/s more per position."""
    cols = [""] + [f"{s}_{kind}_{a}" for s in sensors for kind in ("ACCEL", "GYRO") for a in "xyz"]
    parts = [np.arange(rec.n_samples)]
    for k, _ in enumerate(sensors):
        parts += [rec.acc_mps2 * acc_scale, (rec.gyr_rad_s + 0.01 * k) * gyr_scale]
    np.savetxt(path, np.column_stack(parts), delimiter=",", header=",".join(cols), comments="")


def test_sensor_named_columns_read_the_lower_backs_sensor(tmp_path):
    """Columns after a sensor's name (pelvis_ACCEL_x, no time column): an IMU table; of several sensors the one
    named as the lower back's is read, another by sensor=, and an unknown sensor= is one line naming those there."""
    rec = make_imu_walk(duration_s=4.0).recording
    p = tmp_path / "sensors.csv"
    _sensors_csv(p, rec, ["left_foot", "Pelvis"])
    assert is_imu_file(p)
    back = read_imu(p, acc_unit="g", gyr_unit="deg_s", rate_hz=100.0)
    assert back.metadata["sensor"] == "pelvis"
    assert np.allclose(back.acc_mps2, rec.acc_mps2, atol=1e-6) and np.allclose(back.gyr_rad_s, rec.gyr_rad_s + 0.01)
    foot = read_imu(p, acc_unit="g", gyr_unit="deg_s", rate_hz=100.0, sensor="left_foot")
    assert np.allclose(foot.gyr_rad_s, rec.gyr_rad_s, atol=1e-9)
    with pytest.raises(
        InputError, match=r"no sensor 'wrist' \(sensor=, --sensor\); the columns name left_foot, pelvis"
    ):
        read_imu(p, acc_unit="g", gyr_unit="deg_s", rate_hz=100.0, sensor="wrist")


def test_a_table_missing_units_and_rate_asks_for_all_of_them_in_one_line(tmp_path):
    """No unit on either kind of column and no time column: one line naming --acc-unit, --gyr-unit and
    --capture-rate-hz (not one option per attempt); what is given is no longer asked for."""
    rec = make_imu_walk(duration_s=2.0).recording
    p = tmp_path / "sensors.csv"
    _sensors_csv(p, rec, ["pelvis"])
    with pytest.raises(InputError) as err:
        read_imu(p)
    line = str(err.value)
    assert "\n" not in line
    for option in ("--acc-unit", "--gyr-unit", "--capture-rate-hz"):
        assert option in line, option
    with pytest.raises(InputError) as err:
        read_imu(p, acc_unit="g")
    assert "--acc-unit" not in str(err.value) and "--gyr-unit" in str(err.value)


def test_sensor_named_columns_of_no_lower_back_ask_for_the_sensor(tmp_path):
    """Several sensors, none named as the lower back's: one line naming them and sensor= (--sensor)."""
    rec = make_imu_walk(duration_s=2.0).recording
    p = tmp_path / "feet.csv"
    _sensors_csv(p, rec, ["left_foot", "right_foot"])
    with pytest.raises(InputError, match=r"several sensors \(left_foot, right_foot\).*--sensor"):
        read_imu(p, acc_unit="g", gyr_unit="deg_s", rate_hz=100.0)


def test_an_inertial_table_the_imu_readers_cannot_take_says_what_they_need(tmp_path):
    """Accelerometer columns without a gyro, read as motion capture: one line naming what an IMU table needs."""
    p = tmp_path / "acc_only.csv"
    p.write_text("time,acc_x,acc_y,acc_z\n0,0,0,9.8\n0.01,0,0,9.8\n")
    assert not is_imu_file(p)
    with pytest.raises(InputError, match="an IMU table needs acc and gyr columns for each axis: x, y, z or is, ml, pa"):
        read(p)
    named = tmp_path / "named_acc_only.csv"  # after a sensor's name too, not a point named pelvis_ACCEL
    named.write_text(",pelvis_ACCEL_x,pelvis_ACCEL_y,pelvis_ACCEL_z\n0,0.9,0,0\n1,0.9,0,0\n")
    with pytest.raises(InputError, match="an IMU table needs acc and gyr columns"):
        read(named, capture_rate_hz=100.0)


def test_gravity_in_the_wrong_unit_names_the_option(tmp_path):
    """Accelerations in g declared as m/s^2: the error says 'in g?' and names --acc-unit."""
    rec = make_imu_walk(duration_s=4.0).recording
    p = tmp_path / "imu.csv"
    _write_yoyogait_csv(p, rec, 1 / GRAVITY_MPS2)
    with pytest.raises(InputError, match=r"in g\? pass acc_unit g \(--acc-unit g\)"):
        read_imu(p)


def test_angular_rate_in_deg_s_declared_rad_s_names_the_option(tmp_path):
    """A turning walk's rate in deg/s declared as rad/s: the error names --gyr-unit deg_s."""
    rec = make_imu_walk(None, "3-rectangle", duration_s=12.0).recording
    p = tmp_path / "imu.csv"
    _write_yoyogait_csv(p, rec, 1.0, "acc_{}_mps2", "gyr_{}_rad_s", 180 / np.pi)
    with pytest.raises(InputError, match=r"--gyr-unit deg_s"):
        read_imu(p)


def test_a_rate_read_in_deg_s_beyond_a_lower_backs_asks_where_the_sensor_is(tmp_path):
    """A rate already read in deg/s (as its header says) beyond a lower back's (a foot's 20 rad/s): the error asks
    whether the sensor is on a foot or a leg, and does not name --gyr-unit deg_s, which the file already is."""
    rec = make_imu_walk(None, "3-rectangle", duration_s=12.0).recording
    rec.gyr_rad_s = rec.gyr_rad_s * (20.0 / np.percentile(np.abs(rec.gyr_rad_s), 99))
    p = tmp_path / "imu.csv"
    _write_yoyogait_csv(p, rec, 1.0, "acc_{}_mps2", "gyr_{}_deg_s", 180 / np.pi)
    with pytest.raises(InputError, match=r"20 rad/s \(1146 deg/s\).*a sensor on a foot or a leg\?") as err:
        read_imu(p)
    assert "--gyr-unit" not in str(err.value)


def _xsens(path, rec, rate="100.0"):
    lines = ["// General information:", f"//  Update Rate: {rate}Hz", "//  Filter Profile: general",
             "PacketCounter\tAcc_X\tAcc_Y\tAcc_Z\tGyr_X\tGyr_Y\tGyr_Z"]  # fmt: skip
    for i in range(rec.n_samples):
        vals = [str((i + 65000) % 65536)] + [f"{v:.6f}" for v in (*rec.acc_mps2[i], *rec.gyr_rad_s[i])]
        lines.append("\t".join(vals))
    path.write_text("\n".join(lines) + "\n")


def test_xsens_mt_manager_txt(tmp_path):
    """An Xsens MT Manager export: the rate from its comment, the packet counter's wrap unwrapped into time."""
    rec = make_imu_walk(duration_s=12.0).recording
    p = tmp_path / "MT_012005D6-000-000.txt"
    _xsens(p, rec)
    assert is_imu_file(p)
    back = read_imu(p)
    assert back.rate_hz == 100.0 and np.allclose(np.diff(back.time_s), 0.01)
    assert np.allclose(back.acc_mps2, rec.acc_mps2, atol=1e-5)


def test_xsens_txt_after_a_free_text_preamble_takes_its_rate_from_it(tmp_path):
    """An Xsens export whose header follows a line of free text (``Acquisition frequency: 100 Hz``, as a
    published Awinda data set writes it) is found among .txt files and read at that rate."""
    rec = make_imu_walk(duration_s=6.0).recording
    p = tmp_path / "1-1_lb.txt"
    _xsens(p, rec, rate="60")
    lines = p.read_text().splitlines()
    p.write_text("\n".join(["Acquisition frequency: 100 Hz", *lines[3:]]) + "\n")
    assert is_imu_file(p)
    back = read_imu(p)
    assert back.rate_hz == 100.0 and np.allclose(np.diff(back.time_s), 0.01)
    assert np.allclose(back.gyr_rad_s, rec.gyr_rad_s, atol=1e-5)
    p.write_text("\n".join(["Recorded with a wireless sensor", *lines[3:]]) + "\n")
    with pytest.raises(InputError, match="--capture-rate-hz"):
        read_imu(p)


def test_xsens_packet_received_twice_is_one_sample_and_a_counter_going_back_is_refused(tmp_path):
    """A packet counter repeated (a retransmitted packet) keeps its first copy and says so; one that goes
    back is still an error."""
    rec = make_imu_walk(duration_s=6.0).recording
    p = tmp_path / "MT.txt"
    _xsens(p, rec)
    lines = p.read_text().splitlines()
    head = 4  # the header's line: samples start after it
    p.write_text("\n".join([*lines[: head + 300], lines[head + 299], *lines[head + 300 :]]) + "\n")
    back = read_imu(p)
    assert back.n_samples == rec.n_samples and back.metadata["repeated_packets"] == 1
    assert np.all(np.diff(back.time_s) > 0) and np.allclose(back.acc_mps2, rec.acc_mps2, atol=1e-5)
    p.write_text("\n".join([*lines[: head + 300], lines[head + 290], *lines[head + 300 :]]) + "\n")
    with pytest.raises(InputError, match="timestamps do not increase"):
        read_imu(p)


def _dot(path, rec, columns=("Acc_X", "Acc_Y", "Acc_Z", "Gyr_X", "Gyr_Y", "Gyr_Z"), start_tick=4294000000, app=True):
    """rec as a Movella DOT app's CSV: metadata lines, SampleTimeFine in microseconds (wrapping), deg/s;
    ``app=False``: as the SDK writes it, the column header alone."""
    lines = ["sep=,", "DeviceTag:,Pelvis", "FirmwareVersion:,2.0.0", "OutputRate:,100Hz", ""] if app else []
    lines.append("PacketCounter,SampleTimeFine," + ",".join(columns) + ",Status")
    values = np.column_stack([rec.acc_mps2, np.degrees(rec.gyr_rad_s)])
    for i in range(rec.n_samples):
        tick = (start_tick + round(1e6 * rec.time_s[i])) % 2**32
        lines.append(f"{i},{tick}," + ",".join(f"{v:.6f}" for v in values[i, : len(columns)]) + ",0")
    path.write_text("\n".join(lines) + "\n")


def test_movella_dot_csv(tmp_path):
    """A Movella DOT CSV: found among CSVs, its microsecond clock unwrapped, deg/s read as rad/s, the rate read."""
    rec = make_imu_walk(duration_s=12.0).recording
    p = tmp_path / "Pelvis_20231031.csv"
    _dot(p, rec)
    assert is_imu_file(p)
    back = read_imu(p)
    assert back.rate_hz == 100.0 and np.allclose(back.time_s, rec.time_s - rec.time_s[0], atol=2e-6)
    assert np.allclose(back.acc_mps2, rec.acc_mps2, atol=1e-5)
    assert np.allclose(back.gyr_rad_s, rec.gyr_rad_s, atol=1e-6)


def test_movella_dot_sdk_export_takes_its_rate_from_the_clock_and_a_row_of_zeros_as_missing(tmp_path):
    """A DOT CSV as the SDK writes it (no OutputRate line; its first packet all zeros, as in public
    recordings): the rate is the clock's, and the row of zeros is missing, not a sample of no gravity."""
    rec = make_imu_walk(duration_s=4.0, rate_hz=120.0).recording
    rec.acc_mps2[0] = 0.0
    rec.gyr_rad_s[0] = 0.0
    p = tmp_path / "4_D422CD003437_20231031_133150.csv"
    _dot(p, rec, app=False)
    back = read_imu(p)
    assert back.rate_hz == pytest.approx(120.0, rel=1e-4)
    assert np.isnan(back.acc_mps2[0]).all() and np.isnan(back.gyr_rad_s[0]).all()
    assert back.metadata["zero_rows"] == 1 and np.isfinite(back.acc_mps2[1:]).all()


def test_movella_dot_orientation_only_says_what_to_export(tmp_path):
    """A DOT export of quaternions and free acceleration: one line naming what it holds and what it lacks."""
    rec = make_imu_walk(duration_s=3.0).recording
    p = tmp_path / "Pelvis.csv"
    _dot(p, rec, columns=("Quat_W", "Quat_X", "Quat_Y", "Quat_Z", "FreeAcc_X", "FreeAcc_Y"))
    assert is_imu_file(p)
    with pytest.raises(InputError, match=r"Movella DOT export of Quat_W.*lacks Acc_X.*Gyr_Z; export"):
        read_imu(p)


def test_movella_dot_bad_clock_is_one_line_naming_the_sample(tmp_path):
    """A DOT CSV with a sample's SampleTimeFine missing, or repeated: one line naming the sample."""
    rec = make_imu_walk(duration_s=3.0).recording
    p = tmp_path / "Pelvis.csv"
    _dot(p, rec)
    lines = p.read_text().splitlines()
    head = next(i for i, line in enumerate(lines) if line.startswith("PacketCounter")) + 1
    gap = lines.copy()
    cells = gap[head + 100].split(",")
    gap[head + 100] = ",".join([cells[0], "", *cells[2:]])
    p.write_text("\n".join(gap) + "\n")
    with pytest.raises(InputError, match=r"sample 100 \(after the header\) has no SampleTimeFine, and 0 more"):
        read_imu(p)
    p.write_text("\n".join(lines[: head + 51] + lines[head + 50 :]) + "\n")
    with pytest.raises(InputError, match=r"timestamps do not increase \(sample 51 of .*1 such samples\)"):
        read_imu(p)


def test_xsens_without_gyro_says_what_to_export(tmp_path):
    """An Xsens export without Gyr_ columns: one line saying which columns are missing."""
    p = tmp_path / "MT.txt"
    p.write_text("//  Update Rate: 100.0Hz\nPacketCounter\tAcc_X\tAcc_Y\tAcc_Z\n1\t9.8\t0\t0\n2\t9.8\t0\t0\n")
    with pytest.raises(InputError, match="Gyr_X"):
        read_imu(p)


def test_xsens_cell_that_is_not_a_number_is_named_with_its_line_and_channel(tmp_path):
    """A cell that is not a number: one line naming the file's line and the channel."""
    p = tmp_path / "MT.txt"
    p.write_text("//  Update Rate: 100.0Hz\nPacketCounter\tAcc_X\tAcc_Y\tAcc_Z\tGyr_X\tGyr_Y\tGyr_Z\n"
                 "1\t9.8\t0\t0\t0\t0\t0\n2\t9.8\t0\tn/a\t0\t0\t0\n")  # fmt: skip
    with pytest.raises(InputError, match=r"MT.txt: line 4: Acc_Z 'n/a' is not a number"):
        read_imu(p)


def _bids_imu(folder, rec, points=("pelvis", "left_foot"), acc_unit="g", gyr_unit="deg/s"):
    """rec as a Motion-BIDS IMU file (KeepControl's layout): ACCEL and GYRO channels per tracked point, the rate
    in the JSON sidecar; every point the same signals."""
    prefix = folder / "sub-pp002_task-walk_tracksys-imu"
    rows = [["name", "component", "type", "tracked_point", "units"]]
    columns = []
    for point in points:
        for kind, values, unit in (("ACCEL", rec.acc_mps2 / GRAVITY_MPS2, acc_unit), ("GYRO", np.degrees(rec.gyr_rad_s),
                                                                                      gyr_unit)):  # fmt: skip
            for a, axis in enumerate("xyz"):
                rows.append([f"{point}_{kind}_{axis}", axis, kind, point, unit])
                columns.append(values[:, a])
    prefix.with_name(prefix.name + "_channels.tsv").write_text("\n".join("\t".join(r) for r in rows) + "\n")
    prefix.with_name(prefix.name + "_motion.json").write_text('{"SamplingFrequency": 100}')
    data = np.column_stack(columns)
    path = prefix.with_name(prefix.name + "_motion.tsv")
    path.write_text("\n".join("\t".join(f"{v:.8f}" for v in row) for row in data) + "\n")
    return path


def test_motion_bids_imu_reads_the_lower_back_sensor_in_its_units(tmp_path):
    """A Motion-BIDS IMU file (ACCEL in g, GYRO in deg/s, a pelvis and a foot): an IMU file, the pelvis chosen by
    its label, m/s^2 and rad/s; --sensor picks another; a unit that is not one names the option."""
    rec = make_imu_walk(duration_s=6.0).recording
    p = _bids_imu(tmp_path, rec)
    assert is_imu_file(p)
    back = read_imu(p)
    assert back.metadata["sensor"] == "pelvis" and back.rate_hz == 100.0
    assert np.allclose(back.acc_mps2, rec.acc_mps2, atol=1e-6) and np.allclose(back.gyr_rad_s, rec.gyr_rad_s, atol=1e-6)
    assert np.allclose(back.time_s, rec.time_s - rec.time_s[0])
    assert read_imu(p, sensor="left_foot").metadata["sensor"] == "left_foot"
    with pytest.raises(InputError, match=r"no sensor 'wrist'.*the file has pelvis \(pelvis\), left_foot"):
        read_imu(p, sensor="wrist")
    other = tmp_path / "other"
    other.mkdir()
    q = _bids_imu(other, rec, points=("pelvis",), acc_unit="furlong/s^2")
    with pytest.raises(InputError, match=r"ACCEL channels in 'furlong/s\^2'; pass acc_unit \(--acc-unit\)"):
        read_imu(q)


def test_inspect_on_a_motion_bids_imu_file_names_the_sensor_and_finds_the_cadence(tmp_path, capsys):
    """`yoyogait inspect` on a Motion-BIDS IMU file: the IMU path (not the marker reader), its sensor named, the
    SYNTHETIC walk's cadence."""
    from yoyogait.cli import main

    walk = make_imu_walk(duration_s=12.0)
    p = _bids_imu(tmp_path, walk.recording)
    assert main(["inspect", str(p)]) == 0
    out = capsys.readouterr().out
    assert "IMU (motion_bids)" in out and "\nsensor         pelvis\n" in out and "100 Hz" in out
    cadence = float(out.split("cadence")[1].split("steps/min")[0])
    assert abs(cadence - 60 * walk.truth.step_frequency_hz[-1]) < 2.0


@pytest.mark.parametrize("phase_samples", [0.0, 0.5])
def test_an_exactly_periodic_signal_is_not_read_as_clipped_but_a_plateau_is(phase_samples):
    """A smooth periodic signal reaches the same maximum once per period (twice in a row where its peak
    falls between two samples): no sensor range is read from it; held three samples in a row, it is."""
    from yoyogait.io.imu_read import clipped_ranges
    from yoyogait.io.imu_recording import ImuRecording

    t = np.arange(3000) / 100.0
    theta = 2.0 * np.pi * 1.0 * (t + phase_samples / 100.0)
    acc = np.column_stack([-0.4 * np.sin(theta), np.zeros_like(t), GRAVITY_MPS2 - 0.8 * np.cos(theta)])
    acc = np.round(acc, 6)  # as a CSV with six decimals stores it
    rec = ImuRecording(time_s=t, acc_mps2=acc, gyr_rad_s=np.zeros((t.size, 3)), rate_hz=100.0, source="periodic")
    assert clipped_ranges(rec) == {}
    clipped = acc.copy()
    clipped[:, 2] = np.minimum(clipped[:, 2], 10.5)  # the peaks above 10.5 m/s^2 held there for several samples
    rec = ImuRecording(time_s=t, acc_mps2=clipped, gyr_rad_s=np.zeros((t.size, 3)), rate_hz=100.0, source="clip")
    level, count = clipped_ranges(rec)["acc"]
    assert level == 10.5 and count > 100


def _log(path, time_header, times, rec):
    a, g = rec.acc_mps2 / GRAVITY_MPS2, np.degrees(rec.gyr_rad_s)
    rows = [f"{int(tt)},{','.join(f'{v:.5f}' for v in (*ai, *gi))}" for tt, ai, gi in zip(times, a, g)]
    path.write_text(f"{time_header},ax,ay,az,gx,gy,gz\n" + "\n".join(rows) + "\n")


@pytest.mark.parametrize(
    "header, scale, unit",
    [("timestamp", 1000, "ms"), ("timestamp", 1_000_000, "us"), ("millis", 1000, None), ("time_us", 1_000_000, None)],
)
def test_a_microcontroller_log_with_short_columns_and_a_timestamp_reads_in_seconds(tmp_path, header, scale, unit):
    """ax..gz columns (in g and deg/s, given) are an IMU table; its time column named in ms or us, or a bare
    timestamp whose unit its intervals tell (a rate of 4-4000 Hz), reads as seconds."""
    rec = make_imu_walk(duration_s=3.0).recording
    p = tmp_path / "log.csv"
    _log(p, header, np.round(rec.time_s * scale).astype(int), rec)
    assert is_imu_file(p)
    back = read_imu(p, acc_unit="g", gyr_unit="deg_s")
    assert np.allclose(back.time_s, rec.time_s) and back.rate_hz == pytest.approx(100.0)
    assert np.allclose(back.acc_mps2, rec.acc_mps2, atol=1e-3) and np.allclose(back.gyr_rad_s, rec.gyr_rad_s, atol=1e-3)
    assert back.metadata.get("time_unit") == (f"{header} in {unit}" if unit else None)


def test_a_timestamp_whose_unit_no_rate_explains_names_the_options(tmp_path):
    """A bare timestamp stepping by 1e9 (no unit gives a rate of 4-4000 Hz) is one line naming the columns
    and the option that settle it."""
    rec = make_imu_walk(duration_s=1.0).recording
    p = tmp_path / "log.csv"
    _log(p, "timestamp", np.arange(rec.time_s.size) * 10**9, rec)
    with pytest.raises(InputError, match=r"unit of its timestamp column is unclear .* time_ms .*\(--capture-rate-hz"):
        read_imu(p, acc_unit="g", gyr_unit="deg_s")


@pytest.mark.parametrize("separator", ["\t", " "])
def test_a_text_log_of_imu_columns_reads_as_the_csv_does(tmp_path, separator):
    """A .txt log with ax..gz columns separated by tabs or spaces (a serial monitor saved to a file) reads as the
    same log with commas does, not as an Xsens export."""
    rec = make_imu_walk(duration_s=2.0).recording
    csv_path = tmp_path / "log.csv"
    _log(csv_path, "timestamp", np.round(rec.time_s * 1000).astype(int), rec)
    txt_path = tmp_path / "log.txt"
    txt_path.write_text(csv_path.read_text().replace(",", separator))
    a, b = (read_imu(p, acc_unit="g", gyr_unit="deg_s") for p in (csv_path, txt_path))
    assert np.array_equal(a.time_s, b.time_s) and np.array_equal(a.acc_mps2, b.acc_mps2)
    assert np.array_equal(a.gyr_rad_s, b.gyr_rad_s)
