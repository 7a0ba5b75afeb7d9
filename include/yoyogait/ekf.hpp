/// @file ekf.hpp
/// @brief The paper's sinusoid EKF (Sec. III): transition eq. 6, its Jacobian, measurement eq. 9.
///
/// The prediction and update are the textbook EKF equations that the paper refers to:
///   x- = f(x),            P- = F P F^T + Q                (F = df/dx at x)
///   y  = z - H x-,        S  = H P- H^T + V,  K = P- H^T S^-1
///   x+ = x- + K y,        P+ = (I - K H) P- = P- - K S K^T
/// Both are written out for the sparse F and H of this model and a symmetric P, so a step costs
/// about 200 flops, and arranged so that the loop-carried chain through sin w, cos w and 1 / det(S)
/// stays short.
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

/// EKF prediction through eq. 6: x' = f(x), P' = F P F^T + Q, with F taken at x.
///
/// F = [[G, G J x12, 0], [0, 1, 0], [0, 0, 1]] with G the rotation by w and J x12 = (-x2, x1), so
/// the (x1, x2) rows of F are G L with L = [[1, 0, -x2, 0], [0, 1, x1, 0]]. Hence
///   P'(12, 12) = G (L P L^T) G^T,   P'(12, 34) = G (L P)(:, 34),   P'(34, 34) = P(34, 34),
/// and L P L^T and L P are formed from the prior alone, before sin w and cos w are known: only a
/// rotation of a 2x2 and of two 2-vectors waits for the sincos, which is on the filter's
/// loop-carried chain.
///
/// Out of place (x_pred, P_pred must not alias x, P), so that each entry is stored as soon as it is
/// computed: done in place, all of them would be held in registers until the last read of P.
inline void predict(const State& x, const SymMatrix4& P, const std::array<double, kStateDim>& q, State& x_pred,
                    SymMatrix4& P_pred) noexcept {
  const double x1 = x.a1_cos(), x2 = x.a1_sin();
  // E = L P, and B = L P L^T (symmetric 2x2).
  const double e00 = P(0, 0) - x2 * P(2, 0), e01 = P(0, 1) - x2 * P(2, 1), e02 = P(0, 2) - x2 * P(2, 2),
               e03 = P(0, 3) - x2 * P(2, 3);
  const double e11 = P(1, 1) + x1 * P(2, 1), e12 = P(1, 2) + x1 * P(2, 2), e13 = P(1, 3) + x1 * P(2, 3);
  const double b00 = e00 - x2 * e02, b01 = e01 + x1 * e02, b11 = e11 + x1 * e12;

  double sn, c;
  sincos(x.omega_rad_per_sample(), sn, c);
  x_pred.a1_cos() = x1 * c - x2 * sn;
  x_pred.a1_sin() = x1 * sn + x2 * c;
  x_pred.omega_rad_per_sample() = x.omega_rad_per_sample();
  x_pred.bias_mps() = x.bias_mps();
  const double cc = c * c, ss = sn * sn, cs = c * sn;
  // G B G^T + Q(12): q enters first, the late products last.
  P_pred(0, 0) = (q[kCos] + cc * b00) + (ss * b11 - (cs + cs) * b01);
  P_pred(0, 1) = cs * (b00 - b11) + (cc - ss) * b01;
  P_pred(1, 1) = (q[kSin] + ss * b00) + (cc * b11 + (cs + cs) * b01);
  // G E(:, 34).
  P_pred(0, 2) = c * e02 - sn * e12;
  P_pred(1, 2) = sn * e02 + c * e12;
  P_pred(0, 3) = c * e03 - sn * e13;
  P_pred(1, 3) = sn * e03 + c * e13;
  P_pred(2, 2) = P(2, 2) + q[kOmega];
  P_pred(2, 3) = P(2, 3);
  P_pred(3, 3) = P(3, 3) + q[kBias];
}

