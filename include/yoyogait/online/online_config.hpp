/// @file online/online_config.hpp
/// @brief OnlineConfig: every setting of the online front-end, in seconds, metres or noise densities.
#pragma once

#include <cmath>

#include "yoyogait/config.hpp"

namespace yoyogait {

/// Settings of OnlineEstimator (docs/online.md), declared once, as the estimator's tables of
/// config.hpp are: X(type, name, default, "unit", lo, min, max, hi, "doc"). None is a number of
/// frames: the front-end behaves the same at any capture rate. The struct, its validation, the
/// bindings, the schema (`_core.config_schema()`, section "online"), the Python OnlineConfig, the
/// `[online]` section of the TOML files and docs/configuration.md follow this table.
#define YOYOGAIT_ONLINE_FIELDS(X)                                                                                   \
  X(double, antialias_hz, 0.0, "Hz", "[", 0.0, 1e100, "]",                                                         \
    "Butterworth low-pass (2nd order) of the forward and vertical velocity before the decimation, delay compensated (0: only the interval mean)") \
  X(double, q_jerk_m2_per_s5, 1000.0, "m^2/s^5", "(", 0.0, 1e100, "]",                                            \
    "white-jerk noise density of the constant-acceleration Kalman differentiator")                                \
  X(double, meas_position_std_m, 0.001, "m", "(", 0.0, 1e100, "]",                                                \
    "noise of the centre's position (marker noise); with adapt_to_noise the least the differentiator is given")   \
  X(bool, adapt_to_noise, true, "", "[", 0, 1, "]",                                                                \
    "the differentiator's position noise and the estimator's velocity noise follow the marker noise estimated online") \
  X(double, noise_tau_s, 1.0, "s", "(", 0.0, 1e100, "]", "low-pass of the marker-noise estimate (input_noise_m)")  \
  X(double, noise_knee_m, 0.005, "m", "(", 0.0, 1e100, "]",                                                        \
    "marker noise above which the front-end adapts to it (a laboratory capture stays below; below it nothing changes): the differentiator's jerk density stays that at the knee (its bandwidth falls as noise^(-1/3)), the noise estimate's first noise_tau_s is bounded by the innovations' share of their predicted variance, the forward speed before the first heading loses the noise's part") \
  X(double, walk_noise_sigmas, 3.0, "", "[", 0.0, 1e100, "]",                                                     \
    "wherever the marker noise is above meas_position_std_m, the walking detector's thresholds are raised by this many standard deviations of what the input noise alone gives its low-passes (0: not raised; at a laboratory's noise, nothing)") \
  X(double, outlier_gate_nis, 25.0, "", "(", 0.0, 1e100, "]",                                                      \
    "a centre whose innovation's NIS (over the three axes) exceeds this is an outlier: not differentiated")       \
  X(double, max_outlier_s, 0.1, "s", "[", 0.0, 1e100, "]",                                                        \
    "outliers for longer than this are taken: the input has moved (a jump, not a swap)")                          \
  X(double, initial_velocity_std_mps, 1.0, "m/s", "(", 0.0, 1e100, "]", "velocity uncertainty after a (re)start") \
  X(double, initial_accel_std_mps2, 10.0, "m/s^2", "(", 0.0, 1e100, "]", "acceleration uncertainty after a (re)start") \
  X(double, settle_s, 0.1, "s", "[", 0.0, 1e100, "]",                                                              \
    "the estimator is fed once the differentiator has run this long after a (re)start")                           \
  X(double, centre_blend_tau_s, 0.3, "s", "(", 0.0, 1e100, "]",                                                    \
    "a step of the centre when the visible markers change is blended out over this")                              \
  X(double, centre_forget_s, 2.0, "s", "(", 0.0, 1e100, "]", "a marker unseen this long leaves the centre's set") \
  X(double, max_abs_position_m, 1e5, "m", "(", 0.0, 1e100, "]", "a coordinate beyond this counts as missing")     \
  X(double, max_gap_s, 0.25, "s", "(", 0.0, 1e100, "]", "no point seen for longer than this restarts the front-end") \
  X(double, gait_bob_m, 0.01, "m", "(", 0.0, 1e100, "]",                                                          \
    "a rise or fall of the centre counted as a step's (at least 3 std of the input noise); walking needs two within gait_window_s") \
  X(double, gait_window_s, 2.5, "s", "(", 0.0, 1e100, "]",                                                         \
    "walking is reported only while the centre's last two vertical extrema lie within this")                    \
  X(double, gait_max_bob_m, 0.25, "m", "(", 0.0, 1e100, "]",                                                      \
    "a rise or fall of the centre larger than this is no step (rising from or sitting on a chair: 0.3-0.45 m; a walker's: 2-6 cm): walking is not reported while one led to its last two extrema") \
  X(double, gait_keep_bob_m, 0.005, "m", "(", 0.0, 1e100, "]",                                                   \
    "once walking is reported, rises and falls of this much (at least 6 std of the noise left on the low-passed position) keep it so (a slow or timid walker's smaller steps; they do not start it, nor count in the centre's step frequency)") \
  X(bool, gait_in_place, true, "", "[", 0, 1, "]",                                                                 \
    "walking may be reported while the followed point stays in place (a treadmill without feet or belt speed, then NOT_MOVING): true for a point on the trunk (the pelvis), whose rise and fall at a step's rhythm is gait; false for a hand or a held object, whose bobs in place are gestures: walking then also needs the point to travel 0.5 m over 2 s (a belt from the feet or given counts). OnlineEstimator.for_recording, estimate --online, live and the ROS 2 node (Markers input) set it false when the point followed is a hand") \
  X(double, heading_tau_s, 0.5, "s", "(", 0.0, 1e100, "]",                                                         \
    "low-pass of the horizontal velocity for the heading (its lag in turns is compensated)")                      \
  X(double, heading_min_speed_mps, 0.1, "m/s", "[", 0.0, 1e100, "]", "below this low-passed speed the heading is held") \
  X(double, latency_f_hz, 2.0, "Hz", "(", 0.0, 1e100, "]", "frequency at which the reported input latency is evaluated") \
  X(double, max_time_jump_s, 60.0, "s", "(", 0.0, 1e100, "]",                                                      \
    "a timestamp further ahead is ignored unless the next two frames follow it (then the front-end restarts)")     \
  X(double, valid_after_s, 1.0, "s", "[", 0.0, 1e100, "]",                                                         \
    "an estimate is valid only after this much walking with the start-up bank collapsed (two time constants of the innovation statistics)") \
  X(double, min_rate_hz, 10.0, "Hz", "[", 0.0, 1e100, "]", "a lower mean frame rate makes the estimates not valid") \
  X(double, phase_std_tau_s, 2.0, "s", "(", 0.0, 1e100, "]",                                                       \
    "low-pass of the estimator's phase corrections in the step frequency's std: a correction that persists over it is a cadence the estimate has not followed yet; step-to-step phase jitter averages out") \
  X(double, max_plausible_speed_mps, 6.0, "m/s", "(", 0.0, 1e100, "]",                                             \
    "input moving faster (low-passed over 0.25 s; or 50 m/s in one frame) is implausible; estimates bounded by it") \
  X(double, max_walking_speed_mps, 3.0, "m/s", "(", 0.0, 1e100, "]",                                              \
    "while walking, a faster front-end horizontal velocity is cut to this unless it lasts longer than a step")      \
  X(double, max_input_noise_m, 0.005, "m", "(", 0.0, 1e100, "]",                                                    \
    "a higher marker noise, estimated from the differentiator's innovations, makes the estimates not valid")      \
  X(double, feet_max_input_noise_m, 0.03, "m", "(", 0.0, 1e100, "]",                                               \
    "with foot points in the frames, while the step frequency their separation shows agrees with the estimate (within 0.2 Hz), a higher marker noise than this makes the estimates not valid (max_input_noise_m: without feet, or while they disagree); the feet's evidence tells a right lock from one on the noise") \
  X(double, max_mean_nis, 10.0, "", "(", 0.0, 1e100, "]",                                                           \
    "the estimator's NIS averaged over about a second above this: the model does not hold (not valid); below it the stds are scaled by sqrt(NIS / 2)") \
  X(double, belt_tau_s, 0.5, "s", "(", 0.0, 1e100, "]",                                                            \
    "treadmill (with foot points): low-pass of the stance feet's velocities, over stance time, for the belt's")    \
  X(double, treadmill_min_belt_mps, 0.2, "m/s", "[", 0.0, 1e100, "]",                                             \
    "treadmill: stance feet slower than this are no belt (overground: nothing changes)")                          \
  X(double, stance_band_m, 0.02, "m", "(", 0.0, 1e100, "]",                                                        \
    "treadmill: a foot point this close to its lowest height is in stance")                                       \
  X(double, treadmill_heading_rad, 0.0, "rad", "[", -1e100, 1e100, "]",                                           \
    "treadmill: the walking direction, atan2(b, a), for a known belt speed without stance feet to tell it") \
  X(double, treadmill_max_pelvis_mps, 0.3, "m/s", "(", 0.0, 1e100, "]",                                          \
    "treadmill: stance feet give a belt only while the pelvis's speed (low-passed over 1 s) is below this and half the belt's")


/// Settings of OnlineEstimator: the gait estimator behind it and YOYOGAIT_ONLINE_FIELDS.
struct OnlineConfig {
  /// The gait estimator behind the front-end. It is fed every estimator.sample_time_s (0.04 s, the
  /// paper's 25 Hz) with the mean of the front-end's velocities over that interval (the
  /// anti-aliasing filter of the decimation).
  EstimatorConfig estimator{};
  YOYOGAIT_ONLINE_FIELDS(YOYOGAIT_CONFIG_MEMBER)

  /// nullptr when usable, else what is wrong, naming the field ("online.field") and its range.
  const char* validate() const noexcept {
    if (const char* e = estimator.validate()) return e;
#define YOYOGAIT_CHECK_ONLINE(...) YOYOGAIT_CHECK_FIELD((*this), "online.", __VA_ARGS__)
    YOYOGAIT_ONLINE_FIELDS(YOYOGAIT_CHECK_ONLINE)
#undef YOYOGAIT_CHECK_ONLINE
    if (estimator.algorithm != Algorithm::kGaitFilter)
      return "the online estimator runs the gait filter (algorithm gait_filter)";
    return nullptr;
  }
};

#define YOYOGAIT_SPEC_ONLINE(...) YOYOGAIT_FIELD_SPEC("online", __VA_ARGS__)
/// Every field of the online table, as kConfigFields lists the estimator's.
inline constexpr FieldSpec kOnlineConfigFields[] = {YOYOGAIT_ONLINE_FIELDS(YOYOGAIT_SPEC_ONLINE)};
#undef YOYOGAIT_SPEC_ONLINE

}  // namespace yoyogait
