// One fitting engine underneath (issue #19, item 3): fit_robust states its problem as a
// fit::Problem over fit::readings_block, takes its covariance from the engine's one routine (the
// equilibrated QR of least_squares.cpp) and its identifiability from the engine's one check
// (check_identifiability), which fit::Problem's summary (the diagnosis's) asks too.
//
// Expected values come from outside the engine: closed forms computed here with Eigen's LDLT of
// the normal equations (X^T X)^-1 s^2 for a line, condition numbers from a self-adjoint
// eigen-decomposition, numbers worked by hand, and a generator's truth (seeded_normal.hpp).
#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <cmath>
#include <string>
#include <vector>

#include "epuck2/fit/least_squares.hpp"
#include "epuck2/fit/problem.hpp"
#include "epuck2/fit/readings.hpp"
#include "epuck2/fit/robust.hpp"
#include "seeded_normal.hpp"

namespace fit = epuck2::fit;

namespace {

// y = p0 + p1 x + p2 x^2 (columns 1, x, x^2) or, with `twin`, y = p0 + p1 x + p2 x (two identical
// columns: only p1 + p2 is determined). With `ignored`, p2 does not enter at all.
struct EngineQuadratic {
  std::vector<double> x;
  bool twin = false, ignored = false;
  template <typename T>
  bool operator()(const T* p, T* out) const {
    for (std::size_t i = 0; i < x.size(); ++i) {
      const double third = ignored ? 0.0 : twin ? x[i] : x[i] * x[i];
      out[i] = p[0] + p[1] * x[i] + p[2] * third;
    }
    return true;
  }
};

// y* = a exp(-x / tau) + c.
struct EngineDecay {
  std::vector<double> x;
  template <typename T>
  bool operator()(const T* p, T* out) const {
    using std::exp;
    for (std::size_t i = 0; i < x.size(); ++i) out[i] = p[0] * exp(-x[i] / p[1]) + p[2];
    return true;
  }
};

struct EngineData {
  std::vector<double> x, y;
};

// A quadratic 5 + 2 x - 0.3 x^2 on x in [0, 10], noise sd 0.5, seeded.
EngineData engine_quadratic_data(std::uint64_t seed, std::size_t n = 60) {
  epuck2::testing::Normal normal(seed);
  EngineData d;
  for (std::size_t i = 0; i < n; ++i) {
    const double x = 10.0 * static_cast<double>(i) / static_cast<double>(n - 1);
    d.x.push_back(x);
    d.y.push_back(5 + 2 * x - 0.3 * x * x + 0.5 * normal());
  }
  return d;
}

std::vector<fit::Observation> engine_exact(const std::vector<double>& y) {
  std::vector<fit::Observation> obs;
  for (double v : y) obs.push_back({v, fit::Censoring::none, "", -1});
  return obs;
}

Eigen::MatrixXd engine_design(const std::vector<double>& x) {
  Eigen::MatrixXd X(static_cast<Eigen::Index>(x.size()), 3);
  for (std::size_t i = 0; i < x.size(); ++i) X.row(static_cast<Eigen::Index>(i)) << 1.0, x[i], x[i] * x[i];
  return X;
}

}  // namespace

