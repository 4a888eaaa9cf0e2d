// The report fields every coefficient file and diagnosis report shares (docs/coefficient-files.md
// #fit-statistics): goodness of fit under one convention, correlations, the autocorrelation
// correction of time-series fits, values with their standard errors as rounded text.
#pragma once

#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "epuck2/fit/report.hpp"
#include "epuck2/fit/robust.hpp"

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

}  // namespace epuck2::calibrate
