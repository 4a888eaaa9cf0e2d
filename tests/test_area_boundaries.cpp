// Tests aimed at slips nobody listed (issue #22, item 6), in four areas: the firmware's speed
// cap in the drive fit, the column-unit hints of the log reader, the diagnosis's handling of the
// ToF's "no target" codes, and the reading-noise estimate from replicates. Expected values are worked by hand from the documents (the
// firmware's 1100 steps/s = 14.17 cm/s, docs/logs.md's column names and rails), with cases at the
// branch points (a name exactly at the did-you-mean limit) and per-wheel values that differ, so
// that a swap of left and right shows. The slips they were written against are listed in
// bench/fresh-slips.md.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <vector>

#include "epuck2/diagnose/diagnose.hpp"
#include "epuck2/calibrate/reading_noise.hpp"
#include "epuck2/calibrate/sensors.hpp"
#include "epuck2/logs/log.hpp"

namespace {

using epuck2::logs::InputError;
using epuck2::logs::Kind;
using epuck2::logs::parse_log;

// ----- the firmware's speed cap ------------------------------------------------------------------

// The e-puck2 firmware drives a wheel at most 1100 steps/s; with the plug-in's wheel that is
// 14.17 cm/s (README, docs/logs.md). Commands per row (left, right, cm/s), and what the robot does:
//   20, 5     -> left capped: (14.17 + 5) / 2 = 9.585 cm/s     (capped row 1)
//   -20, -20  -> both capped in reverse: -14.17                 (capped row 2)
//   5, 20     -> right capped: the same 9.585 (a swap shows)    (capped row 3)
//   14, 14    -> under the cap: 14                              (not capped)
//   -3, 16    -> right capped: (-3 + 14.17) / 2 = 5.585         (capped row 4)
TEST(FirmwareCap, EachWheelIsCappedOnItsOwnInBothDirections) {
  const std::string text =
      "# obstacle_distance_m: 0.5\n"
      "time_s,left_speed_cm_s,right_speed_cm_s,left_steps,right_steps,tof_mm\n"
      "0,20,5,0,0,500\n"
      "0.1,-20,-20,0,0,500\n"
      "0.2,5,20,0,0,500\n"
      "0.3,14,14,0,0,500\n"
      "0.4,-3,16,0,0,500\n";
  const auto log = parse_log(text, "cap.csv", Kind::drive);
  const auto run = epuck2::calibrate::drive_run_from_log(log);
  const double cap = 0.1417;  // m/s, to the 4 digits the documents give
  ASSERT_EQ(run.command_m_s.size(), 5u);
  EXPECT_NEAR(run.command_m_s[0], 0.5 * (cap + 0.05), 5e-5);
  EXPECT_NEAR(run.command_m_s[1], -cap, 5e-5);
  EXPECT_NEAR(run.command_m_s[2], 0.5 * (0.05 + cap), 5e-5);
  EXPECT_DOUBLE_EQ(run.command_m_s[3], 0.14);
  EXPECT_NEAR(run.command_m_s[4], 0.5 * (-0.03 + cap), 5e-5);
  EXPECT_EQ(run.capped_rows, 4u);
  EXPECT_TRUE(run.over_speed_limit);
  EXPECT_EQ(run.line, (std::vector<int>{3, 4, 5, 6, 7}));
}

// Exactly at the cap (1100 steps/s as the plug-in converts it) nothing is capped; 0.01 cm/s
// above, the row is counted.
TEST(FirmwareCap, TheCapItselfIsNotAnExcess) {
  const double cap_cm_s = 100.0 * epuck2::calibrate::kFirmwareSpeedLimit_m_s;
  EXPECT_NEAR(cap_cm_s, 14.17, 0.005);  // 1100 steps/s, the documents' figure
  auto run_of = [](double left, double right) {
    char row[128];
    std::snprintf(row, sizeof row, "0,%.17g,%.17g,0,0,500\n", left, right);
    return epuck2::calibrate::drive_run_from_log(
        parse_log(std::string("# obstacle_distance_m: 0.5\ntime_s,left_speed_cm_s,right_speed_cm_s,left_steps,right_steps,tof_mm\n") + row,
                  "edge.csv", Kind::drive));
  };
  EXPECT_EQ(run_of(cap_cm_s, cap_cm_s).capped_rows, 0u);
  EXPECT_EQ(run_of(-cap_cm_s, -cap_cm_s).capped_rows, 0u);
  EXPECT_EQ(run_of(cap_cm_s, cap_cm_s + 0.01).capped_rows, 1u);
  EXPECT_EQ(run_of(-cap_cm_s - 0.01, 0).capped_rows, 1u);
}

// ----- the column-unit hints ---------------------------------------------------------------------

std::string error_of(const std::string& text, Kind kind) {
  try {
    parse_log(text, "hint.csv", kind);
  } catch (const InputError& e) {
    return e.what();
  }
  return "(accepted)";
}

// A unit of two words (cm_s) is one unit: speed_mm_s is the speed in another unit, not a typo.
TEST(ColumnUnitHints, ATwoWordUnitIsNamedWhole) {
  const std::string e = error_of("time_s,speed_mm_s,charge\n0,70,1\n", Kind::battery);
  EXPECT_NE(e.find("hint.csv:1:8: "), std::string::npos) << e;
  EXPECT_NE(e.find("column 'speed_mm_s' has the unit mm_s; this column must be in cm_s"), std::string::npos) << e;
  const std::string drive = error_of("# obstacle_distance_m: 0.5\ntime_s,left_speed_m_s,right_speed_cm_s,left_steps,right_steps,tof_mm\n0,0,0,0,0,500\n",
                                     Kind::drive);
  EXPECT_NE(drive.find("hint.csv:2:8: "), std::string::npos) << drive;
  EXPECT_NE(drive.find("column 'left_speed_m_s' has the unit m_s; this column must be in cm_s"), std::string::npos) << drive;
}

// "Did you mean" only for a slip of the keyboard: at most 2 edits and fewer than half the name's
// letters. At the limit: 'pz' for 'px' is 1 edit of 2 letters (half: no suggestion); 'gr' for
// 'grey' is 2 of 4 (half: none); 'gray' for 'grey' is 1 of 4 (suggested); 'valeu' for 'value' is
// 2 of 5 (suggested).
TEST(ColumnUnitHints, DidYouMeanStopsAtHalfTheName) {
  EXPECT_EQ(error_of("forward_m,lateral_m,vertical_m,pz,py\n0.2,0,0,80,60\n", Kind::camera).find("did you mean"), std::string::npos)
      << error_of("forward_m,lateral_m,vertical_m,pz,py\n0.2,0,0,80,60\n", Kind::camera);
  EXPECT_EQ(error_of("gr,sensor,value\n0.5,0,500\n", Kind::ground).find("did you mean"), std::string::npos);
  const std::string gray = error_of("gray,sensor,value\n0.5,0,500\n", Kind::ground);
  EXPECT_NE(gray.find("hint.csv:1:1: "), std::string::npos) << gray;
  EXPECT_NE(gray.find("the header has 'gray': did you mean 'grey'?"), std::string::npos) << gray;
  const std::string valeu = error_of("grey,sensor,valeu\n0.5,0,500\n", Kind::ground);
  EXPECT_NE(valeu.find("hint.csv:1:13: "), std::string::npos) << valeu;
  EXPECT_NE(valeu.find("the header has 'valeu': did you mean 'value'?"), std::string::npos) << valeu;
}

// The hint points at the header cell's character position, not at its index.
TEST(ColumnUnitHints, TheHintPointsAtTheCellsCharacter) {
  const std::string e = error_of("sensor,value,distanse_m\n0,100,0.01\n", Kind::proximity);
  EXPECT_NE(e.find("hint.csv:1:14: "), std::string::npos) << e;  // "sensor," 7 + "value," 6 = 13 before it
  EXPECT_NE(e.find("did you mean 'distance_m'"), std::string::npos) << e;
  const std::string unit = error_of("sensor,value,distance_cm\n0,100,1\n", Kind::proximity);
  EXPECT_NE(unit.find("hint.csv:1:14: "), std::string::npos) << unit;
  EXPECT_NE(unit.find("has the unit cm; this column must be in m"), std::string::npos) << unit;
}

// ----- the diagnosis's ToF codes ------------------------------------------------------------------

// A robot standing 2.5 m from a wall: beyond the ToF's 2000 mm the VL53L0X reports "no target"
// (8190, 8191). The plug-in's model reads the 2000 mm rail there, so every ToF reading is censored
// at the high rail (none at the low one) and the plug-in's model explains them exactly: MSE 0.
TEST(DiagnosisTofCodes, CodesAreReadingsAtTheHighRail) {
  std::string log = "# obstacle_distance_m: 2.5\ntime_s,left_speed_cm_s,right_speed_cm_s,left_steps,right_steps,tof_mm\n";
  const int rows = 60;
  for (int i = 0; i < rows; ++i) log += std::to_string(i / 10.0) + ",0,0,0,0," + (i % 2 ? "8191" : "8190") + "\n";
  std::vector<epuck2::logs::Log> logs{parse_log(log, "far.csv", Kind::drive)};
  const epuck2::diagnose::Report r = epuck2::diagnose::diagnose(std::move(logs));
  EXPECT_EQ(r.censored_above, static_cast<std::size_t>(rows));
  EXPECT_EQ(r.censored_below, 0u);
  EXPECT_LT(r.heldout_mse_plugin, 1.0);
}

// ----- the reading-noise estimate from replicates -------------------------------------------------

// The pooled within-group sd, written out here apart from the code: sqrt(sum of squares about
// each group's mean / sum of (n_g - 1)).
double pooled_by_hand(const std::vector<std::vector<double>>& groups) {
  double ss = 0, dof = 0;
  for (const auto& g : groups) {
    if (g.size() < 2) continue;
    double mean = 0;
    for (double x : g) mean += x;
    mean /= static_cast<double>(g.size());
    for (double x : g) ss += (x - mean) * (x - mean);
    dof += static_cast<double>(g.size()) - 1;
  }
  return std::sqrt(ss / dof);
}

struct Readings {
  std::vector<double> values;
  std::vector<int> group, sensor;
  std::vector<bool> on_rail;
  void add(const std::vector<double>& g, int s = 0) {
    const int id = group.empty() ? 0 : group.back() + 1;
    for (double x : g) {
      values.push_back(x);
      group.push_back(id);
      sensor.push_back(s);
      on_rail.push_back(false);
    }
  }
};

// {1, 3}: 2 about the mean, 1 degree of freedom; {10, 12, 14}: 8, 2. sqrt(10 / 3) = 1.8257...
TEST(NoiseByHand, PooledSdCountsEachGroupsMean) {
  Readings r;
  r.add({1, 3});
  r.add({10, 12, 14});
  const auto p = epuck2::calibrate::pooled_replicate_sd(r.values, r.group, r.on_rail, 0.0);
  EXPECT_NEAR(p.sd, std::sqrt(10.0 / 3.0), 1e-12);
  EXPECT_EQ(p.n, 5u);
  EXPECT_EQ(p.groups, 2u);
  EXPECT_EQ(p.outliers, 0u);
}

// The second pass screens groups of fewer than kSmallGroup (10) readings only. Thirty tight pairs
// {0, 1} keep the pooled sd near 1.45, so a reading 7 from its group's median lies beyond 4 pooled
// sd (5.8) but within the wild-reading rule's 8 robust sd (the group's 1.48 MAD sd x 8 = 11.9):
// in a group of 9 it is left out, in a group of exactly 10 it stays.
TEST(NoiseByHand, TheSmallGroupRuleStopsAtTenReadings) {
  ASSERT_EQ(epuck2::calibrate::kSmallGroup, 10u);
  auto with = [](const std::vector<double>& g) {
    Readings r;
    for (int i = 0; i < 30; ++i) r.add({0, 1});
    r.add(g);
    return epuck2::calibrate::pooled_replicate_sd(r.values, r.group, r.on_rail, 0.0);
  };
  std::vector<std::vector<double>> pairs(30, std::vector<double>{0, 1});
  const std::vector<double> nine = {0, 0, 0, 0, 2, 2, 2, 2, 9};
  const auto p9 = with(nine);
  auto kept9 = pairs;
  kept9.push_back({0, 0, 0, 0, 2, 2, 2, 2});
  EXPECT_NEAR(p9.sd, pooled_by_hand(kept9), 1e-12);  // sqrt(23 / 37) = 0.7884
  EXPECT_NEAR(p9.sd, std::sqrt(23.0 / 37.0), 1e-12);
  EXPECT_EQ(p9.outliers, 1u);
  EXPECT_EQ(p9.n, 68u);
  const std::vector<double> ten = {0, 0, 0, 0, 2, 2, 2, 2, 2, 9};
  const auto p10 = with(ten);
  auto kept10 = pairs;
  kept10.push_back(ten);
  EXPECT_NEAR(p10.sd, pooled_by_hand(kept10), 1e-12);  // sqrt(79.9 / 39) = 1.4313
  EXPECT_EQ(p10.outliers, 0u);
  EXPECT_EQ(p10.n, 70u);
}

// Per sensor: each sensor's own groups. Sensor 0 reads {1, 3} (sd 1.414), sensor 1 reads
// {10, 30, 50} (sd 20): values far enough apart that a swap or a mix shows.
TEST(NoiseByHand, EachSensorGetsItsOwnReplicates) {
  Readings r;
  r.add({1, 3}, 0);
  r.add({10, 30, 50}, 1);
  const auto n = epuck2::calibrate::noise_from_replicates("value", "counts", 1.0, r.values, r.group, r.on_rail, r.sensor, 2, 0.0);
  ASSERT_EQ(n.per_sensor_sd.size(), 2u);
  EXPECT_NEAR(n.per_sensor_sd[0], std::sqrt(2.0), 1e-12);
  EXPECT_NEAR(n.per_sensor_sd[1], 20.0, 1e-12);
  EXPECT_EQ(n.per_sensor_n, (std::vector<std::size_t>{2, 3}));
  EXPECT_NEAR(n.sd, std::sqrt(802.0 / 3.0), 1e-12);
  EXPECT_EQ(n.n, 5u);
}

// An even group's median is the mean of its two middle readings. Sixty pairs {0, 1} and the group
// {0, 0, 0, 4, 4, 4} pool to sqrt(54 / 65) = 0.911, so the second pass leaves out what lies
// beyond 4 x 0.911 = 3.65 from its group's median. The median is (0 + 4) / 2 = 2: every reading is
// 2 away, all kept (the upper middle reading, 4, would put the zeros 4 away and leave them out).
TEST(NoiseByHand, AnEvenGroupsMedianIsTheMiddlePairsMean) {
  Readings r;
  for (int i = 0; i < 60; ++i) r.add({0, 1});
  r.add({0, 0, 0, 4, 4, 4});
  const auto p = epuck2::calibrate::pooled_replicate_sd(r.values, r.group, r.on_rail, 0.0);
  EXPECT_EQ(p.outliers, 0u);
  EXPECT_EQ(p.n, 126u);
  EXPECT_NEAR(p.sd, std::sqrt(54.0 / 65.0), 1e-12);
  std::vector<std::vector<double>> all(60, std::vector<double>{0, 1});
  all.push_back({0, 0, 0, 4, 4, 4});
  EXPECT_NEAR(p.sd, pooled_by_hand(all), 1e-12);
}

}  // namespace
