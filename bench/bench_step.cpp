// Native step loop of the estimator, single stream: median ns per sample over repeated runs.
// Usage: bench_step SIGNAL.f64 [REPEATS]  (SIGNAL: vx then vz, float64, as written by bench/run.py)
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <vector>

#include "yoyogait/estimator.hpp"

int main(int argc, char** argv) {
  if (argc < 2) {
    std::fprintf(stderr, "usage: bench_step SIGNAL.f64 [REPEATS]\n");
    return 2;
  }
  std::ifstream in(argv[1], std::ios::binary | std::ios::ate);
  if (!in) {
    std::fprintf(stderr, "bench_step: cannot read %s\n", argv[1]);
    return 2;
  }
  const auto bytes = static_cast<std::size_t>(in.tellg());
  const std::size_t n = bytes / (2 * sizeof(double));
  std::vector<double> signal(2 * n);
  in.seekg(0);
  in.read(reinterpret_cast<char*>(signal.data()), static_cast<std::streamsize>(2 * n * sizeof(double)));
  const double* vx = signal.data();
  const double* vz = signal.data() + n;
  const int repeats = argc > 2 ? std::atoi(argv[2]) : 31;

  std::vector<double> ns;
  double sink = 0.0;
  // Every estimate is stored whole, as a control loop would use it; otherwise the compiler could
  // drop the fields nobody reads.
  std::vector<yoyogait::Estimate> ring(1024);
  for (int r = 0; r < repeats; ++r) {
    yoyogait::Estimator est(yoyogait::EstimatorConfig::paper());
    const auto t0 = std::chrono::steady_clock::now();
    for (std::size_t i = 0; i < n; ++i) {
      ring[i & 1023] = est.step(vx[i], vz[i]);
    }
    for (const auto& e : ring) sink += e.vx_hat_mps + e.step_frequency_std_hz + e.speed_std_mps + e.R_m;
    const auto t1 = std::chrono::steady_clock::now();
    ns.push_back(std::chrono::duration<double, std::nano>(t1 - t0).count() / static_cast<double>(n));
  }
  std::sort(ns.begin(), ns.end());
  std::printf("cpp_step_ns_median=%.2f cpp_step_ns_min=%.2f samples=%zu repeats=%d sink=%g\n", ns[ns.size() / 2],
              ns.front(), n, repeats, sink);
  return 0;
}
