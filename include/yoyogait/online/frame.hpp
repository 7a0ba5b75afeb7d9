/// @file online/frame.hpp
/// @brief One motion-capture frame as the online front-end reads it: the points in metres, each
/// seen or missing, and the axes of the data (up, and the two horizontal ones).
#pragma once

#include <array>
#include <cmath>
#include <cstddef>

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
    for (std::size_t j = 0; j < n_; ++j) {
      const double x = positions_xyz[3 * j] * unit_, y = positions_xyz[3 * j + 1] * unit_,
                   z = positions_xyz[3 * j + 2] * unit_;
      pos_[j] = {x, y, z};
      // Not NaN, infinite or absurd, nor exactly (0, 0, 0), how many writers mark a missing point;
      // the tests in the order that settles a seen point soonest (x != 0 nearly always).
      const bool ok = std::fabs(x) <= m && std::fabs(y) <= m && std::fabs(z) <= m &&
                      !(x == 0.0 && y == 0.0 && z == 0.0);
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
