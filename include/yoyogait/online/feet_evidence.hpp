/// @file online/feet_evidence.hpp
/// @brief What two foot points in the frames tell the online estimator about its lock (docs/online.md,
/// "Feet"): their separation along the heading, read from each frame where they lie near the point
/// followed; the step frequency it shows (online/foot_cadence.hpp); per estimator sample, whether to
/// relock the estimator at it or to observe it; and the bounds it sets on the frequency's std.
/// A few comparisons per frame; no allocation.
#pragma once

#include <array>
#include <cmath>
#include <cstddef>

#include "yoyogait/online/foot_cadence.hpp"
#include "yoyogait/online/validity.hpp"

namespace yoyogait::online {

class FeetEvidence {
 public:
  /// The farthest a walker's feet's midpoint is from the point followed, horizontally [m]: a trunk point
  /// (the pelvis: at most 0.60 m on the shared recordings, 0.52 m walking), a hand (its arm's reach more).
  static constexpr double kMaxFeetFromTrunkM = 0.75, kMaxFeetFromHandM = 1.5;
  /// The walker's travel per step over the feet's step length (FootCadence::Figure::carry_ratio) of a walker's own
  /// feet: 0.80-1.38 on the shared recordings as captured, 0.57-1.38 re-rendered markerless (a tight
  /// turn's lowest); a rhythm outside it (a tracker's points swinging at their own rhythm, points that
  /// are no feet) is not the walker's steps. Points above the heels (ankles, knees) part less: the
  /// upper bound leaves them room.
  static constexpr double kMinCarry = 0.6, kMaxCarry = 2.0;
  /// The variance of one feet's figure [Hz^2]: its error after 3 s of walking on the markerless
  /// re-renderings, 0.053 Hz median and 0.121 Hz 95th percentile (docs/online.md, "Feet"), as a normal
  /// spread of 0.07 Hz. Observed, it counts kSteps times less: successive figures share kSteps - 1 of
  /// their kSteps intervals.
  static constexpr double kFigureVarHz2 = 0.07 * 0.07;
  static constexpr double kObservedVarHz2 = kFigureVarHz2 * static_cast<double>(FootCadence::kSteps);

  /// What a sample should do with the feet's figure.
  enum class Action { kNone, kRelock, kObserve };

  FeetEvidence() noexcept = default;
  /// n_feet: the foot points in the frames (the first two are used); a, b: the horizontal axes;
  /// length_unit_m, max_abs_m as the frame's; trunk: the point followed is on the trunk (else a hand).
  FeetEvidence(std::size_t n_feet, std::size_t a, std::size_t b, double length_unit_m, double max_abs_m, bool trunk,
               const FootCadence::Settings& s) noexcept
      : cadence_(s), two_(n_feet >= 2), a_(a), b_(b), unit_(length_unit_m), max_abs_m_(max_abs_m),
        reach_m_(trunk ? kMaxFeetFromTrunkM : kMaxFeetFromHandM) {}

  void reset() noexcept {
    cadence_.reset();
    figures_ = 0;
  }
  /// Whether two feet are in the frames.
  bool two() const noexcept { return two_; }

  /// One frame at t_s: the feet (feet_xyz, in the length unit), the point followed (centre_m [m]), the
  /// heading's unit vector on the axes a, b, the centre's noise variance over its n points [m^2], and
  /// the walker's travel on the axes a, b (on a treadmill, relative to the belt) [m].
  /// The separation |(p_0 - p_1) . u| needs no side (a label swap leaves it); feet whose midpoint is
  /// further from the point followed than a walker's (another person's, a tracking swap) are not taken.
  void frame(double t_s, const double* feet_xyz, const std::array<double, 3>& centre_m,
             const std::array<double, 2>& u, double centre_var_m2, std::size_t n_points, double travel_a_m,
             double travel_b_m) noexcept {
    const double* p = feet_xyz;
    const double* q = feet_xyz + 3;
    const double lim = max_abs_m_;
    if (!(std::fabs(p[a_] * unit_) <= lim && std::fabs(p[b_] * unit_) <= lim && std::fabs(q[a_] * unit_) <= lim &&
          std::fabs(q[b_] * unit_) <= lim))
      return;  // NaN (missing) fails the comparisons too
    const double ma = 0.5 * (p[a_] + q[a_]) * unit_ - centre_m[a_], mb = 0.5 * (p[b_] + q[b_]) * unit_ - centre_m[b_];
    if (!(ma * ma + mb * mb <= reach_m_ * reach_m_)) return;
    const double da = (p[a_] - q[a_]) * unit_, db = (p[b_] - q[b_]) * unit_;
    const double var_m2 = 2.0 * static_cast<double>(n_points) * centre_var_m2;
    cadence_.update(t_s, std::fabs(da * u[0] + db * u[1]), var_m2, travel_a_m, travel_b_m);
  }

  /// The feet's step frequency at t_s [Hz] (0: not known, fewer than two feet, or steps that do not
  /// carry the walker: FootCadence::Figure::carry_ratio outside [kMinCarry, kMaxCarry]).
  double step_frequency_hz(double t_s) const noexcept {
    if (!two_) return 0.0;
    const FootCadence::Figure& f = cadence_.figure(t_s);
    return f.carry_ratio >= kMinCarry && f.carry_ratio <= kMaxCarry ? f.hz : 0.0;
  }

  /// After an estimator sample with the estimate (walking, acquiring, f_hz) and the feet's figure
  /// feet_hz: a failed lock off the feet (Validity::failed_lock_off_feet), or the start-up bank
  /// running with the noise above the knee (where it locks on the noise), relocks at the feet's
  /// cadence; else, above the knee, a new figure that agrees with the estimate is observed.
  Action after_sample(bool failed_lock, bool walking, bool acquiring, double f_hz, double feet_hz,
                      bool above_knee) noexcept {
    const bool fresh = cadence_.figures() != figures_;
    figures_ = cadence_.figures();
    if (failed_lock || (walking && acquiring && feet_hz > 0.0 && above_knee)) return Action::kRelock;
    if (fresh && above_knee && walking && !acquiring && !Validity::off_feet(f_hz, feet_hz)) return Action::kObserve;
    return Action::kNone;
  }

  /// The frequency's std [Hz] with the feet's figure feet_hz > 0, walking: 2 std reach the figure, and,
  /// while the estimate f_hz agrees with a settled figure (four steps, the newest steady), reach no
  /// further than Validity::kFeetToleranceHz and the spread of those steps beyond it (the figure's own
  /// error within the one, its lag behind a change of cadence within the other).
  double bounded_std_hz(double std_hz, double f_hz, double feet_hz) const noexcept {
    const double gap_hz = std::fabs(feet_hz - f_hz);
    const double most_std_hz = 0.5 * (gap_hz + Validity::kFeetToleranceHz + cadence_.whole_ring().spread_hz);
    if (cadence_.settled() && !Validity::off_feet(f_hz, feet_hz) && std_hz > most_std_hz) std_hz = most_std_hz;
    return std_hz < 0.5 * gap_hz ? 0.5 * gap_hz : std_hz;
  }

 private:
  FootCadence cadence_;
  unsigned long figures_ = 0;  ///< the figures seen by after_sample so far
  bool two_ = false;
  std::size_t a_ = 0, b_ = 1;
  double unit_ = 1.0, max_abs_m_ = 1e5, reach_m_ = kMaxFeetFromTrunkM;
};

}  // namespace yoyogait::online
