// fit::Problem: a caller's residual blocks as a Ceres problem, solved and summarized by the
// engine's one solver path (solve, summarize in least_squares.cpp).
#include "epuck2/fit/problem.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <utility>

#include "solver.hpp"

namespace epuck2::fit {

namespace {
// A ResidualBlock as Ceres' CostFunction.
class BlockCost : public ceres::CostFunction {
 public:
  // Only the evaluation is kept: the sizes move into Ceres' own list (no second copy per block;
  // fit_curve's per-observation path adds one block per observation).
  explicit BlockCost(ResidualBlock block) : evaluate_(std::move(block.evaluate)) {
    set_num_residuals(block.residuals);
    *mutable_parameter_block_sizes() = std::move(block.sizes);
  }
  bool Evaluate(double const* const* parameters, double* residuals, double** jacobians) const override {
    return evaluate_(parameters, residuals, jacobians);
  }

 private:
  const std::function<bool(double const* const*, double*, double**)> evaluate_;
};
}  // namespace

namespace {
// The readings block's chain rule, once: the latent predictions land in `residuals` and their
// derivatives in `jacobians`, then each row becomes its reading's residual residual_of(i, f_i),
// the row's derivatives times d r / d f.
template <class ResidualOf>
ResidualBlock chained(ResidualBlock latent, ResidualOf residual_of) {
  ResidualBlock out;
  out.residuals = latent.residuals;
  out.sizes = latent.sizes;
  out.evaluate = [latent = std::move(latent), residual_of = std::move(residual_of)](double const* const* parameters, double* residuals,
                                                                                    double** jacobians) {
    if (!latent.evaluate(parameters, residuals, jacobians)) return false;
    for (std::size_t i = 0; i < static_cast<std::size_t>(latent.residuals); ++i) {
      const Residual r = residual_of(i, residuals[i]);
      residuals[i] = r.value;
      if (!std::isfinite(r.value)) return false;
      if (jacobians == nullptr) continue;
      for (std::size_t b = 0; b < latent.sizes.size(); ++b)
        if (jacobians[b] != nullptr)
          for (int j = 0; j < latent.sizes[b]; ++j) jacobians[b][i * static_cast<std::size_t>(latent.sizes[b]) + static_cast<std::size_t>(j)] *= r.d_prediction;
    }
    return true;
  };
  return out;
}
}  // namespace

ResidualBlock readings_block(ResidualBlock latent, std::vector<double> readings, std::vector<int> channel, Channels channels) {
  if (static_cast<std::size_t>(latent.residuals) != readings.size() || (!channel.empty() && channel.size() != readings.size()))
    throw std::invalid_argument("fit::readings_block: one latent prediction (and channel) per reading");
  return chained(std::move(latent), [y = std::move(readings), channel = std::move(channel), channels = std::move(channels)](
                                        std::size_t i, double f) {
    return channels.residual(f, y[i], channel.empty() ? 0 : static_cast<std::size_t>(channel[i]));
  });
}

ResidualBlock readings_block(ResidualBlock latent, std::vector<double> readings, std::vector<Censoring> censoring,
                             std::vector<double> weights, double sd) {
  const std::size_t n = readings.size();
  if (static_cast<std::size_t>(latent.residuals) != n || censoring.size() != n || weights.size() != n)
    throw std::invalid_argument("fit::readings_block: one latent prediction, censoring and weight per reading");
  return chained(std::move(latent), [y = std::move(readings), censoring = std::move(censoring), w = std::move(weights), sd](
                                        std::size_t i, double f) {
    if (!(w[i] > 0)) return Residual{};
    return reading_residual(f, y[i], censoring[i], sd, std::sqrt(w[i]));
  });
}

struct Problem::Impl {
  ceres::Problem problem;
};

Problem::Problem() : impl_(std::make_unique<Impl>()) {}
Problem::~Problem() = default;

void Problem::add(ResidualBlock block, const std::vector<double*>& parameters, const FitOptions& loss) {
  impl_->problem.AddResidualBlock(new BlockCost(std::move(block)), make_loss(loss), parameters);
}

void Problem::add_parameters(double* block, int size) { impl_->problem.AddParameterBlock(block, size); }

void Problem::set_lower_bound(double* block, int index, double value) { impl_->problem.SetParameterLowerBound(block, index, value); }
void Problem::set_upper_bound(double* block, int index, double value) { impl_->problem.SetParameterUpperBound(block, index, value); }
void Problem::hold(double* block) { impl_->problem.SetParameterBlockConstant(block); }
void Problem::hold(double* block, const std::vector<int>& indices) {
  if (static_cast<int>(indices.size()) >= impl_->problem.ParameterBlockSize(block))
    impl_->problem.SetParameterBlockConstant(block);
  else if (!indices.empty())
    impl_->problem.SetManifold(block, new ceres::SubsetManifold(impl_->problem.ParameterBlockSize(block), indices));
}
bool Problem::held(double* block) const { return impl_->problem.IsParameterBlockConstant(block); }

namespace {
SolveSummary summary_of(const ceres::Solver::Summary& s) {
  SolveSummary out;
  out.usable = s.IsSolutionUsable();
  out.converged = s.termination_type == ceres::CONVERGENCE;
  out.message = s.message;
  out.brief = s.BriefReport();
  out.iterations = static_cast<int>(s.iterations.size());
  out.initial_cost = s.initial_cost;
  out.final_cost = s.final_cost;
  return out;
}
}  // namespace

SolveSummary Problem::solve(const FitOptions& options) { return summary_of(fit::solve(impl_->problem, options)); }

SolveSummary Problem::confirm(const FitOptions& options) {
  // From the least-squares minimum, Levenberg-Marquardt's first step only confirms it (a step of
  // rounding size): the normal equations suffice for it, without Jacobi scaling.
  ceres::Solver::Options confirm = solver_options(options);
  confirm.linear_solver_type = ceres::DENSE_NORMAL_CHOLESKY;
  confirm.jacobi_scaling = false;
  std::vector<double*> blocks;
  impl_->problem.GetParameterBlocks(&blocks);
  std::vector<std::vector<double>> start;
  for (double* b : blocks) start.emplace_back(b, b + impl_->problem.ParameterBlockSize(b));
  ceres::Solver::Summary summary;
  ceres::Solve(confirm, &impl_->problem, &summary);
  // At the exact minimum the gradient is rounding (about 1e-13, above the 1e-15 tolerance) and
  // every step's predicted decrease can round to zero or below: Ceres counts those as invalid
  // steps and, after five, reports FAILURE without moving. The point is still the linear
  // least-squares solution: a converged fit (seen on AR(1) data, 1 series in 300).
  bool moved = false;
  for (std::size_t k = 0; k < blocks.size(); ++k)
    moved = moved || !std::equal(start[k].begin(), start[k].end(), blocks[k]);
  if (summary.termination_type == ceres::FAILURE && !moved) {
    summary.termination_type = ceres::CONVERGENCE;
    summary.message = "linear least-squares solution (the confirming step found nothing to improve: " + summary.message + ")";
  }
  return summary_of(summary);
}

FitResult Problem::summarize(const ParameterLayout& layout, const std::vector<double>& observations, const SolveSummary& summary,
                             const FitOptions& options) {
  return fit::summarize(impl_->problem, layout, observations, summary.iterations, summary.message, summary.usable, options);
}

FitResult Problem::summarize(const ParameterLayout& layout, const std::vector<double>& residuals, bool evaluated,
                             const std::vector<double>& observations, const SolveSummary& summary) {
  return fit::summarize(layout, residuals, evaluated, observations, summary.iterations, summary.message, summary.usable);
}

}  // namespace epuck2::fit
