/// @file online/differentiator.hpp
/// @brief Causal velocity of a 3-D position: a constant-acceleration Kalman filter per axis.
///
/// State per axis [p, v, a]; white jerk of density q_jerk [m^2/s^5]; measurement p with noise std
/// r [m]. The three axes share dt, q and r, so they share one covariance: one 3x3 Riccati step per
/// frame and three gains applied to the three axes. Any frame times (dt from the timestamps); a
/// frame without a position is a prediction only. docs/online.md compares it with a
/// constant-velocity filter and a causal polynomial fit.
#pragma once

#include <array>
#include <cmath>
#include <complex>

#include "yoyogait/online/interval_cache.hpp"

namespace yoyogait::online {

class KalmanDifferentiator {
 public:
  enum Index { kP = 0, kV = 1, kA = 2 };
  using Axis = std::array<double, 3>;  // [p, v, a] of one axis

  /// A centre closer than this to its prediction is never an outlier [m] (update's min_outlier_m for
  /// a pelvis centre): no walker's centre leaves a constant-acceleration prediction by 2 cm within a
  /// frame (a 100 m/s^3 jerk: 0.6 mm at 30 Hz), while the blend of a change of the visible markers
  /// (online/centre.hpp) moves it by millimetres.
  static constexpr double kMinOutlierM = 0.02;

  struct Settings {
    double q_jerk_m2_per_s5 = 1000.0;  ///< white-jerk noise density [m^2/s^5]
    double meas_std_m = 0.001;         ///< noise of the measured position [m]
    double v0_std_mps = 1.0;           ///< initial std of the velocity after a start [m/s]
    double a0_std_mps2 = 10.0;         ///< ... of the acceleration [m/s^2]
    double knee_std_m = 1e100;         ///< above this noise the jerk density stays that at it (noise_knee_m) [m]
  };

  KalmanDifferentiator() noexcept = default;
  explicit KalmanDifferentiator(const Settings& s) noexcept
      : q_(s.q_jerk_m2_per_s5),
        r2_(s.meas_std_m * s.meas_std_m),
        q0_(q_),
        r20_(r2_),
        v0_var_(s.v0_std_mps * s.v0_std_mps),
        a0_var_(s.a0_std_mps2 * s.a0_std_mps2),
        knee2_(s.knee_std_m < 1e150 ? s.knee_std_m * s.knee_std_m : 1e300) {}

  /// Starts at position p_m at rest (velocity and acceleration unknown).
  void start(const std::array<double, 3>& p_m) noexcept {
    for (int k = 0; k < 3; ++k) x_[k] = Axis{p_m[k], 0.0, 0.0};
    P_ = {{{r2_, 0.0, 0.0}, {0.0, v0_var_, 0.0}, {0.0, 0.0, a0_var_}}};
    started_ = true;
  }
  bool started() const noexcept { return started_; }
  void stop() noexcept { started_ = false; }

  /// Propagates over dt_s (> 0).
  void predict(double dt_s) noexcept {
    const double h = dt_s, h2 = h * h;
    for (Axis& x : x_) {
      x[kP] += h * x[kV] + 0.5 * h2 * x[kA];
      x[kV] += h * x[kA];
    }
    // P <- F P F^T + Q, F = [[1, h, h^2/2], [0, 1, h], [0, 0, 1]].
    const auto& P = P_;
    const double hh = 0.5 * h2;
    // A = F P
    double A[3][3];
    for (int j = 0; j < 3; ++j) {
      A[0][j] = P[0][j] + h * P[1][j] + hh * P[2][j];
      A[1][j] = P[1][j] + h * P[2][j];
      A[2][j] = P[2][j];
    }
    std::array<std::array<double, 3>, 3> N;
    for (int i = 0; i < 3; ++i) {
      N[i][0] = A[i][0] + h * A[i][1] + hh * A[i][2];
      N[i][1] = A[i][1] + h * A[i][2];
      N[i][2] = A[i][2];
    }
    // Q depends on q and h only: kept for the last two intervals (q is constant at clean input).
    const Noise& qn = noise_.at(h, [this](double hq) {
      const double q = q_, g2 = hq * hq, g3 = g2 * hq;
      return Noise{q * g3 * g2 / 20.0, q * g2 * g2 / 8.0, q * g3 / 6.0, q * g3 / 3.0, q * g2 / 2.0, q * hq};
    });
    const double q00 = qn.q00, q01 = qn.q01, q02 = qn.q02, q11 = qn.q11, q12 = qn.q12, q22 = qn.q22;
    N[0][0] += q00;
    N[0][1] += q01;
    N[0][2] += q02;
    N[1][0] += q01;
    N[1][1] += q11;
    N[1][2] += q12;
    N[2][0] += q02;
    N[2][1] += q12;
    N[2][2] += q22;
    // Keep it symmetric.
    N[1][0] = N[0][1] = 0.5 * (N[0][1] + N[1][0]);
    N[2][0] = N[0][2] = 0.5 * (N[0][2] + N[2][0]);
    N[2][1] = N[1][2] = 0.5 * (N[1][2] + N[2][1]);
    P_ = N;
  }

