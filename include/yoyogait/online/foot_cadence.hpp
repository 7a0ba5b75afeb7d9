/// @file online/foot_cadence.hpp
/// @brief The step frequency the feet show: an evidence of the cadence that centimetres of marker
/// noise do not blur (docs/online.md, "Feet").
///
/// The separation of the two feet along the walking direction, |(p_0 - p_1) . u|, is a step length
/// at each double support and 0 when the swinging foot passes the standing one: it rises and falls
/// once per step, by 0.3-0.8 m, against the 2-6 cm the pelvis bobs. Taken as an absolute value it
/// needs no side: a left/right label swap (markerless capture) leaves it as it was. Its extrema are
/// followed with a hysteresis of swing_m (at least kNoiseSigmas standard deviations of the
/// separation's noise); the step frequency is that of the last kSteps intervals between extrema (a
/// maximum and a minimum per step) where no step is shorter than kMinRatio of the longest (a missed
/// or an extra pair of extrema is no rhythm), or, where those are not steady and no such figure is
/// current, of the newest steady span of kMinSteps or more (a start's first steps, the steps after
/// an irregular one); it is held over an unsteady stretch of up to window_s (settled() tells a
/// figure of the whole ring at the newest extremum from the others). Each maximum is the length of
/// the step just made, so the walker's travel between the span's first and last maxima over their
/// steps' lengths (Figure::carry_ratio) is about 1 for the walker's own feet (0.8-1.4 on the shared
/// recordings): a rhythm that does not carry the walker is not its feet'. A few comparisons per
/// frame, a few loops over the ring at an extremum; no allocation.
#pragma once

#include <array>
#include <cmath>
#include <cstddef>

namespace yoyogait::online {

class FootCadence {
 public:
  struct Settings {
    double swing_m = 0.1;    ///< the least rise or fall of the separation counted [m]
    double window_s = 2.5;   ///< the last extremum within this: the frequency is current [s]
  };

  /// Intervals between extrema averaged (four steps; from kMinSteps, two steps, on), and their ring's size.
  static constexpr std::size_t kSteps = 8, kMinSteps = 4, kRing = kSteps + 1;
  /// The hysteresis is at least this many standard deviations of the separation's noise.
  static constexpr double kNoiseSigmas = 4.0;
  /// Every step of the ring at least this fraction of the longest: a steady rhythm (a missed pair
  /// of extrema makes a step of 1.5 or more, an extra pair one of half or less).
  static constexpr double kMinRatio = 0.7;

  FootCadence() noexcept = default;
  explicit FootCadence(const Settings& s) noexcept : s_(s) { reset(); }

  void reset() noexcept {
    dir_ = 0;
    have_ = false;
    hi_ = lo_ = 0.0;
    m_ = 0;
    last_ = 0;
    whole_ = newest_ = Figure{};
    figures_ = 0;
  }

  /// The separation sep_m [m] (>= 0; not finite: the feet not seen, skipped) at t_s, with the
  /// variance of its noise [m^2], and where the walker is on the ground it walks on (travel_a_m,
  /// travel_b_m [m]: horizontal; on a treadmill, relative to the belt).
  void update(double t_s, double sep_m, double noise_var_m2, double travel_a_m, double travel_b_m) noexcept {
    if (!std::isfinite(sep_m)) return;
    if (!have_) {
      hi_ = lo_ = sep_m;
      have_ = true;
      return;
    }
    const double h2 = kNoiseSigmas * kNoiseSigmas * noise_var_m2;
    const double h = h2 > s_.swing_m * s_.swing_m ? std::sqrt(h2) : s_.swing_m;
    if (sep_m > hi_) hi_ = sep_m;
    if (sep_m < lo_) lo_ = sep_m;
    bool turned = false;
    double step_m = 0.0;  // a maximum's separation: the step just made (0 at a minimum)
    if (dir_ >= 0 && sep_m < hi_ - h) {  // a maximum, left downwards
      turned = dir_ > 0;
      step_m = hi_;
      dir_ = -1;
      lo_ = sep_m;
    } else if (dir_ <= 0 && sep_m > lo_ + h) {  // a minimum, left upwards
      turned = dir_ < 0;
      dir_ = 1;
      hi_ = sep_m;
    }
    if (!turned) return;
    times_[last_ = last_ + 1 < kRing ? last_ + 1 : 0] = t_s;  // the oldest's slot takes the newest
    steps_m_[last_] = step_m;
    travel_m_[last_] = {travel_a_m, travel_b_m};
    if (m_ < kRing) ++m_;
    // The newest intervals (all kept, up to kSteps; else fewer, down to kMinSteps), oldest to newest;
    // each step is two successive intervals (a maximum and a minimum: their shares of the step
    // differ with the gait), and the steps are within kMinRatio of each other. The newest steady
    // span gives a figure: an irregular step (a start's first, a stumble, a tracking slip) keeps
    // one away for two steps, not four. A figure of the whole ring is kept beside it and preferred
    // while current (two steps' figure varies by 0.1-0.2 Hz in a turn).
    for (std::size_t n = m_ - 1; n >= kMinSteps; --n) {
      const std::size_t first = (last_ + kRing - n) % kRing;
      double short_step = 1e300, long_step = 0.0;
      for (std::size_t i = 0; i + 2 <= n; ++i) {
        const double d = times_[(first + i + 2) % kRing] - times_[(first + i) % kRing];
        if (d < short_step) short_step = d;
        if (d > long_step) long_step = d;
      }
      const double span_s = t_s - times_[first];
      if (span_s > 0.0 && short_step >= kMinRatio * long_step) {
        // A new figure in use (figures()): the whole ring's, or a shorter span's where none is current.
        if (n == kSteps || !(t_s - whole_.t_s <= s_.window_s)) ++figures_;
        newest_ = {0.5 * static_cast<double>(n) / span_s, t_s, 1.0 / short_step - 1.0 / long_step, carried(first, n)};
        if (n == kSteps) whole_ = newest_;
        return;
      }
    }
  }

