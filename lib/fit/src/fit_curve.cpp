// fit_curve's solver side (epuck2/fit/fit_curve.hpp): the curve model's type-erased evaluation
// as Ceres cost functions, the solve, the active set at the bounds and the statistics. The
// template in the header evaluates the model; this file alone states the problem to Ceres.
#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>
#include <string>
#include <utility>
#include <vector>

#include "epuck2/fit/fit_curve.hpp"
#include "solver.hpp"

namespace epuck2::fit {

namespace {

// Every residual in one cost function, evaluated in doubles unless a Jacobian is wanted; with
// `record`, each evaluation with derivatives is also stored there (the caller's to reuse at the
// point the solver ends at, instead of evaluating the same Jets again).
class CurveBlockCost : public ceres::CostFunction {
 public:
  CurveBlockCost(const CurveEvaluation& evaluation, std::size_t observations, RecordedEvaluation* record)
      : evaluation_(evaluation), record_(record) {
    set_num_residuals(static_cast<int>(observations));
    mutable_parameter_block_sizes()->push_back(evaluation.parameters);
  }
  bool Evaluate(double const* const* parameters, double* residuals, double** jacobians) const override {
    if (jacobians == nullptr || jacobians[0] == nullptr) return evaluation_.all(parameters[0], residuals, nullptr, nullptr);
    return evaluation_.all(parameters[0], residuals, jacobians[0], record_);
  }

 private:
  const CurveEvaluation& evaluation_;
  RecordedEvaluation* const record_;
};

// Residual i alone (one block per observation, each with the loss): in doubles when Ceres asks
// for no derivatives at all, else by Jets, as AutoDiffCostFunction evaluates a functor.
class CurvePointCost : public ceres::CostFunction {
 public:
  CurvePointCost(const CurveEvaluation& evaluation, std::size_t i) : evaluation_(evaluation), i_(i) {
    set_num_residuals(1);
    mutable_parameter_block_sizes()->push_back(evaluation.parameters);
  }
  bool Evaluate(double const* const* parameters, double* residuals, double** jacobians) const override {
    return evaluation_.one(i_, parameters[0], residuals, jacobians != nullptr, jacobians != nullptr ? jacobians[0] : nullptr);
  }

 private:
  const CurveEvaluation& evaluation_;
  const std::size_t i_;
};

// The curve's residuals over `parameters`: one block without a loss, or one block per observation
// with the options' loss (robust, or single_residual_block off).
void add_curve_residuals(ceres::Problem& problem, const CurveEvaluation& evaluation, std::size_t n, double* parameters,
                         RecordedEvaluation* record, const FitOptions& options) {
  if (options.single_residual_block && !options.robust)
    problem.AddResidualBlock(new CurveBlockCost(evaluation, n, record), nullptr, parameters);
  else
    for (std::size_t i = 0; i < n; ++i) problem.AddResidualBlock(new CurvePointCost(evaluation, i), make_loss(options), parameters);
}

}  // namespace

namespace detail {

FitResult solve_curve(const CurveEvaluation& evaluation, CurveStart start, const std::vector<Parameter>& parameters,
                      const std::vector<double>& y, const FitOptions& options) {
  const int P = evaluation.parameters;
  const std::size_t n = y.size();
  std::vector<double>& initial = start.initial;
  const std::vector<std::string>& names = start.names;
  std::vector<int>& fixed = start.fixed;
  std::vector<bool>& free_column = start.free_column;
  const bool bounded = start.bounded;
  const bool linear_started = start.linear_started;
  const Eigen::MatrixXd& start_jacobian = start.start_jacobian;
  const Eigen::MatrixXd& start_inverse_normal = start.start_inverse_normal;
  RecordedEvaluation recorded;
  ceres::Problem problem;
  add_curve_residuals(problem, evaluation, n, initial.data(), &recorded, options);
  if (!fixed.empty()) {
    std::vector<int> fixed_sorted = fixed;
    problem.SetManifold(initial.data(), new ceres::SubsetManifold(P, fixed_sorted));
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
    ceres::Solver::Options confirm = solver_options(options);
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
      add_curve_residuals(polish, evaluation, n, initial.data(), nullptr, options);
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
    evaluated = evaluation.at(initial, &residuals, options.compute_covariance ? &jacobian : nullptr);
  }
  ParameterLayout layout{{initial.data()}, {P}, names};
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

}  // namespace detail

}  // namespace epuck2::fit
