// Round 8 of the fresh slips (bench/fresh-slips.md, "Round 8"): one test per slip, each expected
// value worked by hand in its comment or taken from the docs, not from the code under test.
#include <gtest/gtest.h>

#include <array>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <cmath>
#include <limits>
#include <string>
#include <vector>
#include <algorithm>

#include <sys/wait.h>
#include <unistd.h>

#include <nlohmann/json.hpp>

#include "cli_harness.hpp"
#include "epuck2/calibrate/charge_map.hpp"
#include "epuck2/calibrate/reading_noise.hpp"
#include "epuck2/coefficients/battery_tables.hpp"
#include "epuck2/coefficients/model_file.hpp"
#include "epuck2/fit/fit_curve.hpp"
#include "epuck2/fit/jet.hpp"
#include "epuck2/fit/readings.hpp"
#include "epuck2/fit/report.hpp"
#include "epuck2/logs/log.hpp"
#include "epuck2/models/kinds.hpp"
#include "epuck2/models/noise.hpp"
#include "epuck2/models/simulate_log.hpp"
#include "../lib/diagnose/src/engine_detail.hpp"
#include "../lib/diagnose/src/kind_common.hpp"

namespace {

namespace r8_fit = epuck2::fit;
namespace r8_s = epuck2::models::sensors;

// d(s / g)/dg = -s / g^2: 3 / g at g = 2 has derivative -3/4.
TEST(RoundEightJet, ReciprocalOfAParameterHasMinusSOverGSquared) {
  const r8_fit::Jet<1> g(2.0, 0);
  const r8_fit::Jet<1> q = 3.0 / g;
  EXPECT_DOUBLE_EQ(q.a, 1.5);
  EXPECT_DOUBLE_EQ(q.v[0], -0.75);
  const r8_fit::Jet<1> h(-0.5, 0);  // 1 / h at -0.5: derivative -1 / 0.25 = -4
  EXPECT_DOUBLE_EQ((1.0 / h).v[0], -4.0);
}

// docs/fitting.md's channel weights: channel c's residuals in channel 0's units, weight sd_0 / sd_c.
// The ToF at 3 mm and the encoders at 0.3 steps: an encoder residual of 0.3 steps (one of its sd)
// counts as 3 mm, weight 10.
TEST(RoundEightChannels, WeightIsChannelZerosSdOverTheChannels) {
  const r8_fit::Channels ch({r8_fit::Channel{-std::numeric_limits<double>::infinity(), std::numeric_limits<double>::infinity(), 3.0},
                             r8_fit::Channel{-std::numeric_limits<double>::infinity(), std::numeric_limits<double>::infinity(), 0.3}});
  EXPECT_DOUBLE_EQ(ch.weight(0), 1.0);
  EXPECT_NEAR(ch.weight(1), 10.0, 1e-12);
  EXPECT_NEAR(std::abs(ch.weighted_error(0.0, 0.3, 1)), 3.0, 1e-12);
}

// y = 2x + 1 at x = 1..5 with the slope bounded above by 1.5: the slope ends on its bound and is
// held there, the intercept is the mean of y - 1.5x = 0.5x + 1, i.e. 2.5; the residuals
// 0.5x - 1.5 are -1, -0.5, 0, 0.5, 1 (RSS 2.5). One free parameter: AIC = n ln(RSS/n) + 2k =
// 5 ln(0.5) + 2, BIC = 5 ln(0.5) + ln 5.
struct R8Line {
  static constexpr int kParameters = 2;
  template <typename T>
  T operator()(const T* p, double x) const {
    return p[0] * x + p[1];
  }
};

TEST(RoundEightFitCurve, AHeldParameterIsNotCountedInAicOrBic) {
  std::vector<double> x{1, 2, 3, 4, 5}, y;
  for (double v : x) y.push_back(2 * v + 1);
  std::vector<r8_fit::Parameter> p(2);
  p[0].name = "slope";
  p[0].value = 1.0;
  p[0].upper = 1.5;
  p[1].name = "intercept";
  p[1].value = 0.0;
  const r8_fit::FitResult r = r8_fit::fit_curve(R8Line{}, x, y, p);
  ASSERT_TRUE(r.usable) << r.message;
  EXPECT_NEAR(r.parameters[0].value, 1.5, 1e-9);
  EXPECT_NEAR(r.parameters[1].value, 2.5, 1e-7);
  EXPECT_NEAR(r.rss, 2.5, 1e-7);
  EXPECT_EQ(r.free_parameters, 1);
  EXPECT_NEAR(r.aic, 5 * std::log(0.5) + 2.0, 1e-6);
  EXPECT_NEAR(r.bic, 5 * std::log(0.5) + std::log(5.0), 1e-6);
}

// Two runs of 4 residuals, +1 then -1 (mean 0, sum of squares 8). Inside the runs: 3 + 3 pairs,
// each product +1, so rho = 6/8 = 0.75 (the pair across the runs' boundary, -1, is no pair),
// n_eff = 8 (1 - 0.75)/(1 + 0.75) = 8/7, factor sqrt(8 / (8/7)) = sqrt 7.
TEST(RoundEightAutocorrelation, NoPairAcrossTwoRuns) {
  const std::vector<double> e{1, 1, 1, 1, -1, -1, -1, -1};
  const std::vector<int> run{0, 0, 0, 0, 1, 1, 1, 1};
  const r8_fit::AutocorrelationCorrection a = r8_fit::autocorrelation_correction(e, run);
  ASSERT_TRUE(a.computed) << a.why_not;
  EXPECT_EQ(a.pairs, 6u);
  EXPECT_EQ(a.series, 2u);
  EXPECT_NEAR(a.rho, 0.75, 1e-12);
  EXPECT_NEAR(a.n_eff, 8.0 / 7.0, 1e-12);
  EXPECT_NEAR(a.factor, std::sqrt(7.0), 1e-12);
}

// A ground file whose noise gives each sensor's sd and, beside them, an sd of -1: a noise sd is
// never negative (docs/coefficient-files.md), the file is refused.
TEST(RoundEightModelFile, ANegativePooledSdBesideThePerSensorOnesIsRefused) {
  r8_s::GroundModel m;
  m.noise_sd_raw = {1.0, 2.0, 3.0};
  nlohmann::json j = epuck2::coefficients::model_to_json(m);
  ASSERT_TRUE(j["noise"]["ground"].contains("per_sensor_sd")) << j.dump();
  j["noise"]["ground"]["sd"] = -1.0;
  EXPECT_ANY_THROW(epuck2::coefficients::ground_model_from_json(j, "r8.json"));
  j["noise"]["ground"]["sd"] = 2.0;
  EXPECT_NO_THROW(epuck2::coefficients::ground_model_from_json(j, "r8.json"));
}

// Per-sensor noise sds 1, 2, 3 counts written and read back: each sensor keeps its own.
TEST(RoundEightModelFile, DifferentSensorNoiseReadsBackPerSensor) {
  r8_s::GroundModel m;
  m.noise_sd_raw = {1.0, 2.0, 3.0};
  const r8_s::GroundModel back = epuck2::coefficients::ground_model_from_json(epuck2::coefficients::model_to_json(m), "r8.json");
  EXPECT_DOUBLE_EQ(back.noise_sd_raw[0], 1.0);
  EXPECT_DOUBLE_EQ(back.noise_sd_raw[1], 2.0);
  EXPECT_DOUBLE_EQ(back.noise_sd_raw[2], 3.0);
  // And the same sd on every sensor stays one sd.
  m.noise_sd_raw = {2.0, 2.0, 2.0};
  const nlohmann::json same = epuck2::coefficients::model_to_json(m);
  EXPECT_FALSE(same["noise"]["ground"].contains("per_sensor_sd")) << same.dump();
  EXPECT_DOUBLE_EQ(same["noise"]["ground"]["sd"].get<double>(), 2.0);
}

// docs/coefficient-files.md: a speed's cubic is written [d, c, b, a] (charge = d + c t + b t^2 + a t^3).
TEST(RoundEightBatteryTables, CubicIsWrittenDThenCThenBThenA) {
  epuck2::models::battery::CubicRow q;
  q.d = 1.0;
  q.c = -2e-4;
  q.b = 3e-9;
  q.a = -4e-14;
  q.end_s = 5000;
  std::array<epuck2::models::battery::Segment, epuck2::models::battery::kSegmentCount> seg{};
  const nlohmann::json e = epuck2::coefficients::battery_speed_to_json(5.0, q, -2e-4, seg, std::nan(""), false);
  ASSERT_EQ(e.at("cubic").size(), 4u);
  EXPECT_DOUBLE_EQ(e["cubic"][0].get<double>(), 1.0);
  EXPECT_DOUBLE_EQ(e["cubic"][1].get<double>(), -2e-4);
  EXPECT_DOUBLE_EQ(e["cubic"][2].get<double>(), 3e-9);
  EXPECT_DOUBLE_EQ(e["cubic"][3].get<double>(), -4e-14);
}

// A pooled gamma of 0.1 m with sensor 2's own 0.12 m (ratio 1.2): moved to 0.05 m, sensor 2 reads
// 0.06 m and every other sensor the pooled 0.05 m.
TEST(RoundEightLightGammas, MovingThePooledGammaKeepsEachSensorsRatio) {
  r8_s::LightModel m;
  m.base.gamma_m = 0.1;
  m.sensor_gamma_m[2] = 0.12;
  m.sensor_gamma_m[5] = 0.08;
  const r8_s::LightModel w = r8_s::with_pooled_gamma(m, 0.05);
  EXPECT_NEAR(r8_s::light_gamma_m(w, 2), 0.06, 1e-15);
  EXPECT_NEAR(r8_s::light_gamma_m(w, 5), 0.04, 1e-15);
  EXPECT_NEAR(r8_s::light_gamma_m(w, 0), 0.05, 1e-15);
}

// A camera log sweeping an LED across the image's bottom and right edges: every row the
// noiseless simulation reports lies on the 160 x 120 image (docs: a position seen is clamped to
// the edge pixels), and some reach the last row and column.
TEST(RoundEightSimulateLike, NoiselessCameraRowsAndColumnsStayOnTheImage) {
  std::string csv = "forward_m,lateral_m,vertical_m,px,py\n";
  for (int k = -3000; k <= 3000; ++k) {
    const double s = k * 1e-4;
    csv += "0.5,0," + std::to_string(s) + ",0,0\n";
    csv += "0.5," + std::to_string(s) + ",0,0,0\n";
  }
  const epuck2::logs::Log log = epuck2::logs::parse_log(csv, "r8_camera.csv", epuck2::logs::Kind::camera);
  const r8_s::CameraModel m;
  r8_s::StandardNormal normal(1);
  const std::vector<double> covariate(log.rows(), 0.0);
  const auto out = r8_s::simulated_readings(m, log, covariate, false, normal);
  double max_px = -1, max_py = -1;
  for (const auto& r : out) {
    if (r.empty()) continue;
    ASSERT_EQ(r.size(), 2u);
    EXPECT_GE(r[0], 0.0);
    EXPECT_LE(r[0], 159.0);
    EXPECT_GE(r[1], 0.0);
    EXPECT_LE(r[1], 119.0);
    max_px = std::max(max_px, r[0]);
    max_py = std::max(max_py, r[1]);
  }
  EXPECT_EQ(max_px, 159.0);
  EXPECT_EQ(max_py, 119.0);
}

// A map with a load term: offsets 0 V at 0 cm/s and 0.1 V at 10 cm/s, linear in between. A robot
// driving backwards at -5 cm/s loads the battery as at 5 cm/s: 0.05 V.
TEST(RoundEightChargeMap, BackwardsIsTheSameLoadAsForwards) {
  epuck2::calibrate::ChargeMap m;
  m.knots_v = {3.4, 4.2};
  m.knot_charge = {0.0, 1.0};
  m.load_speeds_cm_s = {0.0, 10.0};
  m.load_offset_v = {0.0, 0.1};
  m.voltage_min_v = 3.4;
  m.voltage_max_v = 4.2;
  EXPECT_NEAR(epuck2::calibrate::load_offset_v(m, 5.0), 0.05, 1e-12);
  EXPECT_NEAR(epuck2::calibrate::load_offset_v(m, -5.0), 0.05, 1e-12);
  // 3.75 V + 0.05 V = 3.8 V: half-way along the straight map, charge 0.5.
  EXPECT_NEAR(epuck2::calibrate::convert_voltage(m, 3.75, -5.0).charge, 0.5, 1e-12);
}

// Replicates of sensor 0: two groups of 3 (6 readings); of sensor 1: one group of 4. Each sensor's
// count is its own readings.
TEST(RoundEightReadingNoise, PerSensorCountsAreEachSensorsOwnReadings) {
  const std::vector<double> v{10, 11, 12, 20, 21, 22, 30, 31, 32, 33};
  const std::vector<int> group{0, 0, 0, 1, 1, 1, 2, 2, 2, 2};
  const std::vector<bool> rail(v.size(), false);
  const std::vector<int> sensor{0, 0, 0, 0, 0, 0, 1, 1, 1, 1};
  const epuck2::calibrate::ReadingNoise r =
      epuck2::calibrate::noise_from_replicates("proximity", "counts", 1.0, v, group, rail, sensor, 2, 0.0);
  ASSERT_EQ(r.per_sensor_n.size(), 2u);
  EXPECT_EQ(r.per_sensor_n[0], 6u);
  EXPECT_EQ(r.per_sensor_n[1], 4u);
  EXPECT_EQ(r.n, 10u);
  // Sensor 0: deviations -1, 0, 1 twice: SS 4 on 4 degrees of freedom, sd 1. Sensor 1: 30..33,
  // SS 5 on 3, sd sqrt(5/3).
  EXPECT_NEAR(r.per_sensor_sd[0], 1.0, 1e-12);
  EXPECT_NEAR(r.per_sensor_sd[1], std::sqrt(5.0 / 3.0), 1e-12);
}

// The naming step (docs/diagnose.md): sensor gains equal within their errors are one white level,
// level = offset + (level - offset) g with g the gains' mean -- the mean of the sensors seen. A ground
// log of sensors 0 and 1 only, both gains 0.9 at the plug-in's black 0 and white 1023 counts:
// level = 0 + 1023 x 0.9 = 920.7.
TEST(RoundEightIdentify, TwoSensorsEqualGainsGiveTheWhiteLevelOfTheirMean) {
  std::string csv = "# robot: r8\ngrey,sensor,value\n";
  for (int s = 0; s < 2; ++s)
    for (int k = 0; k <= 20; ++k) csv += std::to_string(k / 20.0) + "," + std::to_string(s) + "," + std::to_string(std::round(920.7 * k / 20.0)) + "\n";
  const std::vector<epuck2::logs::Log> logs{epuck2::logs::parse_log(csv, "r8_ground2.csv", epuck2::logs::Kind::ground)};
  const std::unique_ptr<epuck2::diagnose::detail::Problem> p = epuck2::diagnose::detail::make_ground(logs, epuck2::diagnose::Options{});
  ASSERT_TRUE(p);
  std::vector<double> values;
  int gains = 0;
  for (const auto& q : p->params) {
    values.push_back(q.fallback);
    if (q.name == "offset") {
      EXPECT_EQ(q.fallback, 0.0);
    }
    if (q.name == "level") {
      EXPECT_EQ(q.fallback, 1023.0);
    }
  }
  for (std::size_t j = 0; j < p->params.size(); ++j)
    if (p->params[j].name == "gains[0]" || p->params[j].name == "gains[1]") {
      values[j] = 0.9;
      ++gains;
    }
  ASSERT_EQ(gains, 2);
  const auto P = static_cast<Eigen::Index>(values.size());
  const Eigen::MatrixXd cov = 1e-4 * Eigen::MatrixXd::Identity(P, P);
  const auto id = p->identify("sensor_gain", values, cov);
  ASSERT_TRUE(id.has_value());
  EXPECT_EQ(id->cause, "white_level");
  ASSERT_EQ(id->starts.size(), 1u);
  EXPECT_NEAR(id->starts[0].second, 920.7, 1e-9);
}

// docs/diagnose.md's residual structure: a covariate of at most 24 distinct values is binned by
// value. x = 0..23, each twice; residual +1 at even x, -1 at odd x. By value each bin's mean is its
// residual: the binned means explain all the variance (score 1). (Quantile bins would pair x = 2k
// with 2k + 1, whose means are 0: score 0.)
TEST(RoundEightResidualStructure, TwentyFourDistinctValuesAreBinnedByValue) {
  std::vector<double> x, r;
  for (int v = 0; v < 24; ++v)
    for (int k = 0; k < 2; ++k) {
      x.push_back(v);
      r.push_back(v % 2 == 0 ? 1.0 : -1.0);
    }
  const epuck2::diagnose::CovariateScore s = epuck2::diagnose::engine_detail::score_covariate("x", x, r, 0.1);
  EXPECT_NEAR(s.score, 1.0, 1e-12);
  EXPECT_NEAR(s.size, 1.0, 1e-12);  // the binned means' RMS: every mean is +-1
}

// ----- through the CLI ------------------------------------------------------------------------

struct R8Run {
  int status = -1;
  std::string out, err;
};

std::filesystem::path r8_dir() {
  static const std::filesystem::path d = [] {
    std::filesystem::path p = std::filesystem::temp_directory_path() / ("epuck2_r8_" + std::to_string(::getpid()));
    std::filesystem::create_directories(p);
    return p;
  }();
  return d;
}

std::string r8_write(const std::string& name, const std::string& text) {
  const std::filesystem::path p = r8_dir() / name;
  std::ofstream(p, std::ios::binary) << text;
  return p.string();
}

R8Run r8_cli(const std::string& args) {
  const std::string out = (r8_dir() / "stdout.txt").string(), err = (r8_dir() / "stderr.txt").string();
  const std::string cmd = std::string("\"") + EPUCK2_FIT_EXE + "\" " + args + " >\"" + out + "\" 2>\"" + err + "\"";
  const int s = std::system(cmd.c_str());
  R8Run r;
  r.status = WIFEXITED(s) ? WEXITSTATUS(s) : -1;
  r.out = epuck2::testing::slurp(out);
  r.err = epuck2::testing::slurp(err);
  return r;
}

// docs/diagnose.md, "Too few rows": m = max(folds x blocks per fold, folds x 3 x p), 5 folds of 8
// blocks; proximity of one sensor p = 3 + 2 = 5, m = max(40, 75) = 75. A log of 60 rows (more than
// the 40 blocks, fewer than 75) is not judged.
TEST(RoundEightDiagnosis, SixtyProximityRowsOfOneSensorAreTooFew) {
  std::string csv = "# robot: r8\ndistance_m,sensor,value\n";
  for (int i = 0; i < 60; ++i) {
    const double d = 0.002 + 0.0008 * i;  // 2 .. 49.2 mm
    const double v = std::max(0.0, 4000.0 * (1.0 - d / 0.05) * (1.0 - d / 0.05)) + (i % 3);
    csv += std::to_string(d) + ",0," + std::to_string(std::round(v)) + "\n";
  }
  const std::string log = r8_write("prox60.csv", csv);
  const R8Run r = r8_cli("diagnose --json \"" + log + "\"");
  ASSERT_EQ(r.status, 0) << r.err;
  const nlohmann::json j = nlohmann::json::parse(r.out);
  EXPECT_EQ(j.at("minimum_rows").get<int>(), 75) << r.out.substr(0, 2000);
  EXPECT_TRUE(j.at("too_few_rows").get<bool>());
}

// A ground log whose readings are 40 + 1100 grey, clamped to the 10-bit register's 1023 (docs/logs.md):
// grey 0, 0.01, ..., 0.99 on each of the 3 sensors; 40 + 1100 g >= 1023 for g >= 0.8937, i.e.
// g = 0.90 .. 0.99: 10 rows a sensor, 30 in all, on the high rail and none on the low one.
TEST(RoundEightDiagnosis, ReadingsOnTheHighRailAreCountedThere) {
  std::string csv = "# robot: r8\ngrey,sensor,value\n";
  for (int s = 0; s < 3; ++s)
    for (int k = 0; k < 100; ++k) {
      const double g = k / 100.0;
      const double v = std::min(1023.0, std::round(40 + 1100 * g + ((k * 7 + s) % 5) - 2));
      csv += std::to_string(g) + "," + std::to_string(s) + "," + std::to_string(v) + "\n";
    }
  const std::string log = r8_write("ground_rail.csv", csv);
  const R8Run r = r8_cli("diagnose --json \"" + log + "\"");
  ASSERT_EQ(r.status, 0) << r.err;
  const nlohmann::json j = nlohmann::json::parse(r.out);
  ASSERT_TRUE(j.contains("censored_per_rail")) << r.out.substr(0, 2000);
  EXPECT_EQ(j["censored_per_rail"]["at_or_above"].get<int>(), 30);
  EXPECT_EQ(j["censored_per_rail"]["at_or_below"].get<int>(), 0);
}

// docs/fitting.md's unit check: a proximity log whose distances were written in centimetres
// (1 .. 20 cm as 1 .. 20) stops with "centimetres?", not "millimetres?".
TEST(RoundEightUnitHints, ProximityDistancesInCentimetresAreNamedSo) {
  std::string csv = "# robot: r8\ndistance_m,sensor,value\n";
  for (int cm = 1; cm <= 20; ++cm)
    for (int s = 0; s < 8; ++s) csv += std::to_string(cm) + "," + std::to_string(s) + "," + std::to_string(cm < 5 ? 3000 - 600 * cm : 0) + "\n";
  const std::string log = r8_write("prox_cm.csv", csv);
  const R8Run r = r8_cli("proximity \"" + log + "\"");
  EXPECT_EQ(r.status, 2);
  EXPECT_NE(r.err.find("distance_m reaches 20: centimetres?"), std::string::npos) << r.err;
}

// docs/cli.md: the simulated log keeps the log's metadata but not the recording's seed; with
// --noise it carries the simulation's own (`# seed: N`), without it none.
TEST(RoundEightSimulateLike, WithNoiseTheSimulationsSeedIsWrittenWithoutItNone) {
  std::string csv = "# robot: r8\n# seed: 3\ngrey,sensor,value\n";
  for (int k = 0; k <= 10; ++k) csv += std::to_string(k / 10.0) + ",1," + std::to_string(100 * k) + "\n";
  const std::string log = r8_write("ground_seed.csv", csv);
  const R8Run noisy = r8_cli("simulate ground --like \"" + log + "\" --noise --seed 7");
  ASSERT_EQ(noisy.status, 0) << noisy.err;
  EXPECT_NE(noisy.out.find("# seed: 7\n"), std::string::npos) << noisy.out;
  EXPECT_EQ(noisy.out.find("# seed: 3"), std::string::npos) << noisy.out;
  EXPECT_NE(noisy.out.find("# robot: r8\n"), std::string::npos) << noisy.out;
  const R8Run plain = r8_cli("simulate ground --like \"" + log + "\"");
  ASSERT_EQ(plain.status, 0) << plain.err;
  EXPECT_EQ(plain.out.find("# seed:"), std::string::npos) << plain.out;
}

// docs/logs.md, light: distance_m in 0.001..1000 m ("the model divides by it: 0 is refused").
TEST(RoundEightLogReader, ALightDistanceOfZeroOrDenormalIsRefusedWhereItIs) {
  for (const char* d : {"0", "1e-320", "0.0009"}) {
    const std::string csv = std::string("# robot: r8\ndistance_m,intensity,sensor,value\n0.1,1,0,1792\n") + d + ",1,0,1792\n";
    try {
      (void)epuck2::logs::parse_log(csv, "r8_light.csv", epuck2::logs::Kind::light);
      ADD_FAILURE() << "distance_m " << d << " was accepted";
    } catch (const epuck2::logs::InputError& e) {
      EXPECT_NE(std::string(e.what()).find("r8_light.csv:4:1"), std::string::npos) << e.what();
    }
  }
  EXPECT_NO_THROW((void)epuck2::logs::parse_log("# robot: r8\ndistance_m,intensity,sensor,value\n0.001,1,0,1792\n", "r8_light.csv",
                                                epuck2::logs::Kind::light));
}

// docs/coefficient-files.md, points[]: max_censoring and mean_censoring are each their own --
// `at_or_above` on the 4095 rail, `at_or_below` on 0 or nothing detected, else `none`. In the
// shipped proximity logs the readings at 45 mm include zeros and no 4095 while their maximum is
// above 0 (counted here from the CSVs): the mean is at_or_below, the maximum none.
TEST(RoundEightProximityReport, APointsMeanAndMaximumCarryTheirOwnRail) {
  const std::string dir = std::string(EPUCK2_SOURCE_DIR) + "/data/raw/proximity/";
  int zeros = 0, top = 0;
  double highest = 0;
  for (const char* name : {"proximity_virtual-epuck2-1.csv", "proximity_virtual-epuck2-2.csv"}) {
    std::istringstream in(epuck2::testing::slurp(dir + name));
    std::string line;
    while (std::getline(in, line)) {
      if (line.empty() || line[0] == '#' || line[0] < '0' || line[0] > '9') continue;
      double t = 0, d = 0, sensor = 0, value = 0;  // time_s,distance_m,sensor,value
      if (std::sscanf(line.c_str(), "%lf,%lf,%lf,%lf", &t, &d, &sensor, &value) != 4 || std::abs(d - 0.045) > 1e-9) continue;
      zeros += value == 0;
      top += value >= 4095;
      highest = std::max(highest, value);
    }
  }
  ASSERT_GT(zeros, 0);
  ASSERT_EQ(top, 0);
  ASSERT_GT(highest, 0.01 * 4095);  // detected: the maximum is no rail
  const std::string out = (r8_dir() / "prox.json").string();
  const R8Run r = r8_cli("proximity \"" + dir + "proximity_virtual-epuck2-1.csv\" \"" + dir + "proximity_virtual-epuck2-2.csv\" -o \"" + out + "\"");
  ASSERT_EQ(r.status, 0) << r.err;
  const nlohmann::json j = nlohmann::json::parse(epuck2::testing::slurp(out));
  bool seen = false;
  for (const auto& p : j.at("points"))
    if (std::abs(p.at("distance_m").get<double>() - 0.045) < 1e-9) {
      seen = true;
      EXPECT_EQ(p.at("mean_censoring"), "at_or_below") << p.dump();
      EXPECT_EQ(p.at("max_censoring"), "none") << p.dump();
    }
  EXPECT_TRUE(seen);
}

}  // namespace
