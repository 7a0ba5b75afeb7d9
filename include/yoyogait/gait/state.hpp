/// @file gait/state.hpp
/// @brief The gait filter's state (docs/default_estimator.md sec. 2.1) with named entries, its
/// transition over dt and the transition's Jacobian.
///
///   x = [X1, X2, Z1, Z2, w, A0, dA0, dw]
///   X <- Rot(w dt) X,  Z <- Rot(w dt) Z,  w <- w + dt dw,  dw <- b dw,
///   A0 <- A0 + dt dA0, dA0 <- a dA0,   a = exp(-dt / accel_tau_s), b = exp(-dt / omega_rate_tau_s)
#pragma once

#include <array>
#include <cstddef>

#include "yoyogait/math.hpp"

namespace yoyogait {

namespace gait {

/// Index of each entry of the gait filter's state (sec. 2.1).
enum Index : std::size_t {
  kX1 = 0,   ///< X1: first component of the phasor of the forward oscillation [m/s]; v_x = A0 + X1
  kX2 = 1,   ///< X2: its quadrature component [m/s]
  kZ1 = 2,   ///< Z1: first component of the phasor of the vertical oscillation [m/s]; v_z = Z1
  kZ2 = 3,   ///< Z2: its quadrature component [m/s]
  kW = 4,    ///< w: step angular frequency, in [2 pi f_min_hz, 2 pi f_max_hz] [rad/s]
  kA0 = 5,   ///< A0: forward-speed bias = R w, the stride-averaged speed, >= 0 [m/s]
  kDA0 = 6,  ///< dA0: rate of A0 (first-order Gauss-Markov) [m/s^2]
  kDW = 7,   ///< dw: rate of w (first-order Gauss-Markov) [rad/s^2]
};

inline constexpr std::size_t kDim = 8;
/// The phasor entries X1, X2, Z1, Z2 come first: kPhasors of them.
inline constexpr std::size_t kPhasors = 4;

}  // namespace gait

/// The 8-vector of the gait filter, indexed by gait::Index.
using GaitState = std::array<double, gait::kDim>;
/// A dense 8x8 matrix, row-major (covariance, Jacobian).
using GaitMatrix = std::array<std::array<double, gait::kDim>, gait::kDim>;

/// The transition of sec. 2.1 over dt [s], with a = exp(-dt / accel_tau_s) and
/// b = exp(-dt / omega_rate_tau_s): both phasors turn by phi = w dt, w and A0 integrate their rates,
/// the rates decay.
inline GaitState gait_transition(const GaitState& x, double dt_s, double accel_decay, double omega_rate_decay) noexcept {
  using namespace gait;
  double s, c;
  sincos(x[kW] * dt_s, s, c);
  GaitState y = x;
  y[kX1] = c * x[kX1] - s * x[kX2];
  y[kX2] = s * x[kX1] + c * x[kX2];
  y[kZ1] = c * x[kZ1] - s * x[kZ2];
  y[kZ2] = s * x[kZ1] + c * x[kZ2];
  y[kW] = x[kW] + dt_s * x[kDW];
  y[kDW] = omega_rate_decay * x[kDW];
  y[kA0] = x[kA0] + dt_s * x[kDA0];
  y[kDA0] = accel_decay * x[kDA0];
  return y;
}

/// Jacobian F of gait_transition at x: two 2x2 rotations, d(rotated phasor)/dw = dt J (rotated
/// phasor) with J = [[0, -1], [1, 0]], F[w][dw] = dt, F[dw][dw] = b, F[A0][dA0] = dt, F[dA0][dA0] = a.
inline GaitMatrix gait_transition_jacobian(const GaitState& x, double dt_s, double accel_decay,
                                           double omega_rate_decay) noexcept {
  using namespace gait;
  double s, c;
  sincos(x[kW] * dt_s, s, c);
  const GaitState y = gait_transition(x, dt_s, accel_decay, omega_rate_decay);
  GaitMatrix F{};
  F[kX1][kX1] = c;
  F[kX1][kX2] = -s;
  F[kX2][kX1] = s;
  F[kX2][kX2] = c;
  F[kZ1][kZ1] = c;
  F[kZ1][kZ2] = -s;
  F[kZ2][kZ1] = s;
  F[kZ2][kZ2] = c;
  F[kX1][kW] = -dt_s * y[kX2];
  F[kX2][kW] = dt_s * y[kX1];
  F[kZ1][kW] = -dt_s * y[kZ2];
  F[kZ2][kW] = dt_s * y[kZ1];
  F[kW][kW] = 1.0;
  F[kW][kDW] = dt_s;
  F[kDW][kDW] = omega_rate_decay;
  F[kA0][kA0] = 1.0;
  F[kA0][kDA0] = dt_s;
  F[kDA0][kDA0] = accel_decay;
  return F;
}

}  // namespace yoyogait
