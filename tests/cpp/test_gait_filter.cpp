// The default estimator (gait/gait_filter.hpp): transition and Jacobian, the structured covariance
// propagation, convergence with the real-data phase relation, standing, gaps, outliers, bad input.
#include <gtest/gtest.h>

#include "finite_difference.hpp"

#include <cmath>
#include <limits>
#include <random>
#include <stdexcept>
#include <string>
#include <vector>

#include "yoyogait/estimator.hpp"
#include "yoyogait/gait/gait_filter.hpp"

namespace gait_filter_tests {  // one per file: the sanitizer build compiles the files as one unit
using namespace yoyogait;
using namespace yoyogait::gait;

namespace {

constexpr double kPi = 3.141592653589793238462643383;

struct Walk {
  std::vector<double> t, vx, vz;
};

// Eq. 3-4 at 25 Hz with the forward oscillation shifted by phase_offset (pi: as in real walking),
// a second harmonic of 25 % and white noise.
Walk make_walk(double seconds, double f_hz, double speed_mps, double r_m, double phase_offset, double noise,
               unsigned seed) {
  const double T = 0.04;
  const double w = 2 * kPi * f_hz;
  const double R = speed_mps / w;
  std::mt19937 gen(seed);
  std::normal_distribution<double> nd(0.0, 1.0);
  Walk out;
  const auto n = static_cast<std::size_t>(seconds / T);
  for (std::size_t i = 0; i < n; ++i) {
    const double t = static_cast<double>(i) * T;
    const double th = w * t + 0.3;
    const double a1 = r_m * w;
    out.t.push_back(t);
    out.vx.push_back(R * w + a1 * std::cos(th + phase_offset) + 0.25 * a1 * std::cos(2 * th + 1.0) + noise * nd(gen));
    out.vz.push_back(-a1 * std::sin(th) + 0.25 * a1 * std::cos(2 * th + 2.0) + noise * nd(gen));
  }
  return out;
}

void expect_jacobian_matches(const GaitState& x, double dt, double tol) {
  const double a = std::exp(-dt / 1.0), b = std::exp(-dt / 3.0);
  const GaitMatrix analytic = gait_transition_jacobian(x, dt, a, b);
  const GaitMatrix numeric = yoyogait::testing::central_jacobian<kDim>(
      x, [&](const GaitState& s) { return gait_transition(s, dt, a, b); });
  double scale = 1.0;
  for (double v : x) scale = std::max(scale, std::fabs(v));
  for (std::size_t i = 0; i < kDim; ++i)
    for (std::size_t j = 0; j < kDim; ++j)
      EXPECT_NEAR(analytic[i][j], numeric[i][j], tol * scale) << "entry " << i << "," << j;
}

double median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  return v[v.size() / 2];
}

}  // namespace

TEST(GaitTransition, JacobianMatchesFiniteDifferencesOnRandomStates) {
  // The Jacobian of the transition equals its central finite difference on random walking states.
  std::mt19937 gen(11);
  std::uniform_real_distribution<double> amp(-0.5, 0.5), w(0.6 * 2 * kPi, 3.5 * 2 * kPi), speed(0.0, 2.5),
      rate(-1.0, 1.0), dt(0.01, 0.1);
  for (int n = 0; n < 200; ++n) {
    const GaitState x{amp(gen), amp(gen), amp(gen), amp(gen), w(gen), speed(gen), rate(gen), rate(gen)};
    expect_jacobian_matches(x, dt(gen), 1e-7);
  }
}

TEST(GaitTransition, JacobianMatchesFiniteDifferencesNearZero) {
  // The Jacobian is right at and near the zero state, where the oscillation vanishes.
  expect_jacobian_matches(GaitState{}, 0.04, 1e-8);
  expect_jacobian_matches(GaitState{1e-9, -2e-9, 3e-9, 1e-9, 1e-8, 1e-9, -1e-9, 1e-9}, 0.04, 1e-8);
}

TEST(GaitTransition, JacobianMatchesFiniteDifferencesOnLargeStates) {
  // The Jacobian stays right for large amplitudes and for phase steps beyond pi/4 (libm path).
  expect_jacobian_matches(GaitState{150.0, -80.0, 40.0, 90.0, 22.0, 400.0, 5.0, -3.0}, 0.04, 1e-6);
  expect_jacobian_matches(GaitState{3e3, 1e3, -2e3, 5e2, 30.0, 1e3, -20.0, 10.0}, 0.1, 1e-6);
}

