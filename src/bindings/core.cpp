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
#include <type_traits>
#include <utility>
#include <vector>

#include "imu.hpp"
#include "online.hpp"
#include "yoyogait/imu/imu_config.hpp"
#include "yoyogait/imu/imu_estimate.hpp"
#include "yoyogait/online/online_config.hpp"
#include "yoyogait/online/online_estimate.hpp"
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
// Where each field of Estimate goes in a run (YOYOGAIT_ESTIMATE_FIELDS): a double is a column of
// the row-major table, anything else (Status, bool) an array of its own. Columns: the 4-state, the
// double fields of scope kAll, then (gait filter only) the 8-state and the double fields of scope kGait.
enum EstimateField : std::size_t {
#define YOYO_FIELD_ENUM(type, name, ...) kField_##name,
  YOYOGAIT_ESTIMATE_FIELDS(YOYO_FIELD_ENUM)
#undef YOYO_FIELD_ENUM
  kEstimateFieldCount
};
struct FieldLayout {
  bool is_double;
  yoyogait::FieldScope scope;
};
constexpr FieldLayout kEstimateLayout[] = {
#define YOYO_LAYOUT(type, name, def, unit, scope, doc) {std::is_same_v<type, double>, yoyogait::FieldScope::scope},
    YOYOGAIT_ESTIMATE_FIELDS(YOYO_LAYOUT)
#undef YOYO_LAYOUT
};
constexpr std::size_t kStateCols = yoyogait::paper::kStateDim, kGaitStateCols = yoyogait::gait::kDim;
// Number of double fields of a scope before field f (or in all, f = kEstimateFieldCount).
constexpr std::size_t doubles_before(std::size_t f, yoyogait::FieldScope scope) {
  std::size_t n = 0;
  for (std::size_t i = 0; i < f; ++i) n += kEstimateLayout[i].is_double && kEstimateLayout[i].scope == scope;
  return n;
}
constexpr std::size_t kCommonEnd = kStateCols + doubles_before(kEstimateFieldCount, yoyogait::FieldScope::kAll);
constexpr std::size_t kGaitStateCol = kCommonEnd;
constexpr std::size_t kGaitEnd =
    kGaitStateCol + kGaitStateCols + doubles_before(kEstimateFieldCount, yoyogait::FieldScope::kGait);
// The column of double field f.
constexpr std::size_t column_of(std::size_t f) {
  return kEstimateLayout[f].scope == yoyogait::FieldScope::kAll
             ? kStateCols + doubles_before(f, yoyogait::FieldScope::kAll)
             : kGaitStateCol + kGaitStateCols + doubles_before(f, yoyogait::FieldScope::kGait);
}
// The array type of a field that is not a column: bool stays bool, a code is its byte.
template <class T>
using ByteOf = std::conditional_t<std::is_same_v<T, bool>, bool, std::uint8_t>;

// The estimates of a run. Written for both algorithms: state and the fields of scope kAll. The
// fields of scope kGait (the 8-state, the harmonic reconstruction, lambda, the detector flags) are
// written only for the gait filter: for the paper they carry nothing new (see yoyogait::Estimate)
// and every byte per sample costs run() time.
//
// The doubles are one row-major table, each column a strided view: a step writes its values to
// one place (whole cache lines) rather than to a separate stream per column, which costs a
// long run several ns per sample more.
template <bool kGait, bool kDiag>
nb::dict run_impl(yoyogait::Estimator& est, const InArray& vx, const InArray& vz, const InArray& horizons,
                  const double* pdt) {
  using yoyogait::FieldScope;
  const std::size_t n = vx.shape(0);
  const std::size_t nh = horizons.shape(0);
  // With diagnostics: the Innovation fields; then vx_pred (nh), vz_pred (nh).
  constexpr std::size_t kInnovationCols = 3;
  const std::size_t kDiagCol = kGait ? kGaitEnd : kCommonEnd;
  const std::size_t kPred = kDiagCol + (kDiag ? kInnovationCols : 0);
  const std::size_t width = kPred + 2 * nh;
  Block block(n * (sizeof(double) * width + kEstimateFieldCount) + 64);
  double* rows = block.raw<double>(n * width);
  // One array per field that is not a column, in the table's order (absent for the paper's kGait ones).
#define YOYO_BYTES(type, name, def, unit, scope, doc)                                                          \
  auto bytes_##name = block.take<ByteOf<type>>(                                                                \
      std::is_same_v<type, double> || (FieldScope::scope == FieldScope::kGait && !kGait) ? 0 : n);
  YOYOGAIT_ESTIMATE_FIELDS(YOYO_BYTES)
