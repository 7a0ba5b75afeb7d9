/// @file online/settings.hpp
/// @brief The online front-end's parts configured from OnlineConfig, setting by setting (what
/// OnlineEstimator's constructor builds its parts from).
#pragma once

#include "yoyogait/online/belt.hpp"
#include "yoyogait/online/centre.hpp"
#include "yoyogait/online/decimator.hpp"
#include "yoyogait/online/foot_cadence.hpp"
#include "yoyogait/online/differentiator.hpp"
#include "yoyogait/online/gait_evidence.hpp"
#include "yoyogait/online/heading.hpp"
#include "yoyogait/online/input_noise.hpp"
#include "yoyogait/online/latency.hpp"
#include "yoyogait/online/online_config.hpp"
#include "yoyogait/online/timestamp_gate.hpp"
#include "yoyogait/online/validity.hpp"

namespace yoyogait::online {

/// The centre's settings (centre_blend_tau_s, centre_forget_s).
inline CausalCentre::Settings centre_settings(const OnlineConfig& c) noexcept {
  CausalCentre::Settings s;
  s.blend_tau_s = c.centre_blend_tau_s;
  s.forget_s = c.centre_forget_s;
  return s;
}

/// The differentiator's settings (q_jerk_m2_per_s5, meas_position_std_m, initial_velocity_std_mps,
/// initial_accel_std_mps2).
inline KalmanDifferentiator::Settings differentiator_settings(const OnlineConfig& c) noexcept {
  KalmanDifferentiator::Settings s;
  s.q_jerk_m2_per_s5 = c.q_jerk_m2_per_s5;
  s.meas_std_m = c.meas_position_std_m;
  s.v0_std_mps = c.initial_velocity_std_mps;
  s.a0_std_mps2 = c.initial_accel_std_mps2;
  s.knee_std_m = c.noise_knee_m;
  return s;
}

/// The input-noise estimate's settings (meas_position_std_m, adapt_to_noise, noise_tau_s,
/// outlier_gate_nis).
inline InputNoise::Settings input_noise_settings(const OnlineConfig& c) noexcept {
  InputNoise::Settings s;
  s.floor_m = c.meas_position_std_m;
  s.adapt = c.adapt_to_noise;
  s.tau_s = c.noise_tau_s;
  s.gate_nis = c.outlier_gate_nis;
  s.knee_m = c.noise_knee_m;
  return s;
}

/// The gait evidence's settings (gait_bob_m, gait_window_s, gait_max_bob_m, gait_keep_bob_m).
inline GaitEvidence::Settings gait_evidence_settings(const OnlineConfig& c) noexcept {
  GaitEvidence::Settings s;
  s.bob_m = c.gait_bob_m;
  s.window_s = c.gait_window_s;
  s.max_bob_m = c.gait_max_bob_m;
  s.keep_bob_m = c.gait_keep_bob_m;
  return s;
}

/// The feet's cadence settings (the least swing of the separation, gait_window_s).
inline FootCadence::Settings foot_cadence_settings(const OnlineConfig& c) noexcept {
  FootCadence::Settings s;
  s.window_s = c.gait_window_s;
  return s;
}

/// The heading tracker's settings (heading_tau_s, heading_min_speed_mps).
inline HeadingTracker::Settings heading_settings(const OnlineConfig& c) noexcept {
  HeadingTracker::Settings s;
  s.tau_s = c.heading_tau_s;
  s.min_speed_mps = c.heading_min_speed_mps;
  return s;
}

/// The decimator's settings (the estimator's sample_time_s, antialias_hz).
inline Decimator::Settings decimator_settings(const OnlineConfig& c) noexcept {
  Decimator::Settings s;
  s.sample_time_s = c.estimator.sample_time_s;
  s.antialias_hz = c.antialias_hz;
  return s;
}

/// The latency bookkeeping's settings (latency_f_hz).
inline Latency::Settings latency_settings(const OnlineConfig& c) noexcept {
  Latency::Settings s;
  s.f_hz = c.latency_f_hz;
  return s;
}

/// The validity checks' settings (valid_after_s, min_rate_hz, max_plausible_speed_mps,
/// max_input_noise_m, max_mean_nis, phase_std_tau_s; stale after max_gap_s plus two estimator
/// samples; the estimator's frequency range).
inline Validity::Settings validity_settings(const OnlineConfig& c) noexcept {
  Validity::Settings s;
  s.valid_after_s = c.valid_after_s;
  s.min_rate_hz = c.min_rate_hz;
  s.max_plausible_speed_mps = c.max_plausible_speed_mps;
  s.max_input_noise_m = c.max_input_noise_m;
  s.feet_max_input_noise_m = c.feet_max_input_noise_m;
  s.max_nis = c.max_mean_nis;
  s.stale_s = c.max_gap_s + 2.0 * c.estimator.sample_time_s;
  s.f_min_hz = c.estimator.gait_filter.f_min_hz;
  s.f_max_hz = c.estimator.gait_filter.f_max_hz;
  s.phase_tau_s = c.phase_std_tau_s;
  return s;
}

/// The belt tracker's settings (belt_tau_s, treadmill_min_belt_mps, stance_band_m,
/// treadmill_heading_rad, treadmill_max_pelvis_mps; a stance velocity beyond max_plausible_speed_mps is none).
inline BeltTracker::Settings belt_settings(const OnlineConfig& c) noexcept {
  BeltTracker::Settings s;
  s.tau_s = c.belt_tau_s;
  s.min_belt_mps = c.treadmill_min_belt_mps;
  s.stance_band_m = c.stance_band_m;
  s.heading_rad = c.treadmill_heading_rad;
  s.max_pelvis_mps = c.treadmill_max_pelvis_mps;
  s.max_belt_mps = c.max_plausible_speed_mps;
  return s;
}

/// The timestamp gate's settings (max_time_jump_s, max_gap_s).
inline TimestampGate::Settings timestamp_gate_settings(const OnlineConfig& c) noexcept {
  TimestampGate::Settings s;
  s.max_time_jump_s = c.max_time_jump_s;
  s.max_gap_s = c.max_gap_s;
  return s;
}

}  // namespace yoyogait::online
