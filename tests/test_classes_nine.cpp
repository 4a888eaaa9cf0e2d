// Classes of round 8's survivors (bench/fresh-slips.md, "Round 8"), closed where else they can
// occur: a statistic that counts parameters or readings, a boundary a decision branches on, which
// rail a count comes from. Written from the headers' and docs' definitions before round 9's slips
// were planted; every expected value is worked by hand in its comment.
#include <gtest/gtest.h>

#include <cmath>
#include <string>
#include <vector>

#include "battery_runs.hpp"
#include "epuck2/calibrate/battery.hpp"
#include "epuck2/calibrate/plausibility.hpp"
#include "epuck2/fit/robust.hpp"
#include "epuck2/logs/log.hpp"
#include "epuck2/models/plugin_battery_tables.hpp"
#include "cli_harness.hpp"
#include <fstream>
#include <sstream>

namespace {

namespace c9_fit = epuck2::fit;

c9_fit::ReplicateGroup c9_group(std::vector<double> readings, double prediction, double condition, std::string label) {
  c9_fit::ReplicateGroup g;
  g.predictions.assign(readings.size(), prediction);
  g.readings = std::move(readings);
  g.condition = condition;
  g.label = std::move(label);
  return g;
}

// Three groups of two readings at conditions 1, 2, 3:
//   A {1, 3} predicted 2 (mean 2, miss 0), B {4, 6} predicted 4 (mean 5, miss +1),
//   C {7, 9} predicted 10 (mean 8, miss -2).
// Pure error: each group's squares about its mean are 1 + 1 = 2, so 6 on 6 - 3 = 3 dof: variance 2.
// Residuals about the predictions: A 1 + 1, B 0 + 4, C 9 + 1 = 16; lack of fit 16 - 6 = 10
// (= 2 x 0^2 + 2 x 1^2 + 2 x 2^2) on 3 groups - k dof.
std::vector<c9_fit::ReplicateGroup> c9_three_groups() {
  return {c9_group({1, 3}, 2, 1, "A"), c9_group({4, 6}, 4, 2, "B"), c9_group({7, 9}, 10, 3, "C")};
}

// F(2, d2)'s upper tail has a closed form: P(F > f) = (1 + 2 f / d2)^(-d2 / 2).
double c9_f2_tail(double f, double d2) { return std::pow(1 + 2 * f / d2, -d2 / 2); }

TEST(ClassesNineLackOfFit, OneFreeParameterByHand) {
  const c9_fit::LackOfFit lof = c9_fit::lack_of_fit(c9_three_groups(), 1);
  ASSERT_TRUE(lof.tested) << lof.why_not;
  EXPECT_EQ(lof.groups, 3u);
  EXPECT_EQ(lof.dof_pure, 3u);  // 6 readings - 3 groups
  EXPECT_EQ(lof.dof_lack, 2u);  // 3 groups - 1 parameter
  EXPECT_NEAR(lof.replicate_sd, std::sqrt(2.0), 1e-12);
  EXPECT_NEAR(lof.reduced_chi2, (10.0 / 2) / 2, 1e-12);  // 2.5
  EXPECT_NEAR(lof.p_value, c9_f2_tail(2.5, 3), 1e-9);  // (8/3)^-1.5 = 0.22964
  EXPECT_NEAR(lof.p_value, 0.229640, 1e-6);
  EXPECT_NEAR(lof.misfit_rms, std::sqrt(10.0 / 6), 1e-12);  // per reading, not per group
  EXPECT_NEAR(lof.misfit_ratio, std::sqrt(10.0 / 6) / std::sqrt(2.0), 1e-12);
  // The worst group is C (miss 2, below); B misses on the other side, so C stands alone.
  EXPECT_NE(lof.worst.find("C"), std::string::npos) << lof.worst;
  EXPECT_NE(lof.worst.find("below"), std::string::npos) << lof.worst;
}

TEST(ClassesNineLackOfFit, TwoFreeParametersLeaveOneDegreeOfFreedom) {
  // Same sums, dof_lack 3 - 2 = 1: reduced chi^2 = 10 / 2 = 5; F(1, 3) = t(3)^2, and
  // P(|t3| > sqrt 5) = 1 - (2/pi)(atan(u) + u/(1 + u^2)) with u = sqrt(5/3) (Student's t, 3 dof).
  const c9_fit::LackOfFit lof = c9_fit::lack_of_fit(c9_three_groups(), 2);
  ASSERT_TRUE(lof.tested) << lof.why_not;
  EXPECT_EQ(lof.dof_lack, 1u);
  EXPECT_NEAR(lof.reduced_chi2, 5.0, 1e-12);
  const double u = std::sqrt(5.0 / 3.0);
  EXPECT_NEAR(lof.p_value, 1 - (2 / M_PI) * (std::atan(u) + u / (1 + u * u)), 1e-9);
}

TEST(ClassesNineLackOfFit, NotTestedWhenTheGroupsDoNotOutnumberTheParameters) {
  // 3 groups and 3 free parameters: no degree of freedom for the lack of fit.
  const c9_fit::LackOfFit lof = c9_fit::lack_of_fit(c9_three_groups(), 3);
  EXPECT_FALSE(lof.tested);
  EXPECT_FALSE(lof.why_not.empty());
  // One reading per group and no known noise: no pure error to test against.
  const c9_fit::LackOfFit single =
      c9_fit::lack_of_fit({c9_group({1}, 2, 1, "A"), c9_group({5}, 4, 2, "B"), c9_group({8}, 10, 3, "C")}, 1);
  EXPECT_FALSE(single.tested);
}

TEST(ClassesNineLackOfFit, KnownNoiseReplacesThePureErrorByHand) {
  // Replicate sd 1 known on 10 dof: the pure error is that sd, and the whole residual sum (16) is
  // the lack of fit (nothing subtracted): reduced chi^2 = (16 / 2) / 1 = 8, p = (1 + 1.6)^-5;
  // misfit rms sqrt(16 / 6), ratio the same over sd 1.
  const c9_fit::LackOfFit lof = c9_fit::lack_of_fit(c9_three_groups(), 1, {}, 0.0, 1.0, 10);
  ASSERT_TRUE(lof.tested) << lof.why_not;
  EXPECT_EQ(lof.dof_pure, 10u);
  EXPECT_EQ(lof.dof_lack, 2u);
  EXPECT_NEAR(lof.replicate_sd, 1.0, 1e-12);
  EXPECT_NEAR(lof.reduced_chi2, 8.0, 1e-12);
  EXPECT_NEAR(lof.p_value, std::pow(2.6, -5.0), 1e-9);
  EXPECT_NEAR(lof.misfit_rms, std::sqrt(16.0 / 6), 1e-12);
  EXPECT_NEAR(lof.misfit_ratio, std::sqrt(16.0 / 6), 1e-12);
}

TEST(ClassesNineLackOfFit, TheFloorRaisesIdenticalReplicates) {
  // Identical replicates {2, 2}, {4, 4}, {7, 7} predicted 2, 4.5, 6.5: pure error 0, raised to the
  // floor 0.5 (variance 0.25). Misses 0, -0.5, +0.5, two readings each: lack 2 x (0.25 + 0.25) = 1
  // on 3 - 1 = 2 dof, reduced chi^2 = (1 / 2) / 0.25 = 2 against F(2, 3) (6 readings - 3 groups).
  const c9_fit::LackOfFit lof = c9_fit::lack_of_fit(
      {c9_group({2, 2}, 2, 1, "A"), c9_group({4, 4}, 4.5, 2, "B"), c9_group({7, 7}, 6.5, 3, "C")}, 1, {}, 0.5);
  ASSERT_TRUE(lof.tested) << lof.why_not;
  EXPECT_NEAR(lof.replicate_sd, 0.5, 1e-12);
  EXPECT_NEAR(lof.reduced_chi2, 2.0, 1e-12);
  EXPECT_NEAR(lof.p_value, c9_f2_tail(2.0, 3), 1e-9);
}

TEST(ClassesNineLackOfFit, SpoiltGroupsAndTheirReadingsAreLeftOut) {
  // A spoilt fourth group (wild readings) changes nothing: the same numbers as the three alone.
  auto groups = c9_three_groups();
  groups.push_back(c9_group({100, -100}, 0, 4, "D"));
  groups.back().spoilt = true;
  const c9_fit::LackOfFit lof = c9_fit::lack_of_fit(groups, 1);
  ASSERT_TRUE(lof.tested);
  EXPECT_EQ(lof.groups, 3u);
  EXPECT_EQ(lof.dof_pure, 3u);
  EXPECT_NEAR(lof.reduced_chi2, 2.5, 1e-12);
}

TEST(ClassesNineLackOfFit, TheWorstRunsOfNeighboursMissedOnTheSameSide) {
  // Misses (mean - prediction) at conditions 1..4 mm: +0.2, +1.5, +2, -0.1. The worst is 3 mm
  // (+2); 2 mm misses on the same side by at least half (1.5 >= 1), 1 mm does not (0.2), 4 mm is
  // on the other side: "distances 2-3 mm: the curve misses by 2 counts, the readings above it".
  c9_fit::MisfitWords words;
  words.conditions = "distances";
  words.condition_unit = "mm";
  words.unit = "counts";
  words.condition_scale = 1000;
  const c9_fit::LackOfFit lof = c9_fit::lack_of_fit(
      {c9_group({0.2, 0.2}, 0, 0.001, "a"), c9_group({1.5, 1.5}, 0, 0.002, "b"), c9_group({2, 2}, 0, 0.003, "c"),
       c9_group({-0.1, -0.1}, 0, 0.004, "d")},
      1, words, 0.1);
  ASSERT_TRUE(lof.tested);
  EXPECT_EQ(lof.worst, "distances 2\u20133 mm: the curve misses by 2 counts, the readings above it");
}

// ----- fit_robust's information criteria: the noise counts as a parameter when estimated -----

// A constant plus a slope held by the caller at 0.
struct C9ConstantAndHeldSlope {
  std::vector<double> x;
  template <typename T>
  bool operator()(const T* p, T* out) const {
    for (std::size_t i = 0; i < x.size(); ++i) out[i] = p[0] + p[1] * x[i];
    return true;
  }
};

std::vector<c9_fit::Observation> c9_readings(const std::vector<double>& y) {
  std::vector<c9_fit::Observation> obs;
  for (double v : y) obs.push_back({v, c9_fit::Censoring::none, "", -1});
  return obs;
}

// A free level starting at `start` and a slope held by the caller at 0.
std::vector<c9_fit::Parameter> c9_level_and_held_slope(double start) {
  std::vector<c9_fit::Parameter> p(2);
  p[0].name = "level";
  p[0].value = start;
  p[1].name = "slope";
  p[1].fixed = true;
  return p;
}

// AIC - BIC = 2 p - p ln n = p (2 - ln n) whatever the log-likelihood: the parameter count p and
// the readings n the criteria use, read back without knowing the likelihood's convention.
TEST(ClassesNineRobustCriteria, EstimatedNoiseCountsHeldSlopeDoesNot) {
  // Readings 1..5, the constant free, the slope held, sigma estimated: p = 1 + 1 (sigma), n = 5.
  const std::vector<c9_fit::Parameter> p = c9_level_and_held_slope(0.0);
  c9_fit::RobustOptions o;
  o.robust = false;
  const c9_fit::RobustFit f =
      c9_fit::fit_robust(C9ConstantAndHeldSlope{{1, 2, 3, 4, 5}}, c9_readings({1, 2, 3, 4, 5}), p, o);
  ASSERT_TRUE(f.usable) << f.message;
  EXPECT_NEAR(f.value("level"), 3.0, 1e-6);
  EXPECT_NEAR(f.value("slope"), 0.0, 0.0);
  EXPECT_EQ(f.free_parameters, 1);
  EXPECT_NEAR(f.aic - f.bic, 2 * (2 - std::log(5.0)), 1e-6);
}

TEST(ClassesNineRobustCriteria, ARejectedReadingLeavesTheCount) {
  // Readings 1..5 and a wild 1000, robust: the 1000 is left out, so n = 5 kept (not 6), p = 2.
  const std::vector<c9_fit::Parameter> p = c9_level_and_held_slope(3.0);
  const c9_fit::RobustFit f =
      c9_fit::fit_robust(C9ConstantAndHeldSlope{{1, 2, 3, 4, 5, 6}}, c9_readings({1, 2, 3, 4, 5, 1000}), p);
  ASSERT_TRUE(f.usable) << f.message;
  ASSERT_EQ(f.outliers.size(), 1u);
  EXPECT_EQ(f.outliers[0], 5u);
  EXPECT_EQ(f.observations, 5u);
  EXPECT_NEAR(f.value("level"), 3.0, 1e-4);
  EXPECT_NEAR(f.aic - f.bic, 2 * (2 - std::log(5.0)), 1e-6);
}

TEST(ClassesNineRobustCriteria, AKnownNoiseIsNotAParameter) {
  // sigma given: p = 1, n = 5.
  const std::vector<c9_fit::Parameter> p = c9_level_and_held_slope(0.0);
  c9_fit::RobustOptions o;
  o.robust = false;
  o.noise_sd = 1.0;
  const c9_fit::RobustFit f =
      c9_fit::fit_robust(C9ConstantAndHeldSlope{{1, 2, 3, 4, 5}}, c9_readings({1, 2, 3, 4, 5}), p, o);
  ASSERT_TRUE(f.usable) << f.message;
  EXPECT_NEAR(f.aic - f.bic, 1 * (2 - std::log(5.0)), 1e-6);
}

// ----- the column-unit hints: each range and each branch's denominator -----

// The message a unit check stops with, or "" when it accepts the log.
std::string c9_unit_message(const std::string& text, epuck2::logs::Kind kind) {
  const epuck2::logs::Log log = epuck2::logs::parse_log(text, "hint.csv", kind);
  try {
    epuck2::calibrate::check_plausible_units({log});
  } catch (const epuck2::logs::InputError& e) {
    return e.what();
  }
  return "";
}

std::string c9_proximity_at(double d) {
  return c9_unit_message("distance_m,sensor,value\n0.01,0,3000\n" + std::to_string(d) + ",0,100\n",
                         epuck2::logs::Kind::proximity);
}

TEST(ClassesNineUnitHints, ProximityFactorsAtEachRangesEdge) {
  // The proximity sensor sees to 0.05 m: a distance beyond 10 x 0.05 = 0.5 m stops, and the
  // unit is guessed from d / (2 x 0.05): (30, 300) centimetres, [300, 3000) millimetres.
  EXPECT_EQ(c9_proximity_at(0.5), "");                                              // 10 x, not beyond
  EXPECT_NE(c9_proximity_at(0.6).find("not metres?"), std::string::npos);          // factor 6
  EXPECT_NE(c9_proximity_at(3.0).find("not metres?"), std::string::npos);          // factor 30: not above 30
  EXPECT_NE(c9_proximity_at(3.5).find("centimetres?"), std::string::npos);         // 35
  EXPECT_NE(c9_proximity_at(29.9).find("centimetres?"), std::string::npos);        // 299
  EXPECT_NE(c9_proximity_at(30.0).find("millimetres?"), std::string::npos);        // 300
  EXPECT_NE(c9_proximity_at(299.0).find("millimetres?"), std::string::npos);       // 2990
  EXPECT_NE(c9_proximity_at(300.0).find("not metres?"), std::string::npos);        // 3000
  // The message names line 3 (the second row) and the value.
  EXPECT_NE(c9_proximity_at(3.5).find("hint.csv:3:1: distance_m reaches 3.5"), std::string::npos)
      << c9_proximity_at(3.5);
}

std::string c9_obstacle(const std::string& d, const std::string& tof_mm) {
  return c9_unit_message("# obstacle_distance_m: " + d +
                             "\ntime_s,left_speed_cm_s,right_speed_cm_s,left_steps,right_steps,tof_mm\n0,0,0,0,0," +
                             tof_mm + "\n",
                         epuck2::logs::Kind::drive);
}

TEST(ClassesNineUnitHints, AnObstacleTheToFDoesNotSeeIsJudgedAgainstItsCeiling) {
  // The ToF sees 20..2000 mm; a first reading at its 20 mm floor is no target. An obstacle at
  // "100" (beyond 10 x 2 m): 100 / 2 m = 50 -> centimetres (against the 20 mm reading it would be
  // 5000: "not metres?").
  const std::string m = c9_obstacle("100", "20");
  EXPECT_NE(m.find("obstacle_distance_m is 100: centimetres?"), std::string::npos) << m;
  // Seen at 500 mm: 100 / 0.5 = 200 -> centimetres; at 50 mm: 2000 -> millimetres.
  EXPECT_NE(c9_obstacle("100", "500").find("centimetres?"), std::string::npos) << c9_obstacle("100", "500");
  EXPECT_NE(c9_obstacle("100", "50").find("millimetres?"), std::string::npos) << c9_obstacle("100", "50");
  // 20 m is 10 x the ceiling, not beyond it; unseen: accepted.
  EXPECT_EQ(c9_obstacle("20", "2000"), "");
}

TEST(ClassesNineUnitHints, AnObstacleBeyondTheCeilingThatTheToFSeesIsRefused) {
  // 3 m is beyond the ToF's 2 m but not 10 x: refused only when the ToF sees something
  // (300 mm): 3 / 0.3 = 10 -> "not metres?"; 15 m seen at 150 mm: 100 -> centimetres.
  const std::string m = c9_obstacle("3", "300");
  EXPECT_NE(m.find("beyond the ToF's 2 m, but tof_mm reads 300 mm at line 3: not metres?"), std::string::npos) << m;
  EXPECT_NE(c9_obstacle("15", "150").find("centimetres?"), std::string::npos) << c9_obstacle("15", "150");
  // Not seen (2000 mm: the ceiling, no target): accepted.
  EXPECT_EQ(c9_obstacle("3", "2000"), "");
  // Within the ceiling: accepted.
  EXPECT_EQ(c9_obstacle("1.5", "300"), "");
}

// ----- averages over the right set: the battery's lifetimes, Simple slopes and Table 5 MSEs -----

// A run from full to empty in 1-s rows with a small fixed wiggle (tests/battery_runs.hpp).
constexpr auto* c9_run = &epuck2::testing::wiggly_battery_run;

TEST(ClassesNineBatteryAverages, LifetimesAndSimpleSlopesByHand) {
  // 0 cm/s: runs of 100 and 120 s -> lifetime 110, se sqrt((10^2 + 10^2) / 1 / 2) = 10.
  // 5 cm/s: 50 and 70 s -> 60, se 10. 10 cm/s: one run of 40 s -> 40, se 0.
  // Simple: m0 = -1/110, its se 10 / 110^2; m1 = -1/mean(60, 40) = -1/50, the mean's se
  // sqrt(10^2 + 0^2) / 2 = 5, so m1's se 5 / 50^2 = 0.002 (the static run is not a moving one).
  const std::vector<epuck2::calibrate::BatteryRun> runs{c9_run(0, 100, "a"), c9_run(0, 120, "b"), c9_run(5, 50, "a"),
                                                        c9_run(5, 70, "b"), c9_run(10, 40, "a")};
  const epuck2::calibrate::BatteryFit f = epuck2::calibrate::fit_battery(runs);
  ASSERT_EQ(f.speeds.size(), 3u);
  EXPECT_EQ(f.speeds[0].runs, 2u);
  EXPECT_NEAR(f.speeds[0].lifetime_s, 110.0, 1e-12);
  EXPECT_NEAR(f.speeds[0].lifetime_std_error_s, 10.0, 1e-12);
  EXPECT_NEAR(f.speeds[1].lifetime_s, 60.0, 1e-12);
  EXPECT_NEAR(f.speeds[1].lifetime_std_error_s, 10.0, 1e-12);
  EXPECT_NEAR(f.speeds[2].lifetime_s, 40.0, 1e-12);
  EXPECT_EQ(f.speeds[2].lifetime_std_error_s, 0.0);
  EXPECT_NEAR(f.simple_static_slope_per_s, -1.0 / 110, 1e-15);
  EXPECT_NEAR(f.simple_static_std_error, 10.0 / (110.0 * 110.0), 1e-15);
  EXPECT_NEAR(f.simple_moving_slope_per_s, -1.0 / 50, 1e-15);
  EXPECT_NEAR(f.simple_moving_std_error, 5.0 / 2500.0, 1e-15);
  // One run at 10 cm/s only: said.
  bool said = false;
  for (const std::string& w : f.warnings) said = said || w.find("one run at 10 cm/s") != std::string::npos;
  EXPECT_TRUE(said);
  // Each speed's analytic MSE is over its own runs' rows, and Table 5's is the mean over the
  // speeds (3 speeds, equal weight), not over rows (221, 122, 41 rows).
  namespace mb = epuck2::models::battery;
  for (mb::Model m : mb::kAllModels) {
    double mean_over_speeds = 0;
    for (const epuck2::calibrate::SpeedFit& s : f.speeds) {
      double ss = 0;
      std::size_t n = 0;
      for (const auto& r : runs) {
        if (r.speed_cm_s != s.speed_cm_s) continue;
        for (std::size_t i = 0; i < r.time_s.size(); ++i) {
          const double e = r.charge[i] - epuck2::calibrate::analytic_charge(s, f, m, r.time_s[i]);
          ss += e * e;
          ++n;
        }
      }
      EXPECT_NEAR(s.mse.get(m), ss / static_cast<double>(n), 1e-12 + 1e-9 * ss / static_cast<double>(n)) << s.speed_cm_s;
      mean_over_speeds += s.mse.get(m) / 3.0;
    }
    EXPECT_NEAR(f.mse.get(m), mean_over_speeds, 1e-15 + 1e-12 * mean_over_speeds);
  }
  // The Linear model's Table 5 MSE, worked apart: at 10 cm/s its line 1 - t/40 is the run's own,
  // so only the wiggle is left there: mean of (0.002 sin 1.3t)^2 over t = 0..40.
  double wiggle = 0;
  for (int t = 0; t <= 40; ++t) wiggle += std::pow(0.002 * std::sin(1.3 * t), 2) / 41.0;
  EXPECT_NEAR(f.speeds[2].mse.linear, wiggle, 1e-12);
}

// ----- options only their non-default value reaches: battery --robust's scale, simulate --dt -----

TEST(ClassesNineOptionPaths, BatteryHuberLossAndItsScaleReachTheCubic) {
  // Two runs of 100 s at 5 cm/s, charge 1 - t/100 (+-0.002 wiggle), and the readings at t = 49, 50,
  // 51 of run a off by +0.3, every reading kept (reject_sd 0). Least squares pulls the cubic towards
  // the wild readings; a Huber threshold of 0.005 weighs them linearly, pulling several times less; a
  // threshold of 1 (above every residual: charge is 0..1) is least squares exactly.
  std::vector<epuck2::calibrate::BatteryRun> runs{c9_run(5, 100, "a"), c9_run(5, 100, "b")};
  for (int t : {49, 50, 51}) runs[0].charge[static_cast<std::size_t>(t)] += 0.3;
  namespace mb = epuck2::models::battery;
  auto at50 = [&](bool robust, double scale) {
    epuck2::fit::FitOptions o;
    o.robust = robust;
    o.robust_scale = scale;
    const epuck2::calibrate::BatteryFit f = epuck2::calibrate::fit_battery(runs, o, 0.0);
    EXPECT_EQ(f.speeds.size(), 1u);
    EXPECT_TRUE(f.speeds[0].cubic.usable) << f.speeds[0].cubic.message;
    return epuck2::calibrate::analytic_charge(f.speeds[0], f, mb::Model::cubic, 50.0);
  };
  const double truth = 0.5;
  const double ls = at50(false, 1.0), huber = at50(true, 0.005), wide = at50(true, 1.0);
  EXPECT_GT(std::abs(ls - truth), 0.003) << ls;  // the wild reading moves a least-squares cubic
  EXPECT_LT(std::abs(huber - truth), std::abs(ls - truth) / 4) << huber << " vs " << ls;
  EXPECT_NEAR(wide, ls, 1e-9);
}

class ClassesNineSimulateDt : public epuck2::testing::CliTest {};

TEST_F(ClassesNineSimulateDt, TheTickSetsTheRowsNotTheCharge) {
  // A profile of 5 cm/s for 10 s, then 10 cm/s to 20 s: the Linear model (the plug-in's tables,
  // the corrected behaviour) loses m5 per second then m10, so the charge at 20 s is 1 + 10 m5 + 10 m10 whatever
  // the tick, and --dt 2.5 writes the rows 0, 2.5, ..., 20 (9), each step 2.5 m at its speed.
  const std::string profile = write("profile.csv", "time_s,speed_cm_s\n0,5\n10,10\n20,0\n");
  const double m5 = epuck2::models::battery::plugin_tables().linear_slope_per_s[5];
  const double m10 = epuck2::models::battery::plugin_tables().linear_slope_per_s[10];
  ASSERT_LT(m5, 0.0);
  ASSERT_NE(m5, m10);
  for (const std::string dt : {"2.5", "0.5"}) {
    const epuck2::testing::CliRun r = run("simulate battery --model linear --profile \"" + profile + "\" --coefficients plugin --dt " + dt);
    ASSERT_EQ(r.exit_code, 0) << r.err;
    std::istringstream in(r.out);
    std::string line;
    std::vector<std::pair<double, double>> rows;
    while (std::getline(in, line)) {
      if (line.empty() || line[0] == '#' || line.rfind("time_s", 0) == 0) continue;
      const auto comma = line.find(',');
      rows.emplace_back(std::stod(line.substr(0, comma)), std::stod(line.substr(comma + 1)));
    }
    const double step = std::stod(dt);
    ASSERT_EQ(rows.size(), static_cast<std::size_t>(std::lround(20 / step)) + 1) << dt << r.out;
    for (std::size_t k = 0; k < rows.size(); ++k) {
      const double t = static_cast<double>(k) * step;
      EXPECT_NEAR(rows[k].first, t, 1e-9) << dt;
      const double want = t <= 10 ? 1 + m5 * t : 1 + 10 * m5 + m10 * (t - 10);
      EXPECT_NEAR(rows[k].second, want, 1e-12) << dt << " at " << t;
    }
  }
}

}  // namespace
