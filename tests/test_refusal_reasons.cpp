// Each refusal gives its own reason (issue #22: "every error carries file:line:column and the JSON
// path", and the reason). A rule that a second, weaker rule downstream also enforces can go
// missing with only the message changing: these tests pin the reason of each refusal that no test
// named, on an input built so that only that rule refuses it. The rules and their words are
// docs/coefficient-files.md's and docs/cli.md's; the inputs are edited by hand from the shipped
// coefficient files.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "cli_harness.hpp"

namespace test_refusal_reasons_cpp {

namespace fs = std::filesystem;
using nlohmann::json;

class RefusalReasons : public epuck2::testing::CliTest {
 protected:
  std::string put(const std::string& name, const json& j) { return write(name, j.dump(2)); }
  static std::string raw(const std::string& kind, const std::string& file) {
    return "\"" + (fs::path(EPUCK2_SOURCE_DIR) / "data" / "raw" / kind / file).string() + "\"";
  }
  // Refused with exit 2, naming FILE and the JSON path, with the reason's words.
  void refused(const std::string& args, const std::string& file, const std::string& pointer, const std::string& words) {
    const auto r = run(args);
    EXPECT_EQ(r.exit_code, 2) << args << "\n" << r.err;
    EXPECT_NE(r.err.find(fs::path(file).filename().string() + ":"), std::string::npos) << r.err;
    EXPECT_NE(r.err.find("(at JSON path " + pointer + ")"), std::string::npos) << r.err;
    EXPECT_NE(r.err.find(words), std::string::npos) << "expected '" << words << "' in:\n" << r.err;
    EXPECT_FALSE(fs::exists(dir_ / "out.csv"));
  }
  std::string light_like(const std::string& file) {
    return "simulate light --like " + raw("light", "light_intensity_0.50.csv") + " --coefficients \"" + file + "\" -o \"" +
           (dir_ / "out.csv").string() + "\"";
  }
  std::string battery_like(const std::string& file) {
    return "simulate battery --like " + raw("battery", "robot-a_speed-01.csv") + " --coefficients \"" + file + "\" -o \"" +
           (dir_ / "out.csv").string() + "\"";
  }
};

// docs/coefficient-files.md: "a second entry names the same sensor" is refused. Without the rule
// the second entry would silently replace the first (both gammas are in range).
TEST_F(RefusalReasons, ASecondPerSensorEntryForTheSameSensorIsRefusedByThatRule) {
  json l = epuck2::testing::shipped_fitted("light");
  json second = l.at("per_sensor").at(0);
  second["gamma"] = 0.05;  // in gamma's range (0, 10] m
  l["per_sensor"].push_back(second);
  const std::size_t at = l.at("per_sensor").size() - 1;
  const std::string f = put("dup.json", l);
  refused(light_like(f), f, "/per_sensor/" + std::to_string(at) + "/sensor", "has an entry already");
}

// `noise.CHANNEL.unit` is read: a light channel is in counts (docs/coefficient-files.md, noise).
TEST_F(RefusalReasons, ANoiseUnitOtherThanTheChannelsIsRefused) {
  json l = epuck2::testing::shipped_fitted("light");
  l["noise"]["light"]["unit"] = "lux";
  const std::string f = put("unit.json", l);
  refused(light_like(f), f, "/noise/light/unit", "must be \"counts\"");
}

// A file without `parameters` (and without robots' sets) has no base coefficients to run.
TEST_F(RefusalReasons, AFileWithoutParametersSaysSo) {
  json l = epuck2::testing::shipped_fitted("light");
  l.erase("parameters");
  l.erase("robots");
  const std::string f = put("nop.json", l);
  refused(light_like(f), f, "/", "no `parameters` section");
}

// The unknown-key rule at the top level, with the did-you-mean the docs quote.
TEST_F(RefusalReasons, AnUnknownSectionIsNamedWithTheClosestKnownOne) {
  json l = epuck2::testing::shipped_fitted("light");
  l["efects"] = json::object();
  const std::string f = put("sec.json", l);
  refused(light_like(f), f, "/efects", "unknown section 'efects'");
  const auto r = run(light_like(f));
  EXPECT_NE(r.err.find("did you mean 'effects'?"), std::string::npos) << r.err;
}

// Text that is not JSON: the position of the stray comma's closing brace, worked by hand
// (line 3; `  "parameters": {"gamma": 0.07,}` has the `}` at column 32).
TEST_F(RefusalReasons, TextThatIsNotJsonIsRefusedAtItsPosition) {
  const std::string f = write("bad.json", "{\n  \"kind\": \"light\",\n  \"parameters\": {\"gamma\": 0.07,}\n}\n");
  const auto r = run(light_like(f));
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.err.find("bad.json:3:32: invalid JSON"), std::string::npos) << r.err;
}

