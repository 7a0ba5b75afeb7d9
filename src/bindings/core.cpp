// Private bindings of the yoyogait core (yoyogait._core). Use the wrappers in yoyogait.estimator.
#include <nanobind/nanobind.h>
#include <nanobind/ndarray.h>
#include <nanobind/stl/array.h>

#include <cstdint>
#include <cstdlib>
#include <new>
#include <vector>
#ifdef __linux__
#include <sys/mman.h>
#endif

#include "yoyogait/yoyogait.hpp"

namespace nb = nanobind;
using namespace nb::literals;
using yoyogait::Estimate;
using yoyogait::EstimatorConfig;

namespace {

using InArray = nb::ndarray<const double, nb::ndim<1>, nb::c_contig, nb::device::cpu>;

template <class T>
struct Owned {
  T* data;
  nb::object array;
};

// A numpy array that owns fresh memory, freed with it.
template <class T>
Owned<T> owned(std::size_t rows, std::size_t cols = 0) {
  const std::size_t n = cols ? rows * cols : rows;
  T* data = new T[n > 0 ? n : 1];
  nb::capsule owner(data, [](void* p) noexcept { delete[] static_cast<T*>(p); });
  if (cols) {
    return {data, nb::cast(nb::ndarray<nb::numpy, T, nb::ndim<2>>(data, {rows, cols}, owner))};
  }
  return {data, nb::cast(nb::ndarray<nb::numpy, T, nb::ndim<1>>(data, {rows}, owner))};
}

// One allocation for all the arrays of a run, each a view of it. First touch of fresh pages is
// what a long run() spends most time on; one large block advised for huge pages faults far less
// often than many small ones.
class Block {
 public:
  explicit Block(std::size_t bytes) {
    constexpr std::size_t kHuge = std::size_t{1} << 21;
    const std::size_t align = bytes >= kHuge ? kHuge : 64;
    size_ = (bytes + align - 1) / align * align;
    base_ = static_cast<char*>(std::aligned_alloc(align, size_ ? size_ : align));
    if (!base_) throw std::bad_alloc();
#ifdef __linux__
    if (align == kHuge) madvise(base_, size_, MADV_HUGEPAGE);
#endif
    owner_ = nb::capsule(base_, [](void* p) noexcept { std::free(p); });
  }

  template <class T>
  Owned<T> take(std::size_t rows, std::size_t cols = 0) {
    const std::size_t n = cols ? rows * cols : rows;
    used_ = (used_ + alignof(double) - 1) / alignof(double) * alignof(double);
    T* data = reinterpret_cast<T*>(base_ + used_);
    used_ += n * sizeof(T);
    if (cols) return {data, nb::cast(nb::ndarray<nb::numpy, T, nb::ndim<2>>(data, {rows, cols}, owner_))};
    return {data, nb::cast(nb::ndarray<nb::numpy, T, nb::ndim<1>>(data, {rows}, owner_))};
  }

