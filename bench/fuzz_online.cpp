// Fuzz of the per-frame paths: OnlineEstimator::update on marker frames and ImuOnlineEstimator::update
// on IMU samples, each case with random settings (any the constructor accepts, up to the bounds of
// their ranges) and random input, checked on every frame for what must never happen.
//
// Usage: fuzz_online [CASES [SEED [markers|imu|both [FIRST_CASE]]]] (default 2000 1 both 0); a single
// case (CASES = FIRST_CASE + 1, the same SEED and paths) is rerun with its walk printed. Build it with
// the sanitizers, which report memory errors and undefined behaviour as they happen:
//   g++ -std=c++17 -O1 -g -fsanitize=address,undefined -fno-sanitize-recover=undefined
//       -ffp-contract=off -I include bench/fuzz_online.cpp -o fuzz_online
//
// A case is a walk (one to forty seconds, 5-500 frames per second, straight or turning) with its
// settings. Half the cases take each setting away from its default with probability 0.15 (to a bound
// of its range, or 1e-3 to 1e3 times the default); half the cases carry corruption on every kind of
// frame (missing points or axes, infinities, 1e300, denormals, jumps of metres, repeated, backward,
// late and non-finite timestamps, resets, a belt speed that is NaN or negative), the others fifty
// times less of it. Realistic cases (default settings, little corruption, 1.2-2.3 steps/s, 0.5-1.8
// m/s) are scored against their truth as well; half of them change as walkers do (a start from
// standing, a change of cadence and speed, a stop: Transients below).
//
// Checked on every frame: every output finite but the standard deviations, which are >= 0 and never
// NaN, and the time to the next step (NaN while no phase is known); a valid estimate has finite
// standard deviations, a speed within the settings' bound (max_plausible_speed_mps, 6 m/s; the IMU's
// max_speed_mps, 3 m/s), a step frequency within their range and a time to the next step; the gait
// phase in [0, 1); predict(h) finite for any h. On the realistic cases, the frames where a valid
// estimate is confidently wrong (an error above 0.15 Hz or 0.15 m/s and above 2 standard deviations,
// against the walk's step frequency and speed at the frame: the step frequency while the steps have
// at least a third of their amplitude, the speed on straight walks, for the IMU the speed the
// inverted pendulum gives at the walk's sensor height, 0.8-1.15 m) are counted, and the share of each
// case's frames must stay within 1 % (a 2-std band leaves rare tails; more is not honest). Exit 1
// when a check fails or a case goes over 1 % (the first 20 failures, the first 10 wrong frames of
// each kind and the first 50 cases over 1 % printed).
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <memory>
#include <random>
#include <stdexcept>
#include <string>
#include <type_traits>
#include <vector>

#include "yoyogait/imu.hpp"
#include "yoyogait/online.hpp"

namespace {

constexpr double kPi = 3.14159265358979323846;
constexpr double kG = 9.80665;

class Random {
 public:
  explicit Random(unsigned long long seed) : rng_(seed) {}
  double uniform(double lo, double hi) { return std::uniform_real_distribution<double>(lo, hi)(rng_); }
  bool chance(double p) { return uniform(0.0, 1.0) < p; }
  // A corruption of probability p, scaled by the case's corruption level.
  bool corrupt(double p) { return uniform(0.0, 1.0) < p * corruption; }
  double normal() { return normal_(rng_); }
  std::size_t below(std::size_t n) { return static_cast<std::size_t>(rng_() % n); }
  double corruption = 1.0;

