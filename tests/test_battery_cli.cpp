// The battery subcommands as a user runs them (the real binary): battery, table5, codegen,
// simulate; success on the shipped logs, and bad input rejected with exit 2, file:line:column,
// and no output file written or replaced.
#include <gtest/gtest.h>

#include <algorithm>
#include <nlohmann/json.hpp>
#include <regex>

#include "cli_harness.hpp"

using epuck2::testing::CliRun;
using epuck2::testing::slurp;
namespace fs = std::filesystem;

namespace {
class BatteryCli : public epuck2::testing::CliTest {
 protected:
  static std::string shipped() {
    std::string args;
    std::vector<std::string> files;
    for (const auto& e : fs::directory_iterator(fs::path(EPUCK2_SOURCE_DIR) / "data" / "raw" / "battery"))
      if (e.path().extension() == ".csv") files.push_back(e.path().string());
    std::sort(files.begin(), files.end());
    for (const auto& f : files) args += " \"" + f + "\"";
    return args;
  }
  static std::string source(const std::string& rel) { return (fs::path(EPUCK2_SOURCE_DIR) / rel).string(); }
};

const std::regex kFileLineColumn(R"([^\s:]+\.csv:\d+:\d+: )");

struct BadLog {
  const char* name;
  const char* text;
  bool needs_column;  ///< a message naming a cell (file:line:column) rather than the whole file
};

const BadLog kBadLogs[] = {
    {"missing_column.csv", "time_s,speed_cm_s\n0,3\n10,3\n", true},
    {"not_a_number.csv", "time_s,speed_cm_s,charge\n0,3,1\n10,3,abc\n", true},
    {"nan.csv", "time_s,speed_cm_s,charge\n0,3,1\n10,3,nan\n", true},
    {"decreasing_time.csv", "time_s,speed_cm_s,charge\n0,3,1\n10,3,0.9\n5,3,0.8\n", true},
    {"charge_too_high.csv", "time_s,speed_cm_s,charge\n0,3,1.2\n", true},
    {"empty.csv", "", false},
    {"header_only.csv", "# robot: x\ntime_s,speed_cm_s,charge\n", false},
};
}  // namespace

TEST_F(BatteryCli, FitsTheShippedLogsAndWritesTheCoefficientFile) {
  const fs::path out = dir_ / "battery.json";
  const CliRun r = run("battery" + shipped() + " --json -o \"" + out.string() + "\"");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const auto j = nlohmann::json::parse(r.out);
  ASSERT_EQ(j.at("speeds").size(), 16u);
  for (const auto& s : j.at("speeds")) {
    EXPECT_EQ(s.at("cubic").size(), 4u);
    EXPECT_EQ(s.at("segments").size(), 4u);
    EXPECT_LT(s.at("linear_slope").get<double>(), 0.0);
    for (const char* m : {"simple", "linear", "cubic", "approximated"}) EXPECT_TRUE(s.at("mse").contains(m));
  }
  for (const char* m : {"simple", "linear", "cubic", "approximated"}) EXPECT_GT(j.at("mse").at(m).get<double>(), 0.0);
  EXPECT_EQ(nlohmann::json::parse(slurp(out)), j);
  // The human report names every speed.
  const CliRun h = run("battery" + shipped());
  ASSERT_EQ(h.exit_code, 0);
  EXPECT_NE(h.out.find("15.00"), std::string::npos);
  EXPECT_NE(h.out.find("Average MSE"), std::string::npos);
}

TEST_F(BatteryCli, BadInputExitsTwoNamesFileLineColumnAndLeavesOutputAlone) {
  const std::string previous = "{\"kept\": true}\n";
  const std::string out = write("previous.json", previous);
  for (const BadLog& b : kBadLogs) {
    const std::string path = write(b.name, b.text);
    const CliRun r = run("battery \"" + path + "\" -o \"" + out + "\"");
    EXPECT_EQ(r.exit_code, 2) << b.name << ": " << r.err;
    EXPECT_NE(r.err.find(b.name), std::string::npos) << r.err;
    if (b.needs_column) EXPECT_TRUE(std::regex_search(r.err, kFileLineColumn)) << b.name << ": " << r.err;
    EXPECT_EQ(slurp(out), previous) << b.name;
  }
  const CliRun u = run("battery" + shipped() + " --no-such-option -o \"" + out + "\"");
  EXPECT_EQ(u.exit_code, 2);
  EXPECT_EQ(slurp(out), previous);
  // A speed change inside a calibration run names the line and column where it changes.
  const std::string changing = write("changing.csv", "time_s,speed_cm_s,charge\n0,3,1\n10,3,0.99\n20,4,0.98\n");
  const CliRun c = run("battery \"" + changing + "\"");
  EXPECT_EQ(c.exit_code, 2);
  EXPECT_NE(c.err.find("changing.csv:4:"), std::string::npos) << c.err;
}