  /// The noise of the measured position from now on [m^2] (> 0): the input-noise estimate's. Up to
  /// knee_std_m^2 the jerk density scales with it (q / r^2 fixed: the same gains and bandwidth, a
  /// laboratory capture's, so that only the covariance follows the noise); beyond, it stays at the
  /// knee's, so that the bandwidth falls as r^(-1/3): at centimetres of noise the velocity keeps the
  /// gait's band and not the differentiated jitter above it, which rises as f^2 (docs/online.md,
  /// "Input noise").
  void set_meas_var(double r2_m2) noexcept {
    const double q = q0_ * ((r2_m2 < knee2_ ? r2_m2 : knee2_) / r20_);
    if (q != q_) {
      q_ = q;
      noise_.reset();
    }
    r2_ = r2_m2;
  }
  double meas_var_m2() const noexcept { return r2_; }

  /// Measurement update with position p_m, unless its normalised innovation squared (summed over the
  /// three axes) exceeds gate_nis and the innovation is longer than min_outlier_m: then the frame is
  /// a prediction only (an outlier, not differentiated) and false is returned. Either way the
  /// innovation is kept (innovation2_m2).
  bool update(const std::array<double, 3>& p_m, double gate_nis = 1e300, double min_outlier_m = 0.0) noexcept {
    const double S = P_[0][0] + r2_;
    std::array<double, 3> nu{};
    double nu2 = 0.0;
    for (int k = 0; k < 3; ++k) {
      nu[k] = p_m[k] - x_[k][kP];
      nu2 += nu[k] * nu[k];
    }
    innovation2_m2_ = nu2 / 3.0;
    predicted_var_m2_ = P_[0][0];
    if (!(nu2 <= gate_nis * S) && !(nu2 <= min_outlier_m * min_outlier_m)) return false;
    const double K0 = P_[0][0] / S, K1 = P_[1][0] / S, K2 = P_[2][0] / S;
    for (int k = 0; k < 3; ++k) {
      x_[k][kP] += K0 * nu[k];
      x_[k][kV] += K1 * nu[k];
      x_[k][kA] += K2 * nu[k];
    }
    const std::array<double, 3> row0 = P_[0];
    const double K[3] = {K0, K1, K2};
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j) P_[i][j] -= K[i] * row0[j];
    gain_ = {K0, K1, K2};
    return true;
  }

  /// The last update's mean squared position innovation over the axes [m^2] and the part of it the
  /// filter's own uncertainty explains (H P- H^T) [m^2]: their difference estimates the marker noise.
  double innovation2_m2() const noexcept { return innovation2_m2_; }
  double predicted_var_m2() const noexcept { return predicted_var_m2_; }

  std::array<double, 3> position_m() const noexcept { return {x_[0][kP], x_[1][kP], x_[2][kP]}; }
  std::array<double, 3> velocity_mps() const noexcept { return {x_[0][kV], x_[1][kV], x_[2][kV]}; }
  const std::array<std::array<double, 3>, 3>& covariance() const noexcept { return P_; }
  bool finite() const noexcept {
    for (const Axis& x : x_)
      for (double v : x)
        if (!std::isfinite(v)) return false;
    return std::isfinite(P_[0][0]) && std::isfinite(P_[1][1]) && std::isfinite(P_[2][2]);
  }

