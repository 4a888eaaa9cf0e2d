// The Ceres side of the engine, private to lib/fit (lib/fit/src): only lib/fit's own sources
// include it. Callers state their fits through epuck2/fit/problem.hpp, fit_curve.hpp and
// robust.hpp, none of which names Ceres; CTest `ceres_in_lib_fit_alone` checks that no object
// outside lib/fit is compiled with a Ceres header.
#pragma once

#include <ceres/ceres.h>

#include <string>
#include <vector>

#include "epuck2/fit/least_squares.hpp"

namespace epuck2::fit {

/// The loss to attach to each residual block (nullptr for plain squares), as `options` say.
/// Ownership passes to the problem.
ceres::LossFunction* make_loss(const FitOptions& options);
/// Ceres' settings for one solve, as `options` say (silent, one thread).
ceres::Solver::Options solver_options(const FitOptions& options);

/// Solves `problem` as `options` say: one Levenberg-Marquardt solve by default; with `restarts`
/// and `try_alternatives`, several solves, leaving the parameters at the lowest cost found. The
/// other strategies run only when the first one's solution fails its own checks: Ceres did not
/// report convergence, the restarts ran out while the cost still fell, a parameter no longer
/// moves the residuals (relative sensitivity |b_j| |J_j| below 1e-8 of the largest: a plateau
/// where the model saturates), the equilibrated Jacobian is rank-deficient, or the problem holds
/// parameters through a manifold (not checked: every strategy runs). The
/// summary returned is the winning solve's, its `iterations` holding every iteration of every
/// solve (the total work).
ceres::Solver::Summary solve(ceres::Problem& problem, const FitOptions& options);

/// Everything after Solve: RSS, MSE, R^2 (with `observations` for the total sum of squares; empty
/// for none), information criteria, covariance and standard errors. Blocks held constant in the
/// problem are reported with a zero standard error and do not count as free parameters.
FitResult summarize(ceres::Problem& problem, const ParameterLayout& layout,
                    const std::vector<double>& observations, const ceres::Solver::Summary& summary,
                    const FitOptions& options);

/// summarize from the residuals already evaluated at the solution (`evaluated` false when they
/// could not be), with every parameter free and no covariance (see set_covariance), the solver's
/// summary given as its parts: what fit::Problem's residuals summarize reports through.
FitResult summarize(const ParameterLayout& layout, const std::vector<double>& residuals, bool evaluated,
                    const std::vector<double>& observations, int iterations, const std::string& message, bool usable);

/// summarize's work with the solver's summary given as its parts (iterations made, termination
/// message, whether the solution is usable): what fit::Problem::summarize reports through.
FitResult summarize(ceres::Problem& problem, const ParameterLayout& layout, const std::vector<double>& observations,
                    int iterations, const std::string& message, bool usable, const FitOptions& options);

}  // namespace epuck2::fit
