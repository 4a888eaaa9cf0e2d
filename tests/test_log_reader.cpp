// The log reader's tolerances for what real E-Puck2 loggers write, and the locations of its
// errors: each variation parses to the numbers written in the literal CSV below, each refusal
// throws InputError at the line and column counted by hand, and the real binary (EPUCK2_FIT_EXE)
// takes or refuses the same files with exit 0 or 2 and file:line:column on standard error.
#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>
#include <vector>

#include "cli_harness.hpp"
#include "epuck2/calibrate/battery_json.hpp"
#include "epuck2/coefficients/model_file.hpp"
#include "epuck2/calibrate/sensors.hpp"
#include "epuck2/logs/json_location.hpp"
#include "epuck2/logs/log.hpp"

namespace fs = std::filesystem;
namespace logs = epuck2::logs;
using logs::InputError;
using logs::Kind;

namespace {

/// The InputError parse_log throws (fails the test when it throws none).
InputError error_of_reader(const std::string& csv, std::optional<Kind> kind, const logs::ReadOptions& options = {}) {
  try {
    logs::parse_log(csv, "t.csv", kind, options);
  } catch (const InputError& e) {
    return e;
  }
  ADD_FAILURE() << "expected an InputError for:\n" << csv;
  return InputError("none", -1, -1, "none");
}

bool contains(const std::string& text, const std::string& part) { return text.find(part) != std::string::npos; }

const std::string kDriveHeader = "time_s,left_speed_cm_s,right_speed_cm_s,left_steps,right_steps,tof_mm\n";

}  // namespace

// ---- 1. A trailing delimiter ---------------------------------------------------------------

TEST(LogReader, TrailingDelimiterOnEveryLineIsAccepted) {
  const auto log = logs::parse_log("distance_m,sensor,value,\n0.02,0,1971,\n0.03,1,1500,\n0.04,2,900\n", "t.csv",
                                   Kind::proximity);
  ASSERT_EQ(log.rows(), 3u);
  EXPECT_EQ(log.columns, (std::vector<std::string>{"distance_m", "sensor", "value"}));
  EXPECT_EQ(log.col("distance_m"), (std::vector<double>{0.02, 0.03, 0.04}));
  EXPECT_EQ(log.col("sensor"), (std::vector<double>{0, 1, 2}));
  EXPECT_EQ(log.col("value"), (std::vector<double>{1971, 1500, 900}));
  // CRLF and a trailing delimiter together.
  const auto crlf = logs::parse_log("grey,sensor,value,\r\n0.5,1,512,\r\n", "t.csv", Kind::ground);
  EXPECT_EQ(crlf.col("value"), (std::vector<double>{512}));
}

TEST(LogReader, AnEmptyColumnNameInsideTheHeaderIsStillRefused) {
  const InputError e = error_of_reader("distance_m,,sensor,value\n0.02,,0,1971\n", Kind::proximity);
  EXPECT_EQ(e.line(), 1);
  EXPECT_EQ(e.column(), 12);
  EXPECT_TRUE(contains(e.message(), "empty column name")) << e.what();
  // Two trailing delimiters are one empty column too many.
  const InputError two = error_of_reader("grey,sensor,value,,\n0.5,1,512,,\n", Kind::ground);
  EXPECT_EQ(two.line(), 1);
  EXPECT_EQ(two.column(), 19);
}

// ---- 2. Header names in any letter case ------------------------------------------------------

TEST(LogReader, HeaderNamesInAnyLetterCase) {
  const auto log = logs::parse_log("# Robot: R7\nDistance_m,SENSOR,Value,Surface\n0.02,3,1971,White\n", "t.csv");
  EXPECT_EQ(log.kind, Kind::proximity);  // recognised from the columns whatever their case
  EXPECT_EQ(log.col("distance_m"), (std::vector<double>{0.02}));
  EXPECT_EQ(log.col("sensor"), (std::vector<double>{3}));
  EXPECT_EQ(log.col("value"), (std::vector<double>{1971}));
  EXPECT_EQ(log.text.at("surface"), (std::vector<std::string>{"White"}));  // the cells keep their case
  EXPECT_EQ(log.robot, "R7");
  const auto upper = logs::parse_log("TIME_S,SPEED_CM_S,CHARGE\n0,5,1\n10,5,0.99\n", "t.csv", Kind::battery);
  EXPECT_EQ(upper.col("charge"), (std::vector<double>{1, 0.99}));
}

TEST(LogReader, ANameTwiceInDifferentCaseIsRefused) {
  const InputError e = error_of_reader("distance_m,Distance_M,sensor,value\n0.02,0.02,0,1971\n", Kind::proximity);
  EXPECT_EQ(e.line(), 1);
  EXPECT_EQ(e.column(), 12);
  EXPECT_TRUE(contains(e.message(), "appears twice")) << e.what();
  EXPECT_TRUE(contains(e.message(), "letter case")) << e.what();
}

// ---- 3. ToF out-of-range codes -----------------------------------------------------------------

TEST(LogReader, TofOutOfRangeCodesAreKeptAsRead) {
  EXPECT_EQ(logs::kTofOutOfRangeCode_mm, 8190.0);
  EXPECT_TRUE(logs::is_tof_out_of_range(8190));
  EXPECT_TRUE(logs::is_tof_out_of_range(8191));
  EXPECT_FALSE(logs::is_tof_out_of_range(8189.5));
  EXPECT_FALSE(logs::is_tof_out_of_range(2000));
  const auto log = logs::parse_log("# obstacle_distance_m: 2.5\n" + kDriveHeader +
                                       "0,5,5,0,0,8190\n0.1,5,5,38,38,8191\n0.2,5,5,77,77,1990\n",
                                   "t.csv", Kind::drive);
  EXPECT_EQ(log.col("tof_mm"), (std::vector<double>{8190, 8191, 1990}));
}

