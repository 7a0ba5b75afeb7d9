/// @file imu/imu_config.hpp
/// @brief ImuConfig: every setting of the lower-back IMU front-end (docs/imu.md).
#pragma once

#include <cmath>
#include <cstddef>

#include "yoyogait/config.hpp"

namespace yoyogait {

/// Settings of ImuOnlineEstimator, declared once: X(type, name, default, "unit", lo, min, max, hi,
/// "doc"). None is a number of samples: the front-end behaves the same at any sample rate. The
/// struct, its validation, the bindings, the schema (`_core.config_schema()`, section "imu"), the
/// Python ImuConfig and the `[imu]` section of the TOML files follow this table.
#define YOYOGAIT_IMU_FIELDS(X)                                                                                      \
  X(double, mahony_kp_per_s, 0.5, "1/s", "(", 0.0, 100.0, "]",                                                     \
    "Mahony filter: proportional gain of the gravity correction (about 1/kp s of accelerometer averaging)")       \
  X(double, mahony_ki_per_s2, 0.02, "1/s^2", "[", 0.0, 100.0, "]",                                                  \
    "Mahony filter: integral gain (the gyro bias about the horizontal axes)")                                     \
  X(double, max_gyro_bias_rad_s, 0.1, "rad/s", "[", 0.0, 10.0, "]", "the integral term is limited to this")       \
  X(double, highpass_tau_s, 1.0, "s", "(", 0.0, 1e100, "]",                                                         \
    "time constant of the high-pass of the accelerations and of the leaky integrator after it")                  \
  X(std::size_t, forward_axis, 2, "", "[", 0, 2, "]", "the sensor axis pointing forward (0 x, 1 y, 2 z)")           \
  X(bool, forward_negative, false, "", "[", 0, 1, "]", "the forward direction is minus that axis")                 \
  X(double, sensor_height_m, 0.95, "m", "(", 0.1, 3.0, "]",                                                         \
    "the sensor's height above the floor standing: the inverted pendulum's length l")                             \
  X(double, step_length_factor, 1.05, "", "(", 0.0, 5.0, "]",                                                       \
    "K of the step length K 2 sqrt(2 l h - h^2) (Zijlstra & Hof 2003: 1.25; 1.05 calibrated on one participant, docs/imu.md)") \
  X(double, excursion_tau_s, 0.5, "s", "(", 0.0, 1e100, "]", "low-pass of the vertical excursion h per step")       \
  X(double, speed_rel_std, 0.2, "", "[", 0.0, 10.0, "]",                                                             \
    "relative standard deviation of the pendulum speed (its model error; calibrated on one participant, docs/imu.md)") \
  X(double, max_walk_ratio_m_per_spm, 0.012, "m/(steps/min)", "[", 0.0, 1.0, "]",                                   \
    "a step length (the pendulum's) per step frequency above this is a lock on the stride, not the step (walkers: 0.004-0.008; 0: not checked)") \
  X(double, turn_f_std_hz_per_rad_s, 0.21, "Hz/(rad/s)", "[", 0.0, 100.0, "]",                                     \
    "the step frequency's std grows by this times the yaw rate (low-passed over 0.5 s): in a turn the steps are not the walk's (0.0037 Hz per deg/s, calibrated on one participant, docs/imu.md; 0: not added)") \
  X(double, lock_f_rel_std, 0.1, "", "[", 0.0, 10.0, "]",                                                           \
    "a fresh lock's step frequency has this relative std more, decaying over 1.5 s from the lock (the pendulum's start): gait initiation raises the cadence 3-8 % over the first strides, and the wrong locks are fresh ones (chosen on one participant, docs/imu.md; 0: not added)") \
  X(double, min_periodicity, 0.2, "", "[", -1.0, 1.0, "]",                                                          \
    "valid only while the fed v_z's autocorrelation at the estimate's period over the last periodicity_steps steps is at least this: the last steps repeat at it (a pause, steps of a turn do not; chosen on one participant, docs/imu.md; -1: not checked)") \
  X(double, periodicity_steps, 1.5, "steps", "(", 0.0, 3.0, "]",                                                   \
    "how many of the estimate's periods back the periodicity is taken over")                                       \
  X(double, min_vz_rms_mps, 0.02, "m/s", "[", 0.0, 10.0, "]",                                                      \
    "valid only while the fed vertical velocity's RMS (low-passed over 0.25 s) is at least this: no walker's pelvis moves less (0.02 m/s at 1.8 steps/s is a 5 mm bob; walkers 2-5 cm); a walker who stops otherwise keeps the last cadence, valid, for a second or more (NOT_WALKING; 0: not checked)") \
  X(double, phase_std_tau_s, 1.0, "s", "(", 0.0, 1e100, "]",                                                       \
    "low-pass of the estimator's phase corrections in the step frequency's std (as [online]; chosen on one participant, docs/imu.md)") \
  X(double, phase_onset_tau_s, 0.25, "s", "[", 0.0, 1e100, "]",                                                    \
    "low-pass of the phase corrections, signed and absolute, for the step frequency's std at a cadence change's onset: corrections that keep one sign over it are a change not yet followed (0: not used; docs/imu.md)") \
  X(double, settle_s, 2.0, "s", "[", 0.0, 1e100, "]", "the estimator is fed once the front-end has run this long after a (re)start (2 highpass_tau_s: the integrators' start transient decays)") \
  X(double, max_gap_s, 0.3, "s", "(", 0.0, 1e100, "]", "a longer interval between samples restarts the front-end; a shorter gap (samples lost) is bridged by the model while it holds") \
  X(double, acc_saturation_mps2, 78.0, "m/s^2", "(", 0.0, 1e100, "]",                                                \
    "an acceleration component at or beyond this is saturated (the sensor's range)")                              \
  X(double, gyr_saturation_rad_s, 34.0, "rad/s", "(", 0.0, 1e100, "]",                                               \
    "an angular rate component at or beyond this is saturated (the sensor's range)")                              \
  X(double, saturation_hold_s, 1.0, "s", "[", 0.0, 1e100, "]", "valid is 0 this long after a saturated sample")    \
  X(double, gravity_tau_s, 2.0, "s", "(", 0.0, 1e100, "]", "low-pass of the acceleration's norm for the gravity check") \
  X(double, gravity_tolerance, 0.25, "", "(", 0.0, 1.0, ")",                                                         \
    "valid is 0 while that norm is further than this fraction from 9.81 m/s^2 (a wrong unit, a broken sensor)")  \
  X(double, max_speed_mps, 3.0, "m/s", "(", 0.0, 1e100, "]", "a walking speed above this is not reported as valid") \
  X(double, mag_kp_per_s, 0.2, "1/s", "[", 0.0, 100.0, "]",                                                         \
    "magnetometer (when given): gain of the heading correction towards the tilt-compensated magnetic heading (0: not used)") \
  X(double, mag_norm_tolerance, 0.15, "", "(", 0.0, 10.0, "]",                                                       \
    "a magnetometer sample whose norm is further than this fraction from its low-passed norm (iron nearby) is not used") \
  X(double, latency_f_hz, 2.0, "Hz", "(", 0.0, 1e100, "]", "frequency at which the reported input latency is evaluated")


/// Settings of ImuOnlineEstimator: the gait estimator behind it and YOYOGAIT_IMU_FIELDS.
struct ImuConfig {
  /// The gait estimator behind the front-end, fed every estimator.sample_time_s with the mean of the
  /// front-end's forward and vertical velocities over that interval.
  EstimatorConfig estimator{};
  YOYOGAIT_IMU_FIELDS(YOYOGAIT_CONFIG_MEMBER)

  /// nullptr when usable, else what is wrong, naming the field ("imu.field") and its range.
  const char* validate() const noexcept {
    if (const char* e = estimator.validate()) return e;
#define YOYOGAIT_CHECK_IMU(...) YOYOGAIT_CHECK_FIELD((*this), "imu.", __VA_ARGS__)
    YOYOGAIT_IMU_FIELDS(YOYOGAIT_CHECK_IMU)
#undef YOYOGAIT_CHECK_IMU
    if (estimator.algorithm != Algorithm::kGaitFilter)
      return "the IMU estimator runs the gait filter (algorithm gait_filter)";
    return nullptr;
  }
};

#define YOYOGAIT_SPEC_IMU(...) YOYOGAIT_FIELD_SPEC("imu", __VA_ARGS__)
/// Every field of the IMU table, as kConfigFields lists the estimator's.
inline constexpr FieldSpec kImuConfigFields[] = {YOYOGAIT_IMU_FIELDS(YOYOGAIT_SPEC_IMU)};
#undef YOYOGAIT_SPEC_IMU

}  // namespace yoyogait
