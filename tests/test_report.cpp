// The report helpers of lib/fit (epuck2/fit/report.hpp): values with standard errors as text on
// hand-picked cases, correlations against hand-computed ones, the statistics' formulas, and the
// autocorrelation correction against AR(1) series whose true standard errors are known in closed
// form (computed here, not by the code under test).
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <random>
#include <vector>

#include "epuck2/fit/fit_curve.hpp"
#include "epuck2/fit/least_squares.hpp"
#include "epuck2/fit/report.hpp"

// This file's `using namespace` stays in its own named namespace, so it opens nothing to the
// files compiled after it in the same unity unit (tests/CMakeLists.txt).
namespace test_report_cpp {
namespace {

using namespace epuck2::fit;
const double kNaN = std::numeric_limits<double>::quiet_NaN();

struct Constant {
  static constexpr int kParameters = 1;
  static constexpr bool kLinearInParameters = true;
  template <typename T>
  T operator()(const T* p, double) const { return p[0]; }
};
struct ReportLine {
  static constexpr int kParameters = 2;
  static constexpr bool kLinearInParameters = true;
  template <typename T>
  T operator()(const T* p, double x) const { return p[0] + p[1] * x; }
};

// ----- Formatting ---------------------------------------------------------------------------------

TEST(FormatError, TwoSignificantDigits) {
  EXPECT_EQ(format_error(0.0034567), "0.0035");
  EXPECT_EQ(format_error(789), "790");
  EXPECT_EQ(format_error(3.4), "3.4");
  EXPECT_EQ(format_error(0.0996), "0.10");  // rounds up into the next decade: still two digits
  EXPECT_EQ(format_error(99.6), "100");
  EXPECT_EQ(format_error(1.0), "1.0");
  EXPECT_EQ(format_error(3.9e-07), "3.9e-07");  // below 1e-5: scientific
  EXPECT_EQ(format_error(2.2e-05), "0.000022");
  EXPECT_EQ(format_error(0.0), "");
  EXPECT_EQ(format_error(kNaN), "");
  EXPECT_EQ(format_error(-1.0), "");
}

TEST(FormatUncertain, ValueRoundedToTheErrorsLastDigit) {
  EXPECT_EQ(format_uncertain(197.2, 3.4, "/m²"), "197.2 ± 3.4 /m²");
  EXPECT_EQ(format_uncertain(197.14677, 3.43), "197.1 ± 3.4");
  EXPECT_EQ(format_uncertain(1.0110413, 0.0052), "1.0110 ± 0.0052");
  EXPECT_EQ(format_uncertain(123456, 789), "123460 ± 790");
  EXPECT_EQ(format_uncertain(914.7049, 0.77, "counts"), "914.70 ± 0.77 counts");
  EXPECT_EQ(format_uncertain(-30.397021, 0.068, "1/m"), "-30.397 ± 0.068 1/m");
  EXPECT_EQ(format_uncertain(9.96, 0.0996), "9.96 ± 0.10");
  EXPECT_EQ(format_uncertain(0.073690755, 2.2e-05, "m"), "0.073691 ± 0.000022 m");
  // A value of order 1 with a tiny error stays in fixed notation down to 1e-8.
  EXPECT_EQ(format_uncertain(1.0090459, 3.4653e-07), "1.00904590 ± 0.00000035");
}

TEST(FormatUncertain, ScientificForTinyOrHugeNumbers) {
  EXPECT_EQ(format_uncertain(-2.5757e-13, 5.0e-15), "-2.576e-13 ± 5.0e-15");
  EXPECT_EQ(format_uncertain(-5.0648939e-05, 3.89e-07, "1/s"), "-5.065e-05 ± 3.9e-07 1/s");
  EXPECT_EQ(format_uncertain(1.23456e9, 1.2e6), "1.2346e+09 ± 1.2e+06");
}

TEST(FormatUncertain, NoErrorIsExplainedNeverPlusMinusZero) {
  EXPECT_EQ(format_uncertain(9000.0, 0.0, "s", "end of the log"), "9000 s (end of the log)");
  EXPECT_EQ(format_uncertain(0.05, 0.0, "m"), "0.05 m (no standard error)");
  EXPECT_EQ(format_uncertain(0.05, kNaN, "m"), "0.05 m (standard error undefined)");
  EXPECT_EQ(format_uncertain(19743.75, kNaN, "s", "one run"), "19743.8 s (one run)");
  EXPECT_EQ(format_uncertain(kNaN, 1.0), "undefined");
  for (double se : {0.0, kNaN, std::numeric_limits<double>::infinity(), -2.0})
    EXPECT_EQ(format_uncertain(3.0, se).find("±"), std::string::npos) << se;
}

TEST(FormatUncertain, ValueThatRoundsToZeroHasNoSign) {
  EXPECT_EQ(format_uncertain(-0.00001, 0.0034), "0.0000 ± 0.0034");
}

TEST(PrettyUnit, Superscripts) {
  EXPECT_EQ(pretty_unit("counts^2"), "counts²");
  EXPECT_EQ(pretty_unit("charge/s^3"), "charge/s³");
  EXPECT_EQ(pretty_unit("mm"), "mm");
}

// ----- Correlations -------------------------------------------------------------------------------

TEST(Correlations, FromACovarianceByHand) {
  FitResult r;
  r.parameters = {{"a", 1, 2}, {"b", 1, 3}, {"c", 1, 0}, {"d", 1, 5}};
  r.covariance.resize(4, 4);
  // var a 4, var b 9, cov ab -5.4 (r = -0.9); c held (no variance); d independent but for a
  // weak link to a of r = 0.05 (cov 0.5), below lmfit's 0.1.
  r.covariance << 4, -5.4, 0, 0.5,  //
      -5.4, 9, 0, 0,                //
      0, 0, 0, 0,                   //
      0.5, 0, 0, 25;
  const auto m = r.correlation();
  EXPECT_NEAR(m(0, 1), -0.9, 1e-15);
  EXPECT_NEAR(m(1, 0), -0.9, 1e-15);
  EXPECT_NEAR(m(0, 3), 0.05, 1e-15);
  EXPECT_DOUBLE_EQ(m(0, 0), 1.0);
  EXPECT_TRUE(std::isnan(m(2, 0)));
  EXPECT_TRUE(std::isnan(m(2, 2)));
  const auto list = correlations(r);
  ASSERT_EQ(list.size(), 1u);
  EXPECT_EQ(list[0].a, "a");
  EXPECT_EQ(list[0].b, "b");
  EXPECT_NEAR(list[0].r, -0.9, 1e-15);
  EXPECT_EQ(correlations(r, 0.01).size(), 2u);  // the weak link too
}

TEST(Correlations, StraightLineInterceptAndSlope) {
  // y = a + b x at x = 0, 1, 2, 3: (X^T X) = [[4, 6], [6, 14]], its inverse's correlation
  // -6 / sqrt(4 * 14) = -0.801784 whatever the noise.
  const FitResult f = fit_curve(ReportLine{}, {0, 1, 2, 3}, {1.1, 2.9, 5.2, 6.8}, {{"a", 0.0}, {"b", 0.0}});
  ASSERT_TRUE(f.usable);
  const auto list = correlations(f);
  ASSERT_EQ(list.size(), 1u);
  EXPECT_NEAR(list[0].r, -6 / std::sqrt(56.0), 1e-9);
}

// ----- Statistics ---------------------------------------------------------------------------------

TEST(FitStatistics, LmfitConventions) {
  // n = 10, k = 2, RSS = 5: MSE 0.5, reduced chi^2 5/8, AIC 10 ln 0.5 + 4, BIC 10 ln 0.5 + 2 ln 10.
  const FitStatistics s = fit_statistics(10, 2, 5.0, 0.9);
  EXPECT_DOUBLE_EQ(s.mse, 0.5);
  EXPECT_DOUBLE_EQ(s.reduced_chi2, 0.625);
  EXPECT_NEAR(s.aic, -6.931471805599453 + 4, 1e-12);
  EXPECT_NEAR(s.bic, -6.931471805599453 + 2 * 2.302585092994046, 1e-12);
  EXPECT_DOUBLE_EQ(s.r2, 0.9);
  EXPECT_TRUE(std::isnan(fit_statistics(2, 2, 1.0, 0.5).reduced_chi2));
}

// ----- Autocorrelation ----------------------------------------------------------------------------

TEST(Autocorrelation, HandComputedSeries) {
  // 1, 2, 3, 4 less their mean 2.5: sum of squares 5, neighbours' products 0.75 - 0.25 + 0.75.
  const auto a = autocorrelation_correction({1, 2, 3, 4}, {0, 0, 0, 0});
  ASSERT_TRUE(a.computed);
  EXPECT_NEAR(a.rho, 0.25, 1e-15);
  EXPECT_NEAR(a.n_eff, 4 * 0.75 / 1.25, 1e-12);
  EXPECT_NEAR(a.factor, std::sqrt(1.25 / 0.75), 1e-12);
  // Alternating signs: negative rho, no correction (standard errors are not shrunk).
  const auto b = autocorrelation_correction({1, -1, 1, -1, 1, -1}, {0, 0, 0, 0, 0, 0});
  ASSERT_TRUE(b.computed);
  EXPECT_LT(b.rho, 0);
  EXPECT_DOUBLE_EQ(b.factor, 1.0);
  // Two runs: the pair across the boundary (4, 10) does not count; a NaN breaks the chain too.
  // Mean of {1,2,3,4,10,11,12} = 43/7.
  const std::vector<double> e{1, 2, 3, 4, 10, 11, kNaN, 12};
  const auto c = autocorrelation_correction(e, {0, 0, 0, 0, 1, 1, 1, 1});
  ASSERT_TRUE(c.computed);
  EXPECT_EQ(c.pairs, 4u);  // (1,2) (2,3) (3,4) (10,11)
  EXPECT_EQ(c.series, 2u);
  const double m = 43.0 / 7;
  double ss = 0;
  for (double x : {1.0, 2.0, 3.0, 4.0, 10.0, 11.0, 12.0}) ss += (x - m) * (x - m);
  const double lag = (1 - m) * (2 - m) + (2 - m) * (3 - m) + (3 - m) * (4 - m) + (10 - m) * (11 - m);
  EXPECT_NEAR(c.rho, lag / ss, 1e-12);
  EXPECT_FALSE(autocorrelation_correction({1, 2, 3}, {0, 0, 0}).computed);
}

// AR(1) noise e_t = rho e_{t-1} + eps_t, eps ~ N(0, 1), started from its stationary law.
std::vector<double> ar1(std::mt19937_64& rng, std::size_t n, double rho) {
  std::normal_distribution<double> eps(0.0, 1.0);
  std::vector<double> e(n);
  e[0] = eps(rng) / std::sqrt(1 - rho * rho);
  for (std::size_t t = 1; t < n; ++t) e[t] = rho * e[t - 1] + eps(rng);
  return e;
}

// Residuals of a fitted curve.
template <class Model>
std::vector<double> residuals_of(const Model& m, const FitResult& f, const std::vector<double>& x, const std::vector<double>& y) {
  const std::vector<double> p = f.values();
  std::vector<double> r(x.size());
  for (std::size_t i = 0; i < x.size(); ++i) r[i] = y[i] - m(p.data(), x[i]);
  return r;
}


TEST(Autocorrelation, MeanOfAnAr1SeriesMatchesTheClosedForm) {
  constexpr std::size_t n = 2000;
  constexpr double rho = 0.8;
  // Var(mean) = gamma0 / n^2 (n + 2 sum_{k=1}^{n-1} (n - k) rho^k), gamma0 = 1 / (1 - rho^2).
  double s = n;
  for (std::size_t k = 1; k < n; ++k) s += 2.0 * static_cast<double>(n - k) * std::pow(rho, static_cast<double>(k));
  const double true_se = std::sqrt(s / (1 - rho * rho)) / n;
  std::mt19937_64 rng(20240611);
  std::vector<double> x(n);
  for (std::size_t i = 0; i < n; ++i) x[i] = static_cast<double>(i);
  constexpr int reps = 300;
  double naive = 0, corrected = 0, sum = 0, sum2 = 0;
  for (int r = 0; r < reps; ++r) {
    std::vector<double> y = ar1(rng, n, rho);
    for (double& v : y) v += 5.0;
    const FitResult f = fit_curve(Constant{}, x, y, {{"mean", 0.0}});
    ASSERT_TRUE(f.usable) << f.message << " rep " << r;
    const auto a = autocorrelation_correction(residuals_of(Constant{}, f, x, y), std::vector<int>(n, 0));
    ASSERT_TRUE(a.computed);
    naive += f.std_error("mean") / reps;
    corrected += f.std_error("mean") * a.factor / reps;
    sum += f.value("mean");
    sum2 += f.value("mean") * f.value("mean");
  }
  const double empirical = std::sqrt((sum2 - sum * sum / reps) / (reps - 1));
  // The generator is right: the means' spread over the repetitions is the closed form's.
  EXPECT_NEAR(empirical / true_se, 1.0, 0.12);
  // The covariance's error is three times too small (sqrt(1.8 / 0.2) = 3); the corrected one is right.
  EXPECT_LT(naive / true_se, 0.4);
  EXPECT_NEAR(corrected / true_se, 1.0, 0.08);
}

TEST(Autocorrelation, SlopeOnAnAr1SeriesMatchesTheSandwichVariance) {
  constexpr std::size_t n = 1500;
  constexpr double rho = 0.9;
  std::vector<double> x(n);
  for (std::size_t i = 0; i < n; ++i) x[i] = static_cast<double>(i) / n;
  // The slope's true variance under AR(1) noise: (X^T X)^-1 X^T S X (X^T X)^-1, S_ij = rho^|i-j| / (1 - rho^2).
  Eigen::MatrixXd X(n, 2);
  for (std::size_t i = 0; i < n; ++i) X.row(static_cast<Eigen::Index>(i)) << 1.0, x[i];
  Eigen::MatrixXd S(n, n);
  for (std::size_t i = 0; i < n; ++i)
    for (std::size_t j = 0; j < n; ++j)
      S(static_cast<Eigen::Index>(i), static_cast<Eigen::Index>(j)) =
          std::pow(rho, std::abs(static_cast<double>(i) - static_cast<double>(j))) / (1 - rho * rho);
  const Eigen::Matrix2d A = (X.transpose() * X).inverse();
  const Eigen::Matrix2d V = A * (X.transpose() * S * X) * A;
  const double true_se = std::sqrt(V(1, 1));
  std::mt19937_64 rng(77);
  constexpr int reps = 300;
  double naive = 0, corrected = 0, sum = 0, sum2 = 0;
  for (int r = 0; r < reps; ++r) {
    std::vector<double> y = ar1(rng, n, rho);
    for (std::size_t i = 0; i < n; ++i) y[i] += 1.0 - 0.5 * x[i];
    const FitResult f = fit_curve(ReportLine{}, x, y, {{"a", 0.0}, {"b", 0.0}});
    ASSERT_TRUE(f.usable);
    const auto a = autocorrelation_correction(residuals_of(ReportLine{}, f, x, y), std::vector<int>(n, 0));
    naive += f.std_error("b") / reps;
    corrected += f.std_error("b") * a.factor / reps;
    sum += f.value("b");
    sum2 += f.value("b") * f.value("b");
  }
  const double empirical = std::sqrt((sum2 - sum * sum / reps) / (reps - 1));
  EXPECT_NEAR(empirical / true_se, 1.0, 0.12);
  EXPECT_LT(naive / true_se, 0.3);  // sqrt(1.9 / 0.1) = 4.4 times too small
  EXPECT_NEAR(corrected / true_se, 1.0, 0.12);
}

TEST(Autocorrelation, IndependentNoiseIsLeftAlone) {
  std::mt19937_64 rng(5);
  std::normal_distribution<double> eps(0.0, 1.0);
  std::vector<double> e(5000);
  for (double& v : e) v = eps(rng);
  const auto a = autocorrelation_correction(e, std::vector<int>(e.size(), 0));
  ASSERT_TRUE(a.computed);
  EXPECT_LT(std::abs(a.rho), 0.05);  // 3.5 sd of an estimate whose sd is 1/sqrt(5000)
  EXPECT_LT(a.factor, 1.06);
}

}  // namespace

namespace {

// y = mu + u_run + eps: every run has its own offset u ~ N(0, tau^2), rows eps ~ N(0, sigma^2).
// The mean's true variance is tau^2 / G + sigma^2 / (G m) (G runs of m rows); the lag-1
// correlation is only tau^2 / (tau^2 + sigma^2), so the AR(1) factor misses most of it, and the
// cluster-robust errors (runs as clusters) must not.
TEST(ClusterRobust, RunOffsetsThatTheLagOneFactorMisses) {
  constexpr int G = 40, m = 100;
  constexpr double tau = 0.5, sigma = 1.0;
  const double true_se = std::sqrt(tau * tau / G + sigma * sigma / (G * m));
  std::mt19937_64 rng(31337);
  std::normal_distribution<double> u(0.0, tau), eps(0.0, sigma);
  std::vector<double> x(G * m);
  std::vector<int> run(G * m);
  for (int i = 0; i < G * m; ++i) {
    x[static_cast<std::size_t>(i)] = i;
    run[static_cast<std::size_t>(i)] = i / m;
  }
  constexpr int reps = 300;
  double naive = 0, ar1_se = 0, cluster = 0, sum = 0, sum2 = 0;
  for (int r = 0; r < reps; ++r) {
    std::vector<double> y(G * m);
    for (int g = 0; g < G; ++g) {
      const double offset = u(rng);
      for (int i = 0; i < m; ++i) y[static_cast<std::size_t>(g * m + i)] = 2.0 + offset + eps(rng);
    }
    const FitResult f = fit_curve(Constant{}, x, y, {{"mean", 0.0}});
    ASSERT_TRUE(f.usable) << f.message;
    const std::vector<double> e = residuals_of(Constant{}, f, x, y);
    AutocorrelationCorrection a = autocorrelation_correction(e, run);
    // r = y - mean: dr/dmean = -1 on every row.
    apply_cluster_robust(a, f, Eigen::MatrixXd::Constant(G * m, 1, -1.0), e, run);
    ASSERT_TRUE(a.cluster_robust) << a.cluster_why_not;
    naive += f.std_error("mean") / reps;
    ar1_se += f.std_error("mean") * a.factor / reps;
    cluster += a.std_error("mean") / reps;
    sum += f.value("mean");
    sum2 += f.value("mean") * f.value("mean");
  }
  const double empirical = std::sqrt((sum2 - sum * sum / reps) / (reps - 1));
  EXPECT_NEAR(empirical / true_se, 1.0, 0.12);
  EXPECT_LT(naive / true_se, 0.3);
  EXPECT_LT(ar1_se / true_se, 0.35);  // lag-1 rho = 0.2: factor 1.22 where 4.6 is needed
  EXPECT_NEAR(cluster / true_se, 1.0, 0.1);
}

TEST(ClusterRobust, IndependentAr1RunsAgreeWithTheClosedForm) {
  // 30 runs of 200 rows of AR(1) noise (rho 0.8): the mean's variance is the closed form's for one
  // run divided by 30.
  constexpr int G = 30, m = 200;
  constexpr double rho = 0.8;
  double s = m;
  for (int k = 1; k < m; ++k) s += 2.0 * (m - k) * std::pow(rho, k);
  const double true_se = std::sqrt(s / (1 - rho * rho)) / m / std::sqrt(static_cast<double>(G));
  std::mt19937_64 rng(99);
  std::vector<double> x(G * m);
  std::vector<int> run(G * m);
  for (int i = 0; i < G * m; ++i) {
    x[static_cast<std::size_t>(i)] = i;
    run[static_cast<std::size_t>(i)] = i / m;
  }
  constexpr int reps = 300;
  double cluster = 0, ar1_se = 0;
  for (int r = 0; r < reps; ++r) {
    std::vector<double> y;
    for (int g = 0; g < G; ++g)
      for (double v : ar1(rng, m, rho)) y.push_back(v + 1.0);
    const FitResult f = fit_curve(Constant{}, x, y, {{"mean", 0.0}});
    ASSERT_TRUE(f.usable) << f.message;
    const std::vector<double> e = residuals_of(Constant{}, f, x, y);
    AutocorrelationCorrection a = autocorrelation_correction(e, run);
    apply_cluster_robust(a, f, Eigen::MatrixXd::Constant(G * m, 1, -1.0), e, run);
    cluster += a.std_error("mean") / reps;
    ar1_se += f.std_error("mean") * a.factor / reps;
  }
  EXPECT_NEAR(cluster / true_se, 1.0, 0.1);
  EXPECT_NEAR(ar1_se / true_se, 1.0, 0.12);  // here the lag-1 model is the truth: both agree
}

TEST(ClusterRobust, FewRunsFallBackOnTheLagOneFactorAndSaySo) {
  FitResult f;
  f.parameters = {{"mean", 1.0, 0.1}};
  AutocorrelationCorrection a;
  a.computed = true;
  a.factor = 2.0;
  apply_cluster_robust(a, f, Eigen::MatrixXd::Constant(6, 1, -1.0), {0.1, -0.1, 0.2, 0.0, 0.1, -0.3}, {0, 0, 1, 1, 2, 2});
  EXPECT_FALSE(a.cluster_robust);
  EXPECT_NE(a.cluster_why_not.find("3 runs"), std::string::npos) << a.cluster_why_not;
  EXPECT_DOUBLE_EQ(a.std_error("mean"), 0.2);
  EXPECT_EQ(a.method, kAutocorrelationMethod);
}

}  // namespace
}  // namespace test_report_cpp