TEST(GaitPredict, StructuredPropagationEqualsDenseFPFtPlusQ) {
  // gait_predict gives f(x) and F P F^T + Q (F at the prior x) on the upper triangle, to rounding.
  std::mt19937 gen(5);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  for (int trial = 0; trial < 50; ++trial) {
    GaitState x{0.1 * u(gen), 0.1 * u(gen), 0.1 * u(gen), 0.1 * u(gen), 11.0 + 3 * u(gen), 1.3 + 0.2 * u(gen),
                0.1 * u(gen), 0.2 * u(gen)};
    // A random symmetric positive-definite P = A A^T + 0.1 I.
    GaitMatrix A{}, P{};
    for (auto& row : A)
      for (double& v : row) v = 0.3 * u(gen);
    for (std::size_t i = 0; i < kDim; ++i)
      for (std::size_t j = 0; j < kDim; ++j) {
        for (std::size_t k = 0; k < kDim; ++k) P[i][j] += A[i][k] * A[j][k];
        if (i == j) P[i][j] += 0.1;
      }
    const double dt = trial % 2 ? 0.04 : 0.013 + 0.05 * (u(gen) + 1.0);
    const double a = std::exp(-dt / 1.0), b = std::exp(-dt / 3.0);
    GaitProcessNoise q;
    q.phasor = 2e-3 * dt;
    q.phase = 0.05 * dt;
    q.omega = 0.05 * dt;
    q.speed = 1e-3 * dt;
    q.accel = 1e-2 * dt;
    const GaitMatrix F = gait_transition_jacobian(x, dt, a, b);
    const GaitState fx = gait_transition(x, dt, a, b);
    const double g[4] = {-fx[kX2], fx[kX1], -fx[kZ2], fx[kZ1]};
    GaitMatrix expected{};
    for (std::size_t i = 0; i < kDim; ++i)
      for (std::size_t j = 0; j < kDim; ++j) {
        for (std::size_t k = 0; k < kDim; ++k)
          for (std::size_t l = 0; l < kDim; ++l) expected[i][j] += F[i][k] * P[k][l] * F[j][l];
        if (i < 4 && j < 4) expected[i][j] += q.phase * g[i] * g[j] + (i == j ? q.phasor : 0.0);
      }
    expected[kW][kW] += q.omega;
    expected[kA0][kA0] += q.speed;
    expected[kDA0][kDA0] += q.accel;
    gait_predict(x, P, dt, a, b, q);
    for (std::size_t i = 0; i < kDim; ++i) {
      EXPECT_NEAR(x[i], fx[i], 1e-14 * std::max(1.0, std::fabs(fx[i])));
      for (std::size_t j = i; j < kDim; ++j) EXPECT_NEAR(P[i][j], expected[i][j], 1e-13) << i << "," << j;
    }
  }
}

TEST(GaitPredict, PairFormEqualsTheScalarFormBitForBit) {
  // gait_predict with the target's X/Z pairs (SSE2 where available) gives exactly the scalar form's bits.
  std::mt19937 gen(11);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  std::uniform_real_distribution<double> e(-30.0, 30.0);
  for (int trial = 0; trial < 500; ++trial) {
    GaitState x;
    for (double& v : x) v = u(gen) * std::exp2(std::floor(0.3 * e(gen)));
    x[kW] = 2.0 + 20.0 * (u(gen) + 1.0);  // |w dt| on both sides of pi/4 (the kernel and std::sin/cos)
    GaitMatrix P{};
    for (std::size_t i = 0; i < kDim; ++i)
      for (std::size_t j = i; j < kDim; ++j) P[i][j] = u(gen) * std::exp2(std::floor(e(gen)));
    if (trial % 50 == 0) P[kX1][kZ2] = -0.0;  // signed zeros go through the lanes as well
    const double dt = 0.001 + 0.1 * (u(gen) + 1.0);
    const double a = std::exp(-dt / 1.0), b = std::exp(-dt / 3.0);
    GaitProcessNoise q;
    q.phasor = 2e-3 * dt;
    q.phase = 0.05 * dt;
    q.omega = 0.05 * dt;
    q.speed = 1e-3 * dt;
    q.accel = 1e-2 * dt;
    GaitState xs = x, xp = x;
    GaitMatrix Ps = P, Pp = P;
    gait_predict<ScalarPair>(xs, Ps, dt, a, b, q);
    gait_predict<Pair>(xp, Pp, dt, a, b, q);
    for (std::size_t i = 0; i < kDim; ++i) {
      EXPECT_EQ(std::signbit(xp[i]), std::signbit(xs[i])) << trial << ": x" << i;
      EXPECT_EQ(xp[i], xs[i]) << trial << ": x" << i;
      for (std::size_t j = i; j < kDim; ++j) {
        EXPECT_EQ(std::signbit(Pp[i][j]), std::signbit(Ps[i][j])) << trial << ": P" << i << j;
        EXPECT_EQ(Pp[i][j], Ps[i][j]) << trial << ": P" << i << j;
      }
    }
  }
}

