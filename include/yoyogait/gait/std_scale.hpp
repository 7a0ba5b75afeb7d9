/// @file gait/std_scale.hpp
/// @brief The scale of the reported standard deviations: the low-passed normalised innovation
/// squared (NIS), clipped (sec. 2.6).
#pragma once

#include "yoyogait/math.hpp"

namespace yoyogait::gait {

/// lambda: the reported standard deviations are sqrt(lambda P_ii). Each accepted channel's NIS
/// nu^2 / S moves lambda towards it by the gain 0.5 (1 - exp(-dt / tau)); lambda stays in
/// [min, max]. Not adapting: lambda = 1.
class StdScale {
 public:
  struct Settings {
    bool adapt = true;       ///< false: lambda = 1
    double min_scale = 0.05;  ///< lambda's range [1]
    double max_scale = 4.0;
  };

  StdScale() noexcept = default;
  explicit StdScale(const Settings& s) noexcept : adapt_(s.adapt), min_(s.min_scale), max_(s.max_scale) {}

  void reset() noexcept { lambda_ = 1.0; }
  bool adapts() const noexcept { return adapt_; }

  /// One channel's NIS with the step's gain.
  void update(double nis, double gain) noexcept {
    const double lam = lambda_ + gain * (nis - lambda_);
    lambda_ = detail::py_min(detail::py_max(lam, min_), max_);
  }

  double value() const noexcept { return lambda_; }

 private:
  bool adapt_ = true;
  double min_ = 0.05, max_ = 4.0;
  double lambda_ = 1.0;
};

}  // namespace yoyogait::gait
