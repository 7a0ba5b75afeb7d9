"""The 53 real recordings of ../shared/datasets (eight labs and systems) through readers, points, velocities, events.

The data stay in ../shared; each test takes the ``manifest`` fixture, which
skips with a visible reason when the folder is absent and fails under CI.
Recordings are read once per session.
"""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pytest

import yoyogait
from shared_data import DATASETS
from yoyogait.errors import InputError
from yoyogait.pipeline import events, points, spectral

WALKING = ("straight", "turn")

try:  # the parameter lists come from the manifest; the fixtures decide whether the tests run
    _ENTRIES = json.loads((Path(DATASETS) / "manifest.json").read_text())["recordings"]
except (OSError, ValueError, KeyError):
    _ENTRIES = []


def recordings(walks=None, fmt=None) -> list[str]:
    """Manifest paths (of these walk types / this format); one placeholder when there is no manifest."""
    chosen = [
        r["path"] for r in _ENTRIES if (walks is None or r["walk"] in walks) and (fmt is None or r["format"] == fmt)
    ]
    return chosen or ["(manifest absent)"]


STEP_BAND_HZ = (1.4, 2.6)

# Straight walks whose people really step slower than 1.4 Hz: their foot contacts (and forward
# velocity) say so, and the vertical velocity's strongest peak there is the second harmonic.
STEPS_SLOWER_THAN_BAND = {
    "c3d_org_samples/sample10_TYPE-3.c3d": "slow walk across force plates (0.77 m/s): foot contacts at 1.32 Hz",
    "bandai_namco_motion/dataset-1_walk_proud_001.bvh": "stylised 'proud' walk: foot contacts at 1.27 Hz",
    "bandai_namco_motion/dataset-1_walk_sad_001.bvh": "stylised 'sad' walk: foot contacts at 1.21 Hz",
    "bandai_namco_motion/dataset-1_walk_not-confident_001.bvh": "stylised walk (0.48 m/s): foot contacts at 1.36 Hz",
}


class Loaded:
    """One manifest recording read once: the recording, its velocities, its gait events, its DFT check."""

    def __init__(self, datasets_dir: Path, entry: dict):
        self.entry = entry
        self.recording = yoyogait.read(datasets_dir / entry["path"])
        self.velocities = yoyogait.gait_velocities(self.recording)
        feet = events.feet_of(self.recording)
        self.events = events.detect_gait_events(self.recording) if feet else None
        try:
            self.check = spectral.dft_check(self.velocities)
        except InputError:
            self.check = None


@pytest.fixture(scope="session")
def loaded(datasets_dir, manifest):
    cache: dict[str, Loaded] = {}

    def get(path: str) -> Loaded:
        if path not in cache:
            entry = next(r for r in manifest["recordings"] if r["path"] == path)
            cache[path] = Loaded(datasets_dir, entry)
        return cache[path]

    return get


def test_manifest_lists_every_recording_once(manifest, datasets_dir):
    """The manifest names 53 distinct recordings that exist in ../shared/datasets."""
    paths = [r["path"] for r in manifest["recordings"]]
    assert len(paths) == len(set(paths)) == 53
    assert all((datasets_dir / p).is_file() for p in paths)


@pytest.mark.filterwarnings("ignore:Mean of empty slice", "ignore:All-NaN slice")
@pytest.mark.parametrize("path", recordings())
def test_recording_loads_in_metres(path, loaded):
    """Each recording loads; its pelvis stands 0.6-1.2 m above its lowest point (the unit is right), no C3D zero
    survives."""
    rec = loaded(path).recording
    assert rec.n_frames > 0 and rec.duration_s > 1.5
    axis = "xyz".index(loaded(path).entry["vertical_axis"])
    pelvis = rec.points(loaded(path).entry["pelvis"])[:, :, axis]
    with np.errstate(invalid="ignore"):
        height = np.nanmedian(np.nanmean(pelvis, axis=1) - np.nanmin(rec.positions_m[:, :, axis], axis=1))
    assert 0.6 < height < 1.2, f"pelvis {height:.3f} m above the lowest point"
    if rec.format == "c3d":  # C3D writes an occluded marker as exactly zero: it must have become NaN
        assert not np.any(np.all(rec.positions_m == 0.0, axis=2))


@pytest.mark.parametrize("path", recordings())
def test_detection_finds_the_manifest_pelvis_and_up_axis(path, loaded):
    """Without being told, detection picks the manifest's up axis and its pelvis points (centre within 3 cm)."""
    item = loaded(path)
    rec, entry = item.recording, item.entry
    assert points.detect_up_axis(rec) == entry["vertical_axis"]
    if rec.up_axis is not None:  # the file's own statement agrees as well
        assert rec.up_axis == entry["vertical_axis"]
    found = points.find_pelvis(rec.point_names)
    assert set(entry["pelvis"]) <= set(found.names)
    centre, _ = points.robust_centre(rec.points(found.names))
    reference, _ = points.robust_centre(rec.points(entry["pelvis"]))
    distance = np.linalg.norm(centre - reference, axis=1)
    assert np.nanmedian(distance) < 0.03