TEST(GaitEstimator, ConvergesToThePositiveFrequencyWithTheRealPhaseRelation) {
  // With the forward oscillation in anti-phase (offset pi), f converges to +1.8 Hz within 1 % after 5 s,
  // and the estimated relation is the real one (phase near +pi/2, signed forward amplitude < 0).
  const Walk w = make_walk(30.0, 1.8, 1.3, 0.02, kPi, 0.015, 3);
  Estimator est;  // the default estimator
  for (std::size_t i = 0; i < w.vx.size(); ++i) {
    const Estimate e = est.step(w.vx[i], w.vz[i]);
    ASSERT_GT(e.step_frequency_hz, 0.0) << "sample " << i;
    if (w.t[i] < 5.0) continue;
    ASSERT_NEAR(e.step_frequency_hz, 1.8, 0.018) << "sample " << i;
    ASSERT_NEAR(e.phase_x_rel_z_rad(), kPi / 2, 0.35) << "sample " << i;
    ASSERT_LT(e.signed_amp_x_mps(), 0.0) << "sample " << i;
    ASSERT_TRUE(e.walking);
    ASSERT_FALSE(e.acquiring);
  }
}

// An observed frequency (the feet's steps) is a scalar Kalman update of w: w moves towards it by
// P_ww / (P_ww + r) of the difference and P_ww shrinks by the same factor; nothing while acquiring.
TEST(GaitEstimator, AnObservedFrequencyIsAKalmanUpdateOfW) {
  const Walk w = make_walk(12.0, 1.8, 1.3, 0.02, kPi, 0.015, 3);
  Estimator est, acquiring;
  for (std::size_t i = 0; i < w.vx.size(); ++i) {
    est.step(w.vx[i], w.vz[i]);
    if (i < 10) acquiring.step(w.vx[i], w.vz[i]);
  }
  ASSERT_FALSE(est.step(w.vx.back(), w.vz.back()).acquiring);
  const double w0 = est.gait_state()[kW], p0 = est.gait_covariance()[kW][kW];
  const double r = p0, w_meas = w0 + 2.0 * kPi * 0.2;  // 0.2 Hz above, as certain as the filter
  est.observe_frequency(w_meas / (2.0 * kPi), r / (4.0 * kPi * kPi));
  const double gain = p0 / (p0 + r);
  EXPECT_NEAR(est.gait_state()[kW], w0 + gain * (w_meas - w0), 1e-9);
  EXPECT_NEAR(est.gait_covariance()[kW][kW], (1.0 - gain) * p0, 1e-9 * p0);
  const GaitState before = acquiring.gait_state();
  acquiring.observe_frequency(2.5, 0.01);
  EXPECT_EQ(acquiring.gait_state(), before);
}

TEST(GaitEstimator, TheYoyoRelationGivesTheMirrorPhase) {
  // On eq. 3-4 as written (offset 0) the estimated relation is the Yoyo one: phase near -pi/2, signed amplitude > 0.
  const Walk w = make_walk(20.0, 1.6, 1.2, 0.02, 0.0, 0.01, 4);
  Estimator est;
  Estimate e;
  for (std::size_t i = 0; i < w.vx.size(); ++i) e = est.step(w.vx[i], w.vz[i]);
  EXPECT_NEAR(e.step_frequency_hz, 1.6, 0.016);
  EXPECT_NEAR(e.phase_x_rel_z_rad(), -kPi / 2, 0.35);
  EXPECT_GT(e.signed_amp_x_mps(), 0.0);
  EXPECT_NEAR(e.R_m, 1.2 / (2 * kPi * 1.6), 0.05 * 1.2 / (2 * kPi * 1.6));
}

TEST(GaitEstimator, StandingFreezesTheOscillatorAndTracksTheSpeed) {
  // A walk at 1.8 Hz that slows down over 1 s (cadence kept, steps shortening) and stands: once the
  // detector says standing, f is frozen near the walking cadence, the speed falls to zero without a
  // jump, the reconstruction is (A0, 0) and R, r are frozen.
  const double T = 0.04, w = 2 * kPi * 1.8, R = 1.3 / w, r = 0.02;
  std::mt19937 gen(5);
  std::normal_distribution<double> nd(0.0, 0.015);
  Estimator est;
  bool stopped = false;
  double max_speed_after_stop = 0.0, R_stop = 0.0, r_stop = 0.0, f_stop = 0.0;
  Estimate e;
  for (int i = 0; i < 625; ++i) {
    const double t = i * T, th = w * t;
    const double gain = std::min(1.0, std::max(0.0, 1.0 - (t - 15.0)));
    const double a1 = r * w * gain;
    e = est.step(std::fabs(R * w * gain + a1 * std::cos(th + kPi) + 0.25 * a1 * std::cos(2 * th + 1) + nd(gen)),
                 -a1 * std::sin(th) + 0.25 * a1 * std::cos(2 * th + 2) + nd(gen));
    if (t < 15.0) {
      ASSERT_TRUE(e.walking || t < 0.5) << t;
      continue;
    }
    if (!e.walking) {
      if (!stopped) {
        EXPECT_NEAR(e.step_frequency_hz, 1.8, 0.05 * 1.8);
        R_stop = e.R_m;
        r_stop = e.r_m;
        f_stop = e.step_frequency_hz;
      }
      stopped = true;
      max_speed_after_stop = std::max(max_speed_after_stop, e.speed_mps);
      EXPECT_EQ(e.vx_hat_mps, e.A0_mps);
      EXPECT_EQ(e.vz_hat_mps, 0.0);
      EXPECT_EQ(e.R_m, R_stop);
      EXPECT_EQ(e.r_m, r_stop);
      EXPECT_EQ(e.step_frequency_hz, f_stop);
      EXPECT_FALSE(e.parameters_updated);
    }
  }
  ASSERT_TRUE(stopped);
  EXPECT_LT(max_speed_after_stop, 0.15);  // the detector turns off below 0.15 m/s: no jump back up
  EXPECT_LT(e.speed_mps, 0.03);
}

