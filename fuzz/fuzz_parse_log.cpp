// libFuzzer target: the log reader, epuck2::logs::parse_log(content, name, kind).
// Input: byte 0 picks the kind (0 = recognise it from the columns, 1..6 = battery, proximity,
// light, ground, camera, drive; other values wrap), the rest is the file's content.
// Contract checked (lib/logs/include/epuck2/logs/log.hpp): the reader either throws InputError
// (never anything else, never a crash) or returns a log whose numeric cells are all finite, with
// one source line per row, the kind's required columns, and at least one row.
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <string>

#include "epuck2/logs/log.hpp"

namespace {
void check(bool ok, const char* what) {
  if (!ok) {
    std::fprintf(stderr, "fuzz_parse_log: contract broken: %s\n", what);
    std::abort();
  }
}
}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  if (size == 0) return 0;
  using epuck2::logs::Kind;
  std::optional<Kind> kind;
  const int pick = data[0] % 7;
  if (pick > 0) kind = epuck2::logs::all_kinds().at(static_cast<std::size_t>(pick - 1));
  const std::string content(reinterpret_cast<const char*>(data + 1), size - 1);
  epuck2::logs::Log log;
  try {
    log = epuck2::logs::parse_log(content, "fuzz.csv", kind);
  } catch (const epuck2::logs::InputError& e) {
    check(e.file() == "fuzz.csv", "InputError names the file");
    check(e.line() >= 0 && e.column() >= 0, "InputError line and column are not negative");
    return 0;
  }
  if (kind) check(log.kind == *kind, "the kind asked for");
  check(log.rows() > 0, "at least one data row");
  for (const std::string& c : epuck2::logs::required_columns(log.kind)) {
    const std::string alt = epuck2::logs::stand_in_column(log.kind, c);
    check(log.has(c) || (!alt.empty() && log.has(alt)), "required column (or its stand-in) present");
  }
  for (const auto& [name, values] : log.numeric) {
    check(values.size() == log.rows(), "one value per row in every numeric column");
    for (double v : values) check(std::isfinite(v), "numeric cells finite");
  }
  for (const auto& [name, values] : log.text) check(values.size() == log.rows(), "one value per row in every text column");
  for (std::size_t i = 1; i < log.line_of_row.size(); ++i) check(log.line_of_row[i] > log.line_of_row[i - 1], "rows in line order");
  if (log.has("time_s")) {
    const auto& t = log.col("time_s");
    for (std::size_t i = 1; i < t.size(); ++i) check(t[i] >= t[i - 1], "time_s never decreasing");
  }
  // Every cell's position can be asked for without going out of bounds.
  for (std::size_t r = 0; r < log.rows(); ++r)
    for (const std::string& c : log.columns) check(log.column_of(r, c) >= 0, "cell column");
  return 0;
}
