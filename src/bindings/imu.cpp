// Private bindings of yoyogait::ImuOnlineEstimator (yoyogait._core). Use yoyogait.ImuOnlineEstimator.
#include "imu.hpp"

#include <nanobind/ndarray.h>
#include <nanobind/stl/optional.h>

#include <cmath>
#include <cstdint>
#include <optional>
#include <string>
#include <type_traits>
#include <utility>

#include "yoyogait/imu.hpp"

namespace nb = nanobind;
using namespace nb::literals;
using yoyogait::ImuConfig;
using yoyogait::ImuEstimate;
using yoyogait::ImuOnlineEstimator;

namespace {

using Samples = nb::ndarray<const double, nb::c_contig, nb::device::cpu>;
using Times = nb::ndarray<const double, nb::ndim<1>, nb::c_contig, nb::device::cpu>;

template <class T>
using Stored = std::conditional_t<std::is_same_v<T, double> || std::is_same_v<T, bool>, T, std::uint8_t>;

template <class T>
std::pair<T*, nb::object> fresh(std::size_t n) {
  T* data = new T[n > 0 ? n : 1];
  nb::capsule owner(data, [](void* p) noexcept { delete[] static_cast<T*>(p); });
  return {data, nb::cast(nb::ndarray<nb::numpy, T, nb::ndim<1>>(data, {n}, owner))};
}

const double* three(const Samples& s, const char* what) {
  if (s.size() != 3) throw nb::value_error((std::string(what) + " must hold 3 values, got " + std::to_string(s.size())).c_str());
  return s.data();
}

// Every sample through update(), in C++: one array per field of ImuEstimate. mag: none or n x 3.
nb::dict run(ImuOnlineEstimator& est, const Times& time_s, const Samples& acc, const Samples& gyr,
             std::optional<Samples> mag) {
  const std::size_t n = time_s.shape(0);
  if (acc.size() != 3 * n || gyr.size() != 3 * n)
    throw nb::value_error(("acc and gyr must be " + std::to_string(n) + " x 3 like time_s, got " +
                           std::to_string(acc.size()) + " and " + std::to_string(gyr.size()) + " values")
                              .c_str());
  if (mag && mag->size() != 3 * n)
    throw nb::value_error(
        ("mag must be " + std::to_string(n) + " x 3 like time_s, got " + std::to_string(mag->size()) + " values").c_str());
  const double* mg = mag ? mag->data() : nullptr;
#define YOYO_ARRAY(type, name, ...) auto col_##name = fresh<Stored<type>>(n);
  YOYOGAIT_IMU_ESTIMATE_FIELDS(YOYO_ARRAY)
#undef YOYO_ARRAY
  {
    nb::gil_scoped_release release;
    const double* t = time_s.data();
    const double* a = acc.data();
    const double* g = gyr.data();
    for (std::size_t i = 0; i < n; ++i) {
      const ImuEstimate e = est.update(t[i], a + 3 * i, g + 3 * i, mg ? mg + 3 * i : nullptr);
#define YOYO_STORE(type, name, ...) col_##name.first[i] = static_cast<Stored<type>>(e.name);
      YOYOGAIT_IMU_ESTIMATE_FIELDS(YOYO_STORE)
#undef YOYO_STORE
      col_t_s.first[i] = std::isfinite(t[i]) ? t[i] : e.t_s;
    }
  }
  nb::dict out;
#define YOYO_PUT(type, name, ...) out[#name] = col_##name.second;
  YOYOGAIT_IMU_ESTIMATE_FIELDS(YOYO_PUT)
#undef YOYO_PUT
  out["time_s"] = out["t_s"];
  nb::del(out["t_s"]);
  return out;
}

nb::list imu_estimate_fields() {
  nb::list out;
#define YOYO_FIELD(type, name, def, unit, scope, doc) out.append(nb::make_tuple(#name, unit, doc));
  YOYOGAIT_IMU_ESTIMATE_FIELDS(YOYO_FIELD)
#undef YOYO_FIELD
  return out;
}

}  // namespace

