"""Synthetic lower-back IMU: the gait lab's walker (yoyogait.synthetic) seen by one inertial sensor.

SYNTHETIC data with ground truth.  The sensor sits at the walker's pelvis centre and turns with the
pelvis (heading, pelvis yaw and roll), tilted by a fixed mounting error.  Its axes follow the
Mobilise-D lower-back convention: x up, y to the right, z forward (a right-handed frame).

Per sample it reports the specific force ``R^T (a + g e_z)`` in m/s^2 (at rest upright: +9.81 on x)
and the angular rate in its own frame in rad/s, each with a constant bias, white noise and the
range of the sensor (saturation); on request (``magnetometer=True``) also the earth's magnetic
field ``R^T b`` in microtesla (``SyntheticImuWalk.mag_ut``; world x is magnetic north, the field
dips below the horizon), with white noise and optionally a disturbance (iron nearby) over a span.
Kinematics are differentiated at four times the output rate
(central differences) and then decimated, so the derivative error is far below the noise.

The walker is not a pendulum; so that the inverted-pendulum speed of the IMU estimator has a
truth to be compared with, the recording's ``sensor_height_m`` is the pendulum length for which
the walker's step length ``2 pi R`` equals ``K 2 sqrt(2 l h - h^2)`` with ``h = 2 r`` and ``K``
the estimator's default step-length factor.  The synthetic lab therefore checks the signal chain
(orientation, integration, estimator), not the pendulum model; the real recordings check that.
"""

from __future__ import annotations

import numpy as np

from .errors import InputError
from .io.imu_recording import GRAVITY_MPS2, ImuRecording
from .synthetic import SUBJECTS, SyntheticSubject, SyntheticTruth, make_walk

__all__ = ["SyntheticImuWalk", "make_imu_walk", "pendulum_length_m", "imu_lab", "STEP_LENGTH_FACTOR"]

#: The correction K of the inverted-pendulum step length: the estimator's default (``step_length_factor``).
STEP_LENGTH_FACTOR = 1.05

_OVERSAMPLE = 4
# Sensor axes (x up, y right, z forward) in the body frame (forward, left, up): columns.
_SENSOR_IN_BODY = np.array([[0.0, 0.0, 1.0], [0.0, -1.0, 0.0], [1.0, 0.0, 0.0]])


def pendulum_length_m(subject: SyntheticSubject, factor: float = STEP_LENGTH_FACTOR) -> float:
    """The length l with factor * 2 sqrt(2 l h - h^2) = 2 pi R for h = 2 r (see the module's text)."""
    h = 2.0 * subject.r_m
    half = np.pi * subject.R_m / factor
    return float((half * half + h * h) / (2.0 * h))


class SyntheticImuWalk:
    """A SYNTHETIC IMU recording and the truth of the walk behind it."""

    def __init__(
        self,
        recording: ImuRecording,
        truth: SyntheticTruth,
        subject: SyntheticSubject,
        walk_type: str,
        mag_ut: np.ndarray | None = None,
        forward_heading_rad: np.ndarray | None = None,
    ):
        self.recording = recording
        self.truth = truth
        self.subject = subject
        self.walk_type = walk_type
        #: SYNTHETIC magnetometer, N x 3 in the sensor frame [uT]; None unless asked for.
        self.mag_ut = mag_ut
        #: The true heading of the sensor's forward axis from magnetic north (world x), counter-clockwise [rad].
        self.forward_heading_rad = forward_heading_rad

    @property
    def name(self) -> str:
        """E.g. ``SYNTHETIC IMU synthetic-S1 walk 1-straight``."""
        return f"SYNTHETIC IMU {self.subject.name} walk {self.walk_type}"


def _rot(axis: int, angle):
    a = np.asarray(angle, dtype=float)
    c, s = np.cos(a), np.sin(a)
    out = np.zeros(a.shape + (3, 3))
    i, j = [(1, 2), (2, 0), (0, 1)][axis]
    out[..., axis, axis] = 1.0
    out[..., i, i] = c
    out[..., j, j] = c
    out[..., i, j] = -s
    out[..., j, i] = s
    return out


