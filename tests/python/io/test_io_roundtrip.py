"""Round trips: an analytic walk written to C3D, TRC, BVH and CSV comes back as it went in.

The pelvis follows the Yoyo-model (eq. 1-2) along +x with z up, so its
velocity is known exactly (eq. 3-4).  The velocity pipeline may only differ
from it by what its Savitzky-Golay differentiator is expected to lose: the
filter's gain at the step frequency, computed here from its coefficients.
"""

from __future__ import annotations

import numpy as np
import pytest
from scipy.signal import savgol_coeffs

import yoyogait
import yoyogait.io as yio
from yoyogait.pipeline.velocities import savgol_window_samples

ezc3d = pytest.importorskip("ezc3d")

R_M, SMALL_R_M, STEP_HZ, Z0_M, DURATION_S = 0.115, 0.02, 1.8, 0.95, 4.0
OMEGA = 2 * np.pi * STEP_HZ
# Rigid marker offsets from the pelvis centre (x forward, y left, z up); they average to zero.
PELVIS_OFFSETS = {"LASI": (0.12, 0.12, 0.02), "RASI": (0.12, -0.12, 0.02), "SACR": (-0.24, 0.0, -0.04)}
FEET_OFFSETS = {"LHEE": (0.0, 0.1, -0.9), "RHEE": (0.0, -0.1, -0.9)}


def pelvis_centre(t):
    theta = OMEGA * t
    return np.column_stack(
        [R_M * theta + SMALL_R_M * np.sin(theta), np.full_like(t, 0.3), Z0_M + SMALL_R_M * np.cos(theta)]
    )


def analytic_velocity(t):
    theta = OMEGA * t
    return R_M * OMEGA + SMALL_R_M * OMEGA * np.cos(theta), -SMALL_R_M * OMEGA * np.sin(theta)


def walk(rate_hz):
    """Time, names and positions (frames x points x 3, metres, z up) of the analytic walk."""
    t = np.arange(int(DURATION_S * rate_hz)) / rate_hz
    centre = pelvis_centre(t)
    offsets = {**PELVIS_OFFSETS, **FEET_OFFSETS}
    positions = np.stack([centre + np.array(o) for o in offsets.values()], axis=1)
    return t, list(offsets), positions


# ------------------------------------------------------------------ one writer per format, z up in metres


def to_c3d(path, t, names, pos, gap):
    c = ezc3d.c3d()
    data = np.ones((4, len(names), len(t)))
    data[:3] = np.transpose(pos * 1000.0, (2, 1, 0))
    residuals = np.zeros((1, len(names), len(t)))
    residuals[0, gap[0], gap[1]] = -1.0
    c["parameters"]["POINT"]["RATE"]["value"] = [1.0 / (t[1] - t[0])]
    c["parameters"]["POINT"]["LABELS"]["value"] = names
    c.add_parameter("POINT", "UNITS", ["mm"])
    c["data"]["points"] = data
    c["data"]["meta_points"] = {"residuals": residuals, "camera_masks": np.zeros((7, len(names), len(t)), dtype=bool)}
    c.write(str(path))


def to_trc(path, t, names, pos, gap):
    rate = 1.0 / (t[1] - t[0])
    lines = [
        "PathFileType\t4\t(X/Y/Z)\twalk.trc",
        "DataRate\tCameraRate\tNumFrames\tNumMarkers\tUnits\tOrigDataRate\tOrigDataStartFrame\tOrigNumFrames",
        f"{rate:g}\t{rate:g}\t{len(t)}\t{len(names)}\tmm\t{rate:g}\t1\t{len(t)}",
        "Frame#\tTime\t" + "\t\t\t".join(names),
        "\t\t" + "\t".join(f"X{i + 1}\tY{i + 1}\tZ{i + 1}" for i in range(len(names))),
        "",
    ]
    for f in range(len(t)):
        cells = [str(f + 1), f"{t[f]:.6f}"]
        for p in range(len(names)):
            missing = p == gap[0] and f in gap[1]
            cells += ["", "", ""] if missing else [f"{v * 1000:.9f}" for v in pos[f, p]]
        lines.append("\t".join(cells))
    path.write_text("\n".join(lines) + "\n")


def to_csv(path, t, names, pos, gap):
    header = ["time_s"] + [f"{n}_{a}" for n in names for a in "xyz"]
    rows = []
    for f in range(len(t)):
        cells = [f"{t[f]:.9f}"]
        for p in range(len(names)):
            missing = p == gap[0] and f in gap[1]
            cells += ["", "", ""] if missing else [f"{v:.12f}" for v in pos[f, p]]
        rows.append(",".join(cells))
    path.write_text("# up_axis: z\n" + ",".join(header) + "\n" + "\n".join(rows) + "\n")


