/// @file online/online_estimator.hpp
/// @brief OnlineEstimator: motion-capture frames in, gait estimates out, one frame at a time,
/// nothing taken from the future (docs/online.md).
///
/// Per frame, each step a part of its own: the points read (online/frame.hpp), their centre
/// (online/centre.hpp), its velocity (online/differentiator.hpp), the heading and the forward
/// velocity along it (online/heading.hpp); every EstimatorConfig::sample_time_s the mean velocity
/// over that interval (online/decimator.hpp) feeds the gait Estimator, whose estimate is carried to
/// each frame's time by its own forecast over the delays behind it (online/latency.hpp), with the
/// gait phase (online/gait_phase.hpp); whether it is valid, and why not (online/validity.hpp). With
/// foot points after the centre's (a treadmill), the belt's velocity (online/belt.hpp) is taken out
/// of the centre's: the walking velocity is the pelvis's relative to the belt. With two feet, the
/// step frequency their separation shows checks the estimator's lock (online/feet_evidence.hpp).
#pragma once

#include <array>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <limits>
#include <stdexcept>

#include "yoyogait/estimator.hpp"
#include "yoyogait/online/belt.hpp"
#include "yoyogait/online/centre.hpp"
#include "yoyogait/online/decimator.hpp"
#include "yoyogait/online/differentiator.hpp"
#include "yoyogait/online/feet_evidence.hpp"
#include "yoyogait/online/frame.hpp"
#include "yoyogait/online/gait_evidence.hpp"
#include "yoyogait/online/gait_phase.hpp"
#include "yoyogait/online/heading.hpp"
#include "yoyogait/online/input_noise.hpp"
#include "yoyogait/online/latency.hpp"
#include "yoyogait/online/online_config.hpp"
#include "yoyogait/online/online_estimate.hpp"
#include "yoyogait/online/settings.hpp"
#include "yoyogait/online/validity.hpp"
#include "yoyogait/online/velocity_noise.hpp"

namespace yoyogait {

/// The online gait estimator. update() is noexcept and allocates nothing; the constructor throws
/// std::invalid_argument for an unusable configuration or arguments.
class OnlineEstimator {
 public:
  /// n_points: 1..16 points per frame; up_axis: 0, 1, 2 (x, y, z); length_unit_m: metres per
  /// coordinate unit (1 for metres, 0.001 for millimetres); n_feet: 0..4 foot points (heels, for a
  /// treadmill's belt: online/belt.hpp) that follow the n_points in each frame.
  OnlineEstimator(std::size_t n_points, int up_axis, double length_unit_m = 1.0,
                  const OnlineConfig& config = OnlineConfig{}, std::size_t n_feet = 0)
      : config_(checked(config, n_points, up_axis, length_unit_m, n_feet)),
        frame_(n_points, length_unit_m, config_.max_abs_position_m),
        axes_(up_axis),
        estimator_(config_.estimator),
        centre_(n_points, online::centre_settings(config_)),
        diff_(online::differentiator_settings(config_)),
        noise_(online::input_noise_settings(config_)),
        gait_(online::gait_evidence_settings(config_)),
        heading_(online::heading_settings(config_)),
        decimator_(online::decimator_settings(config_)),
        latency_(online::latency_settings(config_)),
        validity_(online::validity_settings(config_)),
        time_gate_(online::timestamp_gate_settings(config_)),
        belt_(n_feet, axes_.up, axes_.a, axes_.b, length_unit_m, config_.max_abs_position_m,
              online::belt_settings(config_)),
        feet_(n_feet),
        feet_evidence_(n_feet, axes_.a, axes_.b, length_unit_m, config_.max_abs_position_m, config_.gait_in_place,
                       online::foot_cadence_settings(config_)),
        q_f_(config_.estimator.gait_filter.q_omega_rad2_per_s3 * kInvTwoPi * kInvTwoPi) {
    reset();
  }

  /// Back to the state before the first frame.
  void reset() noexcept {
    estimator_.reset();
    centre_.reset();
    diff_.stop();
    noise_.reset();
    vnoise_.reset();
    gait_.reset();
    outlier_s_ = 0.0;
    blend_until_s_ = ungated_until_s_ = -1e300;
    estimator_.set_extra_measurement_variance(0.0, 0.0);
    heading_.reset();
    decimator_.restart();
    latency_.reset();
    phase_.reset();
    validity_.reset();
    belt_.reset();
    feet_evidence_.reset();
    belt_a_m_ = belt_b_m_ = 0.0;
    belt_seen_ = false;
    est_ = Estimate{};
    out_ = OnlineEstimate{};
    time_gate_.reset();
    have_seen_ = false;
    fast_s_ = 0.0;
    jump_s_ = 0.0;
    ignored_frames_ = 0;
  }

