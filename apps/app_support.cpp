#include "app_support.hpp"

#include <algorithm>
#include <cctype>
#include <filesystem>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <fstream>
#include <iostream>
#include <sstream>
#include <streambuf>
#include <tuple>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <unistd.h>

#include "epuck2/calibrate/plausibility.hpp"
#include "epuck2/coefficients/model_file.hpp"
#include "epuck2/logs/log.hpp"
#include "commands.hpp"
#include "epuck2/logs/output.hpp"
#include "epuck2/plot/figure.hpp"
#if __has_include("epuck2/fitted/coefficients.hpp")
#include "epuck2/fitted/coefficients.hpp"  // --coefficients fitted (epuck2::fitted)
#endif

namespace epuck2::app {

namespace {
// The first non-finite number in `j`, as a dotted path ("" when there is none).
bool find_non_finite(const nlohmann::json& j, const std::string& where, std::string& found) {
  if (j.is_number_float()) {
    if (std::isfinite(j.get<double>())) return false;
    found = where.empty() ? "(top level)" : where;
    return true;
  }
  if (j.is_object()) {
    for (const auto& [key, value] : j.items())
      if (find_non_finite(value, where.empty() ? key : where + "." + key, found)) return true;
  } else if (j.is_array()) {
    for (std::size_t i = 0; i < j.size(); ++i)
      if (find_non_finite(j[i], where + "[" + std::to_string(i) + "]", found)) return true;
  }
  return false;
}

// The first reason a write to standard output failed (0: none so far).
int standard_output_errno = 0;

// fopencookie's write function: every byte to file descriptor 1, or the reason it could not.
ssize_t write_standard_output(void*, const char* data, std::size_t size) {
  std::size_t done = 0;
  while (done < size) {
    const ssize_t n = ::write(STDOUT_FILENO, data + done, size - done);
    if (n > 0) {
      done += static_cast<std::size_t>(n);
      continue;
    }
    if (n < 0 && errno == EINTR) continue;
    if (standard_output_errno == 0) standard_output_errno = n < 0 ? errno : EIO;
    return 0;  // fopencookie: 0 is the error
  }
  return static_cast<ssize_t>(size);
}

// std::cout's buffer: hands everything to the stdio stream `stdout` (so that printf and std::cout
// keep their order and share one check).
class StdioForward : public std::streambuf {
 protected:
  int_type overflow(int_type c) override {
    if (traits_type::eq_int_type(c, traits_type::eof())) return traits_type::not_eof(c);
    return std::fputc(traits_type::to_char_type(c), stdout) == EOF ? traits_type::eof() : c;
  }
  std::streamsize xsputn(const char* s, std::streamsize n) override {
    return static_cast<std::streamsize>(std::fwrite(s, 1, static_cast<std::size_t>(n), stdout));
  }
  int sync() override { return std::fflush(stdout) == 0 ? 0 : -1; }
};
}  // namespace

void capture_standard_output() {
  // Never destroyed: std::cout flushes through it until the very end of the process, after the
  // program's own statics are gone (the last std::ios_base::Init, in a shared library, flushes it
  // at exit). A function-local static was destroyed first, and that flush called a dead object
  // (AddressSanitizer: SEGV in std::ostream::flush from ~Init).
  static StdioForward* const forward = new StdioForward;
  cookie_io_functions_t io{};
  io.write = write_standard_output;
  FILE* checked = ::fopencookie(nullptr, "w", io);
  if (checked == nullptr) return;  // stays unchecked stdio: nothing better to do
  std::setvbuf(checked, nullptr, ::isatty(STDOUT_FILENO) ? _IOLBF : _IOFBF, BUFSIZ);
  std::fflush(stdout);
  stdout = checked;  // glibc: stdout is an assignable variable (what printf and fwrite use)
  std::cout.rdbuf(forward);
}

std::string standard_output_error() {
  std::cout.flush();
  std::fflush(stdout);
  if (standard_output_errno == 0 && !std::ferror(stdout) && std::cout.good()) return std::string();
  const int e = standard_output_errno != 0 ? standard_output_errno : EIO;
  return std::string("standard output: ") + std::strerror(e);
}

std::string json_text(const nlohmann::json& j) {
  std::string where;
  if (find_non_finite(j, "", where))
    throw NoUsableFit("the result holds a NaN or infinite value at " + where + "; nothing was written");
  return j.dump(2) + "\n";
}

void write_json(logs::OutputStage& stage, const nlohmann::json& j, const std::string& path) {
  stage.write(path, json_text(j));
}

void write_json(const nlohmann::json& j, const std::string& path) { logs::write_file_atomically(path, json_text(j)); }

void write_output(const std::string& text, const std::string& path) {
  if (path.empty()) {
    std::fwrite(text.data(), 1, text.size(), stdout);
    return;
  }
  logs::write_file_atomically(path, text);
}

CLI::Validator finite_range(double lo, double hi) {
  const std::string range = "[" + logs::format_number(lo) + ", " + logs::format_number(hi) + "]";
  return CLI::Validator(
      [lo, hi, range](std::string& input) -> std::string {
        double v = 0;
        if (!CLI::detail::lexical_cast(input, v)) return "'" + input + "' is not a number (allowed: " + range + ")";
        if (!std::isfinite(v) || v < lo || v > hi) return input + " is out of range: allowed a finite number in " + range;
        return std::string();
      },
      "FINITE in " + range);
}

CLI::Validator whole_number() {
  return CLI::Validator(
      [](std::string& input) -> std::string {
        if (input.empty() || input.find_first_not_of("0123456789") != std::string::npos)
          return "'" + input + "' is not a whole number in [0, 18446744073709551615]";
        // strtoull saturates rather than fail: compare the digits with 2^64 - 1 instead.
        const std::string max = "18446744073709551615";
        const std::string digits = input.substr(std::min(input.find_first_not_of('0'), input.size()));
        if (digits.size() > max.size() || (digits.size() == max.size() && digits > max))
          return input + " is out of range: allowed [0, 18446744073709551615]";
        return std::string();
      },
      "UINT64");
}

nlohmann::json read_json(const std::string& path) { return coefficients::read_json_file(path); }

namespace {
std::string lower(std::string s) {
  for (char& c : s) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return s;
}

}  // namespace

std::string closest(const std::string& word, const std::vector<std::string>& choices) {
  const std::string w = lower(word);
  std::string best;
  std::size_t best_distance = 3;
  for (const std::string& c : choices) {
    const std::size_t d = logs::edit_distance(w, lower(c));
    if (d < best_distance && 2 * d < std::max(w.size(), c.size())) {
      best = c;
      best_distance = d;
    }
  }
  return best;
}

std::string join(const std::vector<std::string>& names, const std::string& separator) {
  std::string out;
  for (const std::string& n : names) out += (out.empty() ? "" : separator) + n;
  return out;
}

std::string unknown_name(const std::string& what, const std::string& word, const std::vector<std::string>& choices,
                         const std::string& list_title) {
  std::string out = "unknown " + what + " '" + logs::escape_control(word) + "'";
  const std::string near = closest(word, choices);
  if (!near.empty()) out += "; did you mean '" + near + "'?";
  out += (near.empty() ? "; " : " ") + (list_title.empty() ? what + "s" : list_title) + ": " + join(choices);
  return out;
}

CLI::Validator one_of(const std::vector<std::string>& choices, const std::string& what) {
  return CLI::Validator(
      [choices, what](std::string& input) -> std::string {
        if (std::find(choices.begin(), choices.end(), input) != choices.end()) return std::string();
        return unknown_name(what, input, choices);
      },
      "{" + join(choices, ",") + "}");
}

std::vector<std::string> kind_names() {
  std::vector<std::string> out;
  for (logs::Kind k : logs::all_kinds()) out.emplace_back(logs::to_string(k));
  return out;
}

const std::string& coefficient_file(const std::string& source) {
  std::error_code ec;
  if (!std::filesystem::exists(source, ec)) {
    const std::string near = closest(source, {"fitted", "plugin"});
    if (!near.empty())
      throw UsageError("--coefficients: '" + logs::escape_control(source) + "' is no file; did you mean '" + near +
                       "'? (fitted, plugin or a battery coefficient FILE)");
  }
  return source;
}

coefficients::LogRobotChoice coefficients_robot(const std::string& source, const std::string& robot,
                                                const std::vector<std::string>& log_robots) {
  if (source.empty() || source == "plugin" || source == "fitted") {
    if (!robot.empty())
      throw UsageError("--robot " + robot + " chooses a robot's set of a coefficient FILE (its `robots`); --coefficients " +
                       (source.empty() ? std::string("is not given") : source + " has no robot sets"));
    return {};
  }
  const std::string& path = coefficient_file(source);
  try {
    return coefficients::choose_robot_for_logs(read_json(path), path, robot, log_robots);
  } catch (const std::invalid_argument& e) {
    throw UsageError(e.what());
  }
}

void add_coefficients_robot(CLI::App* sub, std::string& robot) {
  sub->add_option("--robot", robot,
                  "Run this robot's set of the --coefficients FILE (its robots.ID); default: the log's robot's own set when "
                  "the file has one, else the pooled set")
      ->type_name("ID");
}

std::vector<logs::Log> split_robot_columns(const std::string& command, std::vector<logs::Log> logs) {
  std::vector<logs::Log> out;
  for (logs::Log& l : logs) {
    const std::vector<std::string> names = logs::robot_column_names(l);
    if (names.size() > 1)
      std::cerr << command << ": the robot column of " << logs::escape_control(l.path) << " names " << names.size()
                << " robots (" << join(names) << "): its rows are read as " << names.size()
                << " logs, one per robot (docs/logs.md, \"A robot column\")\n";
    for (logs::Log& piece : logs::split_by_robot_column(std::move(l))) out.push_back(std::move(piece));
  }
  return out;
}

std::vector<logs::Log> select_robot(std::vector<logs::Log> all, const std::string& robot) {
  if (robot.empty()) return all;
  std::vector<logs::Log> out;
  std::vector<std::string> names;
  for (auto& l : all) {
    if (std::find(names.begin(), names.end(), l.robot) == names.end()) names.push_back(l.robot);
    if (l.robot == robot) out.push_back(std::move(l));
  }
  if (out.empty()) throw UsageError("--robot " + robot + ": no log of that robot; these logs are of " + join(names));
  return out;
}

std::string robot_column_warning(const logs::Log& log) {
  const std::vector<std::string> names = logs::robot_column_names(log);
  if (names.size() < 2) return std::string();
  return "the robot column of " + log.path + " names " + std::to_string(names.size()) + " robots (" + join(names) +
         "); the diagnosis reads the file as one log (robot " + log.robot +
         ", its first row's), the robots' rows pooled: diagnose each robot's rows as a log of its own";
}

std::optional<coefficients::AnyModel> coefficients_model(const std::string& kind, const std::string& source,
                                                         nlohmann::json* file, const std::string& robot) {
  if (source.empty() || source == "plugin") return std::nullopt;
  if (source == "fitted") {
    // The models this build compiles in (data/fitted/include): the battery's tables.
    std::vector<coefficients::AnyModel> compiled_in;
#ifdef EPUCK2_FITTED_HAS_BATTERY
    models::sensors::BatteryModel battery;
    battery.tables = fitted::battery_tables();
    compiled_in.push_back(battery);
#endif
    for (const coefficients::AnyModel& m : compiled_in)
      if (coefficients::kind_of(m) == kind) return m;
    if (compiled_in.empty()) throw UsageError("this build has no compiled-in fitted battery tables; give --coefficients FILE");
    throw UsageError("--coefficients fitted names the battery tables compiled in; for " + kind +
                     " logs give the coefficient FILE (data/fitted/" + kind + ".json in this repository)");
  }
  const std::string& path = coefficient_file(source);
  const nlohmann::json j = read_json(path);
  if (file != nullptr) *file = j;
  try {
    return coefficients::model_from_json(kind, j, path, robot);
  } catch (const logs::InputError&) {
    throw;
  } catch (const std::runtime_error& e) {
    throw UsageError(std::string("--coefficients: ") + e.what());
  }
}

CLI::Validator figure_file() {
  return CLI::Validator(
      [](std::string& input) -> std::string { return plot::why_not_a_figure(input); }, "{.png,.svg,.pdf}");
}

void print_figure_warnings(const std::string& command) {
  for (const std::string& w : plot::take_figure_warnings()) std::cerr << command << ": warning: " << w << '\n';
}

std::string why_not_writable(const std::string& path, bool folder_allowed) {
  namespace fs = std::filesystem;
  // An empty name (an unset shell variable, `-o "$OUT"`) would otherwise read as no -o at all:
  // the report on the terminal, exit 0 and no file.
  if (path.empty()) return "an empty file name; give the name of the file to write (or - for standard output)";
  const std::string shown = "'" + logs::escape_control(path) + "'";
  // Standard output, a descriptor, a device or a FIFO: written in place, never renamed over.
  if (logs::output_target(path).way != logs::OutputWay::replace) {
    const std::string why = logs::why_not_writable_in_place(path);
    return why.empty() ? std::string() : shown + ": " + why;
  }
  std::error_code ec;
  fs::path target(path);
  if (fs::is_symlink(target, ec)) target = fs::weakly_canonical(target, ec);  // the file it names is replaced
  if (fs::is_directory(target, ec)) {
    if (!folder_allowed) return shown + " is a folder; give the name of the file to write";
    if (::access(target.c_str(), W_OK | X_OK) != 0) return shown + " is a folder that cannot be written to";
    return std::string();
  }
  const fs::path folder = target.parent_path().empty() ? fs::path(".") : target.parent_path();
  const std::string folder_shown = "'" + logs::escape_control(folder.string()) + "'";
  if (!fs::exists(folder, ec))
    return shown + ": the folder " + folder_shown + " does not exist (create it first: nothing was run)";
  if (!fs::is_directory(folder, ec)) return shown + ": " + folder_shown + " is not a folder";
  if (::access(folder.c_str(), W_OK | X_OK) != 0)
    return shown + ": the folder " + folder_shown + " cannot be written to (nothing was run)";
  return std::string();
}

CLI::Validator output_file(bool folder_allowed) {
  return CLI::Validator(
      [folder_allowed](std::string& input) -> std::string { return why_not_writable(input, folder_allowed); }, "");
}

void add_figure_options(CLI::App* sub) {
  sub->add_option_function<std::string>(
         "--figure-size",
         [](const std::string& v) {
           plot::Page p = plot::page();
           std::tie(p.width_in, p.height_in) = plot::parse_figure_size(v);
           plot::set_page(p);
         },
         "Print size of every figure, WIDTHxHEIGHT in cm, mm or in: 8.5x6cm for one column of a two-column paper, "
         "17x10cm for both (PNG at 300 dpi; SVG and PDF at that size)")
      ->type_name("WxH")
      ->check(CLI::Validator(
          [](std::string& v) -> std::string {
            try {
              plot::parse_figure_size(v);
            } catch (const std::invalid_argument& e) {
              return e.what();
            }
            return std::string();
          },
          "WxH{cm,mm,in}"));
  sub->add_option_function<double>(
         "--font-size",
         [](double pt) {
           plot::Page p = plot::page();
           p.font_pt = pt;
           plot::set_page(p);
         },
         "Size of the figures' text in points (default 11 at the default size; 8-9 suits a paper's column); titles keep "
         "their proportion to it")
      ->type_name("PT")
      ->check(finite_range(4, 40));
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

std::vector<std::string> identical_logs(const std::vector<logs::Log>& logs) {
  std::vector<std::string> out;
  std::vector<bool> copy(logs.size(), false);
  for (std::size_t a = 0; a < logs.size(); ++a) {
    if (copy[a]) continue;
    for (std::size_t b = a + 1; b < logs.size(); ++b) {
      const logs::Log &x = logs[a], &y = logs[b];
      // The same readings: every numeric column and text cell, row by row (the header's order and
      // the comments may differ).
      if (copy[b] || x.robot != y.robot || x.rows() != y.rows() || x.rows() == 0 || x.numeric != y.numeric || x.text != y.text)
        continue;
      copy[b] = true;
      out.push_back(logs::escape_control(y.path) + " holds the same data rows as " + logs::escape_control(x.path) + " (" +
                    std::to_string(x.rows()) + " rows, robot " + x.robot +
                    "): a copy of a log counts its readings twice, as if they were new measurements, and the standard "
                    "errors shrink by about the square root of 2; give each log once");
    }
  }
  return out;
}

std::vector<logs::Log> read_logs_reporting(const std::string& command, const std::vector<std::string>& paths,
                                           std::optional<logs::Kind> kind, bool skip_bad_rows,
                                           std::vector<std::string>* warnings) {
  logs::ReadOptions options;
  options.skip_bad_rows = skip_bad_rows;
  std::vector<logs::Log> logs = logs::read_logs(paths, kind, options);
  report_skipped(command, logs);
  calibrate::check_plausible_units(logs);  // cm written as m: exit 2, not a calibration of nonsense
  for (const std::string& w : identical_logs(logs)) {
    if (warnings != nullptr) warnings->push_back(w);
    else std::cerr << command << ": warning: " << w << '\n';
  }
  return logs;
}

}  // namespace epuck2::app
