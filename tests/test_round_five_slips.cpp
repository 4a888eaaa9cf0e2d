// Round 5 of the fresh slips (bench/fresh-slips.md, issue #22 item 6): each area a slip of round 5
// hit, checked against values worked by hand or computed apart from the code under test (long
// double tails, the docs' sensor names, chi-square tails from erfc), at the boundaries the code
// branches on. File-local names carry the prefix r5 (one unity test program).
#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <sstream>
#include <string>
#include <vector>

#include "../lib/diagnose/src/problem.hpp"
#include "epuck2/calibrate/charge_map.hpp"
#include "epuck2/calibrate/sensor_reports.hpp"
#include "epuck2/calibrate/sensors.hpp"
#include "epuck2/coefficients/codegen.hpp"
#include "epuck2/coefficients/model_file.hpp"
#include "epuck2/diagnose/diagnose.hpp"
#include "epuck2/diagnose/reading_noise.hpp"
#include "epuck2/diagnose/report_output.hpp"
#include "epuck2/fit/readings.hpp"
#include "epuck2/fit/report.hpp"
#include "epuck2/fit/robust.hpp"
#include "epuck2/logs/log.hpp"
#include "epuck2/models/effects.hpp"
#include "epuck2/models/kind_facts.hpp"
#include "epuck2/models/simulate_log.hpp"

// The residual structure's scoring of one covariate (lib/diagnose/src/residual_structure.cpp),
// declared here as the library defines it (its header brings the engine's namespace with it).
namespace epuck2::diagnose::engine_detail {
CovariateScore score_covariate(const std::string& name, const std::vector<double>& x, const std::vector<double>& r,
                               double threshold);
}

