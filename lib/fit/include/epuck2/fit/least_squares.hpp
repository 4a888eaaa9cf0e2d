// The fitting layer's core: nonlinear least squares with Ceres, and what every fit reports.
// This header does not include Ceres (its solver side is lib/fit/src/solver.hpp, lib/fit's own):
// the many units that only read a FitResult do not parse it.
//
// A fit returns a FitResult that says whether it is usable and why (models never throw; this layer
// never throws for numerical trouble either). Standard errors come from the covariance
// (J^T J)^-1 at the solution, scaled by the residual variance s^2 = RSS / (n - p). The covariance
// is computed from the Jacobian with its columns equilibrated and a column-pivoted QR, so that
// badly scaled parameters (a cubic's t^3 coefficient beside its intercept, NIST's Misra or
// Bennett problems) keep their digits; for a model linear in its parameters whose equilibrated
// normal equations are well conditioned (kNormalEquationsMaxCondition), from those equations.
#pragma once

#include "epuck2/fit/parameter.hpp"

#include <Eigen/Dense>
#include <algorithm>
#include <cstring>
#include <limits>
#include <memory>
#include <string>
#include <type_traits>
#include <vector>

namespace epuck2::fit {

struct ParameterEstimate {
  ParameterEstimate() = default;
  ParameterEstimate(std::string name_, double value_, double std_error_, std::string why = {})
      : name(std::move(name_)), value(value_), std_error(std_error_), std_error_why(std::move(why)) {}
  std::string name;
  double value = 0;
  double std_error = 0;  ///< NaN when the covariance could not be computed
  /// Why std_error is NaN, in words (empty when it is a number): not identifiable from these data
  /// (its Jacobian column is zero, or it is not separable from the others), no degrees of freedom
  /// left, covariance not computed, or the fit not usable.
  std::string std_error_why;
};

struct FitResult {
  bool usable = false;
  std::string message;  ///< why not usable, or the solver's termination message
  std::vector<ParameterEstimate> parameters;
  std::size_t observations = 0;
  double rss = 0;                ///< sum of squared residuals (unweighted by any robust loss)
  double mse = 0;                ///< rss / n
  double residual_variance = 0;  ///< rss / (n - p)
  double r2 = 0;                 ///< 1 - rss / tss (NaN when no observations were given)
  double aic = 0;                ///< n ln(rss/n) + 2p
  double bic = 0;                ///< n ln(rss/n) + p ln n
  int iterations = 0;
  int free_parameters = 0;     ///< parameters estimated (not held fixed)
  Eigen::MatrixXd covariance;  ///< scaled by residual_variance, parameter order as `parameters`

  /// The estimate (standard error) of the parameter called `name`; std::out_of_range naming it
  /// and the known ones when there is none (a typo is an error, not a NaN).
  double value(const std::string& name) const;
  double std_error(const std::string& name) const;
  std::vector<double> values() const;
  /// The correlation matrix of `covariance` (epuck2/fit/report.hpp correlation_matrix): NaN in
  /// the rows and columns of parameters without variance.
  Eigen::MatrixXd correlation() const;
};

/// The engine's solver settings, in one place: every fit (fit_curve, fit_robust, a fit::Problem)
/// is solved as these say.
struct FitOptions {
  bool robust = false;          ///< Huber loss instead of squares
  double robust_scale = 1.0;    ///< Huber's threshold, in the residual's units
  /// How each step's linear least-squares problem is solved: a QR of the Jacobian (keeps the
  /// digits of badly scaled columns), or the normal equations' Cholesky (cheaper for thousands of
  /// rows over few well-scaled parameters; loses about twice the digits).
  enum class LinearSolver { dense_qr, dense_normal_cholesky };
  LinearSolver linear_solver = LinearSolver::dense_qr;
  int max_iterations = 500;
  double function_tolerance = 1e-15;
  double gradient_tolerance = 1e-15;
  double parameter_tolerance = 1e-15;
  bool compute_covariance = true;
  /// Solve again from the solution while the cost still falls, at most this many extra times
  /// (0: one solve, the historical behaviour). A fresh trust region often finishes what a stalled
  /// one stopped early.
  int restarts = 0;
  /// When the first solve's solution fails its own checks (see solve), also solve from the same
  /// start with other strategies (dogleg trust region, then Levenberg-Marquardt on the normal
  /// equations, then a cautious first trust region) and keep the lowest cost (false: LM +
  /// DENSE_QR only).
  bool try_alternatives = false;
  /// fit_curve only, without `robust`: all observations in one residual block (one cost function
  /// evaluating every row, derivatives by Jets row by row) instead of one block per observation.
  /// Same least-squares problem, far less Ceres overhead for thousands of rows (false: one block
  /// per observation, the behaviour before it became the default).
  bool single_residual_block = true;
  /// fit_curve only, without `robust`, for models that declare
  /// `static constexpr bool kLinearInParameters = true;`: start Ceres from the linear
  /// least-squares solution, so that the solver only confirms the minimum; the statistics and
  /// covariance are computed as for any fit. The solution comes from the column-equilibrated
  /// normal equations, summed in the pass that evaluates the Jacobian and refined once, when their
  /// condition number is at most kNormalEquationsMaxCondition; otherwise from a column-pivoted QR
  /// of the design matrix. False: start from `initial` as for a nonlinear model.
  bool linear_start = true;