 private:
  std::mt19937_64 rng_;
  std::normal_distribution<double> normal_{0.0, 1.0};
};

// A setting taken away from its default with probability 0.15, within [lo, hi].
template <class T>
void perturb(Random& r, T& value, double lo, double hi) {
  if (!r.chance(0.15)) return;
  if constexpr (std::is_same_v<T, bool>) {
    value = r.chance(0.5);
  } else if constexpr (std::is_floating_point_v<T>) {
    const double u = r.uniform(0.0, 1.0);
    double x = u < 0.1 ? hi : u < 0.2 ? lo : (value == 0.0 ? u : value * std::pow(10.0, r.uniform(-3.0, 3.0)));
    value = x < lo ? lo : x > hi ? hi : x;
  } else {
    value = static_cast<T>(r.below(static_cast<std::size_t>(hi) + 1));
  }
}

// A frame's time step: mostly 1 / rate, sometimes repeated, backward, late or non-finite.
double next_time(Random& r, double& t_s, double rate_hz) {
  double dt_s = 1.0 / rate_hz;
  if (r.corrupt(0.01)) dt_s = 0.0;
  if (r.corrupt(0.005)) dt_s = -r.uniform(0.0, 1.0);
  if (r.corrupt(0.002)) dt_s = r.uniform(0.3, 100.0);
  if (r.corrupt(0.05)) dt_s *= r.uniform(0.5, 1.5);
  t_s += dt_s;
  if (r.corrupt(0.002)) return std::nan("");
  if (r.corrupt(0.001)) return INFINITY;
  return t_s;
}

void corrupt_value(Random& r, double& v) {
  if (r.corrupt(0.002)) v = INFINITY;
  if (r.corrupt(0.002)) v = 1e300;
  if (r.corrupt(0.002)) v = 5e-324;
}

// 0 -> 1 over [0, 1] as a raised cosine (0 before, 1 after).
double raised_cosine(double x) { return x <= 0.0 ? 0.0 : x >= 1.0 ? 1.0 : 0.5 - 0.5 * std::cos(kPi * x); }

// Half of the realistic walks change as walkers do (drawn from a random stream of their own, so that
// the other cases are those of the version without them): a start from standing (steps at the
// cadence from the first, their amplitude and the speed rising over 0.3-1.5 s), a change of cadence
// (x 0.75-1.3, within 1.0-2.5 steps/s) and of speed (with it, x 0.85-1.15 more) over 0.25-1 s, a
// stop (amplitude and speed falling to 0 over 0.5-1 s, then standing). At walking time tau: the
// step frequency, the speed and the amplitude's share of the steady one.
struct Transients {
  bool on = false;
  double start_s = 0.0, rise_s = 0.0, change_at_s = 1e300, change_s = 1.0, f_ratio = 1.0, v_ratio = 1.0;
  double stop_at_s = 1e300, fall_s = 1.0;
  Transients() = default;
  Transients(Random& tr, bool realistic, double duration_s) {
    on = realistic && tr.chance(0.5);
    if (!on) return;
    if (tr.chance(0.6)) {
      start_s = tr.uniform(0.3, 3.0);
      rise_s = tr.uniform(0.3, 1.5);
    }
    const double walking_from_s = start_s + rise_s;
    if (tr.chance(0.6) && duration_s > walking_from_s + 3.0) {
      change_at_s = tr.uniform(walking_from_s + 2.0, duration_s - 1.0);
      change_s = tr.uniform(0.25, 1.0);
      f_ratio = tr.uniform(0.75, 1.3);
      v_ratio = tr.uniform(0.85, 1.15);
    }
    const double steady_from_s = change_at_s < 1e299 ? change_at_s + change_s + 1.0 : walking_from_s + 3.0;
    if (tr.chance(0.4) && duration_s > steady_from_s + 2.0) {
      stop_at_s = tr.uniform(std::fmax(steady_from_s, duration_s - 4.0), duration_s - 1.5);
      fall_s = tr.uniform(0.5, 1.0);
    }
  }
  double step_frequency_hz(double f_hz, double tau_s) const {
    if (!on) return f_hz;
    const double f2 = std::fmin(2.5, std::fmax(1.0, f_hz * f_ratio));
    return f_hz + (f2 - f_hz) * raised_cosine((tau_s - change_at_s) / change_s);
  }
  // The speed at tau for a walk at speed_mps and f_hz (the speed goes with the cadence's ratio).
  double speed_mps(double speed_mps, double f_hz, double tau_s) const {
    if (!on) return speed_mps;
    const double c = raised_cosine((tau_s - change_at_s) / change_s);
    const double ratio = step_frequency_hz(f_hz, tau_s) / f_hz * (1.0 + (v_ratio - 1.0) * c);
    return speed_mps * ratio * amplitude(tau_s);
  }
  // The IMU walker's amplitude at tau relative to the steady one: the speed's change beyond the
  // cadence's is a change of the excursion (the inverted pendulum's speed is the IMU's truth).
  double step_amplitude(double tau_s) const {
    if (!on) return 1.0;
    return amplitude(tau_s) * (1.0 + (v_ratio - 1.0) * raised_cosine((tau_s - change_at_s) / change_s));
  }
  double amplitude(double tau_s) const {
    if (!on) return 1.0;
    const double up = rise_s > 0.0 ? raised_cosine((tau_s - start_s) / rise_s) : 1.0;
    return up * (1.0 - raised_cosine((tau_s - stop_at_s) / fall_s));
  }
  void describe(const char* path, long c) const {
    if (!on) return;
    std::printf("%s case %ld transients: standing %.2f s, rise %.2f s", path, c, start_s, rise_s);
    if (change_at_s < 1e299)
      std::printf("; change at %.2f s over %.2f s, f x %.3f, v x %.3f", change_at_s, change_s, f_ratio, v_ratio);
    if (stop_at_s < 1e299) std::printf("; stop at %.2f s over %.2f s", stop_at_s, fall_s);
    std::printf("\n");
  }
};

bool confidently_wrong(double estimate, double std, double truth) {
  const double error = std::fabs(estimate - truth);
  return error > 0.15 && error > 2.0 * std;
}

struct Tally {
  long cases = 0, refused = 0, frames = 0, valid = 0, failures = 0;
  long realistic_cases = 0, realistic_valid = 0, wrong_f = 0, wrong_speed = 0;
  long case_wrong = 0, cases_over = 0, worst_case = -1;  // confidently wrong frames of the case; cases over 1 %
  long changing_cases = 0, changing_over = 0;  // the realistic walks that change (Transients), over 1 % of them
  long steady_worst_case = -1;                 // the worst of the walks that do not change
  double steady_worst_share = 0.0;
  double worst_share = 0.0;
  const char* path = "";
  bool describe = false;  // print each case's walk (a single case rerun)
  long case_index = 0, frame = 0;
  double t_s = 0.0;
  // The frame being checked, named in a failure.
  void at(long c, long k, double frame_t_s) {
    case_index = c;
    frame = k;
    t_s = frame_t_s;
  }
  void fail(const std::string& what) {
    if (++failures <= 20) std::printf("FAIL %s case %ld frame %ld t %.9g: %s\n", path, case_index, frame, t_s, what.c_str());
  }
  // A valid estimate confidently wrong: printed (the first ten).
  void wrong(long& count, const char* what, double estimate, double std, double truth) {
    if (++count <= 10)
      std::printf("WRONG %s case %ld frame %ld t %.9g: %s %.3f +- %.3f, truth %.3f\n", path, case_index, frame, t_s, what,
                  estimate, std, truth);
  }
  // A valid estimate of a realistic case against the walk at this frame: its step frequency where
  // score_f, its speed where score_speed (either confidently wrong counts the frame once).
  template <class Estimate>
  void score(const Estimate& e, bool score_f, double f_hz, bool score_speed, double speed_mps) {
    ++realistic_valid;
    const bool bad_f = score_f && confidently_wrong(e.step_frequency_hz, e.step_frequency_std_hz, f_hz);
    const bool bad_speed = score_speed && confidently_wrong(e.speed_mps, e.speed_std_mps, speed_mps);
    if (bad_f) wrong(wrong_f, "f [Hz]", e.step_frequency_hz, e.step_frequency_std_hz, f_hz);
    if (bad_speed) wrong(wrong_speed, "speed [m/s]", e.speed_mps, e.speed_std_mps, speed_mps);
    case_wrong += bad_f || bad_speed;
  }
  // A realistic case's end: the share of its frames that were confidently wrong (the honesty target: at most 1 %).
  void end_case(long frames_n, bool changing) {
    ++realistic_cases;
    changing_cases += changing;
    const double share = frames_n > 0 ? static_cast<double>(case_wrong) / static_cast<double>(frames_n) : 0.0;
    if (share > 0.01) {
      changing_over += changing;
      if (++cases_over <= 50)
        std::printf("OVER %s case %ld%s: %.2f %% of its frames confidently wrong\n", path, case_index,
                    changing ? " (a walk that changes)" : "", 100.0 * share);
    }
    if (share > worst_share) {
      worst_share = share;
      worst_case = case_index;
    }
    if (!changing && share > steady_worst_share) {
      steady_worst_share = share;
      steady_worst_case = case_index;
    }
    case_wrong = 0;
  }
};

// A case's corruption level and whether its settings leave their defaults (drawn in this order).
bool wild_case(Random& r) {
  r.corruption = r.chance(0.5) ? 0.02 : 1.0;
  return r.chance(0.5);
}

// The checks both paths share: the outputs in `finite` finite, the stds never NaN or negative, the
// phase in [0, 1); a valid estimate with finite stds, a speed within max_speed_mps and a step
// frequency within the gait filter's range.
template <class Estimate, std::size_t N>
void check(Tally& tally, const Estimate& e, const double (&finite)[N], const yoyogait::GaitFilterConfig& gf,
           double max_speed_mps) {
  bool ok = true;
  for (double v : finite) ok = ok && std::isfinite(v);
  if (!ok) tally.fail("an output not finite");
  if (!(e.step_frequency_std_hz >= 0.0) || !(e.speed_std_mps >= 0.0)) tally.fail("a std NaN or negative");
  if (!(e.gait_phase >= 0.0 && e.gait_phase < 1.0)) tally.fail("gait phase outside [0, 1)");
  if (!e.valid) return;
  if (!std::isfinite(e.step_frequency_std_hz) || !std::isfinite(e.speed_std_mps)) tally.fail("valid with an infinite std");
  if (!(e.speed_mps >= 0.0 && e.speed_mps <= max_speed_mps)) tally.fail("valid with speed " + std::to_string(e.speed_mps));
  if (!(e.step_frequency_hz >= gf.f_min_hz && e.step_frequency_hz <= gf.f_max_hz))
    tally.fail("valid with a step frequency out of range");
}

void markers_case(long c, Random& r, Random& tr, Tally& tally) {
  using yoyogait::OnlineConfig;
  using yoyogait::OnlineEstimate;
  using yoyogait::OnlineEstimator;
  OnlineConfig config;
  const bool wild = wild_case(r);
  if (wild) {
#define YOYOGAIT_FUZZ_PERTURB(type, name, def, unit, lo_b, lo, hi, hi_b, ...) perturb(r, config.name, lo, hi);
    YOYOGAIT_ONLINE_FIELDS(YOYOGAIT_FUZZ_PERTURB)
#undef YOYOGAIT_FUZZ_PERTURB
    if (r.chance(0.3)) config.estimator.sample_time_s = r.uniform(0.005, 0.2);
  }
  const std::size_t n_points = 1 + r.below(6), n_feet = r.chance(0.4) ? 2 : r.chance(0.1) ? 1 : 0;
  const int up = static_cast<int>(r.below(3)), a = (up + 1) % 3, b = (up + 2) % 3;
  const double unit_m = r.chance(0.5) ? 0.001 : 1.0;
  ++tally.cases;
  std::unique_ptr<OnlineEstimator> est;
  try {
    est = std::make_unique<OnlineEstimator>(n_points, up, unit_m, config, n_feet);
  } catch (const std::invalid_argument&) {
    ++tally.refused;
    return;
  }
  const bool belt_given = r.chance(0.2);
  if (belt_given) est->set_belt_speed_mps(r.chance(0.8) ? r.uniform(0.0, 2.0) : r.chance(0.5) ? std::nan("") : -1.0);
  const bool realistic = !wild && r.corruption < 1.0 && r.chance(0.7);
  const double f_hz = realistic ? r.uniform(1.2, 2.3) : r.uniform(0.3, 3.0);
  const double speed_mps = realistic ? r.uniform(0.5, 1.8) : r.uniform(0.0, 2.5);
  const double r_m = realistic ? r.uniform(0.01, 0.03) : r.uniform(0.0, 0.05);
  const double noise_m = realistic ? r.uniform(0.0, 0.002) : r.chance(0.3) ? r.uniform(0.0, 0.05) : r.uniform(0.0, 0.002);
  const double rate_hz = r.chance(0.1) ? r.uniform(5.0, 30.0) : r.uniform(20.0, 500.0);
  const bool treadmill = r.chance(0.2);
  const double turn_rad_s = r.chance(0.3) ? r.uniform(-1.0, 1.0) : 0.0;
  const long frames = static_cast<long>(r.uniform(1.0, 40.0) * rate_hz);
  const bool scored = realistic && !belt_given && !treadmill;  // a truth to score against
  const Transients walk(tr, realistic, static_cast<double>(frames) / rate_hz);
  if (tally.describe)
    std::printf("markers case %ld: %zu points, %zu feet, %.1f Hz, %ld frames, %.3f steps/s, %.3f m/s, r %.4f m, noise %.4f m, "
                "turn %.2f rad/s, treadmill %d, belt given %d, settings %s, corruption %g\n",
                c, n_points, n_feet, rate_hz, frames, f_hz, speed_mps, r_m, noise_m, turn_rad_s, treadmill, belt_given,
                wild ? "random" : "default", r.corruption);
  if (tally.describe) walk.describe("markers", c);
  double t_s = r.chance(0.05) ? 1e12 : r.uniform(-1e3, 1e3), travel_m = 0.0, heading_rad = r.uniform(-kPi, kPi);
  double last_t_s = t_s, tau_s = 0.0, theta = 0.0;  // walking time and step phase (walks that change)
  std::vector<double> xyz(3 * (n_points + n_feet));
  for (long k = 0; k < frames; ++k) {
    const double frame_t_s = next_time(r, t_s, rate_hz);
    const double dt_s = t_s - last_t_s;
    last_t_s = t_s;
    const double f_now_hz = walk.step_frequency_hz(f_hz, tau_s), v_now_mps = walk.speed_mps(speed_mps, f_hz, tau_s);
    const double amp = walk.amplitude(tau_s);
    if (dt_s > 0.0 && dt_s < 10.0) {
      heading_rad += turn_rad_s * dt_s;
      if (!treadmill) travel_m += v_now_mps * dt_s;
      tau_s += dt_s;
      theta += 2.0 * kPi * f_now_hz * dt_s;
    }
    // The Yoyo-model's pelvis: forward travel plus r sin(theta), vertical r cos(theta).
    const double th = walk.on ? theta : 2.0 * kPi * f_hz * t_s, ch = std::cos(heading_rad), sh = std::sin(heading_rad);
    const double fwd_m = travel_m + r_m * amp * std::sin(th), up_m = 1.0 + r_m * amp * std::cos(th);
    for (std::size_t j = 0; j < n_points; ++j) {
      double* q = &xyz[3 * j];
      const double side_m = 0.05 * static_cast<double>(j);
      q[a] = (fwd_m * ch - side_m * sh + noise_m * r.normal()) / unit_m;
      q[b] = (fwd_m * sh + side_m * ch + noise_m * r.normal()) / unit_m;
      q[up] = (up_m + noise_m * r.normal()) / unit_m;
      if (r.corrupt(0.03)) q[0] = q[1] = q[2] = std::nan("");
      for (int i = 0; i < 3; ++i) corrupt_value(r, q[i]);
      if (r.corrupt(0.005)) q[r.below(3)] += r.uniform(-3.0, 3.0) / unit_m;  // a jump, a swap
    }
    // Heels: stance for 60 % of the stride, still on the ground (on a treadmill: back with the belt,
    // at speed_mps), then a swing forward by a step's length and a half; the two in anti-phase.
    const double stride_s = 2.0 / f_now_hz, stance_m = v_now_mps * 0.6 * stride_s;
    for (std::size_t j = 0; j < n_feet; ++j) {
      double* q = &xyz[3 * (n_points + j)];
      const double strides = walk.on ? theta / (4.0 * kPi) : t_s / stride_s;
      const double s = std::fmod(std::fabs(strides + 0.5 * static_cast<double>(j)), 1.0), w = (s - 0.6) / 0.4;
      const double rel_m = s < 0.6 ? 0.5 * stance_m - v_now_mps * s * stride_s : -0.5 * stance_m + stance_m * w;
      const double ahead_m = travel_m + rel_m, side_m = j ? 0.1 : -0.1;
      q[a] = (ahead_m * ch - side_m * sh + noise_m * r.normal()) / unit_m;
      q[b] = (ahead_m * sh + side_m * ch + noise_m * r.normal()) / unit_m;
      q[up] = (0.05 + (s < 0.6 ? 0.0 : 0.1 * amp * std::sin(kPi * w))) / unit_m;
      if (r.corrupt(0.05)) q[0] = q[1] = q[2] = std::nan("");
      if (r.corrupt(0.002)) q[r.below(3)] = -1e300;
    }
    if (r.corrupt(0.01))
      for (double& q : xyz) q = std::nan("");
    const OnlineEstimate& e = est->update(frame_t_s, xyz.data());
    ++tally.frames;
    tally.valid += e.valid;
    tally.at(c, k, frame_t_s);
    const double finite[] = {e.vx_mps,     e.vz_mps,     e.vh_a_mps,        e.vh_b_mps,       e.heading_rad,
                             e.walk_a_mps, e.walk_b_mps, e.vx_hat_mps,      e.vz_hat_mps,     e.step_frequency_hz,
                             e.speed_mps,  e.gait_phase, e.input_latency_s, e.estimate_age_s, e.input_noise_m,
                             e.belt_speed_mps, e.belt_speed_std_mps};
    check(tally, e, finite, config.estimator.gait_filter, config.max_plausible_speed_mps);
    if (e.valid && std::isnan(e.next_step_in_s)) tally.fail("valid without a time to the next step");
    // The step frequency while there are steps to see (a third of the amplitude), the speed on straight walks.
    if (scored && e.valid) tally.score(e, amp > 0.3, f_now_hz, turn_rad_s == 0.0, v_now_mps);
    if (r.chance(0.01)) {
      const double h_s = r.chance(0.8) ? r.uniform(0.0, 1.0) : r.chance(0.5) ? std::nan("") : -1.0;
      const yoyogait::OnlinePrediction p = est->predict(h_s);
      if (!std::isfinite(p.vx_mps) || !std::isfinite(p.vz_mps) || !(p.vx_std_mps >= 0.0) || !(p.vz_std_mps >= 0.0))
        tally.fail("predict(" + std::to_string(h_s) + ") not finite");
    }
    if (r.corrupt(0.0005)) est->reset();
  }
  if (scored) tally.end_case(frames, walk.on);
}

void imu_case(long c, Random& r, Random& tr, Tally& tally) {
  using yoyogait::ImuConfig;
  using yoyogait::ImuEstimate;
  using yoyogait::ImuOnlineEstimator;
  ImuConfig config;
  const bool wild = wild_case(r);
  if (wild) {
#define YOYOGAIT_FUZZ_PERTURB(type, name, def, unit, lo_b, lo, hi, hi_b, ...) perturb(r, config.name, lo, hi);
    YOYOGAIT_IMU_FIELDS(YOYOGAIT_FUZZ_PERTURB)
#undef YOYOGAIT_FUZZ_PERTURB
  }
  config.forward_axis = 2;  // the walk below has z forward and x up; a wrong axis is in the wild settings' reach
  if (wild && r.chance(0.15)) config.forward_axis = r.below(3);
  const bool realistic = !wild && r.corruption < 1.0 && r.chance(0.7);
  const double f_hz = realistic ? r.uniform(1.2, 2.3) : r.uniform(0.3, 3.0);
  const double r_m = realistic ? r.uniform(0.01, 0.03) : r.uniform(0.0, 0.05);
  const double noise_mps2 = realistic ? r.uniform(0.0, 0.1) : r.chance(0.3) ? r.uniform(0.0, 2.0) : r.uniform(0.0, 0.1);
  const double pitch_rad = r.uniform(-0.35, 0.35), bias_rad_s = r.uniform(-0.0175, 0.0175);
  const double saturation_mps2 = !realistic && r.chance(0.2) ? r.uniform(10.0, 80.0) : 1e9;
  const bool upside_down = !realistic && r.chance(0.1), with_mag = r.chance(0.3);
  const double rate_hz = r.chance(0.1) ? r.uniform(5.0, 40.0) : r.uniform(40.0, 400.0);
  const long samples = static_cast<long>(r.uniform(1.0, 40.0) * rate_hz);
  // A realistic walk's sensor height (a lower back's) and the speed the inverted pendulum gives there:
  // the step length K 2 sqrt(2 l h - h^2) with h = 2 r, times the step frequency.
  const double height_m = realistic ? r.uniform(0.8, 1.15) : config.sensor_height_m, h_m = 2.0 * r_m;
  const double speed_mps = f_hz * config.step_length_factor * 2.0 * std::sqrt(std::fmax(0.0, 2.0 * height_m * h_m - h_m * h_m));
  if (realistic) config.sensor_height_m = height_m;
  const Transients walk(tr, realistic, static_cast<double>(samples) / rate_hz);
  // The inverted pendulum's speed at an amplitude r and a step frequency f (the realistic walks' truth).
  const auto pendulum_mps = [&](double rr_m, double ff_hz) {
    const double hh_m = 2.0 * rr_m;
    return ff_hz * config.step_length_factor * 2.0 * std::sqrt(std::fmax(0.0, 2.0 * height_m * hh_m - hh_m * hh_m));
  };
  ++tally.cases;
  std::unique_ptr<ImuOnlineEstimator> est;
  try {
    est = std::make_unique<ImuOnlineEstimator>(config);
  } catch (const std::invalid_argument&) {
    ++tally.refused;
    return;
  }
  if (tally.describe)
    std::printf("imu case %ld: %.1f Hz, %ld samples, %.3f steps/s, %.3f m/s (sensor height %.2f m), r %.4f m, noise "
                "%.3f m/s^2, pitch %.2f rad, gyro bias %.4f rad/s, saturation %g m/s^2, upside down %d, magnetometer %d, "
                "settings %s, corruption %g\n",
                c, rate_hz, samples, f_hz, speed_mps, height_m, r_m, noise_mps2, pitch_rad, bias_rad_s, saturation_mps2,
                upside_down, with_mag, wild ? "random" : "default", r.corruption);
  if (tally.describe) walk.describe("imu", c);
  double t_s = r.chance(0.05) ? 1e12 : r.uniform(-1e3, 1e3), last_t_s = t_s, tau_s = 0.0, theta = 0.0;
  for (long k = 0; k < samples; ++k) {
    const double sample_t_s = next_time(r, t_s, rate_hz);
    const double dt_s = t_s - last_t_s;
    last_t_s = t_s;
    const double f_now_hz = walk.step_frequency_hz(f_hz, tau_s), r_now_m = r_m * walk.step_amplitude(tau_s);
    const double v_now_mps = walk.on ? pendulum_mps(r_now_m, f_now_hz) : speed_mps;
    if (dt_s > 0.0 && dt_s < 10.0) {
      tau_s += dt_s;
      theta += 2.0 * kPi * f_now_hz * dt_s;
    }
    // The walker's specific force (forward r w^2 sin, vertical r w^2 cos about gravity) in a sensor
    // with x up and z forward, pitched forward (a changing r or w adds terms left out: slow changes).
    const double w = 2.0 * kPi * f_now_hz, th = walk.on ? theta : w * t_s;
    const double fwd = -r_now_m * w * w * std::sin(th), up = kG - r_now_m * w * w * std::cos(th);
    const double cp = std::cos(pitch_rad), sp = std::sin(pitch_rad);
    double acc[3] = {(upside_down ? -1.0 : 1.0) * (fwd * sp + up * cp), 0.0, fwd * cp - up * sp};
    double gyr[3] = {bias_rad_s, 0.1 * std::sin(0.5 * th) + bias_rad_s, bias_rad_s};
    double mag[3] = {20.0, 0.0, 40.0};
    for (int i = 0; i < 3; ++i) {
      acc[i] += noise_mps2 * r.normal();
      gyr[i] += 0.01 * r.normal();
      mag[i] += r.corrupt(0.01) ? 100.0 * r.normal() : r.normal();
      if (r.corrupt(0.002)) acc[i] = std::nan("");
      if (r.corrupt(0.002)) gyr[i] = std::nan("");
      corrupt_value(r, acc[i]);
      corrupt_value(r, gyr[i]);
      acc[i] = std::fmax(-saturation_mps2, std::fmin(saturation_mps2, acc[i]));
    }
    if (r.corrupt(0.003)) acc[0] = acc[1] = acc[2] = gyr[0] = gyr[1] = gyr[2] = 0.0;  // a packet of zeros
    const ImuEstimate& e = with_mag && r.chance(0.9) ? est->update(sample_t_s, acc, gyr, mag) : est->update(sample_t_s, acc, gyr);
    ++tally.frames;
    tally.valid += e.valid;
    tally.at(c, k, sample_t_s);
    const double finite[] = {e.az_mps2,     e.vz_mps,       e.vx_osc_mps,        e.vx_mps,    e.heading_rad,
                             e.tilt_rad,    e.vx_hat_mps,   e.vz_hat_mps,        e.step_frequency_hz,
                             e.speed_mps,   e.excursion_m,  e.step_length_m,     e.pendulum_speed_mps,
                             e.gait_phase,  e.input_latency_s};
    check(tally, e, finite, config.estimator.gait_filter, config.max_speed_mps);
    if (e.valid && std::isnan(e.next_step_in_s)) tally.fail("valid without a time to the next step");
    if (realistic && e.valid) tally.score(e, walk.amplitude(tau_s) > 0.3, f_now_hz, true, v_now_mps);
    if (r.corrupt(0.0005)) est->reset();
  }
  if (realistic) tally.end_case(samples, walk.on);
}

void report(const char* path, const Tally& t) {
  char worst[64] = "0 %", steady[64] = "0 %";
  if (t.worst_case >= 0) std::snprintf(worst, sizeof worst, "%.2f %% (case %ld)", 100.0 * t.worst_share, t.worst_case);
  if (t.steady_worst_case >= 0)
    std::snprintf(steady, sizeof steady, "%.2f %% (case %ld)", 100.0 * t.steady_worst_share, t.steady_worst_case);
  std::printf("| %s | %ld | %ld | %ld | %ld | %ld | %ld (%ld) | %ld | %ld | %ld | %s | %s | %ld (%ld) |\n", path,
              t.cases, t.refused, t.frames, t.valid, t.failures, t.realistic_cases, t.changing_cases,
              t.realistic_valid, t.wrong_f, t.wrong_speed, worst, steady, t.cases_over, t.changing_over);
}

}  // namespace

