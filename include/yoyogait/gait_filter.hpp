/// @file gait_filter.hpp
/// @brief The default estimator: a dual-phasor EKF with a positive, bounded step frequency.
///
/// Equations and tuning: docs/default_estimator.md (sections cited as "sec."). In short:
///
///   x = [X1, X2, Z1, Z2, w, A0, dA0, dw]                                           (sec. 2.1)
///   X <- Rot(w dt) X,  Z <- Rot(w dt) Z,  w <- w + dt dw,  dw <- b dw,
///   A0 <- A0 + dt dA0, dA0 <- a dA0,   a = exp(-dt / accel_tau_s), b = exp(-dt / omega_rate_tau_s)
///   v_x = A0 + X1 + h_x,   v_z = Z1 + h_z      (two sequential scalar updates; h: second harmonics)
///   Q = q_phasor dt I(X, Z) + q_phase dt g g^T + diag(q_omega, q_rate(dw_lp), q_speed, q_accel) dt,
///   g = [-X2, X1, -Z2, Z1, 0, 0, 0, 0]                                              (sec. 2.2)
///
/// Around it: a bank of EKFs at several start frequencies with a log-prior (start-up and
/// re-acquisition, sec. 2.3), a spectral initialisation, a walking/standing detector (sec. 2.4),
/// an innovation gate, the actual time step everywhere (sec. 2.5) and NIS-scaled standard
/// deviations (sec. 2.6). step() makes no heap allocation and cannot throw; everything lives in
/// fixed arrays. The steady state (walking, one EKF, the same dt as before) runs no exp, log,
/// bank or spectral code.
#pragma once

#include <array>
#include <cmath>
#include <cstddef>
#include <cstdint>

#include "yoyogait/config.hpp"
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
inline constexpr double kTwoPi = 6.283185307179586476925286766559;

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

namespace detail {
/// min(a, b) and max(a, b) as Python's: the first argument unless the second is strictly
/// smaller (larger). Unlike std::fmin/fmax they compile to one instruction, no libm call.
inline double py_min(double a, double b) noexcept { return b < a ? b : a; }
inline double py_max(double a, double b) noexcept { return b > a ? b : a; }
}  // namespace detail

/// Process noise of one prediction, already multiplied by dt (sec. 2.2). The frequency-rate noise
/// q_rate(dw_lp) dt is added by the filter after the prediction, where dw_lp is known.
struct GaitProcessNoise {
  double phasor = 0.0;  ///< q_phasor dt on each of X1, X2, Z1, Z2 [(m/s)^2]
  double phase = 0.0;   ///< q_phase dt, times g g^T [rad^2]
  double omega = 0.0;   ///< q_omega dt on w [(rad/s)^2]
  double speed = 0.0;   ///< q_speed dt on A0 [(m/s)^2]
  double accel = 0.0;   ///< q_accel dt on dA0 [(m/s^2)^2]
};

/// EKF prediction while walking: x <- f(x) (gait_transition), P <- F P F^T + Q (without the dw
/// term). P is symmetric and only its upper triangle (i <= j) is read and written.
///
/// F is never formed. With a = the phasors (X, Z), b = [w, A0, dA0, dw], F = [[Rr, g e_w^T], [0, L]]
/// (Rr = diag(Rot, Rot), g = dt gq, gq = [-X2', X1', -Z2', Z1'] at the rotated phasors), so
///   P'aa = Rr Paa Rr^T + gq u'^T + u' gq^T + q_phasor I,  u' = dt Rr P[a][w] + (dt^2 P[w][w] + q_phase) / 2 gq
///   P'ab = (Rr Pab + g P[w][b]) L^T,                        P'bb = L Pbb L^T + Q_bb.
/// Rot B Rot^T of a 2x2 block B leaves its rotation-invariant part (alpha I + beta J) alone and turns
/// its reflection part [[p, q], [q, -p]] by 2 phi: about 230 flops instead of ~1900 for the two
/// dense products of F P F^T.
inline void gait_predict(GaitState& x, GaitMatrix& P, double dt, double accel_decay, double omega_rate_decay,
                         const GaitProcessNoise& q) noexcept {
  using namespace gait;
  double s, c;
  sincos(x[kW] * dt, s, c);
  const double X1 = c * x[kX1] - s * x[kX2], X2 = s * x[kX1] + c * x[kX2];
  const double Z1 = c * x[kZ1] - s * x[kZ2], Z2 = s * x[kZ1] + c * x[kZ2];
  x[kX1] = X1;
  x[kX2] = X2;
  x[kZ1] = Z1;
  x[kZ2] = Z2;
  x[kW] += dt * x[kDW];
  x[kDW] *= omega_rate_decay;
  x[kA0] += dt * x[kDA0];
  x[kDA0] *= accel_decay;

  const double a = accel_decay, b = omega_rate_decay;
  const double g0 = -X2, g1 = X1, g2 = -Z2, g3 = Z1;  // gq: d(state)/d(phase) at the rotated phasors

  // Rotation by 2 phi of the reflection parts (cos 2phi, sin 2phi), halves folded in.
  const double C2 = 0.5 * ((c + s) * (c - s)), S2 = c * s;  // = cos(2 phi) / 2, sin(2 phi) / 2
  // XX and ZZ blocks (symmetric: no J part).
  const double mX = 0.5 * (P[0][0] + P[1][1]), hX = P[0][0] - P[1][1], qX = P[0][1];
  const double hXr = C2 * hX - (S2 + S2) * qX, qXr = S2 * hX + (C2 + C2) * qX;
  const double mZ = 0.5 * (P[2][2] + P[3][3]), hZ = P[2][2] - P[3][3], qZ = P[2][3];
  const double hZr = C2 * hZ - (S2 + S2) * qZ, qZr = S2 * hZ + (C2 + C2) * qZ;
  // XZ block (general): alpha I + beta J + [[p, q], [q, -p]].
  const double al = 0.5 * (P[0][2] + P[1][3]), be = 0.5 * (P[1][2] - P[0][3]);
  const double pXZ = P[0][2] - P[1][3], qXZ = P[0][3] + P[1][2];
  const double pr = C2 * pXZ - S2 * qXZ, qr = S2 * pXZ + C2 * qXZ;

  // V = Rr Pab + dt gq P[w][b] (4 x 4), column by column of b = w, A0, dA0, dw.
  double V[4][4];
  for (std::size_t j = 0; j < 4; ++j) {
    const std::size_t k = 4 + j;
    const double pw = dt * P[kW][k];
    V[0][j] = c * P[0][k] - s * P[1][k] + g0 * pw;
    V[1][j] = s * P[0][k] + c * P[1][k] + g1 * pw;
    V[2][j] = c * P[2][k] - s * P[3][k] + g2 * pw;
    V[3][j] = s * P[2][k] + c * P[3][k] + g3 * pw;
  }
  // u' = dt Rr P[a][w] + (dt^2 Pww + q_phase) / 2 gq, from the prior P[a][w] and Pww.
  const double Pww = P[kW][kW];
  const double hw = 0.5 * (dt * dt * Pww + q.phase);
  const double u0 = dt * (c * P[0][kW] - s * P[1][kW]) + hw * g0;
  const double u1 = dt * (s * P[0][kW] + c * P[1][kW]) + hw * g1;
  const double u2 = dt * (c * P[2][kW] - s * P[3][kW]) + hw * g2;
  const double u3 = dt * (s * P[2][kW] + c * P[3][kW]) + hw * g3;

  // P'bb = L Pbb L^T + Q_bb: w' = w + dt dw, A0' = A0 + dt dA0, dA0' = a dA0, dw' = b dw.
  const double m44 = P[4][4] + dt * P[4][7], m47 = P[4][7] + dt * P[7][7];
  const double m45 = P[4][5] + dt * P[5][7], m46 = P[4][6] + dt * P[6][7];
  const double m55 = P[5][5] + dt * P[5][6], m56 = P[5][6] + dt * P[6][6], m57 = P[5][7] + dt * P[6][7];
  const double p44 = m44 + dt * m47 + q.omega;
  const double p45 = m45 + dt * m46;
  const double p46 = a * m46;
  const double p47 = b * m47;
  const double p55 = m55 + dt * m56 + q.speed;
  const double p56 = a * m56;
  const double p57 = b * m57;
  const double p66 = a * a * P[6][6] + q.accel;
  const double p67 = a * b * P[6][7];
  const double p77 = b * b * P[7][7];

  // Write P'aa (rotation part + symmetric rank-2 + q_phasor I).
  P[0][0] = mX + hXr + 2.0 * g0 * u0 + q.phasor;
  P[1][1] = mX - hXr + 2.0 * g1 * u1 + q.phasor;
  P[0][1] = qXr + g0 * u1 + u0 * g1;
  P[2][2] = mZ + hZr + 2.0 * g2 * u2 + q.phasor;
  P[3][3] = mZ - hZr + 2.0 * g3 * u3 + q.phasor;
  P[2][3] = qZr + g2 * u3 + u2 * g3;
  P[0][2] = al + pr + g0 * u2 + u0 * g2;
  P[1][3] = al - pr + g1 * u3 + u1 * g3;
  P[0][3] = qr - be + g0 * u3 + u0 * g3;
  P[1][2] = qr + be + g1 * u2 + u1 * g2;
  // P'ab = V L^T.
  for (std::size_t i = 0; i < 4; ++i) {
    P[i][kW] = V[i][0] + dt * V[i][3];
    P[i][kA0] = V[i][1] + dt * V[i][2];
    P[i][kDA0] = a * V[i][2];
    P[i][kDW] = b * V[i][3];
  }
  P[4][4] = p44;
  P[4][5] = p45;
  P[4][6] = p46;
  P[4][7] = p47;
  P[5][5] = p55;
  P[5][6] = p56;
  P[5][7] = p57;
  P[6][6] = p66;
  P[6][7] = p67;
  P[7][7] = p77;
}

