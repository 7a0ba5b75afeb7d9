/// @file paper/ekf.hpp
/// @brief The paper's sinusoid EKF (Sec. III): transition eq. 6, its Jacobian, measurement eq. 9.
///
/// The prediction and update are the textbook EKF equations that the paper refers to:
///   x- = f(x),            P- = F P F^T + Q                (F = df/dx at x)
///   y  = z - H x-,        S  = H P- H^T + V,  K = P- H^T S^-1
///   x+ = x- + K y,        P+ = (I - K H) P- = P- - K S K^T
/// Both are written out for the sparse F and H of this model and a symmetric P, so a step costs
/// about 200 flops, and arranged so that the loop-carried chain through sin w, cos w and 1 / det(S)
/// stays short.
///
/// The covariance guard (docs/paper_estimator.md, "Covariance guard"): update() certifies its
/// result positive definite by a rounding bound (a few flops); where it cannot (and after a
/// prediction without update), positive_definite() tests it (about 30 flops); only where that
/// fails, which walking data never reach, joseph_update() recomputes the update in the Joseph form
/// and nearest_positive_definite() (covariance_guard.hpp) repairs what is still not positive
/// definite. within_variance_bounds() and bound_variances() keep each variance within what the
/// state's range allows.
#pragma once

#include <array>
#include <cmath>
#include <limits>

#include "yoyogait/covariance_guard.hpp"
#include "yoyogait/math.hpp"
#include "yoyogait/paper/state.hpp"