TEST(LogReader, TofBetweenTheRangeAndTheCodeIsStillRefused) {
  // Line 3 is "0.1,5,5,38,38,2500": tof_mm starts at character 15.
  const InputError e = error_of_reader("# obstacle_distance_m: 0.3\n" + kDriveHeader + "0,5,5,0,0,300\n0.1,5,5,38,38,2500\n",
                                Kind::drive);
  EXPECT_EQ(e.line(), 4);
  EXPECT_EQ(e.column(), 15);
  EXPECT_TRUE(contains(e.message(), "8190")) << e.what();
  const InputError low = error_of_reader("# obstacle_distance_m: 0.3\n" + kDriveHeader + "0,5,5,0,0,19\n", Kind::drive);
  EXPECT_EQ(low.line(), 3);
  EXPECT_EQ(low.column(), 11);
}

// ---- 4. obstacle_distance_m: 0 -----------------------------------------------------------------

TEST(LogReader, ObstacleDistanceZeroIsAccepted) {
  const auto log = logs::parse_log("# obstacle_distance_m: 0\n" + kDriveHeader + "0,-5,-5,0,0,20\n", "t.csv", Kind::drive);
  EXPECT_EQ(log.metadata_number("obstacle_distance_m"), 0.0);
  // Metadata keys in any letter case.
  const auto upper = logs::parse_log("# Obstacle_Distance_M: 0.25\n" + kDriveHeader + "0,5,5,0,0,250\n", "t.csv", Kind::drive);
  EXPECT_EQ(upper.metadata_number("obstacle_distance_m"), 0.25);
}

TEST(LogReader, NegativeObstacleDistanceIsRefusedAtItsLine) {
  // "# obstacle_distance_m: -0.1": the value starts at character 24 of line 2.
  const InputError e = error_of_reader("# robot: r1\n# obstacle_distance_m: -0.1\n" + kDriveHeader + "0,5,5,0,0,300\n", Kind::drive);
  EXPECT_EQ(e.line(), 2);
  EXPECT_EQ(e.column(), 24);
  EXPECT_TRUE(contains(e.message(), ">= 0")) << e.what();
}

// ---- 5. A missing column with a close name -------------------------------------------------------

TEST(LogReader, MissingColumnWithAnotherUnitSaysSo) {
  const InputError e = error_of_reader("sensor,distance_mm,value\n0,20,1971\n", Kind::proximity);
  EXPECT_EQ(e.line(), 1);
  EXPECT_EQ(e.column(), 8);  // where distance_mm is
  EXPECT_TRUE(contains(e.message(), "missing required column 'distance_m'")) << e.what();
  EXPECT_TRUE(contains(e.message(), "column 'distance_mm' has the unit mm; this column must be in m")) << e.what();
  const InputError ms = error_of_reader("# robot: r\ntime_ms,speed_cm_s,charge\n0,5,1\n", Kind::battery);
  EXPECT_EQ(ms.line(), 2);
  EXPECT_EQ(ms.column(), 1);
  EXPECT_TRUE(contains(ms.message(), "column 'time_ms' has the unit ms; this column must be in s")) << ms.what();
  const InputError none = error_of_reader("distance,sensor,value\n0.02,0,1971\n", Kind::proximity);
  EXPECT_TRUE(contains(none.message(), "column 'distance' has no unit; this column must be in m")) << none.what();
}

TEST(LogReader, MissingColumnWithATypoGetsDidYouMean) {
  const InputError e = error_of_reader("sensor,value,distnace_m\n0,1971,0.02\n", Kind::proximity);
  EXPECT_EQ(e.line(), 1);
  EXPECT_EQ(e.column(), 14);
  EXPECT_TRUE(contains(e.message(), "did you mean 'distance_m'?")) << e.what();
  const InputError plural = error_of_reader("grey,sensors,value\n0.5,1,512\n", Kind::ground);
  EXPECT_EQ(plural.column(), 6);
  EXPECT_TRUE(contains(plural.message(), "the header has 'sensors': did you mean 'sensor'?")) << plural.what();
  // Nothing close: no suggestion, the header's first column.
  const InputError far = error_of_reader("grey,colour,value\n0.5,1,512\n", Kind::ground);
  EXPECT_EQ(far.column(), 1);
  EXPECT_FALSE(contains(far.message(), "did you mean")) << far.what();
}

TEST(LogReader, UnrecognisedKindSaysWhichColumnIsClose) {
  // No kind given: the kind whose missing columns are all explained by close names is named.
  const InputError e = error_of_reader("# robot: r\nsensor,value,Distnace_m\n0,1971,0.02\n", std::nullopt);
  EXPECT_EQ(e.line(), 2);
  EXPECT_EQ(e.column(), 14);
  EXPECT_TRUE(contains(e.message(), "cannot recognise the kind")) << e.what();
  EXPECT_TRUE(contains(e.message(), "as a proximity log it lacks 'distance_m': the header has 'distnace_m': did you mean")) << e.what();
  // The most specific kind: light has four columns, proximity three.
  const InputError light = error_of_reader("distance_mm,intensity,sensor,value\n20,1,0,3519\n", std::nullopt);
  EXPECT_TRUE(contains(light.message(), "as a light log it lacks 'distance_m': column 'distance_mm' has the unit mm")) << light.what();
  const InputError none = error_of_reader("a,b\n1,2\n", std::nullopt);
  EXPECT_EQ(none.column(), 1);
  EXPECT_FALSE(contains(none.message(), "lacks")) << none.what();
}

