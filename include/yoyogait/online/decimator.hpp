/// @file online/decimator.hpp
/// @brief From the frame rate to the estimator's sample time: the forward and vertical velocity,
/// optionally low-passed (online/lowpass.hpp), averaged over each interval of sample_time_s, with
/// the age of that mean (docs/online.md sec. 1, "Feeding the estimator").
///
/// The mean's weights are the frames' intervals, so it describes the velocity at the weighted mean
/// of the frames' times; its age is the interval's last frame time minus that mean time (the frame
/// time itself when one frame fills the interval: age 0).
#pragma once

#include <array>

#include "yoyogait/online/lowpass.hpp"

namespace yoyogait::online {

/// Interval means of (v_x, v_z). Everything per frame is noexcept and allocation-free.
class Decimator {
 public:
  struct Settings {
    double sample_time_s = 0.04;  ///< the estimator's sample time: the length of an interval [s]
    double antialias_hz = 0.0;    ///< cutoff of the Butterworth low-pass before the mean (0: none) [Hz]
  };

  /// A completed interval.
  struct Mean {
    double vx_mps = 0.0;  ///< the interval-weighted mean of v_x [m/s]
    double vz_mps = 0.0;  ///< ... of v_z [m/s]
    double age_s = 0.0;   ///< the interval's last frame time - the weighted mean time of its frames [s]
    int frames = 0;       ///< the frames averaged
  };

  Decimator() noexcept = default;
  explicit Decimator(const Settings& s) noexcept : s_(s), aa_(s.antialias_hz) { restart(); }

  /// An empty interval; the low-pass starts again at the next frame.
  void restart() noexcept {
    sum_vx_ = sum_vz_ = span_s_ = sum_age_s2_ = 0.0;
    frames_ = 0;
    aa_started_ = false;
  }

  /// One frame at t_s with (vx_mps, vz_mps), dt_s (> 0) after the previous one. True when it
  /// completes an interval (its span plus half a frame reaches sample_time_s): the mean is then in
  /// mean(), and the next frame opens a new interval.
  bool push(double t_s, double vx_mps, double vz_mps, double dt_s) noexcept {
    std::array<double, 2> v{vx_mps, vz_mps};
    if (s_.antialias_hz > 0.0) {
      if (!aa_started_) {
        aa_.start(v);
        aa_started_ = true;
      }
      v = aa_.step(v, dt_s);
    }
    if (span_s_ == 0.0) t_first_s_ = t_s;
    sum_vx_ += v[0] * dt_s;
    sum_vz_ += v[1] * dt_s;
    sum_age_s2_ += (t_s - t_first_s_) * dt_s;
    span_s_ += dt_s;
    ++frames_;
    if (!(span_s_ + 0.5 * dt_s >= s_.sample_time_s * (1.0 - 1e-9))) return false;
    mean_.vx_mps = sum_vx_ / span_s_;
    mean_.vz_mps = sum_vz_ / span_s_;
    mean_.age_s = (t_s - t_first_s_) - sum_age_s2_ / span_s_;
    mean_.frames = frames_;
    sum_vx_ = sum_vz_ = span_s_ = sum_age_s2_ = 0.0;
    frames_ = 0;
    return true;
  }

  /// The last completed interval.
  const Mean& mean() const noexcept { return mean_; }

  /// The low-pass's phase delay at f_hz for the current frame interval (0 without it) [s].
  double antialias_delay_s(double f_hz) const noexcept { return s_.antialias_hz > 0.0 ? aa_.delay_s(f_hz) : 0.0; }

 private:
  Settings s_;
  Lowpass2 aa_;
  bool aa_started_ = false;
  double sum_vx_ = 0.0, sum_vz_ = 0.0;  ///< sums of v dt over the interval [m]
  double span_s_ = 0.0;                 ///< the interval's length so far [s]
  double t_first_s_ = 0.0;              ///< time of the interval's first frame [s]
  double sum_age_s2_ = 0.0;             ///< sum over the interval's frames of (t - t_first) dt [s^2]
  int frames_ = 0;                      ///< frames in the interval so far
  Mean mean_;
};

}  // namespace yoyogait::online