namespace yoyogait::paper {

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

/// EKF prediction through eq. 6: x' = f(x), P' = F P F^T + Q, with F taken at x.
///
/// F = [[G, G J (x1, x2)^T, 0], [0, 1, 0], [0, 0, 1]] with G the rotation by w and J (x1, x2)^T =
/// (-x2, x1)^T, so the rows 0, 1 (x1, x2) of F are G L with L = [[1, 0, -x2, 0], [0, 1, x1, 0]].
/// With index pairs 01 = (x1, x2) and 23 = (w, A0):
///   P'(01, 01) = G (L P L^T) G^T,   P'(01, 23) = G (L P)(:, 23),   P'(23, 23) = P(23, 23),
/// and L P L^T and L P are formed from the prior alone, before sin w and cos w are known: only a
/// rotation of a 2x2 and of two 2-vectors waits for the sincos, which is on the filter's
/// loop-carried chain.
///
/// Out of place (x_pred, P_pred must not alias x, P), so that each entry is stored as soon as it is
/// computed: done in place, all of them would be held in registers until the last read of P.
///
/// Returns whether every variance of P_pred is within max_variance (the covariance guard's bounds,
/// docs/paper_estimator.md; false also for a NaN), compared while the diagonal is in registers.
inline bool predict_scalar(const State& x, const SymMatrix4& P, const std::array<double, kStateDim>& q,
                           const std::array<double, kStateDim>& max_variance, State& x_pred,
                           SymMatrix4& P_pred) noexcept {
  // The sincos first: its out-of-line fallback (std::sin) would otherwise force everything
  // computed before it out of the registers.
  double sn, c;
  sincos(x.omega_rad_per_sample(), sn, c);
  const double x1 = x.a1_cos(), x2 = x.a1_sin();
  // E = L P, and B = L P L^T (symmetric 2x2).
  const double e00 = P(kCos, kCos) - x2 * P(kOmega, kCos), e01 = P(kCos, kSin) - x2 * P(kOmega, kSin),
               e02 = P(kCos, kOmega) - x2 * P(kOmega, kOmega),
               e03 = P(kCos, kBias) - x2 * P(kOmega, kBias);
  const double e11 = P(kSin, kSin) + x1 * P(kOmega, kSin), e12 = P(kSin, kOmega) + x1 * P(kOmega, kOmega),
               e13 = P(kSin, kBias) + x1 * P(kOmega, kBias);
  const double b00 = e00 - x2 * e02, b01 = e01 + x1 * e02, b11 = e11 + x1 * e12;

  x_pred.a1_cos() = x1 * c - x2 * sn;
  x_pred.a1_sin() = x1 * sn + x2 * c;
  x_pred.omega_rad_per_sample() = x.omega_rad_per_sample();
  x_pred.bias_mps() = x.bias_mps();
  const double cc = c * c, ss = sn * sn, cs = c * sn;
  // G B G^T + Q(01): q enters first, the late products last.
  const double p00 = (q[kCos] + cc * b00) + (ss * b11 - (cs + cs) * b01);
  const double p11 = (q[kSin] + ss * b00) + (cc * b11 + (cs + cs) * b01);
  P_pred(kCos, kCos) = p00;
  P_pred(kCos, kSin) = cs * (b00 - b11) + (cc - ss) * b01;
  P_pred(kSin, kSin) = p11;
  // G E(:, 23).
  P_pred(kCos, kOmega) = c * e02 - sn * e12;
  P_pred(kSin, kOmega) = sn * e02 + c * e12;
  P_pred(kCos, kBias) = c * e03 - sn * e13;
  P_pred(kSin, kBias) = sn * e03 + c * e13;
  const double p22 = P(kOmega, kOmega) + q[kOmega], p33 = P(kBias, kBias) + q[kBias];
  P_pred(kOmega, kOmega) = p22;
  P_pred(kOmega, kBias) = P(kOmega, kBias);
  P_pred(kBias, kBias) = p33;
  return (p00 <= max_variance[kCos]) & (p11 <= max_variance[kSin]) & (p22 <= max_variance[kOmega]) &
         (p33 <= max_variance[kBias]);
}

/// No variance bound: the largest double for each.
inline constexpr std::array<double, kStateDim> kNoVarianceBound{
    std::numeric_limits<double>::max(), std::numeric_limits<double>::max(), std::numeric_limits<double>::max(),
    std::numeric_limits<double>::max()};

/// predict_scalar without the bounds.
inline void predict_scalar(const State& x, const SymMatrix4& P, const std::array<double, kStateDim>& q,
                           State& x_pred, SymMatrix4& P_pred) noexcept {
  predict_scalar(x, P, q, kNoVarianceBound, x_pred, P_pred);
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
///
/// certified: the covariance guard's certificate (docs/paper_estimator.md): true when rounding
/// cannot have made P_post indefinite, i.e.
///   cert_scale trace(P) (1 + x1^2 + x2^2) s00 s11 <= det(S),   cert_scale = kRoundingMargin / floor,
/// with floor a lower bound on the smallest eigenvalue of P_post in exact arithmetic
/// (PaperEstimator: q_min / (1 + q_min (2 / V11 + 1 / V22))), s00 s11 / det(S) >= 1 the condition
/// that amplifies the rounding of the gain, (1 + x1^2 + x2^2) that of the prediction (F holds x1, x2).
inline bool update_scalar(const State& x, const SymMatrix4& P, const Measurement& z, double v_vx_mps2,
                          double v_vz_mps2, double cert_scale, State& x_post, SymMatrix4& P_post,
                          bool& certified) noexcept {
  const double u0 = P(kCos, kCos) + P(kCos, kBias), u1 = P(kSin, kCos) + P(kSin, kBias),
               u2 = P(kOmega, kCos) + P(kOmega, kBias), u3 = P(kBias, kCos) + P(kBias, kBias);
  const double v0 = P(kCos, kSin), v1 = P(kSin, kSin), v2 = P(kOmega, kSin), v3 = P(kBias, kSin);
  // S = [[u0 + u3 + V11, -u1], [-u1, v1 + V22]]; adj S = [[s11, u1], [u1, s00]].
  const double s00 = P(kCos, kCos) + ((P(kCos, kBias) + u3) + v_vx_mps2);
  const double s11 = v1 + v_vz_mps2;
  const double det = s00 * s11 - u1 * u1;
  const double inv_det = 1.0 / det;
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
  P_post(kCos, kCos) = P(kCos, kCos) - (a0 * u0 - b0 * v0) * inv_det;
  P_post(kCos, kSin) = P(kCos, kSin) - (a0 * u1 - b0 * v1) * inv_det;
  P_post(kCos, kOmega) = P(kCos, kOmega) - (a0 * u2 - b0 * v2) * inv_det;
  P_post(kCos, kBias) = P(kCos, kBias) - (a0 * u3 - b0 * v3) * inv_det;
  P_post(kSin, kSin) = P(kSin, kSin) - (a1 * u1 - b1 * v1) * inv_det;
  P_post(kSin, kOmega) = P(kSin, kOmega) - (a1 * u2 - b1 * v2) * inv_det;
  P_post(kSin, kBias) = P(kSin, kBias) - (a1 * u3 - b1 * v3) * inv_det;
  P_post(kOmega, kOmega) = P(kOmega, kOmega) - (a2 * u2 - b2 * v2) * inv_det;
  P_post(kOmega, kBias) = P(kOmega, kBias) - (a2 * u3 - b2 * v3) * inv_det;
  P_post(kBias, kBias) = P(kBias, kBias) - (a3 * u3 - b3 * v3) * inv_det;
  // |P_ij| <= sqrt(P_ii P_jj), so a finite state and diagonal mean everything is finite.
  // (Summed in the order of update_sse2.)
  const double check = ((x_post[0] + x_post[2]) + (P_post(kCos, kCos) + P_post(kOmega, kOmega))) +
                       ((x_post[1] + x_post[3]) + (P_post(kSin, kSin) + P_post(kBias, kBias)));
  // The certificate (in the order of update_sse2).
  const double trace = (P(kCos, kCos) + P(kOmega, kOmega)) + (P(kSin, kSin) + P(kBias, kBias));
  const double amp2 = x[0] * x[0] + x[1] * x[1];
  certified = ((cert_scale * trace) * (1.0 + amp2)) * (s00 * s11) <= det;
  return std::isfinite(check);
}

/// update_scalar without the certificate.
inline bool update_scalar(const State& x, const SymMatrix4& P, const Measurement& z, double v_vx_mps2,
                          double v_vz_mps2, State& x_post, SymMatrix4& P_post) noexcept {
  bool certified;
  return update_scalar(x, P, z, v_vx_mps2, v_vz_mps2, std::numeric_limits<double>::infinity(), x_post, P_post,
                       certified);
}

/// True when the symmetric P is positive definite (and finite), by the block test: with
/// A = P(01, 01), B = P(01, 23) and C = P(23, 23), P > 0 iff A > 0 and the Schur complement
/// C - B^T A^-1 B > 0. Scaled by det A > 0 the complement is M = det(A) C - B^T adj(A) B, which
/// needs no division: P > 0 iff P(0,0) > 0, det A > 0, M(0,0) > 0 and det M > 0. A NaN fails.
inline bool positive_definite_scalar(const SymMatrix4& P) noexcept {
  const double a00 = P(kCos, kCos), a01 = P(kCos, kSin), a11 = P(kSin, kSin);
  const double det_a = a00 * a11 - a01 * a01;
  // N = adj(A) B, column by column (adj A = [[a11, -a01], [-a01, a00]]).
  const double n00 = a11 * P(kCos, kOmega) - a01 * P(kSin, kOmega), n10 = a00 * P(kSin, kOmega) - a01 * P(kCos, kOmega);
  const double n01 = a11 * P(kCos, kBias) - a01 * P(kSin, kBias), n11 = a00 * P(kSin, kBias) - a01 * P(kCos, kBias);
  const double m00 = det_a * P(kOmega, kOmega) - (P(kCos, kOmega) * n00 + P(kSin, kOmega) * n10);
  const double m11 = det_a * P(kBias, kBias) - (P(kCos, kBias) * n01 + P(kSin, kBias) * n11);
  const double m01 = det_a * P(kOmega, kBias) - (P(kCos, kOmega) * n01 + P(kSin, kOmega) * n11);
  const double det_m = m00 * m11 - m01 * m01;
  return a00 > 0.0 && det_a > 0.0 && m00 > 0.0 && det_m > 0.0 && det_m <= std::numeric_limits<double>::max();
}

/// True when no variance of P exceeds its bound (and none is NaN).
inline bool within_variance_bounds(const SymMatrix4& P, const std::array<double, kStateDim>& max_variance) noexcept {
  return P(kCos, kCos) <= max_variance[0] && P(kSin, kSin) <= max_variance[1] && P(kOmega, kOmega) <= max_variance[2] &&
         P(kBias, kBias) <= max_variance[3];
}

#ifdef YOYOGAIT_HAVE_SSE2
namespace simd {

// The same step on pairs of doubles (SSE2), for the storage pairs of SymMatrix4 and State
// ([x1, x2], [w, A0]). Each entry is computed by the same operations in the same order as in
// predict_scalar / update_scalar, so the results are identical bit for bit (tested); the step
// takes about a third fewer instructions than the scalar code, which the compiler does not pair well.

inline __m128d load(const double* p) noexcept { return _mm_loadu_pd(p); }
inline void store(double* p, __m128d v) noexcept { _mm_storeu_pd(p, v); }
inline __m128d lo2(__m128d v) noexcept { return _mm_unpacklo_pd(v, v); }  // [v0, v0]
inline __m128d hi2(__m128d v) noexcept { return _mm_unpackhi_pd(v, v); }  // [v1, v1]
inline double lo(__m128d v) noexcept { return _mm_cvtsd_f64(v); }
inline double hi(__m128d v) noexcept { return _mm_cvtsd_f64(_mm_unpackhi_pd(v, v)); }
// J v = [-v1, v0], the rotation by +90 degrees.
inline __m128d perp(__m128d v) noexcept {
  return _mm_xor_pd(_mm_shuffle_pd(v, v, 1), _mm_set_pd(0.0, -0.0));
}
// G v = c v + s J v, the rotation by w (C = [c, c], S = [s, s]).
inline __m128d rotate(__m128d v, __m128d C, __m128d S) noexcept {
  return _mm_add_pd(_mm_mul_pd(C, v), _mm_mul_pd(S, perp(v)));
}

inline bool predict_sse2(const State& x, const SymMatrix4& P, const std::array<double, kStateDim>& q,
                         const std::array<double, kStateDim>& max_variance, State& x_pred,
                         SymMatrix4& P_pred) noexcept {
  using M = SymMatrix4;
  // The sincos first: its out-of-line fallback (std::sin) would otherwise force everything
  // computed before it out of the registers.
  double sn, c;
  sincos(x.omega_rad_per_sample(), sn, c);
  const __m128d X = load(&x.x[kCos]);
  const __m128d diag01 = load(P.data() + M::kDiag01), off = load(P.data() + M::kOff);
  const __m128d col2 = load(P.data() + M::kCol2), col3 = load(P.data() + M::kCol3);
  const __m128d diag23 = load(P.data() + M::kDiag23);
  // E = L P by columns (rows 0, 1): E(:, j) = P(01, j) + l P(2, j), l = J (x1, x2) = (-x2, x1).
  const __m128d l = perp(X);
  const __m128d E0 = _mm_add_pd(_mm_unpacklo_pd(diag01, off), _mm_mul_pd(l, lo2(col2)));
  const __m128d E1 = _mm_add_pd(_mm_move_sd(diag01, off), _mm_mul_pd(l, hi2(col2)));
  const __m128d E2 = _mm_add_pd(col2, _mm_mul_pd(l, lo2(diag23)));
  const __m128d E3 = _mm_add_pd(col3, _mm_mul_pd(l, hi2(off)));
  // B = L P L^T: [b00, b01] and [b01, b11] (b01 from the second column, as predict_scalar).
  const __m128d B0 = _mm_add_pd(E0, _mm_mul_pd(lo2(l), E2));
  const __m128d B1 = _mm_add_pd(E1, _mm_mul_pd(hi2(l), E2));
  const double b00 = lo(B0), b01 = lo(B1), b11 = hi(B1);

  const __m128d C = _mm_set1_pd(c), S = _mm_set1_pd(sn);
  store(&x_pred.x[kCos], rotate(X, C, S));
  x_pred.omega_rad_per_sample() = x.omega_rad_per_sample();
  x_pred.bias_mps() = x.bias_mps();
  // G B G^T + Q(01): the diagonal as [cc, ss] b00 + [ss, cc] b11 -/+ 2 cs b01.
  const __m128d K = _mm_mul_pd(_mm_set_pd(sn, c), _mm_set_pd(sn, c));  // [cc, ss]
  const double cs = c * sn, cs2 = cs + cs;
  const __m128d diag = _mm_add_pd(_mm_add_pd(load(&q[kCos]), _mm_mul_pd(K, _mm_set1_pd(b00))),
                                  _mm_sub_pd(_mm_mul_pd(_mm_shuffle_pd(K, K, 1), _mm_set1_pd(b11)),
                                             _mm_mul_pd(_mm_set_pd(-cs2, cs2), _mm_set1_pd(b01))));
  const double p01 = cs * (b00 - b11) + (lo(K) - hi(K)) * b01;
  store(P_pred.data() + M::kDiag01, diag);
  store(P_pred.data() + M::kOff, _mm_move_sd(off, _mm_set_sd(p01)));  // [p01, P(w, A0)]
  store(P_pred.data() + M::kCol2, rotate(E2, C, S));
  store(P_pred.data() + M::kCol3, rotate(E3, C, S));
  const __m128d diag23n = _mm_add_pd(diag23, load(&q[kOmega]));
  store(P_pred.data() + M::kDiag23, diag23n);
  // The variance bounds, on the diagonal pairs in registers (predict_scalar).
  const __m128d within = _mm_and_pd(_mm_cmple_pd(diag, load(&max_variance[kCos])),
                                    _mm_cmple_pd(diag23n, load(&max_variance[kOmega])));
  return _mm_movemask_pd(within) == 3;
}

inline bool update_sse2(const State& x, const SymMatrix4& P, const Measurement& z, double v_vx_mps2,
                        double v_vz_mps2, double cert_scale, State& x_post, SymMatrix4& P_post,
                        bool& certified) noexcept {
  using M = SymMatrix4;
  const __m128d X01 = load(&x.x[kCos]), X23 = load(&x.x[kOmega]);
  const __m128d diag01 = load(P.data() + M::kDiag01), off = load(P.data() + M::kOff);
  const __m128d col2 = load(P.data() + M::kCol2), col3 = load(P.data() + M::kCol3);
  const __m128d diag23 = load(P.data() + M::kDiag23);
  // u = P(:, 0) + P(:, 3) and v = P(:, 1), in pairs [0, 1] and [2, 3].
  const __m128d u01 = _mm_add_pd(_mm_unpacklo_pd(diag01, off), col3);
  const __m128d u23 = _mm_add_pd(_mm_unpacklo_pd(col2, col3), _mm_unpackhi_pd(off, diag23));
  const __m128d v01 = _mm_move_sd(diag01, off);
  const __m128d v23 = _mm_unpackhi_pd(col2, col3);
  const double u1 = hi(u01), u3 = hi(u23);
  const double s00 = lo(diag01) + ((lo(col3) + u3) + v_vx_mps2);
  const double s11 = hi(diag01) + v_vz_mps2;
  const double det = s00 * s11 - u1 * u1;
  const double inv_det = 1.0 / det;
  const __m128d S00 = _mm_set1_pd(s00), S11 = _mm_set1_pd(s11), U1 = _mm_set1_pd(u1);
  // A = U adj(S): a = u s11 - v u1, b = u u1 - v s00.
  const __m128d a01 = _mm_sub_pd(_mm_mul_pd(u01, S11), _mm_mul_pd(v01, U1));
  const __m128d a23 = _mm_sub_pd(_mm_mul_pd(u23, S11), _mm_mul_pd(v23, U1));
  const __m128d b01 = _mm_sub_pd(_mm_mul_pd(u01, U1), _mm_mul_pd(v01, S00));
  const __m128d b23 = _mm_sub_pd(_mm_mul_pd(u23, U1), _mm_mul_pd(v23, S00));
  const Measurement h = measure(x);
  const __m128d Y0 = _mm_set1_pd(z.vx_mps - h.vx_mps), Y1 = _mm_set1_pd(z.vz_mps - h.vz_mps);
  const __m128d D = _mm_set1_pd(inv_det);
  const __m128d X01n = _mm_add_pd(X01, _mm_mul_pd(_mm_add_pd(_mm_mul_pd(a01, Y0), _mm_mul_pd(b01, Y1)), D));
  const __m128d X23n = _mm_add_pd(X23, _mm_mul_pd(_mm_add_pd(_mm_mul_pd(a23, Y0), _mm_mul_pd(b23, Y1)), D));
  store(&x_post.x[kCos], X01n);
  store(&x_post.x[kOmega], X23n);
  // P - (a u^T - b v^T) / det, pair by pair.
  const auto minus = [D](__m128d p, __m128d a, __m128d u, __m128d b, __m128d v) noexcept {
    return _mm_sub_pd(p, _mm_mul_pd(_mm_sub_pd(_mm_mul_pd(a, u), _mm_mul_pd(b, v)), D));
  };
  const __m128d diag01n = minus(diag01, a01, u01, b01, v01);
  const __m128d diag23n = minus(diag23, a23, u23, b23, v23);
  store(P_post.data() + M::kDiag01, diag01n);
  store(P_post.data() + M::kDiag23, diag23n);
  store(P_post.data() + M::kCol2, minus(col2, a01, lo2(u23), b01, lo2(v23)));
  store(P_post.data() + M::kCol3, minus(col3, a01, hi2(u23), b01, hi2(v23)));
  store(P_post.data() + M::kOff, minus(off, _mm_unpacklo_pd(a01, a23), _mm_unpackhi_pd(u01, u23),
                                       _mm_unpacklo_pd(b01, b23), _mm_unpackhi_pd(v01, v23)));
  // |P_ij| <= sqrt(P_ii P_jj), so a finite state and diagonal mean everything is finite.
  const __m128d sum = _mm_add_pd(_mm_add_pd(X01n, X23n), _mm_add_pd(diag01n, diag23n));
  // The guard's certificate (update_scalar).
  const __m128d diag_sum = _mm_add_pd(diag01, diag23), X2 = _mm_mul_pd(X01, X01);
  const double trace = lo(diag_sum) + hi(diag_sum), amp2 = lo(X2) + hi(X2);
  certified = ((cert_scale * trace) * (1.0 + amp2)) * (s00 * s11) <= det;
  return std::isfinite(lo(sum) + hi(sum));
}

inline bool update_sse2(const State& x, const SymMatrix4& P, const Measurement& z, double v_vx_mps2,
                        double v_vz_mps2, State& x_post, SymMatrix4& P_post) noexcept {
  bool certified;
  return update_sse2(x, P, z, v_vx_mps2, v_vz_mps2, std::numeric_limits<double>::infinity(), x_post, P_post,
                     certified);
}

// positive_definite_scalar on the storage pairs, the same operations in the same order.
inline bool positive_definite_sse2(const SymMatrix4& P) noexcept {
  using M = SymMatrix4;
  const __m128d diag01 = load(P.data() + M::kDiag01), off = load(P.data() + M::kOff);
  const __m128d col2 = load(P.data() + M::kCol2), col3 = load(P.data() + M::kCol3);
  const __m128d diag23 = load(P.data() + M::kDiag23);
  const double a00 = lo(diag01), a01 = lo(off), a11 = hi(diag01);
  const double det_a = a00 * a11 - a01 * a01;
  // N(:, j) = adj(A) B(:, j) = [a11, a00] B(:, j) - a01 [B(1, j), B(0, j)].
  const __m128d swapped_diag = _mm_shuffle_pd(diag01, diag01, 1), A01 = lo2(off);
  const __m128d N0 = _mm_sub_pd(_mm_mul_pd(swapped_diag, col2), _mm_mul_pd(A01, _mm_shuffle_pd(col2, col2, 1)));
  const __m128d N1 = _mm_sub_pd(_mm_mul_pd(swapped_diag, col3), _mm_mul_pd(A01, _mm_shuffle_pd(col3, col3, 1)));
  // B^T N: [b2 . n0, b3 . n1] and b2 . n1, each dot product summed lane 0 + lane 1.
  const __m128d t0 = _mm_mul_pd(col2, N0), t1 = _mm_mul_pd(col3, N1), t2 = _mm_mul_pd(col2, N1);
  const __m128d bn = _mm_add_pd(_mm_unpacklo_pd(t0, t1), _mm_unpackhi_pd(t0, t1));
  const __m128d m = _mm_sub_pd(_mm_mul_pd(_mm_set1_pd(det_a), diag23), bn);  // [m00, m11]
  const double m00 = lo(m), m11 = hi(m);
  const double m01 = det_a * hi(off) - (lo(t2) + hi(t2));
  const double det_m = m00 * m11 - m01 * m01;
  return a00 > 0.0 && det_a > 0.0 && m00 > 0.0 && det_m > 0.0 && det_m <= std::numeric_limits<double>::max();
}

}  // namespace simd
#endif

/// positive_definite_scalar(); with SSE2 the same arithmetic on pairs, identical results.
inline bool positive_definite(const SymMatrix4& P) noexcept {
#ifdef YOYOGAIT_HAVE_SSE2
  return simd::positive_definite_sse2(P);
#else
  return positive_definite_scalar(P);
#endif
}

/// The EKF prediction (predict_scalar), with the covariance guard's bound test; with SSE2 the same
/// arithmetic on pairs, identical results.
inline bool predict(const State& x, const SymMatrix4& P, const std::array<double, kStateDim>& q,
                    const std::array<double, kStateDim>& max_variance, State& x_pred, SymMatrix4& P_pred) noexcept {
#ifdef YOYOGAIT_HAVE_SSE2
  return simd::predict_sse2(x, P, q, max_variance, x_pred, P_pred);
#else
  return predict_scalar(x, P, q, max_variance, x_pred, P_pred);
#endif
}

/// The EKF prediction without the bounds.
inline void predict(const State& x, const SymMatrix4& P, const std::array<double, kStateDim>& q, State& x_pred,
                    SymMatrix4& P_pred) noexcept {
  predict(x, P, q, kNoVarianceBound, x_pred, P_pred);
}

/// The EKF update (update_scalar); with SSE2 the same arithmetic on pairs, identical results.
inline bool update(const State& x, const SymMatrix4& P, const Measurement& z, double v_vx_mps2, double v_vz_mps2,
                   State& x_post, SymMatrix4& P_post) noexcept {
#ifdef YOYOGAIT_HAVE_SSE2
  return simd::update_sse2(x, P, z, v_vx_mps2, v_vz_mps2, x_post, P_post);
#else
  return update_scalar(x, P, z, v_vx_mps2, v_vz_mps2, x_post, P_post);
#endif
}

/// The EKF update with the covariance guard's certificate (update_scalar); with SSE2 the same
/// arithmetic on pairs, identical results.
inline bool update(const State& x, const SymMatrix4& P, const Measurement& z, double v_vx_mps2, double v_vz_mps2,
                   double cert_scale, State& x_post, SymMatrix4& P_post, bool& certified) noexcept {
#ifdef YOYOGAIT_HAVE_SSE2
  return simd::update_sse2(x, P, z, v_vx_mps2, v_vz_mps2, cert_scale, x_post, P_post, certified);
#else
  return update_scalar(x, P, z, v_vx_mps2, v_vz_mps2, cert_scale, x_post, P_post, certified);
#endif
}

/// The EKF update in the Joseph form, for the guard's cold path: the same gain and state as
/// update(), but P_post = (I - K H) P (I - K H)^T + K V K^T, a sum of two positive semi-definite
/// terms whatever the rounding of K (the first-order effect of an error in K cancels), where
/// P - K S K^T subtracts nearly equal matrices. Equal to update() in exact arithmetic. Written with
/// dense matrices, as the textbook has it; symmetric by construction (one triangle, mirrored).
/// Returns false when the posterior would not be finite (x_post, P_post then unspecified).
inline bool joseph_update(const State& x, const SymMatrix4& P, const Measurement& z, double v_vx_mps2,
                          double v_vz_mps2, State& x_post, SymMatrix4& P_post) noexcept {
  const Matrix4 Pd = P.dense();
  constexpr double H[kMeasurementDim][kStateDim] = {{1, 0, 0, 1}, {0, -1, 0, 0}};
  const double V[kMeasurementDim] = {v_vx_mps2, v_vz_mps2};
  double PHt[kStateDim][kMeasurementDim] = {}, S[kMeasurementDim][kMeasurementDim] = {};
  for (std::size_t i = 0; i < kStateDim; ++i)
    for (std::size_t m = 0; m < kMeasurementDim; ++m)
      for (std::size_t k = 0; k < kStateDim; ++k) PHt[i][m] += Pd[i][k] * H[m][k];
  for (std::size_t m = 0; m < kMeasurementDim; ++m)
    for (std::size_t l = 0; l < kMeasurementDim; ++l) {
      for (std::size_t k = 0; k < kStateDim; ++k) S[m][l] += H[m][k] * PHt[k][l];
      if (m == l) S[m][l] += V[m];
    }
  const double det = S[0][0] * S[1][1] - S[0][1] * S[1][0];
  const double Si[2][2] = {{S[1][1] / det, -S[0][1] / det}, {-S[1][0] / det, S[0][0] / det}};
  double K[kStateDim][kMeasurementDim] = {};
  for (std::size_t i = 0; i < kStateDim; ++i)
    for (std::size_t m = 0; m < kMeasurementDim; ++m)
      for (std::size_t l = 0; l < kMeasurementDim; ++l) K[i][m] += PHt[i][l] * Si[l][m];
  const Measurement h = measure(x);
  const double y[kMeasurementDim] = {z.vx_mps - h.vx_mps, z.vz_mps - h.vz_mps};
  for (std::size_t i = 0; i < kStateDim; ++i) x_post[i] = x[i] + (K[i][0] * y[0] + K[i][1] * y[1]);
  // A = I - K H; P_post = A P A^T + K V K^T.
  Matrix4 A{}, AP{};
  for (std::size_t i = 0; i < kStateDim; ++i)
    for (std::size_t j = 0; j < kStateDim; ++j)
      A[i][j] = (i == j ? 1.0 : 0.0) - (K[i][0] * H[0][j] + K[i][1] * H[1][j]);
  for (std::size_t i = 0; i < kStateDim; ++i)
    for (std::size_t j = 0; j < kStateDim; ++j)
      for (std::size_t k = 0; k < kStateDim; ++k) AP[i][j] += A[i][k] * Pd[k][j];
  bool finite = true;
  for (std::size_t i = 0; i < kStateDim; ++i) {
    finite = finite && std::isfinite(x_post[i]);
    for (std::size_t j = i; j < kStateDim; ++j) {
      double s = K[i][0] * V[0] * K[j][0] + K[i][1] * V[1] * K[j][1];
      for (std::size_t k = 0; k < kStateDim; ++k) s += AP[i][k] * A[j][k];
      P_post(i, j) = s;
      finite = finite && std::isfinite(s);
    }
  }
  return finite;
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

}  // namespace yoyogait::paper
