// The EKF building blocks: transition, Jacobian, fast sincos, update.
#include <gtest/gtest.h>

#include "finite_difference.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <random>
#include <vector>

#include "yoyogait/covariance_guard.hpp"
#include "yoyogait/paper/ekf.hpp"
#include "yoyogait/math.hpp"

namespace ekf_tests {  // one per file: the sanitizer build compiles the files as one unit
using namespace yoyogait;
using namespace yoyogait::paper;

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

TEST(Update, EqualsTheTextbookKalmanUpdate) {
  // The adjugate form equals x + K y, (I - K H) P with K = P H^T S^-1 on random covariances.
  std::mt19937 gen(5);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  const double H[2][4] = {{1, 0, 0, 1}, {0, -1, 0, 0}};
  const double V[2] = {1e-2, 2e-2};
  for (int n = 0; n < 100; ++n) {
    // P = A A^T + 0.1 I is symmetric positive definite.
    double A[4][4];
    for (auto& row : A)
      for (double& a : row) a = u(gen);
    Matrix4 P{};
    for (std::size_t i = 0; i < 4; ++i)
      for (std::size_t j = 0; j < 4; ++j) {
        for (std::size_t k = 0; k < 4; ++k) P[i][j] += A[i][k] * A[j][k];
        if (i == j) P[i][j] += 0.1;
      }
    const State x{{u(gen), u(gen), 0.3 * u(gen), u(gen)}};
    const Measurement z{u(gen), u(gen)};
    // Textbook: PHt (4x2), S (2x2), K = PHt S^-1.
    double PHt[4][2] = {}, S[2][2] = {};
    for (std::size_t i = 0; i < 4; ++i)
      for (std::size_t m = 0; m < 2; ++m)
        for (std::size_t k = 0; k < 4; ++k) PHt[i][m] += P[i][k] * H[m][k];
    for (std::size_t m = 0; m < 2; ++m)
      for (std::size_t l = 0; l < 2; ++l) {
        for (std::size_t k = 0; k < 4; ++k) S[m][l] += H[m][k] * PHt[k][l];
        if (m == l) S[m][l] += V[m];
      }
    const double det = S[0][0] * S[1][1] - S[0][1] * S[1][0];
    const double Si[2][2] = {{S[1][1] / det, -S[0][1] / det}, {-S[1][0] / det, S[0][0] / det}};
    double K[4][2] = {};
    for (std::size_t i = 0; i < 4; ++i)
      for (std::size_t m = 0; m < 2; ++m)
        for (std::size_t l = 0; l < 2; ++l) K[i][m] += PHt[i][l] * Si[l][m];
    const double y[2] = {z.vx_mps - (x[0] + x[3]), z.vz_mps + x[1]};
    State x_post = x;
    Matrix4 P_post = P;
    ASSERT_TRUE(update(x_post, P_post, z, V[0], V[1]));
    for (std::size_t i = 0; i < 4; ++i) {
      EXPECT_NEAR(x_post[i], x[i] + K[i][0] * y[0] + K[i][1] * y[1], 1e-12);
      for (std::size_t j = 0; j < 4; ++j) {
        double KHP = 0.0;
        for (std::size_t m = 0; m < 2; ++m) KHP += K[i][m] * PHt[j][m];
        EXPECT_NEAR(P_post[i][j], P[i][j] - KHP, 1e-12) << i << "," << j;
        EXPECT_EQ(P_post[i][j], P_post[j][i]);
      }
    }
  }
}

TEST(SymMatrix4, NamesEachEntryOnceForBothHalves) {
  // (i, j) and (j, i) are one entry; the 10 entries are distinct and dense() restores the matrix.
  SymMatrix4 m;
  double v = 1.0;
  for (std::size_t i = 0; i < 4; ++i)
    for (std::size_t j = i; j < 4; ++j) m(i, j) = v++;
  const Matrix4 d = m.dense();
  std::vector<double> seen;
  for (std::size_t i = 0; i < 4; ++i)
    for (std::size_t j = 0; j < 4; ++j) {
      EXPECT_EQ(m(i, j), m(j, i));
      EXPECT_EQ(d[i][j], m(i, j));
      if (j >= i) seen.push_back(m(i, j));
    }
  std::sort(seen.begin(), seen.end());
  EXPECT_EQ(std::unique(seen.begin(), seen.end()) - seen.begin(), 10);
  const SymMatrix4 back(d);
  for (std::size_t i = 0; i < 4; ++i)
    for (std::size_t j = 0; j < 4; ++j) EXPECT_EQ(back(i, j), m(i, j));
}

TEST(Sqrt2, EqualsStdSqrt) {
  // The paired square root (both lanes) and sqrt1 are correctly rounded, as std::sqrt.
  std::mt19937_64 gen(11);
  std::uniform_real_distribution<double> e(-300.0, 300.0);
  for (int i = 0; i < 10000; ++i) {
    const double a = std::pow(10.0, e(gen)), b = std::pow(10.0, e(gen));
    double ra, rb;
    yoyogait::sqrt2(a, b, ra, rb);
    ASSERT_EQ(ra, std::sqrt(a));
    ASSERT_EQ(rb, std::sqrt(b));
    ASSERT_EQ(yoyogait::sqrt1(a), std::sqrt(a));
  }
  double ra, rb;
  yoyogait::sqrt2(0.0, -1.0, ra, rb);
  EXPECT_EQ(ra, 0.0);
  EXPECT_TRUE(std::isnan(rb));
}

TEST(SymMatrix4, StoresThePairsTheFilterStepLoads) {
  // data() holds [P11, P22], [P12, P34], [P13, P23], [P14, P24], [P33, P44] (1-based), as documented.
  SymMatrix4 m;
  for (std::size_t i = 0; i < 4; ++i)
    for (std::size_t j = i; j < 4; ++j) m(i, j) = 10.0 * static_cast<double>(i + 1) + static_cast<double>(j + 1);
  const double expected[10] = {11, 22, 12, 34, 13, 23, 14, 24, 33, 44};
  for (std::size_t k = 0; k < 10; ++k) EXPECT_EQ(m.data()[k], expected[k]) << k;
}

namespace {

// A random symmetric positive definite covariance, scaled by scale.
SymMatrix4 random_covariance(std::mt19937& gen, double scale) {
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  double A[4][4];
  for (auto& row : A)
    for (double& a : row) a = u(gen);
  SymMatrix4 P;
  for (std::size_t i = 0; i < 4; ++i)
    for (std::size_t j = i; j < 4; ++j) {
      double s = i == j ? 0.01 : 0.0;
      for (std::size_t k = 0; k < 4; ++k) s += A[i][k] * A[j][k];
      P(i, j) = scale * s;
    }
  return P;
}

}  // namespace

TEST(FilterStep, DispatchedFormEqualsTheScalarFormBitForBit) {
  // predict() and update() (SSE2 pairs where available) give exactly predict_scalar(), update_scalar(),
  // the covariance guard's certificate included.
  std::mt19937 gen(13);
  int certified = 0, within = 0;
  std::uniform_real_distribution<double> u(-1.0, 1.0), w(-1.2, 1.2);
  const std::array<double, 4> q{1e-5, 2e-5, 1e-3, 3e-3};
  for (int n = 0; n < 2000; ++n) {
    const double scale = std::pow(10.0, 4.0 * u(gen));
    const State x{{u(gen), u(gen), w(gen), 2.0 * u(gen)}};  // |w| > pi/4 takes the libm sincos
    const SymMatrix4 P = random_covariance(gen, scale);
    State xa, xb;
    SymMatrix4 Pa, Pb;
    // The variance bounds on both sides of the predicted diagonal.
    std::array<double, 4> bound;
    for (double& b : bound) b = scale * std::pow(10.0, 1.0 + 1.5 * u(gen));
    const bool ina = predict(x, P, q, bound, xa, Pa);
    const bool inb = predict_scalar(x, P, q, bound, xb, Pb);
    ASSERT_EQ(ina, inb);
    ASSERT_EQ(ina, within_variance_bounds(Pa, bound));
    within += ina;
    ASSERT_EQ(xa.x, xb.x);
    for (std::size_t k = 0; k < 10; ++k) ASSERT_EQ(Pa.data()[k], Pb.data()[k]) << k;
    const Measurement z{3.0 * u(gen), u(gen)};
    State ya, yb;
    SymMatrix4 Qa, Qb;
    // The guard's certificate too, with floors on both sides of where it flips.
    const double floor = std::pow(10.0, -12.0 + 10.0 * (0.5 + 0.5 * u(gen)));
    bool ca = false, cb = true;
    const bool oka = update(xa, Pa, z, 1e-2, 2e-2, kRoundingMargin / floor, ya, Qa, ca);
    const bool okb = update_scalar(xb, Pb, z, 1e-2, 2e-2, kRoundingMargin / floor, yb, Qb, cb);
    ASSERT_TRUE(oka);
    ASSERT_EQ(oka, okb);
    ASSERT_EQ(ca, cb);
    certified += ca;
    ASSERT_EQ(ya.x, yb.x);
    for (std::size_t k = 0; k < 10; ++k) ASSERT_EQ(Qa.data()[k], Qb.data()[k]) << k;
  }
  EXPECT_GT(certified, 200);
  EXPECT_LT(certified, 1800);
  EXPECT_GT(within, 100);
  EXPECT_LT(within, 1900);
  // Both refuse the same overflowing measurement.
  State y;
  SymMatrix4 Q;
  const State x{{0.1, 0.0, 0.3, 1.0}};
  const SymMatrix4 P(diagonal({1, 1, 1, 1}));
  EXPECT_FALSE(update(x, P, Measurement{1e308, -1e308}, 1e-2, 1e-2, y, Q));
  EXPECT_FALSE(update_scalar(x, P, Measurement{1e308, -1e308}, 1e-2, 1e-2, y, Q));
}

namespace {

// A symmetric 4x4 with eigenvalues lambda in a random orthonormal basis (Gram-Schmidt).
SymMatrix4 with_eigenvalues(std::mt19937& gen, const std::array<double, 4>& lambda) {
  std::normal_distribution<double> nd(0.0, 1.0);
  double Qm[4][4];
  for (std::size_t j = 0; j < 4; ++j) {
    for (std::size_t i = 0; i < 4; ++i) Qm[i][j] = nd(gen);
    for (std::size_t k = 0; k < j; ++k) {
      double d = 0.0;
      for (std::size_t i = 0; i < 4; ++i) d += Qm[i][j] * Qm[i][k];
      for (std::size_t i = 0; i < 4; ++i) Qm[i][j] -= d * Qm[i][k];
    }
    double n = 0.0;
    for (std::size_t i = 0; i < 4; ++i) n += Qm[i][j] * Qm[i][j];
    for (std::size_t i = 0; i < 4; ++i) Qm[i][j] /= std::sqrt(n);
  }
  SymMatrix4 P;
  for (std::size_t i = 0; i < 4; ++i)
    for (std::size_t j = i; j < 4; ++j) {
      double s = 0.0;
      for (std::size_t k = 0; k < 4; ++k) s += Qm[i][k] * lambda[k] * Qm[j][k];
      P(i, j) = s;
    }
  return P;
}

double min_eigenvalue(const Matrix4& P) {
  Matrix4 A = P, V;
  std::array<double, 4> lambda;
  symmetric_eigen(A, lambda, V);
  return *std::min_element(lambda.begin(), lambda.end());
}

}  // namespace

TEST(PositiveDefinite, BlockTestDecidesAsTheEigenvaluesAndBothFormsAgree) {
  // The division-free block test says "positive definite" exactly for matrices whose smallest
  // eigenvalue is clearly positive, and its SSE2 and scalar forms give the same answer.
  std::mt19937 gen(17);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  int pd = 0, not_pd = 0;
  for (int n = 0; n < 20000; ++n) {
    const double scale = std::pow(10.0, 6.0 * u(gen));
    std::array<double, 4> lambda;
    for (double& l : lambda) l = scale * std::pow(10.0, 4.0 * u(gen));
    if (n % 2) lambda[static_cast<std::size_t>(n / 2) % 4] *= (n % 4 == 1 ? -1e-3 : -1.0);  // one negative
    const SymMatrix4 P = with_eigenvalues(gen, lambda);
    const bool a = positive_definite(P), b = positive_definite_scalar(P);
    ASSERT_EQ(a, b) << n;
    const double lo = *std::min_element(lambda.begin(), lambda.end());
    const double hi = *std::max_element(lambda.begin(), lambda.end());
    if (lo > 1e-6 * hi) {
      EXPECT_TRUE(a) << n;  // condition number below 1e6: certified
      ++pd;
    } else if (lo < 0.0) {
      EXPECT_FALSE(a) << n;
      ++not_pd;
    }
    if (lo < 0.0) {
      EXPECT_FALSE(positive_definite_ldl(P.dense())) << n;
    }
    if (lo > 1e-6 * hi) {
      EXPECT_TRUE(positive_definite_ldl(P.dense())) << n;
    }
  }
  EXPECT_GT(pd, 5000);
  EXPECT_GT(not_pd, 5000);
  // Non-finite and zero matrices fail; the identity passes.
  const double nan = std::numeric_limits<double>::quiet_NaN(), inf = std::numeric_limits<double>::infinity();
  EXPECT_FALSE(positive_definite(SymMatrix4(diagonal({1, 1, nan, 1}))));
  EXPECT_FALSE(positive_definite_scalar(SymMatrix4(diagonal({1, 1, nan, 1}))));
  EXPECT_FALSE(positive_definite(SymMatrix4(diagonal({inf, 1, 1, 1}))));
  EXPECT_FALSE(positive_definite(SymMatrix4{}));
  EXPECT_TRUE(positive_definite(SymMatrix4(diagonal({1, 1, 1, 1}))));
}

TEST(JosephUpdate, EqualsTheStandardUpdateOnWellConditionedCovariances) {
  // The guard's Joseph form gives the state and covariance of update() to rounding.
  std::mt19937 gen(23);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  for (int n = 0; n < 500; ++n) {
    const SymMatrix4 P = random_covariance(gen, 1.0);
    const State x{{u(gen), u(gen), 0.3 * u(gen), u(gen)}};
    const Measurement z{u(gen), u(gen)};
    State xa, xb;
    SymMatrix4 Pa, Pb;
    ASSERT_TRUE(update(x, P, z, 1e-2, 2e-2, xa, Pa));
    ASSERT_TRUE(joseph_update(x, P, z, 1e-2, 2e-2, xb, Pb));
    for (std::size_t i = 0; i < 4; ++i) {
      EXPECT_NEAR(xa[i], xb[i], 1e-12);
      for (std::size_t j = 0; j < 4; ++j) EXPECT_NEAR(Pa(i, j), Pb(i, j), 1e-12);
    }
  }
}

TEST(JosephUpdate, StaysPositiveDefiniteWhereTheStandardFormDoesNot) {
  // The plain filter on sequences like (0, 0), (a, 500..1000), (0, NaN) x 1-3, then small samples
  // (a corrupt sample within range, then missing ones: a huge, nearly singular prediction) loses
  // positive definiteness in the standard update in many of them; the Joseph form of the same
  // update, from the same prediction, never does; and the guard's certificate never vouches for a
  // standard update that lost it.
  std::mt19937 gen(37);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  const std::array<double, 4> q{1e-5, 1e-5, 1e-3, 1e-3};
  const double nan = std::numeric_limits<double>::quiet_NaN();
  int standard_lost = 0, joseph_lost = 0, certified_updates = 0;
  const double cert_scale = kRoundingMargin / (1e-5 / (1.0 + 1e-5 * (2.0 / 1e-2 + 1.0 / 1e-2)));  // as PaperEstimator's
  for (int n = 0; n < 2000; ++n) {
    State x{{0.02, 0.0, 0.1, 0.2}};
    SymMatrix4 P(diagonal({1, 1, 1, 1}));
    std::vector<std::array<double, 2>> in = {{0.0, 0.0}, {5.0 * u(gen), (u(gen) < 0 ? -1 : 1) * (750.0 + 250.0 * u(gen))}};
    for (int i = 0, m = 2 + static_cast<int>(1.5 * u(gen)); i < m; ++i) in.push_back({0.0, nan});
    for (int i = 0; i < 4; ++i) in.push_back({0.3 * u(gen), 0.3 * u(gen)});
    for (const auto& s : in) {
      State xp, xa, xb;
      SymMatrix4 Pp, Pa, Pb;
      predict(x, P, q, xp, Pp);
      if (std::isnan(s[1])) {
        x = xp;
        P = Pp;
        continue;
      }
      bool certified = false;
      ASSERT_TRUE(update(xp, Pp, Measurement{s[0], s[1]}, 1e-2, 1e-2, cert_scale, xa, Pa, certified));
      ASSERT_TRUE(joseph_update(xp, Pp, Measurement{s[0], s[1]}, 1e-2, 1e-2, xb, Pb));
      // The guard's certificate never vouches for an indefinite result.
      if (certified) {
        ASSERT_GT(min_eigenvalue(Pa.dense()), 0.0);
        ++certified_updates;
      }
      if (min_eigenvalue(Pa.dense()) < 0.0) {
        ++standard_lost;
        joseph_lost += !(min_eigenvalue(Pb.dense()) > 0.0 && positive_definite(Pb));
        break;
      }
      x = xa;
      P = Pa;
    }
  }
  EXPECT_GT(standard_lost, 100);
  EXPECT_EQ(joseph_lost, 0);
  EXPECT_GT(certified_updates, 1000);
}

TEST(CovarianceGuard, NearestPositiveDefiniteFloorsTheEigenvalues) {
  // The repair leaves eigenvalues >= 1e-12 of the largest, is symmetric, keeps a well-conditioned
  // positive definite matrix to rounding, and refuses a matrix without a positive eigenvalue.
  std::mt19937 gen(29);
  for (int n = 0; n < 200; ++n) {
    const SymMatrix4 P = with_eigenvalues(gen, {3.0, -0.5, 1e-3, -2e-7});
    Matrix4 d = P.dense();
    ASSERT_TRUE(nearest_positive_definite(d));
    for (std::size_t i = 0; i < 4; ++i)
      for (std::size_t j = 0; j < 4; ++j) ASSERT_EQ(d[i][j], d[j][i]);
    EXPECT_GT(min_eigenvalue(d), 0.9e-12 * 3.0);
    EXPECT_TRUE(positive_definite_ldl(d));
    const SymMatrix4 Q = with_eigenvalues(gen, {3.0, 0.5, 1e-3, 2e-2});
    Matrix4 e = Q.dense();
    ASSERT_TRUE(nearest_positive_definite(e));
    for (std::size_t i = 0; i < 4; ++i)
      for (std::size_t j = 0; j < 4; ++j) EXPECT_NEAR(e[i][j], Q(i, j), 1e-14);
  }
  Matrix4 negative = diagonal({-1.0, -2.0, 0.0, -3.0});
  EXPECT_FALSE(nearest_positive_definite(negative));
  Matrix4 nan = diagonal({1.0, std::numeric_limits<double>::quiet_NaN(), 1.0, 1.0});
  EXPECT_FALSE(nearest_positive_definite(nan));
}

TEST(CovarianceGuard, BoundVariancesKeepsCorrelationsAndDefiniteness) {
  // Variances above their bound are brought to it, the correlations stay, the rest is untouched.
  std::mt19937 gen(31);
  const SymMatrix4 S = with_eigenvalues(gen, {5e7, 2.0, 1e-3, 1e-5});
  Matrix4 P = S.dense();
  const std::array<double, 4> bound{1e6, 1e6, 9.8696044010893586, 1e6};
  bound_variances(P, bound);
  for (std::size_t i = 0; i < 4; ++i) {
    EXPECT_LE(P[i][i], bound[i]);
    if (S(i, i) <= bound[i]) {
      EXPECT_EQ(P[i][i], S(i, i));
    }
    for (std::size_t j = 0; j < 4; ++j) {
      const double before = S(i, j) / std::sqrt(S(i, i) * S(j, j)), after = P[i][j] / std::sqrt(P[i][i] * P[j][j]);
      EXPECT_NEAR(before, after, 1e-12);
    }
  }
  EXPECT_GT(min_eigenvalue(P), 0.0);
  EXPECT_TRUE(within_variance_bounds(SymMatrix4(P), bound));
  EXPECT_FALSE(within_variance_bounds(S, bound));
}

}  // namespace ekf_tests
