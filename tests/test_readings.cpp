// The engine's one treatment of readings (lib/fit readings.hpp): readings clipped at a rail
// (censoring) and channels of different noise (channel weights), used by the calibration's fits
// and the diagnosis's alike.
//
// The logs here come from this file's own generator: a known line (or the light sensor's curve,
// written out below), Gaussian noise from a seeded splitmix64 + Box-Muller, then the register's
// clamp. The truths compared against are the generator's, and the closed forms are computed here
// with Eigen's normal equations, not by the engine.
#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <sstream>
#include <string>
#include <vector>

#include "epuck2/calibrate/sensors.hpp"
#include "epuck2/diagnose/diagnose.hpp"
#include "epuck2/fit/problem.hpp"
#include "epuck2/fit/readings.hpp"
#include "epuck2/fit/robust.hpp"
#include "epuck2/logs/log.hpp"
#include "epuck2/models/saturation.hpp"
#include "seeded_normal.hpp"

namespace fit = epuck2::fit;

namespace {

using epuck2::testing::Normal;  // seeded_normal.hpp

// The line y* = a + b x, x on [0, 10], noise sd 15, clipped to [120, 250]: the low rail takes the
// readings where x < 1 or so (10 %), the high one where x > 7.5 (25 %).
constexpr double kReadingsA = 100, kReadingsB = 20, kSd = 15, kLo = 120, kHi = 250;
constexpr std::size_t kN = 300;

struct Clipped {
  std::vector<double> x, y;
  std::size_t on_rail = 0;
};

Clipped clipped_line(std::uint64_t seed) {
  Normal normal(seed);
  Clipped c;
  for (std::size_t i = 0; i < kN; ++i) {
    const double x = 10.0 * normal.uniform();
    const double latent = kReadingsA + kReadingsB * x + kSd * normal();
    const double y = std::min(std::max(latent, kLo), kHi);
    c.on_rail += (y <= kLo || y >= kHi) ? 1 : 0;
    c.x.push_back(x);
    c.y.push_back(y);
  }
  return c;
}

struct ReadingsLine {
  std::vector<double> x;
  template <typename T>
  bool operator()(const T* p, T* out) const {
    for (std::size_t i = 0; i < x.size(); ++i) out[i] = p[0] + p[1] * x[i];
    return true;
  }
};

// The line through the engine's censored fit (fit_robust, the calibration's), with the rails
// (censored = true) or every reading taken as exact (plain least squares).
fit::RobustFit fit_line(const Clipped& c, bool censored, double noise_sd = std::nan("")) {
  std::vector<fit::Observation> obs;
  for (double y : c.y) obs.push_back({y, censored ? fit::censoring_at(y, kLo, kHi) : fit::Censoring::none, "", -1});
  fit::RobustOptions o;
  o.robust = false;
  o.noise_sd = noise_sd;
  return fit::fit_robust(ReadingsLine{c.x}, obs, {fit::free_parameter("a", 0.0), fit::free_parameter("b", 1.0)}, o);
}

}  // namespace

