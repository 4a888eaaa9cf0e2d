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
};

void print_charge_map(const BatteryInput& in) {
  if (!in.map) return;
  const calibrate::ChargeMap& m = *in.map;
  std::printf("\nVoltage->charge map (%s): charge = f(voltage_v%s), %zu knots, voltage range %.4f..%.4f V",
              in.map_from_file.empty() ? "fitted to the logs with both columns" : ("from " + in.map_from_file).c_str(),
              m.has_load() ? " + load offset per speed" : "", m.knots_v.size(), m.voltage_min_v, m.voltage_max_v);
  if (std::isfinite(m.residual_sd))
    std::printf(", residual sd %.3g (largest %.3g) over %zu rows", m.residual_sd, m.max_abs_residual, m.observations);
  std::printf("\n  knots (V: charge):");
  for (std::size_t k = 0; k < m.knots_v.size(); ++k) std::printf(" %.4f: %.4f%s", m.knots_v[k], m.knot_charge[k], k + 1 < m.knots_v.size() ? "," : "");
  std::printf("\n");
  if (m.has_load()) {
    std::printf("  load offsets (cm/s: V):");
    for (std::size_t k = 0; k < m.load_speeds_cm_s.size(); ++k) std::printf(" %g: %+.4f", m.load_speeds_cm_s[k], m.load_offset_v[k]);
    std::printf("\n");
  }
  if (!m.load_why.empty()) std::printf("  load term: %s\n", m.load_why.c_str());
  const auto& c = in.conversion;
  if (c.logs > 0)
    std::printf("  used for %zu voltage-only logs (%zu rows); clamped to its range: %zu below, %zu above\n", c.logs, c.rows,
                c.below_range, c.above_range);
}

void print_report(const calibrate::BatteryFit& f) {
  std::printf("Battery discharge fits (%zu runs, %zu speeds)\n", f.sources.size(), f.speeds.size());
  std::printf("%6s %4s %6s %16s  %-60s %12s  %8s %8s %8s %8s\n", "speed", "runs", "rows", "lifetime_s",
              "cubic d, c, b, a  (+- standard error)", "linear_slope", "mse_simp", "mse_lin", "mse_cub", "mse_appr");
  for (const auto& s : f.speeds) {
    char cubic[160];
    std::snprintf(cubic, sizeof cubic, "%.4f(%.0e) %.4e(%.0e) %.4e(%.0e) %.4e(%.0e)", s.cubic.value("d"),
                  s.cubic.std_error("d"), s.cubic.value("c"), s.cubic.std_error("c"), s.cubic.value("b"),
                  s.cubic.std_error("b"), s.cubic.value("a"), s.cubic.std_error("a"));
    std::printf("%6.2f %4zu %6zu %9.1f+-%5.1f  %-60s %12.5e  %8.5f %8.5f %8.5f %8.5f\n", s.speed_cm_s, s.runs,
                s.observations, s.lifetime_s, s.lifetime_std_error_s, cubic, s.linear_slope_per_s, s.mse.simple,
                s.mse.linear, s.mse.cubic, s.mse.approximated);
  }
  std::printf("\nApproximated model breakpoints (knots (0,1), (x1,y1), (x2,y2), (lifetime-1,y3), then a 1 s drop to 0):\n");
  for (const auto& s : f.speeds) {
    const auto& p = s.piecewise;
    std::printf("%6.2f  x1 = %7.0f +- %4.0f s  x2 = %7.0f +- %4.0f s  y1 = %.4f  y2 = %.4f  y3 = %.4f%s\n", s.speed_cm_s,
                p.value("x1_s"), p.std_error("x1_s"), p.value("x2_s"), p.std_error("x2_s"), p.value("y1"), p.value("y2"),
                p.value("y3"), p.usable ? "" : ("  [" + p.message + "]").c_str());
  }
  std::printf("\nSimple model: m0 = %.6e +- %.1e /s (static), m1 = %.6e +- %.1e /s (moving)\n", f.simple_static_slope_per_s,
              f.simple_static_std_error, f.simple_moving_slope_per_s, f.simple_moving_std_error);
  std::printf("Average MSE over speeds: simple %.4f, linear %.4f, cubic %.4f, approximated %.4f\n", f.mse.simple,
              f.mse.linear, f.mse.cubic, f.mse.approximated);
  std::size_t wild = 0;
  for (const auto& s : f.speeds) wild += s.outliers.size();
  std::printf("Readings left out as wild (more than 6 robust sd from their speed's cubic; --least-squares keeps them): %zu\n", wild);
  for (const auto& s : f.speeds)
    for (std::size_t i = 0; i < s.outliers.size() && i < 3; ++i)
      std::printf("  %.2f cm/s: %s\n", s.speed_cm_s, s.outliers[i].c_str());
  if (!f.tables) {
    const calibrate::SpeedCoverage c = calibrate::speed_coverage(f);
    std::printf("No complete model tables: they need runs at every speed 0, 1, ..., 15 cm/s and only those.\n");
    std::printf("  speeds covered (cm/s): %s\n  speeds missing (cm/s): %s\n", calibrate::speeds_text(c.covered).c_str(),
                calibrate::speeds_text(c.missing).c_str());
    if (!c.other.empty()) std::printf("  speeds other than 0..15 (cm/s): %s\n", calibrate::speeds_text(c.other).c_str());
  }
  for (const auto& w : f.warnings) std::printf("Warning: %s\n", w.c_str());
}

