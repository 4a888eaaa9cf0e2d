// The fuzzing report's defects through the real binary: crashes (diagnose on small logs and on a
// repeated time stamp), all-or-nothing outputs, option bounds, codegen's identifiers and duplicate
// kinds (the generated header compiled with the system compiler), null standard errors.
#include <gtest/gtest.h>
#include <sys/stat.h>

#include <algorithm>
#include <nlohmann/json.hpp>

#include "cli_harness.hpp"

using epuck2::testing::CliRun;
using epuck2::testing::slurp;
namespace fs = std::filesystem;

namespace {
class SafeCli : public epuck2::testing::CliTest {
 protected:
  static std::string source(const std::string& rel) { return (fs::path(EPUCK2_SOURCE_DIR) / rel).string(); }
  static std::string q(const std::string& p) { return "\"" + p + "\""; }
  /// Files in the test folder whose name starts with a dot (staged temporaries).
  std::vector<std::string> hidden(const fs::path& where) const {
    std::vector<std::string> h;
    for (const auto& e : fs::recursive_directory_iterator(where))
      if (e.path().filename().string()[0] == '.') h.push_back(e.path().string());
    return h;
  }
  /// Compiles `header` with the system compiler against lib/models; returns the compiler's output
  /// (empty on success) and sets `ok`.
  std::string compile(const std::string& header, bool& ok) {
    const fs::path main_cpp = dir_ / "use_header.cpp", log = dir_ / "compile.txt";
    std::ofstream(main_cpp) << "#include \"" << header << "\"\nint main() { return 0; }\n";
    const std::string cmd = std::string(EPUCK2_CXX) + " -fsyntax-only -std=c++17 -I" + q(source("lib/models/include")) + " " +
                            q(main_cpp.string()) + " >" + q(log.string()) + " 2>&1";
    ok = std::system(cmd.c_str()) == 0;
    return slurp(log);
  }
};

// ---- 1. diagnose on too few rows: a report that says so (exit 0, verdict none), no crash, no finding ----

TEST_F(SafeCli, DiagnoseOnAFourRowProximityLogSaysTooFewRows) {
  const auto log = write("p4.csv", "distance_m,sensor,value\n0,0,4000\n0,0,3500\n0,0,3800\n0,0,3900\n");
  const CliRun r = run("diagnose " + q(log));
  EXPECT_EQ(r.exit_code, 0) << r.out << r.err;
  EXPECT_NE(r.out.find("Too few rows (4) to judge effects"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("Verdict: none"), std::string::npos) << r.out;
  EXPECT_EQ(r.out.find("Finding"), std::string::npos) << r.out;
}

TEST_F(SafeCli, DiagnoseOnTwoIdenticalLightRowsSaysTooFewRows) {
  const auto log = write("l2.csv", "distance_m,intensity,sensor,value\n0.1,0.5,0,3524\n0.1,0.5,0,3524\n");
  const CliRun r = run("diagnose " + q(log));
  EXPECT_EQ(r.exit_code, 0) << r.out << r.err;
  EXPECT_NE(r.out.find("Too few rows (2) to judge effects"), std::string::npos) << r.out;
}

// ---- 2. a repeated time stamp in a battery log (allowed: time never decreases) ----

TEST_F(SafeCli, DiagnoseABatteryLogWithARepeatedTimeStampInEveryModel) {
  std::istringstream in(slurp(source("data/raw/battery/robot-a_speed-05.csv")));
  std::string line, text;
  int data_rows = 0;
  while (std::getline(in, line)) {
    text += line + "\n";
    if (!line.empty() && line[0] != '#' && std::isdigit(static_cast<unsigned char>(line[0])) && ++data_rows == 20)
      text += line + "\n";  // the 20th row twice: dt = 0 between them
  }
  const auto log = write("repeated.csv", text);
  for (const char* model : {"simple", "linear", "cubic", "approximated"}) {
    const CliRun r = run(std::string("diagnose --battery-model ") + model + " --json - " + q(log));
    ASSERT_EQ(r.exit_code, 0) << model << ": " << r.err;
    const auto j = nlohmann::json::parse(r.out);
    EXPECT_EQ(j.at("rows").get<std::size_t>(), static_cast<std::size_t>(data_rows + 1)) << model;
    EXPECT_TRUE(j.at("heldout_mse_final").is_number()) << model;
  }
}

// ---- 3. all or nothing ----

TEST_F(SafeCli, CameraWithAPlotThatCannotBeWrittenLeavesTheCoefficientFileAlone) {
  const std::string previous = "{\"kept\": true}\n";
  const auto out = write("o.json", previous);
  const CliRun r = run("camera" + shipped("camera") + " -o " + q(out) + " --plot /nonexistent/x.png");
  EXPECT_EQ(r.exit_code, 2) << r.err;
  EXPECT_NE(r.err.find("/nonexistent"), std::string::npos) << r.err;
  EXPECT_EQ(slurp(out), previous);
  EXPECT_TRUE(hidden(dir_).empty()) << hidden(dir_).front();
}

TEST_F(SafeCli, BatteryWithAFigureThatCannotBeWrittenLeavesEveryOutputAlone) {
  const std::string previous = "{\"kept\": true}\n";
  const auto out = write("o.json", previous);
  const auto fig = write("fits.png", "old figure");
  const CliRun r = run("battery" + shipped("battery") + " -o " + q(out) + " --plot " + q(fig) +
                       " --plot-lifetime /nonexistent/life.png");
  EXPECT_EQ(r.exit_code, 2) << r.err;
  EXPECT_EQ(slurp(out), previous);
  EXPECT_EQ(slurp(fig), "old figure");
  EXPECT_TRUE(hidden(dir_).empty()) << hidden(dir_).front();
}

TEST_F(SafeCli, TheSameFileForTwoOutputsIsABadUsage) {
  // A figure's name must end in its format (.png here); -o takes any name, so both can be one file.
  const auto out = write("o.png", "old\n");
  const CliRun r = run("camera" + shipped("camera") + " -o " + q(out) + " --plot " + q(out));
  EXPECT_EQ(r.exit_code, 2) << r.err;
  EXPECT_NE(r.err.find("o.png"), std::string::npos) << r.err;
  EXPECT_EQ(slurp(out), "old\n");
}

// ---- 4. modes, symlinks, stale temporaries ----

TEST_F(SafeCli, ASymlinkedOutputIsFollowedAndTheReplacedFileKeepsItsMode) {
  fs::create_directories(dir_ / "real");
  const std::string real = (dir_ / "real" / "camera.json").string();
  std::ofstream(real) << "old\n";
  ASSERT_EQ(::chmod(real.c_str(), 0600), 0);
  fs::create_symlink(real, dir_ / "link.json");
  const CliRun r = run("camera" + shipped("camera") + " -o " + q((dir_ / "link.json").string()));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_TRUE(fs::is_symlink(dir_ / "link.json"));
  EXPECT_EQ(nlohmann::json::parse(slurp(real)).at("kind"), "camera");
  struct stat st {};
  ASSERT_EQ(::stat(real.c_str(), &st), 0);
  EXPECT_EQ(st.st_mode & 07777, 0600u);
}

TEST_F(SafeCli, AStaleTemporaryOfADeadRunIsSweptByTheNextRun) {
  // PID 4194304 is above Linux's largest pid_max: no process has it.
  const auto stale = write(".camera.json.epuck2-tmp.4194304", "half written");
  const CliRun r = run("camera" + shipped("camera") + " -o " + q((dir_ / "camera.json").string()));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_FALSE(fs::exists(stale));
}

// ---- 5. codegen ----

TEST_F(SafeCli, TheHeaderOfTheShippedCoefficientFilesCompiles) {
  std::string files;
  for (const char* k : {"battery", "proximity", "light", "ground", "camera", "drive"}) files += " " + q(source(std::string("data/fitted/") + k + ".json"));
  const std::string header = (dir_ / "coefficients.hpp").string();
  const CliRun r = run("codegen" + files + " -o " + q(header));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  bool ok = false;
  const std::string log = compile(header, ok);
  EXPECT_TRUE(ok) << log;
}

TEST_F(SafeCli, UnusualButLegalNamesGiveAHeaderThatCompiles) {
  const auto f = write("lidar.json",
                       R"({"kind": "lidar", "parameters": {"array": 1, "value": [1, 2], "Int": 3, "mse_px": 4, "x": 5,
                          "double_gain": 6}, "std_errors": {"x": 0.1, "array": null}, "mse": 0.5})");
  const std::string header = (dir_ / "lidar.hpp").string();
  const CliRun r = run("codegen " + q(f) + " -o " + q(header));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  bool ok = false;
  const std::string log = compile(header, ok);
  EXPECT_TRUE(ok) << log << slurp(header);
}

