// The configuration tables (config.hpp): every field is range-checked, the schema lists every field
// once, and the cross-field rules hold.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <limits>
#include <set>
#include <stdexcept>
#include <string>

#include "yoyogait/config.hpp"
#include "yoyogait/estimator.hpp"

namespace config_tests {  // one per file: the sanitizer build compiles the files as one unit
using namespace yoyogait;

namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();

// The value v in the field that access names makes the default configuration invalid, with a
// message naming the field, and the Estimator refuses it.
template <class T, class Access>
void expect_rejected(Access access, const char* name, T v) {
  EstimatorConfig c;
  access(c) = v;
  const char* msg = c.validate();
  ASSERT_NE(msg, nullptr) << name;
  EXPECT_NE(std::string(msg).find(name), std::string::npos) << msg;
  EXPECT_THROW(Estimator{c}, std::invalid_argument) << name;
}

template <class Access>
void expect_range_checked(Access access, const char* name, double v, double min, double max, const char* lo,
                          const char* hi) {
  (void)v;
  if (std::isfinite(min)) expect_rejected<double>(access, name, lo[0] == '[' ? std::nextafter(min, -kInf) : min);
  if (std::isfinite(max)) expect_rejected<double>(access, name, hi[0] == ']' ? std::nextafter(max, kInf) : max);
  expect_rejected<double>(access, name, std::numeric_limits<double>::quiet_NaN());
  expect_rejected<double>(access, name, -kInf);
}
template <class Access>
void expect_range_checked(Access access, const char* name, std::size_t, double min, double max, const char*,
                          const char*) {
  if (min > 0) expect_rejected<std::size_t>(access, name, static_cast<std::size_t>(min) - 1);
  expect_rejected<std::size_t>(access, name, static_cast<std::size_t>(max) + 1);
  expect_rejected<std::size_t>(access, name, std::size_t{1} << 63);
}
template <class Access>
void expect_range_checked(Access, const char*, bool, double, double, const char*, const char*) {}
template <class Access>
void expect_range_checked(Access access, const char* name, const FrequencyList&, double min, double max,
                          const char* lo, const char* hi) {
  expect_rejected<FrequencyList>(access, name, FrequencyList{lo[0] == '[' ? std::nextafter(min, -kInf) : min});
  expect_rejected<FrequencyList>(access, name, FrequencyList{hi[0] == ']' ? std::nextafter(max, kInf) : max});
  expect_rejected<FrequencyList>(access, name, FrequencyList{});
  expect_rejected<FrequencyList>(access, name, FrequencyList{1, 1.1, 1.2, 1.3, 1.4, 1.5, 1.6, 1.7, 1.8});
}

}  // namespace

TEST(Config, EveryFieldIsCheckedAgainstItsRange) {
  // Just outside each end of each field's range (and NaN, -inf for floats) is rejected, naming the field.
#define CHECK_SHARED(type, name, def, unit, lo, min, max, hi, doc) \
  expect_range_checked([](EstimatorConfig& c) -> type& { return c.name; }, #name, type{}, min, max, lo, hi);
#define CHECK_PAPER(type, name, def, unit, lo, min, max, hi, doc)                                                  \
  expect_range_checked([](EstimatorConfig& c) -> type& { return c.paper_estimator.name; }, "paper_estimator." #name, \
                       type{}, min, max, lo, hi);
#define CHECK_GAIT(type, name, def, unit, lo, min, max, hi, doc)                                                  \
  expect_range_checked([](EstimatorConfig& c) -> type& { return c.gait_filter.name; }, "gait_filter." #name, \
                       type{}, min, max, lo, hi);
  YOYOGAIT_SHARED_FIELDS(CHECK_SHARED)
  YOYOGAIT_PAPER_FIELDS(CHECK_PAPER)
  YOYOGAIT_GAIT_FILTER_FIELDS(CHECK_GAIT)
#undef CHECK_SHARED
#undef CHECK_PAPER
#undef CHECK_GAIT
}

TEST(Config, DefaultsAreInsideTheirRanges) {
  // Both presets validate, and every default lies in its field's range.
  EXPECT_EQ(EstimatorConfig{}.validate(), nullptr);
  EXPECT_EQ(EstimatorConfig::paper().validate(), nullptr);
  const EstimatorConfig d{};
#define IN_RANGE(obj, type, name, def, unit, lo, min, max, hi, doc) \
  EXPECT_TRUE(detail::in_range(obj.name, min, max, lo, hi)) << #name;
#define IN_SHARED(...) IN_RANGE(d, __VA_ARGS__)
#define IN_PAPER(...) IN_RANGE(d.paper_estimator, __VA_ARGS__)
#define IN_GAIT(...) IN_RANGE(d.gait_filter, __VA_ARGS__)
  YOYOGAIT_SHARED_FIELDS(IN_SHARED)
  YOYOGAIT_PAPER_FIELDS(IN_PAPER)
  YOYOGAIT_GAIT_FILTER_FIELDS(IN_GAIT)
#undef IN_SHARED
#undef IN_PAPER
#undef IN_GAIT
#undef IN_RANGE
}

TEST(Config, TheSchemaListsEveryFieldOnceWithItsRange) {
  // kConfigFields has one entry per table row, unique per section, each with a doc, a type and min <= max.
  std::size_t rows = 0;
#define COUNT(...) ++rows;
  YOYOGAIT_SHARED_FIELDS(COUNT)
  YOYOGAIT_PAPER_FIELDS(COUNT)
  YOYOGAIT_GAIT_FILTER_FIELDS(COUNT)
#undef COUNT
  ASSERT_EQ(sizeof(kConfigFields) / sizeof(kConfigFields[0]), rows);
  std::set<std::string> seen;
  for (const FieldSpec& f : kConfigFields) {
    EXPECT_TRUE(seen.insert(std::string(f.section) + "." + f.name).second) << f.name;
    EXPECT_GT(std::strlen(f.doc), 10u) << f.name;
    EXPECT_LE(f.min, f.max) << f.name;
    const std::string type = f.type;
    EXPECT_TRUE(type == "float" || type == "int" || type == "bool" || type == "float_list") << f.name;
  }
}

TEST(Config, AnInfiniteGateIsAllowedAndTurnsTheGateOff) {
  // gate_sigma = infinity is in range (the bound is inclusive) and no sample is then flagged as an outlier.
  EstimatorConfig c;
  c.gait_filter.gate_sigma = kInf;
  ASSERT_EQ(c.validate(), nullptr);
  Estimator est(c);
  for (int i = 0; i < 500; ++i) {
    const double t = 0.04 * i;
    const Estimate e = est.step(1.2 + 0.1 * std::cos(11.3 * t) + (i % 50 == 49 ? 3.0 : 0.0), 0.08 * std::sin(11.3 * t));
    ASSERT_NE(e.status, Status::kRejectedOutlier) << i;
  }
}

}  // namespace config_tests