  /// The variance that white position noise at the configured measurement noise (meas_std_m, the
  /// floor) leaves on the mean of n consecutive velocity outputs of the steady-state filter, frames
  /// h_s apart [(m/s)^2]: the noise of the estimator's input at the floor (online/decimator.hpp).
  /// The steady gain by its Riccati iteration, then the impulse response (about 0.3 us); n above 16
  /// counts as 16 (more noise left than there is: the detector then counts less of v_z as gait).
  double floor_mean_velocity_var(double h_s, int n) const noexcept {
    if (!(h_s > 0.0) || n < 1) return 0.0;
    const double h = h_s, hh = 0.5 * h * h, q = q0_ / r20_;  // at unit measurement variance
    const double F[3][3] = {{1.0, h, hh}, {0.0, 1.0, h}, {0.0, 0.0, 1.0}};
    const double g2 = h * h, g3 = g2 * h;
    const double Q[3][3] = {{q * g3 * g2 / 20.0, q * g2 * g2 / 8.0, q * g3 / 6.0},
                            {q * g2 * g2 / 8.0, q * g3 / 3.0, q * g2 / 2.0},
                            {q * g3 / 6.0, q * g2 / 2.0, q * h}};
    double P[3][3] = {{1.0, 0.0, 0.0}, {0.0, 1e4, 0.0}, {0.0, 0.0, 1e6}}, K[3] = {0.0, 0.0, 0.0};
    for (int it = 0; it < 400; ++it) {  // to the steady gain (a few dozen steps)
      double A[3][3], N[3][3];
      for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j) A[i][j] = F[i][0] * P[0][j] + F[i][1] * P[1][j] + F[i][2] * P[2][j];
      for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j) N[i][j] = A[i][0] * F[j][0] + A[i][1] * F[j][1] + A[i][2] * F[j][2] + Q[i][j];
      const double S = N[0][0] + 1.0, K1 = N[1][0] / S;
      const bool steady = std::fabs(K1 - K[1]) <= 1e-9 * std::fabs(K1);
      for (int i = 0; i < 3; ++i) K[i] = N[i][0] / S;
      for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j) P[i][j] = N[i][j] - K[i] * N[0][j];
      if (steady) break;
    }
    // x_k = (I - K e0^T) F x_{k-1} + K y_k: the velocity's impulse response h_j, its n-mean's g_j.
    double x[3] = {K[0], K[1], K[2]}, ring[16] = {}, sum = 0.0, var = 0.0;
    const int m = n < 16 ? n : 16;
    for (int j = 0; j < 2000; ++j) {
      const double hv = x[1];
      sum += hv - (j >= m ? ring[j % m] : 0.0);
      ring[j % m] = hv;
      var += (sum / m) * (sum / m);
      const double p = x[0] + h * x[1] + hh * x[2], v = x[1] + h * x[2], a = x[2];
      x[0] = p - K[0] * p;
      x[1] = v - K[1] * p;
      x[2] = a - K[2] * p;
      if (j > m && x[1] * x[1] < 1e-12 * var) break;  // the response has died away
    }
    return r20_ * var;
  }

  /// Delay of the velocity output at frequency f_hz for frames dt_s apart, with the last gain:
  /// the phase of the filter's transfer function from position to velocity against the ideal
  /// derivative's +90 degrees, over 2 pi f [s]. (The steady-state filter is linear time-invariant.)
  double delay_s(double f_hz, double dt_s) const noexcept {
    if (!(dt_s > 0.0 && f_hz > 0.0)) return 0.0;
    using C = std::complex<double>;
    const double h = dt_s, hh = 0.5 * h * h;
    const double w = 6.283185307179586 * f_hz;
    const C zi = std::polar(1.0, -w * h);  // z^-1
    // x_k = A x_{k-1} + K y_k with A = (I - K e0^T) F.
    const double F[3][3] = {{1.0, h, hh}, {0.0, 1.0, h}, {0.0, 0.0, 1.0}};
    C M[3][3];
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j) {
        const double a = F[i][j] - gain_[i] * F[0][j];
        M[i][j] = (i == j ? C(1.0) : C(0.0)) - a * zi;
      }
    // Solve M x = K (Cramer's rule); the velocity is x[1].
    auto det3 = [](const C m[3][3]) {
      return m[0][0] * (m[1][1] * m[2][2] - m[1][2] * m[2][1]) - m[0][1] * (m[1][0] * m[2][2] - m[1][2] * m[2][0]) +
             m[0][2] * (m[1][0] * m[2][1] - m[1][1] * m[2][0]);
    };
    const C d = det3(M);
    if (std::abs(d) == 0.0) return 0.0;
    C M1[3][3];
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j) M1[i][j] = j == 1 ? C(gain_[i]) : M[i][j];
    const C hv = det3(M1) / d;
    double phase = std::arg(hv) - 1.5707963267948966;  // against d/dt
    while (phase > 3.141592653589793) phase -= 6.283185307179586;
    while (phase < -3.141592653589793) phase += 6.283185307179586;
    return -phase / w;
  }

 private:
  double q_ = 1e3, r2_ = 1e-6, q0_ = 1e3, r20_ = 1e-6, v0_var_ = 1.0, a0_var_ = 100.0, knee2_ = 1e300;
  std::array<Axis, 3> x_{};
  std::array<std::array<double, 3>, 3> P_{};
  std::array<double, 3> gain_{};
  struct Noise {
    double q00, q01, q02, q11, q12, q22;
  };
  IntervalCache<Noise> noise_;  ///< Q at the last intervals, for q_
  double innovation2_m2_ = 0.0, predicted_var_m2_ = 0.0;
  bool started_ = false;
};

/// KalmanDifferentiator::floor_mean_velocity_var, computed again only when the frame interval moves
/// by 10 % or the frame count changes: it changes slowly with the interval, and jittered timestamps
/// would otherwise recompute it every frame.
class FloorVelocityNoise {
 public:
  double var_m2_per_s2(const KalmanDifferentiator& diff, double h_s, int frames) noexcept {
    if (frames != frames_ || !(std::fabs(h_s - h_s_) <= 0.1 * h_s_)) {
      h_s_ = h_s;
      frames_ = frames;
      var_ = diff.floor_mean_velocity_var(h_s, frames);
    }
    return var_;
  }

 private:
  double h_s_ = -1.0, var_ = 0.0;  ///< the frame interval it was computed at [s], and its value [(m/s)^2]
  int frames_ = -1;
};

}  // namespace yoyogait::online
