/// @file estimator.hpp
/// @brief The online gait estimator: the default gait filter (gait_filter.hpp) or the paper's
/// EKF (eq. 5-9), heuristic filter (eq. 11-12) and reconstruction (eq. 13-14), chosen by
/// EstimatorConfig::algorithm.
#pragma once

#include <cmath>
#include <cstddef>
#include <cstdint>
#include <stdexcept>

#include "yoyogait/config.hpp"
#include "yoyogait/ekf.hpp"
#include "yoyogait/gait_filter.hpp"
#include "yoyogait/heuristics.hpp"
#include "yoyogait/math.hpp"
#include "yoyogait/state.hpp"

namespace yoyogait {

/// What a step did with its sample.
enum class Status : std::uint8_t {
  kUpdated = 0,            ///< prediction and update
  kRejectedNonFinite = 1,  ///< the sample had a NaN or infinity: prediction only
  kRejectedNumerical = 2,  ///< the update would have made the state non-finite: prediction only
  kRejectedOutOfRange = 3,  ///< |v| above EstimatorConfig::max_abs_velocity_mps: prediction only
  kRejectedOutlier = 4,     ///< gait filter: a channel failed the innovation gate and was not used
};

/// One estimate, after the sample of step k. Physical units beside the paper's.
///
/// Every field is filled by both algorithms. Where the two differ, the comment says "paper:" for
/// Algorithm::kPaper and "gait:" for Algorithm::kGaitFilter (the default).
struct Estimate {
  /// paper: posterior x(k) of eq. 5. gait: the same form, [X1, X2, w T, A0] (the forward phasor,
  /// the frequency in rad/sample at the nominal T = sample_time_s, the bias).
  State state;
  /// gait: the state [X1, X2, Z1, Z2, w, A0, dA0, dw] (gait::Index). paper: eq. 5 in that form,
  /// [x1, x2, -x2, x1, x3 / T, x4, 0, 0] (v_z = -x2 = Z1; the frequency signed, as the filter has it).
  GaitState gait_state{};
  double vx_hat_mps = 0.0;         ///< reconstructed v_x: paper eq. 13; gait A0 + X1 (standing: A0)
  double vz_hat_mps = 0.0;         ///< reconstructed v_z: paper eq. 14; gait Z1 (standing: 0)
  double R_hat_mps = 0.0;          ///< R_hat(k) of eq. 11 in the paper's unit (R/T); gait: R_m / T
  double r_hat_mps = 0.0;          ///< r_hat(k) of eq. 12 in the paper's unit (r/T); gait: r_m / T
  double R_m = 0.0;                ///< R [m]: paper T R_hat; gait A0 / w low-passed while walking
  double r_m = 0.0;                ///< r [m]: paper T r_hat; gait |Z| / w low-passed while walking
  double omega_rad_s = 0.0;        ///< step angular frequency [rad/s]: paper x3 / T (signed); gait w (> 0)
  double step_frequency_hz = 0.0;  ///< omega_rad_s / 2 pi [Hz]
  double step_frequency_std_hz = 0.0;  ///< paper sqrt(P33) / (2 pi T); gait sqrt(lambda P_ww) / 2 pi [Hz]
  double speed_mps = 0.0;          ///< forward speed without the oscillation: paper R_hat x3 = R omega; gait A0 [m/s]
  double speed_std_mps = 0.0;      ///< paper sqrt(P44); gait sqrt(lambda P_A0A0 + speed_std_floor^2) [m/s]
  double A0_mps = 0.0;             ///< bias of v_x: paper x4; gait A0 [m/s]
  double A1_mps = 0.0;             ///< amplitude of the forward oscillation: paper |(x1, x2)|; gait |X| [m/s]
  double vx_hat_h2_mps = 0.0;      ///< gait: vx_hat with the second harmonic; paper: vx_hat [m/s]
  double vz_hat_h2_mps = 0.0;      ///< gait: vz_hat with the second harmonic; paper: vz_hat [m/s]
  double std_scale = 1.0;          ///< gait: lambda, the scale of the reported standard deviations; paper: 1
  Status status = Status::kUpdated;
  bool parameters_updated = false;  ///< paper: eq. 11-12 took the update branch; gait: R, r were updated (walking)
  bool walking = true;              ///< gait: the walking/standing detector; paper: always true
  bool acquiring = false;           ///< gait: the start-up bank is running; paper: always false

