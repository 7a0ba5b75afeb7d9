/// @file estimator.hpp
/// @brief The online gait estimator: EKF (eq. 5-9), heuristic filter (eq. 11-12), reconstruction (eq. 13-14).
#pragma once

#include <cmath>
#include <cstddef>
#include <cstdint>
#include <stdexcept>

#include "yoyogait/config.hpp"
#include "yoyogait/ekf.hpp"
#include "yoyogait/heuristics.hpp"
#include "yoyogait/state.hpp"

namespace yoyogait {

/// What a step did with its sample.
enum class Status : std::uint8_t {
  kUpdated = 0,            ///< prediction and update
  kRejectedNonFinite = 1,  ///< the sample had a NaN or infinity: prediction only
  kRejectedNumerical = 2,  ///< the update would have made the state non-finite: prediction only
  kRejectedOutOfRange = 3,  ///< |v| above EstimatorConfig::max_abs_velocity_mps: prediction only
};

/// One estimate, after the sample of step k. Physical units beside the paper's.
struct Estimate {
  State state;                     ///< posterior x(k) of eq. 5
  double vx_hat_mps = 0.0;         ///< reconstructed v_x, eq. 13
  double vz_hat_mps = 0.0;         ///< reconstructed v_z, eq. 14
  double R_hat_mps = 0.0;          ///< R_hat(k) of eq. 11 in the paper's unit (R/T)
  double r_hat_mps = 0.0;          ///< r_hat(k) of eq. 12 in the paper's unit (r/T)
  double R_m = 0.0;                ///< R = T R_hat [m]
  double r_m = 0.0;                ///< r = T r_hat [m]
  double omega_rad_s = 0.0;        ///< x3 / T [rad/s], signed as the filter has it
  double step_frequency_hz = 0.0;  ///< x3 / (2 pi T) [Hz], signed
  double step_frequency_std_hz = 0.0;  ///< sqrt(P33) / (2 pi T) [Hz]
  double speed_mps = 0.0;          ///< forward speed without the oscillation, R_hat x3 = R omega [m/s]
  double speed_std_mps = 0.0;      ///< sqrt(P44), the uncertainty of the bias A0 [m/s]
  double A0_mps = 0.0;             ///< bias x4 [m/s]
  double A1_mps = 0.0;             ///< amplitude |(x1, x2)| [m/s]
  Status status = Status::kUpdated;
  bool parameters_updated = false;  ///< eq. 11-12 took the update branch at this step
};

/// Predicted velocities [m/s].
using Velocity = Reconstruction;

/// The online estimator of the paper. step() does no heap allocation and cannot throw; the
/// constructor throws std::invalid_argument for a configuration that EstimatorConfig::validate rejects.
class Estimator {
 public:
  explicit Estimator(const EstimatorConfig& config = EstimatorConfig::paper()) : config_(config) {
    if (const char* error = config_.validate()) throw std::invalid_argument(error);
    constexpr double kTwoPi = 6.283185307179586476925286766559;
    inv_T_ = 1.0 / config_.sample_time_s;
    inv_two_pi_T_ = 1.0 / (kTwoPi * config_.sample_time_s);
    q_ = {config_.q_oscillation_mps2, config_.q_oscillation_mps2, config_.q_omega_rad2, config_.q_bias_mps2};
    reset();
  }

  /// Back to x(0), P0 and R_hat(0), r_hat(0): the state before the first sample.
  void reset() noexcept {
    const double w0 = config_.initial_omega_rad_per_sample;
    // x(0) = [r0 w0, 0, w0, R0 w0] (Sec. IV-B): cosine and sine 90 degrees apart.
    state_.a1_cos() = config_.initial_r_hat_mps * w0;
    state_.a1_sin() = 0.0;
    state_.omega_rad_per_sample() = w0;
    state_.bias_mps() = config_.initial_R_hat_mps * w0;
    P_ = diagonal({config_.p0_oscillation_mps2, config_.p0_oscillation_mps2, config_.p0_omega_rad2,
                   config_.p0_bias_mps2});
    params_ = ParameterFilter(config_.smoothing_window_samples, config_.gate_omega_rad_per_sample,
                              config_.gate_bias_mps, config_.initial_R_hat_mps, config_.initial_r_hat_mps);
    samples_ = 0;
  }