#: Foot points the manifest does not list: the foot marker triads (RFT1-3, LFT1-3) of the 1989 clinical file.
FEET_THE_MANIFEST_DOES_NOT_NAME = {
    "c3d_org_samples/sample01_Eb015pr.c3d": {"left": ["LFT1", "LFT2", "LFT3"], "right": ["RFT1", "RFT2", "RFT3"]},
}


@pytest.mark.parametrize("path", recordings())
def test_detection_finds_the_manifest_feet_by_side(path, loaded):
    """Without being told, each recording with manifest feet has a left and a right foot, and every manifest foot
    point that is ever seen is in the foot of its own side; a recording without feet has none."""
    item = loaded(path)
    rec, entry = item.recording, item.entry
    groups = events.foot_groups_of(rec)
    if entry["feet"] is None:
        assert groups == FEET_THE_MANIFEST_DOES_NOT_NAME.get(path, {})
        return
    assert set(groups) == {"left", "right"}
    seen = dict(zip(rec.point_names, rec.visible().mean(axis=0)))
    for name in entry["feet"]:
        side = points.side_of(name)
        assert side in ("left", "right"), name
        if seen[name] > 0:
            assert name in groups[side], f"{name} not in the {side} foot {groups[side]}"
    assert events.foot_groups_of(rec, entry["feet"]).keys() <= {"left", "right"}


# The one treadmill walk (the pelvis stays within 7 cm for 2.5 s). The other "treadmill" entry, HBM, holds no
# walking: the subject stands on the side rails, so its stance feet do not move and it is not called a treadmill.
TREADMILL_WALKS = {"opensim_models/Gait2392_subject01_walk1.trc"}


@pytest.mark.parametrize("path", recordings())
def test_treadmill_is_detected_only_where_a_belt_carries_the_feet(path, loaded):
    """Treadmill walking is detected on the Gait2392 trial only; there the belt (1.0-1.2 m/s) makes the walking
    speed 1.0-1.2 m/s instead of the pelvis's 0.15 m/s; no overground walk is called a treadmill."""
    v = loaded(path).velocities
    assert v.treadmill is not None
    assert v.treadmill.detected == (path in TREADMILL_WALKS), v.treadmill.reason
    if v.treadmill.detected:
        belt_mps = v.treadmill.belt_speed_mps
        assert belt_mps > 1.0 and belt_mps < 1.2, belt_mps
        walking = v.walking & v.finite
        walking_mps = np.mean(v.vx[walking])
        assert walking_mps > 1.0 and walking_mps < 1.2, walking_mps


@pytest.mark.parametrize("path", recordings(fmt="bvh"))
def test_bvh_length_unit_is_inferred_as_in_the_manifest(path, loaded):
    """A BVH's unit, inferred from the pelvis height, is the manifest's length_unit_m (cm, or CMU's 0.0564 m)."""
    rec = loaded(path).recording
    assert rec.metadata["length_unit_m"] == pytest.approx(loaded(path).entry["length_unit_m"], rel=1e-6)
    assert rec.metadata["length_unit_from"].startswith("inferred")


@pytest.mark.parametrize("path", recordings())
def test_velocities_are_finite_over_the_walking_part(path, loaded):
    """Over walking, >= 90 % of velocity samples are known; straight and turning walks give >= 1.5 s of
    plausible velocity."""
    item = loaded(path)
    v = item.velocities
    if v.walking.any():
        assert np.mean(v.finite[v.walking]) >= 0.9
    if item.entry["walk"] in WALKING:
        part = v.walking_part()
        assert (part.stop - part.start) / v.rate_hz >= 1.5
        assert np.all(np.isfinite(v.vx[part])) and np.all(np.isfinite(v.vz[part]))
        assert 0.2 < np.mean(v.vx[part]) < 2.5 and np.max(np.abs(v.vz[part])) < 1.0


def _band_param(path):
    reason = STEPS_SLOWER_THAN_BAND.get(path)
    return pytest.param(path, marks=pytest.mark.xfail(strict=True, reason=reason)) if reason else path


@pytest.mark.parametrize("path", [_band_param(p) for p in recordings(WALKING)])
def test_vertical_velocity_peak_is_a_walking_step_frequency(path, loaded):
    """For straight and turning walks the pelvis vertical-velocity peak (its fundamental) lies in 1.4-2.6 Hz."""
    item = loaded(path)
    assert item.check is not None
    assert STEP_BAND_HZ[0] <= item.check.step_frequency_hz <= STEP_BAND_HZ[1]


@pytest.mark.parametrize("path", recordings(["straight"]))
def test_foot_contacts_agree_with_the_vertical_velocity_spectrum(path, loaded):
    """On straight walks the mean step frequency from foot contacts is within 0.1 Hz of the vertical-velocity DFT."""
    item = loaded(path)
    assert item.events is not None and len(item.events.step_start_s) >= 3
    assert item.check is not None
    assert abs(item.events.mean_step_frequency_hz - item.check.step_frequency_hz) <= 0.1
