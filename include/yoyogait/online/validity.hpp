/// @file online/validity.hpp
/// @brief Whether an online estimate can be used as it is (OnlineEstimate::valid) and, when not,
/// why (OnlineEstimate::invalid_reason, a set of InvalidReason bits); the input-noise estimate; the
/// inflation of the reported standard deviations while the model does not hold (docs/online.md,
/// "Validity").
///
/// Everything here is a first-order low-pass (gain dt / (tau + dt), no exp per frame) or a
/// comparison; a ring of 16 centre positions keeps the distance travelled. No allocation.
#pragma once

#include <array>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <limits>

#include "yoyogait/gait/net_time.hpp"
#include "yoyogait/gait/state.hpp"
#include "yoyogait/math.hpp"
#include "yoyogait/online/interval_cache.hpp"
#include "yoyogait/online/online_estimate.hpp"

namespace yoyogait::online {

/// The phase correction of an estimator sample, as Validity::sample takes it: the vertical phasor's
/// turn from the prior to the posterior less the w dt the model turns it by; NaN while not walking,
/// while acquiring or with a vanishing phasor (no phase to speak of).
inline double phase_correction_rad(const GaitState& prior, const GaitState& posterior, bool walking, bool acquiring,
                                   double dt_s) noexcept {
  const double p1 = prior[gait::kZ1], p2 = prior[gait::kZ2];
  const double q1 = posterior[gait::kZ1], q2 = posterior[gait::kZ2];
  return walking && !acquiring && p1 * p1 + p2 * p2 > 1e-8 && q1 * q1 + q2 * q2 > 1e-8
             ? atan2_fast(p1 * q2 - p2 * q1, p1 * q1 + p2 * q2) - prior[gait::kW] * dt_s
             : std::numeric_limits<double>::quiet_NaN();
}

/// The checks behind OnlineEstimate::valid, one per InvalidReason, fed frame by frame.
class Validity {
 public:
  struct Settings {
    double valid_after_s = 2.0;           ///< walking (bank collapsed) this long before an estimate is valid [s]
    double min_rate_hz = 10.0;            ///< a lower mean frame rate flags kRateTooLow [Hz]
    double max_plausible_speed_mps = 6.0;  ///< a front-end RMS speed (over ~0.25 s) above it: kImplausibleInput [m/s]
    double max_input_noise_m = 0.005;     ///< estimated marker noise above it: kInputNoisy [m]
    double feet_max_input_noise_m = 0.03;  ///< the same while the feet's cadence agrees with the estimate [m]
    double max_nis = 6.0;                 ///< mean NIS of the estimator over about a second above it: kModelNotHolding
    double stale_s = 0.35;                ///< an estimate older than this: kInputMissing [s]
    double min_travel_ratio = 0.5;        ///< distance travelled / (speed x time) below it: kNotMoving
    double f_min_hz = 0.6, f_max_hz = 3.5;  ///< the estimator's frequency range (a pinned estimate is not valid)
    /// Low-pass of the phase corrections' rate behind the frequency's std [s] (the [online] and [imu]
    /// phase_std_tau_s).
    double phase_tau_s = kRateLpTauS;
    /// The phase corrections low-passed over this, signed and absolute, for the frequency's std at a
    /// cadence change's onset (the [imu] phase_onset_tau_s; 0: not used) [s].
    double phase_onset_tau_s = 0.0;
  };

