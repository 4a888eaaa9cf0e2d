// Issue #24, items 2 and 4: every output path is checked before any work (exit 2 at once, naming
// the path), and the reports say what they did: the base model named as it is, unambiguous
// covariate names, sections only where they apply, undefined statistics not printed, every
// writing command saying what it wrote, a simulated log's own metadata, a generated header naming
// the logs it came from. The real binary on the shipped logs and on small files written here.
#include <cmath>
#include <functional>
#include <set>
#include <nlohmann/json.hpp>

#include "cli_harness.hpp"
#include "epuck2/calibrate/report_json.hpp"
#include "epuck2/fit/report.hpp"

using epuck2::testing::CliRun;
using epuck2::testing::CliTest;
using epuck2::testing::slurp;
namespace fs = std::filesystem;

namespace {

std::string src_wording(const std::string& relative) { return "\"" + (fs::path(EPUCK2_SOURCE_DIR) / relative).string() + "\""; }

bool contains_wording(const std::string& text, const std::string& part) { return text.find(part) != std::string::npos; }

}  // namespace

// ----- Item 2: outputs fail fast ------------------------------------------------------------------

class OutputsFailFast : public CliTest {};

// Every option that names a file to write, in every subcommand: a folder that does not exist is
// exit 2 naming the path, before anything is read. The logs given are broken on purpose: had the
// run started, the error would have named the log (bad.csv:4) instead of the output.
TEST_F(OutputsFailFast, EveryOutputOptionIsCheckedBeforeTheLogsAreRead) {
  const std::string bad = "\"" + write("bad.csv", "grey,sensor,value\n0,0,64\n0.5,0,x\n") + "\"";
  const std::string battery_bad = "\"" + write("battery_bad.csv", "time_s,charge,speed_cm_s\n0,1,x\n") + "\"";
  const std::string missing = (dir_ / "no_such_folder").string();
  struct Case {
    std::string args, path;
  };
  const std::vector<Case> cases = {
      {"ground " + bad + " -o \"" + missing + "/g.json\"", missing + "/g.json"},
      {"ground " + bad + " --plot \"" + missing + "/g.png\"", missing + "/g.png"},
      {"proximity " + bad + " -o \"" + missing + "/p.json\"", missing + "/p.json"},
      {"proximity " + bad + " --plot \"" + missing + "/p.png\"", missing + "/p.png"},
      {"light " + bad + " -o \"" + missing + "/l.json\"", missing + "/l.json"},
      {"light " + bad + " --plot \"" + missing + "/l.pdf\"", missing + "/l.pdf"},
      {"camera " + bad + " -o \"" + missing + "/c.json\"", missing + "/c.json"},
      {"drive " + bad + " -o \"" + missing + "/d.json\"", missing + "/d.json"},
      {"drive " + bad + " --plot \"" + missing + "/d.svg\"", missing + "/d.svg"},
      {"camera " + bad + " --plot \"" + missing + "/c.svg\"", missing + "/c.svg"},
      {"battery " + battery_bad + " -o \"" + missing + "/b.json\"", missing + "/b.json"},
      {"battery " + battery_bad + " --plot \"" + missing + "/b.pdf\"", missing + "/b.pdf"},
      {"battery " + battery_bad + " --plot-lifetime \"" + missing + "/l.png\"", missing + "/l.png"},
      {"battery " + battery_bad + " --plot-charge-map \"" + missing + "/m.png\"", missing + "/m.png"},
      {"table5 " + battery_bad + " -o \"" + missing + "/t.json\"", missing + "/t.json"},
      {"diagnose " + bad + " -o \"" + missing + "/d.json\"", missing + "/d.json"},
      {"diagnose " + bad + " --plot \"" + missing + "/d.png\"", missing + "/d.png"},
      {"diagnose " + bad + " --json \"" + missing + "/d.json\"", missing + "/d.json"},
      {"simulate ground --like " + bad + " -o \"" + missing + "/s.csv\"", missing + "/s.csv"},
      {"simulate battery --profile " + src_wording("data/profiles/example_profile.csv") + " -o \"" + missing + "/s.csv\"",
       missing + "/s.csv"},
      {"codegen " + src_wording("data/fitted/ground.json") + " -o \"" + missing + "/h.hpp\"", missing + "/h.hpp"},
      {"nist " + src_wording("tests/data/nist") + " -o \"" + missing + "/n.json\"", missing + "/n.json"},
  };
  for (const auto& c : cases) {
    SCOPED_TRACE(c.args);
    const CliRun r = run(c.args);
    EXPECT_EQ(r.exit_code, 2) << r.err;
    EXPECT_TRUE(contains_wording(r.err, "'" + c.path + "'")) << r.err;  // the path as given
    EXPECT_TRUE(contains_wording(r.err, "does not exist")) << r.err;
    EXPECT_FALSE(contains_wording(r.err, "bad.csv")) << "the logs were read before the output was checked: " << r.err;
    EXPECT_EQ(r.out, "");  // no report: nothing ran
    EXPECT_FALSE(fs::exists(missing));
  }
}

