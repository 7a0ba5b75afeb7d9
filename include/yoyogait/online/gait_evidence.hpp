/// @file online/gait_evidence.hpp
/// @brief Whether the centre moves as a walker's does: the pelvis rises and falls once per step, so
/// walking shows alternating vertical extrema of the centre, a step apart (docs/online.md, "Walking").
///
/// The estimator's detector (sec. 2.4) says walking on a low-passed speed or RMS of v_z, which a
/// single transient also exceeds: rising from a chair, sitting down, a push. Here the vertical
/// position of the differentiated centre, low-passed over kLowpassTauS, is followed with a hysteresis
/// of bob_m (at least three standard deviations of the noise the low-pass leaves, so that noise does
/// not make extrema): a maximum or a minimum counts once the centre has moved bob_m back from it. Gait
/// is seen while the last two extrema lie within window_s (a rise and a fall: one step of the
/// slowest walker, none of a sit-to-stand at an unhurried pace) and neither rise nor fall before them
/// exceeds max_bob_m (a walker's pelvis moves 2-6 cm per step, 14 cm on the bounciest stylised walks
/// seen; rising from a chair, 0.3-0.45 m: brisk repetitions, as in a chair-stand test, are otherwise
/// extrema a step apart). Once gait is seen the hysteresis is keep_bob_m (at least six standard
/// deviations): a slow or timid walker's bobs shrink below bob_m at the slowest steps. The step
/// frequency the extrema show (step_frequency_hz) is taken from the position as measured, with
/// bob_m and three standard deviations of its noise. No allocation.
#pragma once

#include <array>
#include <cmath>
#include <cstddef>
#include <limits>

#include "yoyogait/online/interval_cache.hpp"

namespace yoyogait::online {

class GaitEvidence {
 public:
  struct Settings {
    double bob_m = 0.01;     ///< the least vertical excursion counted [m]
    double window_s = 2.5;   ///< two extrema within this: gait [s]
    double max_bob_m = 0.25; ///< a larger rise or fall between extrema is no step [m]
    double keep_bob_m = 0.005; ///< once gait is seen, extrema of this much keep it seen [m]
  };

  GaitEvidence() noexcept = default;
  explicit GaitEvidence(const Settings& s) noexcept : s_(s) { reset(); }

  void reset() noexcept {
    have_ = false;
    start_ = Extrema{};
    smooth_ = Extrema{};
    z_lp_m_ = 0.0;
    lowpass_cache_.reset();
    lowpass_ = Lowpass{};
    kept_ = false;
    kept_t_s_ = -std::numeric_limits<double>::infinity();
    m_ = 0;
    last_ = 0;
    steps_hz_ = 0.0;
  }

  /// The centre's vertical position z_m at t_s, dt_s after the last update, and the variance of the
  /// input noise [m^2].
  void update(double t_s, double dt_s, double z_m, double z_var_m2) noexcept {
    if (!have_) {
      start_.hi = start_.lo = smooth_.hi = smooth_.lo = z_lp_m_ = z_m;
      have_ = true;
      return;
    }
    // The step frequency's extrema: of the position as measured, with at least three standard
    // deviations of the noise (compared as squares: no square root unless the noise is the larger).
    const double h2 = 9.0 * z_var_m2;
    const double bob = start_.update(t_s, z_m, h2 > s_.bob_m * s_.bob_m ? std::sqrt(h2) : s_.bob_m);
    if (bob > 0.0) {
      times_[last_ = last_ + 1 < kRing ? last_ + 1 : 0] = t_s;  // the oldest's slot takes the newest
      if (m_ < kRing) ++m_;
      // Once full, the ring spans kSteps intervals: from the slot after the newest (the oldest) to it.
      const double span_s = t_s - times_[last_ + 1 < kRing ? last_ + 1 : 0];
      steps_hz_ = m_ == kRing && span_s > 0.0 ? 0.5 * static_cast<double>(kSteps) / span_s : 0.0;
    }
    // Gait seen: extrema of the position low-passed over kLowpassTauS, with the noise it leaves
    // (white: the share g / (2 - g) of its variance), three standard deviations to start, six to keep.
    if (dt_s > 0.0) {
      lowpass_ = lowpass_cache_.at(dt_s, [](double dt) {
        const double g = 1.0 - std::exp(-dt / kLowpassTauS);
        return Lowpass{g, g / (2.0 - g)};
      });
      z_lp_m_ += lowpass_.gain * (z_m - z_lp_m_);
    }
    const double v = lowpass_.noise_share * z_var_m2;
    const double n2 = (kept_ ? kKeepNoiseSigmas * kKeepNoiseSigmas : 9.0) * v, b = kept_ ? s_.keep_bob_m : s_.bob_m;
    smooth_.update(t_s, z_lp_m_, n2 > b * b ? std::sqrt(n2) : b);
    kept_ = smooth_.seen(t_s, s_);
    kept_t_s_ = t_s;
  }

