// Round 11 of the fresh slips (bench/fresh-slips.md, "Round 11"): for areas its slips were planted
// in, tests whose expected values come from outside the code under test -- the docs' statements,
// the NIST certified values, hand-worked cases. Written by the lead after the round's GO, knowing
// the slips.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <regex>
#include <sstream>
#include <string>
#include <vector>

#include <sys/wait.h>
#include <unistd.h>

#include <nlohmann/json.hpp>

#include "cli_harness.hpp"
#include "epuck2/fit/fit_curve.hpp"

namespace test_round_eleven_slips_cpp {
namespace {

namespace fs = std::filesystem;
using nlohmann::json;

using epuck2::testing::slurp;
/// The real binary: standard output to DIR/out, standard error to DIR/err; the exit code.
int r11_run(const std::string& args, const fs::path& dir) {
  const std::string cmd = "cd '" + dir.string() + "' && '" EPUCK2_FIT_EXE "' " + args + " >'" + (dir / "out").string() + "' 2>'" +
                          (dir / "err").string() + "'";
  const int rc = std::system(cmd.c_str());
  return WIFEXITED(rc) ? WEXITSTATUS(rc) : -1;
}
fs::path r11_scratch() {
  char tmpl[] = "/tmp/epuck2-r11-XXXXXX";
  EXPECT_NE(::mkdtemp(tmpl), nullptr);
  return tmpl;
}
std::string shipped(const std::string& rel) { return std::string(EPUCK2_SOURCE_DIR) + "/" + rel; }
/// The shipped logs of a kind as arguments, in name order.
std::string shipped_logs(const std::string& kind) { return epuck2::testing::shipped_args(kind); }

// ---- nist: every LRE from the certified values, the summary's minima over the runs ----

/// The log relative error of `q` against certified `c`: -log10(|q - c| / |c|), at most the
/// certified digits (11), and 11 where they agree exactly (NIST StRD's definition).
double lre(double q, double c) {
  if (q == c) return 11.0;
  return std::clamp(-std::log10(std::abs(q - c) / std::abs(c)), 0.0, 11.0);
}

TEST(RoundElevenNist, EveryLreIsWorkedFromTheCertifiedValuesAndTheSummaryIsTheirMinimum) {
  const fs::path d = r11_scratch();
  fs::create_directory(d / "nist");
  for (const char* p : {"Misra1a", "Chwirut2", "DanWood", "BoxBOD"})
    fs::copy_file(shipped(std::string("tests/data/nist/") + p + ".dat"), d / "nist" / (std::string(p) + ".dat"));
  ASSERT_EQ(r11_run("nist nist --json", d), 0) << slurp(d / "err");
  const json j = json::parse(slurp(d / "out"));
  double min_lre = 99, min_se = 99, min_rss = 99;
  int at_target = 0;
  ASSERT_EQ(j["runs"].size(), 8u);  // two starts each
  for (const json& r : j["runs"]) {
    double run_min = 99, run_se = 99;
    for (const json& p : r["parameters"]) {
      const double l = lre(p["value"], p["certified"]), s = lre(p["std_error"], p["certified_std_error"]);
      EXPECT_NEAR(p["lre"].get<double>(), l, 1e-9) << r["problem"] << " " << p["name"];
      EXPECT_NEAR(p["std_error_lre"].get<double>(), s, 1e-9) << r["problem"] << " " << p["name"];
      run_min = std::min(run_min, l);
      run_se = std::min(run_se, s);
    }
    const double rl = lre(r["rss"], r["certified_rss"]);
    EXPECT_NEAR(r["rss_lre"].get<double>(), rl, 1e-9) << r["problem"];
    EXPECT_NEAR(r["min_lre"].get<double>(), run_min, 1e-9) << r["problem"];
    EXPECT_NEAR(r["min_std_error_lre"].get<double>(), run_se, 1e-9) << r["problem"];
    // The target (docs/cli.md): parameter LRE >= 6 and standard-error LRE >= 4.
    EXPECT_EQ(r["at_target"].get<bool>(), run_min >= 6 && run_se >= 4) << r["problem"];
    at_target += run_min >= 6 && run_se >= 4;
    min_lre = std::min(min_lre, run_min);
    min_se = std::min(min_se, run_se);
    min_rss = std::min(min_rss, rl);
  }
  const json& s = j["summary"];
  EXPECT_NEAR(s["min_lre"].get<double>(), min_lre, 1e-9);
  EXPECT_NEAR(s["min_std_error_lre"].get<double>(), min_se, 1e-9);
  EXPECT_NEAR(s["min_rss_lre"].get<double>(), min_rss, 1e-9);
  EXPECT_EQ(s["at_target"].get<int>(), at_target);
  EXPECT_EQ(s["runs"].get<int>(), 8);
  // (with these four the three minima differ in their printed digits, so that one taken for another shows)
  EXPECT_GT(std::abs(min_lre - min_rss), 0.02);
  EXPECT_GT(std::abs(min_se - min_rss), 0.02);
  // The text's summary line says the same.
  ASSERT_EQ(r11_run("nist nist", d), 0);
  char want[200];
  std::snprintf(want, sizeof want, "min parameter LRE %.2f, min standard-error LRE %.2f, min RSS LRE %.2f", min_lre, min_se, min_rss);
  EXPECT_NE(slurp(d / "out").find(want), std::string::npos) << slurp(d / "out") << "\nexpected: " << want;
  fs::remove_all(d);
}

// ---- a curve fit's size (docs/fitting.md: refused below parameters + 1) ----

struct R11Line {
  static constexpr int kParameters = 2;
  template <typename T>
  T operator()(const T* p, double x) const {
    return p[0] + p[1] * x;
  }
};

TEST(RoundElevenFitCurve, ALineThroughTwoPointsIsRefusedThroughThreeItHasItsError) {
  namespace fit = epuck2::fit;
  const fit::FitResult two = fit::fit_curve(R11Line{}, {0, 1}, {1.0, 3.0}, {{"a", 0.0}, {"b", 0.0}});
  EXPECT_FALSE(two.usable) << "two points, two parameters: nothing left to measure the error with";
  EXPECT_NE(two.message.find("too few observations (2) for 2 parameters"), std::string::npos) << two.message;
  // (0, 1), (1, 3), (2, 4) by hand: slope 1.5, intercept 7/6, residuals -1/6, 1/3, -1/6, RSS 1/6,
  // residual variance RSS / (3 - 2) = 1/6; the slope's error sqrt((1/6) / Sxx), Sxx = 2: 0.288675.
  const fit::FitResult three = fit::fit_curve(R11Line{}, {0, 1, 2}, {1.0, 3.0, 4.0}, {{"a", 0.0}, {"b", 0.0}});
  ASSERT_TRUE(three.usable) << three.message;
  EXPECT_NEAR(three.value("b"), 1.5, 1e-9);
  EXPECT_NEAR(three.value("a"), 7.0 / 6.0, 1e-9);
  EXPECT_NEAR(three.std_error("b"), std::sqrt(1.0 / 12.0), 1e-6);
}

// ---- wild readings: judged against their replicates in groups of at least 3, else against the
// curve (docs/fitting.md, "Wild readings are left out, and listed") ----

// A ground log whose grey 0.5 reads 60 counts above the line (a curve the model misses there), the
// others on it within 1 count, `per` readings per sensor and grey. With 3 (a replicate group) the
// readings at 0.5 agree with each other: none is wild, none left out. With 2 (no group) they are
// judged against the line, 60 counts off it with a noise sd about 1: left out.
TEST(RoundElevenReplicates, GroupsOfThreeAreJudgedAgainstThemselvesPairsAgainstTheCurve) {
  const fs::path d = r11_scratch();
  auto write = [&](const std::string& name, int per) {
    std::ofstream out(d / name);
    out << "# robot: r\ngrey,sensor,value\n";
    for (int g = 0; g <= 10; ++g)
      for (int s = 0; s < 3; ++s)
        for (int i = 0; i < per; ++i) out << g / 10.0 << "," << s << "," << 60 + 90 * g + (g == 5 ? 60 : 0) + (i % 3) - 1 << "\n";
  };
  write("three.csv", 3);
  write("two.csv", 2);
  auto outliers = [&](const std::string& log) {
    EXPECT_EQ(r11_run("ground " + log + " --json --accept-misfit", d), 0) << slurp(d / "err");
    const json j = json::parse(slurp(d / "out"));
    std::size_t n = 0;
    for (const auto& [name, f] : j["fits"].items()) n += f["outliers"].get<std::size_t>();
    return n;
  };
  EXPECT_EQ(outliers("three.csv"), 0u) << "groups of 3: each reading judged against its replicates";
  EXPECT_EQ(outliers("two.csv"), 6u) << "pairs: the 2 readings at 0.5 of each of the 3 sensors judged against the line";
  fs::remove_all(d);
}

// ---- the diagnosis's base from a file (docs/diagnose.md: `--coefficients` gives the base model,
// which the diagnosis recalibrates): a file's gamma below or above the logs' is only where the
// recalibration starts, never a bound. The shipped light logs' calibration (`light --json`, the
// calibration's own fit) says where it must end, within 1 %. ----

TEST(RoundElevenDiagnosisBase, AFilesValueIsAStartNotABound) {
  const fs::path d = r11_scratch();
  const std::string logs = shipped_logs("light");
  ASSERT_EQ(r11_run("light" + logs + " --json", d), 0);
  const double calibrated = json::parse(slurp(d / "out"))["parameters"]["gamma"];
  for (const double start : {0.06, 0.09}) {
    json f = json::parse(slurp(shipped("data/fitted/light.json")));
    f["parameters"]["gamma"] = start;
    f.erase("per_sensor");
    std::ofstream(d / "base.json") << f.dump(2);
    ASSERT_EQ(r11_run("diagnose" + logs + " --coefficients base.json --json", d), 0) << slurp(d / "err");
    const double found = json::parse(slurp(d / "out"))["recalibrated"]["gamma_m"];
    EXPECT_NEAR(found, calibrated, 0.01 * calibrated) << "the file's gamma " << start << " held the recalibration";
  }
  fs::remove_all(d);
}

// ---- an output that is a symbolic link: written through it to its target (docs/cli.md,
// Conventions), a relative target taken from the link's own folder, as the system does ----

TEST(RoundElevenOutputs, ARelativeLinkIsFollowedFromItsOwnFolder) {
  const fs::path d = r11_scratch();
  fs::create_directories(d / "run" / "x");
  fs::create_directories(d / "links");
  fs::create_directories(d / "real");
  fs::create_symlink("../real/ground.json", d / "links" / "ground.json");
  // Run from d/run/x: the link's target read from the working folder would be d/run/real/...;
  // from the link's folder it is d/real.
  const std::string cmd = "cd '" + (d / "run" / "x").string() + "' && '" EPUCK2_FIT_EXE "' ground '" +
                          shipped("data/raw/ground/ground_virtual-epuck2-1.csv") + "' -o ../../links/ground.json >/dev/null 2>'" +
                          (d / "err").string() + "'";
  ASSERT_EQ(std::system(cmd.c_str()), 0) << slurp(d / "err");
  EXPECT_TRUE(fs::is_symlink(d / "links" / "ground.json")) << "the link was replaced by a file";
  ASSERT_TRUE(fs::exists(d / "real" / "ground.json"));
  EXPECT_EQ(json::parse(slurp(d / "real" / "ground.json"))["kind"], "ground");
  EXPECT_FALSE(fs::exists(d / "ground.json"));
  EXPECT_FALSE(fs::exists(d / "run" / "real"));
  fs::remove_all(d);
}

// ---- a drive log's two wheels, each its own columns (docs/logs.md: left_steps, right_steps) ----

// A turn written by hand: from 1 s, left 5 cm/s and right 2.5 cm/s, the host's whole steps/s
// round(0.05 x 7763.656) = 388 and 194, the encoders floor(rate x (t - 1)); the ToF sees nothing
// (8190). Added to the shipped drive logs, it adds no outlier to the encoders' fit and leaves their
// MSE within 10 % and steps per metre within 0.01 %: each wheel's steps are read from its column.
TEST(RoundElevenDrive, ATurnsWheelsAreEachReadFromTheirOwnColumn) {
  const fs::path d = r11_scratch();
  {
    std::ofstream out(d / "turn.csv");
    out << "# robot: virtual-epuck2-1\n# obstacle_distance_m: 0.3\ntime_s,left_speed_cm_s,right_speed_cm_s,left_steps,right_steps,tof_mm\n";
    for (int k = 0; k < 100; ++k) {
      const double t = k / 10.0;
      const bool moving = k >= 10;
      const long l = moving ? static_cast<long>(std::floor(388.0 * (k - 10) / 10.0 + 1e-9)) : 0;
      const long r = moving ? static_cast<long>(std::floor(194.0 * (k - 10) / 10.0 + 1e-9)) : 0;
      out << t << "," << (moving ? 5 : 0) << "," << (moving ? 2.5 : 0) << "," << l << "," << r << ",8190\n";
    }
  }
  const std::string logs = shipped_logs("drive");
  ASSERT_EQ(r11_run("drive" + logs + " --json", d), 0) << slurp(d / "err");
  const json without = json::parse(slurp(d / "out"));
  ASSERT_EQ(r11_run("drive" + logs + " turn.csv --json", d), 0) << slurp(d / "err");
  const json with = json::parse(slurp(d / "out"));
  EXPECT_EQ(with["fits"]["steps"]["outliers"], without["fits"]["steps"]["outliers"]);
  EXPECT_NEAR(with["fits"]["steps"]["mse"].get<double>(), without["fits"]["steps"]["mse"].get<double>(),
              0.1 * without["fits"]["steps"]["mse"].get<double>());
  EXPECT_NEAR(with["parameters"]["steps_per_m"].get<double>(), without["parameters"]["steps_per_m"].get<double>(),
              1e-4 * without["parameters"]["steps_per_m"].get<double>());
  fs::remove_all(d);
}

// ---- generate: --out-dir, or its first spelling --out; both naming one folder is that folder ----

TEST(RoundElevenGenerate, BothSpellingsOfOneFolderAreThatFolderTwoFoldersAreExitTwo) {
  const fs::path d = r11_scratch();
  ASSERT_EQ(r11_run("generate ground --out-dir g --out g", d), 0) << slurp(d / "err");
  EXPECT_TRUE(fs::exists(d / "g" / "ground_virtual-epuck2-1.csv"));
  ASSERT_EQ(r11_run("generate ground --out old", d), 0) << slurp(d / "err");
  EXPECT_TRUE(fs::exists(d / "old" / "ground_virtual-epuck2-1.csv"));
  EXPECT_EQ(r11_run("generate ground --out-dir a --out b", d), 2);
  const std::string err = slurp(d / "err");
  EXPECT_NE(err.find("--out-dir a"), std::string::npos) << err;
  EXPECT_NE(err.find("--out b"), std::string::npos) << err;
  EXPECT_FALSE(fs::exists(d / "a"));
  EXPECT_FALSE(fs::exists(d / "b"));
  fs::remove_all(d);
}

// ---- the sensor fits' --reject-sd (docs/cli.md: readings farther than X noise sd from the curve
// are outliers, default 4; docs/fitting.md: it judges the readings without replicates, such as a
// drive run's encoders and ToF) ----

TEST(RoundElevenRejectSd, ANarrowerRejectionLeavesOutMoreReadings) {
  const fs::path d = r11_scratch();
  const std::string logs = shipped_logs("drive");
  auto outliers = [&](const std::string& opt) {
    EXPECT_EQ(r11_run("drive" + logs + " --json " + opt, d), 0) << opt << ": " << slurp(d / "err");
    const json j = json::parse(slurp(d / "out"));
    std::size_t n = 0;
    for (const auto& [name, f] : j["fits"].items()) n += f["outliers"].get<std::size_t>();
    return n;
  };
  const std::size_t at4 = outliers(""), at2 = outliers("--reject-sd 2"), at100 = outliers("--reject-sd 100"), at4b = outliers("--reject-sd 4");
  EXPECT_EQ(at4, at4b) << "the default is 4";
  // About 3300 readings: beyond 2 sd of a normal about 4.6 % (150), beyond 4 sd only the wild ones
  // (the README's 6 ToF and the steps beyond the cap's transient), beyond 100 sd none.
  EXPECT_GT(at2, at4 + 100) << "2 sd: " << at2 << ", 4 sd: " << at4;
  EXPECT_LT(at100, at4);
  EXPECT_EQ(at100, 0u);
  fs::remove_all(d);
}

// ---- the diagnosis's covariates: a numeric extra column that every log has (docs/diagnose.md),
// never voltage_v ----

TEST(RoundElevenCovariates, AColumnSomeLogsLackIsNoCandidateNorIsVoltage) {
  const fs::path d = r11_scratch();
  // Two ground logs: with and without a temperature column, in either order.
  auto ground = [&](const std::string& name, bool temperature, int seed) {
    std::ofstream out(d / name);
    out << "# robot: r\n" << (temperature ? "grey,sensor,value,temperature_c\n" : "grey,sensor,value\n");
    for (int g = 0; g <= 10; ++g)
      for (int s = 0; s < 3; ++s)
        for (int i = 0; i < 6; ++i) {
          out << g / 10.0 << "," << s << "," << std::lround(60 + 900 * g / 10.0 + ((i * 7 + seed) % 5) - 2);
          if (temperature) out << "," << 20 + (i * 3 + g + seed) % 10;
          out << "\n";
        }
  };
  ground("a_with.csv", true, 1);
  ground("b_without.csv", false, 2);
  ground("c_with.csv", true, 3);
  for (const std::string& logs : {"a_with.csv b_without.csv", "b_without.csv c_with.csv", "a_with.csv b_without.csv c_with.csv"}) {
    ASSERT_EQ(r11_run("diagnose " + logs + " --json", d), 0) << logs << ": " << slurp(d / "err");
    const json j = json::parse(slurp(d / "out"));
    for (const auto& e : j["effects_considered"])
      EXPECT_NE(e.get<std::string>(), "covariate:temperature_c") << logs << ": a column not every log has";
  }
  ASSERT_EQ(r11_run("diagnose a_with.csv c_with.csv --json", d), 0) << slurp(d / "err");
  const json both = json::parse(slurp(d / "out"));
  EXPECT_NE(std::find(both["effects_considered"].begin(), both["effects_considered"].end(), "covariate:temperature_c"),
            both["effects_considered"].end())
      << "both logs have it: a candidate";
  // Battery logs carry voltage_v, a consequence of the charge: never a covariate.
  ASSERT_EQ(r11_run("diagnose '" + shipped("data/raw/battery/robot-a_speed-05.csv") + "' '" +
                        shipped("data/raw/battery/robot-b_speed-05.csv") + "' --json",
                    d),
            0)
      << slurp(d / "err");
  for (const auto& e : json::parse(slurp(d / "out"))["effects_considered"])
    EXPECT_NE(e.get<std::string>(), "covariate:voltage_v");
  fs::remove_all(d);
}

// ---- battery tables: a flat segment (docs/coefficient-files.md: y2 <= y1, m in [-1, 0]) ----

TEST(RoundElevenBatteryTables, AFlatSegmentIsRead) {
  const fs::path d = r11_scratch();
  json b = json::parse(slurp(shipped("data/fitted/battery.json")));
  json& seg = b["speeds"][3]["segments"][0];
  seg["m"] = 0.0;
  seg["h"] = 1.0;
  seg["y1"] = 1.0;
  seg["y2"] = 1.0;  // full for its first x2_s seconds: the band does not rise
  std::ofstream(d / "flat.json") << b.dump(2);
  ASSERT_EQ(r11_run("simulate battery --model approximated --coefficients flat.json --profile '" +
                        shipped("data/profiles/example_profile.csv") + "' -o sim.csv",
                    d),
            0)
      << slurp(d / "err");
  // A rising one is refused where it rises.
  seg["y2"] = 1.0;
  seg["y1"] = 0.99;
  seg["h"] = 0.99;
  seg["m"] = 0.0;
  std::ofstream(d / "rise.json") << b.dump(2);
  EXPECT_EQ(r11_run("simulate battery --model approximated --coefficients rise.json --profile '" +
                        shipped("data/profiles/example_profile.csv") + "' -o sim2.csv",
                    d),
            2);
  EXPECT_NE(slurp(d / "err").find("/speeds/3/segments/0/"), std::string::npos) << slurp(d / "err");
  fs::remove_all(d);
}

// ---- the text report's outliers (docs/cli.md: the first five listed by file:line, then how many
// more; the JSON lists them all) ----

TEST(RoundElevenReport, TheFirstFiveOutliersThenHowManyMore) {
  const fs::path d = r11_scratch();
  const std::string logs = shipped_logs("light");
  ASSERT_EQ(r11_run("light" + logs, d), 0);
  const std::string text = slurp(d / "out");
  ASSERT_EQ(r11_run("light" + logs + " --json", d), 0);
  const json j = json::parse(slurp(d / "out"));
  const std::size_t total = j["fits"]["gamma"]["outliers"];
  ASSERT_GT(total, 6u) << "the pooled fit leaves out more than six: the listing is cut";
  // The pooled fit's block: the first block of outlier lines.
  std::istringstream in(text);
  std::string line;
  std::size_t listed = 0;
  std::string more;
  bool in_block = false;
  while (std::getline(in, line)) {
    const bool outlier = line.find("    outlier: ") == 0;
    if (outlier) {
      in_block = true;
      ++listed;
    } else if (in_block) {
      more = line;
      break;
    }
  }
  EXPECT_EQ(listed, 5u);
  EXPECT_EQ(more, "    ... and " + std::to_string(total - 5) + " more (all in the JSON)");
  fs::remove_all(d);
}

}  // namespace
}  // namespace test_round_eleven_slips_cpp
