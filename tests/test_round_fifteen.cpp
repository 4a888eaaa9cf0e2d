// Round 15 of the fresh slips (bench/fresh-slips.md): a test for each behaviour its slips changed
// that no test had pinned down. Every expected value comes from the docs or the paper, or is worked
// by hand in the comment beside it, never from the code under test.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <sstream>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "cli_harness.hpp"
#include "hand_logs.hpp"
#include "epuck2/coefficients/model_sets.hpp"
#include "epuck2/fit/replicates.hpp"
#include "epuck2/logs/json_location.hpp"
#include "epuck2/models/encoders.hpp"
#include "epuck2/models/proximity.hpp"

namespace test_round_fifteen_cpp {

namespace fs = std::filesystem;
using epuck2::testing::CliTest;
using epuck2::testing::slurp;
using nlohmann::json;
namespace ms = epuck2::models::sensors;

class RoundFifteenCli : public CliTest {
 protected:
  std::string q(const std::string& name) const { return "\"" + (dir_ / name).string() + "\""; }
};

// ---- lib/models ----------------------------------------------------------------------------

// The int16 registers wrap both ways (docs/logs.md: left_steps, right_steps are 16-bit counts).
// Forwards: 32000 then -32000 is 1536 steps on (32767 -> -32768 is one step): 33536. Backwards:
// -32000 then 32000 is 1536 steps back: -33536.
TEST(RoundFifteenModels, TheEncoderRegisterUnwrapsAcrossItsRailBothWays) {
  EXPECT_EQ(ms::unwrap_steps(std::vector<double>{32000, -32000}), (std::vector<double>{32000, 33536}));
  EXPECT_EQ(ms::unwrap_steps(std::vector<double>{-32000, 32000}), (std::vector<double>{-32000, -33536}));
  EXPECT_EQ(ms::unwrap_steps(std::vector<double>{32767, -32768, -32767}), (std::vector<double>{32767, 32768, 32769}));
  EXPECT_EQ(ms::unwrap_steps(std::vector<double>{0, 100, 50}), (std::vector<double>{0, 100, 50}));
}

// Eq. 1 is clamped to [0, 1] before the effects are added (docs/diagnose.md, proximity: the base
// is 4095 clamp01(a d^2 + b d + c), the plug-in's): a = 0, b = -30 /m, c = 1 at 0.05 m is
// 1 - 1.5 = -0.5, clamped to 0, so the mean reading is the ambient offset alone, 100 counts; at
// 0.02 m it is 0.4: 100 + 0.4 x 4095.
TEST(RoundFifteenModels, TheProximityMeanClampsANegativeCurveToZero) {
  ms::ProximityCoefficients k;
  k.a_per_m2 = 0.0;
  k.b_per_m = -30.0;
  k.c = 1.0;
  k.range_m = 0.05;
  ms::ProximityEffects<double> e;
  e.ambient.offset_raw = 100.0;
  EXPECT_DOUBLE_EQ(ms::proximity_mean_raw(k, e, 0, 0.05), 100.0);
  EXPECT_NEAR(ms::proximity_mean_raw(k, e, 0, 0.02), 100.0 + 0.4 * 4095.0, 1e-9);
}

// ---- lib/fit: wild replicates ---------------------------------------------------------------

// docs/fitting.md: a reading farther than 8 robust sd (1.4826 MAD, at least the floor) from its
// group's median is wild. One group of readings 1000, 1000, 1000, X: the MAD is 0, so the sd is
// the floor, 1. X = 1007 is 7 sd off: kept; X = 1009 is 9 sd off: wild.
TEST(RoundFifteenFit, AReadingIsWildBeyondEightRobustSd) {
  const std::vector<int> one{0, 0, 0, 0};
  const std::vector<bool> no_rail(4, false);
  EXPECT_EQ(epuck2::fit::flag_wild_replicates({1000, 1000, 1000, 1007}, one, no_rail, 1.0), (std::vector<bool>{false, false, false, false}));
  EXPECT_EQ(epuck2::fit::flag_wild_replicates({1000, 1000, 1000, 1009}, one, no_rail, 1.0), (std::vector<bool>{false, false, false, true}));
}

// Group 0 is a group like any other (the header: -1 means none): the first group's glitch is wild
// as the second's is. Readings 1000, 1002, 998, 1001, 3000: median 1001, MAD 1 (deviations 1, 1,
// 3, 0, 1999), sd 1.4826: 3000 is ~1348 sd off.
TEST(RoundFifteenFit, TheFirstGroupIsScreenedToo) {
  const std::vector<double> v{1000, 1002, 998, 1001, 3000};
  const std::vector<bool> no_rail(5, false);
  EXPECT_EQ(epuck2::fit::flag_wild_replicates(v, {0, 0, 0, 0, 0}, no_rail, 1.0), (std::vector<bool>{false, false, false, false, true}));
  EXPECT_EQ(epuck2::fit::flag_wild_replicates(v, {1, 1, 1, 1, 1}, no_rail, 1.0), (std::vector<bool>{false, false, false, false, true}));
  // two groups, the glitch in group 0 only
  const std::vector<double> w{1000, 1002, 998, 3000, 500, 501, 499, 500};
  EXPECT_EQ(epuck2::fit::flag_wild_replicates(w, {0, 0, 0, 0, 1, 1, 1, 1}, std::vector<bool>(8, false), 1.0),
            (std::vector<bool>{false, false, false, true, false, false, false, false}));
}

// ---- lib/logs: JSON pointer escapes (RFC 6901: ~1 is '/', ~0 is '~') --------------------------

TEST(RoundFifteenLogs, AJsonPointerUnescapesTildeOneAsSlashAndTildeZeroAsTilde) {
  // {"a/b": 1, "c~d": 2}: the 1 at character 9, the 2 at character 19 (1-based)
  const std::string text = R"({"a/b": 1, "c~d": 2})";
  const auto slash = epuck2::logs::locate_json_pointer(text, "/a~1b");
  EXPECT_EQ(slash.line, 1);
  EXPECT_EQ(slash.column, 9);
  const auto tilde = epuck2::logs::locate_json_pointer(text, "/c~0d");
  EXPECT_EQ(tilde.line, 1);
  EXPECT_EQ(tilde.column, 19);
}

// ---- lib/coefficients: robot_map patterns ---------------------------------------------------

// docs/argos.md: robot_map="PATTERN:ID,..." where '*' matches any run of characters and the first
// match wins. "ep1" has no '*': it matches ep1 only, so ep10 falls to "ep*".
TEST(RoundFifteenCoefficients, ARobotMapPatternWithoutStarMatchesTheWholeId) {
  json root = json::parse(slurp(fs::path(EPUCK2_SOURCE_DIR) / "data" / "fitted" / "proximity.json"));
  const json params = root.at("parameters");
  root["robots"] = {{"robot-a", {{"parameters", params}}}, {"robot-b", {{"parameters", params}}}};
  const std::string map = "ep0:robot-a,ep1:robot-a,ep*:robot-b";
  EXPECT_EQ(epuck2::coefficients::choose_robot(root, "p.json", "auto", map, "ep10").robot, "robot-b");
  EXPECT_EQ(epuck2::coefficients::choose_robot(root, "p.json", "auto", map, "ep1").robot, "robot-a");
  EXPECT_EQ(epuck2::coefficients::choose_robot(root, "p.json", "auto", map, "ep0").robot, "robot-a");
  EXPECT_EQ(epuck2::coefficients::choose_robot(root, "p.json", "auto", map, "ep00").robot, "robot-b");
}

// ---- the calibrations ------------------------------------------------------------------------

/// A proximity log by hand: sensors 0..`sensors`-1, distances 5, 10, ..., `last_mm` mm from
/// Eq. 1 with a = 200, b = -30, c = 1.1 (4095 (200 d^2 - 30 d + 1.1), e.g. 409.5 at 50 mm), then
/// (`beyond`) 60 mm reading 60 counts (detected: >= 41) and 70 mm reading 5 (not detected); six
/// readings each with a jitter {-2, 1, 0, 2, -1, 0} (sd sqrt(10/5) = 1.414 counts). Distances
/// are written times `scale` (100: centimetres).
std::string proximity_log(int sensors, int last_mm, bool beyond, double scale = 1.0) {
  const int jitter[6] = {-2, 1, 0, 2, -1, 0};
  std::ostringstream o;
  o << "# robot: hand-made\ndistance_m,sensor,value\n";
  auto rows = [&](double d, int base) {
    for (int s = 0; s < sensors; ++s)
      for (int k = 0; k < 6; ++k) o << d * scale << ',' << s << ',' << base + jitter[k] << '\n';
  };
  for (int mm = 5; mm <= last_mm; mm += 5) {
    const double d = mm / 1000.0;
    rows(d, static_cast<int>(std::lround(4095.0 * (200 * d * d - 30 * d + 1.1))));
  }
  if (beyond) {
    rows(0.06, 60);
    rows(0.07, 5);
  }
  return o.str();
}

// docs/fitting.md, "range": detected at 60 mm, not at 70 mm: the range is their middle, 65 mm,
// with the standard error of a value uniform between them, 10 mm / sqrt(12) = 2.887 mm.
TEST_F(RoundFifteenCli, TheProximityRangeLiesBetweenTheLastDetectedAndTheNextDistance) {
  const std::string log = write("p.csv", proximity_log(4, 50, true));
  const auto r = run("proximity \"" + log + "\" -o " + q("p.json"));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const json j = json::parse(slurp(dir_ / "p.json"));
  const json& range = j.at("range_fit");
  EXPECT_DOUBLE_EQ(range.at("detected_to_m").get<double>(), 0.06);
  EXPECT_DOUBLE_EQ(range.at("undetected_from_m").get<double>(), 0.07);
  EXPECT_NEAR(range.at("value_m").get<double>(), 0.065, 1e-12);
  EXPECT_NEAR(range.at("std_error_m").get<double>(), 0.01 / std::sqrt(12.0), 1e-12);
  EXPECT_FALSE(range.at("lower_bound").get<bool>());
}

// The report's per-sensor noise line lists the sensors that have readings, each with its count:
// sensors 0..3, 12 distances x 6 readings = 72 each, sd sqrt(2) = 1.414; sensors 4..7 have none
// and take the pooled sd (named as such, not listed with "(0)"). Without replicates, no such line.
TEST_F(RoundFifteenCli, TheNoiseLineListsOnlySensorsWithReadings) {
  const std::string log = write("p.csv", proximity_log(4, 50, true));
  const auto r = run("proximity \"" + log + "\"");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.out.find("per sensor (readings): sensor 0: 1.414 (72), sensor 1: 1.414 (72), sensor 2: 1.414 (72), "
                       "sensor 3: 1.414 (72); sensors without readings take the pooled sd"),
            std::string::npos)
      << r.out;
  EXPECT_EQ(r.out.find("sensor 4:"), std::string::npos) << r.out;
  EXPECT_EQ(r.out.find("(0)"), std::string::npos) << r.out;
  // One reading per distance and sensor: no replicates, the noise comes from the residuals, pooled,
  // and no sensor has replicate readings to list.
  std::ostringstream single;
  single << "# robot: hand-made\ndistance_m,sensor,value\n";
  const int jitter[8] = {-2, 1, 0, 2, -1, 0, 1, -1};
  for (int i = 1; i <= 10; ++i)
    for (int s = 0; s < 8; ++s) {
      const double d = 0.005 * i;
      single << d << ',' << s << ',' << std::lround(4095.0 * (200 * d * d - 30 * d + 1.1)) + jitter[(i + s) % 8] << '\n';
    }
  const auto u = run("proximity \"" + write("single.csv", single.str()) + "\"");
  ASSERT_EQ(u.exit_code, 0) << u.err;
  EXPECT_NE(u.out.find("Reading noise (proximity): sd "), std::string::npos) << u.out;
  EXPECT_NE(u.out.find("from residuals"), std::string::npos) << u.out;
  EXPECT_EQ(u.out.find("per sensor (readings)"), std::string::npos) << u.out;
}

