// The diagnosis engine: recalibration, greedy forward search over the catalogue's effects with
// BIC and held-out error, residual structure (docs/diagnose.md, steps 2 to 5).
#include <ceres/ceres.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <numeric>
#include <set>

#include "problem.hpp"
#include "epuck2/diagnose/diagnose.hpp"
#include "epuck2/calibrate/screening.hpp"
#include "epuck2/fit/least_squares.hpp"

namespace epuck2::diagnose {

using namespace epuck2::fit;  // the engine (lib/fit)
using calibrate::WildReading;
using calibrate::drop_wild_readings;
using calibrate::drop_wild_readings_in_place;
using calibrate::readings_on_rails;

namespace detail {

void add_common_covariates(Problem& p, const std::vector<logs::Log>& logs, const std::vector<std::string>& skip) {
  // Per-row values (rows numbered across all logs), spread to the residuals through Problem::row.
  auto per_residual = [&](const std::vector<double>& per_row) {
    std::vector<double> v(p.row.size());
    for (std::size_t i = 0; i < p.row.size(); ++i) v[i] = per_row[p.row[i]];
    return v;
  };
  std::set<std::string> extras;
  for (const auto& log : logs)
    for (const auto& c : log.extra_numeric_columns())
      if (std::find(skip.begin(), skip.end(), c) == skip.end()) extras.insert(c);
  // A column is a candidate only when every log has it.
  for (const auto& name : extras) {
    bool everywhere = true;
    for (const auto& log : logs) everywhere = everywhere && log.has(name);
    if (!everywhere) continue;
    std::vector<double> rows;
    for (const auto& log : logs)
      for (double x : log.col(name)) rows.push_back(x);
    p.extra_columns.emplace_back(name, per_residual(rows));  // the covariate:NAME effect's, per residual
    p.add_row_covariate(name, std::move(rows));                 // scored: once per row
  }
  std::vector<double> index, which;
  for (std::size_t l = 0; l < logs.size(); ++l)
    for (std::size_t i = 0; i < logs[l].rows(); ++i) {
      index.push_back(static_cast<double>(i));
      which.push_back(static_cast<double>(l));
    }
  p.add_row_covariate("row", std::move(index));
  if (logs.size() > 1) p.add_row_covariate("log", std::move(which));
}

}  // namespace detail

namespace {

/// A reading is a whole count: at least the rounding's sqrt(1/12) ~ 0.29 of spread.
constexpr double kDefaultMinimumSd = 0.3;
/// Above this many residuals, candidate effects are first fitted to the leading ones.
constexpr std::size_t kScreenResiduals = 20000;

using detail::Jet;
using detail::kFewFree;
using detail::kMaxFree;
using detail::Problem;
using detail::ShortJet;

/// E[clamp(mu + e, lo, hi)] for e ~ N(0, sigma^2): the mean of a clamped noisy reading, smooth in
/// mu, so that readings at a clamp are fitted without bias (for hi - lo >> sigma).
template <typename T>
T expected_clamp(const T& mu, double lo, double hi, double sigma) {
  using std::erfc;
  using std::exp;
  constexpr double kInvSqrt2 = 0.70710678118654752440;
  constexpr double kInvSqrt2Pi = 0.39894228040143267794;
  // Beyond 9 sigma from both clamps the correction is below 1e-20 sigma: the mean itself.
  constexpr double kFar = 9.0;
  const double m = detail::value_of(mu);
  if (!(m - lo < kFar * sigma) && !(hi - m < kFar * sigma)) return mu;
  // Beyond 9 sigma outside one clamp (and far from the other), the reading is that clamp.
  if (lo - m > kFar * sigma && hi - m > kFar * sigma) return T(lo);
  if (m - hi > kFar * sigma && m - lo > kFar * sigma) return T(hi);
  T out = mu;
  if (std::isfinite(lo)) {
    const T z = (lo - mu) / sigma;  // E[max(0, lo - X)] = sigma (z Phi(z) + phi(z))
    out += sigma * (z * (0.5 * erfc(-z * kInvSqrt2)) + kInvSqrt2Pi * exp(-0.5 * z * z));
  }
  if (std::isfinite(hi)) {
    const T z = (mu - hi) / sigma;
    out -= sigma * (z * (0.5 * erfc(-z * kInvSqrt2)) + kInvSqrt2Pi * exp(-0.5 * z * z));
  }
  return out;
}

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
      p_.params.push_back({"slope", 0.0, 0.0, -detail::kInf, detail::kInf, {}});
      p_.plugin_values.push_back(0.0);
      p_.effects.push_back({"covariate:" + name, {index}});
      slopes_.push_back({index, centred});
    }
    n_ = p_.y.size();
    if (p_.channel.empty()) p_.channel.assign(n_, 0);
    p_.channel_lo.resize(p_.channel_names.size(), -detail::kInf);
    p_.channel_hi.resize(p_.channel_names.size(), detail::kInf);
    if (p_.channel_min_sd.size() < p_.channel_names.size()) p_.channel_min_sd.resize(p_.channel_names.size(), kDefaultMinimumSd);
    set_sigma(std::vector<double>(p_.channel_names.size(), 1.0));
    // Folds: contiguous blocks of rows dealt round-robin.
    const std::size_t blocks = static_cast<std::size_t>(std::max(1, o_.folds * o_.blocks_per_fold));
    const std::size_t block_rows = std::max<std::size_t>(1, (p_.rows + blocks - 1) / blocks);
    fold_.resize(n_);
    for (std::size_t i = 0; i < n_; ++i) fold_[i] = static_cast<int>((p_.row[i] / block_rows) % static_cast<std::size_t>(o_.folds));
    all_.resize(n_);
    std::iota(all_.begin(), all_.end(), 0);
  }

  std::size_t size() const { return n_; }
  /// Residual i's weight, sigma[0] / sigma[its channel].
  double weight(std::size_t i) const { return channel_weight_[static_cast<std::size_t>(p_.channel[i])]; }
  /// Residual i's clamp (its channel's).
  double lo(std::size_t i) const { return p_.channel_lo[static_cast<std::size_t>(p_.channel[i])]; }
  double hi(std::size_t i) const { return p_.channel_hi[static_cast<std::size_t>(p_.channel[i])]; }

  /// Noise standard deviation per channel; residuals are weighted by sigma[0] / sigma[channel].
  const std::vector<double>& sigma() const { return sigma_; }
  void set_sigma(const std::vector<double>& sigma) {
    sigma_ = sigma;
    // Per channel, not per residual: every residual of a channel has the same weight.
    channel_weight_.resize(sigma_.size());
    for (std::size_t c = 0; c < sigma_.size(); ++c) channel_weight_[c] = sigma_[0] / sigma_[c];
  }

  template <typename T>
  void predict(const T* values, std::vector<T>& out) const {
    out.assign(n_, T(0.0));
    p_.mean(values, out.data());
    const std::size_t n = std::min(n_, p_.needed);  // the residuals the evaluation asked for
    for (const auto& s : slopes_)
      for (std::size_t i = 0; i < n; ++i)
        if (p_.channel[i] == 0) out[i] += values[s.param] * s.centred[i];
    for (std::size_t i = 0; i < n; ++i)
      out[i] = expected_clamp(out[i], lo(i), hi(i), sigma_[static_cast<std::size_t>(p_.channel[i])]);
  }
  std::vector<double> predict(const std::vector<double>& values) const {
    std::vector<double> out;
    predict(values.data(), out);
    return out;
  }
  /// Weighted residuals, in channel 0's units.
  std::vector<double> residuals(const std::vector<double>& values) const {
    std::vector<double> r = predict(values);
    for (std::size_t i = 0; i < n_; ++i) r[i] = weight(i) * (p_.y[i] - r[i]);
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
      const auto r = residuals(f.values);
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
    ceres::Problem problem;
    std::vector<double*> blocks;
    for (std::size_t j = 0; j < P; ++j) blocks.push_back(&f.values[j]);
    problem.AddResidualBlock(new Cost(*this, idx, slot), nullptr, blocks);
    for (std::size_t j = 0; j < P; ++j) {
      if (slot[j] < 0) {
        problem.SetParameterBlockConstant(blocks[j]);
        continue;
      }
      if (std::isfinite(p_.params[j].lower)) problem.SetParameterLowerBound(blocks[j], 0, p_.params[j].lower);
      if (std::isfinite(p_.params[j].upper)) problem.SetParameterUpperBound(blocks[j], 0, p_.params[j].upper);
    }
    FitOptions options;
    options.max_iterations = 200;
    // A relative change of the cost of 1e-8 moves n log(RSS) by 1e-8 n: 0.002 at 200 000
    // residuals, far below the BIC margin of 10; parameters to 1e-8, far below their errors.
    options.function_tolerance = 1e-8;
    options.gradient_tolerance = 1e-12;
    options.parameter_tolerance = 1e-8;
    options.compute_covariance = covariance;
    const auto summary = solve(problem, options);
    ParameterLayout layout;
    layout.blocks = blocks;
    layout.sizes.assign(P, 1);
    for (const auto& q : p_.params) layout.names.push_back(q.name);
    std::vector<double> observed;
    for (std::size_t i : idx) observed.push_back(p_.y[i]);
    f.result = summarize(problem, layout, observed, summary, options);
    return f;
  }

  /// Held-out MSE: each fold predicted by a fit on the other folds.
  /// Held-out MSE of every residual (weighted) and of channel 0's alone (the reading, unweighted).
  struct Heldout {
    double all = 0, reading = 0;
  };
  Heldout heldout_mse(const std::vector<int>& free, const std::vector<double>& start) const {
    double sse = 0, sse0 = 0;
    std::size_t count = 0, count0 = 0;
    for (int f = 0; f < o_.folds; ++f) {
      std::vector<std::size_t> train, test;
      for (std::size_t i = 0; i < n_; ++i) (fold_[i] == f ? test : train).push_back(i);
      if (test.empty() || train.empty()) continue;
      const Fitted fit_f = fit(free, start, train, false);
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
    h.all = count ? sse / static_cast<double>(count) : 0.0;
    h.reading = count0 ? sse0 / static_cast<double>(count0) : 0.0;
    return h;
  }

  const std::vector<std::size_t>& all() const { return all_; }

  /// Noise standard deviation per channel from the residuals of readings away from the clamps.
  std::vector<double> noise_sd(const std::vector<double>& values) const {
    const auto pred = predict(values);
    const std::size_t C = sigma_.size();
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
          const double margin = 3.0 * sigma_[ch];
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
  /// All residuals y_i - E[clamp(model_i)] of the training rows in one block; one parameter block
  /// of size 1 per parameter; derivatives by Jets over the free parameters.
  class Cost : public ceres::CostFunction {
   public:
    Cost(const Engine& e, const std::vector<std::size_t>& idx, const std::vector<int>& slot) : e_(e), idx_(idx), slot_(slot) {
      for (std::size_t i : idx) limit_ = std::max(limit_, i + 1);
      set_num_residuals(static_cast<int>(idx.size()));
      for (std::size_t j = 0; j < slot.size(); ++j) mutable_parameter_block_sizes()->push_back(1);
    }
    bool Evaluate(double const* const* parameters, double* residuals, double** jacobians) const override {
      const std::size_t P = slot_.size();
      bool need = false;
      if (jacobians)
        for (std::size_t j = 0; j < P; ++j) need = need || (jacobians[j] != nullptr);
      if (!need) {
        std::vector<double> v(P);
        for (std::size_t j = 0; j < P; ++j) v[j] = parameters[j][0];
        std::vector<double> pred;
        e_.p_.needed = limit_;
        e_.predict(v.data(), pred);
        e_.p_.needed = std::numeric_limits<std::size_t>::max();
        for (std::size_t k = 0; k < idx_.size(); ++k) {
          residuals[k] = e_.weight(idx_[k]) * (e_.p_.y[idx_[k]] - pred[idx_[k]]);
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
      const std::size_t P = slot_.size();
      std::vector<J> v(P);
      for (std::size_t j = 0; j < P; ++j) v[j] = slot_[j] >= 0 ? J(parameters[j][0], slot_[j]) : J(parameters[j][0]);
      std::vector<J> pred;
      e_.p_.needed = limit_;
      e_.predict(v.data(), pred);
      e_.p_.needed = std::numeric_limits<std::size_t>::max();
      for (std::size_t k = 0; k < idx_.size(); ++k) {
        const J& m = pred[idx_[k]];
        const double w = e_.weight(idx_[k]);
        residuals[k] = w * (e_.p_.y[idx_[k]] - m.a);
        if (!std::isfinite(residuals[k])) return false;
        for (std::size_t j = 0; j < P; ++j)
          if (jacobians[j]) {
            const double d = slot_[j] >= 0 ? -w * m.v[slot_[j]] : 0.0;
            if (!std::isfinite(d)) return false;
            jacobians[j][k] = d;
          }
      }
      return true;
    }

   private:
    const Engine& e_;
    const std::vector<std::size_t>& idx_;  // outlives the problem that owns this cost (Engine::fit)
    const std::vector<int> slot_;
    std::size_t limit_ = 0;  ///< one past the last residual used
  };

  struct Slope {
    int param;
    std::vector<double> centred;
  };
  Problem& p_;
  const Options& o_;
  std::vector<Slope> slopes_;
  std::size_t n_ = 0;
  std::vector<double> sigma_, channel_weight_;
  std::vector<int> fold_;
  std::vector<std::size_t> all_;
};

/// Upper quantile of chi-square with `df` degrees of freedom at tail probability 1e-6
/// (Wilson-Hilferty: chi2_q ~ df (1 - 2/(9 df) + z sqrt(2/(9 df)))^3, z = 4.753 for 1e-6).
double chi2_critical(double df) {
  constexpr double kZ = 4.753;  // standard normal upper quantile at 1e-6
  const double a = 2.0 / (9.0 * df);
  const double c = 1.0 - a + kZ * std::sqrt(a);
  return df * c * c * c;
}

/// How much of the residuals' variance the covariate's binned means explain (value bins when it
/// takes at most 24 values, else 12 quantile bins), and whether that is significant.
CovariateScore score_covariate(const std::string& name, const std::vector<double>& x, const std::vector<double>& r,
                               double threshold) {
  CovariateScore s;
  s.covariate = name;
  const std::size_t n = r.size();
  if (n < 3 || x.size() != n) return s;
  std::vector<double> sorted = x;
  std::sort(sorted.begin(), sorted.end());
  const std::size_t distinct = static_cast<std::size_t>(std::unique(sorted.begin(), sorted.end()) - sorted.begin());
  sorted.resize(distinct);
  if (distinct < 2) return s;
  constexpr std::size_t kMaxValueBins = 24;
  constexpr std::size_t kQuantileBins = 12;
  std::vector<int> bin(n);
  std::size_t bins = 0;
  if (distinct <= kMaxValueBins) {
    for (std::size_t i = 0; i < n; ++i)
      bin[i] = static_cast<int>(std::lower_bound(sorted.begin(), sorted.end(), x[i]) - sorted.begin());
    bins = distinct;
  } else {
    std::vector<double> all = x;
    std::sort(all.begin(), all.end());
    std::vector<double> edges;
    for (std::size_t b = 1; b < kQuantileBins; ++b) edges.push_back(all[b * n / kQuantileBins]);
    for (std::size_t i = 0; i < n; ++i)
      bin[i] = static_cast<int>(std::upper_bound(edges.begin(), edges.end(), x[i]) - edges.begin());
    bins = kQuantileBins;
  }
  std::vector<double> sum(bins, 0.0);
  std::vector<std::size_t> count(bins, 0);
  double mean = 0;
  for (std::size_t i = 0; i < n; ++i) {
    sum[static_cast<std::size_t>(bin[i])] += r[i];
    ++count[static_cast<std::size_t>(bin[i])];
    mean += r[i];
  }
  mean /= static_cast<double>(n);
  double tss = 0, between = 0;
  std::size_t used = 0;
  for (std::size_t i = 0; i < n; ++i) tss += (r[i] - mean) * (r[i] - mean);
  for (std::size_t b = 0; b < bins; ++b)
    if (count[b]) {
      const double m = sum[b] / static_cast<double>(count[b]);
      between += static_cast<double>(count[b]) * (m - mean) * (m - mean);
      ++used;
    }
  if (!(tss > 0) || used < 2) return s;
  s.score = between / tss;
  s.size = std::sqrt(between / static_cast<double>(n));
  const double df1 = static_cast<double>(used - 1), df2 = static_cast<double>(n - used);
  const double chi2 = df2 * s.score / std::max(1e-300, 1.0 - s.score);  // df1 * F
  s.significant = s.score >= threshold && chi2 > chi2_critical(df1);
  return s;
}

/// Scores every covariate against the residuals; with several channels (drive: ToF and encoders),
/// within each channel separately, keeping the channel where the dependence is strongest.
std::vector<CovariateScore> structure(const Problem& p, const std::vector<double>& r, const std::vector<double>& predicted,
                                      double threshold, const std::vector<double>& sigma) {
  std::vector<CovariateScore> out;
  const std::size_t channels = p.channel_names.size();
  auto score = [&](const std::string& name, const std::vector<double>& x) {
    if (channels <= 1) return score_covariate(name, x, r, threshold);
    CovariateScore best;
    best.covariate = name;
    for (std::size_t c = 0; c < channels; ++c) {
      std::vector<double> xc, rc;
      for (std::size_t i = 0; i < r.size(); ++i)
        if (static_cast<std::size_t>(p.channel[i]) == c) {
          xc.push_back(x[i]);
          rc.push_back(r[i]);
        }
      CovariateScore s = score_covariate(name, xc, rc, threshold);
      s.channel = p.channel_names[c];
      if (c < p.channel_min_structure.size()) s.significant = s.significant && s.size >= p.channel_min_structure[c] * sigma[0] / sigma[c];
      if (s.score > best.score) best = s;
    }
    return best;
  };
  for (std::size_t k = 0; k < p.covariates.size(); ++k) {
    if (p.is_per_row(k)) out.push_back(score(p.covariates[k].first, p.covariate_values(k)));  // spread one at a time
    else out.push_back(score(p.covariates[k].first, p.covariates[k].second));
  }
  out.push_back(score("predicted", predicted));
  std::stable_sort(out.begin(), out.end(), [](const CovariateScore& a, const CovariateScore& b) { return a.score > b.score; });
  return out;
}

std::vector<NamedValue> named(const Problem& p, const Engine::Fitted& f, const std::vector<int>& which) {
  std::vector<NamedValue> out;
  for (int j : which) {
    const auto& e = f.result.parameters.size() > static_cast<std::size_t>(j) ? f.result.parameters[static_cast<std::size_t>(j)]
                                                                             : ParameterEstimate{};
    out.push_back({p.params[static_cast<std::size_t>(j)].name, f.values[static_cast<std::size_t>(j)], e.std_error,
                   std::isfinite(e.std_error) ? std::string() : e.std_error_why});
  }
  return out;
}

/// The noise estimate and the fit depend on each other through the clamp's expected value:
/// alternate until the estimate moves by less than 2 %.
void settle_noise(Engine& engine, const std::vector<int>& free, Engine::Fitted& current) {
  constexpr int kMaxRounds = 8;
  constexpr double kSettled = 0.02;
  for (int k = 0; k < kMaxRounds; ++k) {
    const std::vector<double> sd = engine.noise_sd(current.values);
    bool settled = true;
    for (std::size_t c = 0; c < sd.size(); ++c) settled = settled && std::abs(sd[c] - engine.sigma()[c]) <= kSettled * engine.sigma()[c];
    engine.set_sigma(sd);
    current = engine.fit(free, current.values, engine.all(), true);
    if (settled) break;
  }
}

}  // namespace

namespace {
// diagnose(); `owned`, when given, holds `logs` and is emptied once the problem is built (the
// problem keeps what it needs: a long log's parsed cells need not stay beside the fits).
Report run_diagnosis(const std::vector<logs::Log>& all_logs, const Options& options, std::vector<logs::Log>* owned) {
  Report report;
  if (all_logs.empty()) {
    report.message = "no logs";
    return report;
  }
  report.kind = all_logs.front().kind;
  for (const auto& l : all_logs) report.rows += l.rows();
  // Wild readings (far from the others under the same conditions) would be "explained" by
  // whatever effect bends the curve towards them: they leave before anything is fitted.
  // (In place when the caller handed the logs over: a long log is not copied.)
  std::vector<WildReading> wild;
  std::vector<logs::Log> screened;
  if (options.progress) options.progress(Progress{"screening", 0, 0, 0, ""});
  if (owned != nullptr) drop_wild_readings_in_place(*owned, &wild);
  else screened = drop_wild_readings(all_logs, &wild);
  const std::vector<logs::Log>& logs = owned != nullptr ? *owned : screened;
  for (const WildReading& w : wild) report.outliers.push_back(w.where + ": " + w.why);
  if (!wild.empty())
    report.warnings.push_back(std::to_string(wild.size()) + " wild readings left out before the diagnosis (listed under outliers).");
  report.censored = readings_on_rails(logs);
  std::string why;
  std::unique_ptr<Problem> problem = detail::make_problem(logs, options, why);
  if (owned) std::vector<logs::Log>().swap(*owned);  // `logs` is not used below
  if (!problem) {
    report.message = why;
    return report;
  }
  Engine engine(*problem, options);
  Problem& p = *problem;
  report.residuals = engine.size();
  report.supported = true;
  for (const auto& e : p.effects) report.effects_considered.push_back(e.cause);
  auto progress = [&](const char* stage, int step, int done, int total, const std::string& detail) {
    if (options.progress) options.progress(Progress{stage, step, done, total, detail});
  };

  {
    // Enough rows to judge an effect? The held-out test cuts the rows into folds; each must hold
    // rows_per_parameter rows per parameter of the largest model the search tries first (the base
    // model's free parameters and the largest effect's), and a row in every block of every fold.
    // The whole problem must also hold more residuals than twice all its parameters. Below that,
    // any "finding" would be fitted noise: the report says so, with the plug-in's error only.
    std::size_t largest_effect = 0;
    std::string largest_cause;
    for (const auto& e : p.effects)
      if (e.params.size() > largest_effect) {
        largest_effect = e.params.size();
        largest_cause = e.cause;
      }
    const std::size_t first_model = p.base_free.size() + largest_effect;
    const std::size_t folds = static_cast<std::size_t>(std::max(1, options.folds));
    const std::size_t blocks = static_cast<std::size_t>(std::max(1, options.folds * options.blocks_per_fold));
    const std::size_t per_fold = static_cast<std::size_t>(std::max(1, options.rows_per_parameter)) * std::max<std::size_t>(1, first_model);
    const std::size_t min_residuals = 2 * p.params.size() + 1;
    report.minimum_rows = std::max(blocks, folds * per_fold);
    if (report.rows < report.minimum_rows || engine.size() < min_residuals) {
      report.too_few_rows = true;
      report.verdict = "none";
      // The plug-in's error on every row, the one figure that needs no fit (the engine's
      // default noise of 1 in the clamp's expectation: no estimate from so few rows).
      const auto r = engine.residuals(p.plugin_values);
      double sse = 0;
      std::size_t count = 0;
      for (std::size_t i = 0; i < r.size(); ++i)
        if (p.channel.empty() || p.channel[i] == 0) {
          sse += r[i] * r[i];
          ++count;
        }
      report.heldout_mse_plugin = count ? sse / static_cast<double>(count) : 0.0;
      std::string why = "too few rows (" + std::to_string(report.rows) + ") to judge effects; need at least " +
                        std::to_string(report.minimum_rows) + ": the held-out test's " + std::to_string(folds) +
                        " folds must each hold " + std::to_string(options.rows_per_parameter) +
                        " rows per parameter of the largest model tried first (" + std::to_string(first_model) +
                        ": the base model's " + std::to_string(p.base_free.size()) + " free" +
                        (largest_cause.empty() ? std::string() : " and " + largest_cause + "'s " + std::to_string(largest_effect)) +
                        "), and a row in each of its " + std::to_string(blocks) + " blocks";
      if (engine.size() < min_residuals)
        why += "; the model also needs at least " + std::to_string(min_residuals) + " residuals (it has " +
               std::to_string(engine.size()) + ")";
      report.message = why;
      report.warnings.push_back(why + ". No effect was judged: verdict none.");
      return report;
    }
  }
  // Step 1: the plug-in as published; its residuals give the first noise estimate.
  engine.set_sigma(engine.noise_sd(p.plugin_values));
  {
    // The reading's (channel 0's) MSE; the model has nothing fitted, so all rows are held out.
    const auto r = engine.residuals(p.plugin_values);
    double sse = 0;
    std::size_t count = 0;
    for (std::size_t i = 0; i < r.size(); ++i)
      if (p.channel.empty() || p.channel[i] == 0) {
        sse += r[i] * r[i];
        ++count;
      }
    report.heldout_mse_plugin = count ? sse / static_cast<double>(count) : 0.0;
  }

  report.message = problem->notes;

  // The values where the effects are off and the base model is the plug-in's.
  std::vector<double> neutral(p.params.size());
  for (std::size_t j = 0; j < p.params.size(); ++j) neutral[j] = p.params[j].neutral;

  // Step 2: recalibrate the base model.
  progress("recalibrating", 0, 0, 0, "");
  std::vector<int> free = p.base_free;
  Engine::Fitted current = engine.fit(free, neutral, engine.all(), true);
  settle_noise(engine, free, current);
  report.recalibrated = named(p, current, p.base_free);
  Engine::Heldout current_h = engine.heldout_mse(free, current.values);
  double current_cv = current_h.all;
  report.heldout_mse_base = current_h.reading;
  report.heldout_weighted_base = current_h.all;
  const std::vector<double> base_values = current.values;

  // Steps 3 and 4: greedy forward search.
  std::vector<std::size_t> screen_idx(std::min(engine.size(), kScreenResiduals));
  std::iota(screen_idx.begin(), screen_idx.end(), 0);
  std::set<std::size_t> kept;
  std::vector<std::size_t> order;
  for (int step = 1; step <= options.max_findings; ++step) {
    int best = -1;
    double best_cv = current_cv, best_bic = 0;
    Engine::Fitted best_fit;
    struct Passing {
      std::size_t trial, effect;
      std::vector<int> cand;
      Engine::Fitted fit;
    };
    std::vector<Passing> passing;  // effects whose BIC falls by min_delta_bic or more
    double screen_rss = 0;  // the current model's on the leading residuals
    if (engine.size() > kScreenResiduals) {
      const auto r = engine.residuals(current.values);
      for (std::size_t i : screen_idx) screen_rss += r[i] * r[i];
    }
    const int to_try = static_cast<int>(p.effects.size() - kept.size());
    int tried = 0;
    for (std::size_t e = 0; e < p.effects.size(); ++e) {
      if (kept.count(e)) continue;
      progress("fitting effect", step, ++tried, to_try, p.effects[e].cause);
      std::vector<int> cand = free;
      std::vector<double> start = current.values;
      std::size_t starts = 1;
      for (int j : p.effects[e].params) {
        cand.push_back(j);
        start[static_cast<std::size_t>(j)] = p.params[static_cast<std::size_t>(j)].start;
        starts = std::max(starts, 1 + p.params[static_cast<std::size_t>(j)].other_starts.size());
      }
      if (static_cast<int>(cand.size()) > kMaxFree) continue;
      Trial t;
      t.step = step;
      t.cause = p.effects[e].cause;
      // Long logs: the starting points are tried on the leading residuals (a model that
      // simulates row after row stops there), and the best is refined on all of them.
      const std::vector<std::size_t>& screen = engine.size() > kScreenResiduals ? screen_idx : engine.all();
      Engine::Fitted f = engine.fit(cand, start, screen, false);
      for (std::size_t k = 1; k < starts; ++k) {
        std::vector<double> other = start;
        for (int j : p.effects[e].params) {
          const auto& more = p.params[static_cast<std::size_t>(j)].other_starts;
          if (k <= more.size()) other[static_cast<std::size_t>(j)] = more[k - 1];
        }
        Engine::Fitted g = engine.fit(cand, other, screen, false);
        if (g.result.usable && (!f.result.usable || g.result.rss < f.result.rss)) f = g;
      }
      if (&screen != &engine.all()) {
        // No gain at all on the leading residuals (as a speed limit above every command there):
        // the effect has no support in them and is not refined on all residuals.
        if (!f.result.usable || !(f.result.rss < screen_rss * (1.0 - 1e-9))) {
          t.delta_bic = std::log(static_cast<double>(engine.size())) * static_cast<double>(p.effects[e].params.size());
          t.screened_out = true;
          report.trials.push_back(t);
          continue;
        }
        f = engine.fit(cand, f.values, engine.all(), false);
      }
      if (!f.result.usable) {
        report.trials.push_back(t);
        continue;
      }
      t.delta_bic = f.result.bic - current.result.bic;
      report.trials.push_back(t);
      if (t.delta_bic <= -options.min_delta_bic) passing.push_back({report.trials.size() - 1, e, cand, f});
    }
    // Among the effects that pass both tests, the lowest BIC: of two effects that fit alike, the
    // one with fewer parameters (white_level rather than three equal sensor gains). The held-out
    // test runs in BIC order until one passes, then for the others within min_delta_bic of it
    // (its alternatives); the rest need not run.
    std::sort(passing.begin(), passing.end(),
              [&](const Passing& a, const Passing& b) { return report.trials[a.trial].delta_bic < report.trials[b.trial].delta_bic; });
    int tested = 0;
    for (const Passing& c : passing) {
      Trial& t = report.trials[c.trial];
      if (best >= 0 && t.delta_bic - best_bic >= options.min_delta_bic) break;
      progress("held-out test", step, ++tested, static_cast<int>(passing.size()), t.cause);
      t.heldout_mse = engine.heldout_mse(c.cand, c.fit.values).all;
      const bool gain = t.heldout_mse <= current_cv * (1.0 - options.min_heldout_gain);
      if (gain && best < 0) {
        best = static_cast<int>(c.effect);
        best_cv = t.heldout_mse;
        best_bic = t.delta_bic;
        best_fit = c.fit;
      }
    }
    if (best < 0) break;
    const std::vector<int> free_before = free;
    const Engine::Fitted fit_before = current;
    const std::vector<double> sigma_before = engine.sigma();
    Finding finding;
    finding.cause = p.effects[static_cast<std::size_t>(best)].cause;
    finding.heldout_mse_before = current_cv;
    finding.heldout_mse_after = best_cv;
    finding.delta_bic = best_bic;
    report.findings.push_back(finding);
    kept.insert(static_cast<std::size_t>(best));
    order.push_back(static_cast<std::size_t>(best));
    for (int j : p.effects[static_cast<std::size_t>(best)].params) free.push_back(j);
    // Re-estimate the noise with the better model and refit (the clamp's expected value uses
    // it), until the estimate settles; then the held-out error again with that noise.
    current = best_fit;
    settle_noise(engine, free, current);
    const Engine::Heldout h = engine.heldout_mse(free, current.values);
    const double cv = h.all;
    report.findings.back().heldout_mse_before = current_h.reading;
    report.findings.back().heldout_weighted_before = current_h.all;
    if (p.channel_names.size() > 1) {
      // Several channels: the residuals' weights follow the noise estimates, which the finding
      // has just changed. The model without it must lose on held-out rows under the same weights
      // too, or the finding is undone (an effect that only moved weight between channels).
      const Engine::Fitted without = engine.fit(free_before, fit_before.values, engine.all(), false);
      const Engine::Heldout h_without = engine.heldout_mse(free_before, without.values);
      const double cv_without = h_without.all;
      if (!(cv <= cv_without * (1.0 - options.min_heldout_gain))) {
        report.findings.pop_back();
        kept.erase(static_cast<std::size_t>(best));
        order.pop_back();
        free = free_before;
        current = fit_before;
        engine.set_sigma(sigma_before);
        report.notes.push_back(finding.cause + " passed the search but not the held-out test once the noise was re-estimated");
        break;
      }
      report.findings.back().heldout_mse_before = h_without.reading;
      report.findings.back().heldout_weighted_before = h_without.all;
    }
    for (auto& t : report.trials) {
      if (t.step != step) continue;
      if (t.cause == finding.cause) t.kept = true;
      else if (t.heldout_mse > 0 && t.delta_bic <= -options.min_delta_bic && t.delta_bic - best_bic < options.min_delta_bic &&
               t.heldout_mse <= best_cv * (1.0 + options.min_heldout_gain))
        report.findings.back().alternatives.push_back(t.cause);
    }
    current_cv = cv;
    current_h = h;
    report.findings.back().heldout_mse_after = h.reading;
    report.findings.back().heldout_weighted_after = h.all;
  }
  current = engine.fit(free, current.values, engine.all(), true);
  report.heldout_mse_final = current_h.reading;
  report.heldout_weighted_final = current_h.all;
  // The noise of a reading: residuals of readings away from the sensor's rails (a reading on a
  // rail has its noise clipped; the MSE over all rows counts the clipped zeros of every reading
  // beyond the proximity sensor's range).
  const std::vector<double> sd = engine.noise_sd(current.values);
  report.noise_sd = sd.front();
  if (p.channel_names.size() > 1) {
    for (std::size_t c = 0; c < sd.size(); ++c) report.channel_noise_sd.push_back({p.channel_names[c], sd[c], 0.0});
  }
  for (std::size_t k = 0; k < order.size(); ++k) report.findings[k].parameters = named(p, current, p.effects[order[k]].params);
  // The recalibration alone stays in `recalibrated` (step 2's fit); the base parameters of the
  // joint fit with every finding are the extended model's.
  if (!p.base_free.empty()) report.final_base = named(p, current, p.base_free);

  // A finding whose parameter the logs do not pin down (standard error above its size, or none)
  // names a direction of misfit, not a measured effect: say so.
  for (const Finding& f : report.findings)
    for (const NamedValue& v : f.parameters)
      if (!(std::abs(v.std_error) <= std::abs(v.value)))
        report.warnings.push_back("finding " + f.cause + ": " + v.name + " = " + std::to_string(v.value) +
                                  " is not determined by these logs (standard error " +
                                  (std::isfinite(v.std_error) ? std::to_string(v.std_error) : std::string("undefined")) +
                                  "); read it as a direction, not a size.");

  // Step 5: residual structure before (recalibrated base) and after (final model).
  progress("residual structure", 0, 0, 0, "");
  report.residual_before = engine.residuals(base_values);
  report.residual_after = engine.residuals(current.values);
  report.structure_before = structure(p, report.residual_before, engine.predict(base_values), options.structure_threshold, engine.sigma());
  report.structure_after = structure(p, report.residual_after, engine.predict(current.values), options.structure_threshold, engine.sigma());
  bool left = false;
  for (const auto& s : report.structure_after) left = left || s.significant;
  if (left) report.verdict = "unexplained";
  else if (!report.findings.empty()) report.verdict = report.findings.front().cause;
  else report.verdict = "none";
  // For the figure: the covariate it is drawn against (Report::covariates), one, not every one
  // again; the residuals in their channels' own units (the weights were for the fits and scores).
  std::string wanted = "row";
  if (report.verdict == "unexplained") wanted = report.structure_after.front().covariate;
  else if (!report.structure_before.empty() && report.structure_before.front().significant) wanted = report.structure_before.front().covariate;
  if (wanted == "predicted") report.covariates.emplace_back(wanted, engine.predict(base_values));
  for (std::size_t k = 0; k < p.covariates.size(); ++k)
    if (p.covariates[k].first == wanted)
      report.covariates.emplace_back(wanted, p.is_per_row(k) ? p.covariate_values(k) : std::move(p.covariates[k].second));
  if (p.channel_names.size() > 1) {
    report.residual_channel.assign(p.channel.begin(), p.channel.end());
    for (std::size_t i = 0; i < engine.size(); ++i) {
      report.residual_before[i] /= engine.weight(i);
      report.residual_after[i] /= engine.weight(i);
    }
  }
  return report;
}
}  // namespace

Report diagnose(const std::vector<logs::Log>& logs, const Options& options) { return run_diagnosis(logs, options, nullptr); }

Report diagnose(std::vector<logs::Log>&& logs, const Options& options) { return run_diagnosis(logs, options, &logs); }

}  // namespace epuck2::diagnose