TEST_F(SafeCli, CodegenRefusesNamesThatWouldNotCompile) {
  struct Case {
    const char* json;
    const char* name;  ///< what the message names
  };
  const Case cases[] = {
      {R"({"kind": "int", "parameters": {"a": 1}})", "int"},
      {R"({"kind": "namespace", "parameters": {"a": 1}})", "namespace"},
      {R"({"kind": "lidar", "parameters": {"return": 1}})", "return"},
      {R"({"kind": "lidar", "parameters": {"NULL": 1}})", "NULL"},
      {R"({"kind": "lidar", "parameters": {"std": 1}})", "std"},
      {R"({"kind": "lidar", "parameters": {"mse": 1}, "mse": 0.5})", "mse"},
      {R"({"kind": "lidar", "parameters": {"x": 1, "x_std_error": 2}, "std_errors": {"x": 0.1}})", "x_std_error"},
      {R"({"kind": "lidar", "parameters": {"2x": 1}})", "2x"},
      {R"({"kind": "lidar", "parameters": {"__x": 1}})", "__x"},
  };
  const std::string header = (dir_ / "h.hpp").string();
  for (const Case& c : cases) {
    const auto f = write("bad.json", c.json);
    const CliRun r = run("codegen " + q(f) + " -o " + q(header));
    EXPECT_EQ(r.exit_code, 2) << c.json << ": " << r.err;
    EXPECT_NE(r.err.find(c.name), std::string::npos) << r.err;
    EXPECT_NE(r.err.find("bad.json"), std::string::npos) << r.err;
    EXPECT_FALSE(fs::exists(header)) << c.json;
  }
}

