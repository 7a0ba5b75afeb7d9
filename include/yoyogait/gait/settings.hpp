/// @file gait/settings.hpp
/// @brief The gait filter's parts configured from GaitFilterConfig: the EKF members' model and the
/// start-up bank's settings (the configuration in SI units turned into what each step uses).
#pragma once

#include <limits>

#include "yoyogait/config.hpp"
#include "yoyogait/gait/hypothesis_bank.hpp"
#include "yoyogait/gait/member.hpp"
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

}  // namespace yoyogait::gait
