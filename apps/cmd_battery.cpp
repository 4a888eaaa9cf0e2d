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

// A fitted parameter: value ± the covariance's standard error, and the error corrected for the
// residuals' autocorrelation beside it.
std::string parameter(const fit::FitResult& r, const std::string& name, const std::string& unit,
                      const fit::AutocorrelationCorrection& a) {
  const double e = r.std_error(name);
  std::string why;
  for (const auto& p : r.parameters)
    if (p.name == name) why = p.std_error_why;
  std::string text = name + " = " + fit::format_uncertain(r.value(name), e, fit::pretty_unit(unit), why);
  if (std::isfinite(e) && e > 0 && a.std_error(name) > e) text += " [corrected ± " + fit::format_error(a.std_error(name)) + "]";
  return text;
}

void print_fit_statistics(const fit::FitResult& r, const fit::AutocorrelationCorrection& a) {
  const fit::FitStatistics st = fit::fit_statistics(r);
  std::printf("    n %zu, k %d, RSS %.4g charge², MSE %.4g charge², reduced χ² = RSS/(n-k) %.4g charge², R² %.5f, %s\n",
              st.n, st.k, st.rss, st.mse, st.reduced_chi2, st.r2, fit::format_information_criteria(st, 1).c_str());
  const auto c = fit::correlations(r);
  std::printf("    correlations (|r| > 0.1):");
  if (c.empty()) std::printf(" none");
  for (std::size_t i = 0; i < c.size(); ++i) std::printf("%s %s-%s %+.3f", i ? "," : "", c[i].a.c_str(), c[i].b.c_str(), c[i].r);
  std::printf("\n");
  if (a.computed)
    std::printf("    residuals' lag-1 autocorrelation %.5f within %zu runs: n_eff = n (1-rho)/(1+rho) = %.4g of %zu, "
                "standard errors x %.3g [corrected; AR(1), not cluster-robust: %s]\n",
                a.rho, a.series, a.n_eff, a.n, a.factor, a.cluster_why_not.c_str());
  else
    std::printf("    autocorrelation of the residuals not estimated (%s)\n", a.why_not.c_str());
}

std::string lifetime(const calibrate::SpeedFit& s) {
  if (s.runs < 2 || !(s.lifetime_std_error_s > 0)) {
    char h[64];
    std::snprintf(h, sizeof h, "%.3g h; ", s.lifetime_s / 3600.0);
    return fit::format_uncertain(s.lifetime_s, 0.0, "s",
                                 std::string(h) + (s.runs < 2 ? "the end of the only run's log: no spread to estimate an error from"
                                                              : "the runs end at the same time"));
  }
  return fit::format_uncertain(s.lifetime_s, s.lifetime_std_error_s, "s") + " (" +
         fit::format_uncertain(s.lifetime_s / 3600.0, s.lifetime_std_error_s / 3600.0, "h") + "; mean of the " +
         std::to_string(s.runs) + " runs' ends, standard error over runs)";
}

