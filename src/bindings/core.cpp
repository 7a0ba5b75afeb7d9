// Private bindings of the yoyogait core (yoyogait._core). Use the wrappers in yoyogait.estimator.
#include <nanobind/nanobind.h>
#include <nanobind/ndarray.h>
#include <nanobind/stl/array.h>
#include <nanobind/stl/optional.h>
#include <nanobind/stl/string.h>
#include <nanobind/stl/vector.h>

#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <mutex>
#include <new>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "online.hpp"
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

// One allocation for all the arrays of a run, each a view of it, freed with the last of them.
//
// Writing a long run's estimates into fresh pages costs more than computing them (the first touch
// of each page), so the most recently freed block (up to kMaxCached bytes) is kept for the next
// run: repeated runs over recordings reuse warm memory. At most one block is kept.
class Block {
 public:
  explicit Block(std::size_t bytes) {
    size_ = (kHeader + bytes + 63) / 64 * 64;
    base_ = cache().take(size_);
    if (!base_) base_ = static_cast<char*>(std::aligned_alloc(64, size_));
    if (!base_) throw std::bad_alloc();
    std::memcpy(base_, &size_, sizeof size_);  // read back when the block is freed
    used_ = kHeader;
    owner_ = nb::capsule(base_, [](void* p) noexcept {
      char* base = static_cast<char*>(p);
      std::size_t size;
      std::memcpy(&size, base, sizeof size);
      cache().give(base, size);
    });
  }

  /// A contiguous 1-D array of rows elements.
  template <class T>
  Owned<T> take(std::size_t rows) {
    T* data = raw<T>(rows);
    return {data, nb::cast(nb::ndarray<nb::numpy, T, nb::ndim<1>>(data, {rows}, owner_))};
  }

  /// count elements of the block, without an array.
  template <class T>
  T* raw(std::size_t count) {
    used_ = (used_ + alignof(double) - 1) / alignof(double) * alignof(double);
    T* data = reinterpret_cast<T*>(base_ + used_);
    used_ += count * sizeof(T);
    return data;
  }

  /// A view of rows x cols doubles at data, rows row_stride elements apart (cols = 0: 1-D).
  nb::object view(double* data, std::size_t rows, std::size_t cols, std::size_t row_stride) const {
    const auto stride = static_cast<int64_t>(row_stride);
    if (cols) return nb::cast(nb::ndarray<nb::numpy, double, nb::ndim<2>>(data, {rows, cols}, owner_, {stride, 1}));
    return nb::cast(nb::ndarray<nb::numpy, double, nb::ndim<1>>(data, {rows}, owner_, {stride}));
  }

 private:
  static constexpr std::size_t kHeader = 64;  // the block's size, then padding
  static constexpr std::size_t kMaxCached = std::size_t{64} << 20;

  // The kept block. Never destroyed: arrays may be freed during interpreter shutdown.
  class Cache {
   public:
    // A kept block of at least size bytes (and not much larger), or nullptr.
    char* take(std::size_t& size) {
      std::lock_guard<std::mutex> lock(mutex_);
      if (!base_ || size_ < size || size_ > 2 * size) return nullptr;
      size = size_;
      return std::exchange(base_, nullptr);
    }
    void give(char* base, std::size_t size) {
      if (size > kMaxCached) return std::free(base);
      std::lock_guard<std::mutex> lock(mutex_);
      std::free(std::exchange(base_, base));
      size_ = size;
    }

   private:
    std::mutex mutex_;
    char* base_ = nullptr;
    std::size_t size_ = 0;
  };
  static Cache& cache() {
    static Cache* c = new Cache;
    return *c;
  }

  char* base_ = nullptr;
  std::size_t size_ = 0, used_ = 0;
  nb::capsule owner_;
};

