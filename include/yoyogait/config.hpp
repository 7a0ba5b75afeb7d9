/// @file config.hpp
/// @brief The one parameter struct of the estimator, with a unit on every field.
#pragma once

#include <array>
#include <cmath>
#include <cstddef>
#include <cstdint>

namespace yoyogait {

/// Largest smoothing window n of eq. 11-12; the window lives in a fixed buffer so a step never allocates.
inline constexpr std::size_t kMaxSmoothingWindow = 256;
/// Largest start-up bank of the gait filter (EstimatorConfig::bank_f_hz).
inline constexpr std::size_t kMaxBankSize = 8;
/// Largest ring buffer of the gait filter's spectral initialisation [samples].
inline constexpr std::size_t kMaxSpectralBuffer = 256;
/// Largest number of frequencies of the spectral grid search (start-up work, bounded).
inline constexpr std::size_t kMaxSpectralGrid = 10000;

/// Which estimator EstimatorConfig describes.
enum class Algorithm : std::uint8_t {
  kPaper = 0,       ///< the paper's 4-state EKF and heuristics, exactly as published (ekf.hpp, heuristics.hpp)
  kGaitFilter = 1,  ///< the default: the dual-phasor gait filter (gait_filter.hpp, docs/default_estimator.md)
};

/// Parameters of the estimator, both algorithms in one struct.
///
/// `EstimatorConfig{}` is the default estimator (Algorithm::kGaitFilter with its tuned values);
/// `EstimatorConfig::paper()` is the paper's estimator (Sec. IV-B). The paper's fields are in the
/// paper's units: its filter works per sample, so its frequencies are in rad/sample and R_hat, r_hat
/// are R/T and r/T (m/s). The gait filter's fields are in SI units per second (noise densities are
/// multiplied by the actual time step); each says its unit in its name. Each algorithm ignores the
/// other's fields; `sample_time_s` and `max_abs_velocity_mps` are shared.
struct EstimatorConfig {
  /// The estimator to run. The paper's fields below apply to kPaper, the gait filter's to kGaitFilter.
  Algorithm algorithm = Algorithm::kGaitFilter;

  /// T: time between samples [s]. The paper resamples to 25 Hz; the gait filter uses it as the
  /// nominal time step, when step() is called without one.
  double sample_time_s = 0.04;

  // ------------------------------------------------------------------ the paper (Algorithm::kPaper)

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
  /// Both algorithms (the gait filter drops only the channel that is out of range).
  double max_abs_velocity_mps = 1000.0;

  // ------------------------------------------------------- the gait filter (Algorithm::kGaitFilter)
  // State x = [X1, X2, Z1, Z2, w, A0, dA0, dw] (docs/default_estimator.md, sec. 2).

  /// Bounds of the step frequency: w is kept in [2 pi f_min, 2 pi f_max] [Hz]; 0 is excluded.
  double f_min_hz = 0.6;
  double f_max_hz = 3.5;

  /// Start frequencies of the start-up bank of EKFs [Hz]; the first bank_size entries are used.
  /// (Python: one tuple, bank_f_hz, whose length is bank_size.)
  std::array<double, kMaxBankSize> bank_f_hz{0.9, 1.3, 1.8, 2.3, 2.8, 0.0, 0.0, 0.0};
  /// Number of bank members (1..kMaxBankSize) [1].
  std::size_t bank_size = 5;
  /// Walking time after which the bank collapses to its most likely member [s].
  double bank_window_s = 1.5;
  /// Memory of each member's innovation log-likelihood (exponential forgetting) [s].
  double bank_forget_s = 1.5;
  /// Typical step frequency: the member nearest to it starts with the log-prior bonus [Hz].
  double bank_prior_f_hz = 1.8;
  /// Log-prior bonus of that member (on re-acquisition: of the member at the last frequency) [nats].
  double bank_prior_bonus_nats = 2.0;
  /// Initial standard deviations of each member: frequency [Hz], phasors [m/s], A0 [m/s],
  /// dA0 [m/s^2], dw [rad/s^2].
  double p0_f_std_hz = 0.25;
  double p0_phasor_std_mps = 0.3;
  double p0_speed_std_mps = 0.3;
  double p0_accel_std_mps2 = 0.5;
  double p0_omega_rate_std_rad_s2 = 0.05;

