/// @file paper/paper_estimator.hpp
/// @brief The paper's estimator, exactly as published (Sec. III and IV-B): the 4-state EKF
/// (eq. 5-9, paper/ekf.hpp), the heuristic filter of R_hat, r_hat (eq. 11-12) and the reconstruction
/// (eq. 13-14, paper/heuristics.hpp). docs/paper_estimator.md.
#pragma once

#include <array>
#include <cmath>
#include <cstddef>
#include <limits>

#include "yoyogait/config.hpp"
#include "yoyogait/paper/ekf.hpp"
#include "yoyogait/estimate.hpp"
#include "yoyogait/paper/heuristics.hpp"
#include "yoyogait/math.hpp"
#include "yoyogait/paper/state.hpp"

namespace yoyogait::paper {

/// The paper's estimator. Use it through yoyogait::Estimator (EstimatorConfig::paper()); this
/// class is public for tests and for embedding. step() does no heap allocation and cannot throw.
class PaperEstimator {
 public:
  PaperEstimator() noexcept : PaperEstimator(EstimatorConfig::paper()) {}

  /// config must pass EstimatorConfig::validate() (the Estimator checks it); the paper's estimator
  /// reads its section, config.paper_estimator, and the shared fields.
  explicit PaperEstimator(const EstimatorConfig& config) noexcept
      : PaperEstimator(config.paper_estimator, config.sample_time_s, config.max_abs_velocity_mps) {}

  PaperEstimator(const PaperConfig& p, double sample_time_s, double max_abs_velocity_mps) noexcept
      : T_(sample_time_s),
        max_abs_velocity_mps_(max_abs_velocity_mps),
        v_vx_mps2_(p.v_vx_mps2),
        v_vz_mps2_(p.v_vz_mps2),
        initial_R_hat_mps_(p.initial_R_hat_mps),
        initial_r_hat_mps_(p.initial_r_hat_mps),
        initial_omega_(p.initial_omega_rad_per_sample),
        p0_{p.p0_oscillation_mps2, p.p0_oscillation_mps2, p.p0_omega_rad2, p.p0_bias_mps2},
        window_(p.smoothing_window_samples),
        gate_omega_(p.gate_omega_rad_per_sample),
        gate_bias_(p.gate_bias_mps) {
    inv_T_ = 1.0 / T_;
    inv_two_pi_T_ = 1.0 / (kTwoPi * T_);
    q_ = {p.q_oscillation_mps2, p.q_oscillation_mps2, p.q_omega_rad2, p.q_bias_mps2};
    // The guard's variance bounds (docs/paper_estimator.md). Popoviciu's inequality: a quantity
    // confined to an interval of width L has a variance of at most L^2 / 4. The velocities x1, x2
    // (v_z = -x2) and x4 (the cycle mean of v_x) lie within +-max_abs_velocity_mps, as every sample
    // used does; x3 within +-pi rad/sample (beyond, a frequency aliases).
    constexpr double kPi = 0.5 * kTwoPi;
    const double v2 = max_abs_velocity_mps_ * max_abs_velocity_mps_;
    max_variance_ = {v2, v2, kPi * kPi, v2};
    // The certificate's lower bound on the posterior's eigenvalues: P- >= Q gives
    // lambda_min(P+) >= 1 / (1 / q_min + ||H^T V^-1 H||), ||H^T V^-1 H|| <= 2 / V11 + 1 / V22.
    // The update's certificate takes kRoundingMargin / that bound (no bound without process noise).
    const double q_min = detail::py_min(detail::py_min(q_[0], q_[1]), detail::py_min(q_[2], q_[3]));
    const double floor = q_min / (1.0 + q_min * (2.0 / v_vx_mps2_ + 1.0 / v_vz_mps2_));
    cert_scale_ = floor > 0.0 ? kRoundingMargin / floor : std::numeric_limits<double>::infinity();
    reset();
  }

  /// Back to the state before the first sample: x(0), P0 and R_hat(0), r_hat(0).
  void reset() noexcept {
    const double w0 = initial_omega_;
    // x(0) = [r0 w0, 0, w0, R0 w0] (Sec. IV-B): cosine and sine 90 degrees apart.
    state_.a1_cos() = initial_r_hat_mps_ * w0;
    state_.a1_sin() = 0.0;
    state_.omega_rad_per_sample() = w0;
    state_.bias_mps() = initial_R_hat_mps_ * w0;
    P_ = SymMatrix4(diagonal(p0_));
    z_ = Measurement{std::numeric_limits<double>::quiet_NaN(), std::numeric_limits<double>::quiet_NaN()};
    params_ = ParameterFilter(window_, gate_omega_, gate_bias_, initial_R_hat_mps_, initial_r_hat_mps_);
  }

