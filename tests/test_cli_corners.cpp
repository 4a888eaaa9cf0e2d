// CLI paths that no test ran before session 14 (found by line coverage of the suite): a misspelt
// kind for `generate`, a misspelt discharge model for `simulate battery`, text columns of a
// `simulate --like` log, and `--` before diagnose's logs. Expected texts are docs/cli.md's and the
// kinds' names typed here.
#include <gtest/gtest.h>

#include <algorithm>
#include <fstream>
#include <cmath>
#include <cstdio>
#include <cstdint>
#include <cstdlib>
#include <filesystem>
#include <functional>
#include <vector>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>

#include "cli_harness.hpp"

namespace test_cli_corners_cpp {

namespace fs = std::filesystem;
using epuck2::testing::CliRun;

class CliCorners : public epuck2::testing::CliTest {};

using epuck2::testing::shipped_fitted;
using epuck2::testing::shipped_logs;

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

// Light readings of a light beyond the sensor's 0.5 m range, or of intensity 0, are dark whatever
// gamma is: they are left out, each named by file:line with its reason, and the fit is the fit
// without them (the same parameters, to the last bit). A reading at exactly 0.5 m is in range and
// enters. The log: the virtual robot's at intensity 1.00, with four rows appended (lines counted
// here from the file).
TEST_F(CliCorners, LightOutOfRangeOrDarkRowsAreLeftOutByLineAndDoNotMoveTheFit) {
  ASSERT_EQ(run("generate light --out-dir \"" + (dir_ / "lg").string() + "\"").exit_code, 0);
  const std::string base = epuck2::testing::slurp(dir_ / "lg" / "light_intensity_1.00.csv");
  int lines = 0;
  for (char c : base) lines += c == '\n';
  const std::string a = write("a.csv", base);
  const std::string b = write("b.csv", base + "0.6,1,0,4095\n0.2,0,1,4095\n0.75,0,2,4095\n");
  const std::string c = write("c.csv", base + "0.6,1,0,4095\n0.5,1,0,4000\n0.2,0,1,4095\n");
  const CliRun ra = run("light \"" + a + "\" --json"), rb = run("light \"" + b + "\" --json"), rc = run("light \"" + c + "\" --json");
  ASSERT_EQ(ra.exit_code, 0) << ra.err;
  ASSERT_EQ(rb.exit_code, 0) << rb.err;
  ASSERT_EQ(rc.exit_code, 0) << rc.err;
  const auto ja = nlohmann::json::parse(ra.out), jb = nlohmann::json::parse(rb.out), jc = nlohmann::json::parse(rc.out);
  EXPECT_EQ(ja.at("parameters").at("gamma").get<double>(), jb.at("parameters").at("gamma").get<double>());
  EXPECT_EQ(jb.at("readings").get<int>(), ja.at("readings").get<int>() + 3);
  const auto& left = jb.at("left_out");
  ASSERT_EQ(left.at("count").get<int>(), 3) << left.dump();
  const std::string beyond = "light beyond the sensor's range (0.5 m)", dark = "no light (intensity 0)";
  const std::pair<int, std::string> want[3] = {{lines + 1, beyond}, {lines + 2, dark}, {lines + 3, beyond}};
  for (int i = 0; i < 3; ++i) {
    EXPECT_EQ(left.at("rows")[static_cast<std::size_t>(i)].at("where").get<std::string>(), b + ":" + std::to_string(want[i].first));
    EXPECT_EQ(left.at("rows")[static_cast<std::size_t>(i)].at("why").get<std::string>(), want[i].second);
  }
  // At exactly 0.5 m: in range, it enters (and moves gamma); the two others are left out.
  ASSERT_EQ(jc.at("left_out").at("count").get<int>(), 2) << jc.at("left_out").dump();
  EXPECT_EQ(jc.at("left_out").at("rows")[0].at("where").get<std::string>(), c + ":" + std::to_string(lines + 1));
  EXPECT_EQ(jc.at("left_out").at("rows")[1].at("where").get<std::string>(), c + ":" + std::to_string(lines + 3));
  EXPECT_NE(ja.at("parameters").at("gamma").get<double>(), jc.at("parameters").at("gamma").get<double>());
}

// A coefficient file that misnames a parameter of a covariate effect, or whose battery speeds are
// out of order, is refused by every reader with the JSON path (issue #22: one validation).
TEST_F(CliCorners, AMisnamedCovariateParameterOrBatterySpeedsOutOfOrderAreRefusedByEveryReader) {
  auto edit = [&](const std::string& kind, const std::string& name, const std::function<void(nlohmann::json&)>& f) {
    nlohmann::json j = shipped_fitted(kind);
    f(j);
    return write(name, j.dump(1));
  };
  const std::string drive = edit("drive", "d.json", [](nlohmann::json& j) {
    j["effects"] = {{"covariate:temperature_c", {{"slop", 0.5}, {"centre", 25.0}}}};
  });
  ASSERT_FALSE(shipped_logs("drive").empty());
  const std::string drive_log = shipped_logs("drive").front().string();
  for (const std::string& cmd : {"codegen \"" + drive + "\" -o \"" + (dir_ / "d.hpp").string() + "\"",
                                 "simulate drive --like \"" + drive_log + "\" --coefficients \"" + drive + "\"",
                                 "diagnose \"" + drive_log + "\" --coefficients \"" + drive + "\""}) {
    const CliRun r = run(cmd);
    EXPECT_EQ(r.exit_code, 2) << cmd << "\n" << r.err;
    EXPECT_NE(r.err.find("effects.covariate:temperature_c has no parameter 'slop' (it has: slope, centre) (at JSON path "
                         "/effects/covariate:temperature_c/slop)"),
              std::string::npos)
        << cmd << "\n" << r.err;
    EXPECT_NE(r.err.find(drive + ":"), std::string::npos) << cmd << "\n" << r.err;
  }
  const std::string battery = edit("battery", "b.json", [](nlohmann::json& j) { std::swap(j["speeds"][3], j["speeds"][4]); });
  const std::string profile = write("profile.csv", "time_s,speed_cm_s\n0,5\n");
  for (const std::string& cmd : {"codegen \"" + battery + "\" -o \"" + (dir_ / "b.hpp").string() + "\"",
                                 "simulate battery --coefficients \"" + battery + "\" --profile \"" + profile + "\" --model cubic"}) {
    const CliRun r = run(cmd);
    EXPECT_EQ(r.exit_code, 2) << cmd << "\n" << r.err;
    EXPECT_NE(r.err.find("speeds[3]: expected speed_cm_s 3 (at JSON path /speeds/3/speed_cm_s)"), std::string::npos) << cmd << "\n" << r.err;
    EXPECT_NE(r.err.find(battery + ":"), std::string::npos) << cmd << "\n" << r.err;
  }
  EXPECT_FALSE(fs::exists(dir_ / "d.hpp"));
  EXPECT_FALSE(fs::exists(dir_ / "b.hpp"));
}

// A battery segment's ends are charges in [0, 1] (docs/coefficient-files.md), each checked at its
// own key: the last segment of 5 cm/s ending at y2 = -0.05 two seconds after its start, and the
// first beginning at y1 = 1.02, each with its line h + m t through both ends (so that only the
// range is wrong), is refused at that key by codegen and simulate.
TEST_F(CliCorners, ABatterySegmentEndOutsideZeroToOneIsRefusedAtThatEnd) {
  const nlohmann::json shipped = shipped_fitted("battery");
  auto through = [](nlohmann::json& g) {  // the line through (x1, y1) and (x2, y2)
    const double x1 = g["x1_s"].get<double>(), x2 = g["x2_s"].get<double>(), y1 = g["y1"].get<double>(), y2 = g["y2"].get<double>();
    g["m"] = (y2 - y1) / (x2 - x1);
    g["h"] = y1 - g["m"].get<double>() * x1;
  };
  nlohmann::json low = shipped;
  {
    nlohmann::json& g = low["speeds"][5]["segments"][3];
    g["x2_s"] = g["x1_s"].get<double>() + 2.0;
    g["y2"] = -0.05;
    through(g);
  }
  nlohmann::json high = shipped;
  {
    nlohmann::json& g = high["speeds"][5]["segments"][0];
    ASSERT_EQ(g["x1_s"].get<double>(), 0.0);
    g["y1"] = 1.02;
    through(g);
  }
  const std::string profile = write("profile.csv", "time_s,speed_cm_s\n0,5\n");
  const std::pair<std::string, std::string> cases[] = {
      {write("low.json", low.dump(1)), "speeds[5].segments[3].y2 = -0.05 is outside its physical range [0.0, 1.0] charge (at JSON path /speeds/5/segments/3/y2)"},
      {write("high.json", high.dump(1)), "speeds[5].segments[0].y1 = 1.02 is outside its physical range [0.0, 1.0] charge (at JSON path /speeds/5/segments/0/y1)"}};
  for (const auto& [file, want] : cases)
    for (const std::string& cmd : {"codegen \"" + file + "\" -o \"" + (dir_ / "b.hpp").string() + "\"",
                                   "simulate battery --coefficients \"" + file + "\" --profile \"" + profile + "\" --model approximated"}) {
      const CliRun r = run(cmd);
      EXPECT_EQ(r.exit_code, 2) << cmd << "\n" << r.err;
      EXPECT_NE(r.err.find(file + ":"), std::string::npos) << cmd << "\n" << r.err;
      EXPECT_NE(r.err.find(want), std::string::npos) << cmd << "\n" << r.err;
    }
  EXPECT_FALSE(fs::exists(dir_ / "b.hpp"));
}

// The drive's ToF fit is judged on its own readings (docs/fitting.md, "A fit that does not fit"):
// the shipped drive logs with every second log's `# obstacle_distance_m` moved (0.3 m -> 0.9 m,
// then 1.5 m) make the ToF line miss its readings while the encoders fit as before. At 0.9 m:
// R^2 below 0.9, a warning naming the ToF fit, the file written; at 1.5 m: worse than a flat line,
// exit 1 and nothing written, unless --accept-misfit. The encoders' fit draws no such word.
TEST_F(CliCorners, TheDrivesToFFitIsJudgedOnTheToFsReadings) {
  const std::vector<fs::path> shipped = shipped_logs("drive");
  ASSERT_GE(shipped.size(), 10u);
  auto moved = [&](const std::string& folder, const std::string& metres) {
    fs::create_directories(dir_ / folder);
    std::string args;
    for (std::size_t i = 0; i < shipped.size(); ++i) {
      std::string text = epuck2::testing::slurp(shipped[i]);
      if (i % 2 == 1) {
        const std::size_t at = text.find("# obstacle_distance_m: ");
        if (at != std::string::npos) text = text.substr(0, at) + "# obstacle_distance_m: " + metres + text.substr(text.find('\n', at));
      }
      std::ofstream(dir_ / folder / shipped[i].filename()) << text;
      args += " \"" + (dir_ / folder / shipped[i].filename()).string() + "\"";
    }
    return args;
  };
  const std::string shipped_args = moved("same", "0.3");
  const CliRun base = run("drive" + shipped_args + " -o \"" + (dir_ / "base.json").string() + "\"");
  ASSERT_EQ(base.exit_code, 0) << base.err;
  EXPECT_EQ(base.err.find("ToF fit: R^2"), std::string::npos) << base.err;

  const std::string far = moved("far", "0.9");
  const CliRun w = run("drive" + far + " -o \"" + (dir_ / "far.json").string() + "\"");
  ASSERT_EQ(w.exit_code, 0) << w.err;
  EXPECT_TRUE(fs::exists(dir_ / "far.json"));
  const std::size_t at = w.err.find("drive: warning: ToF fit: R^2 = ");
  ASSERT_NE(at, std::string::npos) << w.err;
  EXPECT_LT(std::stod(w.err.substr(at + 31)), 0.9) << w.err;
  EXPECT_EQ(w.err.find("encoder fit: R^2"), std::string::npos) << w.err;

  const std::string farther = moved("farther", "1.5");
  const CliRun x = run("drive" + farther + " -o \"" + (dir_ / "farther.json").string() + "\"");
  EXPECT_EQ(x.exit_code, 1) << x.err;
  EXPECT_NE(x.err.find("ToF fit: R^2 = "), std::string::npos) << x.err;
  EXPECT_NE(x.err.find("the curve does worse than a flat line through the readings' mean. Nothing was written"), std::string::npos) << x.err;
  EXPECT_FALSE(fs::exists(dir_ / "farther.json"));
  const CliRun y = run("drive" + farther + " --accept-misfit -o \"" + (dir_ / "farther.json").string() + "\"");
  EXPECT_EQ(y.exit_code, 0) << y.err;
  EXPECT_NE(y.err.find("ToF fit (accepted by --accept-misfit)"), std::string::npos) << y.err;
  EXPECT_TRUE(fs::exists(dir_ / "farther.json"));
}

// A log column that carries the residuals' strongest structure is the diagnosis figure's x axis,
// labelled by its unit suffix (docs/cli.md, "Figures"): a column in metres drawn in mm, "_c" in °C,
// no suffix "as logged". Ground readings that follow the plug-in's 1023 grey exactly but drift by
// 20 counts per mm of the column, with a reading noise of sd 3 counts (a seeded generator).
TEST_F(CliCorners, TheDiagnosisFigureLabelsALogColumnByItsUnit) {
  std::uint64_t state = 20261127;
  auto unit = [&]() {
    state = state * 6364136223846793005ULL + 1442695040888963407ULL;
    return (static_cast<double>(state >> 11) + 0.5) / 9007199254740992.0;
  };
  auto normal = [&]() { return std::sqrt(-2.0 * std::log(unit())) * std::cos(2.0 * std::acos(-1.0) * unit()); };
  const std::pair<std::string, std::string> cases[] = {{"height_m", "height (mm)"},
                                                       {"temperature_c", "temperature (°C)"},
                                                       {"humidity", "humidity (as logged: no unit in its name)"}};
  for (const auto& [column, label] : cases) {
    std::string text = "grey,sensor,value," + column + "\n";
    for (int g = 0; g <= 10; ++g)
      for (int sensor = 0; sensor < 3; ++sensor)
        for (int i = 0; i < 20; ++i) {
          const double x = 1.0 + 4.0 * unit();  // 1 .. 5
          const double v = std::clamp(std::round(1023.0 * g / 10.0 - 20.0 * (x - 3.0) + 3.0 * normal()), 0.0, 1023.0);
          char row[96];
          std::snprintf(row, sizeof row, "%.1f,%d,%.0f,%.4f\n", g / 10.0, sensor, v, column == "height_m" ? x / 1000.0 : x);
          text += row;
        }
    const std::string log = write(column + ".csv", text);
    const fs::path scripts = dir_ / ("gp_" + column);
    fs::create_directories(scripts);
    const std::string cmd = "EPUCK2_PLOT_SCRIPT_DIR=\"" + scripts.string() + "\" \"" EPUCK2_FIT_EXE "\" diagnose \"" + log +
                            "\" --plot \"" + (dir_ / (column + ".png")).string() + "\" > /dev/null 2>&1";
    ASSERT_EQ(std::system(cmd.c_str()), 0) << cmd;
    const std::string gp = epuck2::testing::slurp(scripts / (column + ".png.gp"));
    EXPECT_NE(gp.find("set xlabel \"" + label + "\""), std::string::npos) << column;
  }
}

}  // namespace test_cli_corners_cpp
