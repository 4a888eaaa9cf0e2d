// The kinds' facts that the log reader and the unit check read from lib/models kind_facts.hpp
// (issue #19, item 4: per-kind facts in one place, not in if-chains of the reader). The expected
// values are docs/logs.md's and docs/fitting.md's, read from the docs themselves: every column
// range of a kind's table is tried through the reader at both ends and just beyond them, on the
// kind's example log of the same page; the rejections quoted on the page come out word for word.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <optional>
#include <regex>
#include <sstream>
#include <string>
#include <vector>

#include "epuck2/calibrate/plausibility.hpp"
#include "epuck2/logs/log.hpp"
#include "epuck2/models/kind_facts.hpp"

namespace {

using epuck2::logs::InputError;
using epuck2::logs::Kind;
namespace logs = epuck2::logs;
namespace models = epuck2::models;

std::string read_doc(const char* name) {
  std::ifstream in(std::string(EPUCK2_SOURCE_DIR) + "/docs/" + name);
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

std::vector<std::string> lines_of(const std::string& text) {
  std::vector<std::string> out;
  std::istringstream in(text);
  for (std::string line; std::getline(in, line);) out.push_back(line);
  return out;
}

/// One row of a kind's column table in docs/logs.md.
struct DocRange {
  std::string column;
  double lo = 0, hi = 0;
  bool lo_open = false;                 ///< "> 0 (up to 1000)"
  bool whole = false;                   ///< ", whole"
  std::optional<double> code_from;      ///< ", or ≥ 8190"
};

/// The section "## KIND" of docs/logs.md: its column table's ranges and its first example log.
struct DocKind {
  std::vector<DocRange> ranges;
  std::vector<std::string> example;  ///< the first ```csv block's lines
};

std::string ascii(std::string s) {
  for (const auto& [from, to] : {std::pair<std::string, std::string>{"−", "-"}, {"10⁶", "1e6"}, {"≥", ">="}}) {
    for (std::size_t at = s.find(from); at != std::string::npos; at = s.find(from, at + to.size())) s.replace(at, from.size(), to);
  }
  return s;
}

DocKind doc_kind(const std::string& kind) {
  DocKind out;
  const std::vector<std::string> lines = lines_of(read_doc("logs.md"));
  const auto start = std::find(lines.begin(), lines.end(), "## " + kind);
  EXPECT_NE(start, lines.end()) << "docs/logs.md has no section '## " << kind << "'";
  if (start == lines.end()) return out;
  const std::regex range(R"(^(-?[0-9.e]+)\.\.(-?[0-9.e]+)(, whole)?(, or >= ([0-9]+))?$)");
  const std::regex open_range(R"(^> (-?[0-9.e]+) \(up to (-?[0-9.e]+)\)$)");
  const std::regex name("`([a-z_]+)`");
  bool in_csv = false, csv_done = false;
  for (auto it = start + 1; it != lines.end() && it->rfind("## ", 0) != 0; ++it) {
    const std::string line = ascii(*it);
    if (line == "```csv" && !csv_done) {
      in_csv = true;
      continue;
    }
    if (in_csv) {
      if (line == "```") {
        in_csv = false;
        csv_done = true;
      } else {
        out.example.push_back(line);
      }
      continue;
    }
    if (line.rfind("| `", 0) != 0) continue;
    // | `name`[, `name`] [(optional)] | unit | range | meaning |
    std::vector<std::string> cells;
    std::stringstream row(line.substr(1));
    for (std::string cell; std::getline(row, cell, '|');) {
      while (!cell.empty() && cell.front() == ' ') cell.erase(cell.begin());
      while (!cell.empty() && cell.back() == ' ') cell.pop_back();
      cells.push_back(cell);
    }
    if (cells.size() < 3) continue;
    DocRange r;
    std::smatch m;
    if (std::regex_match(cells[2], m, range)) {
      r.lo = std::stod(m[1]);
      r.hi = std::stod(m[2]);
      r.whole = m[3].matched;
      if (m[5].matched) r.code_from = std::stod(m[5]);
    } else if (std::regex_match(cells[2], m, open_range)) {
      r.lo = std::stod(m[1]);
      r.hi = std::stod(m[2]);
      r.lo_open = true;
    } else {
      continue;  // time_s: ">= 0, never decreasing" (the order of the rows, not a range)
    }
    for (auto n = std::sregex_iterator(cells[0].begin(), cells[0].end(), name); n != std::sregex_iterator(); ++n) {
      r.column = (*n)[1];
      out.ranges.push_back(r);
    }
  }
  return out;
}

std::string number(double v) {
  char text[64];
  std::snprintf(text, sizeof text, "%.15g", v);
  return text;
}

/// The example log with `column` set to `value` in its first data row (added to every row where
/// the example lacks it, as an optional column).
std::string with_value(const std::vector<std::string>& example, const std::string& column, double value) {
  std::string out;
  std::size_t header = 0;
  while (header < example.size() && example[header].rfind('#', 0) == 0) ++header;
  std::vector<std::string> cols;
  std::stringstream h(example.at(header));
  for (std::string c; std::getline(h, c, ',');) cols.push_back(c);
  const auto at = std::find(cols.begin(), cols.end(), column);
  const bool added = at == cols.end();
  const std::size_t j = static_cast<std::size_t>(at - cols.begin());
  for (std::size_t i = 0; i < example.size(); ++i) {
    std::string line = example[i];
    if (i == header && added) line += "," + column;
    if (i > header) {
      std::vector<std::string> cells;
      std::stringstream r(line);
      for (std::string c; std::getline(r, c, ',');) cells.push_back(c);
      if (added) cells.push_back(number(value));
      else if (i == header + 1) cells.at(j) = number(value);
      line.clear();
      for (std::size_t k = 0; k < cells.size(); ++k) line += (k ? "," : "") + cells[k];
    }
    out += line + "\n";
  }
  return out;
}

/// The reader's message for the example with `column` = `value`, or "" when it reads it.
std::string reader_says(Kind kind, const DocKind& doc, const std::string& column, double value) {
  try {
    logs::parse_log(with_value(doc.example, column, value), "doc.csv", kind);
    return "";
  } catch (const InputError& e) {
    return e.message();
  }
}

class DocumentedRanges : public ::testing::TestWithParam<Kind> {};

TEST_P(DocumentedRanges, EachColumnReadToItsEndsAndRefusedBeyond) {
  const Kind kind = GetParam();
  const std::string name(logs::to_string(kind));
  const DocKind doc = doc_kind(name);
  ASSERT_FALSE(doc.example.empty()) << name << ": no example log in docs/logs.md";
  ASSERT_GE(doc.ranges.size(), 3u) << name << ": the column table of docs/logs.md was not read";
  const models::KindFacts& facts = *models::kind_facts(name);
  for (const DocRange& r : doc.ranges) {
    SCOPED_TRACE(name + " " + r.column);
    const double step = r.whole ? 1.0 : 1e-3 * std::max(1.0, std::max(std::abs(r.lo), std::abs(r.hi)));
    // Both ends are read (an open lower end: just above it).
    EXPECT_EQ(reader_says(kind, doc, r.column, r.lo_open ? r.lo + 1e-6 : r.lo), "");
    EXPECT_EQ(reader_says(kind, doc, r.column, r.hi), "");
    const std::string refused = "column '" + r.column + "': value ";
    for (double beyond : {r.lo_open ? r.lo : r.lo - step, r.hi + step}) {
      if (r.code_from && beyond >= *r.code_from) continue;
      const std::string says = reader_says(kind, doc, r.column, beyond);
      EXPECT_NE(says.find(refused), std::string::npos) << beyond << ": " << says;
      EXPECT_NE(says.find("out of range, expected "), std::string::npos) << beyond << ": " << says;
    }
    if (r.whole) {
      const std::string says = reader_says(kind, doc, r.column, r.lo + 0.5);
      EXPECT_NE(says.find("expected an integer"), std::string::npos) << says;
    }
    if (r.code_from) {
      // The sensor's code and above are kept as read; just below the code, refused.
      EXPECT_EQ(reader_says(kind, doc, r.column, *r.code_from), "");
      EXPECT_EQ(reader_says(kind, doc, r.column, *r.code_from + 1), "");
      EXPECT_NE(reader_says(kind, doc, r.column, *r.code_from - 1).find("out of range"), std::string::npos);
    }
    // Where the kind has a range of its own (not the one every log's distance_m shares), it is the
    // documented one.
    if (const models::ColumnRange* own = facts.range(r.column)) {
      if (r.lo_open) {
        EXPECT_GT(own->lo, r.lo);
        EXPECT_LT(own->lo, 1e-6);
      } else {
        EXPECT_EQ(own->lo, r.lo);
      }
      EXPECT_EQ(own->hi, r.hi);
      EXPECT_EQ(own->integer || r.column == "sensor", r.whole);
    }
  }
}

/// The example log with `column`'s cell set to `text` in its last data row, or in every row
/// (added to every row, as an optional column, where the example lacks it); where the cell starts
/// (line, column, 1-based: the last row's, or the first's when every row has it) in `line`, `col`.
std::string with_text(const std::vector<std::string>& example, const std::string& column, const std::string& text, bool every_row,
                      int& line, int& col) {
  std::size_t header = 0;
  while (header < example.size() && example[header].rfind('#', 0) == 0) ++header;
  std::vector<std::string> cols;
  std::stringstream h(example.at(header));
  for (std::string c; std::getline(h, c, ',');) cols.push_back(c);
  const auto at = std::find(cols.begin(), cols.end(), column);
  const bool added = at == cols.end();
  const std::size_t j = added ? cols.size() : static_cast<std::size_t>(at - cols.begin());
  const std::size_t last = example.size() - 1;
  const std::size_t target = every_row ? header + 1 : last;  // the first cell the reader meets
  std::string out;
  for (std::size_t i = 0; i < example.size(); ++i) {
    std::string l = example[i];
    if (i == header && added) l += "," + column;
    if (i > header) {
      std::vector<std::string> cells;
      std::stringstream r(l);
      for (std::string c; std::getline(r, c, ',');) cells.push_back(c);
      if (added) cells.push_back(every_row || i != last ? (every_row ? text : "0") : text);
      else if (every_row || i == last) cells.at(j) = text;
      l.clear();
      for (std::size_t k = 0; k < cells.size(); ++k) {
        if (i == target && k == j) col = static_cast<int>(l.size()) + (k ? 2 : 1);
        l += (k ? "," : "") + cells[k];
      }
    }
    out += l + "\n";
  }
  line = static_cast<int>(target) + 1;
  return out;
}

// docs/logs.md: every column of a kind's table is a number in its range. A cell that is not a number
// (a logger's "n/a", an empty cell) is refused where it stands -- the last row's line and the cell's
// first character -- whether the other rows of the column are numbers or not: a column with one
// bad cell is never read as a text column whose numbers are dropped, nor is a column of text.
TEST_P(DocumentedRanges, EachColumnRefusesACellThatIsNotANumberWhereItIs) {
  const Kind kind = GetParam();
  const std::string name(logs::to_string(kind));
  const DocKind doc = doc_kind(name);
  ASSERT_GE(doc.example.size(), 3u) << name << ": the example log has fewer than two rows";
  std::vector<std::string> columns;
  for (const DocRange& r : doc.ranges) columns.push_back(r.column);
  if (kind == Kind::battery || kind == Kind::drive) columns.push_back("time_s");  // ">= 0, never decreasing"
  ASSERT_GE(columns.size(), 3u);
  for (const std::string& column : columns) {
    for (const char* text : {"n/a", "", "12abc", "nan", "inf"}) {
      for (bool every_row : {false, true}) {
        // A cell left empty in every row of an optional column, or of voltage_v beside charge,
        // is a column the log does not have; refused is what the other cases expect.
        if (std::string(text).empty() && every_row) continue;
        SCOPED_TRACE(name + " " + column + " '" + text + "'" + (every_row ? " in every row" : " in the last row"));
        int line = 0, col = 0;
        const std::string csv = with_text(doc.example, column, text, every_row, line, col);
        try {
          logs::parse_log(csv, "text.csv", kind);
          ADD_FAILURE() << "read:\n" << csv;
        } catch (const InputError& e) {
          EXPECT_EQ(e.line(), line) << e.what() << "\n" << csv;
          EXPECT_EQ(e.column(), col) << e.what() << "\n" << csv;
        }
      }
    }
  }
}

INSTANTIATE_TEST_SUITE_P(EveryKind, DocumentedRanges,
                         ::testing::Values(Kind::battery, Kind::proximity, Kind::light, Kind::ground, Kind::camera, Kind::drive),
                         [](const ::testing::TestParamInfo<Kind>& i) { return std::string(logs::to_string(i.param)); });

// docs/logs.md, "When a file is rejected": the range messages it quotes, word for word.
TEST(DocumentedRanges, TheRejectionsTheDocQuotes) {
  const std::regex quoted(R"(^error: ([a-z]+)[a-z_0-9]*\.csv:[0-9]+:[0-9]+: column '([a-z_]+)': value ([-0-9.]+) out of range, expected (.*)$)");
  int seen = 0;
  for (const std::string& line : lines_of(read_doc("logs.md"))) {
    std::smatch m;
    if (!std::regex_match(line, m, quoted)) continue;
    // The file names say the kind: battery_run.csv, prox.csv.
    const std::string file = m[1];
    const Kind kind = file.rfind("prox", 0) == 0 ? Kind::proximity : *logs::parse_kind(file);
    const DocKind doc = doc_kind(std::string(logs::to_string(kind)));
    EXPECT_EQ(reader_says(kind, doc, m[2], std::stod(m[3])),
              "column '" + std::string(m[2]) + "': value " + std::string(m[3]) + " out of range, expected " + std::string(m[4]));
    ++seen;
  }
  EXPECT_EQ(seen, 2) << "docs/logs.md quotes two range messages (charge, sensor)";
}

// docs/logs.md, drive: "Required metadata: `# obstacle_distance_m: D`, the distance in metres
// (0..1000)"; a voltage-only battery log (`voltage_v` in place of `charge`) is a battery log.
TEST(DocumentedMetadata, ObstacleDistanceRequiredAndBounded) {
  const DocKind drive = doc_kind("drive");
  std::vector<std::string> without;
  for (const std::string& l : drive.example)
    if (l.rfind("# obstacle_distance_m:", 0) != 0) without.push_back(l);
  ASSERT_EQ(without.size() + 1, drive.example.size());
  auto says = [](const std::vector<std::string>& example) {
    std::string csv;
    for (const std::string& l : example) csv += l + "\n";
    try {
      logs::parse_log(csv, "run3.csv", Kind::drive);
      return std::string();
    } catch (const InputError& e) {
      return e.message();
    }
  };
  const std::string missing = says(without);
  EXPECT_NE(missing.find("missing required metadata line '# obstacle_distance_m: D'"), std::string::npos) << missing;
  EXPECT_NE(missing.find("for a drive log"), std::string::npos) << missing;
  for (const char* ok : {"0", "1000"}) {
    std::vector<std::string> e = without;
    e.insert(e.begin(), std::string("# obstacle_distance_m: ") + ok);
    EXPECT_EQ(says(e), "") << ok;
  }
  for (const char* bad : {"-0.01", "1000.5"}) {
    std::vector<std::string> e = without;
    e.insert(e.begin(), std::string("# obstacle_distance_m: ") + bad);
    EXPECT_EQ(says(e), std::string("metadata 'obstacle_distance_m': expected a distance >= 0 m and <= 1000 m, got ") + bad);
  }
}

TEST(DocumentedMetadata, VoltageStandsInForCharge) {
  // The battery section's second example: the same run, voltage only.
  const std::vector<std::string> lines = lines_of(read_doc("logs.md"));
  const auto header = std::find(lines.begin(), lines.end(), "time_s,speed_cm_s,voltage_v");
  ASSERT_NE(header, lines.end());
  std::string csv;
  for (auto it = header; it != lines.end() && *it != "```"; ++it) csv += *it + "\n";
  const logs::Log log = logs::parse_log(csv, "volts.csv");
  EXPECT_EQ(log.kind, Kind::battery);
  EXPECT_FALSE(log.has("charge"));
  EXPECT_EQ(logs::stand_in_column(Kind::light, "value"), "");
}

// docs/fitting.md, "Implausible units stop the run": proximity beyond 10 x its 0.05 m ray (0.5 m),
// light beyond 10 x the plug-in's 0.5 m range (5 m); a ground log's extra distance_m is not checked.
TEST(DocumentedUnitCheck, DistancesAgainstTheSensorsReach) {
  auto log_at = [](Kind kind, const char* csv) { return logs::parse_log(csv, "u.csv", kind); };
  auto stops = [](const logs::Log& log) {
    try {
      epuck2::calibrate::check_plausible_units({log});
      return std::string();
    } catch (const InputError& e) {
      return e.message();
    }
  };
  EXPECT_EQ(stops(log_at(Kind::proximity, "distance_m,sensor,value\n0.49,0,0\n")), "");
  const std::string prox = stops(log_at(Kind::proximity, "distance_m,sensor,value\n0.51,0,0\n"));
  EXPECT_NE(prox.find("the proximity sensor sees to 0.05 m"), std::string::npos) << prox;
  EXPECT_EQ(stops(log_at(Kind::light, "distance_m,intensity,sensor,value\n4.9,1,0,0\n")), "");
  const std::string light = stops(log_at(Kind::light, "distance_m,intensity,sensor,value\n5.1,1,0,0\n"));
  EXPECT_NE(light.find("sees to 0.5 m"), std::string::npos) << light;
  EXPECT_EQ(stops(log_at(Kind::ground, "grey,sensor,value,distance_m\n0.5,0,500,100\n")), "");
}

}  // namespace