  /// One frame: t_s [s], positions_xyz: (n_points + n_feet) x 3 coordinates (x, y, z of each point,
  /// in the length unit; the feet last), NaN where a point is missing. Never throws; the state stays finite.
  OnlineEstimate update(double t_s, const double* positions_xyz) noexcept {
    OnlineEstimate& o = out_;
    o.estimator_fed = false;
    const double frame_dt_s = time_gate_.have_time() ? t_s - time_gate_.last_s() : 0.0;
    const OnlineStatus time_status = time_gate_.accept(t_s);
    if (time_status != OnlineStatus::kUsed) {  // ignored: its status set, nothing else changed
      o.status = time_status;
      ++ignored_frames_;
      o.valid = false;
      o.invalid_reason |= static_cast<std::uint8_t>(InvalidReason::kInputMissing);
      return o;
    }
    o.t_s = t_s;
    const online::PointFrame::Count seen = frame_.read(positions_xyz);
    if (belt_.has_feet()) belt_.update(t_s, positions_xyz + 3 * frame_.size());
    o.points_seen = static_cast<std::uint8_t>(seen.seen);
    validity_.frame(frame_dt_s);
    if (seen.seen == 0) return carried(t_s, seen.bad ? OnlineStatus::kNonFinite : OnlineStatus::kAllMissing);
    const double gap_s = have_seen_ ? t_s - t_seen_s_ : 0.0;
    bool restart = !diff_.started() || gap_s > config_.max_gap_s;
    if (!track_centre(t_s, gap_s, restart)) return carried(t_s, OnlineStatus::kAllMissing);
    // The heading and the estimator take a frame only once the differentiator has settled, and
    // never the frame that restarted it (it has no velocity yet).
    const bool settled = !restart && t_s - start_t_s_ >= config_.settle_s;
    velocities(gap_s, settled);
    if (feet_evidence_.two() && heading_.known()) {
      const std::array<double, 3> c = diff_.position_m();
      feet_evidence_.frame(t_s, positions_xyz + 3 * frame_.size(), c, heading_.unit(), noise_.var_m2(), frame_.size(),
                           c[axes_.a] - belt_a_m_, c[axes_.b] - belt_b_m_);
    }
    if (settled && decimator_.push(t_s, o.vx_mps, o.vz_mps, gap_s)) feed(t_s, gap_s);
    o.input_latency_s = latency_.input_latency_s();
    carry_estimate(t_s);
    return o;
  }

  /// The longest horizon predict() accepts [s] (validated up to 1 s: docs/online.md sec. 5).
  static constexpr double kMaxHorizonS = 2.0;
  /// The longest horizon an estimate is carried over by the model [s]: beyond it (an estimate that
  /// old is stale: not valid) the forecast stops there and only its standard deviations grow, so that
  /// every call costs a bounded time.
  static constexpr double kMaxCarryS = 2.0;
  /// Timestamps beyond +-this are absurd (31,700 years) and ignored as non-finite [s].
  static constexpr double kMaxAbsTimeS = online::TimestampGate::kMaxAbsTimeS;

  /// Forward and vertical velocity horizon_s [s] after the last frame's time, from the estimator's
  /// forecast (rates of speed and cadence included) over the same horizon as vx_hat_mps plus
  /// horizon_s; predict(0) is the last estimate's vx_hat_mps, vz_hat_mps. Standard deviations: the
  /// estimator's covariance propagated over that horizon (GaitFilter::forecast), scaled as the
  /// estimate's are; the horizon from the last sample capped at kMaxCarryS + kMaxHorizonS (the speed's
  /// random walk beyond), so that the cost is bounded. valid: the last estimate's. Before the estimator
  /// has been fed: the front-end's velocities held (= vx_hat_mps, vz_hat_mps), stds infinite, valid
  /// false; for a horizon outside [0, kMaxHorizonS]: velocities 0, stds infinite, valid false.
  OnlinePrediction predict(double horizon_s) const noexcept;  // online/carry.hpp

