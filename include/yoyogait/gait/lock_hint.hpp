/// @file gait/lock_hint.hpp
/// @brief The re-acquisition hint (sec. 2.3): the frequency of the last lock the evidence chose.
#pragma once

#include "yoyogait/math.hpp"

namespace yoyogait::gait {

/// A restart of the acquisition favours the hint's frequency (the bank's log-prior). A lock is
/// chosen when the bank has walked its window or another evidence relocks it; its frequency, as
/// the one EKF follows it, is the hint from then on. A bank that a stop cut short chose little but
/// its prior, and a lock found failed is wrong: neither is a hint (on noisy input a wrong lock
/// would otherwise win every restart with the hint's bonus).
class LockHint {
 public:
  /// Nothing chosen yet: no hint.
  void reset() noexcept {
    w_ = 0.0;
    chosen_ = false;
  }
  /// An acquisition starts: its lock is not chosen yet (the hint stays the last choice's).
  void acquiring() noexcept { chosen_ = false; }
  /// The evidence chose the lock at w [rad/s].
  void choose(double w) noexcept {
    chosen_ = true;
    w_ = w;
  }
  /// The lock failed: no hint until the next choice.
  void fail() noexcept { w_ = 0.0; }
  /// While walking: a chosen lock's frequency w [rad/s] is the hint.
  void follow(double w) noexcept {
    if (chosen_) w_ = w;
  }
  /// The hint [Hz]; 0 when there is none (nothing chosen, a failed lock, or a non-finite frequency).
  double f_hz() const noexcept { return w_ > 0.0 && w_ < 1e300 ? w_ * kInvTwoPi : 0.0; }

 private:
  double w_ = 0.0;       ///< the hint [rad/s]; 0: none
  bool chosen_ = false;  ///< the one EKF is a lock the evidence chose
};

}  // namespace yoyogait::gait
