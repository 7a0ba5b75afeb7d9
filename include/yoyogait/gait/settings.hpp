/// @file gait/settings.hpp
/// @brief The gait filter's parts configured from EstimatorConfig and its GaitFilterConfig, setting
/// by setting: the configuration in SI units turned into what each part's step uses
/// (FilterSettings, which GaitFilter's constructor builds its parts from).
#pragma once

#include <limits>

#include "yoyogait/config.hpp"
#include "yoyogait/gait/bound_watchdog.hpp"
#include "yoyogait/gait/cadence_change.hpp"
#include "yoyogait/gait/decay_factors.hpp"
#include "yoyogait/gait/hypothesis_bank.hpp"
#include "yoyogait/gait/innovation_gate.hpp"
#include "yoyogait/gait/member.hpp"
#include "yoyogait/gait/radii.hpp"
#include "yoyogait/gait/spectral_init.hpp"
#include "yoyogait/gait/std_scale.hpp"
#include "yoyogait/gait/walking_detector.hpp"
#include "yoyogait/math.hpp"

namespace yoyogait::gait {

/// The EKF members' model (noise, initial variances, bounds; sec. 2.2, 2.7) from the configuration.
inline MemberModel member_model(const GaitFilterConfig& c, double max_abs_velocity_mps) noexcept {
  MemberModel m;
  m.q_phasor = c.q_phasor_m2_per_s3;
  m.q_phase = c.q_phase_rad2_per_s;
  m.q_omega = c.q_omega_rad2_per_s3;
  m.q_speed = c.q_speed_m2_per_s3;
  m.q_accel = c.q_accel_m2_per_s5;
  m.use_omega_rate = c.use_omega_rate;
  m.q_rate_lo = c.q_omega_rate_lo_rad2_per_s5;
  m.q_rate_hi = c.q_omega_rate_hi_rad2_per_s5;
  m.inv_rate_ref = 1.0 / c.omega_rate_ref_rad_s2;
  m.rate_lowpass = c.omega_rate_lp_tau_s > 0.0;
  m.use_harmonic = c.use_harmonic;
  m.q_harmonic = c.q_harmonic_m2_per_s3;
  m.harm_min2 = c.harmonic_min_amp_mps * c.harmonic_min_amp_mps;
  m.p0_phasor = c.p0_phasor_std_mps * c.p0_phasor_std_mps;
  const double sw = kTwoPi * c.p0_f_std_hz;
  m.p0_omega = sw * sw;
  m.p0_speed = c.p0_speed_std_mps * c.p0_speed_std_mps;
  m.p0_accel = c.p0_accel_std_mps2 * c.p0_accel_std_mps2;
  m.p0_rate = c.use_omega_rate ? c.p0_omega_rate_std_rad_s2 * c.p0_omega_rate_std_rad_s2 : 0.0;
  m.p0_harmonic = c.p0_harmonic_std_mps * c.p0_harmonic_std_mps;
  m.w_min = kTwoPi * c.f_min_hz;
  m.w_max = kTwoPi * c.f_max_hz;
  // Popoviciu's inequality (a quantity within an interval of width L has a variance of at most
  // L^2 / 4): the phasors within +-max_abs_velocity_mps (v_z = Z1, and the oscillation of v_x),
  // A0 within [0, max_abs_velocity_mps], w within [w_min, w_max]. The rates are bounded by their
  // decay (stationary variance q tau / 2); no bound.
  const double v2 = max_abs_velocity_mps * max_abs_velocity_mps, half_w = 0.5 * (m.w_max - m.w_min);
  const double inf = std::numeric_limits<double>::infinity();
  m.max_variance = {v2, v2, v2, v2, half_w * half_w, 0.25 * v2, inf, inf};
  // dw without its rate state is held at exactly zero (a zero row): no noise needed there.
  m.q_floor = detail::py_min(detail::py_min(m.q_phasor, m.q_omega), detail::py_min(m.q_speed, m.q_accel));
  if (m.use_omega_rate) m.q_floor = detail::py_min(m.q_floor, detail::py_min(m.q_rate_lo, m.q_rate_hi));
  return m;
}

/// The start-up bank's settings (sec. 2.3) from the configuration.
inline HypothesisBank::Settings bank_settings(const GaitFilterConfig& c) noexcept {
  HypothesisBank::Settings s;
  s.f_hz = c.bank_f_hz.hz;
  s.size = c.bank_f_hz.size;
  s.prior_f_hz = c.bank_prior_f_hz;
  s.prior_bonus_nats = c.bank_prior_bonus_nats;
  const double sw = kTwoPi * c.spectral_f_std_hz;
  s.seed_f_var = sw * sw;
  s.seed_phasor_var = c.spectral_phasor_std_mps * c.spectral_phasor_std_mps;
  return s;
}

/// The time constants of the dt-dependent factors (sec. 2.5).
inline DecayFactors::TimeConstants time_constants(const GaitFilterConfig& c) noexcept {
  DecayFactors::TimeConstants t;
  t.accel_tau_s = c.accel_tau_s;
  t.omega_rate_tau_s = c.omega_rate_tau_s;
  t.omega_rate_lp_tau_s = c.omega_rate_lp_tau_s;
  t.walk_tau_s = c.walk_tau_s;
  t.std_scale_tau_s = c.std_scale_tau_s;
  t.bank_forget_s = c.bank_forget_s;
  t.radii_tau_s = c.radii_tau_s;
  t.cadence_change_tau_s = c.cadence_change_tau_s;
  t.cadence_change_noise_tau_s = c.cadence_change_noise_tau_s;
  return t;
}

/// The measurement noise densities and the nominal interval (sec. 2.2).
inline DecayFactors::MeasurementNoise measurement_noise(const GaitFilterConfig& c, double sample_time_s) noexcept {
  DecayFactors::MeasurementNoise m;
  m.vx_density = c.meas_vx_density_m2_per_s;
  m.vz_density = c.meas_vz_density_m2_per_s;
  m.nominal_dt_s = sample_time_s;
  return m;
}

/// The walking/standing detector's thresholds (sec. 2.4).
inline WalkingDetector::Thresholds walking_thresholds(const GaitFilterConfig& c) noexcept {
  WalkingDetector::Thresholds t;
  t.tau_s = c.walk_tau_s;
  t.speed_on_mps = c.walk_speed_on_mps;
  t.speed_off_mps = c.walk_speed_off_mps;
  t.vz_rms_on_mps = c.walk_vz_rms_on_mps;
  t.vz_rms_off_mps = c.walk_vz_rms_off_mps;
  return t;
}

/// The innovation gate (sec. 2.5): its release counted in samples of the configuration.
inline InnovationGate::Settings gate_settings(const EstimatorConfig& config) noexcept {
  const GaitFilterConfig& c = config.gait_filter;
  InnovationGate::Settings s;
  s.sigma = c.gate_sigma;
  s.max_consecutive = config.samples_in(c.gate_max_consecutive_s);
  return s;
}

/// The NIS scale of the reported standard deviations (sec. 2.6).
inline StdScale::Settings std_scale_settings(const GaitFilterConfig& c) noexcept {
  StdScale::Settings s;
  s.adapt = c.std_scale_adapt;
  s.min_scale = c.std_scale_min;
  s.max_scale = c.std_scale_max;
  return s;
}

/// The radii's initial values (sec. 2.6).
inline RadiiSmoother::Settings radii_settings(const GaitFilterConfig& c) noexcept {
  RadiiSmoother::Settings s;
  s.initial_R_m = c.initial_R_m;
  s.initial_r_m = c.initial_r_m;
  return s;
}

/// The frequency bounds' watchdog (sec. 2.3).
inline BoundWatchdog::Settings watchdog_settings(const GaitFilterConfig& c) noexcept {
  BoundWatchdog::Settings s;
  s.w_min_rad_s = kTwoPi * c.f_min_hz;
  s.w_max_rad_s = kTwoPi * c.f_max_hz;
  s.limit_s = c.bound_watchdog_s;
  return s;
}

/// The cadence-change detector (sec. 2.8).
inline CadenceChangeDetector::Settings cadence_change_settings(const GaitFilterConfig& c) noexcept {
  CadenceChangeDetector::Settings s;
  s.on = c.cadence_change_adapt;
  s.tau_s = c.cadence_change_tau_s;
  s.horizon_s = c.cadence_change_horizon_s;
  s.max_std_rad_s = kTwoPi * c.cadence_change_max_std_hz;
  s.phase_rad = c.cadence_change_phase_rad;
  s.sigma = c.cadence_change_sigma;
  s.min_amp_mps = c.cadence_change_min_amp_mps;
  s.learn_s = c.cadence_change_noise_tau_s;
  return s;
}

/// The spectral initialisation (sec. 2.3): its buffer in samples, the fits weighted by the
/// measurement variances at the nominal interval.
inline SpectralInit::Settings spectral_settings(const EstimatorConfig& config) noexcept {
  const GaitFilterConfig& c = config.gait_filter;
  SpectralInit::Settings s;
  s.enabled = c.spectral_init;
  s.after_s = c.spectral_init_s;
  s.buffer_samples = config.samples_in(c.spectral_buffer_s);
  s.grid_step_hz = c.spectral_grid_step_hz;
  s.f_min_hz = c.f_min_hz;
  s.f_max_hz = c.f_max_hz;
  s.r_vx = c.meas_vx_density_m2_per_s / config.sample_time_s;
  s.r_vz = c.meas_vz_density_m2_per_s / config.sample_time_s;
  return s;
}

/// Every part of the gait filter, configured.
struct FilterSettings {
  MemberModel model;                              ///< the EKFs' noise, initial covariance, bounds
  MemberModel bank_model;                         ///< the same for the start-up bank's members (its q_omega)
  DecayFactors::TimeConstants time_constants;     ///< of the dt-dependent factors
  DecayFactors::MeasurementNoise measurement_noise;
  WalkingDetector::Thresholds walking;
  InnovationGate::Settings gate;
  StdScale::Settings std_scale;
  RadiiSmoother::Settings radii;
  BoundWatchdog::Settings watchdog;
  CadenceChangeDetector::Settings cadence_change;
  HypothesisBank::Settings bank;
  SpectralInit::Settings spectral;
  double nominal_dt_s = 0.04;        ///< sample_time_s [s]
  double speed_std_floor2 = 0.0;     ///< speed_std_floor_mps^2 [(m/s)^2]
};

/// The gait filter's parts from config (which must pass EstimatorConfig::validate()).
inline FilterSettings filter_settings(const EstimatorConfig& config) noexcept {
  const GaitFilterConfig& c = config.gait_filter;
  FilterSettings s;
  s.model = member_model(c, config.max_abs_velocity_mps);
  GaitFilterConfig bank_c = c;  // the bank's members: the model with their own frequency random walk
  bank_c.q_omega_rad2_per_s3 = c.bank_q_omega_rad2_per_s3;
  s.bank_model = member_model(bank_c, config.max_abs_velocity_mps);
  s.time_constants = time_constants(c);
  s.measurement_noise = measurement_noise(c, config.sample_time_s);
  s.walking = walking_thresholds(c);
  s.gate = gate_settings(config);
  s.std_scale = std_scale_settings(c);
  s.radii = radii_settings(c);
  s.watchdog = watchdog_settings(c);
  s.cadence_change = cadence_change_settings(c);
  s.bank = bank_settings(c);
  s.spectral = spectral_settings(config);
  s.nominal_dt_s = config.sample_time_s;
  s.speed_std_floor2 = c.speed_std_floor_mps * c.speed_std_floor_mps;
  return s;
}

}  // namespace yoyogait::gait
