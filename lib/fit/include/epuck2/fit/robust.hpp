// Fits for measured logs as they come: readings clipped at a sensor's rails, wild readings,
// parameters the logs cannot determine (docs/fitting.md).
//
// The model predicts the *latent* reading of every observation (before the sensor's clamp). Each
// observation is either exact (the reading itself) or censored at a rail: a reading on the rail
// says only that the latent reading lies at or beyond it. The likelihood is Tobit's:
//
//   exact:       -log L_i = log sigma + (y_i - f_i)^2 / (2 sigma^2)        (+ const)
//   at_or_above: -log L_i = -log Phi((f_i - rail) / sigma)
//   at_or_below: -log L_i = -log Phi((rail - f_i) / sigma)
//
// stated to the engine as a fit::Problem over fit::readings_block (the engine's one treatment of
// readings, epuck2/fit/readings.hpp, the diagnosis's joint fit's too) and solved by
// Problem::solve with FitOptions::calibration(). The
// noise sigma is estimated with the parameters (EM: the expected squared deviation of a censored
// reading, sigma^2 (1 + z lambda(z)), stands in for its unknown square), unless it is given.
//
// Robust by default: the parameters are first found with Cauchy weights (iteratively reweighted,
// so that no reading pulls with more than a bounded force), then every exact reading farther than
// `reject_sd` noise standard deviations from the curve is left out as an outlier (and listed), and
// the fit is repeated until that set no longer changes. What remains is an ordinary Tobit maximum
// likelihood fit, with its usual covariance. `robust = false` gives plain least squares (Tobit).
//
// Identifiability: the engine's one check (check_identifiability, least_squares.hpp) at the
// solution; a parameter whose column of the Jacobian is zero, or that lies along a direction the
// data do not determine (rank-deficient, or condition number of the equilibrated normal matrix
// above `max_condition`), is held at its documented fallback (the plug-in's value) and reported
// in `not_identifiable`; the fit is repeated without it (the calibration's policy). No starting guess is ever reported as a
// result, and no NaN leaves this layer: a standard error that cannot be computed is NaN here with
// a reason in `std_error_why`, and the caller decides.
#pragma once

#include "epuck2/fit/jet.hpp"

#include <cmath>
#include <cstddef>
#include <functional>
#include <type_traits>
#include <limits>
#include <map>
#include <string>
#include <vector>

#include "epuck2/fit/least_squares.hpp"
#include "epuck2/fit/parameter.hpp"
#include "epuck2/fit/readings.hpp"

