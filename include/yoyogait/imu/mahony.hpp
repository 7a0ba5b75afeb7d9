/// @file imu/mahony.hpp
/// @brief Mahony's complementary filter (Mahony, Hamel & Pflimlin 2008): the sensor's orientation
/// relative to gravity from the rate gyro, corrected towards the measured specific force; its
/// integral term estimates the gyro bias about the horizontal axes. With a magnetometer, the yaw is
/// corrected too, towards the tilt-compensated magnetic heading (about the vertical only, so that a
/// disturbed field cannot tilt the estimate), and the integral then takes in the vertical bias.
///
/// q is the unit quaternion (w, x, y, z) of the rotation world <- sensor, world z up; with a
/// magnetometer world x is magnetic north (y west). Without one the yaw (the rotation about the
/// vertical) is the gyro's integral: relative, drifting with the vertical bias.
#pragma once

#include <array>
#include <cmath>
#include <cstddef>
#include <limits>

#include "yoyogait/math.hpp"

namespace yoyogait::imu {

using Vec3 = std::array<double, 3>;

class Mahony {
 public:
  Mahony() noexcept = default;
  Mahony(double kp_per_s, double ki_per_s2, double max_bias_rad_s) noexcept
      : kp_(kp_per_s), ki_(ki_per_s2), max_bias_(max_bias_rad_s) {}

  /// Starts level with the specific force acc (any non-zero vector), yaw 0, the bias estimate 0.
  void start(const Vec3& acc) noexcept {
    const double n = norm(acc);
    bias_ = {0.0, 0.0, 0.0};
    if (!(n > 0.0)) {
      q_ = {1.0, 0.0, 0.0, 0.0};
      return;
    }
    const Vec3 a{acc[0] / n, acc[1] / n, acc[2] / n};
    // The shortest rotation taking a onto +z: q = (1 + a.z, a x z) normalised.
    const double w = 1.0 + a[2];
    if (w < 1e-9) {
      q_ = {0.0, 1.0, 0.0, 0.0};  // a = -z: half a turn about x
      return;
    }
    q_ = {w, a[1], -a[0], 0.0};
    normalise();
  }

  /// Turns the estimate about the vertical so that the horizontal part of mag (any unit, sensor
  /// frame) points along world x: the yaw from the magnetometer at once (a start).
  void align_yaw(const Vec3& mag) noexcept {
    const double a = field_angle(mag);
    if (!std::isfinite(a)) return;
    // q <- (cos(-a/2), 0, 0, sin(-a/2)) q: a rotation about the world's vertical.
    const double c = std::cos(-0.5 * a), s = std::sin(-0.5 * a);
    const double qw = q_[0], qx = q_[1], qy = q_[2], qz = q_[3];
    q_ = {c * qw - s * qz, c * qx - s * qy, c * qy + s * qx, c * qz + s * qw};
    normalise();
  }

  /// The angle of the horizontal part of mag (sensor frame) in the world frame from world x
  /// (counter-clockwise seen from above) [rad]: the yaw error against magnetic north. NaN when the
  /// field is (nearly) vertical.
  double field_angle(const Vec3& mag) const noexcept {
    const Vec3 h = to_world(mag);
    const double hh = h[0] * h[0] + h[1] * h[1];
    if (!(hh > 1e-6 * (hh + h[2] * h[2]))) return std::numeric_limits<double>::quiet_NaN();
    return std::atan2(h[1], h[0]);
  }

