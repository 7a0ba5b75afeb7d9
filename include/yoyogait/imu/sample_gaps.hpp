/// @file imu/sample_gaps.hpp
/// @brief Samples lost in a stream (a wireless link's dropouts): which interval is a gap the
/// front-end bridges, the stream's mean interval, and the angular rate over a gap (docs/imu.md,
/// "Samples lost").
#pragma once

#include <cmath>
#include <cstddef>
#include <limits>

#include "yoyogait/imu/mahony.hpp"
#include "yoyogait/math.hpp"

namespace yoyogait::imu {

/// A gap: an interval longer than kBridgeIntervals mean ones, in a stream that comes sample by
/// sample. One that comes in bursts (a sensor's packets stamped as they arrive: intervals far below
/// the mean between longer ones) is not bridged for kBurstHoldS after its last short interval: its
/// long intervals carry the packet's samples, which the integrals take as they come. Per sample a
/// comparison or two; nothing allocates.
class SampleGaps {
 public:
  /// An interval longer than this many mean ones is a gap.
  static constexpr double kBridgeIntervals = 2.5;
  /// After an interval below half the mean (a burst), this long without bridging [s].
  static constexpr double kBurstHoldS = 2.0;
  /// A bound on the estimator samples one gap stands for (no loop grows with the input).
  static constexpr int kMaxSwallowed = 64;

  void reset() noexcept {
    mean_s_ = 0.0;
    gap_min_s_ = std::numeric_limits<double>::infinity();
    burst_t_s_ = -std::numeric_limits<double>::infinity();
    last_rate_ = {0.0, 0.0, 0.0};
  }

  /// Whether the interval dt_s that ends at t_s (no restart) is a gap.
  bool gap(double t_s, double dt_s) const noexcept { return dt_s > gap_min_s_ && t_s - burst_t_s_ > kBurstHoldS; }

  /// One more interval of the stream, dt_s > 0 at t_s (not a bridged gap's: a lost sample is no
  /// interval of the stream): the mean and the thresholds with it. A stream at its rate leaves them
  /// as they are, at no cost per sample.
  void track(double t_s, double dt_s) noexcept {
    if (std::fabs(dt_s - mean_s_) <= 1e-6 * mean_s_) return;
    if (dt_s < 0.5 * mean_s_) burst_t_s_ = t_s;
    mean_s_ = mean_s_ > 0.0 ? mean_s_ + 0.05 * (dt_s - mean_s_) : dt_s;
    gap_min_s_ = kBridgeIntervals * mean_s_;
  }

  /// The stream's mean interval (low-passed; 0 before the first) [s].
  double mean_s() const noexcept { return mean_s_; }

  /// The angular rate as measured at this sample, for the next gap.
  void note_rate(const double* gyr) noexcept { last_rate_ = {gyr[0], gyr[1], gyr[2]}; }

  /// Over a gap the mean of the two ends' rates (w, the gap's end, in; the mean out) is the unbiased
  /// guess: the pelvis's rate oscillates over the step, and the end's alone turns the estimate by its
  /// value over the whole gap. Off the per-sample path.
  YOYOGAIT_COLD void rate_over_gap(Vec3& w) const noexcept {
    for (std::size_t i = 0; i < 3; ++i) w[i] = 0.5 * (w[i] + last_rate_[i]);
  }

  /// The estimator samples (of sample_time_s) a gap of dt_s swallowed, at most kMaxSwallowed.
  int swallowed(double dt_s, double sample_time_s) const noexcept {
    const double n = std::floor((dt_s - mean_s_) / sample_time_s + 0.5);
    return n > 0.0 ? (n < kMaxSwallowed ? static_cast<int>(n) : kMaxSwallowed) : 0;
  }

 private:
  double mean_s_ = 0.0;
  double gap_min_s_ = std::numeric_limits<double>::infinity();
  double burst_t_s_ = -std::numeric_limits<double>::infinity();
  Vec3 last_rate_{};
};

}  // namespace yoyogait::imu
