/// @file online/belt.hpp
/// @brief The treadmill belt's velocity, causally, from the feet in stance, or given (docs/online.md,
/// "Treadmills").
///
/// On a treadmill the pelvis stays in place: its velocity holds the body's sway, not the walking
/// speed. A foot in stance stands on the belt and moves back with it, where overground it stands
/// still. So the belt's velocity is the stance feet's: a foot is in stance while it is within
/// stance_band_m of its lowest height (a running minimum that forgets upwards slowly), and the belt's
/// velocity is the running median of the feet's horizontal velocities (frame to frame) over the
/// stance frames, over about belt_tau_s of stance time (the median: the frames where the heel lands
/// or lifts, moving on the belt, count no more than the others). The walking
/// velocity is then the pelvis's less the belt's (online_estimator.hpp). Below treadmill_min_belt_mps,
/// or while the pelvis travels (its horizontal velocity low-passed over 1 s above
/// treadmill_max_pelvis_mps or half the belt's), no belt is taken: overground nothing changes. A known belt speed
/// (set_known_mps) replaces the estimate's length; the direction is the estimate's while there is
/// one, else opposite to treadmill_heading_rad. A few comparisons and one division per frame; no allocation.
#pragma once

#include <array>
#include <cmath>
#include <cstddef>

#include "yoyogait/math.hpp"
#include "yoyogait/online/interval_cache.hpp"

namespace yoyogait::online {

/// The belt's horizontal velocity (its stance feet's), from foot points, or a known speed.
class BeltTracker {
 public:
  struct Settings {
    double tau_s = 0.5;            ///< low-pass of the stance velocities, over stance time [s]
    double min_belt_mps = 0.2;     ///< an estimated belt slower than this is no belt (overground) [m/s]
    double stance_band_m = 0.02;   ///< a foot this close to its lowest height is in stance [m]
    double heading_rad = 0.0;      ///< the walking direction, atan2(b, a), for a known speed without estimate
    double max_belt_mps = 6.0;     ///< a stance velocity beyond this is no belt (a jump, a swap) [m/s]
    double max_pelvis_mps = 0.3;   ///< the belt is taken only while the pelvis's low-passed speed is below this [m/s]
  };

  /// Feet at most (the frame's last points).
  static constexpr std::size_t kMaxFeet = 4;
  /// The lowest height rises by this while a foot is higher (a floor that changes level) [m/s].
  static constexpr double kLowRiseMps = 0.01;
  /// The estimate counts once this much stance time has been averaged [s] (a fraction of tau).
  static constexpr double kMinMeasuredFraction = 0.5;
  /// The deviation the median starts with (its first steps) [m/s]; the stance time over which the
  /// velocities are taken as correlated, for the std [s].
  static constexpr double kDev0Mps = 0.5, kIndependentS = 0.1;
  /// The low-pass of the pelvis's horizontal velocity (over a few steps: the oscillation out) [s];
  /// the pelvis stays while its speed is below this fraction of the belt's too.
  static constexpr double kPelvisTauS = 1.0, kPelvisFraction = 0.5;
  /// Below this low-passed speed the pelvis's direction tells nothing (a treadmill's sway) [m/s].
  static constexpr double kPelvisStillMps = 0.1;
  /// A foot whose height changes faster than this is landing or lifting, not in stance [m/s].
  static constexpr double kMaxStanceVzMps = 0.3;

  BeltTracker() noexcept = default;
  /// n_feet: 0..kMaxFeet; axes: the up axis and the horizontal ones (a, b); length_unit_m, max_abs_m
  /// as the frame's.
  BeltTracker(std::size_t n_feet, std::size_t up, std::size_t a, std::size_t b, double length_unit_m,
              double max_abs_m, const Settings& s) noexcept
      : s_(s), n_(n_feet > kMaxFeet ? kMaxFeet : n_feet), up_(up), a_(a), b_(b), unit_(length_unit_m),
        max_abs_m_(max_abs_m), ua0_(-std::cos(s.heading_rad)), ub0_(-std::sin(s.heading_rad)) {
    reset();
  }

  /// Back to no estimate (a known speed is kept: it is an input, not a state).
  void reset() noexcept {
    for (Foot& f : feet_) f = Foot{};
    va_ = vb_ = measured_s_ = 0.0;
    dev_a_ = dev_b_ = kDev0Mps;
    pelvis_a_ = pelvis_b_ = 0.0;
    have_t_ = false;
    refresh();
  }

