/// @file online/frame.hpp
/// @brief One motion-capture frame as the online front-end reads it: the points in metres, each
/// seen or missing, and the axes of the data (up, and the two horizontal ones).
#pragma once

#include <array>
#include <cmath>
#include <cstddef>

#include "yoyogait/math.hpp"
#include "yoyogait/online/centre.hpp"

namespace yoyogait::online {

/// The axes of the data: the up axis and the two others in increasing order, a then b.
struct Axes {
  explicit Axes(int up_axis) noexcept
      : up(static_cast<std::size_t>(up_axis)), a(up_axis == 0 ? 1 : 0), b(up_axis == 2 ? 1 : 2) {}
  std::size_t up = 2, a = 0, b = 1;
};

/// The points of the last frame read, in metres. A point is seen when each of its coordinates is
/// finite and within max_abs_position_m (after the length unit) and it is not exactly (0, 0, 0)
/// (a missing point as many writers mark it); else it is missing.
class PointFrame {
 public:
  /// What one frame held.
  struct Count {
    std::size_t seen = 0;  ///< points seen
    std::size_t bad = 0;   ///< points missing with some coordinate that is not NaN (infinite or absurd)
  };

  /// n_points: at most kMaxPoints; length_unit_m: metres per coordinate unit.
  PointFrame(std::size_t n_points, double length_unit_m, double max_abs_position_m) noexcept
      : n_(n_points > kMaxPoints ? kMaxPoints : n_points), unit_(length_unit_m), max_abs_m_(max_abs_position_m) {}

  /// Reads n_points x 3 coordinates (x, y, z of each point, in the length unit; NaN: missing).
  Count read(const double* positions_xyz) noexcept {
    Count c;
    const double m = max_abs_m_;
#ifdef YOYOGAIT_HAVE_SSE2
    // x and y of a point as one SSE2 pair (the same products and tests, half the instructions).
    const __m128d unit = _mm_set1_pd(unit_), lim = _mm_set1_pd(m), abs_mask = _mm_castsi128_pd(_mm_set1_epi64x(0x7fffffffffffffff));
#endif
    for (std::size_t j = 0; j < n_; ++j) {
      // Seen: not NaN, infinite or absurd, nor exactly (0, 0, 0), how many writers mark a missing point.
#ifdef YOYOGAIT_HAVE_SSE2
      const __m128d xy = _mm_mul_pd(_mm_loadu_pd(positions_xyz + 3 * j), unit);
      const double z = positions_xyz[3 * j + 2] * unit_;
      _mm_storeu_pd(pos_[j].data(), xy);
      pos_[j][2] = z;
      const bool xy_in = _mm_movemask_pd(_mm_cmple_pd(_mm_and_pd(xy, abs_mask), lim)) == 3;  // NaN: not <=
      const bool ok = xy_in && std::fabs(z) <= m && !(z == 0.0 && _mm_movemask_pd(_mm_cmpeq_pd(xy, _mm_setzero_pd())) == 3);
      const double x = pos_[j][0], y = pos_[j][1];
#else
      const double x = positions_xyz[3 * j] * unit_, y = positions_xyz[3 * j + 1] * unit_,
                   z = positions_xyz[3 * j + 2] * unit_;
      pos_[j] = {x, y, z};
      const bool ok = std::fabs(x) <= m && std::fabs(y) <= m && std::fabs(z) <= m && !(x == 0.0 && y == 0.0 && z == 0.0);
#endif
      visible_[j] = ok;
      c.seen += ok;
      if (!ok) c.bad += !(std::isnan(x) && std::isnan(y) && std::isnan(z));
    }
    return c;
  }

  /// The points of the last frame [m] and whether each was seen.
  const Vec3* positions_m() const noexcept { return pos_.data(); }
  const bool* visible() const noexcept { return visible_.data(); }
  std::size_t size() const noexcept { return n_; }
  double length_unit_m() const noexcept { return unit_; }

 private:
  std::size_t n_ = 1;
  double unit_ = 1.0, max_abs_m_ = 1e5;
  std::array<Vec3, kMaxPoints> pos_{};
  std::array<bool, kMaxPoints> visible_{};
};

}  // namespace yoyogait::online