TEST_F(SafeCli, CodegenRefusesTwoFilesOfTheSameKindNamingBoth) {
  const auto a = write("camera_a.json", slurp(source("data/fitted/camera.json")));
  const auto b = write("camera_b.json", slurp(source("data/fitted/camera.json")));
  const std::string header = (dir_ / "h.hpp").string();
  const CliRun r = run("codegen " + q(a) + " " + q(b) + " -o " + q(header));
  EXPECT_EQ(r.exit_code, 2) << r.err;
  EXPECT_NE(r.err.find("camera_a.json"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("camera_b.json"), std::string::npos) << r.err;
  EXPECT_FALSE(fs::exists(header));
}

// ---- 6. numeric options ----

TEST_F(SafeCli, ATickOutsideItsRangeIsABadUsageNamingTheOption) {
  const auto profile = write("profile.csv", "time_s,speed_cm_s\n0,5\n100,5\n");
  for (const char* dt : {"1e-300", "inf", "nan", "0", "-1", "1e9", "abc"}) {
    const CliRun r = run(std::string("simulate battery --model cubic --profile ") + q(profile) + " --dt " + dt);
    EXPECT_EQ(r.exit_code, 2) << dt << ": " << r.out.substr(0, 200);
    EXPECT_NE(r.err.find("--dt"), std::string::npos) << dt << ": " << r.err;
    EXPECT_NE(r.err.find("0.001"), std::string::npos) << dt << ": " << r.err;  // the allowed range
  }
  const CliRun t = run("table5" + shipped("battery") + " --dt inf");
  EXPECT_EQ(t.exit_code, 2) << t.out.substr(0, 300);
  EXPECT_NE(t.err.find("--dt"), std::string::npos) << t.err;
}

TEST_F(SafeCli, ARobustScaleOutsideItsRangeIsABadUsageNamingTheOption) {
  const auto out = write("o.json", "old\n");
  for (const char* s : {"0", "nan", "-1", "inf"}) {
    const CliRun r = run("battery" + shipped("battery") + " --robust --robust-scale " + s + " -o " + q(out));
    EXPECT_EQ(r.exit_code, 2) << s << ": " << r.err;
    EXPECT_NE(r.err.find("--robust-scale"), std::string::npos) << s << ": " << r.err;
    EXPECT_EQ(slurp(out), "old\n");
  }
}

TEST_F(SafeCli, AProfileEndingAtABillionSecondsRunsUntilTheBatteryIsEmpty) {
  const auto profile = write("profile.csv", "time_s,speed_cm_s\n0,5\n1e9,5\n");
  const std::string out = (dir_ / "sim.csv").string();
  const CliRun r = run("simulate battery --model linear --coefficients plugin --profile " + q(profile) + " -o " + q(out));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const std::string csv = slurp(out);
  const std::string last = csv.substr(csv.rfind('\n', csv.size() - 2) + 1);
  EXPECT_EQ(last.substr(last.find(',') + 1), "0\n") << last;
}

// ---- 7. null standard errors carry their reason; NaN never reaches a file ----

TEST_F(SafeCli, AThreeRowCameraLogGivesEveryNullStandardErrorAReason) {
  // One LED seen three times: the field of view and the centre are not separately determined.
  const auto log = write("c3.csv", "forward_m,lateral_m,vertical_m,px,py\n0.2,-0.05,-0.035,154,108\n"
                                   "0.2,-0.05,-0.035,154,108\n0.2,-0.05,-0.035,154,109\n");
  const std::string out = (dir_ / "c3.json").string();
  const CliRun r = run("camera " + q(log) + " -o " + q(out));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const auto j = nlohmann::json::parse(slurp(out));
  int nulls = 0;
  for (const auto& [name, se] : j.at("std_errors").items()) {
    if (!se.is_null()) continue;
    ++nulls;
    ASSERT_TRUE(j.contains("std_error_why") && j.at("std_error_why").contains(name)) << name << ": " << j.dump(2);
    EXPECT_NE(j.at("std_error_why").at(name).get<std::string>().find("not identifiable"), std::string::npos);
    EXPECT_NE(r.err.find("warning: " + name + " is not identifiable"), std::string::npos) << r.err;
  }
  // Two pixel coordinates for three parameters: one direction is undetermined, and the parameter
  // declared last along it (cy_px) keeps its documented default (60) instead of a guess.
  EXPECT_EQ(nulls, 1);
  EXPECT_EQ(j.at("parameters").at("cy_px").get<double>(), 60.0);
}

TEST_F(SafeCli, ANegativeOrNonNumericSeedIsABadUsage) {
  for (const char* seed : {"-1", "abc", "1.5", "99999999999999999999999"}) {
    const CliRun r = run(std::string("generate drive -o ") + q((dir_ / "g").string()) + " --seed " + seed);
    EXPECT_EQ(r.exit_code, 2) << seed;
    EXPECT_NE(r.err.find("--seed"), std::string::npos) << seed << ": " << r.err;
    EXPECT_FALSE(fs::exists(dir_ / "g")) << seed;
  }
}

}  // namespace

