// The online front-end and OnlineEstimator: accuracy on synthetic walks at several capture rates,
// the causal centre, the differentiator's delay, bad input.
#include <gtest/gtest.h>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <limits>
#include <random>
#include <stdexcept>
#include <utility>
#include <vector>

#include "yoyogait/online.hpp"

// Heap allocations counted by the replaced operator new of test_estimator.cpp.
extern std::atomic<long> g_allocations;

namespace online_tests {  // one per file: the sanitizer build compiles the files as one unit
using namespace yoyogait;

namespace {

constexpr double kPi = 3.14159265358979323846;
constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

// A Yoyo-model walk (eq. 1-4 with the pelvis' forward oscillation in anti-phase) along x, up z,
// carried by four markers of a pelvis 0.25 m wide and 0.15 m deep, with marker noise.
struct SyntheticPelvis {
  double f_hz = 1.8, speed_mps = 1.2, r_m = 0.012, z0_m = 1.0, noise_m = 0.001;
  std::mt19937 rng{7};
  double theta(double t) const { return 2.0 * kPi * f_hz * t; }
  double vz(double t) const { return -r_m * 2.0 * kPi * f_hz * std::sin(theta(t)); }
  // Centre position.
  void centre(double t, double c[3]) const {
    const double w = 2.0 * kPi * f_hz;
    c[0] = speed_mps * t + r_m * std::sin(theta(t));
    c[1] = 0.0;
    c[2] = z0_m + r_m * std::cos(theta(t));
    (void)w;
  }
  void markers(double t, double* p) {
    std::normal_distribution<double> n(0.0, noise_m);
    double c[3];
    centre(t, c);
    const double dx[4] = {0.075, 0.075, -0.075, -0.075}, dy[4] = {0.125, -0.125, 0.125, -0.125};
    for (int j = 0; j < 4; ++j) {
      p[3 * j + 0] = c[0] + dx[j] + n(rng);
      p[3 * j + 1] = c[1] + dy[j] + n(rng);
      p[3 * j + 2] = c[2] + n(rng);
    }
  }
};

// Every value finite; the two stds too once the estimator has been fed (before: +inf, never NaN).
bool all_finite(const OnlineEstimate& e) {
  const double v[] = {e.vx_mps,     e.vz_mps,     e.vh_a_mps,          e.vh_b_mps,   e.heading_rad,
                      e.walk_a_mps, e.walk_b_mps, e.vx_hat_mps,        e.vz_hat_mps, e.step_frequency_hz,
                      e.speed_mps,  e.gait_phase, e.input_latency_s,   e.estimate_age_s, e.input_noise_m};
  for (double x : v)
    if (!std::isfinite(x)) return false;
  for (double x : {e.step_frequency_std_hz, e.speed_std_mps}) {
    if (!(x >= 0.0)) return false;
    if (e.walking && !std::isfinite(x)) return false;
  }
  return true;
}

}  // namespace

// The step frequency and speed converge to the walk's at every capture rate from 30 to 500 Hz.
TEST(OnlineEstimator, ConvergesAtAnyCaptureRate) {
  for (double rate : {30.0, 60.0, 100.0, 120.0, 250.0, 500.0}) {
    SyntheticPelvis walk;
    OnlineEstimator est(4, 2, 1.0);
    double p[12];
    OnlineEstimate e;
    double f_err_max = 0.0;
    for (int k = 0; k < static_cast<int>(30.0 * rate); ++k) {
      const double t = k / rate;
      walk.markers(t, p);
      e = est.update(t, p);
      ASSERT_TRUE(all_finite(e));
      if (t > 10.0) f_err_max = std::max(f_err_max, std::fabs(e.step_frequency_hz - walk.f_hz));
    }
    EXPECT_LT(f_err_max, 0.03) << rate << " Hz";
    EXPECT_NEAR(e.speed_mps, walk.speed_mps, 0.05) << rate << " Hz";
    EXPECT_TRUE(e.walking);
    EXPECT_NEAR(e.heading_rad, 0.0, 0.05);
  }
}

// v_z of the front-end follows the true vertical velocity with the delay input_latency_s reports.
TEST(OnlineEstimator, VerticalVelocityDelayMatchesReportedLatency) {
  SyntheticPelvis walk;
  walk.noise_m = 0.0;
  const double rate = 100.0;
  OnlineEstimator est(4, 2, 1.0);
  double p[12];
  // Fit vz_mps(t) = a cos(th) + b sin(th) over the last 10 s: the phase gives the delay.
  double cc = 0, ss = 0, cs = 0, yc = 0, ys = 0;
  OnlineEstimate e;
  for (int k = 0; k < static_cast<int>(20.0 * rate); ++k) {
    const double t = k / rate;
    walk.markers(t, p);
    e = est.update(t, p);
    if (t > 10.0) {
      // True vz = -A sin(th): write the estimate as -A' sin(th - w d).
      const double c = std::cos(walk.theta(t)), s = std::sin(walk.theta(t));
      cc += c * c;
      ss += s * s;
      cs += c * s;
      yc += e.vz_mps * c;
      ys += e.vz_mps * s;
    }
  }
  const double det = cc * ss - cs * cs;
  const double a = (yc * ss - ys * cs) / det, b = (ys * cc - yc * cs) / det;
  // -A' sin(th - phi) = -A' sin th cos phi + A' cos th sin phi: a = A' sin phi, b = -A' cos phi.
  const double phi = std::atan2(a, -b);
  const double delay_s = phi / (2.0 * kPi * walk.f_hz);
  EXPECT_NEAR(delay_s, e.input_latency_s, 0.001);
  EXPECT_LT(std::fabs(delay_s), 0.010);
  const double gain = std::hypot(a, b) / (walk.r_m * 2.0 * kPi * walk.f_hz);
  EXPECT_NEAR(gain, 1.0, 0.10);  // overshoot at ~2 Hz below 10 %
}

// The gait phase follows the walk: 0 at the fastest rise of the pelvis (v_z ~ cos 2 pi phase).
TEST(OnlineEstimator, GaitPhaseFollowsTheVerticalOscillation) {
  SyntheticPelvis walk;
  const double rate = 100.0;
  OnlineEstimator est(4, 2, 1.0);
  double p[12];
  double worst = 0.0;
  for (int k = 0; k < static_cast<int>(20.0 * rate); ++k) {
    const double t = k / rate;
    walk.markers(t, p);
    const OnlineEstimate e = est.update(t, p);
    if (t > 10.0) {
      // v_z = -A sin th = A cos(th + pi/2): the phase is (th + pi/2) / 2 pi.
      double truth = (walk.theta(t) + kPi / 2.0) / (2.0 * kPi);
      truth -= std::floor(truth);
      double d = std::fabs(e.gait_phase - truth);
      d = std::min(d, 1.0 - d);
      worst = std::max(worst, d);
    }
  }
  EXPECT_LT(worst, 0.05);
}

// The centre does not jump when a marker drops out or returns, even when the body has turned meanwhile.
TEST(CausalCentre, NoJumpWhenMarkersDropOutOrReturn) {
  online::CausalCentre::Settings settings;
  settings.blend_tau_s = 0.3;
  settings.forget_s = 2.0;
  online::CausalCentre centre(3, settings);
  const double dt = 0.01, speed = 1.0, yaw_rate = 0.5;  // turning at 0.5 rad/s
  online::Vec3 pos[3];
  bool vis[3];
  online::Vec3 last{};
  double worst = 0.0;
  for (int k = 0; k < 600; ++k) {
    const double t = k * dt, yaw = yaw_rate * t;
    const double cx = speed * t;
    const double off[3][2] = {{0.1, 0.12}, {0.1, -0.12}, {-0.1, 0.0}};
    for (int j = 0; j < 3; ++j) {
      const double ox = std::cos(yaw) * off[j][0] - std::sin(yaw) * off[j][1];
      const double oy = std::sin(yaw) * off[j][0] + std::cos(yaw) * off[j][1];
      pos[j] = {cx + ox, oy, 1.0};
      // marker 0 missing over 1-2 s, marker 2 over 1.5-2.5 s and 4-4.3 s
      vis[j] = !((j == 0 && t >= 1.0 && t < 2.0) || (j == 2 && ((t >= 1.5 && t < 2.5) || (t >= 4.0 && t < 4.3))));
    }
    const auto r = centre.update(pos, vis, k ? dt : 0.0);
    ASSERT_TRUE(r.ok);
    if (k) {
      const double step = std::hypot(r.centre_m[0] - last[0], r.centre_m[1] - last[1]);
      worst = std::max(worst, std::fabs(step - speed * dt));
    }
    last = r.centre_m;
  }
  // The stale offsets drift by up to ~5 cm over these gaps (0.5 rad of turn x 0.12 m); switching
  // definitions would step by that much in one frame. Blended over 0.3 s, the frame-to-frame
  // step stays within 2.5 mm of the true 1 cm.
  EXPECT_LT(worst, 2.5e-3);
}

// What white position noise at the configured floor leaves on the n-frame mean of the
// differentiator's velocity, computed from its steady-state gain, is what a simulation measures.
TEST(KalmanDifferentiator, FloorVelocityNoiseOfAnIntervalMeanMatchesSimulation) {
  yoyogait::OnlineConfig config;
  const online::KalmanDifferentiator::Settings settings = online::differentiator_settings(config);
  for (const double rate : {30.0, 100.0}) {
    const int n = rate < 50.0 ? 1 : 4;
    online::KalmanDifferentiator diff(settings);
    std::mt19937 rng(7);
    std::normal_distribution<double> noise(0.0, settings.meas_std_m);
    diff.start({0.0, 0.0, 0.0});
    double sum = 0.0, sum2 = 0.0, acc = 0.0;
    double count = 0.0;
    for (int k = 1; k <= 100000; ++k) {
      diff.predict(1.0 / rate);
      diff.update({noise(rng), 0.0, 0.0});
      if (k < 1000) continue;  // the start's transient
      acc += diff.velocity_mps()[0];
      if (k % n == 0) {
        sum += acc / n;
        sum2 += (acc / n) * (acc / n);
        count += 1.0;
        acc = 0.0;
      }
    }
    const double var = sum2 / count - (sum / count) * (sum / count);
    EXPECT_NEAR(var, diff.floor_mean_velocity_var(1.0 / rate, n), 0.05 * var) << rate << " Hz";
  }
}

// The step a set change starts blending out: none for a pelvis that only translates (its offsets
// stay true), the carried offset's drift for one that turned while a marker was unseen.
TEST(CausalCentre, SetChangeStepIsTheOffsetsDrift) {
  online::CausalCentre::Settings settings;
  for (const double yaw_rate : {0.0, 0.5}) {
    online::CausalCentre centre(3, settings);
    const double dt = 0.01, off[3][2] = {{0.1, 0.12}, {0.1, -0.12}, {-0.1, 0.0}};
    online::Vec3 pos[3];
    bool vis[3];
    double return_step = -1.0, other_steps = 0.0;
    for (int k = 0; k < 300; ++k) {
      const double t = k * dt, yaw = yaw_rate * t;
      for (int j = 0; j < 3; ++j) {
        const double ox = std::cos(yaw) * off[j][0] - std::sin(yaw) * off[j][1];
        const double oy = std::sin(yaw) * off[j][0] + std::cos(yaw) * off[j][1];
        pos[j] = {1.0 * t + ox, oy, 1.0};
        vis[j] = !(j == 0 && t >= 1.0 && t < 2.0);  // marker 0 unseen for 1 s
      }
      const auto r = centre.update(pos, vis, k ? dt : 0.0);
      if (k == 200)
        return_step = r.step_m;
      else
        other_steps = std::max(other_steps, r.step_m);
    }
    // Back after 1 s of turning, marker 0's carried offset is 7.8 cm stale (0.5 rad x 0.156 m); the
    // centre carried through the gap is off by centimetres, which the return's step takes back.
    // Without a turn nothing drifts and nothing steps; no frame but the return steps by a centimetre.
    const double drift_m = 2.0 * std::sin(0.5 * yaw_rate * 1.0) * std::hypot(0.1, 0.12);
    if (yaw_rate == 0.0) {
      EXPECT_LT(return_step, 1e-12);
    } else {
      EXPECT_GT(return_step, drift_m / 3.0);
      EXPECT_LT(return_step, drift_m);
    }
    EXPECT_LT(other_steps, 1e-12 + 0.02 * yaw_rate) << "yaw rate " << yaw_rate;
  }
}

// A point that never appears and a point seen only now and then do not stop the estimate.
TEST(OnlineEstimator, PointThatNeverAppears) {
  SyntheticPelvis walk;
  OnlineEstimator est(5, 2, 1.0);
  double p[15];
  OnlineEstimate e;
  for (int k = 0; k < 2000; ++k) {
    const double t = k / 100.0;
    walk.markers(t, p);
    p[12] = p[13] = p[14] = kNaN;
    if ((k / 50) % 3 == 0) p[0] = p[1] = p[2] = kNaN;
    e = est.update(t, p);
    ASSERT_TRUE(all_finite(e));
    ASSERT_EQ(e.status, OnlineStatus::kUsed);
  }
  EXPECT_NEAR(e.step_frequency_hz, walk.f_hz, 0.03);
}

// Bad frames get their status, nothing is thrown, nothing becomes non-finite, and the walk goes on.
TEST(OnlineEstimator, BadInputGetsAStatusAndStateStaysFinite) {
  SyntheticPelvis walk;
  OnlineEstimator est(4, 2, 1.0);
  double p[12];
  const double inf = std::numeric_limits<double>::infinity();
  double t = 0.0;
  for (int k = 0; k < 1000; ++k) {
    t = k / 100.0;
    walk.markers(t, p);
    EXPECT_EQ(est.update(t, p).status, OnlineStatus::kUsed);
  }
  walk.markers(t, p);
  EXPECT_EQ(est.update(t, p).status, OnlineStatus::kTimeNotIncreasing);
  EXPECT_EQ(est.update(t - 1.0, p).status, OnlineStatus::kTimeNotIncreasing);
  EXPECT_EQ(est.update(kNaN, p).status, OnlineStatus::kNonFinite);
  EXPECT_EQ(est.update(inf, p).status, OnlineStatus::kNonFinite);
  double missing[12];
  for (double& x : missing) x = kNaN;
  t += 0.01;
  OnlineEstimate e = est.update(t, missing);
  EXPECT_EQ(e.status, OnlineStatus::kAllMissing);
  EXPECT_TRUE(all_finite(e));
  double absurd[12];
  for (double& x : absurd) x = 1e30;
  t += 0.01;
  EXPECT_EQ(est.update(t, absurd).status, OnlineStatus::kNonFinite);
  for (double& x : absurd) x = inf;
  t += 0.01;
  EXPECT_EQ(est.update(t, absurd).status, OnlineStatus::kNonFinite);
  // One absurd point among good ones: the frame is used without it.
  walk.markers(t + 0.01, p);
  p[3] = -1e300;
  t += 0.01;
  e = est.update(t, p);
  EXPECT_EQ(e.status, OnlineStatus::kUsed);
  EXPECT_EQ(e.points_seen, 3);
  EXPECT_LT(std::fabs(e.vx_mps), 3.0);
  // A gap of ten minutes: held back as a jump ahead until two more frames follow, then it restarts
  // the front-end; the walk is found again.
  t += 600.0;
  walk.markers(t, p);
  EXPECT_EQ(est.update(t, p).status, OnlineStatus::kTimeJump);
  t += 0.01;
  EXPECT_EQ(est.update(t, p).status, OnlineStatus::kTimeJump);
  t += 0.01;
  e = est.update(t, p);
  EXPECT_EQ(e.status, OnlineStatus::kGapRestart);
  for (int k = 1; k < 2000; ++k) {
    walk.markers(t + k / 100.0, p);
    e = est.update(t + k / 100.0, p);
    ASSERT_TRUE(all_finite(e));
    ASSERT_EQ(e.status, OnlineStatus::kUsed);
  }
  EXPECT_NEAR(e.step_frequency_hz, walk.f_hz, 0.03);
  EXPECT_NEAR(e.speed_mps, walk.speed_mps, 0.05);
}

// Millimetres with the length unit give the same estimates as metres; the up axis may be y.
TEST(OnlineEstimator, LengthUnitAndUpAxis) {
  SyntheticPelvis a, b;
  OnlineEstimator metres(4, 2, 1.0), mm_y_up(4, 1, 0.001);
  double p[12], q[12];
  OnlineEstimate ea, eb;
  for (int k = 0; k < 1500; ++k) {
    const double t = k / 100.0;
    a.markers(t, p);
    b.markers(t, q);
    for (int j = 0; j < 4; ++j) {  // (x, y, z) -> (x, z, -y) in mm: y is up
      const double x = q[3 * j], y = q[3 * j + 1], z = q[3 * j + 2];
      q[3 * j] = 1000.0 * x;
      q[3 * j + 1] = 1000.0 * z;
      q[3 * j + 2] = -1000.0 * y;
    }
    ea = metres.update(t, p);
    eb = mm_y_up.update(t, q);
  }
  EXPECT_NEAR(ea.step_frequency_hz, eb.step_frequency_hz, 1e-6);
  EXPECT_NEAR(ea.vz_mps, eb.vz_mps, 1e-6);
  EXPECT_NEAR(ea.speed_mps, eb.speed_mps, 1e-6);
}

// The constructor rejects what it cannot run.
TEST(OnlineEstimator, ConstructorRejectsBadArguments) {
  EXPECT_THROW(OnlineEstimator(0, 2), std::invalid_argument);
  EXPECT_THROW(OnlineEstimator(17, 2), std::invalid_argument);
  EXPECT_THROW(OnlineEstimator(4, 3), std::invalid_argument);
  EXPECT_THROW(OnlineEstimator(4, -1), std::invalid_argument);
  EXPECT_THROW(OnlineEstimator(4, 2, 0.0), std::invalid_argument);
  OnlineConfig c;
  c.heading_tau_s = -1.0;
  EXPECT_THROW(OnlineEstimator(4, 2, 1.0, c), std::invalid_argument);
  c = OnlineConfig{};
  c.estimator = EstimatorConfig::paper();
  EXPECT_THROW(OnlineEstimator(4, 2, 1.0, c), std::invalid_argument);
}

// update() makes no heap allocation: through start-up, walking, dropouts, bad frames and a gap restart.
TEST(OnlineEstimator, UpdateDoesNotAllocate) {
  SyntheticPelvis walk;
  OnlineEstimator est(4, 2, 1.0);
  double p[12];
  const long before = g_allocations.load();
  for (int k = 0; k < 3000; ++k) {
    double t = k / 100.0;
    if (k >= 2000) t += 100.0;  // a gap restart
    walk.markers(t, p);
    if (k % 37 == 0) p[0] = p[1] = p[2] = kNaN;
    if (k % 101 == 0)
      for (double& x : p) x = kNaN;
    est.update(t, p);
    if (k % 53 == 0) est.update(t, p);  // timestamp not increasing
  }
  EXPECT_EQ(g_allocations.load(), before);
}

// Frames a microsecond apart, timestamps far in the future and huge jumps keep every output finite.
TEST(OnlineEstimator, ExtremeTimestampsStayFinite) {
  SyntheticPelvis walk;
  OnlineEstimator est(4, 2, 1.0);
  double p[12];
  double t = 0.0;
  for (int k = 0; k < 3000; ++k) {
    t += (k % 10 == 0) ? 1e-6 : 0.01;
    if (k == 1500) t += 1e12;
    walk.markers(t < 1e6 ? t : t - 1e12, p);
    const OnlineEstimate e = est.update(t, p);
    ASSERT_TRUE(all_finite(e)) << k;
  }
}

// predict(0) is the frame's vx_hat_mps/vz_hat_mps; predict is noexcept, allocates nothing; stds grow with the horizon.
TEST(OnlineEstimator, PredictAtZeroIsTheReconstructionAndAllocatesNothing) {
  static_assert(noexcept(std::declval<const OnlineEstimator&>().predict(0.2)), "predict must be noexcept");
  SyntheticPelvis walk;
  OnlineEstimator est(4, 2, 1.0);
  double p[12];
  EXPECT_FALSE(est.predict(0.2).valid);
  int checked = 0;
  for (int k = 0; k < 1500; ++k) {
    const double t = k / 100.0;
    walk.markers(t, p);
    const OnlineEstimate e = est.update(t, p);
    const long before = g_allocations.load();
    const OnlinePrediction p0 = est.predict(0.0), p5 = est.predict(0.5), p10 = est.predict(1.0);
    EXPECT_EQ(g_allocations.load(), before);
    if (!p0.valid) continue;
    EXPECT_EQ(p0.vx_mps, e.vx_hat_mps);
    EXPECT_EQ(p0.vz_mps, e.vz_hat_mps);
    EXPECT_DOUBLE_EQ(p5.t_s, t + 0.5);
    if (e.walking && t > 5.0) {
      EXPECT_LT(p0.vz_std_mps, p5.vz_std_mps);
      EXPECT_LT(p5.vz_std_mps, p10.vz_std_mps);
      EXPECT_LT(p5.vx_std_mps, p10.vx_std_mps);
      EXPECT_GE(e.next_step_in_s, 0.0);
      EXPECT_LT(e.next_step_in_s, 1.0 / e.step_frequency_hz + 0.02);
      ++checked;
    }
  }
  EXPECT_GT(checked, 500);
  EXPECT_FALSE(est.predict(-0.1).valid);
  EXPECT_FALSE(est.predict(std::numeric_limits<double>::quiet_NaN()).valid);
  EXPECT_TRUE(std::isinf(est.predict(OnlineEstimator::kMaxHorizonS * 2.0).vx_std_mps));
}

// valid is invalid_reason == 0: acquiring at first, valid in steady walking and then right within 2
// std; a walker who vanishes is not walking, not valid (INPUT_MISSING) with growing stds.
TEST(OnlineEstimator, ValidInSteadyWalkingNotAfterTheWalkerVanishes) {
  SyntheticPelvis walk;
  OnlineEstimator est(4, 2, 1.0);
  double p[12];
  OnlineEstimate e = est.update(0.0, (walk.markers(0.0, p), p));
  EXPECT_FALSE(e.valid);
  EXPECT_NE(e.invalid_reason & static_cast<std::uint8_t>(InvalidReason::kAcquiring), 0);
  int valid = 0, frames = 0;
  for (int k = 1; k < 2000; ++k) {
    const double t = k / 100.0;
    walk.markers(t, p);
    e = est.update(t, p);
    ASSERT_EQ(e.valid, e.invalid_reason == 0);
    if (t < 6.0) continue;
    ++frames;
    if (!e.valid) continue;
    ++valid;
    EXPECT_LT(std::fabs(e.step_frequency_hz - walk.f_hz), std::max(0.15, 2.0 * e.step_frequency_std_hz));
    EXPECT_LT(std::fabs(e.speed_mps - walk.speed_mps), std::max(0.15, 2.0 * e.speed_std_mps));
  }
  EXPECT_GT(valid, 0.95 * frames);
  const double f_std = e.step_frequency_std_hz, s_std = e.speed_std_mps;
  double none[12];
  for (double& x : none) x = std::numeric_limits<double>::quiet_NaN();
  for (int k = 1; k <= 6000; ++k) e = est.update(20.0 + k / 100.0, none);
  EXPECT_FALSE(e.walking);
  EXPECT_FALSE(e.valid);
  EXPECT_NE(e.invalid_reason & static_cast<std::uint8_t>(InvalidReason::kInputMissing), 0);
  EXPECT_GT(e.step_frequency_std_hz, 5.0 * f_std);
  EXPECT_GT(e.speed_std_mps, 5.0 * s_std);
}

// A marker that jumps by 1.4 m for one frame in the walk's first 0.1 s, before the noise is known
// (a swap, a ghost marker), is not taken for centimetres of noise: the noise estimate stays at the
// markers' millimetre, and no valid estimate is confidently wrong (found by bench/fuzz_online.cpp).
TEST(OnlineEstimator, AMarkersJumpBeforeTheNoiseIsKnownIsNotTakenForNoise) {
  for (const double rate_hz : {85.0, 100.0, 200.0}) {
    for (const int jump_frame : {3, 5, 8}) {
      SyntheticPelvis walk;
      walk.f_hz = 2.12;
      walk.speed_mps = 0.77;
      OnlineEstimator est(4, 2, 1.0);
      double p[12];
      double noise_max_m = 0.0;
      for (int k = 0; k < static_cast<int>(15.0 * rate_hz); ++k) {
        const double t = k / rate_hz;
        walk.markers(t, p);
        if (k == jump_frame) p[3 * 2 + 2] -= 1.44;
        const OnlineEstimate e = est.update(t, p);
        noise_max_m = std::max(noise_max_m, e.input_noise_m);
        if (!e.valid) continue;
        ASSERT_LT(std::fabs(e.step_frequency_hz - walk.f_hz), std::max(0.15, 2.0 * e.step_frequency_std_hz))
            << rate_hz << " Hz, jump at frame " << jump_frame << ", t " << t;
      }
      EXPECT_LT(noise_max_m, 0.005) << rate_hz << " Hz, jump at frame " << jump_frame;
    }
  }
}

namespace {

// A treadmill walk: the pelvis of SyntheticPelvis held in place (speed 0 in the lab) and two heels
// on a belt at belt_mps: stance for 60 % of the stride (moving back with the belt), swing forward.
struct SyntheticTreadmill {
  SyntheticPelvis pelvis;
  double belt_mps = 1.2, noise_m = 0.001;
  std::mt19937 rng{11};
  SyntheticTreadmill() { pelvis.speed_mps = 0.0; }
  // 6 points: the pelvis's 4, then the two heels.
  void frame(double t, double* p) {
    pelvis.markers(t, p);
    std::normal_distribution<double> n(0.0, noise_m);
    const double stride_s = 2.0 / pelvis.f_hz, len = belt_mps * 0.6 * stride_s;
    for (int j = 0; j < 2; ++j) {
      const double s = std::fmod(t / stride_s + 0.5 * static_cast<double>(j), 1.0), w = (s - 0.6) / 0.4;
      double* q = p + 12 + 3 * j;
      q[0] = (s < 0.6 ? 0.5 * len - belt_mps * s * stride_s : -0.5 * len + len * w) + n(rng);
      q[1] = (j ? 0.1 : -0.1) + n(rng);
      q[2] = 0.05 + (s < 0.6 ? 0.0 : 0.1 * std::sin(kPi * w)) + n(rng);
    }
  }
};

}  // namespace

// With two heels in the frames, the belt is found from the stance feet and the speed is belt plus
// pelvis, at 30 to 250 Hz; valid once walking has settled.
TEST(OnlineEstimator, TreadmillBeltFromTheStanceFeet) {
  for (double rate : {30.0, 60.0, 100.0, 250.0}) {
    SyntheticTreadmill walk;
    OnlineEstimator est(4, 2, 1.0, OnlineConfig{}, 2);
    EXPECT_EQ(est.feet(), 2u);
    double p[18];
    OnlineEstimate e;
    for (int k = 0; k < static_cast<int>(20.0 * rate); ++k) {
      walk.frame(k / rate, p);
      e = est.update(k / rate, p);
      ASSERT_TRUE(all_finite(e));
    }
    EXPECT_NEAR(e.belt_speed_mps, walk.belt_mps, 0.05) << rate << " Hz";
    EXPECT_NEAR(e.speed_mps, walk.belt_mps, 0.05) << rate << " Hz";
    EXPECT_GT(e.belt_speed_std_mps, 0.0);
    EXPECT_TRUE(e.valid) << rate << " Hz, reason " << static_cast<int>(e.invalid_reason);
  }
}

// Valid only with a gait phase: with the position noise set far above any motion
// (meas_position_std_m 1e100) the vertical phasor decays to 0, and no frame is valid without a time
// to the next step (MODEL_NOT_HOLDING), on a treadmill with heels and over ground.
TEST(OnlineEstimator, NotValidWithoutAGaitPhase) {
  OnlineConfig config;
  config.meas_position_std_m = 1e100;
  for (const bool treadmill : {true, false}) {
    SyntheticTreadmill walk;
    if (!treadmill) walk.pelvis.speed_mps = walk.belt_mps = 1.2;
    OnlineEstimator est(4, 2, 1.0, config, 2);
    double p[18];
    int valid = 0, without_phase = 0;
    for (int k = 0; k < 2000; ++k) {  // 20 s at 100 Hz
      walk.frame(k / 100.0, p);
      const OnlineEstimate& e = est.update(k / 100.0, p);
      valid += e.valid;
      if (std::isnan(e.next_step_in_s)) {
        ++without_phase;
        EXPECT_FALSE(e.valid) << (treadmill ? "treadmill" : "over ground") << ", frame " << k;
      }
    }
    EXPECT_GT(without_phase, 0) << "the phasor never decayed: the test does not reach its case";
  }
}

// Without feet or a belt speed the same walk is not valid (the pelvis does not travel: NOT_MOVING);
// a known belt speed (set at any time) gives the walking speed.
TEST(OnlineEstimator, TreadmillWithoutFeetIsNotValidAndAKnownBeltServes) {
  SyntheticTreadmill walk;
  OnlineEstimator unknown(4, 2, 1.0), known(4, 2, 1.0);
  known.set_belt_speed_mps(walk.belt_mps);
  EXPECT_EQ(known.belt_speed_mps(), walk.belt_mps);
  EXPECT_TRUE(std::isnan(unknown.belt_speed_mps()));
  double p[18];
  OnlineEstimate a, b;
  for (int k = 0; k < 2000; ++k) {
    walk.frame(k / 100.0, p);
    a = unknown.update(k / 100.0, p);  // the pelvis's 4 points only
    b = known.update(k / 100.0, p);
    if (k > 1000 && a.walking) {
      EXPECT_FALSE(a.valid);
    }
  }
  EXPECT_TRUE(a.invalid_reason & static_cast<std::uint8_t>(InvalidReason::kNotMoving));
  EXPECT_NEAR(b.speed_mps, walk.belt_mps, 0.05);
  EXPECT_EQ(b.belt_speed_mps, walk.belt_mps);
  EXPECT_TRUE(b.valid);
  known.set_belt_speed_mps(kNaN);  // unknown again
  EXPECT_TRUE(std::isnan(known.belt_speed_mps()));
}

// gait_in_place false (a hand followed): bobbing in place is no walking; the same bobs on a belt
// whose speed is known are (the belt's travel counts); the default (a pelvis) walks in place.
TEST(OnlineEstimator, WithoutGaitInPlaceWalkingNeedsTravel) {
  SyntheticTreadmill walk;
  OnlineConfig hand;
  hand.gait_in_place = false;
  OnlineEstimator pelvis(4, 2, 1.0), in_place(4, 2, 1.0, hand), on_belt(4, 2, 1.0, hand);
  on_belt.set_belt_speed_mps(walk.belt_mps);
  double p[18];
  int pelvis_walking = 0, in_place_walking = 0, on_belt_walking = 0;
  for (int k = 0; k < 2000; ++k) {
    walk.frame(k / 100.0, p);
    pelvis_walking += pelvis.update(k / 100.0, p).walking;
    in_place_walking += in_place.update(k / 100.0, p).walking;
    on_belt_walking += on_belt.update(k / 100.0, p).walking;
  }
  EXPECT_GT(pelvis_walking, 1500);
  EXPECT_EQ(in_place_walking, 0);
  EXPECT_GT(on_belt_walking, 1500);
}

// Heels overground (the pelvis travels, stance feet still): every output equals the run without them.
TEST(OnlineEstimator, HeelsOvergroundChangeNothing) {
  SyntheticTreadmill walk;
  walk.pelvis.speed_mps = walk.belt_mps;
  OnlineEstimator without(4, 2, 1.0), with(4, 2, 1.0, OnlineConfig{}, 2);
  double p[18];
  for (int k = 0; k < 2000; ++k) {
    const double t = k / 100.0;
    walk.frame(t, p);
    for (int j = 0; j < 2; ++j) p[12 + 3 * j] += walk.belt_mps * t;  // the belt's travel undone: feet still in stance
    const OnlineEstimate a = without.update(t, p), b = with.update(t, p);
    ASSERT_EQ(a.speed_mps, b.speed_mps);
    ASSERT_EQ(a.vx_mps, b.vx_mps);
    ASSERT_EQ(a.valid, b.valid);
    ASSERT_EQ(b.belt_speed_mps, 0.0);
  }
}

// update() with feet makes no heap allocation; more than 4 feet are refused.
TEST(OnlineEstimator, TreadmillUpdateDoesNotAllocate) {
  EXPECT_THROW(OnlineEstimator(4, 2, 1.0, OnlineConfig{}, 5), std::invalid_argument);
  SyntheticTreadmill walk;
  OnlineEstimator est(4, 2, 1.0, OnlineConfig{}, 2);
  double p[18];
  const long before = g_allocations.load();
  for (int k = 0; k < 3000; ++k) {
    walk.frame(k / 100.0, p);
    if (k % 29 == 0) p[12] = p[13] = p[14] = kNaN;  // a heel missing
    est.update(k / 100.0, p);
    if (k == 1500) est.set_belt_speed_mps(1.0);
  }
  EXPECT_EQ(g_allocations.load(), before);
}

// Step length = speed / step frequency: 1.44 m (1.3 m/s at 0.9 Hz) is no walker's; 0.72 m is.
TEST(Validity, StepsLongerThanAWalkersAreTooLong) {
  EXPECT_TRUE(online::Validity::too_long_steps(0.9, 1.3));
  EXPECT_FALSE(online::Validity::too_long_steps(1.8, 1.3));
}

// A frequency pinned at a bound is no estimate: its std is that of a frequency spread evenly over
// the range, so 2 std from either bound reach past the range's middle (a walker at 1.9 Hz under an
// estimate pinned at 3.5 Hz is within them; 0.5 Hz stopped at 2.5 Hz).
TEST(Validity, APinnedFrequencysTwoStdReachPastTheMiddleOfTheRange) {
  online::Validity::Settings s;
  s.f_min_hz = 0.4;
  s.f_max_hz = 3.5;
  const online::Validity v{s};
  const double mid_hz = 0.5 * (s.f_min_hz + s.f_max_hz), two_std_hz = 2.0 * v.pinned_std_hz();
  EXPECT_LT(s.f_max_hz - two_std_hz, mid_hz);
  EXPECT_GT(s.f_min_hz + two_std_hz, mid_hz);
  EXPECT_LT(s.f_max_hz - two_std_hz, 1.9);
}

// An estimate below the centre's extrema (jitter's at 4 Hz) is below the steps unless the feet's
// steps agree with it; feet that disagree, or none, leave the centre's figure to judge.
TEST(Validity, FeetThatAgreeOverruleTheCentresExtrema) {
  using online::Validity;
  EXPECT_TRUE(Validity::below_steps(1.7, 4.0, 0.0));
  EXPECT_FALSE(Validity::below_steps(1.7, 4.0, 1.75));
  EXPECT_TRUE(Validity::below_steps(1.7, 4.0, 3.5));
  EXPECT_FALSE(Validity::below_steps(1.7, 2.5, 0.0));
}

// The speed a lagging heading takes from v_x (|v_h| - v_x) is in the speed's transient variance.
TEST(Validity, HeadingLagLossIsInTheSpeedVariance) {
  online::Validity v{online::Validity::Settings{}};
  const double speed = 1.3, lag_rad = 0.5, loss = speed * (1.0 - std::cos(lag_rad));
  for (int k = 0; k < 100; ++k) {  // 1 s at 100 Hz, the heading 0.5 rad behind the velocity
    v.frame(0.01);
    v.heading(0.01, speed * std::cos(lag_rad + 0.01 * k), speed * std::sin(lag_rad + 0.01 * k), speed - loss);
  }
  EXPECT_NEAR(std::sqrt(v.transient_var_speed()), loss, 0.02 * loss);
}

// A jump of the speed reported from one source to another (the IMU's pendulum taking over from A0) is
// no transient: after rebase_speed the speed's rate starts from the new value; the same jump without it is one.
TEST(Validity, ASpeedSourceSwitchIsNoTransient) {
  online::Validity rebased{online::Validity::Settings{}}, jumped{online::Validity::Settings{}};
  for (int k = 0; k < 25; ++k) {  // 1 s at the old source's 0.05 m/s
    rebased.sample(0.04, 2.0, 1.8, 0.05, 0.0);
    jumped.sample(0.04, 2.0, 1.8, 0.05, 0.0);
  }
  rebased.rebase_speed(1.0);
  rebased.sample(0.04, 2.0, 1.8, 1.0, 0.0);
  jumped.sample(0.04, 2.0, 1.8, 1.0, 0.0);
  EXPECT_EQ(rebased.transient_var_speed(), 0.0);
  EXPECT_GT(std::sqrt(jumped.transient_var_speed()), 1.0);  // 0.95 m/s in 0.04 s, low-passed over 0.5 s: 1.8 m/s^2
}

// The v_x innovations' mean (a speed the filter has not followed yet) is in the speed's transient variance.
TEST(Validity, InnovationMeanIsInTheSpeedVariance) {
  online::Validity v{online::Validity::Settings{}};
  for (int k = 0; k < 50; ++k) v.sample(0.04, 2.0, 1.8, 1.3, 0.0, -0.3);  // 2 s, v_x 0.3 m/s below the prediction
  EXPECT_NEAR(std::sqrt(v.transient_var_speed()), 0.3, 0.01);
}

// A phase correction that persists (a cadence not followed) widens the f std by 3 x its rate / 2 pi;
// step-to-step jitter (alternating every step) averages out over phase_tau_s.
TEST(Validity, PersistentPhaseCorrectionWidensTheFrequencyStdAndJitterAveragesOut) {
  online::Validity::Settings s;
  s.phase_tau_s = 2.0;
  online::Validity lag{s}, jitter{s};
  const double dt = 0.04, rate = 0.3;  // rad/s: 3 x 0.3 / 2 pi = 0.14 Hz of frequency error (a third corrected)
  for (int k = 0; k < 250; ++k) {      // 10 s, steps of 0.56 s (14 samples)
    lag.sample(dt, 2.0, 1.8, 1.3, rate * dt);
    jitter.sample(dt, 2.0, 1.8, 1.3, ((k / 14) % 2 ? -5.0 : 5.0) * rate * dt);
  }
  const double expected = 3.0 * rate / (2.0 * kPi);
  EXPECT_NEAR(std::sqrt(lag.transient_var_f()), expected, 0.02 * expected);
  // Five times the rate, but alternating: a fraction of the persistent one's.
  EXPECT_LT(std::sqrt(jitter.transient_var_f()), 2.0 * expected);
  online::Validity fast{online::Validity::Settings{}};  // the default 0.5 s (the rates' low-pass)
  for (int k = 0; k < 250; ++k) fast.sample(dt, 2.0, 1.8, 1.3, ((k / 14) % 2 ? -5.0 : 5.0) * rate * dt);
  EXPECT_GT(std::sqrt(fast.transient_var_f()), 2.0 * std::sqrt(jitter.transient_var_f()));
}

// With phase_onset_tau_s (the IMU's), corrections that keep one sign from a change's onset widen the
// f std to most of 3 x their rate / 2 pi within two of its time constants, where phase_tau_s alone
// has not; corrections five times larger that turn both ways sample by sample (noise) do not.
TEST(Validity, OneSignedPhaseCorrectionsWidenTheFrequencyStdWithinTheOnsetTime) {
  online::Validity::Settings s;
  s.phase_tau_s = 1.0;
  s.phase_onset_tau_s = 0.25;
  online::Validity::Settings off = s;
  off.phase_onset_tau_s = 0.0;
  online::Validity onset{s}, noise{s}, without{off};
  const double dt = 0.04, rate = 0.3;
  for (int k = 0; k < 13; ++k) {  // 0.52 s
    onset.sample(dt, 2.0, 1.8, 1.3, rate * dt);
    without.sample(dt, 2.0, 1.8, 1.3, rate * dt);
    noise.sample(dt, 2.0, 1.8, 1.3, (k % 2 ? -5.0 : 5.0) * rate * dt);
  }
  const double expected = 3.0 * rate / (2.0 * kPi);
  EXPECT_GT(std::sqrt(onset.transient_var_f()), 0.8 * expected);
  EXPECT_LT(std::sqrt(without.transient_var_f()), 0.5 * expected);
  EXPECT_LT(std::sqrt(noise.transient_var_f()), 0.2 * expected);
}

// A mean NIS above 2 but below max_nis scales the stds by sqrt(NIS / 2) without invalidating; above it, not valid.
TEST(Validity, ModerateNisScalesTheStdsAndOnlyALargerOneInvalidates) {
  online::Validity::Settings s;
  s.max_nis = 10.0;
  for (const double nis : {8.0, 12.0}) {
    online::Validity v{s};
    for (int k = 0; k < 100; ++k) v.sample(0.04, nis, 1.8, 1.3, 0.0);  // 4 s, the low-pass settled
    online::Validity::Inputs in;
    in.fed = in.walking = true;
    in.acquiring = false;
    in.step_frequency_hz = 1.8;
    const bool not_holding = v.reasons(10.0, in) & static_cast<std::uint8_t>(InvalidReason::kModelNotHolding);
    EXPECT_EQ(not_holding, nis > s.max_nis);
    EXPECT_NEAR(v.std_inflation(), std::sqrt(0.5 * nis), 0.01);
  }
}

// The estimator's input noise per channel: what the velocity shows above the gait's band.
TEST(VelocityNoise, MeasuresWhiteNoiseAboveTheGaitsBandAndNotTheGait) {
  const double dt = 0.04;
  std::mt19937 rng(11);
  std::normal_distribution<double> unit(0.0, 1.0);
  online::VelocityNoise clean, noisy;
  for (int k = 0; k < 2500; ++k) {
    const double t = k * dt;
    const double vx = 1.3 + 0.2 * std::sin(2 * kPi * 1.8 * t) + 0.05 * std::sin(2 * kPi * 3.6 * t);
    const double vz = 0.2 * std::cos(2 * kPi * 1.8 * t);
    clean.update(vx, vz, dt);
    noisy.update(vx + 0.3 * unit(rng), vz + 0.03 * unit(rng), dt);
  }
  ASSERT_TRUE(clean.known());
  // The gait alone (its harmonic at 3.6 Hz the largest part) stays far below the default's 0.05 m/s.
  EXPECT_LT(std::sqrt(clean.vx_var()), 0.02);
  EXPECT_LT(std::sqrt(clean.vz_var()), 0.02);
  // White noise is measured within a third of its variance, per channel.
  EXPECT_NEAR(noisy.vx_var() / (0.3 * 0.3), 1.0, 1.0 / 3.0);
  EXPECT_NEAR(noisy.vz_var() / (0.03 * 0.03), 1.0, 1.0 / 3.0);
  const std::array<double, 2> e = noisy.excess_var(0.05 * 0.05, 0.05 * 0.05);
  EXPECT_GT(e[0], 0.05);    // v_x: 0.09 - 0.0025
  EXPECT_EQ(e[1], 0.0);     // v_z: within the configured noise
}

// A rise and fall of a step's size a step apart is gait; one of a chair's (0.4 m), however brisk, is not.
TEST(GaitEvidence, ChairSizedRisesAreNoSteps) {
  auto run = [](double amplitude_m, double period_s) {
    online::GaitEvidence g{online::GaitEvidence::Settings{}};
    bool any = false;
    for (int k = 0; k <= 1000; ++k) {  // 10 s at 100 Hz
      const double t = 0.01 * k;
      g.update(t, 0.01, 1.0 + 0.5 * amplitude_m * std::cos(2.0 * kPi * t / period_s), 1e-8);
      any |= t > 3.0 && g.gait(t);
    }
    return any;
  };
  EXPECT_TRUE(run(0.04, 0.55));   // walking: 4 cm per step
  EXPECT_TRUE(run(0.14, 0.55));   // the bounciest stylised walk seen
  EXPECT_FALSE(run(0.40, 2.6));   // brisk sit-to-stand repetitions: extrema 1.3 s apart, 0.4 m
}

// The centre rising and falling once per step shows the step frequency; bobs below bob_m show none.
TEST(GaitEvidence, ExtremaShowTheStepFrequency) {
  auto run = [](double amplitude_m, double f_hz) {
    online::GaitEvidence g{online::GaitEvidence::Settings{}};
    double steps_hz = 0.0;
    for (int k = 0; k <= 1000; ++k) {  // 10 s at 100 Hz
      const double t = 0.01 * k;
      g.update(t, 0.01, 1.0 + 0.5 * amplitude_m * std::cos(2.0 * kPi * f_hz * t), 1e-8);
      steps_hz = g.step_frequency_hz(t);
    }
    return steps_hz;
  };
  EXPECT_NEAR(run(0.04, 1.8), 1.8, 0.02);
  EXPECT_NEAR(run(0.03, 0.7), 0.7, 0.02);
  EXPECT_EQ(run(0.005, 1.8), 0.0);  // a 5 mm bob: below bob_m, no extrema
}

// A person standing still with white noise of 2.5 mm on the centre (5 mm on each of four markers,
// its variance given) makes no gait at 25-100 Hz; a 2.4 cm bob under the same noise does.
TEST(GaitEvidence, WhiteNoiseIsNoGaitButAStepUnderItIs) {
  auto seen_share = [](double rate_hz, double bob_m) {
    online::GaitEvidence g{online::GaitEvidence::Settings{}};
    std::mt19937 rng(7);
    std::normal_distribution<double> noise(0.0, 0.0025);
    int seen = 0, n = 0;
    for (int k = 0; k <= static_cast<int>(20.0 * rate_hz); ++k) {  // 20 s
      const double t = k / rate_hz;
      g.update(t, 1.0 / rate_hz, 1.0 + 0.5 * bob_m * std::cos(2.0 * kPi * 1.8 * t) + noise(rng), 0.0025 * 0.0025);
      if (t > 3.0) {
        seen += g.gait(t) ? 1 : 0;
        ++n;
      }
    }
    return static_cast<double>(seen) / n;
  };
  for (double rate_hz : {25.0, 30.0, 60.0, 100.0}) {
    EXPECT_LT(seen_share(rate_hz, 0.0), 0.02) << rate_hz << " Hz";
    EXPECT_GT(seen_share(rate_hz, 0.024), 0.98) << rate_hz << " Hz";
  }
}

// Bobs of keep_bob_m keep gait seen once steps of bob_m have shown it, never start it, and do not
// count in the step frequency.
TEST(GaitEvidence, SmallerBobsKeepGaitButDoNotStartIt) {
  struct Run {
    bool gait_at_end;
    double steps_hz_after_switch;
  };
  // amplitude_m at 1 step/s for 5 s, then small_m at small_hz.
  auto run = [](double amplitude_m, double small_m, double small_hz) {
    online::GaitEvidence g{online::GaitEvidence::Settings{}};
    Run r{false, 0.0};
    double phase = 0.0;
    for (int k = 0; k <= 1200; ++k) {  // 12 s at 100 Hz
      const double t = 0.01 * k;
      const bool before = t < 5.0;
      phase += 2.0 * kPi * 0.01 * (before ? 1.0 : small_hz);
      g.update(t, 0.01, 1.0 + 0.5 * (before ? amplitude_m : small_m) * (std::cos(phase) - 1.0), 1e-8);  // no jump at 5 s
      r.gait_at_end = g.gait(t);
      if (k == 650) r.steps_hz_after_switch = g.step_frequency_hz(t);
    }
    return r;
  };
  EXPECT_TRUE(run(0.03, 0.008, 1.0).gait_at_end);    // 3 cm steps, then 8 mm: still gait
  EXPECT_FALSE(run(0.008, 0.008, 1.0).gait_at_end);  // 8 mm from the start: never gait
  EXPECT_FALSE(run(0.03, 0.002, 1.0).gait_at_end);   // 3 cm, then 2 mm (below keep_bob_m): gait ends
  // 1.5 s after 3 cm steps at 1 Hz turned into 8 mm bobs at 2 Hz: the steps' frequency, not the bobs'.
  EXPECT_NEAR(run(0.03, 0.008, 2.0).steps_hz_after_switch, 1.0, 0.02);
}

namespace {

// The treadmill walk overground: the pelvis travels at the belt's speed and the heels step on the
// floor (stance still, swing forward at about twice the speed); noise_m on every point.
struct SyntheticOvergroundWithFeet {
  SyntheticTreadmill walk;
  explicit SyntheticOvergroundWithFeet(double noise_m, double rate_hz = 100.0) : rate_hz_(rate_hz) {
    walk.pelvis.speed_mps = walk.belt_mps;
    walk.pelvis.noise_m = walk.noise_m = noise_m;
  }
  void frame(double t, double* p) {
    walk.frame(t, p);
    for (int j = 0; j < 2; ++j) p[12 + 3 * j] += walk.belt_mps * t;
  }
  double rate_hz_;
};

}  // namespace

// The feet's step frequency is the walk's, whatever the share of the step each extremum of their
// separation takes (stance 60 %), and a left/right swap of the feet changes no bit of any output.
TEST(OnlineEstimator, FeetShowTheStepFrequencyAndASwapChangesNothing) {
  SyntheticOvergroundWithFeet walk(0.001);
  OnlineEstimator est(4, 2, 1.0, OnlineConfig{}, 2), swapped(4, 2, 1.0, OnlineConfig{}, 2);
  double p[18], q[18];
  for (int k = 0; k < 2000; ++k) {
    const double t = k / 100.0;
    walk.frame(t, p);
    std::copy(p, p + 18, q);
    if ((k / 150) % 2) std::swap_ranges(q + 12, q + 15, q + 15);  // swapped for 1.5 s every 3 s
    const OnlineEstimate a = est.update(t, p), b = swapped.update(t, q);
    ASSERT_EQ(a.step_frequency_hz, b.step_frequency_hz);
    ASSERT_EQ(a.step_frequency_std_hz, b.step_frequency_std_hz);
    ASSERT_EQ(a.valid, b.valid);
    ASSERT_EQ(est.feet_step_frequency_hz(), swapped.feet_step_frequency_hz());
  }
  EXPECT_NEAR(est.feet_step_frequency_hz(), walk.walk.pelvis.f_hz, 0.03);
  OnlineEstimator no_feet(4, 2, 1.0);
  EXPECT_EQ(no_feet.feet_step_frequency_hz(), 0.0);
}

// Markerless-like noise (2 cm on every point, 60 Hz): without feet never valid (INPUT_NOISY); with
// the feet's steps valid for at least half the walking after 3 s, and never confidently wrong (an
// f or speed error above 0.15 while valid and beyond 2 std).
TEST(OnlineEstimator, FeetMakeANoisyCaptureUsable) {
  for (unsigned seed : {1u, 2u, 3u}) {
    SyntheticOvergroundWithFeet walk(0.02, 60.0);
    walk.walk.pelvis.rng.seed(seed);
    walk.walk.rng.seed(seed + 10);
    OnlineEstimator with(4, 2, 1.0, OnlineConfig{}, 2), without(4, 2, 1.0);
    double p[18];
    int after = 0, valid = 0, valid_without = 0, wrong = 0;
    for (int k = 0; k < 20 * 60; ++k) {
      const double t = k / 60.0;
      walk.frame(t, p);
      const OnlineEstimate a = with.update(t, p), b = without.update(t, p);
      ASSERT_TRUE(all_finite(a));
      valid_without += b.valid;
      if (t < 3.0) continue;
      ++after;
      valid += a.valid;
      const double ef = std::fabs(a.step_frequency_hz - walk.walk.pelvis.f_hz);
      const double es = std::fabs(a.speed_mps - walk.walk.belt_mps);
      if (a.valid && ((ef > 0.15 && ef > 2.0 * a.step_frequency_std_hz) || (es > 0.15 && es > 2.0 * a.speed_std_mps)))
        ++wrong;
    }
    EXPECT_EQ(valid_without, 0) << "seed " << seed;
    EXPECT_GE(valid, 0.5 * after) << "seed " << seed;
    EXPECT_EQ(wrong, 0) << "seed " << seed;
  }
}

// A lock that the feet contradict (the pelvis rising and falling twice per step, the feet at the
// walk's steps) is relocked at the feet's cadence, and never valid while off it.
TEST(OnlineEstimator, ALockTheFeetContradictIsNotValid) {
  SyntheticOvergroundWithFeet walk(0.001);
  walk.walk.pelvis.f_hz = 1.5;  // (twice that within the frequency range)
  OnlineEstimator with(4, 2, 1.0, OnlineConfig{}, 2), without(4, 2, 1.0);
  double p[18];
  int off_valid = 0, wrong_lock_valid = 0, relocked = 0;
  for (int k = 0; k < 3000; ++k) {
    const double t = k / 100.0;
    walk.frame(t, p);
    // The pelvis bobs at twice the step frequency: its own, as a lock on it would be.
    for (int j = 0; j < 4; ++j) p[3 * j + 2] += 0.01 * std::cos(2.0 * kPi * 2.0 * walk.walk.pelvis.f_hz * t) -
                                               walk.walk.pelvis.r_m * std::cos(walk.walk.pelvis.theta(t));
    const OnlineEstimate a = with.update(t, p), b = without.update(t, p);
    off_valid += a.valid && std::fabs(a.step_frequency_hz - walk.walk.pelvis.f_hz) > 0.3;
    wrong_lock_valid += b.valid && std::fabs(b.step_frequency_hz - 2.0 * walk.walk.pelvis.f_hz) < 0.1;
    relocked += t > 10.0 && std::fabs(a.step_frequency_hz - walk.walk.pelvis.f_hz) < 0.1;
  }
  EXPECT_GT(wrong_lock_valid, 1000);  // without feet the lock on the pelvis's own rhythm is valid
  EXPECT_EQ(off_valid, 0);
  EXPECT_GT(relocked, 0);
}

// Each maximum of the feet's separation is a step's length: a walker that travels a step per step
// has a carry ratio of about 1, one that stays in place 0.
TEST(FootCadence, TheWalkersTravelOverItsStepLengthsIsAboutOne) {
  for (const double speed_mps : {1.3, 0.0}) {
    online::FootCadence c{online::FootCadence::Settings{}};
    const double f_hz = 1.8, step_m = 1.3 / f_hz;
    for (int k = 0; k < 1000; ++k) {  // 10 s at 100 Hz: |sin| peaks once per step
      const double t = 0.01 * k;
      c.update(t, step_m * std::fabs(std::sin(kPi * f_hz * t)), 1e-6, speed_mps * t, 0.0);
    }
    EXPECT_NEAR(c.step_frequency_hz(10.0), f_hz, 0.01);
    EXPECT_NEAR(c.figure(10.0).carry_ratio, speed_mps > 0.0 ? 1.0 : 0.0, 0.02);
  }
}

// A tracking slip in the feet's first steps (a spurious rise and fall of 0.25 m within 60 ms) delays
// their figure by two steps, not by the four the whole ring holds it; that first figure is within
// the relock tolerance of the cadence (two steps' figure is not four's) and not settled (the std is
// not bounded by it) until the whole ring is steady again.
TEST(FootCadence, AnIrregularStepDelaysTheFigureByTwoStepsNotFour) {
  online::FootCadence c{online::FootCadence::Settings{}};
  const double f_hz = 1.8, step_m = 1.3 / f_hz, slip_s = 0.6;
  double first_s = -1.0, first_hz = 0.0, settled_s = -1.0;
  for (int k = 0; k < 600; ++k) {  // 6 s at 100 Hz
    const double t = 0.01 * k;
    const double slip = t >= slip_s && t < slip_s + 0.06 ? 0.25 : 0.0;
    c.update(t, step_m * std::fabs(std::sin(kPi * f_hz * t)) + slip, 1e-6, 1.3 * t, 0.0);
    if (first_s < 0.0 && c.step_frequency_hz(t) > 0.0) {
      first_s = t;
      first_hz = c.step_frequency_hz(t);
      EXPECT_FALSE(c.settled());
    }
    if (settled_s < 0.0 && c.settled()) settled_s = t;
  }
  EXPECT_GT(first_s, slip_s);
  EXPECT_LT(first_s - slip_s, 3.0 / f_hz);
  EXPECT_NEAR(first_hz, f_hz, online::Validity::kRelockHz);
  EXPECT_GT(settled_s, first_s);
  EXPECT_NEAR(c.step_frequency_hz(6.0), f_hz, 0.01);
}

// Points given as feet under a noisy pelvis (2 cm, 60 Hz) that swing against each other at a rhythm
// of their own (1.2 m apart at 2.4 steps/s while the walker makes 0.67 m steps at 1.8): the walker
// travels 0.5 m per step of theirs, 0.42 of their steps' length: not its feet, no figure, never
// confidently wrong.
TEST(OnlineEstimator, FeetWhoseStepsDoNotCarryTheWalkerAreNotItsFeet) {
  SyntheticOvergroundWithFeet walk(0.02, 60.0);
  OnlineEstimator with(4, 2, 1.0, OnlineConfig{}, 2);
  std::mt19937 rng(5);
  std::normal_distribution<double> noise(0.0, 0.02);
  double p[18];
  int wrong = 0;
  for (int k = 0; k < 20 * 60; ++k) {
    const double t = k / 60.0;
    walk.frame(t, p);
    const double swing_m = 0.6 * std::sin(kPi * 2.4 * t), x_m = walk.walk.belt_mps * t;
    p[12] = x_m + swing_m + noise(rng);  // both about the pelvis, along the walk
    p[15] = x_m - swing_m + noise(rng);
    const OnlineEstimate a = with.update(t, p);
    ASSERT_EQ(with.feet_step_frequency_hz(), 0.0) << "t " << t;
    const double ef = std::fabs(a.step_frequency_hz - walk.walk.pelvis.f_hz);
    wrong += a.valid && ef > 0.15 && ef > 2.0 * a.step_frequency_std_hz;
  }
  EXPECT_EQ(wrong, 0);
}

// Feet whose midpoint is 1 m beside the pelvis (another walker's, at another cadence) are not its
// feet: no figure, and every estimate is the one without them.
TEST(OnlineEstimator, FeetFarFromThePelvisAreNotItsFeet) {
  SyntheticOvergroundWithFeet walk(0.001), other(0.001);
  other.walk.pelvis.f_hz = 2.4;
  OnlineEstimator with(4, 2, 1.0, OnlineConfig{}, 2), without(4, 2, 1.0);
  double p[18], q[18];
  for (int k = 0; k < 2000; ++k) {
    const double t = k / 100.0;
    walk.frame(t, p);
    other.frame(t, q);
    for (int j = 12; j < 18; j += 3) {
      p[j] = q[j];
      p[j + 1] = q[j + 1] + 1.0;
      p[j + 2] = q[j + 2];
    }
    const OnlineEstimate a = with.update(t, p), b = without.update(t, p);
    ASSERT_EQ(with.feet_step_frequency_hz(), 0.0);
    ASSERT_EQ(a.step_frequency_hz, b.step_frequency_hz);
    ASSERT_EQ(a.valid, b.valid);
  }
}

}  // namespace online_tests
