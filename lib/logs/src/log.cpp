#include "epuck2/logs/log.hpp"

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <limits>
#include <fstream>
#include <sstream>

#include "epuck2/models/kind_facts.hpp"

namespace epuck2::logs {
std::size_t edit_distance(const std::string& a, const std::string& b) {
  std::vector<std::size_t> prev(b.size() + 1), cur(b.size() + 1);
  for (std::size_t j = 0; j <= b.size(); ++j) prev[j] = j;
  for (std::size_t i = 1; i <= a.size(); ++i) {
    cur[0] = i;
    for (std::size_t j = 1; j <= b.size(); ++j)
      cur[j] = std::min({prev[j] + 1, cur[j - 1] + 1, prev[j - 1] + (a[i - 1] == b[j - 1] ? 0 : 1)});
    std::swap(prev, cur);
  }
  return prev[b.size()];
}

namespace {

/// A kind's facts (lib/models kind_facts.hpp): its columns, their ranges, its channels.
const models::KindFacts& facts_of(Kind kind) { return *models::kind_facts(std::string(to_string(kind))); }

// The physical range of a column (docs/logs.md), or nullopt: the kind's own (kind_facts), else
// the ranges every log shares. A value outside is rejected (tof_mm also takes the out-of-range
// code, see kTofOutOfRangeCode_mm).
std::optional<models::ColumnRange> range_of(Kind kind, const std::string& column) {
  if (const models::ColumnRange* r = facts_of(kind).range(column)) return *r;
  if (column == "time_s") return models::ColumnRange{"time_s", 0.0, 1e9, "a time in [0, 1e9] s"};
  if (column == "distance_m") return models::ColumnRange{"distance_m", 0.0, 1e3, "a distance in [0, 1000] m"};
  return std::nullopt;
}

bool must_be_integer(const std::optional<models::ColumnRange>& range, const std::string& column) {
  return column == "sensor" || (range && range->integer);
}

std::string_view trim_view(std::string_view s) {
  std::size_t b = 0, e = s.size();
  while (b < e && (s[b] == ' ' || s[b] == '\t' || s[b] == '\r')) ++b;
  while (e > b && (s[e - 1] == ' ' || s[e - 1] == '\t' || s[e - 1] == '\r')) --e;
  return s.substr(b, e - b);
}

std::string trim(std::string_view s) { return std::string(trim_view(s)); }

std::string lower(std::string s) {
  for (char& c : s)
    if (c >= 'A' && c <= 'Z') c = static_cast<char>(c - 'A' + 'a');
  return s;
}

// The lines of a text: LF, CRLF and a lone CR (old Mac) each end a line.
std::vector<std::string_view> split_lines(std::string_view s) {
  std::vector<std::string_view> lines;
  std::size_t start = 0;
  for (std::size_t i = 0; i < s.size(); ++i) {
    if (s[i] != '\n' && s[i] != '\r') continue;
    lines.push_back(s.substr(start, i - start));
    if (s[i] == '\r' && i + 1 < s.size() && s[i + 1] == '\n') ++i;
    start = i + 1;
  }
  if (start < s.size()) lines.push_back(s.substr(start));
  return lines;
}

// A cell's trimmed text is where it stands in the file's content (begin, size), not a string of
// its own: a 1M-row log's 6M cells as strings took ~300 MB while it was read (bench/README.md).
struct Cell {
  std::uint32_t begin;  // offset of the trimmed text in the content
  std::uint32_t size;
  int column;  // 1-based character position of the field
};

/// The largest content whose cells' offsets fit a Cell.
constexpr std::size_t kMaxContent = std::numeric_limits<std::uint32_t>::max();

// Appends the cells of `line`, a view into `content`.
void split(std::string_view content, std::string_view line, std::vector<Cell>& cells) {
  const std::size_t base = static_cast<std::size_t>(line.data() - content.data());
  std::size_t start = 0;
  while (true) {
    const std::size_t comma = line.find(',', start);
    const std::size_t end = comma == std::string::npos ? line.size() : comma;
    const std::string_view text = trim_view(line.substr(start, end - start));
    cells.push_back({static_cast<std::uint32_t>(base + static_cast<std::size_t>(text.data() - line.data())),
                     static_cast<std::uint32_t>(text.size()), static_cast<int>(start) + 1});
    if (comma == std::string::npos) break;
    start = comma + 1;
  }
}

// Strict number parsing: the whole cell, finite.
enum class NumberStatus { ok, not_a_number, not_finite };
NumberStatus parse_number(std::string_view s, double& out) {
  if (s.empty()) return NumberStatus::not_a_number;
  // strtod reads up to a NUL: the cell is copied into one that ends there (a short cell on the stack).
  char small[64];
  std::string large;
  const char* begin = small;
  if (s.size() < sizeof small) {
    std::memcpy(small, s.data(), s.size());
    small[s.size()] = '\0';
  } else {
    large.assign(s);
    begin = large.c_str();
  }
  char* end = nullptr;
  errno = 0;
  const double v = std::strtod(begin, &end);
  if (end != begin + s.size()) return NumberStatus::not_a_number;
  if (std::isnan(v) || std::isinf(v)) return NumberStatus::not_finite;
  out = v;
  return NumberStatus::ok;
}

std::string format_message(const std::string& file, int line, int column, const std::string& message) {
  std::ostringstream os;
  os << file;
  if (line > 0) os << ':' << line;
  if (line > 0 && column > 0) os << ':' << column;
  os << ": " << message;
  return os.str();
}

// A column name as quantity and unit ("speed_cm_s" -> "speed", "cm_s"); no unit -> "".
std::pair<std::string, std::string> split_unit(const std::string& name) {
  for (const char* unit : {"cm_s", "mm", "deg", "s", "m", "v"}) {
    const std::string suffix = std::string("_") + unit;
    if (name.size() > suffix.size() && name.compare(name.size() - suffix.size(), suffix.size(), suffix) == 0)
      return {name.substr(0, name.size() - suffix.size()), unit};
  }
  return {name, ""};
}

// Why a required column may be missing: a header column with the same quantity in another unit,
// or a close name (a typo). Empty when nothing is close; `column` gets the header cell's position.
std::string explain_missing(const std::string& missing, const std::vector<std::string>& header,
                            const std::vector<int>& header_columns, const std::vector<std::string>& required, int& column) {
  const auto [quantity, unit] = split_unit(missing);
  for (std::size_t j = 0; j < header.size(); ++j) {
    const std::string& h = header[j];
    if (std::find(required.begin(), required.end(), h) != required.end() || unit.empty()) continue;
    column = header_columns[j];
    if (h == quantity)
      return "column '" + h + "' has no unit; this column must be in " + unit + " (named '" + missing + "')";
    if (h.size() > quantity.size() + 1 && h.compare(0, quantity.size() + 1, quantity + "_") == 0)
      return "column '" + h + "' has the unit " + h.substr(quantity.size() + 1) + "; this column must be in " + unit;
  }
  std::size_t best = 0, best_distance = 3;
  for (std::size_t j = 0; j < header.size(); ++j) {
    const std::string& h = header[j];
    if (std::find(required.begin(), required.end(), h) != required.end()) continue;
    const std::size_t d = edit_distance(h, missing);
    if (d < best_distance && 2 * d < missing.size()) {
      best = j;
      best_distance = d;
    }
  }
  if (best_distance <= 2) {
    column = header_columns[best];
    return "the header has '" + header[best] + "': did you mean '" + missing + "'?";
  }
  column = 1;
  return "";
}

}  // namespace

std::string escape_control(std::string_view text) {
  static const char* hex = "0123456789abcdef";
  std::string out;
  out.reserve(text.size());
  for (const char ch : text) {
    const auto c = static_cast<unsigned char>(ch);
    if ((c < 0x20 && c != '\t') || c == 0x7f) {
      out += "\\x";
      out += hex[c >> 4];
      out += hex[c & 0xf];
    } else {
      out += ch;
    }
  }
  return out;
}

InputError::InputError(std::string file, int line, int column, std::string message)
    : std::runtime_error(format_message(escape_control(file), line, column, escape_control(message))),
      file_(escape_control(file)),
      line_(line),
      column_(column),
      message_(escape_control(message)) {}

std::string_view to_string(Kind kind) {
  // The enumerators' names, in their order (log.hpp).
  static constexpr std::string_view kNames[] = {"battery", "proximity", "light", "ground", "camera", "drive"};
  const auto k = static_cast<std::size_t>(kind);
  return k < std::size(kNames) ? kNames[k] : "?";
}

const std::vector<Kind>& all_kinds() {
  static const std::vector<Kind> kinds{Kind::battery, Kind::proximity, Kind::light,
                                       Kind::ground,  Kind::camera,    Kind::drive};
  return kinds;
}

std::optional<Kind> parse_kind(std::string_view name) {
  for (Kind k : all_kinds())
    if (to_string(k) == name) return k;
  return std::nullopt;
}

const std::vector<std::string>& required_columns(Kind kind) {
  // The kinds' facts (lib/models kind_facts.hpp), as strings once.
  static const std::map<Kind, std::vector<std::string>> required = [] {
    std::map<Kind, std::vector<std::string>> m;
    for (Kind k : all_kinds()) {
      const auto& columns = facts_of(k).columns;
      m[k] = std::vector<std::string>(columns.begin(), columns.end());
    }
    return m;
  }();
  return required.at(kind);
}

std::string stand_in_column(Kind kind, const std::string& required) {
  for (const models::StandIn& s : facts_of(kind).stand_ins)
    if (required == s.required) return s.instead;
  return "";
}

const std::vector<double>& Log::col(const std::string& column) const {
  const auto it = numeric.find(column);
  if (it == numeric.end()) throw InputError(path, 0, 0, "no numeric column '" + column + "'");
  return it->second;
}

double Log::metadata_number(const std::string& key) const {
  const auto it = metadata.find(key);
  if (it == metadata.end())
    throw InputError(path, header_line, header_line > 0 ? 1 : 0,
                     "missing metadata line '# " + key + ": VALUE' (before the header)");
  const auto at = metadata_at.find(key);
  const SourcePos pos = at == metadata_at.end() ? SourcePos{} : at->second;
  double v = 0;
  if (parse_number(it->second, v) != NumberStatus::ok)
    throw InputError(path, pos.line, pos.column,
                     "metadata '" + key + "': expected a finite number, got '" + it->second + "'");
  return v;
}

int Log::column_of(std::size_t row, const std::string& column) const {
  const auto it = std::find(columns.begin(), columns.end(), column);
  if (it == columns.end() || row >= line_of_row.size()) return 0;
  return cell_start[row * columns.size() + static_cast<std::size_t>(it - columns.begin())];
}

std::vector<std::string> Log::extra_numeric_columns() const {
  std::vector<std::string> out;
  const auto& req = required_columns(kind);
  for (const std::string& c : columns)
    if (numeric.count(c) && std::find(req.begin(), req.end(), c) == req.end()) out.push_back(c);
  return out;
}

namespace {

// A bad cell or row: where, and what was expected.
struct Problem {
  int line = 0;
  int column = 0;
  std::string message;
};
bool before(const Problem& a, const Problem& b) { return a.line != b.line ? a.line < b.line : a.column < b.column; }


Log parse_impl(const std::string& content, const std::string& name, std::optional<Kind> kind,
               const std::vector<std::string>* table_columns, const ReadOptions& options) {
  Log log;
  log.path = name;
  if (content.size() > kMaxContent)
    throw InputError(name, 0, 0, "larger than 4 GiB: split the log into several files (each one run)");
  int line_no = 0;
  int header_line = 0;
  std::vector<std::string> header;       // lower case
  std::vector<std::string> header_as_written;
  std::vector<int> header_columns;       // character column of each header cell
  // Every data row's cells, row after row: row i's are cells[row_first[i], row_first[i + 1]).
  std::vector<Cell> cells;
  std::vector<std::size_t> row_first{0};
  std::vector<int> raw_lines;
  std::vector<int> raw_length;           // characters in each data row's line
  auto text = [&](const Cell& c) { return std::string_view(content).substr(c.begin, c.size); };
  auto cells_in = [&](std::size_t i) { return row_first[i + 1] - row_first[i]; };
  auto cell = [&](std::size_t i, std::size_t j) -> const Cell& { return cells[row_first[i] + j]; };
  for (std::string_view line : split_lines(content)) {
    ++line_no;
    if (line_no == 1 && line.substr(0, 3) == "\xEF\xBB\xBF") line.remove_prefix(3);  // UTF-8 BOM
    const std::string_view t = trim_view(line);
    if (t.empty()) continue;
    if (t[0] == '#') {
      if (header_line == 0) {
        const std::size_t hash = line.find('#');
        const std::size_t colon = line.find(':', hash);
        if (colon != std::string::npos) {
          const std::string key = lower(escape_control(trim(std::string_view(line).substr(hash + 1, colon - hash - 1))));
          if (!key.empty() && key.find(' ') == std::string::npos) {
            std::size_t value_start = colon + 1;
            while (value_start < line.size() && (line[value_start] == ' ' || line[value_start] == '\t')) ++value_start;
            log.metadata[key] = escape_control(trim(std::string_view(line).substr(colon + 1)));
            log.metadata_at[key] = SourcePos{line_no, static_cast<int>(value_start) + 1};
          }
        }
      }
      continue;
    }
    if (header_line == 0) {
      header_line = line_no;
      std::vector<Cell> names;
      split(content, line, names);
      if (names.size() > 1 && names.back().size == 0) names.pop_back();  // a trailing delimiter
      for (const Cell& c : names) {
        const std::string written(text(c));
        if (written.empty()) throw InputError(name, line_no, c.column, "empty column name in the header");
        const std::string lc = lower(escape_control(written));
        const auto twin = std::find(header.begin(), header.end(), lc);
        if (twin != header.end()) {
          const std::string& first = header_as_written[static_cast<std::size_t>(twin - header.begin())];
          throw InputError(name, line_no, c.column,
                           "column '" + written + "' appears twice in the header" +
                               (first == written ? std::string() : " (as '" + first + "' and '" + written + "': letter case is ignored)"));
        }
        header.push_back(lc);
        header_as_written.push_back(written);
        header_columns.push_back(c.column);
      }
      continue;
    }
    split(content, line, cells);
    // A trailing delimiter: one empty cell past the header's columns.
    if (cells.size() - row_first.back() == header.size() + 1 && cells.back().size == 0) cells.pop_back();
    row_first.push_back(cells.size());
    raw_lines.push_back(line_no);
    raw_length.push_back(static_cast<int>(line.size()));
  }
  log.header_line = header_line;
  if (header_line == 0) throw InputError(name, 1, 1, "empty file: expected a header line and data rows");
  if (raw_lines.empty()) throw InputError(name, header_line, 1, "no data rows after the header");
  log.columns = header;

  // Kind: given, or recognised from the required columns (the most specific match).
  auto in_header = [&](const std::string& c) { return std::find(header.begin(), header.end(), c) != header.end(); };
  auto has_all = [&](Kind k) {
    for (const std::string& c : required_columns(k)) {
      const std::string alt = stand_in_column(k, c);
      if (!in_header(c) && (alt.empty() || !in_header(alt))) return false;
    }
    return true;
  };
  if (table_columns) kind = Kind::battery;  // ranges of time_s and speed_cm_s
  if (!kind) {
    std::size_t best = 0;
    for (Kind k : all_kinds()) {
      if (has_all(k) && required_columns(k).size() > best) {
        kind = k;
        best = required_columns(k).size();
      }
    }
    if (!kind) {
      // A kind whose every missing column has a close name in the header (a typo, another unit):
      // say so, for the most specific such kind.
      std::string hint;
      int column = 1;
      std::size_t most = 0;
      for (Kind k : all_kinds()) {
        const auto& need = required_columns(k);
        std::string why;
        int at = 1;
        bool explained = true;
        for (const std::string& c : need) {
          if (std::find(header.begin(), header.end(), c) != header.end()) continue;
          int col = 1;
          const std::string w = explain_missing(c, header, header_columns, need, col);
          if (w.empty()) {
            explained = false;
            break;
          }
          if (why.empty()) {
            why = "; as a " + std::string(to_string(k)) + " log it lacks '" + c + "': " + w;
            at = col;
          }
        }
        if (explained && !why.empty() && need.size() > most) {
          most = need.size();
          hint = why;
          column = at;
        }
      }
      throw InputError(name, header_line, column,
                       "cannot recognise the kind of log from its columns; expected e.g. time_s,speed_cm_s,charge "
                       "(battery) or distance_m,sensor,value (proximity); or give --kind" + hint);
    }
  }
  log.kind = *kind;
  const auto& req = table_columns ? *table_columns : required_columns(*kind);
  for (const std::string& c : req) {
    if (in_header(c)) continue;
    const std::string alt = table_columns ? std::string() : stand_in_column(*kind, c);
    if (!alt.empty() && in_header(alt)) continue;
    int column = 1;
    const std::string why = explain_missing(c, header, header_columns, req, column);
    throw InputError(name, header_line, column,
                     "missing required column '" + c + "'" +
                         (alt.empty() ? std::string() : " (or '" + alt + "')") +
                         (table_columns ? std::string() : " for a " + std::string(to_string(*kind)) + " log") +
                         (why.empty() ? std::string() : "; " + why));
  }

  // Cells. Required (and known optional) columns must be numbers in every row; an extra column is
  // numeric if all of its cells are, else kept as text. Each row's leftmost problem is kept.
  const std::size_t n = raw_lines.size(), m = header.size();
  // Each bad row's leftmost problem (few rows are bad: not one Problem per row).
  std::vector<std::int32_t> problem_of(n, -1);  // index into problems, or -1
  std::vector<Problem> problems;
  auto problem = [&](std::size_t i) -> const Problem* {
    return problem_of[i] < 0 ? nullptr : &problems[static_cast<std::size_t>(problem_of[i])];
  };
  auto note = [&](std::size_t i, int column, std::string message) {
    Problem p{raw_lines[i], column, std::move(message)};
    if (problem_of[i] < 0) {
      problem_of[i] = static_cast<std::int32_t>(problems.size());
      problems.push_back(std::move(p));
    } else if (before(p, problems[static_cast<std::size_t>(problem_of[i])])) {
      problems[static_cast<std::size_t>(problem_of[i])] = std::move(p);
    }
  };
  for (std::size_t i = 0; i < n; ++i) {
    if (cells_in(i) == m) continue;
    const int col = cells_in(i) > m ? cell(i, m).column : raw_length[i] + 1;
    note(i, col,
         "expected " + std::to_string(m) + " comma-separated cells (as in the header on line " + std::to_string(header_line) +
             "), found " + std::to_string(cells_in(i)));
  }
  std::vector<bool> is_numeric(m, true);
  std::vector<std::vector<double>> values(m, std::vector<double>(n, 0.0));
  // Each column's range and whether it takes whole numbers only, looked up once.
  std::vector<std::optional<models::ColumnRange>> range(m);
  std::vector<bool> integer(m);
  for (std::size_t j = 0; j < m; ++j) {
    range[j] = range_of(*kind, header[j]);
    integer[j] = must_be_integer(range[j], header[j]);
  }
  auto check_cell = [&](std::size_t i, std::size_t j) {
    const Cell& c = cell(i, j);
    const std::string_view written = text(c);
    const std::string& cname = header[j];
    double& v = values[j][i];
    const NumberStatus st = parse_number(written, v);
    if (st == NumberStatus::not_finite)
      return note(i, c.column, "column '" + cname + "': expected a finite number, got '" + std::string(written) + "'");
    if (st == NumberStatus::not_a_number)
      return note(i, c.column, "column '" + cname + "': expected a number, got '" + std::string(written) + "'");
    const std::optional<models::ColumnRange>& r = range[j];
    if (r && !r->in_range(v))
      return note(i, c.column, "column '" + cname + "': value " + std::string(written) + " out of range, expected " + r->what);
    if (integer[j] && v != std::floor(v))
      return note(i, c.column, "column '" + cname + "': expected an integer, got '" + std::string(written) + "'");
  };
  std::vector<std::size_t> extra;
  for (std::size_t j = 0; j < m; ++j) {
    const std::string& cname = header[j];
    const bool required = std::find(req.begin(), req.end(), cname) != req.end() || cname == "angle_deg" || cname == "voltage_v";
    if (!required) {
      extra.push_back(j);
      continue;
    }
    for (std::size_t i = 0; i < n; ++i)
      if (cells_in(i) == m) check_cell(i, j);
  }
  for (const std::size_t j : extra) {
    // Numeric when every cell of the rows that are otherwise good reads as a number (finite or not).
    for (std::size_t i = 0; i < n && is_numeric[j]; ++i) {
      if (problem(i)) continue;
      double v = 0;
      if (parse_number(text(cell(i, j)), v) == NumberStatus::not_a_number) is_numeric[j] = false;
    }
    if (!is_numeric[j]) continue;
    for (std::size_t i = 0; i < n; ++i)
      if (cells_in(i) == m) check_cell(i, j);
  }

  // Time never decreases over the rows kept; this stays an error under skip_bad_rows.
  std::optional<Problem> time_problem;
  const auto time_it = std::find(header.begin(), header.end(), std::string("time_s"));
  if (time_it != header.end() && is_numeric[static_cast<std::size_t>(time_it - header.begin())]) {
    const std::size_t j = static_cast<std::size_t>(time_it - header.begin());
    std::optional<std::size_t> previous;
    for (std::size_t i = 0; i < n && !time_problem; ++i) {
      if (problem(i)) continue;
      if (previous && values[j][i] < values[j][*previous])
        time_problem = Problem{raw_lines[i], cell(i, j).column,
                               "column 'time_s': time decreases from " + std::string(text(cell(*previous, j))) + " (line " +
                                   std::to_string(raw_lines[*previous]) + ") to " + std::string(text(cell(i, j))) +
                                   "; expected a non-decreasing time" +
                                   (options.skip_bad_rows ? " (--skip-bad-rows does not skip this: the order of the rows is in doubt)" : "")};
      previous = i;
    }
  }
  std::optional<Problem> first;
  for (std::size_t i = 0; i < n && !first; ++i)
    if (problem(i)) first = *problem(i);
  if (time_problem && (options.skip_bad_rows || !first || before(*time_problem, *first)))
    throw InputError(name, time_problem->line, time_problem->column, time_problem->message);
  if (first && !options.skip_bad_rows) throw InputError(name, first->line, first->column, first->message);

  std::vector<std::size_t> kept;
  for (std::size_t i = 0; i < n; ++i) {
    if (const Problem* p = problem(i))
      log.skipped.push_back(SkippedRow{p->line, p->column, escape_control(p->message)});
    else
      kept.push_back(i);
  }
  if (kept.empty())
    throw InputError(name, header_line, 1,
                     "no data rows left: all " + std::to_string(n) + " were skipped as bad (--skip-bad-rows); the first, line " +
                         std::to_string(first->line) + ", column " + std::to_string(first->column) + ": " + first->message);

  for (std::size_t j = 0; j < m; ++j) {
    if (is_numeric[j] && kept.size() == n) {
      log.numeric[header[j]] = std::move(values[j]);  // every row kept: no copy
    } else if (is_numeric[j]) {
      std::vector<double> col;
      col.reserve(kept.size());
      for (const std::size_t i : kept) col.push_back(values[j][i]);
      log.numeric[header[j]] = std::move(col);
    } else {
      std::vector<std::string> texts;
      texts.reserve(kept.size());
      for (const std::size_t i : kept) texts.push_back(escape_control(text(cell(i, j))));
      log.text[header[j]] = std::move(texts);
    }
    std::vector<double>().swap(values[j]);
  }
  log.line_of_row.reserve(kept.size());
  log.cell_start.reserve(kept.size() * m);
  for (const std::size_t i : kept) {
    log.line_of_row.push_back(raw_lines[i]);
    for (std::size_t j = 0; j < m; ++j) log.cell_start.push_back(cell(i, j).column);
  }

  for (const models::RequiredMetadata& meta : table_columns ? std::vector<models::RequiredMetadata>{} : facts_of(*kind).metadata) {
    if (!log.metadata.count(meta.key))
      throw InputError(name, header_line, 1,
                       std::string("missing required metadata line '# ") + meta.key + ": " + meta.placeholder +
                           "' (before the header) for a " + std::string(to_string(*kind)) + " log");
    const double d = log.metadata_number(meta.key);
    if (d < meta.lo || d > meta.hi) {
      const SourcePos at = log.metadata_at.at(meta.key);
      throw InputError(name, at.line, at.column,
                       std::string("metadata '") + meta.key + "': expected " + meta.what + ", got " + log.metadata.at(meta.key));
    }
  }

  if (auto it = log.metadata.find("robot"); it != log.metadata.end() && !it->second.empty()) {
    log.robot = it->second;
  } else if (auto t = log.text.find("robot"); t != log.text.end() && !t->second.empty()) {
    log.robot = t->second.front();
  } else {
    log.robot = escape_control(std::filesystem::path(name).stem().string());
  }
  return log;
}

std::string slurp(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw InputError(path, 0, 0, "cannot open the file for reading");
  std::ostringstream ss;
  ss << in.rdbuf();
  return ss.str();
}
}  // namespace

Log parse_log(const std::string& content, const std::string& name, std::optional<Kind> kind, const ReadOptions& options) {
  return parse_impl(content, name, kind, nullptr, options);
}

Log read_table(const std::string& path, const std::vector<std::string>& columns, const ReadOptions& options) {
  return parse_impl(slurp(path), path, std::nullopt, &columns, options);
}

Log read_log(const std::string& path, std::optional<Kind> kind, const ReadOptions& options) {
  return parse_log(slurp(path), path, kind, options);
}

std::vector<std::string> robot_column_names(const Log& log) {
  std::vector<std::string> names;
  if (auto it = log.metadata.find("robot"); it != log.metadata.end() && !it->second.empty()) return names;
  const auto column = log.text.find("robot");
  if (column == log.text.end()) return names;
  for (const std::string& r : column->second)
    if (std::find(names.begin(), names.end(), r) == names.end()) names.push_back(r);
  return names;
}

std::vector<Log> split_by_robot_column(Log log) {
  const std::vector<std::string> names = robot_column_names(log);
  std::vector<Log> out;
  if (names.size() < 2) {
    out.push_back(std::move(log));
    return out;
  }
  const std::vector<std::string>& robot_of = log.text.at("robot");
  const std::size_t rows = log.rows();
  const std::size_t cells = rows == 0 ? 0 : log.cell_start.size() / rows;
  for (const std::string& name : names) {
    Log piece;
    piece.path = log.path;
    piece.kind = log.kind;
    piece.robot = name;
    piece.metadata = log.metadata;
    piece.metadata_at = log.metadata_at;
    piece.header_line = log.header_line;
    piece.columns = log.columns;
    if (out.empty()) piece.skipped = log.skipped;
    std::vector<std::size_t> mine;
    for (std::size_t i = 0; i < rows; ++i)
      if (robot_of[i] == name) mine.push_back(i);
    for (const auto& [c, values] : log.numeric) {
      std::vector<double>& v = piece.numeric[c];
      v.reserve(mine.size());
      for (const std::size_t i : mine) v.push_back(values[i]);
    }
    for (const auto& [c, values] : log.text) {
      std::vector<std::string>& v = piece.text[c];
      v.reserve(mine.size());
      for (const std::size_t i : mine) v.push_back(values[i]);
    }
    piece.line_of_row.reserve(mine.size());
    piece.cell_start.reserve(mine.size() * cells);
    for (const std::size_t i : mine) {
      piece.line_of_row.push_back(log.line_of_row[i]);
      for (std::size_t k = 0; k < cells; ++k) piece.cell_start.push_back(log.cell_start[i * cells + k]);
    }
    out.push_back(std::move(piece));
  }
  return out;
}

std::vector<Log> read_logs(const std::vector<std::string>& paths, std::optional<Kind> kind, const ReadOptions& options) {
  // The same file twice would count its rows twice: refuse it before reading anything.
  std::map<std::string, std::string> seen;  // canonical path -> as given
  for (const std::string& p : paths) {
    std::error_code ec;
    const std::filesystem::path canonical = std::filesystem::weakly_canonical(p, ec);
    const std::string key = ec ? p : canonical.string();
    const auto [it, fresh] = seen.emplace(key, p);
    if (!fresh)
      throw InputError(p, 0, 0,
                       it->second == p ? "given twice; give each log once"
                                       : "is the same file as " + it->second + " (given twice); give each log once");
  }
  std::vector<Log> logs;
  logs.reserve(paths.size());
  for (const std::string& p : paths) {
    logs.push_back(read_log(p, kind, options));
    if (!kind) kind = logs.front().kind;
    if (logs.back().kind != logs.front().kind)
      throw InputError(p, 0, 0, "is a " + std::string(to_string(logs.back().kind)) + " log, but " +
                                    logs.front().path + " is a " + std::string(to_string(logs.front().kind)) +
                                    " log; give logs of one kind");
  }
  return logs;
}

}  // namespace epuck2::logs