TEST(Readings, ResidualIsTobitsLogLikelihoodSignedLikeTheReading) {
  // Worked by hand: an exact reading 3 above the curve, sd 2, weight 4: r = 2 * 3 / 2 = 3.
  const fit::Residual e = fit::reading_residual(10.0, 13.0, fit::Censoring::none, 2.0, 2.0);
  EXPECT_DOUBLE_EQ(e.value, 3.0);
  EXPECT_DOUBLE_EQ(e.d_prediction, -1.0);
  // On the high rail 250 with the curve at 250: Phi(0) = 1/2, r = sqrt(2 log 2), above the curve.
  const fit::Residual at = fit::reading_residual(250.0, 250.0, fit::Censoring::at_or_above, 15.0, 1.0);
  EXPECT_NEAR(at.value, std::sqrt(2 * std::log(2.0)), 1e-15);
  // On the low rail with the curve 2 sd above it: Phi(-2) = 0.0227501319481792 (tables), below.
  const fit::Residual below = fit::reading_residual(150.0, 120.0 + 0.0, fit::Censoring::at_or_below, 15.0, 1.0);
  EXPECT_NEAR(below.value, -std::sqrt(-2 * std::log(0.0227501319481792)), 1e-12);
  // Its derivative against a central difference of the same formula.
  const double h = 1e-6;
  const double up = fit::reading_residual(150.0 + h, 120.0, fit::Censoring::at_or_below, 15.0, 1.0).value;
  const double down = fit::reading_residual(150.0 - h, 120.0, fit::Censoring::at_or_below, 15.0, 1.0).value;
  EXPECT_NEAR(below.d_prediction, (up - down) / (2 * h), 1e-7);
  // The channels censor at their own rails, residuals in channel 0's units (sd 15 here).
  const fit::Channels channels({{kLo, kHi, kSd}});
  EXPECT_EQ(fit::censoring_at(kHi + 3, kLo, kHi), fit::Censoring::at_or_above);
  EXPECT_EQ(fit::censoring_at(kLo, kLo, kHi), fit::Censoring::at_or_below);
  EXPECT_EQ(fit::censoring_at(kLo + 1, kLo, kHi), fit::Censoring::none);
  EXPECT_DOUBLE_EQ(channels.residual(250.0, kHi + 3, 0).value, kSd * at.value);
  EXPECT_DOUBLE_EQ(channels.residual(200.0, 203.0, 0).value, 3.0);
}

TEST(Readings, CensoredFitRecoversTheLineAndLeastSquaresDoesNot) {
  const Clipped c = clipped_line(20261126);
  const double share = static_cast<double>(c.on_rail) / kN;
  ASSERT_GT(share, 0.2);
  ASSERT_LT(share, 0.4);
  const fit::RobustFit tobit = fit_line(c, true);
  ASSERT_TRUE(tobit.usable) << tobit.message;
  EXPECT_EQ(tobit.censored(), c.on_rail);
  // Within 2.5 standard errors of the generator's truth, the noise within 15 %.
  EXPECT_LT(std::abs(tobit.value("a") - kReadingsA), 2.5 * tobit.std_error("a"));
  EXPECT_LT(std::abs(tobit.value("b") - kReadingsB), 2.5 * tobit.std_error("b"));
  EXPECT_NEAR(tobit.noise_sd, kSd, 0.15 * kSd);
  // Every reading taken at face value: the rails flatten the line, the slope falls by many
  // standard errors.
  const fit::RobustFit plain = fit_line(c, false);
  ASSERT_TRUE(plain.usable) << plain.message;
  EXPECT_GT(std::abs(plain.value("b") - kReadingsB), 10 * plain.std_error("b"));
  EXPECT_LT(plain.value("b"), 0.85 * kReadingsB);
}

// Least squares on the expected clamped reading E[clamp(a + b x + noise)] (lib/models
// saturation.hpp) with the true noise sd: the other treatment of a rail the diagnosis once used.
double expected_clamp_slope(const Clipped& c) {
  const std::vector<double> x = c.x, y = c.y;
  double p[2] = {0.0, 1.0};
  fit::Problem problem;
  problem.add(fit::autodiff<static_cast<int>(kN), 2>([x, y](const auto* q, auto* r) {
                for (std::size_t i = 0; i < x.size(); ++i) r[i] = y[i] - epuck2::models::expected_clamp(q[0] + q[1] * x[i], kLo, kHi, kSd);
                return true;
              }),
              {p});
  return problem.solve(fit::FitOptions{}).usable ? p[1] : std::nan("");
}

