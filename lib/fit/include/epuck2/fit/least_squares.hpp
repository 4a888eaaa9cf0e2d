// The fitting layer's core: nonlinear least squares with Ceres, and what every fit reports.
//
// A fit returns a FitResult that says whether it is usable and why (models never throw; this layer
// never throws for numerical trouble either). Standard errors come from the covariance
// (J^T J)^-1 at the solution, scaled by the residual variance s^2 = RSS / (n - p). The covariance
// is computed from the Jacobian with its columns equilibrated and a column-pivoted QR, so that
// badly scaled parameters (a cubic's t^3 coefficient beside its intercept, NIST's Misra or
// Bennett problems) keep their digits; for a model linear in its parameters whose equilibrated
// normal equations are well conditioned (kNormalEquationsMaxCondition), from those equations.
#pragma once

#include <ceres/ceres.h>

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

struct FitOptions {
  bool robust = false;          ///< Huber loss instead of squares
  double robust_scale = 1.0;    ///< Huber's threshold, in the residual's units
  int max_iterations = 500;
  double function_tolerance = 1e-15;
  double gradient_tolerance = 1e-15;
  double parameter_tolerance = 1e-15;
  bool compute_covariance = true;
  /// Solve again from the solution while the cost still falls, at most this many extra times
  /// (0: one solve, the historical behaviour). A fresh trust region often finishes what a stalled
  /// one stopped early.
  int restarts = 0;
  /// Also solve from the same start with other strategies (dogleg trust region, then
  /// Levenberg-Marquardt on the normal equations) and keep the lowest cost (false: LM + DENSE_QR).
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
  /// The loss to attach to each residual block (nullptr for plain squares). Ownership passes to
  /// the problem.
  ceres::LossFunction* make_loss() const;
  ceres::Solver::Options solver_options() const;
};

/// Solves `problem` as `options` say: one Levenberg-Marquardt solve by default; with `restarts`
/// and `try_alternatives`, several solves, leaving the parameters at the lowest cost found. The
/// summary returned is the winning solve's, its `iterations` holding every iteration of every
/// solve (the total work).
ceres::Solver::Summary solve(ceres::Problem& problem, const FitOptions& options);

double akaike(std::size_t n, double rss, int k);
double bayes(std::size_t n, double rss, int k);

/// Parameters of a problem: its blocks in order, and a name for every scalar in them.
struct ParameterLayout {
  std::vector<double*> blocks;
  std::vector<int> sizes;
  std::vector<std::string> names;
};

/// Everything after Solve: RSS, MSE, R^2 (with `observations` for the total sum of squares; empty
/// for none), information criteria, covariance and standard errors. Blocks held constant in the
/// problem are reported with a zero standard error and do not count as free parameters.
FitResult summarize(ceres::Problem& problem, const ParameterLayout& layout,
                    const std::vector<double>& observations, const ceres::Solver::Summary& summary,
                    const FitOptions& options);

/// summarize from the residuals already evaluated at the solution (`evaluated` false when they
/// could not be), with every parameter free and no covariance (see set_covariance).
FitResult summarize(const ParameterLayout& layout, const std::vector<double>& residuals, bool evaluated,
                    const std::vector<double>& observations, const ceres::Solver::Summary& summary);

/// (J^T J)^-1 for a Jacobian of full column rank, from its columns equilibrated and a
/// column-pivoted QR (false when rank-deficient). Covariance = this * RSS / (n - p).
bool inverse_normal_matrix(const Eigen::MatrixXd& jacobian, Eigen::MatrixXd* inverse);

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

/// True for a model that declares `static constexpr bool kLinearInParameters = true;` (its value
/// is an affine function of its parameters, as polynomials in x are): fit_curve can then start
/// from the exact linear least-squares solution.
template <class Model, class = void>
struct is_linear_in_parameters : std::false_type {};
template <class Model>
struct is_linear_in_parameters<Model, std::void_t<decltype(Model::kLinearInParameters)>>
    : std::bool_constant<Model::kLinearInParameters> {};

/// Re-expresses a fit for a more accurate residual sum of squares `rss` (for instance one
/// recomputed in extended precision for a near-exact fit): MSE, residual variance, R^2, AIC, BIC,
/// covariance and standard errors follow it.
void set_rss(FitResult& r, double rss);

