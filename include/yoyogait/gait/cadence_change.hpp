/// @file gait/cadence_change.hpp
/// @brief The cadence-change detector (sec. 2.8): a phase lag of the model that persists opens the
/// frequency variance.
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

/// The phase error of the model, from the innovations: a gait phase ahead of the prior by d and a
/// vertical amplitude larger by a factor 1 + rho give nu_z = rho Z1 - d Z2 (first order; Z1, Z2 of
/// the prior). d is the least-squares solution over the last tau (cadence_change_tau_s; low-passed
/// normal equations), with rho beside it so that a fading oscillation does not read as a lag; v_x
/// is not used (the speed errors of a stop or a change of speed land in X). With the right
/// frequency d is noise about zero; after a change of cadence the EKF keeps lagging the phase one
/// way, every step. Its mean square over noise_tau (cadence_change_noise_tau_s), learnt while it is
/// within the limit, is the walker's own phase noise (real step-to-step variability, left-right
/// asymmetry): d counts as a change of cadence beyond sigma times that RMS and beyond the floor
/// (cadence_change_phase_rad), for at least tau. The noise level starts at the floor at each
/// acquisition and nothing is detected in its first noise_tau: a converging filter lags too. Then
/// P_ww is raised to min((|d| - limit) / horizon, max_std)^2, with the phase covariance that
/// frequency error would have built (after_update): the EKF moves w instead of absorbing the lag
/// in the phasors. The innovations measure the model's error, not the size of the EKF's
/// corrections: opening P does not feed the detector. Below the limit nothing changes: the steady
/// state keeps its noise model.
class CadenceChangeDetector {
 public:
  /// The cadence_change_* settings, the frequency in rad/s.
  struct Settings {
    bool on = true;                ///< cadence_change_adapt
    double tau_s = 0.1;            ///< the lag must last this long; low-pass of the evidence [s]
    double horizon_s = 0.4;        ///< the lag beyond the limit is a frequency error over this [s]
    double max_std_rad_s = 0.0;    ///< the largest frequency std it opens [rad/s]
    double phase_rad = 0.0;        ///< the floor of the limit [rad]
    double sigma = 0.0;            ///< the limit in RMS of the walker's own phase noise [1]
    double min_amp_mps = 0.0;      ///< a sample is evidence only with |Z| above this [m/s]
    double learn_s = 2.0;          ///< noise_tau: the phase noise's low-pass; nothing detected before [s]
  };

  CadenceChangeDetector() noexcept = default;
  explicit CadenceChangeDetector(const Settings& s) noexcept
      : on_(s.on),
        tau_s_(s.tau_s),
        inv_horizon_s_(1.0 / s.horizon_s),
        max_std_rad_s_(s.max_std_rad_s),
        floor2_(s.phase_rad * s.phase_rad),
        sigma2_(s.sigma * s.sigma),
        min_amp2_(s.min_amp_mps * s.min_amp_mps),
        learn_s_(s.learn_s) {}

  /// A new acquisition (and the state before the first walk): the estimate starts again, and so
  /// does the noise level, from the floor: a converging filter's lag is no change of cadence.
  void reset() noexcept {
    s11_ = s12_ = s22_ = s1n_ = s2n_ = 0.0;
    noise2_ = floor2_;
    learnt_s_ = beyond_s_ = 0.0;
  }
  bool on() const noexcept { return on_; }

  static PriorPhasors prior(const GaitState& x) noexcept { return {x[kX1], x[kX2], x[kZ1], x[kZ2]}; }