// generate creates its --out-dir, but a file where the path needs a folder is exit 2 at once,
// naming the path, with nothing recorded (it was a bare "filesystem error" from the middle of the
// run).
TEST_F(OutputsFailFast, GenerateChecksItsFolderBeforeRecording) {
  const std::string file = write("plain.txt", "x\n");
  const CliRun r = run("generate ground --out-dir \"" + file + "/logs\"");
  EXPECT_EQ(r.exit_code, 2) << r.err;
  EXPECT_TRUE(contains_wording(r.err, "--out-dir: '" + file + "/logs': '" + file + "' is not a folder")) << r.err;
  EXPECT_FALSE(contains_wording(r.err, "filesystem error")) << r.err;
  EXPECT_EQ(slurp(file), "x\n");
  // A folder that does not exist yet is created, as documented.
  const CliRun ok = run("generate ground --out-dir \"" + (dir_ / "new" / "logs").string() + "\"");
  EXPECT_EQ(ok.exit_code, 0) << ok.err;
  EXPECT_TRUE(fs::exists(dir_ / "new" / "logs" / "ground_virtual-epuck2-1.csv"));
}

TEST_F(OutputsFailFast, AFolderOrAFileInThePathIsRefusedByName) {
  const std::string log = src_wording("data/raw/ground/ground_virtual-epuck2-1.csv");
  // -o naming an existing folder.
  CliRun r = run("ground " + log + " -o \"" + dir_.string() + "\"");
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_TRUE(contains_wording(r.err, "'" + dir_.string() + "' is a folder")) << r.err;
  // A file where the path needs a folder.
  const std::string file = write("plain.txt", "x\n");
  r = run("ground " + log + " --plot \"" + file + "/g.png\"");
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_TRUE(contains_wording(r.err, "'" + file + "' is not a folder")) << r.err;
  EXPECT_EQ(slurp(file), "x\n");  // untouched
  // diagnose's old spelling --plot DIR still takes an existing folder.
  r = run("diagnose --plot \"" + dir_.string() + "\" " + log);
  EXPECT_EQ(r.exit_code, 0) << r.err;
  EXPECT_TRUE(fs::exists(dir_ / "diagnose_ground.png"));
}

TEST_F(OutputsFailFast, AFileInTheCurrentFolderAndStandardOutputPass) {
  const std::string log = src_wording("data/raw/ground/ground_virtual-epuck2-1.csv");
  CliRun r = run("ground " + log + " -o g.json", dir_.string());  // no folder part: the current one
  EXPECT_EQ(r.exit_code, 0) << r.err;
  EXPECT_TRUE(fs::exists(dir_ / "g.json"));
  r = run("diagnose --json - " + log);  // "-": standard output
  EXPECT_EQ(r.exit_code, 0) << r.err;
  EXPECT_EQ(r.out.front(), '{');
}

