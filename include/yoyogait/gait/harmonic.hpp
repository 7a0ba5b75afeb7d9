/// @file gait/harmonic.hpp
/// @brief The second harmonic of one channel by a cascaded 2-state Kalman filter (sec. 2.1).
#pragma once

#include <cstddef>

namespace yoyogait::gait {

/// The measured channels, each with its harmonic filter.
enum Channel : std::size_t {
  kVx = 0,  ///< v_x: harmonic of the forward phasor X
  kVz = 1,  ///< v_z: harmonic of the vertical phasor Z
};

/// Second harmonic of one channel: h = c0 cos 2th + c1 sin 2th, th the angle of the channel's
/// phasor; (c0, c1) by a 2-state random-walk Kalman filter. P symmetric: p00, p01, p11.
struct Harmonic {
  double c0 = 0.0, c1 = 0.0, p00 = 0.0, p01 = 0.0, p11 = 0.0;
  double value(double u, double v) const noexcept { return c0 * u + c1 * v; }
  /// Kalman update with the regressor (u, v), residual e and noise r, in two halves so that two
  /// channels can share one division: prepare() returns S, apply() takes 1/S.
  double prepare(double u, double v, double r, double& ph0, double& ph1) const noexcept {
    ph0 = p00 * u + p01 * v;
    ph1 = p01 * u + p11 * v;
    return u * ph0 + v * ph1 + r;
  }
  void apply(double ph0, double ph1, double e, double inv_S) noexcept {
    const double k0 = ph0 * inv_S, k1 = ph1 * inv_S;
    c0 += k0 * e;
    c1 += k1 * e;
    p00 -= k0 * ph0;
    p01 -= k0 * ph1;
    p11 -= k1 * ph1;
  }
  /// Back to zero coefficients with variance p0 each.
  void reset(double p0) noexcept {
    c0 = c1 = 0.0;
    p00 = p11 = p0;
    p01 = 0.0;
  }
  /// Random walk of the coefficients over one prediction (q = density times dt).
  void predict(double q) noexcept {
    p00 += q;
    p11 += q;
  }
};

/// A pending harmonic update (sec. 2.1): the coefficients are needed only at the next step.
struct HarmonicStep {
  bool on = false;
  double ph0 = 0.0, ph1 = 0.0, e = 0.0, S = 1.0;
};

/// (cos 2th, sin 2th) of the phasor (p1, p2) by the double-angle formulas; (0, 0) where
/// |p|^2 < min_amp2 (no reliable phase).
inline void harmonic_basis(double p1, double p2, double min_amp2, double& u, double& v) noexcept {
  const double a2 = p1 * p1 + p2 * p2;
  if (a2 < min_amp2) {
    u = v = 0.0;
    return;
  }
  const double inv = 1.0 / a2;
  u = (p1 * p1 - p2 * p2) * inv;
  v = 2.0 * p1 * p2 * inv;
}

}  // namespace yoyogait::gait