/// The gait filter (the default estimator): everything of default_estimator.py's DefaultEstimator.
/// Use it through yoyogait::Estimator; this class is public for tests and for embedding.
class GaitFilter {
 public:
  /// What a step did with its sample (mapped to yoyogait::Status by the Estimator). One per sample,
  /// by precedence: kNumerical, then kNonFinite, then kOutOfRange, then kOutlier, then kOk.
  enum class Outcome : std::uint8_t {
    kOk = 0,          ///< both channels used
    kNonFinite = 1,   ///< a channel (or dt) was NaN or infinite, or dt < 0: that channel (or the sample) not used
    kOutOfRange = 2,  ///< a channel was above max_abs_velocity_mps: not used
    kOutlier = 3,     ///< a channel failed the innovation gate: not used
    kNumerical = 4,   ///< the filter became non-finite and was restarted (not seen with in-range data)
  };

  /// Estimates after a step (sec. 2.6).
  struct Output {
    GaitState x{};                      ///< state of the active EKF
    double step_frequency_std_hz = 0;   ///< sqrt(lambda P_ww) / 2 pi [Hz]
    double speed_std_mps = 0;           ///< sqrt(lambda P_A0A0 + floor^2) [m/s]
    double amp_x_mps = 0;               ///< |X| [m/s]
    double vx_hat_mps = 0;              ///< model reconstruction A0 + X1 (standing: A0) [m/s]
    double vz_hat_mps = 0;              ///< model reconstruction Z1 (standing: 0) [m/s]
    double vx_hat_h2_mps = 0;           ///< ... with the second harmonic [m/s]
    double vz_hat_h2_mps = 0;           ///< ... with the second harmonic [m/s]
    double R_m = 0;                     ///< R = A0 / w, low-passed while walking [m]
    double r_m = 0;                     ///< r = |Z| / w, low-passed while walking [m]
    double std_scale = 1;               ///< lambda [1]
    bool walking = false;               ///< the detector says walking
    bool acquiring = false;             ///< the bank is running (start-up / re-acquisition)
    bool radii_updated = false;         ///< R, r were updated at this step
  };

  /// (v_x, v_z) predicted ahead [m/s].
  struct Prediction {
    double vx_mps = 0.0;
    double vz_mps = 0.0;
  };

  GaitFilter() noexcept : GaitFilter(EstimatorConfig{}) {}

  /// config must pass EstimatorConfig::validate() (the Estimator checks it).
  explicit GaitFilter(const EstimatorConfig& config) noexcept : cfg_(config) {
    using gait::kTwoPi;
    nbank_ = cfg_.bank_size;
    nominal_dt_ = cfg_.sample_time_s;
    w_min_ = kTwoPi * cfg_.f_min_hz;
    w_max_ = kTwoPi * cfg_.f_max_hz;
    r_vx_ = cfg_.meas_vx_std_mps * cfg_.meas_vx_std_mps;
    r_vz_ = cfg_.meas_vz_std_mps * cfg_.meas_vz_std_mps;
    gate2_ = cfg_.gate_sigma * cfg_.gate_sigma;
    harm_min2_ = cfg_.harmonic_min_amp_mps * cfg_.harmonic_min_amp_mps;
    inv_rate_ref_ = 1.0 / cfg_.omega_rate_ref_rad_s2;
    speed_floor2_ = cfg_.speed_std_floor_mps * cfg_.speed_std_floor_mps;
    vz_rms_on2_ = cfg_.walk_vz_rms_on_mps * cfg_.walk_vz_rms_on_mps;
    vz_rms_off2_ = cfg_.walk_vz_rms_off_mps * cfg_.walk_vz_rms_off_mps;
    reset();
  }

