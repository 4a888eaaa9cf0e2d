// Tests written for the third fresh set of planted slips (bench/fresh-slips.md, "Round 3"): one
// or more for each slip the suite let through. Each expected value is worked by hand (the
// arithmetic is in the comments), is a documented boundary or rule, or is computed in the test
// apart from the code under test -- never a number printed by that code.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <fstream>
#include <map>
#include <sstream>
#include <string>
#include <vector>

#include "epuck2/calibrate/charge_map.hpp"
#include "epuck2/calibrate/plausibility.hpp"
#include "epuck2/calibrate/reading_noise.hpp"
#include "epuck2/coefficients/codegen.hpp"
#include "epuck2/coefficients/model_file.hpp"
#include "epuck2/diagnose/diagnose.hpp"
#include "epuck2/diagnose/reading_noise.hpp"
#include "epuck2/fit/report.hpp"
#include "epuck2/fit/robust.hpp"
#include "epuck2/logs/log.hpp"
#include "cli_harness.hpp"
#include "epuck2/models/noise.hpp"

// This file's `using namespace` stays in its own named namespace, so it opens nothing to the
// files compiled after it in the same unity unit (tests/CMakeLists.txt).
namespace test_round_three_slips_cpp {
namespace {

using namespace epuck2;
using nlohmann::json;

// ----- the voltage->charge map -----

json map_file(const std::vector<double>& knots_v, const std::vector<double>& knot_charge) {
  return {{"kind", "charge_map"},
          {"charge_map", {{"form", calibrate::kChargeMapForm}, {"knots_v", knots_v}, {"knot_charge", knot_charge}}}};
}

TEST(RoundThreeChargeMap, AFlatStretchIsAMapAndConvertsByHand) {
  // docs/coefficient-files.md: knot_charge non-decreasing (the fit holds its increments >= 0, so
  // a flat stretch is a fit's possible answer). Knots 3.0, 3.5, 3.7, 4.0 V with charges 0, 0.5,
  // 0.5, 1: flat between 3.5 and 3.7 V.
  const calibrate::ChargeMap m = calibrate::charge_map_from_json(map_file({3.0, 3.5, 3.7, 4.0}, {0.0, 0.5, 0.5, 1.0}), "flat.json");
  // 3.6 V is on the flat stretch: 0.5. 3.85 V is halfway from 3.7 to 4.0: 0.5 + 0.5 x 0.5 = 0.75.
  // 3.25 V halfway from 3.0 to 3.5: 0.25.
  EXPECT_NEAR(calibrate::convert_voltage(m, 3.6, 0.0).charge, 0.5, 1e-12);
  EXPECT_NEAR(calibrate::convert_voltage(m, 3.85, 0.0).charge, 0.75, 1e-12);
  EXPECT_NEAR(calibrate::convert_voltage(m, 3.25, 0.0).charge, 0.25, 1e-12);
  // A decreasing one is refused, at the entry that decreases (knot_charge/2).
  try {
    calibrate::charge_map_from_json(map_file({3.0, 3.5, 3.7, 4.0}, {0.0, 0.5, 0.4, 1.0}), "down.json");
    FAIL() << "a decreasing knot_charge was read";
  } catch (const logs::InputError& e) {
    EXPECT_NE(std::string(e.what()).find("knot_charge/2"), std::string::npos) << e.what();
  }
}

/// Rows on charge = voltage - 3 at the voltages 3.0, 3.1, ..., 4.0 (11 values, 3 rows each), one speed.
std::vector<calibrate::ChargeSample> line_rows() {
  std::vector<calibrate::ChargeSample> rows;
  for (int r = 0; r < 3; ++r)
    for (int i = 0; i <= 10; ++i) rows.push_back({3.0 + 0.1 * i, 0.0, 0.1 * i});
  return rows;
}

TEST(RoundThreeChargeMap, KnotsSitAtQuantilesWithTheExtremesFirstAndLast) {
  // docs/coefficient-files.md: "the knots sit at quantiles of the logged voltages (first and last
  // at the extremes)". 33 sorted voltages (each of 3.0..4.0 three times): with 2 knots, the
  // lowest and the highest, 3.0 and 4.0; with 3, also the median (sorted index 16 -> 3.5).
  calibrate::ChargeMapOptions two;
  two.knot_counts = {2};
  const calibrate::ChargeMapFit a = calibrate::fit_charge_map(line_rows(), {"line"}, two);
  ASSERT_TRUE(a.usable) << a.message;
  ASSERT_EQ(a.map.knots_v.size(), 2u);
  EXPECT_NEAR(a.map.knots_v[0], 3.0, 1e-12);
  EXPECT_NEAR(a.map.knots_v[1], 4.0, 1e-12);
  // The line itself: charge 0 and 1 at the knots.
  EXPECT_NEAR(a.map.knot_charge[0], 0.0, 1e-6);
  EXPECT_NEAR(a.map.knot_charge[1], 1.0, 1e-6);
  calibrate::ChargeMapOptions three;
  three.knot_counts = {3};
  const calibrate::ChargeMapFit b = calibrate::fit_charge_map(line_rows(), {"line"}, three);
  ASSERT_TRUE(b.usable) << b.message;
  ASSERT_EQ(b.map.knots_v.size(), 3u);
  EXPECT_NEAR(b.map.knots_v[0], 3.0, 1e-12);
  EXPECT_NEAR(b.map.knots_v[1], 3.5, 1e-12);
  EXPECT_NEAR(b.map.knots_v[2], 4.0, 1e-12);
}

// ----- the reading-noise estimate of an extended model: each sensor its own replicates -----

TEST(RoundThreeReadingNoise, EachSensorKeepsItsOwnReplicateSdSensorZeroIncluded) {
  // docs: the replicates' sd of the sensor (its own where it has readings), the pooled one at
  // most the residual sd. Sensors 0, 1, 2 scatter 1, 3 and 2 counts (pooled 2); residual sd 10, readings not whole.
  calibrate::ReadingNoise n;
  n.channel = "ground";
  n.unit = "counts";
  n.from = "replicates";
  n.sd = 2.0;
  n.per_sensor_sd = {1.0, 3.0, 2.0};
  n.per_sensor_n = {40, 40, 40};
  const std::map<std::string, calibrate::ReadingNoise> rep{{"ground", n}};
  EXPECT_DOUBLE_EQ(diagnose::model_noise_sd(rep, "ground", 10.0, 0, false), 1.0);
  EXPECT_DOUBLE_EQ(diagnose::model_noise_sd(rep, "ground", 10.0, 1, false), 3.0);
  EXPECT_DOUBLE_EQ(diagnose::model_noise_sd(rep, "ground", 10.0, 2, false), 2.0);
  // No sensor named: the pooled 2. The cap is the pooled one (session 24, probe 6): a residual sd
  // of 2.5, above the pooled replicates' 2, cuts nothing (sensor 1's own 3 is its noise, not
  // misfit); one of 1.5 cuts the pooled sd to 1.5 and every sensor's by the same 0.75.
  EXPECT_DOUBLE_EQ(diagnose::model_noise_sd(rep, "ground", 10.0, -1, false), 2.0);
  EXPECT_DOUBLE_EQ(diagnose::model_noise_sd(rep, "ground", 2.5, 1, false), 3.0);
  EXPECT_DOUBLE_EQ(diagnose::model_noise_sd(rep, "ground", 1.5, -1, false), 1.5);
  EXPECT_DOUBLE_EQ(diagnose::model_noise_sd(rep, "ground", 1.5, 1, false), 2.25);
  EXPECT_DOUBLE_EQ(diagnose::model_noise_sd(rep, "ground", 1.5, 0, false), 0.75);
  // Whole readings: sensor 0's 1 count less the rounding's 1/12: sqrt(11/12).
  EXPECT_NEAR(diagnose::model_noise_sd(rep, "ground", 10.0, 0, true), std::sqrt(11.0 / 12.0), 1e-12);
}

// ----- codegen: every sensor's noise, each channel its own -----

TEST(RoundThreeCodegen, EverySensorsNoiseIsWrittenLastOneIncluded) {
  models::sensors::ProximityModel p;
  p.noise_sd_raw = {1.5, 2.5, 3.5, 4.5, 5.5, 6.5, 7.5, 8.5};
  const std::string cpp = coefficients::model_to_cpp(p, "a hand-made model");
  EXPECT_NE(cpp.find("m.noise_sd_raw = {1.5, 2.5, 3.5, 4.5, 5.5, 6.5, 7.5, 8.5};"), std::string::npos) << cpp;
  models::sensors::GroundModel g;
  g.noise_sd_raw = {0.25, 0.5, 0.75};
  const std::string gcpp = coefficients::model_to_cpp(g, "a hand-made model");
  EXPECT_NE(gcpp.find("m.noise_sd_raw = {0.25, 0.5, 0.75};"), std::string::npos) << gcpp;
}

TEST(RoundThreeCodegen, DriveToFAndEncoderNoiseKeepTheirOwnValues) {
  models::sensors::DriveModel m;
  m.tof_noise_sd_mm = 3.25;
  m.encoder_noise_sd_steps = 0.75;
  const std::string cpp = coefficients::model_to_cpp(m, "a hand-made model");
  EXPECT_NE(cpp.find("m.tof_noise_sd_mm = 3.25;"), std::string::npos) << cpp;
  EXPECT_NE(cpp.find("m.encoder_noise_sd_steps = 0.75;"), std::string::npos) << cpp;
}

// ----- the model-file validator -----

TEST(RoundThreeModelFile, DriveEncoderNoiseIsReadFromItsOwnChannel) {
  const json drive = {{"kind", "drive"},
                      {"parameters", {{"steps_per_m", 7700.0}}},
                      {"noise", {{"tof", {{"sd", 3.0}, {"unit", "mm"}}}, {"encoder", {{"sd", 0.5}, {"unit", "steps"}}}}}};
  const models::sensors::DriveModel m = coefficients::drive_model_from_json(drive, "drive.json");
  EXPECT_DOUBLE_EQ(m.tof_noise_sd_mm, 3.0);
  EXPECT_DOUBLE_EQ(m.encoder_noise_sd_steps, 0.5);
}

TEST(RoundThreeModelFile, ANoiseSdAtTheFullScaleIsRefusedJustBelowIsRead) {
  // docs/coefficient-files.md: a reading's noise sd lies in [0, full scale): 4095 counts for the
  // proximity sensors, 2000 mm for the ToF.
  json prox = {{"kind", "proximity"},
               {"parameters", {{"a", 1.0}, {"b", 0.0}, {"c", 0.0}, {"range_m", 0.1}}},
               {"noise", {{"proximity", {{"sd", 4095.0}, {"unit", "counts"}}}}}};
  EXPECT_THROW(coefficients::proximity_model_from_json(prox, "p.json"), logs::InputError);
  prox["noise"]["proximity"]["sd"] = 4094.5;
  EXPECT_DOUBLE_EQ(coefficients::proximity_model_from_json(prox, "p.json").noise_sd_raw[7], 4094.5);
  json drive = {{"kind", "drive"},
                {"parameters", {{"steps_per_m", 7700.0}}},
                {"noise", {{"tof", {{"sd", 2000.0}, {"unit", "mm"}}}, {"encoder", {{"sd", 0.5}, {"unit", "steps"}}}}}};
  EXPECT_THROW(coefficients::drive_model_from_json(drive, "d.json"), logs::InputError);
  drive["noise"]["tof"]["sd"] = 1999.0;
  EXPECT_DOUBLE_EQ(coefficients::drive_model_from_json(drive, "d.json").tof_noise_sd_mm, 1999.0);
}

// ----- the jackknife: 3 folds are enough -----

TEST(RoundThreeJackknife, ThreeFoldsGiveAJackknifeError) {
  // diagnose.hpp: the jackknife over the held-out folds, NaN with fewer than 3 folds: with exactly
  // 3 it is a number. Proximity logs on the plug-in's curve with white noise of 20 counts (seeded).
  models::sensors::StandardNormal normal(7);
  std::ostringstream csv;
  csv << "distance_m,sensor,value\n";
  for (int r = 0; r < 6; ++r)
    for (int j = 1; j <= 8; ++j)
      for (int k = 0; k < 8; ++k) {
        const double d = 0.005 * j;
        csv << d << "," << k << "," << 4095 * (197.8633 * d * d - 30.47182 * d + 1.011635) + 20 * normal() << "\n";
      }
  diagnose::Options o;
  o.effects = {"ambient_offset"};
  o.folds = 3;
  const diagnose::Report rep = diagnose::diagnose({logs::parse_log(csv.str(), "proximity.csv", logs::Kind::proximity)}, o);
  ASSERT_TRUE(rep.supported) << rep.message;
  EXPECT_EQ(rep.jackknife_folds, 3u);
  int finite = 0;
  for (const diagnose::NamedValue& v : rep.recalibrated)
    if (std::isfinite(v.std_error_jackknife) && v.std_error_jackknife > 0) ++finite;
  EXPECT_GE(finite, 3) << "the recalibrated a, b, c each have a jackknife error with 3 folds";
}

// ----- simulate --like, through the real binary -----

const epuck2::testing::Scratch kRoundThreeScratch{"round_three_slips"};

TEST(RoundThreeSimulateLike, LightReadingByHandIntensityAndDistanceApart) {
  // docs/coefficient-files.md (light): the paper's Eq. 2, reading / 4095 = 1 - (gamma I / d)^2
  // within range_m. gamma 0.1 m, range 1 m: I = 0.5 at d = 0.2 m: ratio 0.25, 4095 x (1 - 1/16) =
  // 3839.0625; I = 0.2 at d = 0.5 m: ratio 0.04, 4095 x (1 - 0.0016) = 4088.448.
  const std::string model = kRoundThreeScratch.write("light.json", R"({"kind": "light", "parameters": {"gamma": 0.1, "range_m": 1.0}})");
  const std::string log = kRoundThreeScratch.write("light.csv", "distance_m,intensity,sensor,value\n0.2,0.5,0,0\n0.5,0.2,3,0\n");
  const logs::Log sim = kRoundThreeScratch.simulate_like("light", log, model);
  ASSERT_EQ(sim.rows(), 2u);
  EXPECT_NEAR(sim.col("value")[0], 3839.0625, 1e-9);
  EXPECT_NEAR(sim.col("value")[1], 4088.448, 1e-9);
}

TEST(RoundThreeSimulateLike, BatteryRunStartsFromTheFirstReading) {
  // docs/cli.md (simulate battery --like): from a full charge when the first reading is >= 0.9,
  // else from the first reading. A log from 0.6 down to 0.3: the simulated charge at the first
  // row (no time elapsed) is 0.6, and a discharge never rises.
  const std::string log = kRoundThreeScratch.write("battery.csv",
                                     "time_s,speed_cm_s,charge\n0,0,0.6\n600,0,0.5\n1200,0,0.4\n1800,0,0.3\n");
  const logs::Log sim = kRoundThreeScratch.simulate_like("battery", log, "");
  ASSERT_EQ(sim.rows(), 4u);
  EXPECT_NEAR(sim.col("charge")[0], 0.6, 1e-9);
  for (std::size_t i = 1; i < sim.rows(); ++i) EXPECT_LE(sim.col("charge")[i], sim.col("charge")[i - 1]);
  EXPECT_LT(sim.col("charge")[3], 0.6);
}

// ----- the cluster-robust errors: every run counts, the first (run 0) included -----

TEST(RoundThreeClusterRobust, FiveRunsNumberedFromZeroByHand) {
  // One parameter, a constant (Jacobian a column of ones), 10 residuals in 5 runs numbered 0..4
  // (as the drive fit numbers its runs): run sums 3 + 1 = 4, -1 - 1 = -2, 2 + 0 = 2, -2 - 1 = -3,
  // 0 - 1 = -1. Sandwich (J'J)^-1 (sum S_g^2) (J'J)^-1 G/(G - 1) = (16 + 4 + 4 + 9 + 1)/100 x 5/4
  // = 0.425: the error sqrt(0.425) = 0.65192, above the covariance's 0.1.
  const std::vector<double> r = {3, 1, -1, -1, 2, 0, -2, -1, 0, -1};
  const std::vector<int> run = {0, 0, 1, 1, 2, 2, 3, 3, 4, 4};
  const Eigen::MatrixXd J = Eigen::MatrixXd::Ones(10, 1);
  fit::FitResult f;
  f.usable = true;
  f.parameters = {{"mu", 0.0, 0.1}};
  ASSERT_EQ(fit::kMinClusters, 5u);  // exactly at the limit: the sandwich is used
  fit::AutocorrelationCorrection a;
  fit::apply_cluster_robust(a, f, J, r, run);
  EXPECT_TRUE(a.cluster_robust) << a.cluster_why_not;
  EXPECT_EQ(a.series, 5u);
  ASSERT_EQ(a.std_errors.size(), 1u);
  EXPECT_NEAR(a.std_errors[0], std::sqrt(0.425), 1e-12);
  // The same runs numbered 1..5: the same error.
  std::vector<int> shifted = run;
  for (int& k : shifted) ++k;
  fit::AutocorrelationCorrection b;
  fit::apply_cluster_robust(b, f, J, r, shifted);
  ASSERT_EQ(b.std_errors.size(), 1u);
  EXPECT_NEAR(b.std_errors[0], std::sqrt(0.425), 1e-12);
}

// ----- the Tobit passes: a floor reading far below the curve is as wild as an exact one -----

struct R3Constant {
  std::size_t n;
  template <typename T>
  bool operator()(const T* p, T* out) const {
    for (std::size_t i = 0; i < n; ++i) out[i] = p[0];
    return true;
  }
};

TEST(RoundThreeTobit, AFloorReadingFarBelowTheCurveIsLeftOut) {
  // 20 exact readings 99, 101, 99, 101, ... (mean 100, sd 1) and one reading at the floor rail,
  // 0 ("at or below 0"): the curve, 100, is 100 sd above that rail -- the rail reading says the
  // truth is at most 0, which no reading near 100 allows: a wild reading (fit::fit_robust: "a rail
  // reading the curve puts far on the other side of the rail is just as wild"), left out. The
  // constant is then the exact readings' mean, 100.
  std::vector<fit::Observation> obs;
  for (int i = 0; i < 20; ++i) obs.push_back({i % 2 ? 101.0 : 99.0, fit::Censoring::none, "", -1});
  obs.push_back({0.0, fit::Censoring::at_or_below, "", -1});
  fit::RobustOptions o;
  o.robust = true;
  const fit::RobustFit f = fit::fit_robust(R3Constant{obs.size()}, obs, {{"mu", 50.0}}, o);
  ASSERT_TRUE(f.usable) << f.message;
  EXPECT_NEAR(f.value("mu"), 100.0, 1e-6);
  EXPECT_NE(std::find(f.outliers.begin(), f.outliers.end(), 20u), f.outliers.end()) << "the floor reading was kept";
}

// ----- the column-unit hints: the largest distance is judged -----

TEST(RoundThreeUnitHints, TheLargestDistanceIsTheOneJudged) {
  // The plug-in's proximity sensor sees to 0.05 m; a distance beyond 10 x that, 0.5 m, is not in
  // metres. Rows 0.01, 0.03 and 5 (line 4): the 5 is named, 5 / (2 x 0.05) = 50 times too large
  // (a largest distance of about twice the range assumed): centimetres.
  const logs::Log log = logs::parse_log("distance_m,sensor,value\n0.01,0,3000\n0.03,0,1000\n5,0,100\n", "cm.csv", logs::Kind::proximity);
  try {
    calibrate::check_plausible_units({log});
    FAIL() << "accepted a distance of 5 m";
  } catch (const logs::InputError& e) {
    EXPECT_EQ(e.line(), 4) << e.what();
    EXPECT_NE(std::string(e.what()).find("centimetres?"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace test_round_three_slips_cpp
