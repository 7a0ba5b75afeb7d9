// Central finite differences, to test analytic Jacobians.
#pragma once

#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>

namespace yoyogait::testing {

/// d f(x) / d x by central differences with a step relative to each entry. S indexes like an array.
template <std::size_t N, class S, class F>
std::array<std::array<double, N>, N> central_jacobian(const S& x, F f) {
  std::array<std::array<double, N>, N> J{};
  for (std::size_t j = 0; j < N; ++j) {
    const double h = 1e-6 * std::max(1.0, std::fabs(x[j]));
    S plus = x, minus = x;
    plus[j] += h;
    minus[j] -= h;
    const S fp = f(plus), fm = f(minus);
    for (std::size_t i = 0; i < N; ++i) J[i][j] = (fp[i] - fm[i]) / (2 * h);
  }
  return J;
}

}  // namespace yoyogait::testing