// clang-format off: the bindings are macro chains
void bind_imu(nb::module_& m) {
  auto config_cls = nb::class_<ImuConfig>(m, "ImuConfig")
      .def(nb::init<>())
      .def("validate", [](const ImuConfig& c) -> nb::object {
        const char* e = c.validate();
        return e ? nb::cast(e) : nb::none();
      })
      .def_rw("estimator", &ImuConfig::estimator);
#define YOYO_FIELD(type, name, ...) config_cls.def_rw(#name, &ImuConfig::name);
  YOYOGAIT_IMU_FIELDS(YOYO_FIELD)
#undef YOYO_FIELD

  nb::enum_<yoyogait::ImuReason>(m, "ImuReason", nb::is_arithmetic())
      .value("OK", yoyogait::ImuReason::kOk)
      .value("NON_FINITE", yoyogait::ImuReason::kNonFinite)
      .value("TIME_NOT_INCREASING", yoyogait::ImuReason::kTimeNotIncreasing)
      .value("SATURATED", yoyogait::ImuReason::kSaturated)
      .value("GAP", yoyogait::ImuReason::kGap)
      .value("GRAVITY", yoyogait::ImuReason::kGravity)
      .value("ACQUIRING", yoyogait::ImuReason::kAcquiring)
      .value("NOT_WALKING", yoyogait::ImuReason::kNotWalking)
      .value("SPEED_IMPLAUSIBLE", yoyogait::ImuReason::kSpeedImplausible)
      .value("IRREGULAR", yoyogait::ImuReason::kIrregular)
      .value("UNCERTAIN", yoyogait::ImuReason::kUncertain);

  auto estimate_cls = nb::class_<ImuEstimate>(m, "ImuEstimate");
#define YOYO_RO(type, name, ...) estimate_cls.def_ro(#name, &ImuEstimate::name);
  YOYOGAIT_IMU_ESTIMATE_FIELDS(YOYO_RO)
#undef YOYO_RO
  estimate_cls.def("__repr__", [](const ImuEstimate& e) {
    return nb::str("ImuEstimate(t_s={:.4f}, step_frequency_hz={:.4f}, speed_mps={:.4f}, gait_phase={:.3f}, "
                   "walking={}, valid={}, reason={})")
        .format(e.t_s, e.step_frequency_hz, e.speed_mps, e.gait_phase, e.walking, e.valid, static_cast<int>(e.reason));
  });
  m.def("imu_estimate_fields", &imu_estimate_fields, "The fields of ImuEstimate: (name, unit, doc).");

  nb::class_<ImuOnlineEstimator>(m, "ImuOnlineEstimator")
      .def(nb::init<const ImuConfig&>(), "config"_a = ImuConfig{})
      .def(
          "update",
          [](ImuOnlineEstimator& est, double t_s, const Samples& acc, const Samples& gyr) {
            return est.update(t_s, three(acc, "acc"), three(gyr, "gyr"));
          },
          "t_s"_a, "acc"_a, "gyr"_a)
      .def(
          "update",
          [](ImuOnlineEstimator& est, double t_s, const Samples& acc, const Samples& gyr, const Samples& mag) {
            return est.update(t_s, three(acc, "acc"), three(gyr, "gyr"), three(mag, "mag"));
          },
          "t_s"_a, "acc"_a, "gyr"_a, "mag"_a)
      .def("run", &run, "time_s"_a, "acc"_a, "gyr"_a, "mag"_a = nb::none())
      .def("reset", &ImuOnlineEstimator::reset)
      .def_prop_ro("config", &ImuOnlineEstimator::config)
      .def_prop_ro("estimate", &ImuOnlineEstimator::estimate)
      .def_prop_ro("quaternion", [](const ImuOnlineEstimator& e) { return e.orientation().quaternion(); });
}
// clang-format on
