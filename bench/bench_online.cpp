// Native OnlineEstimator::update loop (front-end and estimator): median ns per frame over rounds.
// Usage: bench_online [ROUNDS [ESTIMATOR_PERIOD_S [RATE_HZ [treadmill]]]]. Synthetic 4-marker pelvis
// (default 100 Hz) with 1 mm noise, 120 s; "treadmill": the pelvis in place and two heels on a 1.2 m/s
// belt in the frames (the belt from the stance feet).
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <random>
#include <string>
#include <vector>

#include "yoyogait/online.hpp"

template <class T>
inline void do_not_optimize(const T& value) {
  asm volatile("" : : "r,m"(value) : "memory");
}

int main(int argc, char** argv) {
  const int rounds = argc > 1 ? std::atoi(argv[1]) : 7;
  // Optional: the estimator's sample_time_s [s] (default 0.04: fed every 40 ms; 0.001: every frame).
  yoyogait::OnlineConfig config;
  if (argc > 2) config.estimator.sample_time_s = std::atof(argv[2]);
  // Optional: the capture rate [Hz] (default 100).
  const double rate = argc > 3 ? std::atof(argv[3]) : 100.0, f = 1.8, pi = 3.141592653589793;
  const bool treadmill = argc > 4 && std::string(argv[4]) == "treadmill";
  const std::size_t n = static_cast<std::size_t>(120.0 * rate), feet = treadmill ? 2 : 0, k3 = 3 * (4 + feet);
  std::vector<double> t(n), p(n * k3);
  std::mt19937 rng(1);
  std::normal_distribution<double> noise(0.0, 0.001);
  for (std::size_t k = 0; k < n; ++k) {
    t[k] = static_cast<double>(k) / rate;
    const double th = 2.0 * pi * f * t[k];
    const double x = (treadmill ? 0.0 : 1.2 * t[k]) - 0.012 * std::sin(th), z = 1.0 + 0.012 * std::cos(th);
    for (int j = 0; j < 4; ++j) {
      p[k * k3 + 3 * j] = x + (j < 2 ? 0.075 : -0.075) + noise(rng);
      p[k * k3 + 3 * j + 1] = (j % 2 ? 0.125 : -0.125) + noise(rng);
      p[k * k3 + 3 * j + 2] = z + noise(rng);
    }
    for (std::size_t j = 0; j < feet; ++j) {  // stance 60 % of the stride, back at the belt; swing forward
      const double stride_s = 2.0 / f, s = std::fmod(t[k] / stride_s + 0.5 * static_cast<double>(j), 1.0);
      const double len = 1.2 * 0.6 * stride_s, w = (s - 0.6) / 0.4;
      double* q = &p[k * k3 + 3 * (4 + j)];
      q[0] = (s < 0.6 ? 0.5 * len - 1.2 * s * stride_s : -0.5 * len + len * w) + noise(rng);
      q[1] = (j ? 0.1 : -0.1) + noise(rng);
      q[2] = 0.05 + (s < 0.6 ? 0.0 : 0.1 * std::sin(pi * w)) + noise(rng);
    }
  }
  std::vector<double> ns;
  double sink = 0.0, speed = 0.0;
  for (int r = 0; r < rounds; ++r) {
    yoyogait::OnlineEstimator est(4, 2, 1.0, config, feet);
    const auto t0 = std::chrono::steady_clock::now();
    for (std::size_t k = 0; k < n; ++k) {
      const yoyogait::OnlineEstimate e = est.update(t[k], &p[k * k3]);
      do_not_optimize(e);
    }
    const auto t1 = std::chrono::steady_clock::now();
    sink += est.last().step_frequency_hz;
    speed += est.last().speed_mps;
    ns.push_back(std::chrono::duration<double, std::nano>(t1 - t0).count() / static_cast<double>(n));
  }
  std::sort(ns.begin(), ns.end());
  std::printf(
      "OnlineEstimator::update, 4 points%s at %g Hz, estimator every %.3f s, -O3: median %.0f ns per frame, min %.0f ns "
      "(%d rounds of %zu frames; f=%.3f Hz, speed %.3f m/s)\n",
      treadmill ? " + 2 heels on a treadmill" : "", rate, config.estimator.sample_time_s, ns[ns.size() / 2],
      ns.front(), rounds, n, sink / rounds, speed / rounds);
  return 0;
}
