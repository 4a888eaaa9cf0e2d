// One validation of a coefficient file everywhere (issue #22 items 2 and 4): nothing in a file is
// dropped by one reader and refused by another. Through the real binary, `simulate --like`,
// `codegen` and `diagnose --coefficients` each refuse a misspelt section, a misspelt parameter, an
// effect in a robot's set, a camera range_m of -1, a light per-sensor gamma of -1 and a battery
// table that rises, exit 2 at the file:line:column of the value; the writer refuses what the
// reader would refuse; models built (not read) write and read back or are refused.
//
// Expected positions come from the text each test writes (a placeholder's position, as
// argos/tests/hostile.py does), never from the code under test; the ranges from the docs.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <limits>
#include <random>
#include <string>
#include <vector>

#include "../fuzz/built_models.hpp"
#include "cli_harness.hpp"
#include "epuck2/coefficients/battery_tables.hpp"
#include "epuck2/coefficients/codegen.hpp"
#include "epuck2/coefficients/model_file.hpp"
#include "epuck2/logs/log.hpp"
#include "epuck2/models/plugin_battery_tables.hpp"

// This file's `using namespace` stays in its own named namespace, so it opens nothing to the
// files compiled after it in the same unity unit (tests/CMakeLists.txt).
namespace test_strict_files_cpp {
namespace {

using namespace epuck2;
namespace s = models::sensors;
namespace co = epuck2::coefficients;
using nlohmann::json;
namespace fs = std::filesystem;

/// A shipped file data/fitted/NAME.json as JSON.
json strict_shipped(const std::string& kind) {
  return json::parse(epuck2::testing::slurp(std::string(EPUCK2_SOURCE_DIR) + "/data/fitted/" + kind + ".json"));
}

/// `j` as text (indent 2) with `literal` at JSON pointer `pointer` (created when absent), and the
/// line:column where the literal starts, found in the text.
struct StrictPlaced {
  std::string text;
  std::string where;  ///< "LINE:COLUMN"
};
StrictPlaced strict_place(json j, const std::string& pointer, const std::string& literal) {
  const std::string placeholder = "\"@@STRICT@@\"";
  j[json::json_pointer(pointer)] = "@@STRICT@@";
  std::string text = j.dump(2);
  const std::size_t at = text.find(placeholder);
  const std::size_t line = static_cast<std::size_t>(std::count(text.begin(), text.begin() + static_cast<long>(at), '\n')) + 1;
  const std::size_t line_start = text.rfind('\n', at);
  const std::size_t column = at - (line_start == std::string::npos ? 0 : line_start + 1) + 1;
  text.replace(at, placeholder.size(), literal);
  return {text, std::to_string(line) + ":" + std::to_string(column)};
}

struct StrictCase {
  const char* name;
  const char* kind;
  std::string pointer;  ///< where the hostile value goes
  const char* literal;
  const char* reason;  ///< what the message must say
};

std::vector<StrictCase> strict_cases() {
  const json ground = strict_shipped("ground");
  const std::string robot = ground.at("robots").begin().key();
  return {
      {"misspelt_section", "ground", "/efects", R"({"nonlinear_response": {"k": 0.1}})", "did you mean 'effects'?"},
      {"misspelt_parameter", "drive", "/parameters/tof_scael", "0.98", "did you mean 'tof_scale'?"},
      {"robot_set_effect", "ground", "/robots/" + robot + "/effects", R"({"warp_drive": {"speed": 9}})", "unknown key 'effects'"},
      {"camera_range_negative", "camera", "/parameters/range_m", "-1", "parameters.range_m = -1.0 is outside its physical range (0.0, 10.0] m"},
      {"light_gamma_negative", "light", "/per_sensor/0/gamma", "-1", "per_sensor[0].gamma = -1.0 is outside its physical range"},
      {"battery_rises", "battery", "/speeds/3/segments/1/y2", "0.9", "a charge does not rise"},
  };
}

class StrictFilesCli : public epuck2::testing::CliTest {};

TEST_F(StrictFilesCli, SimulateCodegenAndDiagnoseRefuseTheSameFilesAtTheSamePlace) {
  for (const StrictCase& c : strict_cases()) {
    json j = strict_shipped(c.kind);
    if (c.pointer == "/parameters/tof_scael") j.at("parameters").erase("tof_scale");  // misspelt, not added
    const StrictPlaced p = strict_place(j, c.pointer, c.literal);
    const std::string file = write(std::string(c.name) + ".json", p.text);
    const std::string log = shipped(c.kind);
    const std::string first_log = log.substr(0, log.find('"', 2) + 1);
    const std::string expected = file + ":" + p.where + ": ";
    const std::string at_path = "(at JSON path " + c.pointer + ")";
    const std::vector<std::pair<std::string, std::string>> commands{
        {"simulate", "simulate " + std::string(c.kind) + " --like " + first_log + " --coefficients \"" + file + "\" -o \"" +
                         (dir_ / "sim.csv").string() + "\""},
        {"codegen", "codegen \"" + file + "\" -o \"" + (dir_ / "h.hpp").string() + "\""},
        {"diagnose", "diagnose " + first_log + " --coefficients \"" + file + "\" -o \"" + (dir_ / "d.json").string() + "\""}};
    for (const auto& [what, args] : commands) {
      const epuck2::testing::CliRun r = run(args);
      EXPECT_EQ(r.exit_code, 2) << c.name << " " << what << ": " << r.err;
      EXPECT_NE(r.err.find(expected), std::string::npos) << c.name << " " << what << ": expected '" << expected << "' in " << r.err;
      EXPECT_NE(r.err.find(c.reason), std::string::npos) << c.name << " " << what << ": " << r.err;
      EXPECT_NE(r.err.find(at_path), std::string::npos) << c.name << " " << what << ": " << r.err;
    }
    EXPECT_FALSE(fs::exists(dir_ / "sim.csv")) << c.name;
    EXPECT_FALSE(fs::exists(dir_ / "h.hpp")) << c.name;
    EXPECT_FALSE(fs::exists(dir_ / "d.json")) << c.name;
  }
}

TEST_F(StrictFilesCli, CodegensDuplicateConstantIsLocated) {
  // Worked by hand: std_errors.x becomes x_std_error, already declared by parameters.x_std_error;
  // its value 0.1 is on line 4, column 23.
  const std::string file = write("lidar.json",
                                 "{\n  \"kind\": \"lidar\",\n  \"parameters\": {\"x\": 1, \"x_std_error\": 2},\n  \"std_errors\": {\"x\": 0.1}\n}\n");
  const epuck2::testing::CliRun r = run("codegen \"" + file + "\" -o \"" + (dir_ / "h.hpp").string() + "\"");
  EXPECT_EQ(r.exit_code, 2) << r.err;
  EXPECT_NE(r.err.find(file + ":4:23: the constant 'lidar::x_std_error' would be declared twice"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("(at JSON path /std_errors/x)"), std::string::npos) << r.err;
}

TEST_F(StrictFilesCli, EveryShippedFileAndEveryRobotSetReads) {
  for (const char* kind : {"proximity", "light", "ground", "camera", "drive", "battery"}) {
    const json j = strict_shipped(kind);
    EXPECT_NO_THROW((void)co::model_from_json(kind, j, kind)) << kind;
    for (const std::string& robot : co::robot_ids(j)) EXPECT_NO_THROW((void)co::model_from_json(kind, j, kind, robot)) << kind << " " << robot;
  }
}

// ----- the library: what one set refuses, every reading of the file refuses ---------------------

std::string strict_error(const std::string& kind, const json& j, const std::string& robot = "") {
  try {
    (void)co::model_from_json(kind, j, "x.json", robot);
  } catch (const logs::InputError& e) {
    return e.what();
  }
  return "";
}

TEST(StrictFiles, ARobotsBadSetIsRefusedWhicheverSetIsRead) {
  json j = strict_shipped("drive");
  const std::vector<std::string> robots = co::robot_ids(j);
  ASSERT_GE(robots.size(), 2u);
  j["robots"][robots[1]]["parameters"]["steps_per_m"] = -1.0;
  for (const std::string& robot : {std::string(), robots[0], robots[1]}) {
    const std::string e = strict_error("drive", j, robot);
    EXPECT_NE(e.find("/robots/" + robots[1] + "/parameters/steps_per_m"), std::string::npos) << "robot '" << robot << "': " << e;
  }
}

TEST(StrictFiles, UnknownKeysAreRefusedWithTheClosestKnownOne) {
  struct Case {
    const char* kind;
    const char* pointer;
    json value;
    const char* expected;
  };
  const Case cases[] = {
      {"proximity", "/noise/proximty", json{{"sd", 2.0}}, "unknown noise channel 'proximty' for a proximity model (its channels: proximity); did you mean 'proximity'?"},
      {"light", "/noise/light/s_d", 2.0, "unknown key 's_d' in noise.light"},
      {"ground", "/std_errors/gian", json::array({1, 1, 1}), "unknown parameter 'gian' in `std_errors`"},
      {"camera", "/parameters/fov_degs", 30.0, "did you mean 'fov_deg'?"},
      {"light", "/per_sensor/0/gama", 0.07, "unknown key 'gama' in per_sensor[0]"},
      {"battery", "/speeds/2/lifetime_S", 100.0, "unknown key 'lifetime_S' in speeds[2]"},
      {"battery", "/simple/static_slope_per_S", -1e-4, "did you mean 'static_slope_per_s'?"},
  };
  for (const Case& c : cases) {
    json j = strict_shipped(c.kind);
    j[json::json_pointer(c.pointer)] = c.value;
    const std::string e = strict_error(c.kind, j);
    EXPECT_NE(e.find(c.expected), std::string::npos) << c.pointer << ": " << e;
    EXPECT_NE(e.find(std::string("(at JSON path ") + c.pointer + ")"), std::string::npos) << e;
  }
}

TEST(StrictFiles, CameraFixedValuesAndTheLightsUnusableSensors) {
  json j = strict_shipped("camera");
  j["parameters"]["width_px"] = 320;
  EXPECT_NE(strict_error("camera", j).find("is not the E-Puck2 camera's image width, 160 px"), std::string::npos);
  j = strict_shipped("camera");
  j["parameters"]["aperture_deg"] = 25.0;  // fov_deg 30.8 gives 19.0 on a 160x120 diagonal
  EXPECT_NE(strict_error("camera", j).find("does not match fov_deg"), std::string::npos);
  j = strict_shipped("camera");
  j["parameters"]["range_m"] = 2.5;
  const auto cam = std::get<s::CameraModel>(co::model_from_json("camera", j, "x.json"));
  EXPECT_EQ(cam.base.range_m, 2.5);
  j["parameters"]["range_m"] = 10.5;  // beyond the documented 10 m
  EXPECT_NE(strict_error("camera", j).find("(0.0, 10.0] m"), std::string::npos);
  // A sensor the calibration could not fit keeps the common gamma; one that could must have one.
  json l = strict_shipped("light");
  l["per_sensor"][2] = {{"sensor", 2}, {"usable", false}, {"why", "no reading"}};
  const auto light = std::get<s::LightModel>(co::model_from_json("light", l, "x.json"));
  EXPECT_FALSE(light.sensor_gamma_m[2].has_value());
  EXPECT_EQ(s::light_gamma_m(light, 2), light.base.gamma_m);
  l["per_sensor"][2] = {{"sensor", 2}, {"usable", true}};
  EXPECT_NE(strict_error("light", l).find("must be an object with \"sensor\" and \"gamma\""), std::string::npos);
}

TEST(StrictFiles, BatteryTablesInTheirDocumentedRanges) {
  struct Case {
    const char* pointer;
    double value;
    const char* expected;
  };
  // docs/coefficient-files.md, "Battery tables": lifetimes (0, 1e6] s, slopes in [-1, 0] /s,
  // bands in [0, 1], the cubic's d in [0, 1.05] and its charge in [-1, 1.05] over the lifetime.
  const Case cases[] = {
      {"/speeds/3/lifetime_s", 1e308, "speeds[3].lifetime_s = 1e+308 is outside its physical range"},
      {"/speeds/3/lifetime_s", 1.5e6, "speeds[3].lifetime_s = 1500000.0 is outside"},
      {"/speeds/5/linear_slope", -2.0, "speeds[5].linear_slope = -2.0 is outside"},
      {"/speeds/5/segments/0/y1", 1.2, "speeds[5].segments[0].y1 = 1.2 is outside"},
      {"/speeds/5/segments/2/m", 1e-4, "a charge does not rise"},
      {"/speeds/5/segments/2/h", 7.0, "its line h + m t gives"},
      {"/speeds/0/cubic/0", 1.2, "speeds[0].cubic[0] (d, the charge at 0 s) = 1.2 is outside"},
      {"/speeds/0/cubic/3", 1e-9, "speeds[0].cubic: the charge it gives at"},
      {"/simple/moving_slope_per_s", -1e308, "simple.moving_slope_per_s = -1e+308 is outside"},
      {"/speeds/4/noise_sd", 1e200, "speeds[4].noise_sd: a reading's noise sd must lie in [0, 1.0) charge"},
  };
  for (const Case& c : cases) {
    json j = strict_shipped("battery");
    j[json::json_pointer(c.pointer)] = c.value;
    const std::string e = strict_error("battery", j);
    EXPECT_NE(e.find(c.expected), std::string::npos) << c.pointer << " = " << c.value << ": " << e;
  }
  // The plug-in's published tables are inside every range (they are what the ranges come from).
  EXPECT_NO_THROW((void)co::battery_tables_to_json(models::battery::plugin_tables()));
}

// ----- the writer refuses what the reader would refuse -------------------------------------------

TEST(StrictFiles, TheWriterRefusesWhatAReaderWouldRefuse) {
  s::ProximityModel p;
  p.noise_sd_raw.fill(1e200);  // above the 4095-count full scale
  s::CameraModel c;
  c.base.cx_px = 1e6;  // outside the 160 px image
  s::DriveModel d;
  d.steps_per_m = -5;
  s::BatteryModel b;
  b.tables.segments[4][1].y2 = 0.99;  // above its y1: the band rises
  auto refusal = [](const auto& m) -> std::string {
    try {
      (void)co::model_to_json(m);
    } catch (const std::domain_error& e) {
      return e.what();
    }
    return "";
  };
  EXPECT_NE(refusal(p).find("noise sd must lie in [0, 4095.0) counts"), std::string::npos) << refusal(p);
  EXPECT_NE(refusal(c).find("parameters.cx_px = 1000000.0 is outside its physical range"), std::string::npos) << refusal(c);
  EXPECT_NE(refusal(d).find("parameters.steps_per_m = -5.0 is outside"), std::string::npos) << refusal(d);
  EXPECT_NE(refusal(b).find("a charge does not rise"), std::string::npos) << refusal(b);
  EXPECT_THROW((void)co::battery_tables_to_json(b.tables), std::domain_error);
  EXPECT_THROW((void)co::model_to_cpp(d, "x.json"), std::domain_error);
  // A camera's range other than the plug-in's is written and read back.
  s::CameraModel far;
  far.base.range_m = 3.25;
  const json w = co::model_to_json(far);
  EXPECT_EQ(w.at("parameters").at("range_m").get<double>(), 3.25);
  EXPECT_EQ(co::camera_model_from_json(w, "x.json").base.range_m, 3.25);
  EXPECT_FALSE(co::model_to_json(s::CameraModel{}).at("parameters").contains("range_m"));
}

/// Numbers for fuzzing::built_model from a seeded generator: mostly the current value or close to
/// it, sometimes a wild one (0, negative, huge, not finite).
struct StrictNumbers {
  std::mt19937_64 rng{20261126};
  double operator()(double current) {
    std::uniform_real_distribution<double> u(0, 1);
    const double r = u(rng);
    if (r < 0.90) return current;
    if (r < 0.97) return current * (1 + 0.2 * (u(rng) - 0.5));
    const double wild[] = {0.0, -1.0, -5.0, 1e6, 1e200, -1e308, std::nan(""), std::numeric_limits<double>::infinity(), 0.5, 2.0};
    return wild[static_cast<std::size_t>(u(rng) * 10) % 10];
  }
};

template <class Model, class FromJson>
void strict_round_trips(FromJson from_json, int& written, int& refused) {
  StrictNumbers next;
  for (int i = 0; i < 300; ++i) {
    const Model m = fuzzing::built_model<Model>(next);
    std::string why;
    const fuzzing::RoundTrip r = fuzzing::write_and_read_back(m, from_json, why);
    EXPECT_TRUE(r == fuzzing::RoundTrip::equal || r == fuzzing::RoundTrip::refused) << co::kind_of(m) << " model " << i << ": " << why;
    (r == fuzzing::RoundTrip::equal ? written : refused) += 1;
  }
}

TEST(StrictFiles, BuiltModelsAreWrittenAndReadBackOrRefused) {
  int written = 0, refused = 0;
  strict_round_trips<s::ProximityModel>([](const json& j, const std::string& p, const std::string& r) { return co::proximity_model_from_json(j, p, r); }, written, refused);
  strict_round_trips<s::LightModel>([](const json& j, const std::string& p, const std::string& r) { return co::light_model_from_json(j, p, r); }, written, refused);
  strict_round_trips<s::GroundModel>([](const json& j, const std::string& p, const std::string& r) { return co::ground_model_from_json(j, p, r); }, written, refused);
  strict_round_trips<s::CameraModel>([](const json& j, const std::string& p, const std::string& r) { return co::camera_model_from_json(j, p, r); }, written, refused);
  strict_round_trips<s::DriveModel>([](const json& j, const std::string& p, const std::string& r) { return co::drive_model_from_json(j, p, r); }, written, refused);
  strict_round_trips<s::BatteryModel>([](const json& j, const std::string& p, const std::string& r) { return co::battery_model_from_json(j, p, r); }, written, refused);
  // Both branches of the property are exercised (else the generator proves nothing).
  EXPECT_GT(written, 100);
  EXPECT_GT(refused, 100);
}

}  // namespace
}  // namespace test_strict_files_cpp
