// Shared by the sensor subcommands (proximity, light, ground, camera, drive): the subcommand and
// its common options (add_sensor_command), the checks that turn a fit into exit 1 (or a warning
// under --accept-misfit), and the output sequence (-o atomically, then the plot, then --json or
// the human report). The coefficient file's JSON and the report's text are lib/calibrate's
// (report_json.hpp, report_text.hpp, sensor_reports.hpp). The functions are defined in
// sensor_support.cpp (compiled once); the templates that take a subcommand's own lambdas stay here.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <functional>
#include <iostream>
#include <map>
#include <memory>
#include <sstream>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "app_support.hpp"
#include "commands.hpp"
#include "log_help.hpp"
#include "epuck2/fit/least_squares.hpp"
#include "epuck2/fit/report.hpp"
#include "epuck2/fit/robust.hpp"
#include "epuck2/calibrate/report_json.hpp"
#include "epuck2/calibrate/sensor_reports.hpp"
#include "epuck2/calibrate/sensors.hpp"
#include "epuck2/logs/log.hpp"
#include "epuck2/logs/output.hpp"

namespace epuck2::app::sensors {

struct SensorOptions {
  std::vector<std::string> logs;
  bool json = false;
  std::string output;
  std::string plot;
  bool least_squares = false;  ///< plain least squares: no reading left out as an outlier
  double reject_sd = 4.0;      ///< robust: readings farther than this many noise sd are outliers
  std::string robot;           ///< fit only this robot's logs
  calibrate::SensorFitOptions fit_options() const {
    calibrate::SensorFitOptions f;
    f.robust = !least_squares;
    f.reject_sd = reject_sd;
    return f;
  }
  bool skip_bad_rows = false;  ///< skip rows with a bad cell, each reported
  bool accept_misfit = false;  ///< write a calibration whose fit misses its data (a warning, not exit 1)
};

/// Adds LOGS..., --json, -o/--output, --plot and --skip-bad-rows to a subcommand.
void add_common_options(CLI::App* sub, SensorOptions& o, const std::string& what);

using app::select_robot;  // app_support.hpp: battery's --robot too

/// Warnings on standard error, each once.
void print_warnings(const std::string& kind, const nlohmann::json& j);

/// In the report, when several robots were logged and one has no set of its own: each robot's
/// set or why it has none, and whether the robots were compared (calibrate::add_robots).
void print_robot_sets(const nlohmann::json& j);

/// Throws NoUsableFit when the fit is not usable.
void require_usable(const fit::FitResult& r, const std::string& what);

/// A fit that misses its data (fit::misfit_verdict: many times its replicate noise, or R^2 below
/// the floor) throws NoUsableFit (exit 1) naming `what`, unless --accept-misfit: then the verdict
/// joins `warnings`.
void require_fitting(const fit::RobustFit& r, const std::string& what, const SensorOptions& o,
                     std::vector<std::string>& warnings);

/// The outputs all or nothing: -o and the plot staged, renamed into place only when both were
/// written; then the JSON or the report on standard output (none when -o is standard output).
/// `plot(stage, path)` stages the figure.
template <class Report, class Plot>
int finish(const std::string& kind, const SensorOptions& o, const nlohmann::json& j, Report report, Plot plot) {
  logs::OutputStage stage;
  const std::string text = json_text(j);  // refuses a NaN before anything is written
  print_warnings(kind, j);
  if (!o.output.empty()) stage.write(o.output, text);
  if (!o.plot.empty()) plot(stage, o.plot);
  stage.commit();
  if (!o.output.empty()) std::cerr << kind << ": wrote " << o.output << '\n';
  if (!o.plot.empty()) std::cerr << kind << ": drew " << o.plot << '\n';
  print_figure_warnings(kind);
  if (logs::is_standard_output(o.output)) return 0;  // -o -: the file is standard output, alone
  if (o.json) {
    std::cout << text;
  } else {
    report();
    // Every warning the file holds (the fit's, the misfit's, the robots' comparison's), as printed
    // on standard error above.
    if (j.contains("warnings") && !j["warnings"].empty())
      std::cout << j["warnings"].size() << " warnings (on standard error and in the JSON)\n";
  }
  return 0;
}

/// A sensor subcommand from its parts: the logs read (--skip-bad-rows) and selected (--robot),
/// `to_json(logs, options, &fit)` for the pooled file, the same per robot when there are several
/// (compared by their fits' values, calibrate::add_robots),
/// then finish() with the fit's report (calibrate::report_text) and `draw(stage, path, fit)`.
template <class Fit, class ToJson, class Draw>
int run_sensor(const std::string& kind, logs::Kind log_kind, const SensorOptions& o, ToJson to_json, Draw draw) {
  std::vector<std::string> all_copies;  // of every robot's logs; the file says those of the logs it fits
  const auto logs =
      select_robot(split_robot_columns(kind, read_logs_reporting(kind, o.logs, log_kind, o.skip_bad_rows, &all_copies)), o.robot);
  const std::vector<std::string> copies = identical_logs(logs);  // logs of the same rows: in the file's warnings
  Fit f;
  nlohmann::json j = to_json(logs, o, &f);
  calibrate::add_warnings(j, copies);
  calibrate::add_robots(j, logs, [&](const std::vector<logs::Log>& mine) {
    Fit robot;  // compared by its fitted values, not by re-reading its file
    nlohmann::json file = to_json(mine, o, &robot);
    return calibrate::RobotCalibration{std::move(file), calibrate::robot_estimates(robot)};
  });
  return finish(kind, o, j, [&] {
    std::fputs(calibrate::report_text(f).c_str(), stdout);
    print_robot_sets(j);
  }, [&](logs::OutputStage& stage, const std::string& path) { draw(stage, path, f); });
}

/// A rail as --help prints it ("4095").
inline std::string rail(double value) {
  char text[32];
  std::snprintf(text, sizeof text, "%g", value);
  return text;
}

/// What a sensor subcommand is called and says in --help.
struct SensorCommand {
  const char* name;         ///< the subcommand, also the kind in messages ("camera")
  logs::Kind kind;          ///< the logs it reads
  const char* description;  ///< --help's line
  const char* logs_what;    ///< "Camera" in "Camera logs (CSV, docs/logs.md)"
  std::string footer_note;  ///< after the log format in --help (rails and ranges from kind_facts)
};

/// Adds the subcommand: the common options, the log format in --help, and run_sensor<Fit> with
/// `to_json` and `draw` (see run_sensor) as what main runs after parsing.
template <class Fit, class ToJson, class Draw>
void add_sensor_command(CLI::App& app, Action& action, const SensorCommand& c, ToJson to_json, Draw draw) {
  auto o = std::make_shared<SensorOptions>();
  CLI::App* sub = app.add_subcommand(c.name, c.description);
  add_common_options(sub, *o, c.logs_what);
  sub->footer(log_format_footer(c.kind, c.footer_note));
  sub->callback([o, &action, c, to_json, draw] {
    action = [o, c, to_json, draw] { return run_sensor<Fit>(c.name, c.kind, *o, to_json, draw); };
  });
}

}  // namespace epuck2::app::sensors
