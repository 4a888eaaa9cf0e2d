// Round 7 of the fresh slips (bench/fresh-slips.md, issue #22 item 6): for each slip the suite let
// through, a check whose expected value comes from outside the code under test -- worked by hand
// in the comments, computed another way (Eigen's Cholesky of J^T J for the QR's covariance), a
// unit's definition (3600 s an hour), a value the test itself gives (a field written and read
// back), or a documented boundary. File-local names carry the prefix r7 (one unity program).
#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <map>
#include <nlohmann/json.hpp>
#include <algorithm>
#include <random>
#include <sstream>
#include <string>
#include <vector>

#include <sys/wait.h>
#include <unistd.h>

#include "../lib/diagnose/src/engine_detail.hpp"
#include "cli_harness.hpp"
#include "epuck2/coefficients/battery_tables.hpp"
#include "epuck2/coefficients/codegen.hpp"
#include "epuck2/coefficients/model_file.hpp"
#include "epuck2/diagnose/diagnose.hpp"
#include "epuck2/fit/fit_curve.hpp"
#include "epuck2/fit/jet.hpp"
#include "epuck2/fit/least_squares.hpp"
#include "epuck2/fit/problem.hpp"
#include "epuck2/fit/readings.hpp"
#include "epuck2/logs/log.hpp"
#include "epuck2/models/battery.hpp"
#include "epuck2/models/kinds.hpp"
#include "epuck2/models/plugin_battery_tables.hpp"
#include "epuck2/models/simulate_log.hpp"

