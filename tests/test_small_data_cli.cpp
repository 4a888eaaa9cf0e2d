// Small and partial data said plainly, progress on standard error, and the shipped example speed
// profile: through the real binary (EPUCK2_FIT_EXE) and, for the diagnosis's minimum and progress
// callback, through the library.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <nlohmann/json.hpp>
#include <sstream>

#include "cli_harness.hpp"
#include "epuck2/diagnose/diagnose.hpp"
#include "epuck2/logs/log.hpp"

using epuck2::testing::CliRun;
using epuck2::testing::slurp;
namespace fs = std::filesystem;
namespace dg = epuck2::diagnose;

namespace {

class SmallData : public epuck2::testing::CliTest {
 protected:
  static std::string q(const fs::path& p) { return "\"" + p.string() + "\""; }
  static fs::path source(const std::string& rel) { return fs::path(EPUCK2_SOURCE_DIR) / rel; }
};

const char kSevenProximityRows[] =
    "distance_m,sensor,value\n0.01,0,3000\n0.02,0,2000\n0.03,0,1200\n0.04,0,700\n0.05,0,400\n0.06,0,200\n0.07,0,100\n";

/// A one-sensor proximity log of `rows` rows: distances 0, 5, ..., 70 mm in turn, readings
/// falling with distance and a fixed +-20 count pattern (the values only need to be plausible).
std::string proximity_rows(int rows) {
  std::string out = "distance_m,sensor,value\n";
  for (int i = 0; i < rows; ++i) {
    const int mm = 5 * (i % 15);
    const double v = std::max(0.0, 4000.0 * std::exp(-mm / 15.0) + ((i * 7) % 5 - 2) * 10.0);
    out += std::to_string(mm / 1000.0) + ",0," + std::to_string(static_cast<int>(std::round(v))) + "\n";
  }
  return out;
}

}  // namespace

// ---- diagnose: a minimum of rows, from the folds and the parameters --------------------------

