"""Small recordings and files the tests of several stages build: a stepping walk, a camera-like noisy walk,
TRC files, special files (device nodes, FIFOs, sockets)."""

from __future__ import annotations

import dataclasses
import os
import socket
import stat
from pathlib import Path

import ezc3d
import numpy as np
import pytest

from yoyogait import synthetic
from yoyogait.io import Recording

STEP_M = 0.7


def camera_walk(seed: int, depth_jitter_m: float):
    """(walk, recording): a SYNTHETIC lab walk at 60 Hz seen as a camera sees it: 2 mm everywhere and jitter
    correlated over 50 ms along one horizontal axis (the camera's depth), as video keypoints have it."""
    from yoyogait import synthetic as sy
    from yoyogait import synthetic_conditions as sc

    walk = sy.make_walk(sy.SUBJECTS[seed % 3], "1-straight", rate_hz=60.0, seed=seed, noise_m=0.0, dropouts=False)
    rec = walk.recording
    pos = np.array(rec.positions_m)
    rng = np.random.default_rng(seed)
    depth = [a for a in range(3) if a != "xyz".index(rec.up_axis)][0]
    pos += rng.normal(0.0, 0.002, pos.shape)
    pos[:, :, depth] += depth_jitter_m * sc._correlated(rng, pos.shape[:2], 60.0, 0.05)
    return walk, dataclasses.replace(rec, positions_m=pos)


def stepping_walk(
    step_hz=1.8,
    stand_before_s=2.0,
    walk_s=5.0,
    stand_after_s=2.0,
    rate_hz=100.0,
    treadmill=False,
    radius_m=None,
    later_step_hz=None,
):
    """A person who stands, walks and stands, with heels that really step (z up).

    The number of steps taken so far, ``s(t)``, is the integral of the step
    frequency; everything is a function of it, so standing freezes the body.
    Foot contacts happen at whole ``s`` (left on even, right on odd); each
    foot is still in stance and swings forward 2 steps during the last 40 %
    of its stride.  ``later_step_hz`` changes the frequency half way through
    the walk; ``radius_m`` bends the path into a circle; ``treadmill`` removes
    the forward progression.  Returns the recording and the contact times.
    """
    n = int((stand_before_s + walk_s + stand_after_s) * rate_hz)
    t = np.arange(n) / rate_hz
    f = np.where((t >= stand_before_s) & (t < stand_before_s + walk_s), step_hz, 0.0)
    if later_step_hz is not None:
        f[(t >= stand_before_s + walk_s / 2) & (f > 0)] = later_step_hz
    s = np.concatenate([[0.0], np.cumsum(f[:-1]) / rate_hz])
    pelvis_fwd = STEP_M * s
    pelvis_up = 0.95 + 0.02 * np.cos(2 * np.pi * s)

    def foot(first_contact):
        j = np.floor((s - first_contact) / 2)
        local = s - (first_contact + 2 * j)
        planted = STEP_M * (first_contact + 2 * j) + STEP_M / 2
        q = np.clip((local - 1.2) / 0.8, 0, 1)
        fwd = planted + 2 * STEP_M * (1 - np.cos(np.pi * q)) / 2
        return fwd, 0.05 + 0.1 * np.sin(np.pi * q)

    parts = {"pelvis": (pelvis_fwd, 0.0, pelvis_up), "LHEE": (*foot(0),), "RHEE": (*foot(1),)}
    fwd = {"pelvis": pelvis_fwd, "LHEE": parts["LHEE"][0], "RHEE": parts["RHEE"][0]}
    lateral = {"pelvis": 0.02 * np.sin(np.pi * s), "LHEE": 0.1, "RHEE": -0.1}
    up = {"pelvis": pelvis_up, "LHEE": parts["LHEE"][1], "RHEE": parts["RHEE"][1]}
    positions = []
    for name in ("pelvis", "LHEE", "RHEE"):
        a = fwd[name] - (pelvis_fwd if treadmill else 0.0)
        b = np.broadcast_to(lateral[name], a.shape)
        if radius_m is not None:  # bend the straight path onto a circle of this radius
            a, b = (radius_m - b) * np.sin(a / radius_m), radius_m - (radius_m - b) * np.cos(a / radius_m)
        positions.append(np.column_stack([a, b, up[name]]))
    offsets = {"LASI": (0.1, 0.12), "RASI": (0.1, -0.12), "SACR": (-0.2, 0.0)}
    pelvis = positions[0]
    markers = [pelvis + np.array([dx, dy, 0.0]) for dx, dy in offsets.values()]
    pos = np.stack(markers + positions[1:], axis=1)
    rec = Recording(pos, list(offsets) + ["LHEE", "RHEE"], t, rate_hz=rate_hz, up_axis="z", source="synthetic")
    steps_taken = int(round(s[-1]))
    contacts = [float(t[np.argmax(s >= k - 1e-9)]) for k in range(1, steps_taken + 1)]
    return rec, np.array(contacts)


