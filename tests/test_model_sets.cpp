// What a simulator running many robots from one coefficient file needs from lib/coefficients
// (model_sets.hpp, the partial battery tables, the light's per-sensor gammas, the proximity's means
// curve) and lib/models' several-lights mean: the ARGoS plug-in reads its files through these.
// Expected values are written by hand here (tables, positions counted in the text, sums worked
// out), not taken from the code under test.
#include <gtest/gtest.h>

#include <array>
#include <filesystem>
#include <fstream>
#include <functional>
#include <string>
#include <vector>

#include "epuck2/coefficients/battery_tables.hpp"
#include "epuck2/coefficients/model_file.hpp"
#include "epuck2/coefficients/model_sets.hpp"
#include "epuck2/models/kinds.hpp"
#include "epuck2/models/plugin_battery_tables.hpp"

namespace {

namespace co = epuck2::coefficients;
namespace s = epuck2::models::sensors;
namespace mb = epuck2::models::battery;
using nlohmann::json;

std::string write_temp(const std::string& name, const std::string& text) {
  const auto p = std::filesystem::temp_directory_path() / ("epuck2_model_sets_" + name);
  std::ofstream(p) << text;
  return p.string();
}

std::string error_of_sets(const std::function<void()>& f) {
  try {
    f();
  } catch (const std::exception& e) {
    return e.what();
  }
  return "";
}

/// FILE:LINE:COLUMN of the first occurrence of `needle` in one-line `text`.
std::string at_sets(const std::string& path, const std::string& text, const std::string& needle) {
  return path + ":1:" + std::to_string(text.find(needle) + 1) + ":";
}

std::string speed_row(int v, double life) {
  return R"({"speed_cm_s":)" + std::to_string(v) + R"(,"lifetime_s":)" + std::to_string(life) +
         R"(,"cubic":[0.98,-1e-4,2e-9,-1e-13],"linear_slope":-1e-4,"segments":[)"
         R"({"h":1,"m":-1e-2,"x1_s":0,"x2_s":10,"y1":1,"y2":0.9},{"h":1,"m":-1e-2,"x1_s":10,"x2_s":20,"y1":0.9,"y2":0.8},)"
         R"({"h":1,"m":-1e-2,"x1_s":20,"x2_s":30,"y1":0.8,"y2":0.7},{"h":1,"m":-1e-2,"x1_s":30,"x2_s":40,"y1":0.7,"y2":0.6}]})";
}

// A battery file with 2 of the 16 speeds: its tables there, the plug-in's published ones at the
// other 14 and for the Simple model (the file has no `simple`).
TEST(PartialBatteryTables, TheFilesSpeedsAndThePluginsElsewhere) {
  const json j = json::parse(R"({"kind":"battery","speeds":[)" + speed_row(10, 5000) + "," + speed_row(5, 7000) + "]}");
  co::TableSources src;
  const mb::Tables t = co::battery_tables_from_json(j, "b.json", src);
  EXPECT_EQ(src.fitted_speeds, (std::vector<int>{5, 10}));
  EXPECT_FALSE(src.fitted_simple);
  EXPECT_EQ(t.lifetime_s[5], 7000.0);
  EXPECT_EQ(t.lifetime_s[10], 5000.0);
  EXPECT_EQ(t.cubic[5].a, -1e-13);
  EXPECT_EQ(t.segments[10][3].y2, 0.6);
  const mb::Tables& plugin = mb::plugin_tables();
  EXPECT_EQ(t.lifetime_s[6], plugin.lifetime_s[6]);
  EXPECT_EQ(t.cubic[0].d, plugin.cubic[0].d);
  EXPECT_EQ(t.simple_moving_slope_per_s, plugin.simple_moving_slope_per_s);
  // The model reader takes the same path and keeps the file's capacity scale.
  json d = j;
  d["effects"] = {{"capacity_scale", {{"k", 0.8}}}};
  co::TableSources src2;
  const s::BatteryModel m = co::battery_model_from_json(d, "b.json", "", src2);
  EXPECT_EQ(m.capacity.k, 0.8);
  EXPECT_EQ(m.tables.lifetime_s[5], 7000.0);
  // The full reader still wants all 16.
  EXPECT_NE(error_of_sets([&] { co::battery_tables_from_json(j, "b.json"); }).find("expected 16 entries"), std::string::npos);
}

TEST(PartialBatteryTables, BadSpeedsAndValuesAreRefusedWhereTheyAre) {
  auto err = [](const std::string& name, const std::string& text) {
    const std::string path = write_temp(name, text);
    co::TableSources src;
    return error_of_sets([&] { co::battery_tables_from_json(json::parse(text), path, src); });
  };
  const std::string twice = R"({"speeds":[)" + speed_row(5, 7000) + "," + speed_row(5, 6000) + "]}";
  const std::string p1 = write_temp("twice.json", twice);
  const std::string e1 = err("twice.json", twice);
  EXPECT_NE(e1.find("a second table for 5 cm/s"), std::string::npos) << e1;
  EXPECT_NE(e1.find(p1 + ":1:" + std::to_string(twice.rfind(R"("speed_cm_s":5)") + 14) + ":"), std::string::npos) << e1;
  const std::string fast = R"({"speeds":[)" + speed_row(16, 7000) + "]}";
  EXPECT_NE(err("fast.json", fast).find("whole number of cm/s in 0..15"), std::string::npos);
  std::string half = R"({"speeds":[)" + speed_row(5, 7000) + "]}";
  half.replace(half.find(R"("speed_cm_s":5)"), 14, R"("speed_cm_s":2.5)");
  EXPECT_NE(err("half.json", half).find("whole number of cm/s in 0..15"), std::string::npos);
  for (const std::string life : {"0", "-100"}) {
    std::string bad = R"({"speeds":[)" + speed_row(5, 7000) + "]}";
    bad.replace(bad.find("7000.000000"), 11, life);
    const std::string path = write_temp("life.json", bad);
    const std::string e = err("life.json", bad);
    EXPECT_NE(e.find("lifetime_s must be positive"), std::string::npos) << e;
    EXPECT_NE(e.find(at_sets(path, bad, life + ",")), std::string::npos) << e;
  }
  EXPECT_NE(err("none.json", R"({"speeds":[]})").find("expected 1 to 16 entries"), std::string::npos);
}

TEST(ChooseRobot, AutoByMapByEntityAndThePooledWarning) {
  const json j = json::parse(R"({"robots":{"A":{},"B":{}},"robot_spread":[
      {"parameter":"gain[0]","spread_sd":12.5,"exceeds_uncertainty":true},
      {"parameter":"offset[0]","spread_sd":0.1,"exceeds_uncertainty":false}]})");
  EXPECT_EQ(co::choose_robot(j, "f.json", "auto", "ep0:A,ep*:B", "ep0").robot, "A");
  EXPECT_EQ(co::choose_robot(j, "f.json", "auto", "ep0:A,ep*:B", "ep12").robot, "B");
  EXPECT_EQ(co::choose_robot(j, "f.json", "auto", "", "B").robot, "B");
  EXPECT_EQ(co::choose_robot(j, "f.json", "A", "", "ep0").robot, "A");
  const std::string missing = error_of_sets([&] { co::choose_robot(j, "f.json", "auto", "", "ep3"); });
  EXPECT_NE(missing.find("the entity 'ep3' has no robot set in the file (robots: A, B)"), std::string::npos) << missing;
  EXPECT_NE(error_of_sets([&] { co::choose_robot(j, "f.json", "auto", "ep1:A", "ep3"); }).find("no robot_map pattern matches"),
            std::string::npos);
  EXPECT_NE(error_of_sets([&] { co::choose_robot(j, "f.json", "A", "ep1:A", "ep3"); }).find("only with robot=\"auto\""), std::string::npos);
  const co::RobotChoice pooled = co::choose_robot(j, "f.json", "", "", "ep0");
  EXPECT_EQ(pooled.robot, "");
  EXPECT_NE(pooled.warning.find("holds 2 robots (A, B)"), std::string::npos) << pooled.warning;
  EXPECT_NE(pooled.warning.find("gain[0] (spread sd 12.5)"), std::string::npos) << pooled.warning;
  EXPECT_EQ(pooled.warning.find("offset[0]"), std::string::npos) << pooled.warning;
  EXPECT_TRUE(co::choose_robot(json::parse(R"({"robots":{"A":{}}})"), "f.json", "", "", "ep0").warning.empty());
}

