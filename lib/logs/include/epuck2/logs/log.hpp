// Raw robot logs (docs/logs.md): one validated reader for every kind.
//
// A log is read whole and checked: required columns per kind, every numeric cell a finite number,
// physical ranges, time_s never decreasing, at least one data row. Any failure throws InputError
// naming the file, the line and the column (1-based character position and column name).
//
// What real loggers write is taken as well: LF, CRLF or lone-CR (old Mac) line ends, a UTF-8 BOM,
// one trailing delimiter at the end of a line (an empty last column), header names and metadata
// keys in any letter case (compared in lower case; the unit must still be the same), ToF codes
// >= 8190 (no target in range) in tof_mm, and `# obstacle_distance_m: 0`. With
// ReadOptions::skip_bad_rows a row with a bad cell is left out and recorded in Log::skipped
// instead of failing the whole file.
#pragma once

#include <map>
#include <optional>
#include <stdexcept>
#include <string>
#include <string_view>
#include <vector>

#include "epuck2/models/tof.hpp"

namespace epuck2::logs {

enum class Kind { battery, proximity, light, ground, camera, drive };

std::string_view to_string(Kind kind);
std::optional<Kind> parse_kind(std::string_view name);
const std::vector<Kind>& all_kinds();
/// The columns a log of this kind must have (docs/logs.md).
const std::vector<std::string>& required_columns(Kind kind);
/// The column that may stand in for a required one, or "" when none may: a battery log may carry
/// `voltage_v` instead of `charge` (a voltage-only log, as real robots report; its charge then
/// comes from a voltage->charge map, epuck2/calibrate/charge_map.hpp). Such a log is read and
/// recognised as battery; it has no `charge` column.
std::string stand_in_column(Kind kind, const std::string& required);

/// The VL53L0X time-of-flight sensor's "no target in range" code: tof_mm readings at or above it
/// are kept as read in the tof_mm column; they mean "farther than the sensor's range (2000 mm)".
inline constexpr double kTofOutOfRangeCode_mm = models::sensors::kTofOutOfRangeCode_mm;
/// True for a tof_mm reading that is the sensor's out-of-range code (>= kTofOutOfRangeCode_mm).
inline bool is_tof_out_of_range(double mm) { return mm >= kTofOutOfRangeCode_mm; }

/// `text` with every control character (bytes below 0x20 except tab, and 0x7f, NUL included)
/// written as \xHH, so that input quoted in a message cannot drive the terminal or cut it short.
std::string escape_control(std::string_view text);
/// Levenshtein distance (insertions, deletions, substitutions): the reader's and the CLI's
/// "did you mean".
std::size_t edit_distance(const std::string& a, const std::string& b);

/// Bad input: file, line (1-based, 0 when the whole file is meant), column (1-based character
/// position, 0 when none) and what was expected. The file name and the message are stored with
/// their control characters escaped (escape_control).
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

/// A 1-based line and character column in a file (0 when unknown).
struct SourcePos {
  int line = 0;
  int column = 0;
};

/// A data row left out under ReadOptions::skip_bad_rows: where its first bad cell is and why.
struct SkippedRow {
  int line = 0;
  int column = 0;
  std::string reason;  ///< control characters escaped
};

struct ReadOptions {
  /// Leave out a data row with a bad cell (not a number, not finite, out of range, not an integer,
  /// wrong number of cells) and record it in Log::skipped instead of throwing. Time going backwards
  /// stays an error: it puts the order of the rows in doubt, not one cell.
  bool skip_bad_rows = false;
};

struct Log {
  std::string path;
  Kind kind = Kind::battery;
  std::string robot;                              ///< metadata `robot`, a `robot` column, or the file stem
  std::map<std::string, std::string> metadata;    ///< `# key: value` lines before the header (keys in lower case)
  std::map<std::string, SourcePos> metadata_at;   ///< where each metadata value starts in the file
  int header_line = 0;                            ///< the header's line in the file
  std::vector<std::string> columns;               ///< header order, names in lower case
  std::map<std::string, std::vector<double>> numeric;    ///< every all-numeric column
  std::map<std::string, std::vector<std::string>> text;  ///< the other columns, kept as text
  // Text taken from the file (column names, metadata keys and values, text cells) is stored with
  // its control characters escaped (escape_control): reports can print it as it is.
  std::vector<int> line_of_row;                   ///< source line of each data row
  std::vector<int> cell_start;                    ///< 1-based character column of each cell, row-major
  std::vector<SkippedRow> skipped;                ///< rows left out (ReadOptions::skip_bad_rows), in file order

  /// The 1-based character column of a cell (0 when the column does not exist).
  int column_of(std::size_t row, const std::string& column) const;

  std::size_t rows() const { return line_of_row.size(); }
  bool has(const std::string& column) const { return numeric.count(column) != 0; }
  /// A numeric column; throws InputError (line 0) when it is missing.
  const std::vector<double>& col(const std::string& column) const;
  /// A metadata value as a number; throws InputError (at the metadata line, or at the header when
  /// the line is missing) when missing or not a number.
  double metadata_number(const std::string& key) const;
  /// Numeric columns beyond the kind's required ones (candidate covariates for diagnosis).
  std::vector<std::string> extra_numeric_columns() const;
};

/// Reads and validates one log. Without `kind` the kind is recognised from the columns.
Log read_log(const std::string& path, std::optional<Kind> kind = std::nullopt, const ReadOptions& options = {});
/// Parses a log held in memory (`name` stands for the file in messages).
Log parse_log(const std::string& content, const std::string& name, std::optional<Kind> kind = std::nullopt,
              const ReadOptions& options = {});
/// Reads a CSV in the same format with the given required numeric columns (e.g. a speed profile
/// `time_s,speed_cm_s`), with the same checks (finite numbers, time never decreasing).
Log read_table(const std::string& path, const std::vector<std::string>& columns, const ReadOptions& options = {});
/// The robots a log's `robot` column names, in the order they first appear (empty when the log has
/// no such column, or a `# robot:` line, which names the file's robot whatever the column says).
std::vector<std::string> robot_column_names(const Log& log);
/// A log whose `robot` column names several robots (robot_column_names: a logger that appends
/// several robots' sessions to one CSV), as one log per robot: each that robot's rows (their
/// numeric and text cells, lines and cell positions), `robot` that robot; the rows left out under
/// skip_bad_rows stay with the first. Any other log is returned as it is.
std::vector<Log> split_by_robot_column(Log log);

/// Reads several logs; all must be of one kind, and no file may be given twice (compared by
/// canonical path: `a.csv` and `./a.csv` are the same file).
std::vector<Log> read_logs(const std::vector<std::string>& paths, std::optional<Kind> kind = std::nullopt,
                           const ReadOptions& options = {});

}  // namespace epuck2::logs
