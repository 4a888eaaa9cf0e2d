// Internal to the diagnosis: the joint-fit engine (the Engine class, engine.cpp's room), the
// residual-structure scoring (residual_structure.cpp) and what the search (search.cpp) calls.
#pragma once

#include <algorithm>
#include <cmath>
#include <map>
#include <memory>
#include <numeric>
#include <optional>
#include <set>
#include <tuple>

#include "problem.hpp"
#include "screening.hpp"
#include "epuck2/diagnose/diagnose.hpp"
#include "epuck2/fit/least_squares.hpp"
#include "epuck2/fit/problem.hpp"
#include "epuck2/fit/readings.hpp"
#include "epuck2/models/kind_facts.hpp"
#include "epuck2/models/saturation.hpp"

namespace epuck2::diagnose {

using namespace epuck2::fit;  // the engine (lib/fit)

namespace engine_detail {

/// A reading is a whole count: at least the rounding's sqrt(1/12) ~ 0.29 of spread.
constexpr double kDefaultMinimumSd = 0.3;
/// One row carrying this share of a parameter's J^T J makes its covariance error suspect.
constexpr double kOneRowInformation = 0.5;
/// Above this many residuals, candidate effects are first fitted to the leading ones.
constexpr std::size_t kScreenResiduals = 20000;

using detail::Jet;
using detail::kFewFree;
using detail::kMaxFree;
using detail::Problem;
using detail::ShortJet;

/// The mean of a reading clipped at its rails after its noise (lib/models saturation.hpp): what a
/// reading is predicted to be, for the held-out errors, the residual structure and the noise.
using models::expected_clamp;

class Engine {
 public:
  Engine(Problem& problem, const Options& options) : p_(problem), o_(options) {
    // covariate:NAME effects: reading = base + slope (NAME - mean of NAME).
    for (const auto& [name, values] : p_.extra_columns) {
      double mean = 0;
      for (double v : values) mean += v;
      mean /= std::max<std::size_t>(1, values.size());
      std::vector<double> centred(values.size());
      double spread = 0;
      for (std::size_t i = 0; i < values.size(); ++i) {
        centred[i] = values[i] - mean;
        spread = std::max(spread, std::abs(centred[i]));
      }
      if (!(spread > 0)) continue;
      const int index = static_cast<int>(p_.params.size());
      p_.params.push_back({"slope", 0.0, 0.0, -detail::kInf, detail::kInf, false, {}});
      p_.plugin_values.push_back(0.0);
      p_.effects.push_back({"covariate:" + name, {index}});
      slopes_.push_back({index, centred});
    }
    n_ = p_.y.size();
    if (p_.channel.empty()) p_.channel.assign(n_, 0);
    p_.channel_lo.resize(p_.channel_names.size(), -detail::kInf);
    p_.channel_hi.resize(p_.channel_names.size(), detail::kInf);
    p_.channel_saturation_lo.resize(p_.channel_names.size(), -detail::kInf);
    p_.channel_saturation_hi.resize(p_.channel_names.size(), detail::kInf);
    if (p_.channel_min_sd.size() < p_.channel_names.size()) p_.channel_min_sd.resize(p_.channel_names.size(), kDefaultMinimumSd);
    // The readings' rails and channel weights are the fit engine's (lib/fit readings.hpp): the
    // same censoring as the calibration's fits.
    std::vector<fit::Channel> channels(p_.channel_names.size());
    for (std::size_t c = 0; c < channels.size(); ++c) {
      channels[c].rail_lo = p_.channel_lo[c];
      channels[c].rail_hi = p_.channel_hi[c];
    }
    channels_ = fit::Channels(std::move(channels));
    // Folds: contiguous blocks of rows dealt round-robin.
    const std::size_t blocks = static_cast<std::size_t>(std::max(1, o_.folds * o_.blocks_per_fold));
    const std::size_t block_rows = std::max<std::size_t>(1, (p_.rows + blocks - 1) / blocks);
    block_rows_ = block_rows;
    all_.resize(n_);
    std::iota(all_.begin(), all_.end(), 0);
  }

  std::size_t size() const { return n_; }
  /// Residual i's weight, sigma[0] / sigma[its channel] (fit::Channels).
  double weight(std::size_t i) const { return channels_.weight(channel_of(i)); }
  /// Residual i's clamp (its channel's).
  double lo(std::size_t i) const { return p_.channel_lo[static_cast<std::size_t>(p_.channel[i])]; }
  double hi(std::size_t i) const { return p_.channel_hi[static_cast<std::size_t>(p_.channel[i])]; }

