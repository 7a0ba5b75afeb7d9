"""The APDM / Opal .h5 reader: format 5 and formats 3-4 written from the documented layout, the lower-back sensor
found by label, units checked; bad files one line naming the file and what was expected."""

from __future__ import annotations

import numpy as np
import pytest

from yoyogait.cli import main
from yoyogait.errors import InputError
from yoyogait.estimators.imu import ImuReason
from yoyogait.io.imu_read import is_imu_file, read_imu
from yoyogait.io.imu_recording import GRAVITY_MPS2, ImuRecording
from yoyogait.synthetic_imu import make_imu_walk

h5py = pytest.importorskip("h5py")

START_US = 1_613_580_062_915_052  # microseconds since 1970, as APDM's Time holds them


def _other(rec, seed=1):
    """A second sensor's signals (a foot: not the lower back)."""
    rng = np.random.default_rng(seed)
    return rec.acc_mps2 + rng.normal(0, 1, rec.acc_mps2.shape), rec.gyr_rad_s * 3.0


def write_apdm_v5(
    path, rec, labels=("Lumbar", "Left Foot"), acc_units="m/s^2", gyr_units="rad/s", transpose=False, real=0
):
    """An APDM format-5 file: /Sensors/<id>/{Accelerometer, Gyroscope, Magnetometer, Time}, Configuration attrs;
    sensor ``real`` holds ``rec``'s signals, the others another sensor's."""
    with h5py.File(path, "w") as f:
        f.attrs["FileFormatVersion"] = np.int32(5)
        stamps = (START_US + np.round(rec.time_s * 1e6)).astype(np.uint64)
        for k, label in enumerate(labels):
            g = f.create_group(f"Sensors/{1000 + k}")
            acc, gyr = (rec.acc_mps2, rec.gyr_rad_s) if k == real else _other(rec, k)
            a = g.create_dataset("Accelerometer", data=acc.T if transpose else acc)
            a.attrs["Units"] = np.bytes_(acc_units)
            w = g.create_dataset("Gyroscope", data=gyr.T if transpose else gyr)
            w.attrs["Units"] = np.bytes_(gyr_units)
            g.create_dataset("Magnetometer", data=np.tile([20.0, 0.0, -40.0], (rec.n_samples, 1)))
            g.create_dataset("Time", data=stamps)
            conf = g.create_group("Configuration")
            conf.attrs["Label 0"] = np.bytes_(label)
            conf.attrs["Sample Rate"] = np.uint16(round(rec.rate_hz))
            f.create_group(f"Processed/{1000 + k}")


def write_apdm_v4(path, rec, labels=("Sacrum", "Right Foot"), real=0, lists="attributes"):
    """An APDM format-3/4 file: the root's CaseIdList and MonitorLabelList (``lists`` "attributes", or "datasets"
    as older writers have them), /<case>/Calibrated/{Accelerometers, Gyroscopes}; case ``real`` holds ``rec``'s
    signals."""
    with h5py.File(path, "w") as f:
        f.attrs["FileFormatVersion"] = np.int32(4)
        cases = [f"SI-{k:06d}" for k in range(len(labels))]
        if lists == "attributes":
            f.attrs["CaseIdList"] = np.array([c + "  " for c in cases], dtype="S")  # space-padded: stripped
            f.attrs["MonitorLabelList"] = np.array(labels, dtype="S")
        else:
            f.create_dataset("CaseIdList", data=np.array(cases, dtype="S"))
            f.create_dataset("MonitorLabelList", data=np.array(labels, dtype="S"))
        for k, case in enumerate(cases):
            acc, gyr = (rec.acc_mps2, rec.gyr_rad_s) if k == real else _other(rec, k)
            g = f.create_group(case)
            g.attrs["SampleRate"] = np.float64(rec.rate_hz)
            g.create_dataset("Calibrated/Accelerometers", data=acc)
            g.create_dataset("Calibrated/Gyroscopes", data=gyr)
            g.create_dataset("Time", data=(START_US + np.round(rec.time_s * 1e6)).astype(np.uint64))


