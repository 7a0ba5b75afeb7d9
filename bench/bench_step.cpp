// Native step loop of the estimator, single stream, both presets: median ns per sample over
// repeated runs, the presets interleaved so that both see the same machine load.
// Usage: bench_step SIGNAL.f64 [REPEATS]  (SIGNAL: vx then vz, float64, as written by bench/run.py)
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <vector>

#include "yoyogait/estimator.hpp"

namespace {

// Every estimate is materialised in memory, as benchmark::DoNotOptimize does, so that the compiler
// computes every field, as a control loop that reads the whole estimate would need.
template <class T>
inline void do_not_optimize(const T& value) {
  asm volatile("" : : "r,m"(value) : "memory");
}

double time_once(const yoyogait::EstimatorConfig& cfg, const double* vx, const double* vz, std::size_t n,
                 double& sink) {
  yoyogait::Estimator est(cfg);
  const auto t0 = std::chrono::steady_clock::now();
  for (std::size_t i = 0; i < n; ++i) {
    const yoyogait::Estimate e = est.step(vx[i], vz[i]);
    do_not_optimize(e);
  }
  const auto t1 = std::chrono::steady_clock::now();
  sink += est.state().omega_rad_per_sample();
  return std::chrono::duration<double, std::nano>(t1 - t0).count() / static_cast<double>(n);
}

double median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  return v[v.size() / 2];
}

}  // namespace

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

  const yoyogait::EstimatorConfig paper = yoyogait::EstimatorConfig::paper();
  const yoyogait::EstimatorConfig gait{};  // the default estimator
  std::vector<double> ns_paper, ns_default;
  double sink = 0.0;
  for (int r = 0; r < repeats; ++r) {
    ns_paper.push_back(time_once(paper, vx, vz, n, sink));
    ns_default.push_back(time_once(gait, vx, vz, n, sink));
  }
  std::printf("cpp_step_ns_median_paper=%.2f cpp_step_ns_min_paper=%.2f cpp_step_ns_median_default=%.2f "
              "cpp_step_ns_min_default=%.2f samples=%zu repeats=%d sink=%g\n",
              median(ns_paper), *std::min_element(ns_paper.begin(), ns_paper.end()), median(ns_default),
              *std::min_element(ns_default.begin(), ns_default.end()), n, repeats, sink);
  return 0;
}