// ----- Item 4: reports say what they did ---------------------------------------------------------

class ReportWording : public CliTest {};

TEST_F(ReportWording, TheBaseModelIsNamedAsItIs) {
  const std::string log = src_wording("data/raw/ground/ground_virtual-epuck2-1.csv");
  CliRun r = run("diagnose " + log);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_TRUE(contains_wording(r.out, "\nThe plug-in's model with the coefficients given, before recalibration: MSE ")) << r.out;
  // The user's own coefficient file: its name, never "the plug-in's".
  const std::string mine = (dir_ / "my_ground.json").string();
  fs::copy_file(fs::path(EPUCK2_SOURCE_DIR) / "data/fitted/ground.json", mine);
  r = run("diagnose --coefficients \"" + mine + "\" " + log);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  // The shipped file holds each robot's set: the log's robot's own is the base (probe 6, defect 03).
  EXPECT_TRUE(contains_wording(r.out, "\n" + mine + "'s model with robot virtual-epuck2-1's coefficients (robots.virtual-epuck2-1), before recalibration: MSE ")) << r.out;
  EXPECT_FALSE(contains_wording(r.out, "plug-in's model")) << r.out;
}

TEST_F(ReportWording, TheLogsRowNumberIsCalledLogRow) {
  const std::string log = src_wording("data/raw/ground/ground_virtual-epuck2-1.csv");
  const CliRun r = run("diagnose --json " + log);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const auto j = nlohmann::json::parse(r.out);
  bool log_row = false;
  for (const char* key : {"residual_structure", "residual_structure_before"}) {
    if (!j.contains(key)) continue;
    for (const auto& s : j.at(key)) {
      EXPECT_NE(s.at("covariate").get<std::string>(), "row");
      log_row = log_row || s.at("covariate") == "log_row";
    }
  }
  EXPECT_TRUE(log_row) << j.dump().substr(0, 2000);
  // The human report's structure line uses the same name.
  const CliRun human = run("diagnose " + log);
  EXPECT_TRUE(contains_wording(human.out, " log_row ")) << human.out;
}

// In a camera diagnosis both rows exist: the log's row number (log_row) and the LED's row in the
// image (image_row), each under its own name, neither as a bare "row".
TEST_F(ReportWording, TheCameraKeepsLogRowAndImageRowApart) {
  const CliRun r = run("diagnose --json" + shipped("camera"));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const auto j = nlohmann::json::parse(r.out);
  std::set<std::string> names;
  for (const char* key : {"residual_structure", "residual_structure_before"})
    if (j.contains(key))
      for (const auto& s : j.at(key)) names.insert(s.at("covariate").get<std::string>());
  EXPECT_EQ(names.count("log_row"), 1u) << j.dump().substr(0, 1500);
  EXPECT_EQ(names.count("image_row"), 1u) << j.dump().substr(0, 1500);
  EXPECT_EQ(names.count("row"), 0u);
}

// The camera's pixels and the encoders' steps have no rails: no rail counts, no Tobit line. The
// ground sensors and the ToF have rails: both stay.
TEST_F(ReportWording, RailAndTobitLinesOnlyForReadingsWithRails) {
  CliRun r = run("camera " + src_wording("data/raw/camera/camera_virtual-epuck2-1.csv"));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_FALSE(contains_wording(r.out, "Tobit")) << r.out;
  EXPECT_FALSE(contains_wording(r.out, "inside the rails")) << r.out;
  EXPECT_FALSE(contains_wording(r.out, "low rail")) << r.out;
  EXPECT_TRUE(contains_wording(r.out, "(no rails: none censored)")) << r.out;

  r = run("ground " + src_wording("data/raw/ground/ground_virtual-epuck2-1.csv"));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_TRUE(contains_wording(r.out, "Tobit likelihood")) << r.out;
  EXPECT_TRUE(contains_wording(r.out, "inside the rails")) << r.out;

  r = run("drive" + shipped("drive", "drive_toward"));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  // One Tobit likelihood line (the ToF's), and one "no rails" line (the encoders').
  std::size_t tobit = 0, no_rails = 0;
  for (std::size_t at = r.out.find("Tobit likelihood"); at != std::string::npos; at = r.out.find("Tobit likelihood", at + 1)) ++tobit;
  for (std::size_t at = r.out.find("no rails"); at != std::string::npos; at = r.out.find("no rails", at + 1)) ++no_rails;
  EXPECT_EQ(tobit, 1u) << r.out;
  EXPECT_EQ(no_rails, 1u) << r.out;
}