@pytest.fixture(scope="module")
def walk():
    return make_imu_walk(duration_s=8.0).recording


def test_format_5_reads_the_lumbar_sensor_with_its_time_and_rate(tmp_path, walk):
    """Format 5: the sensor labelled Lumbar (not the foot), its signals, Time in microseconds from 0, the rate."""
    p = tmp_path / "opal.h5"
    write_apdm_v5(p, walk, labels=("Left Foot", "Lumbar"), real=1)  # the lower back second: found by label
    assert is_imu_file(p)
    rec = read_imu(p)
    assert rec.metadata["sensor"] == "Lumbar" and rec.metadata["sensor_id"] == "1001"
    assert rec.rate_hz == pytest.approx(walk.rate_hz)
    np.testing.assert_allclose(rec.time_s, walk.time_s, atol=1e-6)
    np.testing.assert_allclose(rec.gyr_rad_s, walk.gyr_rad_s)


def test_format_5_lumbar_first_equals_the_written_signals(tmp_path, walk):
    """The lower-back sensor's acceleration and angular rate are those written (m/s^2, rad/s), stored N x 3 or 3 x N."""
    for transpose in (False, True):
        p = tmp_path / f"opal{transpose}.h5"
        write_apdm_v5(p, walk, transpose=transpose)
        rec = read_imu(p)
        np.testing.assert_allclose(rec.acc_mps2, walk.acc_mps2)
        np.testing.assert_allclose(rec.gyr_rad_s, walk.gyr_rad_s)


@pytest.mark.parametrize("lists", ["attributes", "datasets"])
def test_formats_3_and_4_read_calibrated_data_by_monitor_label(tmp_path, walk, lists):
    """Formats 3/4: CaseIdList and MonitorLabelList (root attributes, or datasets) find the Sacrum sensor; its
    Calibrated data, Time and SampleRate."""
    p = tmp_path / "old.h5"
    write_apdm_v4(p, walk, labels=("Right Foot", "Sacrum"), real=1, lists=lists)
    rec = read_imu(p)
    assert rec.metadata["sensor"] == "Sacrum" and rec.metadata["layout"] == "apdm v4"
    assert rec.rate_hz == pytest.approx(walk.rate_hz)
    np.testing.assert_allclose(rec.time_s, walk.time_s, atol=1e-6)
    np.testing.assert_allclose(rec.acc_mps2, walk.acc_mps2)
    np.testing.assert_allclose(rec.gyr_rad_s, walk.gyr_rad_s)


def test_sensor_option_picks_another_sensor_and_an_unknown_one_lists_the_sensors(tmp_path, walk):
    """sensor= by label or id; an unknown one: one line naming the option and every sensor present."""
    p = tmp_path / "opal.h5"
    write_apdm_v5(p, walk, labels=("Lumbar", "Left Foot"))
    assert read_imu(p, sensor="left foot").metadata["sensor_id"] == "1001"
    assert read_imu(p, sensor="1000").metadata["sensor"] == "Lumbar"
    with pytest.raises(InputError, match=r"no sensor 'Sternum' \(sensor=, --sensor\); the file has Lumbar \(1000\), "
                                         r"Left Foot \(1001\)"):  # fmt: skip
        read_imu(p, sensor="Sternum")


def test_no_lower_back_label_among_several_sensors_asks_for_the_option(tmp_path, walk):
    """Two foot sensors: one line saying no lower-back sensor was found, naming --sensor and the sensors present."""
    p = tmp_path / "feet.h5"
    write_apdm_v5(p, walk, labels=("Left Foot", "Right Foot"))
    with pytest.raises(InputError, match=r"no lower-back sensor by label .*--sensor.*Left Foot \(1000\), Right Foot"):
        read_imu(p)