  /// One sample: prediction (eq. 6), update (eq. 9) unless the sample is not finite or out of
  /// range, heuristic filter (eq. 11-12) and reconstruction (eq. 13-14).
  YOYOGAIT_ALWAYS_INLINE Estimate step(double vx_mps, double vz_mps) noexcept {
    // The prediction goes to scratch members and the update back into state_, P_ (out of place,
    // see predict); a sample that is not used leaves the prediction as the posterior.
    // The covariance guard (docs/paper_estimator.md): the prediction tests its variance bounds, the
    // update certifies its result; one branch to the rest, which walking data never need.
    const bool within = predict(state_, P_, q_, max_variance_, pred_state_, pred_P_);
    z_ = Measurement{vx_mps, vz_mps};  // for innovation(), which recomputes from the prediction
    Status status = Status::kUpdated;
    bool certified = false;
    if (!(std::isfinite(vx_mps) && std::isfinite(vz_mps))) {
      status = Status::kRejectedNonFinite;
    } else if (!(std::fabs(vx_mps) <= max_abs_velocity_mps_ && std::fabs(vz_mps) <= max_abs_velocity_mps_)) {
      status = Status::kRejectedOutOfRange;
    } else if (!update(pred_state_, pred_P_, Measurement{vx_mps, vz_mps}, v_vx_mps2_, v_vz_mps2_, cert_scale_,
                       state_, P_, certified)) {
      status = Status::kRejectedNumerical;
    }
    if (status != Status::kUpdated) {
      state_ = pred_state_;
      P_ = pred_P_;
      certified = false;
    }
    if (!(certified & within)) status = settle_covariance(status, within, vx_mps, vz_mps);
    const double x1 = state_.a1_cos(), x2 = state_.a1_sin(), w = state_.omega_rad_per_sample();
    const double a1 = sqrt1(x1 * x1 + x2 * x2);
    const bool opened = params_.update(w, state_.bias_mps(), a1);
    return make_estimate(status, opened, a1);
  }

  /// Velocities predicted horizon_samples ahead of the last sample: eq. 13-14 with the phase
  /// advanced by eq. 6 and the parameters held.
  Reconstruction predict_ahead(double horizon_samples) const noexcept {
    const double w = state_.omega_rad_per_sample();
    double s, c;
    sincos(w * horizon_samples, s, c);
    const double x1 = state_.a1_cos() * c - state_.a1_sin() * s;
    const double x2 = state_.a1_cos() * s + state_.a1_sin() * c;
    return reconstruct(params_.R_hat_mps(), params_.r_hat_mps(), x1, x2, w, std::sqrt(x1 * x1 + x2 * x2));
  }

  /// The innovation z - H x- of the last step at its prediction x-, and the NIS with
  /// S = H P- H^T + V (eq. 9); NaN when the sample was not used (not finite, out of range).
  /// Computed on demand from the prediction, which the step keeps: the step itself pays nothing.
  Innovation innovation() const noexcept {
    Innovation out;
    const double vx = z_.vx_mps, vz = z_.vz_mps;
    if (!(std::isfinite(vx) && std::isfinite(vz) && std::fabs(vx) <= max_abs_velocity_mps_ &&
          std::fabs(vz) <= max_abs_velocity_mps_))
      return out;
    const Measurement h = measure(pred_state_);
    const SymMatrix4& P = pred_P_;
    out.innovation_vx_mps = vx - h.vx_mps;
    out.innovation_vz_mps = vz - h.vz_mps;
    // S = [[s00, -u1], [-u1, s11]] as in update(); nu^T S^-1 nu = nu^T adj(S) nu / det(S).
    const double u1 = P(kSin, kCos) + P(kSin, kBias);
    const double s00 = P(kCos, kCos) + 2.0 * P(kCos, kBias) + P(kBias, kBias) + v_vx_mps2_;
    const double s11 = P(kSin, kSin) + v_vz_mps2_;
    const double y0 = out.innovation_vx_mps, y1 = out.innovation_vz_mps;
    out.nis = (y0 * y0 * s11 + 2.0 * y0 * y1 * u1 + y1 * y1 * s00) / (s00 * s11 - u1 * u1);
    return out;
  }

  /// x(k) of eq. 5.
  const State& state() const noexcept { return state_; }
  /// P (4x4) of eq. 5.
  const SymMatrix4& covariance() const noexcept { return P_; }
  const ParameterFilter& parameters() const noexcept { return params_; }

 private:
  // The guard's cold paths (docs/paper_estimator.md, "Covariance guard").

  /// The rest of the guard, out of line (rare on data: NaN samples). A prediction beyond its variance
  /// bounds is bounded (bound_prediction) and a usable sample's update redone from it; then a
  /// covariance that no update certified is tested, and repaired if it fails (guard_covariance).
  /// Returns the step's status; by value, so that the caller's status stays in a register.
  YOYOGAIT_NOINLINE Status settle_covariance(Status status, bool within, double vx_mps, double vz_mps) noexcept {
    if (!within) {
      bound_prediction();
      state_ = pred_state_;
      P_ = pred_P_;
      if (status == Status::kUpdated || status == Status::kRejectedNumerical) {
        bool certified = false;
        if (update(pred_state_, pred_P_, Measurement{vx_mps, vz_mps}, v_vx_mps2_, v_vz_mps2_, cert_scale_, state_, P_,
                   certified)) {
          status = Status::kUpdated;
          if (certified) return status;
        } else {
          state_ = pred_state_;
          P_ = pred_P_;
          status = Status::kRejectedNumerical;
        }
      }
    }
    return positive_definite(P_) ? status : guard_covariance(status, vx_mps, vz_mps);
  }