  // Derived from gait_state on demand, so that a step pays for no atan2 nobody reads and the
  // struct stays small enough (<= 256 bytes) to be copied without a string instruction.

  /// Amplitude of the vertical oscillation |Z| [m/s] (paper: A1).
  double amp_z_mps() const noexcept {
    return std::sqrt(gait_state[gait::kZ1] * gait_state[gait::kZ1] + gait_state[gait::kZ2] * gait_state[gait::kZ2]);
  }
  /// Phase of the forward oscillation relative to the vertical one, in [-pi, pi], counted in the
  /// direction of the gait phase: the Yoyo model (eq. 3-4) has -pi/2, real walking about +pi/2.
  /// 0 where |X| or |Z| is at most 1e-9 m/s (no oscillation, no relation; e.g. while standing).
  /// (paper: -pi/2 for x3 >= 0, +pi/2 for x3 < 0: the mirror image that a negative frequency fits.)
  double phase_x_rel_z_rad() const noexcept {
    const GaitState& x = gait_state;
    const double ax2 = x[gait::kX1] * x[gait::kX1] + x[gait::kX2] * x[gait::kX2];
    if (!(ax2 > 1e-18 && amp_z_mps() > 1e-9)) return 0.0;
    const double a = std::atan2(x[gait::kX2] * x[gait::kZ1] - x[gait::kX1] * x[gait::kZ2],
                                x[gait::kX1] * x[gait::kZ1] + x[gait::kX2] * x[gait::kZ2]);
    return x[gait::kW] >= 0.0 ? a : -a;
  }
  /// Forward amplitude signed by the relation: the projection of X on Z turned by -pi/2 (in the
  /// direction of the gait phase); > 0 the Yoyo relation, < 0 the opposite (real walking) [m/s].
  double signed_amp_x_mps() const noexcept {
    const GaitState& x = gait_state;
    const double az = amp_z_mps();
    if (!(az > 1e-9)) return 0.0;
    const double p = (x[gait::kX1] * x[gait::kZ2] - x[gait::kX2] * x[gait::kZ1]) / az;
    return x[gait::kW] >= 0.0 ? p : -p;
  }
  /// Rate of the step angular frequency dw [rad/s^2] (paper: 0).
  double omega_rate_rad_s2() const noexcept { return gait_state[gait::kDW]; }
  /// Rate of the forward-speed bias dA0 [m/s^2] (paper: 0).
  double accel_mps2() const noexcept { return gait_state[gait::kDA0]; }
};

// A larger Estimate is copied with a string instruction by GCC at -O3, about 30 ns more per step.
static_assert(sizeof(Estimate) <= 256, "keep Estimate within 256 bytes (see the comment above amp_z_mps)");

/// Predicted velocities [m/s].
using Velocity = Reconstruction;

/// The online estimator: the gait filter (EstimatorConfig{}, the default) or the paper's
/// (EstimatorConfig::paper()), chosen by EstimatorConfig::algorithm. step() does no heap allocation
/// and cannot throw; the constructor throws std::invalid_argument for a configuration that
/// EstimatorConfig::validate rejects.
class Estimator {
 public:
  explicit Estimator(const EstimatorConfig& config = EstimatorConfig{})
      : config_(checked(config)), gait_(config_), paper_(config_.algorithm == Algorithm::kPaper) {
    constexpr double kTwoPi = 6.283185307179586476925286766559;
    inv_T_ = 1.0 / config_.sample_time_s;
    inv_two_pi_T_ = 1.0 / (kTwoPi * config_.sample_time_s);
    q_ = {config_.q_oscillation_mps2, config_.q_oscillation_mps2, config_.q_omega_rad2, config_.q_bias_mps2};
    // Popoviciu's inequality: a quantity confined to an interval of width L has a variance of at
    // most L^2 / 4. The velocities x1, x2 (v_z = -x2) and x4 (the cycle mean of v_x) lie within
    // +-max_abs_velocity_mps, as every sample used does; x3 within +-pi rad/sample (Nyquist).
    constexpr double kPi = 3.14159265358979323846264338327950;
    const double v2 = config_.max_abs_velocity_mps * config_.max_abs_velocity_mps;
    max_variance_ = {v2, v2, kPi * kPi, v2};
    P0_ = SymMatrix4(diagonal({config_.p0_oscillation_mps2, config_.p0_oscillation_mps2, config_.p0_omega_rad2,
                               config_.p0_bias_mps2}));
    reset();
  }

