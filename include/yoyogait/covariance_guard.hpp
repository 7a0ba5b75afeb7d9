/// @file covariance_guard.hpp
/// @brief Keeping a filter's covariance a covariance: a positive-definiteness test, the nearest
/// positive definite matrix, and variance bounds. Used by both estimators (paper/ekf.hpp, gait/member.hpp).
///
/// The EKF covariance update P - K S K^T is positive semi-definite in exact arithmetic, but in
/// floating point it subtracts two nearly equal matrices when the update removes most of a large
/// variance (a long dropout, a corrupt sample within range), and the rounding of the gain, amplified
/// by the condition of S, can leave a negative eigenvalue. The filters test the result cheaply on
/// every step and only then, on a cold path, recompute or repair it with the functions here.
/// Everything is fixed-size, allocates nothing and cannot throw.
#pragma once

#include <array>
#include <cmath>
#include <cstddef>
#include <limits>

namespace yoyogait {

/// A dense symmetric N x N matrix, row-major (both halves held).
template <std::size_t N>
using SquareMatrix = std::array<std::array<double, N>, N>;

/// The guards' rounding margin: 1024 units of round-off, far above the few units per entry that a
/// prediction and an update make. A filter's certificate, margin x trace(P) x (growth factors)
/// <= a lower bound on the smallest eigenvalue in exact arithmetic, lets it skip the test.
inline constexpr double kRoundingMargin = 1024.0 * std::numeric_limits<double>::epsilon();

/// Smallest eigenvalue that the repair leaves, relative to the largest: the nearest matrix has a
/// condition number of at most 1e12, so that rounding cannot take it back across zero.
inline constexpr double kMinRelativeEigenvalue = 1e-12;

/// True when the symmetric A is positive definite and finite: its LDL^T factorization has only
/// positive pivots (a NaN fails every comparison).
template <std::size_t N>
bool positive_definite_ldl(const SquareMatrix<N>& A) noexcept {
  SquareMatrix<N> L{};
  std::array<double, N> d{};
  for (std::size_t j = 0; j < N; ++j) {
    double dj = A[j][j];
    for (std::size_t k = 0; k < j; ++k) dj -= L[j][k] * L[j][k] * d[k];
    if (!(dj > 0.0 && std::isfinite(dj))) return false;
    d[j] = dj;
    for (std::size_t i = j + 1; i < N; ++i) {
      double s = A[i][j];
      for (std::size_t k = 0; k < j; ++k) s -= L[i][k] * L[j][k] * d[k];
      L[i][j] = s / dj;
    }
  }
  return true;
}

/// True when the symmetric P, of which only the upper triangle (i <= j) is read, is positive
/// semi-definite with only exact zeros for a null space, and finite: in its LDL^T factorization
/// every pivot is positive, or exactly zero with an exactly zero column below it (a state that is
/// held exactly, e.g. a rate the configuration turns off). One division per column; for the gait
/// filter's 8x8 about 170 multiply-adds.
template <std::size_t N>
bool positive_semidefinite_upper(const SquareMatrix<N>& P) noexcept {
  // The Schur complements in place, column by column: S holds the upper triangle of what is left
  // (S[k][i], k <= i), as P does.
  SquareMatrix<N> S = P;
  bool ok = true;
#if defined(__GNUC__) && !defined(__clang__)
#pragma GCC unroll 8
#endif
  for (std::size_t j = 0; j < N; ++j) {
    const double d = S[j][j];
    // A zero pivot is allowed only with a zero row (a state held exactly): then 1 / d is not used.
    const bool zero = d == 0.0;
    ok &= d > 0.0 || zero;
    const double inv = zero ? 0.0 : 1.0 / d;
#if defined(__GNUC__) && !defined(__clang__)
#pragma GCC unroll 8
#endif
    for (std::size_t i = j + 1; i < N; ++i) {
      ok &= !zero || S[j][i] == 0.0;
      const double l = S[j][i] * inv;
#if defined(__GNUC__) && !defined(__clang__)
#pragma GCC unroll 8
#endif
      for (std::size_t k = i; k < N; ++k) S[i][k] -= l * S[j][k];
    }
  }
  // NaN fails the comparisons above; an infinite pivot would pass them.
  for (std::size_t j = 0; j < N; ++j) ok &= S[j][j] <= std::numeric_limits<double>::max();
  return ok;
}

/// Eigenvalues lambda and eigenvectors (the columns of V) of the symmetric A, by cyclic Jacobi
/// rotations (at most 60 sweeps; a 4x4 or 8x8 converges in well under 10). A is overwritten.
template <std::size_t N>
void symmetric_eigen(SquareMatrix<N>& A, std::array<double, N>& lambda, SquareMatrix<N>& V) noexcept {
  for (std::size_t i = 0; i < N; ++i)
    for (std::size_t j = 0; j < N; ++j) V[i][j] = i == j ? 1.0 : 0.0;
  for (int sweep = 0; sweep < 60; ++sweep) {
    double off = 0.0, diag = 0.0;
    for (std::size_t i = 0; i < N; ++i) {
      diag += A[i][i] * A[i][i];
      for (std::size_t j = i + 1; j < N; ++j) off += A[i][j] * A[i][j];
    }
    if (!(off > 1e-36 * diag)) break;  // also stops on NaN
    for (std::size_t p = 0; p < N; ++p) {
      for (std::size_t q = p + 1; q < N; ++q) {
        const double apq = A[p][q];
        if (apq == 0.0) continue;
        // The rotation that zeroes A[p][q] (Golub and Van Loan, Algorithm 8.4.1).
        const double theta = (A[q][q] - A[p][p]) / (2.0 * apq);
        const double t = (theta >= 0.0 ? 1.0 : -1.0) / (std::fabs(theta) + std::sqrt(theta * theta + 1.0));
        const double c = 1.0 / std::sqrt(t * t + 1.0), s = t * c;
        for (std::size_t k = 0; k < N; ++k) {
          const double akp = A[k][p], akq = A[k][q];
          A[k][p] = c * akp - s * akq;
          A[k][q] = s * akp + c * akq;
        }
        for (std::size_t k = 0; k < N; ++k) {
          const double apk = A[p][k], aqk = A[q][k];
          A[p][k] = c * apk - s * aqk;
          A[q][k] = s * apk + c * aqk;
        }
        for (std::size_t k = 0; k < N; ++k) {
          const double vkp = V[k][p], vkq = V[k][q];
          V[k][p] = c * vkp - s * vkq;
          V[k][q] = s * vkp + c * vkq;
        }
      }
    }
  }
  for (std::size_t i = 0; i < N; ++i) lambda[i] = A[i][i];
}

/// Replaces the symmetric P by the nearest (Frobenius norm) symmetric matrix whose eigenvalues are
/// at least kMinRelativeEigenvalue times the largest (Higham's projection onto the positive
/// semi-definite cone, with that floor). Returns false, leaving P unchanged, when P is not finite or
/// has no positive eigenvalue: there is then no covariance to keep, and the caller restarts it.
template <std::size_t N>
bool nearest_positive_definite(SquareMatrix<N>& P) noexcept {
  SquareMatrix<N> A = P, V;
  std::array<double, N> lambda;
  for (std::size_t i = 0; i < N; ++i)
    for (std::size_t j = 0; j < N; ++j)
      if (!std::isfinite(A[i][j])) return false;
  symmetric_eigen(A, lambda, V);
  double top = 0.0;
  for (double l : lambda) top = l > top ? l : top;
  if (!(top > 0.0 && std::isfinite(top))) return false;
  const double floor = kMinRelativeEigenvalue * top;
  for (double& l : lambda) l = l > floor ? l : floor;
  // P = V diag(lambda) V^T, one triangle computed and mirrored: exactly symmetric.
  for (std::size_t i = 0; i < N; ++i)
    for (std::size_t j = i; j < N; ++j) {
      double s = 0.0;
      for (std::size_t k = 0; k < N; ++k) s += V[i][k] * lambda[k] * V[j][k];
      P[i][j] = P[j][i] = s;
    }
  return true;
}

/// Scales row and column i of the symmetric P by sqrt(max_variance[i] / P[i][i]) wherever P[i][i]
/// exceeds max_variance[i] (a congruence D P D with a positive diagonal D: the correlations are
/// kept, and a positive semi-definite P stays so). Every max_variance[i] must be > 0.
template <std::size_t N>
void bound_variances(SquareMatrix<N>& P, const std::array<double, N>& max_variance) noexcept {
  std::array<double, N> d;
  for (std::size_t i = 0; i < N; ++i) d[i] = P[i][i] > max_variance[i] ? std::sqrt(max_variance[i] / P[i][i]) : 1.0;
  for (std::size_t i = 0; i < N; ++i)
    for (std::size_t j = 0; j < N; ++j) P[i][j] *= d[i] * d[j];
  // The diagonal exactly at its bound (d^2 P_ii rounds to within an ulp of it).
  for (std::size_t i = 0; i < N; ++i)
    if (d[i] != 1.0) P[i][i] = max_variance[i];
}

}  // namespace yoyogait