namespace {

namespace r5fx = epuck2::models::effects;
namespace r5s = epuck2::models::sensors;

// ----- voltage -> charge map: a speed below the slowest logged one ---------------------------

epuck2::calibrate::ChargeMap r5_map_with_load() {
  epuck2::calibrate::ChargeMap m;
  m.knots_v = {3.0, 4.0};
  m.knot_charge = {0.0, 1.0};
  m.load_speeds_cm_s = {5.0, 10.0};
  m.load_offset_v = {0.0, 0.1};
  m.voltage_min_v = 3.0;
  m.voltage_max_v = 4.0;
  return m;
}

TEST(RoundFiveChargeMap, ASpeedBelowTheSlowestTakesTheSlowestsOffset) {
  const auto m = r5_map_with_load();
  // Offsets 0 V at 5 cm/s and 0.1 V at 10 cm/s, linear between, the end's value beyond either end.
  EXPECT_DOUBLE_EQ(epuck2::calibrate::load_offset_v(m, 2.0), 0.0);
  EXPECT_DOUBLE_EQ(epuck2::calibrate::load_offset_v(m, 0.0), 0.0);
  EXPECT_DOUBLE_EQ(epuck2::calibrate::load_offset_v(m, 5.0), 0.0);
  EXPECT_NEAR(epuck2::calibrate::load_offset_v(m, 7.5), 0.05, 1e-12);
  EXPECT_DOUBLE_EQ(epuck2::calibrate::load_offset_v(m, 12.0), 0.1);
  // 3.5 V at 2 cm/s: no offset, halfway between the knots: charge 0.5 (at 12 cm/s 3.6 V: 0.6).
  EXPECT_NEAR(epuck2::calibrate::convert_voltage(m, 3.5, 2.0).charge, 0.5, 1e-12);
  EXPECT_NEAR(epuck2::calibrate::convert_voltage(m, 3.5, -2.0).charge, 0.5, 1e-12);
  EXPECT_NEAR(epuck2::calibrate::convert_voltage(m, 3.5, 12.0).charge, 0.6, 1e-12);
}

// ----- the diagnosis's reading noise: residuals against replicates ---------------------------

TEST(RoundFiveReadingNoise, ResidualsScatteringMoreThanTwiceTheReplicatesAreWarnedOf) {
  epuck2::diagnose::Report r;
  r.kind = epuck2::logs::Kind::proximity;
  std::map<std::string, epuck2::calibrate::ReadingNoise> replicates;
  epuck2::calibrate::ReadingNoise n;
  n.channel = "proximity";
  n.unit = "counts";
  n.sd = 4.0;
  n.n = 50;
  n.from = "replicates";
  replicates["proximity"] = n;
  // Residual sd 10 counts against replicates' 4: 2.5 times, above the factor 2 (kImplausibleNoiseRatio).
  r.noise_sd = 10.0;
  const auto warned = epuck2::diagnose::noise_warnings(r, replicates);
  ASSERT_EQ(warned.size(), 1u);
  EXPECT_NE(warned[0].find("2.5 times"), std::string::npos) << warned[0];
  // 6 counts: 1.5 times, within the factor: no warning.
  r.noise_sd = 6.0;
  EXPECT_TRUE(epuck2::diagnose::noise_warnings(r, replicates).empty());
}

// ----- codegen: an Approximated segment's numbers in their order ------------------------------

std::vector<double> r5_numbers_after(const std::string& text, const std::string& prefix) {
  const std::size_t at = text.find(prefix);
  if (at == std::string::npos) return {};
  const std::size_t open = text.find('{', at), close = text.find('}', at);
  std::stringstream ss(text.substr(open + 1, close - open - 1));
  std::vector<double> out;
  std::string cell;
  while (std::getline(ss, cell, ',')) out.push_back(std::stod(cell));
  return out;
}

TEST(RoundFiveCodegen, ApproximatedSegmentsKeepTheirStartAndEndTimes) {
  r5s::BatteryModel m;
  // Segment struct order (models/battery.hpp): h, m, x1_s, x2_s, y1, y2.
  // A physical segment (lib/coefficients refuses to write one whose line misses its ends): the
  // line through (1200 s, 0.9) and (2400 s, 0.6), m = -0.3 / 1200, h = 0.9 + 0.3 = 1.2.
  m.tables.segments[3][1] = {1.2, -0.00025, 1200.0, 2400.0, 0.9, 0.6};
  const std::string cpp = epuck2::coefficients::model_to_cpp(m, "a hand-made table");
  const std::vector<double> v = r5_numbers_after(cpp, "t.segments[3][1] = ");
  ASSERT_EQ(v.size(), 6u) << cpp;
  EXPECT_DOUBLE_EQ(v[0], 1.2);
  EXPECT_DOUBLE_EQ(v[1], -0.00025);
  EXPECT_DOUBLE_EQ(v[2], 1200.0);
  EXPECT_DOUBLE_EQ(v[3], 2400.0);
  EXPECT_DOUBLE_EQ(v[4], 0.9);
  EXPECT_DOUBLE_EQ(v[5], 0.6);
}

// ----- the noise section's summary sd: the root mean square of the sensors' -------------------

TEST(RoundFiveModelFile, PerSensorNoiseSummaryIsTheRootMeanSquare) {
  const auto j = epuck2::coefficients::noise_json({3.0, 4.0}, "counts");
  EXPECT_NEAR(j.at("sd").get<double>(), std::sqrt(12.5), 1e-12);  // sqrt((9 + 16) / 2)
  ASSERT_EQ(j.at("per_sensor_sd").size(), 2u);
  EXPECT_DOUBLE_EQ(j.at("per_sensor_sd")[1].get<double>(), 4.0);
  const auto k = epuck2::coefficients::noise_json({3.0, 4.0, 12.0}, "counts");
  EXPECT_NEAR(k.at("sd").get<double>(), std::sqrt(169.0 / 3.0), 1e-12);
  EXPECT_DOUBLE_EQ(epuck2::coefficients::noise_json({2.0, 2.0}, "mm").at("sd").get<double>(), 2.0);
}

// ----- simulate --like: the drive's readings in the kind's column order -----------------------

struct R5DriveLog {
  std::map<std::string, std::vector<double>> columns;
  double obstacle_m = 1.0;
  bool has(const std::string& c) const { return columns.count(c) > 0; }
  const std::vector<double>& col(const std::string& c) const { return columns.at(c); }
  std::size_t rows() const { return columns.at("time_s").size(); }
  double metadata_number(const std::string&) const { return obstacle_m; }
};

struct R5NoNoise {
  double operator()() const { return 0.0; }
};

TEST(RoundFiveSimulateLike, OnlyTheCommandedLeftWheelTurnsAndIsWrittenFirst) {
  R5DriveLog log;
  for (int i = 0; i <= 20; ++i) {
    log.columns["time_s"].push_back(0.1 * i);
    log.columns["left_speed_cm_s"].push_back(10.0);
    log.columns["right_speed_cm_s"].push_back(0.0);
  }
  const r5s::DriveModel m;  // the plug-in's 7763.656 steps/m, no effect
  R5NoNoise normal;
  const std::vector<double> cov(log.rows(), 0.0);
  const auto out = r5s::simulated_readings(m, log, cov, false, normal);
  ASSERT_EQ(out.size(), log.rows());
  // The kind's reading columns (docs/logs.md): left_steps, right_steps, tof_mm.
  const auto& facts = *epuck2::models::kind_facts("drive");
  ASSERT_EQ(std::string(facts.readings[0]), "left_steps");
  ASSERT_EQ(out.back().size(), 3u);
  // 2 s at 10 cm/s: 0.2 m on the left wheel, about 1553 steps (a little less while it speeds up);
  // the right wheel, commanded 0, never turns.
  EXPECT_GT(out.back()[0], 0.7 * 0.2 * 7763.656);
  EXPECT_LT(out.back()[0], 1.05 * 0.2 * 7763.656);
  EXPECT_EQ(out.back()[1], 0.0);
}

// ----- naming step: the long tail's share of the reading as reported -------------------------

epuck2::logs::Log r5_log(const std::string& text, epuck2::logs::Kind kind) {
  return epuck2::logs::parse_log(text, "r5.csv", kind);
}

TEST(RoundFiveIdentify, ATailIsRenamedOnlyWhenItCarriesMoreThanHalfOfTheReading) {
  // Rows at 40 mm: the plug-in's curve 4095 (197.8633 d^2 - 30.47182 d + 1.011635) = 447.76 counts.
  const double base = 4095.0 * (197.8633 * 0.04 * 0.04 - 30.47182 * 0.04 + 1.011635);
  ASSERT_NEAR(base, 447.76, 0.01);
  const auto log = r5_log("distance_m,sensor,value\n0.04,0,800\n0.04,0,801\n0.04,0,799\n", epuck2::logs::Kind::proximity);
  std::string why;
  const auto p = epuck2::diagnose::detail::make_problem({log}, {}, why);
  ASSERT_TRUE(p) << why;
  std::vector<double> values = p->plugin_values;
  int amplitude = -1, length = -1;
  for (std::size_t i = 0; i < p->params.size(); ++i) {
    if (p->params[i].name == "amplitude") amplitude = static_cast<int>(i);
    if (p->params[i].name == "length_m") length = static_cast<int>(i);
  }
  ASSERT_GE(amplitude, 0);
  ASSERT_GE(length, 0);
  const std::string cause = r5fx::proximity_catalogue()[r5fx::proximity::long_tail].name;
  values[static_cast<std::size_t>(length)] = 0.02;
  // A tail of 400 counts at 40 mm (amplitude 400 e^2, length 20 mm): 400 / (447.76 + 400) = 0.47
  // of the reading: a tail, not renamed.
  values[static_cast<std::size_t>(amplitude)] = 400.0 * std::exp(2.0);
  EXPECT_FALSE(p->identify(cause, values, {}).has_value());
  // 1000 counts: 1000 / 1447.76 = 0.69: it replaces the near-field curve.
  values[static_cast<std::size_t>(amplitude)] = 1000.0 * std::exp(2.0);
  const auto renamed = p->identify(cause, values, {});
  ASSERT_TRUE(renamed.has_value());
  EXPECT_EQ(renamed->cause, "near_field_curve");
  EXPECT_NE(renamed->why.find("69 %"), std::string::npos) << renamed->why;
}

// ----- residual structure: one degree of freedom between two bins -----------------------------

// x: 50 rows at 0, 50 at 1; residuals a + e and a - e alternately in the first bin, -a +- e in the
// second: score a^2 / (a^2 + e^2), F statistic times df1 = 98 a^2 / e^2 on 1 degree of freedom.
std::vector<double> r5_two_bins(double a, std::vector<double>& x) {
  std::vector<double> r;
  x.clear();
  for (int i = 0; i < 100; ++i) {
    x.push_back(i < 50 ? 0.0 : 1.0);
    r.push_back((i < 50 ? a : -a) + (i % 2 ? 1.0 : -1.0));
  }
  return r;
}

TEST(RoundFiveResidualStructure, TwoBinsAreOneDegreeOfFreedom) {
  std::vector<double> x;
  // chi2 = 29 on 1 dof: p = erfc(sqrt(14.5)) = 7e-8, below the 1e-6 cut (on 2 dof it would be 5e-7
  // by the exact tail, but the code's Wilson-Hilferty cut for 2 dof is 30.3: the dof decide).
  const double a29 = std::sqrt(29.0 / 98.0);
  ASSERT_LT(std::erfc(std::sqrt(29.0 / 2.0)), 1e-6);
  std::vector<double> r = r5_two_bins(a29, x);
  const auto sig = epuck2::diagnose::engine_detail::score_covariate("x", x, r, 0.05);
  EXPECT_NEAR(sig.score, 29.0 / (29.0 + 98.0), 1e-9);
  EXPECT_TRUE(sig.significant);
  // chi2 = 22: p = erfc(sqrt(11)) = 2.7e-6, above the cut: not significant.
  r = r5_two_bins(std::sqrt(22.0 / 98.0), x);
  ASSERT_GT(std::erfc(std::sqrt(11.0)), 1e-6);
  EXPECT_FALSE(epuck2::diagnose::engine_detail::score_covariate("x", x, r, 0.05).significant);
}

// ----- the autocorrelation correction: AR(1) by hand -----------------------------------------

TEST(RoundFiveAutocorrelation, PositiveLagOneCorrelationShrinksTheEffectiveSize) {
  // 1 1 -1 -1 1 1 -1 -1: mean 0, sum of squares 8, lag-one products 1 -1 1 -1 1 -1 1 = 1:
  // rho = 1/8, n_eff = 8 (1 - 1/8) / (1 + 1/8) = 56/9, factor sqrt(8 / (56/9)) = sqrt(9/7).
  const std::vector<double> e{1, 1, -1, -1, 1, 1, -1, -1};
  const auto a = epuck2::fit::autocorrelation_correction(e, std::vector<int>(e.size(), 0));
  ASSERT_TRUE(a.computed);
  EXPECT_NEAR(a.rho, 0.125, 1e-12);
  EXPECT_NEAR(a.n_eff, 56.0 / 9.0, 1e-12);
  EXPECT_NEAR(a.factor, std::sqrt(9.0 / 7.0), 1e-12);
}

// ----- the Tobit terms: the hazard's far tail ---------------------------------------------------

long double r5_hazard_long_double(long double z) {
  const long double pi = 3.14159265358979323846264338327950288L;
  const long double phi = std::exp(-0.5L * z * z) / std::sqrt(2.0L * pi);
  const long double Phi = 0.5L * std::erfc(-z / std::sqrt(2.0L));
  return phi / Phi;
}

TEST(RoundFiveTobit, TheHazardFarBelowTheRailIsPositiveAndNearMinusZ) {
  // phi(z) / Phi(z) in long double (exp(-800) is representable there): about -z + 1/(-z).
  for (double z : {-20.0, -29.0, -31.0, -40.0, -100.0}) {
    const double h = epuck2::fit::normal_hazard_lower(z);
    EXPECT_GT(h, 0.0) << z;
    EXPECT_NEAR(h, static_cast<double>(r5_hazard_long_double(z)), 1e-6 * -z) << z;
  }
}

// ----- the robots' Q test: two robots are enough ---------------------------------------------

TEST(RoundFiveRobotSpread, TwoRobotsGetCochransQ) {
  epuck2::fit::FitResult a, b;
  a.usable = b.usable = true;
  a.parameters = {{"k", 10.0, 1.0}};
  b.parameters = {{"k", 14.0, 1.0}};
  const auto s = epuck2::fit::robot_spread({&a, &b});
  ASSERT_EQ(s.size(), 1u);
  // Weighted mean 12; Q = (2/1)^2 + (2/1)^2 = 8 on 1 dof; p = erfc(sqrt(8/2)) = erfc(2) = 0.004678.
  EXPECT_NEAR(s[0].q, 8.0, 1e-12);
  EXPECT_EQ(s[0].dof, 1u);
  EXPECT_NEAR(s[0].p_value, std::erfc(2.0), 1e-9);
  EXPECT_TRUE(s[0].exceeds);
  EXPECT_NEAR(s[0].spread_sd, std::sqrt(8.0), 1e-12);
}

// ----- the firmware cap: one capped row is enough to test it ----------------------------------

// 40 rows standing, then 60 rows at 10 cm/s on both wheels, one of them commanded 20 cm/s (run by
// the firmware at its 14.17 cm/s); encoders and ToF (obstacle `obstacle_m` away) follow the capped
// run; `code_row`: a row whose ToF reads 8190 (no target), -1 none.
std::string r5_drive_csv(double obstacle_m, int code_row) {
  const double steps_per_m = 7763.656, cap_m_s = 1100.0 / steps_per_m;
  std::ostringstream os;
  os << "# obstacle_distance_m: " << obstacle_m << "\n";
  os << "time_s,left_speed_cm_s,right_speed_cm_s,left_steps,right_steps,tof_mm\n";
  double travelled = 0;
  for (int i = 0; i < 100; ++i) {
    const double t = 0.1 * i;
    const double command = i < 40 ? 0.0 : (i == 70 ? 20.0 : 10.0);
    const long steps = std::lround(travelled * steps_per_m);
    long tof = std::lround(1000.0 * (obstacle_m - travelled)) + (i % 3 == 0 ? 1 : i % 3 == 1 ? -1 : 0);
    if (i == code_row) tof = 8190;
    os << t << "," << command << "," << command << "," << steps << "," << steps << "," << tof << "\n";
    travelled += std::min(command / 100.0, cap_m_s) * 0.1;
  }
  return os.str();
}

TEST(RoundFiveFirmwareCap, OneCappedRowIsCountedAndTheCapTested) {
  const auto log = r5_log(r5_drive_csv(1.0, -1), epuck2::logs::Kind::drive);
  auto f = epuck2::calibrate::fit_drive({log});
  EXPECT_EQ(f.capped_rows, 1u);
  EXPECT_TRUE(f.cap_tested);
  // The drive file's steps observations are the encoders' (every row, 100), not the ToF's.
  f.tof.observations = 7;
  const auto j = epuck2::calibrate::coefficient_json(f, {log});
  EXPECT_EQ(j.at("steps_observations").get<std::size_t>(), f.steps.observations);
  EXPECT_EQ(j.at("steps_observations").get<std::size_t>(), 100u);
  EXPECT_EQ(j.at("observations").get<std::size_t>(), 7u);
}

// ----- ToF codes: the encoders' range to the obstacle shrinks as the robot drives ------------

TEST(RoundFiveTofCodes, ACodeWhereTheEncodersPutTheObstacleInViewIsADropout) {
  // Obstacle 1.5 m away; at row 99 the robot has driven about 0.6 m: the obstacle is 0.9 m ahead,
  // inside the ToF's 2 m less its 10 % margin: a code there is a dropout, said in the warnings.
  const auto log = r5_log(r5_drive_csv(1.5, 99), epuck2::logs::Kind::drive);
  std::string why;
  const auto p = epuck2::diagnose::detail::make_problem({log}, {}, why);
  ASSERT_TRUE(p) << why;
  bool said = false;
  for (const auto& w : p->warnings) said = said || w.rfind("1 ToF \"no target\" codes", 0) == 0;
  EXPECT_TRUE(said);
}

// ----- the log reader: condition ranges and unit hints -----------------------------------------

TEST(RoundFiveLogReader, AForwardDistanceOfZeroIsRefusedWhereItIs) {
  // docs/logs.md: forward_m > 0 (up to 1000).
  try {
    r5_log("forward_m,lateral_m,vertical_m,px,py\n0.2,0,0,80,60\n0,0.01,0,80,60\n", epuck2::logs::Kind::camera);
    ADD_FAILURE() << "forward_m 0 accepted";
  } catch (const epuck2::logs::InputError& e) {
    EXPECT_EQ(e.line(), 3);
    EXPECT_EQ(e.column(), 1);
  }
  EXPECT_NO_THROW(r5_log("forward_m,lateral_m,vertical_m,px,py\n1e-6,0,0,80,60\n", epuck2::logs::Kind::camera));
}

TEST(RoundFiveLogReader, AColumnInAnotherUnitIsNamedWithThatUnit) {
  try {
    r5_log("distance_mm,sensor,value\n20,0,1000\n", epuck2::logs::Kind::proximity);
    ADD_FAILURE() << "distance_mm accepted for distance_m";
  } catch (const epuck2::logs::InputError& e) {
    const std::string m = e.message();
    EXPECT_NE(m.find("has the unit mm;"), std::string::npos) << m;
    EXPECT_EQ(m.find("_mm;"), std::string::npos) << m;
  }
}

// ----- kind facts and the registry ----------------------------------------------------------

TEST(RoundFiveKindFacts, GroundSensorsAreNamedRightCentreLeft) {
  // docs/coefficient-files.md and data/raw/ground/README.md: sensors 0 (right), 1 (centre), 2 (left).
  const auto& g = *epuck2::models::kind_facts("ground");
  EXPECT_EQ(g.sensor_name(0), "0 (right)");
  EXPECT_EQ(g.sensor_name(1), "1 (centre)");
  EXPECT_EQ(g.sensor_name(2), "2 (left)");
}

TEST(RoundFiveEffects, ANeutralValueOutsideTheRangeIsAdmissible) {
  // wheel_slip's tau: neutral 0 (no slip), range [1e-3, 10] s.
  const auto& e = r5fx::drive_catalogue()[r5fx::drive::wheel_slip];
  ASSERT_EQ(e.params.size(), 1u);
  EXPECT_TRUE(r5fx::Effect::admissible(e.params[0], 0.0));
  EXPECT_FALSE(r5fx::Effect::admissible(e.params[0], 1e-4));
  EXPECT_TRUE(r5fx::Effect::admissible(e.params[0], 0.1));
  const nlohmann::json file = {{"kind", "drive"}, {"parameters", {{"steps_per_m", 7763.656}, {e.params[0].file_key, 0.0}}}};
  EXPECT_NO_THROW(epuck2::coefficients::drive_model_from_json(file, "r5.json", ""));
}

// ----- the diagnosis: jackknife and the report's residual structure ---------------------------

// Three ground sensors, gains 1000, 950, 1050 counts and offsets 10, 20, 0 over 11 grey levels,
// 8 replicates each, Gaussian noise of sd 4 (seeded), rows shuffled (the folds are blocks of rows).
epuck2::logs::Log r5_ground_log() {
  std::mt19937 rng(20261126);
  std::normal_distribution<double> noise(0.0, 4.0);
  const double gain[3] = {1000.0, 950.0, 1050.0}, offset[3] = {10.0, 20.0, 0.0};
  std::vector<std::string> rows;
  for (int g = 0; g <= 10; ++g)
    for (int s = 0; s < 3; ++s)
      for (int k = 0; k < 8; ++k) {
        const double v = std::clamp(std::round(offset[s] + gain[s] * 0.1 * g + noise(rng)), 0.0, 1023.0);
        rows.push_back(std::to_string(0.1 * g) + "," + std::to_string(s) + "," + std::to_string(static_cast<int>(v)));
      }
  std::shuffle(rows.begin(), rows.end(), rng);
  std::string text = "grey,sensor,value\n";
  for (const auto& r : rows) text += r + "\n";
  return r5_log(text, epuck2::logs::Kind::ground);
}

TEST(RoundFiveDiagnosis, JackknifeErrorsAreOfTheCovariancesSizeAndTheReportShowsTheStructureAfter) {
  const auto log = r5_ground_log();
  auto r = epuck2::diagnose::diagnose(std::vector<epuck2::logs::Log>{log});
  ASSERT_GE(r.jackknife_folds, 3u) << r.message << " recalibrated " << r.recalibrated.size();
  // Both estimate the same sampling sd (independent noise, shuffled rows): within a factor 4,
  // whatever the parameter's value.
  int compared = 0;
  std::vector<epuck2::diagnose::NamedValue> all = r.recalibrated;
  for (const auto& f : r.findings) all.insert(all.end(), f.parameters.begin(), f.parameters.end());
  for (const auto& v : all) {
    if (!(v.std_error > 0) || !std::isfinite(v.std_error_jackknife)) continue;
    ++compared;
    EXPECT_LT(v.std_error_jackknife, 4.0 * v.std_error) << v.name << " = " << v.value;
    EXPECT_GT(v.std_error_jackknife, v.std_error / 4.0) << v.name << " = " << v.value;
  }
  EXPECT_GT(compared, 0);
  // The report's residual_structure is the structure after the findings; _before, before them.
  epuck2::diagnose::CovariateScore before, after;
  before.covariate = after.covariate = "grey";
  before.score = 0.9;
  before.significant = true;
  after.score = 0.02;
  r.structure_before = {before};
  r.structure_after = {after};
  const auto j = epuck2::diagnose::report_json(r, {"r5.csv"}, {});
  ASSERT_EQ(j.at("residual_structure").size(), 1u);
  EXPECT_DOUBLE_EQ(j.at("residual_structure")[0].at("score").get<double>(), 0.02);
  EXPECT_FALSE(j.at("residual_structure")[0].at("significant").get<bool>());
  EXPECT_DOUBLE_EQ(j.at("residual_structure_before")[0].at("score").get<double>(), 0.9);
}

}  // namespace
