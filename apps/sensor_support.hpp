// Shared by the sensor subcommands (proximity, light, ground, camera, drive): the subcommand and
// its common options (add_sensor_command), the JSON shape every sensor coefficient file has, the
// report's common lines, and the output sequence (-o atomically, then the plot, then --json or
// the human report). The functions are defined in sensor_support.cpp (compiled once); the
// templates that take a subcommand's own lambdas stay here.
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

/// The logs of `robot` (all when empty); exit 2 listing the robots when none is that one.
std::vector<logs::Log> select_robot(std::vector<logs::Log> all, const std::string& robot);

/// The robots of the logs, in order of first appearance.
std::vector<std::string> robots_of(const std::vector<logs::Log>& all);

/// {"kind", "parameters": {}, "std_errors": {}, "sources"}: the shape the codegen reads
/// (docs/coefficient-files.md); `sources` are the logs' paths.
nlohmann::json skeleton(const std::string& kind, const std::vector<logs::Log>& logs);

/// A JSON number, or null for NaN/infinity (JSON has no NaN).
nlohmann::json number(double v);

/// Appends to a JSON array member, creating it.
void append(nlohmann::json& j, const std::string& key, const nlohmann::json& v);

/// What a fit did with the readings, for the coefficient file's `fits` (docs/coefficient-files.md):
/// the loss (`method`) and the censoring, the statistics under lmfit's conventions (n, k, RSS in
/// `rss_unit`, MSE, reduced chi^2, R^2, AIC, BIC), the Tobit likelihood's criteria, the
/// correlations, and for a time series (`autocorrelation` given) the correction of its errors.
nlohmann::json fit_details(const fit::RobustFit& r, const std::string& rss_unit = "",
                           const fit::AutocorrelationCorrection* autocorrelation = nullptr);

/// Copies a fit's parameters (named `prefix` + name) and standard errors into the skeleton, with
/// a reason for every standard error that is null, and what the fit did into `fits`, `censored`,
/// `outliers`, `not_identifiable` and `warnings`. `key` names the fit in `fits`.
/// What a fit did (under `fits`.`key`), added to the file's totals: `censored`, `outliers`,
/// `not_identifiable` (names with `prefix`), `lack_of_fit`.`key`.
/// `rss_unit`: the RSS's unit; `autocorrelation`: a time series' correction (its corrected
/// standard errors go to `std_errors_corrected`). The fit's correlations join the file's
/// `correlations` (names with `prefix`).
void add_aggregates(nlohmann::json& j, const fit::RobustFit& r, const std::string& key, const std::string& prefix = "",
                    const std::string& rss_unit = "", const fit::AutocorrelationCorrection* autocorrelation = nullptr);

/// The reason a standard error is null.
std::string std_error_reason(const fit::RobustFit& r, const std::string& name);

/// A parameter's unit from the file's `units` ("" when none).
std::string unit_of(const nlohmann::json& j, const std::string& name);

/// `rounded`.NAME: the value and its standard error as the report prints them (two significant
/// digits, the value rounded to match, the unit of `units`), or the value and why it has none.
void add_rounded(nlohmann::json& j, const std::string& name, double value, double std_error, const std::string& why);

/// Set `units` before: the rounded texts carry them.
void add_parameters(nlohmann::json& j, const fit::RobustFit& r, const std::string& prefix = "",
                    const std::string& key = "fit", const std::string& rss_unit = "",
                    const fit::AutocorrelationCorrection* autocorrelation = nullptr);

/// Readings left out before a fit (wild, beyond a range), each with its reason.
void add_left_out(nlohmann::json& j, const std::vector<calibrate::LeftOut>& rows);

/// The coefficient file's `noise` section (docs/coefficient-files.md): one entry per channel,
/// {sd, unit, per_sensor_sd (where sensors differ), per_sensor_n, from, n, groups (replicates),
/// argos_uniform_level (where the plug-in has such a noise)}. A channel whose noise could not be
/// measured is an error: every calibration writes its reading noise.
void add_noise(nlohmann::json& j, const std::vector<calibrate::ReadingNoise>& channels);

void add_warnings(nlohmann::json& j, const std::vector<std::string>& warnings);

/// Several robots: each robot's logs fitted alone (`fit` gives the same JSON as the pooled file),
/// their parameters and standard errors under `robots`, and for every parameter whether the
/// robots differ beyond their own uncertainties (Cochran's Q against chi^2, p < 0.01) under
/// `robot_spread`, with a warning when they do: the pooled set then describes no robot.
void add_robots(nlohmann::json& j, const std::vector<logs::Log>& all,
                const std::function<nlohmann::json(const std::vector<logs::Log>&)>& fit_logs);

/// The human report's statistics line (lmfit's conventions) for residuals in `unit`.
void print_statistics(const fit::FitStatistics& s, const std::string& unit, const char* indent = "  ");