 private:
  char* base_ = nullptr;
  std::size_t size_ = 0, used_ = 0;
  nb::capsule owner_;
};

nb::dict run(yoyogait::Estimator& est, const InArray& vx, const InArray& vz, const InArray& horizons) {
  const std::size_t n = vx.shape(0);
  if (vz.shape(0) != n) throw nb::value_error("vx and vz must have the same length");
  const std::size_t nh = horizons.shape(0);
  const std::size_t nhc = nh ? nh : 1;
  Block block(n * (sizeof(double) * (yoyogait::kStateDim + 13 + 2 * nhc) + 2) + 64);
  auto state = block.take<double>(n, yoyogait::kStateDim);
  auto vx_hat = block.take<double>(n), vz_hat = block.take<double>(n), R_hat = block.take<double>(n);
  auto r_hat = block.take<double>(n), R_m = block.take<double>(n), r_m = block.take<double>(n);
  auto omega = block.take<double>(n), f = block.take<double>(n), f_std = block.take<double>(n);
  auto speed = block.take<double>(n), speed_std = block.take<double>(n);
  auto a0 = block.take<double>(n), a1 = block.take<double>(n);
  auto pvx = block.take<double>(n, nhc), pvz = block.take<double>(n, nhc);
  auto status = block.take<std::uint8_t>(n);
  auto updated = block.take<bool>(n);
  const double* px = vx.data();
  const double* pz = vz.data();
  const double* ph = horizons.data();
  {
    nb::gil_scoped_release release;
    // A local copy whose address does not escape stays in registers; the output stores could
    // otherwise alias the estimator's members and force a reload after each one.
    yoyogait::Estimator local = est;
    for (std::size_t i = 0; i < n; ++i) {
      const Estimate e = local.step(px[i], pz[i]);
      for (std::size_t j = 0; j < yoyogait::kStateDim; ++j) state.data[i * yoyogait::kStateDim + j] = e.state[j];
      vx_hat.data[i] = e.vx_hat_mps;
      vz_hat.data[i] = e.vz_hat_mps;
      R_hat.data[i] = e.R_hat_mps;
      r_hat.data[i] = e.r_hat_mps;
      R_m.data[i] = e.R_m;
      r_m.data[i] = e.r_m;
      omega.data[i] = e.omega_rad_s;
      f.data[i] = e.step_frequency_hz;
      f_std.data[i] = e.step_frequency_std_hz;
      speed.data[i] = e.speed_mps;
      speed_std.data[i] = e.speed_std_mps;
      a0.data[i] = e.A0_mps;
      a1.data[i] = e.A1_mps;
      status.data[i] = static_cast<std::uint8_t>(e.status);
      updated.data[i] = e.parameters_updated;
      for (std::size_t j = 0; j < nh; ++j) {
        const yoyogait::Velocity v = local.predict_ahead(ph[j]);
        pvx.data[i * nh + j] = v.vx_mps;
        pvz.data[i * nh + j] = v.vz_mps;
      }
    }
    est = local;
  }
  nb::dict out;
  out["state"] = state.array;
  out["vx_hat"] = vx_hat.array;
  out["vz_hat"] = vz_hat.array;
  out["R_hat_mps"] = R_hat.array;
  out["r_hat_mps"] = r_hat.array;
  out["R_m"] = R_m.array;
  out["r_m"] = r_m.array;
  out["omega_rad_s"] = omega.array;
  out["step_frequency_hz"] = f.array;
  out["step_frequency_std_hz"] = f_std.array;
  out["speed_mps"] = speed.array;
  out["speed_std_mps"] = speed_std.array;
  out["A0_mps"] = a0.array;
  out["A1_mps"] = a1.array;
  out["status"] = status.array;
  out["parameters_updated"] = updated.array;
  if (nh) {
    out["vx_pred"] = pvx.array;
    out["vz_pred"] = pvz.array;
  }
  return out;
}

nb::dict yoyo_trajectory(double R_m, double r_m, double z0_m, const InArray& time_s, const InArray& f_hz,
                         double phase_rad) {
  const std::size_t n = time_s.shape(0);
  if (f_hz.shape(0) != n) throw nb::value_error("time_s and step_frequency_hz must have the same length");
  std::vector<yoyogait::YoyoPoint> pts(n);
  yoyogait::yoyo_trajectory(yoyogait::YoyoParams{R_m, r_m, z0_m}, time_s.data(), f_hz.data(), n, phase_rad,
                            pts.data());
  auto theta = owned<double>(n), x = owned<double>(n), z = owned<double>(n), vx = owned<double>(n),
       vz = owned<double>(n);
  for (std::size_t i = 0; i < n; ++i) {
    theta.data[i] = pts[i].theta_rad;
    x.data[i] = pts[i].x_m;
    z.data[i] = pts[i].z_m;
    vx.data[i] = pts[i].vx_mps;
    vz.data[i] = pts[i].vz_mps;
  }
  nb::dict out;
  out["theta_rad"] = theta.array;
  out["x_m"] = x.array;
  out["z_m"] = z.array;
  out["vx_mps"] = vx.array;
  out["vz_mps"] = vz.array;
  return out;
}

nb::object matrix(const yoyogait::Matrix4& m) {
  auto out = owned<double>(4, 4);
  for (std::size_t i = 0; i < 4; ++i)
    for (std::size_t j = 0; j < 4; ++j) out.data[i * 4 + j] = m[i][j];
  return out.array;
}

}  // namespace

