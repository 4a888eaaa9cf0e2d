// Battery fits recover known coefficients from generated data, and their standard errors
// describe the real spread of the estimates (rates over seeds, not one lucky case).
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "epuck2/calibrate/battery.hpp"
#include "epuck2/models/plugin_battery_tables.hpp"

namespace ef = epuck2::fit;
namespace calibrate = epuck2::calibrate;
namespace mb = epuck2::models::battery;

namespace {
// Synthetic run: charge = published cubic at `speed` + Gaussian noise of `sigma`, every 10 s.
calibrate::BatteryRun synthetic_run(int speed, double sigma, std::uint64_t seed, const std::string& robot) {
  const mb::CubicRow& q = mb::plugin_tables().cubic[static_cast<std::size_t>(speed)];
  const double p[4] = {q.d, q.c, q.b, q.a};
  std::mt19937_64 rng(seed);
  std::normal_distribution<double> noise(0.0, sigma);
  calibrate::BatteryRun r;
  r.path = robot + "_" + std::to_string(speed);
  r.robot = robot;
  r.speed_cm_s = speed;
  for (double t = 0; t < q.end_s; t += 10.0) {
    r.time_s.push_back(t);
    r.charge.push_back(mb::cubic_charge(p, t) + noise(rng));
  }
  r.time_s.push_back(q.end_s);
  r.charge.push_back(mb::cubic_charge(p, q.end_s) + noise(rng));
  r.lifetime_s = q.end_s;
  for (double t : r.time_s) r.profile.push_back({t, static_cast<double>(speed)});
  return r;
}
}  // namespace

TEST(BatteryFit, RecoversAKnownCubicAndItsStandardErrorsAreHonest) {
  // Over many seeds: the fraction of estimates within 2 standard errors of the truth must be near
  // the Gaussian 95% (a wrongly scaled covariance gives far more or far fewer).
  constexpr int kSeeds = 60;
  constexpr double kSigma = 0.02;
  const mb::CubicRow& q = mb::plugin_tables().cubic[4];
  const double truth[4] = {q.d, q.c, q.b, q.a};
  const char* names[4] = {"d", "c", "b", "a"};
  int inside = 0, total = 0;
  for (int seed = 1; seed <= kSeeds; ++seed) {
    const calibrate::BatteryFit f = calibrate::fit_battery({synthetic_run(4, kSigma, static_cast<std::uint64_t>(seed), "x")});
    ASSERT_EQ(f.speeds.size(), 1u);
    const ef::FitResult& c = f.speeds[0].cubic;
    ASSERT_TRUE(c.usable) << c.message;
    EXPECT_NEAR(c.residual_variance, kSigma * kSigma, 0.15 * kSigma * kSigma);
    for (int k = 0; k < 4; ++k) {
      inside += std::abs(c.value(names[k]) - truth[k]) <= 2.0 * c.std_error(names[k]) ? 1 : 0;
      ++total;
    }
  }
  const double rate = static_cast<double>(inside) / total;
  EXPECT_GT(rate, 0.88);
  EXPECT_LT(rate, 0.995);
}

TEST(BatteryFit, NoiseFreeCubicIsRecoveredToManyDigits) {
  const calibrate::BatteryFit f = calibrate::fit_battery({synthetic_run(9, 0.0, 1, "x")});
  const mb::CubicRow& q = mb::plugin_tables().cubic[9];
  const auto& c = f.speeds[0].cubic;
  // Log relative error >= 8 digits on every coefficient.
  for (auto [name, truth] : {std::pair{"d", q.d}, {"c", q.c}, {"b", q.b}, {"a", q.a}})
    EXPECT_GE(-std::log10(std::abs(c.value(name) - truth) / std::abs(truth) + 1e-300), 8.0) << name;
}

