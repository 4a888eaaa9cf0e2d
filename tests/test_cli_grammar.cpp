// The command line's one grammar (docs/cli.md), through the real binary: `help`, misspelt
// subcommands and kinds (did you mean, and the list), choices, --json as a flag, -o/--output
// written atomically, --plot's format from the extension, and the spellings published before
// (diagnose --json FILE and --plot DIR, nist --out, generate -o/--out) still working. Every error
// is exit 2 and leaves the outputs as they were.
#include <gtest/gtest.h>

#include <nlohmann/json.hpp>

#include "cli_harness.hpp"

using epuck2::testing::CliRun;
using epuck2::testing::slurp;
namespace fs = std::filesystem;

namespace {

// Written here from docs/cli.md, not read from the binary.
const std::vector<std::string> kSubcommands{"battery", "table5", "codegen", "simulate", "generate", "proximity", "light",
                                            "ground",  "camera", "drive",   "nist",     "diagnose", "help"};
const std::vector<std::string> kKinds{"battery", "proximity", "light", "ground", "camera", "drive"};

class Grammar : public epuck2::testing::CliTest {
 protected:
  static std::string q(const std::string& p) { return "\"" + p + "\""; }
  static std::string source(const std::string& rel) { return (fs::path(EPUCK2_SOURCE_DIR) / rel).string(); }
  /// One camera log: the quickest diagnosis (robot 1's, 405 rows).
  static std::string camera_log() { return q(source("data/raw/camera/camera_virtual-epuck2-1.csv")); }
  static std::string ground_logs() { return shipped("ground"); }
  /// A file with known bytes that a failed run must leave as it is.
  std::string sentinel(const std::string& name) { return write(name, "sentinel: a failed run leaves this as it is\n"); }
  static bool unchanged(const std::string& path) { return slurp(path) == "sentinel: a failed run leaves this as it is\n"; }
  /// Every name in `names` appears in `text`.
  static void expect_all(const std::string& text, const std::vector<std::string>& names, const std::string& what) {
    for (const auto& n : names) EXPECT_NE(text.find(n), std::string::npos) << what << " lacks '" << n << "': " << text;
  }
  /// The profile of a robot spinning at 5 cm/s for 100 s.
  std::string profile() { return write("profile.csv", "time_s,speed_cm_s\n0,5\n100,5\n"); }
};

// ---- help ----

TEST_F(Grammar, HelpAloneAndHelpSubcommandPrintTheHelp) {
  const CliRun top = run("help");
  ASSERT_EQ(top.exit_code, 0) << top.err;
  expect_all(top.out, kSubcommands, "epuck2-fit help");
  EXPECT_EQ(top.out, run("--help").out);
  for (const std::string sub : {"battery", "diagnose", "nist", "generate", "simulate"}) {
    const CliRun h = run("help " + sub);
    ASSERT_EQ(h.exit_code, 0) << sub << ": " << h.err;
    EXPECT_FALSE(h.out.empty()) << sub;
    EXPECT_EQ(h.out, run(sub + " --help").out) << sub;
  }
  const CliRun nested = run("help simulate battery");
  ASSERT_EQ(nested.exit_code, 0) << nested.err;
  EXPECT_NE(nested.out.find("--compat"), std::string::npos) << nested.out;
  EXPECT_EQ(nested.out, run("simulate battery --help").out);
}

TEST_F(Grammar, HelpOfAMisspeltSubcommandSaysWhichWasMeant) {
  const CliRun r = run("help batery");
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.err.find("error: unknown subcommand 'batery'; did you mean 'battery'?"), std::string::npos) << r.err;
  EXPECT_TRUE(r.out.empty()) << r.out;
}

// ---- subcommands and kinds ----

TEST_F(Grammar, AMisspeltSubcommandGetsDidYouMeanAndTheList) {
  const CliRun r = run("batery" + shipped("battery"));
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_EQ(r.err.rfind("error: unknown subcommand 'batery'; did you mean 'battery'?", 0), 0u) << r.err;
  expect_all(r.err, kSubcommands, "the list of subcommands");
  EXPECT_TRUE(r.out.empty());
  const CliRun d = run("diagnos " + camera_log());
  EXPECT_EQ(d.exit_code, 2);
  EXPECT_NE(d.err.find("did you mean 'diagnose'?"), std::string::npos) << d.err;
  // Nothing close: no guess, still the list.
  const CliRun far = run("frobnicate");
  EXPECT_EQ(far.exit_code, 2);
  EXPECT_NE(far.err.find("unknown subcommand 'frobnicate'"), std::string::npos) << far.err;
  EXPECT_EQ(far.err.find("did you mean"), std::string::npos) << far.err;
  expect_all(far.err, kSubcommands, "the list of subcommands");
  // No subcommand at all.
  const CliRun none = run("");
  EXPECT_EQ(none.exit_code, 2);
  EXPECT_NE(none.err.find("a subcommand is required"), std::string::npos) << none.err;
  expect_all(none.err, kSubcommands, "the list of subcommands");
}

