// The residual-structure scoring of the diagnosis (docs/diagnose.md, step 5): how much of the
// residuals each covariate's binned means explain.
#include "engine_detail.hpp"

namespace epuck2::diagnose::engine_detail {

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

}  // namespace epuck2::diagnose::engine_detail