  /// A known belt speed [m/s] (>= 0); NaN or negative: unknown again (the feet's estimate, if any).
  void set_known_mps(double speed_mps) noexcept {
    known_mps_ = speed_mps >= 0.0 && speed_mps <= 1e3 ? speed_mps : -1.0;
    refresh();
  }
  /// The known belt speed, NaN when none is given.
  double known_mps() const noexcept { return known_mps_ >= 0.0 ? known_mps_ : std::nan(""); }
  bool has_feet() const noexcept { return n_ > 0; }

  /// The feet of one frame at t_s: n_feet x 3 coordinates in the length unit (NaN: missing).
  void update(double t_s, const double* feet_xyz) noexcept {
    const double dt_s = have_t_ ? t_s - t_s_ : 0.0;
    have_t_ = true;
    t_s_ = t_s;
    if (!(dt_s > 0.0)) {
      for (std::size_t j = 0; j < n_; ++j) feet_[j].prev = false;
      return;
    }
    // Over the first tau of stance time the step shrinks as 1 / the time measured (a mean's start):
    // the first stance gives the belt at once. After it the gains change only with the frame interval.
    if (dt_s != gains_dt_s_ || measured_s_ < s_.tau_s) {
      const double span_s = measured_s_ < s_.tau_s ? measured_s_ : s_.tau_s;
      gains_dt_s_ = dt_s;
      g_ = dt_s / (span_s + dt_s);
      inv_dt_ = 1.0 / dt_s;
    }
    const double g = g_, inv_dt = inv_dt_;
    for (std::size_t j = 0; j < n_; ++j) {
      Foot& f = feet_[j];
      const double* p = feet_xyz + 3 * j;
      const double h = p[up_] * unit_, pa = p[a_] * unit_, pb = p[b_] * unit_;
      const bool seen = std::fabs(h) <= max_abs_m_ && std::fabs(pa) <= max_abs_m_ && std::fabs(pb) <= max_abs_m_ &&
                        !(h == 0.0 && pa == 0.0 && pb == 0.0);
      if (!seen) {
        f.prev = false;
        continue;
      }
      if (!f.have_low || h < f.low_m) {
        f.low_m = h;
        f.have_low = true;
      } else {
        f.low_m += kLowRiseMps * dt_s;
      }
      const bool stance = h <= f.low_m + s_.stance_band_m;
      // A foot in stance keeps its height: one that lands or lifts within the band is not (yet) on the belt.
      if (stance && f.prev && std::fabs(h - f.h_m) <= kMaxStanceVzMps * dt_s)
        measure((pa - f.a_m) * inv_dt, (pb - f.b_m) * inv_dt, g, dt_s);
      f.prev = stance;  // the next frame's velocity needs this one in stance too
      f.a_m = pa;
      f.b_m = pb;
      f.h_m = h;
    }
  }

  /// The pelvis's horizontal velocity in the lab (before the belt's is taken out), dt_s after the
  /// previous one: a treadmill keeps the pelvis in place, overground walking does not (the offline
  /// check's condition: stance feet that seem to move while the pelvis travels are no belt). The
  /// belt in use is updated here, once per frame with a centre (after update()).
  void pelvis(double va_mps, double vb_mps, double dt_s) noexcept {
    if (!(dt_s > 0.0)) return;
    // One division per new frame interval.
    const double g = pelvis_g_.at(dt_s, [](double dt) { return dt / (kPelvisTauS + dt); });
    pelvis_a_ += g * (va_mps - pelvis_a_);
    pelvis_b_ += g * (vb_mps - pelvis_b_);
    refresh();
  }

  // What is in use, kept from the last change of the state (the frame's cost without feet: loads).
  /// Whether a belt is taken: a known speed, or an estimate at least min_belt_mps.
  bool active() const noexcept { return active_; }
  /// The belt's horizontal velocity on the axes a, b (backwards: the stance feet's) [m/s]; 0 when not active.
  double va_mps() const noexcept { return use_a_; }
  double vb_mps() const noexcept { return use_b_; }
  /// The belt speed in use [m/s] (0 when not active).
  double speed_mps() const noexcept { return use_speed_; }
  /// Its standard deviation [m/s]: 0 when known; estimated: the spread of the stance velocities
  /// (1.25 x their mean absolute deviation) over the sqrt of the independent ones averaged (one per
  /// kIndependentS of stance over tau).
  double std_mps() const noexcept { return use_std_; }

