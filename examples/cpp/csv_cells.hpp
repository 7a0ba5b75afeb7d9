// The cells of one input line as numbers, for the example filters (online_stdin, imu_stdin).
#pragma once

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <vector>

namespace example {

// A cell as a number: NaN for an empty cell or "nan"; false if it is not a number.
inline bool parse_cell(std::string cell, std::vector<double>& out) {
  while (!cell.empty() && (cell.back() == ' ' || cell.back() == '\r' || cell.back() == '\t')) cell.pop_back();
  const std::size_t lead = cell.find_first_not_of(" \t");
  cell = lead == std::string::npos ? std::string() : cell.substr(lead);
  if (cell.empty()) {
    out.push_back(std::nan(""));
    return true;
  }
  char* stop = nullptr;
  const double v = std::strtod(cell.c_str(), &stop);
  if (stop == cell.c_str() || *stop != '\0') return false;
  out.push_back(v);
  return true;
}

// The cells of a line separated by commas or, in a line without a comma, by spaces or tabs (as
// many sensor streams print them); false if a cell is not a number (a header or a comment line).
inline bool parse_cells(const std::string& line, std::vector<double>& out) {
  out.clear();
  const bool commas = line.find(',') != std::string::npos;
  const char* seps = commas ? "," : " \t\r";
  std::size_t start = commas ? 0 : line.find_first_not_of(seps);
  while (start != std::string::npos && start <= line.size()) {
    std::size_t end = line.find_first_of(seps, start);
    if (end == std::string::npos) end = line.size();
    if (!parse_cell(line.substr(start, end - start), out)) return false;
    start = commas ? end + 1 : line.find_first_not_of(seps, end);
  }
  return true;
}

// Says once on stderr that lines are being skipped, from the second on (the first may be a header):
// a stream of lines that are not numbers must not pass in silence.
class SkipNote {
 public:
  explicit SkipNote(const char* program) : program_(program) {}
  void skipped(const std::string& line) {
    if (++count_ == 2)
      std::fprintf(stderr, "%s: skipping lines that are not numbers separated by commas or spaces, e.g. \"%.60s\"\n",
                   program_, line.c_str());
  }

 private:
  const char* program_;
  long count_ = 0;
};

}  // namespace example
