/// @file estimate.hpp
/// @brief What the estimator reports after each sample, for both algorithms: Estimate and Status.
#pragma once

#include <cmath>
#include <cstdint>
#include <limits>

#include "yoyogait/gait/state.hpp"
#include "yoyogait/paper/heuristics.hpp"
#include "yoyogait/paper/state.hpp"

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

/// Diagnostics of a step, as FilterPy exposes them: the innovation of each channel (measurement
/// minus predicted measurement) and the normalised innovation squared, NIS = nu^T S^-1 nu, which
/// averages to the number of channels used (2) when the filter's noise model fits the data.
/// NaN for a channel the step did not use (and NIS NaN when it used none).
/// paper: nu = z - H x- at the prediction x-, S = H P- H^T + V (eq. 9). gait: the two sequential
/// scalar updates, v_x first (its prediction includes the second harmonic); nu_z is the v_z
/// innovation after the v_x update, and NIS = nu_x^2 / S_x + nu_z^2 / S_z, which equals the joint
/// nu^T S^-1 nu of the two channels. Innovations of a channel rejected by the gate are reported.
struct Innovation {
  double vx_mps = std::numeric_limits<double>::quiet_NaN();
  double vz_mps = std::numeric_limits<double>::quiet_NaN();
  double nis = std::numeric_limits<double>::quiet_NaN();
};

}  // namespace yoyogait