def test_accelerometer_units_in_g_are_applied_and_wrong_units_are_caught(tmp_path, walk):
    """Units 'g' are scaled to m/s^2; a g signal declared m/s^2 fails the gravity check naming --acc-unit g."""
    g_walk = make_imu_walk(duration_s=8.0).recording
    g_walk.acc_mps2 = walk.acc_mps2 / GRAVITY_MPS2
    p = tmp_path / "g.h5"
    write_apdm_v5(p, g_walk, acc_units="g")
    np.testing.assert_allclose(read_imu(p).acc_mps2, walk.acc_mps2, rtol=1e-12)
    q = tmp_path / "wrong.h5"
    write_apdm_v5(q, g_walk, acc_units="m/s^2")
    with pytest.raises(InputError, match=r"in g\? pass acc_unit g \(--acc-unit g\)"):
        read_imu(q)
    np.testing.assert_allclose(read_imu(q, acc_unit="g").acc_mps2, walk.acc_mps2, rtol=1e-12)


def test_gyro_in_deg_s_declared_rad_s_is_caught_and_deg_s_units_are_applied(tmp_path):
    """A turning walk's rate in deg/s labelled rad/s names --gyr-unit deg_s; labelled deg/s it is scaled."""
    turn = make_imu_walk(None, "3-rectangle", duration_s=12.0).recording
    deg = make_imu_walk(None, "3-rectangle", duration_s=12.0).recording
    deg.gyr_rad_s = turn.gyr_rad_s * 180 / np.pi
    p = tmp_path / "deg.h5"
    write_apdm_v5(p, deg, gyr_units="rad/s")
    with pytest.raises(InputError, match="--gyr-unit deg_s"):
        read_imu(p)
    write_apdm_v5(p, deg, gyr_units="deg/s")
    np.testing.assert_allclose(read_imu(p).gyr_rad_s, turn.gyr_rad_s, rtol=1e-12)


@pytest.mark.parametrize(
    "damage, message",
    [
        ("not hdf5", "not an HDF5 file"),
        ("no sensors", r"no /Sensors group \(APDM format 5\) nor /CaseIdList"),
        ("no gyroscope", "has no gyroscope data"),
        ("2 axes", r"its accelerometer is \d+x2, expected N x 3"),
        ("short time", r"\d+ times for \d+ samples"),
        ("unknown unit", r"unit 'furlong/s\^2' of /Sensors/1000/Accelerometer not understood; pass acc_unit"),
    ],
)
def test_broken_files_are_one_line_naming_the_file_and_what_was_expected(tmp_path, walk, damage, message, capsys):
    """Each broken .h5: InputError naming the file and what was expected; the CLI prints one line and exits 2."""
    p = tmp_path / "bad.h5"
    if damage == "not hdf5":
        p.write_text("hello\n")
    elif damage == "no sensors":
        with h5py.File(p, "w") as f:
            f.create_group("Annotations")
    else:
        write_apdm_v5(p, walk, labels=("Lumbar",))
        with h5py.File(p, "a") as f:
            g = f["Sensors/1000"]
            if damage == "no gyroscope":
                del g["Gyroscope"]
            elif damage == "2 axes":
                del g["Accelerometer"]
                g.create_dataset("Accelerometer", data=walk.acc_mps2[:, :2])
            elif damage == "short time":
                t = g["Time"][()]
                del g["Time"]
                g.create_dataset("Time", data=t[:-5])
            elif damage == "unknown unit":
                g["Accelerometer"].attrs["Units"] = np.bytes_("furlong/s^2")
    with pytest.raises(InputError, match=message) as err:
        read_imu(p)
    assert str(p) in str(err.value)
    assert main(["inspect", str(p)]) == 2
    out = capsys.readouterr().err
    assert len(out.strip().splitlines()) == 1 and str(p) in out and "Traceback" not in out


