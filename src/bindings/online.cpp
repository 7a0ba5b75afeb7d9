// Private bindings of yoyogait::OnlineEstimator (yoyogait._core). Use yoyogait.OnlineEstimator.
#include "online.hpp"

#include <nanobind/ndarray.h>

#include <cmath>
#include <cstdint>
#include <cstring>
#include <string>
#include <utility>

#include "yoyogait/online.hpp"

namespace nb = nanobind;
using namespace nb::literals;
using yoyogait::OnlineConfig;
using yoyogait::OnlineEstimate;
using yoyogait::OnlineEstimator;

namespace {

using Positions = nb::ndarray<const double, nb::c_contig, nb::device::cpu>;
using Times = nb::ndarray<const double, nb::ndim<1>, nb::c_contig, nb::device::cpu>;

template <class T>
std::pair<T*, nb::object> fresh(std::size_t n) {
  T* data = new T[n > 0 ? n : 1];
  nb::capsule owner(data, [](void* p) noexcept { delete[] static_cast<T*>(p); });
  return {data, nb::cast(nb::ndarray<nb::numpy, T, nb::ndim<1>>(data, {n}, owner))};
}

// Positions of one frame: k x 3 or 3k values.
const double* frame_of(const OnlineEstimator& est, const Positions& p) {
  const std::size_t need = 3 * est.points();
  if (p.size() != need)
    throw nb::value_error(
        ("positions must hold " + std::to_string(est.points()) + " x 3 coordinates, got " + std::to_string(p.size()))
            .c_str());
  return p.data();
}

// Every frame of a recording through update(), in C++: one array per field of OnlineEstimate.
// With predictions: for each frame and each horizon h of predict_ahead_s, predict(h) after the frame
// (arrays n x m, row-major).
nb::dict run(OnlineEstimator& est, const Times& time_s, const Positions& positions, const Times& predict_ahead_s) {
  const std::size_t n = time_s.shape(0), k = est.points(), m = predict_ahead_s.shape(0);
  for (std::size_t j = 0; j < m; ++j) {
    const double h = predict_ahead_s.data()[j];
    if (!(h >= 0.0 && h <= OnlineEstimator::kMaxHorizonS))
      throw nb::value_error(("predict_ahead_s must be in [0, " + std::to_string(OnlineEstimator::kMaxHorizonS) +
                             "] s, got " + std::to_string(h))
                                .c_str());
  }
  if (positions.size() != n * k * 3)
    throw nb::value_error(("positions must be frames x " + std::to_string(k) + " x 3 with " + std::to_string(n) +
                           " frames, got " + std::to_string(positions.size()) + " values")
                              .c_str());
  // clang-format off: the field lists are macro chains
#define YOYO_DOUBLE(name) auto name = fresh<double>(n);
#define YOYO_FIELDS(X)                                                                                             \
  X(vx_mps) X(vz_mps) X(vh_a_mps) X(vh_b_mps) X(heading_rad) X(walk_a_mps) X(walk_b_mps) X(vx_hat_mps)            \
  X(vz_hat_mps) X(step_frequency_hz) X(step_frequency_std_hz) X(speed_mps) X(speed_std_mps) X(gait_phase)         \
  X(input_latency_s) X(estimate_age_s) X(next_step_in_s)
  YOYO_FIELDS(YOYO_DOUBLE)
#undef YOYO_DOUBLE
  // clang-format on
  auto t_out = fresh<double>(n);
  auto status = fresh<std::uint8_t>(n);
  auto estimator_status = fresh<std::uint8_t>(n);
  auto walking = fresh<bool>(n);
  auto fed = fresh<bool>(n);
  auto seen = fresh<std::uint8_t>(n);
  auto pred_vx = fresh<double>(n * m), pred_vz = fresh<double>(n * m);
  auto pred_vx_std = fresh<double>(n * m), pred_vz_std = fresh<double>(n * m);
  {
    nb::gil_scoped_release release;
    const double* t = time_s.data();
    const double* p = positions.data();
    for (std::size_t i = 0; i < n; ++i) {
      const OnlineEstimate e = est.update(t[i], p + i * k * 3);
#define YOYO_STORE(name) name.first[i] = e.name;
      YOYO_FIELDS(YOYO_STORE)
#undef YOYO_STORE
      t_out.first[i] = std::isfinite(t[i]) ? t[i] : e.t_s;  // the row of a NaN timestamp: the last one accepted
      status.first[i] = static_cast<std::uint8_t>(e.status);
      estimator_status.first[i] = static_cast<std::uint8_t>(e.estimator_status);
      walking.first[i] = e.walking;
      fed.first[i] = e.estimator_fed;
      seen.first[i] = e.points_seen;
      for (std::size_t j = 0; j < m; ++j) {
        const yoyogait::OnlinePrediction pr = est.predict(predict_ahead_s.data()[j]);
        pred_vx.first[i * m + j] = pr.vx_mps;
        pred_vz.first[i * m + j] = pr.vz_mps;
        pred_vx_std.first[i * m + j] = pr.vx_std_mps;
        pred_vz_std.first[i * m + j] = pr.vz_std_mps;
      }
    }
  }
  nb::dict out;
#define YOYO_PUT(name) out[#name] = name.second;
  YOYO_FIELDS(YOYO_PUT)
#undef YOYO_PUT
#undef YOYO_FIELDS
  out["time_s"] = t_out.second;
  out["status"] = status.second;
  out["estimator_status"] = estimator_status.second;
  out["walking"] = walking.second;
  out["estimator_fed"] = fed.second;
  out["points_seen"] = seen.second;
  out["pred_vx_mps"] = pred_vx.second;
  out["pred_vz_mps"] = pred_vz.second;
  out["pred_vx_std_mps"] = pred_vx_std.second;
  out["pred_vz_std_mps"] = pred_vz_std.second;
  return out;
}

}  // namespace