  /// One sample k: prediction (eq. 6), update (eq. 9) unless the sample is not finite or out of range,
  /// heuristic filter (eq. 11-12) and reconstruction (eq. 13-14).
  Estimate step(double vx_mps, double vz_mps) noexcept {
    predict(state_, P_, q_);
    Status status = Status::kUpdated;
    if (!(std::isfinite(vx_mps) && std::isfinite(vz_mps))) {
      status = Status::kRejectedNonFinite;
    } else if (!(std::fabs(vx_mps) <= config_.max_abs_velocity_mps && std::fabs(vz_mps) <= config_.max_abs_velocity_mps)) {
      status = Status::kRejectedOutOfRange;
    } else if (!update(state_, P_, Measurement{vx_mps, vz_mps}, config_.v_vx_mps2, config_.v_vz_mps2)) {
      status = Status::kRejectedNumerical;
    }
    ++samples_;
    const double x1 = state_.a1_cos(), x2 = state_.a1_sin();
    const double a1 = std::sqrt(x1 * x1 + x2 * x2);
    const bool opened = params_.update(state_.omega_rad_per_sample(), state_.bias_mps(), a1);
    return make_estimate(status, opened, a1);
  }

  /// step() over n samples; out[i] is the estimate after sample i. Same results as n calls of step().
  void run(const double* vx_mps, const double* vz_mps, std::size_t n, Estimate* out) noexcept {
    for (std::size_t i = 0; i < n; ++i) out[i] = step(vx_mps[i], vz_mps[i]);
  }

  /// Velocities predicted horizon_samples ahead of the last sample: eq. 13-14 with the phase
  /// advanced by eq. 6 and the parameters held.
  Velocity predict_ahead(double horizon_samples) const noexcept {
    const double w = state_.omega_rad_per_sample();
    double s, c;
    sincos(w * horizon_samples, s, c);
    const double x1 = state_.a1_cos() * c - state_.a1_sin() * s;
    const double x2 = state_.a1_cos() * s + state_.a1_sin() * c;
    return reconstruct(params_.R_hat_mps(), params_.r_hat_mps(), x1, x2, w, std::sqrt(x1 * x1 + x2 * x2));
  }

  const EstimatorConfig& config() const noexcept { return config_; }
  const State& state() const noexcept { return state_; }
  const Matrix4& covariance() const noexcept { return P_; }
  std::size_t sample_count() const noexcept { return samples_; }

 private:
  Estimate make_estimate(Status status, bool opened, double a1) const noexcept {
    const double x1 = state_.a1_cos(), x2 = state_.a1_sin(), w = state_.omega_rad_per_sample();
    Estimate e;
    e.state = state_;
    e.R_hat_mps = params_.R_hat_mps();
    e.r_hat_mps = params_.r_hat_mps();
    const Reconstruction v = reconstruct(e.R_hat_mps, e.r_hat_mps, x1, x2, w, a1);
    e.vx_hat_mps = v.vx_mps;
    e.vz_hat_mps = v.vz_mps;
    e.R_m = config_.sample_time_s * e.R_hat_mps;
    e.r_m = config_.sample_time_s * e.r_hat_mps;
    e.omega_rad_s = w * inv_T_;
    e.step_frequency_hz = w * inv_two_pi_T_;
    e.step_frequency_std_hz = std::sqrt(P_[kOmega][kOmega]) * inv_two_pi_T_;
    e.speed_mps = e.R_hat_mps * w;
    e.speed_std_mps = std::sqrt(P_[kBias][kBias]);
    e.A0_mps = state_.bias_mps();
    e.A1_mps = a1;
    e.status = status;
    e.parameters_updated = opened;
    return e;
  }

  EstimatorConfig config_;
  std::array<double, kStateDim> q_{};
  double inv_T_ = 25.0, inv_two_pi_T_ = 1.0;
  State state_;
  Matrix4 P_{};
  ParameterFilter params_;
  std::size_t samples_ = 0;
};

}  // namespace yoyogait