  /// Noise standard deviation per channel; residuals are weighted by sigma[0] / sigma[channel].
  const std::vector<double>& sigma() const { return channels_.noise_sd(); }
  void set_sigma(const std::vector<double>& sigma) { channels_.set_noise_sd(sigma); }

  /// The model's latent readings (before the register's rails: covariate terms and the sensor's
  /// saturation before its noise included) of residuals [0, needed) at least; the others may be
  /// left at 0. `out` holds size() of them (constructed here).
  template <typename T>
  void latent(const T* values, T* out, std::size_t needed = detail::kAllResiduals) const {
    std::uninitialized_fill_n(out, n_, T(0.0));
    p_.mean(values, out, needed);
    const std::size_t n = std::min(n_, needed);
    for (const auto& s : slopes_)
      for (std::size_t i = 0; i < n; ++i)
        if (p_.channel[i] == 0) out[i] += values[s.param] * s.centred[i];
    for (std::size_t i = 0; i < n; ++i)
      out[i] = models::saturate(out[i], p_.channel_saturation_lo[channel_of(i)], p_.channel_saturation_hi[channel_of(i)]);
  }
  /// The model's expected readings E[clamp(latent + noise)] of every residual.
  std::vector<double> predict(const std::vector<double>& values) const {
    std::vector<double> out(n_);
    latent(values.data(), out.data());
    for (std::size_t i = 0; i < n_; ++i) out[i] = expected_clamp(out[i], lo(i), hi(i), sigma()[channel_of(i)]);
    return out;
  }
  /// The readings' errors against their expected values, weighted, in channel 0's units: what
  /// the held-out test, the residual structure and the autocorrelation judge.
  std::vector<double> residuals(const std::vector<double>& values) const {
    std::vector<double> r = predict(values);
    for (std::size_t i = 0; i < n_; ++i) r[i] = error(i, r[i]);
    return r;
  }
  /// Reading i's error against a prediction of the reading itself, weighted (channel 0's units).
  double error(std::size_t i, double predicted) const { return channels_.weighted_error(predicted, p_.y[i], channel_of(i)); }
  /// The fit's residuals (the engine's censored likelihood, fit::Channels), in channel 0's units:
  /// 1/2 their sum of squares over sigma[0]^2 is the negative log-likelihood.
  std::vector<double> loss_residuals(const std::vector<double>& values) const {
    std::vector<double> r(n_);
    latent(values.data(), r.data());
    for (std::size_t i = 0; i < n_; ++i) r[i] = channels_.residual(r[i], p_.y[i], channel_of(i)).value;
    return r;
  }

  struct Fitted {
    std::vector<double> values;
    FitResult result;
  };

  /// Least squares over the residuals `idx`, parameters `free` free (others held), from `start`.
  Fitted fit(const std::vector<int>& free, const std::vector<double>& start, const std::vector<std::size_t>& idx,
             bool covariance) const {
    Fitted f;
    f.values = start;
    const std::size_t P = p_.params.size();
    std::vector<int> slot(P, -1);
    int k = 0;
    for (int j : free) slot[static_cast<std::size_t>(j)] = k++;
    if (free.empty()) {
      const auto r = loss_residuals(f.values);
      double rss = 0;
      for (std::size_t i : idx) rss += r[i] * r[i];
      f.result.usable = true;
      f.result.observations = idx.size();
      f.result.rss = rss;
      f.result.mse = idx.empty() ? 0 : rss / static_cast<double>(idx.size());
      f.result.residual_variance = f.result.mse;
      f.result.bic = bayes(idx.size(), rss, 0);
      f.result.aic = akaike(idx.size(), rss, 0);
      for (std::size_t j = 0; j < P; ++j) f.result.parameters.push_back({p_.params[j].name, f.values[j], 0.0});
      return f;
    }
    fit::Problem problem;
    std::vector<double*> blocks;
    for (std::size_t j = 0; j < P; ++j) blocks.push_back(&f.values[j]);
    add_cost(problem, idx, slot, f.values);
    for (std::size_t j = 0; j < P; ++j) {
      if (slot[j] < 0) {
        problem.hold(blocks[j]);
        continue;
      }
      if (std::isfinite(p_.params[j].lower)) problem.set_lower_bound(blocks[j], 0, p_.params[j].lower);
      if (std::isfinite(p_.params[j].upper)) problem.set_upper_bound(blocks[j], 0, p_.params[j].upper);
    }
    FitOptions options = FitOptions::diagnosis();
    options.compute_covariance = covariance;
    const SolveSummary summary = problem.solve(options);
    ParameterLayout layout;
    layout.blocks = blocks;
    layout.sizes.assign(P, 1);
    for (const auto& q : p_.params) layout.names.push_back(q.name);
    std::vector<double> observed;
    observed.reserve(idx.size());
    for (std::size_t i : idx) observed.push_back(p_.y[i]);
    f.result = problem.summarize(layout, observed, summary, options);
    return f;
  }