TEST(RobustOnEngine, CovarianceOfAnUncensoredFitIsTheClosedFormOfTheLinearModel) {
  // No reading on a rail, no reading left out: the Tobit fit is least squares, and its covariance
  // must be (X^T X)^-1 s^2 with s^2 = RSS / (n - 3) (noise estimated), or (X^T X)^-1 sd^2 (given).
  const EngineData d = engine_quadratic_data(20261126);
  const Eigen::MatrixXd X = engine_design(d.x);
  const Eigen::VectorXd y = Eigen::Map<const Eigen::VectorXd>(d.y.data(), static_cast<Eigen::Index>(d.y.size()));
  const Eigen::LDLT<Eigen::MatrixXd> normal(X.transpose() * X);
  const Eigen::VectorXd beta = normal.solve(X.transpose() * y);
  const Eigen::MatrixXd inverse = normal.solve(Eigen::MatrixXd::Identity(3, 3));
  const double rss = (y - X * beta).squaredNorm();
  const double s2 = rss / static_cast<double>(d.x.size() - 3);

  fit::RobustOptions o;
  o.robust = false;
  const std::vector<fit::Parameter> start{fit::free_parameter("c0", 0.0), fit::free_parameter("c1", 1.0),
                                          fit::free_parameter("c2", 0.0)};
  const fit::RobustFit r = fit::fit_robust(EngineQuadratic{d.x}, engine_exact(d.y), start, o);
  ASSERT_TRUE(r.usable) << r.message;
  ASSERT_EQ(r.identifiability.size(), 1u);
  EXPECT_TRUE(r.identifiability[0].determined());
  for (Eigen::Index j = 0; j < 3; ++j) {
    // The solver stops within the calibration's tolerances: far inside a standard error.
    EXPECT_NEAR(r.parameters[static_cast<std::size_t>(j)].value, beta(j), 1e-4 * std::sqrt(inverse(j, j) * s2));
    for (Eigen::Index k = 0; k < 3; ++k)
      EXPECT_NEAR(r.covariance(j, k), inverse(j, k) * s2, 1e-7 * std::sqrt(inverse(j, j) * inverse(k, k)) * s2) << j << "," << k;
  }
  EXPECT_NEAR(r.noise_sd, std::sqrt(s2), 1e-9 * std::sqrt(s2));

  o.noise_sd = 0.5;
  const fit::RobustFit known = fit::fit_robust(EngineQuadratic{d.x}, engine_exact(d.y), start, o);
  ASSERT_TRUE(known.usable) << known.message;
  for (Eigen::Index j = 0; j < 3; ++j)
    EXPECT_NEAR(known.parameters[static_cast<std::size_t>(j)].std_error, std::sqrt(inverse(j, j)) * 0.5,
                1e-9 * std::sqrt(inverse(j, j)) * 0.5);
}

TEST(RobustOnEngine, TwoIdenticalColumnsAreUndeterminedByTheOneCheckInEveryFit) {
  const EngineData d = engine_quadratic_data(7);
  // The check itself on the design [1, x, x]: the two x columns, each half of the null direction
  // (share 1), rank 2 of 3; the constant column is not along it.
  Eigen::MatrixXd X = engine_design(d.x);
  X.col(2) = X.col(1);
  const fit::Identifiability id = fit::check_identifiability(X, {});
  EXPECT_TRUE(id.rank_deficient());
  EXPECT_EQ(id.rank, 2);
  ASSERT_EQ(id.undetermined.size(), 2u);
  EXPECT_EQ(id.undetermined[0].column, 1);
  EXPECT_EQ(id.undetermined[1].column, 2);
  for (const auto& u : id.undetermined) {
    EXPECT_EQ(u.why, fit::Identifiability::Why::rank_deficient);
    EXPECT_NEAR(u.share, 1.0, 1e-6);
  }
  EXPECT_EQ(id.inverse_normal.size(), 0);

  // The calibration's policy: the last declared along the direction is held at its fallback, the
  // fit repeated; c1 then carries the whole slope (2 + 0.25: the fallback's share).
  std::vector<fit::Parameter> p{{"c0", 0.0, 0.0}, {"c1", 1.0, 0.0}, {"c2", 0.0, 0.25}};
  fit::RobustOptions o;
  o.robust = false;
  EngineData line = d;
  epuck2::testing::Normal normal(8);
  for (std::size_t i = 0; i < line.x.size(); ++i) line.y[i] = 5 + 2 * line.x[i] + 0.5 * normal();
  const fit::RobustFit r = fit::fit_robust(EngineQuadratic{line.x, true}, engine_exact(line.y), p, o);
  ASSERT_TRUE(r.usable) << r.message;
  EXPECT_EQ(r.not_identifiable, std::vector<std::string>{"c2"});
  EXPECT_EQ(r.value("c2"), 0.25);
  EXPECT_TRUE(std::isnan(r.std_error("c2")));
  EXPECT_NE(r.std_error_why.at("c2").find("only together"), std::string::npos) << r.std_error_why.at("c2");
  ASSERT_EQ(r.identifiability.size(), 2u);
  EXPECT_TRUE(r.identifiability[0].rank_deficient());
  EXPECT_TRUE(r.identifiability[0].any(fit::Identifiability::Why::rank_deficient));
  EXPECT_TRUE(r.identifiability[1].determined());
  EXPECT_NEAR(r.value("c1") + 0.25, 2.0, 0.05);

  // The diagnosis's path (fit::Problem's summary): the same check, its policy an explained NaN.
  double q[3] = {0.0, 1.0, 0.0};
  const std::vector<double> x = line.x, yv = line.y;
  fit::Problem problem;
  problem.add(fit::autodiff<60, 3>([x, yv](const auto* b, auto* res) {
                for (std::size_t i = 0; i < x.size(); ++i) res[i] = yv[i] - (b[0] + b[1] * x[i] + b[2] * x[i]);
                return true;
              }),
              {q});
  const fit::SolveSummary s = problem.solve(fit::FitOptions{});
  ASSERT_TRUE(s.usable) << s.message;
  const fit::FitResult f = problem.summarize({{q}, {3}, {"c0", "c1", "c2"}}, yv, s, fit::FitOptions{});
  EXPECT_NE(f.message.find("rank-deficient, rank 2 of 3"), std::string::npos) << f.message;
  for (const char* n : {"c1", "c2"}) {
    EXPECT_TRUE(std::isnan(f.std_error(n)));
    const auto& p_n = f.parameters[n[1] == '1' ? 1 : 2];
    EXPECT_NE(p_n.std_error_why.find("rank-deficient"), std::string::npos) << p_n.std_error_why;
  }
}