  // ----- the named solver settings (docs/fitting.md, "Solver settings"): every fit in the project
  // starts from one of these; only the linear solver and the covariance are chosen beside them.
  // Each sets max_iterations and the three tolerances (and, for reference, the restarts and the
  // alternative strategies); everything else keeps the defaults above.

  /// The defaults above: 500 iterations, every tolerance 1e-15 (fit_curve, fit::Problem's callers
  /// that state nothing, the battery models).
  static FitOptions precise() { return FitOptions{}; }
  /// A calibration's censored robust fit and the charge map: 200 iterations, function and gradient
  /// tolerance 1e-14, parameter tolerance 1e-12 (what the shipped data/fitted was computed with).
  static FitOptions calibration() { return with(200, 1e-14, 1e-14, 1e-12); }
  /// The diagnosis's joint fits: 200 iterations, function tolerance 1e-8 (a relative change of the
  /// cost of 1e-8 moves n log(RSS) by 1e-8 n: 0.002 at 200 000 residuals, far below the BIC margin
  /// of 10), gradient 1e-12, parameters 1e-8 (far below their errors).
  static FitOptions diagnosis() { return with(200, 1e-8, 1e-12, 1e-8); }
  /// Ceres 2.1's stock tolerances (function 1e-6, gradient 1e-10, parameters 1e-8) with 200
  /// iterations: the virtual robot's cell was calibrated with them, and the logs in data/raw
  /// depend on it.
  static FitOptions stock() { return with(200, 1e-6, 1e-10, 1e-8); }
  /// The NIST StRD validation: 10 000 iterations, every tolerance 1e-16, up to 3 restarts while
  /// the cost still falls, and the alternative strategies when a solution fails its checks.
  static FitOptions reference() {
    FitOptions o = with(10000, 1e-16, 1e-16, 1e-16);
    o.restarts = 3;
    o.try_alternatives = true;
    return o;
  }

