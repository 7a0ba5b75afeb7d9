"""``yoyogait inspect`` over every motion file in ../shared/datasets (recordings and export samples), without
overrides: each is read, or refused with one line that says precisely why."""

from __future__ import annotations

import re
from pathlib import Path

import pytest

from shared_data import DATASETS
from yoyogait.cli import main
from yoyogait.io import READERS

try:  # the parameter list comes from the folder; the fixtures decide whether the tests run
    _FILES = sorted(
        str(p.relative_to(DATASETS)) for p in Path(DATASETS).rglob("*") if p.is_file() and p.suffix.lower() in READERS
    )
except OSError:
    _FILES = []

#: Files that cannot be inspected, and the reason the one error line must give.
REFUSED = {
    "addbiomechanics/Camargo2021_levelground_ccw_fast_01_01_grf.mot": r"ground-reaction forces .* no positions",
    "addbiomechanics/treadmill_HBM_initial_off_treadmill_grf.mot": r"ground-reaction forces .* no positions",
    "formats/optitrack_motive_csv/test_default.csv": r"Motive CSV export \(format 1\.23\) with no marker",
    "formats/trc_comma/pyomeca_markers.trc": r"truncated TRC file: the header announces 652 frames, the file holds 93",
}
#: The lower-back IMU tables (acc_x..gyr_z, no positions) are read by the IMU readers: inspect reports
#: them (rate, gravity, the online IMU estimate); none is refused.
IMU_TABLES = [
    f"imu_mobgap/example_data/data_csv/{who}/TimeMeasure1_{test}.csv"
    for who in ("HA/001", "HA/002", "MS/001")
    for test in ("Test11_Trial1", "Test5_Trial1", "Test5_Trial2")
]


def test_every_shared_motion_file_is_listed(datasets_dir):
    """The folder holds the 53 manifest recordings, 5 export samples, 2 force files and 9 IMU tables (69 files)."""
    assert len(_FILES) == 69
    assert set(REFUSED) <= set(_FILES)
    assert set(IMU_TABLES) <= set(_FILES) and not set(IMU_TABLES) & set(REFUSED)


@pytest.mark.filterwarnings("ignore:Mean of empty slice", "ignore:All-NaN slice")
@pytest.mark.parametrize("path", _FILES or ["(datasets absent)"])
def test_inspect_reads_it_or_says_precisely_why_not(path, datasets_dir, capsys):
    """inspect exits 0 with a report, or (for the listed files only) exits 2 with one line giving the reason."""
    code = main(["inspect", str(datasets_dir / path)])
    out, err = capsys.readouterr()
    if path in REFUSED:
        assert code == 2 and out == ""
        assert len(err.strip().splitlines()) == 1 and re.search(REFUSED[path], err), err
    else:
        assert code == 0, err
        assert out.startswith("file") and "walking" in out and "Traceback" not in err