TEST_F(Grammar, AMisspeltKindGetsDidYouMeanAndTheKinds) {
  const CliRun d = run("diagnose --kind proximty " + camera_log());
  EXPECT_EQ(d.exit_code, 2);
  EXPECT_NE(d.err.find("unknown kind 'proximty'; did you mean 'proximity'?"), std::string::npos) << d.err;
  expect_all(d.err, kKinds, "diagnose --kind's list");
  const fs::path out = dir_ / "g";
  const CliRun g = run("generate proximty --out-dir " + q(out.string()));
  EXPECT_EQ(g.exit_code, 2);
  EXPECT_NE(g.err.find("did you mean 'proximity'?"), std::string::npos) << g.err;
  expect_all(g.err, kKinds, "generate's list");
  EXPECT_NE(g.err.find("all"), std::string::npos) << g.err;
  EXPECT_FALSE(fs::exists(out));
  // simulate: battery over a profile, the sensor kinds --like a log; a misspelt kind says so.
  const CliRun s1 = run("simulate batery --model cubic --profile " + q(profile()));
  EXPECT_EQ(s1.exit_code, 2);
  EXPECT_NE(s1.err.find("unknown kind 'batery'; did you mean 'battery'?"), std::string::npos) << s1.err;
  const CliRun s2 = run("simulate proximty");
  EXPECT_EQ(s2.exit_code, 2);
  EXPECT_NE(s2.err.find("did you mean 'proximity'?"), std::string::npos) << s2.err;
  EXPECT_NE(s2.err.find("kinds that can be simulated: battery"), std::string::npos) << s2.err;
  const CliRun s3 = run("simulate proximity");
  EXPECT_EQ(s3.exit_code, 2);
  EXPECT_NE(s3.err.find("--like is required"), std::string::npos) << s3.err;
  const CliRun s5 = run("simulate battery-level");
  EXPECT_EQ(s5.exit_code, 2);
  EXPECT_NE(s5.err.find("kinds that can be simulated: battery, proximity, light, ground, camera, drive"), std::string::npos) << s5.err;
  const CliRun s4 = run("simulate");
  EXPECT_EQ(s4.exit_code, 2);
  EXPECT_NE(s4.err.find("kinds that can be simulated: battery"), std::string::npos) << s4.err;
}

TEST_F(Grammar, ChoicesAreListedInHelpAndOnError) {
  const CliRun h = run("simulate battery --help");
  ASSERT_EQ(h.exit_code, 0);
  EXPECT_NE(h.out.find("{argos,corrected}"), std::string::npos) << h.out;
  EXPECT_NE(h.out.find("{simple,linear,cubic,approximated}"), std::string::npos) << h.out;
  const std::string out = sentinel("sim.csv");
  const CliRun c = run("simulate battery --model cubic --compat argos2 --profile " + q(profile()) + " -o " + q(out));
  EXPECT_EQ(c.exit_code, 2);
  EXPECT_NE(c.err.find("--compat"), std::string::npos) << c.err;
  EXPECT_NE(c.err.find("did you mean 'argos'?"), std::string::npos) << c.err;
  expect_all(c.err, {"argos", "corrected"}, "--compat's values");
  EXPECT_TRUE(unchanged(out));
  const CliRun m = run("simulate battery --model cubik --profile " + q(profile()) + " -o " + q(out));
  EXPECT_EQ(m.exit_code, 2);
  EXPECT_NE(m.err.find("did you mean 'cubic'?"), std::string::npos) << m.err;
  EXPECT_TRUE(unchanged(out));
  const CliRun b = run("diagnose --battery-model linaer " + camera_log());
  EXPECT_EQ(b.exit_code, 2);
  EXPECT_NE(b.err.find("did you mean 'linear'?"), std::string::npos) << b.err;
  // A --coefficients source that is no file but close to a keyword.
  const CliRun k = run("simulate battery --model cubic --coefficients plugn --profile " + q(profile()) + " -o " + q(out));
  EXPECT_EQ(k.exit_code, 2);
  EXPECT_NE(k.err.find("did you mean 'plugin'?"), std::string::npos) << k.err;
  EXPECT_TRUE(unchanged(out));
}

