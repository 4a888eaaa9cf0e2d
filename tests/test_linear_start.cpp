// fit_curve on models linear in their parameters: the linear least-squares start (normal equations
// when well conditioned, refined once; column-pivoted QR otherwise) gives the
// least-squares solution (checked against an independent solve of the normal equations in long
// double), Ceres only confirms it, and the statistics, covariance and fixed parameters come out as
// on the generic path. And the engine's named solver settings (FitOptions::precise() ...) hold
// the values docs/fitting.md's table gives them (the table is the expected value).
#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <fstream>
#include <map>
#include <sstream>
#include <string>
#include <random>
#include <vector>

#include "epuck2/fit/fit_curve.hpp"
#include "epuck2/fit/least_squares.hpp"
#include "epuck2/nist/nist.hpp"

namespace ef = epuck2::fit;

namespace {

// charge-like cubic p0 + p1 u + p2 u^2 + p3 u^3, declared linear in its parameters.
struct LinearCubic {
  static constexpr int kParameters = 4;
  static constexpr bool kLinearInParameters = true;
  template <typename T>
  T operator()(const T* p, double u) const {
    return ((p[3] * u + p[2]) * u + p[1]) * u + p[0];
  }
};

// The same formula without the declaration: fit_curve treats it as any nonlinear model.
struct GenericCubic {
  static constexpr int kParameters = 4;
  template <typename T>
  T operator()(const T* p, double u) const {
    return ((p[3] * u + p[2]) * u + p[1]) * u + p[0];
  }
};

// The cubic with p1 held at `c`: p0 + c u + q1 u^2 + q2 u^3, parameters (p0, q1, q2).
struct CubicWithKnownSlope {
  static constexpr int kParameters = 3;
  static constexpr bool kLinearInParameters = true;
  double c;
  template <typename T>
  T operator()(const T* q, double u) const {
    return ((q[2] * u + q[1]) * u + T(c)) * u + q[0];
  }
};

// Two parameters that only enter as their sum: affine, but the columns are equal.
struct RedundantLine {
  static constexpr int kParameters = 2;
  static constexpr bool kLinearInParameters = true;
  template <typename T>
  T operator()(const T* p, double u) const {
    return (p[0] + p[1]) * u;
  }
};

static_assert(ef::is_linear_in_parameters<LinearCubic>::value);
static_assert(!ef::is_linear_in_parameters<GenericCubic>::value);
static_assert(!ef::is_linear_in_parameters<epuck2::nist::models::Misra1a>::value);

// Standard normal deviates by Box-Muller from the generator's raw bits (portable across
// standard libraries).
double gaussian(std::mt19937_64& rng) {
  constexpr double kTwoPi = 6.283185307179586;
  const double u1 = (static_cast<double>(rng() >> 11) + 1.0) * 0x1.0p-53;  // (0, 1]
  const double u2 = static_cast<double>(rng() >> 11) * 0x1.0p-53;          // [0, 1)
  return std::sqrt(-2.0 * std::log(u1)) * std::cos(kTwoPi * u2);
}

struct Data {
  std::vector<double> u, y;
};

// 400 points on [0, 1.2] of a cubic discharge-like curve with noise of 0.01.
Data noisy_cubic(std::uint64_t seed) {
  constexpr int kPoints = 400;
  constexpr double kSigma = 0.01;
  const double truth[4] = {1.0, -0.4, 0.3, -0.2};
  std::mt19937_64 rng(seed);
  Data d;
  for (int i = 0; i < kPoints; ++i) {
    const double u = 1.2 * i / (kPoints - 1);
    d.u.push_back(u);
    d.y.push_back(LinearCubic{}(truth, u) + kSigma * gaussian(rng));
  }
  return d;
}

// Least squares by the normal equations in long double (an independent method: no QR, more
// precision): the reference the fits are checked against.
std::vector<double> normal_equations_solution(const Data& d) {
  using M = Eigen::Matrix<long double, 4, 4>;
  using V = Eigen::Matrix<long double, 4, 1>;
  M A = M::Zero();
  V b = V::Zero();
  for (std::size_t i = 0; i < d.u.size(); ++i) {
    const long double u = d.u[i];
    const V row(1.0L, u, u * u, u * u * u);
    A += row * row.transpose();
    b += row * static_cast<long double>(d.y[i]);
  }
  const V x = A.ldlt().solve(b);
  return {static_cast<double>(x(0)), static_cast<double>(x(1)), static_cast<double>(x(2)), static_cast<double>(x(3))};
}

const std::vector<std::string> kNames{"p0", "p1", "p2", "p3"};

// Digits in common (the log relative error, capped at 15).
double agree(double a, double reference) { return epuck2::nist::log_relative_error(a, reference, 15.0); }

}  // namespace

