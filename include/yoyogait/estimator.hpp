/// @file estimator.hpp
/// @brief The online gait estimator: one API over the default gait filter (gait/gait_filter.hpp)
/// and the paper's estimator (paper/paper_estimator.hpp), chosen by EstimatorConfig::algorithm.
#pragma once

#include <cstddef>
#include <limits>
#include <new>
#include <stdexcept>
#include <type_traits>

#include "yoyogait/config.hpp"
#include "yoyogait/estimate.hpp"
#include "yoyogait/forecast.hpp"
#include "yoyogait/gait/gait_filter.hpp"
#include "yoyogait/math.hpp"
#include "yoyogait/paper/paper_estimator.hpp"
#include "yoyogait/paper/state.hpp"

namespace yoyogait {

/// The online estimator: the gait filter (EstimatorConfig{}, the default) or the paper's
/// (EstimatorConfig::paper()), chosen by EstimatorConfig::algorithm. step() does no heap allocation
/// and cannot throw; the constructor throws std::invalid_argument for a configuration that
/// EstimatorConfig::validate rejects.
class Estimator {
 public:
  explicit Estimator(const EstimatorConfig& config = EstimatorConfig{})
      : config_(checked(config)),
        gait_(config_),
        paper_(config_),
        is_paper_(config_.algorithm == Algorithm::kPaper),
        inv_T_(1.0 / config_.sample_time_s) {
    reset();
  }

  /// Back to the state before the first sample (paper: x(0), P0 and R_hat(0), r_hat(0)).
  void reset() noexcept {
    paper_.reset();
    gait_.reset();
    samples_ = 0;
  }

  /// One sample, taken sample_time_s after the previous one.
  /// paper: PaperEstimator::step (eq. 6, 9, 11-14). gait: GaitFilter::step.
  YOYOGAIT_ALWAYS_INLINE Estimate step(double vx_mps, double vz_mps) noexcept {
    ++samples_;
    if (is_paper_) return paper_.step(vx_mps, vz_mps);
    return gait_estimate(gait_.step(vx_mps, vz_mps));
  }

  /// One sample, taken dt_s [s] after the previous one. gait: every propagation uses dt_s (a
  /// non-finite or negative dt_s leaves the sample unused, kRejectedNonFinite). paper: dt_s is not
  /// used; the paper's filter works per sample at the nominal T (resample irregular data first).
  YOYOGAIT_ALWAYS_INLINE Estimate step(double vx_mps, double vz_mps, double dt_s) noexcept {
    ++samples_;
    if (is_paper_) return paper_.step(vx_mps, vz_mps);
    return gait_estimate(gait_.step(vx_mps, vz_mps, dt_s));
  }

  /// out = step(vx_mps, vz_mps, dt_s), the estimate built in out itself: an assignment would build
  /// it in a temporary and copy its 232 bytes at every sample.
  YOYOGAIT_ALWAYS_INLINE void step_into(Estimate& out, double vx_mps, double vz_mps, double dt_s) noexcept {
    static_assert(std::is_trivially_destructible<Estimate>::value, "out is reused as storage");
    ::new (static_cast<void*>(&out)) Estimate(step(vx_mps, vz_mps, dt_s));
  }

  /// Variances added to the measurement noise of v_x and v_z from the next sample on [(m/s)^2], and
  /// the v_z variance of the input's noise floor, not walking by itself (gait:
  /// GaitFilter::set_extra_measurement_variance; paper: not used). 0 until set.
  void set_extra_measurement_variance(double vx_m2_per_s2, double vz_m2_per_s2, double noise_sigmas = 0.0,
                                      double floor_vz_m2_per_s2 = 0.0) noexcept {
    if (!is_paper_) gait_.set_extra_measurement_variance(vx_m2_per_s2, vz_m2_per_s2, noise_sigmas, floor_vz_m2_per_s2);
  }

