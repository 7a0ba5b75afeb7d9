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
/// step frequency their separation shows (online/foot_cadence.hpp) checks the estimator's lock.
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
#include "yoyogait/online/foot_cadence.hpp"
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
        foot_cadence_(online::foot_cadence_settings(config_)),
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
    foot_cadence_.reset();
    feet_figures_ = 0;
    belt_a_m_ = belt_b_m_ = 0.0;
    belt_seen_ = false;
    est_ = Estimate{};
    out_ = OnlineEstimate{};
    time_gate_.reset();
    have_seen_ = false;
    fast_s_ = 0.0;
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
    const bool restart = !diff_.started() || gap_s > config_.max_gap_s;
    if (!track_centre(t_s, gap_s, restart)) return carried(t_s, OnlineStatus::kAllMissing);
    // The heading and the estimator take a frame only once the differentiator has settled, and
    // never the frame that restarted it (it has no velocity yet).
    const bool settled = !restart && t_s - start_t_s_ >= config_.settle_s;
    velocities(gap_s, settled);
    if (feet_ >= 2 && heading_.known()) feet_separation(t_s, positions_xyz + 3 * frame_.size());
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
  OnlinePrediction predict(double horizon_s) const noexcept {
    OnlinePrediction p;
    p.horizon_s = horizon_s;
    p.t_s = out_.t_s + horizon_s;
    if (!(horizon_s >= 0.0 && horizon_s <= kMaxHorizonS)) {
      p.vx_mps = p.vz_mps = 0.0;
      return p;
    }
    if (!latency_.fed()) {
      p.vx_mps = out_.vx_hat_mps;
      p.vz_mps = out_.vz_hat_mps;
      return p;
    }
    const double h_s = latency_.horizon_s() + horizon_s;
    const Forecast f = estimator_.forecast(h_s < kMaxCarryS + kMaxHorizonS ? h_s : kMaxCarryS + kMaxHorizonS, true);
    const double k = validity_.std_inflation();
    p.vx_mps = bounded(f.vx_mps);
    p.vz_mps = bounded(f.vz_mps);
    p.vx_std_mps = std::sqrt(k * k * f.vx_std_mps * f.vx_std_mps + grown_var_speed(h_s - kMaxCarryS - kMaxHorizonS));
    p.vz_std_mps = k * f.vz_std_mps;
    p.valid = out_.valid;
    return p;
  }

  /// A known treadmill belt speed [m/s] from now on (it may change at any frame); NaN: unknown again
  /// (the feet's estimate, if there are feet). Its direction: the stance feet's, else against
  /// treadmill_heading_rad.
  void set_belt_speed_mps(double speed_mps) noexcept { belt_.set_known_mps(speed_mps); }
  /// The known belt speed, NaN when none is given.
  double belt_speed_mps() const noexcept { return belt_.known_mps(); }
  std::size_t feet() const noexcept { return feet_; }
  /// The step frequency the first two feet show at the last frame (online/foot_cadence.hpp) [Hz]; 0
  /// while not known (fewer than two feet, the first steps, an unsteady rhythm).
  double feet_step_frequency_hz() const noexcept { return feet_step_frequency_hz(out_.t_s); }

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
  /// longer than max_gap_s, or at the first frame). False when no centre could be formed.
  YOYOGAIT_ALWAYS_INLINE bool track_centre(double t_s, double gap_s, bool restart) noexcept {
    if (restart) centre_.reset();
    const online::CausalCentre::Result c =
        centre_.update(frame_.positions_m(), frame_.visible(), restart ? 0.0 : gap_s);
    if (!c.ok) return false;  // cannot happen with a point seen; kept so that no unset centre is ever used
    validity_.centre_step(c.step_m);
    out_.status = (restart && have_seen_) ? OnlineStatus::kGapRestart : OnlineStatus::kUsed;
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
    const double feet_hz = feet_step_frequency_hz(t_s);
    const double sigmas = above_floor && !(feet_hz > 0.0) ? config_.walk_noise_sigmas : 0.0;
    estimator_.set_extra_measurement_variance(e[0], e[1], sigmas, floor_vz);
    estimator_.step_into(est_, plausible ? m.vx_mps : nan, plausible ? m.vz_mps : nan, dt_s);
    // A lock below the steps the centre shows, held: a failed lock (online/validity.hpp).
    const bool below = est_.walking && !est_.acquiring &&
                       validity_.below_steps(est_.step_frequency_hz, gait_.step_frequency_hz(t_s)) && gait_.gait(t_s);
    if (validity_.failed_lock_below_steps(below, dt_s)) estimator_.reacquire();
    // A lock far off the feet's steps, held, is relocked at theirs (online/validity.hpp); with noise
    // above the knee, where the start-up bank locks on the noise, the EKF starts at their cadence.
    if (feet_ >= 2) {
      const bool off_feet = est_.walking && !est_.acquiring && online::Validity::far_off_feet(est_.step_frequency_hz, feet_hz);
      const bool bank_on_noise = est_.walking && est_.acquiring && feet_hz > 0.0 && noise_.above_knee();
      if (validity_.failed_lock_off_feet(off_feet, dt_s) || bank_on_noise) {
        estimator_.relock(feet_hz);  // (the estimate shows it from the next sample)
      } else if (foot_cadence_.figures() != feet_figures_ && noise_.above_knee() && est_.walking && !est_.acquiring &&
                 !online::Validity::off_feet(est_.step_frequency_hz, feet_hz)) {
        // Above the knee, each new figure of the feet's is an observation of the frequency; the
        // figures overlap in kSteps - 1 of their kSteps intervals, so each counts that many times less.
        estimator_.observe_frequency(feet_hz, kFeetFigureVarHz2 * static_cast<double>(online::FootCadence::kSteps));
      }
      feet_figures_ = foot_cadence_.figures();
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
  void carry_estimate(double t_s) noexcept {
    OnlineEstimate& o = out_;
    const Estimate& e = est_;
    const bool fed = latency_.fed();
    const double h_s = latency_.carry_to(t_s);
    o.estimate_age_s = fed ? latency_.sample_age_s(t_s) : 0.0;
    const bool stale = o.estimate_age_s > validity_stale_s();
    o.step_frequency_hz = e.step_frequency_hz;
    o.speed_mps = bounded(e.speed_mps);
    // The estimator's detector, where the centre rises and falls as in gait (online/gait_evidence.hpp).
    const bool detected = fed && e.walking && !stale;
    // A hand's bobs in place are gestures (gait_in_place false): it must travel as a walker does.
    // (Feet that step at a steady rhythm are gait too: centimetres of noise hide the centre's bobs.)
    const double feet_hz = feet_step_frequency_hz(t_s);
    o.walking = detected && (gait_.gait(t_s) || feet_hz > 0.0) &&
                (config_.gait_in_place || validity_.away(online::Validity::kWalkerTravelM));
    o.estimator_status = e.status;
    o.walk_a_mps = o.speed_mps * heading_.unit()[0];
    o.walk_b_mps = o.speed_mps * heading_.unit()[1];
    o.input_noise_m = validity_.input_noise_m();
    o.belt_speed_mps = belt_.speed_mps();
    o.belt_speed_std_mps = belt_.std_mps();
    online::Validity::Inputs in;
    in.fed = fed;
    in.walking = detected;
    in.gait = o.walking;
    in.acquiring = e.acquiring;
    in.estimate_age_s = o.estimate_age_s;
    in.speed_mps = e.speed_mps;
    in.step_frequency_hz = e.step_frequency_hz;
    const double steps_hz = gait_.step_frequency_hz(t_s);
    in.steps_hz = steps_hz;
    in.feet_hz = feet_hz;
    o.invalid_reason = validity_.reasons(t_s, in);
    o.valid = o.invalid_reason == 0;
    if (!fed) {
      // No estimate yet (the front-end settles, the first interval fills): the measured velocity
      // is the best there is; zero would tell a controller that the walker stands. Nothing is known
      // of the estimator's outputs: infinite stds, as predict() gives.
      o.step_frequency_std_hz = o.speed_std_mps = std::numeric_limits<double>::infinity();
      o.vx_hat_mps = bounded(o.vx_mps);
      o.vz_hat_mps = bounded(o.vz_mps);
      phase_.hold();
      o.next_step_in_s = phase_.next_step_in_s();
      return;
    }
    // The stds (scaled at the sample: feed()), grown by the model's random walks over the
    // estimate's age, and never confident at a bound of the range.
    // (Within two sample times of the sample the growth is below 1e-4 Hz and 3e-4 m/s: not computed.)
    const double age = o.estimate_age_s;
    const bool grown = age > 2.0 * config_.estimator.sample_time_s;
    o.step_frequency_std_hz = grown ? sqrt1(f_var_ + q_f_ * age) : f_std_;
    constexpr double pinned_std_hz = online::Validity::kPinnedStdHz;
    if (e.walking && validity_.pinned(e.step_frequency_hz) && o.step_frequency_std_hz < pinned_std_hz)
      o.step_frequency_std_hz = pinned_std_hz;
    // Below the steps the centre shows: 2 std reach them. Steps longer than a walker's: 2 std reach
    // twice the frequency (a lock on one per stride).
    if (o.walking && validity_.below_steps(e.step_frequency_hz, steps_hz)) {
      const double gap_std_hz = 0.5 * (steps_hz - e.step_frequency_hz);
      if (o.step_frequency_std_hz < gap_std_hz) o.step_frequency_std_hz = gap_std_hz;
    }
    // With the feet's steps: 2 std reach them, and, while the estimate agrees with a settled figure
    // of theirs (four steps, the newest steady), reach no further than kFeetToleranceHz and the
    // spread of those steps beyond them (the feet's own error within the one, their lag behind a
    // change of cadence within the other).
    if (o.walking && feet_hz > 0.0) {
      const double gap_hz = std::fabs(feet_hz - e.step_frequency_hz);
      const double most_std_hz = 0.5 * (gap_hz + online::Validity::kFeetToleranceHz + foot_cadence_.spread_hz());
      if (foot_cadence_.settled() && !online::Validity::off_feet(e.step_frequency_hz, feet_hz) &&
          o.step_frequency_std_hz > most_std_hz)
        o.step_frequency_std_hz = most_std_hz;
      if (o.step_frequency_std_hz < 0.5 * gap_hz) o.step_frequency_std_hz = 0.5 * gap_hz;
    }
    if (o.walking && online::Validity::too_long_steps(e.step_frequency_hz, e.speed_mps) &&
        o.step_frequency_std_hz < 0.5 * e.step_frequency_hz)
      o.step_frequency_std_hz = 0.5 * e.step_frequency_hz;
    o.speed_std_mps = grown ? sqrt1(s_var_ + grown_var_speed(age)) : s_std_;
    // Walking without travelling (a treadmill without feet or belt speed, stepping in place): the
    // speed is unknown, anywhere from 0 to a walker's at this cadence; its std says so.
    if (o.invalid_reason & static_cast<std::uint8_t>(InvalidReason::kNotMoving)) {
      const double unknown = 0.5 * kLongStepM * e.step_frequency_hz;
      if (o.speed_std_mps < unknown) o.speed_std_mps = unknown;
    }
    if (o.belt_speed_std_mps > 0.0)  // the belt's uncertainty is the walking speed's too
      o.speed_std_mps = sqrt1(o.speed_std_mps * o.speed_std_mps + o.belt_speed_std_mps * o.belt_speed_std_mps);
    const Forecast f = estimator_.forecast(h_s < kMaxCarryS ? h_s : kMaxCarryS, false, &carry_decay_);
    o.vx_hat_mps = bounded(f.vx_mps);
    o.vz_hat_mps = bounded(f.vz_mps);
    phase_.update(o.walking, e.gait_state[gait::kZ1], e.gait_state[gait::kZ2], f.phase_advance_rad, f.omega_rad_s,
                  f.omega_rate_rad_s2, e.step_frequency_hz);
    o.next_step_in_s = phase_.next_step_in_s();
    o.gait_phase = phase_.phase();
  }

  /// The separation of the first two feet along the heading, |(p_0 - p_1) . u| (no side needed: a
  /// label swap leaves it), for the feet's cadence; its noise from the centre's (n points averaged).
  /// Feet whose midpoint is further from the point followed than a walker's are (horizontally; kMaxFeetFromTrunkM,
  /// kMaxFeetFromHandM) are not its feet (another person's, a tracking swap): not taken.
  void feet_separation(double t_s, const double* feet_xyz) noexcept {
    const double unit = frame_.length_unit_m(), lim = config_.max_abs_position_m;
    const double da = (feet_xyz[axes_.a] - feet_xyz[3 + axes_.a]) * unit;
    const double db = (feet_xyz[axes_.b] - feet_xyz[3 + axes_.b]) * unit;
    const bool seen = std::fabs(feet_xyz[axes_.a] * unit) <= lim && std::fabs(feet_xyz[axes_.b] * unit) <= lim &&
                      std::fabs(feet_xyz[3 + axes_.a] * unit) <= lim && std::fabs(feet_xyz[3 + axes_.b] * unit) <= lim;
    if (!seen) return;  // NaN (missing) fails the comparisons too
    const std::array<double, 3> c = diff_.position_m();
    const double ma = 0.5 * (feet_xyz[axes_.a] + feet_xyz[3 + axes_.a]) * unit - c[axes_.a];
    const double mb = 0.5 * (feet_xyz[axes_.b] + feet_xyz[3 + axes_.b]) * unit - c[axes_.b];
    const double reach = config_.gait_in_place ? kMaxFeetFromTrunkM : kMaxFeetFromHandM;
    if (!(ma * ma + mb * mb <= reach * reach)) return;
    const std::array<double, 2>& u = heading_.unit();
    const double var_m2 = 2.0 * static_cast<double>(frame_.size()) * noise_.var_m2();
    foot_cadence_.update(t_s, std::fabs(da * u[0] + db * u[1]), var_m2);
  }

  /// The feet's step frequency at t_s (0 without two feet: nothing to ask).
  double feet_step_frequency_hz(double t_s) const noexcept {
    return feet_ >= 2 ? foot_cadence_.step_frequency_hz(t_s) : 0.0;
  }

  /// The farthest a walker's feet's midpoint is from the point followed, horizontally [m]: a trunk point
  /// (the pelvis: at most 0.60 m on the shared recordings, 0.52 m walking), a hand (its arm's reach more).
  static constexpr double kMaxFeetFromTrunkM = 0.75, kMaxFeetFromHandM = 1.5;

  /// The variance of one feet's figure [Hz^2]: its error after 3 s of walking on the markerless
  /// re-renderings, 0.053 Hz median and 0.121 Hz 95th percentile (docs/online.md, "Feet"), as a normal
  /// spread of 0.07 Hz.
  static constexpr double kFeetFigureVarHz2 = 0.07 * 0.07;

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
  online::FootCadence foot_cadence_;  ///< the step frequency the first two feet show
  unsigned long feet_figures_ = 0;    ///< its figures taken so far
  double belt_a_m_ = 0.0, belt_b_m_ = 0.0;  ///< the belt's travel since the reset (a treadmill) [m]
  bool belt_seen_ = false;                   ///< a belt was taken since the reset
  Estimate est_{};
  gait::HorizonDecay carry_decay_;  ///< the carry's forecast factors at its last horizons
  OnlineEstimate out_{};
  bool have_seen_ = false;
  double t_seen_s_ = 0.0;   ///< the last frame with a point seen [s]
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
