/// @file online/online_estimate.hpp
/// @brief What OnlineEstimator reports: OnlineStatus, OnlineEstimate (one per frame) and
/// OnlinePrediction (OnlineEstimator::predict).
#pragma once

#include <cstdint>
#include <limits>

#include "yoyogait/estimate.hpp"

namespace yoyogait {

/// What update() did with its frame.
enum class OnlineStatus : std::uint8_t {
  kUsed = 0,               ///< the frame was used
  kAllMissing = 1,         ///< no point was seen: the estimate is carried forward by prediction
  kTimeNotIncreasing = 2,  ///< the timestamp did not increase: the frame was ignored
  kGapRestart = 3,         ///< used, after a gap longer than max_gap_s that restarted the front-end
  kNonFinite = 4,          ///< non-finite timestamp, or every seen coordinate non-finite or absurd: ignored
};

/// One estimate, at the time of one frame. Velocities in m/s in the frame of the data (the up
/// axis given at construction; "horizontal" = the two other axes in increasing order, a then b).
struct OnlineEstimate {
  double t_s = 0.0;          ///< the frame's timestamp [s] (an ignored frame: the last one accepted)
  double vx_mps = 0.0;       ///< front-end: horizontal velocity along the heading
  double vz_mps = 0.0;       ///< front-end: vertical velocity
  double vh_a_mps = 0.0;     ///< front-end: horizontal velocity, first horizontal axis
  double vh_b_mps = 0.0;     ///< ... second horizontal axis
  double heading_rad = 0.0;  ///< atan2(b, a) of the low-passed horizontal velocity (held when slow)
  double walk_a_mps = 0.0;   ///< walking velocity without the oscillation: speed_mps along the heading, axis a
  double walk_b_mps = 0.0;   ///< ... axis b
  double vx_hat_mps = 0.0;   ///< the estimator's reconstruction of v_x (with harmonics), at t_s;
                             ///< before the estimator's first sample, the front-end's vx_mps
  double vz_hat_mps = 0.0;   ///< ... of v_z, at t_s; before the first sample, vz_mps
  double step_frequency_hz = 0.0;
  double step_frequency_std_hz = 0.0;
  double speed_mps = 0.0;  ///< forward speed without the oscillation (A0)
  double speed_std_mps = 0.0;
  /// Phase within the current step, in [0, 1): the angle of the vertical oscillation's phasor,
  /// v_z ~ |Z| cos(2 pi gait_phase). 0: fastest rise of the pelvis; 0.25: highest; 0.5: fastest
  /// fall; 0.75: lowest (about the double support after heel strike). Held while standing.
  double gait_phase = 0.0;
  /// Time from t_s to the next step [s]: the next time gait_phase reaches 0.75 (the pelvis low
  /// point, about the double support after heel strike), at the present step frequency and its
  /// rate. In [0, 1 / f); counts down and wraps once per step. NaN while not walking.
  double next_step_in_s = 0.0;
  double input_latency_s = 0.0;  ///< delay of vx_mps, vz_mps behind the true velocity at latency_f_hz [s]
  double estimate_age_s = 0.0;   ///< time since the estimator's last sample [s]
  OnlineStatus status = OnlineStatus::kUsed;
  Status estimator_status = Status::kUpdated;  ///< of the estimator's last sample
  bool walking = false;                        ///< the estimator's walking/standing detector
  bool estimator_fed = false;                  ///< this frame completed an interval and fed the estimator
  std::uint8_t points_seen = 0;                ///< points used on this frame
};

/// Velocities predicted ahead of the last frame (OnlineEstimator::predict).
struct OnlinePrediction {
  double t_s = 0.0;         ///< the time predicted for: the last frame's time + horizon_s [s]
  double horizon_s = 0.0;   ///< [s]
  double vx_mps = 0.0;      ///< forward velocity (along the heading) at t_s, oscillation included
  double vz_mps = 0.0;      ///< vertical velocity at t_s
  double vx_std_mps = std::numeric_limits<double>::infinity();  ///< its standard deviation (model uncertainty)
  double vz_std_mps = std::numeric_limits<double>::infinity();
  bool valid = false;       ///< the estimator has been fed and 0 <= horizon_s <= kMaxHorizonS
};

}  // namespace yoyogait
