// The cells of one CSV line as numbers, for the example filters (online_stdin, imu_stdin).
#pragma once

#include <cmath>
#include <cstdlib>
#include <string>
#include <vector>

namespace example {

// NaN for an empty cell or "nan"; false if a cell is not a number (a header or a comment line).
inline bool parse_cells(const std::string& line, std::vector<double>& out) {
  out.clear();
  std::size_t start = 0;
  while (start <= line.size()) {
    std::size_t end = line.find(',', start);
    if (end == std::string::npos) end = line.size();
    std::string cell = line.substr(start, end - start);
    while (!cell.empty() && (cell.back() == ' ' || cell.back() == '\r' || cell.back() == '\t')) cell.pop_back();
    std::size_t lead = cell.find_first_not_of(" \t");
    cell = lead == std::string::npos ? std::string() : cell.substr(lead);
    if (cell.empty()) {
      out.push_back(std::nan(""));
    } else {
      char* stop = nullptr;
      const double v = std::strtod(cell.c_str(), &stop);
      if (stop == cell.c_str() || *stop != '\0') return false;
      out.push_back(v);
    }
    start = end + 1;
  }
  return true;
}

}  // namespace example