  /// Back to the state before the first sample.
  void reset() noexcept {
    started_ = false;
    acquiring_ = true;
    acq_walk_time_s_ = 0.0;
    best_ = 0;
    walking_ = false;
    ema_vx_ = 0.0;
    ema_vz2_ = 0.0;
    R_m_ = cfg_.initial_R_m;
    r_m_ = cfg_.initial_r_m;
    have_params_ = false;
    last_w_ = gait::kTwoPi * cfg_.bank_prior_f_hz;
    n_rejects_ = 0;
    t_at_bound_s_ = 0.0;
    lambda_ = 1.0;
    t_now_s_ = 0.0;
    buf_n_ = 0;
    buf_head_ = 0;
    spec_done_ = false;
    radii_updated_ = false;
    out_hx_ = out_hz_ = 0.0;
    factors_.dt = -1.0;
    // Defined outputs (w > 0) even before the first finite sample.
    start_acquisition(0.0, false, 0.0);
    collapse();
    acquiring_ = true;
  }

  /// One sample at the nominal time step (sample_time_s) since the previous one.
  Outcome step(double vx_mps, double vz_mps) noexcept { return advance(vx_mps, vz_mps, nominal_dt_); }

  /// One sample dt_s [s] after the previous one. A non-finite or negative dt_s: the sample is not
  /// used (kNonFinite). dt_s of the first sample is not used.
  Outcome step(double vx_mps, double vz_mps, double dt_s) noexcept {
    if (!(std::isfinite(dt_s) && dt_s >= 0.0)) return Outcome::kNonFinite;
    return advance(vx_mps, vz_mps, dt_s);
  }

  /// The estimates after the last step (sec. 2.6).
  Output output() const noexcept {
    using namespace gait;
    const Ekf& f = active();
    const GaitState& x = f.x;
    Output o;
    o.x = x;
    if (walking_) {
      o.vx_hat_mps = x[kA0] + x[kX1];  // model reconstruction: R w + phase-shifted oscillation
      o.vz_hat_mps = x[kZ1];
      // The second harmonics at the posterior phasors (computed at the end of the step).
      o.vx_hat_h2_mps = o.vx_hat_mps + out_hx_;
      o.vz_hat_h2_mps = o.vz_hat_mps + out_hz_;
    } else {
      o.vx_hat_mps = o.vx_hat_h2_mps = x[kA0];
      o.vz_hat_mps = o.vz_hat_h2_mps = 0.0;
    }
    o.amp_x_mps = std::sqrt(x[kX1] * x[kX1] + x[kX2] * x[kX2]);
    // |Z|, the X-Z phase relation and the rates: Estimate derives them from x on demand.
    const double lam = lambda_;
    constexpr double kInvTwoPi = 0.15915494309189533576888376337251;
    o.step_frequency_std_hz = std::sqrt(detail::py_max(lam * f.P[kW][kW], 0.0)) * kInvTwoPi;
    o.speed_std_mps = std::sqrt(detail::py_max(lam * f.P[kA0][kA0], 0.0) + speed_floor2_);
    o.R_m = R_m_;
    o.r_m = r_m_;
    o.std_scale = lam;
    o.walking = walking_;
    o.acquiring = acquiring_;
    o.radii_updated = radii_updated_;
    return o;
  }

  /// (v_x, v_z) h_s [s] after the last sample: phasors turned by w h + dw h^2 / 2, A0 held, second
  /// harmonics added unless harmonics is false or the bank is running. Standing: (A0, 0).
  Prediction predict(double h_s, bool harmonics = true) const noexcept {
    using namespace gait;
    const GaitState& x = active().x;
    const double A0 = x[kA0];
    if (!walking_) return Prediction{A0, 0.0};
    double s, c;
    sincos(x[kW] * h_s + 0.5 * x[kDW] * h_s * h_s, s, c);
    const double X1 = c * x[kX1] - s * x[kX2], X2 = s * x[kX1] + c * x[kX2];
    const double Z1 = c * x[kZ1] - s * x[kZ2], Z2 = s * x[kZ1] + c * x[kZ2];
    Prediction p{A0 + X1, Z1};
    if (harmonics && cfg_.use_harmonic && !acquiring_) {
      const Harmonic* fh = active_h();
      double ux, vx2, uz, vz2;
      harmonic_basis(X1, X2, ux, vx2);
      harmonic_basis(Z1, Z2, uz, vz2);
      p.vx_mps += fh[0].value(ux, vx2);
      p.vz_mps += fh[1].value(uz, vz2);
    }
    return p;
  }

  const EstimatorConfig& config() const noexcept { return cfg_; }
  /// State of the active EKF (the best bank member while acquiring).
  const GaitState& state() const noexcept { return active().x; }
  /// Covariance of the active EKF, both triangles filled.
  GaitMatrix covariance() const noexcept {
    GaitMatrix P = active().P;
    for (std::size_t i = 0; i < gait::kDim; ++i)
      for (std::size_t j = 0; j < i; ++j) P[i][j] = P[j][i];
    return P;
  }
  bool walking() const noexcept { return walking_; }
  bool acquiring() const noexcept { return acquiring_; }
  double std_scale() const noexcept { return lambda_; }

 private:
  /// One EKF of sec. 2.1. P: upper triangle only (i <= j).
  struct Ekf {
    GaitMatrix P{};
    GaitState x{};
    double loglik = 0.0;  ///< innovation log-likelihood with exponential memory (bank only)
    double dw_lp = 0.0;   ///< dw low-passed over omega_rate_lp_tau_s: the trend test of q_rate
  };

  /// Second harmonic of one channel: h = c0 cos 2th + c1 sin 2th, th the angle of the channel's
  /// phasor; (c0, c1) by a 2-state random-walk Kalman filter. P symmetric: p00, p01, p11.
  struct Harmonic {
    double c0 = 0.0, c1 = 0.0, p00 = 0.0, p01 = 0.0, p11 = 0.0;
    double value(double u, double v) const noexcept { return c0 * u + c1 * v; }
    /// Kalman update with the regressor (u, v), residual e and noise r, in two halves so that two
    /// channels can share one division: prepare() returns S, apply() takes 1/S.
    double prepare(double u, double v, double r, double& ph0, double& ph1) const noexcept {
      ph0 = p00 * u + p01 * v;
      ph1 = p01 * u + p11 * v;
      return u * ph0 + v * ph1 + r;
    }
    void apply(double ph0, double ph1, double e, double inv_S) noexcept {
      const double k0 = ph0 * inv_S, k1 = ph1 * inv_S;
      c0 += k0 * e;
      c1 += k1 * e;
      p00 -= k0 * ph0;
      p01 -= k0 * ph1;
      p11 -= k1 * ph1;
    }
  };

  /// A pending harmonic update (sec. 2.1): the coefficients are needed only at the next step.
  struct HarmonicStep {
    bool on = false;
    double ph0 = 0.0, ph1 = 0.0, e = 0.0, S = 1.0;
  };