  /// The hold of kImplausibleInput after the last implausible frame [s]; the window of the distance
  /// travelled [s]; an instantaneous front-end speed that is implausible at once [m/s].
  static constexpr double kImplausibleHoldS = 2.0, kTravelWindowS = 2.0, kJumpSpeedMps = 50.0;
  /// Less travel than this over the window is no walking that can be told from noise [m] (0.125 m/s).
  static constexpr double kMinTravelM = 0.25;
  /// The travel over the window of a point that must travel to walk (OnlineConfig::gait_in_place
  /// false: a hand) [m]: more than a standing person's hand sweeps in a gesture (reaching, pointing:
  /// 0.2-0.4 m), within the slowest walker served (0.3 m/s: 0.6 m).
  static constexpr double kWalkerTravelM = 0.5;
  /// Low-pass time constants: frame rate, speed, the centre's steps at changes of the visible set [s].
  static constexpr double kRateTauS = 1.0, kSpeedTauS = 0.25, kSetTauS = 1.0;
  /// The centre's steps at changes of the visible points, summed per second, above which the input
  /// counts as missing [m/s]: each step is blended out over centre_blend_tau_s, so their sum per
  /// second is the speed the blends add; a third of the 0.15 m/s the evaluation calls wrong. (A count
  /// of the changes would flag single dropouts at 100 Hz whose steps are tenths of a millimetre, and
  /// pass flicker at 15 Hz; docs/online.md, "Validity".)
  static constexpr double kMaxCentreStepsMps = 0.05;
  /// The lag of the estimates behind a change of cadence or speed, for their stds [s]; the low-pass
  /// of their rates of change [s] (also the NIS's, and the phase corrections' by default).
  static constexpr double kTransientLagS = 1.0, kRateLpTauS = 0.5;
  /// The frequency error taken per unit of the phase correction rate (the update corrects part of it).
  static constexpr double kPhaseGain = 3.0;
  /// The low-pass of the v_x innovation, two estimator samples [s] (a stop decelerates by 0.2-0.3 m/s
  /// within 0.2 s): its mean is how far the speed's estimate lags a start, a stop or a change of
  /// speed (the oscillation, predicted, is not in it). Also the low-pass of the heading's loss.
  static constexpr double kBiasTauS = 0.08;

  Validity() noexcept = default;
  explicit Validity(const Settings& s) noexcept : s_(s) { reset(); }

  void reset() noexcept {
    dt_lp_s_ = -1.0;
    noise2_lp_m2_ = 0.0;
    speed2_lp_ = 0.0;
    gains_dt_s_ = -1.0;
    nis_lp_ = 2.0;
    centre_steps_mps_ = 0.0;
    below_steps_.reset();
    off_feet_.reset();
    implausible_until_s_ = -1e300;
    steady_since_s_ = 0.0;
    steady_ = false;
    have_last_ = false;
    last_f_hz_ = last_speed_mps_ = f_rate_lp_ = s_rate_lp_ = phase_rate_lp_ = bias_vx_lp_ = heading_loss_lp_ = 0.0;
    onset_rate_lp_ = onset_abs_lp_ = 0.0;
    sample_gains_.reset();
    restart_travel();
  }

  /// A frame accepted dt_s after the previous one (0 for the first).
  void frame(double dt_s) noexcept {
    if (dt_s > 0.0) {
      if (!near_gains_dt(dt_s)) {  // the gains change only with the frame interval
        gains_dt_s_ = dt_s;
        g_rate_ = gain(dt_s, kRateTauS);
        g_set_ = gain(dt_s, kSetTauS);
        g_speed_ = gain(dt_s, kSpeedTauS);
        g_loss_ = gain(dt_s, kBiasTauS);
      }
      dt_lp_s_ = dt_lp_s_ < 0.0 ? dt_s : dt_lp_s_ + g_rate_ * (dt_s - dt_lp_s_);
      centre_steps_mps_ -= g_set_ * centre_steps_mps_;
    }
  }

  /// The step of the centre that a change of the visible points starts blending out [m] (after
  /// frame()): a moving sum over kSetTauS, per second.
  void centre_step(double step_m) noexcept { centre_steps_mps_ += step_m / kSetTauS; }

  /// The front-end restarted: the travel and the noise start again.
  void restart_travel() noexcept {
    ring_n_ = 0;
    ring_next_ = 0;
    ring_t_s_ = -1e300;
    ring_path_m_ = 0.0;
  }