/// EKF update with eq. 9, H = [[1, 0, 0, 1], [0, -1, 0, 0]], from the prediction (x, P) to the
/// posterior (x_post, P_post), which must not alias x, P (see predict). Returns false when the
/// posterior is not finite (an overflowing measurement); x_post, P_post are then unspecified and
/// the caller keeps the prediction, so that the state and covariance never become NaN or infinite.
///
/// With U = P H^T = [u, -v] (u = P(:, 1) + P(:, 4), v = P(:, 2)), S = H P H^T + V and
/// adj S = det(S) S^-1, the gain is K = U adj(S) / det(S). The products with adj(S) do not wait
/// for the division, which is then applied once per result:
///   x_post = x + (U adj(S) y) / det,   P_post = P - (U adj(S) U^T) / det.
inline bool update(const State& x, const SymMatrix4& P, const Measurement& z, double v_vx_mps2, double v_vz_mps2,
                   State& x_post, SymMatrix4& P_post) noexcept {
  const double u0 = P(0, 0) + P(0, 3), u1 = P(1, 0) + P(1, 3), u2 = P(2, 0) + P(2, 3), u3 = P(3, 0) + P(3, 3);
  const double v0 = P(0, 1), v1 = P(1, 1), v2 = P(2, 1), v3 = P(3, 1);
  // S = [[u0 + u3 + V11, -u1], [-u1, v1 + V22]]; adj S = [[s11, u1], [u1, s00]].
  const double s00 = P(0, 0) + ((P(0, 3) + u3) + v_vx_mps2);
  const double s11 = v1 + v_vz_mps2;
  const double inv_det = 1.0 / (s00 * s11 - u1 * u1);
  // A = U adj(S): column a (with y0) and column b (with y1).
  const double a0 = u0 * s11 - v0 * u1, a1 = u1 * s11 - v1 * u1, a2 = u2 * s11 - v2 * u1, a3 = u3 * s11 - v3 * u1;
  const double b0 = u0 * u1 - v0 * s00, b1 = u1 * u1 - v1 * s00, b2 = u2 * u1 - v2 * s00, b3 = u3 * u1 - v3 * s00;
  // Innovation y = z - H x.
  const Measurement h = measure(x);
  const double y0 = z.vx_mps - h.vx_mps;
  const double y1 = z.vz_mps - h.vz_mps;
  x_post[0] = x[0] + (a0 * y0 + b0 * y1) * inv_det;
  x_post[1] = x[1] + (a1 * y0 + b1 * y1) * inv_det;
  x_post[2] = x[2] + (a2 * y0 + b2 * y1) * inv_det;
  x_post[3] = x[3] + (a3 * y0 + b3 * y1) * inv_det;
  // A U^T = a u^T - b v^T.
  P_post(0, 0) = P(0, 0) - (a0 * u0 - b0 * v0) * inv_det;
  P_post(0, 1) = P(0, 1) - (a0 * u1 - b0 * v1) * inv_det;
  P_post(0, 2) = P(0, 2) - (a0 * u2 - b0 * v2) * inv_det;
  P_post(0, 3) = P(0, 3) - (a0 * u3 - b0 * v3) * inv_det;
  P_post(1, 1) = P(1, 1) - (a1 * u1 - b1 * v1) * inv_det;
  P_post(1, 2) = P(1, 2) - (a1 * u2 - b1 * v2) * inv_det;
  P_post(1, 3) = P(1, 3) - (a1 * u3 - b1 * v3) * inv_det;
  P_post(2, 2) = P(2, 2) - (a2 * u2 - b2 * v2) * inv_det;
  P_post(2, 3) = P(2, 3) - (a2 * u3 - b2 * v3) * inv_det;
  P_post(3, 3) = P(3, 3) - (a3 * u3 - b3 * v3) * inv_det;
  // |P_ij| <= sqrt(P_ii P_jj), so a finite state and diagonal mean everything is finite.
  const double check = (x_post[0] + x_post[1]) + (x_post[2] + x_post[3]) + (P_post(0, 0) + P_post(1, 1)) +
                       (P_post(2, 2) + P_post(3, 3));
  return std::isfinite(check);
}

/// predict() in place, on a dense covariance (taken to be symmetric; both halves are written).
inline void predict(State& x, Matrix4& P, const std::array<double, kStateDim>& q) noexcept {
  const State x0 = x;
  SymMatrix4 P_pred;
  predict(x0, SymMatrix4(P), q, x, P_pred);
  P = P_pred.dense();
}

/// update() in place, on a dense covariance (taken to be symmetric; both halves are written).
/// Returns false, leaving x and P untouched, when the posterior would not be finite.
inline bool update(State& x, Matrix4& P, const Measurement& z, double v_vx_mps2, double v_vz_mps2) noexcept {
  State x_post;
  SymMatrix4 P_post;
  if (!update(x, SymMatrix4(P), z, v_vx_mps2, v_vz_mps2, x_post, P_post)) return false;
  x = x_post;
  P = P_post.dense();
  return true;
}

}  // namespace yoyogait
