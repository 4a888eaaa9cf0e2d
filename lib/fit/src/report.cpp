// Values with standard errors as text, correlations, goodness-of-fit statistics and the
// autocorrelation correction of epuck2/fit/report.hpp.
#include "epuck2/fit/report.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>

namespace epuck2::fit {

namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

// Fixed notation for values and errors below 1e7 whose error's last digit is at 1e-6 or above
// (an error from 1e-5), or at 1e-8 or above for a value of at least 1e-3 (1.00904590 ± 0.00000035
// reads better than 1.00904590e+00 ± 3.5e-07); scientific otherwise.
constexpr int kLowestFixedDigit = -6;
constexpr int kLowestFixedDigitBesideValue = -8;
constexpr double kSmallestValueForLongFixed = 1e-3;
constexpr double kLargestFixed = 1e7;

// An error rounded to two significant digits: mantissa m in [10, 99] and the exponent `last` of
// its last digit, error = m 10^last.
struct TwoDigits {
  long m = 0;
  int last = 0;
};

TwoDigits two_digits(double se) {
  int e = static_cast<int>(std::floor(std::log10(se)));
  long m = std::lround(se / std::pow(10.0, e - 1));
  if (m >= 100) {  // 0.0996 -> 0.10: one more digit up
    m = std::lround(static_cast<double>(m) / 10.0);
    ++e;
  }
  if (m < 10) {  // log10 just under an integer (rounding): 9.99999 -> 10
    m *= 10;
    --e;
  }
  return {m, e - 1};
}

bool fixed_notation(double value, const TwoDigits& t) {
  const double se = static_cast<double>(t.m) * std::pow(10.0, t.last);
  if (!(std::abs(value) < kLargestFixed) || !(se < kLargestFixed)) return false;
  return t.last >= kLowestFixedDigit ||
         (t.last >= kLowestFixedDigitBesideValue && std::abs(value) >= kSmallestValueForLongFixed);
}

std::string printf_string(const char* format, int precision, double x) {
  char buf[64];
  std::snprintf(buf, sizeof buf, format, precision, x);
  return buf;
}

// The error of `t` as text, fixed or scientific.
std::string error_text(const TwoDigits& t, bool fixed) {
  const double se = static_cast<double>(t.m) * std::pow(10.0, t.last);
  if (fixed) return printf_string("%.*f", t.last < 0 ? -t.last : 0, se);
  return printf_string("%.*e", 1, se);
}

// -0.0000 reads as a sign error: a value that rounds to zero prints without its sign.
std::string drop_negative_zero(std::string s) {
  if (!s.empty() && s[0] == '-' && s.find_first_not_of("-0.e+", 0) == std::string::npos) return s.substr(1);
  return s;
}

}  // namespace

std::string format_error(double std_error) {
  if (!(std_error > 0) || !std::isfinite(std_error)) return "";
  const TwoDigits t = two_digits(std_error);
  return error_text(t, fixed_notation(0.0, t));
}

std::string format_uncertain(double value, double std_error, const std::string& unit, const std::string& why) {
  const std::string u = unit.empty() ? "" : " " + unit;
  if (!std::isfinite(value)) return "undefined" + u + (why.empty() ? "" : " (" + why + ")");
  if (!(std_error > 0) || !std::isfinite(std_error)) {
    const std::string reason = !why.empty()          ? why
                               : std_error == 0      ? "no standard error"
                                                     : "standard error undefined";
    return drop_negative_zero(printf_string("%.*g", 6, value)) + u + " (" + reason + ")";
  }
  const TwoDigits t = two_digits(std_error);
  const bool fixed = fixed_notation(value, t);
  std::string v;
  if (fixed) {
    const double step = std::pow(10.0, t.last);
    const double rounded = std::round(value / step) * step;
    v = printf_string("%.*f", t.last < 0 ? -t.last : 0, rounded);
  } else {
    // Scientific: the value's mantissa carries digits down to the error's last digit.
    const double top = std::max(std::abs(value), static_cast<double>(t.m) * std::pow(10.0, t.last));
    const int exponent = static_cast<int>(std::floor(std::log10(top)));
    v = printf_string("%.*e", std::max(0, exponent - t.last), value);
  }
  return drop_negative_zero(v) + " ± " + error_text(t, fixed) + u;
}

std::string pretty_unit(const std::string& unit) {
  std::string out;
  for (std::size_t i = 0; i < unit.size(); ++i) {
    if (unit[i] == '^' && i + 1 < unit.size() && (unit[i + 1] == '2' || unit[i + 1] == '3')) {
      out += unit[i + 1] == '2' ? "²" : "³";
      ++i;
    } else {
      out += unit[i];
    }
  }
  return out;
}