TEST(GaitEstimator, RunEqualsStepByStepWithAndWithoutDt) {
  // The batch call gives bit-identical estimates to a loop of step(), with nominal and with given time steps.
  const Walk w = make_walk(20.0, 1.7, 1.2, 0.025, kPi, 0.05, 6);
  std::vector<double> dt(w.t.size());
  for (std::size_t i = 0; i < dt.size(); ++i) dt[i] = 0.04 * (1.0 + 0.3 * std::sin(static_cast<double>(i)));
  for (int with_dt = 0; with_dt < 2; ++with_dt) {
    Estimator a, b;
    std::vector<Estimate> out(w.vx.size());
    a.run(w.vx.data(), w.vz.data(), w.vx.size(), out.data(), with_dt ? dt.data() : nullptr);
    for (std::size_t i = 0; i < w.vx.size(); ++i) {
      const Estimate e = with_dt ? b.step(w.vx[i], w.vz[i], dt[i]) : b.step(w.vx[i], w.vz[i]);
      ASSERT_EQ(e.gait_state, out[i].gait_state);
      ASSERT_EQ(e.vx_hat_h2_mps, out[i].vx_hat_h2_mps);
      ASSERT_EQ(e.step_frequency_std_hz, out[i].step_frequency_std_hz);
      ASSERT_EQ(e.R_m, out[i].R_m);
    }
  }
}

namespace {

struct Restart {
  double held_hz = -1.0;     ///< f held while standing
  double restart_hz = -1.0;  ///< f at the first sample walking again
};

// A walk at f1_hz for walk1_s (fail_before_end_s >= 0: the caller finds the lock failed that long
// before the walk ends, GaitFilter::reacquire), 3 s of standing, then a walk at 1.5 Hz. The bank's
// window is 3 s, longer than a short walk and the detector's hold after it.
Restart restart_after(double f1_hz, double walk1_s, double fail_before_end_s = -1.0) {
  const Walk first = make_walk(walk1_s, f1_hz, 1.2, 0.025, kPi, 0.01, 11);
  const Walk again = make_walk(4.0, 1.5, 1.2, 0.025, kPi, 0.01, 12);
  std::mt19937 gen(13);
  std::normal_distribution<double> nd(0.0, 0.01);
  EstimatorConfig config;
  config.gait_filter.bank_window_s = 3.0;
  Estimator est(config);
  const double fail_at_s = walk1_s - fail_before_end_s;
  for (std::size_t i = 0; i < first.vx.size(); ++i) {
    if (fail_before_end_s >= 0.0 && first.t[i] >= fail_at_s && first.t[i] < fail_at_s + 0.04) est.reacquire();
    est.step(first.vx[i], first.vz[i]);
  }
  Restart out;
  for (int i = 0; i < 75; ++i) {
    const Estimate e = est.step(nd(gen), nd(gen));
    out.held_hz = e.walking ? -1.0 : e.step_frequency_hz;
  }
  for (std::size_t i = 0; i < again.vx.size() && out.restart_hz < 0.0; ++i) {
    const Estimate e = est.step(again.vx[i], again.vz[i]);
    if (e.walking) out.restart_hz = e.step_frequency_hz;
  }
  return out;
}

}  // namespace

