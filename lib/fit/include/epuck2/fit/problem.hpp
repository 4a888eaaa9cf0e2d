// A least-squares problem stated to the engine by a caller whose residuals are not one curve
// (fit_curve) nor one censored model (fit_robust): several parameter arrays, residual blocks that
// share them, bounds, parameters held, a robust loss; solved with the engine's one set of solver
// settings (FitOptions) and summarized into a FitResult as every fit is. The charge map, the
// virtual robot's battery calibration, the diagnosis's joint fit and NIST's two-predictor problem
// use it. Ceres stays inside lib/fit: this header does not name it.
//
// The model shape is one: a functor computing residuals from parameters, templated on the scalar
// (`autodiff<R, S...>(functor)`, derivatives by epuck2::fit::Jet), or, where a caller has its
// derivatives in closed form or picks its Jet size itself, a ResidualBlock that fills them.
#pragma once

#include <Eigen/Dense>
#include <functional>
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include "epuck2/fit/jet.hpp"
#include "epuck2/fit/least_squares.hpp"
#include "epuck2/fit/readings.hpp"

namespace epuck2::fit {

/// Residuals and, when asked, their derivatives over some parameter arrays ("blocks").
/// `evaluate(parameters, residuals, jacobians)`: parameters[b] holds block b's `sizes[b]` values;
/// `residuals` receives `residuals` values; `jacobians` is null when no derivatives are wanted,
/// else jacobians[b] is null or receives block b's derivatives row-major (residuals x sizes[b]).
/// False when the residuals cannot be evaluated there (a non-finite value: the solver rejects the
/// step).
struct ResidualBlock {
  int residuals = 0;
  std::vector<int> sizes;
  std::function<bool(double const* const* parameters, double* residuals, double** jacobians)> evaluate;
};

namespace detail {
template <int R, int... Sizes, class Functor, std::size_t... B>
bool autodiff_evaluate(const Functor& f, double const* const* parameters, double* residuals, double** jacobians,
                       std::index_sequence<B...>) {
  constexpr int kSizes[] = {Sizes...};
  if (jacobians == nullptr) return f(parameters[B]..., residuals);
  constexpr int N = (Sizes + ...);
  using J = Jet<N>;
  // Every parameter of every block seeded with its own derivative slot, as Ceres' AutoDiff does.
  J x[N];
  J* start[sizeof...(Sizes)];
  {
    int offset = 0;
    for (std::size_t b = 0; b < sizeof...(Sizes); ++b) {
      start[b] = x + offset;
      for (int j = 0; j < kSizes[b]; ++j) x[offset + j] = J(parameters[b][j], offset + j);
      offset += kSizes[b];
    }
  }
  J out[R];
  if (!f(static_cast<const J*>(start[B])..., out)) return false;
  for (int r = 0; r < R; ++r) residuals[r] = out[r].a;
  int offset = 0;
  for (std::size_t b = 0; b < sizeof...(Sizes); ++b) {
    if (jacobians[b] != nullptr)
      for (int r = 0; r < R; ++r)
        for (int j = 0; j < kSizes[b]; ++j) jacobians[b][r * kSizes[b] + j] = out[r].v[offset + j];
    offset += kSizes[b];
  }
  return true;
}
}  // namespace detail

/// The residual block of `functor`, a
/// `template <typename T> bool operator()(const T* block0, ..., T* residuals) const` over blocks
/// of `Sizes...` values with R residuals, differentiated by Jet<sum of Sizes> (the scalar Ceres'
/// AutoDiffCostFunction would use: the same arithmetic).
template <int R, int... Sizes, class Functor>
ResidualBlock autodiff(Functor functor) {
  static_assert(R > 0 && sizeof...(Sizes) > 0 && ((Sizes > 0) && ...), "residuals and parameter blocks must be non-empty");
  ResidualBlock block;
  block.residuals = R;
  block.sizes = {Sizes...};
  block.evaluate = [f = std::move(functor)](double const* const* p, double* r, double** j) {
    return detail::autodiff_evaluate<R, Sizes...>(f, p, r, j, std::make_index_sequence<sizeof...(Sizes)>{});
  };
  return block;
}

/// The engine's treatment of readings (epuck2/fit/readings.hpp) as a residual block: `latent`
/// computes the latent predictions of readings.size() observations (as its "residuals", with their
/// derivatives); each becomes its reading's residual, censored at its channel's rails and weighted
/// by its channel's noise sd (`channel` empty: every reading in channel 0).
ResidualBlock readings_block(ResidualBlock latent, std::vector<double> readings, std::vector<int> channel, Channels channels);

/// The same treatment for readings that state their own censoring (the reading being the rail
/// itself when censored: fit_robust's Observations) and carry a weight each, residuals in noise
/// sd: reading i's residual is reading_residual(f_i, readings[i], censoring[i], sd,
/// sqrt(weights[i])); a weight of 0 leaves the reading out (residual and derivatives 0).
ResidualBlock readings_block(ResidualBlock latent, std::vector<double> readings, std::vector<Censoring> censoring,
                             std::vector<double> weights, double sd);

/// What a solve did (the engine's summary of its solver's).
struct SolveSummary {
  bool usable = false;     ///< the parameters hold a solution (converged, or stopped with one)
  bool converged = false;  ///< the solver reports convergence
  std::string message;     ///< the solver's termination message
  std::string brief;       ///< a one-line report (costs, iterations, termination)
  int iterations = 0;      ///< every iteration of every solve made
  double initial_cost = 0, final_cost = 0;  ///< 1/2 the sum of squared residuals (after the loss)
};

class Problem {
 public:
  Problem();
  ~Problem();
  Problem(const Problem&) = delete;
  Problem& operator=(const Problem&) = delete;

