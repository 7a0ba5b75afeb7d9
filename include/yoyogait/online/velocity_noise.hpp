/// @file online/velocity_noise.hpp
/// @brief The noise of the estimator's input velocities, per channel: their power above the gait's
/// band.
///
/// Walking velocity has its power at the step frequency and its first harmonics, below 6 Hz at any
/// cadence up to 2.5 steps/s; what the input holds above that is noise. A second-order Butterworth
/// high-pass at cutoff_hz, squared and low-passed over tau_s, scaled by nyquist / (nyquist -
/// cutoff_hz) for the noise below the cutoff (a flat noise spectrum), estimates the variance of the
/// noise of each channel (v_x, v_z) as the estimator sees it. The same measure as the offline
/// pipeline's (yoyogait.pipeline.noise), causal. No allocation, no exp.
#pragma once

#include <array>
#include <cmath>

#include "yoyogait/config.hpp"
#include "yoyogait/online/input_noise.hpp"

namespace yoyogait::online {

class VelocityNoise {
 public:
  struct Settings {
    double cutoff_hz = 6.0;  ///< above it the velocity holds no gait [Hz]
    double tau_s = 2.0;      ///< low-pass of the squared high-passed velocity [s]
  };

  VelocityNoise() noexcept = default;
  explicit VelocityNoise(const Settings& s) noexcept : s_(s) {}

  void reset() noexcept {
    x1_ = x2_ = y1_ = y2_ = var_ = {0.0, 0.0};
    n_ = 0;
  }

  /// One sample (v_x, v_z) dt_s after the previous one; non-finite values are skipped.
  void update(double vx_mps, double vz_mps, double dt_s) noexcept {
    if (!(dt_s > 0.0) || !std::isfinite(vx_mps) || !std::isfinite(vz_mps)) return;
    // Sample intervals differ in their last bits from one sample to the next: redesigned only when
    // the interval changes by more than a millionth (the filter does not change by more).
    if (std::fabs(dt_s - dt_s_) > 1e-6 * dt_s) design(dt_s);
    const double x[2] = {vx_mps, vz_mps};
    if (n_ == 0) {
      for (int c = 0; c < 2; ++c) x1_[c] = x2_[c] = x[c];
    }
    ++n_;
    const double g = n_ * g_ < 1.0 ? 1.0 / static_cast<double>(n_) : g_;  // a running mean at first
    for (int c = 0; c < 2; ++c) {
      const double y = b0_ * (x[c] - 2.0 * x1_[c] + x2_[c]) - a1_ * y1_[c] - a2_ * y2_[c];
      x2_[c] = x1_[c];
      x1_[c] = x[c];
      y2_[c] = y1_[c];
      y1_[c] = y;
      if (n_ > kSettleSamples) var_[c] += g * (y * y * scale_ - var_[c]);
    }
  }

  /// The noise variance of v_x and of v_z [(m/s)^2] (0 until the high-pass has settled).
  double vx_var() const noexcept { return var_[0]; }
  double vz_var() const noexcept { return var_[1]; }
  /// What each channel shows beyond the measurement noise r_vx, r_vz the estimator is configured
  /// with [(m/s)^2]: {v_x's, v_z's}, 0 where within it.
  std::array<double, 2> excess_var(double r_vx, double r_vz) const noexcept {
    return {var_[0] > r_vx ? var_[0] - r_vx : 0.0, var_[1] > r_vz ? var_[1] - r_vz : 0.0};
  }
  /// Whether the estimate has its first tau_s.
  bool known() const noexcept { return n_ > kSettleSamples && (n_ - kSettleSamples) * g_ >= 1.0; }

 private:
  static constexpr unsigned kSettleSamples = 4;  ///< the high-pass's start transient is left out

  void design(double dt_s) noexcept {
    dt_s_ = dt_s;
    const double nyquist = 0.5 / dt_s, fc = std::fmin(s_.cutoff_hz, 0.8 * nyquist);
    const double k = std::tan(3.141592653589793 * fc * dt_s), q = 1.4142135623730951;
    const double norm = 1.0 / (1.0 + q * k + k * k);
    b0_ = norm;  // high-pass: (1 - 2 z^-1 + z^-2) norm
    a1_ = 2.0 * (k * k - 1.0) * norm;
    a2_ = (1.0 - q * k + k * k) * norm;
    scale_ = nyquist / (nyquist - fc);
    g_ = dt_s >= s_.tau_s ? 1.0 : dt_s / (s_.tau_s + dt_s);
  }

  Settings s_;
  double dt_s_ = -1.0, b0_ = 1.0, a1_ = 0.0, a2_ = 0.0, scale_ = 1.0, g_ = 1.0;
  std::array<double, 2> x1_{}, x2_{}, y1_{}, y2_{}, var_{};
  unsigned n_ = 0;
};

/// The variance the input noise adds to the estimator's measurement noise of v_x and v_z
/// [(m/s)^2], at a sample dt_s after the previous one: the differentiator's velocity variance P_vv
/// times the share of it the noise above meas_position_std_m makes (0 at clean input, so laboratory
/// results are unchanged); above noise_knee_m, per channel, what the channel shows above the gait's
/// band beyond the configured noise (a camera's depth jitter is v_x's, not v_z's).
inline std::array<double, 2> extra_measurement_var(const InputNoise& noise, double diff_vel_var_m2_per_s2,
                                                   const VelocityNoise& channels, const GaitFilterConfig& gf,
                                                   double dt_s) noexcept {
  if (noise.above_knee() && channels.known())
    return channels.excess_var(gf.meas_vx_density_m2_per_s / dt_s, gf.meas_vz_density_m2_per_s / dt_s);
  const double extra = noise.excess_share() * diff_vel_var_m2_per_s2;
  return {extra, extra};
}

}  // namespace yoyogait::online
