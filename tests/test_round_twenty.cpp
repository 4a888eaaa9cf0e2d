// Round 20 of the fresh slips (bench/fresh-slips.md): a test for each survivor's behaviour, written
// during the round's run (after its GO: not in the run that scores it). Every expected value comes
// from the docs, is counted by the test from the inputs it builds, or is worked by hand in the
// comment beside it, never from the code under test.
#include <gtest/gtest.h>

#include <cmath>
#include <string>
#include <vector>

#include <Eigen/Dense>

#include "epuck2/fit/fit_curve.hpp"
#include "epuck2/fit/least_squares.hpp"

namespace test_round_twenty_cpp {

namespace fit = epuck2::fit;

struct Line {
  static constexpr int kParameters = 2;
  template <typename T>
  T operator()(const T* p, double x) const {
    return p[0] + p[1] * x;
  }
};

struct Quadratic {
  static constexpr int kParameters = 3;
  template <typename T>
  T operator()(const T* p, double x) const {
    return p[0] + p[1] * x + p[2] * x * x;
  }
};

// ---- lib/fit: a parameter held at a bound is said to be on the side it is on ----

// y = 1 + 2x exactly. With the slope bounded below by 2.5 it ends on that lower bound; bounded
// above by 1.5, on the upper one (docs/fitting.md: "ended on its lower/upper bound, where it is
// held: no standard error").
TEST(RoundTwentyFit, AParameterOnItsBoundIsSaidOnTheRightSide) {
  const std::vector<double> x{0, 1, 2, 3}, y{1, 3, 5, 7};
  std::vector<fit::Parameter> low{{"a", 0.0}, {"b", 3.0}};
  low[1].lower = 2.5;
  const fit::FitResult l = fit::fit_curve(Line{}, x, y, low);
  ASSERT_TRUE(l.usable) << l.message;
  EXPECT_NEAR(l.value("b"), 2.5, 1e-9);
  EXPECT_EQ(l.parameters[1].std_error_why, "ended on its lower bound, where it is held: no standard error");
  // The intercept for slope 2.5: mean(y - 2.5 x) = 4 - 2.5 * 1.5 = 0.25.
  EXPECT_NEAR(l.value("a"), 0.25, 1e-9);
  std::vector<fit::Parameter> high{{"a", 0.0}, {"b", 0.0}};
  high[1].upper = 1.5;
  const fit::FitResult h = fit::fit_curve(Line{}, x, y, high);
  ASSERT_TRUE(h.usable) << h.message;
  EXPECT_EQ(h.parameters[1].std_error_why, "ended on its upper bound, where it is held: no standard error");
}

// ---- lib/fit: a fit with as many residuals as parameters has no noise to estimate ----

// fit_curve refuses fewer than k + 1 observations before any covariance; the covariance step itself
// (set_covariance, which every fit of the engine ends with: the sensor fits' robust passes, the
// camera's, the drive's) must still say why when it is handed as many residuals as estimable
// parameters: n - k = 0 leaves no degree of freedom for the noise. A 3 x 3 Jacobian (the quadratic
// through x = 0, 1, 2) and a 2 x 2 one; with one row more, errors exist and no reason is left.
TEST(RoundTwentyFit, AnExactlyDeterminedFitSaysItHasNoDegreeOfFreedom) {
  const auto covariance_of = [](const std::vector<std::string>& names, const Eigen::MatrixXd& jacobian) {
    fit::FitResult r;
    for (const auto& n : names) r.parameters.emplace_back(n, 1.0, std::nan(""), "");
    r.usable = true;
    r.rss = 0.25;
    fit::set_covariance(r, jacobian, std::vector<bool>(names.size(), true));
    return r;
  };
  Eigen::MatrixXd q(3, 3);
  q << 1, 0, 0, 1, 1, 1, 1, 2, 4;
  for (const auto& p : covariance_of({"c0", "c1", "c2"}, q).parameters)
    EXPECT_EQ(p.std_error_why, "undefined: 3 residuals for 3 estimable parameters leave no degree of freedom to estimate the noise")
        << p.name;
  Eigen::MatrixXd l(2, 2);
  l << 1, 0, 1, 1;
  for (const auto& p : covariance_of({"a", "b"}, l).parameters)
    EXPECT_EQ(p.std_error_why, "undefined: 2 residuals for 2 estimable parameters leave no degree of freedom to estimate the noise")
        << p.name;
  Eigen::MatrixXd m(3, 2);
  m << 1, 0, 1, 1, 1, 2;
  for (const auto& p : covariance_of({"a", "b"}, m).parameters) {
    EXPECT_TRUE(p.std_error > 0) << p.name;
    EXPECT_EQ(p.std_error_why, "") << p.name;
  }
  // And fit_curve, which refuses such a fit earlier, says so (docs/fitting.md).
  const fit::FitResult refused = fit::fit_curve(Quadratic{}, {0, 1, 2}, {1, 2, 5}, {{"c0", 0.0}, {"c1", 0.0}, {"c2", 0.0}});
  EXPECT_FALSE(refused.usable);
  EXPECT_EQ(refused.message, "too few observations (3) for 3 parameters");
}

}  // namespace test_round_twenty_cpp