  /// One walking step of the one EKF: the prior phasors, the step's innovations (NaN: channel not
  /// used) and the low-pass factors (fc.cadence_gain = 1 - exp(-dt / tau), fc.cadence_noise_gain
  /// = 1 - exp(-dt / noise_tau); 0 for dt = 0). Returns the increment of P_ww that brings it to
  /// the target variance (0 when none). Only a sample with both channels and a vertical
  /// oscillation (|Z| > min_amp) is evidence; another leaves everything as it is. The lag must stay
  /// beyond the limit for tau: one corrupt sample is no change of cadence.
  double update(const PriorPhasors& p, const Innovations& in, const DecayFactors::Values& fc, double P_ww) noexcept {
    if (std::isnan(in.vx_mps) || std::isnan(in.vz_mps) || !(p.Z1 * p.Z1 + p.Z2 * p.Z2 > min_amp2_)) return 0.0;
    // nu_z = rho Z1 - d Z2 (rho: relative amplitude error, d: phase error; X carries speed errors
    // and is not used). The low-passed normal equations [a -b; -b c] [rho d]' = [p -q]'.
    const double nu = in.vz_mps, z1 = p.Z1, z2 = p.Z2, g = fc.cadence_gain;
    s11_ += g * (z1 * z1 - s11_);
    s12_ += g * (z1 * z2 - s12_);
    s22_ += g * (z2 * z2 - s22_);
    s1n_ += g * (z1 * nu - s1n_);
    s2n_ += g * (z2 * nu - s2n_);
    const double det = s11_ * s22_ - s12_ * s12_;
    const double num = s12_ * s1n_ - s11_ * s2n_;  // d = num / det
    // |d| > limit, in squares (the noise level takes the one division of the step).
    const double limit2 = detail::py_max(sigma2_ * noise2_, floor2_);
    const double num2 = num * num, det2 = det * det;
    const bool learning = learnt_s_ < learn_s_;
    learnt_s_ += fc.dt;
    // Too few samples to tell phase from amplitude (one sample: det = 0): no estimate.
    if (!(det > 1e-3 * s11_ * s22_)) return 0.0;
    if (learning || !(num2 > limit2 * det2)) {
      // Within the limit: noise (a change of cadence does not raise its own limit).
      noise2_ += fc.cadence_noise_gain * (num2 / det2 - noise2_);
      beyond_s_ = 0.0;
      return 0.0;
    }
    beyond_s_ += fc.dt;
    if (beyond_s_ < tau_s_) return 0.0;
    const double excess = (std::fabs(num) / det - std::sqrt(limit2)) * inv_horizon_s_;
    const double capped = detail::py_min(excess, max_std_rad_s_);
    return detail::py_max(capped * capped - P_ww, 0.0);
  }

  /// The hook of the filter (sec. 2.8), after the updates of the one EKF while walking (not when
  /// the gate rejected a channel): P of e gets add v v^T with v = e_w + tau g, g = [-X2, X1, -Z2,
  /// Z1, 0, ...] the direction of the gait phase: the variance and the phase covariance that a
  /// frequency error over the last tau would have built, so that the next updates move w at once.
  /// add: the target's excess over P_ww, within the variance bounds. A rank-one addition keeps P
  /// positive semi-definite.
  void after_update(const MemberModel& model, Ekf& e, const PriorPhasors& p, const DecayFactors::Values& fc,
                    bool rejected) noexcept {
    if (!on_ || rejected) return;
    const double add = update(p, e.innovations, fc, e.P[kW][kW]);
    if (add > 0.0) inflate(model, e, add);
  }

  /// P += add v v^T (upper triangle), v = e_w + tau g at the posterior phasors, add reduced so
  /// that no variance takes more than half the room left below its bound (sec. 2.7; not at the
  /// bound itself, which rounding could pass). Off the steady state's path: only while a change
  /// is detected. v is indexed by the state: the phasors, then w.
  YOYOGAIT_NOINLINE void inflate(const MemberModel& model, Ekf& e, double add) const noexcept {
    static_assert(kX1 == 0 && kX2 == 1 && kZ1 == 2 && kZ2 == 3 && kW == kPhasors, "v follows the state's order");
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

 private:
  bool on_ = true;
  double tau_s_ = 0.1, inv_horizon_s_ = 2.5, max_std_rad_s_ = 0.0, floor2_ = 0.0, sigma2_ = 0.0, min_amp2_ = 0.0;
  double learn_s_ = 2.0, learnt_s_ = 0.0;  ///< no detection before learn_s of walking since the reset
  double beyond_s_ = 0.0;                  ///< how long the lag has been beyond the limit
  double s11_ = 0.0, s12_ = 0.0, s22_ = 0.0, s1n_ = 0.0, s2n_ = 0.0;  ///< low-passed Z1^2, Z1 Z2, Z2^2, Z1 nu, Z2 nu
  double noise2_ = 0.0;  ///< mean square of the phase error while within the limit [rad^2]
};

}  // namespace yoyogait::gait