TEST(GaitEstimator, ARestartStartsFromTheLastLockTheEvidenceChoseAndFromNothingElse) {
  // A lock the bank chose (it walked its window) is the restart's hint; the frequency of a bank a
  // stop cut short, or of a lock found failed, is not: the typical 1.8 Hz leads then (on noisy
  // input a wrong lock would otherwise win every restart with the hint's bonus).
  const Restart chosen = restart_after(1.1, 10.0);
  ASSERT_GT(chosen.held_hz, 0.0);
  EXPECT_GT(std::fabs(chosen.held_hz - 1.8), 0.5);
  EXPECT_NEAR(chosen.restart_hz, chosen.held_hz, 0.05);
  const Restart cut_short = restart_after(2.6, 0.8);
  EXPECT_GT(std::fabs(cut_short.held_hz - 1.8), 0.3);
  EXPECT_NEAR(cut_short.restart_hz, 1.8, 0.05);
  const Restart failed = restart_after(1.1, 10.0, 0.5);
  EXPECT_GT(std::fabs(failed.held_hz - 1.8), 0.2);
  EXPECT_NEAR(failed.restart_hz, 1.8, 0.05);
}

TEST(GaitEstimator, ResetReturnsToTheInitialState) {
  // After reset() the estimator repeats its first run exactly (bank, spectral seed and all).
  const Walk w = make_walk(6.0, 1.7, 1.2, 0.025, kPi, 0.05, 7);
  Estimator est;
  std::vector<Estimate> first(w.vx.size()), second(w.vx.size());
  est.run(w.vx.data(), w.vz.data(), w.vx.size(), first.data());
  est.reset();
  est.run(w.vx.data(), w.vz.data(), w.vx.size(), second.data());
  for (std::size_t i = 0; i < w.vx.size(); ++i) ASSERT_EQ(first[i].gait_state, second[i].gait_state);
}

TEST(GaitEstimator, NonFiniteAndOutOfRangeChannelsAreFlaggedAndSkipped) {
  // A NaN or infinite channel, or one above max_abs_velocity_mps, is not used and flagged; the other channel is.
  const Walk w = make_walk(10.0, 1.8, 1.3, 0.02, kPi, 0.015, 8);
  Estimator est;
  for (std::size_t i = 0; i < w.vx.size(); ++i) est.step(w.vx[i], w.vz[i]);
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const double inf = std::numeric_limits<double>::infinity();
  EXPECT_EQ(est.step(nan, 0.05).status, Status::kRejectedNonFinite);
  EXPECT_EQ(est.step(1.3, inf).status, Status::kRejectedNonFinite);
  EXPECT_EQ(est.step(1.3, 0.0, nan).status, Status::kRejectedNonFinite);   // unusable time step
  EXPECT_EQ(est.step(1.3, 0.0, -0.04).status, Status::kRejectedNonFinite);
  EXPECT_EQ(est.step(5e3, 0.0).status, Status::kRejectedOutOfRange);
  const Estimate e = est.step(1.3, 0.0);
  EXPECT_TRUE(e.status == Status::kUpdated || e.status == Status::kRejectedOutlier);
  EXPECT_NEAR(e.step_frequency_hz, 1.8, 0.05);
  // Before the first usable v_x nothing starts.
  Estimator fresh;
  EXPECT_EQ(fresh.step(nan, 0.1).status, Status::kRejectedNonFinite);
  EXPECT_FALSE(fresh.step(nan, 0.1).walking);
}

TEST(GaitEstimator, OutliersAreFlaggedAndLeaveTheEstimateAsAMissingSample) {
  // Single spikes of 2 m/s while walking are all reported as kRejectedOutlier (no other sample is),
  // the state is exactly what it is with those samples missing (NaN), and f stays within 0.5 % of
  // the spike-free run.
  const Walk w = make_walk(40.0, 1.9, 1.4, 0.02, kPi, 0.015, 9);
  const double nan = std::numeric_limits<double>::quiet_NaN();
  Estimator clean, spiky, missing;
  int flagged = 0, spikes = 0;
  for (std::size_t i = 0; i < w.vx.size(); ++i) {
    const bool spike = i > 250 && i % 53 == 0;
    const Estimate a = clean.step(w.vx[i], w.vz[i]);
    const Estimate b = spiky.step(w.vx[i] + (spike ? 2.0 : 0.0), w.vz[i] - (spike ? 2.0 : 0.0));
    const Estimate c = missing.step(spike ? nan : w.vx[i], spike ? nan : w.vz[i]);
    spikes += spike;
    flagged += spike && b.status == Status::kRejectedOutlier;
    if (i > 250) {
      ASSERT_EQ(b.gait_state, c.gait_state) << i;
      ASSERT_NEAR(a.step_frequency_hz, b.step_frequency_hz, 0.005 * 1.9) << i;
      ASSERT_NEAR(a.speed_mps, b.speed_mps, 0.01) << i;
      if (!spike) {
        ASSERT_NE(b.status, Status::kRejectedOutlier) << i;
      }
    }
  }
  EXPECT_EQ(flagged, spikes);
  EXPECT_GE(spikes, 10);
}