def to_bvh(path, t, names, pos, gap):
    """BVH is Y up in centimetres: file (x, y, z) = walk (x, z, -y) * 100; a skeleton has no gaps."""

    def file_xyz(p):
        return np.column_stack([p[:, 0], p[:, 2], -p[:, 1]]) * 100.0

    centre = pelvis_centre(t)
    joints = "".join(
        f"  JOINT {n}\n  {{\n    OFFSET {' '.join(f'{v:.9f}' for v in file_xyz(np.array([o]))[0])}\n"
        f"    CHANNELS 3 Zrotation Xrotation Yrotation\n  }}\n"
        for n, o in {**PELVIS_OFFSETS, **FEET_OFFSETS}.items()
    )
    rows = [" ".join(f"{v:.9f}" for v in (*xyz, 0, 0, 0, *([0.0] * 3 * len(names)))) for xyz in file_xyz(centre)]
    path.write_text(
        "HIERARCHY\nROOT Hips\n{\n  OFFSET 0 0 0\n"
        "  CHANNELS 6 Xposition Yposition Zposition Zrotation Xrotation Yrotation\n"
        + joints
        + "}\nMOTION\n"
        + f"Frames: {len(t)}\nFrame Time: {t[1] - t[0]:.9f}\n"
        + "\n".join(rows)
        + "\n"
    )


FORMATS = {"c3d": (to_c3d, 100.0), "trc": (to_trc, 200.0), "csv": (to_csv, 50.0), "bvh": (to_bvh, 100.0)}


def written(tmp_path, fmt):
    """Write the walk in ``fmt``; RASI misses 0.3 s (except in BVH). Returns (recording, names, positions)."""
    writer, rate = FORMATS[fmt]
    t, names, pos = walk(rate)
    gap_frames = np.arange(int(1.0 * rate), int(1.3 * rate))
    gap = (names.index("RASI"), gap_frames)
    path = tmp_path / f"walk.{fmt}"
    writer(path, t, names, pos, gap)
    expected = pos.copy()
    if fmt != "bvh":
        expected[gap_frames, gap[0]] = np.nan
    return yio.read(path), names, expected


@pytest.mark.parametrize("fmt", sorted(FORMATS))
def test_positions_come_back_to_a_micrometre(tmp_path, fmt):
    """Written then read, every position is back within 1e-6 m, and the missing samples are NaN."""
    rec, names, expected = written(tmp_path, fmt)
    got = rec.points(names)
    if fmt == "bvh":  # BVH is Y up in its own frame: rotate the expectation into it
        expected = np.stack([expected[..., 0], expected[..., 2], -expected[..., 1]], axis=-1)
    assert got.shape == expected.shape
    assert np.array_equal(np.isnan(got), np.isnan(expected))
    assert np.nanmax(np.abs(got - expected)) < 1e-6


@pytest.mark.parametrize("fmt", sorted(FORMATS))
def test_velocities_match_the_analytic_derivative_within_the_filter_error(tmp_path, fmt):
    """The pipeline's vx and vz equal the Yoyo-model's eq. 3-4 up to the SG filter's gain loss at the step frequency."""
    rec, _, _ = written(tmp_path, fmt)
    v = yoyogait.gait_velocities(rec)
    assert v.up_axis == ("y" if fmt == "bvh" else "z")
    assert v.rate_hz == 25.0 and np.allclose(np.diff(v.time_s), 0.04)
    rate_in = FORMATS[fmt][1]
    window = savgol_window_samples(0.25, rate_in, 3)
    coeffs = savgol_coeffs(window, 3, deriv=1, delta=1.0 / rate_in, use="dot")
    lags = np.arange(window) - window // 2
    gain = np.real(np.sum(coeffs * np.exp(1j * OMEGA * lags / rate_in)) / (1j * OMEGA))  # H(f) / (j 2 pi f)
    amplitude = SMALL_R_M * OMEGA
    tolerance = abs(1.0 - gain) * amplitude + 1e-4
    vx_true, vz_true = analytic_velocity(v.time_s)
    interior = (v.time_s > v.time_s[0] + window / rate_in) & (v.time_s < v.time_s[-1] - window / rate_in)
    assert np.all(np.isfinite(v.vx[interior])) and np.all(np.isfinite(v.vz[interior]))
    assert np.max(np.abs(v.vz[interior] - vz_true[interior])) <= tolerance
    assert np.max(np.abs(v.vx[interior] - vx_true[interior])) <= tolerance
    # The tolerance is the filter's, not a loose bound: it is a small fraction of the oscillation.
    assert tolerance < 0.05 * amplitude + 1e-4
