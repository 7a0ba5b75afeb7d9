/// @file gait/decay_factors.hpp
/// @brief The gait filter's dt-dependent factors (exp(-dt / tau), the measurement noise), cached per
/// time step.
#pragma once

#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>

namespace yoyogait::gait {

/// Factors that depend on dt only through exp: recomputed only when dt changes by more than a
/// relative 1e-9 (differences of regular timestamps jitter by rounding; a factor then differs
/// from its exact value by < 1e-10 relative). The steady state runs no exp.
class DecayFactors {
 public:
  /// The time constants [s] of the filter's first-order processes and low-passes.
  struct TimeConstants {
    double accel_tau_s = 1.0;          ///< dA0 decays
    double omega_rate_tau_s = 3.0;     ///< dw decays
    double omega_rate_lp_tau_s = 1.5;  ///< low-pass of dw for the trend test (0: none)
    double walk_tau_s = 0.3;           ///< walking detector
    double std_scale_tau_s = 10.0;     ///< NIS low-pass of the std scale
    double bank_forget_s = 1.5;        ///< bank log-likelihood memory
    double radii_tau_s = 2.0;          ///< R, r low-pass
    double cadence_change_tau_s = 0.1;        ///< low-pass of the phase evidence (gait/cadence_change.hpp)
    double cadence_change_noise_tau_s = 2.0;  ///< ... and of their mean square
  };

  /// The measurement noise densities [(m/s)^2 s] (sec. 2.2): a sample is the mean velocity over
  /// its interval, so its variance is the density over the interval, R = density / dt. A step
  /// without an interval (dt = 0: the first sample, after a long gap) takes nominal_dt_s.
  struct MeasurementNoise {
    double vx_density = 1e-4, vz_density = 1e-4;
    double nominal_dt_s = 0.04;
    /// The variances R at an interval dt > 0 (else at nominal_dt_s) [(m/s)^2].
    double r_vx(double dt) const noexcept { return vx_density / (dt > 0.0 ? dt : nominal_dt_s); }
    double r_vz(double dt) const noexcept { return vz_density / (dt > 0.0 ? dt : nominal_dt_s); }
  };

  /// The factors for one dt.
  struct Values {
    double dt = -1.0;
    double accel_decay = 1.0, rate_decay = 1.0, rate_lp_gain = 0.0, walk_gain = 0.0, std_gain = 0.0,
           forget = 1.0, radii_gain = 0.0;
    double cadence_gain = 0.0, cadence_noise_gain = 0.0;  ///< 1 - exp(-dt / tau), ... noise_tau (0 at dt = 0)
    /// Measurement noise variances of v_x, v_z [(m/s)^2], and ||H^T R^-1 H|| of the two updates
    /// (2 / r_vx + 1 / r_vz): the covariance guard's certificate (sec. 2.7).
    double r_vx = 0.0, r_vz = 0.0, info = 0.0;
  };

  DecayFactors() noexcept = default;
  DecayFactors(const TimeConstants& tau, const MeasurementNoise& meas) noexcept : tau_(tau), meas_(meas) {}

  /// Forget the cached dt: the next at() computes.
  void reset() noexcept { values_.dt = -1.0; }

  /// Variances added to R of v_x and v_z [(m/s)^2] from now on (0 by default: R is the density's;
  /// the online front-end adds what its input noise puts on the velocities). No exp.
  void set_extra_variance(double vx_m2_per_s2, double vz_m2_per_s2) noexcept {
    if (vx_m2_per_s2 == extra_vx_ && vz_m2_per_s2 == extra_vz_) return;
    extra_vx_ = vx_m2_per_s2;
    extra_vz_ = vz_m2_per_s2;
    if (values_.dt >= 0.0) noise_at(values_);
  }

  const Values& at(double dt) noexcept {
    // Regular sampling repeats dt (up to rounding of timestamp differences): no exp then.
    if (std::fabs(dt - values_.dt) <= 1e-9 * dt) return values_;
    Values& f = values_;
    f.dt = dt;
    f.accel_decay = std::exp(-dt / tau_.accel_tau_s);
    f.rate_decay = std::exp(-dt / tau_.omega_rate_tau_s);
    f.rate_lp_gain = tau_.omega_rate_lp_tau_s > 0.0 ? 1.0 - std::exp(-dt / tau_.omega_rate_lp_tau_s) : 1.0;
    f.walk_gain = dt > 0.0 ? 1.0 - std::exp(-dt / tau_.walk_tau_s) : 0.0;
    // Standard-deviation scale gain: 0.5 (1 - exp(-dt / tau)) (0 when dt = 0).
    f.std_gain = dt > 0.0 ? 0.5 * (1.0 - std::exp(-dt / tau_.std_scale_tau_s)) : 0.0;
    f.forget = std::exp(-dt / tau_.bank_forget_s);
    f.radii_gain = 1.0 - std::exp(-dt / tau_.radii_tau_s);
    f.cadence_gain = dt > 0.0 ? 1.0 - std::exp(-dt / tau_.cadence_change_tau_s) : 0.0;
    f.cadence_noise_gain = dt > 0.0 ? 1.0 - std::exp(-dt / tau_.cadence_change_noise_tau_s) : 0.0;
    noise_at(f);
    return f;
  }

 private:
  void noise_at(Values& f) const noexcept {
    f.r_vx = meas_.r_vx(f.dt) + extra_vx_;
    f.r_vz = meas_.r_vz(f.dt) + extra_vz_;
    f.info = 2.0 / f.r_vx + 1.0 / f.r_vz;
  }

  TimeConstants tau_;
  MeasurementNoise meas_;
  Values values_;
  double extra_vx_ = 0.0, extra_vz_ = 0.0;
};

/// The forecast's factors 1 - exp(-h / tau) of dA0 and dw at the horizons h of the last calls, kept
/// by a caller that forecasts again and again: the online carry's horizon is the time since the
/// sample plus constant delays, and with regular timestamps it takes a few dozen values in turn (at
/// 30 Hz nearly always the same, at 60-100 Hz some 90 % of the calls hit a slot). Direct-mapped by the
/// bits of h, reused only for the same bits: the factors as computed. One per filter (its time constants).
class HorizonDecay {
 public:
  /// The factors at h_s from the cache, or computed and kept.
  void at(double h_s, double accel_tau_s, double rate_tau_s, double& ea, double& eb) noexcept {
    std::uint64_t bits;
    std::memcpy(&bits, &h_s, sizeof bits);
    Slot& s = slots_[(bits * 0x9E3779B97F4A7C15ull) >> (64 - kLogSlots)];  // Fibonacci hashing
    if (s.h_bits != bits) {
      s.h_bits = bits;
      s.accel = -std::expm1(-h_s / accel_tau_s);
      s.rate = -std::expm1(-h_s / rate_tau_s);
    }
    ea = s.accel;
    eb = s.rate;
  }

 private:
  static constexpr int kLogSlots = 6;
  struct Slot {
    std::uint64_t h_bits = ~std::uint64_t{0};  ///< a NaN's bits (then the factors are NaN, as computed)
    double accel = std::numeric_limits<double>::quiet_NaN(), rate = std::numeric_limits<double>::quiet_NaN();
  };
  Slot slots_[1 << kLogSlots];
};

}  // namespace yoyogait::gait