// docs/fitting.md: a proximity distance beyond 10 x the sensor's 0.05 m ray (0.5 m) is refused,
// naming the likely unit. The log in centimetres (0.5 ... 4.5): 4.5 "m" is 9 times the limit.
TEST_F(RoundFifteenCli, AProximityLogInCentimetresIsRefusedBeyondTenTimesTheRay) {
  const std::string log = write("cm.csv", proximity_log(2, 45, false, 100.0));
  const auto r = run("proximity \"" + log + "\" -o " + q("cm.json"));
  EXPECT_EQ(r.exit_code, 2) << r.err;
  EXPECT_NE(r.err.find("distance_m reaches 4.5: centimetres?"), std::string::npos) << r.err;
  EXPECT_FALSE(fs::exists(dir_ / "cm.json"));
  // in metres, the same log calibrates
  const auto m = run("proximity \"" + write("m.csv", proximity_log(2, 45, false)) + "\" -o " + q("m.json"));
  EXPECT_EQ(m.exit_code, 0) << m.err;
}


// The camera's coefficient file holds the fitted image centre, column and row apart: made with
// (80, 60) and a mean jitter of +0.2 px on each axis, cx and cy come out within a pixel of their
// truths, so 20 px apart (the row is never the column).
TEST_F(RoundFifteenCli, TheCameraFileKeepsTheCentresRowApartFromItsColumn) {
  const auto r = run("camera \"" + write("c.csv", epuck2::testing::hand_camera_log()) + "\" -o " + q("c.json"));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const json p = json::parse(slurp(dir_ / "c.json")).at("parameters");
  EXPECT_NEAR(p.at("cx_px").get<double>(), 80.0, 1.0);
  EXPECT_NEAR(p.at("cy_px").get<double>(), 60.0, 1.0);
  EXPECT_NEAR(p.at("fov_deg").get<double>(), 60.0, 1.0);
}

