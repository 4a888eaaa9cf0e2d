// The plug-in's coefficient-file reader (argos/src/coefficient_file.cpp): it needs no ARGoS, so it
// is tested on every machine. The shipped files must load, and each error must name the file and
// what is wrong (the calibrated sensors pass these messages on in their ARGoS exception).
#include <gtest/gtest.h>

#include <filesystem>
#include <functional>
#include <fstream>
#include <nlohmann/json.hpp>
#include <string>

#include "../src/coefficient_file.hpp"

namespace {

namespace ap = epuck2::argos_plugin;
namespace fs = std::filesystem;

std::string fitted(const std::string& name) { return std::string(EPUCK2_SOURCE_DIR) + "/data/fitted/" + name; }

std::string write_temp(const std::string& name, const std::string& text) {
  const fs::path p = fs::temp_directory_path() / ("epuck2_argos_test_" + name);
  std::ofstream(p) << text;
  return p.string();
}

std::string error_of(const std::function<void()>& f) {
  try {
    f();
  } catch (const std::exception& e) {
    return e.what();
  }
  return "";
}

TEST(CoefficientFile, ShippedSensorFilesLoad) {
  // What the loader gives is what the file says (read here with nlohmann-json directly).
  auto json_of = [](const std::string& path) {
    std::ifstream in(path);
    return nlohmann::json::parse(in);
  };
  const auto prox = ap::CoefficientFile::load(fitted("proximity.json"), {"proximity"});
  EXPECT_EQ(prox.scalar("a"), json_of(fitted("proximity.json")).at("parameters").at("a").get<double>());
  EXPECT_EQ(prox.per_sensor("a", 8).size(), 8u);
  const auto ground = ap::CoefficientFile::load(fitted("ground.json"), {"ground"});
  const auto gain = ground.per_sensor("gain", 3);
  EXPECT_EQ(gain[1], json_of(fitted("ground.json")).at("parameters").at("gain").at(1).get<double>());
  const auto drive = ap::CoefficientFile::load(fitted("drive.json"), {"drive", "tof"});
  const auto dj = json_of(fitted("drive.json"));
  EXPECT_EQ(drive.scalar("tof_scale"), dj.at("parameters").at("tof_scale").get<double>());
}

// Every shipped sensor file has the measured reading noise of each channel the calibrated sensors
// draw from, in the units they expect, and per sensor where the kind has several sensors.
TEST(CoefficientFile, ShippedFilesHaveTheReadingNoiseOfEveryChannel) {
  struct Channel {
    const char* file;
    const char* kind;
    const char* channel;
    const char* unit;
    std::size_t sensors;  ///< 0: no per-sensor entries
  };
  const Channel channels[] = {{"proximity.json", "proximity", "proximity", "counts", 8},
                              {"light.json", "light", "light", "counts", 8},
                              {"ground.json", "ground", "ground", "counts", 3},
                              {"drive.json", "drive", "tof", "mm", 0},
                              {"drive.json", "drive", "encoder", "steps", 0},
                              {"camera.json", "camera", "camera", "px", 0}};
  for (const Channel& c : channels) {
    SCOPED_TRACE(std::string(c.file) + " " + c.channel);
    const auto f = ap::CoefficientFile::load(fitted(c.file), {c.kind});
    ASSERT_TRUE(f.has_noise());
    const auto n = f.noise(c.channel, c.unit, c.sensors);
    ASSERT_TRUE(n.has_value());
    EXPECT_GT(n->sd, 0.0);
    EXPECT_GT(n->n, 0.0);
    EXPECT_TRUE(n->from == "replicates" || n->from == "residuals") << n->from;
    EXPECT_EQ(n->per_sensor_sd.size(), c.sensors);
    // The wrong unit is an error naming the entry.
    EXPECT_NE(error_of([&] { f.noise(c.channel, "furlongs", c.sensors); }).find("noise." + std::string(c.channel) + ".unit"),
              std::string::npos);
  }
}

TEST(CoefficientFile, NoiseSectionIsCheckedAndAFileWithoutOneSaysSo) {
  const std::string old = write_temp("old.json", R"({"kind": "ground", "parameters": {"gain": 1023, "offset": 0},
    "fits": {"sensor_0": {"noise_sd": 7}}})");
  const auto o = ap::CoefficientFile::load(old, {"ground"});
  EXPECT_FALSE(o.has_noise());
  EXPECT_FALSE(o.noise("ground", "counts", 3).has_value());  // the fits' noise_sd is not the reading noise
  const std::string no_channel = write_temp("nochannel.json", R"({"kind": "drive", "parameters": {},
    "noise": {"tof": {"sd": 3, "unit": "mm"}}})");
  const auto d = ap::CoefficientFile::load(no_channel, {"drive"});
  EXPECT_EQ(d.noise("tof", "mm", 0)->sd, 3.0);
  EXPECT_TRUE(d.noise("tof", "mm", 0)->per_sensor_sd.empty());
  EXPECT_EQ(d.noise("tof", "mm", 0)->sd_per_sensor(1), (std::vector<double>{3.0}));
  EXPECT_NE(error_of([&] { d.noise("encoder", "steps", 0); }).find("no 'encoder' entry"), std::string::npos);
  const std::string bad = write_temp("badnoise.json", R"({"kind": "ground", "parameters": {},
    "noise": {"ground": {"sd": -1, "unit": "counts"}}})");
  EXPECT_NE(error_of([&] { ap::CoefficientFile::load(bad, {"ground"}).noise("ground", "counts", 3); }).find("non-negative"),
            std::string::npos);
  const std::string short_list = write_temp("shortnoise.json", R"({"kind": "ground", "parameters": {},
    "noise": {"ground": {"sd": 5, "unit": "counts", "per_sensor_sd": [4, 5]}}})");
  EXPECT_NE(error_of([&] { ap::CoefficientFile::load(short_list, {"ground"}).noise("ground", "counts", 3); })
                .find("an array of 3 numbers"),
            std::string::npos);
}

