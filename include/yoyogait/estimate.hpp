/// @file estimate.hpp
/// @brief What the estimator reports after each sample, for both algorithms: Estimate and Status.
#pragma once

#include <cmath>
#include <cstdint>
#include <limits>

#include "yoyogait/gait/state.hpp"
#include "yoyogait/paper/heuristics.hpp"
#include "yoyogait/paper/state.hpp"
#include "yoyogait/record.hpp"

namespace yoyogait {

/// What a step did with its sample.
enum class Status : std::uint8_t {
  kUpdated = 0,            ///< prediction and update
  kRejectedNonFinite = 1,  ///< the sample had a NaN or infinity: prediction only
  kRejectedNumerical = 2,  ///< the update would have made the state non-finite: prediction only
  kRejectedOutOfRange = 3,  ///< |v| above EstimatorConfig::max_abs_velocity_mps: prediction only
  kRejectedOutlier = 4,     ///< gait filter: a channel failed the innovation gate and was not used
};

/// The per-sample fields of Estimate, declared once: X(type, name, default, "unit", scope, "doc").
/// scope kAll: both algorithms fill it; kGait: only the gait filter carries something new (the
/// paper's value is fixed: vx_hat_h2 = vx_hat, std_scale 1, walking true, acquiring false), so a
/// batch run writes it only for the gait filter. The struct below, the bindings' columns and
/// properties, the schema `_core.record_schema()` and the Python result classes, the CSV columns
/// and docs/records.md all follow this table. Beside it, Estimate holds the two state vectors
/// (state, gait_state) and the values derived from gait_state on demand (YOYOGAIT_ESTIMATE_DERIVED).
#define YOYOGAIT_ESTIMATE_FIELDS(X)                                                                                \
  X(double, vx_hat_mps, 0.0, "m/s", kAll, "reconstructed v_x: paper eq. 13; gait A0 + X1 (standing: A0)")         \
  X(double, vz_hat_mps, 0.0, "m/s", kAll, "reconstructed v_z: paper eq. 14; gait Z1 (standing: 0)")               \
  X(double, R_hat_mps, 0.0, "m/s", kAll, "R_hat(k) of eq. 11 in the paper's unit (R/T); gait: R_m / T")           \
  X(double, r_hat_mps, 0.0, "m/s", kAll, "r_hat(k) of eq. 12 in the paper's unit (r/T); gait: r_m / T")           \
  X(double, R_m, 0.0, "m", kAll, "R: paper T R_hat; gait A0 / w low-passed while walking")                       \
  X(double, r_m, 0.0, "m", kAll, "r: paper T r_hat; gait |Z| / w low-passed while walking")                      \
  X(double, omega_rad_s, 0.0, "rad/s", kAll, "step angular frequency: paper x3 / T (signed); gait w (> 0)")      \
  X(double, step_frequency_hz, 0.0, "Hz", kAll, "omega_rad_s / 2 pi")                                             \
  X(double, step_frequency_std_hz, 0.0, "Hz", kAll, "paper sqrt(P33) / (2 pi T); gait sqrt(lambda P_ww) / 2 pi") \
  X(double, speed_mps, 0.0, "m/s", kAll,                                                                          \
    "forward speed without the oscillation: paper R_hat x3 = R omega; gait A0")                                   \
  X(double, speed_std_mps, 0.0, "m/s", kAll, "paper sqrt(P44); gait sqrt(lambda P_A0A0 + speed_std_floor^2)")    \
  X(double, A0_mps, 0.0, "m/s", kAll, "bias of v_x: paper x4; gait A0")                                           \
  X(double, A1_mps, 0.0, "m/s", kAll, "amplitude of the forward oscillation: paper |(x1, x2)|; gait |X|")        \
  X(double, vx_hat_h2_mps, 0.0, "m/s", kGait, "gait: vx_hat with the second harmonic; paper: vx_hat")             \
  X(double, vz_hat_h2_mps, 0.0, "m/s", kGait, "gait: vz_hat with the second harmonic; paper: vz_hat")             \
  X(double, std_scale, 1.0, "", kGait, "gait: lambda, the scale of the reported standard deviations; paper: 1")  \
  X(::yoyogait::Status, status, ::yoyogait::Status::kUpdated, "", kAll, "what the step did with its sample (Status)")                    \
  X(bool, parameters_updated, false, "", kAll,                                                                    \
    "paper: eq. 11-12 took the update branch; gait: R, r were updated (walking)")                                 \
  X(bool, walking, true, "", kGait, "gait: the walking/standing detector; paper: always true")                   \
  X(bool, acquiring, false, "", kGait, "gait: the start-up bank is running; paper: always false")

/// Values of Estimate derived from gait_state when read: X(name, "unit", "doc") (member functions).
#define YOYOGAIT_ESTIMATE_DERIVED(X)                                                                               \
  X(amp_z_mps, "m/s", "amplitude of the vertical oscillation |Z| (paper: A1)")                                    \
  X(phase_x_rel_z_rad, "rad", "phase of the forward oscillation relative to the vertical one, in [-pi, pi]")     \
  X(signed_amp_x_mps, "m/s", "forward amplitude signed by the relation (> 0 the Yoyo relation)")                 \
  X(omega_rate_rad_s2, "rad/s^2", "rate of the step angular frequency dw (paper: 0)")                            \
  X(accel_mps2, "m/s^2", "rate of the forward-speed bias dA0 (paper: 0)")

/// The diagnostics of a step (Innovation), declared once: X(type, name, default, "unit", scope, "doc").
#define YOYOGAIT_INNOVATION_FIELDS(X)                                                                              \
  X(double, innovation_vx_mps, ::std::numeric_limits<double>::quiet_NaN(), "m/s", kAll,                            \
    "v_x measurement minus its prediction; NaN where the channel was not used")                                   \
  X(double, innovation_vz_mps, ::std::numeric_limits<double>::quiet_NaN(), "m/s", kAll,                            \
    "v_z measurement minus its prediction (gait: after the v_x update); NaN where not used")                      \
  X(double, nis, ::std::numeric_limits<double>::quiet_NaN(), "", kAll,                                              \
    "normalised innovation squared nu^T S^-1 nu (about 2 when the noise model fits); NaN when no channel was used")

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
  YOYOGAIT_ESTIMATE_FIELDS(YOYOGAIT_RECORD_MEMBER)

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
using Velocity = paper::Reconstruction;

/// Diagnostics of a step, as FilterPy exposes them: the innovation of each channel (measurement
/// minus predicted measurement) and the normalised innovation squared, NIS = nu^T S^-1 nu, which
/// averages to the number of channels used (2) when the filter's noise model fits the data.
/// NaN for a channel the step did not use (and NIS NaN when it used none).
/// paper: nu = z - H x- at the prediction x-, S = H P- H^T + V (eq. 9). gait: the two sequential
/// scalar updates, v_x first (its prediction includes the second harmonic); nu_z is the v_z
/// innovation after the v_x update, and NIS = nu_x^2 / S_x + nu_z^2 / S_z, which equals the joint
/// nu^T S^-1 nu of the two channels. Innovations of a channel rejected by the gate are reported.
struct Innovation {
  YOYOGAIT_INNOVATION_FIELDS(YOYOGAIT_RECORD_MEMBER)
};

}  // namespace yoyogait
