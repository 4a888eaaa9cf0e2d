// Writing results: whole or not at all (temporary file in the same folder, then rename), and
// logs in the spec's CSV format (what the virtual robot and the simulator write).
#pragma once

#include <map>
#include <string>
#include <utility>
#include <vector>

namespace epuck2::logs {

/// Writes `content` to `path` through a temporary file in the same folder and an atomic rename:
/// an existing file is either replaced whole or left untouched. Throws std::runtime_error.
void write_file_atomically(const std::string& path, const std::string& content);

/// Shortest text that reads back to the same double (up to 17 significant digits).
std::string format_number(double value);
/// Fixed number of significant digits ("%.*g").
std::string format_number(double value, int significant_digits);

/// A log in the format read_log reads (log.hpp), built in memory.
class LogWriter {
 public:
  explicit LogWriter(std::vector<std::string> columns) : columns_(std::move(columns)) {}
  void comment(const std::string& text) { comments_.push_back(text); }
  void metadata(const std::string& key, const std::string& value) { metadata_.emplace_back(key, value); }
  /// One row; values are printed with format_number unless `digits` > 0.
  void row(const std::vector<double>& values, int digits = 0);
  std::string str() const;
  std::size_t rows() const { return rows_.size(); }

 private:
  std::vector<std::string> columns_;
  std::vector<std::string> comments_;
  std::vector<std::pair<std::string, std::string>> metadata_;
  std::vector<std::string> rows_;
};

}  // namespace epuck2::logs
