/// @file paper/heuristics.hpp
/// @brief The heuristic filter of R_hat and r_hat (eq. 11-12) and the reconstruction (eq. 13-14).
#pragma once

#include <array>
#include <cmath>
#include <cstddef>

#include "yoyogait/config.hpp"
#include "yoyogait/paper/state.hpp"

namespace yoyogait::paper {

/// Eq. 11-12: R_hat(k) and r_hat(k) start at R_hat(0), r_hat(0); for k > n, while x3 > mu_w and
/// x4 > mu_A0, each becomes the mean of its previous n values and the new x4/x3 (resp. A1/x3);
/// otherwise it holds. The last n values live in a fixed ring buffer, with their running sums.
class ParameterFilter {
 public:
  ParameterFilter() = default;
  ParameterFilter(std::size_t window_samples, double gate_omega, double gate_bias, double R0, double r0) noexcept
      : n_(window_samples),
        inv_n1_(1.0 / static_cast<double>(window_samples + 1)),
        gate_omega_(gate_omega),
        gate_bias_(gate_bias),
        R0_(R0),
        r0_(r0) {
    reset();
  }

  void reset() noexcept {
    R_hat_ = R0_;
    r_hat_ = r0_;
    k_ = 0;
    head_ = 0;
    R_hist_.fill(0.0);
    r_hist_.fill(0.0);
    sum_R_ = sum_r_ = 0.0;
  }

  /// Eq. 11-12 at the next sample k with the posterior x3 = w, x4 = bias and A1 = |(x1, x2)|.
  /// Returns true when the update branch was taken (the gate was open).
  bool update(double w, double bias, double a1) noexcept {
    ++k_;
    const bool open = k_ > n_ && w > gate_omega_ && bias > gate_bias_;
    if (open) {
      const double inv_w = 1.0 / w;
      // sum_* hold R_hat(k-n..k-1): only the newest value, R_hat(k-1), is on the loop-carried chain.
      R_hat_ = (sum_R_ + bias * inv_w) * inv_n1_;
      r_hat_ = (sum_r_ + a1 * inv_w) * inv_n1_;
    }
    if (n_ > 0) push();
    return open;
  }

  double R_hat_mps() const noexcept { return R_hat_; }
  double r_hat_mps() const noexcept { return r_hat_; }

 private:
  // Appends R_hat(k), r_hat(k) to the window. The sums follow each sample and are recomputed from
  // the buffer, oldest first, whenever the ring wraps, so rounding never accumulates over more than
  // n samples.
  void push() noexcept {
    sum_R_ += R_hat_ - R_hist_[head_];
    sum_r_ += r_hat_ - r_hist_[head_];
    R_hist_[head_] = R_hat_;
    r_hist_[head_] = r_hat_;
    if (++head_ == n_) {
      head_ = 0;
      sum_R_ = sum_r_ = 0.0;
      for (std::size_t i = 0; i < n_; ++i) {
        sum_R_ += R_hist_[i];
        sum_r_ += r_hist_[i];
      }
    }
  }

  std::size_t n_ = 10;
  double inv_n1_ = 1.0 / 11.0;
  double gate_omega_ = 0.1, gate_bias_ = 0.1, R0_ = 2.0, r0_ = 0.2;
  double R_hat_ = 2.0, r_hat_ = 0.2;
  double sum_R_ = 0.0, sum_r_ = 0.0;  ///< sums of the window, R_hat(k-n..k-1) and r_hat(k-n..k-1)
  std::size_t k_ = 0, head_ = 0;
  std::array<double, kMaxSmoothingWindow> R_hist_{};
  std::array<double, kMaxSmoothingWindow> r_hist_{};
};

/// Eq. 13-14: v_x = R_hat x3 + r_hat x3 x1 / A1, v_z = -r_hat x3 x2 / A1, with A1 = |(x1, x2)|.
/// Where A1 = 0 the phase is undefined and the oscillation term is taken as zero. a1 = |(x1, x2)|.
struct Reconstruction {
  double vx_mps = 0.0;
  double vz_mps = 0.0;
};

inline Reconstruction reconstruct(double R_hat, double r_hat, double x1, double x2, double x3,
                                  double a1) noexcept {
  // (r_hat x3) (1 / a1): the division need not wait for r_hat.
  const double scale = a1 > 0.0 ? (r_hat * x3) * (1.0 / a1) : 0.0;
  return Reconstruction{R_hat * x3 + scale * x1, -scale * x2};
}

}  // namespace yoyogait::paper
