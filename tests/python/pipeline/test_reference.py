"""The reference of the evaluation on real data: steps that survive a missed or doubled contact, the file's own
gait events, slow walking, and the quality that says whether the reference can be trusted."""

from __future__ import annotations

import numpy as np
import pytest

import yoyogait.io as yio
from builders import STEP_M, stepping_walk
from yoyogait.io.body import find_foot_groups
from yoyogait.pipeline import events
from yoyogait.pipeline.velocities import gait_velocities


def _walk(**kw):
    """A stepping walk and its contact times (the builder's trailing placeholder contact left out)."""
    rec, contacts = stepping_walk(**kw)
    return rec, contacts[contacts > 0]


def _with_events(rec, contacts, sides=None):
    sides = sides or ["left" if k % 2 == 0 else "right" for k in range(len(contacts))]
    rec.metadata["events"] = [(s, "foot strike", float(t)) for s, t in zip(sides, contacts)]
    return rec


def _quality(rec, ev):
    vel = gait_velocities(rec, rate_hz=25.0)
    return events.reference_quality(ev, vel.time_s, vel.vz, vel.rate_hz)


def test_a_missed_contact_does_not_halve_the_step_frequency():
    """One foot strike left out of the file's events: the reference stays at 1.8 Hz (a stride is two steps)."""
    rec, contacts = _walk(step_hz=1.8, walk_s=6.0)
    kept = np.delete(contacts, 5)
    sides = ["left" if k % 2 == 0 else "right" for k in range(len(contacts))]
    del sides[5]
    ev = events.file_gait_events(_with_events(rec, kept, sides))
    f = ev.step_frequency_at(rec.time_s, stride_average=True)
    inside = (rec.time_s > contacts[1]) & (rec.time_s < contacts[-2])
    assert np.nanmin(f[inside]) == pytest.approx(1.8, abs=0.05) and np.nanmax(f[inside]) == pytest.approx(1.8, abs=0.05)
    assert len(ev.step_start_s) == len(contacts) - 1


def test_a_doubled_contact_is_dropped():
    """An extra strike 0.1 s after a real one is dropped (and counted); the step frequency stays 1.8 Hz."""
    rec, contacts = _walk(step_hz=1.8, walk_s=6.0)
    doubled = np.sort(np.append(contacts, contacts[4] + 0.1))
    sides = ["left" if k % 2 == 0 else "right" for k in range(len(contacts))]
    sides.insert(5, "right")
    ev = events.file_gait_events(_with_events(rec, doubled, sides))
    assert ev.dropped_contacts == 1
    f = ev.step_frequency_at(rec.time_s, stride_average=True)
    assert np.nanmax(np.abs(f - 1.8)) < 0.05


def test_a_break_in_the_steps_is_left_out_and_counted():
    """Strikes 0.8 s late from the sixth on (a hesitation or two misplaced contacts): the interval is no step, the
    reference is NaN there and the break is counted as a gap."""
    rec, contacts = _walk(step_hz=1.8, walk_s=6.0)
    late = np.where(np.arange(len(contacts)) >= 6, contacts + 0.8, contacts)
    late = late[late < rec.time_s[-1]]
    ev = events.file_gait_events(_with_events(rec, late))
    q = _quality(rec, ev)
    f = ev.step_frequency_at(rec.time_s)
    assert q.gaps == 1 and "1 gap left out" in q.summary()
    assert np.all(np.isnan(f[(rec.time_s > late[5] + 0.05) & (rec.time_s < late[6] - 0.05)]))


def test_detected_contacts_survive_a_marker_gap():
    """A heel marker lost over one contact: the contacts of the foot markers still give 1.8 Hz throughout."""
    rec, contacts = _walk(step_hz=1.8, walk_s=6.0)
    i = rec.point_names.index("LHEE")
    lost = (rec.time_s > contacts[4] - 0.15) & (rec.time_s < contacts[4] + 0.15)
    rec.positions_m[lost, i] = np.nan
    ev = events.detect_gait_events(rec, max_gap_s=0.05)
    f = ev.step_frequency_at(rec.time_s, stride_average=True)
    inside = (rec.time_s > contacts[1]) & (rec.time_s < contacts[-2])
    assert np.nanmax(np.abs(f[inside] - 1.8)) < 0.06


def test_very_slow_walking_is_walking():
    """0.45 steps/s (0.32 m/s): contacts, steps and walking are found, the walk from its start to its end."""
    rec, contacts = _walk(step_hz=0.45, stand_before_s=2.0, walk_s=14.0, stand_after_s=2.0)
    assert 0.3 <= 0.45 * STEP_M <= 0.35
    ev = events.detect_gait_events(rec)
    assert len(ev.step_start_s) >= 4 and ev.mean_step_frequency_hz == pytest.approx(0.45, abs=0.02)
    assert ev.walking_time_s >= 12.0


def test_the_files_own_events_are_the_reference():
    """Foot strikes a file holds are the reference (origin 'file events'), not the contacts found from the feet."""
    rec, contacts = _walk(step_hz=1.8, walk_s=6.0)
    ev = events.reference_events(_with_events(rec, contacts + 0.02))
    assert ev.origin == "file events" and ev.contacts_s == pytest.approx(contacts + 0.02)
    rec.metadata.pop("events")
    assert events.reference_events(rec).origin == "foot contacts"


