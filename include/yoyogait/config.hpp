/// @file config.hpp
/// @brief The estimator's configuration, declared once: one table per section (shared, the paper's
/// estimator, the gait filter), each row a field with its type, name, default, unit, valid range and
/// one-line doc. The structs, their validation, the Python bindings and the schema that the Python
/// configuration, the TOML files and docs/configuration.md follow are all derived from these tables.
#pragma once

#include <array>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <initializer_list>

namespace yoyogait {

/// Largest smoothing window n of eq. 11-12; the window lives in a fixed buffer so a step never allocates.
inline constexpr std::size_t kMaxSmoothingWindow = 256;
/// Largest start-up bank of the gait filter (GaitFilterConfig::bank_f_hz).
inline constexpr std::size_t kMaxBankSize = 8;
/// Largest ring buffer of the gait filter's spectral initialisation [samples].
inline constexpr std::size_t kMaxSpectralBuffer = 256;
/// Largest number of frequencies of the spectral grid search (start-up work, bounded).
inline constexpr std::size_t kMaxSpectralGrid = 10000;

/// Which estimator EstimatorConfig describes.
enum class Algorithm : std::uint8_t {
  kPaper = 0,       ///< the paper's 4-state EKF and heuristics, exactly as published (paper/paper_estimator.hpp)
  kGaitFilter = 1,  ///< the default: the dual-phasor gait filter (gait/gait_filter.hpp, docs/default_estimator.md)
};

/// A short list of frequencies [Hz] in a fixed array (a step never allocates): the gait filter's bank.
struct FrequencyList {
  std::array<double, kMaxBankSize> hz{};
  /// Number of frequencies given; above kMaxBankSize only when too many were given (then invalid,
  /// and only the first kMaxBankSize are stored).
  std::size_t size = 0;