// ---- 6. Metadata errors name their line ----------------------------------------------------------

TEST(LogReader, MetadataErrorsNameTheirLine) {
  // "# obstacle_distance_m: abc" on line 3: the value starts at character 24.
  const InputError bad = error_of_reader("# robot: r1\n# seed: 1\n# obstacle_distance_m: abc\n" + kDriveHeader + "0,5,5,0,0,300\n",
                                  Kind::drive);
  EXPECT_EQ(bad.line(), 3);
  EXPECT_EQ(bad.column(), 24);
  EXPECT_TRUE(contains(bad.message(), "expected a finite number, got 'abc'")) << bad.what();
  // Missing: at the header, before which the line belongs.
  const InputError missing = error_of_reader("# robot: r1\n" + kDriveHeader + "0,5,5,0,0,300\n", Kind::drive);
  EXPECT_EQ(missing.line(), 2);
  EXPECT_EQ(missing.column(), 1);
  // Log::metadata_number on a log read fine.
  const auto log = logs::parse_log("# scale:  x2\ngrey,sensor,value\n0.5,1,512\n", "t.csv", Kind::ground);
  try {
    log.metadata_number("scale");
    FAIL();
  } catch (const InputError& e) {
    EXPECT_EQ(e.line(), 1);
    EXPECT_EQ(e.column(), 11);
  }
  EXPECT_EQ(log.metadata_at.at("scale").line, 1);
}

// ---- 7. Bad rows: an error, or skipped and reported ----------------------------------------------

namespace {
// Line 1 header; 2 good; 3 sensor 'x' (col 6); 4 value 9999 out of range (col 8); 5 too few cells
// (the line has 6 characters: col 7); 6 good.
const std::string kBadRows = "distance_m,sensor,value\n0.02,0,1971\n0.03,x,1500\n0.04,1,9999\n0.05,1\n0.06,2,800\n";
}  // namespace

TEST(LogReader, ABadCellIsAnErrorAtItsLineAndColumn) {
  const InputError e = error_of_reader(kBadRows, Kind::proximity);
  EXPECT_EQ(e.line(), 3);
  EXPECT_EQ(e.column(), 6);
  EXPECT_TRUE(contains(e.message(), "column 'sensor': expected a number, got 'x'")) << e.what();
  // The first problem in file order, the leftmost in its row, whatever the column's order.
  const InputError order = error_of_reader("distance_m,sensor,value\n0.02,0,1971\n0.03,1,abc\n-1,zz,1\n", Kind::proximity);
  EXPECT_EQ(order.line(), 3);
  EXPECT_EQ(order.column(), 8);
  const InputError leftmost = error_of_reader("distance_m,sensor,value\nabc,zz,1\n", Kind::proximity);
  EXPECT_EQ(leftmost.column(), 1);
}

TEST(LogReader, SkipBadRowsLeavesThemOutAndRecordsEach) {
  logs::ReadOptions skip;
  skip.skip_bad_rows = true;
  const auto log = logs::parse_log(kBadRows, "t.csv", Kind::proximity, skip);
  EXPECT_EQ(log.col("distance_m"), (std::vector<double>{0.02, 0.06}));
  EXPECT_EQ(log.col("value"), (std::vector<double>{1971, 800}));
  EXPECT_EQ(log.line_of_row, (std::vector<int>{2, 6}));
  ASSERT_EQ(log.skipped.size(), 3u);
  EXPECT_EQ(log.skipped[0].line, 3);
  EXPECT_EQ(log.skipped[0].column, 6);
  EXPECT_EQ(log.skipped[1].line, 4);
  EXPECT_EQ(log.skipped[1].column, 8);
  EXPECT_TRUE(contains(log.skipped[1].reason, "out of range")) << log.skipped[1].reason;
  EXPECT_EQ(log.skipped[2].line, 5);
  EXPECT_EQ(log.skipped[2].column, 7);
  EXPECT_TRUE(contains(log.skipped[2].reason, "found 2")) << log.skipped[2].reason;
  EXPECT_EQ(log.column_of(1, "value"), 8);  // cell positions follow the rows kept
}

TEST(LogReader, SkipBadRowsStillRefusesTimeGoingBackAndAFileOfBadRows) {
  logs::ReadOptions skip;
  skip.skip_bad_rows = true;
  const InputError back = error_of_reader("time_s,speed_cm_s,charge\n5,5,1\n10,5,abc\n2,5,0.9\n", Kind::battery, skip);
  EXPECT_EQ(back.line(), 4);  // compared with line 2: line 3 is skipped
  EXPECT_EQ(back.column(), 1);
  EXPECT_TRUE(contains(back.message(), "time decreases from 5 (line 2) to 2")) << back.what();
  const InputError all = error_of_reader("# a comment\ngrey,sensor,value\n0.5,7,512\n2,1,512\n", Kind::ground, skip);
  EXPECT_EQ(all.line(), 2);
  EXPECT_EQ(all.column(), 1);
  EXPECT_TRUE(contains(all.message(), "no data rows left")) << all.what();
}

// ---- 8. Complete locations: empty files, line ends, JSON -----------------------------------------

