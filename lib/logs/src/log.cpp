#include "epuck2/logs/log.hpp"

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>

namespace epuck2::logs {
namespace {

struct Range {
  double lo, hi;
  const char* what;
};

// Physical ranges of the columns (docs/logs.md). A value outside is rejected.
std::optional<Range> range_of(Kind kind, const std::string& column) {
  if (column == "time_s") return Range{0.0, 1e9, "a time >= 0 s"};
  if (column == "distance_m") return Range{0.0, 1e3, "a distance >= 0 m"};
  switch (kind) {
    case Kind::battery:
      if (column == "speed_cm_s") return Range{-1e3, 1e3, "a speed in cm/s"};
      if (column == "charge") return Range{-1.0, 1.05, "a normalised charge <= 1.05 (and >= -1)"};
      if (column == "voltage_v") return Range{0.0, 10.0, "a voltage in [0, 10] V"};
      break;
    case Kind::proximity:
      if (column == "sensor") return Range{0, 7, "a proximity sensor index 0..7"};
      if (column == "value") return Range{0, 4095, "a raw reading 0..4095"};
      if (column == "angle_deg") return Range{-90, 90, "an incidence angle in [-90, 90] degrees"};
      break;
    case Kind::light:
      if (column == "sensor") return Range{0, 7, "a light sensor index 0..7"};
      if (column == "value") return Range{0, 4095, "a raw reading 0..4095"};
      if (column == "intensity") return Range{0, 1e6, "an intensity >= 0"};
      break;
    case Kind::ground:
      if (column == "sensor") return Range{0, 2, "a ground sensor index 0..2"};
      if (column == "value") return Range{0, 1023, "a raw reading 0..1023"};
      if (column == "grey") return Range{0, 1, "a grey level in [0, 1]"};
      break;
    case Kind::camera:
      if (column == "forward_m") return Range{1e-12, 1e3, "a forward distance > 0 m"};
      if (column == "px") return Range{0, 159, "a pixel column 0..159"};
      if (column == "py") return Range{0, 119, "a pixel row 0..119"};
      break;
    case Kind::drive:
      if (column == "left_steps" || column == "right_steps")
        return Range{-32768, 32767, "a 16-bit encoder count -32768..32767"};
      if (column == "tof_mm") return Range{20, 2000, "a ToF reading 20..2000 mm"};
      if (column == "left_speed_cm_s" || column == "right_speed_cm_s")
        return Range{-1e3, 1e3, "a speed in cm/s"};
      break;
  }
  return std::nullopt;
}

bool must_be_integer(Kind kind, const std::string& column) {
  if (column == "sensor") return true;
  return kind == Kind::drive && (column == "left_steps" || column == "right_steps");
}

std::string trim(std::string_view s) {
  std::size_t b = 0, e = s.size();
  while (b < e && (s[b] == ' ' || s[b] == '\t' || s[b] == '\r')) ++b;
  while (e > b && (s[e - 1] == ' ' || s[e - 1] == '\t' || s[e - 1] == '\r')) --e;
  return std::string(s.substr(b, e - b));
}

struct Cell {
  std::string text;
  int column;  // 1-based character position of the field
};

std::vector<Cell> split(const std::string& line) {
  std::vector<Cell> cells;
  std::size_t start = 0;
  while (true) {
    const std::size_t comma = line.find(',', start);
    const std::size_t end = comma == std::string::npos ? line.size() : comma;
    cells.push_back({trim(std::string_view(line).substr(start, end - start)), static_cast<int>(start) + 1});
    if (comma == std::string::npos) break;
    start = comma + 1;
  }
  return cells;
}

// Strict number parsing: the whole cell, finite.
enum class NumberStatus { ok, not_a_number, not_finite };
NumberStatus parse_number(const std::string& s, double& out) {
  if (s.empty()) return NumberStatus::not_a_number;
  const char* begin = s.c_str();
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

}  // namespace

InputError::InputError(std::string file, int line, int column, std::string message)
    : std::runtime_error(format_message(file, line, column, message)),
      file_(std::move(file)),
      line_(line),
      column_(column),
      message_(std::move(message)) {}

std::string_view to_string(Kind kind) {
  switch (kind) {
    case Kind::battery: return "battery";
    case Kind::proximity: return "proximity";
    case Kind::light: return "light";
    case Kind::ground: return "ground";
    case Kind::camera: return "camera";
    case Kind::drive: return "drive";
  }
  return "?";
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
  static const std::map<Kind, std::vector<std::string>> required{
      {Kind::battery, {"time_s", "speed_cm_s", "charge"}},
      {Kind::proximity, {"distance_m", "sensor", "value"}},
      {Kind::light, {"distance_m", "intensity", "sensor", "value"}},
      {Kind::ground, {"grey", "sensor", "value"}},
      {Kind::camera, {"forward_m", "lateral_m", "vertical_m", "px", "py"}},
      {Kind::drive, {"time_s", "left_speed_cm_s", "right_speed_cm_s", "left_steps", "right_steps", "tof_mm"}},
  };
  return required.at(kind);
}

const std::vector<double>& Log::col(const std::string& column) const {
  const auto it = numeric.find(column);
  if (it == numeric.end()) throw InputError(path, 0, 0, "no numeric column '" + column + "'");
  return it->second;
}

double Log::metadata_number(const std::string& key) const {
  const auto it = metadata.find(key);
  if (it == metadata.end()) throw InputError(path, 0, 0, "missing metadata line '# " + key + ": VALUE'");
  double v = 0;
  if (parse_number(it->second, v) != NumberStatus::ok)
    throw InputError(path, 0, 0, "metadata '" + key + "': expected a finite number, got '" + it->second + "'");
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
Log parse_impl(const std::string& content, const std::string& name, std::optional<Kind> kind,
               const std::vector<std::string>* table_columns) {
  Log log;
  log.path = name;
  std::istringstream in(content);
  std::string line;
  int line_no = 0;
  int header_line = 0;
  std::vector<std::string> header;
  std::vector<std::vector<Cell>> raw_rows;
  std::vector<int> raw_lines;
  while (std::getline(in, line)) {
    ++line_no;
    if (!line.empty() && line.back() == '\r') line.pop_back();
    if (line_no == 1 && line.rfind("\xEF\xBB\xBF", 0) == 0) line.erase(0, 3);  // UTF-8 BOM
    const std::string t = trim(line);
    if (t.empty()) continue;
    if (t[0] == '#') {
      if (header.empty()) {
        const std::size_t colon = t.find(':');
        if (colon != std::string::npos) {
          const std::string key = trim(std::string_view(t).substr(1, colon - 1));
          if (!key.empty() && key.find(' ') == std::string::npos)
            log.metadata[key] = trim(std::string_view(t).substr(colon + 1));
        }
      }
      continue;
    }
    if (header.empty()) {
      header_line = line_no;
      for (const Cell& c : split(line)) {
        if (c.text.empty()) throw InputError(name, line_no, c.column, "empty column name in the header");
        if (std::find(header.begin(), header.end(), c.text) != header.end())
          throw InputError(name, line_no, c.column, "column '" + c.text + "' appears twice in the header");
        header.push_back(c.text);
      }
      continue;
    }
    std::vector<Cell> cells = split(line);
    if (cells.size() != header.size()) {
      const int col = cells.size() > header.size() ? cells[header.size()].column : static_cast<int>(line.size()) + 1;
      throw InputError(name, line_no, col,
                       "expected " + std::to_string(header.size()) + " comma-separated cells (as in the header on line " +
                           std::to_string(header_line) + "), found " + std::to_string(cells.size()));
    }
    raw_rows.push_back(std::move(cells));
    raw_lines.push_back(line_no);
  }
  if (header.empty()) throw InputError(name, 0, 0, "empty file: expected a header line and data rows");
  if (raw_rows.empty()) throw InputError(name, header_line, 0, "no data rows after the header");
  log.columns = header;

  // Kind: given, or recognised from the required columns (the most specific match).
  auto has_all = [&](Kind k) {
    for (const std::string& c : required_columns(k))
      if (std::find(header.begin(), header.end(), c) == header.end()) return false;
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
    if (!kind)
      throw InputError(name, header_line, 1,
                       "cannot recognise the kind of log from its columns; expected e.g. time_s,speed_cm_s,charge "
                       "(battery) or distance_m,sensor,value (proximity); or give --kind");
  }
  log.kind = *kind;
  const auto& req = table_columns ? *table_columns : required_columns(*kind);
  for (const std::string& c : req) {
    if (std::find(header.begin(), header.end(), c) == header.end())
      throw InputError(name, header_line, 1, "missing required column '" + c + "'" +
                                                 (table_columns ? std::string() : " for a " + std::string(to_string(*kind)) + " log"));
  }

  // Columns: required ones must be numeric in every row; an extra column is numeric if all of
  // its cells are, else kept as text.
  for (std::size_t j = 0; j < header.size(); ++j) {
    const std::string& cname = header[j];
    const bool required = std::find(req.begin(), req.end(), cname) != req.end() || cname == "angle_deg" ||
                          cname == "voltage_v";
    std::vector<double> values(raw_rows.size());
    bool numeric = true;
    for (std::size_t i = 0; i < raw_rows.size() && numeric; ++i) {
      const Cell& cell = raw_rows[i][j];
      const NumberStatus st = parse_number(cell.text, values[i]);
      if (st == NumberStatus::ok) continue;
      if (st == NumberStatus::not_finite)
        throw InputError(name, raw_lines[i], cell.column,
                         "column '" + cname + "': expected a finite number, got '" + cell.text + "'");
      if (required)
        throw InputError(name, raw_lines[i], cell.column,
                         "column '" + cname + "': expected a number, got '" + cell.text + "'");
      numeric = false;
    }
    if (!numeric) {
      std::vector<std::string> texts;
      texts.reserve(raw_rows.size());
      for (const auto& row : raw_rows) texts.push_back(row[j].text);
      log.text[cname] = std::move(texts);
      continue;
    }
    const std::optional<Range> r = range_of(*kind, cname);
    for (std::size_t i = 0; i < values.size(); ++i) {
      const double v = values[i];
      if (r && (v < r->lo || v > r->hi))
        throw InputError(name, raw_lines[i], raw_rows[i][j].column,
                         "column '" + cname + "': value " + raw_rows[i][j].text + " out of range, expected " + r->what);
      if (must_be_integer(*kind, cname) && v != std::floor(v))
        throw InputError(name, raw_lines[i], raw_rows[i][j].column,
                         "column '" + cname + "': expected an integer, got '" + raw_rows[i][j].text + "'");
      if (cname == "time_s" && i > 0 && v < values[i - 1])
        throw InputError(name, raw_lines[i], raw_rows[i][j].column,
                         "column 'time_s': time decreases from " + raw_rows[i - 1][j].text + " to " +
                             raw_rows[i][j].text + "; expected a non-decreasing time");
    }
    log.numeric[cname] = std::move(values);
  }
  log.line_of_row = raw_lines;
  log.cell_start.reserve(raw_rows.size() * header.size());
  for (const auto& row : raw_rows)
    for (const Cell& c : row) log.cell_start.push_back(c.column);

  if (!table_columns && *kind == Kind::drive) {
    if (!log.metadata.count("obstacle_distance_m"))
      throw InputError(name, header_line, 0, "missing required metadata line '# obstacle_distance_m: D' for a drive log");
    const double d = log.metadata_number("obstacle_distance_m");
    if (d <= 0) throw InputError(name, 0, 0, "metadata 'obstacle_distance_m' must be > 0");
  }

  if (auto it = log.metadata.find("robot"); it != log.metadata.end() && !it->second.empty()) {
    log.robot = it->second;
  } else if (auto t = log.text.find("robot"); t != log.text.end() && !t->second.empty()) {
    log.robot = t->second.front();
  } else {
    log.robot = std::filesystem::path(name).stem().string();
  }
  return log;
}
}  // namespace

Log parse_log(const std::string& content, const std::string& name, std::optional<Kind> kind) {
  return parse_impl(content, name, kind, nullptr);
}

Log read_table(const std::string& path, const std::vector<std::string>& columns) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw InputError(path, 0, 0, "cannot open the file for reading");
  std::ostringstream ss;
  ss << in.rdbuf();
  return parse_impl(ss.str(), path, std::nullopt, &columns);
}

Log read_log(const std::string& path, std::optional<Kind> kind) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw InputError(path, 0, 0, "cannot open the file for reading");
  std::ostringstream ss;
  ss << in.rdbuf();
  return parse_log(ss.str(), path, kind);
}

std::vector<Log> read_logs(const std::vector<std::string>& paths, std::optional<Kind> kind) {
  std::vector<Log> logs;
  logs.reserve(paths.size());
  for (const std::string& p : paths) {
    logs.push_back(read_log(p, kind));
    if (!kind) kind = logs.front().kind;
    if (logs.back().kind != logs.front().kind)
      throw InputError(p, 0, 0, "is a " + std::string(to_string(logs.back().kind)) + " log, but " +
                                    logs.front().path + " is a " + std::string(to_string(logs.front().kind)) +
                                    " log; give logs of one kind");
  }
  return logs;
}

}  // namespace epuck2::logs