// ---- battery reports -------------------------------------------------------------------------

// The paper's Table 5 (analytic row: simple 0.0221, linear 0.0170, cubic 0.0020, approximated
// 0.0025; ARGoS row: 0.0216, 0.0167, 0.0019, 0.0023), printed by `table5` in the paper's column
// order (docs/battery-models.md).
TEST_F(RoundFifteenCli, Table5PrintsThePapersRowsInItsColumnOrder) {
  const auto r = run("table5" + epuck2::testing::shipped_args("battery"));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  auto row_of = [&](const std::string& label) {
    const std::size_t at = r.out.find(label);
    if (at == std::string::npos) return std::vector<double>{};
    std::istringstream in(r.out.substr(at + label.size(), r.out.find('\n', at) - at - label.size()));
    std::vector<double> v;
    for (double x; in >> x;) v.push_back(x);
    return v;
  };
  EXPECT_EQ(row_of("paper, analytic"), (std::vector<double>{0.0221, 0.0170, 0.0020, 0.0025})) << r.out;
  EXPECT_EQ(row_of("paper, ARGoS"), (std::vector<double>{0.0216, 0.0167, 0.0019, 0.0023})) << r.out;
}

// charge(t) = d + c t + b t^2 + a t^3 (paper Eq. 4): d is a charge, c charge/s, b charge/s^2,
// a charge/s^3. The battery report states each coefficient in its unit.
TEST_F(RoundFifteenCli, TheBatteryReportGivesEachCubicCoefficientItsUnit) {
  const auto r = run("battery" + epuck2::testing::shipped_args("battery"));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  for (const auto& [name, unit] : std::vector<std::pair<std::string, std::string>>{
           {"    d = ", " charge"}, {"    c = ", " charge/s "}, {"    b = ", " charge/s² "}, {"    a = ", " charge/s³ "}}) {
    const std::size_t at = r.out.find(name);
    ASSERT_NE(at, std::string::npos) << name << "\n" << r.out;
    const std::string line = r.out.substr(at, r.out.find('\n', at) - at);
    EXPECT_NE(line.find(unit), std::string::npos) << "\"" << line << "\" lacks \"" << unit << "\"";
  }
}

