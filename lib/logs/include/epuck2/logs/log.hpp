// Raw robot logs (docs/logs.md): one validated reader for every kind.
//
// A log is read whole and checked: required columns per kind, every numeric cell a finite number,
// physical ranges, time_s never decreasing, at least one data row. Any failure throws InputError
// naming the file, the line and the column (1-based character position and column name).
#pragma once

#include <map>
#include <optional>
#include <stdexcept>
#include <string>
#include <string_view>
#include <vector>

namespace epuck2::logs {

enum class Kind { battery, proximity, light, ground, camera, drive };

std::string_view to_string(Kind kind);
std::optional<Kind> parse_kind(std::string_view name);
const std::vector<Kind>& all_kinds();
/// The columns a log of this kind must have (docs/logs.md).
const std::vector<std::string>& required_columns(Kind kind);

/// Bad input: file, line (1-based, 0 when the whole file is meant), column (1-based character
/// position, 0 when none) and what was expected.
class InputError : public std::runtime_error {
 public:
  InputError(std::string file, int line, int column, std::string message);
  const std::string& file() const { return file_; }
  int line() const { return line_; }
  int column() const { return column_; }
  const std::string& message() const { return message_; }

 private:
  std::string file_;
  int line_;
  int column_;
  std::string message_;
};

struct Log {
  std::string path;
  Kind kind = Kind::battery;
  std::string robot;                              ///< metadata `robot`, a `robot` column, or the file stem
  std::map<std::string, std::string> metadata;    ///< `# key: value` lines before the header
  std::vector<std::string> columns;               ///< header order
  std::map<std::string, std::vector<double>> numeric;    ///< every all-numeric column
  std::map<std::string, std::vector<std::string>> text;  ///< the other columns, kept as text
  std::vector<int> line_of_row;                   ///< source line of each data row
  std::vector<int> cell_start;                    ///< 1-based character column of each cell, row-major

  /// The 1-based character column of a cell (0 when the column does not exist).
  int column_of(std::size_t row, const std::string& column) const;

  std::size_t rows() const { return line_of_row.size(); }
  bool has(const std::string& column) const { return numeric.count(column) != 0; }
  /// A numeric column; throws InputError (line 0) when it is missing.
  const std::vector<double>& col(const std::string& column) const;
  /// A metadata value as a number; throws InputError when missing or not a number.
  double metadata_number(const std::string& key) const;
  /// Numeric columns beyond the kind's required ones (candidate covariates for diagnosis).
  std::vector<std::string> extra_numeric_columns() const;
};

/// Reads and validates one log. Without `kind` the kind is recognised from the columns.
Log read_log(const std::string& path, std::optional<Kind> kind = std::nullopt);
/// Parses a log held in memory (`name` stands for the file in messages).
Log parse_log(const std::string& content, const std::string& name, std::optional<Kind> kind = std::nullopt);
/// Reads a CSV in the same format with the given required numeric columns (e.g. a speed profile
/// `time_s,speed_cm_s`), with the same checks (finite numbers, time never decreasing).
Log read_table(const std::string& path, const std::vector<std::string>& columns);
/// Reads several logs; all must be of one kind.
std::vector<Log> read_logs(const std::vector<std::string>& paths, std::optional<Kind> kind = std::nullopt);

}  // namespace epuck2::logs
