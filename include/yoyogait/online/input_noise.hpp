/// @file online/input_noise.hpp
/// @brief The noise of the measured centre, estimated online from the differentiator's innovations,
/// and the measurement noise the differentiator is given from it (docs/online.md, "Input noise").
///
/// A Kalman filter whose model holds has innovations of variance H P- H^T + R: the mean squared
/// innovation less the part the filter's own uncertainty explains (P-_pp) estimates R, whatever R the
/// filter was given. Low-passed (a running mean over the first frames, then over noise_tau_s), it is
/// the differentiator's measurement noise from the next frame on (never below meas_position_std_m),
/// so that the same defaults serve a 0.2 mm camera system and centimetres of markerless jitter. An
/// innovation beyond the outlier gate counts only up to the gate (a swap or a jump does not inflate
/// the estimate). No allocation, no exp.
#pragma once

#include <cstddef>

#include "yoyogait/online/interval_cache.hpp"

namespace yoyogait::online {

class InputNoise {
 public:
  struct Settings {
    double floor_m = 0.001;     ///< the least noise given to the differentiator (meas_position_std_m) [m]
    double tau_s = 1.0;         ///< low-pass of the estimate [s]
    double gate_nis = 25.0;     ///< the outlier gate on the innovation's NIS over the three axes
    bool adapt = true;          ///< false: the differentiator keeps floor_m
    double knee_m = 1e100;      ///< above it the ratio estimate bounds the difference (noise_knee_m) [m]
  };

  InputNoise() noexcept = default;
  explicit InputNoise(const Settings& s) noexcept
      : s_(s), floor2_(s.floor_m * s.floor_m), knee2_(s.knee_m < 1e150 ? s.knee_m * s.knee_m : 1e300) {
    reset();
  }

  void reset() noexcept {
    var_m2_ = rat_m2_ = 0.0;
    n_ = 0;
  }

  /// One update dt_s after the previous frame: the mean squared innovation per axis and the
  /// predicted variance P-_pp [m^2], with the measurement variance r2_m2 the filter used.
  void update(double dt_s, double innovation2_m2, double predicted_var_m2, double r2_m2) noexcept {
    if (!(dt_s > 0.0)) return;
    g_ = gain_.at(dt_s, [this](double dt) { return dt >= s_.tau_s ? 1.0 : dt / (s_.tau_s + dt); });
    const double s = predicted_var_m2 + r2_m2, cap = s_.gate_nis * (1.0 / 3.0) * s;
    const double nu2 = innovation2_m2 < cap ? innovation2_m2 : cap;
    const double x = nu2 - predicted_var_m2;
    // A running mean until it is longer than the low-pass: the estimate is there within a few frames.
    ++n_;
    const double g = g_ * static_cast<double>(n_) < 1.0 ? 1.0 / static_cast<double>(n_) : g_;
    var_m2_ += g * ((x > 0.0 ? x : 0.0) - var_m2_);
    rat_m2_ += g * (nu2 * (r2_m2 / s) - rat_m2_);
    // While the running mean lasts the differentiator has not followed the noise yet, and the
    // difference overshoots it by P-_pp / r^2 (40 at 30 Hz at the floor): above knee_m the innovations'
    // share of their predicted variance, times the noise assumed, bounds it (with a jerk density
    // that follows the noise, the consistent estimate in one step). Both have the same fixed point.
    if (g != g_ && var_m2_ > knee2_) {
      const double b = rat_m2_ > knee2_ ? rat_m2_ : knee2_;
      if (b < var_m2_) var_m2_ = b;
    }
  }

  /// Whether the estimated noise is above knee_m (the front-end adapts to it: noise_knee_m).
  bool above_knee() const noexcept { return var_m2_ > knee2_; }
  /// Whether the running mean of the first frames is over (the estimate is known; the gate applies).
  bool known() const noexcept { return g_ * static_cast<double>(n_) >= 1.0; }
  /// The estimated noise variance of the centre per axis [m^2].
  double var_m2() const noexcept { return var_m2_; }
  /// The measurement variance for the differentiator [m^2]: the estimate, at least floor_m^2.
  double meas_var_m2() const noexcept { return s_.adapt && var_m2_ > floor2_ ? var_m2_ : floor2_; }
  double gate_nis() const noexcept { return s_.gate_nis; }
  /// The share of a velocity variance that the noise above floor_m adds: 1 - floor^2 / r^2 (0 at the floor).
  double excess_share() const noexcept {
    const double r2 = meas_var_m2();
    return r2 > floor2_ ? 1.0 - floor2_ / r2 : 0.0;
  }

 private:
  Settings s_;
  double floor2_ = 1e-6, knee2_ = 1e300, var_m2_ = 0.0, g_ = 1.0;
  IntervalCache<double> gain_;  ///< g_ at the last intervals
  double rat_m2_ = 0.0;  ///< low-passed innovation^2 r^2 / (P-_pp + r^2) [m^2]
  std::size_t n_ = 0;
};

}  // namespace yoyogait::online