namespace epuck2::fit {

struct Observation {
  double value = 0;                       ///< the reading (the rail itself when censored)
  Censoring censoring = Censoring::none;  ///< at or beyond `value`
  std::string where;                      ///< "file:line", for the report
  int group = -1;                         ///< replicates: same conditions, same group (-1: none)
  /// Which robot read it (-1: not said). A reading is judged wild against the replicates of its own
  /// robot only (robots differ by more than their noise); the lack-of-fit test keeps the groups of
  /// conditions, which then span robots (LackOfFit::robots).
  int robot = -1;
};


struct RobustOptions {
  bool robust = true;              ///< false: plain (Tobit) least squares, no reading left out
  double reject_sd = 4.0;          ///< exact readings farther than this many sigma are outliers
  double cauchy_scale_sd = 2.385;  ///< Cauchy's scale for the first, reweighted pass (95 % efficiency)
  /// Known noise sd in the readings' units (NaN: estimated with the parameters).
  double noise_sd = std::numeric_limits<double>::quiet_NaN();
  /// Smallest noise sd the estimate may take (a quantised reading: 1/sqrt(12) of a count).
  double noise_floor = 0;
  /// Above this condition number of the column-equilibrated normal matrix, the parameter most
  /// along its least-determined direction is not identifiable (about 8 digits lost of 16).
  double max_condition = 1e8;
  int max_passes = 25;
};

/// Lack of fit against the replicates' own noise (observations sharing a group).
struct LackOfFit {
  bool tested = false;
  double replicate_sd = 0;   ///< pooled within-group sd
  double reduced_chi2 = 0;   ///< (lack-of-fit sum of squares / its dof) / replicate variance
  double p_value = 1;        ///< F(dof_lack, dof_pure) upper tail
  std::size_t groups = 0, dof_lack = 0, dof_pure = 0;
  /// Robots whose readings the tested groups pool: above 1, replicate_sd holds the robots'
  /// differences beside the reading noise (the curve is judged as the robots' average).
  std::size_t robots = 0;
  std::string why_not;       ///< when not tested
  /// Not tested because the replicates agree to the last digit (no floor, no known sd): no noise
  /// scale to judge a misfit by (most likely the same log given twice).
  bool replicates_agree_exactly = false;
  /// How far the curve misses the replicates' means, per reading (readings' units):
  /// sqrt(sum_g sum_i (mean_g - prediction)^2 / readings), and that over replicate_sd.
  double misfit_rms = 0, misfit_ratio = 0;
  /// The worst conditions, in words ("distances 5-15 mm: the curve misses by 300 counts, the
  /// readings above it"); empty when not tested.
  std::string worst;
};

/// A misfit the report warns about: the curve misses the replicates' means by more than this many
/// replicate sd (per reading, LackOfFit::misfit_ratio).
constexpr double kMisfitWarnRatio = 3.0;
/// A misfit that is not a calibration: beyond this many replicate sd, or an R^2 below
/// kMisfitR2Floor, the CLI exits 1 unless --accept-misfit (docs/fitting.md, "Lack of fit").
constexpr double kMisfitFailRatio = 10.0;
constexpr double kMisfitR2Floor = 0.9;
/// Below this R^2 (0 less rounding) the curve does worse than a flat line: exit 1 whatever else.
constexpr double kMisfitR2Negative = -0.01;

/// One set of replicates: readings under the same conditions and the fit's prediction for each
/// (readings' units). `condition` orders the groups and names them (e.g. a distance); `label`
/// names a group when the conditions are not one number. A spoilt group (censored or left-out
/// readings) is not tested.
struct ReplicateGroup {
  std::vector<double> readings, predictions;
  double condition = 0;
  std::string label;
  bool spoilt = false;
};

/// How `worst` names the conditions and the miss: "<conditions> A-B <condition_unit>: the curve
/// misses by X <unit>", conditions times condition_scale, misses times unit_scale; with
/// `conditions` empty, the worst group's label.
struct MisfitWords {
  std::string conditions, condition_unit, unit;
  double condition_scale = 1, unit_scale = 1;
};

/// The lack-of-fit F test of a fit with `free_parameters` against its replicates' own noise, with
/// the misfit ratio and the worst conditions. The replicate sd is at least `sd_floor` (a quantised
/// reading's 1/sqrt(12) of a count: identical replicates are not noise-free); without a floor,
/// replicates that agree exactly are not tested (why_not says so). `replicate_sd` > 0
/// with `dof_pure` replaces the noise estimated from the groups: the groups may then hold one
/// reading each (a maximum per distance, tested against the raw replicates' sd behind it).
LackOfFit lack_of_fit(const std::vector<ReplicateGroup>& groups, std::size_t free_parameters, const MisfitWords& words = {},
                      double sd_floor = 0, double replicate_sd = 0, std::size_t dof_pure = 0);

/// The sentence that stops a calibration (exit 1 unless --accept-misfit), or "" when the fit
/// passes: its misfit ratio beyond kMisfitFailRatio; its R^2 below kMisfitR2Floor with a misfit
/// beyond kMisfitWarnRatio; or its R^2 below kMisfitR2Negative.
std::string misfit_verdict(const LackOfFit& lof, double r2);

/// The warning for an R^2 below the floor that does not stop the calibration (the replicates show
/// no misfit, or there are none to tell), or "".
std::string misfit_warning(const LackOfFit& lof, double r2);

/// The fit's statistics (FitResult: names, values, standard errors, NaN with a reason in
/// std_error_why) and what the fit did with the readings.
struct RobustFit : FitResult {
  std::vector<Parameter> final_parameters;     ///< final values, bounds and fallbacks
  std::map<std::string, std::string> std_error_why;  ///< reason for every NaN standard error
  double noise_sd = 0;                         ///< estimated (or given) sigma, readings' units
  std::size_t exact = 0, censored_below = 0, censored_above = 0;  ///< of all readings given
  /// Readings inside the rails that the final fit kept (not outliers): the residuals of `rss`.
  std::size_t kept_exact = 0;
  /// Censored readings the final fit kept, per rail.
  std::size_t kept_censored_below = 0, kept_censored_above = 0;
  std::vector<std::size_t> outliers;           ///< indices of the readings left out
  std::vector<std::string> outlier_where;      ///< their file:line
  std::vector<std::string> not_identifiable;   ///< held at their fallback
  /// The engine's one identifiability check (check_identifiability), once per fit made: the last
  /// found every free parameter determined, each one before it held the parameter it names at its
  /// fallback (columns as the parameters' indices; no inverse kept).
  std::vector<Identifiability> identifiability;
  std::vector<std::string> warnings;           ///< sentences
  LackOfFit lack_of_fit;
  std::string method;                          ///< loss and censoring, in words
  std::vector<double> predictions;             ///< latent prediction per observation
  /// At the solution, per observation: the Tobit residual r_i (0 for a reading left out) and its
  /// derivatives over the parameters (n x m, zero columns for held ones); 1/2 sum r_i^2 is the
  /// negative log-likelihood, so J_i r_i is an observation's score (for cluster-robust errors).
  std::vector<double> scaled_residuals;
  Eigen::MatrixXd jacobian;
  double log_likelihood = 0;
  std::size_t censored() const { return censored_below + censored_above; }
};

/// Evaluates a model's latent predictions for every observation, and their derivatives with
/// respect to the parameters (row-major n x m) when `jacobian` is not null. False when a
/// prediction is not finite.
using ModelEvaluator = std::function<bool(const double* p, double* predictions, double* jacobian)>;

/// Below this many readings inside the rails per free parameter (the noise counting as one when
/// it is estimated), a robust fit warns that it is barely determined. Fewer readings than the
/// parameters and the noise, and it is refused (not usable, with the reason).
inline constexpr std::size_t kFewReadingsPerParameter = 3;

/// The most parameters a robust fit takes (one Jet size serves every model).
inline constexpr int kMaxRobustParameters = 8;

/// Wraps a model `template <typename T> bool operator()(const T* p, T* predictions) const` (all
/// observations at once) into an evaluator, derivatives by Jets.
template <class Model>
ModelEvaluator make_evaluator(const Model& model, std::size_t observations, std::size_t parameters) {
  return [model, observations, parameters](const double* p, double* predictions, double* jacobian) {
    using std::isfinite;
    if (jacobian == nullptr) {
      if (!model(p, predictions)) return false;
      for (std::size_t i = 0; i < observations; ++i)
        if (!isfinite(predictions[i])) return false;
      return true;
    }
    using Jet = fit::Jet<kMaxRobustParameters>;
    std::vector<Jet> pj(parameters), out(observations);
    for (std::size_t j = 0; j < parameters; ++j) pj[j] = Jet(p[j], static_cast<int>(j));
    if (!model(pj.data(), out.data())) return false;
    for (std::size_t i = 0; i < observations; ++i) {
      if (!isfinite(out[i].a)) return false;
      predictions[i] = out[i].a;
      for (std::size_t j = 0; j < parameters; ++j) jacobian[i * parameters + j] = out[i].v[static_cast<int>(j)];
    }
    return true;
  };
}

/// The fit described at the top of this file.
RobustFit fit_robust(const ModelEvaluator& model, const std::vector<Observation>& observations,
                     std::vector<Parameter> parameters, const RobustOptions& options = {});

template <class Model>
RobustFit fit_robust(const Model& model, const std::vector<Observation>& observations,
                     std::vector<Parameter> parameters, const RobustOptions& options = {}) {
  static_assert(!std::is_same_v<Model, ModelEvaluator>);
  const std::size_t m = parameters.size();
  return fit_robust(make_evaluator(model, observations.size(), m), observations, std::move(parameters), options);
}

/// The value of a Jet or a double (to branch on a parameter's value where a formula has a
/// limit the Jets cannot take, e.g. a time constant of exactly 0).
inline double scalar_value(double x) { return x; }
template <int N>
double scalar_value(const Jet<N>& x) { return x.a; }

// ----- Several robots -------------------------------------------------------------------------

/// Whether the parameter differs between robots more than their own uncertainties allow:
/// Cochran's Q = sum (x_r - x_w)^2 / se_r^2 against chi^2(R - 1), x_w the inverse-variance mean.
struct RobotSpread {
  std::string parameter;
  double spread_sd = 0;  ///< sample sd of the robots' values
  double q = 0;          ///< Cochran's Q
  std::size_t dof = 0;
  double p_value = 1;
  bool exceeds = false;  ///< p < kRobotSpreadP
};
inline constexpr double kRobotSpreadP = 0.01;

/// Per parameter of the first result, over the robots' fits (at least two usable).
std::vector<RobotSpread> robot_spread(const std::vector<const FitResult*>& robots);

// ----- Distributions --------------------------------------------------------------------------

/// Regularised upper incomplete gamma Q(a, x) = P(chi^2_{2a} > 2x).
double gamma_q(double a, double x);
double chi2_upper_tail(double chi2, double dof);
/// P(F(d1, d2) > f).
double f_upper_tail(double f, double d1, double d2);
// log_normal_cdf and normal_hazard_lower: epuck2/fit/readings.hpp.

}  // namespace epuck2::fit
