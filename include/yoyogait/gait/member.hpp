/// @file gait/member.hpp
/// @brief One EKF of the gait filter (the steady-state filter, or a member of the start-up bank)
/// and its step: prediction with the process-noise model (sec. 2.2), measurement updates with the
/// harmonic cancellation and the innovation gate (sec. 2.1, 2.5), projection onto the bounds.
#pragma once

#include <array>
#include <cmath>
#include <cstddef>
#include <limits>

#include "yoyogait/covariance_guard.hpp"
#include "yoyogait/gait/decay_factors.hpp"
#include "yoyogait/gait/ekf.hpp"
#include "yoyogait/gait/harmonic.hpp"
#include "yoyogait/gait/innovation_gate.hpp"
#include "yoyogait/gait/state.hpp"
#include "yoyogait/gait/std_scale.hpp"
#include "yoyogait/math.hpp"

namespace yoyogait::gait {

/// The innovations of an EKF's last measurement update, per channel: nu = measurement minus
/// predicted measurement (v_z: after the v_x update, as the sequential updates use it) and its
/// variance S. NaN for a channel that was not used (not finite, out of range, standing for v_z).
struct Innovations {
  double vx_mps = std::numeric_limits<double>::quiet_NaN();
  double vz_mps = std::numeric_limits<double>::quiet_NaN();
  double var_vx_mps2 = std::numeric_limits<double>::quiet_NaN();
  double var_vz_mps2 = std::numeric_limits<double>::quiet_NaN();
};

/// One EKF of sec. 2.1. P: upper triangle only (i <= j).
struct Ekf {
  GaitMatrix P{};
  GaitState x{};
  double loglik = 0.0;  ///< innovation log-likelihood with exponential memory (bank only)
  double dw_lp = 0.0;   ///< dw low-passed over omega_rate_lp_tau_s: the trend test of q_rate
  Innovations innovations;  ///< of the last update (diagnostics; the filter does not read them)
  /// Set by the prediction: P- is within its variance bounds and the rounding of this step's
  /// updates cannot make P indefinite, so the covariance guard has nothing to do (sec. 2.7).
  bool psd_certified = false;
};

/// What a member's step needs of the configuration, derived once: noise densities, the initial
/// covariance, the bounds. Shared by every member; holds no state.
struct MemberModel {
  // Process noise densities (sec. 2.2), multiplied by dt at each prediction.
  double q_phasor = 0.0, q_phase = 0.0, q_omega = 0.0, q_speed = 0.0, q_accel = 0.0;
  bool use_omega_rate = true;
  double q_rate_lo = 0.0, q_rate_hi = 0.0, inv_rate_ref = 0.0;  ///< q_rate(dw_lp) between lo and hi
  bool rate_lowpass = true;                                     ///< omega_rate_lp_tau_s > 0
  bool use_harmonic = true;
  double q_harmonic = 0.0, harm_min2 = 0.0;  ///< harmonic noise; squared minimum fundamental amplitude
  // Initial variances of a member: phasors, w, A0, dA0, dw (0 without the rate state), harmonics.
  double p0_phasor = 0.0, p0_omega = 0.0, p0_speed = 0.0, p0_accel = 0.0, p0_rate = 0.0, p0_harmonic = 0.0;
  // The frequency bounds [rad/s].
  double w_min = 0.0, w_max = 0.0;
  /// The covariance guard's variance bounds (docs/default_estimator.md, sec. 2.7); infinite for
  /// the rates, which their decay bounds (and which within_variance_bounds does not test).
  std::array<double, kDim> max_variance{};
  /// The smallest process-noise density on the diagonal of Q: with ||H^T R^-1 H|| of the step's
  /// two updates (DecayFactors::Values::info), the certificate's lower bound on the eigenvalues (sec. 2.7).
  double q_floor = 0.0;

