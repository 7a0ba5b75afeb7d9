/// @file paper/state.hpp
/// @brief The filter state of the paper (eq. 5) with named entries, and its covariance.
#pragma once

#include <array>
#include <cstddef>

namespace yoyogait::paper {

/// Index of each entry of the state x = [A1 cos(w k + phi), A1 sin(w k + phi), w, A0] (eq. 5).
enum StateIndex : std::size_t {
  kCos = 0,    ///< x1 = A1 cos(w k + phi) [m/s]
  kSin = 1,    ///< x2 = A1 sin(w k + phi) [m/s]
  kOmega = 2,  ///< x3 = w, the step frequency in rad/sample
  kBias = 3,   ///< x4 = A0, the bias of v_x [m/s]
};

inline constexpr std::size_t kStateDim = 4;
inline constexpr std::size_t kMeasurementDim = 2;

/// The 4-vector of eq. 5 with accessors, so that code never reads a bare x[2].
struct State {
  std::array<double, kStateDim> x{};

  constexpr double& a1_cos() noexcept { return x[kCos]; }
  constexpr double& a1_sin() noexcept { return x[kSin]; }
  constexpr double& omega_rad_per_sample() noexcept { return x[kOmega]; }
  constexpr double& bias_mps() noexcept { return x[kBias]; }
  constexpr double a1_cos() const noexcept { return x[kCos]; }
  constexpr double a1_sin() const noexcept { return x[kSin]; }
  constexpr double omega_rad_per_sample() const noexcept { return x[kOmega]; }
  constexpr double bias_mps() const noexcept { return x[kBias]; }
  constexpr double& operator[](std::size_t i) noexcept { return x[i]; }
  constexpr double operator[](std::size_t i) const noexcept { return x[i]; }
};

/// A dense 4x4 matrix, row-major; the covariance P and the Jacobian F.
using Matrix4 = std::array<std::array<double, kStateDim>, kStateDim>;

/// A symmetric 4x4 matrix, the covariance P, stored as its 10 distinct entries.
/// (i, j) and (j, i) name the same entry, so the two halves cannot drift apart.
///
/// The entries are stored as five pairs that the SSE2 filter step (paper/ekf.hpp) loads whole:
/// [P(0,0), P(1,1)], [P(0,1), P(2,3)], [P(0,2), P(1,2)], [P(0,3), P(1,3)], [P(2,2), P(3,3)]
/// (indices as StateIndex: x1, x2, w, A0).
class SymMatrix4 {
 public:
  /// Offsets of the pairs in data().
  enum Pair : std::size_t {
    kDiag01 = 0,  ///< [P(0,0), P(1,1)]
    kOff = 2,     ///< [P(0,1), P(2,3)]
    kCol2 = 4,    ///< [P(0,2), P(1,2)]
    kCol3 = 6,    ///< [P(0,3), P(1,3)]
    kDiag23 = 8,  ///< [P(2,2), P(3,3)]
  };

  constexpr SymMatrix4() noexcept = default;
  /// The upper triangle of m (m is taken to be symmetric).
  constexpr explicit SymMatrix4(const Matrix4& m) noexcept {
    for (std::size_t i = 0; i < kStateDim; ++i)
      for (std::size_t j = i; j < kStateDim; ++j) (*this)(i, j) = m[i][j];
  }
  constexpr double& operator()(std::size_t i, std::size_t j) noexcept { return v_[index(i, j)]; }
  constexpr double operator()(std::size_t i, std::size_t j) const noexcept { return v_[index(i, j)]; }
  /// Both halves filled.
  constexpr Matrix4 dense() const noexcept {
    Matrix4 m{};
    for (std::size_t i = 0; i < kStateDim; ++i)
      for (std::size_t j = 0; j < kStateDim; ++j) m[i][j] = (*this)(i, j);
    return m;
  }
  /// The 10 entries in the pair order above.
  double* data() noexcept { return v_.data(); }
  const double* data() const noexcept { return v_.data(); }

 private:
  static constexpr std::size_t index(std::size_t i, std::size_t j) noexcept {
    constexpr std::size_t kIndex[kStateDim][kStateDim] = {
        {kDiag01, kOff, kCol2, kCol3},
        {kOff, kDiag01 + 1, kCol2 + 1, kCol3 + 1},
        {kCol2, kCol2 + 1, kDiag23, kOff + 1},
        {kCol3, kCol3 + 1, kOff + 1, kDiag23 + 1},
    };
    return kIndex[i][j];
  }
  std::array<double, kStateDim*(kStateDim + 1) / 2> v_{};
};

/// The identity scaled by the diagonal d.
constexpr Matrix4 diagonal(const std::array<double, kStateDim>& d) noexcept {
  Matrix4 m{};
  for (std::size_t i = 0; i < kStateDim; ++i) m[i][i] = d[i];
  return m;
}

}  // namespace yoyogait::paper

namespace yoyogait {
/// The facade reports the state in the paper's form for both algorithms (Estimate::state,
/// Estimator::state() and covariance(): [X1, X2, w T, A0] of the gait filter): the two names at the root.
using paper::Matrix4;
using paper::State;
}  // namespace yoyogait