  /// Factors that depend on dt only through exp: recomputed only when dt changes by more than a
  /// relative 1e-9 (differences of regular timestamps jitter by rounding; a factor then differs
  /// from its exact value by < 1e-10 relative).
  struct Factors {
    double dt = -1.0;
    double accel_decay = 1.0, rate_decay = 1.0, rate_lp_gain = 0.0, walk_gain = 0.0, std_gain = 0.0,
           forget = 1.0, radii_gain = 0.0;
  };

  const Ekf& active() const noexcept { return acquiring_ ? bank_[best_] : main_; }
  Ekf& active() noexcept { return acquiring_ ? bank_[best_] : main_; }
  const Harmonic* active_h() const noexcept { return acquiring_ ? bank_h_[best_].data() : main_h_.data(); }
  bool harmonics_on() const noexcept { return cfg_.use_harmonic && !acquiring_; }
  Harmonic* main_or_best_h() noexcept { return acquiring_ ? bank_h_[best_].data() : main_h_.data(); }

  /// (cos 2th, sin 2th) of the phasor (p1, p2) by the double-angle formulas; (0, 0) if too small.
  void harmonic_basis(double p1, double p2, double& u, double& v) const noexcept {
    const double a2 = p1 * p1 + p2 * p2;
    if (a2 < harm_min2_) {
      u = v = 0.0;
      return;
    }
    const double inv = 1.0 / a2;
    u = (p1 * p1 - p2 * p2) * inv;
    v = 2.0 * p1 * p2 * inv;
  }

  const Factors& factors(double dt) noexcept {
    // Regular sampling repeats dt (up to rounding of timestamp differences): no exp then.
    if (std::fabs(dt - factors_.dt) <= 1e-9 * dt) return factors_;
    Factors& f = factors_;
    f.dt = dt;
    f.accel_decay = std::exp(-dt / cfg_.accel_tau_s);
    f.rate_decay = std::exp(-dt / cfg_.omega_rate_tau_s);
    f.rate_lp_gain = cfg_.omega_rate_lp_tau_s > 0.0 ? 1.0 - std::exp(-dt / cfg_.omega_rate_lp_tau_s) : 1.0;
    f.walk_gain = dt > 0.0 ? 1.0 - std::exp(-dt / cfg_.walk_tau_s) : 0.0;
    f.std_gain = dt > 0.0 ? 0.5 * (1.0 - std::exp(-dt / cfg_.std_scale_tau_s)) : 0.0;
    f.forget = std::exp(-dt / cfg_.bank_forget_s);
    f.radii_gain = 1.0 - std::exp(-dt / cfg_.radii_tau_s);
    return f;
  }

  void reset_ekf(Ekf& e, double f_hz, double A0) const noexcept {
    using namespace gait;
    e.x = GaitState{};
    e.x[kW] = kTwoPi * f_hz;
    e.x[kA0] = A0;
    e.P = GaitMatrix{};
    const double sp = cfg_.p0_phasor_std_mps * cfg_.p0_phasor_std_mps;
    e.P[kX1][kX1] = e.P[kX2][kX2] = e.P[kZ1][kZ1] = e.P[kZ2][kZ2] = sp;
    const double sw = kTwoPi * cfg_.p0_f_std_hz;
    e.P[kW][kW] = sw * sw;
    e.P[kA0][kA0] = cfg_.p0_speed_std_mps * cfg_.p0_speed_std_mps;
    e.P[kDA0][kDA0] = cfg_.p0_accel_std_mps2 * cfg_.p0_accel_std_mps2;
    e.P[kDW][kDW] = cfg_.use_omega_rate ? cfg_.p0_omega_rate_std_rad_s2 * cfg_.p0_omega_rate_std_rad_s2 : 0.0;
    e.loglik = 0.0;
    e.dw_lp = 0.0;
  }

  void reset_harmonic(Harmonic& h) const noexcept {
    h.c0 = h.c1 = 0.0;
    h.p00 = h.p11 = cfg_.p0_harmonic_std_mps * cfg_.p0_harmonic_std_mps;
    h.p01 = 0.0;
  }

  /// Sec. 2.3: every member restarts at its frequency with speed A0; the member nearest to the hint
  /// (re-acquisition: the last frequency) or to the typical frequency gets the log-prior, and the hint.
  void start_acquisition(double A0, bool has_hint, double f_hint_hz) noexcept {
    for (std::size_t i = 0; i < nbank_; ++i) {
      reset_ekf(bank_[i], cfg_.bank_f_hz[i], A0);
      reset_harmonic(bank_h_[i][0]);
      reset_harmonic(bank_h_[i][1]);
    }
    const double f_pri = has_hint ? f_hint_hz : cfg_.bank_prior_f_hz;
    std::size_t j = 0;
    for (std::size_t i = 1; i < nbank_; ++i)
      if (std::fabs(cfg_.bank_f_hz[i] - f_pri) < std::fabs(cfg_.bank_f_hz[j] - f_pri)) j = i;
    if (has_hint) reset_ekf(bank_[j], f_hint_hz, A0);
    bank_[j].loglik = cfg_.bank_prior_bonus_nats;
    best_ = j;
    acquiring_ = true;
    acq_walk_time_s_ = 0.0;
    buf_n_ = 0;
    buf_head_ = 0;
    spec_done_ = false;
    t_at_bound_s_ = 0.0;
  }

  /// The bank's best member becomes the one EKF.
  void collapse() noexcept {
    main_ = bank_[best_];
    main_h_ = bank_h_[best_];
    acquiring_ = false;
  }

  /// Standing: the oscillator is frozen; only A0 and dA0 evolve. F = I + dt e_A0 e_dA0^T + (a - 1) e_dA0 e_dA0^T.
  static void predict_standing(Ekf& e, double dt, double a, double qb, double qa) noexcept {
    using namespace gait;
    GaitState& x = e.x;
    GaitMatrix& P = e.P;
    x[kA0] += dt * x[kDA0];
    x[kDA0] *= a;
    // Rows and columns A0 (5) and dA0 (6); upper triangle: P[i][5], P[i][6] for i < 5, P[5][j], P[6][j] for j > 6.
    for (std::size_t i = 0; i < kA0; ++i) {
      P[i][kA0] += dt * P[i][kDA0];
      P[i][kDA0] *= a;
    }
    P[kA0][kDW] += dt * P[kDA0][kDW];
    P[kDA0][kDW] *= a;
    const double m55 = P[kA0][kA0] + dt * P[kA0][kDA0], m56 = P[kA0][kDA0] + dt * P[kDA0][kDA0];
    P[kA0][kA0] = m55 + dt * m56 + qb;
    P[kA0][kDA0] = a * m56;
    P[kDA0][kDA0] = a * a * P[kDA0][kDA0] + qa;
  }

  /// Column col of the symmetric P (upper triangle stored): P[r][col] for every r.
  template <std::size_t Col>
  static void column(const GaitMatrix& P, double (&out)[gait::kDim]) noexcept {
    for (std::size_t r = 0; r < gait::kDim; ++r) out[r] = r <= Col ? P[r][Col] : P[Col][r];
  }