  /// A steady span's figure.
  struct Figure {
    double hz = 0.0;       ///< the step frequency: the span's intervals / 2 steps over its duration [Hz]
    double t_s = -1e300;   ///< the time of its newest extremum [s]
    /// The fastest step's frequency less the slowest's [Hz] (a walk that changes its cadence, turns,
    /// stops: the figure lags it by up to this).
    double spread_hz = 0.0;
    /// The walker's travel per step over the steps' mean length (between the span's first and last
    /// maxima, over the maxima after the first): about 1 for the walker's own feet; 0 while not known
    /// (fewer than two maxima, or no length).
    double carry_ratio = 0.0;
  };
  /// The figure at t_s: the whole ring's while it and the last extremum lie within window_s of t_s,
  /// else the newest steady span's while they do; none (hz 0) otherwise.
  const Figure& figure(double t_s) const noexcept {
    if (!(t_s - times_[last_] <= s_.window_s)) return none_;
    if (t_s - whole_.t_s <= s_.window_s) return whole_;
    return t_s - newest_.t_s <= s_.window_s ? newest_ : none_;
  }
  /// The step frequency of figure(t_s) [Hz] (0: none).
  double step_frequency_hz(double t_s) const noexcept { return figure(t_s).hz; }
  /// Whether the figure is of a full ring (kSteps intervals) that is the newest: no unsteady
  /// extremum since. Only then is it taken as within Validity::kFeetToleranceHz of the cadence.
  bool settled() const noexcept { return whole_.t_s == times_[last_]; }
  /// The last steady figure of the whole ring (hz 0: none yet).
  const Figure& whole_ring() const noexcept { return whole_; }
  /// Figures since the reset (one more per steady figure that figure() gives from then on: a caller
  /// tells a new figure by it).
  unsigned long figures() const noexcept { return figures_; }
 private:
  /// The travel per step over the mean step length of the ring of n intervals from slot first.
  double carried(std::size_t first, std::size_t n) const noexcept {
    std::size_t first_max = kRing, last_max = kRing, maxima = 0;
    double length_m = 0.0;
    for (std::size_t i = 0; i <= n; ++i) {
      const std::size_t k = (first + i) % kRing;
      if (!(steps_m_[k] > 0.0)) continue;
      if (first_max == kRing)
        first_max = k;
      else
        length_m += steps_m_[k];
      last_max = k;
      ++maxima;
    }
    if (maxima < 2 || !(length_m > 0.0)) return 0.0;
    const double da = travel_m_[last_max][0] - travel_m_[first_max][0];
    const double db = travel_m_[last_max][1] - travel_m_[first_max][1];
    return std::sqrt(da * da + db * db) / length_m;
  }

  Settings s_;
  int dir_ = 0;  ///< +1 rising, -1 falling, 0 not yet known
  bool have_ = false;
  double hi_ = 0.0, lo_ = 0.0;  ///< the extremes since the last turn [m]
  std::array<double, kRing> times_{};  ///< the times of the last kRing extrema (last_: the newest)
  std::array<double, kRing> steps_m_{};  ///< their separations if maxima (a step's length), else 0 [m]
  std::array<std::array<double, 2>, kRing> travel_m_{};  ///< where the walker was at each [m]
  std::size_t m_ = 0, last_ = 0;
  Figure whole_;   ///< the last steady figure of the whole ring (kSteps intervals)
  Figure newest_;  ///< the last steady figure of any span (kMinSteps to kSteps intervals)
  Figure none_;    ///< no figure (hz 0)
  unsigned long figures_ = 0;  ///< figures in use since the reset (figures())
};

}  // namespace yoyogait::online