  /// A fresh member at frequency f_hz and speed A0, with its initial covariance.
  void reset(Ekf& e, double f_hz, double A0) const noexcept {
    e.x = GaitState{};
    e.x[kW] = kTwoPi * f_hz;
    e.x[kA0] = A0;
    reset_covariance(e);
    e.loglik = 0.0;
    e.dw_lp = 0.0;
    e.innovations = Innovations{};
  }
  void reset(Harmonic* h) const noexcept {
    h[kVx].reset(p0_harmonic);
    h[kVz].reset(p0_harmonic);
  }

  /// Projection onto the physical set: w in [w_min, w_max] (a rate pushing outward is zeroed), A0 >= 0.
  void clamp(Ekf& e) const noexcept {
    GaitState& x = e.x;
    if (x[kA0] < 0.0) {
      x[kA0] = 0.0;
      if (x[kDA0] < 0.0) x[kDA0] = 0.0;
    }
    if (x[kW] < w_min) {
      x[kW] = w_min;
      if (x[kDW] < 0.0) x[kDW] = 0.0;
    } else if (x[kW] > w_max) {
      x[kW] = w_max;
      if (x[kDW] > 0.0) x[kDW] = 0.0;
    }
  }

  /// Prediction of one EKF and its harmonics over dt (sec. 2.1-2.2).
  void predict(Ekf& e, Harmonic* h, double dt, const DecayFactors::Values& fc, bool oscillate) const noexcept {
    const double qb = q_speed * dt, qa = q_accel * dt;
    if (!oscillate) {
      predict_standing(e.x, e.P, dt, fc.accel_decay, qb, qa);
      e.psd_certified = false;  // no noise on the frozen oscillator, no lower bound: settle() tests
      return;
    }
    GaitProcessNoise q;
    q.phasor = q_phasor * dt;
    q.phase = q_phase * dt;
    q.omega = q_omega * dt;
    q.speed = qb;
    q.accel = qa;
    gait_predict(e.x, e.P, dt, fc.accel_decay, fc.rate_decay, q);
    if (use_omega_rate) {
      // Trend-adaptive rate noise on the low-passed rate (the raw dw would feed back on itself).
      if (rate_lowpass)
        e.dw_lp += fc.rate_lp_gain * (e.x[kDW] - e.dw_lp);
      else
        e.dw_lp = e.x[kDW];
      double rr = e.dw_lp * inv_rate_ref;
      rr = detail::py_min(rr * rr, 1.0);
      const double qlo = q_rate_lo;
      e.P[kDW][kDW] += (qlo + (q_rate_hi - qlo) * rr) * dt;
    }
    const double qh = q_harmonic * dt;
    h[kVx].predict(qh);
    h[kVz].predict(qh);
    certify(e, dt, fc.info);
  }

  /// The covariance guard's certificate (sec. 2.7): P- is within its variance bounds, and P+ stays
  /// positive definite: P- >= Q, so lambda_min(P+) >= 1 / (1 / (dt q_floor) + info) in exact
  /// arithmetic, and the rounding of the prediction and the two downdates moves an eigenvalue by a
  /// few units of round-off times trace(P-) (1 + dt^2 |phasors|^2), far within a margin of 1024
  /// units (kRoundingMargin). Multiplied out, no division; on walking data the two sides are some
  /// 1e8 apart.
  void certify(Ekf& e, double dt, double info) const noexcept {
    const GaitMatrix& P = e.P;
    const GaitState& x = e.x;
    const double trace = ((P[kX1][kX1] + P[kX2][kX2]) + (P[kZ1][kZ1] + P[kZ2][kZ2])) +
                         ((P[kW][kW] + P[kA0][kA0]) + (P[kDA0][kDA0] + P[kDW][kDW]));
    const double amp2 = (x[kX1] * x[kX1] + x[kX2] * x[kX2]) + (x[kZ1] * x[kZ1] + x[kZ2] * x[kZ2]);
    const double floor = dt * q_floor;
    e.psd_certified = within_variance_bounds(P) &
                      (kRoundingMargin * trace * (1.0 + dt * dt * amp2) * (1.0 + floor * info) <= floor);
  }