  /// A known treadmill belt speed [m/s] from now on (it may change at any frame); NaN: unknown again
  /// (the feet's estimate, if there are feet). Its direction: the stance feet's, else against
  /// treadmill_heading_rad.
  void set_belt_speed_mps(double speed_mps) noexcept { belt_.set_known_mps(speed_mps); }
  /// The known belt speed, NaN when none is given.
  double belt_speed_mps() const noexcept { return belt_.known_mps(); }
  std::size_t feet() const noexcept { return feet_; }
  /// The step frequency the first two feet show at the last frame (online/feet_evidence.hpp) [Hz]; 0
  /// while not known (fewer than two feet, the first steps, an unsteady rhythm).
  double feet_step_frequency_hz() const noexcept { return feet_evidence_.step_frequency_hz(out_.t_s); }

  const OnlineConfig& config() const noexcept { return config_; }
  /// The estimator's last estimate (at its last sample, estimate_age_s ago).
  const Estimate& estimate() const noexcept { return est_; }
  const Estimator& estimator() const noexcept { return estimator_; }
  std::size_t points() const noexcept { return frame_.size(); }
  int up_axis() const noexcept { return static_cast<int>(axes_.up); }
  double length_unit_m() const noexcept { return frame_.length_unit_m(); }
  /// The last estimate returned by update().
  const OnlineEstimate& last() const noexcept { return out_; }
  /// Frames ignored since the last reset (a timestamp not finite, absurd, not increasing or jumping
  /// ahead unconfirmed).
  std::uint64_t ignored_frames() const noexcept { return ignored_frames_; }

 private:
  static const OnlineConfig& checked(const OnlineConfig& c, std::size_t n, int up, double unit, std::size_t feet) {
    if (const char* e = c.validate()) throw std::invalid_argument(e);
    if (n < 1 || n > online::kMaxPoints) throw std::invalid_argument("n_points must be in [1, 16]");
    if (feet > online::BeltTracker::kMaxFeet) throw std::invalid_argument("n_feet must be in [0, 4]");
    if (up < 0 || up > 2) throw std::invalid_argument("up_axis must be 0, 1 or 2 (x, y, z)");
    if (!(std::isfinite(unit) && unit > 0.0)) throw std::invalid_argument("length_unit_m must be finite and > 0");
    return c;
  }

  /// A frame without a usable centre: the estimate carried to t_s, with the status.
  const OnlineEstimate& carried(double t_s, OnlineStatus status) noexcept {
    out_.status = status;
    carry_estimate(t_s);
    return out_;
  }

  /// The centre of the points seen, and the differentiator's step to it (a restart after a gap
  /// longer than max_gap_s, or at the first frame, or at a jump before the noise is known: restart
  /// is then set). False when no centre could be formed.
  YOYOGAIT_ALWAYS_INLINE bool track_centre(double t_s, double gap_s, bool& restart) noexcept {
    if (restart) centre_.reset();
    const online::CausalCentre::Result c =
        centre_.update(frame_.positions_m(), frame_.visible(), restart ? 0.0 : gap_s);
    if (!c.ok) return false;  // cannot happen with a point seen; kept so that no unset centre is ever used
    validity_.centre_step(c.step_m);
    out_.status = (restart && have_seen_) ? OnlineStatus::kGapRestart : OnlineStatus::kUsed;
    // Until the noise is known (its first noise_tau_s) the gate below is off: it needs the noise.
    // A centre that moved further since the last frame than a walker and the noisiest capture
    // accepted can (a marker's jump, a swap) starts the front-end again instead: differentiated,
    // its ringing would be taken for centimetres of noise for seconds, and the estimator fed with it.
    // Jumps that go on for max_outlier_s are the input's motion (implausible or not): differentiated.
    if (!restart && !noise_.known()) {
      double d2 = 0.0;
      for (int k = 0; k < 3; ++k) d2 += (c.centre_m[k] - last_centre_m_[k]) * (c.centre_m[k] - last_centre_m_[k]);
      const double reach_m = config_.max_plausible_speed_mps * gap_s +
                             std::sqrt(noise_.gate_nis()) * config_.feet_max_input_noise_m;  // 5 sigma at 25
      jump_s_ = d2 > reach_m * reach_m ? jump_s_ + gap_s : 0.0;
      restart = jump_s_ > 0.0 && jump_s_ < config_.max_outlier_s;
    }
    last_centre_m_ = c.centre_m;
    if (restart) {
      start_front_end(t_s, c.centre_m);
    } else {
      // The noise estimated so far is the measurement's; a centre beyond the gate is not
      // differentiated, unless the outliers last longer than max_outlier_s (the input has moved).
      diff_.predict(gap_s);
      const double r2 = noise_.meas_var_m2();
      diff_.set_meas_var(r2);
      // Until the noise is known (its first noise_tau_s) nothing is an outlier.
      const bool known = noise_.known();
      const bool gated = known && outlier_s_ < config_.max_outlier_s && t_s > ungated_until_s_;
      const bool coasted = outlier_s_ > 0.0;  // the prediction ran over outliers: its innovation is not noise
      const bool taken = diff_.update(c.centre_m, gated ? noise_.gate_nis() : 1e300, diff_.kMinOutlierM);
      if (!taken) {
        outlier_s_ += gap_s;
        validity_.outlier(t_s, std::sqrt(3.0 * diff_.innovation2_m2()), gap_s);
      } else {
        // A jump taken after outliers: the filter catches up ungated over centre_blend_tau_s (else its
        // shrunk covariance would gate the next frames again, and it would never reach the input).
        if (outlier_s_ > 0.0 && known && !gated) ungated_until_s_ = t_s + config_.centre_blend_tau_s;
        outlier_s_ = 0.0;
      }
      // Neither an outlier, nor a jump taken and the filter's catching up, nor the centre's blend
      // after a change of the visible markers (a correction the model does not know) is noise.
      if (c.set_changed || (known && !gated) || coasted) blend_until_s_ = t_s + config_.centre_blend_tau_s;
      // (Nor the differentiator's own start: its innovations hold the velocity it starts without.)
      if (taken && t_s - start_t_s_ >= config_.settle_s && (!known || t_s > blend_until_s_)) noise_.update(gap_s, diff_.innovation2_m2(), diff_.predicted_var_m2(), r2);
      if (!diff_.finite()) start_front_end(t_s, c.centre_m);  // cannot happen with in-range data
    }
    have_seen_ = true;
    t_seen_s_ = t_s;
    return true;
  }