// The estimates of a run. Written for both algorithms: state, the physical estimates, status.
// The gait filter's own outputs (its 8-state, the harmonic reconstruction, lambda, the detector
// flags) are written only for it: for the paper they carry nothing new (see yoyogait::Estimate)
// and every byte per sample costs run() time.
//
// The doubles are one row-major table, each column a strided view: a step writes its values to
// one place (whole cache lines) rather than to a separate stream per column, which costs a
// long run several ns per sample more.
template <bool kGait, bool kDiag>
nb::dict run_impl(yoyogait::Estimator& est, const InArray& vx, const InArray& vz, const InArray& horizons,
                  const double* pdt) {
  constexpr std::size_t kS = yoyogait::paper::kStateDim;
  constexpr std::size_t kG = yoyogait::gait::kDim;
  const std::size_t n = vx.shape(0);
  const std::size_t nh = horizons.shape(0);
  // Column layout of a row.
  enum : std::size_t {
    kState = 0, kVx = kS, kVz, kRhat, krhat, kRm, krm, kOmega, kF, kFstd, kSpeed, kSpeedStd, kA0, kA1,
    kCommon,  // the gait filter's columns follow
    kGstate = kCommon, kVxH2 = kGstate + kG, kVzH2, kScale, kGaitEnd
  };
  // With diagnostics: innovation_vx_mps, innovation_vz_mps, nis; then vx_pred (nh), vz_pred (nh).
  const std::size_t kDiagCol = kGait ? kGaitEnd : kCommon;
  const std::size_t kPred = kDiagCol + (kDiag ? 3 : 0);
  const std::size_t width = kPred + 2 * nh;
  Block block(n * (sizeof(double) * width + (kGait ? 4 : 2)) + 64);
  double* rows = block.raw<double>(n * width);
  auto status = block.take<std::uint8_t>(n);
  auto updated = block.take<bool>(n);
  auto walking = block.take<bool>(kGait ? n : 0), acquiring = block.take<bool>(kGait ? n : 0);
  const double* px = vx.data();
  const double* pz = vz.data();
  const double* ph = horizons.data();
  {
    nb::gil_scoped_release release;
    // A local copy whose address does not escape stays in registers; the output stores could
    // otherwise alias the estimator's members and force a reload after each one.
    yoyogait::Estimator local = est;
    // One loop per form of step(), so that the loop body has no branch on it.
    const auto loop = [&](auto step) {
      for (std::size_t i = 0; i < n; ++i) {
        const Estimate e = step(local, i);
        double* r = rows + i * width;
        for (std::size_t j = 0; j < kS; ++j) r[kState + j] = e.state[j];
        r[kVx] = e.vx_hat_mps;
        r[kVz] = e.vz_hat_mps;
        r[kRhat] = e.R_hat_mps;
        r[krhat] = e.r_hat_mps;
        r[kRm] = e.R_m;
        r[krm] = e.r_m;
        r[kOmega] = e.omega_rad_s;
        r[kF] = e.step_frequency_hz;
        r[kFstd] = e.step_frequency_std_hz;
        r[kSpeed] = e.speed_mps;
        r[kSpeedStd] = e.speed_std_mps;
        r[kA0] = e.A0_mps;
        r[kA1] = e.A1_mps;
        status.data[i] = static_cast<std::uint8_t>(e.status);
        updated.data[i] = e.parameters_updated;
        if constexpr (kGait) {
          for (std::size_t j = 0; j < kG; ++j) r[kGstate + j] = e.gait_state[j];
          r[kVxH2] = e.vx_hat_h2_mps;
          r[kVzH2] = e.vz_hat_h2_mps;
          r[kScale] = e.std_scale;
          walking.data[i] = e.walking;
          acquiring.data[i] = e.acquiring;
        }
        if constexpr (kDiag) {
          const yoyogait::Innovation d = local.innovation();
          r[kDiagCol] = d.vx_mps;
          r[kDiagCol + 1] = d.vz_mps;
          r[kDiagCol + 2] = d.nis;
        }
        for (std::size_t j = 0; j < nh; ++j) {
          const yoyogait::Velocity v = local.predict_ahead(ph[j]);
          r[kPred + j] = v.vx_mps;
          r[kPred + nh + j] = v.vz_mps;
        }
      }
    };
    if (pdt) {
      loop([&](yoyogait::Estimator& e, std::size_t i) { return e.step(px[i], pz[i], pdt[i]); });
    } else {
      // step(vx, vz, sample_time_s) is step(vx, vz) bit for bit; one loop body instead of two
      // copies of the inlined filter step keeps the compiler's code for this loop as fast as the
      // one with timestamps (the second copy measured 1.3x slower).
      const double nominal_dt_s = est.config().sample_time_s;
      loop([&](yoyogait::Estimator& e, std::size_t i) { return e.step(px[i], pz[i], nominal_dt_s); });
    }
    est = local;
  }
  const auto column = [&](std::size_t c) { return block.view(rows + c, n, 0, width); };
  nb::dict out;
  out["state"] = block.view(rows + kState, n, kS, width);
  out["vx_hat"] = column(kVx);
  out["vz_hat"] = column(kVz);
  out["R_hat_mps"] = column(kRhat);
  out["r_hat_mps"] = column(krhat);
  out["R_m"] = column(kRm);
  out["r_m"] = column(krm);
  out["omega_rad_s"] = column(kOmega);
  out["step_frequency_hz"] = column(kF);
  out["step_frequency_std_hz"] = column(kFstd);
  out["speed_mps"] = column(kSpeed);
  out["speed_std_mps"] = column(kSpeedStd);
  out["A0_mps"] = column(kA0);
  out["A1_mps"] = column(kA1);
  out["status"] = status.array;
  out["parameters_updated"] = updated.array;
  if constexpr (kGait) {
    out["gait_state"] = block.view(rows + kGstate, n, kG, width);
    out["vx_hat_h2"] = column(kVxH2);
    out["vz_hat_h2"] = column(kVzH2);
    out["std_scale"] = column(kScale);
    out["walking"] = walking.array;
    out["acquiring"] = acquiring.array;
  }
  if constexpr (kDiag) {
    out["innovation_vx_mps"] = column(kDiagCol);
    out["innovation_vz_mps"] = column(kDiagCol + 1);
    out["nis"] = column(kDiagCol + 2);
  }
  if (nh) {
    out["vx_pred"] = block.view(rows + kPred, n, nh, width);
    out["vz_pred"] = block.view(rows + kPred + nh, n, nh, width);
  }
  return out;
}


