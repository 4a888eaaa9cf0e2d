#include "epuck2/calibrate/battery_json.hpp"

#include <cmath>

#include "epuck2/calibrate/report_json.hpp"
#include "epuck2/logs/json_location.hpp"

namespace epuck2::calibrate {

using namespace epuck2::fit;  // the engine (lib/fit)

namespace mb = models::battery;
using nlohmann::json;

namespace {

// How the battery's fits treat the readings (docs/battery-models.md).
std::string battery_method(bool robust, double reject_sd) {
  std::string m = robust ? "Huber loss (--robust)" : "least squares";
  m += reject_sd > 0 ? "; readings more than " + std::to_string(static_cast<int>(reject_sd)) +
                           " robust sd from the speed's cubic left out of every model first"
                     : "; every reading kept";
  return m + "; no censoring (a charge has no rail)";
}

json fit_stats(const FitResult& r, const AutocorrelationCorrection& autocorrelation, const std::string& method) {
  // r2 is null (not NaN) when the charge never changes: no variance to explain.
  json j = statistics_json(fit::fit_statistics(r), "charge^2");
  j["usable"] = r.usable;
  j["iterations"] = r.iterations;
  j["observations"] = r.observations;
  j["method"] = method;
  j["censored"] = {{"at_or_below", 0}, {"at_or_above", 0}};
  if (!std::isfinite(r.r2)) j["r2_why"] = "the charge does not vary: there is no variance to explain";
  j["correlations"] = correlations_json(fit::correlations(r));
  j["autocorrelation"] = autocorrelation_json(autocorrelation);
  return j;
}

// Standard errors times the autocorrelation correction's factor (null where there is none).
json corrected_errors(const FitResult& r, const AutocorrelationCorrection& a) {
  json j = json::object();
  // Only the parameters with a standard error to correct (the others' reasons: std_error_why).
  for (const auto& p : r.parameters)
    if (std::isfinite(a.std_error(p.name))) j[p.name] = a.std_error(p.name);
  return j;
}

// {name: "value ± error unit"} as the report prints them.
json rounded(const FitResult& r, const std::vector<std::string>& units) {
  json j = json::object();
  for (std::size_t k = 0; k < r.parameters.size(); ++k) {
    const auto& p = r.parameters[k];
    j[p.name] = fit::format_uncertain(p.value, p.std_error, k < units.size() ? units[k] : "",
                                      p.std_error_why.empty() ? "" : p.std_error_why);
  }
  return j;
}

json named_values(const FitResult& r, bool std_errors) {
  json j = json::object();
  for (const auto& p : r.parameters)
    j[p.name] = !std_errors ? json(p.value) : std::isfinite(p.std_error) ? json(p.std_error) : json(nullptr);
  return j;
}

// {"parameters", "std_errors"} of a fit, and "std_error_why" for the standard errors written as
// null (the data do not determine them): a reason beside every null.
json fit_values(const FitResult& r, const AutocorrelationCorrection& a, const std::vector<std::string>& units) {
  json j{{"parameters", named_values(r, false)}, {"std_errors", named_values(r, true)},
         {"std_errors_corrected", corrected_errors(r, a)}, {"rounded", rounded(r, units)}};
  for (const auto& p : r.parameters)
    if (!std::isfinite(p.std_error)) j["std_error_why"][p.name] = p.std_error_why.empty() ? "undefined" : p.std_error_why;
  return j;
}

json mse_json(const ModelMse& m) {
  json j = json::object();
  for (mb::Model model : mb::kAllModels) j[std::string(mb::to_string(model))] = m.get(model);
  return j;
}

}  // namespace

std::string lifetime_text(const SpeedFit& s) {
  const std::string why = lifetime_no_error_why(s);
  if (!why.empty()) return fit::format_uncertain(s.lifetime_s, 0.0, "s", why);
  return fit::format_uncertain(s.lifetime_s, s.lifetime_std_error_s, "s") + " (mean of " + std::to_string(s.runs) +
         " runs' ends, standard error over runs)";
}

json battery_fit_to_json(const BatteryFit& fit, bool robust, double reject_sd) {
  std::vector<std::string> unreadable;  // the warnings of tables written though no reader takes them
  const std::string method = battery_method(robust, reject_sd);
  json speeds = json::array();
  std::vector<std::string> outlier_rows;
  for (const SpeedFit& s : fit.speeds) {
    json cubic_se = json::array(), cubic_why = json::array(), corrected_cubic = json::array(), cubic_rounded = json::array();
    {
      // [d, c, b, a], parallel to `cubic`.
      const json by_name = rounded(s.cubic, {"charge", "charge/s", "charge/s^2", "charge/s^3"});
      for (const char* name : {"d", "c", "b", "a"}) cubic_rounded.push_back(by_name.value(name, std::string()));
    }
    for (const auto& p : s.cubic.parameters)
      corrected_cubic.push_back(json_number(s.cubic_autocorrelation.std_error(p.name)));
    bool cubic_undefined = false;
    for (const auto& p : s.cubic.parameters) {
      const bool defined = std::isfinite(p.std_error);
      cubic_se.push_back(defined ? json(p.std_error) : json(nullptr));
      cubic_why.push_back(defined ? json(nullptr) : json(p.std_error_why.empty() ? "undefined" : p.std_error_why));
      cubic_undefined = cubic_undefined || !defined;
    }
    // The speed's tables (what a reader turns into the model) by the file's owner, lib/coefficients;
    // the fit's report around them.
    const mb::CubicRow cubic{s.cubic.value("d"), s.cubic.value("c"), s.cubic.value("b"), s.cubic.value("a"), s.lifetime_s};
    json entry;
    try {
      // At its place in the file's `speeds`, which a refusal's JSON path names.
      entry = coefficients::battery_speed_to_json(s.speed_cm_s, cubic, s.linear_slope_per_s, s.segments, s.noise_sd, true,
                                                  speeds.size());
    } catch (const std::domain_error& e) {
      // Reported as fitted, and said: no reader takes these tables.
      entry = coefficients::battery_speed_to_json(s.speed_cm_s, cubic, s.linear_slope_per_s, s.segments, s.noise_sd, false,
                                                  speeds.size());
      unreadable.push_back(std::string("written as fitted though no reader takes it: ") + e.what() +
                           "; codegen, simulate, diagnose --coefficients and ARGoS refuse this file.");
    }
    entry.update(json{
        {"runs", s.runs},
        {"observations", s.observations},
        {"lifetime_std_error_s", s.lifetime_std_error_s},
        {"lifetime_h", s.lifetime_s / 3600.0},
        {"lifetime", lifetime_text(s)},
        {"cubic_std_errors", cubic_se},
        {"cubic_std_errors_corrected", corrected_cubic},
        {"cubic_rounded", cubic_rounded},
        {"linear_slope_std_error", s.linear_slope_std_error},
        {"linear_slope_rounded", fit::format_uncertain(s.linear_slope_per_s, s.linear_slope_std_error, "1/s",
                                                       "-1/lifetime, and the lifetime has no standard error: " +
                                                           lifetime_no_error_why(s))},
        {"free_line", fit_values(s.free_line, s.free_line_autocorrelation, {"charge", "1/s"})},
        {"breakpoints", fit_values(s.piecewise, s.piecewise_autocorrelation, {"s", "s", "charge", "charge", "charge"})},
        {"mse", mse_json(s.mse)},
        {"fit", {{"cubic", fit_stats(s.cubic, s.cubic_autocorrelation, method)},
                 {"free_line", fit_stats(s.free_line, s.free_line_autocorrelation, method)},
                 {"piecewise", fit_stats(s.piecewise, s.piecewise_autocorrelation, method)}}},
        {"outliers", s.outliers},
    });
    speeds.push_back(entry);
    outlier_rows.insert(outlier_rows.end(), s.outliers.begin(), s.outliers.end());
    if (cubic_undefined) {
      speeds.back()["cubic_std_error_why"] = cubic_why;
      speeds.back()["cubic_std_errors_corrected_why"] = cubic_why;
    }
  }
  // The Simple model's slopes by the owner too, their report beside them.
  json simple;
  try {
    simple = coefficients::battery_simple_to_json(fit.simple_static_slope_per_s, fit.simple_moving_slope_per_s);
  } catch (const std::domain_error& e) {
    simple = coefficients::battery_simple_to_json(fit.simple_static_slope_per_s, fit.simple_moving_slope_per_s, false);
    unreadable.push_back(std::string("written as fitted though no reader takes it: ") + e.what() +
                         "; codegen, simulate, diagnose --coefficients and ARGoS refuse this file.");
  }
  simple.update(json{{"static_std_error", fit.simple_static_std_error},
                     {"moving_std_error", fit.simple_moving_std_error},
                     {"static_rounded", fit::format_uncertain(fit.simple_static_slope_per_s, fit.simple_static_std_error, "1/s",
                                                              "-1/lifetime at 0 cm/s, which has no standard error: " +
                                                                  simple_static_no_error_why(fit))},
                     {"moving_rounded", fit::format_uncertain(fit.simple_moving_slope_per_s, fit.simple_moving_std_error, "1/s",
                                                              "-1/mean lifetime while moving, which has no standard error: " +
                                                                  simple_moving_no_error_why(fit))}});
  const SpeedCoverage coverage = speed_coverage(fit);
  std::vector<std::string> warnings = fit.warnings;
  warnings.insert(warnings.end(), unreadable.begin(), unreadable.end());
  return json{
      {"kind", "battery"},
      {"units", {{"time", "s"}, {"speed", "cm/s"}, {"charge", "1 (normalised, 1 = full)"},
                 {"speed_cm_s", "cm/s"}, {"lifetime_s", "s"}, {"lifetime_h", "h"},
                 {"cubic", {"charge", "charge/s", "charge/s^2", "charge/s^3"}},
                 {"linear_slope", "1/s (charge per s)"}, {"free_line.intercept", "charge"}, {"free_line.slope_per_s", "1/s"},
                 {"breakpoints.x1_s", "s"}, {"breakpoints.x2_s", "s"}, {"breakpoints.y1", "charge"},
                 {"breakpoints.y2", "charge"}, {"breakpoints.y3", "charge"},
                 {"segments.h", "charge"}, {"segments.m", "1/s"}, {"segments.x1_s", "s"}, {"segments.x2_s", "s"},
                 {"segments.y1", "charge"}, {"segments.y2", "charge"},
                 {"simple.static_slope_per_s", "1/s"}, {"simple.moving_slope_per_s", "1/s"},
                 {"mse", "charge^2"}, {"rss", "charge^2"}, {"noise_sd", "charge"}}},
      {"statistics_conventions", statistics_conventions_json()},
      {"models", "paper Appendix: simple, linear, cubic, approximated; see docs/battery-models.md"},
      {"sources", fit.sources},
      {"outliers", {{"count", outlier_rows.size()}, {"rows", outlier_rows}}},
      {"censored", 0},
      {"not_identifiable", json::array()},
      {"speeds", speeds},
      {"simple", simple},
      {"mse", mse_json(fit.mse)},
      {"complete_tables", fit.tables.has_value()},
      {"speeds_covered_cm_s", coverage.covered},
      {"speeds_missing_cm_s", coverage.missing},
      {"speeds_other_cm_s", coverage.other},
      {"warnings", warnings},
  };
}

}  // namespace epuck2::calibrate
