// The diagnosis's steps that name and restrict what it finds, and the one parameter type:
// - a finding whose fitted parameters make it another effect is named for what it is: three equal
//   ground sensor gains are one white level; a proximity "long tail" that carries the whole
//   near-field curve is the curve's shape, not a tail;
// - Options::effects restricts the search, and an effect the logs cannot show is an error naming
//   those they can;
// - no hidden state between evaluations: two diagnoses of the same drive log on two threads give
//   the sequential one's numbers bit for bit;
// - a parameter looked up by a name the fit does not have is an error, never a NaN.
// The logs are drawn here with their own arithmetic (std::pow, their own clamps), not lib/models'.
#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <sstream>
#include <stdexcept>
#include <thread>

#include "diagnose_generators.hpp"
#include "epuck2/diagnose/diagnose.hpp"
#include "epuck2/diagnose/extended_model.hpp"
#include "epuck2/fit/fit_curve.hpp"
#include "epuck2/fit/least_squares.hpp"
#include "epuck2/fit/parameter.hpp"
#include "epuck2/logs/log.hpp"

// This file's `using namespace` stays in its own named namespace, so it opens nothing to the
// files compiled after it in the same unity unit (tests/CMakeLists.txt).
namespace test_diagnose_steps_cpp {
namespace {

using namespace epuck2;
namespace gen = epuck2::testing::diagnose;

/// Ground readings v = round(clamp(level * grey + noise, 0, 1023)), the same level for every
/// sensor: a white level, drawn without lib/models.
logs::Log equal_gains_ground(double level, double noise_sd, std::uint64_t seed) {
  std::mt19937_64 rng(seed);
  std::normal_distribution<double> noise(0.0, noise_sd);
  std::ostringstream csv;
  csv << "grey,sensor,value\n";
  for (int rep = 0; rep < 20; ++rep)
    for (int g = 0; g <= 20; ++g)
      for (int sensor = 0; sensor < 3; ++sensor) {
        const double grey = g / 20.0;
        const double v = std::round(std::min(1023.0, std::max(0.0, level * grey + noise(rng))));
        csv << grey << "," << sensor << "," << v << "\n";
      }
  return logs::parse_log(csv.str(), "equal_gains.csv", logs::Kind::ground);
}

const diagnose::NamedValue* parameter(const diagnose::Finding& f, const std::string& name) {
  for (const auto& v : f.parameters)
    if (v.name == name) return &v;
  return nullptr;
}

TEST(DiagnoseNaming, EqualSensorGainsAreOneWhiteLevel) {
  constexpr double kLevel = 900.0;
  const logs::Log log = equal_gains_ground(kLevel, 5.0, 7);
  diagnose::Options o;
  o.effects = {"sensor_gain"};  // the search may only try the gains
  const diagnose::Report r = diagnose::diagnose({log}, o);
  ASSERT_TRUE(r.supported) << r.message;
  ASSERT_EQ(r.findings.size(), 1u) << r.verdict_name();
  const diagnose::Finding& f = r.findings.front();
  EXPECT_EQ(f.cause, "white_level");
  EXPECT_EQ(f.effect, "white_level");
  EXPECT_EQ(f.renamed_from, "sensor_gain");
  EXPECT_TRUE(r.verdict == diagnose::Verdict::effect);
  EXPECT_EQ(r.verdict_name(), "white_level");
  const diagnose::NamedValue* level = parameter(f, "level");
  ASSERT_NE(level, nullptr);
  // 1260 readings of sd 5 over grey 0..1: the level's error is about 0.3 counts.
  EXPECT_NEAR(level->value, kLevel, 2.0);
  // The extended model carries the white level, not gains.
  const auto m = diagnose::extended_ground(r);
  for (const auto& sensor : m.sensors) EXPECT_NEAR(sensor.gain_raw, kLevel, 2.0);
}

TEST(DiagnoseNaming, UnequalSensorGainsStaySensorGains) {
  // The generator's sensor_gain effect (gains drawn apart): the same search keeps its name.
  for (std::uint64_t seed : {3u, 4u}) {
    gen::Hidden h = gen::hidden("sensor_gain");
    const auto log = logs::parse_log(gen::make_log(logs::Kind::ground, seed, h), "g.csv", logs::Kind::ground);
    diagnose::Options o;
    o.effects = {"sensor_gain"};
    const diagnose::Report r = diagnose::diagnose({log}, o);
    ASSERT_FALSE(r.findings.empty()) << seed;
    EXPECT_EQ(r.findings.front().cause, "sensor_gain") << seed;
    EXPECT_TRUE(r.findings.front().renamed_from.empty()) << seed;
  }
}

/// Proximity readings whose near-field curve is an exponential, v = 3800 exp(-d / 0.012) + noise
/// (no quadratic), out to 0.05 m, and 0 beyond: a "tail" can only fit it by replacing the curve.
logs::Log exponential_proximity(std::uint64_t seed) {
  std::mt19937_64 rng(seed);
  std::normal_distribution<double> noise(0.0, 10.0);
  std::ostringstream csv;
  csv << "distance_m,sensor,value\n";
  for (int rep = 0; rep < 6; ++rep)
    for (int k = 1; k <= 60; ++k)
      for (int sensor = 0; sensor < 8; ++sensor) {
        const double d = 0.001 * k;
        const double mean = d <= 0.05 ? 3800.0 * std::exp(-d / 0.012) : 0.0;
        const double v = std::round(std::min(4095.0, std::max(0.0, mean + noise(rng))));
        csv << d << "," << sensor << "," << v << "\n";
      }
  return logs::parse_log(csv.str(), "exponential.csv", logs::Kind::proximity);
}

TEST(DiagnoseNaming, ATailThatReplacesTheNearFieldCurveIsNotATail) {
  diagnose::Options o;
  o.effects = {"long_tail"};
  const diagnose::Report r = diagnose::diagnose({exponential_proximity(11)}, o);
  ASSERT_TRUE(r.supported) << r.message;
  ASSERT_FALSE(r.findings.empty()) << r.verdict_name();
  const diagnose::Finding& f = r.findings.front();
  EXPECT_EQ(f.cause, "near_field_curve");
  EXPECT_EQ(f.effect, "long_tail");  // the same formula, carried into the model
  EXPECT_EQ(f.renamed_from, "long_tail");
  // The extended model still simulates what was fitted.
  const auto m = diagnose::extended_proximity(r);
  EXPECT_GT(m.effects.tail.amplitude_raw, 0.0);
}

TEST(DiagnoseNaming, AGenuineTailKeepsItsName) {
  gen::Hidden h = gen::hidden("long_tail");
  const auto log = logs::parse_log(gen::make_log(logs::Kind::proximity, 3, h), "p.csv", logs::Kind::proximity);
  const diagnose::Report r = diagnose::diagnose({log});
  ASSERT_FALSE(r.findings.empty());
  EXPECT_EQ(r.findings.front().cause, "long_tail") << r.findings.front().renamed_from;
}

TEST(DiagnoseOptions, AnEffectTheLogsCannotShowIsAnErrorNamingThoseTheyCan) {
  const logs::Log log = equal_gains_ground(1023.0, 5.0, 1);
  diagnose::Options o;
  o.effects = {"white_levle"};
  const diagnose::Report r = diagnose::diagnose({log}, o);
  EXPECT_FALSE(r.supported);
  EXPECT_NE(r.message.find("white_levle"), std::string::npos) << r.message;
  EXPECT_NE(r.message.find("white_level"), std::string::npos) << r.message;
}

TEST(DiagnoseSteps, TwoThreadsGiveTheSequentialNumbersBitForBit) {
  gen::Hidden h = gen::hidden("latency");
  const auto log = logs::parse_log(gen::make_log(logs::Kind::drive, 21, h), "d.csv", logs::Kind::drive);
  const diagnose::Report sequential = diagnose::diagnose({log});
  diagnose::Report a, b;
  std::thread ta([&] { a = diagnose::diagnose({log}); });
  std::thread tb([&] { b = diagnose::diagnose({log}); });
  ta.join();
  tb.join();
  for (const diagnose::Report* r : {&a, &b}) {
    EXPECT_EQ(r->verdict_name(), sequential.verdict_name());
    EXPECT_EQ(r->heldout_mse_final, sequential.heldout_mse_final);
    ASSERT_EQ(r->findings.size(), sequential.findings.size());
    for (std::size_t k = 0; k < r->findings.size(); ++k)
      for (std::size_t q = 0; q < r->findings[k].parameters.size(); ++q)
        EXPECT_EQ(r->findings[k].parameters[q].value, sequential.findings[k].parameters[q].value);
  }
}

// ----- the base model given (--coefficients FILE) -------------------------------------------------

/// Ground readings of three sensors that differ, v = round(clamp(B_s + G_s grey^p + noise)).
logs::Log differing_ground(double exponent, std::uint64_t seed) {
  const double B[3] = {30, 40, 55}, G[3] = {950, 1000, 900};
  std::mt19937_64 rng(seed);
  std::normal_distribution<double> noise(0.0, 5.0);
  std::ostringstream csv;
  csv << "grey,sensor,value\n";
  for (int rep = 0; rep < 20; ++rep)
    for (int g = 0; g <= 20; ++g)
      for (int sensor = 0; sensor < 3; ++sensor) {
        const double grey = g / 20.0;
        const double v = std::round(std::min(1023.0, std::max(0.0, B[sensor] + G[sensor] * std::pow(grey, exponent) + noise(rng))));
        csv << grey << "," << sensor << "," << v << "\n";
      }
  return logs::parse_log(csv.str(), "differing.csv", logs::Kind::ground);
}

models::sensors::GroundModel calibrated_ground() {
  models::sensors::GroundModel m;
  m.sensors = {models::sensors::GroundCoefficients{950, 30}, {1000, 40}, {900, 55}};
  return m;
}

TEST(DiagnoseBase, ACalibratedGroundModelLeavesNothingToFind) {
  const logs::Log log = differing_ground(1.0, 5);
  const diagnose::Report plugin = diagnose::diagnose({log});
  EXPECT_FALSE(plugin.findings.empty()) << "the plug-in's 1023 grey must miss these sensors";
  diagnose::Options o;
  o.base_model = calibrated_ground();
  const diagnose::Report r = diagnose::diagnose({log}, o);
  ASSERT_TRUE(r.supported) << r.message;
  EXPECT_EQ(r.verdict_name(), "none");
  // The base given, before any fit: its error is the readings' noise (25 + 1/12 counts^2 of
  // rounding), within the spread of an MSE over 1260 readings (about 4 %).
  EXPECT_NEAR(r.heldout_mse_plugin, 25.0 + 1.0 / 12.0, 0.15 * 25.0);
}

TEST(DiagnoseBase, AnEffectFoundOnACalibratedBaseExtendsIt) {
  diagnose::Options o;
  o.base_model = calibrated_ground();
  const diagnose::Report r = diagnose::diagnose({differing_ground(1.4, 6)}, o);
  ASSERT_FALSE(r.findings.empty()) << r.message;
  EXPECT_EQ(r.findings.front().cause, "nonlinear_response");
  const auto m = diagnose::extended_ground(r);
  const auto base = calibrated_ground();
  for (std::size_t k = 0; k < 3; ++k) {
    EXPECT_NEAR(m.sensors[k].gain_raw, base.sensors[k].gain_raw, 1e-9) << k;
    EXPECT_NEAR(m.sensors[k].offset_raw, base.sensors[k].offset_raw, 1e-9) << k;
  }
  EXPECT_NEAR(m.effects.exponent, 1.4, 0.02);
}

TEST(DiagnoseBase, ABaseOfAnotherKindIsAnError) {
  diagnose::Options o;
  o.base_model = models::sensors::ProximityModel{};
  const diagnose::Report r = diagnose::diagnose({differing_ground(1.0, 1)}, o);
  EXPECT_FALSE(r.supported);
  EXPECT_NE(r.message.find("proximity"), std::string::npos) << r.message;
}

// ----- the one parameter type -------------------------------------------------------------------

struct Line {
  static constexpr int kParameters = 2;
  template <typename T>
  T operator()(const T* p, double x) const {
    return p[0] + p[1] * x;
  }
};

TEST(ParameterType, AMisspeltNameIsAnErrorNotANaN) {
  const fit::FitResult r = fit::fit_curve(Line{}, {0, 1, 2, 3}, {1.0, 3.1, 4.9, 7.0}, {{"a", 0.0}, {"b", 0.0}});
  ASSERT_TRUE(r.usable);
  EXPECT_NEAR(r.value("b"), 1.98, 1e-9);  // least squares by hand: slope 9.9 / 5
  EXPECT_THROW(r.value("B"), std::out_of_range);
  EXPECT_THROW(r.std_error("c"), std::out_of_range);
  const std::vector<fit::Parameter> p{{"a", 1.0}, {"b", 2.0}};
  EXPECT_EQ(fit::index_of(p, "b"), 1u);
  try {
    fit::index_of(p, "bb");
    FAIL() << "no throw";
  } catch (const std::out_of_range& e) {
    EXPECT_NE(std::string(e.what()).find("a, b"), std::string::npos) << e.what();
  }
}

TEST(ParameterType, FitCurveKeepsBoundsAndHeldParameters) {
  // y = 1 + 2x exactly; the slope bounded above by 1.5 ends on its bound, the intercept then
  // minimises the squares for slope 1.5: mean(y - 1.5 x) = 1 + 0.5 * 1.5 = 1.75.
  const std::vector<double> x{0, 1, 2, 3}, y{1, 3, 5, 7};
  std::vector<fit::Parameter> p{{"a", 0.0}, {"b", 0.0}};
  p[1].upper = 1.5;
  const fit::FitResult bounded = fit::fit_curve(Line{}, x, y, p);
  ASSERT_TRUE(bounded.usable) << bounded.message;
  EXPECT_NEAR(bounded.value("b"), 1.5, 1e-9);
  EXPECT_NEAR(bounded.value("a"), 1.75, 1e-9);
  std::vector<fit::Parameter> held{{"a", 0.5}, {"b", 0.0}};
  held[0].fixed = true;
  const fit::FitResult r = fit::fit_curve(Line{}, x, y, held);
  ASSERT_TRUE(r.usable);
  EXPECT_EQ(r.value("a"), 0.5);
  EXPECT_EQ(r.std_error("a"), 0.0);
  // Slope through (x, y - 0.5) with no intercept: sum x (y - 0.5) / sum x^2 = 31 / 14.
  EXPECT_NEAR(r.value("b"), 31.0 / 14.0, 1e-9);
}

}  // namespace
}  // namespace test_diagnose_steps_cpp
