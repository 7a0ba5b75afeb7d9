/// @file imu/leaky_integrator.hpp
/// @brief The drift-free integral of an acceleration: a first-order high-pass followed by a leaky
/// integrator (docs/imu.md), and its bridge over samples lost.
#pragma once

#include <cmath>

#include "yoyogait/math.hpp"

namespace yoyogait::imu {

/// High-pass (first order) followed by a leaky integrator, both with time constant tau: the
/// drift-free integral of an acceleration. Against the true integral it leads by
/// 2 atan(1 / (w tau)) at w and scales by (w tau)^2 / (1 + (w tau)^2).
class LeakyIntegrator {
 public:
  LeakyIntegrator() noexcept = default;
  explicit LeakyIntegrator(double tau_s) noexcept : tau_(tau_s) {}

  /// Starts with the integral 0. from_x: the input so far was x (no step at the start: the first
  /// start, at rest with a constant offset); else it was 0 (a restart in the middle of a movement,
  /// where x is one point of an oscillation: taking it as the past level would add a decaying
  /// offset of x tau to the integral).
  void start(double x, bool from_x = true) noexcept {
    x_prev_ = from_x ? x : 0.0;
    hp_ = 0.0;
    v_ = 0.0;
  }

  double step(double x, double dt_s) noexcept {
    // A recording's time stamps jitter in their last bits: the decay is recomputed only for
    // another interval, not per sample (an exp each time).
    if (!(std::fabs(dt_s - dt_s_) <= 1e-9 * dt_s_)) {
      dt_s_ = dt_s;
      decay_ = std::exp(-dt_s / tau_);
    }
    hp_ = decay_ * (hp_ + x - x_prev_);
    x_prev_ = x;
    v_ = decay_ * v_ + hp_ * dt_s;
    return v_;
  }

  double value() const noexcept { return v_; }

  /// A step over dt_s without samples (a gap in the stream) to the sample x at its end, given what
  /// a model of the integral says it is at the gap's start (m0) and end (m1): the rectangle step()
  /// would take over a fraction of a step's period misses the oscillation between. The integral is
  /// m1 plus its excess over m0 at the start, decayed; the high-pass is x less its low-pass, which
  /// moved by (1 - decay) times the input's mean over the gap less it: the model's (m1 - m0) / dt_s.
  double bridge(double x, double dt_s, double m0, double m1) noexcept {
    const double d = std::fabs(dt_s - dt_s_) <= 1e-9 * dt_s_ ? decay_ : std::exp(-dt_s / tau_);
    hp_ += x - x_prev_ - (1.0 - d) * (m1 - m0) / dt_s;
    x_prev_ = x;
    v_ = m1 + d * (v_ - m0);
    return v_;
  }

  /// Delay of the output behind the true integral at f_hz [s] (negative: it leads).
  double delay_s(double f_hz) const noexcept {
    const double w = kTwoPi * f_hz;
    return -2.0 * std::atan(1.0 / (w * tau_)) / w;
  }

 private:
  double tau_ = 1.0, dt_s_ = -1.0, decay_ = 1.0;
  double x_prev_ = 0.0, hp_ = 0.0, v_ = 0.0;
};

}  // namespace yoyogait::imu