TEST(GaitEstimator, StateStaysFiniteUnderExtremeInput) {
  // Huge, tiny, non-finite samples and time steps never make the state or covariance non-finite.
  Estimator est;
  const double values[] = {1e308, -1e308, 1e-308, std::numeric_limits<double>::quiet_NaN(), 1e200, -3e150, 0.0,
                           999.0, -999.0, 1.3};
  const double dts[] = {0.04, 1e-12, 0.0, 5.0, 1e300, std::numeric_limits<double>::infinity(), 0.04};
  int k = 0;
  for (int round = 0; round < 200; ++round) {
    for (double v : values) {
      const double dt = dts[static_cast<std::size_t>(k++) % (sizeof(dts) / sizeof(dts[0]))];
      const Estimate e = est.step(v, -v * 0.5, dt);
      for (double x : e.gait_state) ASSERT_TRUE(std::isfinite(x));
      ASSERT_TRUE(std::isfinite(e.step_frequency_std_hz) && std::isfinite(e.speed_std_mps));
      ASSERT_TRUE(std::isfinite(e.R_m) && std::isfinite(e.r_m) && std::isfinite(e.vx_hat_h2_mps));
      ASSERT_GT(e.step_frequency_hz, 0.0);
      for (const auto& row : est.gait_covariance())
        for (double p : row) ASSERT_TRUE(std::isfinite(p));
    }
  }
}

TEST(GaitEstimator, BadConfigurationIsRejectedWithAMessage) {
  // Each kind of bad value of the gait filter's fields throws std::invalid_argument naming the field.
  struct Case {
    void (*change)(EstimatorConfig&);
    const char* field;
  };
  const Case cases[] = {
      {[](EstimatorConfig& c) { c.gait_filter.f_min_hz = 0.0; }, "f_min_hz"},
      {[](EstimatorConfig& c) { c.gait_filter.f_max_hz = 0.5; }, "f_max_hz"},
      {[](EstimatorConfig& c) { c.gait_filter.bank_f_hz = FrequencyList{}; }, "bank_f_hz"},
      {[](EstimatorConfig& c) { c.gait_filter.bank_f_hz = {1.0, 1.1, 1.2, 1.3, 1.4, 1.5, 1.6, 1.7, 1.8}; }, "bank_f_hz"},
      {[](EstimatorConfig& c) { c.gait_filter.bank_f_hz[0] = 5.0; }, "bank_f_hz"},
      {[](EstimatorConfig& c) { c.gait_filter.q_phase_rad2_per_s = -1.0; }, "q_phase_rad2_per_s"},
      {[](EstimatorConfig& c) { c.gait_filter.meas_vz_density_m2_per_s = 0.0; }, "meas_vz_density_m2_per_s"},
      {[](EstimatorConfig& c) { c.gait_filter.gate_sigma = std::numeric_limits<double>::quiet_NaN(); }, "gate_sigma"},
      {[](EstimatorConfig& c) { c.gait_filter.walk_speed_off_mps = 0.5; }, "walk_speed_off_mps"},
      {[](EstimatorConfig& c) { c.gait_filter.spectral_buffer_s = 1000.0; }, "spectral_buffer_s"},
      {[](EstimatorConfig& c) { c.gait_filter.spectral_buffer_s = 20.0; }, "spectral_buffer_s"},  // 500 samples
      {[](EstimatorConfig& c) { c.gait_filter.spectral_buffer_s = 0.01; }, "spectral_buffer_s"},  // < 1 sample
      {[](EstimatorConfig& c) { c.gait_filter.spectral_grid_step_hz = 0.0; }, "spectral_grid_step_hz"},
      {[](EstimatorConfig& c) { c.gait_filter.accel_tau_s = 0.0; }, "accel_tau_s"},
      {[](EstimatorConfig& c) { c.gait_filter.std_scale_max = 0.01; }, "std_scale_max"},
      {[](EstimatorConfig& c) { c.gait_filter.bank_f_hz = {1.8, 1.3}; }, "bank_f_hz"},
      {[](EstimatorConfig& c) { c.gait_filter.bank_f_hz = {1.3, 1.3}; }, "bank_f_hz"},
      {[](EstimatorConfig& c) { c.gait_filter.q_omega_rate_hi_rad2_per_s5 = 0.001; }, "q_omega_rate_hi_rad2_per_s5"},
      {[](EstimatorConfig& c) { c.gait_filter.p0_phasor_std_mps = 1e300; }, "p0_phasor_std_mps"},
      {[](EstimatorConfig& c) { c.gait_filter.speed_std_floor_mps = 1e300; }, "speed_std_floor_mps"},
      {[](EstimatorConfig& c) { c.gait_filter.gate_max_consecutive_s = 1e19; }, "gate_max_consecutive_s"},
      {[](EstimatorConfig& c) { c.algorithm = static_cast<Algorithm>(7); }, "algorithm"},
  };
  for (const Case& k : cases) {
    EstimatorConfig c;
    k.change(c);
    const char* msg = c.validate();
    ASSERT_NE(msg, nullptr) << k.field;
    EXPECT_NE(std::string(msg).find(k.field), std::string::npos) << msg;
    EXPECT_THROW(Estimator{c}, std::invalid_argument) << k.field;
  }
  EXPECT_EQ(EstimatorConfig{}.validate(), nullptr);
  EXPECT_EQ(EstimatorConfig{}.algorithm, Algorithm::kGaitFilter);
  EXPECT_EQ(EstimatorConfig::paper().algorithm, Algorithm::kPaper);
}