  /// The differentiator's update at t_s, dt_s after the previous frame with a point (the frame of
  /// frame()): the input-noise estimate (online/input_noise.hpp), position and velocity. The speed
  /// is low-passed as its square (an RMS).
  void front_end(double t_s, double dt_s, double noise2_m2, double pa_m, double pb_m, double va_mps, double vb_mps,
                 double vz_mps) noexcept {
    noise2_lp_m2_ = noise2_m2;
    if (dt_s > 0.0) {
      const bool same = near_gains_dt(dt_s);
      const double gs = same ? g_speed_ : gain(dt_s, kSpeedTauS);
      const double v2 = va_mps * va_mps + vb_mps * vb_mps + vz_mps * vz_mps;
      speed2_lp_ += gs * ((v2 <= 1e300 ? v2 : 1e300) - speed2_lp_);
      const double lim = s_.max_plausible_speed_mps;
      if (!(v2 <= kJumpSpeedMps * kJumpSpeedMps) || !(speed2_lp_ <= lim * lim))
        implausible_until_s_ = t_s + kImplausibleHoldS;
    }
    if (t_s - ring_t_s_ >= kTravelWindowS / static_cast<double>(kRing)) {
      // The path along the marks: the new segment in, the one of the mark overwritten out.
      const double sa = pa_m - pa_m_, sb = pb_m - pb_m_, d = std::sqrt(sa * sa + sb * sb);
      const double seg = ring_n_ > 0 && std::isfinite(d) ? d : 0.0;
      if (ring_n_ == kRing) ring_path_m_ -= ring_[ring_next_].seg_m;
      ring_path_m_ += seg;
      ring_[ring_next_] = {t_s, pa_m, pb_m, seg};
      ring_t_s_ = t_s;
      ring_next_ = (ring_next_ + 1) % kRing;
      if (ring_n_ < kRing) ++ring_n_;
      pa_m_ = pa_m;
      pb_m_ = pb_m;
    }
  }

  /// The horizontal velocity (va_mps, vb_mps) and its component vx_mps along the reported heading,
  /// dt_s after the previous frame: the speed that the heading's lag in a turn takes from v_x
  /// (|v_h| - v_x), low-passed over kBiasTauS, is an error of the speed that no innovation shows.
  void heading(double dt_s, double va_mps, double vb_mps, double vx_mps) noexcept {
    if (!(dt_s > 0.0)) return;
    const double loss = std::sqrt(va_mps * va_mps + vb_mps * vb_mps) - vx_mps;
    const double g = near_gains_dt(dt_s) ? g_loss_ : gain(dt_s, kBiasTauS);
    if (std::isfinite(loss)) heading_loss_lp_ += g * (loss - heading_loss_lp_);
  }

  /// An outlier at t_s that moved the centre dist_m within dt_s (not differentiated): a jump faster
  /// than kJumpSpeedMps is implausible input as a differentiated one would be.
  void outlier(double t_s, double dist_m, double dt_s) noexcept {
    if (!(dist_m <= kJumpSpeedMps * dt_s)) implausible_until_s_ = t_s + kImplausibleHoldS;
  }

