/// @file imu/imu_estimator.hpp
/// @brief ImuOnlineEstimator: one lower-back IMU in, gait estimates out, one sample at a time,
/// nothing taken from the future (docs/imu.md).
///
/// Per sample: the orientation relative to gravity (imu::Mahony), the gravity-free acceleration in
/// the world frame, its vertical component and its component along the heading of the sensor's
/// forward axis integrated without drift (imu::LeakyIntegrator); every
/// EstimatorConfig::sample_time_s the mean over the interval of (pendulum speed + forward
/// oscillation, vertical velocity) feeds the gait Estimator. The pendulum speed is the step length
/// of the inverted pendulum (Zijlstra & Hof 2003), K 2 sqrt(2 l h - h^2), times the step frequency,
/// with h = 2 |Z| / w the vertical excursion per step from the estimator's own vertical phasor.
/// The Estimator has no observation of A0 of its own; the pendulum speed enters as the mean of the
/// forward velocity it is fed, which is what A0 is (the mean forward velocity over a step).
#pragma once

#include <array>
#include <cmath>
#include <cstddef>
#include <limits>
#include <stdexcept>

#include "yoyogait/estimator.hpp"
#include "yoyogait/imu/harmonic_check.hpp"
#include "yoyogait/imu/imu_config.hpp"
#include "yoyogait/imu/imu_estimate.hpp"
#include "yoyogait/imu/leaky_integrator.hpp"
#include "yoyogait/imu/mag_gate.hpp"
#include "yoyogait/imu/mahony.hpp"
#include "yoyogait/imu/pendulum.hpp"
#include "yoyogait/imu/sample_gaps.hpp"
#include "yoyogait/imu/speed_variance.hpp"
#include "yoyogait/math.hpp"
#include "yoyogait/online/gait_phase.hpp"
#include "yoyogait/online/validity.hpp"

namespace yoyogait {

/// The IMU gait estimator. update() is noexcept and allocates nothing; the constructor throws
/// std::invalid_argument for an unusable configuration.
class ImuOnlineEstimator {
 public:
  static constexpr double kGravityMps2 = 9.80665;

  explicit ImuOnlineEstimator(const ImuConfig& config = ImuConfig{})
      : config_(checked(config)),
        estimator_(config_.estimator),
        mahony_(config_.mahony_kp_per_s, config_.mahony_ki_per_s2, config_.max_gyro_bias_rad_s),
        int_z_(config_.highpass_tau_s),
        int_x_(config_.highpass_tau_s),
        pendulum_(pendulum_settings(config_)),
        speed_var_(config_.speed_rel_std, config_.max_speed_mps, locked_min_hz(config_)),
        gravity_gain_(config_.gravity_tau_s),
        mag_gate_(config_.mag_norm_tolerance, config_.gravity_tau_s) {
    fwd_sign_ = config_.forward_negative ? -1.0 : 1.0;
    input_latency_s_ = int_z_.delay_s(config_.latency_f_hz);
    f_locked_min_hz_ = locked_min_hz(config_);
    f_locked_max_hz_ = 0.98 * config_.estimator.gait_filter.f_max_hz;
    online::Validity::Settings vs;
    vs.f_min_hz = config_.estimator.gait_filter.f_min_hz;
    vs.f_max_hz = config_.estimator.gait_filter.f_max_hz;
    vs.phase_tau_s = config_.phase_std_tau_s;
    vs.phase_onset_tau_s = config_.phase_onset_tau_s;
    validity_ = online::Validity(vs);
    reset();
  }

  /// Back to the state before the first sample.
  void reset() noexcept {
    estimator_.reset();
    restart_estimate();
    harmonic_.clear();
    est_ = Estimate{};
    out_ = ImuEstimate{};
    have_time_ = false;
    fed_ = false;
    started_ = false;
    started_before_ = false;
    sum_vx_ = sum_vz_ = sum_az2_ = span_s_ = sum_age_s2_ = 0.0;
    tick_age_s_ = carry_h_s_ = 0.0;
    gaps_.reset();
    gap_in_tick_ = false;
    phase_.reset();
    vz2_step_lp_ = yaw_rate_lp_rad_s_ = 0.0;
    speed_var_.clear();
    heading_tick_ = {1.0, 0.0};
    pendulum_.clear();
    heading_ = {1.0, 0.0};
    t_saturated_s_ = -std::numeric_limits<double>::infinity();
    gap_restart_ = false;
    acc_norm_lp_ = kGravityMps2;
    mag_gate_.reset();
    heading_absolute_ = false;
  }

