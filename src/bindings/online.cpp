// Private bindings of yoyogait::OnlineEstimator (yoyogait._core). Use yoyogait.OnlineEstimator.
#include "online.hpp"

#include <nanobind/ndarray.h>

#include <atomic>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <stdexcept>
#include <string>
#include <type_traits>
#include <utility>

#include "yoyogait/online.hpp"

namespace nb = nanobind;
using namespace nb::literals;
using yoyogait::OnlineConfig;
using yoyogait::OnlineEstimate;
using yoyogait::OnlineEstimator;

namespace {

// The estimator as bound: with a flag that one call at a time holds. Taken and released in C++, where
// no Python signal handler can run between the two, so that no exception leaves it set.
struct Guarded : OnlineEstimator {
  using OnlineEstimator::OnlineEstimator;
  std::atomic<bool> busy{false};
};

// Raised (as _core.ConcurrentUse) by a call made while another one is running.
struct ConcurrentUse : std::runtime_error {
  using std::runtime_error::runtime_error;
};

// Holds the flag for one call; throws ConcurrentUse when another call holds it.
class Busy {
 public:
  explicit Busy(Guarded& g) : flag_(g.busy) {
    if (flag_.exchange(true, std::memory_order_acquire)) throw ConcurrentUse("the estimator is in use");
  }
  ~Busy() { flag_.store(false, std::memory_order_release); }
  Busy(const Busy&) = delete;
  Busy& operator=(const Busy&) = delete;