  /// Spectral initialisation: after spectral_init_s of walking, a least-squares frequency grid
  /// search over the last spectral_buffer_samples samples seeds the least likely bank member.
  bool spectral_init = true;
  double spectral_init_s = 1.0;                 ///< [s]
  std::size_t spectral_buffer_samples = 40;     ///< ring buffer length (<= kMaxSpectralBuffer) [samples]
  double spectral_grid_step_hz = 0.025;         ///< grid step over [f_min_hz, f_max_hz] [Hz]
  double spectral_f_std_hz = 0.08;              ///< frequency std given to the seeded member [Hz]
  double spectral_phasor_std_mps = 0.05;        ///< phasor and A0 std given to the seeded member [m/s]

  /// Process noise densities, multiplied by the time step (sec. 2.2).
  double q_phasor_m2_per_s3 = 2e-3;   ///< independent drift of each phasor entry [(m/s)^2/s]
  double q_phase_rad2_per_s = 0.05;   ///< common gait-phase jitter, rotates X and Z together [rad^2/s]
  double q_omega_rad2_per_s3 = 0.05;  ///< random walk of w [(rad/s)^2/s]
  /// Frequency-rate state dw (tracks cadence ramps); false keeps dw at zero.
  bool use_omega_rate = true;
  double q_omega_rate_lo_rad2_per_s5 = 0.01;  ///< noise of dw while no trend is seen [(rad/s^2)^2/s]
  double q_omega_rate_hi_rad2_per_s5 = 2.0;   ///< ... and once |dw_lp| reaches omega_rate_ref_rad_s2
  double omega_rate_ref_rad_s2 = 0.2;         ///< trend level of the low-passed rate [rad/s^2]
  double omega_rate_lp_tau_s = 1.5;           ///< low-pass of dw for the trend test (0: none) [s]
  double omega_rate_tau_s = 3.0;              ///< dw decays with this time constant [s]
  double q_speed_m2_per_s3 = 1e-3;            ///< random walk of A0 [(m/s)^2/s]
  double q_accel_m2_per_s5 = 1e-2;            ///< random walk of dA0 [(m/s^2)^2/s]
  double accel_tau_s = 1.0;                   ///< dA0 decays with this time constant [s]

  /// Second harmonic of each channel by a cascaded 2-state Kalman filter (sec. 2.1).
  bool use_harmonic = true;
  double p0_harmonic_std_mps = 0.1;     ///< initial std of each coefficient [m/s]
  double q_harmonic_m2_per_s3 = 1e-3;   ///< random walk of the coefficients [(m/s)^2/s]
  double harmonic_min_amp_mps = 0.02;   ///< below this fundamental amplitude the harmonic is not used [m/s]

  /// Measurement noise (standard deviation) of v_x and v_z: noise and what the model leaves [m/s].
  double meas_vx_std_mps = 0.05;
  double meas_vz_std_mps = 0.05;

  /// Innovation gate: a channel with |nu| > gate_sigma sqrt(S) is not used (kRejectedOutlier) [sigma].
  double gate_sigma = 5.0;
  /// After this many consecutive rejections the sample is accepted and P inflated [samples].
  std::size_t gate_max_consecutive = 6;
  /// A longer time between samples restarts the acquisition around the last frequency [s].
  double max_gap_s = 1.5;

  /// Walking / standing detector: low-passes of v_x and v_z^2 with hysteresis (sec. 2.4).
  double walk_tau_s = 0.3;             ///< [s]
  double walk_speed_on_mps = 0.2;      ///< walking when LP(v_x) exceeds it ... [m/s]
  double walk_speed_off_mps = 0.15;    ///< standing when LP(v_x) is below it ... [m/s]
  double walk_vz_rms_on_mps = 0.05;    ///< ... or RMS(v_z) exceeds it [m/s]
  double walk_vz_rms_off_mps = 0.025;  ///< ... and RMS(v_z) is below it [m/s]

  /// w pinned within 5 % of a bound this long while walking restarts the acquisition [s].
  double bound_watchdog_s = 1.0;

  /// Reported standard deviations: sqrt(lambda P_ii), lambda the low-passed normalised innovation
  /// squared, clipped to [std_scale_min, std_scale_max] (sec. 2.6). false: lambda = 1.
  bool std_scale_adapt = true;
  double std_scale_tau_s = 10.0;        ///< [s]
  double std_scale_min = 0.05;          ///< [1]
  double std_scale_max = 4.0;           ///< [1]
  double speed_std_floor_mps = 0.025;   ///< added in quadrature to the speed std [m/s]

  /// R = A0 / w and r = |Z| / w are low-passed with this time constant while walking [s].
  double radii_tau_s = 2.0;
  /// R and r reported before the first walk [m].
  double initial_R_m = 0.12;
  double initial_r_m = 0.02;

