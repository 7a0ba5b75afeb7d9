/// @file gait/bound_watchdog.hpp
/// @brief The watchdog of the frequency bounds: w pinned at a bound while walking is a failed lock
/// (sec. 2.3).
#pragma once

#include "yoyogait/gait/net_time.hpp"

namespace yoyogait::gait {

/// The walking time with w within 5 % of a bound, net of the time it is well inside (15 %;
/// gait/net_time.hpp). Fires once it exceeds limit_s (the filter then restarts the acquisition).
class BoundWatchdog {
 public:
  struct Settings {
    double w_min_rad_s = 0.0;  ///< the frequency bounds [rad/s]
    double w_max_rad_s = 0.0;
    double limit_s = 1.0;      ///< walking time near a bound before it fires [s]
  };

  BoundWatchdog() noexcept = default;
  explicit BoundWatchdog(const Settings& s) noexcept
      : near_min_(1.05 * s.w_min_rad_s),
        near_max_(0.95 * s.w_max_rad_s),
        inside_min_(1.15 * s.w_min_rad_s),
        inside_max_(0.85 * s.w_max_rad_s),
        limit_s_(s.limit_s) {}

  void reset() noexcept { at_bound_.reset(); }

  /// One walking step of dt [s] with the frequency w [rad/s]; true: restart the acquisition.
  bool update(double w, double dt) noexcept {
    if (w <= near_min_ || w >= near_max_)
      at_bound_.up(dt);
    else if (inside_min_ < w && w < inside_max_)
      at_bound_.down(dt);
    return at_bound_.s() > limit_s_;
  }

 private:
  // The thresholds, multiplied out once (the same products as per step).
  double near_min_ = 0.0, near_max_ = 0.0, inside_min_ = 0.0, inside_max_ = 0.0, limit_s_ = 1.0;
  NetTime at_bound_;
};

}  // namespace yoyogait::gait
