/// @file online/online_estimate.hpp
/// @brief What OnlineEstimator reports: OnlineStatus, OnlineEstimate (one per frame) and
/// OnlinePrediction (OnlineEstimator::predict).
#pragma once

#include <cstdint>
#include <limits>

#include "yoyogait/estimate.hpp"
#include "yoyogait/record.hpp"

namespace yoyogait {

/// What update() did with its frame.
enum class OnlineStatus : std::uint8_t {
  kUsed = 0,               ///< the frame was used
  kAllMissing = 1,         ///< no point was seen: the estimate is carried forward by prediction
  kTimeNotIncreasing = 2,  ///< the timestamp did not increase: the frame was ignored
  kGapRestart = 3,         ///< used, after a gap longer than max_gap_s that restarted the front-end
  kNonFinite = 4,          ///< non-finite or absurd timestamp, or every seen coordinate non-finite or absurd: ignored
  kTimeJump = 5,           ///< the timestamp jumped more than max_time_jump_s ahead: ignored until frames confirm it
};

/// Why an estimate is not valid: the bits of OnlineEstimate::invalid_reason (0: valid). Each names
/// a check of online/validity.hpp (docs/online.md, "Validity").
enum class InvalidReason : std::uint8_t {
  kAcquiring = 1,          ///< no estimate yet, the start-up bank running, or walking for less than valid_after_s
  kNotWalking = 2,         ///< the walking detector says standing
  kInputNoisy = 4,         ///< the marker noise estimated online is above max_input_noise_m
  kInputMissing = 8,       ///< a frame ignored, a stale estimate, or changes of the visible points moving the centre
  kModelNotHolding = 16,   ///< innovations too large (mean NIS), f at a bound, f below the steps, steps over 1 m, f off the feet's steps, no gait phase
  kImplausibleInput = 32,  ///< the input moves faster than a person can (wrong length unit, jumps, zeros)
  kRateTooLow = 64,        ///< the mean frame rate is below min_rate_hz
  kNotMoving = 128,        ///< the centre travels much less than the speed says (treadmill, sway, turning on the spot)
};

/// The fields of OnlineEstimate, declared once: X(type, name, default, "unit", scope, "doc") (scope:
/// always kAll). The struct, the bindings' properties and run() columns, the schema
/// `_core.record_schema()`, the Python OnlineResult, the CSV of `estimate --online` and
/// docs/records.md follow this table. Velocities in m/s in the frame of the data (the up axis given
/// at construction; "horizontal" = the two other axes in increasing order, a then b).
#define YOYOGAIT_ONLINE_ESTIMATE_FIELDS(X)                                                                         \
  X(double, t_s, 0.0, "s", kAll, "the frame's timestamp (an ignored frame: the last one accepted)")               \
  X(double, vx_mps, 0.0, "m/s", kAll, "front-end: horizontal velocity along the heading")                        \
  X(double, vz_mps, 0.0, "m/s", kAll, "front-end: vertical velocity")                                             \
  X(double, vh_a_mps, 0.0, "m/s", kAll, "front-end: horizontal velocity, first horizontal axis")                 \
  X(double, vh_b_mps, 0.0, "m/s", kAll, "front-end: horizontal velocity, second horizontal axis")                \
  X(double, heading_rad, 0.0, "rad", kAll, "atan2(b, a) of the low-passed horizontal velocity (held when slow)") \
  X(double, walk_a_mps, 0.0, "m/s", kAll, "walking velocity without the oscillation: speed_mps along the heading, axis a") \
  X(double, walk_b_mps, 0.0, "m/s", kAll, "walking velocity without the oscillation, axis b")                    \
  X(double, vx_hat_mps, 0.0, "m/s", kAll,                                                                         \
    "the estimator's reconstruction of v_x (with harmonics) at t_s; before its first sample the front-end's vx_mps") \
  X(double, vz_hat_mps, 0.0, "m/s", kAll, "the reconstruction of v_z at t_s; before the first sample vz_mps")     \
  X(double, step_frequency_hz, 0.0, "Hz", kAll, "step frequency")                                                 \
  X(double, step_frequency_std_hz, 0.0, "Hz", kAll, "its standard deviation")                                    \
  X(double, speed_mps, 0.0, "m/s", kAll, "forward speed without the oscillation (A0)")                           \
  X(double, speed_std_mps, 0.0, "m/s", kAll, "its standard deviation")                                            \
  X(double, gait_phase, 0.0, "", kAll,                                                                            \
    "phase within the step in [0, 1): v_z ~ |Z| cos(2 pi gait_phase); 0.25 highest, 0.75 lowest; held while standing") \
  X(double, next_step_in_s, 0.0, "s", kAll,                                                                       \
    "time to the next gait_phase 0.75 (pelvis low point, about heel strike), in [0, 1/f); NaN while not walking "  \
    "or while no phase is known (an acquisition restarted: its oscillation at zero)")                              \
  X(double, input_latency_s, 0.0, "s", kAll, "delay of vx_mps, vz_mps behind the true velocity at latency_f_hz") \
  X(double, estimate_age_s, 0.0, "s", kAll, "time since the estimator's last sample")                            \
  X(::yoyogait::OnlineStatus, status, ::yoyogait::OnlineStatus::kUsed, "", kAll, "what update() did with the frame (OnlineStatus)")     \
  X(::yoyogait::Status, estimator_status, ::yoyogait::Status::kUpdated, "", kAll, "Status of the estimator's last sample")               \
  X(bool, walking, false, "", kAll, "the estimator's walking/standing detector, while the centre rises and falls as in gait (0 once the estimate is stale)")                                  \
  X(bool, estimator_fed, false, "", kAll, "this frame completed an interval and fed the estimator")              \
  X(::std::uint8_t, points_seen, 0, "", kAll, "points used on this frame")                                        \
  X(bool, valid, false, "", kAll, "the estimate can be used as it is: invalid_reason is 0")                       \
  X(::std::uint8_t, invalid_reason, 1, "", kAll, "why not valid: a set of InvalidReason bits (0: valid)")         \
  X(double, input_noise_m, 0.0, "m", kAll, "the marker noise estimated from the differentiator's innovations") \
  X(double, belt_speed_mps, 0.0, "m/s", kAll,                                                                     \
    "treadmill belt speed in the walking speed (known, or from the stance feet; 0: none, overground)")            \
  X(double, belt_speed_std_mps, 0.0, "m/s", kAll, "its standard deviation (0 when known; in speed_std_mps too)")

/// One estimate, at the time of one frame (YOYOGAIT_ONLINE_ESTIMATE_FIELDS).
struct OnlineEstimate {
  YOYOGAIT_ONLINE_ESTIMATE_FIELDS(YOYOGAIT_RECORD_MEMBER)
};

/// Velocities predicted ahead of the last frame (OnlineEstimator::predict).
struct OnlinePrediction {
  double t_s = 0.0;         ///< the time predicted for: the last frame's time + horizon_s [s]
  double horizon_s = 0.0;   ///< [s]
  double vx_mps = 0.0;      ///< forward velocity (along the heading) at t_s, oscillation included
  double vz_mps = 0.0;      ///< vertical velocity at t_s
  double vx_std_mps = std::numeric_limits<double>::infinity();  ///< its standard deviation (model uncertainty)
  double vz_std_mps = std::numeric_limits<double>::infinity();
  bool valid = false;       ///< 0 <= horizon_s <= kMaxHorizonS and the last estimate is valid (OnlineEstimate::valid)
};

}  // namespace yoyogait
