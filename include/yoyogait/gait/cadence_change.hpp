/// @file gait/cadence_change.hpp
/// @brief The cadence-change detector (sec. 2.8): the trend of the phase corrections of the
/// measurement updates opens the frequency variance while the model is consistently off.
#pragma once

#include <cmath>
#include <cstddef>

#include "yoyogait/gait/decay_factors.hpp"
#include "yoyogait/gait/member.hpp"
#include "yoyogait/gait/state.hpp"
#include "yoyogait/math.hpp"

namespace yoyogait::gait {

/// The prior phasors of one step (after the prediction, before the updates).
struct PriorPhasors {
  double X1 = 0.0, X2 = 0.0, Z1 = 0.0, Z2 = 0.0;
};

/// An update turns the phasors by dphi = (X- x X+ + Z- x Z+) / (|X-|^2 + |Z-|^2) (x: the 2-D
/// cross product; the amplitude-weighted small angle, no atan2). With the right frequency these
/// turns are noise about zero; after a cadence change of dw they push the phase by about dw per
/// second, every step the same way. Their rate, low-passed over tau (cadence_change_tau_s),
/// estimates that frequency error. Its mean square over noise_tau (cadence_change_noise_tau_s) is
/// the walker's own level of phase noise (real step-to-step variability, left-right asymmetry),
/// learnt from the steps within the limit only: the rate counts as a cadence change only beyond
/// sigma times that RMS and beyond the floor threshold (the noise level starts at the floor at each
/// acquisition: in the first seconds of walking the test is that much stricter). Beyond both, P_ww is raised to the excess squared, so that the EKF moves w instead
/// of absorbing the difference in the phasors. Below, it does nothing: the steady state keeps its
/// noise model.
class CadenceChangeDetector {
 public:
  CadenceChangeDetector() noexcept = default;
  CadenceChangeDetector(bool on, double tau_s, double threshold_rad_s, double sigma, double min_amp_mps) noexcept
      : on_(on), tau_s_(tau_s), threshold_rad_s_(threshold_rad_s), sigma2_(sigma * sigma), min_amp2_(min_amp_mps * min_amp_mps) {}

  /// A new acquisition (and the state before the first walk): the rate starts again, and so does
  /// the noise level, from the floor: the corrections of a converging filter are no cadence change.
  void reset() noexcept {
    rate_x_ = rate_z_ = rate_rad_s_ = 0.0;
    noise2_ = threshold_rad_s_ * threshold_rad_s_;
  }
  bool on() const noexcept { return on_; }

  static PriorPhasors prior(const GaitState& x) noexcept { return {x[kX1], x[kX2], x[kZ1], x[kZ2]}; }