  /// One sample: t_s [s], acc[3] the specific force [m/s^2] and gyr[3] the angular rate [rad/s],
  /// both in the sensor frame. Never throws; the state stays finite.
  ImuEstimate update(double t_s, const double* acc, const double* gyr) noexcept { return update(t_s, acc, gyr, nullptr); }

  /// As update(t_s, acc, gyr), with mag[3] the magnetic field in the sensor frame (any unit: only its
  /// direction and its norm's steadiness are used; nullptr or a non-finite value: none): the heading
  /// becomes absolute, from magnetic north (docs/imu.md).
  ImuEstimate update(double t_s, const double* acc, const double* gyr, const double* mag) noexcept {
    ImuEstimate& o = out_;
    o.estimator_fed = false;
    bool finite = std::isfinite(t_s);
    imu::Vec3 a{}, w{};
    for (std::size_t i = 0; i < 3; ++i) {
      a[i] = acc[i];
      w[i] = gyr[i];
      finite = finite && std::isfinite(a[i]) && std::isfinite(w[i]);
    }
    if (!finite) {
      o.reason = ImuReason::kNonFinite;
      o.valid = false;
      return o;
    }
    if (have_time_ && !(t_s > t_last_s_)) {
      o.reason = ImuReason::kTimeNotIncreasing;
      o.valid = false;
      return o;
    }
    const double dt_s = have_time_ ? t_s - t_last_s_ : 0.0;
    have_time_ = true;
    t_last_s_ = t_s;
    o.t_s = t_s;

    bool saturated = false;
    for (std::size_t i = 0; i < 3; ++i)
      saturated = saturated || std::fabs(a[i]) >= config_.acc_saturation_mps2 ||
                  std::fabs(w[i]) >= config_.gyr_saturation_rad_s;
    if (saturated) t_saturated_s_ = t_s;

    const double a_norm = imu::Mahony::norm(a);
    // The first start takes the sensor's tilt from this sample's specific force: one that is not
    // about gravity (a stream's first packet of zeros, a jolt) would start it tilted, and the Mahony
    // filter takes seconds to right it (a DOT's zero first row: 90 degrees, 7 s). Such a sample
    // starts nothing: GRAVITY, and the next one is tried (tested behind restart: no cost per sample).
    const bool restart = !started_ || dt_s > config_.max_gap_s;
    // Samples lost, up to max_gap_s (imu::SampleGaps): the integrals follow the model where it holds.
    const bool gap = !restart && gaps_.gap(t_s, dt_s);
    const bool bridged = gap && fed_ && est_.walking && !est_.acquiring;
    if (restart && !started_ && !(std::fabs(a_norm - kGravityMps2) <= config_.gravity_tolerance * kGravityMps2)) {
      o.reason = ImuReason::kGravity;
      o.valid = o.walking = o.estimator_fed = false;
      o.step_frequency_std_hz = o.speed_std_mps = std::numeric_limits<double>::infinity();
      return o;
    }
    // The magnetometer's sample, when given, finite and not disturbed (imu::MagGate).
    imu::Vec3 m{};
    if (mag != nullptr) m = {mag[0], mag[1], mag[2]};
    const bool mag_ok = mag != nullptr && config_.mag_kp_per_s > 0.0 && mag_gate_.accept(t_s, dt_s, m);
    if (restart) {
      gap_restart_ = started_;
      start_front_end(t_s, a);
      if (mag_ok && !heading_absolute_) {
        mahony_.align_yaw(m);
        heading_absolute_ = true;
      }
      acc_norm_lp_ = started_before_ ? acc_norm_lp_ : a_norm;
      started_before_ = true;
    } else {
      double yaw_error = 0.0;
      if (mag_ok) {
        yaw_error = mahony_.field_angle(m);
        if (!std::isfinite(yaw_error)) yaw_error = 0.0;
        else if (!heading_absolute_) {  // the first usable field after a start without one: at once
          mahony_.align_yaw(m);
          yaw_error = 0.0;
          heading_absolute_ = true;
        }
      }
      if (gap) gaps_.rate_over_gap(w);
      mahony_.step(a, w, dt_s, !saturated, yaw_error, config_.mag_kp_per_s);
      acc_norm_lp_ += gravity_gain_(dt_s) * (a_norm - acc_norm_lp_);
    }

    gaps_.note_rate(gyr);  // as measured (w is the gap's mean over a gap)

    // The specific force in the world frame, gravity removed; the heading of the forward axis.
    const imu::Vec3 f_w = mahony_.to_world(a);
    imu::Vec3 x_w = mahony_.axis_to_world(config_.forward_axis);
    for (double& c : x_w) c *= fwd_sign_;
    const double hn = sqrt1(x_w[0] * x_w[0] + x_w[1] * x_w[1]);
    if (hn > 0.2) heading_ = {x_w[0] / hn, x_w[1] / hn};  // held while the axis is near vertical
    o.heading_rad = atan2_fast(heading_[1], heading_[0]);  // within 2e-6 rad, no library call per sample
    o.tilt_rad = atan2_fast(x_w[2], hn);
    o.heading_absolute = heading_absolute_;
    // A saturated sample is no measurement: the integrators get the last unsaturated values.
    if (!saturated || restart) {
      az_last_ = f_w[2] - kGravityMps2;
      ax_last_ = f_w[0] * heading_[0] + f_w[1] * heading_[1];
    }
    o.az_mps2 = az_last_;
    const double ax = ax_last_;
    if (restart) {
      int_z_.start(o.az_mps2, !gap_restart_);
      int_x_.start(ax, !gap_restart_);
      o.vz_mps = o.vx_osc_mps = 0.0;
    } else if (bridged) {
      bridge_gap(t_s, dt_s, ax);
    } else {
      o.vz_mps = int_z_.step(o.az_mps2, dt_s);
      o.vx_osc_mps = int_x_.step(ax, dt_s);
    }
    if (!restart && !bridged) gaps_.track(t_s, dt_s);
    o.vx_mps = pendulum_.fed_speed_mps() + o.vx_osc_mps;
    o.input_latency_s = input_latency_s_;

    const bool settled = t_s - start_t_s_ >= config_.settle_s;
    if (settled && !restart) {
      if (span_s_ == 0.0) t_first_s_ = t_s;
      // A bridged gap's end stands for one mean interval: the estimator's samples are means of
      // what was measured, the model's own values over the gap are not fed back to it.
      const double weight_s = bridged ? gaps_.mean_s() : dt_s;
      sum_vx_ += o.vx_mps * weight_s;
      sum_vz_ += o.vz_mps * weight_s;
      sum_az2_ += o.az_mps2 * o.az_mps2 * weight_s;
      sum_age_s2_ += (t_s - t_first_s_) * weight_s;
      span_s_ += weight_s;
      const double T = config_.estimator.sample_time_s;
      if (span_s_ + 0.5 * weight_s >= T * (1.0 - 1e-9)) {
        const double step_dt_s = fed_ ? t_s - t_tick_s_ : T;
        const GaitState prior = est_.gait_state;
        const double vz_mean = sum_vz_ / span_s_;
        est_ = estimator_.step(sum_vx_ / span_s_, vz_mean, step_dt_s);
        fed_ = true;
        // First: the checks and stds of this sample use its step length.
        pendulum_.update(est_.gait_state, amplitude_var(), est_.walking, est_.acquiring, step_dt_s);
        // The periodicity check's lags are in samples of the estimator's period: a sample whose
        // interval spans a bridged gap (its swallowed samples filled in) counts as one.
        sampled(prior, step_dt_s, vz_mean, sum_az2_ / span_s_,
                gap_in_tick_ ? config_.estimator.sample_time_s : step_dt_s);
        gap_in_tick_ = false;
        o.estimator_fed = true;
        t_tick_s_ = t_s;
        tick_age_s_ = (t_s - t_first_s_) - sum_age_s2_ / span_s_;
        sum_vx_ = sum_vz_ = sum_az2_ = span_s_ = sum_age_s2_ = 0.0;
      }
    }
    carry_estimate(t_s);
    o.valid = false;
    if (t_s - t_saturated_s_ <= config_.saturation_hold_s)
      o.reason = ImuReason::kSaturated;
    else if (gap_restart_ && !settled)
      o.reason = ImuReason::kGap;
    else if (std::fabs(acc_norm_lp_ - kGravityMps2) > config_.gravity_tolerance * kGravityMps2)
      o.reason = ImuReason::kGravity;
    else if (!fed_)
      o.reason = ImuReason::kAcquiring;
    else if (!o.walking)  // standing says more than a bank waiting for steps (it restarts at each stop)
      o.reason = ImuReason::kNotWalking;
    else if (est_.acquiring || harmonic_off_ ||
             !(o.step_frequency_hz > f_locked_min_hz_ && o.step_frequency_hz < f_locked_max_hz_) ||
             std::isnan(o.next_step_in_s))  // no phase yet: the vertical phasor still 0 (every sample rejected)
      o.reason = ImuReason::kAcquiring;
    else if (irregular_)
      o.reason = ImuReason::kIrregular;
    else if (uncertain_)
      o.reason = ImuReason::kUncertain;
    else if (!(o.speed_mps >= 0.0 && o.speed_mps <= config_.max_speed_mps))
      o.reason = ImuReason::kSpeedImplausible;
    else {
      o.reason = ImuReason::kOk;
      o.valid = true;
    }
    if (settled) gap_restart_ = false;
    return o;
  }

