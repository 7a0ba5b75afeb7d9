/// @file gait/forecast.hpp
/// @brief GaitFilter::predict and GaitFilter::forecast, a yoyogait::Forecast: the mean of the filter's
/// own model h_s ahead (rates included in the forecast) and the covariance propagated by its
/// prediction (docs/online.md sec. 5).
/// Included by gait/gait_filter.hpp.
#pragma once

#include <array>
#include <cmath>

#include "yoyogait/forecast.hpp"
#include "yoyogait/gait/gait_filter.hpp"

namespace yoyogait {

namespace gait {
/// x weighted by x^2 / (x^2 + var): the part of an estimate x of variance var that its std does not
/// hide (0 for x = 0 and var = 0 both).
inline double known_part(double x, double var) noexcept {
  const double x2 = x * x, d = x2 + var;
  return d > 0.0 ? x * (x2 / d) : 0.0;
}
}  // namespace gait

inline GaitFilter::Prediction GaitFilter::predict(double h_s, bool harmonics) const noexcept {
  using namespace gait;
  const GaitState& x = active().x;
  if (!detector_.walking()) return Prediction{x[kA0], 0.0};
  return turned(x[kW] * h_s + 0.5 * x[kDW] * h_s * h_s, x[kA0], harmonics);
}

inline GaitFilter::Prediction GaitFilter::turned(double angle_rad, double A0, bool harmonics,
                                                  double coherence) const noexcept {
  using namespace gait;
  const GaitState& x = active().x;
  double s, c;
  sincos(angle_rad, s, c);
  const double X1 = c * x[kX1] - s * x[kX2], X2 = s * x[kX1] + c * x[kX2];
  const double Z1 = c * x[kZ1] - s * x[kZ2], Z2 = s * x[kZ1] + c * x[kZ2];
  Prediction p{A0 + coherence * X1, coherence * Z1};
  if (harmonics && model_.use_harmonic && !acquiring_) {
    const gait::Harmonic* fh = active_harmonics();
    double ux, vx2, uz, vz2;
    harmonic_basis(X1, X2, model_.harm_min2, ux, vx2);
    harmonic_basis(Z1, Z2, model_.harm_min2, uz, vz2);
    const double c2 = coherence * coherence, c4 = c2 * c2;
    p.vx_mps += c4 * fh[kVx].value(ux, vx2);
    p.vz_mps += c4 * fh[kVz].value(uz, vz2);
  }
  return p;
}

// The mean of the filter's own model h_s >= 0 ahead (docs/online.md sec. 5), in closed form: dA0 and
// dw decay as exp(-t / tau) (accel_tau_s, omega_rate_tau_s), so A0(h) = A0 + dA0 tau_a (1 -
// e^{-h/tau_a}), w(h) = w + dw tau_b (1 - e^{-h/tau_b}) and the phasors turn by the integral of w(t);
// each rate weighted by the share of it that its std does not hide (x^2 / (x^2 + lambda P)), and the
// oscillation by exp(-s2 / 2), s2 the variance of the turn over h (its harmonic by exp(-2 s2)): the
// mean under the model's own phase uncertainty. Second harmonics at the turned phasors unless the
// bank is running. with_std: the covariance is propagated by the filter's prediction (transition
// Jacobian and process noise, sec. 2.1-2.2) in steps of at most sample_time_s, scaled by the std
// scale lambda. Copies only; no allocation. With decay, its exp factors are the caller's cache (no
// expm1 at a repeated h_s).
inline Forecast GaitFilter::forecast(double h_s, bool with_std, double phase_var_scale) const noexcept {
  const GaitFilterConfig& g = cfg_.gait_filter;
  return forecast_at(h_s, with_std, -std::expm1(-h_s / g.accel_tau_s), -std::expm1(-h_s / g.omega_rate_tau_s),
                     phase_var_scale);
}

inline Forecast GaitFilter::forecast(double h_s, bool with_std, gait::HorizonDecay& decay,
                                     double phase_var_scale) const noexcept {
  const GaitFilterConfig& g = cfg_.gait_filter;
  double ea, eb;
  decay.at(h_s, g.accel_tau_s, g.omega_rate_tau_s, ea, eb);
  return forecast_at(h_s, with_std, ea, eb, phase_var_scale);
}

// ea, eb: 1 - exp(-h_s / tau) of accel_tau_s and omega_rate_tau_s.
inline Forecast GaitFilter::forecast_at(double h_s, bool with_std, double ea, double eb,
                                        double phase_var_scale) const noexcept {
  using namespace gait;
  const Ekf& f = active();
  const GaitState& x = f.x;
  const GaitFilterConfig& g = cfg_.gait_filter;
  Forecast out;
  // The rates where they are known: each weighted by x^2 / (x^2 + lambda P), the share of its
  // estimate that stands above its std (a rate lost in its noise, as early in a walk, is not
  // extrapolated; one well above it is used in full).
  const double lam = scale_.value();
  const double dA0 = gait::known_part(x[kDA0], lam * f.P[kDA0][kDA0]);
  const double dW = gait::known_part(x[kDW], lam * f.P[kDW][kDW]);
  out.speed_mps = x[kA0] + dA0 * g.accel_tau_s * ea;
  out.omega_rate_rad_s2 = dW * (1.0 - eb);
  out.omega_rad_s = x[kW] + dW * g.omega_rate_tau_s * eb;
  out.phase_advance_rad = x[kW] * h_s + dW * g.omega_rate_tau_s * (h_s - g.omega_rate_tau_s * eb);
  const bool walking = detector_.walking();
  if (walking) {
    // The mean of the oscillation under the model's phase uncertainty over h: the turn's variance
    // from P_ww, P_w,dw, P_dwdw and the random walks of w and of the phase over h (q_omega h^3 / 3,
    // q_phase h), so that a far or uncertain forecast tends to the mean velocity instead of
    // extrapolating a phase it does not know. At frame-time horizons (tens of ms) it is ~1.
    // The estimate's share scaled by phase_var_scale, as the stds are where the model holds less.
    const double h2 = h_s * h_s;
    const double var_turn = phase_var_scale * lam *
                                (f.P[kW][kW] * h2 + f.P[kW][kDW] * h2 * h_s + 0.25 * f.P[kDW][kDW] * h2 * h2) +
                            (acquiring_ ? bank_model_ : model_).q_omega * h2 * h_s * (1.0 / 3.0) + model_.q_phase * h_s;
    // exp(-v / 2); below 1e-3 its second-order series (within 1e-10, no exp on the per-frame path).
    const double coherence =
        var_turn < 1e-3 ? 1.0 - 0.5 * var_turn * (1.0 - 0.25 * var_turn) : std::exp(-0.5 * var_turn);
    const Prediction p = turned(out.phase_advance_rad, out.speed_mps, true, coherence);
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