// The covariance after every step, (n, k * k) row-major (k = 4 for the paper, 8 for the gait
// filter), for checks over many samples. From a pass over a copy of the estimator before run_impl
// runs: the estimator is deterministic, so the copy goes through the same states, and run_impl's
// loop stays as it is.
template <bool kGait>
nb::object covariances(const yoyogait::Estimator& est, const InArray& vx, const InArray& vz, const double* pdt) {
  constexpr std::size_t k = kGait ? yoyogait::gait::kDim : yoyogait::paper::kStateDim;
  const std::size_t n = vx.shape(0);
  auto out = owned<double>(n, k * k);
  const double* px = vx.data();
  const double* pz = vz.data();
  {
    nb::gil_scoped_release release;
    yoyogait::Estimator copy = est;
    for (std::size_t i = 0; i < n; ++i) {
      if (pdt)
        copy.step(px[i], pz[i], pdt[i]);
      else
        copy.step(px[i], pz[i]);
      double* c = out.data + i * k * k;
      if constexpr (kGait) {
        const yoyogait::GaitMatrix P = copy.gait_covariance();
        for (std::size_t a = 0; a < k; ++a)
          for (std::size_t b = 0; b < k; ++b) c[a * k + b] = P[a][b];
      } else {
        const yoyogait::Matrix4 P = copy.covariance();
        for (std::size_t a = 0; a < k; ++a)
          for (std::size_t b = 0; b < k; ++b) c[a * k + b] = P[a][b];
      }
    }
  }
  return out.array;
}

