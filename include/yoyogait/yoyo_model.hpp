/// @file yoyo_model.hpp
/// @brief The Yoyo-model of walking (eq. 1-4): positions and velocities of the centre of mass.
#pragma once

#include <cmath>
#include <cstddef>

#include "yoyogait/math.hpp"

namespace yoyogait {

/// Parameters of the Yoyo-model: the rolling radius R, the inner radius r and the height z0.
struct YoyoParams {
  double R_m = 0.115;  ///< radius of the rolling cylinder [m]; forward speed = R omega
  double r_m = 0.02;   ///< radius of the inner cylinder [m]; amplitude of the oscillation
  double z0_m = 1.0;   ///< height of the centre of the inner cylinder [m]
};

/// One point of the model at cylinder angle theta.
struct YoyoPoint {
  double theta_rad = 0.0;    ///< cylinder angle; one turn is one step
  double x_m = 0.0;          ///< forward position, eq. 1
  double z_m = 0.0;          ///< vertical position, eq. 2
  double vx_mps = 0.0;       ///< forward velocity, eq. 3
  double vz_mps = 0.0;       ///< vertical velocity, eq. 4
};

/// Eq. 1-4 at angle theta and angular velocity omega = d theta / dt [rad/s].
inline YoyoPoint yoyo_point(const YoyoParams& p, double theta_rad, double omega_rad_s) noexcept {
  const double c = std::cos(theta_rad);
  const double s = std::sin(theta_rad);
  YoyoPoint out;
  out.theta_rad = theta_rad;
  out.x_m = p.R_m * theta_rad + p.r_m * s;                   // eq. 1
  out.z_m = p.z0_m + p.r_m * c;                              // eq. 2
  out.vx_mps = p.R_m * omega_rad_s + p.r_m * omega_rad_s * c;  // eq. 3
  out.vz_mps = -p.r_m * omega_rad_s * s;                     // eq. 4
  return out;
}

/// Eq. 1-4 on a time grid with a step frequency that may change over time.
/// theta is the trapezoidal integral of omega = 2 pi f from theta(t[0]) = phase_rad, as in
/// yoyogait.model.yoyo_model. time_s must be increasing; n points are written to out.
inline void yoyo_trajectory(const YoyoParams& p, const double* time_s, const double* step_frequency_hz,
                            std::size_t n, double phase_rad, YoyoPoint* out) noexcept {
  double theta = phase_rad;
  for (std::size_t i = 0; i < n; ++i) {
    const double omega = kTwoPi * step_frequency_hz[i];
    if (i > 0) theta += 0.5 * (omega + kTwoPi * step_frequency_hz[i - 1]) * (time_s[i] - time_s[i - 1]);
    out[i] = yoyo_point(p, theta, omega);
  }
}

}  // namespace yoyogait
