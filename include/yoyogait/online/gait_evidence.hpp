/// @file online/gait_evidence.hpp
/// @brief Whether the centre moves as a walker's does: the pelvis rises and falls once per step, so
/// walking shows alternating vertical extrema of the centre, a step apart (docs/online.md, "Walking").
///
/// The estimator's detector (sec. 2.4) says walking on a low-passed speed or RMS of v_z, which a
/// single transient also exceeds: rising from a chair, sitting down, a push. Here the vertical
/// position of the differentiated centre is followed with a hysteresis of bob_m (at least three
/// standard deviations of the input noise, so that noise does not make extrema): a maximum or a minimum
/// counts once the centre has moved bob_m back from it. Gait is seen while the last two extrema lie
/// within window_s (a rise and a fall: one step of the slowest walker, none of a sit-to-stand at
/// an unhurried pace) and neither rise nor fall before them exceeds max_bob_m (a walker's pelvis
/// moves 2-6 cm per step, 14 cm on the bounciest stylised walks seen; rising from a chair, 0.3-0.45
/// m: brisk repetitions, as in a chair-stand test, are otherwise extrema a step apart). No
/// allocation, no division.
#pragma once

#include <array>
#include <cmath>
#include <cstddef>

namespace yoyogait::online {

class GaitEvidence {
 public:
  struct Settings {
    double bob_m = 0.01;     ///< the least vertical excursion counted [m]
    double window_s = 2.5;   ///< two extrema within this: gait [s]
    double max_bob_m = 0.25; ///< a larger rise or fall between extrema is no step [m]
  };

  GaitEvidence() noexcept = default;
  explicit GaitEvidence(const Settings& s) noexcept : s_(s) { reset(); }

  void reset() noexcept {
    dir_ = 0;
    have_ = false;
    n_ = 0;
    next_ = 0;
    m_ = 0;
    last_ = 0;
    steps_hz_ = 0.0;
  }

  /// The centre's vertical position z_m at t_s and the variance of the input noise [m^2].
  void update(double t_s, double z_m, double z_var_m2) noexcept {
    if (!have_) {
      hi_ = lo_ = z_m;
      have_ = true;
      return;
    }
    const double h2 = 9.0 * z_var_m2, b2 = s_.bob_m * s_.bob_m;
    const double h = h2 > b2 ? std::sqrt(h2) : s_.bob_m;
    if (z_m > hi_) hi_ = z_m;
    if (z_m < lo_) lo_ = z_m;
    if (dir_ >= 0 && z_m < hi_ - h) {  // a maximum, left downwards (the rise to it: hi_ - lo_)
      if (dir_ > 0) turn(t_s, hi_ - lo_);
      dir_ = -1;
      lo_ = z_m;
    } else if (dir_ <= 0 && z_m > lo_ + h) {  // a minimum, left upwards (the fall to it: hi_ - lo_)
      if (dir_ < 0) turn(t_s, hi_ - lo_);
      dir_ = 1;
      hi_ = z_m;
    }
  }

  /// The step frequency the last kSteps + 1 extrema imply (a rise and a fall per step: kSteps / 2
  /// steps over their span), while the last of them lies within window_s of t_s; 0 otherwise [Hz].
  /// Extrema of bobs below bob_m are not counted, so a slow walker's may be missed (a lower figure),
  /// not made: an estimate far below it is below the steps the centre shows.
  double step_frequency_hz(double t_s) const noexcept {
    return t_s - times_[last_] <= s_.window_s ? steps_hz_ : 0.0;
  }

  /// Whether the last two extrema lie within window_s of t_s, each reached by a rise or fall of at
  /// most max_bob_m.
  bool gait(double t_s) const noexcept {
    return n_ >= kN && t_s - ring_[next_] <= s_.window_s && bob_[0] <= s_.max_bob_m && bob_[1] <= s_.max_bob_m;
  }

 private:
  static constexpr std::size_t kN = 2;
  /// Intervals between extrema averaged for step_frequency_hz (two steps), and their ring's size.
  static constexpr std::size_t kSteps = 4, kRing = kSteps + 1;
  void turn(double t_s, double bob_m) noexcept {
    ring_[next_] = t_s;
    bob_[next_] = bob_m;
    next_ = (next_ + 1) % kN;
    if (n_ < kN) ++n_;
    last_ = last_ + 1 < kRing ? last_ + 1 : 0;  // the oldest's slot takes the newest
    times_[last_] = t_s;
    if (m_ < kRing) ++m_;
    // Once full, the ring spans kSteps intervals: from the slot after the newest (the oldest) to it.
    const double span_s = t_s - times_[last_ + 1 < kRing ? last_ + 1 : 0];
    steps_hz_ = m_ == kRing && span_s > 0.0 ? 0.5 * static_cast<double>(kSteps) / span_s : 0.0;
  }

  Settings s_;
  int dir_ = 0;  ///< +1 rising, -1 falling, 0 not yet known
  bool have_ = false;
  double hi_ = 0.0, lo_ = 0.0;  ///< the extremes since the last turn
  std::array<double, kN> ring_{};  ///< the times of the last extrema (next_: the oldest of a full ring)
  std::array<double, kN> bob_{};   ///< the rise or fall that reached each of them [m]
  std::size_t n_ = 0, next_ = 0;
  std::array<double, kRing> times_{};  ///< the times of the last kRing extrema (last_: the newest)
  std::size_t m_ = 0, last_ = 0;
  double steps_hz_ = 0.0;  ///< the step frequency over the ring's span (0 until it is full) [Hz]
};

}  // namespace yoyogait::online