  /// The measurement updates of one EKF (sec. 2.1, 2.5): for each usable channel, cancel the
  /// predicted harmonic, gate, update, adapt the std scale, then let the harmonic learn from the
  /// residual. Returns true when a channel was rejected by the gate. fc: the step's measurement
  /// noise variances and std-scale gain.
  ///
  /// While walking the two channels are the sequential scalar updates of v_x (H = e_X1 + e_A0) and
  /// then v_z (H = e_Z1); P is touched once: the second update's P H^T is the first-updated column,
  /// P[:, Z1] - k1 ph1[Z1], and P -= k1 ph1^T + k2 ph2^T is the same as the two downdates in turn.
  /// kBank: a member of the start-up bank (acquiring: no gate, no harmonics, no std scale, the
  /// log-likelihood accumulates); else the one EKF of the steady state.
  /// Always inlined: as a call it would take ten arguments and spill the caller's registers.
  template <bool kBank>
  YOYOGAIT_ALWAYS_INLINE bool update(Ekf& e, Harmonic* h, double vx, double vz, bool use_x, bool use_z,
                                     bool oscillate, const InnovationGate& gate_, StdScale& scale,
                                     const DecayFactors::Values& fc) const noexcept {
    const double r_vx = fc.r_vx, r_vz = fc.r_vz, std_gain = fc.std_gain;
    bool rejected = false;
    const bool gate = !kBank && gate_.active();
    GaitState& x = e.x;
    e.innovations = Innovations{};
    if (!oscillate) {
      // Standing: v_x = A0 (H = e_A0).
      if (use_x) {
        const double nu = vx - x[kA0];
        const double S = e.P[kA0][kA0] + r_vx;
        e.innovations.vx_mps = nu;
        e.innovations.var_vx_mps2 = S;
        if (gate && gate_.rejects(nu, S)) {
          rejected = true;
        } else {
          double ph[kDim], k[kDim];
          const double zero[kDim] = {};
          column<kA0>(e.P, ph);
          const double inv_S = 1.0 / S;
          for (std::size_t r = 0; r < kDim; ++r) {
            k[r] = ph[r] * inv_S;
            x[r] += k[r] * nu;
          }
          downdate(e.P, k, ph, zero, zero);
          if (kBank) e.loglik += -0.5 * (nu * nu / S + std::log(S));
        }
      }
      clamp(e);
      if (!e.psd_certified) settle(e, true);
      return rejected;
    }
    const bool harm = !kBank && use_harmonic;
    // Zeroed only where a channel is not used: an accepted update writes every entry.
    double ph1[kDim], k1[kDim], ph2[kDim], k2[kDim];
    bool x_used = false;
    HarmonicStep hx, hz;
    if (use_x) {
      double u = 0.0, v = 0.0;
      if (harm) harmonic_basis(x[kX1], x[kX2], harm_min2, u, v);
      const double yc = vx - h[kVx].value(u, v);  // the predicted harmonic is cancelled first
      const double nu = yc - (x[kA0] + x[kX1]);
      const double S = e.P[kX1][kX1] + 2.0 * e.P[kX1][kA0] + e.P[kA0][kA0] + r_vx;
      e.innovations.vx_mps = nu;
      e.innovations.var_vx_mps2 = S;
      if (gate && gate_.rejects(nu, S)) {
        rejected = true;
      } else {
        double pa[kDim];
        column<kX1>(e.P, ph1);
        column<kA0>(e.P, pa);
        const double inv_S = 1.0 / S;
        for (std::size_t r = 0; r < kDim; ++r) {
          ph1[r] += pa[r];
          k1[r] = ph1[r] * inv_S;
          x[r] += k1[r] * nu;
        }
        x_used = true;
        if (kBank) e.loglik += -0.5 * (nu * nu / S + std::log(S));
        if (!kBank && scale.adapts()) scale.update(nu * nu * inv_S, std_gain);
        // The harmonic learns from the residual left by the updated fundamental.
        if (u != 0.0 || v != 0.0) {
          hx.on = true;
          hx.e = yc - (x[kA0] + x[kX1]);
          hx.S = h[kVx].prepare(u, v, r_vx, hx.ph0, hx.ph1);
        }
      }
    }
    if (!x_used)
      for (std::size_t r = 0; r < kDim; ++r) ph1[r] = k1[r] = 0.0;
    if (use_z) {
      double u = 0.0, v = 0.0;
      if (harm) harmonic_basis(x[kZ1], x[kZ2], harm_min2, u, v);
      const double yc = vz - h[kVz].value(u, v);
      const double nu = yc - x[kZ1];
      // P H^T of the v_z update with P after the v_x update.
      column<kZ1>(e.P, ph2);
      const double c1 = ph1[kZ1];
      for (std::size_t r = 0; r < kDim; ++r) ph2[r] -= k1[r] * c1;
      const double S = ph2[kZ1] + r_vz;
      e.innovations.vz_mps = nu;
      e.innovations.var_vz_mps2 = S;
      if (gate && gate_.rejects(nu, S)) {
        rejected = true;
        for (std::size_t r = 0; r < kDim; ++r) k2[r] = 0.0;
      } else {
        const double inv_S = 1.0 / S;
        for (std::size_t r = 0; r < kDim; ++r) {
          k2[r] = ph2[r] * inv_S;
          x[r] += k2[r] * nu;
        }
        if (kBank) e.loglik += -0.5 * (nu * nu / S + std::log(S));
        if (!kBank && scale.adapts()) scale.update(nu * nu * inv_S, std_gain);
        if (u != 0.0 || v != 0.0) {
          hz.on = true;
          hz.e = yc - x[kZ1];
          hz.S = h[kVz].prepare(u, v, r_vz, hz.ph0, hz.ph1);
        }
      }
    } else {
      for (std::size_t r = 0; r < kDim; ++r) ph2[r] = k2[r] = 0.0;
    }
    downdate(e.P, k1, ph1, k2, ph2);
    clamp(e);
    // The covariance guard (docs/default_estimator.md, sec. 2.7): out of line where the prediction
    // could not certify the step; a repair never needed on walking data.
    if (!e.psd_certified) settle(e, false);
    // Both harmonic gains from one division (1/S_x = S_z / (S_x S_z)).
    if (hx.on || hz.on) {
      const double inv = 1.0 / (hx.S * hz.S);
      if (hx.on) h[kVx].apply(hx.ph0, hx.ph1, hx.e, hz.S * inv);
      if (hz.on) h[kVz].apply(hz.ph0, hz.ph1, hz.e, hx.S * inv);
    }
    return rejected;
  }

