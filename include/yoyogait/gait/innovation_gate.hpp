/// @file gait/innovation_gate.hpp
/// @brief The innovation gate and its release (sec. 2.5).
#pragma once

#include <cstddef>

namespace yoyogait::gait {

/// A channel with nu^2 > sigma^2 S is not used. After max_consecutive steps with a rejection in a
/// row the gate stands open for one step: the persistent disagreement is accepted, and the filter
/// inflates its covariance so that it follows again.
class InnovationGate {
 public:
  struct Settings {
    double sigma = 5.0;                ///< a channel with nu^2 > sigma^2 S is rejected [1]
    std::size_t max_consecutive = 6;   ///< after this many steps with a rejection the gate opens once
  };

  InnovationGate() noexcept = default;
  explicit InnovationGate(const Settings& s) noexcept
      : sigma2_(s.sigma * s.sigma), max_consecutive_(s.max_consecutive) {}

  void reset() noexcept { n_rejects_ = 0; }

  /// Whether this step's updates are gated (not after max_consecutive rejections in a row).
  bool active() const noexcept { return n_rejects_ < max_consecutive_; }
  /// Whether the innovation nu with variance S is rejected.
  bool rejects(double nu, double S) const noexcept { return nu * nu > sigma2_ * S; }

  /// After a step; true when a persistent disagreement has just been accepted (inflate P).
  bool after_step(bool rejected) noexcept {
    if (rejected) {
      ++n_rejects_;
      return false;
    }
    const bool released = n_rejects_ > 0 && n_rejects_ >= max_consecutive_;
    n_rejects_ = 0;
    return released;
  }

 private:
  double sigma2_ = 25.0;
  std::size_t max_consecutive_ = 6;
  std::size_t n_rejects_ = 0;
};

}  // namespace yoyogait::gait
