/// @file imu/mag_gate.hpp
/// @brief Which magnetometer samples the heading may use: finite, and with a norm near the field's
/// own (a passing disturbance, a steel door, changes it); a field rejected for long on end is a new
/// place's and becomes the reference (docs/imu.md, section 2, "With a magnetometer"). No allocation.
#pragma once

#include <cmath>

#include "yoyogait/imu/mahony.hpp"
#include "yoyogait/math.hpp"

namespace yoyogait::imu {

class MagGate {
 public:
  /// A norm rejected this long on end becomes the reference norm [s].
  static constexpr double kAdaptS = 30.0;

  /// tolerance: the accepted relative distance from the reference norm; tau_s: the reference's low-pass.
  MagGate(double tolerance, double tau_s) noexcept : tolerance_(tolerance), gain_(tau_s) {}

  void reset() noexcept { norm_lp_ = rejected_since_s_ = 0.0; }

  /// Whether the field m (any unit, sensor frame) at t_s, dt_s after the previous sample, may be used.
  bool accept(double t_s, double dt_s, const Vec3& m) noexcept {
    const double mn = Mahony::norm(m);
    if (!(std::isfinite(mn) && mn > 0.0)) return false;
    if (!(norm_lp_ > 0.0)) {
      norm_lp_ = mn;
      rejected_since_s_ = t_s;
    }
    const bool ok = std::fabs(mn - norm_lp_) <= tolerance_ * norm_lp_;
    // The norm follows accepted samples (over tau_s); a field rejected for kAdaptS on end is a new
    // place's, not a passing disturbance: it becomes the reference.
    if (ok) {
      rejected_since_s_ = t_s;
      if (dt_s > 0.0) norm_lp_ += gain_(dt_s) * (mn - norm_lp_);
    } else if (t_s - rejected_since_s_ > kAdaptS) {
      norm_lp_ = mn;
    }
    return ok;
  }

 private:
  double tolerance_;
  ExpGain gain_;  ///< the reference's low-pass gain per interval
  double norm_lp_ = 0.0, rejected_since_s_ = 0.0;  ///< the reference norm; since when the field is rejected [s]
};

}  // namespace yoyogait::imu
