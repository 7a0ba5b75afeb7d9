// Online gait estimation as a filter: motion-capture frames as lines on standard input, one
// estimate per frame as a CSV line on standard output, flushed at once (a pipe to a controller).
//
//   online_stdin [UP_AXIS] [LENGTH_UNIT_M]    UP_AXIS: x, y or z (default z); LENGTH_UNIT_M: metres
//                                            per coordinate unit (default 1; 0.001 for millimetres)
// Input line:  t_s, x1, y1, z1, x2, y2, z2, ...   (the number of points from the first frame, <= 16;
//              cells separated by commas, or by spaces or tabs; an empty cell or "nan" is a missing
//              coordinate; lines that are not numbers are skipped, from the second on with a note on stderr)
// Output line: t_s, vx_mps, vz_mps, vx_hat_mps, vz_hat_mps, step_frequency_hz, step_frequency_std_hz,
//              speed_mps, speed_std_mps, heading_rad, gait_phase, walking, status, valid, invalid_reason
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <memory>
#include <string>
#include <vector>

#include <yoyogait/online.hpp>

#include "csv_cells.hpp"

int main(int argc, char** argv) {
  int up = 2;
  if (argc > 1) {
    const char a = argv[1][0];
    if (std::strlen(argv[1]) != 1 || (a != 'x' && a != 'y' && a != 'z')) {
      std::fprintf(stderr, "online_stdin: UP_AXIS must be x, y or z, not '%s'\n", argv[1]);
      return 2;
    }
    up = a - 'x';
  }
  const double unit = argc > 2 ? std::strtod(argv[2], nullptr) : 1.0;
  if (!(unit > 0.0 && std::isfinite(unit))) {
    std::fprintf(stderr, "online_stdin: LENGTH_UNIT_M must be a number > 0\n");
    return 2;
  }
  std::unique_ptr<yoyogait::OnlineEstimator> est;
  std::size_t n_points = 0;
  std::vector<double> cells, frame;
  example::SkipNote skip("online_stdin");
  std::string line;
  std::printf(
      "t_s,vx_mps,vz_mps,vx_hat_mps,vz_hat_mps,step_frequency_hz,step_frequency_std_hz,speed_mps,speed_std_mps,"
      "heading_rad,gait_phase,walking,status,valid,invalid_reason\n");
  std::fflush(stdout);
  char buf[65536];
  while (std::fgets(buf, sizeof buf, stdin)) {
    line = buf;
    while (!line.empty() && (line.back() == '\n' || line.back() == '\r')) line.pop_back();
    if (line.find_first_not_of(" \t\r") == std::string::npos) continue;  // a blank line
    if (!example::parse_cells(line, cells)) {  // a header or a comment
      skip.skipped(line);
      continue;
    }
    if (!est) {
      if (cells.size() < 4 || (cells.size() - 1) % 3 != 0 || (cells.size() - 1) / 3 > yoyogait::online::kMaxPoints) {
        std::fprintf(stderr, "online_stdin: a frame is t followed by x, y, z of 1 to 16 points; got %zu cells\n",
                     cells.size());
        return 2;
      }
      n_points = (cells.size() - 1) / 3;
      est = std::make_unique<yoyogait::OnlineEstimator>(n_points, up, unit);
      frame.resize(3 * n_points);
    }
    for (std::size_t i = 0; i < frame.size(); ++i) frame[i] = i + 1 < cells.size() ? cells[i + 1] : std::nan("");
    const double t = cells[0];
    const yoyogait::OnlineEstimate e = est->update(t, frame.data());  // noexcept, no allocation
    // A controller acts on an estimate only where valid is 1; invalid_reason holds why not (InvalidReason bits).
    std::printf("%.6f,%.6g,%.6g,%.6g,%.6g,%.6g,%.6g,%.6g,%.6g,%.6g,%.6g,%d,%d,%d,%d\n", std::isfinite(t) ? t : e.t_s,
                e.vx_mps, e.vz_mps, e.vx_hat_mps, e.vz_hat_mps, e.step_frequency_hz, e.step_frequency_std_hz,
                e.speed_mps, e.speed_std_mps, e.heading_rad, e.gait_phase, e.walking ? 1 : 0,
                static_cast<int>(e.status), e.valid ? 1 : 0, static_cast<int>(e.invalid_reason));
    std::fflush(stdout);
  }
  return 0;
}
