"""Plausibility after reading: a body off by a unit factor, a wrong up axis or a pelvis faster than anyone is one
error line naming the cause and the option that fixes it; real people pass."""

from __future__ import annotations

import numpy as np
import pytest

import yoyogait
from builders import write_trc_positions as write_trc
from yoyogait.errors import InputError
from yoyogait.io.plausibility import body_measures


def _walker_mm(n=300, rate_hz=100.0):
    """Pelvis markers 0.95 m up walking at 1.2 m/s, heels on the floor (mm, z up)."""
    t = np.arange(n) / rate_hz
    pelvis = np.column_stack([1200.0 * t, np.zeros(n), 950.0 + 20 * np.sin(2 * np.pi * 1.8 * t)])
    offsets = {"LASI": (100, 120, 0), "RASI": (100, -120, 0), "SACR": (-100, 0, 0)}
    heels = {"LHEE": (0, 100, -900), "RHEE": (0, -100, -900)}
    pos = np.stack([pelvis + np.array(o) for o in {**offsets, **heels}.values()], axis=1)
    return pos, list(offsets) + list(heels)


@pytest.mark.parametrize(
    "units, message",
    [
        ("m", r"spans 900 m .*Units = m.* look like mm: pass --length-unit-m 0.001"),
        ("cm", r"spans 9 m .*Units = cm.* look like mm: pass --length-unit-m 0.001"),
    ],
)
def test_trc_with_the_wrong_unit_is_refused_naming_the_fix(tmp_path, units, message):
    """A TRC holding mm whose header says m (or cm) is refused: the size, the unit said, the fix (--length-unit-m)."""
    pos, names = _walker_mm()
    path = write_trc(tmp_path / "walk.trc", pos, names, units=units)
    with pytest.raises(InputError, match=message):
        yoyogait.read(path)
    rec = yoyogait.read(path, length_unit_m=0.001)
    assert body_measures(rec, "z")["speed_mps"] == pytest.approx(1.2, rel=0.01)
    assert yoyogait.read(path, plausibility=False).metadata["length_unit_m"] == {"m": 1.0, "cm": 0.01}[units]


def test_wrong_up_axis_is_refused_naming_the_axis(tmp_path):
    """A stated up axis along which the pelvis is near the floor, while another axis puts it 0.9 m up, is refused."""
    pos, names = _walker_mm()
    path = write_trc(tmp_path / "walk.trc", pos, names, units="mm")
    assert yoyogait.read(path, up_axis="z").metadata["plausibility"]["pelvis_height_m"] == pytest.approx(0.9, abs=0.02)
    with pytest.raises(InputError, match=r"up axis y \(from --up-axis\) .* z puts it 0.90 m.*pass --up-axis z"):
        yoyogait.read(path, up_axis="y")


def test_a_pelvis_faster_than_a_person_is_refused(tmp_path):
    """A pelvis alone (no size to judge) moving at 1200 m/s is refused naming --length-unit-m and --capture-rate-hz."""
    t = np.arange(300) / 100
    path = tmp_path / "pelvis.csv"
    path.write_text("time_s,LASI_x,LASI_y,LASI_z\n" + "".join(f"{a},{1200 * a},0,950\n" for a in t))
    with pytest.raises(InputError, match=r"faster than a person: .* 1200.00 m/s.*length-unit-m 0.001.*capture-rate"):
        yoyogait.read(path)


def test_a_sprinter_is_refused_as_a_sprint_not_as_faster_than_a_person(tmp_path):
    """A body of a person's size whose pelvis moves at 9.5 m/s is refused as a sprint, naming --capture-rate-hz."""
    pos, names = _walker_mm()
    pos[..., 0] *= 9.5 / 1.2  # the same body, 9.5 m/s forward
    path = write_trc(tmp_path / "sprint.trc", pos, names, units="mm")
    with pytest.raises(InputError, match=r"faster than anyone walks: .* 9.50 m/s.*a sprint.*capture-rate-hz") as err:
        yoyogait.read(path)
    assert "faster than a person" not in str(err.value)


def test_a_plausible_walker_passes_and_its_measures_are_kept(tmp_path):
    """A walker in mm labelled mm reads; the measures (size, pelvis height, speed) are in the metadata."""
    pos, names = _walker_mm()
    rec = yoyogait.read(write_trc(tmp_path / "walk.trc", pos, names, units="mm"))
    measures = rec.metadata["plausibility"]
    assert measures["size_m"] == pytest.approx(0.9, abs=0.02) and measures["speed_mps"] < 2.0