TEST(LogReader, EmptyFileAndNoDataRowsHaveALineAndColumn) {
  for (const std::string text : {"", "\n\n", "# only a comment\n"}) {
    const InputError e = error_of_reader(text, Kind::ground);
    EXPECT_EQ(e.line(), 1) << text;
    EXPECT_EQ(e.column(), 1) << text;
    EXPECT_TRUE(contains(e.message(), "empty file")) << e.what();
  }
  const InputError rows = error_of_reader("# robot: r\n\ngrey,sensor,value\n# nothing\n", Kind::ground);
  EXPECT_EQ(rows.line(), 3);
  EXPECT_EQ(rows.column(), 1);
  EXPECT_TRUE(contains(rows.message(), "no data rows")) << rows.what();
}

TEST(LogReader, LoneCarriageReturnsEndLines) {
  const auto log = logs::parse_log("# robot: mac\rgrey,sensor,value\r0.5,1,512\r1,2,1000", "t.csv", Kind::ground);
  EXPECT_EQ(log.robot, "mac");
  EXPECT_EQ(log.col("grey"), (std::vector<double>{0.5, 1}));
  EXPECT_EQ(log.line_of_row, (std::vector<int>{3, 4}));
  const InputError e = error_of_reader("grey,sensor,value\r0.5,1,512\r0.5,1,abc\r", Kind::ground);
  EXPECT_EQ(e.line(), 3);
  EXPECT_EQ(e.column(), 7);
}

TEST(JsonLocation, PointersAndOverflowsAreFoundAtTheirLine) {
  const std::string text = "{\n  \"kind\": \"x\",\n  \"speeds\": [\n    {\"h\": 1, \"m\": [2, 3]},\n    {\"a/b\": true}\n  ]\n}\n";
  auto at = [&](const std::string& pointer) {
    const logs::SourcePos p = logs::locate_json_pointer(text, pointer);
    return std::to_string(p.line) + ":" + std::to_string(p.column);
  };
  EXPECT_EQ(at(""), "1:1");
  EXPECT_EQ(at("/kind"), "2:11");
  EXPECT_EQ(at("/speeds"), "3:13");
  EXPECT_EQ(at("/speeds/0"), "4:5");
  EXPECT_EQ(at("/speeds/0/m/1"), "4:23");
  EXPECT_EQ(at("/speeds/1/a~1b"), "5:13");
  EXPECT_EQ(at("/speeds/2"), "0:0");
  EXPECT_EQ(at("/nope"), "0:0");
  const logs::SourcePos big = logs::locate_json_overflow("{\"a\": \"1e999\",\r\n \"b\": [1, -2e400]}");
  EXPECT_EQ(big.line, 2);
  EXPECT_EQ(big.column, 11);
  EXPECT_EQ(logs::locate_json_overflow("[1e300, 2]").line, 0);
  // A missing key names the object it is missing from, and the JSON path.
  const InputError e = logs::json_error("f.json", text, "/speeds/0/x1_s", "expected a number 'x1_s'");
  EXPECT_EQ(e.line(), 4);
  EXPECT_EQ(e.column(), 5);
  EXPECT_TRUE(contains(e.message(), "/speeds/0/x1_s")) << e.what();
}

class CoefficientFiles : public epuck2::testing::CliTest {};

TEST_F(CoefficientFiles, SensorLoaderErrorsNameFileLineAndColumn) {
  // gamma's value starts at character 14 of line 4.
  const std::string overflow = write("light.json", "{\n  \"kind\": \"light\",\n  \"parameters\": {\n    \"gamma\": 1e999\n  }\n}\n");
  try {
    epuck2::coefficients::read_model_file<epuck2::models::sensors::LightModel>(overflow);
    FAIL();
  } catch (const InputError& e) {
    EXPECT_EQ(e.file(), overflow);
    EXPECT_EQ(e.line(), 4);
    EXPECT_EQ(e.column(), 14);
  }
  const std::string type = write("t.json", "{\"kind\": \"light\",\n \"parameters\": {\"gamma\": \"0.07\"}}");
  try {
    epuck2::coefficients::read_model_file<epuck2::models::sensors::LightModel>(type);
    FAIL();
  } catch (const InputError& e) {
    EXPECT_EQ(e.line(), 2);
    EXPECT_EQ(e.column(), 26);
    EXPECT_TRUE(contains(e.message(), "/parameters/gamma")) << e.what();
  }
  const std::string ground = write("g.json", "{\"kind\": \"ground\", \"parameters\": {\n\"gain\": [1, 2, 3],\n\"offset\": [1, null, 3]}}");
  try {
    epuck2::coefficients::read_model_file<epuck2::models::sensors::GroundModel>(ground);
    FAIL();
  } catch (const InputError& e) {
    EXPECT_EQ(e.line(), 3);
    EXPECT_EQ(e.column(), 15);
  }
  const std::string syntax = write("s.json", "{\"kind\": \"light\",\n \"parameters\": {\"gamma\": 0.07,}}");
  try {
    epuck2::coefficients::read_model_file<epuck2::models::sensors::LightModel>(syntax);
    FAIL();
  } catch (const InputError& e) {
    EXPECT_EQ(e.line(), 2);
    EXPECT_EQ(e.column(), 31);  // the '}' where a key was expected
  }
}