Eigen::MatrixXd correlation_matrix(const Eigen::MatrixXd& c) {
  const Eigen::Index m = c.rows();
  Eigen::MatrixXd r = Eigen::MatrixXd::Constant(m, c.cols(), kNaN);
  if (c.rows() != c.cols()) return r;
  for (Eigen::Index i = 0; i < m; ++i)
    for (Eigen::Index j = 0; j < m; ++j) {
      const double vi = c(i, i), vj = c(j, j);
      if (!(vi > 0) || !(vj > 0) || !std::isfinite(vi) || !std::isfinite(vj)) continue;
      // Rounding can push |r| a hair above 1 for a nearly degenerate pair.
      r(i, j) = i == j ? 1.0 : std::clamp(c(i, j) / std::sqrt(vi * vj), -1.0, 1.0);
    }
  return r;
}

Eigen::MatrixXd FitResult::correlation() const { return correlation_matrix(covariance); }

std::vector<Correlation> correlations(const FitResult& fit, double min_abs) {
  std::vector<Correlation> out;
  const Eigen::Index m = static_cast<Eigen::Index>(fit.parameters.size());
  if (fit.covariance.rows() != m || fit.covariance.cols() != m) return out;
  const Eigen::MatrixXd r = fit.correlation();
  for (Eigen::Index i = 0; i < m; ++i)
    for (Eigen::Index j = i + 1; j < m; ++j)
      if (std::isfinite(r(i, j)) && std::abs(r(i, j)) > min_abs)
        out.push_back({fit.parameters[static_cast<std::size_t>(i)].name, fit.parameters[static_cast<std::size_t>(j)].name, r(i, j)});
  return out;
}

FitStatistics fit_statistics(std::size_t n, int k, double rss, double r2) {
  FitStatistics s;
  s.n = n;
  s.k = k;
  s.rss = rss;
  s.r2 = r2;
  const double nn = static_cast<double>(n);
  s.mse = n > 0 ? rss / nn : kNaN;
  s.reduced_chi2 = nn > k ? rss / (nn - k) : kNaN;
  // RSS 0 (every residual exactly 0): n ln(0) has no value; akaike() would floor it at the
  // smallest double and print a meaningless -1e5. RSS 0 to the arithmetic's rounding alike: R² 1
  // to double precision (RSS below 1e-15 of the total sum of squares: readings lying exactly on
  // the model leave an RSS of about 1e-19, whose ln gave an AIC of -2087 for 45 readings, a
  // number that says only how the solver rounded).
  const bool zero = !(rss > 0) || (std::isfinite(r2) && 1.0 - r2 < 1e-15);
  s.aic = n > 0 && !zero ? akaike(n, rss, k) : kNaN;
  s.bic = n > 0 && !zero ? bayes(n, rss, k) : kNaN;
  return s;
}

std::string format_information_criteria(const FitStatistics& s, int decimals) {
  if (!std::isfinite(s.aic) || !std::isfinite(s.bic))
    return std::string("AIC and BIC undefined (") + (s.n == 0 ? "no residual" : kInformationCriteriaUndefined) + ")";
  char buf[96];
  std::snprintf(buf, sizeof buf, "AIC %.*f, BIC %.*f", decimals, s.aic, decimals, s.bic);
  return buf;
}

FitStatistics fit_statistics(const FitResult& r) { return fit_statistics(r.observations, r.free_parameters, r.rss, r.r2); }

AutocorrelationCorrection autocorrelation_correction(const std::vector<double>& e, const std::vector<int>& series) {
  AutocorrelationCorrection a;
  if (e.size() != series.size()) {
    a.why_not = "internal: residuals and series differ in length";
    return a;
  }
  double sum = 0;
  std::size_t n = 0;
  for (double x : e)
    if (std::isfinite(x)) {
      sum += x;
      ++n;
    }
  a.n = n;
  const double mean = n ? sum / static_cast<double>(n) : 0.0;
  double ss = 0, lag = 0;
  std::size_t pairs = 0, runs = 0;
  for (std::size_t i = 0; i < e.size(); ++i) {
    if (i == 0 || series[i] != series[i - 1]) ++runs;
    if (!std::isfinite(e[i])) continue;
    ss += (e[i] - mean) * (e[i] - mean);
    if (i + 1 < e.size() && series[i + 1] == series[i] && std::isfinite(e[i + 1])) {
      lag += (e[i] - mean) * (e[i + 1] - mean);
      ++pairs;
    }
  }
  a.pairs = pairs;
  a.series = runs;
  if (pairs < 3 || !(ss > 0)) {
    a.why_not = pairs < 3 ? "fewer than 3 neighbouring residuals in one run" : "the residuals do not vary";
    a.n_eff = static_cast<double>(n);
    return a;
  }
  a.computed = true;
  a.rho = std::clamp(lag / ss, -1.0, 1.0);
  const double nn = static_cast<double>(n);
  if (a.rho <= 0) {
    a.n_eff = nn;
    a.factor = 1.0;
    return a;
  }
  a.n_eff = std::clamp(nn * (1.0 - a.rho) / (1.0 + a.rho), 1.0, nn);
  a.factor = std::sqrt(nn / a.n_eff);
  return a;
}