TEST(RobustOnEngine, ConditionAboveTheLimitIsTheEigenDecompositionsNumber) {
  // Columns 1, x, x + 1e-4 w (w a fixed zigzag): full rank, but the equilibrated normal matrix's
  // condition number is far above 1e8. Computed here by a self-adjoint eigen-decomposition of the
  // equilibrated X^T X in long double; the check's (from R's singular values) must agree to 1e-6,
  // and name the two near-twins as undetermined by the condition.
  std::vector<double> x;
  for (int i = 0; i < 40; ++i) x.push_back(0.25 * i);
  Eigen::MatrixXd X(40, 3);
  for (int i = 0; i < 40; ++i) X.row(i) << 1.0, x[static_cast<std::size_t>(i)], x[static_cast<std::size_t>(i)] + 1e-4 * ((i % 2) ? 1.0 : -1.0);
  // In long double: in double the eigen-decomposition's smallest eigenvalue (1e-10 of the largest)
  // keeps only about 6 digits, which is why the check takes R's singular values instead.
  using LongMatrix = Eigen::Matrix<long double, Eigen::Dynamic, Eigen::Dynamic>;
  LongMatrix E = X.cast<long double>();
  for (Eigen::Index c = 0; c < 3; ++c) E.col(c) /= E.col(c).norm();
  const Eigen::SelfAdjointEigenSolver<LongMatrix> eig(E.transpose() * E);
  const double expected = static_cast<double>(eig.eigenvalues()(2) / eig.eigenvalues()(0));
  ASSERT_GT(expected, 1e8);
  const fit::Identifiability id = fit::check_identifiability(X, {}, 1e8);
  EXPECT_FALSE(id.rank_deficient());
  EXPECT_NEAR(id.condition, expected, 1e-6 * expected);
  EXPECT_TRUE(id.any(fit::Identifiability::Why::condition));
  ASSERT_EQ(id.undetermined.size(), 2u);
  EXPECT_EQ(id.undetermined[0].column, 1);
  EXPECT_EQ(id.undetermined[1].column, 2);
  // Without a limit (the diagnosis's), the same columns are determined and get their covariance,
  // (X^T X)^-1 from the one routine against the LDLT's within the digits the condition leaves.
  const fit::Identifiability free = fit::check_identifiability(X, {});
  ASSERT_TRUE(free.determined());
  EXPECT_TRUE(std::isnan(free.condition));
  const Eigen::MatrixXd inverse = (X.transpose() * X).ldlt().solve(Eigen::MatrixXd::Identity(3, 3));
  EXPECT_NEAR(free.inverse_normal(2, 2), inverse(2, 2), 1e-3 * inverse(2, 2));
}