  /// A measurement of w itself, w_meas [rad/s] with variance r [(rad/s)^2] (another evidence of the
  /// cadence: the feet's steps, online/foot_cadence.hpp): one scalar update, H = e_W, after the
  /// step's; the covariance guard tests the result (it is outside the step's certificate).
  void observe_w(Ekf& e, double w_meas, double r) const noexcept {
    double ph[kDim], k[kDim];
    const double zero[kDim] = {};
    column<kW>(e.P, ph);
    const double nu = w_meas - e.x[kW], inv_S = 1.0 / (ph[kW] + r);
    for (std::size_t i = 0; i < kDim; ++i) {
      k[i] = ph[i] * inv_S;
      e.x[i] += k[i] * nu;
    }
    downdate(e.P, k, ph, zero, zero);
    clamp(e);
    settle(e, false);
  }

  // The covariance guard (docs/default_estimator.md, sec. 2.7).

  /// P[i][i] += add, but not beyond the variance bound (nor below the current value).
  void inflate(Ekf& e, std::size_t i, double add) const noexcept {
    const double room = max_variance[i] - e.P[i][i];
    e.P[i][i] += detail::py_max(detail::py_min(add, room), 0.0);
  }

  /// True when no variance of P exceeds its bound (and none of X, Z, w, A0 is NaN; the rates have
  /// no bound).
  bool within_variance_bounds(const GaitMatrix& P) const noexcept {
    return ((P[kX1][kX1] <= max_variance[kX1]) & (P[kX2][kX2] <= max_variance[kX2])) &
           ((P[kZ1][kZ1] <= max_variance[kZ1]) & (P[kZ2][kZ2] <= max_variance[kZ2])) &
           ((P[kW][kW] <= max_variance[kW]) & (P[kA0][kA0] <= max_variance[kA0]));
  }

