// The battery calibration's human report and the voltage->charge map's, from their results
// (calibrate::fit_battery, the map); the coefficient file is battery_json.cpp's.
#include "epuck2/calibrate/battery_report.hpp"

#include <cmath>
#include <cstdio>
#include <string>

#include "epuck2/calibrate/published.hpp"
#include "epuck2/calibrate/report_text.hpp"
#include "epuck2/models/plugin_battery_tables.hpp"
#include "epuck2/fit/report.hpp"

namespace epuck2::calibrate {

namespace {

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

void write_fit_statistics(Text& out, const fit::FitResult& r, const fit::AutocorrelationCorrection& a) {
  const fit::FitStatistics st = fit::fit_statistics(r);
  out("    n %zu, k %d, RSS %.4g charge², MSE %.4g charge², reduced χ² = RSS/(n-k) %.4g charge², R² %.5f, %s\n",
      st.n, st.k, st.rss, st.mse, st.reduced_chi2, st.r2, fit::format_information_criteria(st, 1).c_str());
  const auto c = fit::correlations(r);
  out("    correlations (|r| > 0.1):");
  if (c.empty()) out(" none");
  for (std::size_t i = 0; i < c.size(); ++i) out("%s %s-%s %+.3f", i ? "," : "", c[i].a.c_str(), c[i].b.c_str(), c[i].r);
  out("\n");
  if (a.computed)
    out("    residuals' lag-1 autocorrelation %.5f within %zu runs: n_eff = n (1-rho)/(1+rho) = %.4g of %zu, "
        "standard errors x %.3g [corrected; AR(1), not cluster-robust: %s]\n",
        a.rho, a.series, a.n_eff, a.n, a.factor, a.cluster_why_not.c_str());
  else
    out("    autocorrelation of the residuals not estimated (%s)\n", a.why_not.c_str());
}

std::string lifetime(const SpeedFit& s) {
  const std::string why = lifetime_no_error_why(s);
  if (!why.empty()) {
    char h[64];
    std::snprintf(h, sizeof h, "%.3g h; ", s.lifetime_s / 3600.0);
    return fit::format_uncertain(s.lifetime_s, 0.0, "s", std::string(h) + why);
  }
  return fit::format_uncertain(s.lifetime_s, s.lifetime_std_error_s, "s") + " (" +
         fit::format_uncertain(s.lifetime_s / 3600.0, s.lifetime_std_error_s / 3600.0, "h") + "; mean of the " +
         std::to_string(s.runs) + " runs' ends, standard error over runs)";
}

}  // namespace

std::string report_text(const BatteryFit& f, bool robust, double reject_sd) {
  Text out;
  out("Battery discharge fits (%zu runs, %zu speeds); charge is normalised (1 = full), time in s\n", f.sources.size(),
      f.speeds.size());
  out("Loss: %s; no reading is censored (a charge has no rail).\n",
      robust ? "Huber (--robust)" : "least squares");
  out("Standard errors: the covariance's, and [corrected] for the residuals' autocorrelation within a run (AR(1): "
      "n_eff = n (1-rho)/(1+rho), errors x sqrt(n/n_eff)); a run's rows are a time series, so the covariance's alone "
      "are too small. Two runs a speed cannot show a misfit that lasts a whole run: the between-run spread is in the "
      "lifetime's error, not in the curves'.\n\n");
  out("%6s %4s %6s  %-44s  %9s %9s %9s %9s\n", "speed", "runs", "rows", "lifetime", "MSE simp", "linear", "cubic",
      "approx");
  for (const auto& s : f.speeds) {
    const std::string life = fit::format_uncertain(s.lifetime_s, s.lifetime_std_error_s, "s",
                                                   s.runs < 2 ? "one run" : "runs end together");
    out("%6.2f %4zu %6zu  %-44s  %9.5f %9.5f %9.5f %9.5f\n", s.speed_cm_s, s.runs, s.observations, life.c_str(),
        s.mse.simple, s.mse.linear, s.mse.cubic, s.mse.approximated);
  }
  out("(speed in cm/s; MSE in charge²)\n");
  for (const auto& s : f.speeds) {
    out("\nSpeed %.2f cm/s: %zu runs, %zu rows; lifetime %s\n", s.speed_cm_s, s.runs, s.observations, lifetime(s).c_str());
    out("  Cubic, charge(t) = d + c t + b t² + a t³:\n");
    const auto& a = s.cubic_autocorrelation;
    out("    %s\n    %s\n    %s\n    %s\n", parameter(s.cubic, "d", "charge", a).c_str(),
        parameter(s.cubic, "c", "charge/s", a).c_str(), parameter(s.cubic, "b", "charge/s^2", a).c_str(),
        parameter(s.cubic, "a", "charge/s^3", a).c_str());
    write_fit_statistics(out, s.cubic, a);
    out("  Linear (paper): slope -1/lifetime = %s\n",
        fit::format_uncertain(s.linear_slope_per_s, s.linear_slope_std_error, "1/s",
                              "the lifetime has no standard error: " + lifetime_no_error_why(s))
            .c_str());
    out("    free least-squares line (reference): %s, %s\n",
        parameter(s.free_line, "intercept", "charge", s.free_line_autocorrelation).c_str(),
        parameter(s.free_line, "slope_per_s", "1/s", s.free_line_autocorrelation).c_str());
    write_fit_statistics(out, s.free_line, s.free_line_autocorrelation);
    const auto& p = s.piecewise;
    const auto& pa = s.piecewise_autocorrelation;
    out("  Approximated: knots (0 s, 1), (x1, y1), (x2, y2), (lifetime - 1 s, y3) (fixed by the model), then a 1 s drop to 0%s\n",
        p.usable ? "" : ("  [" + p.message + "]").c_str());
    out("    %s, %s\n    %s, %s, %s\n", parameter(p, "x1_s", "s", pa).c_str(), parameter(p, "x2_s", "s", pa).c_str(),
        parameter(p, "y1", "charge", pa).c_str(), parameter(p, "y2", "charge", pa).c_str(),
        parameter(p, "y3", "charge", pa).c_str());
    write_fit_statistics(out, p, pa);
  }
  out("\nSimple model: m0 = %s (static), m1 = %s (moving); from the lifetimes' standard errors\n",
      fit::format_uncertain(f.simple_static_slope_per_s, f.simple_static_std_error, "1/s",
                            "the static lifetime has no standard error: " + simple_static_no_error_why(f))
          .c_str(),
      fit::format_uncertain(f.simple_moving_slope_per_s, f.simple_moving_std_error, "1/s",
                            "the moving lifetimes have no standard error: " + simple_moving_no_error_why(f))
          .c_str());
  out("Average MSE over speeds: simple %.4f, linear %.4f, cubic %.4f, approximated %.4f charge²\n", f.mse.simple,
      f.mse.linear, f.mse.cubic, f.mse.approximated);
  std::size_t wild = 0;
  for (const auto& s : f.speeds) wild += s.outliers.size();
  if (reject_sd > 0)
    out("Readings left out as wild (more than %g robust sd from their speed's cubic; --least-squares keeps them): %zu\n",
        reject_sd, wild);
  else
    out("Every reading kept (--least-squares)\n");
  for (const auto& s : f.speeds)
    for (std::size_t i = 0; i < s.outliers.size() && i < 3; ++i)
      out("  %.2f cm/s: %s\n", s.speed_cm_s, s.outliers[i].c_str());
  if (!f.tables) {
    const SpeedCoverage c = speed_coverage(f);
    out("No complete model tables: they need runs at every speed 0, 1, ..., 15 cm/s and only those.\n");
    out("  speeds covered (cm/s): %s\n  speeds missing (cm/s): %s\n", speeds_text(c.covered).c_str(),
        speeds_text(c.missing).c_str());
    if (!c.other.empty()) out("  speeds other than 0..15 (cm/s): %s\n", speeds_text(c.other).c_str());
  }
  for (const auto& w : f.warnings) out("Warning: %s\n", w.c_str());
  return out.str();
}

std::string charge_map_text(const ChargeMap& m, const std::string& map_from_file, const ChargeConversionReport& c) {
  Text out;
  out("\nVoltage->charge map (%s): charge = f(voltage_v%s), %zu knots, voltage range %.4f..%.4f V",
      map_from_file.empty() ? "fitted to the logs with both columns" : ("from " + map_from_file).c_str(),
      m.has_load() ? " + load offset per speed" : "", m.knots_v.size(), m.voltage_min_v, m.voltage_max_v);
  if (std::isfinite(m.residual_sd))
    out(", residual sd %.3g (largest %.3g) over %zu rows", m.residual_sd, m.max_abs_residual, m.observations);
  out("\n  knots (V: charge):");
  for (std::size_t k = 0; k < m.knots_v.size(); ++k) out(" %.4f: %.4f%s", m.knots_v[k], m.knot_charge[k], k + 1 < m.knots_v.size() ? "," : "");
  out("\n");
  if (m.has_load()) {
    out("  load offsets (cm/s: V):");
    for (std::size_t k = 0; k < m.load_speeds_cm_s.size(); ++k) out(" %g: %+.4f", m.load_speeds_cm_s[k], m.load_offset_v[k]);
    out("\n");
  }
  if (!m.load_why.empty()) out("  load term: %s\n", m.load_why.c_str());
  if (c.logs > 0)
    out("  used for %zu voltage-only logs (%zu rows); clamped to its range: %zu below, %zu above\n", c.logs, c.rows,
        c.below_range, c.above_range);
  return out.str();
}

nlohmann::json charge_conversion_json(const ChargeConversionReport& c, const std::string& map_from_file) {
  if (c.logs == 0) return nullptr;
  return {{"logs", c.logs},
          {"rows", c.rows},
          {"clamped_below_range", c.below_range},
          {"clamped_above_range", c.above_range},
          {"clamped_rows", c.clamped},
          {"map", map_from_file.empty() ? "fitted to the logs with both columns" : map_from_file}};
}

namespace {

namespace mb = models::battery;

nlohmann::json as_json(const ModelMse& m) {
  nlohmann::json j = nlohmann::json::object();
  for (mb::Model model : mb::kAllModels) j[std::string(mb::to_string(model))] = m.get(model);
  return j;
}

}  // namespace

Table5 table5(const std::vector<BatteryRun>& runs, const BatteryFit& f, std::size_t logs, double tick_s) {
  Table5 t;
  t.logs = logs;
  t.speeds = f.speeds.size();
  t.tick_s = tick_s;
  t.coverage = speed_coverage(f);
  t.analytic = f.mse;
  t.simulated = simulated_mse(runs, *f.tables, mb::Behaviour::argos_compatible, tick_s);
  t.argos_cubic_stalls = mb::argos_cubic_stalls(*f.tables, tick_s);
  t.simulated_corrected = simulated_mse(runs, *f.tables, mb::Behaviour::corrected, tick_s);
  t.plugin_tables_simulated = simulated_mse(runs, mb::plugin_tables(), mb::Behaviour::argos_compatible, tick_s);
  t.published_analytic = paper_table5_analytic();
  t.published_argos = paper_table5_argos();
  return t;
}

nlohmann::json table5_json(const Table5& t) {
  const ModelMse& pa = t.published_analytic;
  const ModelMse& pg = t.published_argos;
  nlohmann::json ratio_a = nlohmann::json::object(), ratio_s = nlohmann::json::object();
  for (mb::Model m : mb::kAllModels) {
    ratio_a[std::string(mb::to_string(m))] = t.analytic.get(m) / pa.get(m);
    ratio_s[std::string(mb::to_string(m))] = t.simulated.get(m) / pg.get(m);
  }
  return {
      {"complete", true},
      {"speeds_covered_cm_s", t.coverage.covered},
      {"speeds_missing_cm_s", t.coverage.missing},
      {"speeds_other_cm_s", t.coverage.other},
      {"logs", t.logs},
      {"speeds", t.speeds},
      {"tick_s", t.tick_s},
      {"analytic", as_json(t.analytic)},
      {"simulated", as_json(t.simulated)},
      {"simulated_corrected", as_json(t.simulated_corrected)},
      {"plugin_tables_simulated", as_json(t.plugin_tables_simulated)},
      {"published", {{"analytic", as_json(pa)}, {"argos", as_json(pg)}}},
      {"ratio_to_published", {{"analytic", ratio_a}, {"simulated", ratio_s}}},
      {"warnings", t.argos_cubic_stalls.empty() ? nlohmann::json::array()
                                                : nlohmann::json::array({"simulated cubic: " + mb::argos_cubic_stall_text(t.argos_cubic_stalls, t.tick_s)})},
  };
}

std::string table5_text(const Table5& t) {
  Text out;
  const ModelMse& pa = t.published_analytic;
  const ModelMse& pg = t.published_argos;
  out("Table 5: average MSE (charge units^2) over %zu speeds, %zu logs\n\n", t.speeds, t.logs);
  out("%-34s %9s %9s %9s %13s\n", "source", "Simple", "Linear", "Cubic", "Approximated");
  auto row = [&out](const char* name, const ModelMse& m) {
    out("%-34s %9.4f %9.4f %9.4f %13.4f\n", name, m.simple, m.linear, m.cubic, m.approximated);
  };
  row("analytic (fitted to these logs)", t.analytic);
  row("paper, analytic", pa);
  row("simulated, fitted tables (ARGoS)", t.simulated);
  // The ARGoS row's Cubic cell when the plug-in's arithmetic cannot run these tables: said beside it.
  if (!t.argos_cubic_stalls.empty())
    out("  ^ its Cubic cell: %s\n", mb::argos_cubic_stall_text(t.argos_cubic_stalls, t.tick_s).c_str());
  row("paper, ARGoS", pg);
  row("simulated, fitted, corrected", t.simulated_corrected);
  row("simulated, plug-in's tables", t.plugin_tables_simulated);
  out("\nratio analytic/paper:  simple %.2f  linear %.2f  cubic %.2f  approximated %.2f\n", t.analytic.simple / pa.simple,
      t.analytic.linear / pa.linear, t.analytic.cubic / pa.cubic, t.analytic.approximated / pa.approximated);
  out("ratio simulated/paper: simple %.2f  linear %.2f  cubic %.2f  approximated %.2f\n", t.simulated.simple / pg.simple,
      t.simulated.linear / pg.linear, t.simulated.cubic / pg.cubic, t.simulated.approximated / pg.approximated);
  return out.str();
}

std::string charge_conversion_text(const ChargeConversionReport& c, const std::string& map_from_file, double map_residual_sd) {
  Text out;
  if (c.logs == 0) return out.str();
  // A map given by hand has no residual sd (`residual_sd` null in its file): said, not printed as nan.
  char sd[96];
  if (std::isfinite(map_residual_sd)) std::snprintf(sd, sizeof sd, "residual sd %.3g", map_residual_sd);
  else std::snprintf(sd, sizeof sd, "%s", map_from_file.empty() ? "no residual sd" : "no residual sd: the file's map has none");
  out("\nCharge of %zu voltage-only logs from voltage_v through the voltage->charge map %s (%s); "
      "clamped to its range: %zu below, %zu above.\n",
      c.logs, map_from_file.empty() ? "fitted to the logs with both columns" : ("of " + map_from_file).c_str(), sd,
      c.below_range, c.above_range);
  return out.str();
}

}  // namespace epuck2::calibrate