// clang-format off: the bindings are macro chains
void bind_online(nb::module_& m) {
#define YOYO_FIELD(name) .def_rw(#name, &OnlineConfig::name)
  nb::class_<OnlineConfig>(m, "OnlineConfig")
      .def(nb::init<>())
      .def("validate", [](const OnlineConfig& c) -> nb::object {
        const char* e = c.validate();
        return e ? nb::cast(e) : nb::none();
      })
      YOYO_FIELD(estimator) YOYO_FIELD(antialias_hz) YOYO_FIELD(q_jerk_m2_per_s5) YOYO_FIELD(meas_position_std_m)
      YOYO_FIELD(initial_velocity_std_mps) YOYO_FIELD(initial_accel_std_mps2) YOYO_FIELD(settle_s)
      YOYO_FIELD(centre_blend_tau_s) YOYO_FIELD(centre_forget_s) YOYO_FIELD(max_abs_position_m)
      YOYO_FIELD(max_gap_s) YOYO_FIELD(heading_tau_s) YOYO_FIELD(heading_min_speed_mps) YOYO_FIELD(latency_f_hz);
#undef YOYO_FIELD

  nb::enum_<yoyogait::OnlineStatus>(m, "OnlineStatus", nb::is_arithmetic())
      .value("USED", yoyogait::OnlineStatus::kUsed)
      .value("ALL_MISSING", yoyogait::OnlineStatus::kAllMissing)
      .value("TIME_NOT_INCREASING", yoyogait::OnlineStatus::kTimeNotIncreasing)
      .value("GAP_RESTART", yoyogait::OnlineStatus::kGapRestart)
      .value("NON_FINITE", yoyogait::OnlineStatus::kNonFinite);

#define YOYO_RO(name) .def_ro(#name, &OnlineEstimate::name)
  nb::class_<OnlineEstimate>(m, "OnlineEstimate")
      YOYO_RO(t_s) YOYO_RO(vx_mps) YOYO_RO(vz_mps) YOYO_RO(vh_a_mps) YOYO_RO(vh_b_mps) YOYO_RO(heading_rad)
      YOYO_RO(walk_a_mps) YOYO_RO(walk_b_mps) YOYO_RO(vx_hat_mps) YOYO_RO(vz_hat_mps) YOYO_RO(step_frequency_hz)
      YOYO_RO(step_frequency_std_hz) YOYO_RO(speed_mps) YOYO_RO(speed_std_mps) YOYO_RO(gait_phase)
      YOYO_RO(input_latency_s) YOYO_RO(estimate_age_s) YOYO_RO(next_step_in_s) YOYO_RO(status) YOYO_RO(estimator_status)
      YOYO_RO(walking) YOYO_RO(estimator_fed) YOYO_RO(points_seen)
      .def("__repr__", [](const OnlineEstimate& e) {
        return nb::str("OnlineEstimate(t_s={:.4f}, vx_mps={:.4f}, vz_mps={:.4f}, step_frequency_hz={:.4f}, "
                       "speed_mps={:.4f}, gait_phase={:.3f}, walking={}, status={})")
            .format(e.t_s, e.vx_mps, e.vz_mps, e.step_frequency_hz, e.speed_mps, e.gait_phase, e.walking,
                    static_cast<int>(e.status));
      });
#undef YOYO_RO

  nb::class_<yoyogait::OnlinePrediction>(m, "OnlinePrediction")
      .def_ro("t_s", &yoyogait::OnlinePrediction::t_s)
      .def_ro("horizon_s", &yoyogait::OnlinePrediction::horizon_s)
      .def_ro("vx_mps", &yoyogait::OnlinePrediction::vx_mps)
      .def_ro("vz_mps", &yoyogait::OnlinePrediction::vz_mps)
      .def_ro("vx_std_mps", &yoyogait::OnlinePrediction::vx_std_mps)
      .def_ro("vz_std_mps", &yoyogait::OnlinePrediction::vz_std_mps)
      .def_ro("valid", &yoyogait::OnlinePrediction::valid)
      .def("__repr__", [](const yoyogait::OnlinePrediction& p) {
        return nb::str("OnlinePrediction(t_s={:.4f}, horizon_s={:.3f}, vx_mps={:.4f}+-{:.4f}, vz_mps={:.4f}+-{:.4f}, "
                       "valid={})")
            .format(p.t_s, p.horizon_s, p.vx_mps, p.vx_std_mps, p.vz_mps, p.vz_std_mps, p.valid);
      });

  nb::class_<OnlineEstimator>(m, "OnlineEstimator")
      .def(nb::init<std::size_t, int, double, const OnlineConfig&>(), "n_points"_a, "up_axis"_a,
           "length_unit_m"_a = 1.0, "config"_a = OnlineConfig{})
      .def(
          "update",
          [](OnlineEstimator& est, double t_s, const Positions& p) { return est.update(t_s, frame_of(est, p)); },
          "t_s"_a, "positions"_a)
      .def("run", &run, "time_s"_a, "positions"_a, "predict_ahead_s"_a)
      .def("predict", &OnlineEstimator::predict, "horizon_s"_a)
      .def_prop_ro_static("max_horizon_s", [](nb::handle) { return OnlineEstimator::kMaxHorizonS; })
      .def("reset", &OnlineEstimator::reset)
      .def_prop_ro("points", &OnlineEstimator::points)
      .def_prop_ro("up_axis", &OnlineEstimator::up_axis)
      .def_prop_ro("length_unit_m", &OnlineEstimator::length_unit_m)
      .def_prop_ro("config", &OnlineEstimator::config)
      .def_prop_ro("estimate", &OnlineEstimator::estimate);
}
// clang-format on