  const ImuConfig& config() const noexcept { return config_; }
  /// The estimator's last estimate (at its last sample, estimate_age_s ago).
  const Estimate& estimate() const noexcept { return est_; }
  const Estimator& estimator() const noexcept { return estimator_; }
  /// The orientation filter.
  const imu::Mahony& orientation() const noexcept { return mahony_; }
  /// The last estimate returned by update().
  const ImuEstimate& last() const noexcept { return out_; }

 private:
  static const ImuConfig& checked(const ImuConfig& c) {
    if (const char* e = c.validate()) throw std::invalid_argument(e);
    return c;
  }
  // A frequency at a bound of the estimator's range is a filter that has not locked.
  static double locked_min_hz(const ImuConfig& c) noexcept { return 1.02 * c.estimator.gait_filter.f_min_hz; }
  static imu::Pendulum::Settings pendulum_settings(const ImuConfig& c) noexcept {
    imu::Pendulum::Settings s;
    s.length_m = c.sensor_height_m;
    s.step_length_factor = c.step_length_factor;
    s.excursion_tau_s = c.excursion_tau_s;
    s.max_speed_mps = c.max_speed_mps;
    return s;
  }

  // A (re)start: the integrators from rest. The orientation is taken from the specific force only
  // at the first sample: after a gap the filter's own orientation (held over the gap) is closer
  // than one reading taken mid-step. The estimator starts again (a gap in its input would read as
  // a jump of phase and amplitude), and so does the pendulum speed.
  void start_front_end(double t_s, const imu::Vec3& a) noexcept {
    if (!started_) mahony_.start(a);
    harmonic_.clear();
    if (started_) {
      estimator_.reset();
      restart_estimate();
      est_ = Estimate{};
      fed_ = false;
      pendulum_.clear(true);
    }
    started_ = true;
    yaw_rate_lp_rad_s_ = 0.0;
    heading_tick_ = heading_;
    start_t_s_ = t_s;
    sum_vx_ = sum_vz_ = sum_az2_ = span_s_ = sum_age_s2_ = 0.0;
  }