double AutocorrelationCorrection::std_error(const std::string& name) const {
  for (std::size_t i = 0; i < names.size() && i < std_errors.size(); ++i)
    if (names[i] == name) return std_errors[i];
  return kNaN;
}

void apply_ar1(AutocorrelationCorrection& a, const FitResult& fit) {
  a.names.clear();
  a.std_errors.clear();
  a.cluster_robust = false;
  const double factor = a.computed ? std::max(1.0, a.factor) : 1.0;
  for (const auto& p : fit.parameters) {
    a.names.push_back(p.name);
    a.std_errors.push_back(std::isfinite(p.std_error) && p.std_error > 0 ? p.std_error * factor : kNaN);
  }
  a.method = kAutocorrelationMethod;
}

void apply_cluster_robust(AutocorrelationCorrection& a, const FitResult& fit, const Eigen::MatrixXd& jacobian,
                          const std::vector<double>& residuals, const std::vector<int>& run) {
  apply_ar1(a, fit);
  const std::size_t m = fit.parameters.size();
  if (static_cast<std::size_t>(jacobian.cols()) != m || static_cast<std::size_t>(jacobian.rows()) != residuals.size() ||
      run.size() != residuals.size()) {
    a.cluster_why_not = "internal: the Jacobian, residuals and runs disagree in size";
    return;
  }
  std::vector<Eigen::Index> cols;
  for (std::size_t j = 0; j < m; ++j)
    if (std::isfinite(fit.parameters[j].std_error) && fit.parameters[j].std_error > 0) cols.push_back(static_cast<Eigen::Index>(j));
  std::vector<Eigen::Index> rows;
  std::vector<int> runs_seen;
  for (std::size_t i = 0; i < residuals.size(); ++i)
    if (std::isfinite(residuals[i]) && run[i] >= 0) {
      rows.push_back(static_cast<Eigen::Index>(i));
      if (std::find(runs_seen.begin(), runs_seen.end(), run[i]) == runs_seen.end()) runs_seen.push_back(run[i]);
    }
  const std::size_t G = runs_seen.size();
  if (G < kMinClusters) {
    a.cluster_why_not = std::to_string(G) + " runs: too few to estimate the spread between runs (cluster-robust needs " +
                        std::to_string(kMinClusters) + ")";
    return;
  }
  if (cols.empty()) {
    a.cluster_why_not = "no parameter has a standard error";
    return;
  }
  const auto k = static_cast<Eigen::Index>(cols.size());
  Eigen::MatrixXd J(static_cast<Eigen::Index>(rows.size()), k);
  for (std::size_t r = 0; r < rows.size(); ++r)
    for (Eigen::Index c = 0; c < k; ++c) J(static_cast<Eigen::Index>(r), c) = jacobian(rows[r], cols[static_cast<std::size_t>(c)]);
  Eigen::MatrixXd bread;
  if (!inverse_normal_matrix(J, &bread)) {
    a.cluster_why_not = "J^T J is singular";
    return;
  }
  // Per run: s = sum of J_i r_i over its rows.
  std::vector<Eigen::VectorXd> score(G, Eigen::VectorXd::Zero(k));
  for (std::size_t r = 0; r < rows.size(); ++r) {
    const std::size_t g = static_cast<std::size_t>(
        std::find(runs_seen.begin(), runs_seen.end(), run[static_cast<std::size_t>(rows[r])]) - runs_seen.begin());
    score[g] += J.row(static_cast<Eigen::Index>(r)).transpose() * residuals[static_cast<std::size_t>(rows[r])];
  }
  Eigen::MatrixXd meat = Eigen::MatrixXd::Zero(k, k);
  for (const auto& s : score) meat += s * s.transpose();
  const double g = static_cast<double>(G);
  const Eigen::MatrixXd V = bread * meat * bread * (g / (g - 1.0));
  for (Eigen::Index c = 0; c < k; ++c) {
    const std::size_t j = static_cast<std::size_t>(cols[static_cast<std::size_t>(c)]);
    const double se = std::sqrt(std::max(0.0, V(c, c)));
    if (std::isfinite(se)) a.std_errors[j] = std::max(se, fit.parameters[j].std_error);
  }
  a.cluster_robust = true;
  a.cluster_why_not.clear();
  a.series = G;
  a.method = kClusterRobustMethod;
}

}  // namespace epuck2::fit