  /// Back to the state before the first sample (paper: x(0), P0 and R_hat(0), r_hat(0)).
  void reset() noexcept {
    const double w0 = config_.initial_omega_rad_per_sample;
    // x(0) = [r0 w0, 0, w0, R0 w0] (Sec. IV-B): cosine and sine 90 degrees apart.
    state_.a1_cos() = config_.initial_r_hat_mps * w0;
    state_.a1_sin() = 0.0;
    state_.omega_rad_per_sample() = w0;
    state_.bias_mps() = config_.initial_R_hat_mps * w0;
    P_ = P0_;
    params_ = ParameterFilter(config_.smoothing_window_samples, config_.gate_omega_rad_per_sample,
                              config_.gate_bias_mps, config_.initial_R_hat_mps, config_.initial_r_hat_mps);
    gait_.reset();
    samples_ = 0;
  }

  /// One sample, taken sample_time_s after the previous one.
  /// paper: prediction (eq. 6), update (eq. 9) unless the sample is not finite or out of range,
  /// heuristic filter (eq. 11-12) and reconstruction (eq. 13-14). gait: GaitFilter::step.
  Estimate step(double vx_mps, double vz_mps) noexcept {
    ++samples_;
    if (paper_) return paper_step(vx_mps, vz_mps);
    return gait_estimate(gait_.step(vx_mps, vz_mps));
  }

  /// One sample, taken dt_s [s] after the previous one. gait: every propagation uses dt_s (a
  /// non-finite or negative dt_s leaves the sample unused, kRejectedNonFinite). paper: dt_s is not
  /// used; the paper's filter works per sample at the nominal T (resample irregular data first).
  Estimate step(double vx_mps, double vz_mps, double dt_s) noexcept {
    ++samples_;
    if (paper_) return paper_step(vx_mps, vz_mps);
    return gait_estimate(gait_.step(vx_mps, vz_mps, dt_s));
  }

  /// step() over n samples; out[i] is the estimate after sample i. Same results as n calls of step().
  /// dt_s: the time since the previous sample of each one [s], or nullptr for sample_time_s.
  void run(const double* vx_mps, const double* vz_mps, std::size_t n, Estimate* out,
           const double* dt_s = nullptr) noexcept {
    if (dt_s) {
      for (std::size_t i = 0; i < n; ++i) out[i] = step(vx_mps[i], vz_mps[i], dt_s[i]);
    } else {
      for (std::size_t i = 0; i < n; ++i) out[i] = step(vx_mps[i], vz_mps[i]);
    }
  }

  /// Velocities predicted horizon_samples (of sample_time_s) ahead of the last sample.
  /// paper: eq. 13-14 with the phase advanced by eq. 6 and the parameters held. gait: the phasors
  /// turned by w h + dw h^2 / 2, A0 held, second harmonics added (GaitFilter::predict).
  Velocity predict_ahead(double horizon_samples) const noexcept {
    if (!paper_) {
      const GaitFilter::Prediction p = gait_.predict(horizon_samples * config_.sample_time_s);
      return Velocity{p.vx_mps, p.vz_mps};
    }
    const double w = state_.omega_rad_per_sample();
    double s, c;
    sincos(w * horizon_samples, s, c);
    const double x1 = state_.a1_cos() * c - state_.a1_sin() * s;
    const double x2 = state_.a1_cos() * s + state_.a1_sin() * c;
    return reconstruct(params_.R_hat_mps(), params_.r_hat_mps(), x1, x2, w, std::sqrt(x1 * x1 + x2 * x2));
  }