/// Residual of a curve model y = model(p, x): (y - model(p, x)) / sigma.
/// Model: `static constexpr int kParameters;` and `template <typename T> T operator()(const T* p, double x) const`.
template <class Model>
class CurveResidual {
 public:
  CurveResidual(const Model& model, double x, double y, double sigma) : model_(model), x_(x), y_(y), inv_sigma_(1.0 / sigma) {}
  template <typename T>
  bool operator()(const T* p, T* residual) const {
    residual[0] = (T(y_) - model_(p, x_)) * inv_sigma_;
    // A non-finite model value (overflow on a wild trial step) is reported as a failed
    // evaluation: Ceres rejects the step either way, but this way without logging a warning.
    using std::isfinite;
    return isfinite(residual[0]);
  }
  static ceres::CostFunction* Create(const Model& model, double x, double y, double sigma = 1.0) {
    return new ceres::AutoDiffCostFunction<CurveResidual, 1, Model::kParameters>(new CurveResidual(model, x, y, sigma));
  }

 private:
  const Model model_;
  const double x_, y_, inv_sigma_;
};

/// The residuals and Jacobian of a curve model's last evaluation with derivatives, at the
/// parameters `at` (`valid` false until an evaluation succeeded).
struct RecordedEvaluation {
  bool valid = false;
  std::vector<double> at;
  std::vector<double> residuals;
  Eigen::MatrixXd jacobian;  ///< n x p, column-major (as fit_curve's statistics take it)
};

/// All residuals (y_i - model(p, x_i)) of a curve model in one cost function; x and y are
/// referenced, not copied (they must outlive the problem). With `record`, each evaluation with
/// derivatives also stores its residuals and Jacobian there (the caller's to reuse at the point
/// the solver ends at, instead of evaluating the same Jets again).
template <class Model>
class CurveBlockResidual : public ceres::CostFunction {
 public:
  CurveBlockResidual(const Model& model, const std::vector<double>& x, const std::vector<double>& y,
                     RecordedEvaluation* record = nullptr)
      : model_(model), x_(x), y_(y), record_(record) {
    set_num_residuals(static_cast<int>(x.size()));
    mutable_parameter_block_sizes()->push_back(Model::kParameters);
  }
  bool Evaluate(double const* const* parameters, double* residuals, double** jacobians) const override {
    constexpr int P = Model::kParameters;
    const double* p = parameters[0];
    using std::isfinite;
    if (jacobians == nullptr || jacobians[0] == nullptr) {
      for (std::size_t i = 0; i < x_.size(); ++i) {
        residuals[i] = y_[i] - model_(p, x_[i]);
        if (!isfinite(residuals[i])) return false;
      }
      return true;
    }
    using Jet = ceres::Jet<double, P>;
    Jet pj[P];
    for (int j = 0; j < P; ++j) pj[j] = Jet(p[j], j);
    if (record_ == nullptr) {
      for (std::size_t i = 0; i < x_.size(); ++i) {
        const Jet r = Jet(y_[i]) - model_(pj, x_[i]);
        if (!isfinite(r)) return false;
        residuals[i] = r.a;
        for (int j = 0; j < P; ++j) jacobians[0][i * P + static_cast<std::size_t>(j)] = r.v[j];
      }
      return true;
    }
    // The same, also written to the record as it goes (no second pass over the rows).
    record_->valid = false;
    record_->residuals.resize(x_.size());
    record_->jacobian.resize(static_cast<Eigen::Index>(x_.size()), P);
    double* record_residuals = record_->residuals.data();
    double* record_jacobian = record_->jacobian.data();
    const std::size_t n = x_.size();
    for (std::size_t i = 0; i < n; ++i) {
      const Jet r = Jet(y_[i]) - model_(pj, x_[i]);
      if (!isfinite(r)) return false;
      residuals[i] = record_residuals[i] = r.a;
      for (int j = 0; j < P; ++j)
        jacobians[0][i * P + static_cast<std::size_t>(j)] = record_jacobian[static_cast<std::size_t>(j) * n + i] = r.v[j];
    }
    record_->at.assign(p, p + P);
    record_->valid = true;
    return true;
  }

 private:
  const Model model_;
  const std::vector<double>& x_;
  const std::vector<double>& y_;
  RecordedEvaluation* const record_;
};