  /// The weighted residuals' derivatives at `values` over every parameter (n x P; zero columns
  /// for those not in `free`), as the fits evaluate them (false when they cannot be evaluated).
  bool jacobian(const std::vector<int>& free, std::vector<double> values, Eigen::MatrixXd* out) const {
    const std::size_t P = p_.params.size();
    std::vector<int> slot(P, -1);
    int k = 0;
    for (int j : free) slot[static_cast<std::size_t>(j)] = k++;
    *out = Eigen::MatrixXd::Zero(static_cast<Eigen::Index>(n_), static_cast<Eigen::Index>(P));
    if (free.empty()) return true;
    // The fits' cost evaluated directly, each free parameter's derivatives written into its
    // column: what the engine's Problem::evaluate gives, without Ceres' evaluation scratch and its two
    // sparse copies of the Jacobian (~100 MB on a 1M-row drive log).
    const Cost cost(*this, all_, slot, values);
    std::vector<const double*> parameters;
    std::vector<double*> columns;
    for (std::size_t j = 0; j < P; ++j)
      if (slot[j] >= 0) {
        parameters.push_back(&values[j]);
        columns.push_back(out->col(static_cast<Eigen::Index>(j)).data());
      }
    std::vector<double> residuals(n_);
    return cost(parameters.data(), residuals.data(), columns.data());
  }

  /// Held-out MSE: each fold predicted by a fit on the other folds.
  /// Held-out MSE of every residual (weighted) and of channel 0's alone (the reading, unweighted).
  struct Heldout {
    double all = 0, reading = 0;
    /// Each fold's fit (on the other folds): every parameter's value, for the jackknife.
    std::vector<std::vector<double>> fold_values;
  };
  Heldout heldout_mse(const std::vector<int>& free, const std::vector<double>& start) const {
    double sse = 0, sse0 = 0;
    std::size_t count = 0, count0 = 0;
    std::vector<std::vector<double>> fold_values;
    for (int f = 0; f < o_.folds; ++f) {
      std::vector<std::size_t> train, test;
      for (std::size_t i = 0; i < n_; ++i) (fold_of(i) == f ? test : train).push_back(i);
      if (test.empty() || train.empty()) continue;
      const Fitted fit_f = fit(free, start, train, false);
      if (fit_f.result.usable) fold_values.push_back(fit_f.values);
      const auto r = residuals(fit_f.values);
      for (std::size_t i : test) {
        sse += r[i] * r[i];
        if (p_.channel[i] == 0) {
          sse0 += r[i] * r[i];
          ++count0;
        }
      }
      count += test.size();
    }
    Heldout h;
    h.fold_values = std::move(fold_values);
    h.all = count ? sse / static_cast<double>(count) : 0.0;
    h.reading = count0 ? sse0 / static_cast<double>(count0) : 0.0;
    return h;
  }

  const std::vector<std::size_t>& all() const { return all_; }

