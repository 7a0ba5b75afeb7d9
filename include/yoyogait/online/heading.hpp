/// @file online/heading.hpp
/// @brief The walking heading, frame by frame: the horizontal velocity low-passed over about a
/// stride, turned forward by the low-pass's lag in a turn (docs/online.md sec. 1, "Heading,
/// forward and vertical velocity").
///
/// A first-order low-pass of a vector turning at w lags it by atan(w tau). The turn rate of the
/// low-passed direction (itself low-passed with the same gain) gives that lag, and the heading is
/// the low-passed direction turned forward by it. Below a minimum low-passed speed the last heading
/// is held and the turn rate forgotten.
#pragma once

#include <array>
#include <cmath>

#include "yoyogait/online/interval_cache.hpp"

namespace yoyogait::online {

/// Heading tracker with turn-lag compensation. Everything per frame is noexcept and allocation-free.
class HeadingTracker {
 public:
  struct Settings {
    double tau_s = 0.5;            ///< low-pass time constant of the horizontal velocity [s]
    double min_speed_mps = 0.1;    ///< below this low-passed speed the heading is held [m/s]
  };

  HeadingTracker() noexcept = default;
  explicit HeadingTracker(const Settings& s) noexcept : s_(s) { reset(); }

  /// No heading yet: the low-pass at rest, the unit vector along the first horizontal axis.
  void reset() noexcept {
    lp_ = {0.0, 0.0};
    unit_ = {1.0, 0.0};
    known_ = false;
    dir_ = {1.0, 0.0};
    dir_known_ = false;
    turn_rate_rad_s_ = 0.0;
    alpha_.reset();
  }

  /// One frame of horizontal velocity (va_mps, vb_mps) on the axes a, b, dt_s (> 0) after the
  /// previous one.
  void update(double va_mps, double vb_mps, double dt_s) noexcept {
    // The gain changes only with the frame interval.
    const double alpha = alpha_.at(dt_s, [this](double dt) { return 1.0 - std::exp(-dt / s_.tau_s); });
    lp_[0] += alpha * (va_mps - lp_[0]);
    lp_[1] += alpha * (vb_mps - lp_[1]);
    const double s = std::sqrt(lp_[0] * lp_[0] + lp_[1] * lp_[1]);
    if (!(s >= s_.min_speed_mps && s > 0.0)) {
      dir_known_ = false;
      turn_rate_rad_s_ = 0.0;
      return;
    }
    const double ua = lp_[0] / s, ub = lp_[1] / s;
    if (dir_known_) {
      const double sin_turn = dir_[0] * ub - dir_[1] * ua;  // sin of the turn since the last frame
      turn_rate_rad_s_ += alpha * (sin_turn / dt_s - turn_rate_rad_s_);
      // No walker turns faster than this; it also keeps frames microseconds apart harmless.
      if (!(std::fabs(turn_rate_rad_s_) <= kMaxTurnRateRadS))
        turn_rate_rad_s_ = turn_rate_rad_s_ > 0.0 ? kMaxTurnRateRadS : -kMaxTurnRateRadS;
    }
    dir_ = {ua, ub};
    dir_known_ = true;
    const double k = turn_rate_rad_s_ * s_.tau_s;  // tan of the lag
    const double cs = 1.0 / std::sqrt(1.0 + k * k), sn = k * cs;
    unit_ = {ua * cs - ub * sn, ua * sn + ub * cs};
    known_ = true;
  }

  /// Whether a heading has been found since the last reset.
  bool known() const noexcept { return known_; }
  /// The heading's unit vector on the axes a, b ((1, 0) before the first heading).
  const std::array<double, 2>& unit() const noexcept { return unit_; }
  /// atan2(b, a) of unit() [rad].
  double heading_rad() const noexcept { return std::atan2(unit_[1], unit_[0]); }
  /// The horizontal velocity (va_mps, vb_mps) along the heading; before the first heading, its norm
  /// less what a velocity noise of noise_var_m2_per_s2 per axis gives it: sqrt(max(0, |v|^2 -
  /// kNoiseChi2 noise_var)), so that noise alone exceeds 0 with probability exp(-kNoiseChi2 / 2).
  double forward_mps(double va_mps, double vb_mps, double noise_var_m2_per_s2 = 0.0) const noexcept {
    if (known_) return va_mps * unit_[0] + vb_mps * unit_[1];
    const double n2 = va_mps * va_mps + vb_mps * vb_mps - kNoiseChi2 * noise_var_m2_per_s2;
    return n2 > 0.0 ? std::sqrt(n2) : 0.0;
  }
  /// |v|^2 of a 2-D Gaussian noise of variance N per axis exceeds x with probability exp(-x / 2N):
  /// 6 N, 5 %.
  static constexpr double kNoiseChi2 = 6.0;
  /// The low-passed turn rate of the direction [rad/s].
  double turn_rate_rad_s() const noexcept { return turn_rate_rad_s_; }

  /// The turn rate is clipped to +-this [rad/s].
  static constexpr double kMaxTurnRateRadS = 10.0;

 private:
  Settings s_;
  std::array<double, 2> lp_{};             ///< the low-passed horizontal velocity [m/s]
  std::array<double, 2> unit_{1.0, 0.0};   ///< the heading (lag-compensated)
  std::array<double, 2> dir_{1.0, 0.0};    ///< the low-passed direction at the last frame
  bool known_ = false, dir_known_ = false;
  double turn_rate_rad_s_ = 0.0;
  IntervalCache<double> alpha_;  ///< the low-pass gain at the last intervals
};

}  // namespace yoyogait::online
