/// @file gait/walking_detector.hpp
/// @brief Walking / standing detector: low-passes of v_x and v_z^2 with hysteresis (sec. 2.4).
#pragma once

#include <cmath>

#include "yoyogait/math.hpp"

namespace yoyogait::gait {

/// Walking when LP(v_x) exceeds speed_on or RMS(v_z) exceeds vz_rms_on; standing again when
/// LP(v_x) is below speed_off and RMS(v_z) below vz_rms_off.
class WalkingDetector {
 public:
  struct Thresholds {
    double tau_s = 0.3;             ///< low-pass time constant [s]
    double speed_on_mps = 0.2;      ///< [m/s]
    double speed_off_mps = 0.15;    ///< [m/s]
    double vz_rms_on_mps = 0.05;    ///< [m/s]
    double vz_rms_off_mps = 0.025;  ///< [m/s]
  };

  WalkingDetector() noexcept = default;
  explicit WalkingDetector(const Thresholds& t) noexcept
      : tau_s_(t.tau_s),
        speed_on_(t.speed_on_mps),
        speed_off_(t.speed_off_mps),
        vz_rms_on2_(t.vz_rms_on_mps * t.vz_rms_on_mps),
        vz_rms_off2_(t.vz_rms_off_mps * t.vz_rms_off_mps) {}

  /// Standing, low-passes at zero.
  void reset() noexcept {
    walking_ = false;
    ema_vx_ = 0.0;
    ema_vz2_ = 0.0;
  }

  /// The low-passes start at the first usable sample.
  void start(double vx, double vz, bool use_z) noexcept {
    ema_vx_ = vx;
    ema_vz2_ = use_z ? vz * vz : 0.0;
  }

  /// The low-pass gain over dt [s] (the filter's cached factor where dt is the usual one).
  double gain(double dt_s) const noexcept { return 1.0 - std::exp(-dt_s / tau_s_); }

  /// One sample; a channel not usable leaves its low-pass alone.
  void update(double vx, double vz, bool use_x, bool use_z, double gain) noexcept {
    if (use_x) ema_vx_ += gain * (vx - ema_vx_);
    if (use_z) ema_vz2_ += gain * (vz * vz - ema_vz2_);
    // RMS(v_z) = sqrt(LP(v_z^2)) compared through its square (no square root per step), less the
    // variance the input noise is known to add (0 unless set).
    const double ms = detail::py_max(ema_vz2_ - noise_vz2_ - floor_vz2_, 0.0);
    // Both thresholds raised by noise_sigmas standard deviations of what the noise alone gives the
    // low-passes (for white samples of variance N: N g / (2 - g) for LP(v_x), 2 N^2 g / (2 - g) for
    // LP(v_z^2)), so that noise does not walk (none without noise: nothing computed).
    double mx = 0.0, mz2 = 0.0;
    if (noise_sigmas_ > 0.0 && (noise_vx2_ > 0.0 || noise_vz2_ > 0.0)) {
      const double spread = gain / (2.0 - gain);
      mx = noise_sigmas_ * std::sqrt(noise_vx2_ * spread);
      mz2 = noise_sigmas_ * noise_vz2_ * std::sqrt(2.0 * spread);
    }
    if (walking_) {
      if (ema_vx_ < speed_off_ + mx && ms < vz_rms_off2_ + mz2) walking_ = false;
    } else if (ema_vx_ > speed_on_ + mx || ms > vz_rms_on2_ + mz2) {
      walking_ = true;
    }
  }

  /// After a non-finite result: the low-passes made finite (LP(v_x) >= 0); returns LP(v_x).
  double recover() noexcept {
    const double A0 = std::isfinite(ema_vx_) ? detail::py_max(ema_vx_, 0.0) : 0.0;
    ema_vx_ = A0;
    if (!std::isfinite(ema_vz2_)) ema_vz2_ = 0.0;
    return A0;
  }

  bool walking() const noexcept { return walking_; }

  /// The input noise's variances of v_x and v_z [(m/s)^2] (0 by default; the online front-end's; the
  /// v_z part is not counted in RMS(v_z)) and how many of their standard deviations
  /// in the low-passes the thresholds are raised by (0: none); floor_vz: the variance of v_z that
  /// the input's noise floor leaves on every sample, not counted in RMS(v_z) either.
  void set_noise(double vx_m2_per_s2, double vz_m2_per_s2, double sigmas, double floor_vz_m2_per_s2 = 0.0) noexcept {
    noise_vx2_ = vx_m2_per_s2;
    noise_vz2_ = vz_m2_per_s2;
    noise_sigmas_ = sigmas;
    floor_vz2_ = floor_vz_m2_per_s2;
  }

 private:
  double tau_s_ = 0.3, speed_on_ = 0.2, speed_off_ = 0.15, vz_rms_on2_ = 0.0025, vz_rms_off2_ = 0.000625;
  double ema_vx_ = 0.0, ema_vz2_ = 0.0, noise_vz2_ = 0.0, noise_vx2_ = 0.0, noise_sigmas_ = 0.0, floor_vz2_ = 0.0;
  bool walking_ = false;
};

}  // namespace yoyogait::gait