  /// Noise standard deviation per channel from the residuals of readings away from the clamps.
  std::vector<double> noise_sd(const std::vector<double>& values) const {
    const auto pred = predict(values);
    const std::size_t C = sigma().size();
    std::vector<double> s(C, 0.0), c(C, 0.0);
    if (p_.noise_from_differences) {
      // Time series: half the mean square of successive residuals of a channel, which a model
      // error that changes slowly from row to row does not inflate.
      std::vector<double> last(C, std::nan(""));
      for (std::size_t i = 0; i < n_; ++i) {
        if (!(p_.y[i] > lo(i) && p_.y[i] < hi(i))) continue;
        const std::size_t ch = static_cast<std::size_t>(p_.channel[i]);
        const double r = p_.y[i] - pred[i];
        if (std::isfinite(last[ch])) {
          s[ch] += 0.5 * (r - last[ch]) * (r - last[ch]);
          c[ch] += 1;
        }
        last[ch] = r;
      }
    } else {
      // Readings whose mean lies near a rail have their noise clipped on one side: their
      // residuals are left out (a mean within 3 of the current sd of a rail), unless too few
      // readings remain.
      std::vector<double> s_far(C, 0.0), c_far(C, 0.0);
      for (std::size_t i = 0; i < n_; ++i)
        if (p_.y[i] > lo(i) && p_.y[i] < hi(i)) {
          const std::size_t ch = static_cast<std::size_t>(p_.channel[i]);
          const double r2 = (p_.y[i] - pred[i]) * (p_.y[i] - pred[i]);
          s[ch] += r2;
          c[ch] += 1;
          const double margin = 3.0 * sigma()[ch];
          if (pred[i] - lo(i) > margin && hi(i) - pred[i] > margin) {
            s_far[ch] += r2;
            c_far[ch] += 1;
          }
        }
      constexpr double kEnoughFar = 30;
      for (std::size_t ch = 0; ch < C; ++ch)
        if (c_far[ch] >= kEnoughFar) {
          s[ch] = s_far[ch];
          c[ch] = c_far[ch];
        }
    }
    std::vector<double> out(C);
    for (std::size_t ch = 0; ch < C; ++ch) out[ch] = std::max(p_.channel_min_sd[ch], c[ch] > 0 ? std::sqrt(s[ch] / c[ch]) : 1.0);
    return out;
  }

 private:
  /// The cost of the residuals `idx` with the parameters whose `slot` is >= 0 free: every
  /// parameter of `values` is a block of the problem (in index order, as the fit's layout has
  /// them), the residual block holds the free ones only, in index order. (Ceres sizes its
  /// evaluation scratch, and zeroes it at every solve, by the residual block's parameters: with
  /// all of them in the block, 2M residuals x 7 drive parameters took 112 MB a solve.)
  void add_cost(fit::Problem& problem, const std::vector<std::size_t>& idx, const std::vector<int>& slot,
                std::vector<double>& values) const {
    std::vector<double*> free_blocks;
    for (std::size_t j = 0; j < values.size(); ++j) {
      problem.add_parameters(&values[j], 1);
      if (slot[j] >= 0) free_blocks.push_back(&values[j]);
    }
    problem.add(Cost(*this, idx, slot, values).block(), free_blocks);
  }

  /// All residuals of the training rows in one block, the engine's censored likelihood of each
  /// reading against its latent model (fit::Channels); one parameter block of size 1 per free
  /// parameter (the others held at their values); derivatives by Jets over the free parameters.
  class Cost {
   public:
    Cost(const Engine& e, const std::vector<std::size_t>& idx, const std::vector<int>& slot, const std::vector<double>& values)
        : e_(e), idx_(idx), slot_(slot), held_(values) {
      for (std::size_t i : idx) limit_ = std::max(limit_, i + 1);
      for (std::size_t j = 0; j < slot.size(); ++j)
        if (slot[j] >= 0) block_of_.push_back(j);
    }
    /// The engine's residual block: one value per free parameter, derivatives filled by operator().
    fit::ResidualBlock block() const {
      fit::ResidualBlock b;
      b.residuals = static_cast<int>(idx_.size());
      b.sizes.assign(block_of_.size(), 1);
      b.evaluate = *this;
      return b;
    }
    bool operator()(double const* const* parameters, double* residuals, double** jacobians) const {
      const std::size_t B = block_of_.size();
      bool need = false;
      if (jacobians)
        for (std::size_t b = 0; b < B; ++b) need = need || (jacobians[b] != nullptr);
      if (!need) {
        std::vector<double> v = held_;
        for (std::size_t b = 0; b < B; ++b) v[block_of_[b]] = parameters[b][0];
        double* pred = e_.scratch<double>();
        e_.latent(v.data(), pred, limit_);
        for (std::size_t k = 0; k < idx_.size(); ++k) {
          const std::size_t i = idx_[k];
          residuals[k] = e_.channels_.residual(pred[i], e_.p_.y[i], e_.channel_of(i)).value;
          if (!std::isfinite(residuals[k])) return false;
        }
        return true;
      }
      int free = 0;
      for (int s : slot_) free += s >= 0 ? 1 : 0;
      if (free <= detail::kTwoFree) return with_jets<detail::PairJet>(parameters, residuals, jacobians);
      return free <= kFewFree ? with_jets<ShortJet>(parameters, residuals, jacobians)
                              : with_jets<Jet>(parameters, residuals, jacobians);
    }