// ---- the diagnosis ---------------------------------------------------------------------------

/// A light log by hand (Eq. 2, gamma 0.1 m, intensity 0.5, as test_like_checks'), with sensor
/// `odd` reading through a gain of 0.8: 4095 (1 - 0.8 (0.05/d)^2).
std::string light_log_with_gain(int odd) {
  const int jitter[6] = {-2, 1, 0, 2, -1, 0};
  std::ostringstream o;
  o << "# robot: hand-made\ndistance_m,intensity,sensor,value\n";
  for (int i = 0; i <= 8; ++i) {
    const double d = 0.10 + 0.05 * i;
    for (int s = 0; s < 8; ++s)
      for (int k = 0; k < 6; ++k)
        o << d << ",0.5," << s << ','
          << std::lround(4095.0 * (1.0 - (s == odd ? 0.8 : 1.0) * std::pow(0.05 / d, 2))) + jitter[k] << '\n';
  }
  return o.str();
}

// A per-sensor parameter is named by the sensor's number as the logs number it (0..7): sensor 2
// reading through a gain of 0.8 is found as sensor_gain's gains[2] = 0.8, in the report and the
// JSON's findings (element 2 of gains).
TEST_F(RoundFifteenCli, APerSensorParameterIsNamedByTheLogsSensorNumber) {
  const std::string log = write("l.csv", light_log_with_gain(2));
  const auto r = run("diagnose \"" + log + "\" -o " + q("d.json"));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const json j = json::parse(slurp(dir_ / "d.json"));
  bool found = false;
  for (const json& f : j.at("findings"))
    if (f.at("cause") == "sensor_gain") {
      found = true;
      const json& g = f.at("parameters").at("gains");
      ASSERT_EQ(g.size(), 8u);
      ASSERT_TRUE(g[2].is_number()) << g.dump();
      EXPECT_NEAR(g[2].get<double>(), 0.8, 0.01) << g.dump();
    }
  EXPECT_TRUE(found) << j.at("findings").dump();
  const auto t = run("diagnose \"" + log + "\"");
  // the report: gains[2] = 0.7998 (to its five digits), and no sensor numbered 8
  EXPECT_NE(t.out.find("gains[2] = 0.799"), std::string::npos) << t.out;
  EXPECT_EQ(t.out.find("gains[8]"), std::string::npos) << t.out;
}