  constexpr FrequencyList() noexcept = default;
  constexpr FrequencyList(std::initializer_list<double> f) noexcept : size(f.size()) {
    std::size_t i = 0;
    for (const double v : f) {
      if (i < kMaxBankSize) hz[i] = v;
      ++i;
    }
  }
  constexpr double operator[](std::size_t i) const noexcept { return hz[i]; }
  constexpr double& operator[](std::size_t i) noexcept { return hz[i]; }
};

// ------------------------------------------------------------------------------------ the tables
//
// X(type, name, default, "unit", lo, min, max, hi, "doc"): the valid range is lo min, max hi, with
// lo "[" (min allowed) or "(" (min excluded) and hi "]" or ")". Every field is checked against it
// when an Estimator is built (EstimatorConfig::validate); NaN never passes, and infinity only where
// a bound is infinite and inclusive. Cross-field rules follow
// in EstimatorConfig::validate. Ranges are wide (every value in them gives finite estimates), not
// advice: docs/default_estimator.md and docs/paper_estimator.md say which values are sensible.

/// Fields shared by both algorithms (besides EstimatorConfig::algorithm).
#define YOYOGAIT_SHARED_FIELDS(X)                                                                                   \
  X(double, sample_time_s, 0.04, "s", "[", 1e-5, 1.0, "]",                                                         \
    "T: time between samples; the paper resamples to 25 Hz, the gait filter takes it as the nominal time step")    \
  X(double, max_abs_velocity_mps, 1000.0, "m/s", "(", 0.0, 1e100, "]",                                             \
    "a sample (gait filter: a channel) with |v| above it is rejected like a non-finite one")

/// The paper's estimator (Sec. III and IV-B), in the paper's units: its filter works per sample.
#define YOYOGAIT_PAPER_FIELDS(X)                                                                                    \
  X(double, initial_R_hat_mps, 2.0, "m/s", "[", 0.0, 1e6, "]", "R_hat(0) = R/T for the average person (R0 = 2)")  \
  X(double, initial_r_hat_mps, 0.2, "m/s", "[", 0.0, 1e6, "]", "r_hat(0) = r/T (r0 = 0.2)")                       \
  X(double, initial_omega_rad_per_sample, 0.1, "rad/sample", "[", -3.141592653589793, 3.141592653589793, "]",     \
    "w(0), the initial step frequency per sample (0.1: 0.4 Hz at 25 Hz)")                                          \
  X(double, q_oscillation_mps2, 1e-5, "(m/s)^2", "[", 0.0, 1e4, "]", "Q11 = Q22: process noise of x1, x2")         \
  X(double, q_omega_rad2, 1e-3, "(rad/sample)^2", "[", 0.0, 10.0, "]", "Q33: process noise of the frequency x3")   \
  X(double, q_bias_mps2, 1e-3, "(m/s)^2", "[", 0.0, 1e4, "]", "Q44: process noise of the bias x4 = A0")            \
  X(double, v_vx_mps2, 1e-2, "(m/s)^2", "[", 1e-12, 1e4, "]", "V11: measurement noise of v_x")                     \
  X(double, v_vz_mps2, 1e-2, "(m/s)^2", "[", 1e-12, 1e4, "]", "V22: measurement noise of v_z")                     \
  X(double, p0_oscillation_mps2, 1.0, "(m/s)^2", "[", 0.0, 1e4, "]", "P0 of x1, x2 (P0 = I in the paper)")         \
  X(double, p0_omega_rad2, 1.0, "(rad/sample)^2", "[", 0.0, 10.0, "]", "P0 of the frequency x3")                                 \
  X(double, p0_bias_mps2, 1.0, "(m/s)^2", "[", 0.0, 1e4, "]", "P0 of the bias x4")                                          \
  X(std::size_t, smoothing_window_samples, 10, "samples", "[", 0, 256, "]",                                        \
    "n of eq. 11-12: the moving average's length; R_hat, r_hat first change at k > n")                             \
  X(double, gate_omega_rad_per_sample, 0.1, "rad/sample", "[", 1e-3, 3.141592653589793, "]",                       \
    "mu_w of eq. 11-12: R_hat, r_hat update only while x3 exceeds it")                                             \
  X(double, gate_bias_mps, 0.1, "m/s", "[", 0.0, 1e3, "]", "mu_A0 of eq. 11-12: ... and while x4 exceeds it")

/// The gait filter (docs/default_estimator.md), in SI units per second: noise densities are
/// multiplied by the actual time step. State x = [X1, X2, Z1, Z2, w, A0, dA0, dw].
#define YOYOGAIT_GAIT_FILTER_FIELDS(X)                                                                              \
  X(double, f_min_hz, 0.4, "Hz", "[", 0.05, 10.0, "]", "lower bound of the step frequency (0 is excluded)")        \
  X(double, f_max_hz, 3.5, "Hz", "[", 0.1, 20.0, "]", "upper bound of the step frequency (> f_min_hz)")            \
  X(::yoyogait::FrequencyList, bank_f_hz, (::yoyogait::FrequencyList{0.9, 1.3, 1.8, 2.3, 2.8}), "Hz", "[", 0.05, 20.0, "]",               \
    "start frequencies of the start-up bank of EKFs: 1 to 8, increasing, within [f_min_hz, f_max_hz]")             \
  X(double, bank_window_s, 1.5, "s", "[", 0.0, 60.0, "]", "walking time after which the bank collapses to its best member") \
  X(double, bank_forget_s, 1.5, "s", "[", 0.01, 600.0, "]", "memory of the members' innovation log-likelihood")    \
  X(double, bank_prior_f_hz, 1.8, "Hz", "[", 0.05, 20.0, "]", "typical step frequency: its member starts with the log-prior bonus") \
  X(double, bank_prior_bonus_nats, 2.0, "nats", "[", -100.0, 100.0, "]",                                           \
    "log-prior bonus (on re-acquisition: for the member at the last chosen lock's frequency)")                     \
  X(double, bank_q_omega_rad2_per_s3, 0.05, "(rad/s)^2/s", "[", 0.0, 1e4, "]",                                      \
    "random walk of w in the start-up bank's members (0.25 follows a start's rising cadence better, docs/default_estimator.md)") \
  X(double, p0_f_std_hz, 0.25, "Hz", "[", 0.0, 10.0, "]", "initial frequency std of each member")                  \
  X(double, p0_phasor_std_mps, 0.3, "m/s", "[", 0.0, 100.0, "]", "initial std of the phasors")                     \
  X(double, p0_speed_std_mps, 0.3, "m/s", "[", 0.0, 100.0, "]", "initial std of A0")                               \
  X(double, p0_accel_std_mps2, 0.5, "m/s^2", "[", 0.0, 100.0, "]", "initial std of dA0")                           \
  X(double, p0_omega_rate_std_rad_s2, 0.05, "rad/s^2", "[", 0.0, 100.0, "]", "initial std of dw")                  \
  X(bool, spectral_init, true, "", "[", 0, 1, "]",                                                                 \
    "seed the least likely bank member by a least-squares frequency grid search")                                  \
  X(double, spectral_init_s, 1.0, "s", "[", 0.0, 60.0, "]", "... after this much walking")                         \
  X(double, spectral_buffer_s, 1.6, "s", "(", 0.0, 60.0, "]",                                                      \
    "... over the samples of the last this long (in samples of sample_time_s, rounded: 1 to 256)")                \
  X(double, spectral_grid_step_hz, 0.025, "Hz", "[", 1e-4, 10.0, "]",                                              \
    "grid step of the search (at most 10000 grid frequencies in [f_min_hz, f_max_hz])")                            \
  X(double, spectral_f_std_hz, 0.08, "Hz", "[", 0.0, 10.0, "]", "frequency std given to the seeded member")        \
  X(double, spectral_phasor_std_mps, 0.05, "m/s", "[", 0.0, 100.0, "]", "phasor and A0 std given to the seeded member") \
  X(double, q_phasor_m2_per_s3, 2e-3, "(m/s)^2/s", "[", 0.0, 1e4, "]", "independent drift of each phasor entry")   \
  X(double, q_phase_rad2_per_s, 0.05, "rad^2/s", "[", 0.0, 1e3, "]", "common gait-phase jitter, rotating X and Z together") \
  X(double, q_omega_rad2_per_s3, 0.05, "(rad/s)^2/s", "[", 0.0, 1e4, "]", "random walk of w")                     \
  X(bool, use_omega_rate, true, "", "[", 0, 1, "]", "frequency-rate state dw (tracks cadence ramps)")              \
  X(double, q_omega_rate_lo_rad2_per_s5, 0.01, "(rad/s^2)^2/s", "[", 0.0, 1e4, "]", "noise of dw while no trend is seen") \
  X(double, q_omega_rate_hi_rad2_per_s5, 2.0, "(rad/s^2)^2/s", "[", 0.0, 1e4, "]",                                 \
    "noise of dw once the low-passed rate reaches omega_rate_ref_rad_s2 (>= the lo value)")                        \
  X(double, omega_rate_ref_rad_s2, 0.2, "rad/s^2", "[", 1e-3, 100.0, "]", "trend level of the low-passed rate")    \
  X(double, omega_rate_lp_tau_s, 1.5, "s", "[", 0.0, 600.0, "]", "low-pass of dw for the trend test (0: none)")    \
  X(double, omega_rate_tau_s, 3.0, "s", "[", 0.01, 600.0, "]", "decay time of dw")                                 \
  X(double, q_speed_m2_per_s3, 1e-3, "(m/s)^2/s", "[", 0.0, 1e4, "]", "random walk of A0")                         \
  X(double, q_accel_m2_per_s5, 1e-2, "(m/s^2)^2/s", "[", 0.0, 1e4, "]", "random walk of dA0")                      \
  X(double, accel_tau_s, 1.0, "s", "[", 0.01, 600.0, "]", "decay time of dA0")                                     \
  X(bool, use_harmonic, true, "", "[", 0, 1, "]", "second harmonic of each channel by a cascaded 2-state Kalman filter") \
  X(double, p0_harmonic_std_mps, 0.1, "m/s", "[", 0.0, 100.0, "]", "initial std of the harmonic coefficients")      \
  X(double, q_harmonic_m2_per_s3, 1e-3, "(m/s)^2/s", "[", 0.0, 1e4, "]", "random walk of the harmonic coefficients") \
  X(double, harmonic_min_amp_mps, 0.02, "m/s", "[", 0.0, 100.0, "]", "below this fundamental amplitude the harmonic is not used") \
  X(double, meas_vx_density_m2_per_s, 1e-4, "(m/s)^2 s", "[", 1e-12, 1e4, "]",                                    \
    "measurement noise density of v_x (noise and what the model leaves): R = density / dt; 1e-4 is 0.05 m/s at 25 Hz") \
  X(double, meas_vz_density_m2_per_s, 1e-4, "(m/s)^2 s", "[", 1e-12, 1e4, "]",                                    \
    "measurement noise density of v_z: R = density / dt")                                                          \
  X(double, gate_sigma, 5.0, "sigma", "[", 0.1, INFINITY, "]",                                                      \
    "innovation gate: a channel with |nu| > gate_sigma sqrt(S) is not used (infinity: no gate)")                   \
  X(double, gate_max_consecutive_s, 0.24, "s", "[", 0.0, 3600.0, "]",                                              \
    "after consecutive rejections for this long (in samples of sample_time_s, rounded) a sample is accepted and P inflated") \
  X(double, max_gap_s, 1.5, "s", "[", 1e-3, 3600.0, "]", "a longer time between samples restarts the acquisition")  \
  X(double, walk_tau_s, 0.3, "s", "[", 1e-3, 60.0, "]", "low-pass of the walking detector")                        \
  X(double, walk_speed_on_mps, 0.2, "m/s", "[", 0.0, 10.0, "]", "walking when the low-passed v_x exceeds it ...")  \
  X(double, walk_speed_off_mps, 0.15, "m/s", "[", 0.0, 10.0, "]",                                                  \
    "standing when the low-passed v_x is below it (<= walk_speed_on_mps) ...")                                     \
  X(double, walk_vz_rms_on_mps, 0.05, "m/s", "[", 0.0, 10.0, "]", "... or when the RMS of v_z exceeds it")         \
  X(double, walk_vz_rms_off_mps, 0.025, "m/s", "[", 0.0, 10.0, "]",                                                \
    "... and the RMS of v_z is below it (<= walk_vz_rms_on_mps)")                                                  \
  X(double, bound_watchdog_s, 1.0, "s", "[", 0.0, 600.0, "]",                                                      \
    "w within 5 % of a bound this long while walking (less the time more than 15 % inside) restarts the acquisition") \
  X(bool, cadence_change_adapt, true, "", "[", 0, 1, "]",                                                          \
    "a phase lag of the model that persists opens the frequency variance (changes of cadence)")                    \
  X(double, cadence_change_tau_s, 0.1, "s", "[", 0.01, 60.0, "]",                                                  \
    "the phase lag: least squares of the v_z innovations over this long (with the amplitude error)")               \
  X(double, cadence_change_phase_rad, 0.05, "rad", "[", 0.0, 3.2, "]",                                             \
    "a lag beyond this (and beyond cadence_change_sigma RMS) is a change of cadence")                              \
  X(double, cadence_change_sigma, 3.0, "sigma", "[", 0.0, 1e3, "]",                                                \
    "... the lag must exceed this many times its own RMS (the walker's phase noise)")                              \
  X(double, cadence_change_noise_tau_s, 2.0, "s", "[", 0.01, 3600.0, "]",                                          \
    "low-pass of the lag's mean square; no detection in the first this long after an acquisition")                 \
  X(double, cadence_change_horizon_s, 0.4, "s", "[", 0.01, 60.0, "]",                                              \
    "the excess lag over this long is the frequency error: P_ww is raised to (excess / horizon)^2")                \
  X(double, cadence_change_max_std_hz, 0.15, "Hz", "[", 0.0, 10.0, "]",                                           \
    "... at most to this std (a jump to a harmonic of the cadence would need more)")                               \
  X(double, cadence_change_min_amp_mps, 0.05, "m/s", "[", 0.0, 100.0, "]",                                         \
    "a sample is evidence only while |Z| exceeds this (not while the oscillation fades)")                           \
  X(bool, std_scale_adapt, true, "", "[", 0, 1, "]",                                                               \
    "scale the reported standard deviations by the low-passed normalised innovation squared")                      \
  X(double, std_scale_tau_s, 10.0, "s", "[", 0.01, 1e4, "]", "low-pass of that scale")                             \
  X(double, std_scale_min, 0.05, "", "[", 1e-6, 1e3, "]", "lower clip of the scale")                               \
  X(double, std_scale_max, 4.0, "", "[", 1e-6, 1e6, "]", "upper clip of the scale (>= std_scale_min)")             \
  X(double, speed_std_floor_mps, 0.025, "m/s", "[", 0.0, 10.0, "]", "added in quadrature to the speed std")       \
  X(double, radii_tau_s, 2.0, "s", "[", 0.01, 1e4, "]", "low-pass of R = A0 / w and r = |Z| / w while walking")    \
  X(double, initial_R_m, 0.12, "m", "[", 0.0, 10.0, "]", "R reported before the first walk")                       \
  X(double, initial_r_m, 0.02, "m", "[", 0.0, 10.0, "]", "r reported before the first walk")

// ----------------------------------------------------------------------------------- the structs

// The three uses of a settings table row, shared by every settings table (these, and the online and
// IMU front-ends'): a struct member, its range check in validate() (obj.name, errors "prefix" + name),
// and its FieldSpec (below).
#define YOYOGAIT_CONFIG_MEMBER(type, name, def, unit, lo, min, max, hi, doc) type name = def;
#define YOYOGAIT_CHECK_FIELD(obj, prefix, type, name, def, unit, lo, min, max, hi, doc) \
  if (!::yoyogait::detail::in_range(obj.name, min, max, lo, hi))                      \
    return ::yoyogait::detail::range_message(prefix, #name, obj.name, min, max, lo, hi, unit);

/// The paper's estimator (Algorithm::kPaper): YOYOGAIT_PAPER_FIELDS.
struct PaperConfig {
  YOYOGAIT_PAPER_FIELDS(YOYOGAIT_CONFIG_MEMBER)
};

/// The gait filter (Algorithm::kGaitFilter, the default): YOYOGAIT_GAIT_FILTER_FIELDS.
struct GaitFilterConfig {
  YOYOGAIT_GAIT_FILTER_FIELDS(YOYOGAIT_CONFIG_MEMBER)
};

namespace detail {

inline bool in_range(double v, double min, double max, const char* lo, const char* hi) noexcept {
  return (lo[0] == '[' ? v >= min : v > min) && (hi[0] == ']' ? v <= max : v < max);
}
inline bool in_range(std::size_t v, double min, double max, const char* lo, const char* hi) noexcept {
  return in_range(static_cast<double>(v), min, max, lo, hi);
}
inline bool in_range(bool, double, double, const char*, const char*) noexcept { return true; }
/// 1 to kMaxBankSize frequencies, each within the range.
inline bool in_range(const FrequencyList& f, double min, double max, const char* lo, const char* hi) noexcept {
  if (f.size < 1 || f.size > kMaxBankSize) return false;
  for (std::size_t i = 0; i < f.size; ++i)
    if (!in_range(f[i], min, max, lo, hi)) return false;
  return true;
}

/// The message of a field outside its range, in a buffer of this thread (valid until the next).
inline char* message_buffer() noexcept {
  static thread_local char buffer[320];
  return buffer;
}
inline const char* range_message(const char* prefix, const char* name, double v, double min, double max,
                                 const char* lo, const char* hi, const char* unit) noexcept {
  std::snprintf(message_buffer(), 320, "%s%s = %.15g is outside its valid range %s%.15g, %.15g%s%s%s", prefix, name, v,
                lo, min, max, hi, unit[0] ? " " : "", unit);
  return message_buffer();
}
inline const char* range_message(const char* prefix, const char* name, std::size_t v, double min, double max,
                                 const char* lo, const char* hi, const char* unit) noexcept {
  return range_message(prefix, name, static_cast<double>(v), min, max, lo, hi, unit);
}
inline const char* range_message(const char* prefix, const char* name, bool v, double min, double max,
                                 const char* lo, const char* hi, const char* unit) noexcept {
  return range_message(prefix, name, v ? 1.0 : 0.0, min, max, lo, hi, unit);
}
inline const char* range_message(const char* prefix, const char* name, const FrequencyList&, double min, double max,
                                 const char* lo, const char* hi, const char* unit) noexcept {
  std::snprintf(message_buffer(), 320, "%s%s must hold 1 to %zu frequencies, each in %s%.15g, %.15g%s %s", prefix, name,
                kMaxBankSize, lo, min, max, hi, unit);
  return message_buffer();
}

}  // namespace detail

/// Parameters of the estimator: the algorithm, the shared fields, and one section per algorithm.
///
/// `EstimatorConfig{}` is the default estimator (Algorithm::kGaitFilter with its tuned values);
/// `EstimatorConfig::paper()` is the paper's estimator (Sec. IV-B). Each algorithm reads its own
/// section and ignores the other's; both are validated, whichever is selected.
struct EstimatorConfig {
  /// The estimator to run.
  Algorithm algorithm = Algorithm::kGaitFilter;
  YOYOGAIT_SHARED_FIELDS(YOYOGAIT_CONFIG_MEMBER)
  /// The paper's estimator (read when algorithm is kPaper).
  PaperConfig paper_estimator{};
  /// The gait filter (read when algorithm is kGaitFilter).
  GaitFilterConfig gait_filter{};

  /// The paper's estimator exactly as published (Sec. III and IV-B).
  static constexpr EstimatorConfig paper() noexcept {
    EstimatorConfig c{};
    c.algorithm = Algorithm::kPaper;
    return c;
  }

  /// nullptr when the configuration is usable, else what is wrong with it, naming the field
  /// ("section.field") and its valid range. Both algorithms' sections are checked.
  const char* validate() const noexcept {
    if (algorithm != Algorithm::kPaper && algorithm != Algorithm::kGaitFilter)
      return "algorithm must be paper or gait_filter";
#define YOYOGAIT_CHECK_SHARED(...) YOYOGAIT_CHECK_FIELD((*this), "", __VA_ARGS__)
#define YOYOGAIT_CHECK_PAPER(...) YOYOGAIT_CHECK_FIELD(paper_estimator, "paper_estimator.", __VA_ARGS__)
#define YOYOGAIT_CHECK_GAIT(...) YOYOGAIT_CHECK_FIELD(gait_filter, "gait_filter.", __VA_ARGS__)
    YOYOGAIT_SHARED_FIELDS(YOYOGAIT_CHECK_SHARED)
    YOYOGAIT_PAPER_FIELDS(YOYOGAIT_CHECK_PAPER)
    YOYOGAIT_GAIT_FILTER_FIELDS(YOYOGAIT_CHECK_GAIT)
#undef YOYOGAIT_CHECK_SHARED
#undef YOYOGAIT_CHECK_PAPER
#undef YOYOGAIT_CHECK_GAIT
    // Rules between fields of the gait filter.
    const GaitFilterConfig& g = gait_filter;
    if (!(g.f_max_hz > g.f_min_hz)) return "gait_filter.f_max_hz must be > gait_filter.f_min_hz";
    for (std::size_t i = 0; i < g.bank_f_hz.size; ++i) {
      if (!(g.bank_f_hz[i] >= g.f_min_hz && g.bank_f_hz[i] <= g.f_max_hz))
        return "gait_filter.bank_f_hz must lie in [f_min_hz, f_max_hz]";
      if (i > 0 && !(g.bank_f_hz[i] > g.bank_f_hz[i - 1]))
        return "gait_filter.bank_f_hz must be increasing (sorted and distinct)";
    }
    if (!((g.f_max_hz - g.f_min_hz) / g.spectral_grid_step_hz < static_cast<double>(kMaxSpectralGrid)))
      return "gait_filter.spectral_grid_step_hz must give at most 10000 grid frequencies in [f_min_hz, f_max_hz]";
    if (!(g.q_omega_rate_hi_rad2_per_s5 >= g.q_omega_rate_lo_rad2_per_s5))
      return "gait_filter.q_omega_rate_hi_rad2_per_s5 must be >= q_omega_rate_lo_rad2_per_s5";
    if (!(g.walk_speed_off_mps <= g.walk_speed_on_mps))
      return "gait_filter.walk_speed_off_mps must be <= walk_speed_on_mps";
    if (!(g.walk_vz_rms_off_mps <= g.walk_vz_rms_on_mps))
      return "gait_filter.walk_vz_rms_off_mps must be <= walk_vz_rms_on_mps";
    if (!(g.std_scale_max >= g.std_scale_min)) return "gait_filter.std_scale_max must be >= std_scale_min";
    const double buffer = g.spectral_buffer_s / sample_time_s;
    if (!(buffer >= 0.5 && buffer < static_cast<double>(kMaxSpectralBuffer) + 0.5))
      return "gait_filter.spectral_buffer_s must hold 1 to 256 samples of sample_time_s";
    return nullptr;
  }

  /// A duration [s] in samples of sample_time_s, rounded to the nearest (half away from zero): the
  /// settings of the gait filter that count samples are durations, so that they mean the same time
  /// at any rate. At the defaults: spectral_buffer_s 1.6 s = 40, gate_max_consecutive_s 0.24 s = 6.
  std::size_t samples_in(double duration_s) const noexcept {
    const double n = duration_s / sample_time_s;
    return n >= 0.5 ? static_cast<std::size_t>(std::floor(n + 0.5)) : 0;
  }
};


// ------------------------------------------------------------------------------------ the schema

/// One field of a table, for code that lists, documents or checks the configuration.
struct FieldSpec {
  const char* section;  ///< "" (shared), "paper_estimator" or "gait_filter"
  const char* name;
  const char* type;     ///< "float", "int", "bool" or "float_list"
  const char* unit;     ///< "" where the field has none
  double min, max;      ///< valid range (for float_list: of each entry; bool: 0, 1)
  bool min_inclusive, max_inclusive;
  const char* doc;
};

namespace detail {
template <class T>
constexpr const char* type_name() noexcept;
template <>
constexpr const char* type_name<double>() noexcept { return "float"; }
template <>
constexpr const char* type_name<std::size_t>() noexcept { return "int"; }
template <>
constexpr const char* type_name<bool>() noexcept { return "bool"; }
template <>
constexpr const char* type_name<FrequencyList>() noexcept { return "float_list"; }
}  // namespace detail

#define YOYOGAIT_FIELD_SPEC(section, type, name, def, unit, lo, min, max, hi, doc) \
  FieldSpec{section, #name, detail::type_name<type>(), unit, static_cast<double>(min), static_cast<double>(max), \
            lo[0] == '[', hi[0] == ']', doc},
#define YOYOGAIT_SPEC_SHARED(...) YOYOGAIT_FIELD_SPEC("", __VA_ARGS__)
#define YOYOGAIT_SPEC_PAPER(...) YOYOGAIT_FIELD_SPEC("paper_estimator", __VA_ARGS__)
#define YOYOGAIT_SPEC_GAIT(...) YOYOGAIT_FIELD_SPEC("gait_filter", __VA_ARGS__)
/// Every field of the three tables, in their order: shared, paper_estimator, gait_filter.
inline constexpr FieldSpec kConfigFields[] = {
    YOYOGAIT_SHARED_FIELDS(YOYOGAIT_SPEC_SHARED) YOYOGAIT_PAPER_FIELDS(YOYOGAIT_SPEC_PAPER)
        YOYOGAIT_GAIT_FILTER_FIELDS(YOYOGAIT_SPEC_GAIT)};
#undef YOYOGAIT_SPEC_SHARED
#undef YOYOGAIT_SPEC_PAPER
#undef YOYOGAIT_SPEC_GAIT

}  // namespace yoyogait
