"""Motion-BIDS: a *_motion.tsv with its *_channels.tsv and *_motion.json, written here in the layouts the
specification and the tools that write it use."""

from __future__ import annotations

import json

import numpy as np
import pytest

import yoyogait.io as yio
from builders import stepping_walk
from yoyogait.cli import main
from yoyogait.errors import InputError

MARKERS = ("LASI", "RASI", "SACR", "LHEE", "RHEE")
TRACKED = {"LASI": "pelvis", "RASI": "pelvis", "SACR": "pelvis", "LHEE": "left_heel", "RHEE": "right_heel"}


def _write(folder, prefix="sub-01_task-walk_tracksys-omc", *, motion_suffix=True, units="mm", rate_in="json",
           latency=False, component=True):  # fmt: skip
    """A stepping walk as Motion-BIDS files; returns (data file, the walk's positions in m, its contacts)."""
    rec, contacts = stepping_walk(stand_before_s=0.5, walk_s=4.0, stand_after_s=0.5)
    pos = rec.positions_m[:, [rec.index_of(n) for n in MARKERS], :]
    scale = {"m": 1.0, "cm": 100.0, "mm": 1000.0}[units]
    head = ["name", "component", "type", "tracked_point", "units"] if component else ["name", "type", "tracked_point",
                                                                                      "units"]  # fmt: skip
    if rate_in == "channels":
        head.append("sampling_frequency")
    rows, columns = [], []
    if latency:
        rows.append(["LATENCY", "n/a", "LATENCY", "n/a", "s"][: 2 if component else 1] + ["LATENCY", "n/a", "s"])
        columns.append(rec.time_s + 12.5)
    for k, n in enumerate(MARKERS):
        for a, axis in enumerate("xyz"):
            row = [f"{n}_Pos{axis.upper()}"] + ([axis] if component else []) + ["POS", TRACKED[n], units]
            rows.append(row)
            columns.append(pos[:, k, a] * scale)
    if rate_in == "channels":
        rows = [r + ["100"] for r in rows]
    (folder / f"{prefix}_channels.tsv").write_text("\n".join("\t".join(r) for r in [head, *rows]) + "\n")
    if rate_in == "json":
        (folder / f"{prefix}_motion.json").write_text(json.dumps({"SamplingFrequency": 100, "TaskName": "walk"}))
    data = np.column_stack(columns)
    lines = ["\t".join("n/a" if not np.isfinite(v) else f"{v:.6f}" for v in row) for row in data]
    path = folder / (f"{prefix}_motion.tsv" if motion_suffix else f"{prefix}.tsv")
    path.write_text("\n".join(lines) + "\n")
    return path, pos, contacts


@pytest.mark.parametrize(
    "options",
    [{}, {"motion_suffix": False, "rate_in": "channels", "units": "m"}, {"units": "cm", "latency": True},
     {"component": False}],
    ids=["spec", "channels-rate", "latency-cm", "no-component"],
)  # fmt: skip
def test_motion_bids_points_are_read_in_metres_named_as_markers(tmp_path, options):
    """Each tracked point's x, y, z POS channels are a point named by its channels (LHEE_PosX -> LHEE), in metres
    from the channels' units, at the rate of the channels or the JSON sidecar, or timed by a LATENCY channel."""
    path, pos, _ = _write(tmp_path, **options)
    rec = yio.read(path)
    assert rec.metadata["format"] == "motion_bids" and list(rec.point_names) == list(MARKERS)
    assert np.allclose(rec.positions_m, pos, atol=2e-6, equal_nan=True)
    assert rec.rate_hz == 100.0
    assert np.allclose(np.diff(rec.time_s), 0.01, atol=1e-9) and rec.time_s[0] == 0.0
    assert rec.metadata["tracked_points"]["LHEE"] == "left_heel"


def test_motion_bids_walk_through_inspect_finds_pelvis_feet_and_cadence(tmp_path, capsys):
    """inspect on a Motion-BIDS walk: the format named, the pelvis and the heels found, the step frequency."""
    path, _, contacts = _write(tmp_path)
    assert main(["inspect", str(path)]) == 0
    out = capsys.readouterr().out
    assert "MOTION_BIDS" in out and "pelvis centre of LASI, RASI, SACR" in out and "left LHEE, right RHEE" in out
    f = 1.0 / float(np.median(np.diff(np.sort(contacts))))
    assert f"{f:.2f} Hz" in out


def test_motion_bids_without_a_rate_or_with_a_bad_row_is_one_line(tmp_path):
    """No sampling frequency anywhere: one line naming --capture-rate-hz; a row with another count of values, or a
    value that is not a number: one line naming the file and the line."""
    path, _, _ = _write(tmp_path, rate_in="none")
    with pytest.raises(InputError, match=r"no sampling frequency .* pass capture_rate_hz \(--capture-rate-hz\)"):
        yio.read(path)
    assert yio.read(path, capture_rate_hz=100.0).rate_hz == 100.0
    lines = path.read_text().splitlines()
    path.write_text("\n".join(lines[:10] + [lines[10] + "\t1.0"] + lines[11:]) + "\n")
    with pytest.raises(InputError, match=r"line 11 holds 16 values, but .*_channels.tsv lists 15 channels"):
        yio.read(path, capture_rate_hz=100.0)
    bad = lines[10].split("\t")
    bad[3] = "abc"
    path.write_text("\n".join(lines[:10] + ["\t".join(bad)] + lines[11:]) + "\n")
    with pytest.raises(InputError, match=r"line 11: 'abc' is not a number"):
        yio.read(path, capture_rate_hz=100.0)


def test_a_tsv_without_channels_beside_it_is_still_read_as_qtm(tmp_path):
    """Only a _channels.tsv beside it makes a .tsv Motion-BIDS: without one the QTM reader says what it expects."""
    path, _, _ = _write(tmp_path)
    (tmp_path / "sub-01_task-walk_tracksys-omc_channels.tsv").unlink()
    with pytest.raises(InputError, match="not a QTM TSV export"):
        yio.read(path)
