/// @file imu/speed_variance.hpp
/// @brief The variance of the IMU's reported speed, the inverted pendulum's (docs/imu.md section 1):
/// the estimator's own until the pendulum runs, the pendulum's model error, its way to the current
/// excursion, the excursion's own uncertainty, the step frequency's share, nothing known while not
/// locked, and the speed the vertical motion allows for (a slow walk the detector calls standing, a
/// stop the filter has not followed yet).
#pragma once

#include <cmath>

#include "yoyogait/imu/pendulum.hpp"
#include "yoyogait/math.hpp"

namespace yoyogait::imu {

class SpeedVariance {
 public:
  /// What an estimator sample gives it.
  struct Sample {
    double std_inflation = 1.0;         ///< the stds' scale by the innovations' excess (Validity)
    double transient_var = 0.0;         ///< the reported speed's transient variance [(m/s)^2]
    double f_hz = 0.0, f_var_hz2 = 0.0;  ///< the step frequency and its reported variance
    double est_speed_mps = 0.0, est_speed_std_mps = 0.0;  ///< the estimator's speed (A0) and its std
    bool walking = false;               ///< the estimator's walking detector
    bool locked = false;                ///< neither acquiring nor on a wrong harmonic
    double vz_mean_mps = 0.0;           ///< the interval's mean fed v_z
    double az2_mean_m2_per_s4 = 0.0;    ///< the interval's mean squared vertical acceleration
  };

  /// speed_rel_std, max_speed_mps: ImuConfig's; f_floor_hz: the frequency taken for the vertical
  /// motion's speed when the estimate's is lower (the range's locked bound).
  SpeedVariance(double speed_rel_std, double max_speed_mps, double f_floor_hz) noexcept
      : speed_rel_std_(speed_rel_std), max_speed_mps_(max_speed_mps), f_floor_hz_(f_floor_hz) {}

  void clear() noexcept { vz2_lp_ = az2_lp_ = 0.0; }

  /// The speed's variance [(m/s)^2] after an estimator sample dt_s after the last.
  double sample(const Pendulum& pendulum, const Sample& s, double dt_s) noexcept {
    const double k = s.std_inflation;
    const double pendulum_mps = pendulum.speed_mps(), model_std = speed_rel_std_ * pendulum_mps;
    double var = (pendulum_mps > 0.0 ? 0.0 : k * k * s.est_speed_std_mps * s.est_speed_std_mps) + s.transient_var +
                 model_std * model_std;
    // While the pendulum speed rises from 0 (excursion_tau_s) or the lock is off, the speed is as
    // uncertain as the pendulum's own estimate of where it goes.
    const double gap = pendulum.target_speed_mps() - (pendulum_mps > 0.0 ? pendulum_mps : s.est_speed_mps);
    var += gap * gap;
    // The excursion's own uncertainty (the filter's |Z|, scaled as its stds are): while the phasor's
    // amplitude converges after a lock, h and with it the speed are low, and the target with them.
    var += k * k * pendulum_mps * pendulum_mps * pendulum.speed_rel_var();
    // The pendulum speed is taken at the estimate's frequency: L f with L from h = 2 |Z| / w goes as
    // sqrt(|Z| f) (h << l), so the frequency's relative std reaches the speed halved.
    if (pendulum_mps > 0.0 && s.f_hz > 0.0) {
      const double v_per_f = 0.5 * pendulum_mps / s.f_hz;  // dv/df
      var += v_per_f * v_per_f * s.f_var_hz2;
    }
    // Not locked: nothing is known of the speed within what is plausible.
    if (!s.locked) var += max_speed_mps_ * max_speed_mps_;
    vz2_lp_ += standing_gain_(dt_s) * (s.vz_mean_mps * s.vz_mean_mps - vz2_lp_);
    az2_lp_ += acc_gain_(dt_s) * (s.az2_mean_m2_per_s4 - az2_lp_);
    if (!s.walking) {
      // Standing, by the detector: a slow walk it cannot tell from standing goes at the pendulum
      // speed of the vertical motion seen (the fed v_z's low-passed RMS as the fundamental's amplitude).
      const double f = s.f_hz > f_floor_hz_ ? s.f_hz : f_floor_hz_;
      const double hidden_mps = speed_at(pendulum, 2.0 * std::sqrt(2.0 * vz2_lp_) / (kTwoPi * f), f);
      var += hidden_mps * hidden_mps;
    } else if (pendulum_mps > 0.0 && s.f_hz > 0.0) {
      // Walking: a stop or shorter steps show in the vertical acceleration at once, a second before
      // the filter's |Z| and the integrated v_z follow them. The pendulum speed of the vertical
      // acceleration of the last 0.1 s (its RMS as the fundamental's amplitude, h = 2 a / w^2; the
      // harmonics make it larger while the steps go on) below the reported one: the walker may be
      // that much slower already.
      const double f = s.f_hz, w2 = kTwoPi * kTwoPi * f * f, hp = pendulum.excursion_m() * w2;
      if (8.0 * az2_lp_ < hp * hp) {  // its h below the pendulum's (without a square root)
        const double slower_mps = pendulum_mps - speed_at(pendulum, 2.0 * std::sqrt(2.0 * az2_lp_) / w2, f);
        if (slower_mps > 0.0) var += slower_mps * slower_mps;
      }
    }
    return var;
  }

 private:
  // The pendulum speed of an excursion h_m at f_hz, at most max_speed_mps.
  double speed_at(const Pendulum& pendulum, double h_m, double f_hz) const noexcept {
    return std::fmin(pendulum.step_length(h_m) * f_hz, max_speed_mps_);
  }

  double speed_rel_std_ = 0.2, max_speed_mps_ = 3.0, f_floor_hz_ = 0.0;
  /// Low-pass of the fed v_z's square, for the speed while standing [s].
  static constexpr double kStandingTauS = 1.0;
  double vz2_lp_ = 0.0;
  ExpGain standing_gain_{kStandingTauS};
  /// Low-pass of the vertical acceleration's square, for the speed while walking [s]: at a fifth of
  /// a step it falls within 0.2 s of a stop; its ripple at twice the step frequency only widens the
  /// std where its RMS dips below the fundamental's (the harmonics hold it above).
  static constexpr double kAccTauS = 0.1;
  double az2_lp_ = 0.0;
  ExpGain acc_gain_{kAccTauS};
};

}  // namespace yoyogait::imu
