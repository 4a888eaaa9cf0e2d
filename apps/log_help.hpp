// The --help footers of the subcommands that read logs: the columns each kind requires, taken from
// the reader itself (epuck2::logs::required_columns), so that the help and the reader never
// disagree, and where the full format is documented (docs/logs.md). tests/test_docs.cpp checks
// that every required column appears both there and in `epuck2-fit KIND --help`.
#pragma once

#include <string>
#include <vector>

#include "epuck2/logs/log.hpp"

namespace epuck2::app {

/// "a, b, c": the names joined.
inline std::string join_columns(const std::vector<std::string>& columns) {
  std::string out;
  for (const std::string& c : columns) out += (out.empty() ? "" : ", ") + c;
  return out;
}

/// A kind's required columns joined, each with the column that may stand in for it
/// ("time_s, speed_cm_s, charge (or voltage_v)").
inline std::string required_columns_text(logs::Kind kind) {
  std::string out;
  for (const std::string& c : logs::required_columns(kind)) {
    const std::string alt = logs::stand_in_column(kind, c);
    out += (out.empty() ? "" : ", ") + c + (alt.empty() ? "" : " (or " + alt + ")");
  }
  return out;
}

/// The footer for a subcommand that reads logs of one kind; `more` (optional columns, metadata,
/// what the subcommand needs beyond the format) follows the required columns on its own line.
inline std::string log_format_footer(logs::Kind kind, const std::string& more = "") {
  const std::string k(logs::to_string(kind));
  std::string out = "Log format (" + k + "): CSV, one header line, columns in any order, '#' comments,\n";
  out += "  '# key: value' metadata before the header.\n";
  out += "  Required columns: " + required_columns_text(kind) + ".\n";
  if (!more.empty()) out += "  " + more + "\n";
  out += "  Units, ranges, sentinels and an example: docs/logs.md#" + k + " in the repository.\n";
  out += "Exit status: 0 ok, 1 no usable fit, 2 bad usage or bad input (the message gives file:line:column).";
  return out;
}

/// The footer of diagnose: every kind's required columns (the kind is recognised from them).
inline std::string all_log_formats_footer() {
  std::string out = "Log formats (CSV; the kind is recognised from its required columns, or given with --kind):\n";
  for (logs::Kind kind : logs::all_kinds())
    out += "  " + std::string(logs::to_string(kind)) + ": " + join_columns(logs::required_columns(kind)) + "\n";  // diagnose needs charge
  out += "  drive logs also need the metadata line '# obstacle_distance_m: D'. Extra numeric columns\n";
  out += "  (e.g. temperature_c) are candidate causes (covariate:NAME).\n";
  out += "  Formats: docs/logs.md; the diagnosis, its catalogue and reports: docs/diagnose.md.\n";
  out += "Exit status: 0 whenever a report was produced, whatever the verdict; 2 bad usage or bad input.";
  return out;
}

}  // namespace epuck2::app
