/// @file gait/radii.hpp
/// @brief R = A0 / w and r = |Z| / w, low-passed while walking (sec. 2.6).
#pragma once

#include <cmath>

namespace yoyogait::gait {

/// The Yoyo-model radii R and r [m]: the initial values until the first walk, then the first
/// walking values, then a first-order low-pass.
class RadiiSmoother {
 public:
  struct Settings {
    double initial_R_m = 0.12;  ///< R until the first walk [m]
    double initial_r_m = 0.02;  ///< r until the first walk [m]
  };

  RadiiSmoother() noexcept = default;
  explicit RadiiSmoother(const Settings& s) noexcept : R0_(s.initial_R_m), r0_(s.initial_r_m) { reset(); }

  void reset() noexcept {
    R_m_ = R0_;
    r_m_ = r0_;
    have_ = false;
  }

  /// One walking sample with the instantaneous radii and the low-pass gain.
  void update(double R_m, double r_m, double gain) noexcept {
    if (!have_) {
      R_m_ = R_m;
      r_m_ = r_m;
      have_ = true;
    } else {
      R_m_ += gain * (R_m - R_m_);
      r_m_ += gain * (r_m - r_m_);
    }
  }

  /// After a non-finite result: back to the initial values unless both are finite.
  void recover() noexcept {
    if (!(std::isfinite(R_m_) && std::isfinite(r_m_))) reset();
  }

  /// Whether a walk has been seen (the radii are estimates, not the initial values).
  bool have_estimate() const noexcept { return have_; }
  double R_m() const noexcept { return R_m_; }
  double r_m() const noexcept { return r_m_; }

 private:
  double R0_ = 0.12, r0_ = 0.02;
  double R_m_ = 0.12, r_m_ = 0.02;
  bool have_ = false;
};

}  // namespace yoyogait::gait