def write_trc_positions(path, positions, names, *, rate_hz=100.0, units="mm", blank=None, frames_announced=None):
    """A TRC file as OpenSim writes it; ``blank`` (frame, point) cells are left empty."""
    n_frames = positions.shape[0]
    lines = [
        f"PathFileType\t4\t(X/Y/Z)\t{path.name}",
        "DataRate\tCameraRate\tNumFrames\tNumMarkers\tUnits\tOrigDataRate\tOrigDataStartFrame\tOrigNumFrames",
        f"{rate_hz}\t{rate_hz}\t{frames_announced or n_frames}\t{len(names)}\t{units}\t{rate_hz}\t1\t{n_frames}",
        "Frame#\tTime\t" + "\t\t\t".join(names),
        "\t\t" + "\t".join(f"X{i + 1}\tY{i + 1}\tZ{i + 1}" for i in range(len(names))),
        "",
    ]
    for f in range(n_frames):
        cells = [str(f + 1), f"{f / rate_hz:.6f}"]
        for p in range(len(names)):
            if blank is not None and (f, p) in blank:
                cells += ["", "", ""]
            else:
                cells += [f"{v:.9f}" for v in positions[f, p]]
        lines.append("\t".join(cells))
    path.write_text("\n".join(lines) + "\n")
    return path


def write_trc(path, recording):
    """A synthetic recording as a TRC file in metres, missing samples as empty cells."""
    pos = recording.positions_m
    blank = {(f, p) for f, p in zip(*np.nonzero(np.isnan(pos).any(axis=2)))}
    return write_trc_positions(
        Path(path), np.nan_to_num(pos), recording.point_names, rate_hz=recording.rate_hz, units="m", blank=blank
    )


def write_walk_c3d(path, **walk):
    """The stepping walk as a Vicon-like C3D in mm (Z up stated in Y_SCREEN)."""
    rec, _ = stepping_walk(**walk)
    c = ezc3d.c3d()
    data = np.ones((4, len(rec.point_names), rec.n_frames))
    data[:3] = np.transpose(np.nan_to_num(rec.positions_m * 1000.0), (2, 1, 0))
    c["parameters"]["POINT"]["RATE"]["value"] = [rec.rate_hz]
    c["parameters"]["POINT"]["LABELS"]["value"] = rec.point_names
    c.add_parameter("POINT", "UNITS", ["mm"])
    c.add_parameter("POINT", "Y_SCREEN", ["+Z"])
    c["data"]["points"] = data
    c.write(str(path))
    return path


def make_special(path: Path, kind: str) -> Path:
    """A special file of ``kind`` at ``path``: 'null' and 'zero' (character devices like /dev/null and
    /dev/zero, made here with mknod), 'fifo', 'socket'; skips when this machine does not let the test
    make it."""
    if kind in ("null", "zero", "urandom"):
        minor = {"null": 3, "zero": 5, "urandom": 9}[kind]
        try:
            os.mknod(path, 0o666 | stat.S_IFCHR, os.makedev(1, minor))
        except PermissionError:
            pytest.skip(f"making a device node needs CAP_MKNOD (root); cannot make {kind} here")
    elif kind == "fifo":
        os.mkfifo(path)
    elif kind == "socket":
        s = socket.socket(socket.AF_UNIX)
        try:
            s.bind(str(path))
        except OSError as exc:  # a path too long for a socket address
            pytest.skip(f"cannot bind a UNIX socket at {path}: {exc}")
        finally:
            s.close()
    else:
        raise ValueError(kind)
    return path


def identity(path: Path) -> tuple:
    """What must not change about a path: its type, inode and (for a regular file) content."""
    st = os.lstat(path)
    content = path.read_bytes() if stat.S_ISREG(st.st_mode) else None
    return stat.S_IFMT(st.st_mode), st.st_ino, st.st_rdev, content


def write_two_walks(folder: Path) -> Path:
    """Two short synthetic walks (12 s) as TRC files in ``folder``: a straight walk and one with stops."""
    for subject, walk_type in ((synthetic.SUBJECTS[0], "1-straight"), (synthetic.SUBJECTS[1], "5-stop-and-go")):
        walk = synthetic.make_walk(subject, walk_type, duration_s=12.0)
        write_trc(folder / f"{subject.name}_{walk_type}.trc", walk.recording)
    return folder
