/// @file imu/imu_estimate.hpp
/// @brief What ImuOnlineEstimator reports: ImuReason and ImuEstimate (one per sample).
#pragma once

#include <cstdint>

#include "yoyogait/estimate.hpp"
#include "yoyogait/record.hpp"

namespace yoyogait {

/// Why an ImuEstimate is not valid (the first that applies, in this order); kOk when it is.
enum class ImuReason : std::uint8_t {
  kOk = 0,                 ///< valid
  kNonFinite = 1,          ///< this sample had a non-finite time or value: ignored, the estimate carried
  kTimeNotIncreasing = 2,  ///< this sample's time did not increase: ignored
  kSaturated = 3,          ///< a component reached the sensor's range within saturation_hold_s
  kGap = 4,                ///< the front-end restarted after a gap and has not settled yet
  kGravity = 5,            ///< the acceleration's low-passed norm is not about 9.81 m/s^2 (unit? sensor?); before the first start, this sample's norm
  kAcquiring = 6,          ///< not fed yet; or walking, the start-up bank running or f at a bound (not locked)
  kNotWalking = 7,         ///< the estimator's walking detector says standing, or the vertical motion is smaller than a walker's
  kSpeedImplausible = 8,   ///< the speed is negative or above max_speed_mps
  kIrregular = 9,          ///< the last steps do not repeat at the estimate's period (a pause, a turn's steps)
  kUncertain = 10,         ///< a std as large as a value spread evenly over its range: f's over [f_min_hz, f_max_hz], the speed's over [0, max_speed_mps]
};

/// The fields of ImuEstimate, declared once: X(type, name, default, "unit", scope, "doc") (scope
/// always kAll). The struct, the bindings' properties and run() columns and the Python ImuResult
/// follow this table. "Forward" is the horizontal direction of the sensor's forward axis.
#define YOYOGAIT_IMU_ESTIMATE_FIELDS(X)                                                                           \
  X(double, t_s, 0.0, "s", kAll, "the sample's timestamp (an ignored sample: the last one accepted)")             \
  X(double, az_mps2, 0.0, "m/s^2", kAll, "front-end: gravity-free vertical acceleration")                         \
  X(double, vz_mps, 0.0, "m/s", kAll, "front-end: vertical velocity (high-passed, leaky integral of az)")         \
  X(double, vx_osc_mps, 0.0, "m/s", kAll, "front-end: forward oscillation (high-passed, leaky integral)")         \
  X(double, vx_mps, 0.0, "m/s", kAll, "front-end: forward velocity fed to the estimator, pendulum speed + vx_osc") \
  X(double, heading_rad, 0.0, "rad", kAll, "heading of the forward axis (counter-clockwise from above): from the rate gyro, relative to the start; from magnetic north once heading_absolute") \
  X(double, tilt_rad, 0.0, "rad", kAll, "angle between the sensor's forward axis and the horizontal plane")      \
  X(double, vx_hat_mps, 0.0, "m/s", kAll, "the estimator's reconstruction of v_x at t_s (before it is fed: vx_mps)") \
  X(double, vz_hat_mps, 0.0, "m/s", kAll, "the estimator's reconstruction of v_z at t_s (before it is fed: vz_mps)") \
  X(double, step_frequency_hz, 0.0, "Hz", kAll, "step frequency")                                                 \
  X(double, step_frequency_std_hz, 0.0, "Hz", kAll, "its standard deviation")                                    \
  X(double, speed_mps, 0.0, "m/s", kAll, "walking speed (the estimator's A0)")                                    \
  X(double, speed_std_mps, 0.0, "m/s", kAll, "its standard deviation, the pendulum model's error included")      \
  X(double, excursion_m, 0.0, "m", kAll, "vertical excursion per step h = 2 |Z| / w, low-passed")                \
  X(double, step_length_m, 0.0, "m", kAll, "inverted-pendulum step length K 2 sqrt(2 l h - h^2)")                \
  X(double, pendulum_speed_mps, 0.0, "m/s", kAll, "step_length_m times the step frequency")                      \
  X(double, gait_phase, 0.0, "", kAll, "phase within the step in [0, 1): v_z ~ |Z| cos(2 pi gait_phase); held while standing") \
  X(double, next_step_in_s, 0.0, "s", kAll, "time to the next gait_phase 0.75 (about heel strike), in [0, 1/f); NaN while not walking or no phase is known") \
  X(double, input_latency_s, 0.0, "s", kAll, "delay of vz_mps behind the true velocity at latency_f_hz (negative: a lead)") \
  X(::yoyogait::ImuReason, reason, ::yoyogait::ImuReason::kAcquiring, "", kAll, "why valid is 0 (ImuReason); 0 when valid") \
  X(::yoyogait::Status, estimator_status, ::yoyogait::Status::kUpdated, "", kAll, "Status of the estimator's last sample") \
  X(bool, valid, false, "", kAll, "the estimate may be used: walking, settled, in range (reason 0)")              \
  X(bool, walking, false, "", kAll, "the estimator's walking/standing detector, while the vertical motion is a walker's (min_vz_rms_mps)") \
  X(bool, heading_absolute, false, "", kAll, "heading_rad is from magnetic north: a magnetometer sample has been used since the first sample (reset)") \
  X(bool, estimator_fed, false, "", kAll, "this sample completed an interval and fed the estimator")

/// One estimate, at the time of one sample (YOYOGAIT_IMU_ESTIMATE_FIELDS).
struct ImuEstimate {
  YOYOGAIT_IMU_ESTIMATE_FIELDS(YOYOGAIT_RECORD_MEMBER)
};

}  // namespace yoyogait
