// epuck2-fit battery LOGS...: fits the paper's four discharge models per speed; human report,
// --json, -o coefficient file (atomic), --plot figures.
#include <cstdio>
#include <iostream>

#include "app_support.hpp"
#include "commands.hpp"
#include "log_help.hpp"
#include "epuck2/calibrate/battery.hpp"
#include "epuck2/calibrate/battery_json.hpp"
#include "epuck2/plot/battery_figures.hpp"

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
};

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
  if (!f.tables) std::printf("(the logs do not cover every speed 0..15 cm/s: no complete model tables)\n");
}

int run_battery(const BatteryOptions& o) {
  const auto logs = read_logs_reporting("battery", o.logs, logs::Kind::battery, o.skip_bad_rows);
  const auto runs = calibrate::battery_runs(logs);
  fit::FitOptions options;
  options.robust = o.robust;
  options.robust_scale = o.robust_scale;
  const calibrate::BatteryFit f = calibrate::fit_battery(runs, options, o.least_squares ? 0.0 : calibrate::kBatteryRejectSd);
  std::string unusable;
  for (const auto& s : f.speeds) {
    if (!s.cubic.usable) unusable += " cubic at " + std::to_string(s.speed_cm_s) + " cm/s: " + s.cubic.message + ";";
    if (!s.piecewise.usable) unusable += " piecewise at " + std::to_string(s.speed_cm_s) + " cm/s: " + s.piecewise.message + ";";
  }
  if (!unusable.empty()) throw NoUsableFit(unusable);
  const nlohmann::json j = calibrate::battery_fit_to_json(f);
  const std::string text = json_text(j);  // refuses a NaN before anything is written
  // All or nothing: the coefficient file and the figures are renamed into place together.
  logs::OutputStage stage;
  if (!o.output.empty()) stage.write(o.output, text);
  if (!o.plot.empty()) plot::battery_fits_png(stage, o.plot, runs, f);
  if (!o.plot_lifetime.empty()) plot::battery_lifetime_png(stage, o.plot_lifetime, runs, f);
  stage.commit();
  if (!o.output.empty()) std::cerr << "battery: wrote " << o.output << '\n';
  for (const std::string& path : {o.plot, o.plot_lifetime})
    if (!path.empty()) std::cerr << "battery: drew " << path << '\n';
  if (o.json) {
    std::cout << text;
  } else {
    print_report(f);
  }
  return 0;
}
}  // namespace

void setup_battery(CLI::App& app, Action& action) {
  auto o = std::make_shared<BatteryOptions>();
  CLI::App* sub = app.add_subcommand("battery", "Fit the four discharge models (simple, linear, cubic, approximated) per speed");
  sub->add_option("logs", o->logs, "Battery discharge logs (CSV, docs/logs.md#battery)")->required()->check(CLI::ExistingFile);
  sub->add_flag("--json", o->json, "Print one JSON object instead of the report");
  sub->add_option("-o,--output", o->output, "Write the coefficient file (JSON), atomically");
  sub->add_option("--plot", o->plot, "Draw the logs and the four fitted models per speed (PNG)");
  sub->add_option("--plot-lifetime", o->plot_lifetime, "Draw lifetime against speed, as the paper's Fig. 10b (PNG)");
  sub->add_flag("--robust", o->robust, "Huber loss instead of least squares");
  sub->add_flag("--least-squares", o->least_squares,
                "Keep every reading (by default readings more than 6 robust sd from a speed's cubic are left out and listed)");
  // Charge runs from 0 to 1: a threshold above 1 is least squares, and 0 is no loss at all (the
  // cubic fit then fails).
  sub->add_option("--robust-scale", o->robust_scale, "Huber threshold in charge units")
      ->capture_default_str()
      ->check(finite_range(1e-6, 1.0));
  sub->footer(log_format_footer(logs::Kind::battery, "Optional: voltage_v. One speed per run; the last row is the moment the robot stopped."));
  add_skip_bad_rows(sub, o->skip_bad_rows);
  sub->callback([o, &action] { action = [o] { return run_battery(*o); }; });
}

}  // namespace epuck2::app
