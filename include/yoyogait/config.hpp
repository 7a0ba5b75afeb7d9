/// @file config.hpp
/// @brief The one parameter struct of the estimator, with a unit on every field.
#pragma once

#include <cmath>
#include <cstddef>

namespace yoyogait {

/// Largest smoothing window n of eq. 11-12; the window lives in a fixed buffer so a step never allocates.
inline constexpr std::size_t kMaxSmoothingWindow = 256;

/// Parameters of the estimator. Defaults are the paper's (Sec. IV-B), in the paper's units where
/// it has them: the filter works per sample, so frequencies are in rad/sample and R_hat, r_hat are
/// R/T and r/T (the unit of x4/x3: m/s per rad/sample, i.e. metres per second).
struct EstimatorConfig {
  /// T: time between samples [s]. The paper resamples to 25 Hz.
  double sample_time_s = 0.04;

  /// R_hat(0) = R/T for the average person [m/s]; the paper's "R0 = 2".
  double initial_R_hat_mps = 2.0;
  /// r_hat(0) = r/T [m/s]; the paper's "r0 = 0.2".
  double initial_r_hat_mps = 0.2;
  /// w(0) [rad/sample]; the paper's 0.1 (0.4 Hz at 25 Hz).
  double initial_omega_rad_per_sample = 0.1;

  /// Q11 = Q22: process noise of the oscillation x1, x2 [(m/s)^2].
  double q_oscillation_mps2 = 1e-5;
  /// Q33: process noise of the frequency [(rad/sample)^2].
  double q_omega_rad2 = 1e-3;
  /// Q44: process noise of the bias A0 [(m/s)^2].
  double q_bias_mps2 = 1e-3;
  /// V11: measurement noise of v_x [(m/s)^2].
  double v_vx_mps2 = 1e-2;
  /// V22: measurement noise of v_z [(m/s)^2].
  double v_vz_mps2 = 1e-2;
  /// P0 diagonal for x1, x2 [(m/s)^2], x3 [(rad/sample)^2] and x4 [(m/s)^2]: P0 = I in the paper.
  double p0_oscillation_mps2 = 1.0;
  double p0_omega_rad2 = 1.0;
  double p0_bias_mps2 = 1.0;

  /// n: length of the moving average of eq. 11-12 [samples]; also the number of samples before
  /// R_hat, r_hat may first change (k > n).
  std::size_t smoothing_window_samples = 10;
  /// mu_w: R_hat, r_hat update only while x3 exceeds it [rad/sample].
  double gate_omega_rad_per_sample = 0.1;
  /// mu_A0: ... and while x4 exceeds it [m/s].
  double gate_bias_mps = 0.1;

  /// A sample with |v_x| or |v_z| above this is rejected like a non-finite one [m/s]. Far above any
  /// walking speed, it keeps a corrupt sample from overflowing the covariance at the next prediction.
  double max_abs_velocity_mps = 1000.0;

  /// The paper's estimator exactly as published (Sec. III and IV-B).
  static constexpr EstimatorConfig paper() noexcept { return EstimatorConfig{}; }

  /// nullptr when the configuration is usable, else what is wrong with it.
  const char* validate() const noexcept {
    auto finite = [](double v) { return std::isfinite(v); };
    if (!(finite(sample_time_s) && sample_time_s > 0.0)) return "sample_time_s must be finite and > 0";
    if (!finite(initial_R_hat_mps)) return "initial_R_hat_mps must be finite";
    if (!finite(initial_r_hat_mps)) return "initial_r_hat_mps must be finite";
    if (!finite(initial_omega_rad_per_sample)) return "initial_omega_rad_per_sample must be finite";
    if (!(finite(q_oscillation_mps2) && q_oscillation_mps2 >= 0.0)) return "q_oscillation_mps2 must be finite and >= 0";
    if (!(finite(q_omega_rad2) && q_omega_rad2 >= 0.0)) return "q_omega_rad2 must be finite and >= 0";
    if (!(finite(q_bias_mps2) && q_bias_mps2 >= 0.0)) return "q_bias_mps2 must be finite and >= 0";
    if (!(finite(v_vx_mps2) && v_vx_mps2 > 0.0)) return "v_vx_mps2 must be finite and > 0";
    if (!(finite(v_vz_mps2) && v_vz_mps2 > 0.0)) return "v_vz_mps2 must be finite and > 0";
    if (!(finite(p0_oscillation_mps2) && p0_oscillation_mps2 >= 0.0)) return "p0_oscillation_mps2 must be finite and >= 0";
    if (!(finite(p0_omega_rad2) && p0_omega_rad2 >= 0.0)) return "p0_omega_rad2 must be finite and >= 0";
    if (!(finite(p0_bias_mps2) && p0_bias_mps2 >= 0.0)) return "p0_bias_mps2 must be finite and >= 0";
    if (smoothing_window_samples > kMaxSmoothingWindow) return "smoothing_window_samples must be <= 256";
    if (!finite(gate_omega_rad_per_sample)) return "gate_omega_rad_per_sample must be finite";
    if (!finite(gate_bias_mps)) return "gate_bias_mps must be finite";
    if (!(max_abs_velocity_mps > 0.0 && max_abs_velocity_mps <= 1e100)) return "max_abs_velocity_mps must be in (0, 1e100]";
    return nullptr;
  }
};

}  // namespace yoyogait