int run_battery(const BatteryOptions& o) {
  const BatteryInput in = read_battery_input("battery", o.logs, o.skip_bad_rows, o.charge_map, true);
  const auto& runs = in.runs;
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
  nlohmann::json j = calibrate::battery_fit_to_json(f);
  for (const auto& w : in.warnings) j["warnings"].push_back(w);
  if (in.map) {
    j["charge_map"] = calibrate::charge_map_to_json(*in.map);
    if (!in.map_from_file.empty()) j["charge_map"]["from_file"] = in.map_from_file;
  }
  if (const nlohmann::json c = conversion_json(in); !c.is_null()) j["charge_conversion"] = c;
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
  for (const auto& w : f.warnings) std::cerr << "battery: warning: " << w << '\n';
  if (!o.output.empty()) std::cerr << "battery: wrote " << o.output << '\n';
  for (const std::string& path : {o.plot, o.plot_lifetime, o.plot_charge_map})
    if (!path.empty()) std::cerr << "battery: drew " << path << '\n';
  if (o.json) {
    std::cout << text;
  } else {
    print_report(f);
    print_charge_map(in);
  }
  return 0;
}
}  // namespace

void setup_battery(CLI::App& app, Action& action) {
  auto o = std::make_shared<BatteryOptions>();
  CLI::App* sub = app.add_subcommand("battery", "Fit the four discharge models (simple, linear, cubic, approximated) per speed");
  sub->add_option("logs", o->logs, "Battery discharge logs (CSV, docs/logs.md#battery)")->required()->check(CLI::ExistingFile);
  sub->add_flag("--json", o->json, "Print one JSON object instead of the report");
  sub->add_option("-o,--output", o->output, "Write the coefficient file (JSON), atomically")->type_name("FILE");
  sub->add_option("--plot", o->plot, "Draw the logs and the four fitted models per speed to FILE (.png, .svg or .pdf, by the extension)")
      ->type_name("FILE")
      ->check(figure_file());
  sub->add_option("--plot-lifetime", o->plot_lifetime,
                  "Draw lifetime against speed, as the paper's Fig. 10b, to FILE (.png, .svg or .pdf, by the extension)")
      ->type_name("FILE")
      ->check(figure_file());
  sub->add_flag("--robust", o->robust, "Huber loss instead of least squares");
  sub->add_flag("--least-squares", o->least_squares,
                "Keep every reading (by default readings more than 6 robust sd from a speed's cubic are left out and listed)");
  // Charge runs from 0 to 1: a threshold above 1 is least squares, and 0 is no loss at all (the
  // cubic fit then fails).
  sub->add_option("--robust-scale", o->robust_scale, "Huber threshold in charge units")
      ->capture_default_str()
      ->check(finite_range(1e-6, 1.0));
  add_charge_map_option(sub, o->charge_map);
  sub->add_option("--plot-charge-map", o->plot_charge_map, "Draw the voltage->charge map and the rows it was fitted to (PNG)");
  sub->footer(log_format_footer(logs::Kind::battery,
                                "Optional: voltage_v (with charge: the voltage->charge map is fitted and written; without charge: "
                                "converted through the map). One speed per run; the last row is the moment the robot stopped."));
  add_skip_bad_rows(sub, o->skip_bad_rows);
  sub->callback([o, &action] { action = [o] { return run_battery(*o); }; });
}

}  // namespace epuck2::app
