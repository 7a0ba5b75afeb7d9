/// @file online/interval_cache.hpp
/// @brief A value that depends only on the frame interval (a low-pass gain: an exp or a division),
/// kept for the last two intervals.
#pragma once

#include <limits>

namespace yoyogait::online {

/// The differences of regular timestamps (k / rate) take two roundings in turn over long stretches
/// (at 30 Hz 13 distinct intervals in two minutes, but a change at every other frame): a value kept
/// for one interval is computed again at every other frame, one kept for two almost never. Reused
/// only for the same interval (==), so it is the value computed. Everything is noexcept.
template <class T>
class IntervalCache {
 public:
  /// Nothing kept.
  void reset() noexcept { dt_[0] = dt_[1] = std::numeric_limits<double>::quiet_NaN(); }

  /// f(dt_s): kept, or computed and kept in place of the older of the two.
  template <class F>
  const T& at(double dt_s, F&& f) noexcept {
    if (dt_s == dt_[0]) return v_[0];
    if (dt_s == dt_[1]) return v_[1];
    const int i = older_;
    older_ = 1 - i;
    dt_[i] = dt_s;
    v_[i] = f(dt_s);
    return v_[i];
  }

 private:
  double dt_[2] = {std::numeric_limits<double>::quiet_NaN(), std::numeric_limits<double>::quiet_NaN()};
  T v_[2]{};
  int older_ = 0;
};

}  // namespace yoyogait::online
