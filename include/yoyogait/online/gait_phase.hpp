/// @file online/gait_phase.hpp
/// @brief The phase within the current step and the time to the next step, from the estimator's
/// vertical phasor carried to the frame's time (OnlineEstimate::gait_phase, next_step_in_s).
#pragma once

#include <cmath>
#include <limits>

#include "yoyogait/math.hpp"

namespace yoyogait::online {

/// gait_phase in [0, 1): the angle of the vertical phasor Z, v_z ~ |Z| cos(2 pi gait_phase), held
/// while standing; the next step: the next time the phase reaches 0.75 (the pelvis low point).
class GaitPhase {
 public:
  /// The phase at which a step is counted (the pelvis low point, about the double support).
  static constexpr double kStepPhase = 0.75;

  void reset() noexcept {
    phase_ = 0.0;
    next_step_in_s_ = std::numeric_limits<double>::quiet_NaN();
  }

  /// No estimate to carry: the phase held, no next step.
  void hold() noexcept { next_step_in_s_ = std::numeric_limits<double>::quiet_NaN(); }

  /// The estimate (walking, vertical phasor z1, z2 at its sample) carried over a turn of
  /// phase_advance_rad, to where the step angular frequency is omega_rad_s with rate omega_rate_rad_s2.
  /// next_step_in_s stays below 1 / f_hz (the reported step frequency; also at a falling rate).
  void update(bool walking, double z1, double z2, double phase_advance_rad, double omega_rad_s,
              double omega_rate_rad_s2, double f_hz) noexcept {
    const bool phased = walking && z1 * z1 + z2 * z2 > 1e-12 && std::isfinite(phase_advance_rad) &&
                        std::fabs(phase_advance_rad) < 1e9 && std::isfinite(omega_rad_s);
    if (phased) {
      // The phasor's angle (within 2e-6 rad: 3e-7 of a step) changes only with the estimate, not
      // from frame to frame as the carry does: taken once per estimate (its branches follow the
      // phasor round and mispredict; a quarter of an IMU sample's cost before).
      if (z1 != angle_of_[0] || z2 != angle_of_[1]) {
        angle_of_[0] = z1;
        angle_of_[1] = z2;
        angle_rad_ = atan2_fast(z2, z1);
      }
      double ph = (angle_rad_ + phase_advance_rad) / kTwoPi;
      ph -= std::floor(ph);
      if (ph >= 1.0) ph = 0.0;
      phase_ = ph;
    }
    if (phased && omega_rad_s > 0.0) {
      // The turn to the next step phase, at the present w and its rate: w t + dw t^2 / 2 = turn.
      double left = kStepPhase - phase_;
      left -= std::floor(left);
      if (left >= 1.0) left = 0.0;
      // t = turn / w * 2 / (1 + sqrt(1 + e)), e = 2 dw turn / w^2; for a walk's small rates (|e| <
      // 1e-3) its series to e^3 (within 6e-14 relative) without the square root.
      const double turn = kTwoPi * left, w = omega_rad_s, e = 2.0 * omega_rate_rad_s2 * turn / (w * w);
      if (std::fabs(e) < 1e-3)
        next_step_in_s_ = turn / w * (1.0 - e * (0.25 - e * (0.125 - e * 0.078125)));
      else
        next_step_in_s_ = 1.0 + e > 0.0 ? 2.0 * turn / (w * (1.0 + std::sqrt(1.0 + e))) : turn / w;
      // Below the period 1 / f_hz (as the caller divides); the division only near it.
      if (!(f_hz > 0.0 && next_step_in_s_ * f_hz < 1.0 - 1e-12)) {
        const double period_s = f_hz > 0.0 ? 1.0 / f_hz : 0.0;
        if (!(next_step_in_s_ < period_s)) next_step_in_s_ = std::nextafter(period_s, 0.0);
      }
      if (!(next_step_in_s_ >= 0.0)) next_step_in_s_ = 0.0;
    } else {
      next_step_in_s_ = std::numeric_limits<double>::quiet_NaN();
    }
  }

  /// The phase in [0, 1) (0 before the first walking estimate).
  double phase() const noexcept { return phase_; }
  /// Time to the next step [s]; NaN while not walking or while the phasor is at zero (no phase).
  double next_step_in_s() const noexcept { return next_step_in_s_; }

 private:
  double phase_ = 0.0;
  double next_step_in_s_ = std::numeric_limits<double>::quiet_NaN();
  double angle_of_[2] = {0.0, 0.0};  ///< the phasor angle_rad_ is the angle of
  double angle_rad_ = 0.0;
};

}  // namespace yoyogait::online
