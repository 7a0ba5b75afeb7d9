// The lower-back IMU front-end and ImuOnlineEstimator: a synthetic sensor on a Yoyo-model walker
// (tilted, biased), the orientation filter, validity and its reasons, bad input.
#include <gtest/gtest.h>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <limits>
#include <random>
#include <stdexcept>
#include <vector>

#include "yoyogait/imu.hpp"

// Heap allocations counted by the replaced operator new of test_estimator.cpp.
extern std::atomic<long> g_allocations;

namespace imu_tests {  // one per file: the sanitizer build compiles the files as one unit
using namespace yoyogait;

namespace {

constexpr double kPi = 3.14159265358979323846;
constexpr double kG = 9.80665;

// A walker along world x, up z: forward x = v t + r sin(theta), vertical z = r cos(theta). The
// sensor's axes (x up, y right, z forward) are tilted forward by pitch_rad about its right axis and
// turned about its forward axis by roll_rad; its gyro has a bias in every axis.
struct SyntheticImu {
  double f_hz = 1.8, speed_mps = 1.3, r_m = 0.022, pitch_rad = 0.0, roll_rad = 0.0, bias_rad_s = 0.0;
  double noise_mps2 = 0.02, scale = 1.0;
  double stop_s = 1e9, fall_s = 0.6;  // a stop: the steps' amplitude falls to 0 from stop_s over fall_s
  double amplitude(double t) const {
    const double x = (t - stop_s) / fall_s;
    return x <= 0.0 ? 1.0 : x >= 1.0 ? 0.0 : 0.5 + 0.5 * std::cos(kPi * x);
  }
  std::mt19937 rng{3};
  // The pendulum length for which K 2 sqrt(2 l h - h^2) is the step length v / f (h = 2 r, K the default).
  double pendulum_length_m() const {
    const double half = 0.5 * speed_mps / f_hz / ImuConfig{}.step_length_factor, h = 2.0 * r_m;
    return (half * half + h * h) / (2.0 * h);
  }
  // The specific force and angular rate in the sensor frame at t (walking when walk).
  void sample(double t, bool walk, double acc[3], double gyr[3]) {
    const double w = 2.0 * kPi * f_hz, th = w * t;
    const double r = r_m * amplitude(t);
    const double ax = walk ? -r * w * w * std::sin(th) : 0.0, az = walk ? -r * w * w * std::cos(th) : 0.0;
    const double fw[3] = {ax, 0.0, az + kG};  // world (forward, left, up)
    // Sensor axes in the world: x = up, y = right, z = forward, then the tilts.
    const double cp = std::cos(pitch_rad), sp = std::sin(pitch_rad), cr = std::cos(roll_rad), sr = std::sin(roll_rad);
    // Untilted: ex = (0,0,1), ey = (0,-1,0), ez = (1,0,0). Pitch turns ex towards ez about ey.
    double ex[3] = {sp, 0.0, cp}, ez[3] = {cp, 0.0, -sp}, ey[3] = {0.0, -1.0, 0.0};
    // Roll about ez: ex, ey turn.
    double ex2[3], ey2[3];
    for (int i = 0; i < 3; ++i) {
      ex2[i] = cr * ex[i] + sr * ey[i];
      ey2[i] = -sr * ex[i] + cr * ey[i];
    }
    std::normal_distribution<double> n(0.0, noise_mps2);
    acc[0] = scale * (fw[0] * ex2[0] + fw[1] * ex2[1] + fw[2] * ex2[2]) + n(rng);
    acc[1] = scale * (fw[0] * ey2[0] + fw[1] * ey2[1] + fw[2] * ey2[2]) + n(rng);
    acc[2] = scale * (fw[0] * ez[0] + fw[1] * ez[1] + fw[2] * ez[2]) + n(rng);
    for (int i = 0; i < 3; ++i) gyr[i] = bias_rad_s;
  }
};

struct Outcome {
  double f_err_rel = 0.0, speed_err_mps = 0.0, valid_fraction = 0.0;
  ImuEstimate last{};
};

// Walks for duration_s after 2 s standing (the front-end settles at rest; the walk starts abruptly);
// errors: the worst from 5 s of walking on.
Outcome walk(SyntheticImu& s, double duration_s = 20.0, ImuConfig c = ImuConfig{}) {
  c.sensor_height_m = s.pendulum_length_m();
  ImuOnlineEstimator est(c);
  Outcome o;
  int n_after = 0, n_valid = 0;
  const double dt = 0.01;
  for (int k = 0; k * dt < duration_s + 2.0; ++k) {
    const double t = k * dt;
    double a[3], g[3];
    s.sample(t, t >= 2.0, a, g);
    o.last = est.update(t, a, g);
    if (t >= 7.0) {
      ++n_after;
      n_valid += o.last.valid;
      o.f_err_rel = std::fmax(o.f_err_rel, std::fabs(o.last.step_frequency_hz / s.f_hz - 1.0));
      o.speed_err_mps = std::fmax(o.speed_err_mps, std::fabs(o.last.speed_mps - s.speed_mps));
    }
  }
  o.valid_fraction = n_after ? static_cast<double>(n_valid) / n_after : 0.0;
  return o;
}

TEST(Imu, LevelSensorGivesStepFrequencyAndSpeed) {
  // A level sensor: f within 1 %, speed within 0.05 m/s from 5 s of walking on, valid throughout.
  SyntheticImu s;
  const Outcome o = walk(s);
  EXPECT_LT(o.f_err_rel, 0.01);
  EXPECT_LT(o.speed_err_mps, 0.05);
  EXPECT_GT(o.valid_fraction, 0.99);
}

TEST(Imu, TiltAndGyroBiasWithinTargets) {
  // 20 deg of tilt both ways and 1 deg/s of gyro bias on every axis: the same targets.
  SyntheticImu s;
  s.pitch_rad = 20.0 * kPi / 180.0;
  s.roll_rad = -20.0 * kPi / 180.0;
  s.bias_rad_s = 1.0 * kPi / 180.0;
  const Outcome o = walk(s);
  EXPECT_LT(o.f_err_rel, 0.01);
  EXPECT_LT(o.speed_err_mps, 0.05);
}

TEST(Imu, UpsideDownSensorSameCadence) {
  // Half a turn about the forward axis: the orientation filter finds gravity, the cadence stays.
  SyntheticImu s;
  s.roll_rad = kPi;
  const Outcome o = walk(s);
  EXPECT_LT(o.f_err_rel, 0.01);
  EXPECT_LT(o.speed_err_mps, 0.05);
}

TEST(Imu, AtRestIsNeverValid) {
  // A sensor at rest the whole time: never valid, and the speed reported stays near zero.
  SyntheticImu s;
  ImuOnlineEstimator est;
  for (int k = 0; k < 2000; ++k) {
    double a[3], g[3];
    s.sample(k * 0.01, false, a, g);
    const ImuEstimate e = est.update(k * 0.01, a, g);
    ASSERT_FALSE(e.valid) << k;
    ASSERT_TRUE(e.reason == ImuReason::kAcquiring || e.reason == ImuReason::kNotWalking);
    ASSERT_LT(std::fabs(e.speed_mps), 0.3);
  }
}

TEST(Imu, AWalkRatioNoWalkerHasIsNotValid) {
  // 42 steps/min at 1.3 m/s (1.9 m per step: what a lock on the stride reads) is never valid; the
  // same walk with the walk-ratio check off is, so it is that check.
  SyntheticImu s;
  s.f_hz = 0.7;
  s.r_m = 0.1;  // a pendulum of 2.1 m: within sensor_height_m's range
  ImuConfig off;
  off.max_walk_ratio_m_per_spm = 0.0;
  EXPECT_GT(walk(s, 20.0, off).valid_fraction, 0.9);
  const Outcome o = walk(s);
  EXPECT_EQ(o.valid_fraction, 0.0);
  EXPECT_EQ(o.last.reason, ImuReason::kAcquiring);
}

TEST(Imu, ATurnWidensTheFrequencyStdByTheYawRate) {
  // Walking on a circle at 0.5 rad/s: the f std squared grows by (turn_f_std_hz_per_rad_s x 0.5)^2;
  // the estimate itself and its validity do not move.
  ImuConfig on, off;
  off.turn_f_std_hz_per_rad_s = 0.0;
  const double yaw_rad_s = 0.5;
  ImuEstimate e_on{}, e_off{};
  SyntheticImu s_on, s_off;
  on.sensor_height_m = off.sensor_height_m = s_on.pendulum_length_m();
  ImuOnlineEstimator est_on(on), est_off(off);
  for (int k = 0; k < 2000; ++k) {
    const double t = k * 0.01;
    double a[3], g[3], a2[3], g2[3];
    s_on.sample(t, t >= 2.0, a, g);
    s_off.sample(t, t >= 2.0, a2, g2);
    if (t >= 2.0) {  // a level sensor: x is up; the centripetal acceleration points left (-y)
      g[0] += yaw_rad_s;
      g2[0] += yaw_rad_s;
      a[1] -= s_on.speed_mps * yaw_rad_s;
      a2[1] -= s_off.speed_mps * yaw_rad_s;
    }
    e_on = est_on.update(t, a, g);
    e_off = est_off.update(t, a2, g2);
    ASSERT_EQ(e_on.valid, e_off.valid);
    ASSERT_EQ(e_on.step_frequency_hz, e_off.step_frequency_hz);
  }
  ASSERT_TRUE(e_on.valid);
  const double added = std::sqrt(e_on.step_frequency_std_hz * e_on.step_frequency_std_hz -
                                 e_off.step_frequency_std_hz * e_off.step_frequency_std_hz);
  EXPECT_NEAR(added, on.turn_f_std_hz_per_rad_s * yaw_rad_s, 0.1 * on.turn_f_std_hz_per_rad_s * yaw_rad_s);
}

TEST(Imu, GravityInTheWrongUnitIsNotValid) {
  // Accelerations in g, not m/s^2: valid 0 with the reason kGravity while walking.
  SyntheticImu s;
  s.scale = 1.0 / kG;
  const Outcome o = walk(s, 10.0);
  EXPECT_EQ(o.valid_fraction, 0.0);
  EXPECT_EQ(o.last.reason, ImuReason::kGravity);
}

TEST(Imu, SaturationMakesItInvalidForTheHoldTime) {
  // One saturated sample: invalid with kSaturated for saturation_hold_s, valid again after.
  SyntheticImu s;
  ImuConfig c;
  c.sensor_height_m = s.pendulum_length_m();
  ImuOnlineEstimator est(c);
  for (int k = 0; k < 1500; ++k) {
    const double t = k * 0.01;
    double a[3], g[3];
    s.sample(t, t >= 1.0, a, g);
    if (k == 1000) a[0] = 200.0;
    const ImuEstimate e = est.update(t, a, g);
    if (k >= 1000 && t <= 10.0 + c.saturation_hold_s - 0.01) {
      ASSERT_EQ(e.reason, ImuReason::kSaturated) << k;
    }
    if (k == 1400) {
      EXPECT_TRUE(e.valid);
    }
  }
}

TEST(Imu, GapRestartsTheFrontEnd) {
  // A gap longer than max_gap_s: kGap until the front-end settles, and valid again later.
  SyntheticImu s;
  ImuConfig c;
  c.sensor_height_m = s.pendulum_length_m();
  ImuOnlineEstimator est(c);
  bool saw_gap = false;
  ImuEstimate e;
  for (int k = 0; k < 2000; ++k) {
    if (k >= 1000 && k < 1050) continue;
    const double t = k * 0.01;
    double a[3], g[3];
    s.sample(t, t >= 1.0, a, g);
    e = est.update(t, a, g);
    if (k == 1050) {
      EXPECT_EQ(e.reason, ImuReason::kGap);
      saw_gap = true;
    }
  }
  EXPECT_TRUE(saw_gap);
  EXPECT_TRUE(e.valid);
}

TEST(Imu, SamplesLostForLessThanMaxGapAreBridgedWhileWalking) {
  // 0.2 s lost every 4 s (below max_gap_s): no restart; valid on >= 90 % of the samples after 7 s,
  // within 0.1 Hz on 95 % of the valid ones (as the Python test of the SYNTHETIC lab asks) and never
  // confidently wrong (off by more than 0.15 Hz and 2 std).
  SyntheticImu s;
  ImuConfig c;
  c.sensor_height_m = s.pendulum_length_m();
  ImuOnlineEstimator est(c);
  int n_after = 0, n_wrong = 0;
  std::vector<double> f_err_hz;
  for (int k = 0; k < 4000; ++k) {
    const double t = k * 0.01;
    if (t > 6.0 && std::fmod(t - 6.0, 4.0) < 0.2) continue;
    double a[3], g[3];
    s.sample(t, t >= 1.0, a, g);
    const ImuEstimate e = est.update(t, a, g);
    EXPECT_NE(e.reason, ImuReason::kGap);
    if (t < 7.0) continue;
    ++n_after;
    if (!e.valid) continue;
    const double err_hz = std::fabs(e.step_frequency_hz - s.f_hz);
    f_err_hz.push_back(err_hz);
    n_wrong += err_hz > 0.15 && err_hz > 2.0 * e.step_frequency_std_hz;
  }
  EXPECT_GE(static_cast<double>(f_err_hz.size()), 0.9 * n_after);
  std::sort(f_err_hz.begin(), f_err_hz.end());
  EXPECT_LE(f_err_hz[f_err_hz.size() * 95 / 100], 0.1);
  EXPECT_EQ(n_wrong, 0);
}

TEST(Imu, NonFiniteAndRepeatedSamplesAreIgnored) {
  // NaN values and a repeated time are ignored with their reason; the state stays finite.
  SyntheticImu s;
  ImuOnlineEstimator est;
  double a[3], g[3];
  s.sample(0.0, false, a, g);
  est.update(0.0, a, g);
  double bad[3] = {std::numeric_limits<double>::quiet_NaN(), 0.0, 0.0};
  EXPECT_EQ(est.update(0.01, bad, g).reason, ImuReason::kNonFinite);
  EXPECT_EQ(est.update(0.0, a, g).reason, ImuReason::kTimeNotIncreasing);
  const ImuEstimate e = est.update(0.02, a, g);
  EXPECT_TRUE(std::isfinite(e.vz_mps) && std::isfinite(e.speed_mps));
}

TEST(Imu, UpdateAllocatesNothing) {
  // update() makes no heap allocation.
  SyntheticImu s;
  ImuOnlineEstimator est;
  double a[3], g[3];
  const long before = g_allocations.load();
  for (int k = 0; k < 1000; ++k) {
    s.sample(k * 0.01, true, a, g);
    est.update(k * 0.01, a, g);
  }
  EXPECT_EQ(g_allocations.load(), before);
}

TEST(Imu, ConfigIsValidated) {
  // A setting out of range names itself; the constructor throws.
  ImuConfig c;
  c.sensor_height_m = -1.0;
  ASSERT_NE(c.validate(), nullptr);
  EXPECT_NE(std::string(c.validate()).find("imu.sensor_height_m"), std::string::npos);
  EXPECT_THROW(ImuOnlineEstimator{c}, std::invalid_argument);
  EXPECT_EQ(ImuConfig{}.validate(), nullptr);
}

TEST(Imu, MahonyFindsGravityFromAnyStart) {
  // Started from one reading, the filter's up direction is the normalised specific force.
  imu::Mahony m(0.5, 0.0, 0.1);
  for (const imu::Vec3 a : {imu::Vec3{0.0, 0.0, kG}, imu::Vec3{kG, 0.0, 0.0}, imu::Vec3{0.0, 0.0, -kG},
                            imu::Vec3{3.0, -4.0, 8.0}}) {
    m.start(a);
    const imu::Vec3 up = m.up_in_sensor();
    const double n = imu::Mahony::norm(a);
    for (int i = 0; i < 3; ++i) EXPECT_NEAR(up[i], a[i] / n, 1e-12);
  }
}

TEST(Imu, MagnetometerMakesTheHeadingAbsoluteDespiteAGyroBias) {
  // A sensor at rest facing 60 deg from magnetic north, 1 deg/s of bias on every gyro axis: with the
  // field the heading is within 2 deg of 60 deg after 60 s; without it it is relative (0 at the start) and drifts.
  ImuConfig c;
  ImuOnlineEstimator with(c), without(c);
  const double psi = 60.0 * kPi / 180.0, bias = kPi / 180.0;
  // World (north, west, up) field of 20 uT north, 44 uT down; the sensor's axes: x up, y right, z forward
  // with forward at psi: sensor z = (cos psi, sin psi, 0), y (right) = (sin psi, -cos psi, 0), x = up.
  const double bn = 20.0, bu = -44.0;
  const double mag[3] = {bu, bn * std::sin(psi), bn * std::cos(psi)};
  const double acc[3] = {kG, 0.0, 0.0}, gyr[3] = {bias, bias, bias};
  ImuEstimate a{}, b{};
  for (int k = 0; k <= 6000; ++k) {
    a = with.update(0.01 * k, acc, gyr, mag);
    b = without.update(0.01 * k, acc, gyr);
  }
  EXPECT_TRUE(a.heading_absolute);
  EXPECT_FALSE(b.heading_absolute);
  EXPECT_NEAR(std::remainder(a.heading_rad - psi, 2.0 * kPi), 0.0, 2.0 * kPi / 180.0);
  EXPECT_GT(std::fabs(std::remainder(b.heading_rad, 2.0 * kPi)), 20.0 * kPi / 180.0);
}

TEST(Imu, LeakyIntegratorDoesNotDrift) {
  // A constant acceleration bias integrates to nothing; a sine integrates to its integral's amplitude.
  imu::LeakyIntegrator li(1.0);
  li.start(0.3);
  double v = 0.0;
  for (int k = 0; k < 3000; ++k) v = li.step(0.3, 0.01);
  EXPECT_NEAR(v, 0.0, 1e-12);
  const double w = 2.0 * kPi * 2.0;
  li.start(0.0);
  double peak = 0.0;
  for (int k = 0; k < 3000; ++k) {
    v = li.step(std::cos(w * k * 0.01), 0.01);
    if (k > 2000) peak = std::fmax(peak, std::fabs(v));
  }
  EXPECT_NEAR(peak, 1.0 / w, 0.02 / w);
}

}  // namespace

// HarmonicCheck::periodicity: a steady oscillation repeats at its period (r near 1); the same
// oscillation whose newest 1.2 s are still but for a small tremor at another frequency (a pause)
// does not, nor one at another rhythm than the estimate's; too short a history gives -1.
TEST(Imu, PeriodicityTellsAPauseFromSteps) {
  const double dt = 0.04, f = 1.8;
  imu::HarmonicCheck steady, paused, short_history;
  for (int k = 0; k < 200; ++k) {
    const double v = 0.1 * std::cos(2.0 * kPi * f * k * dt);
    steady.update(v, f, false, dt);
    paused.update(k < 200 - 30 ? v : 0.005 * std::sin(2.0 * kPi * 5.3 * k * dt), f, false, dt);
    if (k < 20) short_history.update(v, f, false, dt);
  }
  EXPECT_GT(steady.periodicity(f, dt, 1.5), 0.99);
  EXPECT_LT(paused.periodicity(f, dt, 1.5), 0.2);
  EXPECT_EQ(short_history.periodicity(f, dt, 1.5), -1.0);
  EXPECT_LT(steady.periodicity(1.5 * f, dt, 1.5), 0.2);
}

// A stop within about a step (the steps' amplitude falling to 0 over 0.6 s): while the estimate is
// still valid its speed is within 2 std (or 0.15 m/s) of the inverted pendulum's speed of the steps
// under way; the vertical acceleration shows the stop before the filter's amplitude follows it.
TEST(Imu, AValidSpeedInAStopIsWithinTwoStdOfTheSlowingWalker) {
  for (const double f_hz : {1.2, 1.8, 2.1}) {
    SyntheticImu s;
    s.f_hz = f_hz;
    s.speed_mps = 0.9;
    s.stop_s = 14.0;
    ImuConfig c;
    c.sensor_height_m = s.pendulum_length_m();
    ImuOnlineEstimator est(c);
    int valid_in_stop = 0;
    for (int k = 0; k * 0.01 < 17.0; ++k) {
      const double t = k * 0.01;
      double a[3], g[3];
      s.sample(t, t >= 2.0, a, g);
      const ImuEstimate& e = est.update(t, a, g);
      if (!e.valid || t < s.stop_s) continue;
      ++valid_in_stop;
      const double h = 2.0 * s.r_m * s.amplitude(t), l = c.sensor_height_m;
      const double truth_mps = c.step_length_factor * 2.0 * std::sqrt(std::fmax(0.0, 2.0 * l * h - h * h)) * f_hz;
      const double error = std::fabs(e.speed_mps - truth_mps);
      EXPECT_TRUE(error <= 0.15 || error <= 2.0 * e.speed_std_mps)
          << f_hz << " steps/s, " << t - s.stop_s << " s into the stop: " << e.speed_mps << " +- " << e.speed_std_mps
          << " m/s against " << truth_mps;
    }
    EXPECT_GT(valid_in_stop, 20);  // the stop is seen while the estimate is still valid
  }
}

// Pendulum::speed_rel_var: a quarter of the phasor amplitude's relative variance (v goes as
// sqrt(h), h as |Z|), averaged over excursion_tau_s as h is: large after a lock on an uncertain
// amplitude, falling towards the certain one's over the time constant, cleared with the excursion.
TEST(Imu, PendulumSpeedCarriesTheAmplitudesUncertainty) {
  imu::Pendulum::Settings ps;
  ps.length_m = 0.95;
  ps.step_length_factor = 1.0;
  ps.excursion_tau_s = 0.5;
  ps.max_speed_mps = 3.0;
  imu::Pendulum p(ps);
  GaitState x{};
  x[gait::kW] = 2.0 * kPi * 1.2;
  x[gait::kZ1] = 0.04;  // |Z| 0.05 m/s
  x[gait::kZ2] = 0.03;
  const double dt = 0.04, uncertain_var = 0.025 * 0.025, certain_var = 0.005 * 0.005;
  p.update(x, uncertain_var, true, false, dt);
  EXPECT_NEAR(p.speed_rel_var(), 0.25 * uncertain_var / 0.0025, 1e-12);
  for (int k = 0; k < 25; ++k) p.update(x, certain_var, true, false, dt);  // two time constants
  const double expected = 0.25 * (certain_var + (uncertain_var - certain_var) * std::exp(-25 * dt / 0.5)) / 0.0025;
  EXPECT_NEAR(p.speed_rel_var(), expected, 1e-3 * expected);
  p.update(x, 1.0, true, false, dt);  // an amplitude far below its std: at most 4 (std twice |Z|)
  EXPECT_LE(p.speed_rel_var(), 0.25 * 4.0);
  p.update(x, 0.0, false, false, dt);  // standing: cleared
  EXPECT_EQ(p.speed_rel_var(), 0.0);
}

}  // namespace imu_tests