def test_nexus_events_reach_the_reference(tmp_path):
    """A Nexus CSV's Events section gives the reference (read through yoyogait.io.read)."""
    rec, contacts = _walk(step_hz=1.8, walk_s=5.0)
    names = rec.point_names
    head = ["", ""] + [c for n in names for c in (f"S:{n}", "", "")]
    lines = ["Events", "Subject,Context,Name,Time (s),Description"]
    lines += [f"S,{'Left' if k % 2 == 0 else 'Right'},Foot Strike,{t:.3f}," for k, t in enumerate(contacts)]
    lines += [
        "",
        "Trajectories",
        "100",
        ",".join(head),
        ",".join(["Frame", "Sub Frame"] + ["X", "Y", "Z"] * len(names)),
    ]
    lines.append(",," + ",".join(["mm"] * 3 * len(names)))
    for f, frame in enumerate(rec.positions_m * 1000.0):
        lines.append(f"{f + 1},0," + ",".join(f"{v:.2f}" for v in frame.ravel()))
    path = tmp_path / "trial.csv"
    path.write_text("\n".join(lines) + "\n")
    ev = events.reference_events(yio.read(path))
    assert ev.origin == "file events" and ev.contacts_s == pytest.approx(contacts, abs=1e-3)


def test_a_clean_walk_is_trusted_and_says_so():
    """A clean walk's reference is trusted: its cadence, the feet and the DFT agree."""
    rec, _ = _walk(step_hz=1.8, walk_s=6.0)
    ev = events.detect_gait_events(rec)
    q = _quality(rec, ev)
    assert q.trusted and q.reason == "" and q.steps >= 8
    assert q.cadence_hz == pytest.approx(1.8, abs=0.02) and q.dft_disagreement_hz <= events.MAX_DFT_DISAGREEMENT_HZ
    assert q.summary().startswith("trusted: foot contacts")


def test_a_reference_against_the_pelvis_is_not_trusted():
    """Strikes at 1.4 Hz on a body that steps at 1.8 Hz: not trusted, the DFT named in the reason."""
    rec, _ = _walk(step_hz=1.8, walk_s=6.0)
    wrong = 2.0 + np.arange(9) / 1.4
    q = _quality(rec, events.file_gait_events(_with_events(rec, wrong)))
    assert not q.trusted and "DFT of the vertical velocity 1.80 Hz" in q.reason


def test_few_steps_are_not_trusted():
    """Three steps are too few to trust, whatever they agree with."""
    rec, contacts = _walk(step_hz=1.8, walk_s=6.0)
    q = _quality(rec, events.file_gait_events(_with_events(rec, contacts[:4])))
    assert not q.trusted and "3 steps, fewer than 4" in q.reason


def test_heel_markers_come_first_and_malleoli_are_feet():
    """Heel before ankle before toe, whatever the order of the file; 'l mall' and 'R.Heel.Bottom' are feet."""
    groups = find_foot_groups(["LTOE", "LMT5", "LHEE", "l mall", "RTOE", "R.Heel.Bottom"])
    assert groups == {"left": ["LHEE", "l mall", "LTOE", "LMT5"], "right": ["R.Heel.Bottom", "RTOE"]}


def test_c3d_event_group_is_the_reference(tmp_path):
    """A C3D whose EVENT group holds Vicon foot strikes (minutes, seconds; contexts Left/Right) and Motion
    Analysis-style ones (context 'RHS') gives them as the reference, on the recording's clock."""
    import ezc3d

    rec, contacts = _walk(step_hz=1.8, walk_s=5.0)
    c = ezc3d.c3d()
    data = np.ones((4, len(rec.point_names), rec.n_frames))
    data[:3] = np.transpose(np.nan_to_num(rec.positions_m * 1000.0), (2, 1, 0))
    c["parameters"]["POINT"]["RATE"]["value"] = [rec.rate_hz]
    c["parameters"]["POINT"]["LABELS"]["value"] = rec.point_names
    c.add_parameter("POINT", "UNITS", ["mm"])
    c["data"]["points"] = data
    n = len(contacts)
    labels = ["Foot Strike" if k % 2 == 0 else "" for k in range(n)]
    sides = ["Left" if k % 2 == 0 else "RHS" for k in range(n)]
    c.add_parameter("EVENT", "USED", [n])
    c.add_parameter("EVENT", "LABELS", labels)
    c.add_parameter("EVENT", "CONTEXTS", sides)
    c.add_parameter("EVENT", "TIMES", np.array([[0.0] * n, list(contacts)]))
    path = tmp_path / "walk.c3d"
    c.write(str(path))
    read = yio.read(path)
    strikes = [(side, t) for side, kind, t in read.metadata["events"] if kind == "foot strike"]
    assert [s for s, _ in strikes] == ["left" if k % 2 == 0 else "right" for k in range(n)]
    assert [t for _, t in strikes] == pytest.approx(contacts, abs=1e-4)
    ev = events.reference_events(read)
    assert ev.origin == "file events" and len(ev.step_start_s) == n - 1