TEST_F(CoefficientFiles, BatteryTableErrorsNameTheLineOfTheKey) {
  // A battery file whose speeds[0] lacks lifetime_s; the object starts on line 3.
  const std::string path = write("b.json", "{\"speeds\": [\n  {\"speed_cm_s\": 0,\n   \"cubic\": [1, 0, 0, 0], \"linear_slope\": 0}\n]}\n");
  const nlohmann::json j = nlohmann::json::parse(epuck2::testing::slurp(path));
  try {
    epuck2::coefficients::battery_tables_from_json(j, path);
    FAIL();
  } catch (const InputError& e) {
    // 16 speeds are expected: the error is at the 'speeds' array (line 1, character 12).
    EXPECT_EQ(e.line(), 1);
    EXPECT_EQ(e.column(), 12);
    EXPECT_TRUE(contains(e.message(), "expected 16 entries")) << e.what();
  }
  std::string speeds;
  for (int s = 0; s < 16; ++s)
    speeds += std::string(s ? ",\n" : "") + "{\"speed_cm_s\": " + std::to_string(s) +
              ", \"cubic\": [1, 0, 0, 0], \"lifetime_s\": 100, \"linear_slope\": -0.01, \"segments\": []}";
  // speeds[0] (line 2) has no 4 segments: its "segments" value starts at character 96 (a valid, negative linear_slope before it).
  const std::string full = write("full.json", "{\"speeds\": [\n" + speeds + "\n]}\n");
  try {
    epuck2::coefficients::battery_tables_from_json(nlohmann::json::parse(epuck2::testing::slurp(full)), full);
    FAIL();
  } catch (const InputError& e) {
    EXPECT_EQ(e.line(), 2);
    EXPECT_EQ(e.column(), 96);
    EXPECT_TRUE(contains(e.message(), "speeds[0]: expected 4 'segments'")) << e.what();
  }
}

// ---- 9. Control characters in messages -------------------------------------------------------------

TEST(LogReader, ControlCharactersAreEscapedInMessages) {
  EXPECT_EQ(logs::escape_control("a\tb\x1b[2J\x7f\n"), "a\tb\\x1b[2J\\x7f\\x0a");
  EXPECT_EQ(logs::escape_control(std::string("x\0y", 3)), "x\\x00y");
  const InputError esc = error_of_reader("grey,sensor,value\n0.5,\x1b[31m,512\n", Kind::ground);
  const std::string what = esc.what();
  EXPECT_EQ(what.find('\x1b'), std::string::npos) << what;
  EXPECT_TRUE(contains(what, "got '\\x1b[31m'")) << what;
  // A NUL inside a cell no longer cuts the message short.
  const char with_nul[] = "grey,sensor,value\n0.5,1,5\0" "12\n";
  const InputError nul = error_of_reader(std::string(with_nul, sizeof with_nul - 1), Kind::ground);
  EXPECT_TRUE(contains(nul.what(), "got '5\\x0012'")) << nul.what();
  EXPECT_EQ(nul.line(), 2);
  EXPECT_EQ(nul.column(), 7);
  // The file name too, and the reasons of skipped rows.
  EXPECT_EQ(std::string(InputError("a\x1b.csv", 1, 1, "m").what()), "a\\x1b.csv:1:1: m");
  logs::ReadOptions skip;
  skip.skip_bad_rows = true;
  const auto log = logs::parse_log("grey,sensor,value\n0.5,\x07,512\n0.5,1,512\n", "t.csv", Kind::ground, skip);
  ASSERT_EQ(log.skipped.size(), 1u);
  EXPECT_TRUE(contains(log.skipped[0].reason, "'\\x07'")) << log.skipped[0].reason;
}

TEST(LogReader, TextFromTheFileIsStoredEscaped) {
  const auto log = logs::parse_log("# robot: r\x1b" "1\ngrey,sensor,value,tag\x07\n0.5,1,512,a\x1b" "b\n", "t.csv", Kind::ground);
  EXPECT_EQ(log.robot, "r\\x1b1");
  EXPECT_EQ(log.columns.back(), "tag\\x07");
  EXPECT_EQ(log.text.at("tag\\x07"), (std::vector<std::string>{"a\\x1bb"}));
  EXPECT_EQ(log.col("value"), (std::vector<double>{512}));
}

// ---- 10. The same file twice -----------------------------------------------------------------------

TEST_F(CoefficientFiles, TheSameLogTwiceIsRefused) {
  const std::string a = write("a.csv", "grey,sensor,value\n0.5,1,512\n");
  fs::create_directories(dir_ / "sub");
  const std::string b = write("sub/b.csv", "grey,sensor,value\n0.5,1,600\n");
  EXPECT_EQ(logs::read_logs({a, b}, Kind::ground).size(), 2u);
  for (const std::string& again : {a, (dir_ / "sub" / ".." / "a.csv").string()}) {
    try {
      logs::read_logs({a, b, again}, Kind::ground);
      FAIL() << again;
    } catch (const InputError& e) {
      EXPECT_EQ(e.file(), again);
      EXPECT_TRUE(contains(e.message(), "twice")) << e.what();
    }
  }
  fs::create_symlink(a, dir_ / "link.csv");
  EXPECT_THROW(logs::read_logs({(dir_ / "link.csv").string(), a}, Kind::ground), InputError);
}

// ---- 11. Battery logs with voltage_v instead of charge ------------------------------------------

TEST(LogReader, AVoltageOnlyBatteryLogIsReadAndRecognisedAsBattery) {
  const std::string csv = "# robot: r1\ntime_s,speed_cm_s,voltage_v\n0,4,4.2\n1800,4,3.988\n";
  for (const std::optional<Kind> kind : {std::optional<Kind>(Kind::battery), std::optional<Kind>()}) {
    const auto log = logs::parse_log(csv, "v.csv", kind);
    EXPECT_EQ(log.kind, Kind::battery);
    EXPECT_FALSE(log.has("charge"));
    EXPECT_EQ(log.col("voltage_v"), (std::vector<double>{4.2, 3.988}));
    EXPECT_EQ(log.col("time_s"), (std::vector<double>{0, 1800}));
  }
  EXPECT_EQ(logs::stand_in_column(Kind::battery, "charge"), "voltage_v");
  EXPECT_EQ(logs::stand_in_column(Kind::battery, "time_s"), "");
  EXPECT_EQ(logs::stand_in_column(Kind::proximity, "value"), "");
}

