// A tethered-guidance admittance controller that uses yoyogait's oscillation-free walking velocity.
//
//   guide_controller                 handle frames as CSV lines on standard input: t_s,x_m,y_m,z_m
//   guide_controller --synthetic     a built-in SYNTHETIC walk of the handle (Yoyo model, 1.2 m/s, 1.8 steps/s)
//
// The robot is a point mass at a fixed height, admittance-controlled in the floor plane (Tognon, Alami,
// Siciliano, IEEE T-RO 37(3), 2021, and its human-state-aware follow-up; docs/guidance.md):
//   M_A dv_R/dt = -B_A v_R - f_c + u_A,   u_A = K_H e_R + f_c^r + B_A v_H_hat,
// with v_H_hat the estimate's walking velocity (speed along the heading, no step oscillation), gated on
// the estimate's valid flag. The cable (1 m, k_c) pulls only when taut. The handle moves as given (the
// walker is not simulated here): the controller keeps its reference point a cable's length ahead of the
// handle along the walking direction and pulls with f_c^r along it.
// Output, one line per frame: t_s, walking, valid, speed_mps, vh_hat_x_mps, vh_hat_y_mps, u_x_n, u_y_n,
// robot_x_m, robot_y_m, robot_vx_mps, robot_vy_mps, tension_n
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <string>
#include <yoyogait/online.hpp>

namespace {

struct Admittance {
  double mass_kg = 0.8;          // M_A (T-RO 2021)
  double damping_ns_per_m = 2.4; // B_A (T-RO 2021)
  double gain_n_per_m = 1.8;     // K_H = B_A^2 / (4 M_A): critically damped position loop
  double max_speed_mps = 2.0;
  double reference_force_n = 5.0;
  double cable_m = 1.0, stiffness_n_per_m = 300.0, height_m = 0.5;
  double x = 0, y = 0, z = 0, vx = 0, vy = 0;
  bool started = false;

  // The cable's force on the handle (the robot feels the opposite); zero when slack.
  void cable(const double h[3], double f[3]) const {
    const double lx = x - h[0], ly = y - h[1], lz = z - h[2];
    const double d = std::sqrt(lx * lx + ly * ly + lz * lz);
    const double k = d > cable_m ? stiffness_n_per_m * (d - cable_m) / d : 0.0;
    f[0] = k * lx;
    f[1] = k * ly;
    f[2] = k * lz;
  }

  // One frame interval dt_s with the command (ux, uy) held, integrated in 10 sub-steps.
  void step(double dt_s, const double h[3], double ux, double uy, double f[3]) {
    const int n = 10;
    const double dt = dt_s / n;
    for (int i = 0; i < n; ++i) {
      cable(h, f);
      vx += (-damping_ns_per_m * vx - f[0] + ux) / mass_kg * dt;
      vy += (-damping_ns_per_m * vy - f[1] + uy) / mass_kg * dt;
      const double s = std::hypot(vx, vy);
      if (s > max_speed_mps) {
        vx *= max_speed_mps / s;
        vy *= max_speed_mps / s;
      }
      x += vx * dt;
      y += vy * dt;
    }
  }
};

// The built-in SYNTHETIC handle: a Yoyo-model walk along +x after 1 s standing (1.2 m/s, 1.8 steps/s,
// r = 2 cm forward and vertical oscillation), 0.2 m to the right of the path.
void synthetic_handle(double t, double h[3]) {
  const double start = 1.0, ramp = 1.5, f_hz = 1.8, speed = 1.2, r = 0.02;
  const double u = t < start ? 0.0 : (t > start + ramp ? 1.0 : (t - start) / ramp);
  const double g = u * u * (3.0 - 2.0 * u);  // smooth start
  static double theta = 0.0, x = 0.0, last_t = 0.0;
  const double dt = t - last_t;
  last_t = t;
  theta += 2.0 * 3.14159265358979 * f_hz * g * dt;
  x += speed * g * dt;
  h[0] = x - g * r * std::sin(theta);
  h[1] = -0.2;
  h[2] = 1.0 + g * r * std::cos(theta);
}

}  // namespace

int main(int argc, char** argv) {
  const bool synthetic = argc > 1 && std::strcmp(argv[1], "--synthetic") == 0;
  if (argc > 1 && !synthetic) {
    std::fprintf(stderr, "guide_controller: the only option is --synthetic (else frames t_s,x_m,y_m,z_m on stdin)\n");
    return 2;
  }
  yoyogait::OnlineEstimator est(1, 2, 1.0);  // one point (the handle), z up, metres
  Admittance robot;
  std::printf(
      "t_s,walking,valid,speed_mps,vh_hat_x_mps,vh_hat_y_mps,u_x_n,u_y_n,robot_x_m,robot_y_m,robot_vx_mps,"
      "robot_vy_mps,tension_n\n");
  double t_last = 0.0, h[3] = {0, 0, 0}, f[3] = {0, 0, 0};
  char buf[4096];
  for (long k = 0;; ++k) {
    double t = 0.0;
    if (synthetic) {
      if (k > 1500) break;  // 15 s at 100 Hz
      t = k / 100.0;
      synthetic_handle(t, h);
    } else {
      if (!std::fgets(buf, sizeof buf, stdin)) break;
      if (std::sscanf(buf, "%lf,%lf,%lf,%lf", &t, &h[0], &h[1], &h[2]) != 4) continue;  // header, comment
    }
    const yoyogait::OnlineEstimate e = est.update(t, h);  // noexcept, no allocation
    if (e.status == yoyogait::OnlineStatus::kTimeNotIncreasing || e.status == yoyogait::OnlineStatus::kNonFinite)
      continue;
    if (!robot.started) {  // hover a cable's length ahead (+x) at the handle's height + height_m
      robot.x = h[0] + std::sqrt(robot.cable_m * robot.cable_m - robot.height_m * robot.height_m);
      robot.y = h[1];
      robot.z = h[2] + robot.height_m;
      robot.started = true;
      t_last = t;
    }
    const bool walking = e.walking;
    // The gate: the walking velocity is fed forward only while the estimate may be used (valid); while it
    // is acquiring, or says its model does not hold, the robot follows the cable alone.
    const bool use = e.valid;
    const double vhx = use ? e.walk_a_mps : 0.0, vhy = use ? e.walk_b_mps : 0.0;
    const double cx = std::cos(e.heading_rad), cy = std::sin(e.heading_rad);
    const double lead = std::sqrt(robot.cable_m * robot.cable_m - robot.height_m * robot.height_m);
    const double fr = walking || t > 1.0 ? robot.reference_force_n : 0.0;
    const double ux = robot.gain_n_per_m * (h[0] + lead * cx - robot.x) + fr * cx + robot.damping_ns_per_m * vhx;
    const double uy = robot.gain_n_per_m * (h[1] + lead * cy - robot.y) + fr * cy + robot.damping_ns_per_m * vhy;
    robot.step(t - t_last, h, ux, uy, f);
    t_last = t;
    std::printf("%.3f,%d,%d,%.4f,%.4f,%.4f,%.4f,%.4f,%.4f,%.4f,%.4f,%.4f,%.4f\n", t, walking ? 1 : 0, use ? 1 : 0,
                e.speed_mps, vhx, vhy, ux, uy, robot.x, robot.y, robot.vx, robot.vy,
                std::sqrt(f[0] * f[0] + f[1] * f[1] + f[2] * f[2]));
  }
  return 0;
}