TEST_F(Grammar, CompatCorrectedIsTheDefaultAndArgosDiffers) {
  const std::string p = profile();
  const CliRun def = run("simulate battery --model cubic --coefficients plugin --profile " + q(p));
  const CliRun cor = run("simulate battery --model cubic --coefficients plugin --compat corrected --profile " + q(p));
  const CliRun arg = run("simulate battery --model cubic --coefficients plugin --compat argos --profile " + q(p));
  ASSERT_EQ(def.exit_code, 0) << def.err;
  ASSERT_EQ(cor.exit_code, 0) << cor.err;
  ASSERT_EQ(arg.exit_code, 0) << arg.err;
  EXPECT_EQ(def.out, cor.out);
  EXPECT_NE(arg.out, cor.out);
  EXPECT_EQ(arg.out.rfind("time_s,charge\n0,1\n", 0), 0u) << arg.out.substr(0, 80);
}

TEST_F(Grammar, ParseErrorsSayErrorAndPointAtTheSubcommandsHelp) {
  const std::string out = sentinel("o.json");
  const CliRun r = run("ground" + ground_logs() + " --no-such-option -o " + q(out));
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_EQ(r.err.rfind("error: ", 0), 0u) << r.err;
  EXPECT_NE(r.err.find("epuck2-fit ground --help"), std::string::npos) << r.err;
  EXPECT_TRUE(unchanged(out));
}

// ---- --json, -o/--output ----

TEST_F(Grammar, JsonPrintsWhatOutputWritesForEveryFittingSubcommand) {
  for (const std::string sub : {"ground", "camera"}) {
    const fs::path out = dir_ / (sub + ".json");
    const CliRun j = run(sub + shipped(sub) + " --json");
    const CliRun o = run(sub + shipped(sub) + " --output " + q(out.string()));
    ASSERT_EQ(j.exit_code, 0) << j.err;
    ASSERT_EQ(o.exit_code, 0) << o.err;
    EXPECT_EQ(slurp(out), j.out) << sub;
    EXPECT_FALSE(nlohmann::json::accept(o.out)) << sub << ": -o alone prints the human report";
    EXPECT_NE(o.err.find("wrote " + out.string()), std::string::npos) << o.err;
  }
}

TEST_F(Grammar, DiagnoseJsonIsAFlagThatNeverTakesALogForTheOutput) {
  // A log right after --json is a log: the JSON goes to standard output, the log stays as it was.
  const std::string log = write("log.csv", slurp(source("data/raw/camera/camera_virtual-epuck2-1.csv")));
  const std::string before = slurp(log);
  const CliRun r = run("diagnose --json " + q(log));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const auto j = nlohmann::json::parse(r.out);
  EXPECT_EQ(j.at("kind"), "camera");
  EXPECT_EQ(j.at("rows").get<int>(), 405);
  EXPECT_EQ(slurp(log), before);
  // --json - (published): the same JSON on standard output.
  const CliRun dash = run("diagnose --json - " + q(log));
  ASSERT_EQ(dash.exit_code, 0) << dash.err;
  EXPECT_EQ(dash.out, r.out);
  // --json=LOG.csv cannot be the old spelling: refused, the log untouched.
  const CliRun eq = run("diagnose --json=" + q(log) + " " + camera_log());
  EXPECT_EQ(eq.exit_code, 2);
  EXPECT_NE(eq.err.find("must end in .json"), std::string::npos) << eq.err;
  EXPECT_EQ(slurp(log), before);
}

