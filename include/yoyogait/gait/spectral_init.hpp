/// @file gait/spectral_init.hpp
/// @brief The spectral initialisation (sec. 2.3): a least-squares frequency grid search over the
/// first walking samples, which seeds a member of the start-up bank. Start-up work only.
#pragma once

#include <array>
#include <cmath>
#include <cstddef>

#include "yoyogait/config.hpp"
#include "yoyogait/math.hpp"

namespace yoyogait::gait {

/// A ring buffer of the last samples of the acquisition and the fit over it.
class SpectralInit {
 public:
  struct Settings {
    bool enabled = true;
    double after_s = 1.0;            ///< walking time of the acquisition before the search [s]
    std::size_t buffer_samples = 40;  ///< ring buffer length (<= kMaxSpectralBuffer)
    double grid_step_hz = 0.025;     ///< grid step over [f_min_hz, f_max_hz] [Hz]
    double f_min_hz = 0.6, f_max_hz = 3.5;
    double r_vx = 0.0025, r_vz = 0.0025;  ///< measurement noise variances: weights of the two fits
  };

  /// The fit at the best frequency: v_x(tau) = a + b tau + Xc cos(w tau) + Xs sin(w tau),
  /// v_z(tau) = c + Zc cos(w tau) + Zs sin(w tau), tau the time since the last sample.
  struct Fit {
    /// The coefficients in sol.
    enum Coefficient : std::size_t { kA = 0, kB = 1, kXc = 2, kXs = 3, kC = 4, kZc = 5, kZs = 6, kCount = 7 };
    double f_hz = 0.0;
    double sol[kCount] = {};  ///< a, b, Xc, Xs, c, Zc, Zs
  };

  SpectralInit() noexcept = default;
  explicit SpectralInit(const Settings& s) noexcept : s_(s) {}

  /// An empty buffer; the search not yet done.
  void reset() noexcept {
    n_ = 0;
    head_ = 0;
    done_ = false;
  }

  void push(double t, double vx, double vz) noexcept {
    const std::size_t nb = s_.buffer_samples;
    t_[head_] = t;
    x_[head_] = vx;
    z_[head_] = vz;
    head_ = (head_ + 1) % nb;
    if (n_ < nb) ++n_;
  }

  /// True once, when the acquisition has walked long enough for the search.
  bool due(double walk_time_s) noexcept {
    if (!(s_.enabled && !done_ && walk_time_s >= s_.after_s)) return false;
    done_ = true;
    return true;
  }

  /// Grid search of the fit's weighted residual over [f_min, f_max] with a parabolic refinement.
  /// false (no fit) with fewer than 10 buffered samples.
  YOYOGAIT_COLD bool fit(Fit& out) const noexcept {  // once per acquisition: out of the per-sample code
    const std::size_t n = n_;
    if (n < 10) return false;
    const Buffer b = ordered();
    const double step = s_.grid_step_hz;
    const auto nf = static_cast<std::size_t>((s_.f_max_hz - s_.f_min_hz) / step) + 1;
    // cos and sin of w tau per sample at the grid's first frequency, then turned by the grid step's
    // angle per sample: two sincos per sample for the whole grid instead of one per grid point (the
    // turns' rounding, some 1e-14 over the grid, is far below the costs' differences).
    Phases ph = phases(kTwoPi * s_.f_min_hz, b);
    const Phases turn = phases(kTwoPi * step, b);
    // Costs of the best grid point and its two neighbours, without storing the grid.
    std::size_t best_k = 0;
    double best = 0.0, prev = 0.0, before_best = 0.0, after_best = 0.0;
    for (std::size_t k = 0; k < nf; ++k) {
      if (k > 0) {
        for (std::size_t q = 0; q < n; ++q) {
          const double c = ph.c[q], sn = ph.s[q];
          ph.c[q] = c * turn.c[q] - sn * turn.s[q];
          ph.s[q] = sn * turn.c[q] + c * turn.s[q];
        }
      }
      const double cost = ls_cost(ph, b, nullptr);
      if (k == 0) best = cost;
      if (k == best_k + 1) after_best = cost;
      if (cost < best) {
        best = cost;
        best_k = k;
        before_best = prev;
      }
      prev = cost;
    }
    double f_best = s_.f_min_hz + static_cast<double>(best_k) * step;
    if (best_k > 0 && best_k + 1 < nf) {
      const double y0 = before_best, y1 = best, y2 = after_best;
      const double den = y0 - 2.0 * y1 + y2;
      if (den > 0.0) f_best += detail::py_max(-0.5, detail::py_min(0.5, 0.5 * (y0 - y2) / den)) * step;
    }
    out.f_hz = f_best;
    ls_cost(phases(kTwoPi * f_best, b), b, out.sol);  // the fit itself at the refined frequency, exactly
    return true;
  }