  /// P -= k1 ph1^T + k2 ph2^T on the upper triangle (rows from their first even column, so that
  /// pairs of entries go together; the few lower entries this touches are never read).
  template <std::size_t R>
  static void downdate_row(GaitMatrix& P, const double (&k1)[gait::kDim], const double (&ph1)[gait::kDim],
                           const double (&k2)[gait::kDim], const double (&ph2)[gait::kDim]) noexcept {
    constexpr std::size_t c0 = R & ~std::size_t{1};  // compile-time bounds: unrolled, in pairs
    const double a = k1[R], b = k2[R];
    for (std::size_t c = c0; c < gait::kDim; ++c) P[R][c] -= a * ph1[c] + b * ph2[c];
  }
  static void downdate(GaitMatrix& P, const double (&k1)[gait::kDim], const double (&ph1)[gait::kDim],
                       const double (&k2)[gait::kDim], const double (&ph2)[gait::kDim]) noexcept {
    downdate_row<0>(P, k1, ph1, k2, ph2);
    downdate_row<1>(P, k1, ph1, k2, ph2);
    downdate_row<2>(P, k1, ph1, k2, ph2);
    downdate_row<3>(P, k1, ph1, k2, ph2);
    downdate_row<4>(P, k1, ph1, k2, ph2);
    downdate_row<5>(P, k1, ph1, k2, ph2);
    downdate_row<6>(P, k1, ph1, k2, ph2);
    downdate_row<7>(P, k1, ph1, k2, ph2);
  }

  /// Projection onto the physical set: w in [w_min, w_max] (a rate pushing outward is zeroed), A0 >= 0.
  void clamp(Ekf& e) const noexcept {
    using namespace gait;
    GaitState& x = e.x;
    if (x[kA0] < 0.0) {
      x[kA0] = 0.0;
      if (x[kDA0] < 0.0) x[kDA0] = 0.0;
    }
    if (x[kW] < w_min_) {
      x[kW] = w_min_;
      if (x[kDW] < 0.0) x[kDW] = 0.0;
    } else if (x[kW] > w_max_) {
      x[kW] = w_max_;
      if (x[kDW] > 0.0) x[kDW] = 0.0;
    }
  }

  /// Prediction of one EKF and its harmonics over dt (sec. 2.1-2.2).
  void predict_member(Ekf& e, Harmonic* h, double dt, const Factors& fc, bool oscillate) const noexcept {
    const double qb = cfg_.q_speed_m2_per_s3 * dt, qa = cfg_.q_accel_m2_per_s5 * dt;
    if (!oscillate) {
      predict_standing(e, dt, fc.accel_decay, qb, qa);
      return;
    }
    GaitProcessNoise q;
    q.phasor = cfg_.q_phasor_m2_per_s3 * dt;
    q.phase = cfg_.q_phase_rad2_per_s * dt;
    q.omega = cfg_.q_omega_rad2_per_s3 * dt;
    q.speed = qb;
    q.accel = qa;
    gait_predict(e.x, e.P, dt, fc.accel_decay, fc.rate_decay, q);
    if (cfg_.use_omega_rate) {
      // Trend-adaptive rate noise on the low-passed rate (the raw dw would feed back on itself).
      if (cfg_.omega_rate_lp_tau_s > 0.0)
        e.dw_lp += fc.rate_lp_gain * (e.x[gait::kDW] - e.dw_lp);
      else
        e.dw_lp = e.x[gait::kDW];
      double rr = e.dw_lp * inv_rate_ref_;
      rr = detail::py_min(rr * rr, 1.0);
      const double qlo = cfg_.q_omega_rate_lo_rad2_per_s5;
      e.P[gait::kDW][gait::kDW] += (qlo + (cfg_.q_omega_rate_hi_rad2_per_s5 - qlo) * rr) * dt;
    }
    const double qh = cfg_.q_harmonic_m2_per_s3 * dt;
    h[0].p00 += qh;
    h[0].p11 += qh;
    h[1].p00 += qh;
    h[1].p11 += qh;
  }