TEST(CoefficientFile, AFileIsParsedOncePerProcessUntilItChanges) {
  const std::string p = write_temp("cache.json", R"({"kind": "proximity", "parameters": {"a": 1, "b": 2, "c": 3}})");
  const auto first = ap::parse_coefficient_file(p);
  EXPECT_EQ(ap::parse_coefficient_file(p).get(), first.get());  // the same parse, shared
  std::ofstream(p) << R"({"kind": "proximity", "parameters": {"a": 10, "b": 2, "c": 3}, "padding": "changes the size"})";
  const auto second = ap::parse_coefficient_file(p);
  EXPECT_NE(second.get(), first.get());
  EXPECT_EQ(ap::CoefficientFile::load(p, {"proximity"}).scalar("a"), 10.0);
}

TEST(CoefficientFile, ShippedBatteryFileLoads) {
  // Every robot's model shares one copy of a file's tables, equal to a fresh load's.
  const auto shared = ap::shared_battery_file(fitted("battery.json"));
  EXPECT_EQ(ap::shared_battery_file(fitted("battery.json")).get(), shared.get());
  const auto f = ap::load_battery_file(fitted("battery.json"));
  EXPECT_EQ(shared->tables.lifetime_s, f.tables.lifetime_s);
  EXPECT_EQ(shared->tables.cubic[7].d, f.tables.cubic[7].d);
  EXPECT_GT(f.tables.lifetime_s[0], 10000.0);
  EXPECT_LT(f.tables.simple_moving_slope_per_s, 0.0);
  EXPECT_EQ(f.fitted_speeds.size(), 16u);
  EXPECT_EQ(f.capacity_k, 1.0);
}

