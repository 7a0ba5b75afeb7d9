// Online gait estimation from one lower-back IMU as a filter: samples as lines on standard
// input, one estimate per sample as a CSV line on standard output, flushed at once (a pipe to an
// exoskeleton's or a walking aid's controller).
//
//   imu_stdin [SENSOR_HEIGHT_M [FORWARD_AXIS]]   SENSOR_HEIGHT_M: the sensor's height above the floor,
//                                                standing (the inverted pendulum's length; default
//                                                0.95); FORWARD_AXIS: x, y, z, -x, -y or -z, the sensor
//                                                axis pointing forward (default z)
// Input line:  t_s, ax, ay, az, gx, gy, gz [, mx, my, mz]   (specific force in m/s^2, angular rate in
//              rad/s, both in the sensor frame; an optional magnetometer in any unit; cells separated
//              by commas, or by spaces or tabs; an empty cell or "nan" makes the sample non-finite:
//              ignored; lines that are not numbers are skipped, from the second on with a note on stderr)
// Output line: every field of yoyogait::ImuEstimate (include/yoyogait/imu/imu_estimate.hpp), in its
//              order, its name in the header; booleans and enums as integers.
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <stdexcept>
#include <string>
#include <vector>
#include <yoyogait/imu.hpp>

#include "csv_cells.hpp"

namespace {

// One field as a printed number: the record's types are double, bool and small enums.
double number(double v) { return v; }
double number(bool v) { return v ? 1.0 : 0.0; }
template <class E>
double number(E v) {
  return static_cast<double>(static_cast<int>(v));
}

}  // namespace

int main(int argc, char** argv) {
  yoyogait::ImuConfig config;
  if (argc > 1) {
    char* stop = nullptr;
    config.sensor_height_m = std::strtod(argv[1], &stop);
    if (stop == argv[1] || *stop != '\0') {
      std::fprintf(stderr, "imu_stdin: SENSOR_HEIGHT_M must be a number of metres, not '%s'\n", argv[1]);
      return 2;
    }
  }
  if (argc > 2) {
    const char* a = argv[2];
    const bool negative = a[0] == '-';
    const char axis = a[negative ? 1 : 0];
    if (std::strlen(a) != (negative ? 2u : 1u) || (axis != 'x' && axis != 'y' && axis != 'z')) {
      std::fprintf(stderr, "imu_stdin: FORWARD_AXIS must be x, y, z, -x, -y or -z, not '%s'\n", a);
      return 2;
    }
    config.forward_axis = static_cast<std::size_t>(axis - 'x');
    config.forward_negative = negative;
  }
  try {
    yoyogait::ImuOnlineEstimator est(config);  // checks the settings: throws std::invalid_argument
    // The header: the record's field names, declared once.
    const char* sep = "";
#define YOYOGAIT_EXAMPLE_NAME(type, name, def, unit, scope, doc) \
  std::printf("%s%s", sep, #name);                               \
  sep = ",";
    YOYOGAIT_IMU_ESTIMATE_FIELDS(YOYOGAIT_EXAMPLE_NAME)
#undef YOYOGAIT_EXAMPLE_NAME
    std::printf("\n");
    std::fflush(stdout);
    std::vector<double> cells;
    example::SkipNote skip("imu_stdin");
    std::string line;
    char buf[4096];
    while (std::fgets(buf, sizeof buf, stdin)) {
      line = buf;
      while (!line.empty() && (line.back() == '\n' || line.back() == '\r')) line.pop_back();
      if (line.find_first_not_of(" \t\r") == std::string::npos) continue;  // a blank line
      if (!example::parse_cells(line, cells)) {  // a header or a comment
        skip.skipped(line);
        continue;
      }
      if (cells.size() != 7 && cells.size() != 10) {
        std::fprintf(stderr, "imu_stdin: a sample is t_s, ax, ay, az, gx, gy, gz [, mx, my, mz]; got %zu cells\n",
                     cells.size());
        return 2;
      }
      // noexcept, no allocation; a non-finite sample is ignored (reason NON_FINITE), the estimate carried.
      const yoyogait::ImuEstimate e = cells.size() == 10 ? est.update(cells[0], &cells[1], &cells[4], &cells[7])
                                                         : est.update(cells[0], &cells[1], &cells[4]);
      // A controller acts on an estimate only where valid is 1; reason holds why not (ImuReason).
      sep = "";
      // The time to the microsecond (a clock that counts from an epoch has ten digits before the point).
#define YOYOGAIT_EXAMPLE_VALUE(type, name, def, unit, scope, doc)                          \
  std::printf(std::strcmp(#name, "t_s") == 0 ? "%s%.6f" : "%s%.9g", sep, number(e.name)); \
  sep = ",";
      YOYOGAIT_IMU_ESTIMATE_FIELDS(YOYOGAIT_EXAMPLE_VALUE)
#undef YOYOGAIT_EXAMPLE_VALUE
      std::printf("\n");
      std::fflush(stdout);
    }
  } catch (const std::invalid_argument& err) {
    std::fprintf(stderr, "imu_stdin: %s\n", err.what());
    return 2;
  }
  return 0;
}