/// Fits y = model(p, x) by least squares from the parameters' values (epuck2/fit/parameter.hpp):
/// those marked `fixed` are held at their value, finite `lower`/`upper` bounds are kept by the
/// solver (a bounded fit does not take the linear start, whose solution may lie outside them).
/// `fallback` and `other_starts` are not used here.
template <class Model>
FitResult fit_curve(const Model& model, const std::vector<double>& x, const std::vector<double>& y,
                    const std::vector<Parameter>& parameters, const FitOptions& options = {}) {
  static_assert(Model::kParameters > 0, "a model needs parameters");
  FitResult bad;
  if (x.size() != y.size() || static_cast<int>(parameters.size()) != Model::kParameters) {
    bad.message = "internal: " + std::to_string(parameters.size()) + " parameters given for a model of " +
                  std::to_string(Model::kParameters) + ", or x and y differ in length";
    return bad;
  }
  std::vector<double> initial = values_of(parameters);
  std::vector<std::string> names;
  std::vector<int> fixed;
  bool bounded = false;
  for (std::size_t j = 0; j < parameters.size(); ++j) {
    names.push_back(parameters[j].name);
    if (parameters[j].fixed) fixed.push_back(static_cast<int>(j));
    bounded = bounded || (!parameters[j].fixed && (std::isfinite(parameters[j].lower) || std::isfinite(parameters[j].upper)));
  }
  if (x.size() < static_cast<std::size_t>(Model::kParameters) + 1) {
    for (const std::string& name : names)
      bad.parameters.emplace_back(name, std::numeric_limits<double>::quiet_NaN(), std::numeric_limits<double>::quiet_NaN(),
                                  "the fit was not made");
    bad.message = "too few observations (" + std::to_string(x.size()) + ") for " +
                  std::to_string(Model::kParameters) + " parameters";
    return bad;
  }
  constexpr int P = Model::kParameters;
  std::vector<bool> free_column(static_cast<std::size_t>(P), true);
  for (int j : fixed)
    if (j >= 0 && j < P) free_column[static_cast<std::size_t>(j)] = false;
  // Residuals y - model(p, x) at p and, when `jacobian` is given, their Jacobian by Jets (what
  // Ceres' automatic derivatives compute). False when a residual is not finite.
  // With `sums`, the same pass also sums the normal equations J^T J (lower triangle) and J^T r;
  // `residuals` may then be null (the sums hold what a solve needs).
  struct NormalSums {
    double normal[P][P] = {};
    double gradient[P] = {};
  };
  auto evaluate = [&](const std::vector<double>& p, std::vector<double>* residuals, Eigen::MatrixXd* jacobian,
                      NormalSums* sums = nullptr) {
    if (residuals != nullptr) residuals->resize(x.size());
    bool finite = true;
    using std::isfinite;
    if (jacobian == nullptr) {
      for (std::size_t i = 0; i < x.size(); ++i) {
        (*residuals)[i] = y[i] - model(p.data(), x[i]);
        finite = finite && isfinite((*residuals)[i]);
      }
      return finite;
    }
    using Jet = ceres::Jet<double, P>;
    Jet pj[P];
    for (int j = 0; j < P; ++j) pj[j] = Jet(p[static_cast<std::size_t>(j)], j);
    jacobian->resize(static_cast<Eigen::Index>(x.size()), P);
    for (std::size_t i = 0; i < x.size(); ++i) {
      const Jet r = Jet(y[i]) - model(pj, x[i]);
      if (residuals != nullptr) (*residuals)[i] = r.a;
      jacobian->row(static_cast<Eigen::Index>(i)) = r.v.transpose();
      finite = finite && isfinite(r);
      if (sums != nullptr)
        for (int a = 0; a < P; ++a) {
          sums->gradient[a] += r.v[a] * r.a;
          for (int b = 0; b <= a; ++b) sums->normal[a][b] += r.v[a] * r.v[b];
        }
    }
    return finite;
  };
  // For a model linear in its parameters, r(p0 + d) = r(p0) + J d exactly: one linear least-squares
  // solve from any p0 gives the minimum, and the same factorization gives (J^T J)^-1.
  // The solve takes the normal equations, summed in the same pass as the Jacobian, when they are
  // well conditioned (the battery cubic's equilibrated J has condition number 86: 4 of 16 digits
  // lost, then recovered by one step of iterative refinement); otherwise J's column-pivoted QR,
  // from the same pass's Jacobian.
  Eigen::MatrixXd start_jacobian, start_inverse_normal;
  bool linear_started = false;
  if constexpr (is_linear_in_parameters<Model>::value) {
    NormalSums sums;
    if (options.linear_start && !options.robust && !bounded && evaluate(initial, nullptr, &start_jacobian, &sums)) {
      Eigen::MatrixXd N(P, P);
      Eigen::VectorXd g(P);
      for (int a = 0; a < P; ++a) {
        g(a) = sums.gradient[a];
        for (int b = 0; b <= a; ++b) N(a, b) = sums.normal[a][b];
      }
      Eigen::VectorXd step;
      linear_started = normal_equations_least_squares(N, g, free_column, &step, &start_inverse_normal);
      if (linear_started) {
        // One step of iterative refinement: the residuals at the solution found, computed
        // afresh, through the same normal equations (r(p + d) = r(p) + J d for this model). It
        // recovers the digits the normal equations lose, so that Ceres has nothing left to do.
        std::vector<double> p1 = initial;
        for (int j = 0; j < P; ++j) p1[static_cast<std::size_t>(j)] += step(j);
        const std::size_t n = x.size();
        const double* jac = start_jacobian.data();
        double refined_gradient[P] = {};
        for (std::size_t i = 0; i < n; ++i) {
          const double r = y[i] - model(p1.data(), x[i]);
          for (int a = 0; a < P; ++a) refined_gradient[a] += jac[static_cast<std::size_t>(a) * n + i] * r;
        }
        for (int a = 0; a < P; ++a) g(a) = refined_gradient[a];
        Eigen::VectorXd correction;
        if (normal_equations_least_squares(N, g, free_column, &correction)) step += correction;
      } else {
        // Ill-conditioned normal equations: J's own QR, with the residuals (evaluated again here,
        // on this rare path, rather than stored on every fit). Rank-deficient or non-finite:
        // Ceres starts from `initial` and reports what it finds.
        std::vector<double> r0;
        evaluate(initial, &r0, nullptr);
        linear_started = linear_least_squares(
            start_jacobian, Eigen::Map<const Eigen::VectorXd>(r0.data(), static_cast<Eigen::Index>(r0.size())),
            free_column, &step, &start_inverse_normal);
      }
      if (linear_started)
        for (int j = 0; j < P; ++j) initial[static_cast<std::size_t>(j)] += step(j);
    }
  }
  RecordedEvaluation recorded;
  ceres::Problem problem;
  if (options.single_residual_block && !options.robust)
    problem.AddResidualBlock(new CurveBlockResidual<Model>(model, x, y, &recorded), nullptr, initial.data());
  else
    for (std::size_t i = 0; i < x.size(); ++i)
      problem.AddResidualBlock(CurveResidual<Model>::Create(model, x[i], y[i]), options.make_loss(), initial.data());
  if (!fixed.empty()) {
    std::vector<int> fixed_sorted = fixed;
    problem.SetManifold(initial.data(), new ceres::SubsetManifold(Model::kParameters, fixed_sorted));
  }
  for (std::size_t j = 0; j < parameters.size(); ++j) {
    if (parameters[j].fixed) continue;
    if (std::isfinite(parameters[j].lower)) problem.SetParameterLowerBound(initial.data(), static_cast<int>(j), parameters[j].lower);
    if (std::isfinite(parameters[j].upper)) problem.SetParameterUpperBound(initial.data(), static_cast<int>(j), parameters[j].upper);
  }
  ceres::Solver::Summary summary;
  if (linear_started && options.restarts <= 0 && !options.try_alternatives) {
    // From the least-squares minimum, Levenberg-Marquardt's first step only confirms it (a step of
    // rounding size): the normal equations suffice for it, without Jacobi scaling.
    ceres::Solver::Options confirm = options.solver_options();
    confirm.linear_solver_type = ceres::DENSE_NORMAL_CHOLESKY;
    confirm.jacobi_scaling = false;
    const std::vector<double> linear_solution = initial;
    ceres::Solve(confirm, &problem, &summary);
    // At the exact minimum the gradient is rounding (about 1e-13, above the 1e-15 tolerance) and
    // every step's predicted decrease can round to zero or below: Ceres counts those as invalid
    // steps and, after five, reports FAILURE without moving. The point is still the linear
    // least-squares solution: a converged fit (seen on AR(1) data, 1 series in 300).
    if (summary.termination_type == ceres::FAILURE && initial == linear_solution) {
      summary.termination_type = ceres::CONVERGENCE;
      summary.message = "linear least-squares solution (the confirming step found nothing to improve: " + summary.message + ")";
    }
  } else {
    summary = solve(problem, options);
  }
  // Ceres' projected steps crawl along a bound (a parameter pressed against it shrinks every
  // step): the parameters that end on a bound are held there and the others solved again (an
  // active set, one pass: a parameter held is not released again). They are reported without a
  // standard error and do not count as free parameters (the others' errors are conditional on
  // the bound).
  std::vector<std::pair<int, const char*>> at_bound;
  if (bounded && summary.IsSolutionUsable()) {
    for (std::size_t j = 0; j < parameters.size(); ++j) {
      if (!free_column[j]) continue;
      const double lo = parameters[j].lower, hi = parameters[j].upper;
      if (std::isfinite(lo) && initial[j] <= lo + 1e-12 * (1.0 + std::abs(lo))) {
        initial[j] = lo;
        at_bound.emplace_back(static_cast<int>(j), "lower");
      } else if (std::isfinite(hi) && initial[j] >= hi - 1e-12 * (1.0 + std::abs(hi))) {
        initial[j] = hi;
        at_bound.emplace_back(static_cast<int>(j), "upper");
      }
    }
    if (!at_bound.empty()) {
      for (const auto& [j, side] : at_bound) {
        fixed.push_back(j);
        free_column[static_cast<std::size_t>(j)] = false;
      }
      std::sort(fixed.begin(), fixed.end());
      ceres::Problem polish;
      if (options.single_residual_block && !options.robust)
        polish.AddResidualBlock(new CurveBlockResidual<Model>(model, x, y), nullptr, initial.data());
      else
        for (std::size_t i = 0; i < x.size(); ++i)
          polish.AddResidualBlock(CurveResidual<Model>::Create(model, x[i], y[i]), options.make_loss(), initial.data());
      if (static_cast<int>(fixed.size()) < P) {
        polish.SetManifold(initial.data(), new ceres::SubsetManifold(P, fixed));
        for (std::size_t j = 0; j < parameters.size(); ++j) {
          if (!free_column[j]) continue;
          if (std::isfinite(parameters[j].lower)) polish.SetParameterLowerBound(initial.data(), static_cast<int>(j), parameters[j].lower);
          if (std::isfinite(parameters[j].upper)) polish.SetParameterUpperBound(initial.data(), static_cast<int>(j), parameters[j].upper);
        }
        ceres::Solver::Summary second = solve(polish, options);
        second.iterations.insert(second.iterations.begin(), summary.iterations.begin(), summary.iterations.end());
        summary = second;
      }
      recorded.valid = false;  // the record is of the first problem's last evaluation
    }
  }
  // The statistics and the covariance from the residuals and their Jacobian at the solution,
  // over the ambient parameters with the fixed ones left out (Problem::Evaluate would give the
  // SubsetManifold's tangent columns instead).
  // When the solver ended where it last evaluated the Jacobian (from the linear start, where the
  // confirming step is rejected or too small to count), that evaluation is the one this would
  // repeat: the same Jets on the same doubles, so the same digits.
  std::vector<double> residuals;
  Eigen::MatrixXd jacobian;
  bool evaluated = false;
  if (recorded.valid && std::equal(recorded.at.begin(), recorded.at.end(), initial.begin(),
                                   [](double a, double b) { return std::memcmp(&a, &b, sizeof a) == 0; })) {
    residuals.swap(recorded.residuals);
    if (options.compute_covariance) jacobian.swap(recorded.jacobian);
    evaluated = true;
  } else {
    evaluated = evaluate(initial, &residuals, options.compute_covariance ? &jacobian : nullptr);
  }
  ParameterLayout layout{{initial.data()}, {Model::kParameters}, names};
  FitResult r = summarize(layout, residuals, evaluated, y, summary);
  if (!fixed.empty()) {
    // Fixed parameters do not count as free and have no uncertainty.
    int free = 0;
    for (bool f : free_column) free += f ? 1 : 0;
    const double n = static_cast<double>(r.observations);
    r.residual_variance = n > free ? r.rss / (n - free) : r.residual_variance;
    r.free_parameters = free;
    r.aic = akaike(r.observations, r.rss, free);
    r.bic = bayes(r.observations, r.rss, free);
  }
  if (options.compute_covariance && r.usable) {
    // The Jacobian the linear start solved with, when it is the same matrix (always, for a model
    // that is truly affine in its parameters): its (J^T J)^-1 is reused, not computed again.
    const bool same_jacobian = linear_started && start_jacobian.rows() == jacobian.rows() &&
                               start_jacobian.cols() == jacobian.cols() &&
                               std::memcmp(start_jacobian.data(), jacobian.data(),
                                           static_cast<std::size_t>(jacobian.size()) * sizeof(double)) == 0;
    set_covariance(r, jacobian, free_column, same_jacobian ? &start_inverse_normal : nullptr);
  }
  for (int i : fixed) r.parameters[static_cast<std::size_t>(i)].std_error = 0.0;
  for (const auto& [j, side] : at_bound) {
    r.parameters[static_cast<std::size_t>(j)].std_error = std::numeric_limits<double>::quiet_NaN();
    r.parameters[static_cast<std::size_t>(j)].std_error_why =
        std::string("ended on its ") + side + " bound, where it is held: no standard error";
  }
  return r;
}

}  // namespace epuck2::fit
