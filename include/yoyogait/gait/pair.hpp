/// @file gait/pair.hpp
/// @brief Two doubles that go through the same operations (the X and Z phasors of the gait filter):
/// one SSE2 instruction for both where the target has it (SsePair), two scalar ones elsewhere
/// (ScalarPair), with the same bits either way (each lane is one IEEE operation). Pair is the
/// target's form; the scalar one exists everywhere, so the tests can compare the two.
#pragma once

#include "yoyogait/math.hpp"

namespace yoyogait::gait {

/// The portable form: two scalar operations.
struct ScalarPair {
  double l, h;
  double lo() const noexcept { return l; }
  double hi() const noexcept { return h; }
  static ScalarPair of(double lo, double hi) noexcept { return {lo, hi}; }
  static ScalarPair splat(double a) noexcept { return {a, a}; }
};
/// p[0] = a.lo, p[1] = a.hi.
inline void store2(double* p, ScalarPair a) noexcept {
  p[0] = a.l;
  p[1] = a.h;
}
/// (a.hi, b.hi).
inline ScalarPair highs(ScalarPair a, ScalarPair b) noexcept { return {a.h, b.h}; }
/// -a, exactly (the sign bits flipped).
inline ScalarPair negated(ScalarPair a) noexcept { return {-a.l, -a.h}; }
inline ScalarPair operator+(ScalarPair a, ScalarPair b) noexcept { return {a.l + b.l, a.h + b.h}; }
inline ScalarPair operator-(ScalarPair a, ScalarPair b) noexcept { return {a.l - b.l, a.h - b.h}; }
inline ScalarPair operator*(ScalarPair a, ScalarPair b) noexcept { return {a.l * b.l, a.h * b.h}; }

#ifdef YOYOGAIT_HAVE_SSE2
/// The SSE2 form: one packed instruction.
struct SsePair {
  __m128d v;
  double lo() const noexcept { return _mm_cvtsd_f64(v); }
  double hi() const noexcept { return _mm_cvtsd_f64(_mm_unpackhi_pd(v, v)); }
  static SsePair of(double lo, double hi) noexcept { return {_mm_set_pd(hi, lo)}; }
  static SsePair splat(double a) noexcept { return {_mm_set1_pd(a)}; }
};
inline void store2(double* p, SsePair a) noexcept { _mm_storeu_pd(p, a.v); }
inline SsePair highs(SsePair a, SsePair b) noexcept { return {_mm_unpackhi_pd(a.v, b.v)}; }
inline SsePair negated(SsePair a) noexcept { return {_mm_xor_pd(a.v, _mm_set1_pd(-0.0))}; }
inline SsePair operator+(SsePair a, SsePair b) noexcept { return {_mm_add_pd(a.v, b.v)}; }
inline SsePair operator-(SsePair a, SsePair b) noexcept { return {_mm_sub_pd(a.v, b.v)}; }
inline SsePair operator*(SsePair a, SsePair b) noexcept { return {_mm_mul_pd(a.v, b.v)}; }
using Pair = SsePair;
#else
using Pair = ScalarPair;
#endif

}  // namespace yoyogait::gait
