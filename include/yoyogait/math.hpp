/// @file math.hpp
/// @brief Shared math: the constants, small numeric kernels for the per-sample path, and a small
/// fixed-size SPD solver.
#pragma once

#include <cmath>
#include <cstddef>

#if defined(__SSE2__) || defined(_M_X64)
#include <emmintrin.h>
#define YOYOGAIT_HAVE_SSE2 1
#endif

// Forces inlining where a compiler's size heuristics would keep a per-sample function out of line
// (a call per sample, and the estimate returned through memory).
#if defined(__GNUC__)
#define YOYOGAIT_ALWAYS_INLINE inline __attribute__((always_inline))
#elif defined(_MSC_VER)
#define YOYOGAIT_ALWAYS_INLINE __forceinline
#else
#define YOYOGAIT_ALWAYS_INLINE inline
#endif

// Keeps a rarely taken path (the covariance guard's tests and repairs) out of the per-sample
// loop's code, so that the loop stays small enough to be inlined; COLD also moves it out of the
// hot code's cache lines.
#if defined(__GNUC__)
#define YOYOGAIT_NOINLINE __attribute__((noinline))
#define YOYOGAIT_COLD __attribute__((noinline, cold))
#elif defined(_MSC_VER)
#define YOYOGAIT_NOINLINE __declspec(noinline)
#define YOYOGAIT_COLD __declspec(noinline)
#else
#define YOYOGAIT_NOINLINE
#define YOYOGAIT_COLD
#endif

namespace yoyogait {

/// 2 pi and 1 / (2 pi), the only copies in the core.
inline constexpr double kTwoPi = 6.283185307179586476925286766559;
inline constexpr double kInvTwoPi = 0.15915494309189533576888376337251;

/// The std of a value spread evenly over a range of this width (width / sqrt 12): an estimate whose
/// std is that wide says no more than the range does.
inline constexpr double uniform_std(double width) noexcept { return width * 0.28867513459481287; }

namespace detail {
/// min(a, b) and max(a, b) as Python's: the first argument unless the second is strictly
/// smaller (larger). Unlike std::fmin/fmax they compile to one instruction, no libm call.
inline double py_min(double a, double b) noexcept { return b < a ? b : a; }
inline double py_max(double a, double b) noexcept { return b > a ? b : a; }
/// v within [-lim, lim], NaN: 0. Without branches (min and max keep a NaN of their first argument).
inline double clamp_or_zero(double v, double lim) noexcept {
  const double c = py_max(py_min(v, lim), -lim);
  return c == c ? c : 0.0;
}
}  // namespace detail

/// atan2(y, x) within 2e-6 rad, without a library call (a minimax polynomial of atan on [0, 1]);
/// 0 at the origin. For angles that need no more (the gait phase, phase corrections).
inline double atan2_fast(double y, double x) noexcept {
  const double ax = std::fabs(x), ay = std::fabs(y), hi = ax > ay ? ax : ay, lo = ax > ay ? ay : ax;
  if (!(hi > 0.0)) return 0.0;
  const double r = lo / hi, r2 = r * r, r4 = r2 * r2;
  // Estrin's scheme: three independent pairs, so that the chain of dependent products is 3 deep, not 6.
  const double p01 = 0.99997726 + r2 * -0.33262347, p23 = 0.19354346 + r2 * -0.11643287,
               p45 = 0.05265332 + r2 * -0.01172120;
  double a = r * (p01 + r4 * (p23 + r4 * p45));
  if (ay > ax) a = 1.5707963267948966 - a;
  if (x < 0.0) a = 3.141592653589793 - a;
  return y < 0.0 ? -a : a;
}

/// The gain 1 - exp(-dt_s / tau_s) of a first-order low-pass, recomputed only when dt_s moves by
/// more than 1e-9 of itself: sample times jitter in their last bits, and an exp per sample costs.
class ExpGain {
 public:
  explicit ExpGain(double tau_s = 1.0) noexcept : tau_s_(tau_s) {}
  double operator()(double dt_s) noexcept {
    if (!(std::fabs(dt_s - dt_s_) <= 1e-9 * dt_s_)) {
      dt_s_ = dt_s;
      gain_ = 1.0 - std::exp(-dt_s / tau_s_);
    }
    return gain_;
  }

