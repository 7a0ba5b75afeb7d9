/// @file ekf.hpp
/// @brief The paper's sinusoid EKF (Sec. III): transition eq. 6, its Jacobian, measurement eq. 9.
///
/// The prediction and update are the textbook EKF equations that the paper refers to:
///   x- = f(x),            P- = F P F^T + Q                (F = df/dx at x)
///   y  = z - H x-,        S  = H P- H^T + V,  K = P- H^T S^-1
///   x+ = x- + K y,        P+ = (I - K H) P- = P- - K S K^T
/// Both are written out for the sparse F and H of this model, so a step costs about 200 flops.
#pragma once

#include <cmath>

#include "yoyogait/math.hpp"
#include "yoyogait/state.hpp"

namespace yoyogait {

/// Measured velocities [m/s].
struct Measurement {
  double vx_mps = 0.0;
  double vz_mps = 0.0;
};

/// Eq. 6: rotate (x1, x2) by x3 radians; x3 and x4 are constant.
inline State transition(const State& s) noexcept {
  double sn, c;
  sincos(s.omega_rad_per_sample(), sn, c);
  State out = s;
  out.a1_cos() = s.a1_cos() * c - s.a1_sin() * sn;
  out.a1_sin() = s.a1_cos() * sn + s.a1_sin() * c;
  return out;
}

/// Jacobian of eq. 6 with respect to the state, at s.
inline Matrix4 transition_jacobian(const State& s) noexcept {
  double sn, c;
  sincos(s.omega_rad_per_sample(), sn, c);
  const double x1 = s.a1_cos();
  const double x2 = s.a1_sin();
  Matrix4 F{};
  F[kCos][kCos] = c;
  F[kCos][kSin] = -sn;
  F[kCos][kOmega] = -x1 * sn - x2 * c;
  F[kSin][kCos] = sn;
  F[kSin][kSin] = c;
  F[kSin][kOmega] = x1 * c - x2 * sn;
  F[kOmega][kOmega] = 1.0;
  F[kBias][kBias] = 1.0;
  return F;
}

/// Eq. 9: v_x = x4 + x1, v_z = -x2. H = [[1, 0, 0, 1], [0, -1, 0, 0]].
constexpr Measurement measure(const State& s) noexcept {
  return Measurement{s.bias_mps() + s.a1_cos(), -s.a1_sin()};
}

/// Diagonal process noise Q (eq. 6) and measurement noise V (eq. 9).
struct Noise {
  std::array<double, kStateDim> q{};  ///< diag(Q): [(m/s)^2, (m/s)^2, (rad/sample)^2, (m/s)^2]
  double v_vx_mps2 = 0.0;             ///< V11
  double v_vz_mps2 = 0.0;             ///< V22
};

/// EKF prediction through eq. 6: x <- f(x), P <- F P F^T + Q, with F taken at the prior x.
/// F differs from the identity only in its (x1, x2) rows, so only those rows and columns of P change.
inline void predict(State& s, Matrix4& P, const std::array<double, kStateDim>& q) noexcept {
  double sn, c;
  sincos(s.omega_rad_per_sample(), sn, c);
  const double x1 = s.a1_cos() * c - s.a1_sin() * sn;
  const double x2 = s.a1_cos() * sn + s.a1_sin() * c;
  // The omega column of F: d x1'/d w = -x2', d x2'/d w = x1'.
  const double g0 = -x2;
  const double g1 = x1;
  s.a1_cos() = x1;
  s.a1_sin() = x2;

  // M = F P: rows 0 and 1 change.
  double m0[kStateDim], m1[kStateDim];
  for (std::size_t j = 0; j < kStateDim; ++j) {
    m0[j] = c * P[0][j] - sn * P[1][j] + g0 * P[2][j];
    m1[j] = sn * P[0][j] + c * P[1][j] + g1 * P[2][j];
  }
  // P' = M F^T: columns 0 and 1 change; symmetric, so fill both halves from the same value.
  const double p00 = c * m0[0] - sn * m0[1] + g0 * m0[2];
  const double p01 = sn * m0[0] + c * m0[1] + g1 * m0[2];
  const double p11 = sn * m1[0] + c * m1[1] + g1 * m1[2];
  P[0][0] = p00 + q[0];
  P[0][1] = P[1][0] = p01;
  P[1][1] = p11 + q[1];
  for (std::size_t j = 2; j < kStateDim; ++j) {
    P[0][j] = P[j][0] = m0[j];
    P[1][j] = P[j][1] = m1[j];
  }
  P[2][2] += q[2];
  P[3][3] += q[3];
}

/// EKF update with eq. 9. Returns false, leaving s and P untouched, when the result would not be
/// finite (an overflowing measurement): the state and covariance never become NaN or infinite.
inline bool update(State& s, Matrix4& P, const Measurement& z, double v_vx_mps2, double v_vz_mps2) noexcept {
  // U = P H^T (4x2), using the symmetry of P.
  double u0[kStateDim], u1[kStateDim];
  for (std::size_t i = 0; i < kStateDim; ++i) {
    u0[i] = P[i][0] + P[i][3];
    u1[i] = -P[i][1];
  }
  // S = H P H^T + V (2x2, symmetric) and its inverse.
  const double s00 = u0[0] + u0[3] + v_vx_mps2;
  const double s01 = u1[0] + u1[3];
  const double s11 = -u1[1] + v_vz_mps2;
  const double inv_det = 1.0 / (s00 * s11 - s01 * s01);
  const double i00 = s11 * inv_det;
  const double i01 = -s01 * inv_det;
  const double i11 = s00 * inv_det;
  // Innovation y = z - H x.
  const Measurement h = measure(s);
  const double y0 = z.vx_mps - h.vx_mps;
  const double y1 = z.vz_mps - h.vz_mps;
  // K = U S^-1; x += K y; P -= K U^T (= U S^-1 U^T, symmetric).
  double k0[kStateDim], k1[kStateDim];
  State xs = s;
  for (std::size_t i = 0; i < kStateDim; ++i) {
    k0[i] = u0[i] * i00 + u1[i] * i01;
    k1[i] = u0[i] * i01 + u1[i] * i11;
    xs[i] += k0[i] * y0 + k1[i] * y1;
  }
  Matrix4 Pn;
  for (std::size_t i = 0; i < kStateDim; ++i) {
    for (std::size_t j = i; j < kStateDim; ++j) {
      Pn[i][j] = Pn[j][i] = P[i][j] - (k0[i] * u0[j] + k1[i] * u1[j]);
    }
  }
  // |P_ij| <= sqrt(P_ii P_jj), so a finite state and diagonal mean everything is finite.
  const double check = (xs[0] + xs[1]) + (xs[2] + xs[3]) + (Pn[0][0] + Pn[1][1]) + (Pn[2][2] + Pn[3][3]);
  if (!std::isfinite(check)) return false;
  s = xs;
  P = Pn;
  return true;
}

}  // namespace yoyogait