TEST(LinearStart, ReachesTheLeastSquaresSolutionAndCeresOnlyConfirmsIt) {
  for (std::uint64_t seed : {1u, 2u, 3u}) {
    const Data d = noisy_cubic(seed);
    const std::vector<double> ref = normal_equations_solution(d);
    const ef::FitResult r = ef::fit_curve(LinearCubic{}, d.u, d.y, ef::free_parameters(kNames, {0.0, 0.0, 0.0, 0.0}));
    ASSERT_TRUE(r.usable) << r.message;
    for (std::size_t j = 0; j < 4; ++j)
      EXPECT_GE(agree(r.parameters[j].value, ref[j]), 11.0) << "seed " << seed << " p" << j;
    // Iteration 0 and at most one step: from the minimum there is nothing left to do.
    EXPECT_LE(r.iterations, 2) << r.message;

    // The generic path (no linear start, one block per observation, LM from the same start)
    // reaches the same minimum to the digits its 1e-15 tolerances leave, with the same statistics.
    ef::FitOptions generic;
    generic.linear_start = false;
    generic.single_residual_block = false;
    const ef::FitResult g = ef::fit_curve(LinearCubic{}, d.u, d.y, ef::free_parameters(kNames, {0.0, 0.0, 0.0, 0.0}), generic);
    ASSERT_TRUE(g.usable) << g.message;
    EXPECT_GT(g.iterations, r.iterations);
    for (std::size_t j = 0; j < 4; ++j) {
      EXPECT_GE(agree(g.parameters[j].value, r.parameters[j].value), 8.0);
      EXPECT_GE(agree(g.parameters[j].std_error, r.parameters[j].std_error), 8.0);
      EXPECT_GT(r.parameters[j].std_error, 0.0);
    }
    EXPECT_GE(agree(g.rss, r.rss), 10.0);
    EXPECT_GE(agree(g.r2, r.r2), 10.0);
    EXPECT_GE(agree(g.aic, r.aic), 10.0);
    // The undeclared model takes the generic path by itself.
    const ef::FitResult u = ef::fit_curve(GenericCubic{}, d.u, d.y, ef::free_parameters(kNames, {0.0, 0.0, 0.0, 0.0}));
    ASSERT_TRUE(u.usable);
    EXPECT_GT(u.iterations, r.iterations);
  }
}

TEST(LinearStart, StandardErrorsMatchTheCovarianceOfTheDesign) {
  // For a linear model, cov = s^2 (X^T X)^-1 exactly; check against the long-double normal
  // equations.
  const Data d = noisy_cubic(7);
  const ef::FitResult r = ef::fit_curve(LinearCubic{}, d.u, d.y, ef::free_parameters(kNames, {0.0, 0.0, 0.0, 0.0}));
  ASSERT_TRUE(r.usable);
  using M = Eigen::Matrix<long double, 4, 4>;
  M A = M::Zero();
  for (double u : d.u) {
    const Eigen::Matrix<long double, 4, 1> row(1.0L, u, static_cast<long double>(u) * u,
                                               static_cast<long double>(u) * u * u);
    A += row * row.transpose();
  }
  const M inv = A.inverse();
  const double s2 = r.rss / static_cast<double>(d.u.size() - 4);
  for (int j = 0; j < 4; ++j)
    EXPECT_GE(agree(r.parameters[static_cast<std::size_t>(j)].std_error,
                                           std::sqrt(s2 * static_cast<double>(inv(j, j)))),
              10.0);
}