TEST(LogReader, ABatteryLogWithNeitherChargeNorVoltageSaysBoth) {
  const InputError e = error_of_reader("time_s,speed_cm_s\n0,4\n", Kind::battery);
  EXPECT_EQ(e.line(), 1);
  EXPECT_TRUE(contains(e.message(), "missing required column 'charge' (or 'voltage_v') for a battery log")) << e.what();
  // A voltage column that is not a number is refused where it is, as a charge column would be.
  const InputError v = error_of_reader("time_s,speed_cm_s,voltage_v\n0,4,4.2\n10,4,high\n", Kind::battery);
  EXPECT_EQ(v.line(), 3);
  EXPECT_EQ(v.column(), 6);
  EXPECT_TRUE(contains(v.message(), "column 'voltage_v': expected a number, got 'high'")) << v.what();
}

// ---- Through the real binary -----------------------------------------------------------------------

namespace {

using ReaderCli = epuck2::testing::CliTest;
using epuck2::testing::CliRun;

// A ground log written by hand: value = offset + gain grey exactly, sensors 0, 1, 2 with gains
// 900, 800, 950 and offsets 50, 60, 40 (the fit must find these numbers).
const std::vector<std::string> kGroundRows{
    "0,0,50",   "0.25,0,275", "0.5,0,500", "0.75,0,725", "1,0,950",
    "0,1,60",   "0.25,1,260", "0.5,1,460", "0.75,1,660", "1,1,860",
    "0,2,40",   "0.25,2,277.5", "0.5,2,515", "0.75,2,752.5", "1,2,990",
};

std::string ground_log_reader(const std::string& header, const std::string& end, const std::string& trailing) {
  std::string text = "# robot: hand" + end + header + trailing + end;
  for (const auto& r : kGroundRows) text += r + trailing + end;
  return text;
}

void expect_hand_ground_fit(const CliRun& r, const std::string& what) {
  ASSERT_EQ(r.exit_code, 0) << what << ": " << r.err;
  const auto j = nlohmann::json::parse(r.out);
  const std::vector<double> gain{900, 800, 950}, offset{50, 60, 40};
  for (std::size_t k = 0; k < 3; ++k) {
    EXPECT_NEAR(j.at("parameters").at("gain").at(k).get<double>(), gain[k], 1e-6) << what << " sensor " << k;
    EXPECT_NEAR(j.at("parameters").at("offset").at(k).get<double>(), offset[k], 1e-6) << what << " sensor " << k;
  }
  EXPECT_EQ(j.at("observations").get<int>(), 15) << what;
}

}  // namespace

TEST_F(ReaderCli, WhatLoggersWriteFitsToTheSameNumbers) {
  // Items 1, 2 and 8: plain, trailing delimiters (LF and CRLF), upper-case header, old-Mac CR.
  expect_hand_ground_fit(run("ground --json \"" + write("plain.csv", ground_log_reader("grey,sensor,value", "\n", "")) + "\""), "plain");
  expect_hand_ground_fit(run("ground --json \"" + write("trail.csv", ground_log_reader("grey,sensor,value", "\n", ",")) + "\""), "trailing");
  expect_hand_ground_fit(run("ground --json \"" + write("crlf.csv", ground_log_reader("grey,sensor,value", "\r\n", ",")) + "\""),
                         "CRLF and trailing");
  expect_hand_ground_fit(run("ground --json \"" + write("case.csv", ground_log_reader("Grey,SENSOR,Value", "\n", "")) + "\""), "case");
  expect_hand_ground_fit(run("ground --json \"" + write("mac.csv", ground_log_reader("grey,sensor,value", "\r", "")) + "\""), "CR only");
}

TEST_F(ReaderCli, RefusalsExitTwoWithFileLineColumn) {
  struct Refusal {
    std::string command, file, text, expected;  // expected: the text after "FILE:"
  };
  const std::string drive_header = "time_s,left_speed_cm_s,right_speed_cm_s,left_steps,right_steps,tof_mm\n";
  const std::vector<Refusal> cases{
      // 5: another unit; a typo.
      {"proximity", "mm.csv", "sensor,distance_mm,value\n0,20,1971\n",
       "1:8: missing required column 'distance_m' for a proximity log; column 'distance_mm' has the unit mm; this column must be in m"},
      {"proximity", "typo.csv", "distnace_m,sensor,value\n0.02,0,1971\n",
       "1:1: missing required column 'distance_m' for a proximity log; the header has 'distnace_m': did you mean 'distance_m'?"},
      // 6: a metadata error at its line.
      {"drive", "meta.csv", "# robot: r\n# obstacle_distance_m: abc\n" + drive_header + "0,5,5,0,0,300\n",
       "2:24: metadata 'obstacle_distance_m': expected a finite number, got 'abc'"},
      {"drive", "nometa.csv", "# robot: r\n" + drive_header + "0,5,5,0,0,300\n", "2:1: missing required metadata line"},
      // 3: the ToF between its range and its out-of-range code.
      {"drive", "tof.csv", "# obstacle_distance_m: 0.3\n" + drive_header + "0,5,5,0,0,4000\n", "3:11: column 'tof_mm': value 4000 out of range"},
      // 7: a bad cell without --skip-bad-rows.
      {"ground", "cell.csv", "grey,sensor,value\n0.5,1,512\n0.5,1,5x2\n", "3:7: column 'value': expected a number, got '5x2'"},
      // 8: empty file, no data rows.
      {"ground", "empty.csv", "", "1:1: empty file"},
      {"ground", "norows.csv", "# robot: r\ngrey,sensor,value\n", "2:1: no data rows after the header"},
  };
  for (const Refusal& c : cases) {
    const std::string path = write(c.file, c.text);
    const CliRun r = run(c.command + " \"" + path + "\"");
    EXPECT_EQ(r.exit_code, 2) << c.file << ": " << r.err;
    EXPECT_TRUE(contains(r.err, "error: " + path + ":" + c.expected)) << c.file << ": " << r.err;
  }
}

