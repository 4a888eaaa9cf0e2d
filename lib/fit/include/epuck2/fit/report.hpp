// What every fit report says beyond the values (docs/fitting.md#what-a-report-gives): a value and
// its standard error as text (two significant digits, the value rounded to match), the
// correlations between parameters, the goodness-of-fit statistics under one stated convention,
// and a standard error corrected for autocorrelated residuals (time series).
#pragma once

#include <Eigen/Dense>
#include <cstddef>
#include <string>
#include <vector>

#include "epuck2/fit/least_squares.hpp"

namespace epuck2::fit {

// ----- Values and standard errors as text --------------------------------------------------------

/// A standard error rounded to two significant digits: 0.0034567 -> "0.0035", 789 -> "790",
/// 3.9e-07 -> "3.9e-07" (scientific below 1e-5 and from 1e7 on). "" when not finite and > 0.
std::string format_error(double std_error);

/// "value ± error unit": the error with two significant digits and the value rounded to the
/// same last digit (197.146 ± 3.43 -> "197.1 ± 3.4", 123456 ± 789 -> "123460 ± 790",
/// -2.5755e-13 ± 5.0e-15 -> "-2.576e-13 ± 5.0e-15"; scientific when the error is below 1e-5,
/// or 1e-7 for a value of at least 1e-3, or the value or error reaches 1e7). When the standard error is 0, NaN or
/// infinite, there is none to print: "value unit (why)", the value to 6 significant digits and
/// `why` saying what the value is (a table value, fixed by the protocol, not identifiable...);
/// without a `why`, "no standard error" (0) or "standard error undefined". Never "± 0".
std::string format_uncertain(double value, double std_error, const std::string& unit = "",
                             const std::string& why = "");

/// A unit for the human reports: "^2" and "^3" as superscripts (counts^2 -> counts²).
std::string pretty_unit(const std::string& unit);

// ----- Correlations ------------------------------------------------------------------------------

struct Correlation {
  std::string a, b;  ///< parameter names
  double r = 0;      ///< cov(a, b) / (se_a se_b), in [-1, 1]
};

/// The correlation matrix of a covariance: r_ij = C_ij / sqrt(C_ii C_jj); NaN in the rows and
/// columns of a parameter without variance (held, or not identifiable); 1 on the diagonal otherwise.
Eigen::MatrixXd correlation_matrix(const Eigen::MatrixXd& covariance);

/// The pairs of parameters (i < j, in the parameters' order) whose |r| exceeds `min_abs` (0.1:
/// lmfit's default for its report), from the fit's covariance. Empty without a covariance.
inline constexpr double kReportedCorrelation = 0.1;
std::vector<Correlation> correlations(const FitResult& r, double min_abs = kReportedCorrelation);

// ----- Goodness of fit ---------------------------------------------------------------------------

/// The statistics every report gives, under lmfit's conventions for an unweighted fit:
///   mse = RSS / n, reduced_chi2 = RSS / (n - k) (unit weights: in the residuals' units squared,
///   the residual variance), AIC = n ln(RSS / n) + 2k, BIC = n ln(RSS / n) + k ln n.
/// n counts the residuals in the RSS, k the free parameters.
struct FitStatistics {
  std::size_t n = 0;
  int k = 0;
  double rss = 0, mse = 0, reduced_chi2 = 0, r2 = 0, aic = 0, bic = 0;
};
inline constexpr const char* kReducedChi2Convention = "RSS / (n - k), unit weights (the residual variance)";
inline constexpr const char* kAicConvention = "n ln(RSS/n) + 2k (lmfit)";
inline constexpr const char* kBicConvention = "n ln(RSS/n) + k ln(n) (lmfit)";
/// Why AIC and BIC are not given when the RSS is 0: their ln(RSS/n) has no finite value.
inline constexpr const char* kInformationCriteriaUndefined =
    "RSS is 0 to rounding: R² is 1 to double precision, the fit passes through every reading, and ln(RSS/n) has "
    "no value, or one that says only how the arithmetic rounded";
/// From n, k, RSS and R^2 (NaN reduced chi^2 when n <= k; NaN AIC and BIC when n = 0 or RSS = 0,
/// or R^2 within 1e-15 of 1 (RSS 0 to rounding): kInformationCriteriaUndefined says why).
FitStatistics fit_statistics(std::size_t n, int k, double rss, double r2);
/// "AIC 12.3, BIC 15.6" with `decimals` decimals, or "AIC and BIC undefined (why)" when they are NaN.
std::string format_information_criteria(const FitStatistics& s, int decimals);
/// From a FitResult whose RSS is over its `observations` residuals.
FitStatistics fit_statistics(const FitResult& r);

// ----- Autocorrelated residuals ------------------------------------------------------------------

/// Standard errors from the covariance assume independent residuals. Residuals of a time series
/// (a discharge run, a drive run) are not: each row repeats much of its neighbour's error, and
/// the covariance's errors are too small by about sqrt(n / n_eff). With the residuals' lag-1
/// autocorrelation rho (AR(1)): n_eff = n (1 - rho) / (1 + rho), and every standard error is
/// multiplied by factor = sqrt(n / n_eff) = sqrt((1 + rho) / (1 - rho)) (1 when rho <= 0: a
/// negative correlation is not taken to shrink them). Exact for the mean of an AR(1) series as n
/// grows, and for a regression on a smooth regressor (time, travel) likewise.
///
/// The lag-1 model misses a misfit that persists through a whole run (each log's own offset or
/// capacity: tiny lag-1 correlation, but the same sign for a thousand rows). With enough runs
/// (kMinClusters), the corrected errors are instead cluster-robust with each run a cluster (the
/// sandwich (JᵀJ)⁻¹ (Σ_c s_c s_cᵀ) (JᵀJ)⁻¹ G/(G − 1), s_c = Σ_{i in run c} J_iᵀ r_i), which holds
/// whatever the correlation inside a run, as long as runs are independent of each other.
/// Either way a corrected error is never below the covariance's.
struct AutocorrelationCorrection {
  bool computed = false;
  std::string why_not;     ///< when not computed
  double rho = 0;          ///< lag-1 autocorrelation of the residuals (pooled over the series)
  std::size_t n = 0;       ///< residuals
  std::size_t pairs = 0;   ///< neighbouring pairs inside one series
  std::size_t series = 0;  ///< series (runs) the residuals come from
  double n_eff = 0;        ///< effective number of independent residuals (at least 1)
  double factor = 1;       ///< AR(1): multiplies every standard error
  /// The corrected standard errors (apply_ar1 or apply_cluster_robust), by parameter name; NaN
  /// where the fit gives none.
  std::vector<std::string> names;
  std::vector<double> std_errors;
  bool cluster_robust = false;   ///< std_errors are cluster-robust over runs (else AR(1))
  std::string cluster_why_not;   ///< why not cluster-robust
  std::string method;            ///< how std_errors were computed, in words
  double std_error(const std::string& name) const;  ///< NaN when none
};
inline constexpr const char* kAutocorrelationMethod =
    "AR(1): lag-1 autocorrelation rho of the residuals within each run, n_eff = n (1 - rho) / (1 + rho), "
    "standard errors times sqrt(n / n_eff)";
inline constexpr const char* kClusterRobustMethod =
    "cluster-robust over runs: (J^T J)^-1 (sum over runs of s s^T) (J^T J)^-1 G/(G-1), s = J^T r over a run's rows, "
    "G runs; never below the covariance's";
/// Fewest runs for the cluster-robust errors (below, the AR(1) factor).
inline constexpr std::size_t kMinClusters = 5;

/// rho = sum of e_i e_{i+1} over neighbouring residuals (same series, both finite) / sum of e_i^2
/// (finite ones), e the residuals less their mean. `series[i]` names residual i's series (run);
/// residuals i and i + 1 are neighbours in time when their series are equal. A NaN residual
/// (left out, censored) breaks the chain. Not computed with fewer than 3 pairs.
AutocorrelationCorrection autocorrelation_correction(const std::vector<double>& residuals,
                                                     const std::vector<int>& series);

/// Sets a.names and a.std_errors from the fit: each standard error times a.factor (1 when a is
/// not computed), never below the covariance's; a.method says so.
void apply_ar1(AutocorrelationCorrection& a, const FitResult& fit);

/// With at least kMinClusters runs: a.std_errors cluster-robust (above) from `jacobian` (rows:
/// residuals, columns: the fit's parameters in order; columns of parameters without a standard
/// error are ignored), `residuals` (rows with a NaN residual or a negative run left out) and each
/// row's `run`. Fewer runs, or a singular JᵀJ: apply_ar1, with a.cluster_why_not saying why.
void apply_cluster_robust(AutocorrelationCorrection& a, const FitResult& fit, const Eigen::MatrixXd& jacobian,
                          const std::vector<double>& residuals, const std::vector<int>& run);

}  // namespace epuck2::fit