TEST(BatteryFit, PiecewiseRecoversKnownBreakpoints) {
  // Data on a known polyline (0,1), (3000,0.7), (8000,0.45), (L-1,0.15), small noise.
  const double L = 10000.0;
  const double xs[4] = {0.0, 3000.0, 8000.0, L - 1.0}, ys[4] = {1.0, 0.7, 0.45, 0.15};
  std::mt19937_64 rng(7);
  std::normal_distribution<double> noise(0.0, 0.005);
  calibrate::BatteryRun r;
  r.path = "poly";
  r.speed_cm_s = 3;
  for (double t = 0; t <= L; t += 5.0) {
    r.time_s.push_back(t);
    r.charge.push_back(mb::polyline_charge(xs, ys, 4, t) + noise(rng));
    r.profile.push_back({t, 3.0});
  }
  r.lifetime_s = L;
  const calibrate::BatteryFit f = calibrate::fit_battery({r});
  const auto& p = f.speeds[0].piecewise;
  ASSERT_TRUE(p.usable) << p.message;
  EXPECT_NEAR(p.value("x1_s"), 3000.0, 4 * p.std_error("x1_s") + 1.0);
  EXPECT_NEAR(p.value("x2_s"), 8000.0, 4 * p.std_error("x2_s") + 1.0);
  EXPECT_LT(p.std_error("x1_s"), 100.0);
  EXPECT_NEAR(p.value("y3"), 0.15, 0.005);
  // The plug-in format: M1 starts at full charge, M4 is the 1-second drop to 0 at the lifetime.
  const auto& segs = f.speeds[0].segments;
  EXPECT_DOUBLE_EQ(segs[0].h, 1.0);
  EXPECT_DOUBLE_EQ(segs[3].x2_s, L);
  EXPECT_DOUBLE_EQ(segs[3].y2, 0.0);
  EXPECT_NEAR(segs[3].m * 1.0, -segs[3].y1, 1e-12);
}

TEST(BatteryFit, LinesAndSimpleSlopesFollowThePapersDefinitions) {
  std::vector<calibrate::BatteryRun> runs;
  for (int s : {0, 5, 10})
    for (int k = 0; k < 2; ++k) runs.push_back(synthetic_run(s, 0.01, 100 + s * 2 + k, k ? "a" : "b"));
  const calibrate::BatteryFit f = calibrate::fit_battery(runs);
  const mb::Tables& pt = mb::plugin_tables();
  ASSERT_EQ(f.speeds.size(), 3u);
  EXPECT_NEAR(f.speeds[1].linear_slope_per_s, -1.0 / pt.lifetime_s[5], 1e-15);
  EXPECT_NEAR(f.simple_static_slope_per_s, -1.0 / pt.lifetime_s[0], 1e-15);
  EXPECT_NEAR(f.simple_moving_slope_per_s, -2.0 / (pt.lifetime_s[5] + pt.lifetime_s[10]), 1e-15);
  EXPECT_FALSE(f.tables.has_value());  // only 3 of 16 speeds
}

TEST(BatteryFit, RobustLossResistsOutliers) {
  calibrate::BatteryRun r = synthetic_run(6, 0.01, 3, "x");
  for (std::size_t i = 50; i < r.charge.size(); i += 97) r.charge[i] -= 0.4;  // dropouts
  ef::FitOptions robust;
  robust.robust = true;
  robust.robust_scale = 0.03;
  // Plain least squares: every reading kept (reject_sd 0).
  const auto plain = calibrate::fit_battery({r}, {}, 0.0).speeds[0].cubic;
  const auto huber = calibrate::fit_battery({r}, robust, 0.0).speeds[0].cubic;
  const double d_true = mb::plugin_tables().cubic[6].d;
  EXPECT_LT(std::abs(huber.value("d") - d_true), std::abs(plain.value("d") - d_true));
  // The default: the dropouts (0.4 = 40 noise sd) are left out and listed, and the cubic is the
  // one fitted without them.
  const calibrate::BatteryFit rejected = calibrate::fit_battery({r});
  const std::size_t dropouts = (r.charge.size() - 50 + 96) / 97;
  EXPECT_EQ(rejected.speeds[0].outliers.size(), dropouts);
  EXPECT_LT(std::abs(rejected.speeds[0].cubic.value("d") - d_true), std::abs(huber.value("d") - d_true));
}