#undef YOYO_BYTES
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
        for (std::size_t j = 0; j < kStateCols; ++j) r[j] = e.state[j];
        if constexpr (kGait)
          for (std::size_t j = 0; j < kGaitStateCols; ++j) r[kGaitStateCol + j] = e.gait_state[j];
#define YOYO_STORE(type, name, def, unit, scope, doc)                                          \
  if constexpr (FieldScope::scope == FieldScope::kAll || kGait) {                              \
    if constexpr (std::is_same_v<type, double>)                                                \
      r[column_of(kField_##name)] = e.name;                                                    \
    else                                                                                       \
      bytes_##name.data[i] = static_cast<ByteOf<type>>(e.name);                                \
  }
        YOYOGAIT_ESTIMATE_FIELDS(YOYO_STORE)
#undef YOYO_STORE
        if constexpr (kDiag) {
          const yoyogait::Innovation d = local.innovation();
          std::size_t c = kDiagCol;
#define YOYO_STORE_DIAG(type, name, ...) r[c++] = d.name;
          YOYOGAIT_INNOVATION_FIELDS(YOYO_STORE_DIAG)
#undef YOYO_STORE_DIAG
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
  out["state"] = block.view(rows, n, kStateCols, width);
  if constexpr (kGait) out["gait_state"] = block.view(rows + kGaitStateCol, n, kGaitStateCols, width);
#define YOYO_PUT(type, name, def, unit, scope, doc)                                         \
  if constexpr (FieldScope::scope == FieldScope::kAll || kGait) {                           \
    if constexpr (std::is_same_v<type, double>)                                             \
      out[#name] = column(column_of(kField_##name));                                        \
    else                                                                                    \
      out[#name] = bytes_##name.array;                                                      \
  }
  YOYOGAIT_ESTIMATE_FIELDS(YOYO_PUT)
#undef YOYO_PUT
  if constexpr (kDiag) {
    std::size_t c = kDiagCol;
#define YOYO_PUT_DIAG(type, name, ...) out[#name] = column(c++);
    YOYOGAIT_INNOVATION_FIELDS(YOYO_PUT_DIAG)
#undef YOYO_PUT_DIAG
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
  const yoyogait::OnlineConfig online{};
#define YOYO_SCHEMA_ONLINE(...) YOYO_SCHEMA("online", online, __VA_ARGS__)
  YOYOGAIT_ONLINE_FIELDS(YOYO_SCHEMA_ONLINE)
#undef YOYO_SCHEMA_ONLINE
  const yoyogait::ImuConfig imu{};
#define YOYO_SCHEMA_IMU(...) YOYO_SCHEMA("imu", imu, __VA_ARGS__)
  YOYOGAIT_IMU_FIELDS(YOYO_SCHEMA_IMU)
#undef YOYO_SCHEMA_IMU
#undef YOYO_SCHEMA_SHARED
#undef YOYO_SCHEMA_PAPER
#undef YOYO_SCHEMA_GAIT
#undef YOYO_SCHEMA
  return out;
}

// An estimate with the step's diagnostics (yoyogait::Innovation), for the streaming form.
struct DiagnosedEstimate : Estimate {
  YOYOGAIT_INNOVATION_FIELDS(YOYOGAIT_RECORD_MEMBER)
};

DiagnosedEstimate diagnosed(const yoyogait::Estimator& est, const Estimate& e) {
  const yoyogait::Innovation d = est.innovation();
  DiagnosedEstimate out;
  static_cast<Estimate&>(out) = e;
#define YOYO_COPY(type, name, ...) out.name = d.name;
  YOYOGAIT_INNOVATION_FIELDS(YOYO_COPY)
#undef YOYO_COPY
  return out;
}

// The type of a record field as the schema names it.
template <class T>
const char* record_type() {
  if constexpr (std::is_same_v<T, double>) return "float";
  if constexpr (std::is_same_v<T, bool>) return "bool";
  return "uint8";
}

nb::dict record_field(const char* name, const char* type, const char* unit, const char* scope, const char* doc) {
  nb::dict f;
  f["name"] = name;
  f["type"] = type;
  f["unit"] = unit;
  f["scope"] = scope;
  f["doc"] = doc;
  return f;
}

// Every per-sample record, from its table: record name -> list of fields (name, type, unit, scope, doc).
// Estimate also lists its two state vectors first and its derived values (type "derived") last.
nb::dict record_schema() {
  nb::dict out;
  nb::list est;
  est.append(record_field("state", "float[4]", "", "all", "the paper's state form [x1, x2, x3, x4] (eq. 5)"));
  est.append(record_field("gait_state", "float[8]", "", "gait", "the gait filter's state [X1, X2, Z1, Z2, w, A0, dA0, dw]"));
#define YOYO_SCOPE(scope) (yoyogait::FieldScope::scope == yoyogait::FieldScope::kAll ? "all" : "gait")
#define YOYO_SCHEMA(type, name, def, unit, scope, doc) \
  list.append(record_field(#name, record_type<type>(), unit, YOYO_SCOPE(scope), doc));
  {
    nb::list& list = est;
    YOYOGAIT_ESTIMATE_FIELDS(YOYO_SCHEMA)
#define YOYO_SCHEMA_DERIVED(name, unit, doc) list.append(record_field(#name, "derived", unit, "all", doc));
    YOYOGAIT_ESTIMATE_DERIVED(YOYO_SCHEMA_DERIVED)
#undef YOYO_SCHEMA_DERIVED
  }
  out["Estimate"] = est;
  {
    nb::list list;
    YOYOGAIT_INNOVATION_FIELDS(YOYO_SCHEMA)
    out["Innovation"] = list;
  }
  {
    nb::list list;
    YOYOGAIT_ONLINE_ESTIMATE_FIELDS(YOYO_SCHEMA)
    out["OnlineEstimate"] = list;
  }
  {
    nb::list list;
    YOYOGAIT_IMU_ESTIMATE_FIELDS(YOYO_SCHEMA)
    out["ImuEstimate"] = list;
  }
#undef YOYO_SCHEMA
#undef YOYO_SCOPE
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

  // Estimate, Innovation: every field of their tables, under the table's name.
  auto estimate_cls = nb::class_<Estimate>(m, "Estimate")
      .def_prop_ro("state", [](const Estimate& e) { return e.state.x; })
      .def_prop_ro("gait_state", [](const Estimate& e) { return e.gait_state; });
#define YOYO_RO(type, name, ...) estimate_cls.def_ro(#name, &Estimate::name);
#define YOYO_DERIVED(name, ...) estimate_cls.def_prop_ro(#name, &Estimate::name);
  YOYOGAIT_ESTIMATE_FIELDS(YOYO_RO)
  YOYOGAIT_ESTIMATE_DERIVED(YOYO_DERIVED)
#undef YOYO_DERIVED
#undef YOYO_RO
  estimate_cls.def("__repr__", [](const Estimate& e) {
    return nb::str("Estimate(step_frequency_hz={:.4f}, speed_mps={:.4f}, R_m={:.4f}, r_m={:.4f}, "
                   "vx_hat_mps={:.4f}, vz_hat_mps={:.4f}, status={})")
        .format(e.step_frequency_hz, e.speed_mps, e.R_m, e.r_m, e.vx_hat_mps, e.vz_hat_mps,
                static_cast<int>(e.status));
  });

  auto diagnosed_cls = nb::class_<DiagnosedEstimate, Estimate>(m, "DiagnosedEstimate");
#define YOYO_RO(type, name, ...) diagnosed_cls.def_ro(#name, &DiagnosedEstimate::name);
  YOYOGAIT_INNOVATION_FIELDS(YOYO_RO)
#undef YOYO_RO
  m.def("record_schema", &record_schema,
        "Every per-sample record (Estimate, Innovation, OnlineEstimate): its fields' names, types, units, docs.");

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
  bind_imu(m);
}