TEST(Readings, CensoredFitIsUnbiasedWithHonestErrorsOverSeeds) {
  // 40 logs: the censored fit's z-scores (estimate - truth) / standard error average near 0 with
  // a spread near 1; least squares on the same logs misses the slope by far more than its errors.
  // Least squares on the expected clamped reading is unbiased too, but scatters more: the censored
  // likelihood is the efficient one (docs/fitting.md has the numbers over 400 logs).
  constexpr int kSeeds = 40;
  double sum_z = 0, sum_z2 = 0, sum_plain_z = 0, sum_b = 0, sum_b2 = 0, sum_e = 0, sum_e2 = 0;
  for (int s = 0; s < kSeeds; ++s) {
    const Clipped c = clipped_line(1000 + static_cast<std::uint64_t>(s));
    const fit::RobustFit tobit = fit_line(c, true);
    const fit::RobustFit plain = fit_line(c, false);
    ASSERT_TRUE(tobit.usable && plain.usable);
    const double b = tobit.value("b"), z = (b - kReadingsB) / tobit.std_error("b");
    sum_z += z;
    sum_z2 += z * z;
    sum_b += b;
    sum_b2 += b * b;
    sum_plain_z += (plain.value("b") - kReadingsB) / plain.std_error("b");
    const double e = expected_clamp_slope(c);
    ASSERT_TRUE(std::isfinite(e));
    sum_e += e;
    sum_e2 += e * e;
  }
  const double mean_z = sum_z / kSeeds, rms_z = std::sqrt(sum_z2 / kSeeds);
  // The mean of 40 standard normals has sd 0.16: |mean| < 0.5 is 3 of them.
  EXPECT_LT(std::abs(mean_z), 0.5);
  EXPECT_GT(rms_z, 0.7);
  EXPECT_LT(rms_z, 1.35);
  EXPECT_LT(sum_plain_z / kSeeds, -10.0);
  const double sd_tobit = std::sqrt(sum_b2 / kSeeds - (sum_b / kSeeds) * (sum_b / kSeeds));
  const double sd_expected = std::sqrt(sum_e2 / kSeeds - (sum_e / kSeeds) * (sum_e / kSeeds));
  std::printf("slope over %d logs: censored mean z %.3f, rms z %.3f, sd %.4f; least squares on E[clamp] sd %.4f; "
              "plain least squares mean z %.2f\n", kSeeds, mean_z, rms_z, sd_tobit, sd_expected, sum_plain_z / kSeeds);
  EXPECT_LT(std::abs(sum_e / kSeeds - kReadingsB), 3 * sd_expected / std::sqrt(double(kSeeds)));
  EXPECT_LT(sd_tobit, sd_expected) << "censored " << sd_tobit << " expected clamp " << sd_expected;
}

TEST(Readings, ProblemWithReadingsBlockIsTheSameCensoredFit) {
  // The diagnosis's path (fit::Problem with the readings block) and the calibration's (fit_robust)
  // are one treatment: with the same noise sd, the same estimates.
  const Clipped c = clipped_line(77);
  const fit::RobustFit robust = fit_line(c, true, kSd);
  ASSERT_TRUE(robust.usable) << robust.message;
  std::vector<double> x = c.x;
  fit::ResidualBlock latent = fit::autodiff<static_cast<int>(kN), 2>([x](const auto* p, auto* out) {
    for (std::size_t i = 0; i < x.size(); ++i) out[i] = p[0] + p[1] * x[i];
    return true;
  });
  double p[2] = {0.0, 1.0};
  fit::Problem problem;
  problem.add(fit::readings_block(std::move(latent), c.y, {}, fit::Channels({{kLo, kHi, kSd}})), {p});
  fit::FitOptions options;
  options.function_tolerance = 1e-14;
  options.gradient_tolerance = 1e-14;
  options.parameter_tolerance = 1e-12;
  ASSERT_TRUE(problem.solve(options).usable);
  EXPECT_NEAR(p[0], robust.value("a"), 1e-6 * std::abs(robust.value("a")));
  EXPECT_NEAR(p[1], robust.value("b"), 1e-6 * std::abs(robust.value("b")));
}

