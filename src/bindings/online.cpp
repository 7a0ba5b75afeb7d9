// Private bindings of yoyogait::OnlineEstimator (yoyogait._core). Use yoyogait.OnlineEstimator.
#include "online.hpp"

#include <nanobind/ndarray.h>

// numpy's C API, for the per-frame path (FrameView); imported in bind_online.
#define NPY_NO_DEPRECATED_API NPY_1_7_API_VERSION
#define PY_ARRAY_UNIQUE_SYMBOL yoyogait_online_ARRAY_API
#include <numpy/arrayobject.h>

#include <atomic>
#include <cmath>
#include <cstdint>
#include <cstdio>
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
  // The Python objects the per-frame calls hand out, refilled when no one else holds them (below).
  nb::object estimates[2], predictions[2];
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

// ---------------------------------------------------------------------------------- the per-frame path
// update_frame, update_point and predict_horizon are what yoyogait.OnlineEstimator binds as its update,
// update_point and predict (no Python code per call): the frame read through the buffer protocol (no
// array object made), the result handed out in a Python object that is refilled rather than allocated
// when nothing else refers to it, and the errors raised as the package's (InputError,
// ConcurrentUseError) with the wrapper's one-line messages.

// The package's error types, given once by yoyogait.estimators.online (_core.set_online_errors);
// ValueError and ConcurrentUse until then. Owned references, kept for the process' life.
PyObject* g_input_error = nullptr;
PyObject* g_busy_error = nullptr;

[[noreturn]] void raise_input(const std::string& text) {
  PyErr_SetString(g_input_error ? g_input_error : PyExc_ValueError, text.c_str());
  throw nb::python_error();
}

// Takes the estimator's flag or raises ConcurrentUseError naming the call; released by ~Held.
struct Held {
  Held(Guarded& g, const char* what) : flag(g.busy) {
    if (flag.exchange(true, std::memory_order_acquire)) {
      if (!g_busy_error) throw ConcurrentUse("the estimator is in use");
      PyErr_SetString(g_busy_error, (std::string("OnlineEstimator.") + what +
                                     " called while another thread is using this estimator; use one estimator per "
                                     "thread or serialise the calls")
                                        .c_str());
      throw nb::python_error();
    }
  }
  ~Held() { flag.store(false, std::memory_order_release); }
  Held(const Held&) = delete;
  Held& operator=(const Held&) = delete;
  std::atomic<bool>& flag;
};

// A value handed to Python in one of the estimator's two objects of its type when only the estimator
// refers to it (so that no one can see it change: `e = est.update(...)` in a loop alternates between
// the two), else in a new object. Same values, same type as a copy; no allocation in the usual loop.
template <class T>
nb::object hand_out(nb::object (&pool)[2], const T& value) {
  for (nb::object& o : pool) {
    if (o.is_valid() && Py_REFCNT(o.ptr()) == 1) {
      *nb::inst_ptr<T>(o) = value;
      return o;
    }
  }
  nb::object fresh_object = nb::cast(value, nb::rv_policy::copy);
  for (nb::object& o : pool) {
    if (!o.is_valid() || Py_REFCNT(o.ptr()) > 1) {
      o = fresh_object;
      break;
    }
  }
  return fresh_object;
}

double seconds_of(nb::handle t) {
  if (PyFloat_Check(t.ptr())) return PyFloat_AS_DOUBLE(t.ptr());  // float and numpy.float64
  const double v = PyFloat_AsDouble(t.ptr());
  if (v == -1.0 && PyErr_Occurred()) {
    PyErr_Clear();
    raise_input(std::string("t_s must be a number in seconds, got ") + nb::repr(t).c_str());
  }
  return v;
}

// A frame's coordinates: the data of a C-contiguous, aligned, native float64 ndarray as it is (read
// through numpy's C API: the buffer protocol would build a format string and shape for each new array,
// a few hundred ns, more than the update), else of the array numpy makes from it (a list, another dtype
// or layout). The caller's reference keeps the array alive for the call, and no Python code runs in it.
class FrameView {
 public:
  // points: every point of the frame (the followed points, then the feet, of which there are `feet`).
  FrameView(nb::handle positions, std::size_t points, std::size_t feet) {
    PyObject* o = positions.ptr();
    if (!usable(o)) {
      converted_ = nb::steal(PyArray_FROMANY(o, NPY_DOUBLE, 0, 0, NPY_ARRAY_IN_ARRAY));
      if (!converted_.is_valid()) throw nb::python_error();
      o = converted_.ptr();
    }
    auto* a = reinterpret_cast<PyArrayObject*>(o);
    if (static_cast<std::size_t>(PyArray_SIZE(a)) != 3 * points) {
      std::string shape = "(";
      const int nd = PyArray_NDIM(a);
      for (int i = 0; i < nd; ++i)  // as numpy writes a shape: (3,), (1, 3)
        shape += std::to_string(PyArray_DIMS(a)[i]) + (nd == 1 ? "," : i + 1 < nd ? ", " : "");
      shape += ")";
      raise_input("positions must hold " + std::to_string(points) + " x 3 coordinates" +
                  (feet > 0 ? " (the points, then the feet)" : "") + ", got shape " + shape);
    }
    data_ = static_cast<const double*>(PyArray_DATA(a));
  }
  const double* data() const { return data_; }