  // Samples missing over a fraction of a step (a wireless link's dropout) while the model holds:
  // the integrals at the gap's end (t_s, dt_s after the last sample; ax the forward acceleration,
  // out_.az_mps2 the vertical) are the model's values there plus what the integrals held beyond the
  // model at its start, decayed as the leaky integrator decays it. The model's values are those of
  // the front-end's own velocities (fed to it), at the age of the last estimator sample. The
  // periodicity check's ring gets the model's v_z for the estimator samples the gap swallowed.
  YOYOGAIT_COLD void bridge_gap(double t_s, double dt_s, double ax) noexcept {
    ImuEstimate& o = out_;
    const double h0 = (t_s - dt_s - t_tick_s_) + tick_age_s_, h1 = h0 + dt_s;
    const Forecast f0 = estimator_.forecast(h0 > 0.0 ? h0 : 0.0, false);
    const Forecast f1 = estimator_.forecast(h1 > 0.0 ? h1 : 0.0, false);
    o.vz_mps = int_z_.bridge(o.az_mps2, dt_s, f0.vz_mps, f1.vz_mps);
    o.vx_osc_mps = int_x_.bridge(ax, dt_s, f0.vx_mps - f0.speed_mps, f1.vx_mps - f1.speed_mps);
    const double T = config_.estimator.sample_time_s;
    for (int k = 1, n = gaps_.swallowed(dt_s, T); k <= n; ++k)
      harmonic_.fill(estimator_.forecast(h0 + (static_cast<double>(k) - 0.5) * T, false).vz_mps);
    gap_in_tick_ = true;
  }

