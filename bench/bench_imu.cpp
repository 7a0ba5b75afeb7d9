// ns per sample of yoyogait::ImuOnlineEstimator::update at 100 Hz on a synthetic walking signal
// (a tilted sensor, a Yoyo-model walker): median over rounds; with a third argument "mag" the
// update with a magnetometer (a constant field). Used by bench/imu.py.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <vector>

#include "yoyogait/imu.hpp"

int main(int argc, char** argv) {
  const std::size_t n = argc > 1 ? static_cast<std::size_t>(std::atol(argv[1])) : 60000;
  const int rounds = argc > 2 ? std::atoi(argv[2]) : 9;
  const bool with_mag = argc > 3 && std::string(argv[3]) == "mag";
  const double mag[3] = {-44.0, 3.0, 20.0};
  const double kPi = 3.14159265358979323846, g = 9.80665, f = 1.8, r = 0.022, tilt = 0.2;
  std::vector<double> t(n), acc(3 * n), gyr(3 * n);
  for (std::size_t i = 0; i < n; ++i) {
    t[i] = 0.01 * static_cast<double>(i);
    const double w = 2.0 * kPi * f, th = w * t[i];
    const double ax = -r * w * w * std::sin(th), az = -r * w * w * std::cos(th) + g;
    acc[3 * i] = std::cos(tilt) * az + std::sin(tilt) * ax;
    acc[3 * i + 1] = 0.0;
    acc[3 * i + 2] = std::cos(tilt) * ax - std::sin(tilt) * az;
    gyr[3 * i] = gyr[3 * i + 1] = gyr[3 * i + 2] = 0.01;
  }
  std::vector<double> ns;
  double sink = 0.0;
  for (int k = 0; k < rounds; ++k) {
    yoyogait::ImuOnlineEstimator est;
    const auto t0 = std::chrono::steady_clock::now();
    if (with_mag)
      for (std::size_t i = 0; i < n; ++i) sink += est.update(t[i], &acc[3 * i], &gyr[3 * i], mag).speed_mps;
    else
      for (std::size_t i = 0; i < n; ++i) sink += est.update(t[i], &acc[3 * i], &gyr[3 * i]).speed_mps;
    const auto t1 = std::chrono::steady_clock::now();
    ns.push_back(std::chrono::duration<double, std::nano>(t1 - t0).count() / static_cast<double>(n));
  }
  std::sort(ns.begin(), ns.end());
  std::printf("{\"median_ns\": %.1f, \"max_ns\": %.1f, \"samples\": %zu, \"rounds\": %d, \"sink\": %.3f}\n",
              ns[ns.size() / 2], ns.back(), n, rounds, sink);
  return 0;
}
