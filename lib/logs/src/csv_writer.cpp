#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <random>
#include <sstream>
#include <stdexcept>
#include <system_error>
#include <unistd.h>

#include "epuck2/logs/output.hpp"

namespace epuck2::logs {

std::string format_number(double value, int significant_digits) {
  char buf[64];
  std::snprintf(buf, sizeof buf, "%.*g", significant_digits, value);
  return buf;
}

std::string format_number(double value) {
  char buf[64];
  for (int digits = 6; digits <= 17; ++digits) {
    std::snprintf(buf, sizeof buf, "%.*g", digits, value);
    if (std::strtod(buf, nullptr) == value) return buf;
  }
  return buf;
}

void LogWriter::row(const std::vector<double>& values, int digits) {
  std::string line;
  for (std::size_t i = 0; i < values.size(); ++i) {
    if (!std::isfinite(values[i]))
      throw std::domain_error("row " + std::to_string(rows_.size() + 1) + ", column '" +
                              (i < columns_.size() ? columns_[i] : std::to_string(i + 1)) + "': " + format_number(values[i]) +
                              " is not a finite number; nothing was written");
    if (i) line += ',';
    line += digits > 0 ? format_number(values[i], digits) : format_number(values[i]);
  }
  rows_.push_back(std::move(line));
}

std::string LogWriter::str() const {
  std::ostringstream os;
  for (const auto& c : comments_) os << "# " << c << '\n';
  for (const auto& [k, v] : metadata_) os << "# " << k << ": " << v << '\n';
  for (std::size_t i = 0; i < columns_.size(); ++i) os << (i ? "," : "") << columns_[i];
  os << '\n';
  for (const auto& r : rows_) os << r << '\n';
  return os.str();
}

}  // namespace epuck2::logs
