// A measured log to replay in ARGoS (scripts/argos-record.sh KIND FILE OUT --like LOG), read
// through the project's one log reader (lib/logs): what each row asks ARGoS to set up (the
// conditions), which columns ARGoS writes (the readings), and the replay written in the log's own
// format, row for row. Needs no ARGoS (the protocol loop functions use it). The header does not
// include lib/logs' (ARGoS's math headers define a macro `Log`).
#pragma once

#include <map>
#include <string>
#include <vector>

namespace epuck2::argos_replay {

struct ReplayLog {
  /* The log as lib/logs read it (epuck2::logs::Log's fields of the same names) */
  std::string path;
  std::map<std::string, std::string> metadata;
  std::map<std::string, std::vector<double>> numeric;
  std::map<std::string, std::vector<std::string>> text;
  std::vector<int> line_of_row;
  std::size_t rows() const { return line_of_row.size(); }
  double obstacle_distance_m = 0;  ///< a drive log's metadata (required by lib/logs)
  /// A numeric column (std::out_of_range when the log has none).
  const std::vector<double>& col(const std::string& c) const { return numeric.at(c); }
  /// The replay's header: the log's columns in their order, less those ARGoS does not produce
  /// (a battery log's voltage_v: ARGoS's battery has a charge, no voltage).
  std::vector<std::string> columns;
  /// The columns ARGoS's readings fill (value; px, py; left_steps, right_steps, tof_mm; charge);
  /// the others are copied.
  std::vector<std::string> readings;
};

/// Reads LOG as a log of `kind` (proximity, light, ground, camera, drive or battery) and checks that
/// ARGoS can set up every row: a column that is neither a condition ARGoS sets, a reading it
/// writes, `time_s` nor a `robot` text column is refused (epuck2::logs::InputError at the header,
/// naming the column). Errors name the file, the line and what was expected.
ReplayLog read_replay_log(const std::string& path, const std::string& kind);

/// The replay's comment lines and header: `# robot: ROBOT`, the log's other metadata (less its
/// robot and protocol), `# replayed_from: LOG`, `# protocol: PROTOCOL`, then the header.
std::string replay_head(const ReplayLog& r, const std::string& robot, const std::string& protocol);

/// Row `row` of the replay: the log's cells, the reading columns replaced by `readings` (each a
/// number already formatted, e.g. "3539"). A reading column missing from `readings` is an error.
std::string replay_row(const ReplayLog& r, std::size_t row, const std::map<std::string, std::string>& readings);

/// A number as the replay writes copied cells: up to 10 significant digits.
std::string replay_number(double v, int digits = 10);

}  // namespace epuck2::argos_replay