TEST(ModelSets, NoiseSectionAndThePathBesideTheExperiment) {
  EXPECT_FALSE(co::has_noise_section(json::parse(R"({"parameters":{}})"), ""));
  EXPECT_TRUE(co::has_noise_section(json::parse(R"({"noise":{}})"), ""));
  EXPECT_TRUE(co::has_noise_section(json::parse(R"({"robots":{"A":{"noise":{}}}})"), "A"));
  EXPECT_FALSE(co::has_noise_section(json::parse(R"({"robots":{"A":{"noise":{}}}})"), "B"));
  const std::string here = write_temp("beside.json", "{}");
  const std::string dir = std::filesystem::path(here).parent_path().string();
  EXPECT_EQ(co::resolve_model_path("epuck2_model_sets_beside.json", dir + "/exp.argos"), here);
  EXPECT_EQ(co::resolve_model_path("/abs/x.json", dir + "/exp.argos"), "/abs/x.json");
  EXPECT_EQ(co::resolve_model_path("nowhere.json", "/e/exp.argos"), "/e/nowhere.json");
  // Shared: the same parse while the file stays the same.
  EXPECT_EQ(co::shared_json_file(here).get(), co::shared_json_file(here).get());
  const std::string bad = write_temp("big.json", R"({"a": 1e999})");
  EXPECT_NE(error_of_sets([&] { co::shared_json_file(bad); }).find(bad + ":1:7:"), std::string::npos)
      << error_of_sets([&] { co::shared_json_file(bad); });
}