  void start_front_end(double t_s, const std::array<double, 3>& centre_m) noexcept {
    diff_.set_meas_var(noise_.meas_var_m2());
    diff_.start(centre_m);
    outlier_s_ = 0.0;
    start_t_s_ = t_s;
    decimator_.restart();
    validity_.restart_travel();
  }

  /// The differentiator's velocity on the axes; the heading (updated once settled) and the
  /// forward velocity along it.
  void velocities(double gap_s, bool settled) noexcept {
    OnlineEstimate& o = out_;
    const std::array<double, 3> v = diff_.velocity_mps();
    double va = v[axes_.a], vb = v[axes_.b];
    std::array<double, 3> pos = diff_.position_m();
    if (belt_.has_feet()) belt_.pelvis(va, vb, gap_s);
    const bool belt_on = belt_.active();
    if (belt_on && !belt_seen_) {
      // The first belt found: what the estimator took so far was the sway, not the walking; it starts
      // again (once: a belt that comes and goes near treadmill_min_belt_mps restarts nothing more).
      belt_seen_ = true;
      estimator_.reset();
      latency_.reset();
      decimator_.restart();
      est_ = Estimate{};
    }
    if (belt_on) {  // on a treadmill: the pelvis relative to the belt, and its travel on it
      const double ba = belt_.va_mps(), bb = belt_.vb_mps();
      va -= ba;
      vb -= bb;
      belt_a_m_ += ba * gap_s;
      belt_b_m_ += bb * gap_s;
    }
    const double va0 = va, vb0 = vb;  // before any cut
    // A horizontal velocity beyond max_walking_speed_mps that has lasted less than a step (at the
    // estimated step frequency while walking, else at f_min_hz: the longest step) is a jump, a swap,
    // noise or the differentiator's start, not the person: cut to that speed.
    const double lim = config_.max_walking_speed_mps, vh2 = va * va + vb * vb;
    if (vh2 > lim * lim) {
      fast_s_ += gap_s;
      const double f_hz = est_.walking && est_.step_frequency_hz > 0.0 ? est_.step_frequency_hz
                                                                        : config_.estimator.gait_filter.f_min_hz;
      if (fast_s_ * f_hz < 1.0) {
        const double k = lim / sqrt1(vh2);
        va *= k;
        vb *= k;
      }
    } else {
      fast_s_ = 0.0;
    }
    o.vh_a_mps = va;
    o.vh_b_mps = vb;
    o.vz_mps = v[axes_.up];
    gait_.update(o.t_s, gap_s, pos[axes_.up], noise_.var_m2());
    validity_.front_end(o.t_s, gap_s, noise_.var_m2(), pos[axes_.a] - belt_a_m_, pos[axes_.b] - belt_b_m_, va0, vb0,
                        o.vz_mps);  // the velocity before any cut
    if (settled) heading_.update(va, vb, gap_s);
    o.heading_rad = heading_.heading_rad();
    // Above noise_knee_m the velocity noise biases the norm before the first heading: taken out.
    o.vx_mps = heading_.forward_mps(va, vb, noise_.above_knee() ? noise_.excess_share() * diff_.covariance()[1][1] : 0.0);
    validity_.heading(gap_s, va, vb, o.vx_mps);
  }