 private:
  double tau_s_;
  double dt_s_ = -1.0, gain_ = 0.0;
};

/// sqrt(a), correctly rounded as std::sqrt, but without the errno check that std::sqrt carries
/// under the default -fmath-errno (a branch to a library call on the per-sample path).
inline double sqrt1(double a) noexcept {
#ifdef YOYOGAIT_HAVE_SSE2
  return _mm_cvtsd_f64(_mm_sqrt_sd(_mm_setzero_pd(), _mm_set_sd(a)));
#else
  return std::sqrt(a);
#endif
}

/// sqrt(a) and sqrt(b), correctly rounded as std::sqrt. With SSE2 one packed instruction: square
/// roots and divisions share one unit that is not fully pipelined, and the next step's 1 / det(S)
/// waits for it.
inline void sqrt2(double a, double b, double& ra, double& rb) noexcept {
#ifdef YOYOGAIT_HAVE_SSE2
  const __m128d r = _mm_sqrt_pd(_mm_set_pd(b, a));
  ra = _mm_cvtsd_f64(r);
  rb = _mm_cvtsd_f64(_mm_unpackhi_pd(r, r));
#else
  ra = std::sqrt(a);
  rb = std::sqrt(b);
#endif
}

/// sin(x) and cos(x). For |x| <= pi/4, which covers every walking step frequency at the paper's
/// 25 Hz (up to 3.1 Hz), the fdlibm kernel polynomials (error below 1 ulp), evaluated in Estrin form
/// because this call sits on the filter's loop-carried dependency chain; std::sin/std::cos elsewhere.
inline void sincos(double x, double& s, double& c) noexcept {
  if (!(std::fabs(x) <= 0.78539816339744830962)) {
    s = std::sin(x);
    c = std::cos(x);
    return;
  }
  constexpr double S1 = -1.66666666666666324348e-01, S2 = 8.33333333332248946124e-03,
                   S3 = -1.98412698298579493134e-04, S4 = 2.75573137070700676789e-06,
                   S5 = -2.50507602534068634195e-08, S6 = 1.58969099521155010221e-10;
  constexpr double C1 = 4.16666666666666019037e-02, C2 = -1.38888888888741095749e-03,
                   C3 = 2.48015872894767294178e-05, C4 = -2.75573143513906633035e-07,
                   C5 = 2.08757232129817482790e-09, C6 = -1.13596475577881948265e-11;
  const double z = x * x;
  const double z2 = z * z;
  const double z4 = z2 * z2;
  const double rs = (S2 + z * S3) + z2 * (S4 + z * S5) + z4 * S6;
  s = x + (z * x) * (S1 + z * rs);
  const double rc = z * ((C1 + z * C2) + z2 * (C3 + z * C4) + z4 * (C5 + z * C6));
  const double hz = 0.5 * z;
  const double w = 1.0 - hz;
  c = w + (((1.0 - w) - hz) + z * rc);
}

/// Solves A x = b for a small symmetric positive-definite A by Cholesky (fixed size; a pivot that
/// is not positive is replaced by a tiny one, so the result stays finite for a semi-definite A).
template <std::size_t N>
void solve_spd(const double (&A)[N][N], const double (&b)[N], double (&x)[N]) noexcept {
  double L[N][N] = {};
  for (std::size_t i = 0; i < N; ++i) {
    for (std::size_t j = 0; j <= i; ++j) {
      double s = A[i][j];
      for (std::size_t k = 0; k < j; ++k) s -= L[i][k] * L[j][k];
      if (i == j)
        L[i][i] = s > 1e-300 ? std::sqrt(s) : 1e-150;
      else
        L[i][j] = s / L[j][j];
    }
  }
  double y[N];
  for (std::size_t i = 0; i < N; ++i) {
    double s = b[i];
    for (std::size_t k = 0; k < i; ++k) s -= L[i][k] * y[k];
    y[i] = s / L[i][i];
  }
  for (std::size_t ii = N; ii-- > 0;) {
    double s = y[ii];
    for (std::size_t k = ii + 1; k < N; ++k) s -= L[k][ii] * x[k];
    x[ii] = s / L[ii][ii];
  }
}

}  // namespace yoyogait