TEST_F(ReaderCli, DiagnoseAndCodegenNameTheLine) {
  const std::string typo = write("typo.csv", "sensor,value,distnace_m\n0,1971,0.02\n");
  const CliRun d = run("diagnose \"" + typo + "\"");
  EXPECT_EQ(d.exit_code, 2);
  EXPECT_TRUE(contains(d.err, "error: " + typo + ":1:14: cannot recognise the kind")) << d.err;
  EXPECT_TRUE(contains(d.err, "did you mean 'distance_m'?")) << d.err;
  // A coefficient file whose kind is no C++ identifier: the line of "kind".
  const std::string bad = write("bad.json", "{\n  \"parameters\": {\"a\": 1},\n  \"kind\": \"two words\"\n}\n");
  const CliRun c = run("codegen \"" + bad + "\" -o \"" + (dir_ / "out.hpp").string() + "\"");
  EXPECT_EQ(c.exit_code, 2);
  EXPECT_TRUE(contains(c.err, "error: " + bad + ":3:11: the kind 'two words' is not a C++ identifier ([A-Za-z_][A-Za-z0-9_]*) (at JSON path /kind)")) << c.err;
  EXPECT_FALSE(fs::exists(dir_ / "out.hpp"));
}

TEST_F(ReaderCli, TofOutOfRangeCodesAndObstacleZeroReachTheFit) {
  // A shipped drive log with the ToF of five rows replaced by the sensor's out-of-range codes.
  const std::string shipped_drive = epuck2::testing::slurp(
      fs::path(EPUCK2_SOURCE_DIR) / "data" / "raw" / "drive" /
      [] {
        std::vector<std::string> names;
        for (const auto& e : fs::directory_iterator(fs::path(EPUCK2_SOURCE_DIR) / "data" / "raw" / "drive"))
          if (e.path().extension() == ".csv") names.push_back(e.path().filename().string());
        std::sort(names.begin(), names.end());
        return names.front();
      }());
  std::string codes, zero;
  int data_row = 0;
  std::size_t start = 0;
  while (start < shipped_drive.size()) {
    const std::size_t nl = shipped_drive.find('\n', start);
    std::string line = shipped_drive.substr(start, nl - start);
    start = nl == std::string::npos ? shipped_drive.size() : nl + 1;
    std::string z = line;
    if (!line.empty() && line[0] != '#' && line.rfind("time_s", 0) != 0 && ++data_row >= 10 && data_row < 15)
      line = line.substr(0, line.rfind(',') + 1) + (data_row % 2 ? "8190" : "8191");
    if (z.rfind("# obstacle_distance_m:", 0) == 0) z = "# obstacle_distance_m: 0";
    codes += line + "\n";
    zero += z + "\n";
  }
  ASSERT_GE(data_row, 15);
  const CliRun r = run("drive --json" + shipped("drive") + " \"" + write("codes.csv", codes) + "\"");
  EXPECT_EQ(r.exit_code, 0) << r.err;
  EXPECT_TRUE(nlohmann::json::accept(r.out)) << r.out;
  // D = 0 is read; whether these runs (written for D = 0.3 m) still fit is the fit's business.
  const CliRun z = run("drive --json" + shipped("drive") + " \"" + write("zero.csv", zero) + "\"");
  EXPECT_NE(z.exit_code, 2) << z.err;
  EXPECT_FALSE(contains(z.err, "obstacle_distance_m")) << z.err;
}

TEST_F(ReaderCli, SkipBadRowsReportsEveryRowItLeavesOut) {
  // The hand ground log with 12 bad rows among the good ones: lines 3.. of the file.
  std::string text = "# robot: hand\ngrey,sensor,value\n";
  std::vector<std::string> expected_locations;
  int line = 2;
  for (std::size_t i = 0; i < kGroundRows.size(); ++i) {
    text += kGroundRows[i] + "\n";
    ++line;
    if (i < 12) {
      text += "0.5,1,bad" + std::to_string(i) + "\n";  // the value at character 7
      ++line;
      expected_locations.push_back(":" + std::to_string(line) + ":7: column 'value': expected a number, got 'bad" +
                                   std::to_string(i) + "'");
    }
  }
  const std::string path = write("bad.csv", text);
  const CliRun strict = run("ground --json \"" + path + "\"");
  EXPECT_EQ(strict.exit_code, 2);
  EXPECT_TRUE(contains(strict.err, path + expected_locations[0])) << strict.err;

  const CliRun r = run("ground --json --skip-bad-rows \"" + path + "\"");
  expect_hand_ground_fit(r, "skip");
  EXPECT_TRUE(contains(r.err, "ground: skipped 12 bad rows (--skip-bad-rows), the first 10:")) << r.err;
  for (std::size_t i = 0; i < 10; ++i) EXPECT_TRUE(contains(r.err, "  " + path + expected_locations[i] + "\n")) << i << r.err;
  EXPECT_FALSE(contains(r.err, path + expected_locations[10])) << r.err;
  EXPECT_TRUE(contains(r.err, "  ... and 2 more\n")) << r.err;

  // Nothing to skip: nothing said about skipping (the hand log's 5 readings a sensor for 2
  // parameters and the noise are still worth a warning each).
  const CliRun clean = run("ground --json --skip-bad-rows \"" + write("clean.csv", ground_log_reader("grey,sensor,value", "\n", "")) + "\"");
  EXPECT_EQ(clean.exit_code, 0);
  EXPECT_FALSE(contains(clean.err, "skipped")) << clean.err;
  std::istringstream lines(clean.err);
  for (std::string line; std::getline(lines, line);) EXPECT_EQ(line.rfind("ground: warning: sensor ", 0), 0u) << line;
}