namespace {
/// Two JSON documents alike: the same keys, strings and structure, numbers equal to 12 significant
/// digits. The linear algebra under the covariances (BLAS kernels chosen by the processor) may
/// round the last digit of a standard error differently on another machine; a real change moves
/// far more than that. Returns where they differ ("" when alike).
std::string json_difference(const nlohmann::json& a, const nlohmann::json& b, const std::string& at = "") {
  if (a.is_number() && b.is_number()) {
    const double x = a.get<double>(), y = b.get<double>();
    if (x == y || std::abs(x - y) <= 1e-12 * std::max(std::abs(x), std::abs(y))) return "";
    return at + ": " + a.dump() + " against " + b.dump();
  }
  if (a.type() != b.type()) return at + ": " + a.dump() + " against " + b.dump();
  if (a.is_object()) {
    if (a.size() != b.size()) return at + ": " + std::to_string(a.size()) + " keys against " + std::to_string(b.size());
    for (auto it = a.begin(); it != a.end(); ++it) {
      if (!b.contains(it.key())) return at + "/" + it.key() + ": missing";
      const std::string d = json_difference(it.value(), b.at(it.key()), at + "/" + it.key());
      if (!d.empty()) return d;
    }
    return "";
  }
  if (a.is_array()) {
    if (a.size() != b.size()) return at + ": " + std::to_string(a.size()) + " entries against " + std::to_string(b.size());
    for (std::size_t i = 0; i < a.size(); ++i) {
      const std::string d = json_difference(a.at(i), b.at(i), at + "/" + std::to_string(i));
      if (!d.empty()) return d;
    }
    return "";
  }
  return a == b ? "" : at + ": " + a.dump() + " against " + b.dump();
}

// The staged writes, the summarize rewrite and the compaction of the diagnosis change no digit:
// every shipped coefficient file and report comes out the same (numbers to 12 significant digits,
// everything else to the byte).
TEST_F(SafeCli, TheShippedCoefficientFilesAndReportsRegenerateByteForByte) {
  const std::string root = EPUCK2_SOURCE_DIR;
  // Relative paths in name order, as scripts/regenerate.sh gives them (the files name their sources).
  auto relative_logs = [&](const std::string& kind) {
    std::vector<std::string> names;
    for (const auto& e : fs::directory_iterator(fs::path(root) / "data" / "raw" / kind))
      if (e.path().extension() == ".csv") names.push_back(e.path().filename().string());
    std::sort(names.begin(), names.end());
    std::string args;
    for (const auto& n : names) args += " data/raw/" + kind + "/" + n;
    return args;
  };
  const std::string battery = (dir_ / "battery.json").string();
  ASSERT_EQ(run("battery" + relative_logs("battery") + " -o " + q(battery), root).exit_code, 0);
  auto same = [&](const std::string& got, const std::string& shipped) {
    EXPECT_EQ(json_difference(nlohmann::json::parse(slurp(got)), nlohmann::json::parse(slurp(source(shipped)))), "") << shipped;
  };
  same(battery, "data/fitted/battery.json");
  const std::string table5 = (dir_ / "table5.json").string();
  ASSERT_EQ(run("table5" + relative_logs("battery") + " -o " + q(table5), root).exit_code, 0);
  same(table5, "data/fitted/reports/table5.json");
  for (const std::string kind : {"proximity", "light", "ground", "camera", "drive"}) {
    const std::string out = (dir_ / (kind + ".json")).string();
    const CliRun r = run(kind + relative_logs(kind) + " -o " + q(out), root);
    ASSERT_EQ(r.exit_code, 0) << kind << ": " << r.err;
    same(out, "data/fitted/" + kind + ".json");
  }
}
}  // namespace