  /// The estimator's sample dt_s after the previous one: its NIS (NaN: nothing updated), step
  /// frequency and speed (their rates of change, low-passed, measure how far a transient is off).
  /// correction_rad: the phase correction of the vertical phasor by the update (the posterior's
  /// angle less the prior's, turned by w dt; NaN: none): while the cadence is off, the update keeps
  /// turning the phase the same way, by about the frequency error times dt.
  /// innovation_vx_mps: the v_x measurement less its prediction (NaN: none); low-passed over
  /// kBiasTauS, it measures the speed's lag behind a change the model has not followed yet.
  void sample(double dt_s, double nis, double f_hz, double speed_mps, double correction_rad,
              double innovation_vx_mps = std::numeric_limits<double>::quiet_NaN()) noexcept {
    if (!(dt_s > 0.0)) return;
    // One gain for the NIS and the rates (kNisTauS = kRateLpTauS), one for the phase corrections.
    const double phase_tau_s = s_.phase_tau_s, onset_tau_s = s_.phase_onset_tau_s;
    const SampleGains& sg = sample_gains_.at(dt_s, [phase_tau_s, onset_tau_s](double dt) {
      return SampleGains{gain(dt, kRateLpTauS), gain(dt, kBiasTauS), 1.0 / dt, gain(dt, phase_tau_s),
                         onset_tau_s > 0.0 ? gain(dt, onset_tau_s) : 0.0};
    });
    const double g = sg.g, g_bias = sg.bias, inv = sg.inv_dt;
    if (std::isfinite(nis)) nis_lp_ += g * (nis - nis_lp_);
    if (std::isfinite(innovation_vx_mps)) bias_vx_lp_ += g_bias * (innovation_vx_mps - bias_vx_lp_);
    if (have_last_) {
      f_rate_lp_ += g * ((f_hz - last_f_hz_) * inv - f_rate_lp_);
      s_rate_lp_ += g * ((speed_mps - last_speed_mps_) * inv - s_rate_lp_);
    }
    have_last_ = true;
    last_f_hz_ = f_hz;
    last_speed_mps_ = speed_mps;
    if (correction_rad > 3.141592653589793) correction_rad -= 6.283185307179586;
    if (correction_rad < -3.141592653589793) correction_rad += 6.283185307179586;
    if (std::isfinite(correction_rad)) {
      phase_rate_lp_ += sg.phase * (correction_rad * inv - phase_rate_lp_);
      if (sg.onset > 0.0) {  // phase_onset_tau_s set (the IMU's)
        onset_rate_lp_ += sg.onset * (correction_rad * inv - onset_rate_lp_);
        onset_abs_lp_ += sg.onset * (std::fabs(correction_rad) * inv - onset_abs_lp_);
      }
    }
  }

  /// The speed reported takes its value from another source from now on (the IMU's pendulum taking
  /// over from the estimator's A0): the next sample's rate starts from speed_mps, and the rate of the
  /// old source is dropped; a jump from one source to the other is no transient of the walk.
  void rebase_speed(double speed_mps) noexcept {
    last_speed_mps_ = speed_mps;
    s_rate_lp_ = 0.0;
  }

  /// The variance a transient adds to f [Hz^2] and to the speed [(m/s)^2]: (kTransientLagS x the
  /// low-passed rate)^2, how far an estimate that lags by kTransientLagS is behind a change; for f,
  /// also (kPhaseGain x the low-passed phase correction rate / 2 pi)^2, or, when larger, the same of
  /// the rate over phase_onset_tau_s times its coherence (|signed mean| / mean of |correction|: near
  /// 1 while the corrections keep one sign at a change's onset, small for step-to-step jitter).
  double transient_var_f() const noexcept {
    const double c = kPhaseGain * phase_rate_lp_ * 0.15915494309189535;
    double phase_var = c * c;
    if (onset_abs_lp_ > 0.0) {
      const double coherence = std::fabs(onset_rate_lp_) / onset_abs_lp_;
      const double o = kPhaseGain * coherence * onset_rate_lp_ * 0.15915494309189535;
      if (o * o > phase_var) phase_var = o * o;
    }
    return kTransientLagS * kTransientLagS * f_rate_lp_ * f_rate_lp_ + phase_var;
  }
  /// For the speed, also the low-passed v_x innovation squared (the lag the innovations show) and the
  /// low-passed speed lost to the heading's lag (heading()).
  double transient_var_speed() const noexcept {
    return kTransientLagS * kTransientLagS * s_rate_lp_ * s_rate_lp_ + bias_vx_lp_ * bias_vx_lp_ +
           heading_loss_lp_ * heading_loss_lp_;
  }