TEST_F(Grammar, DiagnoseOldJsonFileAndOutputWriteTheSameReport) {
  const CliRun flag = run("diagnose --json " + camera_log());
  ASSERT_EQ(flag.exit_code, 0) << flag.err;
  const fs::path old_file = dir_ / "old.JSON", out = dir_ / "new.json", eq = dir_ / "eq.json";
  const CliRun a = run("diagnose --json " + q(old_file.string()) + " " + camera_log());
  const CliRun b = run("diagnose -o " + q(out.string()) + " " + camera_log());
  const CliRun c = run("diagnose --json=" + q(eq.string()) + " " + camera_log());
  for (const CliRun* x : {&a, &b, &c}) {
    ASSERT_EQ(x->exit_code, 0) << x->err;
    EXPECT_NE(x->out.find("Diagnosis of 405 camera rows"), std::string::npos) << "the human report: " << x->out;
  }
  EXPECT_EQ(slurp(old_file), flag.out);
  EXPECT_EQ(slurp(out), flag.out);
  EXPECT_EQ(slurp(eq), flag.out);
  // --json with -o: the JSON on standard output and in the file.
  const fs::path both = dir_ / "both.json";
  const CliRun d = run("diagnose --json --output " + q(both.string()) + " " + camera_log());
  ASSERT_EQ(d.exit_code, 0) << d.err;
  EXPECT_EQ(d.out, flag.out);
  EXPECT_EQ(slurp(both), flag.out);
}

TEST_F(Grammar, DiagnoseRefusesTwoNamesForTheReportAndWritesNeither) {
  const std::string a = sentinel("a.json"), b = sentinel("b.json");
  const CliRun r = run("diagnose --json " + q(a) + " -o " + q(b) + " " + camera_log());
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.err.find("give one"), std::string::npos) << r.err;
  EXPECT_TRUE(unchanged(a));
  EXPECT_TRUE(unchanged(b));
}

TEST_F(Grammar, DiagnoseFailuresLeaveTheReportAndTheFigureAlone) {
  const std::string out = sentinel("r.json"), fig = sentinel("f.png");
  // Bad input (exit 2) ...
  const std::string bad = write("bad.csv", "forward_m,lateral_m,vertical_m,px,py\n0.2,0,0,80,60\n0.2,0,0,abc,60\n");
  const CliRun r = run("diagnose -o " + q(out) + " --plot " + q(fig) + " " + q(bad));
  EXPECT_EQ(r.exit_code, 2) << r.err;
  EXPECT_NE(r.err.find("bad.csv:3:"), std::string::npos) << r.err;
  EXPECT_TRUE(unchanged(out));
  EXPECT_TRUE(unchanged(fig));
  // Too few rows is a report (exit 0, docs/diagnose.md): verdict "not judged", and it says why.
  const std::string tiny = write("tiny.csv", "distance_m,sensor,value\n0,0,4000\n0,0,3500\n0,0,3800\n0,0,3900\n");
  const CliRun t = run("diagnose -o " + q(out) + " " + q(tiny));
  EXPECT_EQ(t.exit_code, 0) << t.err;
  EXPECT_NE(t.err.find("too few rows (4)"), std::string::npos) << t.err;
  EXPECT_EQ(nlohmann::json::parse(slurp(out)).at("verdict"), "not judged (too few rows: 4 of 75)");
}

TEST_F(Grammar, NistOutputAndItsOldSpellingWriteTheSameReport) {
  // Two problems are enough for the grammar.
  fs::create_directories(dir_ / "nist");
  for (const char* p : {"Misra1a.dat", "DanWood.dat"}) fs::copy_file(source(std::string("tests/data/nist/") + p), dir_ / "nist" / p);
  const std::string nist = q((dir_ / "nist").string());
  const CliRun j = run("nist " + nist + " --json");
  ASSERT_EQ(j.exit_code, 0) << j.err;
  const auto report = nlohmann::json::parse(j.out);
  EXPECT_EQ(report.at("summary").at("runs").get<int>(), 4);
  for (const std::string opt : {"-o", "--output", "--out"}) {
    const fs::path out = dir_ / ("n" + opt + ".json");
    const CliRun r = run("nist " + nist + " " + opt + " " + q(out.string()));
    ASSERT_EQ(r.exit_code, 0) << opt << ": " << r.err;
    const auto written = nlohmann::json::parse(slurp(out));
    // Timings differ from run to run; everything else is the same report.
    EXPECT_EQ(written.at("summary"), report.at("summary")) << opt;
    EXPECT_EQ(written.at("runs").size(), report.at("runs").size()) << opt;
  }
  const CliRun h = run("nist --help");
  EXPECT_NE(h.out.find("--output"), std::string::npos) << h.out;
  EXPECT_EQ(h.out.find("--out "), std::string::npos) << "the old spelling is not advertised: " << h.out;
}

// ---- --plot ----