nb::dict run(yoyogait::Estimator& est, const InArray& vx, const InArray& vz, const InArray& horizons,
             const std::optional<InArray>& dt, bool diagnostics, bool covariance) {
  const std::size_t n = vx.shape(0);
  if (vz.shape(0) != n) throw nb::value_error("vx and vz must have the same length");
  if (dt && dt->shape(0) != n) throw nb::value_error("dt_s must have the length of vx");
  const double* pdt = dt ? dt->data() : nullptr;
  const bool paper = est.algorithm() == yoyogait::Algorithm::kPaper;
  nb::object cov;
  if (covariance) cov = paper ? covariances<false>(est, vx, vz, pdt) : covariances<true>(est, vx, vz, pdt);
  nb::dict out;
  if (diagnostics)
    out = paper ? run_impl<false, true>(est, vx, vz, horizons, pdt) : run_impl<true, true>(est, vx, vz, horizons, pdt);
  else
    out = paper ? run_impl<false, false>(est, vx, vz, horizons, pdt) : run_impl<true, false>(est, vx, vz, horizons, pdt);
  if (covariance) out["covariance"] = cov;
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

template <class M>
nb::object matrix(const M& m) {
  const std::size_t k = m.size();
  auto out = owned<double>(k, k);
  for (std::size_t i = 0; i < k; ++i)
    for (std::size_t j = 0; j < k; ++j) out.data[i * k + j] = m[i][j];
  return out.array;
}

const char* algorithm_name(yoyogait::Algorithm a) {
  return a == yoyogait::Algorithm::kPaper ? "paper" : "gait_filter";
}

yoyogait::Algorithm algorithm_from(const std::string& name) {
  if (name == "paper") return yoyogait::Algorithm::kPaper;
  if (name == "gait_filter") return yoyogait::Algorithm::kGaitFilter;
  throw nb::value_error(("algorithm must be 'paper' or 'gait_filter', got '" + name + "'").c_str());
}

// One field of a configuration table as a read-write attribute; the bank's frequencies as a tuple.
template <class T, class Class, class Struct>
void bind_field(Class& cls, const char* name, T Struct::*member) {
  cls.def_rw(name, member);
}
template <class Class, class Struct>
void bind_field(Class& cls, const char* name, yoyogait::FrequencyList Struct::*member) {
  cls.def_prop_rw(
      name,
      [member](const Struct& c) {
        const yoyogait::FrequencyList& f = c.*member;
        nb::list out;
        for (std::size_t i = 0; i < f.size && i < yoyogait::kMaxBankSize; ++i) out.append(f[i]);
        return nb::tuple(out);
      },
      [member, name](Struct& c, const std::vector<double>& f) {
        if (f.empty() || f.size() > yoyogait::kMaxBankSize)
          throw nb::value_error((std::string(name) + " must hold 1 to 8 frequencies").c_str());
        yoyogait::FrequencyList out;
        for (std::size_t i = 0; i < f.size(); ++i) out[i] = f[i];
        out.size = f.size();
        c.*member = out;
      });
}

nb::object py_value(double v) { return nb::float_(v); }
nb::object py_value(std::size_t v) { return nb::int_(v); }
nb::object py_value(bool v) { return nb::bool_(v); }
nb::object py_value(const yoyogait::FrequencyList& f) {
  nb::list out;
  for (std::size_t i = 0; i < f.size; ++i) out.append(f[i]);
  return nb::tuple(out);
}

// The schema of the configuration, from the tables of config.hpp: one dict per field.
nb::list config_schema() {
  nb::list out;
  const EstimatorConfig d{};
  const auto add = [&](const char* section, const char* name, const char* type, nb::object def, const char* unit,
                       const char* lo, double min, double max, const char* hi, const char* doc) {
    nb::dict f;
    f["section"] = section;
    f["name"] = name;
    f["type"] = type;
    f["default"] = def;
    f["unit"] = unit;
    f["doc"] = doc;
    f["min"] = min;
    f["max"] = max;
    f["min_inclusive"] = lo[0] == '[';
    f["max_inclusive"] = hi[0] == ']';
    out.append(f);
  };
  {
    nb::dict f;
    f["section"] = "";
    f["name"] = "algorithm";
    f["type"] = "str";
    f["default"] = algorithm_name(d.algorithm);
    f["unit"] = "";
    f["doc"] = "the estimator to run: 'gait_filter' (the default estimator) or 'paper' (the paper's, as published)";
    f["choices"] = nb::make_tuple("paper", "gait_filter");
    out.append(f);
  }
#define YOYO_SCHEMA(section, obj, type, name, def, unit, lo, min, max, hi, doc) \
  add(section, #name, yoyogait::detail::type_name<type>(), py_value(obj.name), unit, lo, static_cast<double>(min), \
      static_cast<double>(max), hi, doc);
#define YOYO_SCHEMA_SHARED(...) YOYO_SCHEMA("", d, __VA_ARGS__)
#define YOYO_SCHEMA_PAPER(...) YOYO_SCHEMA("paper_estimator", d.paper_estimator, __VA_ARGS__)
#define YOYO_SCHEMA_GAIT(...) YOYO_SCHEMA("gait_filter", d.gait_filter, __VA_ARGS__)
  YOYOGAIT_SHARED_FIELDS(YOYO_SCHEMA_SHARED)
  YOYOGAIT_PAPER_FIELDS(YOYO_SCHEMA_PAPER)
  YOYOGAIT_GAIT_FILTER_FIELDS(YOYO_SCHEMA_GAIT)
#undef YOYO_SCHEMA_SHARED
#undef YOYO_SCHEMA_PAPER
#undef YOYO_SCHEMA_GAIT
#undef YOYO_SCHEMA
  return out;
}

// An estimate with the step's diagnostics (yoyogait::Innovation), for the streaming form.
struct DiagnosedEstimate : Estimate {
  double innovation_vx_mps = 0.0, innovation_vz_mps = 0.0, nis = 0.0;
};

DiagnosedEstimate diagnosed(const yoyogait::Estimator& est, const Estimate& e) {
  const yoyogait::Innovation d = est.innovation();
  DiagnosedEstimate out;
  static_cast<Estimate&>(out) = e;
  out.innovation_vx_mps = d.vx_mps;
  out.innovation_vz_mps = d.vz_mps;
  out.nis = d.nis;
  return out;
}

}  // namespace

