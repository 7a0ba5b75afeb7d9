// The Yoyo-model (eq. 1-4).
#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "yoyogait/yoyo_model.hpp"

namespace model_tests {  // one per file: the sanitizer build compiles the files as one unit
using namespace yoyogait;

TEST(YoyoModel, VelocitiesAreTheDerivativesOfThePositions) {
  // Eq. 3-4 are the time derivatives of eq. 1-2 (central differences, constant omega).
  const YoyoParams p{0.115, 0.02, 0.95};
  const double omega = 2 * M_PI * 1.8, h = 1e-6;
  for (double t = 0.0; t < 2.0; t += 0.037) {
    const YoyoPoint a = yoyo_point(p, omega * (t - h), omega), b = yoyo_point(p, omega * (t + h), omega);
    const YoyoPoint c = yoyo_point(p, omega * t, omega);
    EXPECT_NEAR((b.x_m - a.x_m) / (2 * h), c.vx_mps, 1e-6);
    EXPECT_NEAR((b.z_m - a.z_m) / (2 * h), c.vz_mps, 1e-6);
  }
}

TEST(YoyoModel, ForwardSpeedAveragesToROmegaAndPelvisIsHighestWhenVxPeaks) {
  // Over whole steps the mean of v_x is R omega; v_x peaks at theta = 0 where z = z0 + r.
  const YoyoParams p{0.12, 0.025, 1.0};
  const std::size_t n = 1000;
  std::vector<double> t(n), f(n, 2.0);
  for (std::size_t i = 0; i < n; ++i) t[i] = static_cast<double>(i) * 0.001;  // two whole steps
  std::vector<YoyoPoint> pts(n);
  yoyo_trajectory(p, t.data(), f.data(), n, 0.0, pts.data());
  double mean = 0.0;
  for (const auto& q : pts) mean += q.vx_mps / static_cast<double>(n);
  EXPECT_NEAR(mean, p.R_m * 2 * M_PI * 2.0, 1e-3);
  EXPECT_NEAR(pts[0].z_m, p.z0_m + p.r_m, 1e-15);
  EXPECT_NEAR(pts[0].vx_mps, (p.R_m + p.r_m) * 2 * M_PI * 2.0, 1e-12);
}

TEST(YoyoModel, PhaseIntegratesAVaryingStepFrequency) {
  // With a linearly rising frequency, theta is the exact integral (trapezoid is exact for linear f).
  const std::size_t n = 501;
  std::vector<double> t(n), f(n);
  for (std::size_t i = 0; i < n; ++i) {
    t[i] = static_cast<double>(i) * 0.01;
    f[i] = 1.0 + 0.2 * t[i];
  }
  std::vector<YoyoPoint> pts(n);
  yoyo_trajectory(YoyoParams{}, t.data(), f.data(), n, 0.3, pts.data());
  const double T = t[n - 1];
  EXPECT_NEAR(pts[n - 1].theta_rad, 0.3 + 2 * M_PI * (T + 0.1 * T * T), 1e-9);
}

}  // namespace model_tests