TEST_F(SmallData, DiagnoseOnSevenProximityRowsSaysTooFewAndNamesNoFinding) {
  const std::string log = write("p7.csv", kSevenProximityRows);
  const CliRun r = run("diagnose " + q(log));
  EXPECT_EQ(r.exit_code, 0) << r.err;  // a report was produced (docs/diagnose.md: exit 0)
  // One sensor: the base model's a, b, c and long_tail's amplitude and length, 5 parameters;
  // 5 folds x 3 rows x 5 parameters = 75 rows.
  EXPECT_NE(r.out.find("Too few rows (7) to judge effects; need at least 75"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("Verdict: not judged (too few rows: 7 of 75)"), std::string::npos) << r.out;
  EXPECT_EQ(r.out.find("Finding:"), std::string::npos) << r.out;
  EXPECT_EQ(r.out.find("saturation"), std::string::npos) << r.out;

  const CliRun j = run("diagnose --json - " + q(log));
  ASSERT_EQ(j.exit_code, 0) << j.err;
  const auto report = nlohmann::json::parse(j.out);
  EXPECT_EQ(report.at("verdict"), "not judged (too few rows: 7 of 75)");
  EXPECT_TRUE(report.at("too_few_rows").get<bool>());
  EXPECT_EQ(report.at("minimum_rows"), 75);
  EXPECT_TRUE(report.at("findings").empty());
  EXPECT_TRUE(report.at("heldout_mse_final").is_null());
  EXPECT_NE(report.at("heldout_mse_final_why").get<std::string>().find("too few rows (7)"), std::string::npos);
  EXPECT_TRUE(report.at("heldout_mse_plugin").is_number());
}

TEST(SmallDataLibrary, TheMinimumIsFoldsTimesRowsPerParameterTimesTheFirstModelsParameters) {
  const auto at = [](int rows) {
    return dg::diagnose({epuck2::logs::parse_log(proximity_rows(rows), "p.csv", epuck2::logs::Kind::proximity)});
  };
  const dg::Report below = at(74);
  EXPECT_TRUE(below.too_few_rows);
  EXPECT_EQ(below.minimum_rows, 75u);
  EXPECT_EQ(below.verdict_name(), "not judged (too few rows: 74 of 75)");
  EXPECT_EQ(below.verdict, dg::Verdict::not_judged);
  EXPECT_TRUE(below.findings.empty());
  EXPECT_TRUE(below.trials.empty());
  const dg::Report enough = at(75);
  EXPECT_FALSE(enough.too_few_rows) << enough.message;
  EXPECT_EQ(enough.minimum_rows, 75u);
  EXPECT_FALSE(enough.trials.empty());  // the search ran
  // Other settings, other minimum: 10 folds x 2 rows x 5 parameters = 100 rows.
  dg::Options o;
  o.folds = 10;
  o.blocks_per_fold = 4;
  o.rows_per_parameter = 2;
  const dg::Report ten = dg::diagnose({epuck2::logs::parse_log(proximity_rows(99), "p.csv", epuck2::logs::Kind::proximity)}, o);
  EXPECT_TRUE(ten.too_few_rows);
  EXPECT_EQ(ten.minimum_rows, 100u);
}

TEST(SmallDataLibrary, TheProgressCallbackFollowsTheStages) {
  std::vector<dg::Progress> seen;
  dg::Options o;
  o.progress = [&](const dg::Progress& p) { seen.push_back(p); };
  const dg::Report r = dg::diagnose({epuck2::logs::parse_log(proximity_rows(150), "p.csv", epuck2::logs::Kind::proximity)}, o);
  ASSERT_FALSE(r.too_few_rows) << r.message;
  ASSERT_GE(seen.size(), 4u);
  EXPECT_EQ(seen.front().stage, "screening");
  EXPECT_EQ(seen[1].stage, "recalibrating");
  EXPECT_EQ(seen.back().stage, "residual structure");
  // Step 1 fits every effect considered, counted 1..N with its cause.
  std::vector<std::string> step1;
  for (const auto& p : seen)
    if (p.stage == "fitting effect" && p.step == 1) {
      EXPECT_EQ(p.total, static_cast<int>(r.effects_considered.size()));
      EXPECT_EQ(p.done, static_cast<int>(step1.size()) + 1);
      step1.push_back(p.detail);
    }
  EXPECT_EQ(step1, r.effects_considered);
  // Too few rows: screened, then nothing fitted.
  seen.clear();
  dg::diagnose({epuck2::logs::parse_log(kSevenProximityRows, "p7.csv", epuck2::logs::Kind::proximity)}, o);
  ASSERT_EQ(seen.size(), 1u);
  EXPECT_EQ(seen.front().stage, "screening");
}

// ---- progress on standard error, never in the JSON -------------------------------------------

TEST_F(SmallData, DiagnoseProgressGoesToStandardErrorAndLeavesTheJsonAlone) {
  const std::string log = write("p150.csv", proximity_rows(150));
  const CliRun plain = run("diagnose --json - " + q(log));
  const CliRun shown = run("diagnose --progress --json - " + q(log));
  ASSERT_EQ(plain.exit_code, 0) << plain.err;
  ASSERT_EQ(shown.exit_code, 0) << shown.err;
  EXPECT_EQ(shown.out, plain.out);  // standard output: the same JSON, byte for byte
  EXPECT_NO_THROW(nlohmann::json::parse(shown.out));
  EXPECT_NE(shown.err.find("diagnose: recalibrating..."), std::string::npos) << shown.err;
  EXPECT_NE(shown.err.find("diagnose: fitting effect 1/"), std::string::npos) << shown.err;
  EXPECT_NE(shown.err.find("search step 1"), std::string::npos) << shown.err;
  // Standard error is a file here, not a terminal: no progress without --progress.
  EXPECT_EQ(plain.err.find("diagnose: fitting effect"), std::string::npos) << plain.err;
  // The human report with --progress: the report on standard output, progress not in it.
  const CliRun human = run("diagnose --progress " + q(log));
  EXPECT_EQ(human.out.find("fitting effect"), std::string::npos) << human.out;
}

TEST_F(SmallData, GenerateProgressGoesToStandardError) {
  const CliRun r = run("generate all --progress --out " + q(dir_ / "all"));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_EQ(r.out, "");
  for (const char* line : {"generate: recording battery logs (1/6)...", "generate: recording drive logs (6/6)..."})
    EXPECT_NE(r.err.find(line), std::string::npos) << r.err;
  const CliRun quiet = run("generate light --out " + q(dir_ / "light"));
  EXPECT_EQ(quiet.err.find("recording"), std::string::npos) << quiet.err;
}

// ---- battery and table5: the speeds covered and missing, by value ----------------------------

TEST_F(SmallData, Table5ListsTheCoveredAndMissingSpeedsByValue) {
  const std::string logs = " " + q(source("data/raw/battery/robot-a_speed-03.csv")) + " " + q(source("data/raw/battery/robot-a_speed-07.csv"));
  const CliRun r = run("table5" + logs);
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_NE(r.err.find("these logs cover 2 speeds: 3, 7 cm/s; missing: 0, 1, 2, 4, 5, 6, 8, 9, 10, 11, 12, 13, 14, 15 cm/s"),
            std::string::npos)
      << r.err;
  const CliRun j = run("table5 --json" + logs);
  EXPECT_EQ(j.exit_code, 1);
  const auto report = nlohmann::json::parse(j.out);
  EXPECT_FALSE(report.at("complete").get<bool>());
  EXPECT_EQ(report.at("speeds_covered_cm_s"), nlohmann::json({3, 7}));
  EXPECT_EQ(report.at("speeds_missing_cm_s"), nlohmann::json({0, 1, 2, 4, 5, 6, 8, 9, 10, 11, 12, 13, 14, 15}));
  // A speed that is not a whole 0..15 one is named as such.
  std::string half = slurp(source("data/raw/battery/robot-a_speed-03.csv"));
  for (std::size_t at = half.find("\n", half.find("time_s")); (at = half.find(",3,", at)) != std::string::npos;) half.replace(at, 3, ",2.5,");
  const std::string log = write("half.csv", half);
  const CliRun h = run("table5 " + q(log));
  EXPECT_NE(h.err.find("not one of 0..15: 2.5 cm/s"), std::string::npos) << h.err;
}

TEST_F(SmallData, BatteryListsMissingSpeedsAndWarnsOnWeakData) {
  const std::string logs = " " + q(source("data/raw/battery/robot-a_speed-03.csv")) + " " + q(source("data/raw/battery/robot-a_speed-07.csv"));
  const CliRun r = run("battery" + logs);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.out.find("speeds covered (cm/s): 3, 7"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("speeds missing (cm/s): 0, 1, 2, 4, 5, 6, 8, 9, 10, 11, 12, 13, 14, 15"), std::string::npos) << r.out;
  EXPECT_NE(r.err.find("no run at 0 cm/s: the Simple model's static slope m0 is taken from the moving runs"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("one run at 3, 7 cm/s"), std::string::npos) << r.err;
  const auto j = nlohmann::json::parse(run("battery --json" + logs).out);
  EXPECT_EQ(j.at("speeds_covered_cm_s"), nlohmann::json({3, 7}));
  EXPECT_EQ(j.at("speeds_missing_cm_s").size(), 14u);
  EXPECT_FALSE(j.at("complete_tables").get<bool>());
  EXPECT_GE(j.at("warnings").size(), 2u);
}

TEST_F(SmallData, ABatterySpeedWithTooFewRowsForItsModelsIsRefusedWithTheReason) {
  // 4 rows at 3 cm/s: the cubic has 4 parameters, one more row is the least for any residual.
  const std::string log = write("b4.csv", "time_s,speed_cm_s,charge\n0,3,1\n100,3,0.98\n200,3,0.95\n300,3,0.93\n");
  const CliRun r = run("battery " + q(log));
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_NE(r.err.find("cubic at 3 cm/s: too few observations (4) for 4 parameters"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("approximated (piecewise) at 3 cm/s: too few observations (4) for 5 parameters"), std::string::npos) << r.err;
}

// ---- sensors: a fit with few readings for its parameters warns -----------------------------

TEST_F(SmallData, SensorFitsWithFewReadingsForTheirParametersWarn) {
  // Proximity: 5 distances inside the 5 cm range for a, b, c and the noise (fewer than 12).
  const CliRun p = run("proximity " + q(write("p7.csv", kSevenProximityRows)));
  EXPECT_EQ(p.exit_code, 0) << p.err;
  EXPECT_NE(p.err.find("maxima fit: only 5 readings inside the rails for 3 free parameters and the noise (fewer than 3 per parameter)"),
            std::string::npos)
      << p.err;
  // Light: 2 readings for gamma and the noise.
  const CliRun l = run("light " + q(write("l2.csv", "distance_m,intensity,sensor,value\n0.1,0.5,0,3000\n0.2,0.5,0,3800\n")));
  EXPECT_EQ(l.exit_code, 0) << l.err;
  EXPECT_NE(l.err.find("only 2 readings inside the rails for 1 free parameter and the noise"), std::string::npos) << l.err;
  // Ground: one reading per sensor is refused, with the reason.
  const CliRun g = run("ground " + q(write("g3.csv", "grey,sensor,value\n0.5,0,500\n0.5,1,510\n0.5,2,505\n")));
  EXPECT_EQ(g.exit_code, 1);
  EXPECT_NE(g.err.find("too few readings inside the rails (1) for 2 parameters and the noise"), std::string::npos) << g.err;
}

// ---- the example speed profile ---------------------------------------------------------------

TEST_F(SmallData, TheExampleProfileRunsAsDocsCliMdShows) {
  const fs::path profile = source("data/profiles/example_profile.csv");
  ASSERT_TRUE(fs::exists(profile));
  // docs/cli.md's example: the plug-in's Cubic model, ARGoS-compatible.
  const CliRun c = run("simulate battery --model cubic --compat argos --profile " + q(profile));
  ASSERT_EQ(c.exit_code, 0) << c.err;
  EXPECT_EQ(std::count(c.out.begin(), c.out.end(), '\n'), 36002);  // header, t = 0, 36 000 ticks of 0.1 s
  // The Linear model with the published tables, corrected behaviour: the charge falls by dt/end[s]
  // at speed s, so after the hour it is 1 - sum(duration / end[s]), end[s] the published end times
  // (data/raw/battery/README.md, to 0.1 s: the sum is good to 3e-6).
  const CliRun l = run("simulate battery --model linear --coefficients plugin --profile " + q(profile));
  ASSERT_EQ(l.exit_code, 0) << l.err;
  const double end0 = 19743.5, end2 = 12856.6, end5 = 9355.3, end7 = 9729.1, end10 = 11057.3, end14 = 13228.3;
  const double expected = 1.0 - (600.0 / end0 + 600.0 / end5 + 600.0 / end10 + 600.0 / end2 + 600.0 / end14 + 600.0 / end7);
  const std::string last = l.out.substr(l.out.rfind('\n', l.out.size() - 2) + 1);
  EXPECT_EQ(last.substr(0, 5), "3600,");
  EXPECT_NEAR(std::stod(last.substr(5)), expected, 1e-5) << last;
}