  /// What the estimator reports, at t_s.
  struct Inputs {
    bool fed = false, walking = false, acquiring = true, frame_ignored = false;
    bool gait = true;  ///< walking and the centre moves as in gait (online/gait_evidence.hpp)
    double estimate_age_s = 0.0, speed_mps = 0.0, step_frequency_hz = 0.0;
    double steps_hz = 0.0;  ///< the step frequency the centre's extrema show (0: not known)
    double feet_hz = 0.0;   ///< the step frequency the feet show (online/foot_cadence.hpp; 0: not known)
  };

  /// The InvalidReason bits at t_s.
  std::uint8_t reasons(double t_s, const Inputs& in) noexcept {
    std::uint8_t r = 0;
    const bool steady = in.fed && in.walking && !in.acquiring;
    if (steady && !steady_) steady_since_s_ = t_s;
    steady_ = steady;
    if (!in.fed || in.acquiring || (steady && t_s - steady_since_s_ < s_.valid_after_s)) r |= bit(InvalidReason::kAcquiring);
    if (in.fed && !(in.walking && in.gait)) r |= bit(InvalidReason::kNotWalking);
    // The feet's steps agreeing with the estimate tell a right lock from one on the noise: more
    // noise is served then.
    const double f = in.step_frequency_hz, margin = 0.02 * (s_.f_max_hz - s_.f_min_hz);
    const bool off_feet_now = off_feet(f, in.feet_hz);
    const double max_noise = in.feet_hz > 0.0 && !off_feet_now ? s_.feet_max_input_noise_m : s_.max_input_noise_m;
    if (noise2_lp_m2_ > max_noise * max_noise) r |= bit(InvalidReason::kInputNoisy);
    if (in.frame_ignored || in.estimate_age_s > s_.stale_s || centre_steps_mps_ > kMaxCentreStepsMps)
      r |= bit(InvalidReason::kInputMissing);
    const bool at_bound = f <= s_.f_min_hz + margin || f >= s_.f_max_hz - margin;
    if (nis_lp_ > s_.max_nis ||
        (in.walking && (off_feet_now || at_bound || too_long_steps(f, in.speed_mps) ||
                        (in.gait && below_steps(f, in.steps_hz, in.feet_hz)))))
      r |= bit(InvalidReason::kModelNotHolding);
    if (t_s < implausible_until_s_ || !(std::fabs(in.speed_mps) <= s_.max_plausible_speed_mps))
      r |= bit(InvalidReason::kImplausibleInput);
    if (dt_lp_s_ * s_.min_rate_hz > 1.0) r |= bit(InvalidReason::kRateTooLow);
    if (in.walking && !moved(in.speed_mps)) r |= bit(InvalidReason::kNotMoving);
    return r;
  }

  /// Whether the centre moved at least kMinTravelM away over the window (away(); a treadmill walk is
  /// not taken for travel during its first seconds) and travelled at least min_travel_ratio x speed x
  /// time along the window's marks (the path, 0.125 s apart: a tight turn travels its arc, not its
  /// chord); true until two marks are kept. On a treadmill the belt's travel counts.
  bool moved(double speed_mps) const noexcept {
    if (ring_n_ < 2) return true;
    const Mark& old = oldest();
    const double dt = ring_t_s_ - old.t_s, need = s_.min_travel_ratio * std::fabs(speed_mps) * dt;
    const double path_m = ring_path_m_ - old.seg_m;  // the oldest's segment leads to a mark no longer kept
    return away(kMinTravelM) && path_m >= need;
  }
  /// Whether the centre is at least least_m from where it was at the window's start (in proportion
  /// while the window fills after a restart); true until two marks are kept.
  bool away(double least_m) const noexcept {
    if (ring_n_ < 2) return true;
    const Mark& old = oldest();
    const double dt = ring_t_s_ - old.t_s, da = pa_m_ - old.a_m, db = pb_m_ - old.b_m;
    const double least = dt < kTravelWindowS ? least_m * dt * (1.0 / kTravelWindowS) : least_m;
    return da * da + db * db >= least * least;
  }

