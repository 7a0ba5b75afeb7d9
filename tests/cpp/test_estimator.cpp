// The estimator of the paper (EstimatorConfig::paper()): convergence, eq. 11-12, streaming vs batch,
// bad input, no allocation.
#include <gtest/gtest.h>

#include <atomic>
#include <cmath>
#include <cstdlib>
#include <limits>
#include <new>
#include <random>
#include <stdexcept>
#include <vector>

#include "yoyogait/estimator.hpp"
#include "yoyogait/yoyo_model.hpp"

// Count heap allocations, to show that step() makes none.
std::atomic<long> g_allocations{0};  // also read by test_online.cpp
void* operator new(std::size_t n) {
  ++g_allocations;
  if (void* p = std::malloc(n ? n : 1)) return p;
  throw std::bad_alloc();
}
// The replaced operator new takes its memory from malloc, so free is right; GCC >= 11 cannot see
// that at -O3 and warns.
#if defined(__GNUC__) && !defined(__clang__) && __GNUC__ >= 11
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wmismatched-new-delete"
#endif
void operator delete(void* p) noexcept { std::free(p); }
void operator delete(void* p, std::size_t) noexcept { std::free(p); }
#if defined(__GNUC__) && !defined(__clang__) && __GNUC__ >= 11
#pragma GCC diagnostic pop
#endif