  // The estimator (re)starts: what its outputs' stds know goes too (the v_z ring stays: it is the
  // front-end's, cleared at a start of the front-end).
  void restart_estimate() noexcept {
    validity_.reset();
    speed_from_pendulum_ = false;
    lock_scale_ = 0.0;
    harmonic_.restart(false);
    harmonic_off_ = false;
    harmonic_off_s_ = 0.0;
    irregular_ = false;
    f_std_ = s_std_ = std::numeric_limits<double>::infinity();
    uncertain_ = true;
  }

  // After each estimator sample: its stds made honest (as OnlineEstimator does: scaled by the
  // innovations' excess, plus what a transient adds, at least Validity::pinned_std_hz() at a bound of the range;
  // the speed's the pendulum's terms, imu::SpeedVariance) and the harmonic check on the fed v_z, whose
  // lags are in intervals of check_dt_s. imu/imu_sampled.hpp.
  void sampled(const GaitState& prior, double dt_s, double vz_mean, double az2_mean, double check_dt_s) noexcept;
  // The filter's variance of |Z| along Z (0 at Z = 0: the pendulum then takes 4, its bound).
  double amplitude_var() const noexcept;  // imu/imu_sampled.hpp
  // Whether the estimator sits on a wrong harmonic of the step: by the fed v_z's autocorrelation
  // (imu::HarmonicCheck) or by the walk ratio; held kHarmonicRestartS, the estimator restarts.
  void check_harmonic(double vz, double dt_s) noexcept;  // imu/imu_sampled.hpp

  // The estimator's last estimate carried to t_s by its own forecast (as OnlineEstimator does).
  void carry_estimate(double t_s) noexcept {
    ImuEstimate& o = out_;
    const Estimate& e = est_;
    o.step_frequency_hz = e.step_frequency_hz;
    // The speed is the pendulum's, once it runs: the estimator's A0 follows the fed speed only over
    // seconds (its random walk), too slowly for a walk of a few steps.
    o.speed_mps = pendulum_.speed_mps() > 0.0 ? pendulum_.speed_mps() : e.speed_mps;
    if (!fed_) {  // nothing is known of the estimator's outputs yet
      o.step_frequency_std_hz = o.speed_std_mps = std::numeric_limits<double>::infinity();
    } else {
      o.step_frequency_std_hz = f_std_;
      o.speed_std_mps = s_std_;
    }
    o.excursion_m = pendulum_.excursion_m();
    o.step_length_m = pendulum_.step_length_m();
    o.pendulum_speed_mps = pendulum_.speed_mps();
    // The detector's walking, while the vertical motion is a walker's (min_vz_rms_mps): a still
    // sensor after a stop is standing, whatever the detector's low-passes still hold.
    o.walking = fed_ && e.walking && !(vz2_step_lp_ < config_.min_vz_rms_mps * config_.min_vz_rms_mps);
    o.estimator_status = e.status;
    if (!fed_) {
      o.vx_hat_mps = o.vx_mps;
      o.vz_hat_mps = o.vz_mps;
      o.next_step_in_s = std::numeric_limits<double>::quiet_NaN();
      carry_h_s_ = 0.0;
      return;
    }
    const double h_s = (t_s - t_tick_s_) + tick_age_s_ + o.input_latency_s;
    carry_h_s_ = h_s;
    const Forecast f = estimator_.forecast(std::fmax(0.0, h_s), false, &carry_decay_);
    o.vx_hat_mps = f.vx_mps;
    o.vz_hat_mps = f.vz_mps;
    const GaitState& x = e.gait_state;
    phase_.update(e.walking, x[gait::kZ1], x[gait::kZ2], f.phase_advance_rad, f.omega_rad_s, f.omega_rate_rad_s2,
                  e.step_frequency_hz);
    o.next_step_in_s = phase_.next_step_in_s();
    o.gait_phase = phase_.phase();
  }

