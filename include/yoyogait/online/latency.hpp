/// @file online/latency.hpp
/// @brief How far the estimator's last sample lies behind the frame time: the bookkeeping by which
/// OnlineEstimator carries each estimate to its frame (docs/online.md sec. 1, "Feeding the
/// estimator").
///
/// A sample fed at t_tick describes the velocity some time before t_tick: the age of its interval
/// mean (online/decimator.hpp), the anti-aliasing low-pass's delay and the differentiator's delay
/// (input_latency_s), each at latency_f_hz. At a frame t_s the estimate is the estimator's forecast
/// over the horizon (t_s - t_tick) + mean age + anti-aliasing delay + input latency.
#pragma once

#include <cmath>

#include "yoyogait/online/differentiator.hpp"

namespace yoyogait::online {

/// The estimator's sample times and the delays behind them. Everything per frame is noexcept.
class Latency {
 public:
  struct Settings {
    double f_hz = 2.0;  ///< the frequency the delays are evaluated at (a typical step frequency) [Hz]
  };

  Latency() noexcept = default;
  explicit Latency(const Settings& s) noexcept : s_(s) { reset(); }

  /// No sample yet; no delay known.
  void reset() noexcept {
    fed_ = false;
    t_sample_s_ = 0.0;
    mean_age_s_ = 0.0;
    antialias_s_ = 0.0;
    input_s_ = 0.0;
    input_dt_s_ = -1.0;
    input_t_s_ = 0.0;
    horizon_s_ = 0.0;
  }

  /// The time step of a sample fed at t_s: since the last sample, or nominal_dt_s for the first.
  double sample_dt_s(double t_s, double nominal_dt_s) const noexcept { return fed_ ? t_s - t_sample_s_ : nominal_dt_s; }

  /// A sample was fed at t_s, the frame dt_s after the previous one: mean_age_s of its interval
  /// mean, antialias_delay_s of the low-pass. The differentiator's delay changes only with the frame
  /// interval and its (converging) gain: evaluated when the interval changes, else once a second.
  void sampled(double t_s, double dt_s, double mean_age_s, double antialias_delay_s,
               const KalmanDifferentiator& diff) noexcept {
    fed_ = true;
    t_sample_s_ = t_s;
    mean_age_s_ = mean_age_s;
    if (std::fabs(dt_s - input_dt_s_) > 1e-6 * dt_s || t_s - input_t_s_ >= 1.0) {
      input_s_ = diff.delay_s(s_.f_hz, dt_s);
      input_dt_s_ = dt_s;
      input_t_s_ = t_s;
    }
    antialias_s_ = antialias_delay_s;
  }

  /// The horizon from the last sample's state to t_s [s] (0 before the first sample); kept as
  /// horizon_s().
  double carry_to(double t_s) noexcept {
    horizon_s_ = fed_ ? (t_s - t_sample_s_) + mean_age_s_ + antialias_s_ + input_s_ : 0.0;
    return horizon_s_;
  }

  /// Whether the estimator has been fed since the last reset.
  bool fed() const noexcept { return fed_; }
  /// Time from the last sample to t_s [s].
  double sample_age_s(double t_s) const noexcept { return t_s - t_sample_s_; }
  /// The differentiator's delay behind the true velocity at f_hz [s] (0 before the first sample).
  double input_latency_s() const noexcept { return input_s_; }
  /// The horizon of the last carry_to [s].
  double horizon_s() const noexcept { return horizon_s_; }

 private:
  Settings s_;
  bool fed_ = false;
  double t_sample_s_ = 0.0;   ///< time of the last sample [s]
  double mean_age_s_ = 0.0;   ///< its interval mean's age [s]
  double antialias_s_ = 0.0;  ///< the anti-aliasing delay at that sample [s]
  double input_s_ = 0.0, input_dt_s_ = -1.0, input_t_s_ = 0.0;  ///< the differentiator's delay, when evaluated
  double horizon_s_ = 0.0;    ///< the last carry_to [s]
};

}  // namespace yoyogait::online