def test_inspect_and_estimate_an_apdm_file(tmp_path, walk, capsys):
    """inspect names the sensor and finds the cadence; estimate writes one row per sample, valid while walking."""
    p = tmp_path / "opal.h5"
    write_apdm_v5(p, walk, labels=("Left Foot", "Lower Back"), real=1)
    assert main(["inspect", str(p)]) == 0
    out = capsys.readouterr().out
    assert "IMU (apdm v5)" in out and "Lower Back (1001)" in out and "steps/min" in out
    est = tmp_path / "e.csv"
    assert main(["estimate", str(p), "--out", str(est), "--sensor", "Lower Back"]) == 0
    rows = np.genfromtxt(est, delimiter=",", names=True)
    assert rows.shape[0] == walk.n_samples and rows["valid"][-1] == 1
    assert main(["estimate", str(p), "--out", str(tmp_path / "f.csv"), "--sensor", "Chest"]) == 2
    assert "Left Foot (1000), Lower Back (1001)" in capsys.readouterr().err


def _rest(n=1000, rate_hz=100.0):
    """A sensor lying still (x up, the Mobilise-D convention), with sensor noise."""
    rng = np.random.default_rng(3)
    acc = np.tile([GRAVITY_MPS2, 0.0, 0.0], (n, 1)) + rng.normal(0, 0.02, (n, 3))
    return ImuRecording(np.arange(n) / rate_hz, acc, rng.normal(0, 0.002, (n, 3)), rate_hz=rate_hz)


def test_issue_22_bad_input_on_an_apdm_file_is_said_or_flagged_never_a_traceback(tmp_path, capsys):
    """A clipped accelerometer, a sensor worn upside down, a gap, a file at rest: inspect says what it found in
    one line each (saturated, gaps, not valid), estimate flags the samples (SATURATED, GAP, never valid at rest)
    or estimates the walk (upside down); exit 0, no traceback."""
    clipped = make_imu_walk(duration_s=10.0, acc_range_mps2=11.0).recording
    upside = make_imu_walk(duration_s=10.0, upside_down=True).recording
    walk = make_imu_walk(duration_s=10.0).recording
    keep = (walk.time_s < 5.0) | (walk.time_s >= 5.5)
    gap = ImuRecording(walk.time_s[keep], walk.acc_mps2[keep], walk.gyr_rad_s[keep], rate_hz=walk.rate_hz)
    found = {}
    for case, rec in (("clipped", clipped), ("upside", upside), ("gap", gap), ("rest", _rest())):
        p = tmp_path / f"{case}.h5"
        write_apdm_v5(p, rec, labels=("Lumbar",))
        assert main(["inspect", str(p)]) == 0
        out, err = capsys.readouterr()
        assert "Traceback" not in out + err
        est = tmp_path / f"{case}.csv"
        assert main(["estimate", str(p), "--out", str(est)]) == 0
        found[case] = (out, capsys.readouterr().err, np.genfromtxt(est, delimiter=",", names=True))
    out, err, rows = found["clipped"]
    assert "the accelerometer clipped at 11 m/s^2" in out and "SATURATED" in out
    assert f"{tmp_path / 'clipped.h5'}: the accelerometer clipped at 11 m/s^2" in err
    assert not rows["valid"].any() and (rows["reason"] == int(ImuReason.SATURATED)).any()
    out, _, rows = found["upside"]
    assert "steps/min" in out and rows["valid"][-1] == 1
    out, _, rows = found["gap"]
    assert "gaps           1 (longest 0.51 s)" in out
    k = int(np.searchsorted(rows["time_s"], 5.5))
    assert rows["reason"][k] == int(ImuReason.GAP)
    out, _, rows = found["rest"]
    assert "valid          0.00 s" in out and "walking        none found" in out and "steps/min" not in out
    assert "not valid      ACQUIRING" in out or "not valid      NOT_WALKING" in out
    assert not rows["valid"].any()