  /// The rest of the guard, out of line, for a step the prediction could not certify: variances
  /// beyond their bounds are bounded, and the covariance is tested and repaired if it fails. While
  /// standing (the oscillator frozen and decoupled from A0, dA0 since the stop, as after a reset),
  /// only the (A0, dA0) block changes, so that block is tested when the decoupling holds.
  YOYOGAIT_NOINLINE void settle(Ekf& e, bool standing) const noexcept {
    if (!within_variance_bounds(e.P)) bound_variances_of(e);
    if (standing && standing_block_positive_definite(e.P)) return;
    if (!positive_semidefinite_upper(e.P)) restore_covariance(e);
  }

  /// True when A0 and dA0 have no covariance with the other states and their 2x2 block is positive
  /// definite: then P is positive definite if the rest is, and the rest has not changed since the
  /// last step that was certified or tested.
  static bool standing_block_positive_definite(const GaitMatrix& P) noexcept {
    bool decoupled = true;
    for (std::size_t i = 0; i < kA0; ++i) decoupled &= (P[i][kA0] == 0.0) & (P[i][kDA0] == 0.0);
    decoupled &= (P[kA0][kDW] == 0.0) & (P[kDA0][kDW] == 0.0);
    const double a = P[kA0][kA0], b = P[kA0][kDA0], d = P[kDA0][kDA0];
    return decoupled & (a > 0.0) & (a * d - b * b > 0.0) & (a * d <= std::numeric_limits<double>::max());
  }

  /// Variances beyond their bounds: those rows and columns scaled (bound_variances), the
  /// correlations kept; a covariance that is not finite restarts from the initial one.
  YOYOGAIT_COLD void bound_variances_of(Ekf& e) const noexcept {
    GaitMatrix P = full(e.P);
    for (const auto& row : P)
      for (double v : row)
        if (!std::isfinite(v)) return reset_covariance(e);
    bound_variances(P, max_variance);
    e.P = P;
  }

  /// A covariance that the rounding of the updates left indefinite: the nearest positive definite
  /// matrix (eigenvalues at least 1e-12 of the largest), or the initial covariance if none is left.
  YOYOGAIT_COLD void restore_covariance(Ekf& e) const noexcept {
    GaitMatrix P = full(e.P);
    if (nearest_positive_definite(P))
      e.P = P;
    else
      reset_covariance(e);
  }

  /// Both halves of the symmetric P of which the upper triangle is kept.
  static GaitMatrix full(const GaitMatrix& P) noexcept {
    GaitMatrix F = P;
    for (std::size_t i = 0; i < kDim; ++i)
      for (std::size_t j = 0; j < i; ++j) F[i][j] = P[j][i];
    return F;
  }

  void reset_covariance(Ekf& e) const noexcept {
    e.psd_certified = false;
    e.P = GaitMatrix{};
    e.P[kX1][kX1] = e.P[kX2][kX2] = e.P[kZ1][kZ1] = e.P[kZ2][kZ2] = p0_phasor;
    e.P[kW][kW] = p0_omega;
    e.P[kA0][kA0] = p0_speed;
    e.P[kDA0][kDA0] = p0_accel;
    e.P[kDW][kDW] = p0_rate;
  }
};

}  // namespace yoyogait::gait
