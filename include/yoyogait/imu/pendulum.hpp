/// @file imu/pendulum.hpp
/// @brief The inverted pendulum's walking speed from the estimator's vertical phasor (Zijlstra & Hof
/// 2003): the vertical excursion per step h = 2 |Z| / w, the step length K 2 sqrt(2 l h - h^2) for a
/// pendulum of length l (the sensor's height), the speed that times the step frequency (docs/imu.md).
#pragma once

#include <cmath>

#include "yoyogait/gait/state.hpp"
#include "yoyogait/math.hpp"

namespace yoyogait::imu {

class Pendulum {
 public:
  /// From ImuConfig (sensor_height_m, step_length_factor, excursion_tau_s, max_speed_mps).
  struct Settings {
    double length_m = 0.0;            ///< the pendulum's length: the sensor's height standing [m]
    double step_length_factor = 0.0;  ///< K
    double excursion_tau_s = 0.0;     ///< low-pass of the excursion while walking [s]
    double max_speed_mps = 0.0;       ///< speeds are bounded at twice this [m/s]
  };

  Pendulum() noexcept = default;
  explicit Pendulum(const Settings& s) noexcept : s_(s), gain_(s.excursion_tau_s) {}

  /// Everything back to 0; with keep_target, the speed it was heading for stays (a restart of the
  /// estimator while walking: the speed std still measures the way to it).
  void clear(bool keep_target = false) noexcept {
    speed_mps_ = excursion_m_ = step_length_m_ = fed_speed_mps_ = ramp_excursion_m_ = excursion_rel_var_ = 0.0;
    if (!keep_target) target_speed_mps_ = 0.0;
  }

  /// One estimator sample dt_s after the last: its state x, the variance of |Z| along Z (the
  /// filter's, m^2/s^2), walking and acquiring. Follows h while walking and locked, cleared when not
  /// walking, held while acquiring.
  void update(const GaitState& x, double amp_var, bool walking, bool acquiring, double dt_s) noexcept {
    const double omega = x[gait::kW];
    if (!(walking && !acquiring && omega > 0.0)) {
      if (!walking) clear();
      return;
    }
    // At most a fifth of the pendulum's length: no walker's pelvis rises more per step; a larger
    // value is a phasor that has not locked (|Z| / w with w small).
    const double amp = std::sqrt(x[gait::kZ1] * x[gait::kZ1] + x[gait::kZ2] * x[gait::kZ2]);
    const double h = std::fmin(2.0 * amp / omega, 0.2 * s_.length_m);
    if (!std::isfinite(h)) return;
    // The relative variance of this h (that of |Z|; at most 4, an amplitude twice its std), averaged
    // as h is: the excursion's errors while the phasor's amplitude converges go one way, so the mean
    // of its samples' variances, not less.
    const double a2 = amp * amp, rel_var = amp_var >= 0.0 && amp_var < 4.0 * a2 ? amp_var / a2 : 4.0;
    // Fed to the estimator from 0 at the start of a walk (a step of the forward velocity it is fed
    // would disturb its phase and frequency while they lock); reported from the first value on.
    const double g = gain_(dt_s);
    ramp_excursion_m_ += g * (h - ramp_excursion_m_);
    excursion_rel_var_ = excursion_m_ > 0.0 ? excursion_rel_var_ + g * (rel_var - excursion_rel_var_) : rel_var;
    excursion_m_ = excursion_m_ > 0.0 ? excursion_m_ + g * (h - excursion_m_) : h;
    const double f = omega * 0.15915494309189533576888376337251;
    fed_speed_mps_ = std::fmin(step_length(ramp_excursion_m_) * f, 2.0 * s_.max_speed_mps);
    step_length_m_ = step_length(excursion_m_);
    speed_mps_ = std::fmin(step_length_m_ * f, 2.0 * s_.max_speed_mps);
    const double hm = std::fmin(h, s_.length_m);
    target_speed_mps_ = std::fmin(step_length(hm) * f, 2.0 * s_.max_speed_mps);
  }

  /// The step length for a vertical excursion h per step [m].
  double step_length(double h) const noexcept {
    const double l = s_.length_m, he = std::fmin(h, l);
    return s_.step_length_factor * 2.0 * std::sqrt(std::fmax(0.0, 2.0 * l * he - he * he));
  }

  /// The speed [m/s]: step length times f (0 until walking is seen).
  double speed_mps() const noexcept { return speed_mps_; }
  /// The speed fed to the estimator: from the excursion ramped from 0 at a walk's start [m/s].
  double fed_speed_mps() const noexcept { return fed_speed_mps_; }
  /// The speed of the last excursion, unfiltered: where speed_mps() goes [m/s].
  double target_speed_mps() const noexcept { return target_speed_mps_; }
  /// The low-passed vertical excursion per step [m].
  double excursion_m() const noexcept { return excursion_m_; }
  /// The relative variance of speed_mps() from the excursion's: d ln L / d ln h = (l - h) / (2 l - h)
  /// is 0.44-0.5 for h <= l / 5, taken as 1/2.
  double speed_rel_var() const noexcept { return 0.25 * excursion_rel_var_; }
  double step_length_m() const noexcept { return step_length_m_; }

 private:
  Settings s_{};
  ExpGain gain_{1.0};  ///< the excursion's low-pass gain at the estimator's sample time (one exp per interval)
  double speed_mps_ = 0.0, excursion_m_ = 0.0, step_length_m_ = 0.0, target_speed_mps_ = 0.0;
  double fed_speed_mps_ = 0.0, ramp_excursion_m_ = 0.0;
  double excursion_rel_var_ = 0.0;  ///< low-passed relative variance of h (that of |Z|)
};

}  // namespace yoyogait::imu