TEST(RobustOnEngine, AColumnOfZerosIsHeldByTheCalibrationAndExplainedByTheSummary) {
  const EngineData d = engine_quadratic_data(11);
  Eigen::MatrixXd X = engine_design(d.x);
  X.col(2).setZero();
  const fit::Identifiability id = fit::check_identifiability(X, {}, 1e8);
  ASSERT_EQ(id.undetermined.size(), 1u);
  EXPECT_EQ(id.undetermined[0].column, 2);
  EXPECT_EQ(id.undetermined[0].why, fit::Identifiability::Why::zero_column);
  EXPECT_EQ(id.estimable, (std::vector<Eigen::Index>{0, 1}));
  // The covariance over the other two is still given: (X^T X)^-1 of [1, x].
  const Eigen::MatrixXd X2 = X.leftCols(2);
  const Eigen::MatrixXd inverse = (X2.transpose() * X2).ldlt().solve(Eigen::MatrixXd::Identity(2, 2));
  ASSERT_EQ(id.inverse_normal.rows(), 2);
  EXPECT_NEAR(id.inverse_normal(1, 1), inverse(1, 1), 1e-10 * inverse(1, 1));

  fit::RobustOptions o;
  o.robust = false;
  const fit::RobustFit r = fit::fit_robust(EngineQuadratic{d.x, false, true}, engine_exact(d.y),
                                           {{"c0", 0.0, 0.0}, {"c1", 1.0, 0.0}, {"c2", 0.0, -0.3}}, o);
  ASSERT_TRUE(r.usable) << r.message;
  EXPECT_EQ(r.not_identifiable, std::vector<std::string>{"c2"});
  EXPECT_EQ(r.value("c2"), -0.3);
  EXPECT_NE(r.std_error_why.at("c2").find("do not depend on it"), std::string::npos);
  ASSERT_FALSE(r.identifiability.empty());
  EXPECT_TRUE(r.identifiability[0].any(fit::Identifiability::Why::zero_column));

  // set_covariance on the same Jacobian: c2 NaN with its reason, the others finite.
  fit::FitResult f;
  f.parameters = {{"c0", 0, 0}, {"c1", 0, 0}, {"c2", 0, 0}};
  f.rss = 1.0;
  fit::set_covariance(f, X, {true, true, true});
  EXPECT_TRUE(std::isnan(f.parameters[2].std_error) || f.parameters[2].std_error == 0) << f.parameters[2].std_error;
  EXPECT_NE(f.parameters[2].std_error_why.find("Jacobian column is zero"), std::string::npos) << f.parameters[2].std_error_why;
  EXPECT_NEAR(f.parameters[1].std_error, std::sqrt(inverse(1, 1) / static_cast<double>(d.x.size() - 2)),
              1e-10 * std::sqrt(inverse(1, 1)));
}