TEST(GaitEstimator, DtIsUsedAndADoubledSampleTimeMatches) {
  // Dropping every other sample and giving dt = 2 T tracks the same frequency as the full-rate stream.
  const Walk w = make_walk(30.0, 1.8, 1.3, 0.02, kPi, 0.015, 10);
  Estimator full, half;
  std::vector<double> f_full, f_half;
  for (std::size_t i = 0; i < w.vx.size(); ++i) {
    const Estimate a = full.step(w.vx[i], w.vz[i]);
    if (w.t[i] > 10.0) f_full.push_back(a.step_frequency_hz);
    if (i % 2 == 0) {
      const Estimate b = half.step(w.vx[i], w.vz[i], 0.08);
      if (w.t[i] > 10.0) f_half.push_back(b.step_frequency_hz);
    }
  }
  EXPECT_NEAR(median(f_full), 1.8, 0.01);
  EXPECT_NEAR(median(f_half), 1.8, 0.01);
}

TEST(GaitEstimator, PredictionAheadFollowsTheWalk) {
  // After convergence, the 0.2 s-ahead prediction (with harmonics) matches the noise-free walk 0.2 s later.
  const Walk w = make_walk(30.0, 1.8, 1.3, 0.02, kPi, 0.0, 11);
  Estimator est;
  double worst = 0.0;
  for (std::size_t i = 0; i + 5 < w.vx.size(); ++i) {
    est.step(w.vx[i], w.vz[i]);
    if (w.t[i] < 15.0) continue;
    const Velocity v = est.predict_ahead(0.2);  // 5 samples of 0.04 s
    worst = std::max({worst, std::fabs(v.vx_mps - w.vx[i + 5]), std::fabs(v.vz_mps - w.vz[i + 5])});
  }
  EXPECT_LT(worst, 0.02);
}

TEST(GaitForecast, AWiderPhaseSpreadPullsTheOscillationAheadTowardsTheMeanAndNothingElse) {
  // phase_var_scale 1 is the default call bit for bit; a larger one shrinks the forecast oscillation
  // (v_z ahead, v_x about A0) and leaves the speed, the phase advance and the stds as they were.
  const Walk w = make_walk(20.0, 1.8, 1.3, 0.02, kPi, 0.002, 5);
  Estimator est;
  for (std::size_t i = 0; i < w.vx.size(); ++i) est.step(w.vx[i], w.vz[i]);
  for (const double h : {0.2, 0.5, 1.0}) {
    const Forecast base = est.forecast(h), one = est.forecast(h, true, nullptr, 1.0);
    const Forecast wide = est.forecast(h, true, nullptr, 1e6);
    EXPECT_EQ(one.vz_mps, base.vz_mps);
    EXPECT_EQ(one.vx_mps, base.vx_mps);
    EXPECT_LT(std::fabs(wide.vz_mps), std::fabs(base.vz_mps));
    EXPECT_LT(std::fabs(wide.vx_mps - wide.speed_mps), std::fabs(base.vx_mps - base.speed_mps));
    EXPECT_EQ(wide.speed_mps, base.speed_mps);
    EXPECT_EQ(wide.phase_advance_rad, base.phase_advance_rad);
    EXPECT_EQ(wide.vz_std_mps, base.vz_std_mps);
  }
}

TEST(GaitForecast, KnownPartKeepsAKnownRateAndDropsOneLostInItsStd) {
  // known_part(x, var): x itself when var = 0, 0 for x = 0, and shrinking towards 0 as var grows past x^2.
  EXPECT_EQ(known_part(0.3, 0.0), 0.3);
  EXPECT_EQ(known_part(0.0, 0.0), 0.0);
  EXPECT_EQ(known_part(0.0, 1.0), 0.0);
  EXPECT_NEAR(known_part(-0.3, 0.09), -0.15, 1e-15);
  EXPECT_LT(std::fabs(known_part(0.3, 9.0)), 0.01 * 0.3);
}

