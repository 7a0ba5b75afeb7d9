/// @file gait/net_time.hpp
/// @brief The time a condition has held, net of the time it clearly has not: the failed-lock checks'
/// counter (gait/bound_watchdog.hpp; online/validity.hpp, below the steps).
#pragma once

namespace yoyogait::gait {

/// Counts up while the condition holds and down (to 0) while it clearly does not, so that a state
/// that keeps coming back between short excursions still adds up (a reset at every excursion let a
/// failed lock hover for 16 s; docs/default_estimator.md, sec. 2.3).
class NetTime {
 public:
  void reset() noexcept { t_s_ = 0.0; }
  void up(double dt_s) noexcept { t_s_ += dt_s; }
  void down(double dt_s) noexcept {
    if (t_s_ != 0.0) t_s_ = t_s_ > dt_s ? t_s_ - dt_s : 0.0;
  }
  /// The net time [s].
  double s() const noexcept { return t_s_; }
  /// up(dt_s) while holds, else down(dt_s); true once the net time exceeds limit_s (then it starts
  /// again from 0): a failed lock's one-time alarm.
  bool held_beyond(bool holds, double dt_s, double limit_s) noexcept {
    if (holds)
      up(dt_s);
    else
      down(dt_s);
    if (!(t_s_ > limit_s)) return false;
    reset();
    return true;
  }

 private:
  double t_s_ = 0.0;
};

}  // namespace yoyogait::gait
