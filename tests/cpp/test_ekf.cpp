// The EKF building blocks: transition, Jacobian, fast sincos, update.
#include <gtest/gtest.h>

#include "finite_difference.hpp"

#include <cmath>
#include <random>

#include "yoyogait/ekf.hpp"
#include "yoyogait/math.hpp"

using namespace yoyogait;

namespace {

void expect_jacobian_matches(const State& s, double tol) {
  const Matrix4 analytic = transition_jacobian(s);
  const Matrix4 numeric = yoyogait::testing::central_jacobian<kStateDim>(s, [](const State& v) { return transition(v); });
  double scale = 1.0;
  for (std::size_t i = 0; i < kStateDim; ++i) scale = std::max(scale, std::fabs(s[i]));
  for (std::size_t i = 0; i < kStateDim; ++i)
    for (std::size_t j = 0; j < kStateDim; ++j)
      EXPECT_NEAR(analytic[i][j], numeric[i][j], tol * scale) << "entry " << i << "," << j;
}

}  // namespace

TEST(Jacobian, MatchesFiniteDifferencesOnRandomStates) {
  // The Jacobian of eq. 6 equals its central finite difference on random walking states.
  std::mt19937 gen(7);
  std::uniform_real_distribution<double> amp(-0.5, 0.5), w(-0.6, 0.6), bias(-2.0, 2.0);
  for (int n = 0; n < 200; ++n) expect_jacobian_matches(State{{amp(gen), amp(gen), w(gen), bias(gen)}}, 1e-7);
}

TEST(Jacobian, MatchesFiniteDifferencesNearZero) {
  // The Jacobian is right at and near the origin, where the oscillation vanishes.
  expect_jacobian_matches(State{{0.0, 0.0, 0.0, 0.0}}, 1e-8);
  expect_jacobian_matches(State{{1e-9, -2e-9, 1e-8, 1e-9}}, 1e-8);
}

TEST(Jacobian, MatchesFiniteDifferencesOnLargeStates) {
  // The Jacobian stays right for large amplitudes and for frequencies beyond pi/4 (libm path).
  expect_jacobian_matches(State{{150.0, -80.0, 2.5, 400.0}}, 1e-6);
  expect_jacobian_matches(State{{3e3, 1e3, -3.0, -1e3}}, 1e-6);
}

TEST(Sincos, AgreesWithLibmWithinOneUlp) {
  // The polynomial sincos equals std::sin/std::cos to an ulp on [-pi/4, pi/4] and exactly beyond.
  std::mt19937_64 gen(3);
  std::uniform_real_distribution<double> u(-0.7853981633974483, 0.7853981633974483);
  for (int i = 0; i < 200000; ++i) {
    const double x = u(gen);
    double s, c;
    yoyogait::sincos(x, s, c);
    EXPECT_LE(std::fabs(s - std::sin(x)), 2.3e-16 * std::fabs(std::sin(x)) + 1e-300);
    EXPECT_LE(std::fabs(c - std::cos(x)), 1.2e-16);
  }
  double s, c;
  yoyogait::sincos(2.0, s, c);
  EXPECT_EQ(s, std::sin(2.0));
  EXPECT_EQ(c, std::cos(2.0));
}

TEST(Predict, RotatesTheOscillationAndKeepsCovarianceSymmetric) {
  // Prediction is eq. 6 for the state and F P F^T + Q (symmetric) for the covariance.
  State s{{0.3, -0.1, 0.4, 1.2}};
  Matrix4 P{};
  std::mt19937 gen(1);
  std::uniform_real_distribution<double> u(-0.1, 0.1);
  for (std::size_t i = 0; i < 4; ++i) {
    P[i][i] = 1.0 + static_cast<double>(i);
    for (std::size_t j = 0; j < i; ++j) P[i][j] = P[j][i] = u(gen);
  }
  const std::array<double, 4> q{1e-5, 1e-5, 1e-3, 1e-3};
  const Matrix4 F = transition_jacobian(s);
  Matrix4 expected{};
  for (std::size_t i = 0; i < 4; ++i)
    for (std::size_t j = 0; j < 4; ++j) {
      for (std::size_t a = 0; a < 4; ++a)
        for (std::size_t b = 0; b < 4; ++b) expected[i][j] += F[i][a] * P[a][b] * F[j][b];
      if (i == j) expected[i][j] += q[i];
    }
  const State fs = transition(s);
  predict(s, P, q);
  for (std::size_t i = 0; i < 4; ++i) {
    EXPECT_DOUBLE_EQ(s[i], fs[i]);
    for (std::size_t j = 0; j < 4; ++j) {
      EXPECT_NEAR(P[i][j], expected[i][j], 1e-14);
      EXPECT_EQ(P[i][j], P[j][i]);
    }
  }
}

TEST(Update, RefusesAMeasurementThatWouldOverflow) {
  // An update that would make the state infinite is refused and leaves state and covariance as they were.
  State s{{0.1, 0.0, 0.3, 1.0}};
  Matrix4 P = diagonal({1, 1, 1, 1});
  const State s0 = s;
  const Matrix4 P0 = P;
  EXPECT_FALSE(update(s, P, Measurement{1e308, -1e308}, 1e-2, 1e-2));
  EXPECT_EQ(s.x, s0.x);
  EXPECT_EQ(P, P0);
  EXPECT_TRUE(update(s, P, Measurement{1.0, 0.0}, 1e-2, 1e-2));
}