/// The correlations with |r| > 0.1, or that there are none.
void print_correlations(const std::vector<fit::Correlation>& c, const char* indent = "  ");

/// The autocorrelation correction of a time series' standard errors, in words.
void print_autocorrelation(const fit::AutocorrelationCorrection& a, const char* indent = "  ");

/// The human report's lines on what a fit did with the readings: the loss, the censoring per
/// rail, the outliers, the statistics in `unit` (the readings' unit), the correlations, the
/// autocorrelation correction when given, the lack of fit. A reading without rails (`has_rails`
/// false: the camera's pixels, the encoders' steps) gets no rail counts and no Tobit line.
void print_handling(const fit::RobustFit& r, const std::string& unit = "", const char* indent = "  ",
                    const fit::AutocorrelationCorrection* autocorrelation = nullptr, bool has_rails = true);

/// The human report's line on a channel's reading noise (the coefficient file's `noise` entry).
void print_noise(const calibrate::ReadingNoise& n);

/// What every sensor report ends with: each channel's reading noise, then how many warnings there
/// were (each went to standard error).
void print_noise_and_warnings(const std::vector<calibrate::ReadingNoise>& channels,
                              const std::vector<std::string>& warnings);

/// A parameter line: value ± standard error (two significant digits, fit::format_uncertain), or
/// the reason there is none; `note` follows in parentheses; with an autocorrelation correction,
/// the corrected error beside the covariance's.
void print_parameter(const fit::RobustFit& r, const std::string& name, const std::string& unit = "",
                     const char* indent = "  ", const std::string& note = "",
                     const fit::AutocorrelationCorrection* autocorrelation = nullptr);

/// Warnings on standard error, each once.
void print_warnings(const std::string& kind, const nlohmann::json& j);

/// One warning on standard error per standard error written as null, with its reason.
void warn_undefined_std_errors(const std::string& kind, const nlohmann::json& j);

/// Throws NoUsableFit when the fit is not usable.
void require_usable(const fit::FitResult& r, const std::string& what);

/// A fit that misses its data (fit::misfit_verdict: many times its replicate noise, or R^2 below
/// the floor) throws NoUsableFit (exit 1) naming `what`, unless --accept-misfit: then the verdict
/// joins `warnings`.
void require_fitting(const fit::RobustFit& r, const std::string& what, const SensorOptions& o,
                     std::vector<std::string>& warnings);

/// The outputs all or nothing: -o and the plot staged, renamed into place only when both were
/// written; then the JSON or the report on standard output. `plot(stage, path)` stages the figure.
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
  if (o.json) {
    std::cout << text;
  } else {
    report();
  }
  return 0;
}

/// A sensor subcommand from its parts: the logs read (--skip-bad-rows) and selected (--robot),
/// `to_json(logs, options, &fit)` for the pooled file, the same per robot when there are several,
/// then finish() with `report(fit)` and `draw(stage, path, fit)`.
template <class Fit, class ToJson, class Report, class Draw>
int run_sensor(const std::string& kind, logs::Kind log_kind, const SensorOptions& o, ToJson to_json, Report report,
               Draw draw) {
  const auto logs = select_robot(read_logs_reporting(kind, o.logs, log_kind, o.skip_bad_rows), o.robot);
  Fit f;
  nlohmann::json j = to_json(logs, o, &f);
  add_robots(j, logs, [&](const std::vector<logs::Log>& mine) { return to_json(mine, o, nullptr); });
  return finish(kind, o, j, [&] { report(f); }, [&](logs::OutputStage& stage, const std::string& path) { draw(stage, path, f); });
}

/// What a sensor subcommand is called and says in --help.
struct SensorCommand {
  const char* name;         ///< the subcommand, also the kind in messages ("camera")
  logs::Kind kind;          ///< the logs it reads
  const char* description;  ///< --help's line
  const char* logs_what;    ///< "Camera" in "Camera logs (CSV, docs/logs.md)"
  const char* footer_note;  ///< after the log format in --help
};

/// Adds the subcommand: the common options, the log format in --help, and run_sensor<Fit> with
/// `to_json`, `report` and `draw` (see run_sensor) as what main runs after parsing.
template <class Fit, class ToJson, class Report, class Draw>
void add_sensor_command(CLI::App& app, Action& action, const SensorCommand& c, ToJson to_json, Report report, Draw draw) {
  auto o = std::make_shared<SensorOptions>();
  CLI::App* sub = app.add_subcommand(c.name, c.description);
  add_common_options(sub, *o, c.logs_what);
  sub->footer(log_format_footer(c.kind, c.footer_note));
  sub->callback([o, &action, c, to_json, report, draw] {
    action = [o, c, to_json, report, draw] { return run_sensor<Fit>(c.name, c.kind, *o, to_json, report, draw); };
  });
}

}  // namespace epuck2::app::sensors
