// One light model everywhere (issue #22): a light calibration's per-sensor gammas
// (LightModel::sensor_gamma_m, the file's per_sensor[i].gamma) are read once by lib/coefficients,
// written back by its writer, emitted by codegen and used by simulate --like and the diagnosis's
// base model, as ARGoS uses them (argos/tests/light_per_sensor.sh). Every expected reading is
// paper Eq. 2 worked by hand from the gammas below, never the code's. File-local names carry the
// prefix lg (one unity test program).
#include <gtest/gtest.h>

#include <nlohmann/json.hpp>

#include <cmath>
#include <random>
#include <sstream>
#include <string>
#include <vector>

#include "cli_harness.hpp"
#include "epuck2/coefficients/codegen.hpp"
#include "epuck2/coefficients/model_file.hpp"
#include "epuck2/diagnose/diagnose.hpp"
#include "epuck2/diagnose/extended_model.hpp"
#include "epuck2/logs/log.hpp"
#include "epuck2/models/kinds.hpp"

namespace {

namespace lgs = epuck2::models::sensors;
namespace lgco = epuck2::coefficients;
using lg_json = nlohmann::json;

constexpr double kLgPooled = 0.075;  // m
const std::vector<double> kLgGammas{0.05, 0.06, 0.07, 0.08, 0.09, 0.10, 0.11, 0.12};  // m, sensors 0..7
// Eq. 2 at 0.2 m, intensity 1, by hand: (gamma I / d)^2 = 0.25^2 ... 0.60^2 = 0.0625, 0.09, 0.1225,
// 0.16, 0.2025, 0.25, 0.3025, 0.36, each times 4095 subtracted from 4095.
const std::vector<double> kLgHand{3839.0625, 3726.45, 3593.3625, 3439.8, 3265.7625, 3071.25, 2856.2625, 2620.8};
constexpr double kLgHandPooled = 3519.140625;  // 4095 (1 - 0.375^2): the pooled gamma's reading there

lgs::LightModel lg_model() {
  lgs::LightModel m;
  m.base.gamma_m = kLgPooled;
  for (std::size_t k = 0; k < kLgGammas.size(); ++k) m.sensor_gamma_m[k] = kLgGammas[k];
  return m;
}

lg_json lg_file(const std::vector<int>& sensors) {
  lg_json j = {{"kind", "light"}, {"parameters", {{"gamma", kLgPooled}, {"range_m", 0.5}}}};
  j["per_sensor"] = lg_json::array();
  for (int k : sensors) j["per_sensor"].push_back({{"sensor", k}, {"gamma", kLgGammas[static_cast<std::size_t>(k)]}});
  return j;
}

TEST(LightGammas, EachSensorReadsWithItsOwnGammaTheOthersWithThePooledOne) {
  const lgs::LightModel m = lg_model();
  for (int k = 0; k < 8; ++k) EXPECT_NEAR(lgs::mean_raw(m, k, 1.0, 0.2), kLgHand[static_cast<std::size_t>(k)], 1e-9) << k;
  lgs::LightModel some;
  some.base.gamma_m = kLgPooled;
  some.sensor_gamma_m[6] = 0.11;
  EXPECT_NEAR(lgs::mean_raw(some, 6, 1.0, 0.2), kLgHand[6], 1e-9);
  EXPECT_NEAR(lgs::mean_raw(some, 5, 1.0, 0.2), kLgHandPooled, 1e-9);
  // Without per-sensor gammas the formula is the pooled one's bit for bit (the plug-in's path).
  lgs::LightModel pooled;
  pooled.base.gamma_m = 0.0731;
  for (double d : {0.1, 0.17, 0.33})
    EXPECT_EQ(lgs::mean_raw(pooled, 4, 1.5, d), lgs::light_mean_raw(pooled.base, pooled.effects, 4, 1.5, d)) << d;
}

TEST(LightGammas, TheFileReadsAndWritesThemOncePerSensor) {
  const lgs::LightModel m = lgco::light_model_from_json(lg_file({0, 7}), "l.json");
  EXPECT_EQ(m.sensor_gamma_m[0], 0.05);
  EXPECT_EQ(m.sensor_gamma_m[7], 0.12);
  EXPECT_FALSE(m.sensor_gamma_m[3].has_value());
  EXPECT_NEAR(lgs::mean_raw(m, 3, 1.0, 0.2), kLgHandPooled, 1e-9);
  // The writer writes what the model holds, the sensors with their own gamma alone, and it reads back.
  const lg_json w = lgco::model_to_json(m);
  ASSERT_TRUE(w.contains("per_sensor"));
  ASSERT_EQ(w.at("per_sensor").size(), 2u);
  EXPECT_EQ(w.at("per_sensor")[1].at("sensor").get<int>(), 7);
  EXPECT_EQ(w.at("per_sensor")[1].at("gamma").get<double>(), 0.12);
  const lgs::LightModel back = lgco::light_model_from_json(w, "w.json");
  EXPECT_EQ(back.sensor_gamma_m, m.sensor_gamma_m);
  EXPECT_FALSE(lgco::model_to_json(lgs::LightModel{}).contains("per_sensor"));
  // Two entries for one sensor: which gamma would it be? Refused, located.
  lg_json twice = lg_file({2, 2});
  std::string e;
  try {
    lgco::light_model_from_json(twice, "twice.json");
  } catch (const std::exception& x) {
    e = x.what();
  }
  EXPECT_NE(e.find("/per_sensor/1/sensor"), std::string::npos) << e;
  // A gamma outside (0, 10] m is refused by the writer as by the reader.
  lgs::LightModel wild = m;
  wild.sensor_gamma_m[2] = 11.0;
  EXPECT_THROW(lgco::model_to_json(wild), std::domain_error);
}

TEST(LightGammas, CodegenEmitsThem) {
  const std::string cpp = lgco::model_to_cpp(lgco::light_model_from_json(lg_file({0, 7}), "l.json"), "l.json");
  EXPECT_NE(cpp.find("  m.sensor_gamma_m[0] = 0.05;\n"), std::string::npos) << cpp;
  EXPECT_NE(cpp.find("  m.sensor_gamma_m[7] = 0.12;\n"), std::string::npos) << cpp;
  EXPECT_EQ(cpp.find("m.sensor_gamma_m[3]"), std::string::npos) << cpp;
  EXPECT_EQ(lgco::model_to_cpp(lgs::LightModel{}, "plugin").find("sensor_gamma_m"), std::string::npos);
}

TEST(LightGammas, SimulateLikeTheBinaryReadsThemAtTheHandPoint) {
  const epuck2::testing::Scratch scratch("lg_simulate");
  std::string log = "# robot: lg\ndistance_m,intensity,sensor,value\n";
  for (int k = 0; k < 8; ++k) log += "0.2,1," + std::to_string(k) + ",0\n";
  const std::string like = scratch.write("lg.csv", log);
  const std::string file = scratch.write("lg.json", lg_file({0, 1, 2, 3, 4, 5, 6, 7}).dump());
  const epuck2::logs::Log sim = scratch.simulate_like("light", like, file);
  ASSERT_EQ(sim.rows(), 8u);
  for (std::size_t i = 0; i < 8; ++i) {
    const auto k = static_cast<std::size_t>(sim.col("sensor")[i]);
    EXPECT_NEAR(sim.col("value")[i], kLgHand[k], 1e-6) << "sensor " << k;
  }
}

/// Light readings of 8 sensors with their own gammas (kLgGammas), Eq. 2 with Gaussian noise of
/// 5 counts, rounded (no reading near a rail: 0.2 to 0.45 m, intensity 1 and 1.5).
epuck2::logs::Log lg_log(std::uint64_t seed) {
  std::mt19937_64 rng(seed);
  std::normal_distribution<double> noise(0.0, 5.0);
  std::ostringstream csv;
  csv << "# robot: lg\ndistance_m,intensity,sensor,value\n";
  for (int rep = 0; rep < 6; ++rep)
    for (int di = 0; di <= 5; ++di)
      for (double in : {1.0, 1.5})
        for (int k = 0; k < 8; ++k) {
          const double d = 0.2 + 0.05 * di, r = kLgGammas[static_cast<std::size_t>(k)] * in / d;
          csv << d << "," << in << "," << k << "," << std::round(4095.0 * (1.0 - r * r) + noise(rng)) << "\n";
        }
  return epuck2::logs::parse_log(csv.str(), "lg.csv", epuck2::logs::Kind::light);
}

TEST(LightGammas, TheDiagnosisBaseModelHasThem) {
  const epuck2::logs::Log log = lg_log(11);
  epuck2::diagnose::Options o;
  o.base_model = lg_model();
  const epuck2::diagnose::Report r = epuck2::diagnose::diagnose({log}, o);
  ASSERT_TRUE(r.supported) << r.message;
  // The base given, before any fit: its error is the readings' noise, 25 + 1/12 counts^2 of
  // rounding, within the spread of an MSE over 576 readings (about 6 %).
  EXPECT_NEAR(r.heldout_mse_plugin, 25.0 + 1.0 / 12.0, 0.2 * 25.0);
  EXPECT_EQ(r.verdict_name(), "none");
  // The extended model keeps each sensor's gamma (the pooled one recalibrated, each moved with it).
  const lgs::LightModel m = epuck2::diagnose::extended_light(r);
  for (std::size_t k = 0; k < 8; ++k) {
    ASSERT_TRUE(m.sensor_gamma_m[k].has_value()) << k;
    EXPECT_NEAR(*m.sensor_gamma_m[k], kLgGammas[k], 2e-4) << k;
  }
  // The pooled gamma alone misses the sensors by hundreds of counts.
  lgs::LightModel pooled;
  pooled.base.gamma_m = kLgPooled;
  o.base_model = pooled;
  EXPECT_GT(epuck2::diagnose::diagnose({log}, o).heldout_mse_plugin, 100.0 * 25.0);
}

}  // namespace