def make_imu_walk(
    subject: SyntheticSubject | None = None,
    walk_type: str = "1-straight",
    *,
    rate_hz: float = 100.0,
    duration_s: float | None = None,
    seed: int = 0,
    tilt_pitch_deg: float = 0.0,
    tilt_roll_deg: float = 0.0,
    gyro_bias_rad_s=(0.0, 0.0, 0.0),
    acc_bias_mps2=(0.0, 0.0, 0.0),
    acc_noise_mps2: float = 0.02,
    gyr_noise_rad_s: float = 0.002,
    acc_range_mps2: float = 16.0 * GRAVITY_MPS2,
    gyr_range_rad_s: float = np.deg2rad(2000.0),
    upside_down: bool = False,
    magnetometer: bool = False,
    mag_field_ut=(20.0, 0.0, -44.0),
    mag_noise_ut: float = 0.3,
    mag_disturbance_ut=(0.0, 0.0, 0.0),
    mag_disturbance_s=(0.0, 0.0),
    **walk_options,
) -> SyntheticImuWalk:
    """One SYNTHETIC lower-back IMU walk (deterministic for a seed).

    ``tilt_pitch_deg`` tilts the sensor forward about its right axis, ``tilt_roll_deg`` sideways
    about its forward axis (mounting errors).  ``upside_down`` turns it half a turn about its
    forward axis.  Biases are constant, in the sensor frame; the noise is white, per sample.
    Values beyond ``acc_range_mps2`` / ``gyr_range_rad_s`` are clipped (saturation).
    ``magnetometer``: also the field ``mag_field_ut`` (world frame: x magnetic north, z up) in the
    sensor frame with white noise ``mag_noise_ut``, plus ``mag_disturbance_ut`` (world frame) from
    ``mag_disturbance_s[0]`` to ``[1]`` s.  Other keywords go to :func:`yoyogait.synthetic.make_walk`.
    """
    subject = SUBJECTS[0] if subject is None else subject
    if not (np.isfinite(rate_hz) and rate_hz > 0):
        raise InputError(f"rate_hz must be positive, got {rate_hz}")
    fine_hz = rate_hz * _OVERSAMPLE
    walk = make_walk(
        subject,
        walk_type,
        rate_hz=fine_hz,
        duration_s=duration_s,
        seed=seed,
        noise_m=0.0,
        dropouts=False,
        **walk_options,
    )
    truth = walk.truth
    t = truth.time_s
    dt = 1.0 / fine_hz
    pos = truth.pelvis_centre_m
    acc_w = np.gradient(np.gradient(pos, dt, axis=0), dt, axis=0)
    # The pelvis's turn, as the walker turns its markers: yaw (heading + pelvis yaw), roll.
    stride_phase = 0.5 * truth.theta_rad
    yaw = truth.heading_rad + subject.pelvis_yaw_rad * np.sin(stride_phase)
    roll = subject.pelvis_roll_rad * np.cos(stride_phase)
    body = _rot(2, yaw) @ _rot(0, roll)  # world <- body (forward, left, up)
    mount = _SENSOR_IN_BODY @ _rot(1, np.deg2rad(tilt_pitch_deg)) @ _rot(2, np.deg2rad(tilt_roll_deg))
    if upside_down:
        mount = mount @ _rot(2, np.pi)
    r_ws = body @ mount  # world <- sensor
    f_w = acc_w + np.array([0.0, 0.0, GRAVITY_MPS2])
    acc = np.einsum("nji,nj->ni", r_ws, f_w)
    # Angular rate in the sensor frame: vee(R(t-dt)^T R(t+dt)) / (2 dt), ends one-sided.
    rel = np.einsum("nji,njk->nik", r_ws[:-2], r_ws[2:])
    w_mid = 0.5 * np.stack([rel[:, 2, 1] - rel[:, 1, 2], rel[:, 0, 2] - rel[:, 2, 0], rel[:, 1, 0] - rel[:, 0, 1]], 1)
    gyr = np.vstack([w_mid[:1], w_mid, w_mid[-1:]]) / (2.0 * dt)

    keep = slice(0, None, _OVERSAMPLE)
    time_s = t[keep]
    acc, gyr = acc[keep], gyr[keep]
    rng = np.random.default_rng(
        np.random.SeedSequence(
            [int(seed), 22, int(round(abs(tilt_pitch_deg) * 10)), int(tilt_pitch_deg < 0), int(upside_down)]
        )
    )
    acc = acc + np.asarray(acc_bias_mps2, dtype=float) + rng.normal(0.0, acc_noise_mps2, acc.shape)
    gyr = gyr + np.asarray(gyro_bias_rad_s, dtype=float) + rng.normal(0.0, gyr_noise_rad_s, gyr.shape)
    acc = np.clip(acc, -acc_range_mps2, acc_range_mps2)
    gyr = np.clip(gyr, -gyr_range_rad_s, gyr_range_rad_s)
    r_out = r_ws[keep]
    fwd_w = r_out[:, :, 2]  # the sensor's forward axis (z) in the world frame
    forward_heading = np.arctan2(fwd_w[:, 1], fwd_w[:, 0])
    mag = None
    if magnetometer:
        b_w = np.tile(np.asarray(mag_field_ut, dtype=float), (time_s.size, 1))
        t0, t1 = (float(v) for v in mag_disturbance_s)
        b_w[(time_s >= t0) & (time_s < t1)] += np.asarray(mag_disturbance_ut, dtype=float)
        mag_rng = np.random.default_rng(np.random.SeedSequence([int(seed), 22, 7]))
        mag = np.einsum("nji,nj->ni", r_out, b_w) + mag_rng.normal(0.0, mag_noise_ut, (time_s.size, 3))

    options = dict(
        rate_hz=float(rate_hz),
        tilt_pitch_deg=float(tilt_pitch_deg),
        tilt_roll_deg=float(tilt_roll_deg),
        gyro_bias_rad_s=[float(b) for b in gyro_bias_rad_s],
        acc_bias_mps2=[float(b) for b in acc_bias_mps2],
        acc_noise_mps2=float(acc_noise_mps2),
        gyr_noise_rad_s=float(gyr_noise_rad_s),
        acc_range_mps2=float(acc_range_mps2),
        gyr_range_rad_s=float(gyr_range_rad_s),
        upside_down=bool(upside_down),
        magnetometer=bool(magnetometer),
    )
    recording = ImuRecording(
        time_s=time_s,
        acc_mps2=acc,
        gyr_rad_s=gyr,
        rate_hz=float(rate_hz),
        source=f"synthetic-imu:{subject.name}/{walk_type}/seed{int(seed)}",
        sensor_height_m=pendulum_length_m(subject),
        metadata={
            "synthetic": True,
            "description": "SYNTHETIC lower-back IMU generated by yoyogait.synthetic_imu, not a real recording",
            "subject": subject.name,
            "walk_type": walk_type,
            "seed": int(seed),
            "axes": "x up, y right, z forward",
            **options,
        },
    )
    return SyntheticImuWalk(recording, truth.at(time_s), subject, walk_type, mag, forward_heading)


def imu_lab(seed: int = 0, rate_hz: float = 100.0) -> list[SyntheticImuWalk]:
    """The SYNTHETIC IMU lab: each subject walking straight, with a 10 deg forward tilt and a small gyro bias."""
    bias = np.deg2rad([0.5, -0.5, 0.5])
    return [
        make_imu_walk(s, "1-straight", rate_hz=rate_hz, seed=seed, tilt_pitch_deg=10.0, gyro_bias_rad_s=bias)
        for s in SUBJECTS
    ]