void print_report(const calibrate::BatteryFit& f, bool robust, double reject_sd) {
  std::printf("Battery discharge fits (%zu runs, %zu speeds); charge is normalised (1 = full), time in s\n", f.sources.size(),
              f.speeds.size());
  std::printf("Loss: %s; no reading is censored (a charge has no rail).\n",
              robust ? "Huber (--robust)" : "least squares");
  std::printf("Standard errors: the covariance's, and [corrected] for the residuals' autocorrelation within a run (AR(1): "
              "n_eff = n (1-rho)/(1+rho), errors x sqrt(n/n_eff)); a run's rows are a time series, so the covariance's alone "
              "are too small. Two runs a speed cannot show a misfit that lasts a whole run: the between-run spread is in the "
              "lifetime's error, not in the curves'.\n\n");
  std::printf("%6s %4s %6s  %-44s  %9s %9s %9s %9s\n", "speed", "runs", "rows", "lifetime", "MSE simp", "linear", "cubic",
              "approx");
  for (const auto& s : f.speeds) {
    std::string life = s.runs >= 2 && s.lifetime_std_error_s > 0 ? fit::format_uncertain(s.lifetime_s, s.lifetime_std_error_s, "s")
                                                                : fit::format_uncertain(s.lifetime_s, 0.0, "s", "one run");
    std::printf("%6.2f %4zu %6zu  %-44s  %9.5f %9.5f %9.5f %9.5f\n", s.speed_cm_s, s.runs, s.observations, life.c_str(),
                s.mse.simple, s.mse.linear, s.mse.cubic, s.mse.approximated);
  }
  std::printf("(speed in cm/s; MSE in charge²)\n");
  for (const auto& s : f.speeds) {
    std::printf("\nSpeed %.2f cm/s: %zu runs, %zu rows; lifetime %s\n", s.speed_cm_s, s.runs, s.observations, lifetime(s).c_str());
    std::printf("  Cubic, charge(t) = d + c t + b t² + a t³:\n");
    const auto& a = s.cubic_autocorrelation;
    std::printf("    %s\n    %s\n    %s\n    %s\n", parameter(s.cubic, "d", "charge", a).c_str(),
                parameter(s.cubic, "c", "charge/s", a).c_str(), parameter(s.cubic, "b", "charge/s^2", a).c_str(),
                parameter(s.cubic, "a", "charge/s^3", a).c_str());
    print_fit_statistics(s.cubic, a);
    std::printf("  Linear (paper): slope -1/lifetime = %s\n",
                fit::format_uncertain(s.linear_slope_per_s, s.linear_slope_std_error, "1/s",
                                      "the lifetime has no standard error")
                    .c_str());
    std::printf("    free least-squares line (reference): %s, %s\n",
                parameter(s.free_line, "intercept", "charge", s.free_line_autocorrelation).c_str(),
                parameter(s.free_line, "slope_per_s", "1/s", s.free_line_autocorrelation).c_str());
    print_fit_statistics(s.free_line, s.free_line_autocorrelation);
    const auto& p = s.piecewise;
    const auto& pa = s.piecewise_autocorrelation;
    std::printf("  Approximated: knots (0 s, 1), (x1, y1), (x2, y2), (lifetime - 1 s, y3) (fixed by the model), then a 1 s drop to 0%s\n",
                p.usable ? "" : ("  [" + p.message + "]").c_str());
    std::printf("    %s, %s\n    %s, %s, %s\n", parameter(p, "x1_s", "s", pa).c_str(), parameter(p, "x2_s", "s", pa).c_str(),
                parameter(p, "y1", "charge", pa).c_str(), parameter(p, "y2", "charge", pa).c_str(),
                parameter(p, "y3", "charge", pa).c_str());
    print_fit_statistics(p, pa);
  }
  std::printf("\nSimple model: m0 = %s (static), m1 = %s (moving); from the lifetimes' standard errors\n",
              fit::format_uncertain(f.simple_static_slope_per_s, f.simple_static_std_error, "1/s",
                                    "the static lifetime has no standard error (one run)")
                  .c_str(),
              fit::format_uncertain(f.simple_moving_slope_per_s, f.simple_moving_std_error, "1/s",
                                    "the moving lifetimes have no standard error (one run a speed)")
                  .c_str());
  std::printf("Average MSE over speeds: simple %.4f, linear %.4f, cubic %.4f, approximated %.4f charge²\n", f.mse.simple,
              f.mse.linear, f.mse.cubic, f.mse.approximated);
  std::size_t wild = 0;
  for (const auto& s : f.speeds) wild += s.outliers.size();
  if (reject_sd > 0)
    std::printf("Readings left out as wild (more than %g robust sd from their speed's cubic; --least-squares keeps them): %zu\n",
                reject_sd, wild);
  else
    std::printf("Every reading kept (--least-squares)\n");
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
  for (const auto& w : in.warnings) j["warnings"].push_back(w);
  for (const auto& m : misfits) j["warnings"].push_back(m + " (accepted by --accept-misfit).");
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
  for (const auto& m : misfits) std::cerr << "battery: warning: " << m << " (accepted by --accept-misfit).\n";
  if (!o.output.empty()) std::cerr << "battery: wrote " << o.output << '\n';
  for (const std::string& path : {o.plot, o.plot_lifetime, o.plot_charge_map})
    if (!path.empty()) std::cerr << "battery: drew " << path << '\n';
  print_figure_warnings("battery");
  if (o.json) {
    std::cout << text;
  } else {
    print_report(f, o.robust, reject_sd);
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
  sub->add_option("-o,--output", o->output, "Write the coefficient file (JSON), atomically")->type_name("FILE")->check(output_file());
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
  add_skip_bad_rows(sub, o->skip_bad_rows);
  sub->callback([o, &action] { action = [o] { return run_battery(*o); }; });
}

}  // namespace epuck2::app
