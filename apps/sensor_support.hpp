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

namespace epuck2::app::sensors {

struct SensorOptions {
  std::vector<std::string> logs;
  bool json = false;
  std::string output;
  std::string plot;
  bool skip_bad_rows = false;
};

/// Adds LOGS..., --json, -o/--output, --plot and --skip-bad-rows to a subcommand.
inline void add_common_options(CLI::App* sub, SensorOptions& o, const std::string& what) {
  sub->add_option("logs", o.logs, what + " logs (CSV)")->required()->check(CLI::ExistingFile);
  sub->add_flag("--json", o.json, "Print one JSON object instead of the report");
  sub->add_option("-o,--output", o.output, "Write the coefficient file (JSON), atomically");
  sub->add_option("--plot", o.plot, "Draw the data, the fitted curve and the plug-in's curve (PNG)");
  add_skip_bad_rows(sub, o.skip_bad_rows);
}

/// {"kind", "parameters": {}, "std_errors": {}, "mse", "observations", "sources"}: the shape the
/// codegen reads (apps/cmd_codegen.cpp).
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

/// Copies a fit's parameters (named `prefix` + name) and standard errors into the skeleton.
inline void add_parameters(nlohmann::json& j, const fit::FitResult& r, const std::string& prefix = "") {
  for (const auto& p : r.parameters) {
    j["parameters"][prefix + p.name] = number(p.value);
    j["std_errors"][prefix + p.name] = number(p.std_error);
  }
}

/// Throws NoUsableFit when the fit is not usable.
inline void require_usable(const fit::FitResult& r, const std::string& what) {
  if (!r.usable) throw NoUsableFit(what + ": " + (r.message.empty() ? std::string("the solver found no solution") : r.message));
}

/// -o first (atomic), then the plot, then the JSON or the report on standard output.
template <class Report, class Plot>
int finish(const std::string& kind, const SensorOptions& o, const nlohmann::json& j, Report report, Plot plot) {
  if (!o.output.empty()) {
    write_json(j, o.output);
    std::cerr << kind << ": wrote " << o.output << '\n';
  }
  if (!o.plot.empty()) {
    plot(o.plot);
    std::cerr << kind << ": drew " << o.plot << '\n';
  }
  if (o.json) {
    write_json(j, "-");
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
