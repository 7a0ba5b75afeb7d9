/// @file gait/forecast.hpp
/// @brief GaitFilter::forecast, a yoyogait::Forecast: the mean of the filter's own model h_s ahead,
/// rates included, and the covariance propagated by its prediction (docs/online.md sec. 5).
/// Included by gait/gait_filter.hpp.
#pragma once

#include <array>
#include <cmath>

#include "yoyogait/forecast.hpp"
#include "yoyogait/gait/gait_filter.hpp"

namespace yoyogait {

inline Forecast GaitFilter::forecast(double h_s, bool with_std) const noexcept {
  using namespace gait;
  const Ekf& f = active();
  const GaitState& x = f.x;
  const GaitFilterConfig& g = cfg_.gait_filter;
  const double ea = -std::expm1(-h_s / g.accel_tau_s), eb = -std::expm1(-h_s / g.omega_rate_tau_s);
  Forecast out;
  out.speed_mps = x[kA0] + x[kDA0] * g.accel_tau_s * ea;
  out.omega_rate_rad_s2 = x[kDW] * (1.0 - eb);
  out.omega_rad_s = x[kW] + x[kDW] * g.omega_rate_tau_s * eb;
  out.phase_advance_rad = x[kW] * h_s + x[kDW] * g.omega_rate_tau_s * (h_s - g.omega_rate_tau_s * eb);
  const bool walking = detector_.walking();
  if (walking) {
    const Prediction p = turned(out.phase_advance_rad, out.speed_mps, true);
    out.vx_mps = p.vx_mps;
    out.vz_mps = p.vz_mps;
  } else {
    out.vx_mps = out.speed_mps;
  }
  if (!with_std) return out;
  Ekf e = f;
  std::array<gait::Harmonic, 2> hc{active_harmonics()[kVx], active_harmonics()[kVz]};
  if (h_s > 0.0) {
    // At most kMaxForecastSteps steps (longer ones beyond): a bounded cost for any horizon.
    double n = std::ceil(h_s / nominal_dt_ - 1e-9);
    if (!(n <= kMaxForecastSteps)) n = kMaxForecastSteps;
    const double dt = h_s / (n > 1.0 ? n : 1.0);
    DecayFactors::Values fc;
    fc.dt = dt;
    fc.accel_decay = std::exp(-dt / g.accel_tau_s);
    fc.rate_decay = std::exp(-dt / g.omega_rate_tau_s);
    fc.rate_lp_gain = g.omega_rate_lp_tau_s > 0.0 ? 1.0 - std::exp(-dt / g.omega_rate_lp_tau_s) : 1.0;
    for (double k = 0.0; k < n; k += 1.0) model_.predict(e, hc.data(), dt, fc, walking);
  }
  const double lam = scale_.value();
  const GaitMatrix& P = e.P;  // upper triangle
  // Averaged over the step cycle: the variance of X1 alone swings between the phasor's radial
  // (amplitude) and tangential (phase) variance as it turns; half the trace is their mean, and the
  // X1-A0 covariance turns with it and averages out.
  const double var_x = walking ? 0.5 * (P[kX1][kX1] + P[kX2][kX2]) + P[kA0][kA0] : P[kA0][kA0];
  out.vx_std_mps = std::sqrt(detail::py_max(lam * var_x, 0.0));
  out.vz_std_mps = walking ? std::sqrt(detail::py_max(lam * 0.5 * (P[kZ1][kZ1] + P[kZ2][kZ2]), 0.0)) : 0.0;
  return out;
}

}  // namespace yoyogait