int main(int argc, char** argv) {
  const long cases = argc > 1 ? std::atol(argv[1]) : 2000;
  const unsigned long long seed = argc > 2 ? std::strtoull(argv[2], nullptr, 10) : 1;
  const std::string which = argc > 3 ? argv[3] : "both";
  if (cases <= 0 || (which != "markers" && which != "imu" && which != "both")) {
    std::fprintf(stderr, "usage: fuzz_online [CASES [SEED [markers|imu|both [FIRST_CASE]]]]\n");
    return 2;
  }
  Tally markers, imu;
  markers.path = "markers";
  imu.path = "imu";
  const long first = argc > 4 ? std::atol(argv[4]) : 0;  // rerun from a case that failed
  markers.describe = imu.describe = cases - first == 1;
  for (long c = first; c < cases; ++c) {
    Random r(seed * 1000003ull + static_cast<unsigned long long>(c));
    Random tr_markers(seed * 1000003ull + static_cast<unsigned long long>(c) + (1ull << 40));
    Random tr_imu(seed * 1000003ull + static_cast<unsigned long long>(c) + (2ull << 40));
    if (which != "imu") markers_case(c, r, tr_markers, markers);
    if (which != "markers") imu_case(c, r, tr_imu, imu);
  }
  std::printf("\n| path | cases | settings refused | frames | valid | failures | realistic cases (that change) | "
              "realistic valid | confidently wrong f | confidently wrong speed | worst case's share | worst of those "
              "that do not change | cases over 1 %% (that change) |\n"
              "|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|\n");
  if (which != "imu") report("markers", markers);
  if (which != "markers") report("imu", imu);
  return markers.failures + imu.failures + markers.cases_over + imu.cases_over > 0 ? 1 : 0;
}
