// Where a log's clock starts is no condition of the robot: the same log with every time_s moved
// by 1024 s (a power of two, so that row-to-row intervals keep their values to the last bits a
// double has at that size) must simulate and diagnose the same. A model that read the absolute
// time (an interval taken from 0 instead of from the run's first row, a time used as a speed's
// index) changes its output here. Expected values are the unshifted runs' own outputs: the test
// checks an invariance, not a value.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <sstream>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "cli_harness.hpp"

namespace test_time_origin_cpp {

namespace fs = std::filesystem;
using epuck2::testing::CliRun;
using epuck2::testing::slurp;

/// The log's text with `shift` seconds added to its time_s column (column 0 in both kinds).
std::string shifted(const std::string& text, double shift) {
  std::istringstream in(text);
  std::string line, out;
  bool header = false;
  while (std::getline(in, line)) {
    if (line.empty() || line[0] == '#' || !header) {
      if (!line.empty() && line[0] != '#') header = true;
      out += line + "\n";
      continue;
    }
    const std::size_t comma = line.find(',');
    char t[64];
    std::snprintf(t, sizeof t, "%.17g", std::stod(line.substr(0, comma)) + shift);
    out += t + line.substr(comma) + "\n";
  }
  return out;
}

/// The data rows of a simulated log, split into numbers.
std::vector<std::vector<double>> rows_of(const std::string& text) {
  std::istringstream in(text);
  std::string line;
  std::vector<std::vector<double>> rows;
  bool header = false;
  while (std::getline(in, line)) {
    if (line.empty() || line[0] == '#') continue;
    if (!header) {
      header = true;
      continue;
    }
    std::vector<double> r;
    std::stringstream cells(line);
    for (std::string c; std::getline(cells, c, ',');) r.push_back(std::stod(c));
    rows.push_back(r);
  }
  return rows;
}

class TimeOrigin : public epuck2::testing::CliTest {
 protected:
  static fs::path raw(const std::string& kind, const std::string& file) {
    return fs::path(EPUCK2_SOURCE_DIR) / "data" / "raw" / kind / file;
  }
};

// simulate battery --like: the charges of a shipped run and of the run 1024 s later agree to
// rounding (the row intervals are whole seconds: exact).
TEST_F(TimeOrigin, ABatteryRunSimulatesTheSameWheneverItsClockStarts) {
  for (const char* model : {"cubic", "approximated", "linear", "simple"}) {
    const fs::path log = raw("battery", "robot-a_speed-05.csv");
    const std::string later = write("later.csv", shifted(slurp(log), 1024));
    const CliRun a = run("simulate battery --like \"" + log.string() + "\" --battery-model " + model);
    const CliRun b = run("simulate battery --like \"" + later + "\" --battery-model " + model);
    ASSERT_EQ(a.exit_code, 0) << a.err;
    ASSERT_EQ(b.exit_code, 0) << b.err;
    const auto ra = rows_of(a.out), rb = rows_of(b.out);
    ASSERT_EQ(ra.size(), rb.size());
    ASSERT_GT(ra.size(), 100u);
    for (std::size_t i = 0; i < ra.size(); ++i) {
      EXPECT_EQ(rb[i][0], ra[i][0] + 1024) << model << " row " << i;
      EXPECT_NEAR(rb[i].back(), ra[i].back(), 1e-12) << model << " row " << i;
    }
  }
}

// simulate drive --like: the encoder registers and the ToF of a shipped run and of the run 1024 s
// later agree. The ToF's mean is 300 + 50 t mm at 5 cm/s with t logged to the millisecond: every
// 10 ms it sits on a half millimetre, where the intervals' last bits (1024 + t rounds t to 2e-13)
// decide the rounding: a millimetre apart there at most. The registers (7763.656 steps/m) sit on
// no such tie: all but a hundredth equal.
TEST_F(TimeOrigin, ADriveRunSimulatesTheSameWheneverItsClockStarts) {
  const fs::path log = raw("drive", "drive_away_05.0_cm_s.csv");
  const std::string later = write("later.csv", shifted(slurp(log), 1024));
  const CliRun a = run("simulate drive --like \"" + log.string() + "\"");
  const CliRun b = run("simulate drive --like \"" + later + "\"");
  ASSERT_EQ(a.exit_code, 0) << a.err;
  ASSERT_EQ(b.exit_code, 0) << b.err;
  const auto ra = rows_of(a.out), rb = rows_of(b.out);
  ASSERT_EQ(ra.size(), rb.size());
  ASSERT_GT(ra.size(), 50u);
  std::size_t equal = 0, registers = 0;
  for (std::size_t i = 0; i < ra.size(); ++i) {
    ASSERT_EQ(ra[i].size(), 6u);  // time_s,left_speed_cm_s,right_speed_cm_s,left_steps,right_steps,tof_mm
    for (std::size_t c = 3; c < 5; ++c) {
      ++registers;
      EXPECT_LE(std::abs(rb[i][c] - ra[i][c]), 1.0) << "row " << i << " column " << c;
      equal += rb[i][c] == ra[i][c];
    }
    EXPECT_LE(std::abs(rb[i][5] - ra[i][5]), 1.0) << "row " << i << " (ToF)";
  }
  EXPECT_GE(equal, registers * 99 / 100);
  // and the run moved: the registers are not all 0, the ToF not constant
  EXPECT_GT(std::abs(ra.back()[3]), 100.0);
  EXPECT_GT(std::abs(ra.back()[5] - ra.front()[5]), 100.0);
}

// diagnose: a battery run and a drive run diagnosed 1024 s later find the same effects with the
// same held-out MSEs (to the last digits of sums of other rounding).
TEST_F(TimeOrigin, ADiagnosisDoesNotDependOnWhereTheClockStarts) {
 for (const fs::path& log : {raw("battery", "robot-a_speed-05.csv"), raw("drive", "drive_away_05.0_cm_s.csv")}) {
  SCOPED_TRACE(log.string());
  const std::string later = write("later.csv", shifted(slurp(log), 1024));
  const CliRun a = run("diagnose \"" + log.string() + "\" --json -");
  const CliRun b = run("diagnose \"" + later + "\" --json -");
  ASSERT_EQ(a.exit_code, 0) << a.err;
  ASSERT_EQ(b.exit_code, 0) << b.err;
  const auto ja = nlohmann::json::parse(a.out), jb = nlohmann::json::parse(b.out);
  for (const char* k : {"heldout_mse_plugin", "heldout_mse_recalibrated", "heldout_mse_final"})
    EXPECT_NEAR(jb.at(k).get<double>(), ja.at(k).get<double>(), 1e-9 * (1 + std::abs(ja.at(k).get<double>()))) << k;
  ASSERT_EQ(ja.at("findings").size(), jb.at("findings").size());
  for (std::size_t i = 0; i < ja.at("findings").size(); ++i)
    EXPECT_EQ(ja.at("findings").at(i).at("cause"), jb.at("findings").at(i).at("cause"));
 }
}

}  // namespace test_time_origin_cpp