  /// The interval just completed feeds the estimator (its time step: since its last sample).
  void feed(double t_s, double gap_s) noexcept {
    const online::Decimator::Mean& m = decimator_.mean();
    // Velocities no person reaches are not fed (the estimator predicts only): they would drive its
    // amplitudes without bound.
    const double lim = config_.max_plausible_speed_mps;
    const bool plausible = std::fabs(m.vx_mps) <= lim && std::fabs(m.vz_mps) <= lim;
    const double nan = std::numeric_limits<double>::quiet_NaN();
    const double dt_s = latency_.sample_dt_s(t_s, config_.estimator.sample_time_s);
    const GaitState prior = est_.gait_state;
    // What the input noise adds to the estimator's measurement noise (online/velocity_noise.hpp; its
    // per-channel measure, used above the knee, runs once the noise is above the floor).
    const bool above_floor = noise_.excess_share() > 0.0;
    if (plausible && above_floor) vnoise_.update(m.vx_mps, m.vz_mps, dt_s);
    const std::array<double, 2> e =
        online::extra_measurement_var(noise_, diff_.covariance()[1][1], vnoise_, config_.estimator.gait_filter, dt_s);
    // The floor's part is only kept out of the detector's RMS(v_z) (what one frame per sample leaves).
    // The detector's thresholds rise with any noise above the floor: below the knee too, where a
    // person standing with 8 mm per marker (4 mm on the centre) otherwise started the estimator.
    const double floor_vz = floor_noise_.var_m2_per_s2(diff_, dt_s / (m.frames > 0 ? m.frames : 1), m.frames);
    // Feet that step at a steady rhythm tell walking from noise: the thresholds need not rise then.
    const double feet_hz = feet_evidence_.step_frequency_hz(t_s);
    const double sigmas = above_floor && !(feet_hz > 0.0) ? config_.walk_noise_sigmas : 0.0;
    estimator_.set_extra_measurement_variance(e[0], e[1], sigmas, floor_vz);
    estimator_.step_into(est_, plausible ? m.vx_mps : nan, plausible ? m.vz_mps : nan, dt_s);
    // A lock below the steps the centre shows, held: a failed lock (online/validity.hpp).
    const bool below = est_.walking && !est_.acquiring && gait_.gait(t_s) &&
                       online::Validity::below_steps(est_.step_frequency_hz, gait_.step_frequency_hz(t_s), feet_hz);
    if (validity_.failed_lock_below_steps(below, dt_s)) estimator_.reacquire();
    // The feet's steps: a lock far off them, held, relocked at theirs (online/feet_evidence.hpp; the
    // estimate shows it from the next sample), or a new figure of theirs observed.
    if (feet_evidence_.two()) {
      using online::Validity;
      const bool off =
          est_.walking && !est_.acquiring && Validity::off_feet(est_.step_frequency_hz, feet_hz, Validity::kRelockHz);
      const auto act = feet_evidence_.after_sample(validity_.failed_lock_off_feet(off, dt_s), est_.walking,
                                                   est_.acquiring, est_.step_frequency_hz, feet_hz, noise_.above_knee());
      if (act == online::FeetEvidence::Action::kRelock) estimator_.relock(feet_hz);
      if (act == online::FeetEvidence::Action::kObserve)
        estimator_.observe_frequency(feet_hz, online::FeetEvidence::kObservedVarHz2);
    }
    const double correction =
        online::phase_correction_rad(prior, est_.gait_state, est_.walking, est_.acquiring, dt_s);
    const Innovation innov = estimator_.innovation();
    validity_.sample(dt_s, innov.nis, est_.step_frequency_hz, est_.speed_mps, correction, innov.innovation_vx_mps);
    // The variances reported until the next sample: scaled while the innovations are larger than
    // the model expects (sqrt of the mean NIS over 2, at least 1), plus what a transient adds.
    const double k = validity_.std_inflation();
    // A change of speed comes with one of cadence (at a constant step length, f / speed per m/s):
    // the speed's transient counts for f too.
    const double sp = est_.speed_mps > 0.3 ? est_.speed_mps : 0.3, fs = est_.step_frequency_hz / sp;
    const double tv_s = validity_.transient_var_speed();
    f_var_ = k * k * est_.step_frequency_std_hz * est_.step_frequency_std_hz + validity_.transient_var_f() + fs * fs * tv_s;
    s_var_ = k * k * est_.speed_std_mps * est_.speed_std_mps + tv_s;
    f_std_ = sqrt1(f_var_);
    s_std_ = sqrt1(s_var_);
    out_.estimator_fed = true;
    latency_.sampled(t_s, gap_s, m.age_s, decimator_.antialias_delay_s(config_.latency_f_hz), diff_);
  }

