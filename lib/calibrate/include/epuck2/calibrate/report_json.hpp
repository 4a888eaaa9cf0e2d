// A calibration's results as JSON: the report fields every coefficient file and diagnosis report
// shares (docs/coefficient-files.md#fit-statistics: goodness of fit under one convention,
// correlations, the autocorrelation correction of time-series fits, values with their standard
// errors as rounded text), and the shape every sensor coefficient file has (the skeleton, what a
// fit did with the readings, the noise section, the readings left out, the robots apart). The
// same results as text: report_text.hpp.
#pragma once

#include <array>
#include <functional>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "epuck2/calibrate/reading_noise.hpp"
#include "epuck2/calibrate/sensors.hpp"
#include "epuck2/coefficients/model_file.hpp"
#include "epuck2/fit/report.hpp"
#include "epuck2/fit/robust.hpp"
#include "epuck2/logs/log.hpp"

namespace epuck2::calibrate {

/// A JSON number, or null for NaN and infinity (JSON has no NaN).
nlohmann::json json_number(double v);

/// {"n", "free_parameters", "rss", "mse", "reduced_chi2", "r2", "aic", "bic", "rss_unit"}
/// (r2 null with "r2_why" when the data do not vary).
nlohmann::json statistics_json(const fit::FitStatistics& s, const std::string& rss_unit);

/// What `n` counts in a calibration: the readings inside the rails that the fit kept (a censored
/// reading enters the Tobit likelihood, not the RSS).
inline constexpr const char* kCalibrationResidualsConvention = "residuals in the RSS (readings inside the rails that the fit kept)";
/// What `n` counts in a diagnosis: every residual it kept, a reading on a rail by its censored term.
inline constexpr const char* kDiagnosisResidualsConvention =
    "residuals in the RSS: every reading the diagnosis kept (wild readings left out), a reading on a rail by its "
    "censored (Tobit) term, as `loss` says";
/// The conventions of statistics_json, once per file: {"n", "reduced_chi2", "aic", "bic",
/// "correlations"} in words; `n_convention` says what n counts.
nlohmann::json statistics_conventions_json(const char* n_convention = kCalibrationResidualsConvention);

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

/// The file's model sections `model` ({"kind", "parameters", "noise"}: lib/coefficients'
/// calibration_model_json of the fit's model, the one writer of what a reader turns into a model)
/// with `std_errors` {} and `sources` (the logs' paths) beside them: the shape the codegen reads
/// (docs/coefficient-files.md). The calibration's report fields are added around it.
nlohmann::json skeleton(const nlohmann::json& model, const std::vector<logs::Log>& logs);

/// `write()`, the owner's model sections (coefficients::calibration_model_json of the fit's model),
/// with a model the owner refuses (a fitted value a reader would refuse: std::domain_error) made a
/// fit that is not usable (NoUsableFit, exit 1): such a calibration is never written.
nlohmann::json owned_model(const std::function<nlohmann::json()>& write);

/// What the file's owner writes beside the model from the calibration's noise `channels`: each
/// channel's pooled sd (coefficients::CalibrationExtras). Throws NoUsableFit for a channel whose
/// noise could not be measured: every calibration writes its reading noise.
coefficients::CalibrationExtras measured_noise(const std::vector<ReadingNoise>& channels);

/// A channel's noise per sensor, as a model holds it: each sensor's sd (a sensor without readings
/// of its own has the pooled one), or the pooled sd for every sensor when the channel has none.
template <std::size_t N>
std::array<double, N> per_sensor_noise(const ReadingNoise& c) {
  std::array<double, N> out{};
  for (std::size_t i = 0; i < N; ++i) out[i] = i < c.per_sensor_sd.size() ? c.per_sensor_sd[i] : c.sd;
  return out;
}

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

/// A fit's standard errors (named `prefix` + name) into the skeleton, with a reason for every
/// one that is null and the rounded texts (of the values the skeleton's `parameters` hold from the
/// model), then add_aggregates under `key`. Set `units` before: the rounded texts carry them.
void add_estimates(nlohmann::json& j, const fit::RobustFit& r, const std::string& prefix = "",
                    const std::string& key = "fit", const std::string& rss_unit = "",
                    const fit::AutocorrelationCorrection* autocorrelation = nullptr);

/// Readings left out before a fit (wild, beyond a range), each with its reason.
void add_left_out(nlohmann::json& j, const std::vector<LeftOut>& rows);

/// What the calibration says of how it measured each channel's noise, added to the channel of the
/// file's `noise` section (whose sd, per_sensor_sd and unit the owner wrote from the model,
/// docs/coefficient-files.md): per_sensor_n, from, n, groups (replicates), argos_uniform_level
/// (where the plug-in has such a noise).
void add_noise(nlohmann::json& j, const std::vector<ReadingNoise>& channels);

void add_warnings(nlohmann::json& j, const std::vector<std::string>& warnings);

/// The robots of the logs, in order of first appearance.
std::vector<std::string> robots_of(const std::vector<logs::Log>& all);

/// One robot's calibration, as add_robots compares and writes it.
struct RobotCalibration {
  /// Its coefficient file (coefficient_json of its fit): its `parameters` and `noise` are the
  /// owner's (calibration_model_json of the robot's model), copied into the robot's set.
  nlohmann::json file;
  /// Its fitted parameters with their standard errors, named as in `parameters` (`gain[0]`,
  /// `mean_a`, the camera's derived `aperture_deg`: robot_estimates): what the robots are compared by.
  std::vector<fit::ParameterEstimate> estimates;
};

/// `r`'s parameters renamed `prefix` + name + `suffix` (e.g. "mean_" + "a", "gain" + "[0]").
std::vector<fit::ParameterEstimate> named_estimates(const fit::FitResult& r, const std::string& prefix = "",
                                                    const std::string& suffix = "");

/// Several robots: each robot's logs fitted alone (`fit_logs`; a NoUsableFit it throws makes that
/// robot `usable: false` with the reason), its set under `robots` (its file's parameters, standard
/// errors and noise, written through lib/coefficients' add_robot_set, which reads it back), and
/// for every parameter of the robots' fits whether they differ beyond their own uncertainties
/// (Cochran's Q against chi^2, p < 0.01, fit::robot_spread on the fitted values) under
/// `robot_spread`, with a warning when they do: the pooled set then describes no robot.
void add_robots(nlohmann::json& j, const std::vector<logs::Log>& all,
                const std::function<RobotCalibration(const std::vector<logs::Log>&)>& fit_logs);

}  // namespace epuck2::calibrate
