// epuck2-fit battery LOGS...: fits the paper's four discharge models per speed; human report,
// --json, -o coefficient file (atomic), --plot and --plot-lifetime figures (PNG, SVG or PDF).
#include <cmath>
#include <cstdio>
#include <iostream>

#include "app_support.hpp"
#include "battery_input.hpp"
#include "commands.hpp"
#include "log_help.hpp"
#include "epuck2/calibrate/battery.hpp"
#include "epuck2/calibrate/battery_json.hpp"
#include "epuck2/calibrate/battery_report.hpp"
#include "epuck2/fit/report.hpp"
#include "epuck2/plot/battery_figures.hpp"
#include "epuck2/plot/charge_map_figure.hpp"

namespace epuck2::app {

namespace {
struct BatteryOptions {
  std::vector<std::string> logs;
  bool json = false;
  std::string output;
  std::string plot;
  std::string plot_lifetime;
  bool robust = false;
  bool least_squares = false;
  double robust_scale = 0.05;
  bool skip_bad_rows = false;
  std::string charge_map;
  std::string plot_charge_map;
  bool accept_misfit = false;
  std::string robot;  ///< --robot: fit only this robot's logs
};

int run_battery(const BatteryOptions& o) {
  const BatteryInput in = read_battery_input("battery", o.logs, o.skip_bad_rows, o.charge_map, true, o.robot);
  const auto& runs = in.runs;
  const std::string robots_warning = calibrate::pooled_robots_warning(runs);
  if (!o.plot_charge_map.empty() && !in.map)
    throw UsageError("--plot-charge-map: there is no voltage->charge map to draw (no log has both charge and voltage_v, and no --charge-map)");
  fit::FitOptions options;
  options.robust = o.robust;
  options.robust_scale = o.robust_scale;
  const calibrate::BatteryFit f = calibrate::fit_battery(runs, options, o.least_squares ? 0.0 : calibrate::kBatteryRejectSd);
  std::string unusable;
  for (const auto& s : f.speeds) {
    char speed[32];
    std::snprintf(speed, sizeof speed, "%g", s.speed_cm_s);
    if (!s.cubic.usable) unusable += std::string(" cubic at ") + speed + " cm/s: " + s.cubic.message + ";";
    if (!s.piecewise.usable) unusable += std::string(" approximated (piecewise) at ") + speed + " cm/s: " + s.piecewise.message + ";";
  }
  if (!unusable.empty()) throw NoUsableFit(unusable);
  // A cubic that misses its replicates by many sd is not a calibration (as the sensor fits).
  std::vector<std::string> misfits;
  for (const auto& s : f.speeds) {
    const std::string verdict = fit::misfit_verdict(s.cubic_lack_of_fit, s.cubic.r2);
    if (verdict.empty()) continue;
    char speed[32];
    std::snprintf(speed, sizeof speed, "%g", s.speed_cm_s);
    misfits.push_back(std::string("cubic at ") + speed + " cm/s: " + verdict);
  }
  if (!misfits.empty() && !o.accept_misfit)
    throw NoUsableFit("battery " + misfits.front() + ". Nothing was written; --accept-misfit writes it anyway.");
  const double reject_sd = o.least_squares ? 0.0 : calibrate::kBatteryRejectSd;
  nlohmann::json j = calibrate::battery_fit_to_json(f, o.robust, reject_sd);
  // The fit's warnings, and the file's own beyond them (tables no reader takes).
  const std::vector<std::string> file_warnings = j.at("warnings").get<std::vector<std::string>>();
  for (const auto& w : in.warnings) j["warnings"].push_back(w);
  if (!robots_warning.empty()) j["warnings"].push_back(robots_warning);
  for (const auto& m : misfits) j["warnings"].push_back(m + " (accepted by --accept-misfit).");
  if (in.map) {
    j["charge_map"] = calibrate::charge_map_to_json(*in.map);
    if (!in.map_from_file.empty()) j["charge_map"]["from_file"] = in.map_from_file;
  }
  if (const nlohmann::json c = calibrate::charge_conversion_json(in.conversion, in.map_from_file); !c.is_null()) j["charge_conversion"] = c;
  const std::string text = json_text(j);  // refuses a NaN before anything is written
  // All or nothing: the coefficient file and the figures are renamed into place together.
  logs::OutputStage stage;
  if (!o.output.empty()) stage.write(o.output, text);
  if (!o.plot.empty()) plot::battery_fits_figure(stage, o.plot, runs, f);
  if (!o.plot_lifetime.empty()) plot::battery_lifetime_figure(stage, o.plot_lifetime, runs, f);
  if (!o.plot_charge_map.empty()) plot::charge_map_figure(stage, o.plot_charge_map, in.map_rows, *in.map);
  stage.commit();
  report_conversion("battery", in);
  for (const auto& w : in.warnings) std::cerr << "battery: warning: " << w << '\n';
  for (const auto& w : file_warnings) std::cerr << "battery: warning: " << w << '\n';
  for (const auto& m : misfits) std::cerr << "battery: warning: " << m << " (accepted by --accept-misfit).\n";
  if (!robots_warning.empty()) std::cerr << "battery: warning: " << robots_warning << '\n';
  if (!o.output.empty()) std::cerr << "battery: wrote " << o.output << '\n';
  for (const std::string& path : {o.plot, o.plot_lifetime, o.plot_charge_map})
    if (!path.empty()) std::cerr << "battery: drew " << path << '\n';
  print_figure_warnings("battery");
  if (logs::is_standard_output(o.output)) return 0;  // -o -: the file is standard output, alone
  if (o.json) {
    std::cout << text;
  } else {
    std::fputs(calibrate::report_text(f, o.robust, reject_sd).c_str(), stdout);
    if (in.map) std::fputs(calibrate::charge_map_text(*in.map, in.map_from_file, in.conversion).c_str(), stdout);
  }
  return 0;
}
}  // namespace

void setup_battery(CLI::App& app, Action& action) {
  auto o = std::make_shared<BatteryOptions>();
  CLI::App* sub = app.add_subcommand("battery", "Fit the four discharge models (simple, linear, cubic, approximated) per speed");
  sub->add_option("logs", o->logs, "Battery discharge logs (CSV, docs/logs.md#battery)")->required()->check(CLI::ExistingFile);
  sub->add_flag("--json", o->json, "Print one JSON object instead of the report");
  sub->add_option("-o,--output", o->output, "Write the coefficient file (JSON), atomically (-: to standard output, in place of the report)")->type_name("FILE")->check(output_file());
  sub->add_option("--plot", o->plot, "Draw the logs and the four fitted models per speed to FILE (.png, .svg or .pdf, by the extension)")
      ->type_name("FILE")
      ->check(figure_file())
      ->check(output_file());
  sub->add_option("--plot-lifetime", o->plot_lifetime,
                  "Draw lifetime against speed, as the paper's Fig. 10b, to FILE (.png, .svg or .pdf, by the extension)")
      ->type_name("FILE")
      ->check(figure_file())
      ->check(output_file());
  sub->add_flag("--robust", o->robust, "Huber loss instead of least squares");
  sub->add_flag("--accept-misfit", o->accept_misfit,
                "Write the models even when a speed's cubic misses its replicates (the runs' readings at the same time) "
                "by more than 10 of their sd (a warning, not exit 1)");
  sub->add_flag("--least-squares", o->least_squares,
                "Keep every reading (by default readings more than 6 robust sd from a speed's cubic are left out and listed)");
  // Charge runs from 0 to 1: a threshold above 1 is least squares, and 0 is no loss at all (the
  // cubic fit then fails).
  sub->add_option("--robust-scale", o->robust_scale, "Huber threshold in charge units")
      ->capture_default_str()
      ->check(finite_range(1e-6, 1.0));
  add_figure_options(sub);
  add_charge_map_option(sub, o->charge_map);
  sub->add_option("--plot-charge-map", o->plot_charge_map, "Draw the voltage->charge map and the rows it was fitted to (PNG)")->check(output_file());
  sub->footer(log_format_footer(logs::Kind::battery,
                                "Optional: voltage_v (with charge: the voltage->charge map is fitted and written; without charge: "
                                "converted through the map). One speed per run; the last row is the moment the robot stopped."));
  sub->add_option("--robot", o->robot,
                  "Fit only this robot's logs (# robot: metadata, a robot column, or the file name); without it the robots' "
                  "runs are pooled, with a warning when there are several");
  add_skip_bad_rows(sub, o->skip_bad_rows);
  sub->callback([o, &action] { action = [o] { return run_battery(*o); }; });
}

}  // namespace epuck2::app
