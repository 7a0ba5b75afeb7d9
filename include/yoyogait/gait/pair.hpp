/// @file gait/pair.hpp
/// @brief Two doubles that go through the same operations (the X and Z phasors of the gait filter):
/// one SSE2 instruction for both where the target has it, two scalar ones elsewhere, with the same
/// bits either way (each lane is one IEEE operation).
#pragma once

#include "yoyogait/math.hpp"

namespace yoyogait::gait {

#ifdef YOYOGAIT_HAVE_SSE2
struct Pair {
  __m128d v;
  double lo() const noexcept { return _mm_cvtsd_f64(v); }
  double hi() const noexcept { return _mm_cvtsd_f64(_mm_unpackhi_pd(v, v)); }
};
inline Pair pair(double lo, double hi) noexcept { return {_mm_set_pd(hi, lo)}; }
inline Pair splat(double a) noexcept { return {_mm_set1_pd(a)}; }
/// p[0] = a.lo, p[1] = a.hi.
inline void store2(double* p, Pair a) noexcept { _mm_storeu_pd(p, a.v); }
/// (a.hi, b.hi).
inline Pair highs(Pair a, Pair b) noexcept { return {_mm_unpackhi_pd(a.v, b.v)}; }
/// -a, exactly (the sign bits flipped).
inline Pair negated(Pair a) noexcept { return {_mm_xor_pd(a.v, _mm_set1_pd(-0.0))}; }
inline Pair operator+(Pair a, Pair b) noexcept { return {_mm_add_pd(a.v, b.v)}; }
inline Pair operator-(Pair a, Pair b) noexcept { return {_mm_sub_pd(a.v, b.v)}; }
inline Pair operator*(Pair a, Pair b) noexcept { return {_mm_mul_pd(a.v, b.v)}; }
#else
struct Pair {
  double l, h;
  double lo() const noexcept { return l; }
  double hi() const noexcept { return h; }
};
inline Pair pair(double lo, double hi) noexcept { return {lo, hi}; }
inline Pair splat(double a) noexcept { return {a, a}; }
inline void store2(double* p, Pair a) noexcept {
  p[0] = a.l;
  p[1] = a.h;
}
inline Pair highs(Pair a, Pair b) noexcept { return {a.h, b.h}; }
inline Pair negated(Pair a) noexcept { return {-a.l, -a.h}; }
inline Pair operator+(Pair a, Pair b) noexcept { return {a.l + b.l, a.h + b.h}; }
inline Pair operator-(Pair a, Pair b) noexcept { return {a.l - b.l, a.h - b.h}; }
inline Pair operator*(Pair a, Pair b) noexcept { return {a.l * b.l, a.h * b.h}; }
#endif

}  // namespace yoyogait::gait