// AIC = n ln(RSS/n) + 2k has no value at RSS = 0. By hand: n 10, k 2, RSS 0.1 gives
// 10 ln(0.01) + 4 = -42.0517 and BIC 10 ln(0.01) + 2 ln 10 = -41.4465.
TEST(InformationCriteria, UndefinedAtZeroRssAndSaidWhy) {
  const auto defined = epuck2::fit::fit_statistics(10, 2, 0.1, 0.9);
  EXPECT_NEAR(defined.aic, -42.0517, 1e-4);
  EXPECT_NEAR(defined.bic, -41.4465, 1e-4);
  EXPECT_EQ(epuck2::fit::format_information_criteria(defined, 1), "AIC -42.1, BIC -41.4");
  const auto zero = epuck2::fit::fit_statistics(140, 2, 0.0, 1.0);
  EXPECT_TRUE(std::isnan(zero.aic));
  EXPECT_TRUE(std::isnan(zero.bic));
  EXPECT_EQ(zero.mse, 0.0);  // the other statistics stay
  const std::string text = epuck2::fit::format_information_criteria(zero, 1);
  EXPECT_TRUE(contains_wording(text, "AIC and BIC undefined (RSS is 0")) << text;
  const nlohmann::json j = epuck2::calibrate::statistics_json(zero, "counts^2");
  EXPECT_TRUE(j.at("aic").is_null());
  EXPECT_TRUE(j.at("bic").is_null());
  EXPECT_TRUE(contains_wording(j.at("aic_why").get<std::string>(), "RSS is 0")) << j.dump();
  EXPECT_TRUE(contains_wording(j.at("bic_why").get<std::string>(), "RSS is 0")) << j.dump();
}

// Through the real binary: readings lying exactly on a line (grey 0.1..0.9, reading 1000 x grey,
// 5 repeats, 3 sensors; none at a rail) leave an RSS of rounding alone (about 1e-19, not 0): the
// report printed "AIC -2086.65". Now the statistics say why they are not given, in the human
// report and the JSON alike; the RSS itself is still printed.
TEST_F(ReportWording, AFitThroughEveryReadingPrintsNoAic) {
  std::string csv = "# robot: exact\ngrey,sensor,value\n";
  for (int s = 0; s < 3; ++s)
    for (int k = 1; k <= 9; ++k)
      for (int rep = 0; rep < 5; ++rep) csv += "0." + std::to_string(k) + "," + std::to_string(s) + "," + std::to_string(100 * k) + "\n";
  const std::string log = "\"" + write("exact_ground.csv", csv) + "\"";
  CliRun r = run("ground " + log);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_TRUE(contains_wording(r.out, "AIC and BIC undefined (RSS is 0 to rounding")) << r.out;
  EXPECT_FALSE(contains_wording(r.out, "\n  AIC -")) << r.out;  // (the Tobit likelihood's line keeps its own AIC: defined there)
  r = run("ground " + log + " --json");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const auto j = nlohmann::json::parse(r.out);
  bool found = false;
  std::function<void(const nlohmann::json&)> walk = [&](const nlohmann::json& v) {
    if (v.is_object()) {
      if (v.contains("aic_why")) {
        found = true;
        EXPECT_TRUE(v.at("aic").is_null()) << v.dump();
        EXPECT_TRUE(contains_wording(v.at("aic_why").get<std::string>(), "RSS is 0")) << v.dump();
      }
      for (const auto& [key, item] : v.items()) walk(item);
    } else if (v.is_array()) {
      for (const auto& item : v) walk(item);
    }
  };
  walk(j);
  EXPECT_TRUE(found) << j.dump().substr(0, 1500);
}