  /// The paper's estimator exactly as published (Sec. III and IV-B).
  static constexpr EstimatorConfig paper() noexcept {
    EstimatorConfig c{};
    c.algorithm = Algorithm::kPaper;
    return c;
  }

  /// The default estimator (the same as EstimatorConfig{}).
  static constexpr EstimatorConfig gait_filter() noexcept { return EstimatorConfig{}; }

  /// nullptr when the configuration is usable, else what is wrong with it. Both algorithms' fields
  /// are checked, whichever is selected.
  const char* validate() const noexcept {
    auto finite = [](double v) { return std::isfinite(v); };
    auto nonneg = [](double v) { return std::isfinite(v) && v >= 0.0; };
    auto positive = [](double v) { return std::isfinite(v) && v > 0.0; };
    if (algorithm != Algorithm::kPaper && algorithm != Algorithm::kGaitFilter) return "algorithm must be paper or gait_filter";
    if (!positive(sample_time_s)) return "sample_time_s must be finite and > 0";
    // The paper.
    if (!finite(initial_R_hat_mps)) return "initial_R_hat_mps must be finite";
    if (!finite(initial_r_hat_mps)) return "initial_r_hat_mps must be finite";
    if (!finite(initial_omega_rad_per_sample)) return "initial_omega_rad_per_sample must be finite";
    if (!nonneg(q_oscillation_mps2)) return "q_oscillation_mps2 must be finite and >= 0";
    if (!nonneg(q_omega_rad2)) return "q_omega_rad2 must be finite and >= 0";
    if (!nonneg(q_bias_mps2)) return "q_bias_mps2 must be finite and >= 0";
    if (!positive(v_vx_mps2)) return "v_vx_mps2 must be finite and > 0";
    if (!positive(v_vz_mps2)) return "v_vz_mps2 must be finite and > 0";
    if (!nonneg(p0_oscillation_mps2)) return "p0_oscillation_mps2 must be finite and >= 0";
    if (!nonneg(p0_omega_rad2)) return "p0_omega_rad2 must be finite and >= 0";
    if (!nonneg(p0_bias_mps2)) return "p0_bias_mps2 must be finite and >= 0";
    if (smoothing_window_samples > kMaxSmoothingWindow) return "smoothing_window_samples must be <= 256";
    if (!finite(gate_omega_rad_per_sample)) return "gate_omega_rad_per_sample must be finite";
    if (!finite(gate_bias_mps)) return "gate_bias_mps must be finite";
    if (!(max_abs_velocity_mps > 0.0 && max_abs_velocity_mps <= 1e100)) return "max_abs_velocity_mps must be in (0, 1e100]";
    // The gait filter.
    if (!positive(f_min_hz)) return "f_min_hz must be finite and > 0";
    if (!(finite(f_max_hz) && f_max_hz > f_min_hz)) return "f_max_hz must be finite and > f_min_hz";
    if (bank_size < 1 || bank_size > kMaxBankSize) return "bank_f_hz must hold 1 to 8 frequencies";
    for (std::size_t i = 0; i < bank_size; ++i) {
      if (!(finite(bank_f_hz[i]) && bank_f_hz[i] >= f_min_hz && bank_f_hz[i] <= f_max_hz))
        return "bank_f_hz must lie in [f_min_hz, f_max_hz]";
    }
    if (!nonneg(bank_window_s)) return "bank_window_s must be finite and >= 0";
    if (!positive(bank_forget_s)) return "bank_forget_s must be finite and > 0";
    if (!finite(bank_prior_f_hz)) return "bank_prior_f_hz must be finite";
    if (!finite(bank_prior_bonus_nats)) return "bank_prior_bonus_nats must be finite";
    if (!nonneg(p0_f_std_hz)) return "p0_f_std_hz must be finite and >= 0";
    if (!nonneg(p0_phasor_std_mps)) return "p0_phasor_std_mps must be finite and >= 0";
    if (!nonneg(p0_speed_std_mps)) return "p0_speed_std_mps must be finite and >= 0";
    if (!nonneg(p0_accel_std_mps2)) return "p0_accel_std_mps2 must be finite and >= 0";
    if (!nonneg(p0_omega_rate_std_rad_s2)) return "p0_omega_rate_std_rad_s2 must be finite and >= 0";
    if (!nonneg(spectral_init_s)) return "spectral_init_s must be finite and >= 0";
    if (spectral_buffer_samples < 1 || spectral_buffer_samples > kMaxSpectralBuffer)
      return "spectral_buffer_samples must be in [1, 256]";
    if (!positive(spectral_grid_step_hz) ||
        !((f_max_hz - f_min_hz) / spectral_grid_step_hz < static_cast<double>(kMaxSpectralGrid)))
      return "spectral_grid_step_hz must be > 0 with at most 10000 grid frequencies in [f_min_hz, f_max_hz]";
    if (!nonneg(spectral_f_std_hz)) return "spectral_f_std_hz must be finite and >= 0";
    if (!nonneg(spectral_phasor_std_mps)) return "spectral_phasor_std_mps must be finite and >= 0";
    if (!nonneg(q_phasor_m2_per_s3)) return "q_phasor_m2_per_s3 must be finite and >= 0";
    if (!nonneg(q_phase_rad2_per_s)) return "q_phase_rad2_per_s must be finite and >= 0";
    if (!nonneg(q_omega_rad2_per_s3)) return "q_omega_rad2_per_s3 must be finite and >= 0";
    if (!nonneg(q_omega_rate_lo_rad2_per_s5)) return "q_omega_rate_lo_rad2_per_s5 must be finite and >= 0";
    if (!nonneg(q_omega_rate_hi_rad2_per_s5)) return "q_omega_rate_hi_rad2_per_s5 must be finite and >= 0";
    if (!positive(omega_rate_ref_rad_s2)) return "omega_rate_ref_rad_s2 must be finite and > 0";
    if (!nonneg(omega_rate_lp_tau_s)) return "omega_rate_lp_tau_s must be finite and >= 0";
    if (!positive(omega_rate_tau_s)) return "omega_rate_tau_s must be finite and > 0";
    if (!nonneg(q_speed_m2_per_s3)) return "q_speed_m2_per_s3 must be finite and >= 0";
    if (!nonneg(q_accel_m2_per_s5)) return "q_accel_m2_per_s5 must be finite and >= 0";
    if (!positive(accel_tau_s)) return "accel_tau_s must be finite and > 0";
    if (!nonneg(p0_harmonic_std_mps)) return "p0_harmonic_std_mps must be finite and >= 0";
    if (!nonneg(q_harmonic_m2_per_s3)) return "q_harmonic_m2_per_s3 must be finite and >= 0";
    if (!nonneg(harmonic_min_amp_mps)) return "harmonic_min_amp_mps must be finite and >= 0";
    if (!positive(meas_vx_std_mps)) return "meas_vx_std_mps must be finite and > 0";
    if (!positive(meas_vz_std_mps)) return "meas_vz_std_mps must be finite and > 0";
    if (!(gate_sigma > 0.0)) return "gate_sigma must be > 0 (infinity turns the gate off)";
    if (!positive(max_gap_s)) return "max_gap_s must be finite and > 0";
    if (!positive(walk_tau_s)) return "walk_tau_s must be finite and > 0";
    if (!nonneg(walk_speed_on_mps)) return "walk_speed_on_mps must be finite and >= 0";
    if (!(nonneg(walk_speed_off_mps) && walk_speed_off_mps <= walk_speed_on_mps))
      return "walk_speed_off_mps must be finite, >= 0 and <= walk_speed_on_mps";
    if (!nonneg(walk_vz_rms_on_mps)) return "walk_vz_rms_on_mps must be finite and >= 0";
    if (!(nonneg(walk_vz_rms_off_mps) && walk_vz_rms_off_mps <= walk_vz_rms_on_mps))
      return "walk_vz_rms_off_mps must be finite, >= 0 and <= walk_vz_rms_on_mps";
    if (!nonneg(bound_watchdog_s)) return "bound_watchdog_s must be finite and >= 0";
    if (!positive(std_scale_tau_s)) return "std_scale_tau_s must be finite and > 0";
    if (!positive(std_scale_min)) return "std_scale_min must be finite and > 0";
    if (!(finite(std_scale_max) && std_scale_max >= std_scale_min)) return "std_scale_max must be finite and >= std_scale_min";
    if (!nonneg(speed_std_floor_mps)) return "speed_std_floor_mps must be finite and >= 0";
    if (!positive(radii_tau_s)) return "radii_tau_s must be finite and > 0";
    if (!nonneg(initial_R_m)) return "initial_R_m must be finite and >= 0";
    if (!nonneg(initial_r_m)) return "initial_r_m must be finite and >= 0";
    return nullptr;
  }
};

}  // namespace yoyogait
