// CLI paths that no test ran before session 14 (found by line coverage of the suite): a misspelt
// kind for `generate`, a misspelt discharge model for `simulate battery`, text columns of a
// `simulate --like` log, and `--` before diagnose's logs. Expected texts are docs/cli.md's and the
// kinds' names typed here.
#include <gtest/gtest.h>

#include <nlohmann/json.hpp>
#include <sstream>
#include <string>

#include "cli_harness.hpp"

namespace test_cli_corners_cpp {

using epuck2::testing::CliRun;

class CliCorners : public epuck2::testing::CliTest {};

TEST_F(CliCorners, GenerateAMisspeltKindNamesTheClosestAndEveryKind) {
  const CliRun r = run("generate lihgt --out-dir \"" + (dir_ / "g").string() + "\"");
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.err.find("unknown kind 'lihgt'; did you mean 'light'?"), std::string::npos) << r.err;
  for (const char* k : {"battery", "proximity", "light", "ground", "camera", "drive", "all"})
    EXPECT_NE(r.err.find(k), std::string::npos) << k << "\n" << r.err;
  EXPECT_FALSE(fs::exists(dir_ / "g")) << "nothing is recorded after a usage error";
  EXPECT_EQ(r.out, "");
}

TEST_F(CliCorners, SimulateBatteryAMisspeltModelNamesTheClosestAndTheFour) {
  const CliRun r = run("simulate battery --model cubik");
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.err.find("--model: unknown discharge model 'cubik'; did you mean 'cubic'?"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("simple, linear, cubic, approximated"), std::string::npos) << r.err;
  EXPECT_EQ(r.out, "");
  // The four names are taken, each giving a different run of the same profile.
  const std::string profile = write("profile.csv", "time_s,speed_cm_s\n0,5\n3000,10\n");
  std::string previous;
  for (const char* m : {"simple", "linear", "cubic", "approximated"}) {
    const CliRun ok = run("simulate battery --profile \"" + profile + "\" --model " + m);
    ASSERT_EQ(ok.exit_code, 0) << m << ": " << ok.err;
    EXPECT_NE(ok.out, previous) << m;
    previous = ok.out;
  }
}

// A log with a text column (notes) and a numeric extra column: the simulated log keeps the
// numeric one, drops the text one, and says so on standard error (docs/cli.md, simulate --like).
TEST_F(CliCorners, SimulateLikeDropsTextColumnsSayingSoAndKeepsNumericOnes) {
  const std::string log = write("g.csv", "grey,sensor,value,note,temp_c\n0.5,0,500,hello,20\n0.6,1,560,x,21\n1.0,2,900,y,22\n");
  const CliRun r = run("simulate ground --like \"" + log + "\"");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.err.find("simulate: text columns of " + log + " are not copied (only numeric columns are)"), std::string::npos) << r.err;
  std::istringstream in(r.out);
  std::string line, header;
  int rows = 0;
  while (std::getline(in, line)) {
    if (line.empty() || line[0] == '#') continue;
    if (header.empty()) {
      header = line;
      continue;
    }
    ++rows;
    // the copied temperature is the log's (20, 21, 22 in order)
    EXPECT_EQ(line.substr(line.rfind(',') + 1), std::to_string(19 + rows)) << line;
  }
  EXPECT_EQ(header, "grey,sensor,value,temp_c");
  EXPECT_EQ(rows, 3);
  // Without a text column: no such line.
  const std::string plain = write("p.csv", "grey,sensor,value,temp_c\n0.5,0,500,20\n");
  const CliRun p = run("simulate ground --like \"" + plain + "\"");
  ASSERT_EQ(p.exit_code, 0) << p.err;
  EXPECT_EQ(p.err.find("text columns"), std::string::npos) << p.err;
}

// `--` ends the options: what follows is a log, even a word diagnose would otherwise read as its
// --json option; the options before it still apply.
TEST_F(CliCorners, DiagnoseDoubleDashEndsTheOptions) {
  std::string text = "grey,sensor,value\n";
  for (int g = 0; g <= 10; ++g)
    for (int s = 0; s < 3; ++s)
      for (int k = 0; k < 3; ++k) text += std::to_string(g / 10.0) + "," + std::to_string(s) + "," + std::to_string(60 + 90 * g + k) + "\n";
  const std::string log = write("g.csv", text);
  const CliRun j = run("diagnose --json -- \"" + log + "\"");
  ASSERT_EQ(j.exit_code, 0) << j.err;
  EXPECT_EQ(nlohmann::json::parse(j.out).at("kind"), "ground");
  // After --, "--json" is a file name (that does not exist), not the option.
  const CliRun k = run("diagnose \"" + log + "\" -- --json");
  EXPECT_EQ(k.exit_code, 2) << k.out;
  EXPECT_NE(k.err.find("--json"), std::string::npos) << k.err;
  EXPECT_EQ(k.out, "");
}

}  // namespace test_cli_corners_cpp
