// Issue #21: a fit that does not fit says so. Each test builds its logs here, from a generator
// written for the test (not the virtual robot), and checks the generator's truth or the exact
// message, never a number taken from the code under test.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <nlohmann/json.hpp>
#include <random>
#include <sstream>
#include <string>
#include <vector>

#include "cli_harness.hpp"
#include "epuck2/calibrate/sensor_reports.hpp"
#include "epuck2/calibrate/sensors.hpp"
#include "epuck2/diagnose/diagnose.hpp"
#include "epuck2/diagnose/extended_model.hpp"
#include "epuck2/logs/log.hpp"

namespace {

namespace dg = epuck2::diagnose;
namespace logs = epuck2::logs;
using epuck2::testing::CliRun;

// The e-puck2's encoders: 1000 steps a wheel turn, wheel diameter 41 mm (GCtronic's e-puck2
// documentation), so 1000 / (pi 0.041) steps a metre.
const double kStepsPerMetre = 1000.0 / (M_PI * 0.041);

struct DriveTruth {
  double obstacle_m = 0.6;   ///< ToF to obstacle at t = 0
  double speed_cm_s = 5.0;   ///< both wheels, from row `start` on, towards the obstacle
  double tof_sd_mm = 3.0;    ///< Gaussian noise of a ToF reading before its rounding
  std::size_t rows = 76;
  std::size_t start = 1;     ///< first row that commands the speed
  std::size_t second = 0;    ///< from this row on (0: never) the command is second_cm_s ...
  double second_cm_s = 0;
  double second_runs_cm_s = 0;  ///< ... and the wheels run at this
  double dt_s = 0.1;
  std::vector<std::size_t> code_rows;  ///< rows whose ToF reads 8190 ("no target")
  unsigned seed = 21;
};

/// A drive log as an ideal robot would write it: the body moves exactly as commanded (the command
/// holds from its row's time to the next row's), the encoders count floor(steps/m x), the ToF
/// reads round(1000 (D - x) + noise). `sq_error` gets the sum of squared ToF errors (reading minus
/// 1000 (D - x)) of the rows that are not codes, and `n_exact` their number.
std::string drive_log(const DriveTruth& t, double* sq_error = nullptr, std::size_t* n_exact = nullptr) {
  std::mt19937 rng(t.seed);
  std::normal_distribution<double> noise(0.0, t.tof_sd_mm);
  std::ostringstream os;
  os << "# obstacle_distance_m: " << t.obstacle_m << "\n";
  os << "time_s,left_speed_cm_s,right_speed_cm_s,left_steps,right_steps,tof_mm\n";
  double x = 0, se = 0;
  std::size_t n = 0;
  for (std::size_t i = 0; i < t.rows; ++i) {
    const double time = static_cast<double>(i) * t.dt_s;
    const bool second = t.second > 0;
    if (i > 0 && i - 1 >= t.start)  // the previous row's command, held
      x += (second && i - 1 >= t.second ? t.second_runs_cm_s : t.speed_cm_s) / 100.0 * t.dt_s;
    const double v = second && i >= t.second ? t.second_cm_s : i >= t.start ? t.speed_cm_s : 0.0;
    const long steps = static_cast<long>(std::floor(kStepsPerMetre * x));
    const double truth_mm = 1000.0 * (t.obstacle_m - x);
    double tof = std::round(truth_mm + noise(rng));
    const bool code = std::find(t.code_rows.begin(), t.code_rows.end(), i) != t.code_rows.end();
    if (code) {
      tof = 8190;
    } else {
      se += (tof - truth_mm) * (tof - truth_mm);
      ++n;
    }
    os << time << "," << v << "," << v << "," << steps << "," << steps << "," << tof << "\n";
  }
  if (sq_error) *sq_error = se;
  if (n_exact) *n_exact = n;
  return os.str();
}

// ---- (7) ToF codes in a diagnosed drive log are read as the calibration reads them ----------

TEST(HonestDiagnosis, ToFNoTargetCodesInViewAreLeftOutNotFittedAsReadings) {
  DriveTruth t;
  t.code_rows = {12, 30, 31, 50, 70};  // five dropouts, the obstacle between 0.25 and 0.55 m away
  double se = 0;
  std::size_t n = 0;
  const std::string text = drive_log(t, &se, &n);
  ASSERT_EQ(n, 71u);
  const dg::Report r = dg::diagnose({logs::parse_log(text, "codes.csv", logs::Kind::drive)});
  ASSERT_TRUE(r.supported) << r.message;
  ASSERT_FALSE(r.too_few_rows) << r.message;
  // The plug-in's model is this generator's without noise: its MSE on the readings is the
  // generator's own squared error (the ToF readings that are not codes), to rounding. Each code
  // fitted as a 2000 mm reading would add ~ (2000 - 400)^2 / 76 ~ 3e4 mm^2.
  const double truth_mse = se / static_cast<double>(n);
  EXPECT_NEAR(r.heldout_mse_plugin, truth_mse, 0.05 * truth_mse) << "generator's MSE " << truth_mse;
  bool said = false;
  for (const auto& w : r.warnings)
    said = said || w.rfind("5 ToF \"no target\" codes (>= 8190) where the encoders put the obstacle within 1800 mm: dropouts, "
                           "left out of the ToF residuals as the drive calibration leaves them out (codes.csv:15, codes.csv:33, "
                           "codes.csv:34, codes.csv:53, codes.csv:73)", 0) == 0;
  EXPECT_TRUE(said) << (r.warnings.empty() ? std::string("no warning") : r.warnings.front());
  // Nothing is wrong with this robot: no finding.
  EXPECT_TRUE(r.findings.empty()) << r.findings.front().cause;
  EXPECT_EQ(r.verdict_name(), "none");
}

TEST(HonestDiagnosis, ToFCodesBeyondTheCeilingStayReadingsAtTheRail) {
  // The obstacle 2.5 m away: nothing within the ToF's 2000 mm, every reading a code. They are
  // what the sensor reads beyond its ceiling (censored at the rail), not dropouts.
  DriveTruth t;
  t.obstacle_m = 2.5;
  t.rows = 60;
  for (std::size_t i = 0; i < t.rows; ++i) t.code_rows.push_back(i);
  const dg::Report r = dg::diagnose({logs::parse_log(drive_log(t), "far.csv", logs::Kind::drive)});
  ASSERT_TRUE(r.supported) << r.message;
  for (const auto& w : r.warnings) EXPECT_EQ(w.find("no target"), std::string::npos) << w;
  // At the rail the clamped model reads the rail: no ToF error at all.
  EXPECT_LT(r.heldout_mse_plugin, 1e-6);
}

// ---- (7) too few rows is "not judged", never "none" --------------------------------------------

TEST(HonestDiagnosis, TooFewRowsIsNotJudgedWithTheCounts) {
  DriveTruth t;
  t.rows = 20;  // a drive log needs a row in each of the 40 blocks (docs/diagnose.md)
  const dg::Report r = dg::diagnose({logs::parse_log(drive_log(t), "short.csv", logs::Kind::drive)});
  EXPECT_TRUE(r.too_few_rows);
  EXPECT_EQ(r.verdict, dg::Verdict::not_judged);
  EXPECT_EQ(r.verdict_name(), "not judged (too few rows: 20 of 40)");
}

// ---- (6) findings the logs cannot determine are not kept ---------------------------------------

/// Three ground sensors over 11 grey levels, 10 readings each: round(clamp(offset + 1023 grey +
/// N(0, sd), 0, 1023)) -- the plug-in's 1023 per unit grey with a black offset added.
std::string ground_log(double offset, double sd, unsigned seed) {
  std::mt19937 rng(seed);
  std::normal_distribution<double> noise(0.0, sd);
  std::ostringstream os;
  os << "grey,sensor,value\n";
  for (int g = 0; g <= 10; ++g)
    for (int sensor = 0; sensor < 3; ++sensor)
      for (int k = 0; k < 10; ++k)
        os << g / 10.0 << "," << sensor << "," << std::clamp(std::round(offset + 1023.0 * g / 10.0 + noise(rng)), 0.0, 1023.0) << "\n";
  return os.str();
}

TEST(HonestDiagnosis, AFindingBeyondTheStatedUncertaintyIsPossibleNotDeterminedAndLeftOutOfTheModel) {
  const logs::Log log = logs::parse_log(ground_log(40.0, 5.0, 7), "g.csv", logs::Kind::ground);
  // The generator in the diagnosis's terms: black reads 40 (black_offset) and white 1063
  // (white_level), a straight line (no nonlinear_response). The greedy first step takes
  // nonlinear_response (it bends the line part of the way towards the offset); once black_offset
  // joins, backward elimination removes it. black_offset carries most of the gain and names the
  // verdict. Tolerances: a few standard errors (5 / sqrt(330) ~ 0.3 counts).
  const dg::Report kept = dg::diagnose({log});
  ASSERT_EQ(kept.findings.size(), 2u) << kept.message;
  const dg::Finding* offset = nullptr;
  const dg::Finding* level = nullptr;
  for (const auto& f : kept.findings) (f.cause == "black_offset" ? offset : level) = &f;
  ASSERT_NE(offset, nullptr);
  ASSERT_NE(level, nullptr);
  EXPECT_EQ(level->cause, "white_level");
  EXPECT_NEAR(offset->parameters.front().value, 40.0, 2.0);
  EXPECT_NEAR(level->parameters.front().value, 1063.0, 3.0);
  EXPECT_EQ(kept.verdict_name(), "black_offset");
  EXPECT_EQ(kept.dominant(), offset);
  EXPECT_TRUE(kept.possible.empty());
  EXPECT_NEAR(dg::extended_ground(kept).sensors[0].offset_raw, 40.0, 2.0);
  // The same finding judged against a limit no standard error meets: possible, not determined,
  // said why, and absent from the final and the extended model (the plug-in's offset 0 again).
  dg::Options strict;
  strict.max_relative_se = 1e-12;
  const dg::Report r = dg::diagnose({log}, strict);
  ASSERT_EQ(r.possible.size(), 2u);
  for (const auto& f : r.possible)
    EXPECT_NE(f.undetermined.find("a standard error beyond 1e-12 times its size"), std::string::npos) << f.undetermined;
  EXPECT_TRUE(r.findings.empty());
  EXPECT_NE(r.verdict_name(), "black_offset");
  EXPECT_EQ(dg::extended_ground(r).sensors[0].offset_raw, 0.0);
  EXPECT_EQ(dg::extended_ground(r).sensors[0].gain_raw, 1023.0);
  // The final model without it misses by the generator's 40 counts again: MSE ~ 40^2.
  EXPECT_GT(r.heldout_mse_final, 0.5 * 40.0 * 40.0);
  bool warned = false;
  for (const auto& w : r.warnings) warned = warned || w.rfind("possible, not determined: black_offset (", 0) == 0;
  EXPECT_TRUE(warned);
}

TEST(HonestDiagnosis, TwoFindingsTheLogsCannotTellApartAreBothPossibleNotDetermined) {
  // black_offset and white_level both move the reading of mid greys: their parameters correlate.
  // Judged against a correlation limit they exceed (a stated option), neither is determined.
  const logs::Log log = logs::parse_log(ground_log(40.0, 5.0, 7), "g.csv", logs::Kind::ground);
  dg::Options strict;
  strict.max_correlation = 1e-9;
  const dg::Report r = dg::diagnose({log}, strict);
  ASSERT_EQ(r.possible.size(), 2u);
  for (const auto& f : r.possible)
    EXPECT_EQ(f.undetermined.rfind("these logs cannot tell ", 0), 0u) << f.undetermined;
  EXPECT_TRUE(r.findings.empty());
  EXPECT_EQ(dg::extended_ground(r).sensors[0].offset_raw, 0.0);
}

// ---- (5) the firmware cap is tested, not assumed ----------------------------------------------

TEST(HonestDrive, WheelsThatRunFasterThanTheFirmwareCapAreFittedAsTheyRun) {
  // 5 cm/s, then 15 cm/s, and the wheels do turn at 15 (the generator has no cap). Taken as
  // capped at 14.17, the two speeds disagree on the steps per metre. (At one speed alone the cap
  // and the steps per metre cannot be told apart: the cap is then kept.)
  DriveTruth t;
  t.obstacle_m = 1.5;
  t.speed_cm_s = 5.0;
  t.second = 30;
  t.second_cm_s = t.second_runs_cm_s = 15.0;
  t.rows = 60;  // 0.59 m driven
  const auto f = epuck2::calibrate::fit_drive({logs::parse_log(drive_log(t), "fast.csv", logs::Kind::drive)});
  ASSERT_TRUE(f.steps.usable) << f.steps.message;
  EXPECT_TRUE(f.cap_tested);
  EXPECT_FALSE(f.cap_kept);
  EXPECT_LT(f.bic_uncapped, f.bic_capped - 10);
  // The generator's steps per metre, within 0.1 %.
  EXPECT_NEAR(f.steps.value("steps_per_m"), kStepsPerMetre, 1e-3 * kStepsPerMetre);
  bool said = false;
  for (const auto& w : f.warnings) said = said || w.find("the wheels exceed the firmware's limit and are fitted as they run") != std::string::npos;
  EXPECT_TRUE(said);
  // The text report says which way the test went (docs/fitting.md, "Drive").
  const std::string text = epuck2::calibrate::report_text(f);
  EXPECT_NE(text.find("taken as commanded (the encoders beat the limit on the BIC): 30 rows)"), std::string::npos) << text.substr(0, 600);
  EXPECT_NE(text.find(" without: the wheels run faster, fitted as they run\n"), std::string::npos) << text.substr(0, 600);
  // The run above the limit is listed, and not as capped: it was fitted as commanded.
  EXPECT_NE(text.find("  commands above the limit (not capped: the wheels ran them): fast.csv\n"), std::string::npos) << text;
}

TEST(HonestDrive, WheelsHeldAtTheCapKeepIt) {
  // The same commands, the wheels held at the firmware's 1100 steps/s: the cap stays.
  DriveTruth t;
  t.obstacle_m = 1.5;
  t.speed_cm_s = 5.0;
  t.second = 30;
  t.second_cm_s = 15.0;
  t.second_runs_cm_s = 100.0 * 1100.0 / kStepsPerMetre;
  t.rows = 60;
  const auto f = epuck2::calibrate::fit_drive({logs::parse_log(drive_log(t), "held.csv", logs::Kind::drive)});
  ASSERT_TRUE(f.steps.usable) << f.steps.message;
  EXPECT_TRUE(f.cap_tested);
  EXPECT_TRUE(f.cap_kept);
  EXPECT_EQ(f.capped_rows, 30u);
  EXPECT_NEAR(f.steps.value("steps_per_m"), kStepsPerMetre, 1e-3 * kStepsPerMetre);
  const std::string text = epuck2::calibrate::report_text(f);
  // The cap: 1100 steps/s over the fitted steps per metre (14.17 cm/s at the plug-in's 7763.656).
  char cap[96];
  std::snprintf(cap, sizeof cap, "1100 / steps_per_m = %.3f cm/s taken as that limit: 30 rows)", 110000.0 / f.steps.value("steps_per_m"));
  EXPECT_NE(text.find(cap), std::string::npos) << cap << "\n" << text.substr(0, 600);
  EXPECT_NE(text.find(" without: kept\n"), std::string::npos) << text.substr(0, 600);
  EXPECT_NE(text.find("  commands above the limit (capped): held.csv\n"), std::string::npos) << text;
}

// ---- (4) units that cannot be the columns' stop the run (exit 2, the column, the likely unit) --

class HonestUnits : public epuck2::testing::CliTest {
 protected:
  static std::string q(const std::string& p) { return "\"" + p + "\""; }
};

/// A proximity log of one sensor at `distances` (in metres), each read 10 times off the plug-in's
/// published curve 4095 clamp01(197.8633 d^2 - 30.47182 d + 1.011635) (the ARGoS plug-in's
/// source), written in `unit` metres (100: centimetres).
std::string proximity_log(const std::vector<double>& distances, double unit) {
  std::ostringstream os;
  os << "distance_m,sensor,value\n";
  for (double d : distances)
    for (int k = 0; k < 10; ++k) {
      const double v = d <= 0.05 ? std::clamp(197.8633 * d * d - 30.47182 * d + 1.011635, 0.0, 1.0) : 0.0;
      os << d * unit << ",0," << std::lround(4095 * v) << "\n";
    }
  return os.str();
}

TEST_F(HonestUnits, ProximityDistancesInCentimetresStopWithTheColumnAndTheUnit) {
  // 0.5..7 cm written as metres: the first row at the largest, 7, is row 70 (line 72).
  const std::string log = write("cm.csv", proximity_log({0.005, 0.01, 0.02, 0.03, 0.04, 0.05, 0.06, 0.07}, 100));
  for (const std::string cmd : {"proximity ", "diagnose "}) {
    const CliRun r = run(cmd + q(log));
    EXPECT_EQ(r.exit_code, 2) << cmd << r.out << r.err;
    EXPECT_NE(r.err.find(log + ":72:1: distance_m reaches 7: centimetres?"), std::string::npos) << cmd << r.err;
  }
  // The same log in metres is a calibration.
  const std::string metres = write("m.csv", proximity_log({0.005, 0.01, 0.02, 0.03, 0.04, 0.05, 0.06, 0.07}, 1));
  EXPECT_EQ(run("proximity " + q(metres)).exit_code, 0);
}

TEST_F(HonestUnits, ProximityDistancesInMillimetresAreNamedSo) {
  const std::string log = write("mm.csv", proximity_log({0.005, 0.01, 0.02, 0.03, 0.04, 0.05, 0.06, 0.07}, 1000));
  const CliRun r = run("proximity " + q(log));
  EXPECT_EQ(r.exit_code, 2) << r.err;
  EXPECT_NE(r.err.find(log + ":72:1: distance_m reaches 70: millimetres?"), std::string::npos) << r.err;
}

TEST_F(HonestUnits, AnObstacleDistanceInCentimetresStopsTheDriveFitAndTheDiagnosis) {
  // The obstacle 30 cm away written as 30 (m): the ToF reads ~300 mm. Line 1 is the metadata,
  // its value starts at column 24.
  DriveTruth t;
  t.obstacle_m = 0.3;
  t.rows = 40;  // 0.195 m driven: the ToF ends at 105 mm
  std::string text = drive_log(t);
  text.replace(0, text.find('\n'), "# obstacle_distance_m: 30");
  const std::string log = write("cm_drive.csv", text);
  for (const std::string cmd : {"drive ", "diagnose "}) {
    const CliRun r = run(cmd + q(log));
    EXPECT_EQ(r.exit_code, 2) << cmd << r.out << r.err;
    EXPECT_NE(r.err.find(log + ":1:24: obstacle_distance_m is 30: centimetres?"), std::string::npos) << cmd << r.err;
  }
}

TEST_F(HonestUnits, AnObstacleBeyondTheToFThatTheToFSeesStops) {
  // 2.5 m is beyond the ToF's 2 m, yet its first reading is ~300 mm: the metadata is not metres.
  DriveTruth t;
  t.obstacle_m = 0.3;
  t.rows = 40;
  std::string text = drive_log(t);
  text.replace(0, text.find('\n'), "# obstacle_distance_m: 2.5");
  const std::string log = write("dm.csv", text);
  const CliRun r = run("drive " + q(log));
  EXPECT_EQ(r.exit_code, 2) << r.err;
  EXPECT_NE(r.err.find(log + ":1:24: obstacle_distance_m is 2.5 m, beyond the ToF's 2 m, but tof_mm reads "), std::string::npos)
      << r.err;
}

TEST_F(HonestUnits, PixelsOfA640By480ImageStopAtTheirCell) {
  // An LED 0.2 m ahead, centred: (320, 240) in a 640x480 image, (80, 60) in the camera's 160x120.
  const std::string log = write("vga.csv", "forward_m,lateral_m,vertical_m,px,py\n0.2,0,0,320,240\n");
  const CliRun r = run("camera " + q(log));
  EXPECT_EQ(r.exit_code, 2) << r.err;
  EXPECT_NE(r.err.find(log + ":2:"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("a pixel column 0..159"), std::string::npos) << r.err;
}

// ---- (2) every fit tests its lack of fit against its replicates, aggregated fits included -----

/// A proximity log of one sensor, `per` readings at each of `distances` (m): round(truth(d) +
/// N(0, sd)) counts, seeded. The truth is the generator's, never the fit's.
template <class Truth>
std::string replicated_proximity_log(const std::vector<double>& distances, int per, double sd, Truth truth, unsigned seed) {
  std::mt19937 rng(seed);
  std::normal_distribution<double> noise(0.0, sd);
  std::ostringstream os;
  os << "distance_m,sensor,value\n";
  for (double d : distances)
    for (int k = 0; k < per; ++k) os << d << ",0," << std::lround(truth(d) + noise(rng)) << "\n";
  return os.str();
}

const std::vector<double> kLofDistances = {0.002, 0.004, 0.006, 0.008, 0.01, 0.015, 0.02, 0.025, 0.03, 0.035, 0.04};

/// The RMS, over `x`, of f minus its least-squares quadratic (3x3 normal equations solved here by
/// Cramer's rule): the least any quadratic can miss f by, whatever the fit's constraints.
/// `worst` gets the x it misses most.
template <class F>
double best_quadratic_miss(const std::vector<double>& x, F f, double* worst = nullptr) {
  double S[5] = {0, 0, 0, 0, 0}, T[3] = {0, 0, 0};
  for (double d : x) {
    double p = 1;
    for (int k = 0; k < 5; ++k, p *= d) S[k] += p;
    T[0] += f(d);
    T[1] += d * f(d);
    T[2] += d * d * f(d);
  }
  auto det3 = [](double a, double b, double c, double d, double e, double g, double h, double i, double j) {
    return a * (e * j - g * i) - b * (d * j - g * h) + c * (d * i - e * h);
  };
  const double D = det3(S[0], S[1], S[2], S[1], S[2], S[3], S[2], S[3], S[4]);
  const double c0 = det3(T[0], S[1], S[2], T[1], S[2], S[3], T[2], S[3], S[4]) / D;
  const double c1 = det3(S[0], T[0], S[2], S[1], T[1], S[3], S[2], T[2], S[4]) / D;
  const double c2 = det3(S[0], S[1], T[0], S[1], S[2], T[1], S[2], S[3], T[2]) / D;
  double ss = 0, top = -1;
  for (double d : x) {
    const double r = std::abs(f(d) - (c0 + c1 * d + c2 * d * d));
    ss += r * r;
    if (r > top && worst != nullptr) *worst = d;
    top = std::max(top, r);
  }
  return std::sqrt(ss / static_cast<double>(x.size()));
}

class HonestLackOfFit : public epuck2::testing::CliTest {
 protected:
  static std::string q(const std::string& p) { return "\"" + p + "\""; }
};

TEST_F(HonestLackOfFit, AQuadraticProximityCurveIsTestedOnItsReplicatesAndPasses) {
  // The plug-in's published quadratic (ARGoS plug-in source), 20 readings a distance, sd 5 counts:
  // the aggregated fits are tested now, their replicate sd is the generator's, and they pass.
  auto plugin = [](double d) { return 4095 * (197.8633 * d * d - 30.47182 * d + 1.011635); };
  const std::string log = write("quad.csv", replicated_proximity_log(kLofDistances, 20, 5.0, plugin, 2101));
  const CliRun r = run("proximity --json " + q(log));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const auto j = nlohmann::json::parse(r.out);
  for (const char* fit : {"maxima", "means"}) {
    const auto& lof = j["fits"][fit]["lack_of_fit"];
    ASSERT_TRUE(lof.contains("replicate_sd")) << fit << lof.dump();
    EXPECT_EQ(lof["groups"], kLofDistances.size()) << fit;
    EXPECT_NEAR(lof["replicate_sd"].get<double>() * 4095, 5.0, 0.75) << fit;  // 15 %: 209 dof
    EXPECT_LT(lof["misfit_ratio"].get<double>(), 3.0) << fit;
  }
  EXPECT_EQ(r.err.find("the curve misses"), std::string::npos) << r.err;
}

TEST_F(HonestLackOfFit, ANonQuadraticProximityCurveStopsWithTheWorstDistancesUnlessAccepted) {
  // An exponential tail 3900 exp(-d / 8 mm): no quadratic follows it. Replicates of sd 5 counts.
  auto tail = [](double d) { return 3900 * std::exp(-d / 0.008); };
  // Below 1 % of full scale (41 counts) a mean says only "at most": 40 mm (26 counts) is censored.
  std::vector<double> exact(kLofDistances.begin(), kLofDistances.end() - 1);
  double worst_m = 0;
  const double least_miss = best_quadratic_miss(exact, tail, &worst_m);  // counts, the generator's
  ASSERT_GT(least_miss, 10 * 5.0);  // the generator makes a misfit beyond the failing ratio
  const std::string log = write("exp.csv", replicated_proximity_log(kLofDistances, 20, 5.0, tail, 2102));
  const std::string out = (dir_ / "exp.json").string();
  const CliRun r = run("proximity -o " + q(out) + " " + q(log));
  EXPECT_EQ(r.exit_code, 1) << r.out << r.err;
  EXPECT_NE(r.err.find("proximity fit to the maxima: the curve misses its data by "), std::string::npos) << r.err;
  // The distance the best quadratic misses most, in the generator's truth, is named.
  const std::string named = "worst: distance " + std::to_string(std::lround(worst_m * 1000));
  EXPECT_NE(r.err.find("times the replicates' own sd (limit 10); " + named), std::string::npos) << named << r.err;
  EXPECT_NE(r.err.find("--accept-misfit writes it anyway"), std::string::npos) << r.err;
  EXPECT_FALSE(std::filesystem::exists(out)) << "a misfit is not written as a calibration";

  const CliRun a = run("proximity --accept-misfit --json " + q(log));
  ASSERT_EQ(a.exit_code, 0) << a.err;
  const auto j = nlohmann::json::parse(a.out);
  const auto& lof = j["fits"]["means"]["lack_of_fit"];
  EXPECT_NEAR(lof["replicate_sd"].get<double>() * 4095, 5.0, 0.75);
  // Each mean carries its own noise (sd 5 / sqrt 20): the curve misses them by at least the best
  // quadratic's miss of the truth, less that noise.
  EXPECT_GT(lof["misfit_rms"].get<double>() * 4095, least_miss - 2.0);
  EXPECT_GT(lof["misfit_ratio"].get<double>(), 10.0);
  EXPECT_EQ(lof["groups"], exact.size());
  EXPECT_EQ(lof["worst"].get<std::string>().rfind(named.substr(7), 0), 0u) << named << lof.dump();
  bool warned = false, accepted = false;
  for (const auto& w : j["warnings"]) {
    warned = warned || w.get<std::string>().find("means fit: the curve misses the readings by ") == 0;
    accepted = accepted || w.get<std::string>().find("(accepted by --accept-misfit)") != std::string::npos;
  }
  EXPECT_TRUE(warned) << j["warnings"].dump();
  EXPECT_TRUE(accepted) << j["warnings"].dump();
}

TEST_F(HonestLackOfFit, AGroundSensorThatDoesNotRespondIsBelowTheR2FloorWithoutAMisfitAndWarns) {
  // Three sensors that read 500 + N(0, 20) counts whatever the grey level: by the generator's
  // construction no line through grey explains any of the variance (R^2 about 0, below 0.9),
  // but the flat line misses no replicate mean: noise, not misfit. A warning, not exit 1.
  std::mt19937 rng(2103);
  std::normal_distribution<double> noise(0.0, 20.0);
  std::ostringstream os;
  os << "grey,sensor,value\n";
  for (int sensor = 0; sensor < 3; ++sensor)
    for (int g = 0; g <= 10; ++g)
      for (int k = 0; k < 20; ++k) os << g / 10.0 << "," << sensor << "," << std::lround(500 + noise(rng)) << "\n";
  const std::string log = write("flat.csv", os.str());
  const CliRun r = run("ground --json " + q(log));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const auto j = nlohmann::json::parse(r.out);
  for (const char* sensor : {"0 (right)", "1 (centre)", "2 (left)"})
    EXPECT_NE(r.err.find(std::string("ground sensor ") + sensor + ": R^2 = "), std::string::npos) << sensor << r.err;
  EXPECT_NE(r.err.find("is below 0.9, but the curve misses the replicates by only "), std::string::npos) << r.err;
  for (const char* fit : {"sensor_0", "sensor_1", "sensor_2"}) {
    const auto& lof = j["fits"][fit]["lack_of_fit"];
    EXPECT_LT(lof["misfit_ratio"].get<double>(), 3.0) << fit;
    EXPECT_NEAR(lof["replicate_sd"].get<double>(), 20.0, 2.0) << fit;  // the generator's sd, 10 %
  }
}

}  // namespace

// ---- (1) saturation before the noise ------------------------------------------------------------

namespace {

/// A phototransistor that saturates before its noise: one light of intensity 1 at `distances`,
/// `per` readings each, round(clamp(clamp(4095 (1 - (gamma / d)^2), 0, 4095) + N(0, sd), 0, 4095)).
/// Where gamma / d >= 1 the sensor is saturated: it reads max(0, noise), half the readings 0 and
/// half a few counts (sd 25: 1..60 or so), never the unclamped curve's thousands below 0.
std::string saturated_light_log(double gamma_m, double sd, const std::vector<double>& distances, int per, unsigned seed,
                                std::size_t* saturated_zero = nullptr, std::size_t* saturated_above = nullptr) {
  std::mt19937 rng(seed);
  std::normal_distribution<double> noise(0.0, sd);
  std::ostringstream os;
  os << "distance_m,intensity,sensor,value\n";
  std::size_t zero = 0, above = 0;
  for (double d : distances)
    for (int sensor = 0; sensor < 8; ++sensor)
      for (int k = 0; k < per; ++k) {
        const double r = gamma_m / d;
        const double physical = std::clamp(4095.0 * (1.0 - r * r), 0.0, 4095.0);
        const double reading = std::clamp(std::round(physical + noise(rng)), 0.0, 4095.0);
        if (physical == 0.0) (reading == 0.0 ? zero : above) += 1;
        os << d << ",1," << sensor << "," << reading << "\n";
      }
  if (saturated_zero) *saturated_zero = zero;
  if (saturated_above) *saturated_above = above;
  return os.str();
}

}  // namespace

TEST(HonestSaturation, ASaturatedPhototransistorsNoisyZerosDoNotBendGamma) {
  // gamma 0.09 m: saturated at 3..8 cm (gamma / d >= 1), read on its curve from 10 to 50 cm.
  const double gamma = 0.09;
  std::size_t zero = 0, above = 0;
  const std::string text = saturated_light_log(gamma, 25.0, {0.03, 0.04, 0.05, 0.06, 0.07, 0.08, 0.1, 0.12, 0.15, 0.2, 0.25, 0.3, 0.4, 0.5},
                                               5, 2111, &zero, &above);
  // The generator makes what a real saturated sensor gives: about half its saturated readings at
  // 0, half a few counts above.
  ASSERT_GT(zero, 80u);
  ASSERT_GT(above, 80u);
  const auto f = epuck2::calibrate::fit_light({logs::parse_log(text, "sat.csv", logs::Kind::light)});
  ASSERT_TRUE(f.gamma.usable) << f.gamma.message;
  EXPECT_NEAR(f.gamma.value("gamma"), gamma, 0.02 * gamma);
  // The diagnosis reads the same log with the same treatment: with gamma recalibrated, nothing is
  // wrong with this sensor, and the recalibrated gamma is the generator's.
  const dg::Report r = dg::diagnose({logs::parse_log(text, "sat.csv", logs::Kind::light)});
  ASSERT_TRUE(r.supported) << r.message;
  EXPECT_TRUE(r.findings.empty()) << r.findings.front().cause;
  ASSERT_EQ(r.recalibrated.size(), 1u);
  EXPECT_NEAR(r.recalibrated[0].value, gamma, 0.02 * gamma);
}

TEST(HonestSaturation, AProximitySensorSaturatedAtContactKeepsItsCurve) {
  // 4095 (300 d^2 - 35 d + 1.15): above full scale under 4.5 mm, so the sensor saturates there
  // and reads 4095 minus noise (sd 25), half the readings on the register's rail.
  auto truth = [](double d) { return 300 * d * d - 35 * d + 1.15; };
  std::mt19937 rng(2112);
  std::normal_distribution<double> noise(0.0, 25.0);
  std::ostringstream os;
  os << "distance_m,sensor,value\n";
  std::size_t below_rail = 0;
  for (double d : {0.001, 0.002, 0.003, 0.004, 0.006, 0.008, 0.01, 0.015, 0.02, 0.025, 0.03, 0.035, 0.04, 0.045, 0.05})
    for (int k = 0; k < 20; ++k) {
      const double physical = std::clamp(4095 * truth(d), 0.0, 4095.0);
      const double v = std::clamp(std::round(physical + noise(rng)), 0.0, 4095.0);
      if (physical == 4095.0 && v < 4095) ++below_rail;
      os << d << ",0," << v << "\n";
    }
  ASSERT_GT(below_rail, 30u);  // saturated readings under the rail, as a real sensor gives
  const auto f = epuck2::calibrate::fit_proximity({logs::parse_log(os.str(), "contact.csv", logs::Kind::proximity)});
  ASSERT_TRUE(f.means.usable) << f.means.message;
  EXPECT_NEAR(f.means.value("a"), 300.0, 0.02 * 300.0);
  EXPECT_NEAR(f.means.value("b"), -35.0, 0.02 * 35.0);
  EXPECT_NEAR(f.means.value("c"), 1.15, 0.02 * 1.15);
  const dg::Report r = dg::diagnose({logs::parse_log(os.str(), "contact.csv", logs::Kind::proximity)});
  ASSERT_TRUE(r.supported) << r.message;
  ASSERT_EQ(r.recalibrated.size(), 3u);
  EXPECT_NEAR(r.recalibrated[0].value, 300.0, 0.02 * 300.0);
  EXPECT_NEAR(r.recalibrated[1].value, -35.0, 0.02 * 35.0);
  EXPECT_NEAR(r.recalibrated[2].value, 1.15, 0.02 * 1.15);
  EXPECT_TRUE(r.findings.empty()) << r.findings.front().cause;
}

// ---- (3) left-out readings are shown as measured; the range is fitted ---------------------------

/// The plug-in's published curve to 50 mm (sd 5 counts, 20 readings a distance), then `beyond`
/// (distance, counts) pairs read the same way.
std::string curve_and_beyond(const std::vector<std::pair<double, double>>& beyond, unsigned seed) {
  std::mt19937 rng(seed);
  std::normal_distribution<double> noise(0.0, 5.0);
  std::ostringstream os;
  os << "distance_m,sensor,value\n";
  auto write = [&](double d, double counts) {
    for (int k = 0; k < 20; ++k) os << d << ",0," << std::clamp(std::round(counts + noise(rng)), 0.0, 4095.0) << "\n";
  };
  for (double d : {0.002, 0.005, 0.01, 0.015, 0.02, 0.025, 0.03, 0.035, 0.04, 0.045})
    write(d, 4095 * std::clamp(197.8633 * d * d - 30.47182 * d + 1.011635, 0.0, 1.0));
  for (const auto& [d, counts] : beyond) write(d, counts);
  return os.str();
}

TEST_F(HonestLackOfFit, ReadingsBeyondTheRangeAreShownAsMeasuredWithTheirReason) {
  // About 100 counts at 60 and 70 mm: beyond the model's 50 mm, still detected.
  const std::string log = write("beyond.csv", curve_and_beyond({{0.06, 100.0}, {0.07, 100.0}}, 2113));
  const CliRun r = run("proximity --json " + q(log));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const auto j = nlohmann::json::parse(r.out);
  std::size_t shown = 0;
  for (const auto& p : j["points"]) {
    if (p["distance_m"].get<double>() < 0.055) continue;
    ++shown;
    EXPECT_FALSE(p["used"].get<bool>());
    EXPECT_EQ(p["left_out_why"], "beyond the sensor's range (50 mm)");
    // The generator's 100 counts, within 4 standard errors of a mean of 20 (5 / sqrt 20 ~ 1.1).
    EXPECT_NEAR(p["mean"].get<double>() * 4095, 100.0, 4.5) << p.dump();
    EXPECT_GT(p["min"].get<double>() * 4095, 100.0 - 5 * 5.0) << p.dump();
    EXPECT_LT(p["max"].get<double>() * 4095, 100.0 + 5 * 5.0) << p.dump();
  }
  EXPECT_EQ(shown, 2u);
  // Detected at the farthest distance logged: the range is at least 70 mm, without an error.
  ASSERT_TRUE(j.contains("range_fit")) << j.dump();
  EXPECT_TRUE(j["range_fit"]["lower_bound"].get<bool>());
  EXPECT_DOUBLE_EQ(j["range_fit"]["value_m"].get<double>(), 0.07);
  EXPECT_FALSE(j["range_fit"].contains("std_error_m"));
  // The text report's table shows the same, never 0.0000.
  const CliRun t = run("proximity " + q(log));
  EXPECT_NE(t.out.find("    0.0600       20      0   0.02"), std::string::npos) << t.out;
  EXPECT_EQ(t.out.find("0.0000   0.0000   0.0000"), std::string::npos) << t.out;
}

TEST_F(HonestLackOfFit, TheRangeIsBracketedByTheLastDetectedDistanceAndTheNext) {
  // Detected at 60 mm (100 counts), nothing at 70 mm (0 counts): the range lies between them,
  // 65 mm with the uniform bracket's sd 10 / sqrt(12) = 2.887 mm.
  const std::string log = write("bracket.csv", curve_and_beyond({{0.06, 100.0}, {0.07, 0.0}}, 2114));
  const CliRun r = run("proximity --json " + q(log));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const auto j = nlohmann::json::parse(r.out);
  ASSERT_TRUE(j.contains("range_fit")) << j.dump();
  const auto& range = j["range_fit"];
  EXPECT_FALSE(range["lower_bound"].get<bool>());
  EXPECT_NEAR(range["value_m"].get<double>(), 0.065, 1e-12);
  EXPECT_NEAR(range["std_error_m"].get<double>(), 0.010 / std::sqrt(12.0), 1e-12);
  EXPECT_NEAR(range["detected_to_m"].get<double>(), 0.06, 1e-12);
  EXPECT_NEAR(range["undetected_from_m"].get<double>(), 0.07, 1e-12);
  const CliRun t = run("proximity " + q(log));
  EXPECT_NE(t.out.find("Range (where the readings stop being detected): 65.0 ± 2.9 mm, between 60 mm"), std::string::npos) << t.out;
}

// ---- (6) a sensor whose curve is exactly an exponential: the tail is found whole ----------------

/// Eight sensors, 5 readings each at 2..70 mm: round(amplitude exp(-d / length) + N(0, 5)),
/// clipped to the register's 0..4095.
std::string exponential_log(double amplitude, double length_m, const std::vector<double>& distances, unsigned seed) {
  std::mt19937 rng(seed);
  std::normal_distribution<double> noise(0.0, 5.0);
  std::ostringstream os;
  os << "distance_m,sensor,value\n";
  for (double d : distances)
    for (int sensor = 0; sensor < 8; ++sensor)
      for (int k = 0; k < 5; ++k)
        os << d << "," << sensor << "," << std::clamp(std::round(amplitude * std::exp(-d / length_m) + noise(rng)), 0.0, 4095.0) << "\n";
  return os.str();
}

TEST(HonestDiagnosis, AnExponentialCurveIsFoundWholeNotAsAPartialTail) {
  // 3900 exp(-d / 8 mm): the tail carries the whole response. From the registry's start alone the
  // fit stopped at a tail of 190 counts over 64 mm beside the quadratic (verdict "unexplained");
  // the generator's amplitude and length, within 2 %, are what the diagnosis must find, with
  // every effect and with long_tail alone. Within the range the tail is the whole curve: the
  // finding carries long_tail's formula, named near_field_curve (docs/diagnose.md).
  const std::string text = exponential_log(3900.0, 0.008, {0.002, 0.004, 0.006, 0.008, 0.01, 0.015, 0.02, 0.025, 0.03, 0.035, 0.04, 0.05, 0.06, 0.07}, 2115);
  dg::Options only_tail;
  only_tail.effects = {"long_tail"};
  for (const dg::Options& o : {dg::Options{}, only_tail}) {
    const dg::Report r = dg::diagnose({logs::parse_log(text, "exp.csv", logs::Kind::proximity)}, o);
    ASSERT_TRUE(r.supported) << r.message;
    ASSERT_EQ(r.findings.size(), 1u) << r.verdict_name();
    const dg::Finding& f = r.findings.front();
    EXPECT_EQ(f.effect, "long_tail");
    EXPECT_EQ(r.verdict_name(), f.cause);
    EXPECT_NE(r.verdict_name(), "saturation");
    ASSERT_EQ(f.parameters.size(), 2u);
    EXPECT_NEAR(f.parameters[0].value, 3900.0, 0.02 * 3900.0);
    EXPECT_NEAR(f.parameters[1].value, 0.008, 0.02 * 0.008);
  }
}

// ---- (6) two effects too weak alone, found together by the pair search -------------------------

/// One light of intensity 1 at 0.1..0.5 m (within the plug-in's 0.5 m range: no reading pins the
/// offset alone), 8 sensors, 5 readings each:
/// round(4095 (1 - (gamma / d)^exponent) - offset + N(0, 20)), clipped to 0..4095.
std::string falloff_and_offset_log(double gamma_m, double exponent, double offset, unsigned seed) {
  std::mt19937 rng(seed);
  std::normal_distribution<double> noise(0.0, 20.0);
  std::ostringstream os;
  os << "distance_m,intensity,sensor,value\n";
  for (double d : {0.1, 0.12, 0.15, 0.2, 0.25, 0.3, 0.4, 0.5})
    for (int sensor = 0; sensor < 8; ++sensor)
      for (int k = 0; k < 5; ++k)
        os << d << ",1," << sensor << ","
           << std::clamp(std::round(4095.0 * (1.0 - std::pow(gamma_m / d, exponent)) - offset + noise(rng)), 0.0, 4095.0) << "\n";
  return os.str();
}

TEST(HonestDiagnosis, TwoEffectsTooWeakAloneAreFoundTogetherByThePairSearch) {
  // A falloff exponent of 2.08 and an ambient offset of 26 counts: over 0.1..0.5 m the offset's
  // signature is mostly what gamma and the steeper falloff already bend the curve by, so that
  // with gamma refitted each alone barely moves the BIC (worked apart from the code, by a
  // linearised fit of the same formula: offset alone +3, exponent alone -2, both -61 on the
  // BIC; this log's trials: +5.4 and -5.6, neither past the margin of 10), while the two together
  // explain the misfit. The generator's exponent within 0.03 (3 standard errors of ~0.01) and
  // offset within 10 counts (3 of ~3.2).
  const std::string text = falloff_and_offset_log(0.075, 2.08, 26.0, 2117);
  dg::Options greedy;
  greedy.pair_search = false;
  const dg::Report alone = dg::diagnose({logs::parse_log(text, "pair.csv", logs::Kind::light)}, greedy);
  ASSERT_TRUE(alone.supported) << alone.message;
  // Without the pair search: no single passes, nothing is found.
  EXPECT_TRUE(alone.findings.empty()) << alone.findings.front().cause;
  for (const auto& t : alone.trials)
    if (t.cause == "ambient_offset" || t.cause == "falloff_exponent") EXPECT_GT(t.delta_bic, -10.0) << t.cause;
  const dg::Report r = dg::diagnose({logs::parse_log(text, "pair.csv", logs::Kind::light)});
  ASSERT_TRUE(r.supported) << r.message;
  ASSERT_EQ(r.findings.size(), 2u) << r.verdict_name();
  const dg::Finding* exponent = nullptr;
  const dg::Finding* offset = nullptr;
  for (const auto& f : r.findings) (f.cause == "falloff_exponent" ? exponent : offset) = &f;
  ASSERT_NE(exponent, nullptr);
  ASSERT_NE(offset, nullptr);
  EXPECT_EQ(offset->cause, "ambient_offset");
  EXPECT_EQ(exponent->accepted_with, "ambient_offset");
  EXPECT_EQ(offset->accepted_with, "falloff_exponent");
  EXPECT_LE(exponent->delta_bic, -10.0);
  EXPECT_EQ(exponent->delta_bic, offset->delta_bic);  // the pair's, counted for both
  ASSERT_EQ(exponent->parameters.size(), 1u);
  ASSERT_EQ(offset->parameters.size(), 1u);
  EXPECT_NEAR(exponent->parameters[0].value, 2.08, 0.03);
  EXPECT_NEAR(offset->parameters[0].value, 26.0, 10.0);
  // Gamma comes back too, within 2 %.
  ASSERT_EQ(r.final_base.size(), 1u);
  EXPECT_NEAR(r.final_base[0].value, 0.075, 0.02 * 0.075);
  // The pair in the order the search found it (the better single first).
  const std::string note = r.findings[0].cause + " and " + r.findings[1].cause +
                           " were accepted together (pair search): neither passed alone";
  bool said = false;
  for (const auto& n : r.notes) said = said || n.rfind(note, 0) == 0;
  EXPECT_TRUE(said) << (r.notes.empty() ? std::string("no note") : r.notes.front());
}

// ---- (4) a finding outside the physical range of its quantity is never written ------------------

TEST(HonestDiagnosis, ATailAboveFullScaleIsNotWrittenWithTheReason) {
  // 6000 exp(-d / 8 mm) from 4 mm on: the readings stay under 4095 (3639 at 4 mm), but the tail
  // that draws them reads 6000 counts at contact, above what the sensor can read.
  const std::string text = exponential_log(6000.0, 0.008, {0.004, 0.006, 0.008, 0.01, 0.015, 0.02, 0.025, 0.03, 0.035, 0.04, 0.05, 0.06, 0.07}, 2116);
  const dg::Report r = dg::diagnose({logs::parse_log(text, "big.csv", logs::Kind::proximity)});
  ASSERT_TRUE(r.supported) << r.message;
  EXPECT_TRUE(r.findings.empty()) << r.findings.front().cause;
  ASSERT_EQ(r.possible.size(), 1u);
  const dg::Finding& f = r.possible.front();
  EXPECT_EQ(f.effect, "long_tail");
  // The amplitude in the message is the fit's; the generator's 6000 within 1 % of it.
  ASSERT_EQ(f.parameters.size(), 2u);
  EXPECT_NEAR(f.parameters[0].value, 6000.0, 60.0);
  char amplitude[40];
  std::snprintf(amplitude, sizeof amplitude, "%.4g", f.parameters[0].value);
  const std::string why = std::string("amplitude = ") + amplitude +
                          " counts is above the sensor's full scale (4095 counts): outside the physical range of the quantity";
  EXPECT_EQ(f.undetermined, why);
  bool warned = false;
  for (const auto& w : r.warnings)
    warned = warned || w == "not written: " + f.cause + " (" + why + "); left out of the final and the extended model";
  EXPECT_TRUE(warned) << (r.warnings.empty() ? std::string("no warning") : r.warnings.back());
  // The extended model carries no tail.
  EXPECT_EQ(dg::extended_proximity(r).effects.tail.amplitude_raw, 0.0);
}

/// One light of intensity 1 at 8..16 cm, 8 sensors, 5 readings each:
/// round(4095 (1 - (gamma / d)^exponent) + N(0, 20)), clipped to 0..4095.
std::string steep_light_log(double gamma_m, double exponent, unsigned seed) {
  std::mt19937 rng(seed);
  std::normal_distribution<double> noise(0.0, 20.0);
  std::ostringstream os;
  os << "distance_m,intensity,sensor,value\n";
  for (double d : {0.08, 0.085, 0.09, 0.1, 0.11, 0.12, 0.14, 0.16})
    for (int sensor = 0; sensor < 8; ++sensor)
      for (int k = 0; k < 5; ++k)
        os << d << ",1," << sensor << ","
           << std::clamp(std::round(4095.0 * (1.0 - std::pow(gamma_m / d, exponent)) + noise(rng)), 0.0, 4095.0) << "\n";
  return os.str();
}

TEST(HonestDiagnosis, AFalloffPushedToTheEndOfItsPhysicalRangeIsNotWrittenWithTheReason) {
  // A falloff exponent of 11, beyond the registry's physical range (0.2..10): over 8..16 cm the
  // logs determine the exponent (the readings fall by a factor of 2^11 in intensity over a
  // doubling of the distance, which gamma cannot imitate), so the fit stops on the bound 10 with a
  // small standard error: the logs take it to the end of the range, not a calibration.
  const std::string text = steep_light_log(0.075, 11.0, 2118);
  dg::Options o;
  o.effects = {"falloff_exponent"};
  const dg::Report r = dg::diagnose({logs::parse_log(text, "steep.csv", logs::Kind::light)}, o);
  ASSERT_TRUE(r.supported) << r.message;
  EXPECT_TRUE(r.findings.empty()) << r.findings.front().cause;
  ASSERT_EQ(r.possible.size(), 1u);
  const dg::Finding& f = r.possible.front();
  EXPECT_EQ(f.cause, "falloff_exponent");
  EXPECT_TRUE(f.outside_physical_range);  // "not written", not "possible, not determined"
  ASSERT_EQ(f.parameters.size(), 1u);
  EXPECT_EQ(f.parameters[0].value, 10.0);  // the registry's upper bound
  ASSERT_TRUE(std::isfinite(f.parameters[0].std_error));
  EXPECT_LT(f.parameters[0].std_error, 1.0);  // determined: within 10 % of the bound
  char se[40];
  std::snprintf(se, sizeof se, "%.3g", f.parameters[0].std_error);
  const std::string why = std::string("exponent = 10 is on its bound 10, the end of its physical range (0.2 to 10), with a "
                                      "standard error of ") + se + ": the logs take it there, outside the physical range of the quantity";
  EXPECT_EQ(f.undetermined, why);
  bool warned = false;
  for (const auto& w : r.warnings)
    warned = warned || w == "not written: falloff_exponent (" + why + "); left out of the final and the extended model";
  EXPECT_TRUE(warned) << (r.warnings.empty() ? std::string("no warning") : r.warnings.front());
}

// ---- (5) a battery cubic that misses its replicates stops, as the sensor fits do ----------------

/// The RMS, over `u`, of f minus its least-squares cubic (4x4 normal equations solved here by
/// Gaussian elimination): the least any cubic can miss f by.
template <class F>
double best_cubic_miss(const std::vector<double>& u, F f) {
  double A[4][5] = {};
  for (double x : u) {
    const double p[4] = {1, x, x * x, x * x * x};
    for (int r = 0; r < 4; ++r) {
      for (int c = 0; c < 4; ++c) A[r][c] += p[r] * p[c];
      A[r][4] += p[r] * f(x);
    }
  }
  for (int k = 0; k < 4; ++k)
    for (int r = k + 1; r < 4; ++r) {
      const double m = A[r][k] / A[k][k];
      for (int c = k; c < 5; ++c) A[r][c] -= m * A[k][c];
    }
  double coef[4];
  for (int k = 3; k >= 0; --k) {
    double v = A[k][4];
    for (int c = k + 1; c < 4; ++c) v -= A[k][c] * coef[c];
    coef[k] = v / A[k][k];
  }
  double ss = 0;
  for (double x : u) {
    const double r = f(x) - (coef[0] + coef[1] * x + coef[2] * x * x + coef[3] * x * x * x);
    ss += r * r;
  }
  return std::sqrt(ss / static_cast<double>(u.size()));
}

TEST_F(HonestLackOfFit, ABatteryCubicThatMissesItsReplicatesStopsUnlessAccepted) {
  // Two runs at 5 cm/s on one clock (every 10 s to 3000 s): charge 1 - 0.3 u - 0.7 u^12
  // (u = t / 3000 s), a knee no cubic follows, read with noise sd 0.002.
  const double lifetime = 3000, sd = 0.002;
  auto truth = [](double u) { return 1 - 0.3 * u - 0.7 * std::pow(u, 12); };
  std::vector<double> u;
  for (int i = 0; i <= 300; ++i) u.push_back(i * 10.0 / lifetime);
  // The generator makes a misfit: its best cubic misses it by more than 10 replicate sd.
  ASSERT_GT(best_cubic_miss(u, truth), 10 * sd);
  std::mt19937 rng(2117);
  std::normal_distribution<double> noise(0.0, sd);
  std::vector<std::string> logs;
  for (const char* robot : {"a", "b"}) {
    std::ostringstream os;
    os << "# robot: " << robot << "\ntime_s,speed_cm_s,charge\n";
    for (double x : u) os << x * lifetime << ",5," << std::max(0.0, truth(x) + noise(rng)) << "\n";
    logs.push_back(q(write(std::string("knee_") + robot + ".csv", os.str())));
  }
  const std::string out = (dir_ / "knee.json").string();
  const CliRun r = run("battery -o " + q(out) + " " + logs[0] + " " + logs[1]);
  EXPECT_EQ(r.exit_code, 1) << r.out << r.err;
  EXPECT_NE(r.err.find("battery cubic at 5 cm/s: the curve misses its data by "), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("times the replicates' own sd (limit 10); worst: times "), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("Nothing was written; --accept-misfit writes it anyway."), std::string::npos) << r.err;
  EXPECT_FALSE(std::filesystem::exists(out));
  const CliRun a = run("battery --accept-misfit -o " + q(out) + " " + logs[0] + " " + logs[1]);
  EXPECT_EQ(a.exit_code, 0) << a.err;
  EXPECT_TRUE(std::filesystem::exists(out));
  EXPECT_NE(a.err.find("(accepted by --accept-misfit)."), std::string::npos) << a.err;

  // The same protocol on a cubic discharge passes: 1 - 0.5 u - 0.5 u^3.
  std::vector<std::string> fine;
  for (const char* robot : {"a", "b"}) {
    std::ostringstream os;
    os << "# robot: " << robot << "\ntime_s,speed_cm_s,charge\n";
    for (double x : u) os << x * lifetime << ",5," << std::max(0.0, 1 - 0.5 * x - 0.5 * x * x * x + noise(rng)) << "\n";
    fine.push_back(q(write(std::string("cubic_") + robot + ".csv", os.str())));
  }
  const CliRun c = run("battery " + fine[0] + " " + fine[1]);
  EXPECT_EQ(c.exit_code, 0) << c.err;
}