NB_MODULE(_core, m) {
  m.doc() = "Private bindings of the yoyogait C++ core; use yoyogait.GaitEstimator.";

  // The configuration, bound from the tables of config.hpp: every field once.
  auto paper_cls = nb::class_<yoyogait::PaperConfig>(m, "PaperConfig").def(nb::init<>());
  auto gait_cls = nb::class_<yoyogait::GaitFilterConfig>(m, "GaitFilterConfig").def(nb::init<>());
  auto config_cls = nb::class_<EstimatorConfig>(m, "EstimatorConfig");
#define YOYO_BIND(cls, Struct, type, name, ...) bind_field(cls, #name, &Struct::name);
#define YOYO_BIND_SHARED(...) YOYO_BIND(config_cls, EstimatorConfig, __VA_ARGS__)
#define YOYO_BIND_PAPER(...) YOYO_BIND(paper_cls, yoyogait::PaperConfig, __VA_ARGS__)
#define YOYO_BIND_GAIT(...) YOYO_BIND(gait_cls, yoyogait::GaitFilterConfig, __VA_ARGS__)
  YOYOGAIT_SHARED_FIELDS(YOYO_BIND_SHARED)
  YOYOGAIT_PAPER_FIELDS(YOYO_BIND_PAPER)
  YOYOGAIT_GAIT_FILTER_FIELDS(YOYO_BIND_GAIT)
#undef YOYO_BIND_SHARED
#undef YOYO_BIND_PAPER
#undef YOYO_BIND_GAIT
#undef YOYO_BIND
  config_cls.def(nb::init<>())
      .def_static("paper", &EstimatorConfig::paper)
      .def("validate", [](const EstimatorConfig& c) -> nb::object {
        const char* e = c.validate();
        return e ? nb::cast(e) : nb::none();
      })
      .def_prop_rw(
          "algorithm", [](const EstimatorConfig& c) { return std::string(algorithm_name(c.algorithm)); },
          [](EstimatorConfig& c, const std::string& name) { c.algorithm = algorithm_from(name); })
      .def_rw("paper_estimator", &EstimatorConfig::paper_estimator)
      .def_rw("gait_filter", &EstimatorConfig::gait_filter);
  m.def("config_schema", &config_schema,
        "Every field of the configuration: section, name, type, default, unit, doc, valid range.");
  m.attr("MAX_BANK_SIZE") = yoyogait::kMaxBankSize;

  nb::enum_<yoyogait::Status>(m, "Status", nb::is_arithmetic())
      .value("UPDATED", yoyogait::Status::kUpdated)
      .value("REJECTED_NON_FINITE", yoyogait::Status::kRejectedNonFinite)
      .value("REJECTED_NUMERICAL", yoyogait::Status::kRejectedNumerical)
      .value("REJECTED_OUT_OF_RANGE", yoyogait::Status::kRejectedOutOfRange)
      .value("REJECTED_OUTLIER", yoyogait::Status::kRejectedOutlier);

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
      .def_prop_ro("gait_state", [](const Estimate& e) { return e.gait_state; })
      .def_ro("vx_hat_h2", &Estimate::vx_hat_h2_mps)
      .def_ro("vz_hat_h2", &Estimate::vz_hat_h2_mps)
      .def_prop_ro("amp_z_mps", &Estimate::amp_z_mps)
      .def_prop_ro("phase_x_rel_z_rad", &Estimate::phase_x_rel_z_rad)
      .def_prop_ro("signed_amp_x_mps", &Estimate::signed_amp_x_mps)
      .def_prop_ro("omega_rate_rad_s2", &Estimate::omega_rate_rad_s2)
      .def_prop_ro("accel_mps2", &Estimate::accel_mps2)
      .def_ro("std_scale", &Estimate::std_scale)
      .def_ro("status", &Estimate::status)
      .def_ro("parameters_updated", &Estimate::parameters_updated)
      .def_ro("walking", &Estimate::walking)
      .def_ro("acquiring", &Estimate::acquiring)
      .def("__repr__", [](const Estimate& e) {
        return nb::str("Estimate(step_frequency_hz={:.4f}, speed_mps={:.4f}, R_m={:.4f}, r_m={:.4f}, "
                       "vx_hat={:.4f}, vz_hat={:.4f}, status={})")
            .format(e.step_frequency_hz, e.speed_mps, e.R_m, e.r_m, e.vx_hat_mps, e.vz_hat_mps,
                    static_cast<int>(e.status));
      });

  nb::class_<DiagnosedEstimate, Estimate>(m, "DiagnosedEstimate")
      .def_ro("innovation_vx_mps", &DiagnosedEstimate::innovation_vx_mps)
      .def_ro("innovation_vz_mps", &DiagnosedEstimate::innovation_vz_mps)
      .def_ro("nis", &DiagnosedEstimate::nis);

  nb::class_<yoyogait::Estimator>(m, "Estimator")
      .def(nb::init<const EstimatorConfig&>(), "config"_a)
      .def("step", nb::overload_cast<double, double>(&yoyogait::Estimator::step), "vx"_a, "vz"_a)
      .def("step", nb::overload_cast<double, double, double>(&yoyogait::Estimator::step), "vx"_a, "vz"_a, "dt_s"_a)
      .def("run", &run, "vx"_a, "vz"_a, "horizons_s"_a, "dt_s"_a = nb::none(), "diagnostics"_a = false,
           "covariance"_a = false)
      .def("step_diagnosed",
           [](yoyogait::Estimator& e, double vx, double vz) { return diagnosed(e, e.step(vx, vz)); }, "vx"_a, "vz"_a)
      .def("step_diagnosed",
           [](yoyogait::Estimator& e, double vx, double vz, double dt) { return diagnosed(e, e.step(vx, vz, dt)); },
           "vx"_a, "vz"_a, "dt_s"_a)
      .def("reset", &yoyogait::Estimator::reset)
      .def("predict_ahead", [](const yoyogait::Estimator& e, double h) {
        const auto v = e.predict_ahead(h);
        return std::array<double, 2>{v.vx_mps, v.vz_mps};
      })
      .def_prop_ro("state", [](const yoyogait::Estimator& e) { return e.state().x; })
      .def_prop_ro("gait_state", [](const yoyogait::Estimator& e) { return e.gait_state(); })
      .def_prop_ro("covariance", [](const yoyogait::Estimator& e) {
        return e.algorithm() == yoyogait::Algorithm::kPaper ? matrix(e.covariance()) : matrix(e.gait_covariance());
      })
      .def_prop_ro("sample_count", &yoyogait::Estimator::sample_count)
      .def_prop_ro("config", &yoyogait::Estimator::config);

  m.def("yoyo_trajectory", &yoyo_trajectory, "R_m"_a, "r_m"_a, "z0_m"_a, "time_s"_a, "step_frequency_hz"_a,
        "phase_rad"_a);
  m.def("transition", [](std::array<double, 4> x) { return yoyogait::paper::transition(yoyogait::paper::State{x}).x; });
  m.def("transition_jacobian", [](std::array<double, 4> x) {
    return matrix(yoyogait::paper::transition_jacobian(yoyogait::paper::State{x}));
  });
  m.def("gait_transition", [](const yoyogait::GaitState& x, double dt_s, double accel_decay, double rate_decay) {
    return yoyogait::gait_transition(x, dt_s, accel_decay, rate_decay);
  }, "x"_a, "dt_s"_a, "accel_decay"_a, "omega_rate_decay"_a);
  m.def("gait_transition_jacobian", [](const yoyogait::GaitState& x, double dt_s, double accel_decay, double rate_decay) {
    return matrix(yoyogait::gait_transition_jacobian(x, dt_s, accel_decay, rate_decay));
  }, "x"_a, "dt_s"_a, "accel_decay"_a, "omega_rate_decay"_a);
  bind_online(m);
}
