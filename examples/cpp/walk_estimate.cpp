// Estimate the gait of a synthetic Yoyo-model walk (eq. 3-4) sample by sample, as a control loop would.
#include <cstdio>
#include <yoyogait/yoyogait.hpp>

int main() {
  const yoyogait::YoyoParams person{0.115, 0.02, 1.0};  // R, r, z0 [m]
  const double step_frequency_hz = 1.8, T = 0.04;       // 25 Hz, as in the paper
  yoyogait::Estimator estimator(yoyogait::EstimatorConfig::paper());
  yoyogait::Estimate e;
  for (int k = 1; k <= 750; ++k) {  // 30 s
    const double omega = 2.0 * 3.141592653589793 * step_frequency_hz;
    const yoyogait::YoyoPoint p = yoyogait::yoyo_point(person, omega * k * T, omega);
    e = estimator.step(p.vx_mps, p.vz_mps);  // no allocation, noexcept
  }
  std::printf("step_frequency_hz=%.4f speed_mps=%.4f R_m=%.4f r_m=%.4f\n", e.step_frequency_hz, e.speed_mps, e.R_m,
              e.r_m);
  return 0;
}