  /// The estimator's last estimate carried to t_s: its forecast over the time since its sample plus
  /// the delays behind that sample (online/latency.hpp), and the gait phase at t_s.
  void carry_estimate(double t_s) noexcept;  // online/carry.hpp

  /// A long step [m]: walking without travelling, 2 speed stds reach kLongStepM x the step frequency.
  static constexpr double kLongStepM = 0.8;

  /// An estimate older than this is stale [s] (Validity's stale_s).
  double validity_stale_s() const noexcept { return config_.max_gap_s + 2.0 * config_.estimator.sample_time_s; }

  /// The variance the speed's random walk adds over age_s [(m/s)^2] (0 for age_s <= 0).
  double grown_var_speed(double age_s) const noexcept {
    return config_.estimator.gait_filter.q_speed_m2_per_s3 * (age_s > 0.0 ? age_s : 0.0);
  }

  /// A velocity within +-max_plausible_speed_mps (NaN: 0).
  double bounded(double v_mps) const noexcept {
    return detail::clamp_or_zero(v_mps, config_.max_plausible_speed_mps);
  }

  OnlineConfig config_;
  online::PointFrame frame_;
  online::Axes axes_;
  Estimator estimator_;
  online::CausalCentre centre_;
  online::KalmanDifferentiator diff_;
  online::InputNoise noise_;
  online::VelocityNoise vnoise_;
  online::GaitEvidence gait_;
  online::HeadingTracker heading_;
  online::Decimator decimator_;
  online::Latency latency_;
  online::GaitPhase phase_;
  online::Validity validity_;
  online::TimestampGate time_gate_;
  online::BeltTracker belt_;
  std::size_t feet_ = 0;
  online::FeetEvidence feet_evidence_;  ///< what the first two feet tell about the lock
  double belt_a_m_ = 0.0, belt_b_m_ = 0.0;  ///< the belt's travel since the reset (a treadmill) [m]
  bool belt_seen_ = false;                   ///< a belt was taken since the reset
  Estimate est_{};
  gait::HorizonDecay carry_decay_;  ///< the carry's forecast factors at its last horizons
  OnlineEstimate out_{};
  bool have_seen_ = false;
  double t_seen_s_ = 0.0;   ///< the last frame with a point seen [s]
  std::array<double, 3> last_centre_m_{};  ///< the centre of that frame [m]
  double jump_s_ = 0.0;                     ///< how long the centre has been jumping before the noise is known [s]
  double start_t_s_ = 0.0;  ///< the differentiator's last (re)start [s]
  double f_var_ = 0.0, s_var_ = 0.0;  ///< the variances of f and speed reported at the last sample
  double f_std_ = 0.0, s_std_ = 0.0;  ///< their square roots
  double q_f_ = 0.0;  ///< the random walk of f [Hz^2/s]
  double outlier_s_ = 0.0;  ///< how long the centre has been an outlier [s]
  double blend_until_s_ = -1e300;  ///< the centre blends a change of the visible markers until then [s]
  double ungated_until_s_ = -1e300;  ///< after a jump taken, the outlier gate is off until then [s]
  double fast_s_ = 0.0;     ///< how long the horizontal velocity has exceeded max_walking_speed_mps [s]
  std::uint64_t ignored_frames_ = 0;
  online::FloorVelocityNoise floor_noise_;  ///< the v_z variance of the noise floor on a sample
};

}  // namespace yoyogait

// The estimate carried to a frame's time and ahead (predict, carry_estimate): online/carry.hpp.
#include "yoyogait/online/carry.hpp"
