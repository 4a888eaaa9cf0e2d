// fit_curve: least squares of a curve model y = model(p, x) (one residual block of Jets, a linear
// start for models linear in their parameters, bounds with an active set). The template below
// evaluates the model (residuals, their Jacobian by epuck2::fit::Jet, the linear start) and hands
// that evaluation, type-erased, to detail::solve_curve (lib/fit/src/fit_curve.cpp), which states
// the problem to Ceres, solves it and summarizes it: no Ceres header is parsed by a caller.
// Included only by the units that fit a curve, so that the many that only read a FitResult
// (epuck2/fit/least_squares.hpp) do not parse it.
#pragma once

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <cstddef>
#include <functional>
#include <limits>
#include <string>
#include <type_traits>
#include <utility>
#include <vector>

#include "epuck2/fit/jet.hpp"
#include "epuck2/fit/least_squares.hpp"
#include "epuck2/fit/parameter.hpp"

namespace epuck2::fit {

/// True for a model that declares `static constexpr bool kLinearInParameters = true;` (its value
/// is an affine function of its parameters, as polynomials in x are): fit_curve can then start
/// from the exact linear least-squares solution.
template <class Model, class = void>
struct is_linear_in_parameters : std::false_type {};
template <class Model>
struct is_linear_in_parameters<Model, std::void_t<decltype(Model::kLinearInParameters)>>
    : std::bool_constant<Model::kLinearInParameters> {};

/// The residuals and Jacobian of a curve model's last evaluation with derivatives, at the
/// parameters `at` (`valid` false until an evaluation succeeded).
struct RecordedEvaluation {
  bool valid = false;
  std::vector<double> at;
  std::vector<double> residuals;
  Eigen::MatrixXd jacobian;  ///< n x p, column-major (as fit_curve's statistics take it)
};

/// A curve model's residuals r_i = y_i - model(p, x_i) at parameters p, type-erased: what
/// fit_curve's template hands to the engine's solver (detail::solve_curve).
struct CurveEvaluation {
  int parameters = 0;  ///< P, the model's kParameters
  /// All residuals at p. Without `jacobian`, in doubles; with it, by Jets, their derivatives
  /// written there row-major (n x P) and, with `record`, to the record as well. False when a
  /// residual is not finite.
  std::function<bool(const double* p, double* residuals, double* jacobian, RecordedEvaluation* record)> all;
  /// Residual i alone at p: in doubles unless `jets`, else by Jets, its P derivatives written to
  /// `gradient` when given. False when it is not finite.
  std::function<bool(std::size_t i, const double* p, double* residual, bool jets, double* gradient)> one;
  /// The residuals at p and, when `jacobian` is given, their Jacobian (n x P, column-major) by
  /// Jets, for the statistics at the solution. False when a residual is not finite.
  std::function<bool(const std::vector<double>& p, std::vector<double>* residuals, Eigen::MatrixXd* jacobian)> at;
};

namespace detail {
/// What fit_curve's template found before the solve: the start (the linear least-squares
/// solution when the model allowed it), the parameters held, and the linear start's Jacobian and
/// (J^T J)^-1, reused for the covariance when the Jacobian at the solution is the same matrix.
struct CurveStart {
  std::vector<double> initial;
  std::vector<std::string> names;
  std::vector<int> fixed;         ///< held parameters, in index order
  std::vector<bool> free_column;  ///< per parameter: not held
  bool bounded = false;           ///< a free parameter has a finite bound
  bool linear_started = false;
  Eigen::MatrixXd start_jacobian, start_inverse_normal;
};

/// The solve and everything after it (lib/fit/src/fit_curve.cpp): the problem with its bounds and
/// held parameters, one solve (or the confirming step from a linear start), the active set at the
/// bounds, the statistics and covariance at the solution.
FitResult solve_curve(const CurveEvaluation& evaluation, CurveStart start, const std::vector<Parameter>& parameters,
                      const std::vector<double>& y, const FitOptions& options);
}  // namespace detail

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
    using Jet = fit::Jet<P>;
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
  CurveEvaluation evaluation;
  evaluation.parameters = P;
  evaluation.all = [&model, &x, &y](const double* p, double* residuals, double* jacobian, RecordedEvaluation* record) {
    using std::isfinite;
    if (jacobian == nullptr) {
      for (std::size_t i = 0; i < x.size(); ++i) {
        residuals[i] = y[i] - model(p, x[i]);
        if (!isfinite(residuals[i])) return false;
      }
      return true;
    }
    using Jet = fit::Jet<P>;
    Jet pj[P];
    for (int j = 0; j < P; ++j) pj[j] = Jet(p[j], j);
    if (record == nullptr) {
      for (std::size_t i = 0; i < x.size(); ++i) {
        const Jet r = Jet(y[i]) - model(pj, x[i]);
        if (!isfinite(r)) return false;
        residuals[i] = r.a;
        for (int j = 0; j < P; ++j) jacobian[i * P + static_cast<std::size_t>(j)] = r.v[j];
      }
      return true;
    }
    // The same, also written to the record as it goes (no second pass over the rows).
    record->valid = false;
    record->residuals.resize(x.size());
    record->jacobian.resize(static_cast<Eigen::Index>(x.size()), P);
    double* record_residuals = record->residuals.data();
    double* record_jacobian = record->jacobian.data();
    const std::size_t n = x.size();
    for (std::size_t i = 0; i < n; ++i) {
      const Jet r = Jet(y[i]) - model(pj, x[i]);
      if (!isfinite(r)) return false;
      residuals[i] = record_residuals[i] = r.a;
      for (int j = 0; j < P; ++j)
        jacobian[i * P + static_cast<std::size_t>(j)] = record_jacobian[static_cast<std::size_t>(j) * n + i] = r.v[j];
    }
    record->at.assign(p, p + P);
    record->valid = true;
    return true;
  };
  // One residual, differentiated as Ceres' AutoDiffCostFunction<.., 1, P> differentiated it: in
  // doubles when no derivative is wanted, else by Jets seeded one slot per parameter. A
  // non-finite value (overflow on a wild trial step) is a failed evaluation: the solver rejects
  // the step either way, but this way without logging a warning.
  evaluation.one = [&model, &x, &y](std::size_t i, const double* p, double* residual, bool jets, double* gradient) {
    using std::isfinite;
    if (!jets) {
      residual[0] = y[i] - model(p, x[i]);
      return static_cast<bool>(isfinite(residual[0]));
    }
    using Jet = fit::Jet<P>;
    Jet pj[P];
    for (int j = 0; j < P; ++j) pj[j] = Jet(p[j], j);
    const Jet r = Jet(y[i]) - model(pj, x[i]);
    if (!isfinite(r)) return false;
    residual[0] = r.a;
    if (gradient != nullptr)
      for (int j = 0; j < P; ++j) gradient[j] = r.v[j];
    return true;
  };
  evaluation.at = [&evaluate](const std::vector<double>& p, std::vector<double>* residuals, Eigen::MatrixXd* jacobian) {
    return evaluate(p, residuals, jacobian);
  };
  detail::CurveStart start;
  start.initial = std::move(initial);
  start.names = std::move(names);
  start.fixed = std::move(fixed);
  start.free_column = std::move(free_column);
  start.bounded = bounded;
  start.linear_started = linear_started;
  start.start_jacobian = std::move(start_jacobian);
  start.start_inverse_normal = std::move(start_inverse_normal);
  return detail::solve_curve(evaluation, std::move(start), parameters, y, options);
}

}  // namespace epuck2::fit