  /// A failed lock found by the caller: the gait filter's acquisition restarts from the next sample
  /// (GaitFilter::reacquire; paper: nothing).
  void reacquire() noexcept {
    if (!is_paper_) gait_.reacquire();
  }
  /// The step frequency f_hz [Hz] with variance var_hz2 [Hz^2] from the caller's evidence: an
  /// observation of the gait filter's frequency (GaitFilter::observe_frequency; paper: nothing).
  void observe_frequency(double f_hz, double var_hz2) noexcept {
    if (!is_paper_) gait_.observe_frequency(f_hz, var_hz2);
  }
  /// The gait filter's lock restarts at f_hz, which the caller's evidence shows (GaitFilter::relock;
  /// paper: nothing).
  void relock(double f_hz) noexcept {
    if (!is_paper_) gait_.relock(f_hz);
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

  /// Velocities predicted horizon_s [s] ahead of the last sample.
  /// paper: eq. 13-14 with the phase advanced by eq. 6 over horizon_s / sample_time_s samples and
  /// the parameters held. gait: the phasors turned by w h + dw h^2 / 2, A0 held, second harmonics
  /// added (GaitFilter::predict; forecast() adds the rate of A0 and the standard deviations).
  Velocity predict_ahead(double horizon_s) const noexcept {
    if (is_paper_) return paper_.predict_ahead(horizon_s / config_.sample_time_s);
    const GaitFilter::Prediction p = gait_.predict(horizon_s);
    return Velocity{p.vx_mps, p.vz_mps};
  }

  /// The model's forecast horizon_s [s] after the last sample (yoyogait::Forecast), rates included,
  /// with standard deviations when with_std. gait: GaitFilter::forecast. paper: predict_ahead's velocities, the phase
  /// advance w h, the stds NaN (the paper's filter has no rates to propagate).
  /// decay: the caller's cache of the gait filter's exp factors (GaitFilter::forecast);
  /// phase_var_scale: the factor on the phase's variance (GaitFilter::forecast).
  Forecast forecast(double horizon_s, bool with_std = true, gait::HorizonDecay* decay = nullptr,
                    double phase_var_scale = 1.0) const noexcept {
    if (!is_paper_)
      return decay ? gait_.forecast(horizon_s, with_std, *decay, phase_var_scale)
                   : gait_.forecast(horizon_s, with_std, phase_var_scale);
    Forecast f;
    const Velocity v = predict_ahead(horizon_s);
    const State x = paper_.state();
    f.vx_mps = v.vx_mps;
    f.vz_mps = v.vz_mps;
    f.omega_rad_s = x.omega_rad_per_sample() * inv_T_;
    f.phase_advance_rad = f.omega_rad_s * horizon_s;
    f.speed_mps = x.bias_mps();
    f.vx_std_mps = f.vz_std_mps = with_std ? std::numeric_limits<double>::quiet_NaN() : 0.0;
    return f;
  }

  /// Diagnostics of the last step: the innovation of each channel and the NIS (yoyogait::Innovation).
  /// Read on demand; step() does not compute them.
  Innovation innovation() const noexcept { return is_paper_ ? paper_.innovation() : gait_.innovation(); }

  const EstimatorConfig& config() const noexcept { return config_; }
  Algorithm algorithm() const noexcept { return config_.algorithm; }
  /// paper: x(k) of eq. 5. gait: [X1, X2, w T, A0] (as Estimate::state).
  State state() const noexcept {
    if (is_paper_) return paper_.state();
    const GaitState& x = gait_.state();
    return State{{x[gait::kX1], x[gait::kX2], x[gait::kW] * config_.sample_time_s, x[gait::kA0]}};
  }
  /// paper: P (4x4) of eq. 5. gait: the covariance of the same 4-vector [X1, X2, w T, A0].
  Matrix4 covariance() const noexcept {
    if (is_paper_) return paper_.covariance().dense();
    const GaitMatrix G = gait_.covariance();
    const std::size_t idx[paper::kStateDim] = {gait::kX1, gait::kX2, gait::kW, gait::kA0};
    const double scale[paper::kStateDim] = {1.0, 1.0, config_.sample_time_s, 1.0};
    Matrix4 P{};
    for (std::size_t i = 0; i < paper::kStateDim; ++i)
      for (std::size_t j = 0; j < paper::kStateDim; ++j) P[i][j] = scale[i] * scale[j] * G[idx[i]][idx[j]];
    return P;
  }
  /// gait: the state x (gait::Index) of the active EKF. paper: zeros.
  GaitState gait_state() const noexcept { return is_paper_ ? GaitState{} : gait_.state(); }
  /// gait: the covariance (8x8) of the active EKF. paper: zeros.
  GaitMatrix gait_covariance() const noexcept { return is_paper_ ? GaitMatrix{} : gait_.covariance(); }
  /// gait: one element (gait::Index) of the active EKF's covariance, without copying it. paper: 0.
  double gait_covariance(std::size_t i, std::size_t j) const noexcept {
    return is_paper_ ? 0.0 : gait_.covariance(i, j);
  }
  std::size_t sample_count() const noexcept { return samples_; }

 private:
  static const EstimatorConfig& checked(const EstimatorConfig& c) {
    if (const char* error = c.validate()) throw std::invalid_argument(error);
    return c;
  }

  // Initialises every field in declaration order: a default-constructed Estimate would first be
  // zeroed (GCC: a string store) and then overwritten, ~20 ns per step.
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
        /*step_frequency_hz=*/x[kW] * kInvTwoPi,
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
  paper::PaperEstimator paper_;
  bool is_paper_ = false;
  double inv_T_ = 25.0;
  std::size_t samples_ = 0;
};

}  // namespace yoyogait