namespace {

namespace r7fs = std::filesystem;
using r7json = nlohmann::json;

// ----- helpers ------------------------------------------------------------------------------

/// A scratch folder of this test, emptied first.
r7fs::path r7_scratch(const std::string& name) {
  const r7fs::path p = r7fs::temp_directory_path() / ("epuck2_r7_" + name + "_" + std::to_string(::getpid()));
  r7fs::remove_all(p);
  r7fs::create_directories(p);
  return p;
}


/// Runs `args` (a shell command line after the CLI's path) from the source folder; its standard
/// output and error into files of `dir`; the exit code.
int r7_cli(const std::string& args, const r7fs::path& dir, std::string* out = nullptr, std::string* err = nullptr,
           const std::string& stdout_to = "") {
  const r7fs::path o = dir / "stdout.txt", e = dir / "stderr.txt";
  const std::string cmd = "cd '" + std::string(EPUCK2_SOURCE_DIR) + "' && '" + std::string(EPUCK2_FIT_EXE) + "' " + args + " > " +
                          (stdout_to.empty() ? "'" + o.string() + "'" : stdout_to) + " 2> '" + e.string() + "'";
  const int status = std::system(cmd.c_str());
  if (out) *out = epuck2::testing::slurp(o);
  if (err) *err = epuck2::testing::slurp(e);
  return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

// ----- lib/fit ---------------------------------------------------------------------------------

// (J^T J)^-1 from the equilibrated, column-pivoted QR against the same matrix by Eigen's Cholesky
// of J^T J (another factorization of another matrix): random Jacobians whose columns differ in
// scale by up to 1e3, so that the QR pivots them in every order, 3-cycles included.
TEST(RoundSevenCovariance, InverseNormalMatrixIsTheInverseOfJtJ) {
  std::mt19937 rng(7);
  std::normal_distribution<double> g(0.0, 1.0);
  int cyclic = 0;
  for (int trial = 0; trial < 40; ++trial) {
    Eigen::MatrixXd J(12, 4);
    for (int r = 0; r < J.rows(); ++r)
      for (int c = 0; c < J.cols(); ++c) J(r, c) = g(rng);
    const double scales[4] = {1.0, 1e3, 0.01, 30.0};
    for (int c = 0; c < 4; ++c) J.col(c) *= scales[(c + trial) % 4];
    Eigen::MatrixXd inv;
    ASSERT_TRUE(epuck2::fit::inverse_normal_matrix(J, &inv));
    const Eigen::MatrixXd N = J.transpose() * J;
    const Eigen::MatrixXd expected = N.llt().solve(Eigen::MatrixXd::Identity(4, 4));
    for (int a = 0; a < 4; ++a)
      for (int b = 0; b < 4; ++b)
        EXPECT_NEAR(inv(a, b), expected(a, b), 1e-8 * std::sqrt(expected(a, a) * expected(b, b))) << trial << ": " << a << "," << b;
    // The power of the check: a permutation that is not its own inverse (P != P^T).
    Eigen::MatrixXd Jn = J;
    for (int c = 0; c < 4; ++c) Jn.col(c) /= J.col(c).norm();
    const Eigen::ColPivHouseholderQR<Eigen::MatrixXd> qr(Jn);
    const Eigen::MatrixXd P = qr.colsPermutation();
    if (!(P - P.transpose()).isZero()) ++cyclic;
  }
  EXPECT_GT(cyclic, 0) << "no trial pivoted the columns in a cycle: the check could not tell P from P^T";
}

// d/dx erfc(x) = -2/sqrt(pi) exp(-x^2): at 0.5, -1.1283792 x 0.7788008 = -0.8787826; at -1.2,
// -1.1283792 x 0.2369278 = -0.2673443 (negative everywhere: erfc falls).
TEST(RoundSevenJet, ErfcFallsWithTheGaussiansSlope) {
  using J = epuck2::fit::Jet<1>;
  using std::erfc;  // the Jet's own by argument-dependent lookup
  const J a = erfc(J(0.5, 0));
  EXPECT_NEAR(a.a, 0.4795001222, 1e-9);
  EXPECT_NEAR(a.v[0], -0.8787825789, 1e-9);
  const J b = erfc(J(-1.2, 0));
  EXPECT_NEAR(b.a, 1.9103139782, 1e-9);
  EXPECT_NEAR(b.v[0], -0.2673443470, 1e-9);
}

// Channel weights (docs/fitting.md): channel c's residual is sd_0 / sd_c times its error, in
// channel 0's units. ToF sd 3 mm, encoders 0.3 steps: an encoder reading 0.6 steps above the
// prediction is 2 of its sd, 6 mm in the ToF's units; a ToF reading 1.5 mm below is -1.5.
TEST(RoundSevenChannels, ASecondChannelsResidualIsInTheFirstChannelsUnits) {
  epuck2::fit::Channel tof, enc;
  tof.noise_sd = 3.0;
  enc.noise_sd = 0.3;
  const epuck2::fit::Channels ch({tof, enc});
  EXPECT_NEAR(ch.residual(100.0, 100.6, 1).value, 6.0, 1e-12);
  EXPECT_NEAR(ch.residual(100.0, 98.5, 0).value, -1.5, 1e-12);
  EXPECT_NEAR(ch.residual(100.0, 100.6, 1).d_prediction, -10.0, 1e-12);
  EXPECT_NEAR(ch.weight(1), 10.0, 1e-12);
}

struct R7Line {
  static constexpr int kParameters = 2;
  template <class T>
  T operator()(const T* p, double x) const {
    return p[0] * x + p[1];
  }
};

// The active set: y = 2 x + 1 at x = 1..5 with the slope bounded above by 1.5 ends on that bound,
// held there, and the intercept refitted with the slope at 1.5: the mean of y - 1.5 x = 0.5 x + 1,
// 0.5 x 3 + 1 = 2.5. The slope has no standard error (it sits on a bound).
TEST(RoundSevenActiveSet, ASlopeEndingOnItsUpperBoundIsHeldThereAndTheRestRefitted) {
  const std::vector<double> x{1, 2, 3, 4, 5};
  std::vector<double> y;
  for (double v : x) y.push_back(2 * v + 1);
  std::vector<epuck2::fit::Parameter> p{epuck2::fit::free_parameter("slope", 0.5), epuck2::fit::free_parameter("intercept", 0.0)};
  p[0].lower = 0.0;
  p[0].upper = 1.5;
  const epuck2::fit::FitResult r = epuck2::fit::fit_curve(R7Line{}, x, y, p);
  ASSERT_TRUE(r.usable) << r.message;
  EXPECT_EQ(r.value("slope"), 1.5);
  EXPECT_NEAR(r.value("intercept"), 2.5, 1e-9);
  EXPECT_TRUE(std::isnan(r.std_error("slope")));
}

struct R7Pull {
  template <class T>
  bool operator()(const T* p, T* r) const {
    r[0] = p[0] - T(0.0);  // pulls the parameter to 0
    return true;
  }
};

// fit::Problem's lower bound: a residual p - 0 with p >= 1, from 3, ends at 1 (the bound), not at
// 0 and not stuck at the start.
TEST(RoundSevenProblem, ALowerBoundHoldsAParameterAboveIt) {
  double p[1] = {3.0};
  epuck2::fit::Problem problem;
  problem.add(epuck2::fit::autodiff<1, 1>(R7Pull{}), {p});
  problem.set_lower_bound(p, 0, 1.0);
  const epuck2::fit::SolveSummary s = problem.solve(epuck2::fit::FitOptions{});
  ASSERT_TRUE(s.usable) << s.message;
  EXPECT_NEAR(p[0], 1.0, 1e-9);
}

// ----- lib/coefficients ------------------------------------------------------------------------

// A proximity calibration's file: the maxima's curve under a, b, c and the means' under mean_a,
// mean_b, mean_c, each from its own model (values the test gives, all different).
TEST(RoundSevenModelFile, ProximityMeansCurveIsWrittenFromTheMeansModel) {
  namespace s = epuck2::models::sensors;
  s::ProximityModel maxima, means;
  maxima.base = {197.8633, -30.47182, 1.011635, 0.05};
  means.base = {150.25, -21.5, 0.75, 0.05};
  const r7json j = epuck2::coefficients::calibration_model_json(maxima, means, epuck2::coefficients::CalibrationExtras{});
  EXPECT_EQ(j["parameters"]["c"].get<double>(), 1.011635);
  EXPECT_EQ(j["parameters"]["mean_a"].get<double>(), 150.25);
  EXPECT_EQ(j["parameters"]["mean_b"].get<double>(), -21.5);
  EXPECT_EQ(j["parameters"]["mean_c"].get<double>(), 0.75);
  const s::ProximityModel back =
      epuck2::coefficients::proximity_model_from_json(j, "r7", "", epuck2::coefficients::ProximityCurve::means);
  EXPECT_EQ(back.base.c, 0.75);
}

// The battery tables' writer: every Approximated segment of the plug-in's published tables
// (plugin_battery_tables.hpp, the paper's numbers) written with its own y1 and y2.
TEST(RoundSevenBatteryTables, EverySegmentIsWrittenWithItsOwnBand) {
  namespace mb = epuck2::models::battery;
  const mb::Tables t = mb::plugin_tables();
  int differing = 0;
  for (int s = 0; s < mb::kSpeedCount; ++s) {
    const auto su = static_cast<std::size_t>(s);
    const r7json e = epuck2::coefficients::battery_speed_to_json(s, t.cubic[su], t.linear_slope_per_s[su], t.segments[su]);
    for (std::size_t k = 0; k < mb::kSegmentCount; ++k) {
      const mb::Segment& g = t.segments[su][k];
      EXPECT_EQ(e["segments"][k]["y1"].get<double>(), g.y1) << s << " cm/s, segment " << k;
      EXPECT_EQ(e["segments"][k]["y2"].get<double>(), g.y2) << s << " cm/s, segment " << k;
      EXPECT_EQ(e["segments"][k]["x1_s"].get<double>(), g.x1_s);
      EXPECT_EQ(e["segments"][k]["x2_s"].get<double>(), g.x2_s);
      differing += g.y1 != g.y2 ? 1 : 0;
    }
  }
  EXPECT_GT(differing, 0) << "every segment's band has y1 == y2: the check has no power";
}

/// The number after `key` in generated C++ ("  m.base.range_m = 2.5;"), NaN when absent.
double r7_cpp_value(const std::string& cpp, const std::string& key) {
  const std::size_t at = cpp.find(key + " = ");
  if (at == std::string::npos) return std::nan("");
  return std::strtod(cpp.c_str() + at + key.size() + 3, nullptr);
}

// codegen: a camera's range other than the default (2.5 m here) is in the header, so that the
// generated camera_model() sees as far as the file says.
TEST(RoundSevenCodegen, ACameraRangeOtherThanTheDefaultIsWritten) {
  namespace s = epuck2::models::sensors;
  s::CameraModel m;
  ASSERT_NE(m.base.range_m, 2.5);
  m.base.range_m = 2.5;
  const std::string cpp = epuck2::coefficients::model_to_cpp(m, "r7");
  EXPECT_EQ(r7_cpp_value(cpp, "m.base.range_m"), 2.5) << cpp;
}

// ----- lib/models ------------------------------------------------------------------------------

// The light's per-sensor gammas: sensor 2's own 0.12 m over the pooled 0.1 m is 1.2; a sensor
// without its own has ratio 1. The pooled gamma recalibrated to 0.05 m moves sensor 2's to
// 0.05 x 1.2 = 0.06 m and leaves the others on the pooled one.
TEST(RoundSevenLightGammas, EachSensorsRatioToThePooledGammaIsKeptWhenItMoves) {
  namespace s = epuck2::models::sensors;
  s::LightModel m;
  m.base.gamma_m = 0.1;
  m.sensor_gamma_m[2] = 0.12;
  EXPECT_NEAR(s::light_gamma_ratio(m, 2), 1.2, 1e-15);
  EXPECT_EQ(s::light_gamma_ratio(m, 0), 1.0);
  const s::LightModel moved = s::with_pooled_gamma(m, 0.05);
  EXPECT_NEAR(s::light_gamma_m(moved, 2), 0.06, 1e-15);
  EXPECT_EQ(s::light_gamma_m(moved, 0), 0.05);
}

// The effect registry: a proximity model's long tail (amplitude 300 counts, length 0.05 m) is
// written under long_tail's two keys and read back as it was.
TEST(RoundSevenEffects, LongTailsAmplitudeAndLengthKeepTheirOwnKeys) {
  namespace s = epuck2::models::sensors;
  s::ProximityModel m;
  m.effects.tail.amplitude_raw = 300.0;
  m.effects.tail.length_m = 0.05;
  const r7json j = epuck2::coefficients::model_to_json(m);
  EXPECT_EQ(j["effects"]["long_tail"]["amplitude"].get<double>(), 300.0) << j.dump();
  EXPECT_EQ(j["effects"]["long_tail"]["length_m"].get<double>(), 0.05) << j.dump();
  const s::ProximityModel back = epuck2::coefficients::proximity_model_from_json(j, "r7");
  EXPECT_EQ(back.effects.tail.amplitude_raw, 300.0);
  EXPECT_EQ(back.effects.tail.length_m, 0.05);
}

/// A drive log's conditions, as simulated_readings reads a log.
struct R7DriveLog {
  std::map<std::string, std::vector<double>> c;
  double obstacle_m = 1.0;
  bool has(const std::string& k) const { return c.count(k) != 0; }
  const std::vector<double>& col(const std::string& k) const { return c.at(k); }
  std::size_t rows() const { return c.at("time_s").size(); }
  double metadata_number(const std::string&) const { return obstacle_m; }
};

struct R7ZeroNormal {
  double operator()() { return 0.0; }
};

// simulate drive --like with noise (every draw 0 here, so the readings are the model's own): 2 s
// with the left wheel commanded 10 cm/s and the right 0 turn the left encoder by at most
// 0.2 m x 7763.656 steps/m = 1552.7 steps (at least 0.7 of it after the acceleration), and the
// right not at all; left_steps first.
TEST(RoundSevenSimulateLike, WithNoiseOnlyTheCommandedLeftWheelTurns) {
  namespace s = epuck2::models::sensors;
  R7DriveLog log;
  for (int i = 0; i <= 20; ++i) {
    log.c["time_s"].push_back(0.1 * i);
    log.c["left_speed_cm_s"].push_back(10.0);
    log.c["right_speed_cm_s"].push_back(0.0);
  }
  s::DriveModel m;
  R7ZeroNormal normal;
  const std::vector<double> cov(log.rows(), 0.0);
  const auto out = s::simulated_readings(m, log, cov, true, normal);
  ASSERT_EQ(out.size(), log.rows());
  EXPECT_GE(out.back()[0], 0.7 * 1552.7);
  EXPECT_LE(out.back()[0], 1.05 * 1552.7);
  EXPECT_EQ(out.back()[1], 0.0);
}

// ----- lib/diagnose ----------------------------------------------------------------------------

/// A ground log written by hand: 3 sensors with their own line (offsets 40, 25, 15; gains 900,
/// 950, 1000) over 21 grey levels 0, 0.05 .. 1, `replicates` readings each with the deviations
/// +2, -2, +1, -1, +3, -3 (mean 0, sd sqrt(28/6)); with `exponent` the grey level raised to it
/// (the catalogue's nonlinear_response). Rows dealt in a seeded shuffle, so that any prefix holds
/// every sensor and grey level.
std::string r7_ground_log(int replicates, double exponent, unsigned seed) {
  const double offset[3] = {40, 25, 15}, gain[3] = {900, 950, 1000};
  const double dev[6] = {2, -2, 1, -1, 3, -3};
  std::vector<std::string> rows;
  for (int s = 0; s < 3; ++s)
    for (int k = 0; k <= 20; ++k)
      for (int r = 0; r < replicates; ++r) {
        const double grey = 0.05 * k;
        const double v = std::round(offset[s] + gain[s] * std::pow(grey, exponent)) + dev[r % 6];
        std::ostringstream row;
        row << grey << "," << s << "," << v;
        rows.push_back(row.str());
      }
  std::mt19937 rng(seed);
  std::shuffle(rows.begin(), rows.end(), rng);
  std::string text = "grey,sensor,value\n";
  for (const std::string& r : rows) text += r + "\n";
  return text;
}

/// The first `n` rows of a log's text (its header kept).
std::string r7_first_rows(const std::string& text, std::size_t n) {
  std::istringstream in(text);
  std::string line, out;
  std::getline(in, line);
  out = line + "\n";
  for (std::size_t i = 0; i < n && std::getline(in, line); ++i) out += line + "\n";
  return out;
}

// The diagnosis says it needs "at least" minimum_rows rows: a log of exactly that many is
// judged, one row fewer is not.
TEST(RoundSevenDiagnosis, ALogOfExactlyTheMinimumRowsIsJudged) {
  namespace d = epuck2::diagnose;
  const std::string text = r7_ground_log(6, 1.0, 7);
  d::Options o;
  o.effects = {"nonlinear_response"};
  const d::Report all = d::diagnose({epuck2::logs::parse_log(text, "r7.csv", epuck2::logs::Kind::ground)}, o);
  ASSERT_FALSE(all.too_few_rows) << all.message;
  const std::size_t m = all.minimum_rows;
  ASSERT_GT(m, 10u);
  ASSERT_LT(m, 378u);
  const d::Report exactly = d::diagnose({epuck2::logs::parse_log(r7_first_rows(text, m), "r7.csv", epuck2::logs::Kind::ground)}, o);
  EXPECT_EQ(exactly.rows, m);
  EXPECT_FALSE(exactly.too_few_rows) << m << " rows: " << exactly.message;
  EXPECT_NE(exactly.verdict, d::Verdict::not_judged);
  const d::Report fewer = d::diagnose({epuck2::logs::parse_log(r7_first_rows(text, m - 1), "r7.csv", epuck2::logs::Kind::ground)}, o);
  EXPECT_TRUE(fewer.too_few_rows);
}

// The residual structure's size is the RMS of the binned means about the mean: residuals -3 +- 1
// over x = 0 and +3 +- 1 over x = 1 (50 each) have binned means -3 and 3, between-bins sum 900
// of a total 1000: score 0.9, size sqrt(900 / 100) = 3 (in the residuals' units).
TEST(RoundSevenResidualStructure, SizeIsTheRootMeanSquareOfTheBinnedMeans) {
  std::vector<double> x, r;
  for (int i = 0; i < 100; ++i) {
    x.push_back(i < 50 ? 0.0 : 1.0);
    r.push_back((i < 50 ? -3.0 : 3.0) + (i % 2 ? 1.0 : -1.0));
  }
  const epuck2::diagnose::CovariateScore s = epuck2::diagnose::engine_detail::score_covariate("x", x, r, 0.03);
  EXPECT_NEAR(s.score, 0.9, 1e-12);
  EXPECT_NEAR(s.size, 3.0, 1e-12);
  EXPECT_TRUE(s.significant);
}

// The diagnosis file's fit.final is the fit with the findings: a ground log whose readings follow
// the grey level to the power 1.6 is found nonlinear; the final fit then has one parameter more
// than the recalibrated one (the exponent) and an MSE near the readings' own noise, 28/6 = 4.67
// counts^2, where the recalibrated straight line misses by far more.
TEST(RoundSevenDiagnosisReport, FinalFitIsTheFitWithTheFindings) {
  const r7fs::path dir = r7_scratch("final");
  {
    std::ofstream f(dir / "ground.csv");
    f << r7_ground_log(6, 1.6, 11);
  }
  std::string out;
  ASSERT_EQ(r7_cli("diagnose '" + (dir / "ground.csv").string() + "' --json", dir, &out), 0) << epuck2::testing::slurp(dir / "stderr.txt");
  const r7json j = r7json::parse(out);
  ASSERT_FALSE(j["findings"].empty()) << out;
  const r7json& rec = j["fit"]["recalibrated"];
  const r7json& fin = j["fit"]["final"];
  EXPECT_GT(fin["free_parameters"].get<int>(), rec["free_parameters"].get<int>());
  EXPECT_GT(fin["mse"].get<double>(), 0.5 * 28.0 / 6.0);
  EXPECT_LT(fin["mse"].get<double>(), 2.0 * 28.0 / 6.0);
  EXPECT_GT(rec["mse"].get<double>(), 4.0 * fin["mse"].get<double>());
  r7fs::remove_all(dir);
}

// ----- lib/calibrate (through the binary) ------------------------------------------------------

// The battery file's lifetime in hours is its lifetime in seconds over 3600 at every speed.
TEST(RoundSevenReports, BatteryLifetimeInHoursIsSecondsOver3600) {
  const r7fs::path dir = r7_scratch("battery");
  ASSERT_EQ(r7_cli("battery data/raw/battery/*.csv -o '" + (dir / "b.json").string() + "'", dir), 0) << epuck2::testing::slurp(dir / "stderr.txt");
  const r7json j = r7json::parse(epuck2::testing::slurp(dir / "b.json"));
  ASSERT_FALSE(j["speeds"].empty());
  for (const r7json& s : j["speeds"]) {
    const double sec = s["lifetime_s"].get<double>();
    ASSERT_GT(sec, 3600.0);
    EXPECT_NEAR(s["lifetime_h"].get<double>(), sec / 3600.0, 1e-12 * sec) << s["speed_cm_s"];
  }
  r7fs::remove_all(dir);
}

// The camera file's aperture error follows the field of view's through the derivative of
// A(f) = atan(k tan(f / 2)), k = sqrt(160^2 + 120^2) / 160 = 1.25 (ARGoS's half-angle on the
// diagonal): dA/df = (k / 2) sec^2(f / 2) / (1 + k^2 tan^2(f / 2)), degrees over degrees.
TEST(RoundSevenReports, CameraApertureErrorIsTheFieldOfViewsThroughItsDerivative) {
  const r7fs::path dir = r7_scratch("camera");
  ASSERT_EQ(r7_cli("camera data/raw/camera/*.csv -o '" + (dir / "c.json").string() + "'", dir), 0) << epuck2::testing::slurp(dir / "stderr.txt");
  const r7json j = r7json::parse(epuck2::testing::slurp(dir / "c.json"));
  const double pi = std::acos(-1.0);
  const double f = j["parameters"]["fov_deg"].get<double>() * pi / 180.0;
  const double se_f = j["std_errors"]["fov_deg"].get<double>();
  ASSERT_GT(se_f, 0.0);
  const double k = 1.25, t = std::tan(f / 2);
  const double slope = (k / 2) / (std::cos(f / 2) * std::cos(f / 2)) / (1 + k * k * t * t);
  EXPECT_NEAR(j["std_errors"]["aperture_deg"].get<double>(), slope * se_f, 1e-6 * slope * se_f);
  EXPECT_NEAR(j["parameters"]["aperture_deg"].get<double>(), std::atan(k * t) * 180.0 / pi, 1e-9);
  r7fs::remove_all(dir);
}

// ----- lib/logs, apps --------------------------------------------------------------------------

// docs/logs.md: time never decreases; two rows at the same time are a log (a battery log sampled
// twice in one second).
TEST(RoundSevenLogReader, TwoRowsAtTheSameTimeAreRead) {
  const epuck2::logs::Log log = epuck2::logs::parse_log("time_s,speed_cm_s,charge\n0,5,1\n1,5,0.99\n1,5,0.985\n2,5,0.98\n", "r7.csv",
                                                        epuck2::logs::Kind::battery);
  EXPECT_EQ(log.rows(), 4u);
  EXPECT_THROW(epuck2::logs::parse_log("time_s,speed_cm_s,charge\n0,5,1\n1,5,0.99\n0.5,5,0.985\n", "r7.csv",
                                       epuck2::logs::Kind::battery),
               epuck2::logs::InputError);
}

// --effects takes a list: two ground effects between a comma are searched, each by its name.
TEST(RoundSevenCli, EffectsListNamesEachEffectWhole) {
  const r7fs::path dir = r7_scratch("effects");
  std::string out;
  ASSERT_EQ(r7_cli("diagnose data/raw/ground/ground_virtual-epuck2-1.csv --effects black_offset,white_level --json", dir, &out), 0)
      << epuck2::testing::slurp(dir / "stderr.txt");
  const r7json j = r7json::parse(out);
  EXPECT_EQ(j["effects_considered"], r7json({"black_offset", "white_level"})) << j["effects_considered"].dump();
  r7fs::remove_all(dir);
}

// A full disk under standard output: exit 2 with the reason the system gave (ENOSPC).
TEST(RoundSevenCli, StandardOutputOnAFullDiskNamesNoSpace) {
  if (!r7fs::exists("/dev/full")) GTEST_SKIP() << "no /dev/full";
  const r7fs::path dir = r7_scratch("full");
  std::string err;
  EXPECT_EQ(r7_cli("table5 data/raw/battery/*.csv", dir, nullptr, &err, "/dev/full"), 2);
  EXPECT_NE(err.find("standard output: No space left on device"), std::string::npos) << err;
  r7fs::remove_all(dir);
}

}  // namespace
