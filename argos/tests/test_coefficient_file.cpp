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
  // The fit's reading noise (fits.tof.noise_sd) is what the calibrated ToF draws from.
  ASSERT_TRUE(drive.noise_sd("tof").has_value());
  EXPECT_EQ(*drive.noise_sd("tof"), dj.at("fits").at("tof").at("noise_sd").get<double>());
}

TEST(CoefficientFile, ShippedBatteryFileLoads) {
  const auto t = ap::load_battery_tables(fitted("battery.json"));
  EXPECT_GT(t.lifetime_s[0], 10000.0);
  EXPECT_LT(t.simple_moving_slope_per_s, 0.0);
}

TEST(CoefficientFile, RobotSetsAndNoiseOverrideTheTopLevel) {
  const std::string p = write_temp("robots.json", R"({"kind": "ground",
    "parameters": {"gain": [1000, 1001, 1002], "offset": 5},
    "fits": {"ground": {"noise_sd": 2.5}},
    "robots": {"r7": {"parameters": {"offset": [1, 2, 3]}, "fits": {"ground": {"noise_sd": 4}}}}})");
  const auto top = ap::CoefficientFile::load(p, {"ground"});
  EXPECT_EQ(top.per_sensor("offset", 3), (std::vector<double>{5, 5, 5}));
  EXPECT_EQ(*top.noise_sd("ground"), 2.5);
  const auto r7 = ap::CoefficientFile::load(p, {"ground"}, "r7");
  EXPECT_EQ(r7.per_sensor("offset", 3), (std::vector<double>{1, 2, 3}));
  EXPECT_EQ(r7.per_sensor("gain", 3)[2], 1002);
  EXPECT_EQ(*r7.noise_sd("ground"), 4);
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
  EXPECT_NE(error_of([&] { ap::load_battery_tables(fitted("ground.json")); }).find("expected battery"), std::string::npos);
}

TEST(CoefficientFile, RelativeNamesResolveNextToTheExperimentFirst) {
  const fs::path dir = fs::temp_directory_path() / "epuck2_argos_resolve";
  fs::create_directories(dir / "fitted");
  std::ofstream(dir / "fitted" / "p.json") << "{}";
  EXPECT_EQ(ap::resolve_coefficient_path("fitted/p.json", (dir / "exp.argos").string()), (dir / "fitted" / "p.json").string());
  EXPECT_EQ(ap::resolve_coefficient_path("/abs/p.json", (dir / "exp.argos").string()), "/abs/p.json");
}

}  // namespace
