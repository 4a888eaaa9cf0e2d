// Shared by the sensor subcommands (proximity, light, ground, camera, drive): the common options,
// the JSON shape every sensor coefficient file has, and the output sequence (-o atomically, then
// the plot, then --json or the human report).
#pragma once

#include <cmath>
#include <iostream>
#include <memory>
#include <sstream>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "app_support.hpp"
#include "commands.hpp"
#include "epuck2/fit/least_squares.hpp"
#include "epuck2/logs/log.hpp"
#include "epuck2/logs/output.hpp"

namespace epuck2::app::sensors {

struct SensorOptions {
  std::vector<std::string> logs;
  bool json = false;
  std::string output;
  std::string plot;
};

/// Adds LOGS..., --json, -o/--output and --plot to a subcommand.
inline void add_common_options(CLI::App* sub, SensorOptions& o, const std::string& what) {
  sub->add_option("logs", o.logs, what + " logs (CSV, shared/spec/logs.md)")->required()->check(CLI::ExistingFile);
  sub->add_flag("--json", o.json, "Print one JSON object instead of the report");
  sub->add_option("-o,--output", o.output, "Write the coefficient file (JSON), atomically");
  sub->add_option("--plot", o.plot, "Draw the data, the fitted curve and the plug-in's curve (PNG)");
}

/// {"kind", "parameters": {}, "std_errors": {}, "mse", "observations", "sources"}: the shape the
/// codegen reads (shared/spec/cli.md).
inline nlohmann::json skeleton(const std::string& kind, const std::vector<std::string>& sources) {
  nlohmann::json j;
  j["kind"] = kind;
  j["parameters"] = nlohmann::json::object();
  j["std_errors"] = nlohmann::json::object();
  j["sources"] = sources;
  return j;
}

/// A JSON number, or null for NaN/infinity (JSON has no NaN).
inline nlohmann::json number(double v) { return std::isfinite(v) ? nlohmann::json(v) : nlohmann::json(nullptr); }

/// Copies a fit's parameters (named `prefix` + name) and standard errors into the skeleton. A
/// standard error the data do not determine is written as null, with its reason under
/// "std_error_why" (same name): the file says why instead of holding a bare null.
inline void add_parameters(nlohmann::json& j, const fit::FitResult& r, const std::string& prefix = "") {
  for (const auto& p : r.parameters) {
    j["parameters"][prefix + p.name] = p.value;  // a NaN value is not a usable fit: json_text refuses it
    if (std::isfinite(p.std_error)) {
      j["std_errors"][prefix + p.name] = p.std_error;
    } else {
      j["std_errors"][prefix + p.name] = nullptr;
      j["std_error_why"][prefix + p.name] = p.std_error_why.empty() ? std::string("undefined") : p.std_error_why;
    }
  }
}

/// One warning on standard error per standard error written as null, with its reason.
inline void warn_undefined_std_errors(const std::string& kind, const nlohmann::json& j) {
  if (!j.contains("std_error_why")) return;
  for (const auto& [name, why] : j.at("std_error_why").items())
    std::cerr << kind << ": warning: no standard error for " << name << ": " << why.get<std::string>() << '\n';
}

/// Throws NoUsableFit when the fit is not usable.
inline void require_usable(const fit::FitResult& r, const std::string& what) {
  if (!r.usable) throw NoUsableFit(what + ": " + (r.message.empty() ? std::string("the solver found no solution") : r.message));
}

/// The outputs all or nothing: -o and the plot staged, renamed into place only when both were
/// written; then the JSON or the report on standard output. `plot(stage, path)` stages the figure.
template <class Report, class Plot>
int finish(const std::string& kind, const SensorOptions& o, const nlohmann::json& j, Report report, Plot plot) {
  logs::OutputStage stage;
  const std::string text = json_text(j);  // refuses a NaN before anything is written
  warn_undefined_std_errors(kind, j);
  if (!o.output.empty()) stage.write(o.output, text);
  if (!o.plot.empty()) plot(stage, o.plot);
  stage.commit();
  if (!o.output.empty()) std::cerr << kind << ": wrote " << o.output << '\n';
  if (!o.plot.empty()) std::cerr << kind << ": drew " << o.plot << '\n';
  if (o.json) {
    std::cout << text;
  } else {
    report();
  }
  return 0;
}

/// A gnuplot datablock: `$name << EOD`, rows, `EOD`.
inline std::string datablock(const std::string& name, const std::vector<std::vector<double>>& rows) {
  std::ostringstream os;
  os.precision(10);
  os << '$' << name << " << EOD\n";
  for (const auto& r : rows) {
    for (std::size_t i = 0; i < r.size(); ++i) os << (i ? " " : "") << r[i];
    os << '\n';
  }
  os << "EOD\n";
  return os.str();
}

}  // namespace epuck2::app::sensors
