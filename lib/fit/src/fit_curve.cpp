// fit_curve's solver side (epuck2/fit/fit_curve.hpp): the curve model's type-erased evaluation
// as the engine's residual blocks (fit::Problem), the solve, the active set at the bounds and
// the statistics. The template in the header evaluates the model; this file states the problem.
#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>
#include <string>
#include <utility>
#include <vector>

#include "epuck2/fit/fit_curve.hpp"
#include "epuck2/fit/problem.hpp"

namespace epuck2::fit {

namespace {

// The curve's residuals over `parameters`, added to `problem`: without a loss, every residual in
// one block, evaluated in doubles unless a Jacobian is wanted; with `record`, each evaluation with
// derivatives is also stored there (the caller's to reuse at the point the solver ends at,
// instead of evaluating the same Jets again). With the options' loss (robust, or
// single_residual_block off), one block per observation: residual i alone, in doubles when no
// derivatives are asked for at all, else by Jets, as AutoDiffCostFunction evaluates a functor.
void add_curve_residuals(Problem& problem, const CurveEvaluation& evaluation, std::size_t n, double* parameters,
                         RecordedEvaluation* record, const FitOptions& options) {
  ResidualBlock block;
  block.sizes = {evaluation.parameters};
  if (options.single_residual_block && !options.robust) {
    block.residuals = static_cast<int>(n);
    block.evaluate = [&evaluation, record](double const* const* p, double* residuals, double** jacobians) {
      if (jacobians == nullptr || jacobians[0] == nullptr) return evaluation.all(p[0], residuals, nullptr, nullptr);
      return evaluation.all(p[0], residuals, jacobians[0], record);
    };
    problem.add(std::move(block), {parameters});
  } else {
    block.residuals = 1;
    const std::vector<double*> over{parameters};
    for (std::size_t i = 0; i < n; ++i) {
      block.evaluate = [&evaluation, i](double const* const* p, double* residuals, double** jacobians) {
        return evaluation.one(i, p[0], residuals, jacobians != nullptr, jacobians != nullptr ? jacobians[0] : nullptr);
      };
      problem.add(block, over, options);
    }
  }
}

// Holds the `fixed` values of the curve's parameters and bounds the free ones (finite bounds
// only): the solve and the active set's polish alike.
void hold_and_bound(Problem& problem, double* values, const std::vector<int>& fixed, const std::vector<bool>& free_column,
                    const std::vector<Parameter>& parameters) {
  problem.hold(values, fixed);
  for (std::size_t j = 0; j < parameters.size(); ++j) {
    if (!free_column[j]) continue;
    if (std::isfinite(parameters[j].lower)) problem.set_lower_bound(values, static_cast<int>(j), parameters[j].lower);
    if (std::isfinite(parameters[j].upper)) problem.set_upper_bound(values, static_cast<int>(j), parameters[j].upper);
  }
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
  Problem problem;
  add_curve_residuals(problem, evaluation, n, initial.data(), &recorded, options);
  hold_and_bound(problem, initial.data(), fixed, free_column, parameters);
  // From the least-squares minimum, a confirming step (Problem::confirm) rather than a solve.
  SolveSummary summary = linear_started && options.restarts <= 0 && !options.try_alternatives ? problem.confirm(options)
                                                                                              : problem.solve(options);
  // Ceres' projected steps crawl along a bound (a parameter pressed against it shrinks every
  // step): the parameters that end on a bound are held there and the others solved again (an
  // active set, one pass: a parameter held is not released again). They are reported without a
  // standard error and do not count as free parameters (the others' errors are conditional on
  // the bound).
  std::vector<std::pair<int, const char*>> at_bound;
  if (bounded && summary.usable) {
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
      Problem polish;
      add_curve_residuals(polish, evaluation, n, initial.data(), nullptr, options);
      if (static_cast<int>(fixed.size()) < P) {
        hold_and_bound(polish, initial.data(), fixed, free_column, parameters);
        // The polish solve's result, counting the first solve's iterations too (the total work).
        SolveSummary second = polish.solve(options);
        second.iterations += summary.iterations;
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
  FitResult r = Problem::summarize(layout, residuals, evaluated, y, summary);
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