// A battery calibrated from two runs: its tables at 5 and 10 cm/s, the plug-in's elsewhere; a
// diagnosis's model and capacity scale; what ARGoS cannot apply is refused by name.
TEST(CoefficientFile, PartialBatteryTablesAndADiagnosisCapacityScale) {
  std::ifstream in(fitted("battery.json"));
  nlohmann::json j = nlohmann::json::parse(in);
  nlohmann::json two = nlohmann::json::array({j.at("speeds").at(5), j.at("speeds").at(10)});
  j["speeds"] = two;
  j.erase("simple");
  j["battery_model"] = "linear";
  j["effects"] = {{"capacity_scale", {{"k", 0.8}}}};
  const auto f = ap::load_battery_file(write_temp("partial_battery.json", j.dump()));
  EXPECT_EQ(f.fitted_speeds, (std::vector<int>{5, 10}));
  const auto& plugin = epuck2::models::battery::plugin_tables();
  EXPECT_EQ(f.tables.lifetime_s[5], two.at(0).at("lifetime_s").get<double>());
  EXPECT_EQ(f.tables.lifetime_s[10], two.at(1).at("lifetime_s").get<double>());
  EXPECT_EQ(f.tables.lifetime_s[6], plugin.lifetime_s[6]);
  EXPECT_EQ(f.tables.cubic[0].d, plugin.cubic[0].d);
  EXPECT_FALSE(f.fitted_simple);
  EXPECT_EQ(f.tables.simple_moving_slope_per_s, plugin.simple_moving_slope_per_s);
  ASSERT_TRUE(f.model.has_value());
  EXPECT_EQ(*f.model, epuck2::models::battery::Model::linear);
  EXPECT_EQ(f.capacity_k, 0.8);
  j["effects"] = {{"covariate:temperature_c", {{"slope", 0.01}, {"centre", 20}}}};
  const std::string cov = error_of([&] { ap::load_battery_file(write_temp("cov_battery.json", j.dump())); });
  EXPECT_NE(cov.find("effects.covariate:temperature_c: the calibrated battery cannot apply it in ARGoS: it needs the log "
                     "column 'temperature_c', which ARGoS does not have"),
            std::string::npos)
      << cov;
  j.erase("effects");
  j["speeds"].push_back(j["speeds"][0]);
  EXPECT_NE(error_of([&] { ap::load_battery_file(write_temp("dup_battery.json", j.dump())); }).find("a second table for 5 cm/s"),
            std::string::npos);
}

TEST(CoefficientFile, RobotSetsAndNoiseOverrideTheTopLevel) {
  const std::string p = write_temp("robots.json", R"({"kind": "ground",
    "parameters": {"gain": [1000, 1001, 1002], "offset": 5},
    "noise": {"ground": {"sd": 2.5, "unit": "counts", "per_sensor_sd": [2, 2.5, 3]}},
    "robots": {"r7": {"parameters": {"offset": [1, 2, 3]}, "noise": {"ground": {"sd": 4, "unit": "counts"}}}}})");
  const auto top = ap::CoefficientFile::load(p, {"ground"});
  EXPECT_EQ(top.per_sensor("offset", 3), (std::vector<double>{5, 5, 5}));
  EXPECT_EQ(top.noise("ground", "counts", 3)->sd, 2.5);
  EXPECT_EQ(top.noise("ground", "counts", 3)->sd_per_sensor(3), (std::vector<double>{2, 2.5, 3}));
  const auto r7 = ap::CoefficientFile::load(p, {"ground"}, "r7");
  EXPECT_EQ(r7.per_sensor("offset", 3), (std::vector<double>{1, 2, 3}));
  EXPECT_EQ(r7.per_sensor("gain", 3)[2], 1002);
  // The robot's channel replaces the top level's whole: its sd for every sensor.
  EXPECT_EQ(r7.noise("ground", "counts", 3)->sd_per_sensor(3), (std::vector<double>{4, 4, 4}));
  const std::string e = error_of([&] { ap::CoefficientFile::load(p, {"ground"}, "r8"); });
  EXPECT_NE(e.find(p), std::string::npos) << e;
  EXPECT_NE(e.find("no coefficients for robot 'r8'"), std::string::npos) << e;
  EXPECT_NE(e.find("r7"), std::string::npos) << e;
}

TEST(CoefficientFile, ErrorsNameTheFileAndTheProblem) {
  EXPECT_NE(error_of([] { ap::CoefficientFile::load("/nonexistent/x.json", {"proximity"}); }).find("/nonexistent/x.json: cannot open"),
            std::string::npos);
  const std::string bad = write_temp("bad.json", "{ not json");
  EXPECT_NE(error_of([&] { ap::CoefficientFile::load(bad, {"proximity"}); }).find("not JSON"), std::string::npos);
  EXPECT_NE(error_of([] { ap::CoefficientFile::load(fitted("ground.json"), {"proximity"}); }).find("a 'ground' file, expected proximity"),
            std::string::npos);
  const std::string missing = write_temp("missing.json", R"({"kind": "proximity", "parameters": {"a": 1, "b": 2}})");
  const auto f = ap::CoefficientFile::load(missing, {"proximity"});
  EXPECT_NE(error_of([&] { f.scalar("c"); }).find("missing parameter 'c'"), std::string::npos);
  const std::string wrong = write_temp("wrong.json", R"({"kind": "ground", "parameters": {"gain": [1, 2], "offset": 0}})");
  const auto g = ap::CoefficientFile::load(wrong, {"ground"});
  EXPECT_NE(error_of([&] { g.per_sensor("gain", 3); }).find("an array of 3 numbers"), std::string::npos);
  EXPECT_NE(error_of([&] { ap::load_battery_file(fitted("ground.json")); }).find("expected battery"), std::string::npos);
}

