// A calibration's results as JSON: the report fields every coefficient file and diagnosis report
// shares (docs/coefficient-files.md#fit-statistics: goodness of fit under one convention,
// correlations, the autocorrelation correction of time-series fits, values with their standard
// errors as rounded text), and the shape every sensor coefficient file has (the skeleton, what a
// fit did with the readings, the noise section, the readings left out, the robots apart). The
// same results as text: report_text.hpp.
#pragma once

#include <functional>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "epuck2/calibrate/reading_noise.hpp"
#include "epuck2/calibrate/sensors.hpp"
#include "epuck2/fit/report.hpp"
#include "epuck2/fit/robust.hpp"
#include "epuck2/logs/log.hpp"

namespace epuck2::calibrate {

/// A JSON number, or null for NaN and infinity (JSON has no NaN).
nlohmann::json json_number(double v);

/// {"n", "free_parameters", "rss", "mse", "reduced_chi2", "r2", "aic", "bic", "rss_unit"}
/// (r2 null with "r2_why" when the data do not vary).
nlohmann::json statistics_json(const fit::FitStatistics& s, const std::string& rss_unit);

/// The conventions of statistics_json, once per file: {"reduced_chi2", "aic", "bic"} in words.
nlohmann::json statistics_conventions_json();

/// [{"a", "b", "r"}], names prefixed by `prefix`.
nlohmann::json correlations_json(const std::vector<fit::Correlation>& c, const std::string& prefix = "");

/// {"computed", "method" (what gives the corrected errors), "cluster_robust", "rho", "n", "n_eff",
/// "factor" (the AR(1) estimate; "why" instead when not computed), "series", and
/// "cluster_robust_why_not" when the errors are the AR(1) factor's}.
nlohmann::json autocorrelation_json(const fit::AutocorrelationCorrection& a);

/// The statistics of a censored, robust fit: n = the readings inside the rails it kept (the RSS's
/// residuals), k its free parameters.
fit::FitStatistics robust_statistics(const fit::RobustFit& r);

// ----- the sensor coefficient file's shape (docs/coefficient-files.md) -------------------------

/// {"kind", "parameters": {}, "std_errors": {}, "sources"}: the shape the codegen reads
/// (docs/coefficient-files.md); `sources` are the logs' paths.
nlohmann::json skeleton(const std::string& kind, const std::vector<logs::Log>& logs);

/// Appends to a JSON array member, creating it.
void append(nlohmann::json& j, const std::string& key, const nlohmann::json& v);

/// What a fit did with the readings, for the coefficient file's `fits` (docs/coefficient-files.md):
/// the loss (`method`) and the censoring, the statistics under lmfit's conventions (n, k, RSS in
/// `rss_unit`, MSE, reduced chi^2, R^2, AIC, BIC), the Tobit likelihood's criteria, the
/// correlations, and for a time series (`autocorrelation` given) the correction of its errors.
nlohmann::json fit_details(const fit::RobustFit& r, const std::string& rss_unit = "",
                           const fit::AutocorrelationCorrection* autocorrelation = nullptr);

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

/// Copies a fit's parameters (named `prefix` + name) and standard errors into the skeleton, with
/// a reason for every standard error that is null and the rounded texts, then add_aggregates
/// under `key`. Set `units` before: the rounded texts carry them.
void add_parameters(nlohmann::json& j, const fit::RobustFit& r, const std::string& prefix = "",
                    const std::string& key = "fit", const std::string& rss_unit = "",
                    const fit::AutocorrelationCorrection* autocorrelation = nullptr);

/// Readings left out before a fit (wild, beyond a range), each with its reason.
void add_left_out(nlohmann::json& j, const std::vector<LeftOut>& rows);

/// The coefficient file's `noise` section (docs/coefficient-files.md): one entry per channel,
/// {sd, unit, per_sensor_sd (where sensors differ), per_sensor_n, from, n, groups (replicates),
/// argos_uniform_level (where the plug-in has such a noise)}. A channel whose noise could not be
/// measured throws NoUsableFit: every calibration writes its reading noise.
void add_noise(nlohmann::json& j, const std::vector<ReadingNoise>& channels);

void add_warnings(nlohmann::json& j, const std::vector<std::string>& warnings);

/// The robots of the logs, in order of first appearance.
std::vector<std::string> robots_of(const std::vector<logs::Log>& all);

/// Several robots: each robot's logs fitted alone (`fit_logs` gives the same JSON as the pooled
/// file; a NoUsableFit it throws makes that robot `usable: false` with the reason), their
/// parameters and standard errors under `robots`, and for every parameter whether the robots
/// differ beyond their own uncertainties (Cochran's Q against chi^2, p < 0.01) under
/// `robot_spread`, with a warning when they do: the pooled set then describes no robot.
void add_robots(nlohmann::json& j, const std::vector<logs::Log>& all,
                const std::function<nlohmann::json(const std::vector<logs::Log>&)>& fit_logs);

}  // namespace epuck2::calibrate