NB_MODULE(_core, m) {
  m.doc() = "Private bindings of the yoyogait C++ core; use yoyogait.GaitEstimator.";

#define YOYO_FIELD(name) .def_rw(#name, &EstimatorConfig::name)
  nb::class_<EstimatorConfig>(m, "EstimatorConfig")
      .def(nb::init<>())
      .def_static("paper", &EstimatorConfig::paper)
      .def("validate", [](const EstimatorConfig& c) -> nb::object {
        const char* e = c.validate();
        return e ? nb::cast(e) : nb::none();
      })
      YOYO_FIELD(sample_time_s) YOYO_FIELD(initial_R_hat_mps) YOYO_FIELD(initial_r_hat_mps)
      YOYO_FIELD(initial_omega_rad_per_sample) YOYO_FIELD(q_oscillation_mps2) YOYO_FIELD(q_omega_rad2)
      YOYO_FIELD(q_bias_mps2) YOYO_FIELD(v_vx_mps2) YOYO_FIELD(v_vz_mps2) YOYO_FIELD(p0_oscillation_mps2)
      YOYO_FIELD(p0_omega_rad2) YOYO_FIELD(p0_bias_mps2) YOYO_FIELD(smoothing_window_samples)
      YOYO_FIELD(gate_omega_rad_per_sample) YOYO_FIELD(gate_bias_mps) YOYO_FIELD(max_abs_velocity_mps);
#undef YOYO_FIELD

  nb::enum_<yoyogait::Status>(m, "Status", nb::is_arithmetic())
      .value("UPDATED", yoyogait::Status::kUpdated)
      .value("REJECTED_NON_FINITE", yoyogait::Status::kRejectedNonFinite)
      .value("REJECTED_NUMERICAL", yoyogait::Status::kRejectedNumerical)
      .value("REJECTED_OUT_OF_RANGE", yoyogait::Status::kRejectedOutOfRange);

  nb::class_<Estimate>(m, "Estimate")
      .def_prop_ro("state", [](const Estimate& e) { return e.state.x; })
      .def_ro("vx_hat", &Estimate::vx_hat_mps)
      .def_ro("vz_hat", &Estimate::vz_hat_mps)
      .def_ro("R_hat_mps", &Estimate::R_hat_mps)
      .def_ro("r_hat_mps", &Estimate::r_hat_mps)
      .def_ro("R_m", &Estimate::R_m)
      .def_ro("r_m", &Estimate::r_m)
      .def_ro("omega_rad_s", &Estimate::omega_rad_s)
      .def_ro("step_frequency_hz", &Estimate::step_frequency_hz)
      .def_ro("step_frequency_std_hz", &Estimate::step_frequency_std_hz)
      .def_ro("speed_mps", &Estimate::speed_mps)
      .def_ro("speed_std_mps", &Estimate::speed_std_mps)
      .def_ro("A0_mps", &Estimate::A0_mps)
      .def_ro("A1_mps", &Estimate::A1_mps)
      .def_ro("status", &Estimate::status)
      .def_ro("parameters_updated", &Estimate::parameters_updated)
      .def("__repr__", [](const Estimate& e) {
        return nb::str("Estimate(step_frequency_hz={:.4f}, speed_mps={:.4f}, R_m={:.4f}, r_m={:.4f}, "
                       "vx_hat={:.4f}, vz_hat={:.4f}, status={})")
            .format(e.step_frequency_hz, e.speed_mps, e.R_m, e.r_m, e.vx_hat_mps, e.vz_hat_mps,
                    static_cast<int>(e.status));
      });

  nb::class_<yoyogait::Estimator>(m, "Estimator")
      .def(nb::init<const EstimatorConfig&>(), "config"_a)
      .def("step", &yoyogait::Estimator::step, "vx"_a, "vz"_a)
      .def("run", &run, "vx"_a, "vz"_a, "horizons_samples"_a)
      .def("reset", &yoyogait::Estimator::reset)
      .def("predict_ahead", [](const yoyogait::Estimator& e, double h) {
        const auto v = e.predict_ahead(h);
        return std::array<double, 2>{v.vx_mps, v.vz_mps};
      })
      .def_prop_ro("state", [](const yoyogait::Estimator& e) { return e.state().x; })
      .def_prop_ro("covariance", [](const yoyogait::Estimator& e) { return matrix(e.covariance()); })
      .def_prop_ro("sample_count", &yoyogait::Estimator::sample_count)
      .def_prop_ro("config", &yoyogait::Estimator::config);

  m.def("yoyo_trajectory", &yoyo_trajectory, "R_m"_a, "r_m"_a, "z0_m"_a, "time_s"_a, "step_frequency_hz"_a,
        "phase_rad"_a);
  m.def("transition", [](std::array<double, 4> x) { return yoyogait::transition(yoyogait::State{x}).x; });
  m.def("transition_jacobian",
        [](std::array<double, 4> x) { return matrix(yoyogait::transition_jacobian(yoyogait::State{x})); });
}
