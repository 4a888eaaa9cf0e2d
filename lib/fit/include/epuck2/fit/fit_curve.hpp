// fit_curve: least squares of a curve model y = model(p, x) with Ceres (one residual block of Jets,
// a linear start for models linear in their parameters, bounds with an active set), and the
// residual classes it builds on. A template over the model: included only by the units that fit
// a curve, so that the many that only read a FitResult (epuck2/fit/least_squares.hpp) do not
// parse it.
#pragma once

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>
#include <string>
#include <type_traits>
#include <utility>
#include <vector>

#include "epuck2/fit/least_squares.hpp"
#include "epuck2/fit/parameter.hpp"
#include "epuck2/fit/solver.hpp"

namespace epuck2::fit {

/// True for a model that declares `static constexpr bool kLinearInParameters = true;` (its value
/// is an affine function of its parameters, as polynomials in x are): fit_curve can then start
/// from the exact linear least-squares solution.
template <class Model, class = void>
struct is_linear_in_parameters : std::false_type {};
template <class Model>
struct is_linear_in_parameters<Model, std::void_t<decltype(Model::kLinearInParameters)>>
    : std::bool_constant<Model::kLinearInParameters> {};

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
      problem.AddResidualBlock(CurveResidual<Model>::Create(model, x[i], y[i]), make_loss(options), initial.data());
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
      if (options.single_residual_block && !options.robust)
        polish.AddResidualBlock(new CurveBlockResidual<Model>(model, x, y), nullptr, initial.data());
      else
        for (std::size_t i = 0; i < x.size(); ++i)
          polish.AddResidualBlock(CurveResidual<Model>::Create(model, x[i], y[i]), make_loss(options), initial.data());
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
