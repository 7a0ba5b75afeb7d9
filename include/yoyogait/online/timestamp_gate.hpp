/// @file online/timestamp_gate.hpp
/// @brief Which frame timestamps the online estimator takes: finite, increasing, and a jump far
/// ahead only once frames confirm it (docs/online.md, "Bad input").
#pragma once

#include <cmath>

#include "yoyogait/online/online_estimate.hpp"

namespace yoyogait::online {

/// A finite timestamp within +-kMaxAbsTimeS after the last accepted one is accepted, unless it lies
/// more than max_time_jump_s ahead: then only once two more frames follow it, each within max_gap_s
/// of the one before. Everything is noexcept and allocation-free.
class TimestampGate {
 public:
  /// Timestamps beyond +-this are absurd (31,700 years) and ignored as non-finite [s].
  static constexpr double kMaxAbsTimeS = 1e12;

  struct Settings {
    double max_time_jump_s = 1.0;  ///< a jump further ahead waits for frames that confirm it [s]
    double max_gap_s = 0.25;       ///< ... each within this of the one before [s]
  };

  TimestampGate() noexcept = default;
  explicit TimestampGate(const Settings& s) noexcept : s_(s) {}

  void reset() noexcept {
    have_time_ = false;
    jump_n_ = 0;
    jump_t_s_ = 0.0;
  }

  /// kUsed when t_s is taken (it is then last_s()), else why it is not (nothing else changes).
  OnlineStatus accept(double t_s) noexcept {
    if (!(std::fabs(t_s) <= kMaxAbsTimeS)) return OnlineStatus::kNonFinite;
    if (have_time_ && !(t_s > t_last_s_)) return OnlineStatus::kTimeNotIncreasing;
    if (have_time_ && t_s - t_last_s_ > s_.max_time_jump_s) {
      const bool follows = jump_n_ > 0 && t_s > jump_t_s_ && t_s - jump_t_s_ <= s_.max_gap_s;
      jump_n_ = follows ? jump_n_ + 1 : 1;
      jump_t_s_ = t_s;
      if (jump_n_ < 3) return OnlineStatus::kTimeJump;
    }
    jump_n_ = 0;
    have_time_ = true;
    t_last_s_ = t_s;
    return OnlineStatus::kUsed;
  }

  /// Whether a timestamp has been taken since the reset, and the last one [s].
  bool have_time() const noexcept { return have_time_; }
  double last_s() const noexcept { return t_last_s_; }

 private:
  Settings s_;
  bool have_time_ = false;
  double t_last_s_ = 0.0;  ///< the last accepted frame [s]
  double jump_t_s_ = 0.0;  ///< the last timestamp held back as a jump ahead [s]
  int jump_n_ = 0;         ///< frames in a row that followed it
};

}  // namespace yoyogait::online