    template <typename J>
    bool with_jets(double const* const* parameters, double* residuals, double** jacobians) const {
      const std::size_t P = slot_.size(), B = block_of_.size();
      std::vector<J> v(P);
      for (std::size_t j = 0; j < P; ++j) v[j] = J(held_[j]);
      for (std::size_t b = 0; b < B; ++b) v[block_of_[b]] = J(parameters[b][0], slot_[block_of_[b]]);
      J* pred = e_.scratch<J>();
      e_.latent(v.data(), pred, limit_);
      for (std::size_t k = 0; k < idx_.size(); ++k) {
        const J& m = pred[idx_[k]];
        const fit::Residual r = e_.channels_.residual(m.a, e_.p_.y[idx_[k]], e_.channel_of(idx_[k]));
        residuals[k] = r.value;
        if (!std::isfinite(residuals[k])) return false;
        for (std::size_t b = 0; b < B; ++b)
          if (jacobians[b]) {
            const double d = r.d_prediction * m.v[slot_[block_of_[b]]];
            if (!std::isfinite(d)) return false;
            jacobians[b][k] = d;
          }
      }
      return true;
    }

   private:
    const Engine& e_;
    const std::vector<std::size_t>& idx_;  // outlives the problem that owns this cost (Engine::fit)
    const std::vector<int> slot_;
    const std::vector<double> held_;    ///< every parameter's value (the free ones' are the blocks')
    std::vector<std::size_t> block_of_;  ///< parameter block b is parameter block_of_[b]
    std::size_t limit_ = 0;  ///< one past the last residual used
  };

  /// The predictions of Cost::Evaluate, kept from one evaluation (and one fit) to the next
  /// instead of allocated in each: on a 1M-row drive log the Jets' are 48 MB or more, which glibc
  /// serves by mmap (above its largest threshold, 32 MiB) and unmaps on free, so that every
  /// evaluation faulted every page of them in afresh (3.3 million page faults, 6 s of system
  /// time). One evaluation at a time (the engine's solves run on one thread), so one buffer for
  /// every scalar type, sized for the largest asked: the doubles' 16 MB no longer sit beside the
  /// Jets' (nor 2-wide Jets' beside 8-wide ones). size() of them, constructed by predict.
  template <typename T>
  T* scratch() const {
    static_assert(alignof(T) <= alignof(ScratchBlock), "a scalar aligned beyond the scratch's blocks");
    const std::size_t blocks = (n_ * sizeof(T) + sizeof(ScratchBlock) - 1) / sizeof(ScratchBlock);
    if (scratch_.size() < blocks) {
      std::vector<ScratchBlock>().swap(scratch_);  // not held beside the larger one
      scratch_.resize(blocks);
    }
    return reinterpret_cast<T*>(scratch_.data());
  }
  struct alignas(64) ScratchBlock {
    unsigned char bytes[64];
  };
  mutable std::vector<ScratchBlock> scratch_;

  struct Slope {
    int param;
    std::vector<double> centred;
  };
  Problem& p_;
  const Options& o_;
  std::vector<Slope> slopes_;
  std::size_t n_ = 0;
  fit::Channels channels_;  ///< rails, noise sd and weights per channel
  std::size_t block_rows_ = 1;  ///< rows per block of the folds
  std::vector<std::size_t> all_;
  std::size_t channel_of(std::size_t i) const { return static_cast<std::size_t>(p_.channel[i]); }
  /// Residual i's fold (not stored: 8 MB on a 1M-row drive log).
  int fold_of(std::size_t i) const { return static_cast<int>((p_.row[i] / block_rows_) % static_cast<std::size_t>(o_.folds)); }
};

/// Upper quantile of chi-square with `df` degrees of freedom at tail probability 1e-6.
double chi2_critical(double df);

/// How much of the residuals' variance the covariate's binned means explain, and whether that is significant.
CovariateScore score_covariate(const std::string& name, const std::vector<double>& x, const std::vector<double>& r,
                               double threshold);

/// Scores every covariate against the residuals (per channel, keeping the strongest).
std::vector<CovariateScore> structure(const Problem& p, const std::vector<double>& r, const std::vector<double>& predicted,
                                      double threshold, const std::vector<double>& sigma);

}  // namespace engine_detail
}  // namespace epuck2::diagnose
