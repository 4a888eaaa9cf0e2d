// The sensor subcommands' shared code (apps/sensor_support.hpp): compiled once here rather than
// in every cmd_<sensor>.cpp that includes the header.
#include "sensor_support.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <iostream>
#include <map>

namespace epuck2::app::sensors {

void add_common_options(CLI::App* sub, SensorOptions& o, const std::string& what) {
  sub->add_option("logs", o.logs, what + " logs (CSV, docs/logs.md)")->required()->check(CLI::ExistingFile);
  sub->add_flag("--json", o.json, "Print one JSON object instead of the report");
  sub->add_option("-o,--output", o.output, "Write the coefficient file (JSON), atomically (-: to standard output, in place of the report)")->type_name("FILE")->check(output_file());
  sub->add_option("--plot", o.plot,
                  "Draw the data, the fitted curve and the plug-in's curve to FILE (.png, .svg or .pdf, by the extension)")
      ->type_name("FILE")
      ->check(figure_file())
      ->check(output_file());
  add_figure_options(sub);
  sub->add_flag("--least-squares", o.least_squares,
                "Plain least squares: no reading is left out as an outlier (readings on a rail stay censored)");
  sub->add_option("--reject-sd", o.reject_sd, "Robust fits: readings farther than this many noise sd are outliers")
      ->check(CLI::Range(2.0, 100.0));
  sub->add_option("--robot", o.robot, "Fit only this robot's logs (# robot: metadata, a robot column, or the file name)");
  add_skip_bad_rows(sub, o.skip_bad_rows);
  sub->add_flag("--accept-misfit", o.accept_misfit,
                "Write the calibration even when a fit misses its data by many times its replicate noise or its R^2 is "
                "below the floor (a warning instead of exit 1; docs/fitting.md)");
}

void print_warnings(const std::string& kind, const nlohmann::json& j) {
  if (!j.contains("warnings")) return;
  for (const auto& w : j["warnings"]) std::cerr << kind << ": warning: " << w.get<std::string>() << '\n';
}

void print_robot_sets(const nlohmann::json& j) {
  if (!j.contains("robots") || !j["robots"].is_object()) return;
  std::size_t usable = 0, without = 0;
  std::string lines;
  for (const auto& [id, set] : j["robots"].items()) {
    if (set.value("usable", false)) {
      ++usable;
      lines += "  " + id + ": its own set (robots." + id + ")\n";
    } else {
      ++without;
      lines += "  " + id + ": no set of its own (" + set.value("why", std::string("not fitted")) +
               "); its logs count only in the pooled fit\n";
    }
  }
  if (without == 0) return;
  std::printf("\nRobots (%zu logged):\n%s", usable + without, lines.c_str());
  if (usable < 2)
    std::printf("  the robots were not compared: %zu of %zu have a set of their own (robot_spread is empty)\n", usable,
                usable + without);
  else
    std::printf("  the %zu robots with a set of their own were compared (robot_spread)\n", usable);
}

void require_usable(const fit::FitResult& r, const std::string& what) {
  if (!r.usable) throw NoUsableFit(what + ": " + (r.message.empty() ? std::string("the solver found no solution") : r.message));
}

void require_fitting(const fit::RobustFit& r, const std::string& what, const SensorOptions& o,
                     std::vector<std::string>& warnings) {
  if (!r.usable) return;
  const std::string verdict = fit::misfit_verdict(r.lack_of_fit, r.r2);
  const std::string low_r2 = fit::misfit_warning(r.lack_of_fit, r.r2);
  if (!low_r2.empty()) warnings.push_back(what + ": " + low_r2 + ".");
  if (verdict.empty()) return;
  if (!o.accept_misfit)
    throw NoUsableFit(what + ": " + verdict + ". Nothing was written; --accept-misfit writes it anyway.");
  warnings.push_back(what + " (accepted by --accept-misfit): " + verdict + ".");
}

}  // namespace epuck2::app::sensors