TEST(LinearStart, FixedParameterKeepsItsValueAndTheOthersTheirOwnErrors) {
  // Holding p1 (not the last parameter) is the same as fitting the three-parameter model with p1
  // known: same values, same standard errors, in the right places.
  const Data d = noisy_cubic(11);
  constexpr double kSlope = -0.35;
  const ef::FitResult reduced =
      ef::fit_curve(CubicWithKnownSlope{kSlope}, d.u, d.y, {{"p0", 0.0}, {"p2", 0.0}, {"p3", 0.0}});
  ASSERT_TRUE(reduced.usable);
  for (bool linear_start : {true, false}) {
    ef::FitOptions o;
    o.linear_start = linear_start;
    std::vector<ef::Parameter> start = ef::free_parameters(kNames, {0.0, kSlope, 0.0, 0.0});
    start[1].fixed = true;
    const ef::FitResult r = ef::fit_curve(LinearCubic{}, d.u, d.y, start, o);
    ASSERT_TRUE(r.usable) << r.message;
    EXPECT_EQ(r.parameters[1].value, kSlope);
    EXPECT_EQ(r.parameters[1].std_error, 0.0);
    EXPECT_EQ(r.free_parameters, 3);
    const double digits = linear_start ? 11.0 : 7.0;
    const std::size_t full[3] = {0, 2, 3};
    for (std::size_t k = 0; k < 3; ++k) {
      EXPECT_GE(agree(r.parameters[full[k]].value, reduced.parameters[k].value), digits)
          << "linear_start " << linear_start << " p" << full[k];
      EXPECT_GE(agree(r.parameters[full[k]].std_error, reduced.parameters[k].std_error), digits)
          << "linear_start " << linear_start << " p" << full[k];
    }
    EXPECT_EQ(r.covariance(1, 1), 0.0);
    EXPECT_EQ(r.covariance(0, 1), 0.0);
  }
}

TEST(LinearStart, RankDeficientDesignFallsBackAndSaysSo) {
  // p0 and p1 only enter as their sum: no unique least-squares solution. The linear start is
  // refused, Ceres fits from the initial values, and the covariance is reported unavailable.
  const Data d = noisy_cubic(5);
  const ef::FitResult r = ef::fit_curve(RedundantLine{}, d.u, d.y, {{"a", 0.1}, {"b", 0.2}});
  EXPECT_NE(r.message.find("rank-deficient"), std::string::npos) << r.message;
  EXPECT_TRUE(std::isnan(r.parameters[0].std_error));
}

TEST(LinearStart, RobustFitsKeepTheirOwnPath) {
  // Huber's loss is not least squares: no linear start, one residual block per observation; on
  // data without outliers it lands near the least-squares solution.
  const Data d = noisy_cubic(3);
  ef::FitOptions robust;
  robust.robust = true;
  robust.robust_scale = 1.0;  // far above the noise (0.01): every residual in the quadratic zone
  const ef::FitResult r = ef::fit_curve(LinearCubic{}, d.u, d.y, ef::free_parameters(kNames, {0.0, 0.0, 0.0, 0.0}), robust);
  ASSERT_TRUE(r.usable) << r.message;
  EXPECT_GT(r.iterations, 2);
  const std::vector<double> ref = normal_equations_solution(d);
  for (std::size_t j = 0; j < 4; ++j) EXPECT_GE(agree(r.parameters[j].value, ref[j]), 6.0);
}

TEST(LinearStart, NormalEquationsSolveOnlyWellConditionedSystems) {
  // The same cubic design on u in [0, 1.2] (equilibrated condition number about 1e2: its normal
  // matrix about 1e4) and shifted to u in [10, 11.2] (3e5, numpy's cond: 1e11 once squared, beyond
  // kNormalEquationsMaxCondition).
  for (double shift : {0.0, 10.0}) {
    const Data d = noisy_cubic(13);
    Eigen::MatrixXd N = Eigen::MatrixXd::Zero(4, 4);
    Eigen::VectorXd g = Eigen::VectorXd::Zero(4);
    for (std::size_t i = 0; i < d.u.size(); ++i) {
      const double u = d.u[i] + shift;
      const Eigen::Vector4d row(1.0, u, u * u, u * u * u);
      N += row * row.transpose();
      g += row * (-d.y[i]);
    }
    // r(p) = y - X p: J = -X, so J^T J = X^T X and J^T r(0) = -X^T y (g above).
    Eigen::VectorXd step;
    Eigen::MatrixXd inverse;
    const bool solved = ef::normal_equations_least_squares(N, g, {true, true, true, true}, &step, &inverse);
    if (shift == 0.0) {
      ASSERT_TRUE(solved);
      // step = -(J^T J)^-1 J^T r(0) = (X^T X)^-1 X^T y: the least-squares coefficients.
      const std::vector<double> ref = normal_equations_solution(d);
      for (int j = 0; j < 4; ++j) EXPECT_GE(agree(step(j), ref[static_cast<std::size_t>(j)]), 10.0) << "p" << j;
      EXPECT_GE(agree(inverse(0, 0), N.inverse()(0, 0)), 8.0);
    } else {
      EXPECT_FALSE(solved) << "an ill-conditioned system must go to the QR path";
    }
  }
}