  /// Adds `block` over the parameter arrays `parameters` (one per entry of block.sizes, of that
  /// size; an array given to several blocks is one set of parameters). The loss is squares, or
  /// Huber's at options.robust_scale when options.robust.
  void add(ResidualBlock block, const std::vector<double*>& parameters, const FitOptions& loss = FitOptions{});
  /// Adds the array `block` of `size` values as parameters of the problem before (or without) a
  /// residual block over it: a caller whose residual block takes only the free arrays keeps the
  /// held ones in the problem (hold() them) so that summarize() reports every array of its layout.
  void add_parameters(double* block, int size);
  /// Bounds on value `index` of the array `block` (already added).
  void set_lower_bound(double* block, int index, double value);
  void set_upper_bound(double* block, int index, double value);
  /// Holds every value of the array `block` where it is.
  void hold(double* block);
  /// Holds the values `indices` of the array `block` where they are, the others free (every one
  /// of them: as hold(block)).
  void hold(double* block, const std::vector<int>& indices);
  bool held(double* block) const;

  /// Solves as `options` say (epuck2/fit/least_squares.hpp FitOptions: the solver settings, the
  /// restarts and alternative strategies); the arrays end at the solution.
  SolveSummary solve(const FitOptions& options);
  /// One solve from a point that should already be the minimum (fit_curve's linear least-squares
  /// start): Levenberg-Marquardt on the normal equations (dense Cholesky) without Jacobi scaling,
  /// no restarts. A FAILURE that left every array where it was is reported as convergence: at the
  /// exact minimum every step's predicted decrease rounds to zero or below, and Ceres gives up
  /// after five such steps without moving.
  SolveSummary confirm(const FitOptions& options);

  /// The fit's statistics at the arrays' current values (FitResult: RSS, R^2 against
  /// `observations`, AIC, BIC, covariance and standard errors over the arrays not held), as
  /// every fit of the engine reports them.
  FitResult summarize(const ParameterLayout& layout, const std::vector<double>& observations, const SolveSummary& summary,
                      const FitOptions& options);
  /// The statistics from residuals the caller evaluated itself at the arrays' values (`evaluated`
  /// false when they could not be), every parameter counted free and no covariance (see
  /// set_covariance): fit_curve's, which keeps the Jacobian its solve already evaluated.
  static FitResult summarize(const ParameterLayout& layout, const std::vector<double>& residuals, bool evaluated,
                             const std::vector<double>& observations, const SolveSummary& summary);

  struct Impl;

 private:
  std::unique_ptr<Impl> impl_;
};

}  // namespace epuck2::fit