  /// One sample dt_s after the previous one. correct: use acc (false while it is saturated).
  /// yaw_error_rad (field_angle of a magnetometer sample, 0 without one) is corrected with gain
  /// yaw_kp_per_s about the vertical; its share of the integral term is yaw_kp / kp of it.
  void step(const Vec3& acc, const Vec3& gyr, double dt_s, bool correct, double yaw_error_rad = 0.0,
            double yaw_kp_per_s = 0.0) noexcept {
    Vec3 w = gyr;
    const double n = norm(acc);
    const bool use_acc = correct && n > 0.0, use_mag = yaw_kp_per_s > 0.0 && yaw_error_rad != 0.0;
    if (use_acc || use_mag) {
      const Vec3 v = up_in_sensor();
      Vec3 e{0.0, 0.0, 0.0};
      if (use_acc) {
        const double inv = 1.0 / n, ax = acc[0] * inv, ay = acc[1] * inv, az = acc[2] * inv;
        e = {ay * v[2] - az * v[1], az * v[0] - ax * v[2], ax * v[1] - ay * v[0]};  // a x v
      }
      if (use_mag) {
        // A turn about the world's vertical by -yaw_error (the vertical in the sensor frame is v),
        // in units of the accelerometer's error so that kp and ki act on it as yaw_kp / kp.
        const double k = -yaw_error_rad * (kp_ > 0.0 ? yaw_kp_per_s / kp_ : 0.0);
        for (int i = 0; i < 3; ++i) e[i] += k * v[i];
        if (!(kp_ > 0.0))
          for (int i = 0; i < 3; ++i) w[i] -= yaw_kp_per_s * yaw_error_rad * v[i];
      }
      for (int i = 0; i < 3; ++i) {
        if (ki_ > 0.0) {
          // Limited by comparisons: std::fmin / std::fmax are library calls per axis and sample.
          const double b = bias_[i] + ki_ * e[i] * dt_s;
          bias_[i] = !(b >= -max_bias_) ? -max_bias_ : (b > max_bias_ ? max_bias_ : b);
        }
        w[i] += kp_ * e[i] + bias_[i];
      }
    }
    const double hx = 0.5 * dt_s * w[0], hy = 0.5 * dt_s * w[1], hz = 0.5 * dt_s * w[2];
    const double qw = q_[0], qx = q_[1], qy = q_[2], qz = q_[3];
    q_[0] = qw - qx * hx - qy * hy - qz * hz;
    q_[1] = qx + qw * hx + qy * hz - qz * hy;
    q_[2] = qy + qw * hy - qx * hz + qz * hx;
    q_[3] = qz + qw * hz + qx * hy - qy * hx;
    normalise();
  }

  /// The world's up direction in the sensor frame (R^T e_z).
  Vec3 up_in_sensor() const noexcept {
    const double w = q_[0], x = q_[1], y = q_[2], z = q_[3];
    return {2.0 * (x * z - w * y), 2.0 * (w * x + y * z), w * w - x * x - y * y + z * z};
  }

  /// A sensor-frame vector in the world frame (R v).
  Vec3 to_world(const Vec3& v) const noexcept {
    const double w = q_[0], x = q_[1], y = q_[2], z = q_[3];
    return {(1.0 - 2.0 * (y * y + z * z)) * v[0] + 2.0 * (x * y - w * z) * v[1] + 2.0 * (x * z + w * y) * v[2],
            2.0 * (x * y + w * z) * v[0] + (1.0 - 2.0 * (x * x + z * z)) * v[1] + 2.0 * (y * z - w * x) * v[2],
            2.0 * (x * z - w * y) * v[0] + 2.0 * (y * z + w * x) * v[1] + (1.0 - 2.0 * (x * x + y * y)) * v[2]};
  }

  /// Sensor axis i (0 x, 1 y, 2 z) in the world frame: column i of R, what to_world gives for the
  /// unit vector without its products with zeros.
  Vec3 axis_to_world(std::size_t i) const noexcept {
    const double w = q_[0], x = q_[1], y = q_[2], z = q_[3];
    if (i == 0) return {1.0 - 2.0 * (y * y + z * z), 2.0 * (x * y + w * z), 2.0 * (x * z - w * y)};
    if (i == 1) return {2.0 * (x * y - w * z), 1.0 - 2.0 * (x * x + z * z), 2.0 * (y * z + w * x)};
    return {2.0 * (x * z + w * y), 2.0 * (y * z - w * x), 1.0 - 2.0 * (x * x + y * y)};
  }

  const std::array<double, 4>& quaternion() const noexcept { return q_; }
  /// The integral term: minus the estimated gyro bias [rad/s].
  const Vec3& bias_correction() const noexcept { return bias_; }

  static double norm(const Vec3& v) noexcept { return sqrt1(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]); }

 private:
  void normalise() noexcept {
    const double n = sqrt1(q_[0] * q_[0] + q_[1] * q_[1] + q_[2] * q_[2] + q_[3] * q_[3]);
    if (!(n > 0.0) || !std::isfinite(n)) {
      q_ = {1.0, 0.0, 0.0, 0.0};
      return;
    }
    for (double& c : q_) c /= n;
  }

  double kp_ = 0.5, ki_ = 0.02, max_bias_ = 0.1;
  std::array<double, 4> q_{1.0, 0.0, 0.0, 0.0};
  Vec3 bias_{0.0, 0.0, 0.0};
};

}  // namespace yoyogait::imu