TEST(LinearStart, IllConditionedDesignTakesTheQrPathAndStillReachesTheMinimum) {
  // The cubic in v = u + 10: the normal equations are refused (above), the column-pivoted QR
  // solves it (losing about 5.5 of 16 digits to the condition number 3e5; 11.8 digits measured),
  // Ceres confirms.
  const Data d = noisy_cubic(17);
  Data shifted = d;
  for (double& u : shifted.u) u += 10.0;
  // The reference: a QR of the design itself in long double (about 13 digits here; the normal
  // equations would leave 8).
  using MX = Eigen::Matrix<long double, Eigen::Dynamic, Eigen::Dynamic>;
  using VX = Eigen::Matrix<long double, Eigen::Dynamic, 1>;
  MX X(static_cast<Eigen::Index>(shifted.u.size()), 4);
  VX yv(static_cast<Eigen::Index>(shifted.u.size()));
  for (std::size_t i = 0; i < shifted.u.size(); ++i) {
    const long double v = shifted.u[i];
    const auto row = static_cast<Eigen::Index>(i);
    X(row, 0) = 1.0L;
    X(row, 1) = v;
    X(row, 2) = v * v;
    X(row, 3) = v * v * v;
    yv(row) = shifted.y[i];
  }
  const VX ref = X.colPivHouseholderQr().solve(yv);
  const ef::FitResult r = ef::fit_curve(LinearCubic{}, shifted.u, shifted.y, ef::free_parameters(kNames, {0.0, 0.0, 0.0, 0.0}));
  ASSERT_TRUE(r.usable) << r.message;
  for (std::size_t j = 0; j < 4; ++j)
    EXPECT_GE(agree(r.parameters[j].value, static_cast<double>(ref(static_cast<Eigen::Index>(j)))), 10.0) << "p" << j;
  // Without the linear start, Levenberg-Marquardt from zero needs many more iterations.
  ef::FitOptions generic;
  generic.linear_start = false;
  const ef::FitResult g = ef::fit_curve(LinearCubic{}, shifted.u, shifted.y, ef::free_parameters(kNames, {0.0, 0.0, 0.0, 0.0}), generic);
  EXPECT_GT(g.iterations, r.iterations);
}

namespace {
// a exp(-b u) + c: nonlinear, so fit_curve iterates, and on its default path (one residual block)
// reuses the Jacobian of the solver's last evaluation for the covariance instead of evaluating
// it again.
struct Decay {
  static constexpr int kParameters = 3;
  template <typename T>
  T operator()(const T* p, double u) const {
    using std::exp;
    return p[0] * exp(-p[1] * u) + p[2];
  }
};
}  // namespace