  /// The marker noise estimated from the differentiator's innovations (the last front_end's) [m].
  double input_noise_m() const noexcept { return std::sqrt(noise2_lp_m2_); }
  /// The factor on the reported standard deviations: sqrt(mean NIS / 2), at least 1.
  double std_inflation() const noexcept { return nis_lp_ > 2.0 ? sqrt1(0.5 * nis_lp_) : 1.0; }
  /// Its square, the factor on variances (no square root per frame).
  double var_inflation() const noexcept { return nis_lp_ > 2.0 ? 0.5 * nis_lp_ : 1.0; }
  /// An estimate below this fraction of the step frequency the centre's extrema show is below the
  /// steps the walker makes (a lock on a start's slow first steps, or on half the steps): the model
  /// does not hold. On the shared recordings and the SYNTHETIC walks the valid estimates lie at 0.71
  /// and more of it (1st percentile; slow walks' small bobs are missed, which only lowers the
  /// extrema's figure); a lock on half the steps lies at 0.5 (docs/online.md, "Validity").
  /// The feet's steps, where known (feet_hz > 0) and agreeing with the estimate (not off_feet),
  /// overrule the centre's: centimetres of markerless jitter make extrema of the centre at 3-5 Hz
  /// that no step made, while the feet's cadence is off by 0.05 Hz (median; docs/online.md, "Feet").
  static constexpr double kBelowStepsRatio = 0.6;
  static bool below_steps(double f_hz, double steps_hz, double feet_hz) noexcept {
    return steps_hz > 0.0 && f_hz < kBelowStepsRatio * steps_hz && !(feet_hz > 0.0 && !off_feet(f_hz, feet_hz));
  }
  /// No walker's step is longer than this [m] (step length = speed / step frequency: about 0.4 x body
  /// height at a fast walk, 0.75-0.95 m; the valid estimates of the shared recordings and the SYNTHETIC
  /// walks reach 0.94 m). Longer: the frequency is below the steps (a lock on one per stride, as a
  /// hand that swings or dribbles once per stride shows), the model does not hold.
  static constexpr double kMaxStepM = 1.0;
  static bool too_long_steps(double f_hz, double speed_mps) noexcept { return speed_mps > kMaxStepM * f_hz; }
  /// A lock (walking, acquired, the centre moving as in gait) below_steps for kBelowStepsS of
  /// walking, net of the time it is not (gait/net_time.hpp), is a failed lock: true once, when the
  /// caller is to restart the acquisition. Per estimator sample, dt_s after the last.
  static constexpr double kBelowStepsS = 1.0;
  bool failed_lock_below_steps(bool locked_below, double dt_s) noexcept {
    return below_steps_.held_beyond(locked_below, dt_s, kBelowStepsS);
  }

  /// An estimate further than this from the step frequency the feet show is off their steps [Hz]:
  /// beyond the 0.15 Hz the evaluation calls wrong by the feet's own error over four steps (0.031 Hz
  /// median on the shared recordings, 0.053 with markerless noise; docs/online.md, "Feet").
  static constexpr double kFeetToleranceHz = 0.2;
  static bool off_feet(double f_hz, double feet_hz, double tolerance_hz = kFeetToleranceHz) noexcept {
    return feet_hz > 0.0 && std::fabs(f_hz - feet_hz) > tolerance_hz;
  }
  /// A lock (walking, acquired) off_feet by more than kRelockHz for kOffFeetS of walking, net
  /// (gait/net_time.hpp), is a failed lock: true once, when the caller is to relock at the feet's
  /// cadence. Per estimator sample, dt_s after the last. Wider and longer than off_feet: a relock
  /// starts the lock again, and the feet's figure has its own error (its 95th percentile: 0.12 Hz
  /// with markerless noise).
  static constexpr double kRelockHz = 0.3, kOffFeetS = 1.0;
  bool failed_lock_off_feet(bool locked_off, double dt_s) noexcept {
    if (!off_feet_.held_beyond(locked_off, dt_s, kOffFeetS)) return false;
    steady_ = false;  // a new lock: valid_after_s of walking again
    return true;
  }

