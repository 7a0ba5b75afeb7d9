/// @file online/lowpass.hpp
/// @brief Second-order Butterworth low-pass for two channels at any (slowly varying) frame interval:
/// the anti-aliasing filter in front of the estimator's decimation.
///
/// Bilinear transform with the cutoff prewarped, coefficients recomputed only when the frame
/// interval changes. Its phase delay at a given frequency is what OnlineEstimator adds to the
/// horizon of its prediction, so the estimates stay aligned with the frame time.
#pragma once

#include <array>
#include <cmath>
#include <complex>

namespace yoyogait::online {

class Lowpass2 {
 public:
  Lowpass2() noexcept = default;
  explicit Lowpass2(double cutoff_hz) noexcept : fc_(cutoff_hz) {}

  /// Starts at rest at the value x of each channel.
  void start(const std::array<double, 2>& x) noexcept {
    for (int c = 0; c < 2; ++c) {
      x1_[c] = x2_[c] = x[c];
      y1_[c] = y2_[c] = x[c];
    }
  }

  /// One frame dt_s after the previous one; returns the filtered values.
  std::array<double, 2> step(const std::array<double, 2>& x, double dt_s) noexcept {
    if (dt_s != dt_s_) design(dt_s);
    std::array<double, 2> y{};
    for (int c = 0; c < 2; ++c) {
      y[c] = b0_ * x[c] + b1_ * x1_[c] + b2_ * x2_[c] - a1_ * y1_[c] - a2_ * y2_[c];
      if (!std::isfinite(y[c])) y[c] = x[c];  // cannot happen with finite input; keeps the state finite
      x2_[c] = x1_[c];
      x1_[c] = x[c];
      y2_[c] = y1_[c];
      y1_[c] = y[c];
    }
    return y;
  }

  /// Phase delay at f_hz for the current frame interval [s].
  double delay_s(double f_hz) const noexcept {
    if (!(dt_s_ > 0.0 && f_hz > 0.0)) return 0.0;
    const double w = 6.283185307179586 * f_hz;
    const std::complex<double> z1 = std::polar(1.0, -w * dt_s_), z2 = z1 * z1;
    const std::complex<double> h = (b0_ + b1_ * z1 + b2_ * z2) / (1.0 + a1_ * z1 + a2_ * z2);
    return -std::arg(h) / w;
  }

 private:
  void design(double dt_s) noexcept {
    dt_s_ = dt_s;
    // Cutoff at most 0.45 of the frame rate (the bilinear transform needs it below Nyquist).
    const double fc = std::fmin(fc_, 0.45 / dt_s);
    const double k = std::tan(3.141592653589793 * fc * dt_s);
    const double q = 1.4142135623730951;  // 1 / Q of a Butterworth pair
    const double norm = 1.0 / (1.0 + q * k + k * k);
    b0_ = k * k * norm;
    b1_ = 2.0 * b0_;
    b2_ = b0_;
    a1_ = 2.0 * (k * k - 1.0) * norm;
    a2_ = (1.0 - q * k + k * k) * norm;
  }

  double fc_ = 6.0, dt_s_ = -1.0;
  double b0_ = 1.0, b1_ = 0.0, b2_ = 0.0, a1_ = 0.0, a2_ = 0.0;
  std::array<double, 2> x1_{}, x2_{}, y1_{}, y2_{};
};

}  // namespace yoyogait::online
