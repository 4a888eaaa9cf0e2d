#include "app_support.hpp"

#include <fstream>
#include <iostream>
#include <sstream>

#include "epuck2/logs/json_location.hpp"
#include "epuck2/logs/log.hpp"
#include "epuck2/logs/output.hpp"

namespace epuck2::app {

void write_json(const nlohmann::json& j, const std::string& path) {
  const std::string text = j.dump(2) + "\n";
  if (path == "-") {
    std::cout << text;
    return;
  }
  logs::write_file_atomically(path, text);
}

nlohmann::json read_json(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw logs::InputError(path, 0, 0, "cannot open the file for reading");
  std::stringstream ss;
  ss << in.rdbuf();
  const std::string text = ss.str();
  try {
    return nlohmann::json::parse(text);
  } catch (const nlohmann::json::parse_error& e) {
    // e.byte is the 1-based offset of the character where parsing failed.
    const logs::SourcePos at = logs::position_of(text, e.byte > 0 ? e.byte - 1 : 0);
    throw logs::InputError(path, at.line, at.column, std::string("invalid JSON: ") + e.what());
  } catch (const nlohmann::json::exception& e) {
    // E.g. a number too large for a double (1e999): nlohmann says what, not where.
    const logs::SourcePos at = logs::locate_json_overflow(text);
    throw logs::InputError(path, at.line, at.column,
                           std::string("invalid JSON: ") + e.what() + (at.line > 0 ? " (a number too large for a double)" : ""));
  }
}

void add_skip_bad_rows(CLI::App* sub, bool& flag) {
  sub->add_flag("--skip-bad-rows", flag,
                "Leave out a data row with a bad cell (not a number, not finite, out of range, not an integer, "
                "wrong number of cells) instead of stopping; every row left out is reported on standard error "
                "(the count, then the first 10 as file:line:column). Time going backwards still stops the run "
                "(the order of the rows is in doubt, not one cell)");
}

void report_skipped(const std::string& command, const std::vector<logs::Log>& logs) {
  std::size_t total = 0;
  for (const auto& l : logs) total += l.skipped.size();
  if (total == 0) return;
  std::cerr << command << ": skipped " << total << " bad row" << (total == 1 ? "" : "s") << " (--skip-bad-rows)"
            << (total > 10 ? ", the first 10:" : ":") << '\n';
  std::size_t shown = 0;
  for (const auto& l : logs)
    for (const auto& r : l.skipped) {
      if (shown == 10) break;
      std::cerr << "  " << logs::escape_control(l.path) << ':' << r.line << ':' << r.column << ": " << r.reason << '\n';
      ++shown;
    }
  if (total > shown) std::cerr << "  ... and " << total - shown << " more\n";
}

std::vector<logs::Log> read_logs_reporting(const std::string& command, const std::vector<std::string>& paths,
                                           std::optional<logs::Kind> kind, bool skip_bad_rows) {
  logs::ReadOptions options;
  options.skip_bad_rows = skip_bad_rows;
  std::vector<logs::Log> logs = logs::read_logs(paths, kind, options);
  report_skipped(command, logs);
  return logs;
}

}  // namespace epuck2::app