// docs/coefficient-files.md, battery tables: 0 <= x1_s <= x2_s. A flat segment (m = 0, y1 = y2,
// h = y1) run backwards passes every other rule (the band does not rise, m in [-1, 0], the line
// goes through both ends), so only this rule can refuse it.
TEST_F(RefusalReasons, ABatterySegmentRunningBackwardsIsRefusedByTheTimeOrderRule) {
  json b = epuck2::testing::shipped_fitted("battery");
  json& s = b["speeds"][1]["segments"][0];
  const double y = s.at("y1").get<double>();
  const double x1 = s.at("x1_s").get<double>(), x2 = s.at("x2_s").get<double>();
  ASSERT_LT(x1, x2);
  s["m"] = 0.0;
  s["h"] = y;
  s["y2"] = y;
  s["x1_s"] = x2;
  s["x2_s"] = x1;
  const std::string f = put("x2.json", b);
  refused(battery_like(f), f, "/speeds/1/segments/0/x2_s", "x2_s must not be before x1_s");
}

TEST_F(RefusalReasons, ABatteryFileWithoutTheSimpleModelsSlopesSaysSo) {
  json b = epuck2::testing::shipped_fitted("battery");
  b.erase("simple");
  const std::string f = put("nosimple.json", b);
  refused(battery_like(f), f, "/", "expected a 'simple' object");
}

// linear_slope in [-1, -1e-6] 1/s: a flat line (0) never reaches an empty battery.
TEST_F(RefusalReasons, AFlatLinearSlopeIsRefusedAsNotFalling) {
  json b = epuck2::testing::shipped_fitted("battery");
  b["speeds"][2]["linear_slope"] = 0.0;
  const std::string f = put("slope.json", b);
  refused(battery_like(f), f, "/speeds/2/linear_slope", "a charge falls");
}

// docs/coefficient-files.md#charge-map: the map's form is monotone piecewise linear.
TEST_F(RefusalReasons, AChargeMapOfAnotherFormIsRefusedAtItsForm) {
  json b = epuck2::testing::shipped_fitted("battery");
  ASSERT_TRUE(b.contains("charge_map"));
  b["charge_map"]["form"] = "spline";
  const std::string f = put("form.json", b);
  const auto r = run("battery --charge-map \"" + f + "\" " + raw("battery", "robot-a_speed-01.csv") + " -o \"" +
                     (dir_ / "out.json").string() + "\"");
  EXPECT_EQ(r.exit_code, 2) << r.err;
  EXPECT_NE(r.err.find("(at JSON path /charge_map/form)"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("monotone_piecewise_linear"), std::string::npos) << r.err;
  EXPECT_FALSE(fs::exists(dir_ / "out.json"));
}

// Usage errors that name what is missing (docs/cli.md).
TEST_F(RefusalReasons, MissingRequiredPartsAreNamed) {
  {
    const auto r = run("generate light");
    EXPECT_EQ(r.exit_code, 2);
    EXPECT_NE(r.err.find("--out-dir DIR is required"), std::string::npos) << r.err;
  }
  {
    fs::create_directories(dir_ / "empty");
    const auto r = run("nist \"" + (dir_ / "empty").string() + "\"");
    EXPECT_EQ(r.exit_code, 2);
    EXPECT_NE(r.err.find("no .dat files in"), std::string::npos) << r.err;
  }
  {
    const std::string p = write("p.csv", "t_s,speed_cm_s\n0,0\n");
    const auto r = run("simulate battery --profile \"" + p + "\"");
    EXPECT_EQ(r.exit_code, 2);
    EXPECT_NE(r.err.find("--model is required with --profile"), std::string::npos) << r.err;
  }
}

// docs/cli.md: `--figure-size` is WIDTHxHEIGHT in cm, mm or in, each side from 1 in to 40 in.
TEST_F(RefusalReasons, AFigureSizeIsRefusedForItsUnitAndForItsSide) {
  const std::string log = raw("light", "light_intensity_0.50.csv");
  const std::string png = " --plot \"" + (dir_ / "f.png").string() + "\"";
  auto r = run("light " + log + " --figure-size 8x6pt" + png);
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.err.find("unknown unit 'pt'"), std::string::npos) << r.err;
  // 2.5 cm is below 1 in (2.54 cm); 2.54 cm is exactly 1 in and is taken.
  r = run("light " + log + " --figure-size 2.5x6cm" + png);
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.err.find("each side must lie between 1 in"), std::string::npos) << r.err;
  r = run("light " + log + " --figure-size 2.54x6cm --plot \"" + (dir_ / "ok.png").string() + "\"");
  EXPECT_EQ(r.exit_code, 0) << r.err;
  EXPECT_TRUE(fs::exists(dir_ / "ok.png"));
  // 40 in = 101.6 cm is the largest side; 101.7 cm is over it.
  r = run("light " + log + " --figure-size 8x101.7cm" + png);
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.err.find("each side must lie between 1 in"), std::string::npos) << r.err;
  EXPECT_FALSE(fs::exists(dir_ / "f.png"));
}