  /// The step frequency the last kSteps + 1 extrema imply (a rise and a fall per step: kSteps / 2
  /// steps over their span), while the last of them lies within window_s of t_s; 0 otherwise [Hz].
  /// Extrema of bobs below bob_m are not counted, so a slow walker's may be missed (a lower figure),
  /// not made: an estimate far below it is below the steps the centre shows.
  double step_frequency_hz(double t_s) const noexcept {
    return t_s - times_[last_] <= s_.window_s ? steps_hz_ : 0.0;
  }

  /// Whether the last two extrema of the low-passed position lie within window_s of t_s, each reached
  /// by a rise or fall of at most max_bob_m: of bob_m or more, or, while gait has been seen without a
  /// break, of keep_bob_m or more (a slow walker's smaller steps keep it; they do not start it, nor
  /// count in step_frequency_hz).
  bool gait(double t_s) const noexcept { return t_s == kept_t_s_ ? kept_ : smooth_.seen(t_s, s_); }

 private:
  static constexpr std::size_t kN = 2;
  /// Intervals between extrema averaged for step_frequency_hz (two steps), and their ring's size.
  static constexpr std::size_t kSteps = 4, kRing = kSteps + 1;
  /// The keeping hysteresis is at least this many standard deviations of the noise: with three, as to
  /// start, noise that had started gait kept it (before the low-pass, a person standing with 5 mm of
  /// white noise on each marker was walking 76-90 % of the time at 25-100 Hz, 52-80 % without keeping,
  /// 56-80 % with six).
  static constexpr double kKeepNoiseSigmas = 6.0;
  /// The low-pass of the position that gait is seen on [s]: a corner at 4 Hz, a step's bob passes at
  /// 0.9 of its amplitude and 40 ms later, white noise at 0.35-0.68 of its std (100-25 Hz). The same
  /// standing person: walking 0-2 % of the time at 25-100 Hz.
  static constexpr double kLowpassTauS = 0.04;

  /// Extrema of the vertical position with a hysteresis, and the last kN of them.
  struct Extrema {
    int dir = 0;  ///< +1 rising, -1 falling, 0 not yet known
    double hi = 0.0, lo = 0.0;  ///< the extremes since the last turn
    std::array<double, kN> times{};  ///< the times of the last extrema (next: the oldest of a full ring)
    std::array<double, kN> bobs{};   ///< the rise or fall that reached each of them [m]
    std::size_t n = 0, next = 0;
    /// One position; returns the rise or fall that reached a new extremum (0: none).
    double update(double t_s, double z_m, double h_m) noexcept {
      if (z_m > hi) hi = z_m;
      if (z_m < lo) lo = z_m;
      double bob = 0.0;
      if (dir >= 0 && z_m < hi - h_m) {  // a maximum, left downwards (the rise to it: hi - lo)
        if (dir > 0) bob = hi - lo;
        dir = -1;
        lo = z_m;
      } else if (dir <= 0 && z_m > lo + h_m) {  // a minimum, left upwards (the fall to it: hi - lo)
        if (dir < 0) bob = hi - lo;
        dir = 1;
        hi = z_m;
      }
      if (bob > 0.0) {
        times[next] = t_s;
        bobs[next] = bob;
        next = (next + 1) % kN;
        if (n < kN) ++n;
      }
      return bob;
    }
    bool seen(double t_s, const Settings& s) const noexcept {
      return n >= kN && t_s - times[next] <= s.window_s && bobs[0] <= s.max_bob_m && bobs[1] <= s.max_bob_m;
    }
  };

  Settings s_;
  bool have_ = false;
  Extrema start_;         ///< of the position, hysteresis bob_m: the step frequency
  Extrema smooth_;        ///< of the low-passed position, bob_m (keep_bob_m while gait is seen): gait
  double z_lp_m_ = 0.0;  ///< the low-passed position [m]
  /// The low-pass's gain for a frame interval, and the share of a white noise's variance it leaves.
  struct Lowpass {
    double gain = 0.0, noise_share = 0.0;
  };
  IntervalCache<Lowpass> lowpass_cache_;
  Lowpass lowpass_;  ///< the last frame interval's
  bool kept_ = false;     ///< gait seen at the last update, at kept_t_s_ (what gait() gives then)
  double kept_t_s_ = -std::numeric_limits<double>::infinity();
  std::array<double, kRing> times_{};  ///< the times of the last kRing extrema of start_ (last_: the newest)
  std::size_t m_ = 0, last_ = 0;
  double steps_hz_ = 0.0;  ///< the step frequency over the ring's span (0 until it is full) [Hz]
};

}  // namespace yoyogait::online