 private:
  static bool usable(PyObject* o) {
    if (!PyArray_Check(o)) return false;
    auto* a = reinterpret_cast<PyArrayObject*>(o);
    return PyArray_TYPE(a) == NPY_DOUBLE && PyArray_ISCARRAY_RO(a) && PyArray_ISNOTSWAPPED(a);
  }
  const double* data_ = nullptr;
  nb::object converted_;
};

nb::object update_frame(Guarded& est, nb::handle t_s, nb::handle positions) {
  const double t = seconds_of(t_s);
  const FrameView frame(positions, est.points() + est.feet(), est.feet());
  OnlineEstimate e;
  {
    const Held held(est, "update");
    e = est.update(t, frame.data());
  }
  return hand_out(est.estimates, e);
}

nb::object update_point(Guarded& est, nb::handle t_s, double x, double y, double z) {
  if (est.points() + est.feet() != 1)
    raise_input("update_point takes one point; this estimator's frames hold " +
                std::to_string(est.points() + est.feet()) + ": update(t_s, positions)");
  const double t = seconds_of(t_s);
  const double xyz[3] = {x, y, z};
  OnlineEstimate e;
  {
    const Held held(est, "update_point");
    e = est.update(t, xyz);
  }
  return hand_out(est.estimates, e);
}

nb::object predict_horizon(Guarded& est, nb::handle horizon_s) {
  const double h = PyFloat_Check(horizon_s.ptr()) ? PyFloat_AS_DOUBLE(horizon_s.ptr()) : -1.0;
  if (!(h >= 0.0 && h <= OnlineEstimator::kMaxHorizonS)) {
    // Not a float in range: a number in range (an int, numpy's) is converted, anything else is one line.
    double v = PyFloat_AsDouble(horizon_s.ptr());
    if (v == -1.0 && PyErr_Occurred()) PyErr_Clear();
    if (!(v >= 0.0 && v <= OnlineEstimator::kMaxHorizonS)) {
      char top[32];
      std::snprintf(top, sizeof top, "%g", OnlineEstimator::kMaxHorizonS);
      raise_input(std::string("prediction horizons must be in [0, ") + top + "] s, got " + nb::repr(horizon_s).c_str());
    }
    return predict_horizon(est, nb::float_(v));
  }
  yoyogait::OnlinePrediction pr;
  {
    const Held held(est, "predict");
    pr = est.predict(h);
  }
  return hand_out(est.predictions, pr);
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
  if (_import_array() < 0) throw nb::python_error();
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
  m.def(
      "set_online_errors",
      [](nb::handle input_error, nb::handle busy_error) {
        Py_XDECREF(g_input_error);
        Py_XDECREF(g_busy_error);
        g_input_error = nb::borrow(input_error).release().ptr();
        g_busy_error = nb::borrow(busy_error).release().ptr();
      },
      "input_error"_a, "busy_error"_a, "The exception types the per-frame calls raise (InputError, ConcurrentUseError).");

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
      .def("update_frame", &update_frame, "t_s"_a, "positions"_a,
           "One frame at t_s [s]: positions of the points (k x 3, in the length unit, NaN where missing). "
           "Returns the OnlineEstimate; bad frames get a status, never an exception.")
      .def("update_point", &update_point, "t_s"_a, "x"_a, "y"_a, "z"_a,
           "update() of an estimator of one point, its coordinates as numbers (no array).")
      .def("predict_horizon", &predict_horizon, "horizon_s"_a,
           "Forward and vertical velocity horizon_s [s] after the last frame, with stds: an OnlinePrediction.")
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
      .def_prop_ro("feet_step_frequency_hz", [](const Guarded& e) { return e.feet_step_frequency_hz(); })
      .def_prop_ro("feet", [](const Guarded& e) { return e.feet(); })
      .def_prop_ro("points", [](const Guarded& e) { return e.points(); })
      .def_prop_ro("up_axis", [](const Guarded& e) { return e.up_axis(); })
      .def_prop_ro("length_unit_m", [](const Guarded& e) { return e.length_unit_m(); })
      .def_prop_ro("config", [](const Guarded& e) { return e.config(); })
      .def_prop_ro("estimate", [](const Guarded& e) { return e.estimate(); });
}
// clang-format on