TEST(Readings, ChannelWeightsGiveTheWeightedLeastSquaresErrors) {
  // Two channels observe the same line a + b x: channel 0 with noise sd 1 (say mm), channel 1
  // with sd 10 (another unit's counts). Weighted by sd_0 / sd_c, the fit is weighted least
  // squares: its standard errors are sqrt(diag(s^2 (X^T W X)^-1)), W = diag(sd_0^2 / sd_c^2) and
  // s^2 = sum W r^2 / (n - 2), computed here from the normal equations; and they are near the
  // truth (X^T diag(1 / sd_c^2) X)^-1 of known noise.
  constexpr int kRows = 200;
  const double a = 5, b = 0.5, sd[2] = {1.0, 10.0};
  Normal normal(42);
  std::vector<double> x, y;
  std::vector<int> channel;
  for (int i = 0; i < kRows; ++i) {
    const int c = i % 2;
    const double xi = 20.0 * normal.uniform();
    x.push_back(xi);
    y.push_back(a + b * xi + sd[c] * normal());
    channel.push_back(c);
  }
  fit::ResidualBlock latent = fit::autodiff<kRows, 2>([x](const auto* p, auto* out) {
    for (std::size_t i = 0; i < x.size(); ++i) out[i] = p[0] + p[1] * x[i];
    return true;
  });
  double p[2] = {0.0, 0.0};
  fit::Problem problem;
  problem.add(fit::readings_block(std::move(latent), y, channel, fit::Channels({{-INFINITY, INFINITY, sd[0]}, {-INFINITY, INFINITY, sd[1]}})),
              {p});
  fit::FitOptions options;
  options.function_tolerance = 1e-15;
  options.gradient_tolerance = 1e-15;
  options.parameter_tolerance = 1e-14;
  const fit::SolveSummary summary = problem.solve(options);
  ASSERT_TRUE(summary.usable);
  fit::ParameterLayout layout;
  layout.blocks = {p};
  layout.sizes = {2};
  layout.names = {"a", "b"};
  const fit::FitResult r = problem.summarize(layout, y, summary, fit::FitOptions{});
  ASSERT_TRUE(r.usable);

  // The closed form, by the normal equations.
  Eigen::MatrixXd X(kRows, 2);
  Eigen::VectorXd Y(kRows), W(kRows), truth_w(kRows);
  for (int i = 0; i < kRows; ++i) {
    X(i, 0) = 1;
    X(i, 1) = x[static_cast<std::size_t>(i)];
    Y(i) = y[static_cast<std::size_t>(i)];
    const double s = sd[channel[static_cast<std::size_t>(i)]];
    W(i) = sd[0] * sd[0] / (s * s);
    truth_w(i) = 1 / (s * s);
  }
  const Eigen::MatrixXd XtWX = X.transpose() * W.asDiagonal() * X;
  const Eigen::VectorXd beta = XtWX.ldlt().solve(X.transpose() * W.asDiagonal() * Y);
  const Eigen::VectorXd e = Y - X * beta;
  const double s2 = e.dot(W.asDiagonal() * e) / (kRows - 2);
  const Eigen::MatrixXd cov = s2 * XtWX.inverse();
  const Eigen::MatrixXd truth = (X.transpose() * truth_w.asDiagonal() * X).inverse();
  // The same minimum, to a hundred-thousandth of a standard error.
  EXPECT_NEAR(p[0], beta(0), 1e-5 * std::sqrt(cov(0, 0)));
  EXPECT_NEAR(p[1], beta(1), 1e-5 * std::sqrt(cov(1, 1)));
  EXPECT_NEAR(r.std_error("a"), std::sqrt(cov(0, 0)), 1e-8 * std::sqrt(cov(0, 0)));
  EXPECT_NEAR(r.std_error("b"), std::sqrt(cov(1, 1)), 1e-8 * std::sqrt(cov(1, 1)));
  EXPECT_NEAR(r.std_error("a"), std::sqrt(truth(0, 0)), 0.15 * std::sqrt(truth(0, 0)));
  EXPECT_NEAR(r.std_error("b"), std::sqrt(truth(1, 1)), 0.15 * std::sqrt(truth(1, 1)));
  // Unweighted, the noisy channel dominates: the slope's error is over twice the weighted one.
  const Eigen::VectorXd beta_ols = (X.transpose() * X).ldlt().solve(X.transpose() * Y);
  const double s2_ols = (Y - X * beta_ols).squaredNorm() / (kRows - 2);
  EXPECT_GT(std::sqrt(s2_ols * (X.transpose() * X).inverse()(1, 1)), 2 * r.std_error("b"));
}

