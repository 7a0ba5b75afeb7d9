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
    for (std::size_t j = 0; j < n_; ++j) {
      bool ok = true, any_value = false;
      for (std::size_t a = 0; a < 3; ++a) {
        const double v = positions_xyz[3 * j + a] * unit_;
        if (!std::isnan(v)) any_value = true;
        if (!(std::fabs(v) <= max_abs_m_)) ok = false;  // NaN, infinite or absurd
        pos_[j][a] = v;
      }
      // Exactly (0, 0, 0): how many writers mark a missing point.
      if (ok && pos_[j][0] == 0.0 && pos_[j][1] == 0.0 && pos_[j][2] == 0.0) ok = false;
      visible_[j] = ok;
      c.seen += ok;
      c.bad += (!ok && any_value);
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