  const EstimatorConfig& config() const noexcept { return config_; }
  Algorithm algorithm() const noexcept { return config_.algorithm; }
  /// paper: x(k) of eq. 5. gait: [X1, X2, w T, A0] (as Estimate::state).
  State state() const noexcept {
    if (paper_) return state_;
    const GaitState& x = gait_.state();
    return State{{x[gait::kX1], x[gait::kX2], x[gait::kW] * config_.sample_time_s, x[gait::kA0]}};
  }
  /// paper: P (4x4) of eq. 5. gait: the covariance of the same 4-vector [X1, X2, w T, A0].
  Matrix4 covariance() const noexcept {
    if (paper_) return P_.dense();
    const GaitMatrix G = gait_.covariance();
    const std::size_t idx[4] = {gait::kX1, gait::kX2, gait::kW, gait::kA0};
    const double scale[4] = {1.0, 1.0, config_.sample_time_s, 1.0};
    Matrix4 P{};
    for (std::size_t i = 0; i < 4; ++i)
      for (std::size_t j = 0; j < 4; ++j) P[i][j] = scale[i] * scale[j] * G[idx[i]][idx[j]];
    return P;
  }
  /// gait: the state x (gait::Index) of the active EKF. paper: zeros.
  GaitState gait_state() const noexcept { return paper_ ? GaitState{} : gait_.state(); }
  /// gait: the covariance (8x8) of the active EKF. paper: zeros.
  GaitMatrix gait_covariance() const noexcept { return paper_ ? GaitMatrix{} : gait_.covariance(); }
  std::size_t sample_count() const noexcept { return samples_; }

 private:
  static const EstimatorConfig& checked(const EstimatorConfig& c) {
    if (const char* error = c.validate()) throw std::invalid_argument(error);
    return c;
  }

  YOYOGAIT_ALWAYS_INLINE Estimate paper_step(double vx_mps, double vz_mps) noexcept {
    // The prediction goes to scratch members and the update back into state_, P_ (out of place,
    // see predict); a sample that is not used leaves the prediction as the posterior.
    predict(state_, P_, q_, pred_state_, pred_P_);
    // The covariance guard (docs/paper_estimator.md): two tests, whose repairs walking data never need.
    if (!within_variance_bounds(pred_P_, max_variance_)) bound_prediction();
    Status status = Status::kUpdated;
    if (!(std::isfinite(vx_mps) && std::isfinite(vz_mps))) {
      status = Status::kRejectedNonFinite;
    } else if (!(std::fabs(vx_mps) <= config_.max_abs_velocity_mps && std::fabs(vz_mps) <= config_.max_abs_velocity_mps)) {
      status = Status::kRejectedOutOfRange;
    } else if (!update(pred_state_, pred_P_, Measurement{vx_mps, vz_mps}, config_.v_vx_mps2, config_.v_vz_mps2, state_,
                       P_)) {
      status = Status::kRejectedNumerical;
    }
    if (status != Status::kUpdated) {
      state_ = pred_state_;
      P_ = pred_P_;
    }
    if (!positive_definite(P_)) guard_covariance(status, vx_mps, vz_mps);
    const double x1 = state_.a1_cos(), x2 = state_.a1_sin(), w = state_.omega_rad_per_sample();
    const double a1 = sqrt1(x1 * x1 + x2 * x2);
    const bool opened = params_.update(w, state_.bias_mps(), a1);
    return make_estimate(status, opened, a1);
  }

  // The guard's cold paths (docs/paper_estimator.md, "Covariance guard").

  /// A prediction with a variance beyond its bound: bounded by bound_variances (correlations kept);
  /// a prediction that is not finite (possible only from an absurd state) restarts from P0.
  YOYOGAIT_COLD void bound_prediction() noexcept {
    Matrix4 P = pred_P_.dense();
    for (const auto& row : P)
      for (double v : row)
        if (!std::isfinite(v)) {
          pred_P_ = P0_;
          return;
        }
    bound_variances(P, max_variance_);
    pred_P_ = SymMatrix4(P);
  }