// docs/cli.md: an empty output name (`-o "$OUT"` with OUT unset) is exit 2, never read as no -o:
// every command that takes -o, nothing on standard output.
TEST_F(RefusalReasons, AnEmptyOutputNameIsRefusedByEveryCommand) {
  const std::string light = raw("light", "light_intensity_0.50.csv");
  const std::string battery = raw("battery", "robot-a_speed-01.csv");
  const std::string fitted = "\"" + (fs::path(EPUCK2_SOURCE_DIR) / "data" / "fitted" / "light.json").string() + "\"";
  const std::string nist = "\"" + (fs::path(EPUCK2_SOURCE_DIR) / "tests" / "data" / "nist").string() + "\"";
  const std::vector<std::string> commands{
      "light " + light,
      "battery " + battery,
      "diagnose " + light,
      "simulate light --like " + light,
      "simulate battery --profile \"" + write("p.csv", "t_s,speed_cm_s\n0,0\n10,0\n") + "\" --model cubic",
      "table5 " + battery,
      "nist " + nist,
      "codegen " + fitted,
  };
  for (const std::string& c : commands) {
    const auto r = run(c + " -o ''");
    EXPECT_EQ(r.exit_code, 2) << c << "\n" << r.err;
    EXPECT_TRUE(r.out.empty()) << c;
    EXPECT_NE(r.err.find("empty"), std::string::npos) << c << "\n" << r.err;
  }
}

// A warning is a reason too: battery logs whose voltage_v never varies cannot give a voltage->charge
// map; the charge column still gives the tables, and the run says why the map is missing (in the
// report's warnings and on standard error), writing no `charge_map`.
TEST_F(RefusalReasons, BatteryLogsWithAConstantVoltageSayWhyThereIsNoChargeMap) {
  std::string args;
  for (const auto& p : epuck2::testing::shipped_logs("battery", "robot-a")) {
    std::ifstream in(p);
    std::string text, line;
    while (std::getline(in, line)) {
      if (!line.empty() && line[0] >= '0' && line[0] <= '9') line = line.substr(0, line.rfind(',')) + ",3.7";  // voltage_v last
      text += line + "\n";
    }
    args += " \"" + write(p.filename().string(), text) + "\"";
  }
  const fs::path out = dir_ / "b.json";
  const auto r = run("battery" + args + " -o \"" + out.string() + "\"");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.err.find("warning: no voltage->charge map: voltage_v does not vary"), std::string::npos) << r.err;
  const json j = json::parse(epuck2::testing::slurp(out));
  EXPECT_FALSE(j.contains("charge_map"));
  bool said = false;
  for (const auto& w : j.at("warnings")) said = said || w.get<std::string>().find("no voltage->charge map") != std::string::npos;
  EXPECT_TRUE(said) << j.at("warnings").dump();
}

// A diagnosis with too few rows judges nothing and says so in its warnings as well as in its
// message: 8 rows of one light log (the minimum is far above 8 for any fold count).
TEST_F(RefusalReasons, ADiagnosisOfTooFewRowsWarnsThatNoEffectWasJudged) {
  std::ifstream in(fs::path(EPUCK2_SOURCE_DIR) / "data" / "raw" / "light" / "light_intensity_0.50.csv");
  std::string text, line;
  int rows = 0;
  while (std::getline(in, line) && rows < 8) {
    text += line + "\n";
    if (!line.empty() && line[0] >= '0' && line[0] <= '9') ++rows;
  }
  const std::string log = write("tiny.csv", text);
  const fs::path out = dir_ / "d.json";
  const auto r = run("diagnose \"" + log + "\" -o \"" + out.string() + "\"");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const json j = json::parse(epuck2::testing::slurp(out));
  EXPECT_EQ(j.at("rows").get<int>(), 8);
  EXPECT_TRUE(j.at("findings").empty());
  bool said = false;
  for (const auto& w : j.at("warnings")) said = said || w.get<std::string>().find("No effect was judged") != std::string::npos;
  EXPECT_TRUE(said) << j.at("warnings").dump();
  EXPECT_NE(r.err.find("warning: too few rows (8)"), std::string::npos) << r.err;
}

}  // namespace test_refusal_reasons_cpp