// fit_curve's second fast path (the Jacobian recorded during the solve and reused) against the
// plain path (one block per observation: nothing recorded, the Jacobian evaluated afresh) and
// against the covariance computed here from the analytic derivatives in long double.
TEST(JacobianReuse, GivesTheCovarianceOfAFreshJacobianAndThePlainPathsFit) {
  for (std::uint64_t seed : {4u, 5u, 6u}) {
    std::mt19937_64 rng(seed);
    std::vector<double> u, y;
    for (int i = 0; i < 300; ++i) {
      u.push_back(3.0 * i / 299.0);
      y.push_back(2.0 * std::exp(-1.3 * u.back()) + 0.5 + 0.02 * gaussian(rng));
    }
    const std::vector<std::string> names{"a", "b", "c"};
    const ef::FitResult fast = ef::fit_curve(Decay{}, u, y, ef::free_parameters(names, {1.0, 1.0, 0.0}));
    ASSERT_TRUE(fast.usable) << fast.message;
    ef::FitOptions plain;
    plain.single_residual_block = false;
    const ef::FitResult slow = ef::fit_curve(Decay{}, u, y, ef::free_parameters(names, {1.0, 1.0, 0.0}), plain);
    ASSERT_TRUE(slow.usable) << slow.message;

    // Independent covariance at the fast path's solution: J_i = (e, -a u e, 1), e = exp(-b u).
    const long double a = fast.parameters[0].value, b = fast.parameters[1].value, c = fast.parameters[2].value;
    Eigen::Matrix<long double, 3, 3> normal = Eigen::Matrix<long double, 3, 3>::Zero();
    long double rss = 0;
    for (std::size_t i = 0; i < u.size(); ++i) {
      const long double e = std::exp(-b * u[i]);
      const Eigen::Matrix<long double, 3, 1> row(e, -a * u[i] * e, 1.0L);
      normal += row * row.transpose();
      const long double r = y[i] - (a * e + c);
      rss += r * r;
    }
    const Eigen::Matrix<long double, 3, 3> covariance = normal.inverse() * (rss / (u.size() - 3));
    for (int j = 0; j < 3; ++j) {
      const double se = static_cast<double>(std::sqrt(covariance(j, j)));
      EXPECT_GE(agree(fast.parameters[static_cast<std::size_t>(j)].std_error, se), 9.0) << "seed " << seed << " " << names[static_cast<std::size_t>(j)];
      EXPECT_GE(agree(slow.parameters[static_cast<std::size_t>(j)].value, fast.parameters[static_cast<std::size_t>(j)].value), 8.0);
      EXPECT_GE(agree(slow.parameters[static_cast<std::size_t>(j)].std_error, fast.parameters[static_cast<std::size_t>(j)].std_error), 7.0);
    }
    EXPECT_GE(agree(fast.rss, static_cast<double>(rss)), 9.0);
    EXPECT_GE(agree(slow.rss, fast.rss), 10.0);
  }
}

// ----- the named solver settings -----------------------------------------------------------------

namespace {

/// The rows of docs/fitting.md's "Solver settings" table, by preset: the cells after the name.
std::map<std::string, std::vector<std::string>> documented_presets() {
  std::ifstream in(std::string(EPUCK2_SOURCE_DIR) + "/docs/fitting.md");
  std::map<std::string, std::vector<std::string>> rows;
  std::string line;
  while (std::getline(in, line)) {
    if (line.rfind("| `", 0) != 0 || line.find("()` |") == std::string::npos) continue;
    std::vector<std::string> cells;
    std::stringstream ss(line.substr(1));
    std::string cell;
    while (std::getline(ss, cell, '|')) {
      const auto b = cell.find_first_not_of(' '), e = cell.find_last_not_of(' ');
      cells.push_back(b == std::string::npos ? "" : cell.substr(b, e - b + 1));
    }
    const std::string name = cells.front().substr(1, cells.front().size() - 2);  // without the backquotes
    cells.erase(cells.begin());
    rows[name] = cells;
  }
  return rows;
}

}  // namespace

// Each preset holds what the docs' table says (iterations, three tolerances, restarts,
// alternatives), and the table lists every preset; what a preset leaves alone keeps the defaults.
TEST(SolverPresets, EachHasTheValuesOfThisTable) {
  const std::map<std::string, ef::FitOptions> presets{
      {"precise()", ef::FitOptions::precise()},       {"calibration()", ef::FitOptions::calibration()},
      {"diagnosis()", ef::FitOptions::diagnosis()},   {"stock()", ef::FitOptions::stock()},
      {"reference()", ef::FitOptions::reference()}};
  const auto rows = documented_presets();
  EXPECT_EQ(rows.size(), presets.size()) << "docs/fitting.md's table and the presets differ in number";
  for (const auto& [name, o] : presets) {
    const auto it = rows.find(name);
    ASSERT_NE(it, rows.end()) << name << " is not in docs/fitting.md's table";
    const auto& c = it->second;
    ASSERT_GE(c.size(), 6u) << name;
    EXPECT_EQ(o.max_iterations, std::stoi(c[0])) << name;
    EXPECT_EQ(o.function_tolerance, std::stod(c[1])) << name;
    EXPECT_EQ(o.gradient_tolerance, std::stod(c[2])) << name;
    EXPECT_EQ(o.parameter_tolerance, std::stod(c[3])) << name;
    EXPECT_EQ(o.restarts, std::stoi(c[4])) << name;
    EXPECT_EQ(o.try_alternatives, c[5] == "yes") << name;
    const ef::FitOptions d;
    EXPECT_EQ(o.linear_solver, d.linear_solver) << name;
    EXPECT_EQ(o.compute_covariance, d.compute_covariance) << name;
    EXPECT_EQ(o.robust, d.robust) << name;
  }
}