TEST_F(ReportWording, EveryWritingCommandSaysWhatItWrote) {
  const std::string sim = (dir_ / "sim.csv").string();
  CliRun r = run("simulate battery --model cubic --profile " + src_wording("data/profiles/example_profile.csv") + " -o \"" + sim + "\"");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_TRUE(contains_wording(r.err, "simulate: wrote " + sim + "\n")) << r.err;
  const std::string like = (dir_ / "like.csv").string();
  r = run("simulate ground --like " + src_wording("data/raw/ground/ground_virtual-epuck2-1.csv") + " -o \"" + like + "\"");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_TRUE(contains_wording(r.err, "simulate: wrote " + like + "\n")) << r.err;
  const std::string t5 = (dir_ / "t5.json").string();
  r = run("table5" + shipped("battery") + " -o \"" + t5 + "\"");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_TRUE(contains_wording(r.err, "table5: wrote " + t5 + "\n")) << r.err;
  EXPECT_TRUE(fs::exists(t5));
}

// The shipped ground log says `# seed: 20241121` (the recording's). A simulated log carries the
// conditions (robot) but not that seed: its own with --noise, none without.
TEST_F(ReportWording, ASimulatedLogHasItsOwnSeed) {
  const std::string log = src_wording("data/raw/ground/ground_virtual-epuck2-1.csv");
  ASSERT_TRUE(contains_wording(slurp(fs::path(EPUCK2_SOURCE_DIR) / "data/raw/ground/ground_virtual-epuck2-1.csv"), "# seed: 20241121\n"));
  CliRun r = run("simulate ground --like " + log);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_FALSE(contains_wording(r.out, "seed: 20241121")) << r.out.substr(0, 400);
  EXPECT_FALSE(contains_wording(r.out, "# seed:")) << r.out.substr(0, 400);
  EXPECT_TRUE(contains_wording(r.out, "# robot: virtual-epuck2-1\n")) << r.out.substr(0, 400);
  r = run("simulate ground --like " + log + " --coefficients " + src_wording("data/fitted/ground.json") + " --noise --seed 7");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_TRUE(contains_wording(r.out, "# seed: 7\n")) << r.out.substr(0, 400);
  EXPECT_FALSE(contains_wording(r.out, "20241121")) << r.out.substr(0, 400);
}

// A header generated from a user's own files names those files and the logs they were fitted
// to, not the shipped data/raw.
TEST_F(ReportWording, AGeneratedHeaderNamesTheLogsItCameFrom) {
  const fs::path log = dir_ / "my_robot_ground.csv";
  fs::copy_file(fs::path(EPUCK2_SOURCE_DIR) / "data/raw/ground/ground_virtual-epuck2-1.csv", log);
  CliRun r = run("ground my_robot_ground.csv -o mine.json", dir_.string());
  ASSERT_EQ(r.exit_code, 0) << r.err;
  r = run("codegen mine.json -o mine.hpp", dir_.string());
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_TRUE(contains_wording(r.err, "codegen: wrote mine.hpp")) << r.err;
  const std::string header = slurp(dir_ / "mine.hpp");
  EXPECT_TRUE(contains_wording(header, "// ground (mine.json) fitted from my_robot_ground.csv\n")) << header.substr(0, 800);
  EXPECT_FALSE(contains_wording(header, "data/raw")) << header.substr(0, 800);
  EXPECT_FALSE(contains_wording(header, "scripts/regenerate.sh")) << header.substr(0, 800);
}