 private:
  /// The buffered samples in time order (tau: the time since the last one) and the sums of the
  /// normal equations that do not depend on the frequency, formed once for the whole grid (each sum
  /// by the same additions in the same order as within a cost: the same bits).
  struct Buffer {
    std::size_t n = 0;
    std::array<double, kMaxSpectralBuffer> tau{}, x{}, z{};
    double A00 = 0.0, A01 = 0.0, A11 = 0.0, bx0 = 0.0, bx1 = 0.0, bz0 = 0.0, yy_x = 0.0, yy_z = 0.0;
  };
  Buffer ordered() const noexcept {
    Buffer b;
    b.n = n_;
    const std::size_t nb = s_.buffer_samples;
    const double t_last = t_[(head_ + nb - 1) % nb];
    const std::size_t i0 = (head_ + nb - n_) % nb;
    for (std::size_t q = 0; q < b.n; ++q) {
      const std::size_t i = (i0 + q) % nb;
      const double tau = t_[i] - t_last, x = x_[i], z = z_[i];
      b.tau[q] = tau;
      b.x[q] = x;
      b.z[q] = z;
      b.A00 += 1.0 * 1.0;
      b.A01 += 1.0 * tau;
      b.A11 += tau * tau;
      b.bx0 += 1.0 * x;
      b.bx1 += tau * x;
      b.bz0 += z;
      b.yy_x += x * x;
      b.yy_z += z * z;
    }
    return b;
  }

  /// cos(w tau) and sin(w tau) of each buffered sample at one frequency w.
  struct Phases {
    std::array<double, kMaxSpectralBuffer> c{}, s{};
  };
  static Phases phases(double w, const Buffer& b) noexcept {
    Phases ph;
    for (std::size_t q = 0; q < b.n; ++q) {
      ph.c[q] = std::cos(w * b.tau[q]);
      ph.s[q] = std::sin(w * b.tau[q]);
    }
    return ph;
  }

  /// Weighted residual of two linear least-squares fits at angular frequency w over the buffer
  /// (ph: its cos and sin per sample): v_x(tau) = a + b tau + Xc cos(w tau) + Xs sin(w tau),
  /// v_z(tau) = c + Zc cos(w tau) + Zs sin(w tau).
  double ls_cost(const Phases& ph, const Buffer& b, double* sol) const noexcept {
    double A[4][4] = {}, bx[4] = {}, bz[3] = {};
    for (std::size_t q = 0; q < b.n; ++q) {
      const double tau = b.tau[q], x = b.x[q], z = b.z[q];
      const double cs = ph.c[q], sn = ph.s[q];
      // The rows of phi = (1, tau, cs, sn) that depend on w.
      A[0][2] += 1.0 * cs;
      A[0][3] += 1.0 * sn;
      A[1][2] += tau * cs;
      A[1][3] += tau * sn;
      A[2][2] += cs * cs;
      A[2][3] += cs * sn;
      A[3][3] += sn * sn;
      bx[2] += cs * x;
      bx[3] += sn * x;
      bz[1] += cs * z;
      bz[2] += sn * z;
    }
    A[0][0] = b.A00;
    A[0][1] = b.A01;
    A[1][1] = b.A11;
    bx[0] = b.bx0;
    bx[1] = b.bx1;
    bz[0] = b.bz0;
    for (std::size_t a = 0; a < 4; ++a)
      for (std::size_t c = 0; c < a; ++c) A[a][c] = A[c][a];
    constexpr double ridge = 1e-9;
    double Ax[4][4];
    for (std::size_t a = 0; a < 4; ++a)
      for (std::size_t c = 0; c < 4; ++c) Ax[a][c] = A[a][c] + (a == c ? ridge : 0.0);
    const double Az[3][3] = {{A[0][0] + ridge, A[0][2], A[0][3]},
                             {A[2][0], A[2][2] + ridge, A[2][3]},
                             {A[3][0], A[3][2], A[3][3] + ridge}};
    double ax[4], az[3];
    solve_spd(Ax, bx, ax);
    solve_spd(Az, bz, az);
    const double rss_x = b.yy_x - (bx[0] * ax[0] + bx[1] * ax[1] + bx[2] * ax[2] + bx[3] * ax[3]);
    const double rss_z = b.yy_z - (bz[0] * az[0] + bz[1] * az[1] + bz[2] * az[2]);
    if (sol) {
      for (std::size_t i = 0; i < 4; ++i) sol[i] = ax[i];
      for (std::size_t i = 0; i < 3; ++i) sol[Fit::kC + i] = az[i];
    }
    return rss_x / s_.r_vx + rss_z / s_.r_vz;
  }

  Settings s_;
  std::size_t n_ = 0, head_ = 0;
  bool done_ = false;
  std::array<double, kMaxSpectralBuffer> t_{}, x_{}, z_{};
};

}  // namespace yoyogait::gait