/// A drive log by hand: the robot stands still (speeds 0, steps 0) with the obstacle at
/// `obstacle_m`; the ToF reads it +- 2 mm, but rows 50, 120, 170 read the "no target" code 8190.
std::string still_drive_log(double obstacle_m) {
  const int jitter[8] = {-2, 0, 1, 2, -1, 0, 1, -2};
  std::ostringstream o;
  o << "# robot: hand-made\n# obstacle_distance_m: " << obstacle_m << "\ntime_s,left_speed_cm_s,right_speed_cm_s,left_steps,right_steps,tof_mm\n";
  for (int i = 0; i < 200; ++i) {
    const long tof = (i == 50 || i == 120 || i == 170) ? 8190 : std::lround(obstacle_m * 1000) + jitter[i % 8];
    o << i / 10.0 << ",0,0,0,0," << tof << '\n';
  }
  return o.str();
}

// docs/fitting.md and docs/diagnose.md: a "no target" code is a dropout when the encoders put the
// obstacle within 1800 mm (90 % of the 2000 mm ceiling); beyond, it is a reading past the ceiling,
// kept and censored. At 1.95 m: no dropout, 3 censored at the high rail; at 1.0 m: 3 dropouts,
// named at file lines 54, 124, 174 (three lines before the data: data row i, from 0, is on line
// i + 4; rows 50, 120, 170).
TEST_F(RoundFifteenCli, ANoTargetCodeIsADropoutOnlyWithinNinetyPercentOfTheCeiling) {
  const std::string far = write("far.csv", still_drive_log(1.95));
  const auto f = run("diagnose \"" + far + "\"");
  ASSERT_EQ(f.exit_code, 0) << f.err;
  EXPECT_EQ(f.err.find("dropout"), std::string::npos) << f.err;
  EXPECT_NE(f.out.find("3 at or above the high one"), std::string::npos) << f.out;
  const std::string near = write("near.csv", still_drive_log(1.0));
  const auto n = run("diagnose \"" + near + "\"");
  ASSERT_EQ(n.exit_code, 0) << n.err;
  EXPECT_NE(n.err.find("3 ToF \"no target\" codes (>= 8190) where the encoders put the obstacle within 1800 mm: dropouts"),
            std::string::npos)
      << n.err;
  EXPECT_NE(n.err.find(near + ":54, " + near + ":124, " + near + ":174"), std::string::npos) << n.err;
}

// ---- apps ------------------------------------------------------------------------------------

// docs/cli.md: `-o -` writes the coefficient file to standard output, and that file alone: the
// output parses as one JSON document (the report goes nowhere).
TEST_F(RoundFifteenCli, DashOWritesTheFileAloneToStandardOutput) {
  const auto r = run("ground" + epuck2::testing::shipped_args("ground") + " -o -");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  json j;
  ASSERT_NO_THROW(j = json::parse(r.out)) << r.out.substr(0, 300);
  EXPECT_EQ(j.at("kind"), "ground");
}

// codegen's inputs must exist and be files: a usage error (exit 2) from the option check, before
// any reading.
TEST_F(RoundFifteenCli, CodegenRefusesAMissingFileOrAFolderAsItsInput) {
  const auto missing = run("codegen " + q("missing.json") + " -o " + q("h.hpp"));
  EXPECT_EQ(missing.exit_code, 2) << missing.err;
  EXPECT_NE(missing.err.find("File does not exist"), std::string::npos) << missing.err;
  fs::create_directories(dir_ / "folder");
  const auto folder = run("codegen " + q("folder") + " -o " + q("h.hpp"));
  EXPECT_EQ(folder.exit_code, 2) << folder.err;
  EXPECT_NE(folder.err.find("directory"), std::string::npos) << folder.err;
  EXPECT_FALSE(fs::exists(dir_ / "h.hpp"));
}

}  // namespace test_round_fifteen_cpp