TEST_F(Grammar, PlotFormatFollowsTheExtensionAndAnyOtherIsRefused) {
  const std::string out = sentinel("g.json");
  for (const std::string bad : {"fig.jpg", "fig", "fig.png.txt", "fig.eps"}) {
    const CliRun r = run("ground" + ground_logs() + " -o " + q(out) + " --plot " + q((dir_ / bad).string()));
    EXPECT_EQ(r.exit_code, 2) << bad;
    expect_all(r.err, {"--plot", ".png", ".svg", ".pdf"}, bad + "'s message");
    EXPECT_TRUE(unchanged(out)) << bad;
    EXPECT_FALSE(fs::exists(dir_ / bad)) << bad;
  }
  const CliRun life = run("battery" + shipped("battery") + " -o " + q(out) + " --plot-lifetime " + q((dir_ / "l.gif").string()));
  EXPECT_EQ(life.exit_code, 2);
  EXPECT_NE(life.err.find("--plot-lifetime"), std::string::npos) << life.err;
  EXPECT_TRUE(unchanged(out));
  // The extension's case does not matter; the bytes are the format's.
  const fs::path upper = dir_ / "FIG.SVG";
  const CliRun ok = run("ground" + ground_logs() + " --plot " + q(upper.string()));
  ASSERT_EQ(ok.exit_code, 0) << ok.err;
  EXPECT_NE(slurp(upper).find("<svg"), std::string::npos);
}

TEST_F(Grammar, DiagnosePlotDrawsOneFigureToAFileOrAFolder) {
  const fs::path pdf = dir_ / "d.pdf";
  const CliRun f = run("diagnose --plot " + q(pdf.string()) + " " + camera_log());
  ASSERT_EQ(f.exit_code, 0) << f.err;
  EXPECT_EQ(slurp(pdf).substr(0, 5), "%PDF-");
  // The published spelling: an existing folder gets diagnose_<kind>.png.
  fs::create_directories(dir_ / "plots");
  const CliRun d = run("diagnose --plot " + q((dir_ / "plots").string()) + " " + camera_log());
  ASSERT_EQ(d.exit_code, 0) << d.err;
  std::vector<std::string> files;
  for (const auto& e : fs::directory_iterator(dir_ / "plots")) files.push_back(e.path().filename().string());
  ASSERT_EQ(files, std::vector<std::string>{"diagnose_camera.png"});
  EXPECT_EQ(slurp(dir_ / "plots" / "diagnose_camera.png").substr(0, 4), "\x89PNG");
  // Neither a figure nor a folder.
  const CliRun n = run("diagnose --plot " + q((dir_ / "no-such-folder").string()) + " " + camera_log());
  EXPECT_EQ(n.exit_code, 2);
  expect_all(n.err, {".png", ".svg", ".pdf", "folder"}, "--plot's message");
}

// ---- generate ----

TEST_F(Grammar, GenerateOutDirAndItsOldSpellingsWriteTheSameLogs) {
  for (const std::string opt : {"--out-dir", "--out", "-o"}) {
    const CliRun r = run("generate ground " + opt + " " + q((dir_ / ("g" + opt)).string()));
    ASSERT_EQ(r.exit_code, 0) << opt << ": " << r.err;
  }
  std::vector<std::string> names;
  for (const auto& e : fs::directory_iterator(dir_ / "g--out-dir")) names.push_back(e.path().filename().string());
  ASSERT_FALSE(names.empty());
  for (const auto& n : names) {
    EXPECT_EQ(slurp(dir_ / "g--out" / n), slurp(dir_ / "g--out-dir" / n)) << n;
    EXPECT_EQ(slurp(dir_ / "g-o" / n), slurp(dir_ / "g--out-dir" / n)) << n;
  }
  // Two different folders, or none: exit 2, nothing written.
  const CliRun two = run("generate ground --out-dir " + q((dir_ / "a").string()) + " --out " + q((dir_ / "b").string()));
  EXPECT_EQ(two.exit_code, 2);
  EXPECT_FALSE(fs::exists(dir_ / "a"));
  EXPECT_FALSE(fs::exists(dir_ / "b"));
  const CliRun none = run("generate ground");
  EXPECT_EQ(none.exit_code, 2);
  EXPECT_NE(none.err.find("--out-dir"), std::string::npos) << none.err;
  const CliRun h = run("generate --help");
  EXPECT_NE(h.out.find("--out-dir"), std::string::npos) << h.out;
  EXPECT_EQ(h.out.find("--out "), std::string::npos) << "the old spelling is not advertised: " << h.out;
}

}  // namespace