  /// The frequency std reported at a bound of the range, at least [Hz]: a bound is no estimate, so
  /// what is known is the range alone, the std of a frequency spread evenly over it ((f_max - f_min)
  /// / sqrt 12: 0.89 Hz for the default 0.4-3.5 Hz; 2 std from a bound reach past the middle of the range).
  double pinned_std_hz() const noexcept { return uniform_std(s_.f_max_hz - s_.f_min_hz); }
  /// Whether the frequency lies at a bound of its range (within 2 % of the range).
  bool pinned(double f_hz) const noexcept {
    const double margin = 0.02 * (s_.f_max_hz - s_.f_min_hz);
    return f_hz <= s_.f_min_hz + margin || f_hz >= s_.f_max_hz - margin;
  }
  double mean_nis() const noexcept { return nis_lp_; }

 private:
  static constexpr std::size_t kRing = 16;
  struct Mark {
    double t_s = 0.0, a_m = 0.0, b_m = 0.0, seg_m = 0.0;  ///< seg_m: the distance from the mark before
  };
  static double gain(double dt_s, double tau_s) noexcept { return dt_s >= tau_s ? 1.0 : dt_s / (tau_s + dt_s); }
  /// Whether dt_s is the interval of the gains within 1e-6 (timestamps' rounding: no new divisions).
  bool near_gains_dt(double dt_s) const noexcept { return std::fabs(dt_s - gains_dt_s_) <= 1e-6 * dt_s; }
  static std::uint8_t bit(InvalidReason r) noexcept { return static_cast<std::uint8_t>(r); }
  const Mark& oldest() const noexcept { return ring_n_ < kRing ? ring_[0] : ring_[ring_next_]; }

  Settings s_;
  double dt_lp_s_ = -1.0, noise2_lp_m2_ = 0.0, speed2_lp_ = 0.0, nis_lp_ = 2.0, centre_steps_mps_ = 0.0;
  double gains_dt_s_ = -1.0, g_rate_ = 1.0, g_set_ = 1.0, g_speed_ = 1.0, g_loss_ = 1.0;  ///< gains at that dt
  double heading_loss_lp_ = 0.0;  ///< the low-passed |v_h| - v_x [m/s]
  gait::NetTime below_steps_;     ///< the walking time locked below the steps, net (failed_lock_below_steps)
  gait::NetTime off_feet_;        ///< the walking time locked off the feet's steps, net (failed_lock_off_feet)
  double implausible_until_s_ = -1e300, steady_since_s_ = 0.0;
  bool steady_ = false, have_last_ = false;
  double last_f_hz_ = 0.0, last_speed_mps_ = 0.0, f_rate_lp_ = 0.0, s_rate_lp_ = 0.0;  ///< transient rates
  double phase_rate_lp_ = 0.0;  ///< the low-passed phase correction rate [rad/s]
  double onset_rate_lp_ = 0.0, onset_abs_lp_ = 0.0;  ///< the same and its absolute value over phase_onset_tau_s
  double bias_vx_lp_ = 0.0;     ///< the low-passed v_x innovation [m/s]
  struct SampleGains {
    double g = 1.0, bias = 1.0, inv_dt = 1.0, phase = 1.0, onset = 0.0;
  };
  IntervalCache<SampleGains> sample_gains_;  ///< the sample gains at the last intervals
  std::array<Mark, kRing> ring_{};
  std::size_t ring_n_ = 0, ring_next_ = 0;
  double ring_t_s_ = -1e300, pa_m_ = 0.0, pb_m_ = 0.0;
  double ring_path_m_ = 0.0;  ///< the sum of the kept marks' seg_m [m]
};

}  // namespace yoyogait::online
