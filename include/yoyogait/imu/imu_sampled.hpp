/// @file imu/imu_sampled.hpp
/// @brief ImuOnlineEstimator after each estimator sample: the stds made honest (sampled), the
/// amplitude's variance the pendulum takes (amplitude_var), and the wrong-harmonic and periodicity
/// checks on the fed v_z (check_harmonic). Included by imu/imu_estimator.hpp.
#pragma once

#include <cmath>

#include "yoyogait/imu/imu_estimator.hpp"

namespace yoyogait {

inline void ImuOnlineEstimator::sampled(const GaitState& prior, double dt_s, double vz_mean, double az2_mean,
                                       double check_dt_s) noexcept {
  const double correction =
      online::phase_correction_rad(prior, est_.gait_state, est_.walking, est_.acquiring, dt_s);
  // The transients are those of the speed reported (the pendulum's once it runs, carry_estimate),
  // as the marker path's Validity sees the speed it reports: the estimator's A0 follows the fed
  // speed only over seconds and missed the reported speed's changes (its fall at a stop, its step
  // at the lock).
  const bool from_pendulum = pendulum_.speed_mps() > 0.0;
  const double speed_mps = from_pendulum ? pendulum_.speed_mps() : est_.speed_mps;
  if (from_pendulum != speed_from_pendulum_) {
    validity_.rebase_speed(speed_mps);
    lock_scale_ = from_pendulum ? 1.0 : 0.0;  // the pendulum starts at a lock
  }
  speed_from_pendulum_ = from_pendulum;
  validity_.sample(dt_s, estimator_.innovation().nis, est_.step_frequency_hz, speed_mps, correction);
  check_harmonic(vz_mean, check_dt_s);
  const double k = validity_.std_inflation();
  const double sp = speed_mps > 0.3 ? speed_mps : 0.3, fs = est_.step_frequency_hz / sp;
  const double tv_s = validity_.transient_var_speed();
  double f_var = k * k * est_.step_frequency_std_hz * est_.step_frequency_std_hz + validity_.transient_var_f() +
                 fs * fs * tv_s;
  const double pinned_std_hz = validity_.pinned_std_hz();
  if (est_.walking && validity_.pinned(est_.step_frequency_hz) && f_var < pinned_std_hz * pinned_std_hz)
    f_var = pinned_std_hz * pinned_std_hz;
  // Turning: the steps of a turn (on the spot, a pivot) are not the walk's; the lock holds the
  // walk's cadence for a while. The yaw rate from the heading's change since the last estimator
  // sample, low-passed (kTurnTauS; the pelvis's own rotation at the stride leaks in at 0.01 Hz).
  const double turn_gain = turn_gain_(dt_s);
  const double dpsi = atan2_fast(heading_tick_[0] * heading_[1] - heading_tick_[1] * heading_[0],
                                 heading_tick_[0] * heading_[0] + heading_tick_[1] * heading_[1]);
  heading_tick_ = heading_;
  if (dt_s > 0.0) yaw_rate_lp_rad_s_ += turn_gain * (dpsi / dt_s - yaw_rate_lp_rad_s_);
  const double turn_std_hz = config_.turn_f_std_hz_per_rad_s * yaw_rate_lp_rad_s_;
  f_var += turn_std_hz * turn_std_hz;
  // A fresh lock: the bank chose on the first strides, whose cadence is still rising (lock_f_rel_std).
  if (lock_scale_ > 0.0) {
    const double lock_std_hz = config_.lock_f_rel_std * lock_scale_ * est_.step_frequency_hz;
    f_var += lock_std_hz * lock_std_hz;
    lock_scale_ *= 1.0 - lock_gain_(dt_s);
  }
  // Locked on a wrong harmonic: the truth is f / 2 or 2 f away.
  if (harmonic_off_) f_var += 0.25 * est_.step_frequency_hz * est_.step_frequency_hz;
  // The bank still choosing: any of its members may win; the range's half-width.
  if (est_.acquiring) {
    const double half = 0.5 * (config_.estimator.gait_filter.f_max_hz - config_.estimator.gait_filter.f_min_hz);
    f_var += half * half;
  }
  imu::SpeedVariance::Sample sv;
  sv.std_inflation = k;
  sv.transient_var = tv_s;
  sv.f_hz = est_.step_frequency_hz;
  sv.f_var_hz2 = f_var;
  sv.est_speed_mps = est_.speed_mps;
  sv.est_speed_std_mps = est_.speed_std_mps;
  sv.walking = est_.walking;
  sv.locked = !(harmonic_off_ || est_.acquiring);
  sv.vz_mean_mps = vz_mean;
  sv.az2_mean_m2_per_s4 = az2_mean;
  const double s_var = speed_var_.sample(pendulum_, sv, dt_s);
  vz2_step_lp_ += step_gain_(dt_s) * (vz_mean * vz_mean - vz2_step_lp_);
  f_std_ = std::sqrt(f_var);
  s_std_ = std::sqrt(s_var);
  uncertain_ = !(f_std_ < pinned_std_hz && s_std_ < uniform_std(config_.max_speed_mps));
}

inline double ImuOnlineEstimator::amplitude_var() const noexcept {
  const GaitState& x = est_.gait_state;
  const double z1 = x[gait::kZ1], z2 = x[gait::kZ2], a2 = z1 * z1 + z2 * z2;
  if (!(a2 > 0.0)) return 0.0;
  const double p11 = estimator_.gait_covariance(gait::kZ1, gait::kZ1);
  const double p12 = estimator_.gait_covariance(gait::kZ1, gait::kZ2);
  const double p22 = estimator_.gait_covariance(gait::kZ2, gait::kZ2);
  return (z1 * z1 * p11 + 2.0 * z1 * z2 * p12 + z2 * z2 * p22) / a2;
}

inline void ImuOnlineEstimator::check_harmonic(double vz, double dt_s) noexcept {
  const double f = est_.step_frequency_hz;
  const bool locked = est_.walking && !est_.acquiring && f > 0.0 && dt_s > 0.0;
  const bool acf_off = harmonic_.update(vz, f, locked, dt_s);
  // A stride lock reads half the cadence and about twice the step length: a walk ratio (step
  // length per step frequency in steps/min) no walker has, whatever the autocorrelation says (an
  // asymmetric gait's v_z repeats over the stride too). Every sample: it costs a comparison.
  const double wr_max = config_.max_walk_ratio_m_per_spm;
  const bool off = acf_off || (locked && wr_max > 0.0 && pendulum_.step_length_m() > wr_max * 60.0 * f);
  // Valid only while the last steps repeat at the period (a pause mid-bout, the steps of a turn on
  // the spot: the lock holds the walk's cadence over strides that are not the walk's).
  irregular_ = locked && config_.min_periodicity > -1.0 &&
               harmonic_.periodicity(f, dt_s, config_.periodicity_steps) < config_.min_periodicity;
  if (off && !harmonic_off_) harmonic_off_s_ = 0.0;
  harmonic_off_ = off;
  if (off) {
    harmonic_off_s_ += dt_s;
    if (harmonic_off_s_ >= kHarmonicRestartS) {  // it stays there: acquire afresh
      estimator_.reset();
      restart_estimate();
      harmonic_off_ = true;  // not valid until the check has run again
      harmonic_.restart(true);
      pendulum_.clear(true);
    }
  }
}

}  // namespace yoyogait