TEST(RobustOnEngine, CensoredFitWithAHeldParameterRecoversTheGeneratorsTruth) {
  // y* = a exp(-x / tau) + c, clipped at 600 above and 40 below; c held at its truth 30 by the
  // caller (fit_robust holds it inside the one fit::Problem). a and tau within 3 standard errors
  // of the generator's 1000 and 2.5 over 20 seeds at least 18 times; c exactly 30.
  int within = 0;
  for (std::uint64_t seed = 1; seed <= 20; ++seed) {
    epuck2::testing::Normal normal(seed);
    std::vector<double> x;
    std::vector<fit::Observation> obs;
    std::size_t railed = 0;
    for (int i = 0; i < 200; ++i) {
      const double xi = 10.0 * normal.uniform();
      const double latent = 1000 * std::exp(-xi / 2.5) + 30 + 12 * normal();
      const fit::Censoring c = fit::censoring_at(latent, 40, 600);
      railed += c != fit::Censoring::none ? 1 : 0;
      x.push_back(xi);
      obs.push_back({c == fit::Censoring::none ? latent : c == fit::Censoring::at_or_above ? 600.0 : 40.0, c, "", -1});
    }
    ASSERT_GT(railed, 20u);
    fit::Parameter a = fit::free_parameter("a", 500), tau = fit::free_parameter("tau", 1.0), c = fit::fixed_parameter("c", 30);
    tau.lower = 0.01;
    fit::RobustOptions o;
    o.robust = false;
    const fit::RobustFit r = fit::fit_robust(EngineDecay{x}, obs, {a, tau, c}, o);
    ASSERT_TRUE(r.usable) << r.message;
    EXPECT_EQ(r.value("c"), 30.0);
    EXPECT_EQ(r.std_error("c"), 0.0);
    EXPECT_EQ(r.censored(), railed);
    if (std::abs(r.value("a") - 1000) < 3 * r.std_error("a") && std::abs(r.value("tau") - 2.5) < 3 * r.std_error("tau")) ++within;
  }
  EXPECT_GE(within, 18);
}

TEST(RobustOnEngine, StatedCensoringBlockIsTheChannelsBlockInNoiseSd) {
  // One latent prediction per reading, f = p0 = 10 (one parameter): readings 13 (exact, weight
  // 4), 11 (on a high rail, at or above), 9 (on a low rail, at or below), 7 (weight 0: left out).
  fit::ResidualBlock latent;
  latent.residuals = 4;
  latent.sizes = {1};
  latent.evaluate = [](double const* const* p, double* f, double** jac) {
    for (int i = 0; i < 4; ++i) f[i] = p[0][0];
    if (jac != nullptr && jac[0] != nullptr)
      for (int i = 0; i < 4; ++i) jac[0][i] = 1.0;
    return true;
  };
  const fit::ResidualBlock stated = fit::readings_block(
      latent, {13, 11, 9, 7},
      {fit::Censoring::none, fit::Censoring::at_or_above, fit::Censoring::at_or_below, fit::Censoring::none}, {4, 1, 1, 0}, 2.0);
  const double p0 = 10;
  const double* params[1] = {&p0};
  double r[4], j[4];
  double* jacs[1] = {j};
  ASSERT_TRUE(stated.evaluate(params, r, jacs));
  // By hand: exact, weight 4, sd 2: 2 * (13 - 10) / 2 = 3, d/df = -1.
  EXPECT_DOUBLE_EQ(r[0], 3.0);
  EXPECT_DOUBLE_EQ(j[0], -1.0);
  // Each rail half an sd beyond the curve: Phi(-0.5) = 0.308537538725987 (tables), the residual
  // sqrt(-2 log Phi(-0.5)) signed like the reading against the curve.
  const double tail = std::sqrt(-2 * std::log(0.308537538725987));
  EXPECT_NEAR(r[1], tail, 1e-12);
  EXPECT_NEAR(r[2], -tail, 1e-12);
  EXPECT_EQ(r[3], 0.0);
  EXPECT_EQ(j[3], 0.0);
  // The channels' block with rails 9 and 11 and sd 2 gives the rails' residuals in units of sd 2:
  // the same times 2, derivatives too.
  const fit::ResidualBlock channels = fit::readings_block(latent, {13, 11, 9, 7}, {}, fit::Channels({{9, 11, 2.0}}));
  double rc[4], jc[4];
  double* jcs[1] = {jc};
  ASSERT_TRUE(channels.evaluate(params, rc, jcs));
  for (int i = 1; i < 3; ++i) {
    EXPECT_NEAR(2 * r[i], rc[i], 1e-12 * std::abs(rc[i])) << i;
    EXPECT_NEAR(2 * j[i], jc[i], 1e-12 * std::abs(jc[i])) << i;
  }
}