TEST(LightSensorGammas, PerSensorEntriesOverTheCommonGammaChecked) {
  const std::string text =
      R"({"kind":"light","parameters":{"gamma":0.075},"per_sensor":[{"sensor":0,"gamma":0.07},{"sensor":7,"gamma":0.08}],)"
      R"("robots":{"r":{"per_sensor":[{"sensor":3,"gamma":0.06}]}}})";
  const json j = json::parse(text);
  const s::LightModel m = co::light_model_from_json(j, "l.json");
  EXPECT_EQ(s::light_gamma_m(m, 0), 0.07);
  EXPECT_EQ(s::light_gamma_m(m, 7), 0.08);
  EXPECT_EQ(s::light_gamma_m(m, 3), 0.075);
  const s::LightModel r = co::light_model_from_json(j, "l.json", "r");
  EXPECT_EQ(s::light_gamma_m(r, 3), 0.06);
  EXPECT_EQ(s::light_gamma_m(r, 0), 0.075);  // the robot's list replaces the top level's
  for (const auto& [bad, why] : std::vector<std::pair<std::string, std::string>>{
           {R"({"sensor":8,"gamma":0.07})", "a light sensor's number, 0 to 7"},
           {R"({"sensor":1,"gamma":0})", "outside its physical range"},
           {R"({"sensor":1,"gamma":-0.07})", "outside its physical range"},
           {R"({"sensor":1,"gamma":1e308})", "outside its physical range"}}) {
    const std::string t = R"({"kind":"light","parameters":{"gamma":0.075},"per_sensor":[)" + bad + "]}";
    const std::string path = write_temp("gamma.json", t);
    const std::string e = error_of_sets([&] {
      const json jj = json::parse(t);
      co::light_model_from_json(jj, path);
    });
    EXPECT_NE(e.find(why), std::string::npos) << e;
    const std::string key = why.find("number") != std::string::npos ? R"(8,)" : bad.substr(bad.find("gamma") + 7);
    EXPECT_NE(e.find(at_sets(path, t, key)), std::string::npos) << e << " expected " << at_sets(path, t, key);
  }
}

TEST(ProximityCurve, TheMeansCurveIsReadAndCheckedWithTheSameRanges) {
  const json j = json::parse(R"({"kind":"proximity","parameters":{"a":197,"b":-30,"c":1.01,"mean_a":231,"mean_b":-31.5,"mean_c":0.97}})");
  const s::ProximityModel m = co::proximity_model_from_json(j, "p.json", "", co::ProximityCurve::means);
  EXPECT_EQ(m.base.a_per_m2, 231.0);
  EXPECT_EQ(m.base.b_per_m, -31.5);
  EXPECT_EQ(m.base.c, 0.97);
  EXPECT_EQ(co::proximity_model_from_json(j, "p.json").base.a_per_m2, 197.0);
  json big = j;
  big["parameters"]["mean_a"] = 1e308;
  EXPECT_NE(error_of_sets([&] { co::proximity_model_from_json(big, "p.json", "", co::ProximityCurve::means); })
                .find("parameters.mean_a = 1e+308 is outside its physical range"),
            std::string::npos)
      << error_of_sets([&] { co::proximity_model_from_json(big, "p.json", "", co::ProximityCurve::means); });
}

// Several lights at once, as a simulator sees them: worked by hand. gamma 0.075, lights (0.1 m,
// I 1) and (0.2 m, I 2): each (gamma I / d) = 0.75, so each adds 0.5625; 4095 (1 - 1.125) =
// -511.875. With exponent 3 each adds 0.421875; gain 0.5 and offset 10: 4095 (1 - 0.5 x 0.84375) -
// 10 = 2357.421875. A light beyond range_m or of intensity 0 adds nothing.
TEST(LightMean, SeveralLightsSumAsThePlugInDoes) {
  s::LightModel m;
  m.base.gamma_m = 0.075;
  const std::vector<s::LightSource> two{{0.1, 1.0}, {0.2, 2.0}, {0.6, 5.0}, {0.1, 0.0}};
  EXPECT_NEAR(s::mean_raw(m, 0, two), -511.875, 1e-9);
  m.effects.falloff.exponent = 3.0;
  m.effects.gains.gain[2] = 0.5;
  m.effects.ambient.offset_raw = 10.0;
  EXPECT_NEAR(s::mean_raw(m, 2, two), 2357.421875, 1e-9);
  EXPECT_NEAR(s::mean_raw(m, 2, std::vector<s::LightSource>{}), 4085.0, 1e-12);
  // One light: the one-light mean bit for bit, neutral or not.
  for (double d : {0.05, 0.13, 0.37})
    EXPECT_EQ(s::mean_raw(m, 2, std::vector<s::LightSource>{{d, 1.5}}), s::mean_raw(m, 2, 1.5, d));
  s::LightModel plain;
  EXPECT_EQ(s::mean_raw(plain, 0, std::vector<s::LightSource>{{0.21, 1.5}}), s::mean_raw(plain, 0, 1.5, 0.21));
}

}  // namespace
