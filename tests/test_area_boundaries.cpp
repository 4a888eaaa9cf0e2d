// Tests aimed at slips nobody listed (issue #22, item 6), in three areas: the firmware's speed
// cap in the drive fit, the column-unit hints of the log reader, and the diagnosis's handling of
// the ToF's "no target" codes. Expected values are worked by hand from the documents (the
// firmware's 1100 steps/s = 14.17 cm/s, docs/logs.md's column names and rails), with cases at the
// branch points (a name exactly at the did-you-mean limit) and per-wheel values that differ, so
// that a swap of left and right shows. The slips they were written against are listed in
// bench/fresh-slips.md.
#include <gtest/gtest.h>

#include "epuck2/diagnose/diagnose.hpp"
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

}  // namespace