// A light log saturated before its noise in bright light and clipped at the register's rail 0:
// reading = clamp(round(max(4095 (1 - (gamma I / d)^2), 0) + N(0, noise)), 0, 4095), gamma 0.09,
// I = 1, d on [0.085, 0.1] m: the curve falls to the rail across the log, a quarter of the
// readings land on it, and they carry much of what the log says about gamma.
epuck2::logs::Log censored_light(std::uint64_t seed, int* railed) {
  const double gamma = 0.09, noise = 200;
  Normal normal(seed);
  std::string text = "distance_m,intensity,sensor,value\n";
  *railed = 0;
  for (int i = 0; i < 600; ++i) {
    const double d = 0.085 + 0.015 * normal.uniform();
    const double q = gamma / d;
    const double latent = std::max(4095 * (1 - q * q), 0.0);
    const double v = std::min(std::max(std::round(latent + noise * normal()), 0.0), 4095.0);
    *railed += v == 0 ? 1 : 0;
    std::ostringstream line;
    line.precision(10);
    line << d << ",1,0," << v << "\n";
    text += line.str();
  }
  return epuck2::logs::parse_log(text, "censored_light.csv", epuck2::logs::Kind::light);
}

TEST(Readings, CalibrationAndDiagnosisRefitTheSameBaseOnACensoredLog) {
  // The calibration (fit_light) and the diagnosis's recalibrated base fit gamma with the one
  // censored likelihood: over 30 logs their gammas differ by 0.11 of the calibration's standard
  // error (rms), what their two noise estimates leave (the calibration's by maximum likelihood,
  // the diagnosis's from the readings away from the rails); the diagnosis's former loss, least
  // squares on the expected clamped reading, differed by 0.38 on these same logs (this test run
  // against the libraries before the change) and fails the bound.
  constexpr int kSeeds = 30;
  double sum_d2 = 0, sum_se = 0, sum_z = 0;
  for (int s = 0; s < kSeeds; ++s) {
    int railed = 0;
    const epuck2::logs::Log log = censored_light(static_cast<std::uint64_t>(s + 1), &railed);
    ASSERT_GT(railed, 600 / 6);
    ASSERT_LT(railed, 600 * 2 / 5);
    const auto calibration = epuck2::calibrate::fit_light({log});
    ASSERT_TRUE(calibration.gamma.usable) << calibration.gamma.message;
    const epuck2::diagnose::Report diagnosis = epuck2::diagnose::diagnose({log});
    ASSERT_EQ(diagnosis.recalibrated.size(), 1u);
    const double g_cal = calibration.gamma.value("gamma"), se_cal = calibration.gamma.std_error("gamma");
    const double g_diag = diagnosis.recalibrated[0].value;
    const double d = (g_diag - g_cal) / se_cal;
    sum_d2 += d * d;
    sum_se += diagnosis.recalibrated[0].std_error / se_cal;
    sum_z += (g_cal - 0.09) / se_cal;
  }
  const double rms_d = std::sqrt(sum_d2 / kSeeds);
  std::printf("light over %d logs: diagnosis - calibration gamma, rms %.3f of the calibration's standard error; "
              "standard errors' mean ratio %.3f; calibration's mean z %.3f\n",
              kSeeds, rms_d, sum_se / kSeeds, sum_z / kSeeds);
  EXPECT_LT(rms_d, 0.2);
  EXPECT_NEAR(sum_se / kSeeds, 1.0, 0.15);
  // The calibration itself is unbiased (the mean of 30 z-scores has sd 0.18).
  EXPECT_LT(std::abs(sum_z / kSeeds), 0.55);
}
