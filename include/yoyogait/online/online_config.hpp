/// @file online/online_config.hpp
/// @brief OnlineConfig: every setting of the online front-end, in seconds, metres or noise densities.
#pragma once

#include <cmath>

#include "yoyogait/config.hpp"

namespace yoyogait {

/// Settings of OnlineEstimator (docs/online.md). None is a number of frames: the front-end behaves
/// the same at any capture rate.
struct OnlineConfig {
  /// The gait estimator behind the front-end. It is fed every estimator.sample_time_s (0.04 s, the
  /// paper's 25 Hz) with the mean of the front-end's velocities over that interval (the
  /// anti-aliasing filter of the decimation).
  EstimatorConfig estimator{};

  /// Anti-aliasing in front of the decimation: second-order Butterworth low-pass of the forward and
  /// vertical velocity at this cutoff (0: only the mean over the interval) [Hz]. Its delay is
  /// compensated by the estimator's prediction, so the estimates stay aligned with the frame time.
  double antialias_hz = 0.0;

  /// Differentiator: constant-acceleration Kalman filter, white-jerk noise density [m^2/s^5] ...
  double q_jerk_m2_per_s5 = 1000.0;
  /// ... and the noise of the centre's position [m] (marker noise, about 1 mm).
  double meas_position_std_m = 0.001;
  /// Initial uncertainty of velocity [m/s] and acceleration [m/s^2] after a (re)start.
  double initial_velocity_std_mps = 1.0;
  double initial_accel_std_mps2 = 10.0;
  /// After a (re)start, the estimator is fed only once the differentiator has run this long [s].
  double settle_s = 0.1;

  /// Centre of the points: a step of the centre when the visible markers change is blended out
  /// with this time constant [s]; a marker unseen for centre_forget_s leaves the set [s].
  double centre_blend_tau_s = 0.3;
  double centre_forget_s = 2.0;
  /// A coordinate beyond this (after the length unit) counts as missing [m].
  double max_abs_position_m = 1e5;
  /// No point seen for longer than this: the front-end restarts (kGapRestart) [s].
  double max_gap_s = 0.25;

  /// Heading: first-order low-pass of the horizontal velocity over about half a stride, turned
  /// forward by its lag in a turn (atan of the low-passed turn rate times heading_tau_s) [s]; below
  /// heading_min_speed_mps of low-passed speed the last heading is held [m/s].
  double heading_tau_s = 0.5;
  double heading_min_speed_mps = 0.1;

  /// Frequency at which input_latency_s is evaluated (a typical step frequency) [Hz].
  double latency_f_hz = 2.0;

  /// nullptr when usable, else what is wrong.
  const char* validate() const noexcept {
    auto positive = [](double v) { return std::isfinite(v) && v > 0.0; };
    auto nonneg = [](double v) { return std::isfinite(v) && v >= 0.0; };
    if (const char* e = estimator.validate()) return e;
    if (!nonneg(antialias_hz)) return "antialias_hz must be finite and >= 0";
    if (!positive(q_jerk_m2_per_s5)) return "q_jerk_m2_per_s5 must be finite and > 0";
    if (!positive(meas_position_std_m)) return "meas_position_std_m must be finite and > 0";
    if (!positive(initial_velocity_std_mps)) return "initial_velocity_std_mps must be finite and > 0";
    if (!positive(initial_accel_std_mps2)) return "initial_accel_std_mps2 must be finite and > 0";
    if (!nonneg(settle_s)) return "settle_s must be finite and >= 0";
    if (!positive(centre_blend_tau_s)) return "centre_blend_tau_s must be finite and > 0";
    if (!positive(centre_forget_s)) return "centre_forget_s must be finite and > 0";
    if (!positive(max_abs_position_m)) return "max_abs_position_m must be finite and > 0";
    if (!positive(max_gap_s)) return "max_gap_s must be finite and > 0";
    if (!positive(heading_tau_s)) return "heading_tau_s must be finite and > 0";
    if (!nonneg(heading_min_speed_mps)) return "heading_min_speed_mps must be finite and >= 0";
    if (!positive(latency_f_hz)) return "latency_f_hz must be finite and > 0";
    if (estimator.algorithm != Algorithm::kGaitFilter)
      return "the online estimator runs the gait filter (algorithm gait_filter)";
    return nullptr;
  }
};

}  // namespace yoyogait
