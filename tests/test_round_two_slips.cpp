// Tests written for the second fresh set of planted slips (bench/fresh-slips.md, "Round 2"):
// each expected value is worked by hand (the arithmetic is in the comments) or is a documented
// boundary, never a number printed by the code under test.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdlib>
#include <fstream>
#include <iostream>
#include <map>
#include <sstream>
#include <string>
#include <vector>

#include "epuck2/calibrate/charge_map.hpp"
#include "epuck2/calibrate/plausibility.hpp"
#include "epuck2/calibrate/reading_noise.hpp"
#include "epuck2/calibrate/sensors.hpp"
#include "epuck2/coefficients/codegen.hpp"
#include "epuck2/coefficients/model_file.hpp"
#include "epuck2/diagnose/diagnose.hpp"
#include "epuck2/diagnose/reading_noise.hpp"
#include "epuck2/fit/report.hpp"
#include "epuck2/fit/robust.hpp"
#include "epuck2/logs/log.hpp"
#include "cli_harness.hpp"
#include "epuck2/models/effects.hpp"
#include "epuck2/models/noise.hpp"
// The diagnosis's problems (make_problem, Problem::identify) are the library's own, not in its
// public headers.
#include "../lib/diagnose/src/problem.hpp"

// This file's `using namespace` stays in its own named namespace, so it opens nothing to the
// files compiled after it in the same unity unit (tests/CMakeLists.txt).
namespace test_round_two_slips_cpp {
namespace {

using namespace epuck2;
using nlohmann::json;

// ----- the voltage->charge map: the load offset beyond the fastest logged speed -----

// f through (3 V, 0) and (4 V, 1): f(x) = x - 3. Offsets 0, 0.1, 0.2 V at 0, 5, 10 cm/s.
calibrate::ChargeMap hand_map() {
  calibrate::ChargeMap m;
  m.knots_v = {3.0, 4.0};
  m.knot_charge = {0.0, 1.0};
  m.load_speeds_cm_s = {0.0, 5.0, 10.0};
  m.load_offset_v = {0.0, 0.1, 0.2};
  m.voltage_min_v = 3.0;
  m.voltage_max_v = 4.0;
  return m;
}

TEST(RoundTwoChargeMap, ASpeedAboveTheFastestTakesTheFastestOffset) {
  const calibrate::ChargeMap m = hand_map();
  // Held at the ends (docs/coefficient-files.md: linear between the load speeds): 15 cm/s takes
  // 10 cm/s's 0.2 V, 0 cm/s's 0 V -- not the slowest's.
  EXPECT_DOUBLE_EQ(calibrate::load_offset_v(m, 15.0), 0.2);
  EXPECT_DOUBLE_EQ(calibrate::load_offset_v(m, -15.0), 0.2);
  EXPECT_DOUBLE_EQ(calibrate::load_offset_v(m, 7.5), 0.15);  // halfway between 0.1 and 0.2
  // 3.5 V + 0.2 V = 3.7 V -> charge 0.7.
  EXPECT_NEAR(calibrate::convert_voltage(m, 3.5, 15.0).charge, 0.7, 1e-12);
  EXPECT_EQ(calibrate::convert_voltage(m, 3.5, 15.0).side, 0);
}

// ----- the reading-noise estimate: the screen of small groups has the floor -----

TEST(RoundTwoReadingNoise, SmallGroupScreenNeverCutsInsideTheFloor) {
  // 20 groups of 3 (fewer than kSmallGroup): 19 read 100, 100, 100; one 100, 100, 101.
  // Pooled sd: that group's squares 2 (1/3)^2 + (2/3)^2 = 2/3 over 2 x 20 = 40 degrees of
  // freedom: sqrt(1/60) = 0.1291 counts. The screen cuts at 4 x max(0.1291, floor 1) = 4
  // counts: the 101 (1 count from its median) stays. Without the floor it would cut at 0.52.
  std::vector<double> v;
  std::vector<int> g;
  for (int k = 0; k < 20; ++k)
    for (int i = 0; i < 3; ++i) {
      v.push_back(k == 7 && i == 2 ? 101.0 : 100.0);
      g.push_back(k);
    }
  const std::vector<bool> rail(v.size(), false);
  const calibrate::PooledSd p = calibrate::pooled_replicate_sd(v, g, rail, 1.0, calibrate::kNoiseRejectSd);
  EXPECT_EQ(p.outliers, 0u);
  EXPECT_EQ(p.n, 60u);
  EXPECT_NEAR(p.sd, std::sqrt(1.0 / 60.0), 1e-12);
}

TEST(RoundTwoReadingNoise, WholeReadingsLoseTheRoundingsTwelfth) {
  // No replicates: the residual sd 0.5, less the rounding's 1/12 for whole readings:
  // sqrt(0.25 - 1/12) = sqrt(1/6) = 0.408248.
  const std::map<std::string, calibrate::ReadingNoise> none;
  EXPECT_NEAR(diagnose::model_noise_sd(none, "proximity", 0.5, 0, true), std::sqrt(1.0 / 6.0), 1e-12);
  EXPECT_DOUBLE_EQ(diagnose::model_noise_sd(none, "proximity", 0.5, 0, false), 0.5);
  // Below the rounding's own sd (sqrt(1/12) = 0.2887): nothing left.
  EXPECT_DOUBLE_EQ(diagnose::model_noise_sd(none, "proximity", 0.25, 0, true), 0.0);
}

// ----- codegen: the camera's image centre, row and column apart -----

TEST(RoundTwoCodegen, CameraCentreRowAndColumnKeepTheirOwnValues) {
  models::sensors::CameraModel m;
  m.base.cx_px = 81.5;
  m.base.cy_px = 58.25;
  const std::string cpp = coefficients::model_to_cpp(m, "a hand-made model");
  EXPECT_NE(cpp.find("m.base.cx_px = 81.5;"), std::string::npos) << cpp;
  EXPECT_NE(cpp.find("m.base.cy_px = 58.25;"), std::string::npos) << cpp;
}

// ----- the corrected standard errors: AR(1) -----

TEST(RoundTwoAutocorrelation, FactorIsTheSquareRootOfNOverNeff) {
  // Residuals 3, 1, 2, -1, -2, -3 (mean 0), one run: sum of squares 28, lag-1 products
  // 3 + 2 - 2 + 2 + 6 = 11, rho = 11/28; n_eff = 6 (17/28)/(39/28) = 6 x 17/39 = 2.6154;
  // factor sqrt(6 / 2.6154) = sqrt(39/17) = 1.51463.
  const fit::AutocorrelationCorrection a = fit::autocorrelation_correction({3, 1, 2, -1, -2, -3}, {0, 0, 0, 0, 0, 0});
  ASSERT_TRUE(a.computed) << a.why_not;
  EXPECT_NEAR(a.rho, 11.0 / 28.0, 1e-12);
  EXPECT_NEAR(a.n_eff, 6.0 * 17.0 / 39.0, 1e-12);
  EXPECT_NEAR(a.factor, std::sqrt(39.0 / 17.0), 1e-12);
  fit::FitResult f;
  f.usable = true;
  f.parameters = {{"x", 1.0, 0.2}};
  fit::AutocorrelationCorrection b = a;
  fit::apply_ar1(b, f);
  ASSERT_EQ(b.std_errors.size(), 1u);
  EXPECT_NEAR(b.std_errors[0], 0.2 * std::sqrt(39.0 / 17.0), 1e-12);
}

// ----- the robots' spread: the sample sd beside Cochran's Q -----

TEST(RoundTwoRobotSpread, SpreadIsTheSampleSdAndQByHand) {
  // Values 1, 2, 4 with errors 0.5, 0.5, 1: mean 7/3, squares 16/9 + 1/9 + 25/9 = 42/9, sample
  // sd sqrt(21/9) = 1.52753. Weights 4, 4, 1: weighted mean 16/9; Q = 4 (7/9)^2 + 4 (2/9)^2 +
  // (20/9)^2 = (196 + 16 + 400)/81 = 612/81 = 7.5556 on 2 dof, p = exp(-Q/2) = 0.02287.
  std::vector<fit::FitResult> r(3);
  const double x[3] = {1, 2, 4}, se[3] = {0.5, 0.5, 1};
  std::vector<const fit::FitResult*> robots;
  for (int i = 0; i < 3; ++i) {
    r[i].usable = true;
    r[i].parameters = {{"k", x[i], se[i]}};
    robots.push_back(&r[i]);
  }
  const auto s = fit::robot_spread(robots);
  ASSERT_EQ(s.size(), 1u);
  EXPECT_NEAR(s[0].spread_sd, std::sqrt(21.0 / 9.0), 1e-12);
  EXPECT_NEAR(s[0].q, 612.0 / 81.0, 1e-12);
  EXPECT_EQ(s[0].dof, 2u);
  EXPECT_NEAR(s[0].p_value, std::exp(-306.0 / 81.0), 1e-9);
  EXPECT_FALSE(s[0].exceeds);  // 0.023 is not below 0.01
}

// ----- the Tobit terms: an exact reading's log-likelihood has its -ln sigma -----

struct R2Constant {
  std::size_t n;
  template <typename T>
  bool operator()(const T* p, T* out) const {
    for (std::size_t i = 0; i < n; ++i) out[i] = p[0];
    return true;
  }
};

TEST(RoundTwoTobit, LogLikelihoodOfExactReadingsByHand) {
  // Readings 1..5, a constant, sigma known = 2: mu = 3, squares 10;
  // ln L = -5 ln 2 - 5 ln sqrt(2 pi) - 10 / (2 x 4) = -3.46574 - 4.59469 - 1.25 = -9.31043.
  std::vector<fit::Observation> obs;
  for (int i = 1; i <= 5; ++i) obs.push_back({static_cast<double>(i), fit::Censoring::none, "", -1});
  fit::RobustOptions o;
  o.robust = false;
  o.noise_sd = 2.0;
  const fit::RobustFit f = fit::fit_robust(R2Constant{5}, obs, {{"mu", 0.0}}, o);
  ASSERT_TRUE(f.usable) << f.message;
  EXPECT_NEAR(f.value("mu"), 3.0, 1e-6);
  const double expected = -5 * std::log(2.0) - 5 * 0.5 * std::log(2 * M_PI) - 1.25;
  EXPECT_NEAR(f.log_likelihood, expected, 1e-6);
  EXPECT_NEAR(f.aic, -2 * expected + 2 * 1, 1e-5);  // sigma given: one parameter
}

// ----- the firmware cap: kept unless the encoders say otherwise by the margin -----

TEST(RoundTwoFirmwareCap, CapKeptWhenTheEncodersCannotTellTheDifference) {
  // Commands of 14.2 cm/s, just above the firmware's 1100 steps/s = 14.168 cm/s; the wheels run at
  // the cap, the encoders count floor(7763.656 x). As commanded, the run is a 0.2 % longer one
  // that a 0.2 % smaller steps per metre fits as well: the BICs differ by less than the margin
  // (10), and the firmware's cap, the documented default, stays. The rows come about every 0.1 s
  // (+-0.02 s, as a host's loop logs them): at exactly 0.1 s every count would be a whole 110 steps,
  // half a step above the register's mean (floor) that the capped model, 1100 steps/s with nothing
  // to fit, cannot absorb and a free slope can.
  const double k = models::sensors::kPluginStepsPerMetre, cap = calibrate::kFirmwareSpeedLimit_m_s;
  std::ostringstream log;
  log << "# obstacle_distance_m: 1.5\ntime_s,left_speed_cm_s,right_speed_cm_s,left_steps,right_steps,tof_mm\n";
  for (int i = 0; i <= 50; ++i) {
    const double t = 0.1 * i + (i > 0 ? 0.004 * ((i * 37) % 11 - 5) : 0.0), x = cap * t;
    const long steps = static_cast<long>(std::floor(k * x));
    log << t << ",14.2,14.2," << steps << "," << steps << "," << std::lround(1000 * (1.5 - x)) << "\n";
  }
  const calibrate::DriveFit d = calibrate::fit_drive({logs::parse_log(log.str(), "capped.csv", logs::Kind::drive)});
  ASSERT_TRUE(d.cap_tested);
  EXPECT_LT(std::abs(d.bic_uncapped - d.bic_capped), calibrate::kCapBicMargin);
  EXPECT_TRUE(d.cap_kept);
}

// ----- the column-unit hints: an obstacle distance in millimetres -----

TEST(RoundTwoUnitHints, ObstacleDistanceInMillimetresIsNamedSo) {
  // `# obstacle_distance_m: 500` with the ToF reading 500 mm: 500 / 0.5 m = 1000 times what the
  // ToF sees: millimetres.
  const logs::Log log = logs::parse_log(
      "# obstacle_distance_m: 500\ntime_s,left_speed_cm_s,right_speed_cm_s,left_steps,right_steps,tof_mm\n0,0,0,0,0,500\n",
      "mm.csv", logs::Kind::drive);
  try {
    calibrate::check_plausible_units({log});
    FAIL() << "accepted an obstacle 500 m away";
  } catch (const logs::InputError& e) {
    EXPECT_NE(std::string(e.what()).find("millimetres?"), std::string::npos) << e.what();
  }
}

// ----- the coefficient-file validation: bounds open at 0 -----

TEST(RoundTwoModelFile, ZeroIsRefusedWhereTheRangeIsOpenAtZero) {
  // docs/coefficient-files.md: range_m, gamma, gain > 0; fov_deg in (0, 180).
  const json prox = {{"kind", "proximity"}, {"parameters", {{"a", 1.0}, {"b", 0.0}, {"c", 0.0}, {"range_m", 0.0}}}};
  EXPECT_THROW(coefficients::proximity_model_from_json(prox, "p.json"), logs::InputError);
  const json light = {{"kind", "light"}, {"parameters", {{"gamma", 0.0}}}};
  EXPECT_THROW(coefficients::light_model_from_json(light, "l.json"), logs::InputError);
  const json ground = {{"kind", "ground"}, {"parameters", {{"gain", {0.0, 500.0, 500.0}}, {"offset", {0.0, 0.0, 0.0}}}}};
  EXPECT_THROW(coefficients::ground_model_from_json(ground, "g.json"), logs::InputError);
  const json camera = {{"kind", "camera"}, {"parameters", {{"fov_deg", 0.0}, {"cx_px", 80.0}, {"cy_px", 60.0}}}};
  EXPECT_THROW(coefficients::camera_model_from_json(camera, "c.json"), logs::InputError);
  // The same files a hair above 0 are read.
  json ok = prox;
  ok["parameters"]["range_m"] = 1e-3;
  EXPECT_NO_THROW(coefficients::proximity_model_from_json(ok, "p.json"));
}

// ----- simulate --like, through the real binary -----

const epuck2::testing::Scratch kRoundTwoScratch{"round_two_slips"};

TEST(RoundTwoSimulateLike, CameraRowAndColumnByHand) {
  // fov 90 deg: f = (160/2) / tan(45 deg) = 80 px; centre (70, 50). An LED at forward 1 m,
  // lateral 0.25 m, vertical 0.125 m: px = 70 - 80 x 0.25 = 50, py = 50 - 80 x 0.125 = 40.
  const std::string model = kRoundTwoScratch.write(
      "camera.json", R"({"kind": "camera", "parameters": {"fov_deg": 90, "cx_px": 70, "cy_px": 50}})");
  const std::string log = kRoundTwoScratch.write("camera.csv", "forward_m,lateral_m,vertical_m,px,py\n1,0.25,0.125,0,0\n1,-0.5,-0.25,0,0\n");
  const logs::Log sim = kRoundTwoScratch.simulate_like("camera", log, model);
  ASSERT_EQ(sim.rows(), 2u);
  EXPECT_NEAR(sim.col("px")[0], 50.0, 1e-9);
  EXPECT_NEAR(sim.col("py")[0], 40.0, 1e-9);
  // lateral -0.5, vertical -0.25: px = 70 + 40 = 110, py = 50 + 20 = 70.
  EXPECT_NEAR(sim.col("px")[1], 110.0, 1e-9);
  EXPECT_NEAR(sim.col("py")[1], 70.0, 1e-9);
}

TEST(RoundTwoSimulateLike, ProximityIncidenceAngleIsInDegrees) {
  // a = b = 0, c = 0.5: 4095 x 0.5 = 2047.5 counts within range_m facing the surface; with
  // incidence_angle k = 2 at 60 deg, times cos(60 deg)^2 = 1/4: 511.875.
  const std::string model = kRoundTwoScratch.write(
      "proximity.json",
      R"({"kind": "proximity", "parameters": {"a": 0, "b": 0, "c": 0.5, "range_m": 0.1}, "effects": {"incidence_angle": {"k": 2}}})");
  const std::string log = kRoundTwoScratch.write("proximity.csv", "distance_m,sensor,value,angle_deg\n0.05,0,0,0\n0.05,0,0,60\n0.05,3,0,-60\n");
  const logs::Log sim = kRoundTwoScratch.simulate_like("proximity", log, model);
  ASSERT_EQ(sim.rows(), 3u);
  EXPECT_NEAR(sim.col("value")[0], 2047.5, 1e-9);
  EXPECT_NEAR(sim.col("value")[1], 511.875, 1e-9);
  EXPECT_NEAR(sim.col("value")[2], 511.875, 1e-9);
}

// ----- the diagnosis's ToF codes: "in view" is judged in millimetres -----

/// A straight run at 10 cm/s for 10 s towards an obstacle `start_m` away, the encoders at the
/// plug-in's steps per metre, the ToF reading the distance, or the "no target" code 8190 beyond
/// its 2000 mm; `code_at_s`: one more 8190 at that time (a dropout where the target is in view).
std::string drive_run(double start_m, double code_at_s = -1) {
  const double k = models::sensors::kPluginStepsPerMetre;
  std::ostringstream log;
  log << "# obstacle_distance_m: " << start_m << "\ntime_s,left_speed_cm_s,right_speed_cm_s,left_steps,right_steps,tof_mm\n";
  for (int i = 0; i <= 100; ++i) {
    const double t = 0.1 * i, x = 0.1 * t;
    const long steps = static_cast<long>(std::floor(k * x));
    const long mm = std::lround(1000 * (start_m - x));
    const bool code = mm > 2000 || (code_at_s >= 0 && std::abs(t - code_at_s) < 1e-9);
    log << t << ",10,10," << steps << "," << steps << "," << (code ? 8190 : mm) << "\n";
  }
  return log.str();
}

bool warns_of_dropouts(const diagnose::Report& r) {
  for (const std::string& w : r.warnings)
    if (w.find("dropouts") != std::string::npos) return true;
  return false;
}

TEST(RoundTwoDiagnosisTofCodes, CodesBeyondTheCeilingAreNotDropouts) {
  // From 2.4 m to 1.4 m: the codes of the first 4 s are read where the encoders put the obstacle
  // 2.4 to 2.0 m away, beyond 90 % of the 2000 mm ceiling: "no target", not dropouts.
  diagnose::Options o;
  o.effects = {"tof_offset"};
  const diagnose::Report far = diagnose::diagnose({logs::parse_log(drive_run(2.4), "far.csv", logs::Kind::drive)}, o);
  ASSERT_TRUE(far.supported) << far.message;
  ASSERT_FALSE(far.too_few_rows) << far.message;
  EXPECT_FALSE(warns_of_dropouts(far));
  // One code at 8 s (the obstacle 1.6 m away, in view): a dropout, said.
  const diagnose::Report near = diagnose::diagnose({logs::parse_log(drive_run(2.4, 8.0), "near.csv", logs::Kind::drive)}, o);
  EXPECT_TRUE(warns_of_dropouts(near));
}

// ----- the naming step: a white level common to every sensor keeps the black offset's term -----

TEST(RoundTwoIdentify, WhiteLevelFromEqualGainsKeepsTheBlackOffset) {
  // Gains 1.0, 1.2, 1.1 (mean 1.1), uncorrelated errors 0.006 each (Wald 0.02/0.006 = 3.3 on 2
  // dof, p = 0.19: equal), the black offset 50 counts: the common white level reads
  // 50 + (level - 50) x 1.1, the straight line through black 50 with the gains' slope (with the
  // plug-in's level 1023: 50 + 973 x 1.1 = 1120.3).
  std::string csv = "grey,sensor,value\n";
  for (double grey : {0.0, 0.25, 0.5, 0.75, 1.0})
    for (int k = 0; k < 3; ++k) csv += std::to_string(grey) + "," + std::to_string(k) + "," + std::to_string(40 + 900 * grey) + "\n";
  std::string why;
  const auto p = diagnose::detail::make_problem({logs::parse_log(csv, "ground.csv", logs::Kind::ground)}, diagnose::Options{}, why);
  ASSERT_NE(p, nullptr) << why;
  namespace fx = models::effects;
  auto first_param = [&](std::size_t id) {
    for (const diagnose::detail::Effect& e : p->effects)
      if (e.cause == fx::ground_catalogue()[id].name) return e.params;
    return std::vector<int>{};
  };
  const std::vector<int> gains = first_param(fx::ground::sensor_gain), level = first_param(fx::ground::white_level),
                         offset = first_param(fx::ground::black_offset);
  ASSERT_EQ(gains.size(), 3u);
  ASSERT_EQ(level.size(), 1u);
  ASSERT_EQ(offset.size(), 1u);
  std::vector<double> values = p->plugin_values;
  const auto P = static_cast<Eigen::Index>(p->params.size());
  Eigen::MatrixXd cov = Eigen::MatrixXd::Zero(P, P);
  const double g[3] = {1.0, 1.2, 1.1};
  for (int a = 0; a < 3; ++a) {
    values[static_cast<std::size_t>(gains[a])] = g[a];
    cov(gains[a], gains[a]) = 0.006;
  }
  values[static_cast<std::size_t>(offset[0])] = 50.0;
  const double L = values[static_cast<std::size_t>(level[0])];
  ASSERT_EQ(L, models::sensors::kGroundFullScale_raw);  // the plug-in's white level, 1023
  const auto named = p->identify(fx::ground_catalogue()[fx::ground::sensor_gain].name, values, cov);
  ASSERT_TRUE(named.has_value());
  ASSERT_EQ(named->starts.size(), 1u);
  EXPECT_NEAR(named->starts[0].second, 50.0 + (1023.0 - 50.0) * 1.1, 1e-9);
}

// ----- the corrected standard errors: the jackknife's (G - 1)/G -----

TEST(RoundTwoJackknife, AgreesWithTheCovarianceOnWhiteNoise) {
  // Proximity logs on the plug-in's curve 4095 (197.8633 d^2 - 30.47182 d + 1.011635) between 5
  // and 40 mm (no rail), white Gaussian noise of 20 counts: least squares with independent, equal
  // errors, where the delete-a-group jackknife variance (G - 1)/G sum (theta_g - mean)^2
  // estimates the same variance as the covariance does (Efron and Stein 1981). Over 5 seeds and
  // the three recalibrated coefficients, the mean of (jackknife / covariance)^2 is 1 within its
  // scatter (each term about chi^2_4 / 4 with 5 folds, sd 0.71: the mean of N has sd
  // 0.71/sqrt(N), less for correlated terms); a sample sd's 1/(G - 1) instead would make it
  // G/(G - 1)^2 = 0.31.
  double sum = 0;
  int terms = 0;
  for (std::uint64_t seed = 1; seed <= 5; ++seed) {
    models::sensors::StandardNormal normal(seed);
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
    const diagnose::Report rep = diagnose::diagnose({logs::parse_log(csv.str(), "proximity.csv", logs::Kind::proximity)}, o);
    ASSERT_TRUE(rep.supported) << rep.message;
    ASSERT_EQ(rep.jackknife_folds, 5u);
    for (const diagnose::NamedValue& v : rep.recalibrated) {
      if (!(v.std_error > 0) || !std::isfinite(v.std_error_jackknife)) continue;
      sum += (v.std_error_jackknife / v.std_error) * (v.std_error_jackknife / v.std_error);
      ++terms;
    }
  }
  ASSERT_GE(terms, 12);
  const double mean = sum / terms;
  std::cout << "(jackknife / covariance)^2: mean " << mean << " over " << terms << " terms\n";
  // Within 3 sd of 1 (0.45 to 1.55 for N = 15).
  EXPECT_GT(mean, 1.0 - 3 * 0.71 / std::sqrt(static_cast<double>(terms))) << terms << " terms, mean " << mean;
  EXPECT_LT(mean, 1.0 + 3 * 0.71 / std::sqrt(static_cast<double>(terms))) << terms << " terms";
}

}  // namespace
}  // namespace test_round_two_slips_cpp