  ImuConfig config_;
  Estimator estimator_;
  imu::Mahony mahony_;
  imu::LeakyIntegrator int_z_, int_x_;
  double fwd_sign_ = 1.0;  ///< the forward direction is +1 or -1 times forward_axis
  double input_latency_s_ = 0.0;  ///< the integrators' delay at latency_f_hz (constant)
  double f_locked_min_hz_ = 0.0, f_locked_max_hz_ = 1e9, az_last_ = 0.0, ax_last_ = 0.0;
  Estimate est_{};
  gait::HorizonDecay carry_decay_;  ///< the carry's forecast factors at its last horizons
  ImuEstimate out_{};
  bool have_time_ = false, fed_ = false, started_ = false, started_before_ = false, gap_restart_ = false;
  bool heading_absolute_ = false;
  double t_last_s_ = 0.0, start_t_s_ = 0.0, t_tick_s_ = 0.0, t_first_s_ = 0.0;
  double sum_vx_ = 0.0, sum_vz_ = 0.0, sum_az2_ = 0.0, span_s_ = 0.0, sum_age_s2_ = 0.0;
  double tick_age_s_ = 0.0, carry_h_s_ = 0.0;
  imu::SampleGaps gaps_;
  bool gap_in_tick_ = false;  ///< a bridged gap since the last estimator sample
  online::GaitPhase phase_;
  imu::Pendulum pendulum_;
  imu::SpeedVariance speed_var_;
  online::Validity validity_{};
  double f_std_ = 0.0, s_std_ = 0.0;  ///< the reported stds until the next estimator sample
  /// The stds say no more than the ranges do (a std of f at least uniform_std of its range, of the
  /// speed at least uniform_std of [0, max_speed_mps]): no estimate to act on (UNCERTAIN).
  bool uncertain_ = true;
  bool speed_from_pendulum_ = false;  ///< the speed reported at the last estimator sample was the pendulum's
  /// A fresh lock's share of the step frequency's std decays over this [s] (lock_f_rel_std).
  static constexpr double kLockTauS = 1.5;
  double lock_scale_ = 0.0;  ///< exp(-time since the lock / kLockTauS); 0 without a lock
  ExpGain lock_gain_{kLockTauS};
  /// A wrong harmonic held this long: the estimator restarts [s].
  static constexpr double kHarmonicRestartS = 1.0;
  /// The low-pass of the fed v_z's square over about a step, against min_vz_rms_mps [s]: once the
  /// walker stands, it falls below a walker's within half a second (the speed's standing one holds
  /// it a second: imu/speed_variance.hpp).
  static constexpr double kStepTauS = 0.25;
  double vz2_step_lp_ = 0.0;
  ExpGain step_gain_{kStepTauS};
  /// Low-pass of the yaw rate, for the step frequency's std in a turn [s].
  static constexpr double kTurnTauS = 0.5;
  double yaw_rate_lp_rad_s_ = 0.0;
  ExpGain turn_gain_{kTurnTauS};
  std::array<double, 2> heading_tick_{1.0, 0.0};  ///< the heading at the last estimator sample
  imu::HarmonicCheck harmonic_;
  bool harmonic_off_ = false;  ///< off a harmonic (by the autocorrelation or the walk ratio)
  bool irregular_ = false;  ///< the last steps do not repeat at the estimate's period (min_periodicity)
  double harmonic_off_s_ = 0.0;
  std::array<double, 2> heading_{1.0, 0.0};
  double t_saturated_s_ = 0.0, acc_norm_lp_ = kGravityMps2;
  ExpGain gravity_gain_;
  imu::MagGate mag_gate_;  ///< which magnetometer samples the heading may use
};

}  // namespace yoyogait

// What follows each estimator sample (sampled, amplitude_var, check_harmonic): imu/imu_sampled.hpp.
#include "yoyogait/imu/imu_sampled.hpp"