TEST_F(BatteryCli, Table5LandsWithinOneAndAHalfOfEveryPublishedCell) {
  const CliRun r = run("table5" + shipped() + " --json");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const auto j = nlohmann::json::parse(r.out);
  for (const char* m : {"simple", "linear", "cubic", "approximated"}) {
    for (const char* row : {"analytic", "simulated"}) {
      const double ours = j.at(row).at(m).get<double>();
      const double paper = j.at("published").at(row == std::string("analytic") ? "analytic" : "argos").at(m).get<double>();
      EXPECT_GT(ours / paper, 1.0 / 1.5) << row << " " << m;
      EXPECT_LT(ours / paper, 1.5) << row << " " << m;
    }
    EXPECT_TRUE(j.at("plugin_tables_simulated").contains(m));
  }
  // What the data resolve, cell by cell:
  // * Analytic Cubic: the virtual robot's load-pulse dip was sized so that this MSE equals the
  //   paper's 0.0020 (data/raw/battery/README.md). The paper prints two significant digits
  //   (+-2.5 %), and the mean of the 16 per-speed MSEs is known to 0.9 % (their spread is 3.5 %
  //   of the mean in data/fitted/battery.json, over sqrt(16)): 2.5 % + 3 x 0.9 % = 5.1 %, so
  //   0.0019..0.0021, where the x1.5 band above allowed 0.0013..0.0030.
  const double cubic = j.at("analytic").at("cubic").get<double>();
  EXPECT_NEAR(cubic, 0.0020, 0.051 * 0.0020);
  // * Simple and Linear are straight lines in time: run at 10 ticks per second they reproduce the
  //   analytic values but for the last tick of each run (0.1 s of >= 5 h, 1e-5 relative).
  for (const char* m : {"simple", "linear"}) {
    const double analytic = j.at("analytic").at(m).get<double>(), simulated = j.at("simulated").at(m).get<double>();
    EXPECT_NEAR(simulated, analytic, 1e-4 * analytic) << m;
  }
  // * The paper's ranking simple > linear > approximated > cubic. In data/fitted/battery.json
  //   Linear is >= 6.9 times Approximated at every one of the 16 speeds, and Approximated 3-14 %
  //   above Cubic at every speed: both hold with margin. Simple against Linear varies from 0.4 to
  //   4.1 between speeds (the mean is resolved to about 20 %), so only its sign is asserted.
  const auto& a = j.at("analytic");
  EXPECT_GT(a.at("simple").get<double>(), a.at("linear").get<double>());
  EXPECT_GT(a.at("linear").get<double>(), 5.0 * a.at("approximated").get<double>());
  EXPECT_GT(a.at("approximated").get<double>(), cubic);
  // The other cells depend on how closely the virtual robot imitates the paper's robot, which
  // nothing here resolves better than the x1.5 band.
  // Too few speeds for the tables: data read, no usable result: exit 1.
  const CliRun few = run("table5 \"" + source("data/raw/battery/robot-a_speed-03.csv") + "\"");
  EXPECT_EQ(few.exit_code, 1) << few.err;
}

TEST_F(BatteryCli, CommittedHeaderIsWhatCodegenWritesToday) {
  // The header's first line records the codegen command; run it again from the source folder
  // into a temporary file and compare byte for byte.
  const std::string header_rel = "data/fitted/include/epuck2/fitted/coefficients.hpp";
  const std::string committed = slurp(source(header_rel));
  ASSERT_FALSE(committed.empty());
  std::smatch m;
  const std::regex command(R"(`epuck2-fit codegen ([^`]*) -o (\S+)`)");
  ASSERT_TRUE(std::regex_search(committed, m, command)) << "no codegen command in the header's first line";
  const fs::path fresh = dir_ / "coefficients.hpp";
  const CliRun r = run("codegen " + m[1].str() + " -o \"" + fresh.string() + "\"", EPUCK2_SOURCE_DIR);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  std::string regenerated = slurp(fresh);
  // The recorded output path differs; everything else must be identical.
  const std::string recorded_out = m[2].str();
  const std::size_t at = regenerated.find(fresh.string());
  ASSERT_NE(at, std::string::npos);
  regenerated.replace(at, fresh.string().size(), recorded_out);
  EXPECT_EQ(regenerated, committed) << "data/fitted is stale: run scripts/regenerate.sh";
}

TEST_F(BatteryCli, CodegenRejectsABrokenCoefficientFile) {
  const std::string bad = write("bad.json", "{\"kind\": \"battery\", \"speeds\": [ {\"speed_cm_s\": 0,\n  oops } ]}");
  const fs::path out = dir_ / "out.hpp";
  const CliRun r = run("codegen \"" + bad + "\" -o \"" + out.string() + "\"");
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.err.find("bad.json:2:"), std::string::npos) << r.err;
  EXPECT_FALSE(fs::exists(out));
}

TEST_F(BatteryCli, SimulateReproducesThePluginAndRejectsBadInput) {
  const std::string profile = write("profile.csv", "time_s,speed_cm_s\n0,7\n1,7\n");
  const CliRun r = run("simulate battery --model cubic --compat argos --profile \"" + profile + "\"");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_EQ(r.out.substr(0, r.out.find('\n', r.out.find('\n', 14) + 1) + 1),
            "time_s,charge\n0,1\n0.1,0.98983534873817192\n");
  const CliRun corrected = run("simulate battery --model cubic --coefficients plugin --profile \"" + profile + "\"");
  ASSERT_EQ(corrected.exit_code, 0) << corrected.err;
  EXPECT_EQ(std::count(corrected.out.begin(), corrected.out.end(), '\n'), 12);  // header, t=0, 10 ticks
  EXPECT_EQ(run("simulate battery --model quartic --profile \"" + profile + "\"").exit_code, 2);
  const std::string bad = write("bad_profile.csv", "time_s,speed_cm_s\n0,7\n1,x\n");
  const CliRun b = run("simulate battery --model linear --profile \"" + bad + "\"");
  EXPECT_EQ(b.exit_code, 2);
  EXPECT_NE(b.err.find("bad_profile.csv:3:3:"), std::string::npos) << b.err;
}

TEST_F(BatteryCli, HelpAndVersion) {
  EXPECT_EQ(run("--help").exit_code, 0);
  EXPECT_EQ(run("battery --help").exit_code, 0);
  const CliRun v = run("--version");
  EXPECT_EQ(v.exit_code, 0);
  EXPECT_NE(v.out.find("epuck2-fit"), std::string::npos);
  EXPECT_EQ(run("").exit_code, 2);
}