namespace estimator_tests {  // one per file: the sanitizer build compiles the files as one unit
using namespace yoyogait;
using namespace yoyogait::paper;

namespace {

struct Walk {
  std::vector<double> vx, vz;
};

// Eq. 3-4 sampled at 25 Hz, optionally with white noise.
Walk yoyo_walk(double seconds, double f_hz, double R_m, double r_m, double noise = 0.0, unsigned seed = 1) {
  const double T = 0.04;
  const auto n = static_cast<std::size_t>(seconds / T);
  std::vector<double> t(n), f(n, f_hz);
  for (std::size_t i = 0; i < n; ++i) t[i] = static_cast<double>(i + 1) * T;
  std::vector<YoyoPoint> pts(n);
  yoyo_trajectory(YoyoParams{R_m, r_m, 1.0}, t.data(), f.data(), n, 0.0, pts.data());
  std::mt19937 gen(seed);
  std::normal_distribution<double> nd(0.0, noise > 0 ? noise : 1.0);
  Walk w;
  for (const auto& p : pts) {
    w.vx.push_back(p.vx_mps + (noise > 0 ? nd(gen) : 0.0));
    w.vz.push_back(p.vz_mps + (noise > 0 ? nd(gen) : 0.0));
  }
  return w;
}

}  // namespace

TEST(PaperEstimator, ConvergesOnACleanYoyoWalk) {
  // On eq. 3-4 at 25 Hz (1.8 Hz, R = 0.115 m, r = 0.02 m) the paper preset has f within 1 % and R, r within 5 % after 10 s.
  const Walk w = yoyo_walk(30.0, 1.8, 0.115, 0.02);
  Estimator est(EstimatorConfig::paper());
  for (std::size_t i = 0; i < w.vx.size(); ++i) {
    const Estimate e = est.step(w.vx[i], w.vz[i]);
    if (static_cast<double>(i + 1) * 0.04 < 10.0) continue;
    ASSERT_NEAR(e.step_frequency_hz, 1.8, 0.018) << "sample " << i;
    ASSERT_NEAR(e.R_m, 0.115, 0.05 * 0.115) << "sample " << i;
    ASSERT_NEAR(e.r_m, 0.02, 0.05 * 0.02) << "sample " << i;
  }
}

TEST(PaperEstimator, StartsFromThePapersInitialState) {
  // x(0) = [r0 w0, 0, w0, R0 w0] and P0 = I before the first sample.
  Estimator est(EstimatorConfig::paper());
  EXPECT_DOUBLE_EQ(est.state().a1_cos(), 0.2 * 0.1);
  EXPECT_DOUBLE_EQ(est.state().a1_sin(), 0.0);
  EXPECT_DOUBLE_EQ(est.state().omega_rad_per_sample(), 0.1);
  EXPECT_DOUBLE_EQ(est.state().bias_mps(), 2.0 * 0.1);
  for (std::size_t i = 0; i < 4; ++i)
    for (std::size_t j = 0; j < 4; ++j) EXPECT_EQ(est.covariance()[i][j], i == j ? 1.0 : 0.0);
}

TEST(ParameterFilter, HoldsTheInitialValuesForTheFirstNSamples) {
  // Eq. 11-12 leave R_hat(k) = R_hat(0) for k <= n even with an open gate.
  ParameterFilter f(10, 0.1, 0.1, 2.0, 0.2);
  for (int k = 1; k <= 10; ++k) {
    EXPECT_FALSE(f.update(0.3, 1.0, 0.05));
    EXPECT_EQ(f.R_hat_mps(), 2.0);
    EXPECT_EQ(f.r_hat_mps(), 0.2);
  }
  EXPECT_TRUE(f.update(0.3, 1.0, 0.05));
  EXPECT_DOUBLE_EQ(f.R_hat_mps(), (10 * 2.0 + 1.0 / 0.3) / 11.0);
  EXPECT_DOUBLE_EQ(f.r_hat_mps(), (10 * 0.2 + 0.05 / 0.3) / 11.0);
}

TEST(ParameterFilter, HoldsWhileTheGateIsClosed) {
  // R_hat, r_hat keep their value while x3 <= mu_w or x4 <= mu_A0, and average the last n + new when open.
  ParameterFilter f(3, 0.1, 0.1, 2.0, 0.2);
  std::vector<double> R{2.0, 2.0, 2.0};  // R_hat(1..3)
  for (int k = 1; k <= 3; ++k) f.update(0.5, 1.0, 0.1);
  f.update(0.5, 1.0, 0.1);  // k = 4 > n: open
  const double R4 = (2.0 + 2.0 + 2.0 + 1.0 / 0.5) / 4.0;
  EXPECT_DOUBLE_EQ(f.R_hat_mps(), R4);
  EXPECT_FALSE(f.update(0.1, 1.0, 0.1));  // x3 == mu_w: closed
  EXPECT_EQ(f.R_hat_mps(), R4);
  EXPECT_FALSE(f.update(-0.5, 1.0, 0.1));  // negative frequency: closed
  EXPECT_FALSE(f.update(0.5, 0.05, 0.1));  // bias below mu_A0: closed
  EXPECT_EQ(f.R_hat_mps(), R4);
  EXPECT_TRUE(f.update(0.5, 1.5, 0.1));  // window is R_hat(5..7) = R4 held three times
  EXPECT_DOUBLE_EQ(f.R_hat_mps(), (3 * R4 + 1.5 / 0.5) / 4.0);
}

TEST(ParameterFilter, EqualsTheDirectMeanOverLongRuns) {
  // The running window sums give eq. 11-12 computed directly, to 1e-13, over 20,000 samples.
  std::mt19937 gen(3);
  std::uniform_real_distribution<double> w(0.0, 0.6), bias(0.0, 2.0), a1(0.0, 0.1);
  for (const std::size_t n : {std::size_t{1}, std::size_t{10}, std::size_t{37}}) {
    ParameterFilter f(n, 0.1, 0.1, 2.0, 0.2);
    std::vector<double> R_hist, r_hist;  // R_hat(1..k), r_hat(1..k)
    double R = 2.0, r = 0.2;
    for (std::size_t k = 1; k <= 20000; ++k) {
      const double wk = w(gen), bk = bias(gen), ak = a1(gen);
      const bool open = k > n && wk > 0.1 && bk > 0.1;
      if (open) {
        double sR = 0.0, sr = 0.0;
        for (std::size_t i = k - 1 - n; i < k - 1; ++i) {
          sR += R_hist[i];
          sr += r_hist[i];
        }
        R = (sR + bk / wk) / static_cast<double>(n + 1);
        r = (sr + ak / wk) / static_cast<double>(n + 1);
      }
      R_hist.push_back(R);
      r_hist.push_back(r);
      ASSERT_EQ(f.update(wk, bk, ak), open);
      ASSERT_NEAR(f.R_hat_mps(), R, 1e-13 * std::fabs(R)) << "n " << n << " k " << k;
      ASSERT_NEAR(f.r_hat_mps(), r, 1e-13 * std::fabs(r)) << "n " << n << " k " << k;
    }
  }
}

TEST(Estimator, RunEqualsStepByStep) {
  // The batch call gives bit-identical estimates to a loop of step().
  const Walk w = yoyo_walk(20.0, 1.7, 0.11, 0.025, 0.05);
  Estimator a(EstimatorConfig::paper()), b(EstimatorConfig::paper());
  std::vector<Estimate> out(w.vx.size());
  a.run(w.vx.data(), w.vz.data(), w.vx.size(), out.data());
  for (std::size_t i = 0; i < w.vx.size(); ++i) {
    const Estimate e = b.step(w.vx[i], w.vz[i]);
    ASSERT_EQ(e.state.x, out[i].state.x);
    ASSERT_EQ(e.vx_hat_mps, out[i].vx_hat_mps);
    ASSERT_EQ(e.R_hat_mps, out[i].R_hat_mps);
  }
}

TEST(Estimator, ResetReturnsToTheInitialState) {
  // After reset() the estimator repeats its first run exactly.
  const Walk w = yoyo_walk(5.0, 1.7, 0.11, 0.025, 0.05);
  Estimator est(EstimatorConfig::paper());
  std::vector<Estimate> first(w.vx.size()), second(w.vx.size());
  est.run(w.vx.data(), w.vz.data(), w.vx.size(), first.data());
  est.reset();
  est.run(w.vx.data(), w.vz.data(), w.vx.size(), second.data());
  for (std::size_t i = 0; i < w.vx.size(); ++i) ASSERT_EQ(first[i].state.x, second[i].state.x);
}

TEST(Estimator, NonFiniteSampleSkipsTheUpdate) {
  // A NaN or infinite sample leaves the pure prediction (eq. 6) and is flagged.
  Estimator est(EstimatorConfig::paper()), ref(EstimatorConfig::paper());
  for (int i = 0; i < 50; ++i) {
    est.step(1.2, 0.05 * std::sin(i * 0.4));
    ref.step(1.2, 0.05 * std::sin(i * 0.4));
  }
  const State predicted = transition(ref.state());
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const Estimate e = est.step(nan, 0.1);
  EXPECT_EQ(e.status, Status::kRejectedNonFinite);
  EXPECT_EQ(e.state.x, predicted.x);
  EXPECT_EQ(est.step(0.1, std::numeric_limits<double>::infinity()).status, Status::kRejectedNonFinite);
  EXPECT_EQ(est.step(1e4, 0.0).status, Status::kRejectedOutOfRange);
  EXPECT_EQ(est.step(1.2, 0.0).status, Status::kUpdated);
}

TEST(Estimator, StateStaysFiniteUnderExtremeInput) {
  // Huge, tiny and non-finite samples never make the state or covariance non-finite.
  Estimator est(EstimatorConfig::paper());
  const double values[] = {1e308, -1e308, 1e-308, std::numeric_limits<double>::quiet_NaN(), 1e200, -3e150, 0.0};
  for (int round = 0; round < 100; ++round) {
    for (double v : values) {
      const Estimate e = est.step(v, -v);
      for (double x : e.state.x) ASSERT_TRUE(std::isfinite(x));
      for (const auto& row : est.covariance())
        for (double p : row) ASSERT_TRUE(std::isfinite(p));
    }
  }
}

TEST(Estimator, StepDoesNotAllocate) {
  // step() and run() make no heap allocation.
  const Walk w = yoyo_walk(10.0, 1.8, 0.115, 0.02, 0.05);
  std::vector<Estimate> out(w.vx.size());
  Estimator est(EstimatorConfig::paper());
  const long before = g_allocations.load();
  for (std::size_t i = 0; i < w.vx.size(); ++i) out[i] = est.step(w.vx[i], w.vz[i]);
  est.run(w.vx.data(), w.vz.data(), w.vx.size(), out.data());
  EXPECT_EQ(g_allocations.load(), before);
}

TEST(GaitEstimator, StepDoesNotAllocate) {
  // The default estimator's step() makes no heap allocation on any path: start-up bank, spectral
  // seed, steady state, outliers, NaN, standing, re-acquisition, long gaps, irregular dt, run().
  const Walk w = yoyo_walk(10.0, 1.8, 0.115, 0.02, 0.05);
  std::vector<Estimate> out(w.vx.size());
  std::vector<double> dt(w.vx.size(), 0.04);
  for (std::size_t i = 0; i < dt.size(); i += 7) dt[i] = 0.05;
  Estimator est;  // EstimatorConfig{}: the default
  const long before = g_allocations.load();
  for (std::size_t i = 0; i < w.vx.size(); ++i) out[i] = est.step(w.vx[i], w.vz[i]);
  out[0] = est.step(w.vx[0] + 5.0, -5.0);                                  // outlier
  out[0] = est.step(std::numeric_limits<double>::quiet_NaN(), 0.0);         // non-finite
  for (int i = 0; i < 100; ++i) out[0] = est.step(0.0, 0.0);                // standing
  est.run(w.vx.data(), w.vz.data(), w.vx.size(), out.data(), dt.data());    // walking again, irregular dt
  out[0] = est.step(w.vx[0], w.vz[0], 3.0);                                 // long gap
  est.run(w.vx.data(), w.vz.data(), w.vx.size(), out.data());
  (void)est.predict_ahead(0.2);
  EXPECT_EQ(g_allocations.load(), before);
  EXPECT_FALSE(out.back().acquiring);
}

TEST(Estimator, RejectsAnInvalidConfiguration) {
  // A non-positive or denormal sample time, a huge P0, zero or negative noise or too long a window is an error at construction.
  EstimatorConfig c = EstimatorConfig::paper();
  c.sample_time_s = 0.0;
  EXPECT_THROW(Estimator{c}, std::invalid_argument);
  c = EstimatorConfig::paper();
  c.sample_time_s = std::numeric_limits<double>::quiet_NaN();
  EXPECT_THROW(Estimator{c}, std::invalid_argument);
  c = EstimatorConfig::paper();
  c.sample_time_s = 5e-324;
  EXPECT_THROW(Estimator{c}, std::invalid_argument);
  c = EstimatorConfig::paper();
  c.paper_estimator.p0_bias_mps2 = 1e300;
  EXPECT_THROW(Estimator{c}, std::invalid_argument);
  c = EstimatorConfig::paper();
  c.paper_estimator.v_vz_mps2 = 0.0;
  EXPECT_THROW(Estimator{c}, std::invalid_argument);
  c = EstimatorConfig::paper();
  c.paper_estimator.q_bias_mps2 = -1.0;
  EXPECT_THROW(Estimator{c}, std::invalid_argument);
  c = EstimatorConfig::paper();
  c.paper_estimator.smoothing_window_samples = kMaxSmoothingWindow + 1;
  EXPECT_THROW(Estimator{c}, std::invalid_argument);
  EXPECT_EQ(EstimatorConfig::paper().validate(), nullptr);
}

TEST(Estimator, PredictionAheadFollowsTheModel) {
  // After convergence on a clean walk, the 0.2 s-ahead prediction matches the walk 0.2 s later.
  const Walk w = yoyo_walk(30.0, 1.8, 0.115, 0.02);
  Estimator est(EstimatorConfig::paper());
  double worst = 0.0;
  for (std::size_t i = 0; i + 5 < w.vx.size(); ++i) {
    est.step(w.vx[i], w.vz[i]);
    if (i < 500) continue;
    const Velocity v = est.predict_ahead(0.2);  // 5 samples of 0.04 s
    worst = std::max({worst, std::fabs(v.vx_mps - w.vx[i + 5]), std::fabs(v.vz_mps - w.vz[i + 5])});
  }
  EXPECT_LT(worst, 0.01);
}

TEST(PaperCovarianceGuard, NeverActsOnWalkingData) {
  // On a noisy walk with NaN samples the estimator's state and covariance equal, bit for bit, the
  // plain paper filter (predict, update, prediction only for unusable samples) without the guard.
  Walk w = yoyo_walk(120.0, 1.7, 0.11, 0.025, 0.08, 3);
  for (std::size_t i = 500; i < 520; ++i) w.vx[i] = std::numeric_limits<double>::quiet_NaN();
  const EstimatorConfig cfg = EstimatorConfig::paper();
  Estimator est(cfg);
  const Estimator fresh(cfg);
  State x = fresh.state();
  SymMatrix4 P(fresh.covariance());
  const PaperConfig& pc = cfg.paper_estimator;
  const std::array<double, 4> q{pc.q_oscillation_mps2, pc.q_oscillation_mps2, pc.q_omega_rad2, pc.q_bias_mps2};
  for (std::size_t i = 0; i < w.vx.size(); ++i) {
    est.step(w.vx[i], w.vz[i]);
    State xp, xu;
    SymMatrix4 Pp, Pu;
    predict(x, P, q, xp, Pp);
    if (std::isfinite(w.vx[i]) && update(xp, Pp, Measurement{w.vx[i], w.vz[i]}, pc.v_vx_mps2, pc.v_vz_mps2, xu, Pu)) {
      x = xu;
      P = Pu;
    } else {
      x = xp;
      P = Pp;
    }
    ASSERT_EQ(est.state().x, x.x) << i;
    ASSERT_EQ(est.covariance(), P.dense()) << i;
  }
}

TEST(PaperCovarianceGuard, KeepsTheCovariancePositiveDefiniteOnTheReproducer) {
  // (0, 0), (-3, 999.90625), (0, NaN), (0, 0), (0, 0): without the guard P44 = -0.0038 and the
  // speed std is NaN at the last sample; with it P stays positive definite and every std finite.
  Estimator est(EstimatorConfig::paper());
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const double in[5][2] = {{0, 0}, {-3, 999.90625}, {0, nan}, {0, 0}, {0, 0}};
  for (const auto& s : in) {
    const Estimate e = est.step(s[0], s[1]);
    ASSERT_TRUE(std::isfinite(e.speed_std_mps) && std::isfinite(e.step_frequency_std_hz));
    ASSERT_TRUE(positive_definite_ldl(est.covariance()));
  }
}

TEST(PaperCovarianceGuard, BoundsTheVariancesOverALongDropout) {
  // 10,000 s of NaN samples after a walk: P stays finite and positive definite, its variances
  // within their bounds (velocities (max_abs_velocity_mps)^2, frequency pi^2), also after the walk resumes.
  const EstimatorConfig cfg = EstimatorConfig::paper();
  Estimator est(cfg);
  const Walk w = yoyo_walk(30.0, 1.8, 0.115, 0.02, 0.02, 4);
  est.run(w.vx.data(), w.vz.data(), w.vx.size(), std::vector<Estimate>(w.vx.size()).data());
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const double v2 = cfg.max_abs_velocity_mps * cfg.max_abs_velocity_mps, pi2 = 9.869604401089358;
  for (int i = 0; i < 250000; ++i) {
    const Estimate e = est.step(nan, nan);
    if (i % 1009 == 0 || i == 249999) {
      const Matrix4 P = est.covariance();
      ASSERT_TRUE(positive_definite_ldl(P)) << i;
      ASSERT_LE(P[0][0], v2);
      ASSERT_LE(P[1][1], v2);
      ASSERT_LE(P[2][2], pi2);
      ASSERT_LE(P[3][3], v2);
      ASSERT_TRUE(std::isfinite(e.step_frequency_std_hz) && std::isfinite(e.speed_std_mps));
    }
  }
  EXPECT_EQ(est.covariance()[2][2], pi2);
  for (std::size_t i = 0; i < w.vx.size(); ++i) {
    const Estimate e = est.step(w.vx[i], w.vz[i]);
    ASSERT_TRUE(positive_definite_ldl(est.covariance())) << i;
    ASSERT_TRUE(std::isfinite(e.step_frequency_std_hz) && std::isfinite(e.speed_std_mps));
  }
}

TEST(Estimator, InnovationIsTheMeasurementMinusThePrediction) {
  // Paper: innovation() = z - H f(x) and NIS = y^T S^-1 y with S = H (F P F^T + Q) H^T + V; NaN for an unused sample.
  const Walk w = yoyo_walk(10.0, 1.8, 0.115, 0.02, 0.05);
  Estimator est(EstimatorConfig::paper());
  EXPECT_TRUE(std::isnan(est.innovation().nis));
  const PaperConfig& pc = est.config().paper_estimator;
  const std::array<double, 4> q{pc.q_oscillation_mps2, pc.q_oscillation_mps2, pc.q_omega_rad2, pc.q_bias_mps2};
  for (std::size_t i = 0; i < w.vx.size(); ++i) {
    State x = est.state();
    Matrix4 P = est.covariance();
    predict(x, P, q);
    est.step(w.vx[i], w.vz[i]);
    const Innovation d = est.innovation();
    const double y0 = w.vx[i] - (x[kBias] + x[kCos]), y1 = w.vz[i] + x[kSin];
    ASSERT_NEAR(d.innovation_vx_mps, y0, 1e-12);
    ASSERT_NEAR(d.innovation_vz_mps, y1, 1e-12);
    const double s00 = P[kCos][kCos] + 2 * P[kCos][kBias] + P[kBias][kBias] + pc.v_vx_mps2;
    const double s01 = -(P[kCos][kSin] + P[kBias][kSin]), s11 = P[kSin][kSin] + pc.v_vz_mps2;
    const double det = s00 * s11 - s01 * s01;
    ASSERT_NEAR(d.nis, (y0 * y0 * s11 - 2 * y0 * y1 * s01 + y1 * y1 * s00) / det, 1e-9 * (1 + d.nis));
  }
  est.step(std::numeric_limits<double>::quiet_NaN(), 0.0);
  EXPECT_TRUE(std::isnan(est.innovation().innovation_vx_mps) && std::isnan(est.innovation().innovation_vz_mps));
  EXPECT_TRUE(std::isnan(est.innovation().nis));
}

TEST(GaitEstimator, InnovationIsUndefinedWhenNothingWasUpdated) {
  // Default: no innovation before the first usable sample or for an unusable time step; both channels while walking.
  const Walk w = yoyo_walk(10.0, 1.8, 0.115, 0.02, 0.05);
  Estimator est;
  EXPECT_TRUE(std::isnan(est.innovation().nis));
  est.step(std::numeric_limits<double>::quiet_NaN(), 0.0);
  EXPECT_TRUE(std::isnan(est.innovation().nis));
  for (std::size_t i = 0; i < w.vx.size(); ++i) est.step(w.vx[i], w.vz[i]);
  const Innovation d = est.innovation();
  EXPECT_TRUE(std::isfinite(d.innovation_vx_mps) && std::isfinite(d.innovation_vz_mps) && d.nis >= 0.0);
  est.step(1.0, 0.0, -1.0);
  EXPECT_TRUE(std::isnan(est.innovation().innovation_vx_mps) && std::isnan(est.innovation().nis));
}

}  // namespace estimator_tests