  /// One walking step of the one EKF: the prior phasors, the posterior state and the step's
  /// low-pass factors (fc.cadence_gain = 1 - exp(-dt / tau), fc.cadence_gain_per_s = that / dt,
  /// fc.cadence_noise_gain = 1 - exp(-dt / noise_tau); all 0 for dt = 0). Returns the increment of
  /// P_ww that brings it to the target variance (0 when none).
  double update(const PriorPhasors& p, const GaitState& x, const DecayFactors::Values& fc, double P_ww) noexcept {
    const double cx = p.X1 * x[kX2] - p.X2 * x[kX1], nx2 = p.X1 * p.X1 + p.X2 * p.X2;
    const double cz = p.Z1 * x[kZ2] - p.Z2 * x[kZ1], nz2 = p.Z1 * p.Z1 + p.Z2 * p.Z2;
    // A faded oscillation has no phase to speak of: its corrections are not counted.
    const bool ox = nx2 > min_amp2_, oz = nz2 > min_amp2_;
    const double inv = 1.0 / ((ox ? nx2 : 1.0) * (oz ? nz2 : 1.0));  // both turns from one division
    const double dx = ox ? cx * (oz ? nz2 : 1.0) * inv : 0.0, dz = oz ? cz * (ox ? nx2 : 1.0) * inv : 0.0;
    rate_x_ += fc.cadence_gain_per_s * dx - fc.cadence_gain * rate_x_;
    rate_z_ += fc.cadence_gain_per_s * dz - fc.cadence_gain * rate_z_;
    // A change of cadence turns both phasors alike; a model that is off in one channel (a stop, a
    // change of speed leaking into X) does not: the common part, the smaller rate of the same sign.
    rate_rad_s_ = rate_x_ * rate_z_ > 0.0 ? (std::fabs(rate_x_) < std::fabs(rate_z_) ? rate_x_ : rate_z_) : 0.0;
    const double rate2 = rate_rad_s_ * rate_rad_s_;
    // Squares first: the steady state takes no square root.
    const double floor2 = threshold_rad_s_ * threshold_rad_s_;
    const double limit2 = detail::py_max(sigma2_ * noise2_, floor2);
    if (!(rate2 > limit2)) {
      // Only the rate within the limit is noise: a cadence change does not raise its own limit.
      noise2_ += fc.cadence_noise_gain * (rate2 - noise2_);
      return 0.0;
    }
    const double excess = std::fabs(rate_rad_s_) - std::sqrt(limit2);
    return detail::py_max(excess * excess - P_ww, 0.0);
  }

  /// The hook of the filter (sec. 2.8), after the updates of the one EKF while walking: P of e
  /// gets add v v^T with v = e_w + tau g, g = [-X2, X1, -Z2, Z1, 0, ...] the direction of the gait
  /// phase: the variance and the phase covariance that a frequency error of the last tau would
  /// have built, so that the next updates move w at once. add: the target's excess over P_ww,
  /// within the variance bounds. A rank-one addition keeps P positive semi-definite.
  void after_update(const MemberModel& model, Ekf& e, const PriorPhasors& p, const DecayFactors::Values& fc) noexcept {
    if (!on_) return;
    const double add = update(p, e.x, fc, e.P[kW][kW]);
    if (add > 0.0) inflate(model, e, add);
  }

  /// P += add v v^T (upper triangle), v = e_w + tau g at the posterior phasors, add reduced so
  /// that no variance takes more than half the room left below its bound (sec. 2.7; not at the
  /// bound itself, which rounding could pass). Off the steady state's path: only while the
  /// trend is beyond the limit.
  YOYOGAIT_NOINLINE void inflate(const MemberModel& model, Ekf& e, double add) const noexcept {
    const GaitState& x = e.x;
    const double v[kPhasors + 1] = {-tau_s_ * x[kX2], tau_s_ * x[kX1], -tau_s_ * x[kZ2], tau_s_ * x[kZ1], 1.0};
    for (std::size_t i = 0; i <= kW; ++i) {
      const double v2 = v[i] * v[i];
      if (v2 > 0.0) add = detail::py_min(add, 0.5 * (model.max_variance[i] - e.P[i][i]) / v2);
    }
    if (!(add > 0.0)) return;
    for (std::size_t i = 0; i <= kW; ++i)
      for (std::size_t j = i; j <= kW; ++j) e.P[i][j] += add * v[i] * v[j];
  }

  /// The low-passed rate of the phase corrections [rad/s] (> 0: the phase runs ahead of w).
  double rate_rad_s() const noexcept { return rate_rad_s_; }

 private:
  bool on_ = true;
  double tau_s_ = 0.3, threshold_rad_s_ = 0.0, sigma2_ = 0.0, min_amp2_ = 0.0;
  double rate_x_ = 0.0, rate_z_ = 0.0;  ///< low-passed turn rates of X and of Z [rad/s]
  double rate_rad_s_ = 0.0;             ///< their common part
  double noise2_ = 0.0;  ///< mean square of the rate over noise_tau [(rad/s)^2]
};

}  // namespace yoyogait::gait