 private:
  std::atomic<bool>& flag_;
};

using Positions = nb::ndarray<const double, nb::c_contig, nb::device::cpu>;
using Times = nb::ndarray<const double, nb::ndim<1>, nb::c_contig, nb::device::cpu>;

// How run() stores a field of OnlineEstimate: doubles and bools as they are, codes and counts as bytes.
template <class T>
using Stored = std::conditional_t<std::is_same_v<T, double> || std::is_same_v<T, bool>, T, std::uint8_t>;

template <class T>
std::pair<T*, nb::object> fresh(std::size_t n) {
  T* data = new T[n > 0 ? n : 1];
  nb::capsule owner(data, [](void* p) noexcept { delete[] static_cast<T*>(p); });
  return {data, nb::cast(nb::ndarray<nb::numpy, T, nb::ndim<1>>(data, {n}, owner))};
}

// Positions of one frame: k x 3 or 3k values (k: the points, then the feet).
const double* frame_of(const OnlineEstimator& est, const Positions& p) {
  const std::size_t need = 3 * (est.points() + est.feet());
  if (p.size() != need)
    throw nb::value_error(("positions must hold " + std::to_string(est.points() + est.feet()) +
                           " x 3 coordinates, got " + std::to_string(p.size()))
                              .c_str());
  return p.data();
}

// Every frame of a recording through update(), in C++: one array per field of OnlineEstimate.
// With predictions: for each frame and each horizon h of predict_ahead_s, predict(h) after the frame
// (arrays n x m, row-major).
nb::dict run(Guarded& est, const Times& time_s, const Positions& positions, const Times& predict_ahead_s) {
  const Busy busy(est);
  const std::size_t n = time_s.shape(0), k = est.points() + est.feet(), m = predict_ahead_s.shape(0);
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
  // One array per field of OnlineEstimate (YOYOGAIT_ONLINE_ESTIMATE_FIELDS): doubles as doubles,
  // bools as bools, codes and counts as bytes.
#define YOYO_ARRAY(type, name, ...) auto col_##name = fresh<Stored<type>>(n);
  YOYOGAIT_ONLINE_ESTIMATE_FIELDS(YOYO_ARRAY)
#undef YOYO_ARRAY
  auto pred_vx = fresh<double>(n * m), pred_vz = fresh<double>(n * m);
  auto pred_vx_std = fresh<double>(n * m), pred_vz_std = fresh<double>(n * m);
  {
    nb::gil_scoped_release release;
    const double* t = time_s.data();
    const double* p = positions.data();
    for (std::size_t i = 0; i < n; ++i) {
      const OnlineEstimate e = est.update(t[i], p + i * k * 3);
#define YOYO_STORE(type, name, ...) col_##name.first[i] = static_cast<Stored<type>>(e.name);
      YOYOGAIT_ONLINE_ESTIMATE_FIELDS(YOYO_STORE)
#undef YOYO_STORE
      // The run's rows are the input frames: a NaN timestamp's row carries the last one accepted.
      col_t_s.first[i] = std::isfinite(t[i]) ? t[i] : e.t_s;
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
#define YOYO_PUT(type, name, ...) out[#name] = col_##name.second;
  YOYOGAIT_ONLINE_ESTIMATE_FIELDS(YOYO_PUT)
#undef YOYO_PUT
  // The rows' time is time_s, as in every per-sample table of the package (the record's t_s).
  out["time_s"] = out["t_s"];
  nb::del(out["t_s"]);
  out["pred_vx_mps"] = pred_vx.second;
  out["pred_vz_mps"] = pred_vz.second;
  out["pred_vx_std_mps"] = pred_vx_std.second;
  out["pred_vz_std_mps"] = pred_vz_std.second;
  return out;
}

}  // namespace

// clang-format off: the bindings are macro chains
void bind_online(nb::module_& m) {
  auto config_cls = nb::class_<OnlineConfig>(m, "OnlineConfig")
      .def(nb::init<>())
      .def("validate", [](const OnlineConfig& c) -> nb::object {
        const char* e = c.validate();
        return e ? nb::cast(e) : nb::none();
      })
      .def_rw("estimator", &OnlineConfig::estimator);
#define YOYO_FIELD(type, name, ...) config_cls.def_rw(#name, &OnlineConfig::name);
  YOYOGAIT_ONLINE_FIELDS(YOYO_FIELD)
#undef YOYO_FIELD

  nb::enum_<yoyogait::OnlineStatus>(m, "OnlineStatus", nb::is_arithmetic())
      .value("USED", yoyogait::OnlineStatus::kUsed)
      .value("ALL_MISSING", yoyogait::OnlineStatus::kAllMissing)
      .value("TIME_NOT_INCREASING", yoyogait::OnlineStatus::kTimeNotIncreasing)
      .value("GAP_RESTART", yoyogait::OnlineStatus::kGapRestart)
      .value("NON_FINITE", yoyogait::OnlineStatus::kNonFinite)
      .value("TIME_JUMP", yoyogait::OnlineStatus::kTimeJump);

  nb::enum_<yoyogait::InvalidReason>(m, "InvalidReason", nb::is_arithmetic(), nb::is_flag())
      .value("ACQUIRING", yoyogait::InvalidReason::kAcquiring)
      .value("NOT_WALKING", yoyogait::InvalidReason::kNotWalking)
      .value("INPUT_NOISY", yoyogait::InvalidReason::kInputNoisy)
      .value("INPUT_MISSING", yoyogait::InvalidReason::kInputMissing)
      .value("MODEL_NOT_HOLDING", yoyogait::InvalidReason::kModelNotHolding)
      .value("IMPLAUSIBLE_INPUT", yoyogait::InvalidReason::kImplausibleInput)
      .value("RATE_TOO_LOW", yoyogait::InvalidReason::kRateTooLow)
      .value("NOT_MOVING", yoyogait::InvalidReason::kNotMoving);

  nb::exception<ConcurrentUse>(m, "ConcurrentUse", PyExc_RuntimeError);

  auto estimate_cls = nb::class_<OnlineEstimate>(m, "OnlineEstimate");
#define YOYO_RO(type, name, ...) estimate_cls.def_ro(#name, &OnlineEstimate::name);
  YOYOGAIT_ONLINE_ESTIMATE_FIELDS(YOYO_RO)
#undef YOYO_RO
  estimate_cls.def("__repr__", [](const OnlineEstimate& e) {
    return nb::str("OnlineEstimate(t_s={:.4f}, vx_mps={:.4f}, vz_mps={:.4f}, step_frequency_hz={:.4f}, "
                   "speed_mps={:.4f}, gait_phase={:.3f}, walking={}, status={})")
        .format(e.t_s, e.vx_mps, e.vz_mps, e.step_frequency_hz, e.speed_mps, e.gait_phase, e.walking,
                static_cast<int>(e.status));
  });

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

  nb::class_<Guarded>(m, "OnlineEstimator")
      .def(nb::init<std::size_t, int, double, const OnlineConfig&, std::size_t>(), "n_points"_a, "up_axis"_a,
           "length_unit_m"_a = 1.0, "config"_a = OnlineConfig{}, "n_feet"_a = 0)
      .def(
          "update",
          [](Guarded& est, double t_s, const Positions& p) {
            const double* frame = frame_of(est, p);
            const Busy busy(est);
            return est.update(t_s, frame);
          },
          "t_s"_a, "positions"_a)
      .def("run", &run, "time_s"_a, "positions"_a, "predict_ahead_s"_a)
      .def(
          "predict",
          [](Guarded& est, double h_s) {
            const Busy busy(est);
            return est.predict(h_s);
          },
          "horizon_s"_a)
      .def_prop_ro_static("max_horizon_s", [](nb::handle) { return OnlineEstimator::kMaxHorizonS; })
      .def("reset",
           [](Guarded& est) {
             const Busy busy(est);
             est.reset();
           })
      .def_prop_ro("ignored_frames", [](const Guarded& e) { return e.ignored_frames(); })
      .def(
          "set_belt_speed_mps",
          [](Guarded& est, double v) {
            const Busy busy(est);
            est.set_belt_speed_mps(v);
          },
          "speed_mps"_a)
      .def_prop_ro("belt_speed_mps", [](const Guarded& e) { return e.belt_speed_mps(); })
      .def_prop_ro("feet", [](const Guarded& e) { return e.feet(); })
      .def_prop_ro("points", [](const Guarded& e) { return e.points(); })
      .def_prop_ro("up_axis", [](const Guarded& e) { return e.up_axis(); })
      .def_prop_ro("length_unit_m", [](const Guarded& e) { return e.length_unit_m(); })
      .def_prop_ro("config", [](const Guarded& e) { return e.config(); })
      .def_prop_ro("estimate", [](const Guarded& e) { return e.estimate(); });
}
// clang-format on