TEST(RobustOnEngine, ProblemHoldsSomeValuesOfAnArray) {
  // y = a + b x with a held at 1 inside the one array: b = sum x (y - 1) / sum x^2 (by hand).
  const std::vector<double> x{1, 2, 3, 4}, y{3.1, 4.9, 7.2, 8.8};
  double p[2] = {1.0, 0.0};
  fit::Problem problem;
  problem.add(fit::autodiff<4, 2>([x, y](const auto* q, auto* r) {
                for (std::size_t i = 0; i < 4; ++i) r[i] = y[i] - (q[0] + q[1] * x[i]);
                return true;
              }),
              {p});
  problem.hold(p, {0});
  ASSERT_TRUE(problem.solve(fit::FitOptions{}).usable);
  EXPECT_EQ(p[0], 1.0);
  // sum x (y - 1) = 2.1 + 7.8 + 18.6 + 31.2 = 59.7; sum x^2 = 30.
  EXPECT_NEAR(p[1], 59.7 / 30.0, 1e-12);
}

TEST(OneEngine, ConfirmReachesAndKeepsTheLinearSolution) {
  // fit_curve's confirming step (Problem::confirm) on y = a + b x. By hand: x mean 2.5, y mean 6,
  // Sxy = 4.35 + 0.55 + 0.6 + 4.2 = 9.7, Sxx = 5: b = 1.94, a = 6 - 1.94 * 2.5 = 1.15.
  const std::vector<double> x{1, 2, 3, 4}, y{3.1, 4.9, 7.2, 8.8};
  double p[2] = {0.0, 0.0};
  fit::Problem problem;
  problem.add(fit::autodiff<4, 2>([x, y](const auto* q, auto* r) {
                for (std::size_t i = 0; i < 4; ++i) r[i] = y[i] - (q[0] + q[1] * x[i]);
                return true;
              }),
              {p});
  const fit::SolveSummary first = problem.confirm(fit::FitOptions{});
  ASSERT_TRUE(first.usable) << first.message;
  EXPECT_NEAR(p[0], 1.15, 1e-9);
  EXPECT_NEAR(p[1], 1.94, 1e-9);
  // From the solution itself, nothing to improve: still a converged fit, the point kept.
  const double a = p[0], b = p[1];
  const fit::SolveSummary again = problem.confirm(fit::FitOptions{});
  EXPECT_TRUE(again.usable) << again.message;
  EXPECT_TRUE(again.converged) << again.message;
  EXPECT_NEAR(p[0], a, 1e-12);
  EXPECT_NEAR(p[1], b, 1e-12);
}

TEST(OneEngine, SummarizeFromResidualsTheCallerEvaluated) {
  // The line above at (1.15, 1.94): residuals 0.01, -0.13, 0.23, -0.11 (by hand), RSS 0.082; the
  // total sum of squares about y's mean 6 is 8.41 + 1.21 + 1.44 + 7.84 = 18.9.
  const std::vector<double> y{3.1, 4.9, 7.2, 8.8}, residuals{0.01, -0.13, 0.23, -0.11};
  double p[2] = {1.15, 1.94};
  fit::SolveSummary summary;
  summary.usable = true;
  summary.iterations = 3;
  summary.message = "stated";
  const fit::FitResult r =
      fit::Problem::summarize(fit::ParameterLayout{{p}, {2}, {"a", "b"}}, residuals, true, y, summary);
  ASSERT_TRUE(r.usable);
  EXPECT_EQ(r.observations, 4u);
  EXPECT_EQ(r.iterations, 3);
  EXPECT_NEAR(r.rss, 0.082, 1e-12);
  EXPECT_NEAR(r.r2, 1 - 0.082 / 18.9, 1e-12);
  EXPECT_NEAR(r.residual_variance, 0.082 / 2, 1e-12);
  EXPECT_EQ(r.value("b"), 1.94);
}