  /// P_ failed positive_definite. After an update: the prediction is made positive definite if it
  /// is not, and the update is recomputed in the Joseph form (the same equations); whatever is
  /// still not positive definite is replaced by the nearest matrix that is.
  YOYOGAIT_COLD void guard_covariance(Status& status, double vx_mps, double vz_mps) noexcept {
    if (status == Status::kUpdated) {
      if (!positive_definite(pred_P_)) restore(pred_P_);
      if (!joseph_update(pred_state_, pred_P_, Measurement{vx_mps, vz_mps}, config_.v_vx_mps2, config_.v_vz_mps2,
                         state_, P_)) {
        state_ = pred_state_;
        P_ = pred_P_;
        status = Status::kRejectedNumerical;
      }
    }
    if (!positive_definite(P_)) restore(P_);
  }

  /// The nearest positive definite matrix (covariance_guard.hpp); P0 if P has nothing to keep.
  void restore(SymMatrix4& P) const noexcept {
    Matrix4 d = P.dense();
    P = nearest_positive_definite(d) ? SymMatrix4(d) : P0_;
  }

  // Both builders initialise every field in declaration order: a default-constructed Estimate
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
        /*R_m=*/config_.sample_time_s * R_hat,
        /*r_m=*/config_.sample_time_s * r_hat,
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

  Estimate gait_estimate(GaitFilter::Outcome outcome) const noexcept {
    using namespace gait;
    const GaitFilter::Output o = gait_.output();
    const GaitState& x = o.x;
    return Estimate{
        /*state=*/State{{x[kX1], x[kX2], x[kW] * config_.sample_time_s, x[kA0]}},
        /*gait_state=*/x,
        /*vx_hat_mps=*/o.vx_hat_mps,
        /*vz_hat_mps=*/o.vz_hat_mps,
        /*R_hat_mps=*/o.R_m * inv_T_,
        /*r_hat_mps=*/o.r_m * inv_T_,
        /*R_m=*/o.R_m,
        /*r_m=*/o.r_m,
        /*omega_rad_s=*/x[kW],
        /*step_frequency_hz=*/x[kW] * 0.15915494309189533576888376337251,  // w / 2 pi
        /*step_frequency_std_hz=*/o.step_frequency_std_hz,
        /*speed_mps=*/x[kA0],
        /*speed_std_mps=*/o.speed_std_mps,
        /*A0_mps=*/x[kA0],
        /*A1_mps=*/o.amp_x_mps,
        /*vx_hat_h2_mps=*/o.vx_hat_h2_mps,
        /*vz_hat_h2_mps=*/o.vz_hat_h2_mps,
        /*std_scale=*/o.std_scale,
        /*status=*/to_status(outcome),
        /*parameters_updated=*/o.radii_updated,
        /*walking=*/o.walking,
        /*acquiring=*/o.acquiring,
    };
  }

  static Status to_status(GaitFilter::Outcome outcome) noexcept {
    switch (outcome) {
      case GaitFilter::Outcome::kOk: return Status::kUpdated;
      case GaitFilter::Outcome::kNonFinite: return Status::kRejectedNonFinite;
      case GaitFilter::Outcome::kOutOfRange: return Status::kRejectedOutOfRange;
      case GaitFilter::Outcome::kOutlier: return Status::kRejectedOutlier;
      case GaitFilter::Outcome::kNumerical: return Status::kRejectedNumerical;
    }
    return Status::kRejectedNumerical;
  }

  EstimatorConfig config_;
  GaitFilter gait_;
  bool paper_ = false;
  std::array<double, kStateDim> q_{};
  double inv_T_ = 25.0, inv_two_pi_T_ = 1.0;
  std::array<double, kStateDim> max_variance_{};  // the guard's variance bounds
  SymMatrix4 P0_;
  State state_;
  SymMatrix4 P_;
  State pred_state_;     // the prediction of the current step (scratch)
  SymMatrix4 pred_P_;
  ParameterFilter params_;
  std::size_t samples_ = 0;
};

}  // namespace yoyogait
