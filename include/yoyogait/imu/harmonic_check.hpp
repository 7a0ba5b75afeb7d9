/// @file imu/harmonic_check.hpp
/// @brief Whether the estimator sits on a wrong harmonic of the step, from the fed v_z's normalised
/// autocorrelation at its period P = 1 / f and at P / 2: on the step, r(P) > 0 > r(P / 2); on the
/// stride (f half the cadence, the second harmonic taking the step) r(P / 2) > 0; on twice the
/// cadence r(P) < 0 (docs/imu.md). And whether the last few steps repeat at P at all
/// (periodicity(): r(P) over that many periods; a pause or irregular steps in a turn do not).
#pragma once

#include <array>
#include <cmath>
#include <cstddef>

namespace yoyogait::imu {

class HarmonicCheck {
 public:
  /// The last kRing fed v_z means, checked every kCheckTicks samples over kCheckWindow of them (256:
  /// periodicity() over up to 3 periods at 0.4 Hz and 25 Hz fits).
  static constexpr std::size_t kRing = 256, kCheckWindow = 50, kCheckTicks = 5;
  static_assert(kCheckWindow + kRing / 2 + 2 <= kRing, "the check's span fits the ring");
  static_assert((kRing & (kRing - 1)) == 0, "the ring's length is a power of 2");
  /// r(P / 2) above this or r(P) below it: a wrong harmonic.
  static constexpr double kHalfLagMax = 0.0, kFullLagMin = 0.0;

  /// The ring emptied (a start of the front-end).
  void clear() noexcept {
    ring_.fill(0.0);
    n_ = next_ = 0;
  }

  /// The estimator (re)starts: the next check comes kCheckTicks samples on; off_ until then as given.
  void restart(bool off) noexcept {
    ticks_ = 0;
    off_ = off;
  }

  /// A value for an estimator sample that a gap in the stream swallowed (the model's v_z there):
  /// into the ring, so that its lags stay in samples of the estimator's period; no check.
  void fill(double vz) noexcept {
    ring_[next_] = ring_[next_ + kRing] = vz;
    next_ = (next_ + 1) & (kRing - 1);
    if (n_ < kRing) ++n_;
  }

  /// One fed v_z mean; f_hz the estimate at that sample, locked whether it is walking and has locked,
  /// dt_s the sample time. Whether the autocorrelation says off (held between its checks).
  bool update(double vz, double f_hz, bool locked, double dt_s) noexcept {
    ring_[next_] = ring_[next_ + kRing] = vz;
    next_ = (next_ + 1) & (kRing - 1);
    if (n_ < kRing) ++n_;
    if (++ticks_ >= kCheckTicks) {
      ticks_ = 0;
      off_ = false;
      const double lag = locked ? 1.0 / (f_hz * dt_s) : 0.0;
      if (locked && lag + static_cast<double>(kCheckWindow) + 2.0 < static_cast<double>(n_) &&
          lag < static_cast<double>(kRing / 2)) {
        const double r_full = autocorrelation(newest(), lag), r_half = autocorrelation(newest(), 0.5 * lag);
        off_ = r_half > kHalfLagMax || r_full < kFullLagMin;
      }
    }
    return off_;
  }

  /// The normalised autocorrelation of the newest steps periods of the fed v_z at the lag of one
  /// period (1 / (f_hz dt_s) samples): 1 when the last steps repeat exactly at the estimate's period,
  /// about 0 or below in a pause (the newest period is still, the one before is a step) or in steps
  /// of another rhythm. -1 (no evidence) while the ring holds fewer than steps + 1 periods.
  double periodicity(double f_hz, double dt_s, double steps) const noexcept {
    if (!(f_hz > 0.0 && dt_s > 0.0 && steps > 0.0)) return -1.0;
    const double lag = 1.0 / (f_hz * dt_s);
    const std::size_t window = static_cast<std::size_t>(steps * lag + 0.5), l0 = static_cast<std::size_t>(lag);
    if (window < 2 || static_cast<double>(window + l0 + 2) > static_cast<double>(n_)) return -1.0;
    const double w = lag - static_cast<double>(l0);
    double sxy = 0.0, sxx = 0.0, syy = 0.0;
    const double* x = newest();
    const std::ptrdiff_t n = static_cast<std::ptrdiff_t>(window), l = static_cast<std::ptrdiff_t>(l0);
    for (std::ptrdiff_t i = 0; i < n; ++i) {
      const double y = (1.0 - w) * x[-(i + l)] + w * x[-(i + l + 1)];
      sxy += x[-i] * y;
      sxx += x[-i] * x[-i];
      syy += y * y;
    }
    const double d = sxx * syy;
    return d > 0.0 ? sxy / std::sqrt(d) : -1.0;
  }

 private:
  // The newest value; newest()[-i] is the i-th newest (i < kRing): each value is stored twice, at
  // next_ and next_ + kRing, so that the last kRing values lie in order without wrapping.
  const double* newest() const noexcept { return ring_.data() + next_ + kRing - 1; }

  // The normalised autocorrelation of the kCheckWindow newest values (x[-i], newest first) at a
  // (fractional) lag.
  static double autocorrelation(const double* x, double lag) noexcept {
    const std::ptrdiff_t l0 = static_cast<std::ptrdiff_t>(lag);
    const double w = lag - static_cast<double>(l0);
    double sxy = 0.0, sxx = 0.0, syy = 0.0;
    for (std::ptrdiff_t i = 0; i < static_cast<std::ptrdiff_t>(kCheckWindow); ++i) {
      const double y = (1.0 - w) * x[-(i + l0)] + w * x[-(i + l0 + 1)];
      sxy += x[-i] * y;
      sxx += x[-i] * x[-i];
      syy += y * y;
    }
    const double d = sxx * syy;
    return d > 0.0 ? sxy / std::sqrt(d) : 0.0;
  }

  std::array<double, 2 * kRing> ring_{};
  std::size_t n_ = 0, next_ = 0, ticks_ = 0;
  bool off_ = false;
};

}  // namespace yoyogait::imu