 private:
  static FitOptions with(int iterations, double function, double gradient, double parameter) {
    FitOptions o;
    o.max_iterations = iterations;
    o.function_tolerance = function;
    o.gradient_tolerance = gradient;
    o.parameter_tolerance = parameter;
    return o;
  }
};

double akaike(std::size_t n, double rss, int k);
double bayes(std::size_t n, double rss, int k);

/// Parameters of a problem: its blocks in order, and a name for every scalar in them.
struct ParameterLayout {
  std::vector<double*> blocks;
  std::vector<int> sizes;
  std::vector<std::string> names;
};

/// (J^T J)^-1 for a Jacobian of full column rank, from its columns equilibrated and a
/// column-pivoted QR (false when rank-deficient). Covariance = this * RSS / (n - p).
bool inverse_normal_matrix(const Eigen::MatrixXd& jacobian, Eigen::MatrixXd* inverse);

/// The share of a column on the least-determined direction (|v_c| / max |v|) from which the
/// column counts as along it: undetermined with the others (docs/fitting.md, "Parameters the
/// logs cannot determine").
inline constexpr double kAlongShare = 0.2;

/// The engine's one identifiability check: which free columns of a Jacobian at the solution the
/// data do not determine, and why, with the numbers. Every fit asks it (fit_robust, fit_curve,
/// fit::Problem::summarize and so the diagnosis) and keeps its own policy on the answer: the
/// calibration holds such a parameter at its documented default and refits; the others leave its
/// standard error NaN with the reason (docs/fitting.md).
///
/// A free column of zeros is undetermined (the data do not depend on it). The other free columns
/// ("estimable") are equilibrated to unit norm and factored by a column-pivoted QR, the
/// factorization every covariance of the engine comes from: when their numerical rank (Eigen's
/// threshold) is below their count, or the condition number of their equilibrated normal matrix
/// exceeds `max_condition` (infinite: not tested), the columns along the least-determined
/// direction (the smallest singular vector of the factor R, share at least kAlongShare) are
/// undetermined. Otherwise `inverse_normal` holds (J^T J)^-1 over the estimable columns from the
/// same factorization. `inverse_normal_given`, when it is the size of the estimable columns, is
/// that inverse already computed from this Jacobian by a factorization that found them of full
/// rank (fit_curve's linear start): the check then factors nothing and tests no condition.
struct Identifiability {
  enum class Why { zero_column, condition, rank_deficient };
  struct Column {
    Eigen::Index column = 0;  ///< in the Jacobian given
    Why why = Why::zero_column;
    double share = 1;  ///< |v_c| / max |v| on the least-determined direction (1 for a zero column)
  };
  std::vector<Column> undetermined;      ///< in column order
  std::vector<Eigen::Index> estimable;   ///< free columns that are not zero, in order
  Eigen::Index rank = 0;                 ///< numerical rank of the estimable columns, equilibrated
  /// Condition number of the estimable columns' equilibrated normal matrix (the square of R's):
  /// computed when `max_condition` is finite or the columns are rank-deficient (NaN otherwise;
  /// infinite when R is singular).
  double condition = std::numeric_limits<double>::quiet_NaN();
  Eigen::MatrixXd inverse_normal;  ///< (J^T J)^-1 over `estimable`, when they are determined
  bool rank_deficient() const { return rank < static_cast<Eigen::Index>(estimable.size()); }
  /// No zero column, full rank and within the condition limit.
  bool determined() const { return undetermined.empty(); }
  bool any(Why why) const {
    return std::any_of(undetermined.begin(), undetermined.end(), [why](const Column& c) { return c.why == why; });
  }
};

Identifiability check_identifiability(const Eigen::MatrixXd& jacobian, const std::vector<bool>& free_column,
                                      double max_condition = std::numeric_limits<double>::infinity(),
                                      const Eigen::MatrixXd* inverse_normal_given = nullptr);

/// For residuals affine in the parameters, r(p + d) = residuals + residual_jacobian d: the step d
/// that minimises |r| over the columns with `free_column` true (the others get 0), from the
/// columns equilibrated and a column-pivoted QR (the factorization inverse_normal_matrix uses),
/// and, when `inverse_normal` is given, (J^T J)^-1 over the free columns from the same
/// factorization. False when a free column is zero or the free columns are rank-deficient, or the
/// step is not finite.
bool linear_least_squares(const Eigen::MatrixXd& residual_jacobian, const Eigen::VectorXd& residuals,
                          const std::vector<bool>& free_column, Eigen::VectorXd* step,
                          Eigen::MatrixXd* inverse_normal = nullptr);

/// Largest condition number of the column-equilibrated normal matrix J^T J (the square of J's)
/// for which normal_equations_least_squares solves: it loses about log10 of that many digits
/// (at most 8 of 16); above it the caller factors J itself (linear_least_squares).
inline constexpr double kNormalEquationsMaxCondition = 1e8;

/// linear_least_squares from the normal equations instead of J: `normal` = J^T J (lower triangle
/// read) and `gradient` = J^T residuals over all columns, both summed in one pass over the rows.
/// The free columns are equilibrated (unit diagonal), and the system is solved by Cholesky when
/// its condition number is at most kNormalEquationsMaxCondition; the step and, when asked,
/// (J^T J)^-1 over the free columns as linear_least_squares gives them. False when a free column
/// is zero, the system is singular or worse conditioned than that, or the step is not finite.
bool normal_equations_least_squares(const Eigen::MatrixXd& normal, const Eigen::VectorXd& gradient,
                                    const std::vector<bool>& free_column, Eigen::VectorXd* step,
                                    Eigen::MatrixXd* inverse_normal = nullptr);

/// The covariance (J^T J)^-1 s^2 (s^2 = RSS / (n - m)) and standard errors of `r` from the
/// residuals' Jacobian at the solution, one column per parameter of `r`, over its m estimable
/// columns (free and not all zero). Held parameters (`free_column` false) get a zero standard
/// error; a free parameter with a zero column keeps NaN; when the estimable columns are
/// rank-deficient, all stay NaN and the message says so. `inverse_normal`, when given, is
/// (J^T J)^-1 over the estimable columns already computed from this same Jacobian.
void set_covariance(FitResult& r, const Eigen::MatrixXd& jacobian, const std::vector<bool>& free_column,
                    const Eigen::MatrixXd* inverse_normal = nullptr);

/// Re-expresses a fit for a more accurate residual sum of squares `rss` (for instance one
/// recomputed in extended precision for a near-exact fit): MSE, residual variance, R^2, AIC, BIC,
/// covariance and standard errors follow it.
void set_rss(FitResult& r, double rss);

}  // namespace epuck2::fit