  /// A prediction with a variance beyond its bound: bounded by bound_variances (correlations kept);
  /// a prediction that is not finite (possible only from an absurd state) restarts from P0.
  YOYOGAIT_COLD void bound_prediction() noexcept {
    Matrix4 P = pred_P_.dense();
    for (const auto& row : P)
      for (double v : row)
        if (!std::isfinite(v)) {
          pred_P_ = SymMatrix4(diagonal(p0_));
          return;
        }
    bound_variances(P, max_variance_);
    pred_P_ = SymMatrix4(P);
  }

  /// P_ failed positive_definite. After an update: the prediction is made positive definite if it
  /// is not, and the update is recomputed from it in the Joseph form (the same equations); whatever
  /// is still not positive definite is replaced by the nearest matrix that is.
  YOYOGAIT_COLD Status guard_covariance(Status status, double vx_mps, double vz_mps) noexcept {
    if (status == Status::kUpdated) {
      if (!positive_definite(pred_P_)) restore(pred_P_);
      if (!joseph_update(pred_state_, pred_P_, Measurement{vx_mps, vz_mps}, v_vx_mps2_, v_vz_mps2_, state_, P_)) {
        state_ = pred_state_;
        P_ = pred_P_;
        status = Status::kRejectedNumerical;
      }
    }
    if (!positive_definite(P_)) restore(P_);
    return status;
  }

  /// The nearest positive definite matrix (covariance_guard.hpp); P0 if P has nothing to keep.
  void restore(SymMatrix4& P) const noexcept {
    Matrix4 d = P.dense();
    P = nearest_positive_definite(d) ? SymMatrix4(d) : SymMatrix4(diagonal(p0_));
  }

  // The builder initialises every field in declaration order: a default-constructed Estimate
  // would first be zeroed (GCC: a string store) and then overwritten, ~20 ns per step.
  Estimate make_estimate(Status status, bool opened, double a1) const noexcept {
    const double x1 = state_.a1_cos(), x2 = state_.a1_sin(), w = state_.omega_rad_per_sample();
    const double R_hat = params_.R_hat_mps(), r_hat = params_.r_hat_mps();
    const Reconstruction v = reconstruct(R_hat, r_hat, x1, x2, w, a1);
    double sd_omega, sd_bias;
    sqrt2(P_(kOmega, kOmega), P_(kBias, kBias), sd_omega, sd_bias);
    const double omega = w * inv_T_;
    const double A0 = state_.bias_mps();
    return Estimate{
        /*state=*/state_,
        // The same estimate in the gait filter's terms: Z is X turned by +90 degrees (v_z = -x2 = Z1).
        /*gait_state=*/{x1, x2, -x2, x1, omega, A0, 0.0, 0.0},
        /*vx_hat_mps=*/v.vx_mps,
        /*vz_hat_mps=*/v.vz_mps,
        /*R_hat_mps=*/R_hat,
        /*r_hat_mps=*/r_hat,
        /*R_m=*/T_ * R_hat,
        /*r_m=*/T_ * r_hat,
        /*omega_rad_s=*/omega,
        /*step_frequency_hz=*/w * inv_two_pi_T_,
        /*step_frequency_std_hz=*/sd_omega * inv_two_pi_T_,
        /*speed_mps=*/R_hat * w,
        /*speed_std_mps=*/sd_bias,
        /*A0_mps=*/A0,
        /*A1_mps=*/a1,
        /*vx_hat_h2_mps=*/v.vx_mps,
        /*vz_hat_h2_mps=*/v.vz_mps,
        /*std_scale=*/1.0,
        /*status=*/status,
        /*parameters_updated=*/opened,
        /*walking=*/true,
        /*acquiring=*/false,
    };
  }

  // The configuration (Sec. IV-B), as the step reads it.
  double T_ = 0.04, inv_T_ = 25.0, inv_two_pi_T_ = 1.0;
  double max_abs_velocity_mps_ = 1000.0, v_vx_mps2_ = 1e-2, v_vz_mps2_ = 1e-2;
  double initial_R_hat_mps_ = 2.0, initial_r_hat_mps_ = 0.2, initial_omega_ = 0.1;
  std::array<double, kStateDim> q_{}, p0_{};
  std::array<double, kStateDim> max_variance_{};  // the guard's variance bounds
  double cert_scale_ = 0.0;                        // the guard's certificate: margin / eigenvalue bound
  std::size_t window_ = 10;
  double gate_omega_ = 0.1, gate_bias_ = 0.1;
  // The filter.
  State state_;
  SymMatrix4 P_;
  State pred_state_;  // the prediction of the current step (scratch)
  SymMatrix4 pred_P_;
  ParameterFilter params_;
  Measurement z_;  // the last sample, for innovation()
};

}  // namespace yoyogait::paper