TEST_F(ReaderCli, EverySubcommandThatReadsLogsHasSkipBadRows) {
  for (const std::string sub : {"battery", "table5", "proximity", "light", "ground", "camera", "drive", "diagnose",
                                "simulate battery"}) {
    const CliRun r = run(sub + " --help");
    EXPECT_EQ(r.exit_code, 0) << sub;
    EXPECT_TRUE(contains(r.out, "--skip-bad-rows")) << sub << ":\n" << r.out;
    EXPECT_TRUE(contains(r.out, "Time going backwards still stops")) << sub;
  }
}

TEST_F(ReaderCli, SimulateProfileSkipsAndJsonOverflowIsLocated) {
  // Line 3 of the profile has a bad speed (character 5).
  const std::string profile = write("p.csv", "time_s,speed_cm_s\n0,5\n1,fast\n2,0\n");
  const CliRun strict = run("simulate battery --model simple --coefficients plugin --profile \"" + profile + "\"");
  EXPECT_EQ(strict.exit_code, 2);
  EXPECT_TRUE(contains(strict.err, profile + ":3:3: column 'speed_cm_s': expected a number, got 'fast'")) << strict.err;
  const CliRun skip = run("simulate battery --model simple --coefficients plugin --skip-bad-rows --profile \"" + profile + "\"");
  EXPECT_EQ(skip.exit_code, 0) << skip.err;
  EXPECT_TRUE(contains(skip.err, "simulate: skipped 1 bad row (--skip-bad-rows):\n  " + profile + ":3:3: ")) << skip.err;
  EXPECT_TRUE(contains(skip.out, "time_s,charge\n0,1\n")) << skip.out.substr(0, 200);

  // A number too large for a double in a coefficient file: file, line and column.
  const std::string big = write("big.json", "{\n  \"speeds\": [\n    1e999\n  ]\n}\n");
  const CliRun b = run("simulate battery --model cubic --coefficients \"" + big + "\" --profile \"" +
                       write("ok.csv", "time_s,speed_cm_s\n0,5\n1,5\n") + "\"");
  EXPECT_EQ(b.exit_code, 2);
  EXPECT_TRUE(contains(b.err, "error: " + big + ":3:5: invalid JSON")) << b.err;
  // A missing key: the line of the object it is missing from, and the JSON path.
  const std::string nokey = write("nokey.json", "{\n  \"kind\": \"battery\",\n  \"speeds\": []\n}\n");
  const CliRun k = run("simulate battery --model cubic --coefficients \"" + nokey + "\" --profile \"" +
                       write("ok2.csv", "time_s,speed_cm_s\n0,5\n1,5\n") + "\"");
  EXPECT_EQ(k.exit_code, 2);
  EXPECT_TRUE(contains(k.err, "error: " + nokey + ":3:13: expected 16 entries in 'speeds'")) << k.err;
  EXPECT_TRUE(contains(k.err, "(at JSON path /speeds)")) << k.err;
}

TEST_F(ReaderCli, ControlCharactersNeverReachTheTerminal) {
  const char raw[] = "grey,sensor,value\n0.5,1,\x1b]0;pwned\x07\n0.5,1,5\0" "12\n0.5,1,512\n";
  const std::string path = write("esc.csv", std::string(raw, sizeof raw - 1));
  const CliRun r = run("ground \"" + path + "\"");
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_TRUE(contains(r.err, path + ":2:7: column 'value': expected a number, got '\\x1b]0;pwned\\x07'\n")) << r.err;
  for (const char c : r.err) EXPECT_TRUE(c == '\n' || static_cast<unsigned char>(c) >= 0x20) << int(c);
  // Skipped, the NUL row is reported whole.
  const CliRun s = run("ground --skip-bad-rows \"" + path + "\"");
  EXPECT_TRUE(contains(s.err, path + ":3:7: column 'value': expected a number, got '5\\x0012'\n")) << s.err;
  for (const char c : s.err) EXPECT_TRUE(c == '\n' || static_cast<unsigned char>(c) >= 0x20) << int(c);
}

TEST_F(ReaderCli, TheSameFileTwiceIsRefused) {
  const std::string a = write("a.csv", ground_log_reader("grey,sensor,value", "\n", ""));
  const CliRun r = run("ground \"" + a + "\" \"" + a + "\"");
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_TRUE(contains(r.err, "error: " + a + ": given twice")) << r.err;
  // Another spelling of the same file, from its folder.
  const CliRun dot = run("ground a.csv ./a.csv", dir_.string());
  EXPECT_EQ(dot.exit_code, 2);
  EXPECT_TRUE(contains(dot.err, "error: ./a.csv: is the same file as a.csv (given twice)")) << dot.err;
}
