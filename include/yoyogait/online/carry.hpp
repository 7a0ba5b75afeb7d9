/// @file online/carry.hpp
/// @brief OnlineEstimator's estimate carried from the estimator's last sample to a frame's time
/// (carry_estimate: the forecast over the delays behind the sample, the stds grown over its age and
/// raised where the estimate is no estimate, the gait phase, the validity) and ahead of it (predict).
/// Included by online/online_estimator.hpp.
#pragma once

#include <cmath>
#include <cstdint>
#include <limits>

#include "yoyogait/online/online_estimator.hpp"

namespace yoyogait {

inline OnlinePrediction OnlineEstimator::predict(double horizon_s) const noexcept {
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
  // The stds' inflation where the innovations exceed their covariance widens the phase's spread
  // too: the oscillation ahead tends to its mean sooner where the model holds less than P says.
  const double k = validity_.std_inflation();
  const Forecast f = estimator_.forecast(h_s < kMaxCarryS + kMaxHorizonS ? h_s : kMaxCarryS + kMaxHorizonS, true,
                                         nullptr, validity_.var_inflation());
  p.vx_mps = bounded(f.vx_mps);
  p.vz_mps = bounded(f.vz_mps);
  p.vx_std_mps = std::sqrt(k * k * f.vx_std_mps * f.vx_std_mps + grown_var_speed(h_s - kMaxCarryS - kMaxHorizonS));
  p.vz_std_mps = k * f.vz_std_mps;
  p.valid = out_.valid;
  return p;
}

inline void OnlineEstimator::carry_estimate(double t_s) noexcept {
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
  const double feet_hz = feet_evidence_.step_frequency_hz(t_s);
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
  const double pinned_std_hz = validity_.pinned_std_hz();
  if (e.walking && validity_.pinned(e.step_frequency_hz) && o.step_frequency_std_hz < pinned_std_hz)
    o.step_frequency_std_hz = pinned_std_hz;
  // Below the steps the centre shows: 2 std reach them.
  if (o.walking && online::Validity::below_steps(e.step_frequency_hz, steps_hz, feet_hz)) {
    const double gap_std_hz = 0.5 * (steps_hz - e.step_frequency_hz);
    if (o.step_frequency_std_hz < gap_std_hz) o.step_frequency_std_hz = gap_std_hz;
  }
  // With the feet's steps: 2 std reach them, and no further than their own error beyond them.
  if (o.walking && feet_hz > 0.0)
    o.step_frequency_std_hz = feet_evidence_.bounded_std_hz(o.step_frequency_std_hz, e.step_frequency_hz, feet_hz);
  // Steps longer than a walker's: 2 std reach twice the frequency (a lock on one per stride).
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
  // As predict() carries it (the phase's spread widened by the stds' inflation): predict(0) is this.
  const Forecast f =
      estimator_.forecast(h_s < kMaxCarryS ? h_s : kMaxCarryS, false, &carry_decay_, validity_.var_inflation());
  o.vx_hat_mps = bounded(f.vx_mps);
  o.vz_hat_mps = bounded(f.vz_mps);
  phase_.update(o.walking, e.gait_state[gait::kZ1], e.gait_state[gait::kZ2], f.phase_advance_rad, f.omega_rad_s,
                f.omega_rate_rad_s2, e.step_frequency_hz);
  o.next_step_in_s = phase_.next_step_in_s();
  o.gait_phase = phase_.phase();
  // Walking with no phase (the vertical phasor decayed to 0: the model holds no oscillation, e.g.
  // with the measurement noise set far above the motion): the phase and the next step are part of
  // the estimate.
  if (o.valid && std::isnan(o.next_step_in_s)) {
    o.valid = false;
    o.invalid_reason |= static_cast<std::uint8_t>(InvalidReason::kModelNotHolding);
  }
}

}  // namespace yoyogait