TEST(GaitEstimator, PaperEstimateInTheGaitForm) {
  // For the paper, gait_state is eq. 5 in the dual-phasor form and the derived relation is the mirror for x3 < 0.
  Estimator est(EstimatorConfig::paper());
  Estimate e;
  for (int i = 0; i < 200; ++i) e = est.step(1.2 + 0.1 * std::cos(0.45 * i), -0.1 * std::sin(0.45 * i));
  const State& x = e.state;
  EXPECT_EQ(e.gait_state[kX1], x[paper::kCos]);
  EXPECT_EQ(e.gait_state[kZ1], -x[paper::kSin]);
  EXPECT_EQ(e.gait_state[kW], e.omega_rad_s);
  EXPECT_EQ(e.gait_state[kA0], e.A0_mps);
  EXPECT_NEAR(e.amp_z_mps(), e.A1_mps, 1e-15);
  EXPECT_NEAR(std::fabs(e.phase_x_rel_z_rad()), kPi / 2, 1e-12);
  EXPECT_EQ(e.phase_x_rel_z_rad() < 0, x[paper::kOmega] >= 0);
  EXPECT_EQ(e.omega_rate_rad_s2(), 0.0);
}

// The gait filter's sample-counting settings are durations: 40 and 6 samples at the 25 Hz defaults, twice that at 50 Hz.
TEST(GaitFilterConfig, DurationsInSamplesOfTheSampleTime) {
  EstimatorConfig c;
  EXPECT_EQ(c.samples_in(c.gait_filter.spectral_buffer_s), 40u);
  EXPECT_EQ(c.samples_in(c.gait_filter.gate_max_consecutive_s), 6u);
  c.sample_time_s = 0.02;
  EXPECT_EQ(c.samples_in(c.gait_filter.spectral_buffer_s), 80u);
  EXPECT_EQ(c.samples_in(c.gait_filter.gate_max_consecutive_s), 12u);
  EXPECT_EQ(c.validate(), nullptr);
}

// Standing with velocity noise of variance N on both channels: the detector's thresholds raised by
// three noise standard deviations of its low-passes keep it standing; not raised, the same noise walks.
TEST(WalkingDetectorNoise, RaisedThresholdsKeepNoiseFromWalking) {
  const double noise_var = 0.04;  // 0.2 m/s per sample
  std::mt19937 rng(7);
  std::normal_distribution<double> n(0.0, std::sqrt(noise_var));
  WalkingDetector::Thresholds th;
  WalkingDetector raised(th), plain(th);
  raised.set_noise(noise_var, noise_var, 3.0);
  plain.set_noise(noise_var, noise_var, 0.0);
  const double g = raised.gain(0.04);
  int raised_walking = 0, plain_walking = 0;
  for (int k = 0; k < 2500; ++k) {  // 100 s at 25 Hz
    const double vx = n(rng), vz = n(rng);
    raised.update(vx, vz, true, true, g);
    plain.update(vx, vz, true, true, g);
    raised_walking += raised.walking();
    plain_walking += plain.walking();
  }
  EXPECT_LE(raised_walking, 125);  // at most 5 % of the time
  EXPECT_GT(plain_walking, 125);
}

// Without noise the margins change nothing: the same decisions as a detector never told of noise.
TEST(WalkingDetectorNoise, NoNoiseNoChange) {
  WalkingDetector::Thresholds th;
  WalkingDetector told(th), untold(th);
  told.set_noise(0.0, 0.0, 3.0);
  const double g = told.gain(0.04);
  for (int k = 0; k < 500; ++k) {
    const double vx = 0.3 * std::sin(0.05 * k), vz = 0.06 * std::cos(0.3 * k);
    told.update(vx, vz, true, true, g);
    untold.update(vx, vz, true, true, g);
    ASSERT_EQ(told.walking(), untold.walking()) << k;
  }
}

// A lock that keeps falling back to the lower bound between short excursions well inside is still
// pinned: the watchdog fires. A frequency that stays well inside (a slow walker's) never does.
TEST(BoundWatchdog, HoveringNearABoundFiresAndSteadyInsideDoesNot) {
  const double two_pi = 6.283185307179586, dt = 0.04;
  yoyogait::gait::BoundWatchdog::Settings s;
  s.w_min_rad_s = two_pi * 0.4;
  s.w_max_rad_s = two_pi * 4.0;
  s.limit_s = 1.0;
  yoyogait::gait::BoundWatchdog hovering(s), slow(s);
  bool fired = false, slow_fired = false;
  for (int k = 0; k < 250 && !fired; ++k) {  // 0.8 s at 0.41 Hz, then 0.2 s at 0.5 Hz, over and over
    const double f_hz = (k % 25) < 20 ? 0.41 : 0.5;
    fired = hovering.update(two_pi * f_hz, dt);
  }
  EXPECT_TRUE(fired);
  for (int k = 0; k < 2500; ++k)  // a slow walker at 0.5 Hz dipping to the bound for 0.2 s every 2 s
    slow_fired |= slow.update(two_pi * ((k % 50) < 5 ? 0.41 : 0.5), dt);
  EXPECT_FALSE(slow_fired);
}

}  // namespace gait_filter_tests