 private:
  struct Foot {
    bool have_low = false, prev = false;  ///< a lowest height; the last frame seen and in stance
    double low_m = 0.0, a_m = 0.0, b_m = 0.0, h_m = 0.0;  ///< the lowest height, the last position [m]
  };

  /// One stance frame's velocity (ma, mb): each axis's running median (a step of g times the mean
  /// absolute deviation towards the measurement: the stance's first and last frames, when the foot
  /// lands and lifts, move it no more than the others), as the offline check takes the median.
  void measure(double ma, double mb, double g, double dt_s) noexcept {
    if (!(ma * ma + mb * mb <= s_.max_belt_mps * s_.max_belt_mps)) return;  // a jump, a swap: no belt
    const double ea = ma - va_, eb = mb - vb_;
    dev_a_ += g * (std::fabs(ea) - dev_a_);
    dev_b_ += g * (std::fabs(eb) - dev_b_);
    va_ += g * (ea > 0.0 ? dev_a_ : ea < 0.0 ? -dev_a_ : 0.0);
    vb_ += g * (eb > 0.0 ? dev_b_ : eb < 0.0 ? -dev_b_ : 0.0);
    measured_s_ += dt_s;
  }

  bool estimated() const noexcept {
    const double belt2 = va_ * va_ + vb_ * vb_, pelvis2 = pelvis_a_ * pelvis_a_ + pelvis_b_ * pelvis_b_;
    const double stays2 = kPelvisFraction * kPelvisFraction * belt2;
    // The belt runs against the walking: stance feet that seem to move along a pelvis that travels are
    // a start, a stop or a turn overground.
    const bool along = va_ * pelvis_a_ + vb_ * pelvis_b_ > 0.0 && pelvis2 > kPelvisStillMps * kPelvisStillMps;
    return measured_s_ >= kMinMeasuredFraction * s_.tau_s && belt2 >= s_.min_belt_mps * s_.min_belt_mps &&
           pelvis2 <= s_.max_pelvis_mps * s_.max_pelvis_mps && pelvis2 <= stays2 && !along;
  }

  /// The belt in use from the state: known (its direction the estimate's, else against heading_rad),
  /// estimated, or none.
  void refresh() noexcept {
    const bool est = estimated();
    active_ = known_mps_ >= 0.0 || est;
    use_a_ = use_b_ = use_speed_ = use_std_ = 0.0;
    if (known_mps_ >= 0.0) {
      double ua = ua0_, ub = ub0_;  // the belt runs against the walking direction
      if (est) {
        const double k = 1.0 / sqrt1(va_ * va_ + vb_ * vb_);
        ua = va_ * k;
        ub = vb_ * k;
      }
      use_a_ = known_mps_ * ua;
      use_b_ = known_mps_ * ub;
      use_speed_ = known_mps_;
    } else if (est) {
      use_a_ = va_;
      use_b_ = vb_;
      use_speed_ = sqrt1(va_ * va_ + vb_ * vb_);
      use_std_ = 1.25 * sqrt1((dev_a_ * dev_a_ + dev_b_ * dev_b_) * (kIndependentS / s_.tau_s));
    }
  }

  Settings s_;
  std::size_t n_ = 0, up_ = 2, a_ = 0, b_ = 1;
  double unit_ = 1.0, max_abs_m_ = 1e5;
  double ua0_ = -1.0, ub0_ = 0.0;  ///< the belt's direction without an estimate (against heading_rad)
  std::array<Foot, kMaxFeet> feet_{};
  double va_ = 0.0, vb_ = 0.0, measured_s_ = 0.0;  ///< the belt's velocity [m/s], stance time measured [s]
  double dev_a_ = kDev0Mps, dev_b_ = kDev0Mps;     ///< mean absolute deviations of the stance velocities [m/s]
  double known_mps_ = -1.0;
  double pelvis_a_ = 0.0, pelvis_b_ = 0.0;  ///< the pelvis's low-passed horizontal velocity [m/s]
  IntervalCache<double> pelvis_g_;  ///< its gain at the last frame intervals
  double gains_dt_s_ = -1.0, g_ = 1.0, inv_dt_ = 1.0;  ///< the median's gain and 1 / dt at that interval
  bool active_ = false;                          ///< the belt in use (refresh())
  double use_a_ = 0.0, use_b_ = 0.0, use_speed_ = 0.0, use_std_ = 0.0;
  double t_s_ = 0.0;
  bool have_t_ = false;
};

}  // namespace yoyogait::online