  /// The measurement updates of one EKF (sec. 2.1, 2.5): for each usable channel, cancel the
  /// predicted harmonic, gate, update, adapt lambda, then let the harmonic learn from the residual.
  /// Returns true when a channel was rejected by the gate.
  ///
  /// While walking the two channels are the sequential scalar updates of v_x (H = e_X1 + e_A0) and
  /// then v_z (H = e_Z1); P is touched once: the second update's P H^T is the first-updated column,
  /// P[:, Z1] - k1 ph1[Z1], and P -= k1 ph1^T + k2 ph2^T is the same as the two downdates in turn.
  /// kBank: a member of the start-up bank (acquiring: no gate, no harmonics, no lambda, the
  /// log-likelihood accumulates); else the one EKF of the steady state.
  template <bool kBank>
  bool update_member(Ekf& e, Harmonic* h, double vx, double vz, bool use_x, bool use_z, bool oscillate,
                     double std_gain) noexcept {
    using namespace gait;
    bool rejected = false;
    const bool gate = !kBank && n_rejects_ < cfg_.gate_max_consecutive;
    GaitState& x = e.x;
    if (!oscillate) {
      // Standing: v_x = A0 (H = e_A0).
      if (use_x) {
        const double nu = vx - x[kA0];
        const double S = e.P[kA0][kA0] + r_vx_;
        if (gate && nu * nu > gate2_ * S) {
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
      return rejected;
    }
    const bool harm = !kBank && cfg_.use_harmonic;
    double ph1[kDim] = {}, k1[kDim] = {}, ph2[kDim], k2[kDim] = {};
    HarmonicStep hx, hz;
    if (use_x) {
      double u = 0.0, v = 0.0;
      if (harm) harmonic_basis(x[kX1], x[kX2], u, v);
      const double yc = vx - h[0].value(u, v);  // the predicted harmonic is cancelled first
      const double nu = yc - (x[kA0] + x[kX1]);
      const double S = e.P[kX1][kX1] + 2.0 * e.P[kX1][kA0] + e.P[kA0][kA0] + r_vx_;
      if (gate && nu * nu > gate2_ * S) {
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
        if (kBank) e.loglik += -0.5 * (nu * nu / S + std::log(S));
        if (!kBank && cfg_.std_scale_adapt) lambda_update(nu * nu * inv_S, std_gain);
        // The harmonic learns from the residual left by the updated fundamental.
        if (u != 0.0 || v != 0.0) {
          hx.on = true;
          hx.e = yc - (x[kA0] + x[kX1]);
          hx.S = h[0].prepare(u, v, r_vx_, hx.ph0, hx.ph1);
        }
      }
    }
    if (use_z) {
      double u = 0.0, v = 0.0;
      if (harm) harmonic_basis(x[kZ1], x[kZ2], u, v);
      const double yc = vz - h[1].value(u, v);
      const double nu = yc - x[kZ1];
      // P H^T of the v_z update with P after the v_x update.
      column<kZ1>(e.P, ph2);
      const double c1 = ph1[kZ1];
      for (std::size_t r = 0; r < kDim; ++r) ph2[r] -= k1[r] * c1;
      const double S = ph2[kZ1] + r_vz_;
      if (gate && nu * nu > gate2_ * S) {
        rejected = true;
      } else {
        const double inv_S = 1.0 / S;
        for (std::size_t r = 0; r < kDim; ++r) {
          k2[r] = ph2[r] * inv_S;
          x[r] += k2[r] * nu;
        }
        if (kBank) e.loglik += -0.5 * (nu * nu / S + std::log(S));
        if (!kBank && cfg_.std_scale_adapt) lambda_update(nu * nu * inv_S, std_gain);
        if (u != 0.0 || v != 0.0) {
          hz.on = true;
          hz.e = yc - x[kZ1];
          hz.S = h[1].prepare(u, v, r_vz_, hz.ph0, hz.ph1);
        }
      }
    } else {
      for (std::size_t r = 0; r < kDim; ++r) ph2[r] = 0.0;
    }
    downdate(e.P, k1, ph1, k2, ph2);
    clamp(e);
    // Both harmonic gains from one division (1/S_x = S_z / (S_x S_z)).
    if (hx.on || hz.on) {
      const double inv = 1.0 / (hx.S * hz.S);
      if (hx.on) h[0].apply(hx.ph0, hx.ph1, hx.e, hz.S * inv);
      if (hz.on) h[1].apply(hz.ph0, hz.ph1, hz.e, hx.S * inv);
    }
    return rejected;
  }

  void lambda_update(double nis, double gain) noexcept {
    const double lam = lambda_ + gain * (nis - lambda_);
    lambda_ = detail::py_min(detail::py_max(lam, cfg_.std_scale_min), cfg_.std_scale_max);
  }

  void update_walking(double vx, double vz, bool use_x, bool use_z, double gain) noexcept {
    if (use_x) ema_vx_ += gain * (vx - ema_vx_);
    if (use_z) ema_vz2_ += gain * (vz * vz - ema_vz2_);
    // RMS(v_z) = sqrt(LP(v_z^2)) compared through its square (no square root per step).
    const double ms = detail::py_max(ema_vz2_, 0.0);
    if (walking_) {
      if (ema_vx_ < cfg_.walk_speed_off_mps && ms < vz_rms_off2_) walking_ = false;
    } else if (ema_vx_ > cfg_.walk_speed_on_mps || ms > vz_rms_on2_) {
      walking_ = true;
    }
  }

  // ------------------------------------------------------------ spectral initialisation (start-up)

  /// Solves A x = b for a small symmetric positive-definite A by Cholesky (fixed size).
  template <std::size_t N>
  static void solve_spd(const double (&A)[N][N], const double (&b)[N], double (&x)[N]) noexcept {
    double L[N][N] = {};
    for (std::size_t i = 0; i < N; ++i) {
      for (std::size_t j = 0; j <= i; ++j) {
        double s = A[i][j];
        for (std::size_t k = 0; k < j; ++k) s -= L[i][k] * L[j][k];
        if (i == j)
          L[i][i] = s > 1e-300 ? std::sqrt(s) : 1e-150;
        else
          L[i][j] = s / L[j][j];
      }
    }
    double y[N];
    for (std::size_t i = 0; i < N; ++i) {
      double s = b[i];
      for (std::size_t k = 0; k < i; ++k) s -= L[i][k] * y[k];
      y[i] = s / L[i][i];
    }
    for (std::size_t ii = N; ii-- > 0;) {
      double s = y[ii];
      for (std::size_t k = ii + 1; k < N; ++k) s -= L[k][ii] * x[k];
      x[ii] = s / L[ii][ii];
    }
  }

  /// Weighted residual of two linear least-squares fits at angular frequency w over the buffer:
  /// v_x(tau) = a + b tau + Xc cos(w tau) + Xs sin(w tau), v_z(tau) = c + Zc cos(w tau) + Zs sin(w tau).
  double ls_cost(double w, std::size_t n, std::size_t i0, double t_last, double* sol) const noexcept {
    const std::size_t nb = cfg_.spectral_buffer_samples;
    double A[4][4] = {}, bx[4] = {}, bz[3] = {};
    double yy_x = 0.0, yy_z = 0.0;
    for (std::size_t q = 0; q < n; ++q) {
      const std::size_t i = (i0 + q) % nb;
      const double tau = buf_t_[i] - t_last;
      const double cs = std::cos(w * tau), sn = std::sin(w * tau);
      const double phi[4] = {1.0, tau, cs, sn};
      for (std::size_t a = 0; a < 4; ++a) {
        for (std::size_t b = a; b < 4; ++b) A[a][b] += phi[a] * phi[b];
        bx[a] += phi[a] * buf_x_[i];
      }
      bz[0] += buf_z_[i];
      bz[1] += cs * buf_z_[i];
      bz[2] += sn * buf_z_[i];
      yy_x += buf_x_[i] * buf_x_[i];
      yy_z += buf_z_[i] * buf_z_[i];
    }
    for (std::size_t a = 0; a < 4; ++a)
      for (std::size_t b = 0; b < a; ++b) A[a][b] = A[b][a];
    constexpr double ridge = 1e-9;
    double Ax[4][4];
    for (std::size_t a = 0; a < 4; ++a)
      for (std::size_t b = 0; b < 4; ++b) Ax[a][b] = A[a][b] + (a == b ? ridge : 0.0);
    const double Az[3][3] = {{A[0][0] + ridge, A[0][2], A[0][3]},
                             {A[2][0], A[2][2] + ridge, A[2][3]},
                             {A[3][0], A[3][2], A[3][3] + ridge}};
    double ax[4], az[3];
    solve_spd(Ax, bx, ax);
    solve_spd(Az, bz, az);
    const double rss_x = yy_x - (bx[0] * ax[0] + bx[1] * ax[1] + bx[2] * ax[2] + bx[3] * ax[3]);
    const double rss_z = yy_z - (bz[0] * az[0] + bz[1] * az[1] + bz[2] * az[2]);
    if (sol) {
      for (std::size_t i = 0; i < 4; ++i) sol[i] = ax[i];
      for (std::size_t i = 0; i < 3; ++i) sol[4 + i] = az[i];
    }
    return rss_x / r_vx_ + rss_z / r_vz_;
  }

  /// Grid search of ls_cost over [f_min, f_max], parabolic refinement; the fit seeds the least
  /// likely bank member (phasors at the last sample: X = (Xc, -Xs), Z = (Zc, -Zs)). Start-up only.
  void spectral_seed() noexcept {
    using namespace gait;
    const std::size_t n = buf_n_;
    if (n < 10) return;
    const std::size_t nb = cfg_.spectral_buffer_samples;
    const double t_last = buf_t_[(buf_head_ + nb - 1) % nb];
    const std::size_t i0 = (buf_head_ + nb - n) % nb;
    const double step = cfg_.spectral_grid_step_hz;
    const auto nf = static_cast<std::size_t>((cfg_.f_max_hz - cfg_.f_min_hz) / step) + 1;
    // Costs of the best grid point and its two neighbours, without storing the grid.
    std::size_t best_k = 0;
    double best = 0.0, prev = 0.0, before_best = 0.0, after_best = 0.0;
    for (std::size_t k = 0; k < nf; ++k) {
      const double cost = ls_cost(kTwoPi * (cfg_.f_min_hz + static_cast<double>(k) * step), n, i0, t_last, nullptr);
      if (k == 0) best = cost;
      if (k == best_k + 1) after_best = cost;
      if (cost < best) {
        best = cost;
        best_k = k;
        before_best = prev;
      }
      prev = cost;
    }
    double f_best = cfg_.f_min_hz + static_cast<double>(best_k) * step;
    if (best_k > 0 && best_k + 1 < nf) {
      const double y0 = before_best, y1 = best, y2 = after_best;
      const double den = y0 - 2.0 * y1 + y2;
      if (den > 0.0) f_best += detail::py_max(-0.5, detail::py_min(0.5, 0.5 * (y0 - y2) / den)) * step;
    }
    double sol[7];
    ls_cost(kTwoPi * f_best, n, i0, t_last, sol);
    std::size_t j = 0, jb = 0;
    for (std::size_t i = 1; i < nbank_; ++i) {
      if (bank_[i].loglik < bank_[j].loglik) j = i;
      if (bank_[i].loglik > bank_[jb].loglik) jb = i;
    }
    Ekf& m = bank_[j];
    reset_ekf(m, f_best, detail::py_max(sol[0], 0.0));
    m.x[kDA0] = sol[1];
    m.x[kX1] = sol[2];
    m.x[kX2] = -sol[3];
    m.x[kZ1] = sol[5];
    m.x[kZ2] = -sol[6];
    const double sp = cfg_.spectral_phasor_std_mps * cfg_.spectral_phasor_std_mps;
    m.P[kX1][kX1] = m.P[kX2][kX2] = m.P[kZ1][kZ1] = m.P[kZ2][kZ2] = sp;
    m.P[kA0][kA0] = sp;
    const double sw = kTwoPi * cfg_.spectral_f_std_hz;
    m.P[kW][kW] = sw * sw;
    m.loglik = bank_[jb].loglik;
    reset_harmonic(bank_h_[j][0]);
    reset_harmonic(bank_h_[j][1]);
  }

  void buffer_push(double t, double vx, double vz) noexcept {
    const std::size_t nb = cfg_.spectral_buffer_samples;
    buf_t_[buf_head_] = t;
    buf_x_[buf_head_] = vx;
    buf_z_[buf_head_] = vz;
    buf_head_ = (buf_head_ + 1) % nb;
    if (buf_n_ < nb) ++buf_n_;
  }

  // ------------------------------------------------------------------------------------ one step

  Outcome advance(double vx, double vz, double dt) noexcept {
    using namespace gait;
    const bool fin_x = std::isfinite(vx), fin_z = std::isfinite(vz);
    // A channel out of range is dropped like a non-finite one (a corrupt 1e200 would overflow P).
    const bool use_x = fin_x && std::fabs(vx) <= cfg_.max_abs_velocity_mps;
    const bool use_z = fin_z && std::fabs(vz) <= cfg_.max_abs_velocity_mps;
    Outcome outcome = !(fin_x && fin_z) ? Outcome::kNonFinite : (use_x && use_z) ? Outcome::kOk : Outcome::kOutOfRange;
    if (!started_) {
      if (!use_x) return outcome;
      started_ = true;
      ema_vx_ = vx;
      ema_vz2_ = use_z ? vz * vz : 0.0;
      start_acquisition(vx, false, 0.0);
      collapse();  // the one EKF is defined from the start
      acquiring_ = true;
      dt = 0.0;
    }
    t_now_s_ += dt;
    const double dt_walk = dt;
    if (dt > cfg_.max_gap_s) {
      // Long gap: keep the speed, restart the acquisition around the last frequency; the fresh
      // members are not propagated over the gap.
      start_acquisition(active().x[kA0], have_params_, last_w_ / kTwoPi);
      dt = 0.0;
    }
    const Factors& fc = factors(dt);
    const bool was_walking = walking_;
    update_walking(vx, vz, use_x, use_z, dt_walk == dt ? fc.walk_gain : 1.0 - std::exp(-dt_walk / cfg_.walk_tau_s));
    if (walking_ && !was_walking) {
      // Walking (re)starts: re-open the acquisition, bias from this sample, one member at the
      // frozen frequency.
      start_acquisition(use_x ? vx : active().x[kA0], have_params_, last_w_ / kTwoPi);
    }
    if (was_walking && !walking_) {
      // Stop: freeze the oscillator, drop the oscillation, decouple the bias. The bank collapses
      // first if it was running; otherwise the one EKF goes on (the bank holds stale members).
      if (acquiring_) collapse();
      Ekf& m = main_;
      m.x[kX1] = m.x[kX2] = m.x[kZ1] = m.x[kZ2] = m.x[kDW] = 0.0;
      for (std::size_t i = 0; i < kDim; ++i) {
        if (i == kA0 || i == kDA0) continue;
        (i < kA0 ? m.P[i][kA0] : m.P[kA0][i]) = 0.0;
        (i < kDA0 ? m.P[i][kDA0] : m.P[kDA0][i]) = 0.0;
      }
    }

    const bool osc = walking_;
    // Standard-deviation scale gain: 0.5 (1 - exp(-dt / tau)) (0 when dt = 0).
    const double std_gain = fc.std_gain;
    bool rejected = false;
    if (acquiring_) {
      for (std::size_t i = 0; i < nbank_; ++i) predict_member(bank_[i], bank_h_[i].data(), dt, fc, osc);
      for (std::size_t i = 0; i < nbank_; ++i)
        rejected |= update_member<true>(bank_[i], bank_h_[i].data(), vx, vz, use_x, use_z, osc, std_gain);
    } else {
      predict_member(main_, main_h_.data(), dt, fc, osc);
      rejected = update_member<false>(main_, main_h_.data(), vx, vz, use_x, use_z, osc, std_gain);
    }
    if (rejected) {
      ++n_rejects_;
      // A non-finite or out-of-range channel says more about the sample than the gate.
      if (outcome == Outcome::kOk) outcome = Outcome::kOutlier;
    } else {
      if (n_rejects_ > 0 && n_rejects_ >= cfg_.gate_max_consecutive) {
        // Persistent disagreement was accepted: inflate P so that the filter follows again.
        const double sp = cfg_.p0_phasor_std_mps * cfg_.p0_phasor_std_mps;
        main_.P[kX1][kX1] += sp;
        main_.P[kX2][kX2] += sp;
        main_.P[kZ1][kZ1] += sp;
        main_.P[kZ2][kZ2] += sp;
        main_.P[kA0][kA0] += cfg_.p0_speed_std_mps * cfg_.p0_speed_std_mps;
      }
      n_rejects_ = 0;
    }

    if (acquiring_) {
      for (std::size_t i = 0; i < nbank_; ++i) bank_[i].loglik *= fc.forget;
      if (walking_) {
        acq_walk_time_s_ += dt;
        if (fin_x && fin_z && use_x && use_z) buffer_push(t_now_s_, vx, vz);
        if (cfg_.spectral_init && !spec_done_ && acq_walk_time_s_ >= cfg_.spectral_init_s) {
          spec_done_ = true;
          spectral_seed();
        }
      }
      best_ = 0;
      for (std::size_t i = 1; i < nbank_; ++i)
        if (bank_[i].loglik > bank_[best_].loglik) best_ = i;
      if (acq_walk_time_s_ >= cfg_.bank_window_s) collapse();
    }

    if (walking_ && !acquiring_) {
      // Watchdog: a frequency pinned at a bound is a failed lock: re-acquire.
      const double w = main_.x[kW];
      if (w <= 1.05 * w_min_ || w >= 0.95 * w_max_)
        t_at_bound_s_ += dt;
      else if (1.15 * w_min_ < w && w < 0.85 * w_max_)
        t_at_bound_s_ = 0.0;
      if (t_at_bound_s_ > cfg_.bound_watchdog_s) start_acquisition(main_.x[kA0], false, 0.0);
    }
    radii_updated_ = false;
    Ekf& act = active();
    if (walking_) {
      // R = A0 / w, r = |Z| / w and the output's harmonic bases (1 / |X|^2, 1 / |Z|^2 at the
      // posterior phasors) from one division.
      const GaitState& x = act.x;
      const double ax2 = x[kX1] * x[kX1] + x[kX2] * x[kX2], az2 = x[kZ1] * x[kZ1] + x[kZ2] * x[kZ2];
      const bool hx = harmonics_on() && !(ax2 < harm_min2_), hz = harmonics_on() && !(az2 < harm_min2_);
      const double dx = hx ? ax2 : 1.0, dz = hz ? az2 : 1.0, w = x[kW];
      const double dxz = dx * dz;
      const double inv = 1.0 / (w * dxz);
      const double inv_w = dxz * inv;
      out_hx_ = hx ? main_or_best_h()[0].value((x[kX1] * x[kX1] - x[kX2] * x[kX2]) * (w * dz * inv),
                                              2.0 * x[kX1] * x[kX2] * (w * dz * inv))
                   : 0.0;
      out_hz_ = hz ? main_or_best_h()[1].value((x[kZ1] * x[kZ1] - x[kZ2] * x[kZ2]) * (w * dx * inv),
                                              2.0 * x[kZ1] * x[kZ2] * (w * dx * inv))
                   : 0.0;
      last_w_ = w;
      const double Rn = x[kA0] * inv_w;
      const double rn = std::sqrt(az2) * inv_w;
      if (!have_params_) {
        R_m_ = Rn;
        r_m_ = rn;
        have_params_ = true;
      } else {
        const double g = fc.radii_gain;
        R_m_ += g * (Rn - R_m_);
        r_m_ += g * (rn - r_m_);
      }
      radii_updated_ = true;
    }
    // Never reached with in-range samples; keeps the state finite whatever comes in: a finite
    // state and diagonal mean a finite covariance (|P_ij| <= sqrt(P_ii P_jj)).
    const GaitState& xa = act.x;
    const double check = ((xa[0] + xa[1]) + (xa[2] + xa[3])) + ((xa[4] + xa[5]) + (xa[6] + xa[7])) +
                         ((act.P[0][0] + act.P[1][1]) + (act.P[2][2] + act.P[3][3])) +
                         ((act.P[4][4] + act.P[5][5]) + (act.P[6][6] + act.P[7][7])) + (R_m_ + r_m_ + lambda_);
    if (!std::isfinite(check)) {
      recover();
      outcome = Outcome::kNumerical;
    }
    return outcome;
  }

  /// After a non-finite result: restart from the last finite speed and frequency.
  void recover() noexcept {
    const double A0 = std::isfinite(ema_vx_) ? detail::py_max(ema_vx_, 0.0) : 0.0;
    ema_vx_ = A0;
    if (!std::isfinite(ema_vz2_)) ema_vz2_ = 0.0;
    if (!(std::isfinite(R_m_) && std::isfinite(r_m_))) {
      R_m_ = cfg_.initial_R_m;
      r_m_ = cfg_.initial_r_m;
      have_params_ = false;
    }
    if (!std::isfinite(last_w_)) last_w_ = gait::kTwoPi * cfg_.bank_prior_f_hz;
    lambda_ = 1.0;
    n_rejects_ = 0;
    out_hx_ = out_hz_ = 0.0;
    start_acquisition(A0, have_params_, last_w_ / gait::kTwoPi);
    collapse();
    acquiring_ = true;
  }

  EstimatorConfig cfg_;
  // Derived constants.
  std::size_t nbank_ = 5;
  double nominal_dt_ = 0.04, w_min_ = 0.0, w_max_ = 0.0, r_vx_ = 0.0, r_vz_ = 0.0, gate2_ = 0.0, harm_min2_ = 0.0,
         inv_rate_ref_ = 0.0, speed_floor2_ = 0.0, vz_rms_on2_ = 0.0, vz_rms_off2_ = 0.0;
  // The one EKF of the steady state and its harmonics.
  Ekf main_;
  std::array<Harmonic, 2> main_h_{};
  Factors factors_;
  double lambda_ = 1.0;
  double ema_vx_ = 0.0, ema_vz2_ = 0.0;
  double R_m_ = 0.0, r_m_ = 0.0, last_w_ = 0.0;
  double out_hx_ = 0.0, out_hz_ = 0.0;  ///< second harmonics at the posterior phasors, for output()
  double t_at_bound_s_ = 0.0, t_now_s_ = 0.0, acq_walk_time_s_ = 0.0;
  std::size_t n_rejects_ = 0, best_ = 0;
  bool started_ = false, acquiring_ = true, walking_ = false, have_params_ = false, spec_done_ = false,
       radii_updated_ = false;
  // Start-up: the bank and the spectral ring buffer.
  std::array<Ekf, kMaxBankSize> bank_{};
  std::array<std::array<Harmonic, 2>, kMaxBankSize> bank_h_{};
  std::size_t buf_n_ = 0, buf_head_ = 0;
  std::array<double, kMaxSpectralBuffer> buf_t_{}, buf_x_{}, buf_z_{};
};

}  // namespace yoyogait