TEST(CoefficientFile, RelativeNamesResolveNextToTheExperimentFirst) {
  const fs::path dir = fs::temp_directory_path() / "epuck2_argos_resolve";
  fs::create_directories(dir / "fitted");
  std::ofstream(dir / "fitted" / "p.json") << "{}";
  EXPECT_EQ(ap::resolve_coefficient_path("fitted/p.json", (dir / "exp.argos").string()), (dir / "fitted" / "p.json").string());
  EXPECT_EQ(ap::resolve_coefficient_path("/abs/p.json", (dir / "exp.argos").string()), "/abs/p.json");
}

}  // namespace

// robot="auto" and robot_map: which set each ARGoS entity uses (argos/tests/swarm.sh runs it in ARGoS).
namespace {
TEST(CoefficientFile, RobotAutoPicksEachEntitysSet) {
  const nlohmann::json root = nlohmann::json::parse(R"({"parameters":{},"robots":{"A":{},"B":{},"ep3":{}},
      "robot_spread":[{"parameter":"gain[0]","spread_sd":12.5,"exceeds_uncertainty":true},
                      {"parameter":"offset[0]","spread_sd":0.1,"exceeds_uncertainty":false}]})");
  EXPECT_EQ(ap::choose_robot(root, "f.json", "auto", "ep0:A,ep1:A,ep*:B", "ep1").robot, "A");
  EXPECT_EQ(ap::choose_robot(root, "f.json", "auto", "ep0:A,ep1:A,ep*:B", "ep4").robot, "B");
  EXPECT_EQ(ap::choose_robot(root, "f.json", "auto", "*bot*:A", "footbot_7").robot, "A");
  EXPECT_EQ(ap::choose_robot(root, "f.json", "auto", "", "ep3").robot, "ep3");  // named like the entity
  EXPECT_EQ(ap::choose_robot(root, "f.json", "B", "", "ep0").robot, "B");
  const std::string missing = error_of([&] { ap::choose_robot(root, "f.json", "auto", "", "ep0"); });
  EXPECT_NE(missing.find("the entity 'ep0' has no robot set in the file (robots: A, B, ep3)"), std::string::npos) << missing;
  const std::string nomatch = error_of([&] { ap::choose_robot(root, "f.json", "auto", "fb*:A", "ep0"); });
  EXPECT_NE(nomatch.find("no robot_map pattern matches the entity 'ep0'"), std::string::npos) << nomatch;
  const std::string bad = error_of([&] { ap::choose_robot(root, "f.json", "auto", "ep0", "ep0"); });
  EXPECT_NE(bad.find("robot_map entry 'ep0' is not PATTERN:ROBOT_ID"), std::string::npos) << bad;
  // No robot= on a multi-robot file: the pooled set, with a warning naming what differs.
  const auto pooled = ap::choose_robot(root, "f.json", "", "", "ep0");
  EXPECT_EQ(pooled.robot, "");
  EXPECT_NE(pooled.warning.find("f.json holds 3 robots (A, B, ep3)"), std::string::npos) << pooled.warning;
  EXPECT_NE(pooled.warning.find("differ beyond their uncertainties in gain[0] (spread sd 12.5)"), std::string::npos);
  EXPECT_EQ(pooled.warning.find("offset[0]"), std::string::npos);
  // One robot, or none: nothing to say.
  EXPECT_EQ(ap::choose_robot(nlohmann::json::parse(R"({"robots":{"A":{}}})"), "f.json", "", "", "ep0").warning, "");
}
}  // namespace
