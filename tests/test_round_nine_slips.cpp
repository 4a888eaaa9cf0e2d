// Round 9 of the fresh slips (bench/fresh-slips.md, "Round 9"): for each area a slip of that round
// hit, a test whose expected value comes from outside the code under test -- worked by hand in
// the comment, computed here independently, or read from the docs -- at the boundary the code
// branches on where there is one. Written from the library headers and docs/ while the run that
// judged the slips went on from its own copy.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <sstream>
#include <string>
#include <vector>

#include <sys/wait.h>
#include <unistd.h>

#include <Eigen/Dense>
#include <nlohmann/json.hpp>

#include "epuck2/calibrate/battery.hpp"
#include "epuck2/coefficients/codegen.hpp"
#include "epuck2/coefficients/model_file.hpp"
#include "epuck2/fit/least_squares.hpp"
#include "epuck2/fit/report.hpp"
#include "epuck2/fit/robust.hpp"
#include "epuck2/logs/log.hpp"
#include "epuck2/models/camera.hpp"
#include "epuck2/models/kinds.hpp"
#include "epuck2/models/noise.hpp"
#include "epuck2/models/simulate_log.hpp"

// The whole file in its own namespace: the unity build puts it beside the other test files.
namespace test_round_nine_slips_cpp {
namespace {

namespace fs = std::filesystem;
namespace s = epuck2::models::sensors;
namespace fit = epuck2::fit;
namespace logs = epuck2::logs;
namespace ec = epuck2::coefficients;
using nlohmann::json;

std::string r9_read(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  return std::string(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
}

void r9_write(const fs::path& p, const std::string& text) {
  std::ofstream out(p, std::ios::binary);
  out << text;
}

fs::path r9_scratch(const std::string& name) {
  const fs::path d = fs::temp_directory_path() / ("epuck2_r9_" + name + "_" + std::to_string(::getpid()));
  fs::remove_all(d);
  fs::create_directories(d);
  return d;
}

/// The CLI's exit status, its standard output in `out`.
int r9_run(const std::string& args, const fs::path& out) {
  const std::string cmd = std::string("'") + EPUCK2_FIT_EXE + "' " + args + " > '" + out.string() + "' 2>/dev/null";
  const int status = std::system(cmd.c_str());
  return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

// ---- lib/fit ------------------------------------------------------------------------------------

// J = [[1, 1], [0, d]]: its columns equilibrated are u = (1, 0) and v = (1, d)/sqrt(1 + d^2), whose
// Gram matrix [[1, c], [c, 1]] (c = 1/sqrt(1 + d^2)) has eigenvalues 1 + c and 1 - c: the normal
// matrix's condition number is (1 + c)/(1 - c), about 4/d^2 = 4e6 at d = 1e-3 (J's own is its
// square root, about 2e3). With max_condition 1e6 the two columns are undetermined by the
// condition; with 1e7 they are determined.
TEST(RoundNineIdentifiability, TheConditionIsTheNormalMatrixsNotTheJacobians) {
  const double d = 1e-3;
  Eigen::MatrixXd J(2, 2);
  J << 1, 1, 0, d;
  const double root = std::sqrt(1 + d * d);
  const double c = 1 / root;
  const double one_minus_c = d * d / ((root + 1) * root);  // 1 - c without cancellation
  const double expected = (1 + c) / one_minus_c;
  ASSERT_NEAR(expected, 4e6, 10.0);  // 4/d^2 + 2 + O(d^2)
  const fit::Identifiability weak = fit::check_identifiability(J, {}, 1e6);
  EXPECT_NEAR(weak.condition, expected, 1e-6 * expected);
  EXPECT_FALSE(weak.determined());
  EXPECT_TRUE(weak.any(fit::Identifiability::Why::condition));
  const fit::Identifiability fine = fit::check_identifiability(J, {}, 1e7);
  EXPECT_TRUE(fine.determined());
  EXPECT_NEAR(fine.condition, expected, 1e-6 * expected);
}

// Two significant digits of the error: 0.0996 rounds to 0.10 (not 0.100); 0.0994 is 0.099. The
// value follows the error's last digit: 1.234 ± 0.0996 is "1.23 ± 0.10".
TEST(RoundNineRounding, AnErrorThatRoundsUpToADecadeKeepsTwoDigits) {
  EXPECT_EQ(fit::format_error(0.0996), "0.10");
  EXPECT_EQ(fit::format_error(0.0994), "0.099");
  EXPECT_EQ(fit::format_error(99.6), "100");
  EXPECT_EQ(fit::format_uncertain(1.234, 0.0996), "1.23 ± 0.10");
  EXPECT_EQ(fit::format_uncertain(1.234, 0.0994), "1.234 ± 0.099");
}

// A covariance [[1, -0.9], [-0.9, 1]]: the correlation -0.9 is strong and listed (|r| > 0.1);
// [[4, 0.1], [0.1, 1]] gives 0.05, not listed; [[4, -1], [-1, 1]] gives -0.5.
TEST(RoundNineCorrelations, NegativeCorrelationsAreListedByTheirSize) {
  fit::FitResult r;
  r.parameters = {{"a", 1.0, 1.0}, {"b", 2.0, 1.0}};
  r.covariance = Eigen::MatrixXd(2, 2);
  r.covariance << 1, -0.9, -0.9, 1;
  auto c = fit::correlations(r);
  ASSERT_EQ(c.size(), 1u);
  EXPECT_EQ(c[0].a, "a");
  EXPECT_EQ(c[0].b, "b");
  EXPECT_NEAR(c[0].r, -0.9, 1e-15);
  r.covariance << 4, 0.1, 0.1, 1;
  EXPECT_TRUE(fit::correlations(r).empty());
  r.covariance << 4, -1, -1, 1;
  c = fit::correlations(r);
  ASSERT_EQ(c.size(), 1u);
  EXPECT_NEAR(c[0].r, -0.5, 1e-15);
}

// Three groups of two replicates, (1, 3), (2, 4), (5, 7), predicted at their means 2, 3, 6: the
// pure error is 2 + 2 + 2 = 6 on 6 - 3 = 3 degrees of freedom, replicate sd sqrt(2); no lack of
// fit (the residuals are the pure error), on 3 - 1 = 2 degrees of freedom for one parameter.
TEST(RoundNineLackOfFit, PureErrorHasReadingsLessGroupsDegreesOfFreedom) {
  std::vector<fit::ReplicateGroup> groups(3);
  const double readings[3][2] = {{1, 3}, {2, 4}, {5, 7}};
  const double means[3] = {2, 3, 6};
  for (int g = 0; g < 3; ++g) {
    groups[static_cast<std::size_t>(g)].readings = {readings[g][0], readings[g][1]};
    groups[static_cast<std::size_t>(g)].predictions = {means[g], means[g]};
    groups[static_cast<std::size_t>(g)].condition = g;
  }
  const fit::LackOfFit lof = fit::lack_of_fit(groups, 1);
  ASSERT_TRUE(lof.tested) << lof.why_not;
  EXPECT_EQ(lof.groups, 3u);
  EXPECT_EQ(lof.dof_pure, 3u);
  EXPECT_EQ(lof.dof_lack, 2u);
  EXPECT_NEAR(lof.replicate_sd, std::sqrt(2.0), 1e-12);
  EXPECT_NEAR(lof.misfit_rms, 0.0, 1e-12);
}

// ---- lib/coefficients --------------------------------------------------------------------------

// docs/coefficient-files.md: `per_sensor` holds one entry per light sensor. Sensor 3 twice is
// refused at the second entry; sensors 3 and 4 read back as written.
TEST(RoundNineModelFile, ALightSensorListedTwiceIsRefused) {
  s::LightModel m;
  m.sensor_gamma_m[3] = 0.1;
  m.sensor_gamma_m[4] = 0.12;
  json j = ec::model_to_json(m);
  const s::LightModel back = ec::light_model_from_json(j, "light.json");
  ASSERT_TRUE(back.sensor_gamma_m[3].has_value());
  ASSERT_TRUE(back.sensor_gamma_m[4].has_value());
  EXPECT_EQ(*back.sensor_gamma_m[3], 0.1);
  EXPECT_EQ(*back.sensor_gamma_m[4], 0.12);
  ASSERT_EQ(j.at("per_sensor").size(), 2u);
  j["per_sensor"][1]["sensor"] = 3;
  try {
    (void)ec::light_model_from_json(j, "light.json");
    ADD_FAILURE() << "a per_sensor list with sensor 3 twice was read";
  } catch (const logs::InputError& e) {
    EXPECT_NE(std::string(e.what()).find("/per_sensor/1"), std::string::npos) << e.what();
  }
}

// docs/coefficient-files.md: the camera's range_m is positive (a range of 0 is a blind camera,
// issue #22); 0.5 reads back as 0.5.
TEST(RoundNineModelFile, ACameraRangeOfZeroIsRefused) {
  const auto m = std::get<s::CameraModel>(ec::plugin_model("camera"));
  json j = ec::model_to_json(m);
  j["parameters"]["range_m"] = 0.5;
  EXPECT_EQ(ec::camera_model_from_json(j, "camera.json").base.range_m, 0.5);
  for (double bad : {0.0, -0.5}) {
    j["parameters"]["range_m"] = bad;
    EXPECT_THROW((void)ec::camera_model_from_json(j, "camera.json"), logs::InputError) << bad;
  }
}

// A battery calibration file without a `noise` section: the charge noise is the root mean square
// of the speeds' noise_sd (docs/coefficient-files.md). Two speeds measured, 0.03 and 0.04, the
// others null: sqrt((0.0009 + 0.0016) / 2) = 0.0353553...
TEST(RoundNineModelFile, ABatteryFilesNoiseIsTheSpeedsRootMeanSquare) {
  json j = ec::read_json_file(std::string(EPUCK2_SOURCE_DIR) + "/data/fitted/battery.json");
  ASSERT_FALSE(j.contains("noise"));
  double sum = 0;
  for (const auto& sp : j.at("speeds")) sum += sp.at("noise_sd").get<double>() * sp.at("noise_sd").get<double>();
  const double shipped = std::sqrt(sum / static_cast<double>(j.at("speeds").size()));
  EXPECT_NEAR(ec::battery_model_from_json(j, "battery.json").noise_sd, shipped, 1e-15);
  for (auto& sp : j.at("speeds")) sp["noise_sd"] = nullptr;
  j["speeds"][2]["noise_sd"] = 0.03;
  j["speeds"][7]["noise_sd"] = 0.04;
  EXPECT_NEAR(ec::battery_model_from_json(j, "battery.json").noise_sd, std::sqrt(0.00125), 1e-15);
}

// codegen of the shipped battery file: each speed's lifetime in the header is that speed's
// lifetime_s in the file (they differ: 19743.75 s at 0 cm/s, 9355.6 s at 5).
TEST(RoundNineCodegen, EachSpeedKeepsItsOwnLifetime) {
  const std::string path = std::string(EPUCK2_SOURCE_DIR) + "/data/fitted/battery.json";
  const json j = ec::read_json_file(path);
  const std::string header = ec::model_to_cpp(ec::battery_model_from_json(j, path), "battery.json");
  int seen = 0;
  for (const auto& sp : j.at("speeds")) {
    const int speed = static_cast<int>(sp.at("speed_cm_s").get<double>());
    const std::string key = "t.lifetime_s[" + std::to_string(speed) + "] = ";
    const auto at = header.find(key);
    ASSERT_NE(at, std::string::npos) << key;
    EXPECT_DOUBLE_EQ(std::stod(header.substr(at + key.size())), sp.at("lifetime_s").get<double>()) << key;
    ++seen;
  }
  EXPECT_EQ(seen, 16);
}

// ---- lib/calibrate -----------------------------------------------------------------------------

// Two runs at 5 cm/s lasting 3600 s and 3700 s, each a straight discharge from 1 to 0: the
// lifetime 3650 s with the standard error of a mean of two, |3700 - 3600| / 2 = 50 s (the runs'
// sd is 70.7 s).
TEST(RoundNineBatteryFit, TheLifetimesErrorIsThatOfTheMean) {
  std::vector<epuck2::calibrate::BatteryRun> runs;
  for (double L : {3600.0, 3700.0}) {
    epuck2::calibrate::BatteryRun r;
    r.path = "run" + std::to_string(static_cast<int>(L)) + ".csv";
    r.robot = "r";
    r.speed_cm_s = 5;
    r.lifetime_s = L;
    for (int k = 0; k <= 100; ++k) {
      const double t = L * k / 100.0;
      r.time_s.push_back(t);
      r.charge.push_back(1.0 - t / L);
      r.profile.push_back({t, 5.0});
      r.line.push_back(k + 2);
    }
    runs.push_back(r);
  }
  const auto f = epuck2::calibrate::fit_battery(runs);
  ASSERT_EQ(f.speeds.size(), 1u);
  EXPECT_EQ(f.speeds[0].runs, 2u);
  EXPECT_DOUBLE_EQ(f.speeds[0].lifetime_s, 3650.0);
  EXPECT_NEAR(f.speeds[0].lifetime_std_error_s, 50.0, 1e-9);
}

// A light calibration's per-sensor gammas belong to the sensors' numbers, not to their places in
// the log: the shipped log of sensors 0 and 7 with the sensors renamed 2 and 5 (nothing else
// changed: Eq. 2 does not depend on the sensor's number) gives sensor 2 the gamma sensor 0 had and
// sensor 5 sensor 7's.
TEST(RoundNineLightReport, PerSensorGammasFollowTheSensorsNumbers) {
  const fs::path d = r9_scratch("light");
  const std::string log = std::string(EPUCK2_SOURCE_DIR) + "/data/raw/light/light_intensity_1.00.csv";
  std::istringstream in(r9_read(log));
  std::string line, renamed;
  bool header = false;
  std::size_t sensor_column = 0;
  while (std::getline(in, line)) {
    if (!line.empty() && line[0] == '#') {
      renamed += line + "\n";
      continue;
    }
    std::vector<std::string> cells;
    std::stringstream ss(line);
    for (std::string c; std::getline(ss, c, ',');) cells.push_back(c);
    if (!header) {
      header = true;
      for (std::size_t i = 0; i < cells.size(); ++i)
        if (cells[i] == "sensor") sensor_column = i;
    } else {
      ASSERT_TRUE(cells.at(sensor_column) == "0" || cells.at(sensor_column) == "7") << line;
      cells[sensor_column] = cells[sensor_column] == "0" ? "2" : "5";
    }
    for (std::size_t i = 0; i < cells.size(); ++i) renamed += (i ? "," : "") + cells[i];
    renamed += "\n";
  }
  r9_write(d / "renamed.csv", renamed);
  ASSERT_EQ(r9_run("light '" + log + "' -o '" + (d / "original.json").string() + "'", d / "original.out"), 0);
  ASSERT_EQ(r9_run("light '" + (d / "renamed.csv").string() + "' -o '" + (d / "renamed.json").string() + "'", d / "renamed.out"), 0);
  const json original = json::parse(r9_read(d / "original.json"));
  const json moved = json::parse(r9_read(d / "renamed.json"));
  auto gamma_of = [](const json& j, int sensor) {
    for (const auto& e : j.at("per_sensor"))
      if (e.at("sensor").get<int>() == sensor) return e.at("gamma").get<double>();
    ADD_FAILURE() << "no per_sensor entry for sensor " << sensor;
    return std::nan("");
  };
  ASSERT_EQ(moved.at("per_sensor").size(), 2u);
  EXPECT_EQ(gamma_of(moved, 2), gamma_of(original, 0));
  EXPECT_EQ(gamma_of(moved, 5), gamma_of(original, 7));
  EXPECT_NE(gamma_of(original, 0), gamma_of(original, 7));
  fs::remove_all(d);
}

// ---- lib/diagnose --------------------------------------------------------------------------------

// The shipped camera log of robot 1 against the camera file calibrated from it (data/fitted/
// camera.json, cy_px 57.9 for that robot): the file's model, before anything is fitted
// (heldout_mse_plugin is the given base's, docs/diagnose.md), predicts the log to within its
// noise, under 1 px^2, and better than the plug-in's published model (cy 60: 2 px off in every
// row). A base whose image centre were taken about the wrong half-dimension (cy - 80 instead of
// cy - 60) would be 20 px off.
TEST(RoundNineDiagnoseCamera, TheCalibratedBaseIsTheFilesImageCentre) {
  const fs::path d = r9_scratch("diagnose_camera");
  const std::string log = std::string(EPUCK2_SOURCE_DIR) + "/data/raw/camera/camera_virtual-epuck2-1.csv";
  const std::string file = std::string(EPUCK2_SOURCE_DIR) + "/data/fitted/camera.json";
  ASSERT_EQ(r9_run("diagnose '" + log + "' --coefficients '" + file + "' --json", d / "file.json"), 0);
  ASSERT_EQ(r9_run("diagnose '" + log + "' --json", d / "plugin.json"), 0);
  const json with_file = json::parse(r9_read(d / "file.json"));
  const json plugin = json::parse(r9_read(d / "plugin.json"));
  EXPECT_LT(with_file.at("heldout_mse_plugin").get<double>(), 1.0);
  EXPECT_LT(with_file.at("heldout_mse_plugin").get<double>(), plugin.at("heldout_mse_plugin").get<double>() / 4);
  fs::remove_all(d);
}

// A finding's parameter is "not determined" when its standard error exceeds its size, whatever
// its sign: the plug-in's diagnosis of the camera log of robot 1 finds principal_offset with
// dy_px about -2.07 px, standard error about 0.03 px -- determined, so no such warning.
TEST(RoundNineDiagnoseWarnings, ANegativeFindingWellDeterminedIsNotCalledUndetermined) {
  const fs::path d = r9_scratch("diagnose_warnings");
  const std::string log = std::string(EPUCK2_SOURCE_DIR) + "/data/raw/camera/camera_virtual-epuck2-1.csv";
  ASSERT_EQ(r9_run("diagnose '" + log + "' --json", d / "report.json"), 0);
  const json j = json::parse(r9_read(d / "report.json"));
  bool negative_seen = false;
  for (const auto& f : j.at("findings"))
    for (const auto& [name, value] : f.at("parameters").items()) {
      const double se = f.at("uncertainty").at(name).get<double>();
      if (value.get<double>() < 0 && std::abs(value.get<double>()) > 10 * se) negative_seen = true;
    }
  ASSERT_TRUE(negative_seen) << "the log no longer gives a negative finding well determined";
  for (const auto& w : j.at("warnings"))
    EXPECT_EQ(w.get<std::string>().find("is not determined"), std::string::npos) << w;
  fs::remove_all(d);
}

// ---- lib/logs ----------------------------------------------------------------------------------

// docs/logs.md: angle_deg, when a proximity log has it, is a number in [-90, 90]; a cell "n/a" is
// refused at its line and column (line 3, column 13 after "0.02,0,2000,").
TEST(RoundNineLogReader, AProximityAngleThatIsNotANumberIsRefusedWhereItIs) {
  const logs::Log ok = logs::parse_log("distance_m,sensor,value,angle_deg\n0.01,0,3000,0\n0.02,0,2000,10\n", "p.csv",
                                       logs::Kind::proximity);
  ASSERT_TRUE(ok.has("angle_deg"));
  EXPECT_EQ(ok.col("angle_deg")[1], 10.0);
  try {
    (void)logs::parse_log("distance_m,sensor,value,angle_deg\n0.01,0,3000,0\n0.02,0,2000,n/a\n", "p.csv", logs::Kind::proximity);
    ADD_FAILURE() << "angle_deg n/a was read";
  } catch (const logs::InputError& e) {
    EXPECT_EQ(e.line(), 3);
    EXPECT_EQ(e.column(), 13);
  }
}

// docs/logs.md: obstacle_distance_m is in [0, 1000] m; 5000 is refused at its metadata line
// (line 1), 0.3 is read.
TEST(RoundNineLogReader, AnObstacleBeyondItsRangeIsRefusedAtItsLine) {
  const std::string rows = "time_s,left_speed_cm_s,right_speed_cm_s,left_steps,right_steps,tof_mm\n0,0,0,0,0,304\n0.1,5,5,6,6,300\n";
  EXPECT_EQ(logs::parse_log("# obstacle_distance_m: 0.3\n" + rows, "d.csv", logs::Kind::drive).metadata_number("obstacle_distance_m"), 0.3);
  try {
    (void)logs::parse_log("# obstacle_distance_m: 5000\n" + rows, "d.csv", logs::Kind::drive);
    ADD_FAILURE() << "obstacle_distance_m 5000 was read";
  } catch (const logs::InputError& e) {
    EXPECT_EQ(e.line(), 1);
  }
}

// docs/logs.md: grey is a level in [0, 1]; 50 (a percentage) is refused at line 3, column 1.
TEST(RoundNineLogReader, AGreyInPercentIsRefused) {
  EXPECT_EQ(logs::parse_log("grey,sensor,value\n0.5,0,500\n1,0,1000\n", "g.csv", logs::Kind::ground).rows(), 2u);
  try {
    (void)logs::parse_log("grey,sensor,value\n0.5,0,500\n50,0,1000\n", "g.csv", logs::Kind::ground);
    ADD_FAILURE() << "grey 50 was read";
  } catch (const logs::InputError& e) {
    EXPECT_EQ(e.line(), 3);
    EXPECT_EQ(e.column(), 1);
  }
}

// ---- lib/models ----------------------------------------------------------------------------------

// simulate --like without noise: the mean plus the row's covariate offset. Sensor 1 with offset
// 50 and gain 800 over grey 0.5 reads 50 + 400 = 450; with an offset of +10 counts, 460; with
// -500, clamped to 0.
TEST(RoundNineSimulateLike, ANoiselessReadingCarriesItsCovariateOffset) {
  const logs::Log log = logs::parse_log("grey,sensor,value\n0.5,1,0\n0.5,1,0\n0.5,1,0\n", "g.csv", logs::Kind::ground);
  s::GroundModel m;
  m.sensors[1] = {800.0, 50.0};
  s::StandardNormal normal(1);
  const auto out = s::simulated_readings(m, log, std::vector<double>{0.0, 10.0, -500.0}, false, normal);
  ASSERT_EQ(out.size(), 3u);
  EXPECT_DOUBLE_EQ(out[0].at(0), 450.0);
  EXPECT_DOUBLE_EQ(out[1].at(0), 460.0);
  EXPECT_DOUBLE_EQ(out[2].at(0), 0.0);
}

// The plug-in's camera sees within its range along the axis (forward), not along the line of
// sight: an LED at forward 0.98 m and lateral 0.3 m (17 degrees off the axis, 1.025 m away) is
// seen with a 1 m range and a 20 degree aperture; one 1.01 m forward is not.
TEST(RoundNineCamera, TheRangeIsAlongTheAxis) {
  const double aperture = 20.0 * M_PI / 180.0;
  EXPECT_GT(std::hypot(0.98, 0.3), 1.0);
  EXPECT_TRUE(s::camera_sees(aperture, 1.0, 0.98, 0.3, 0.0));
  EXPECT_TRUE(s::camera_sees(aperture, 1.0, 0.98, 0.0, 0.3));
  EXPECT_FALSE(s::camera_sees(aperture, 1.0, 1.01, 0.0, 0.0));
  EXPECT_FALSE(s::camera_sees(aperture, 1.0, 0.5, 0.3, 0.0));  // 31 degrees off the axis
}

// ---- apps: simulate battery --profile ------------------------------------------------------------

// A profile driving backwards at 5 cm/s discharges as forwards (the battery spends on the
// wheels' speed, not its sign: docs/battery-models.md); standing still discharges differently.
// Without --coefficients and without --compat argos, the fitted tables (--help: "Default: plugin
// with --compat argos or --like, else fitted"), which differ from the plug-in's.
TEST(RoundNineSimulateBattery, BackwardsDischargesAsForwardsAndTheDefaultTablesAreTheFitted) {
  const fs::path d = r9_scratch("simulate");
  r9_write(d / "fwd.csv", "time_s,speed_cm_s\n0,5\n600,5\n");
  r9_write(d / "back.csv", "time_s,speed_cm_s\n0,-5\n600,-5\n");
  r9_write(d / "still.csv", "time_s,speed_cm_s\n0,0\n600,0\n");
  for (const char* name : {"fwd", "back", "still"})
    ASSERT_EQ(r9_run(std::string("simulate battery --model linear --profile '") + (d / (std::string(name) + ".csv")).string() + "'",
                     d / (std::string(name) + ".out")),
              0)
        << name;
  const std::string fwd = r9_read(d / "fwd.out");
  ASSERT_GT(fwd.size(), 100u);
  EXPECT_EQ(r9_read(d / "back.out"), fwd);
  EXPECT_NE(r9_read(d / "still.out"), fwd);
  const std::string profile = "--profile '" + (d / "fwd.csv").string() + "'";
  ASSERT_EQ(r9_run("simulate battery --model linear --coefficients fitted " + profile, d / "fitted.out"), 0);
  ASSERT_EQ(r9_run("simulate battery --model linear --coefficients plugin " + profile, d / "plugin.out"), 0);
  ASSERT_NE(r9_read(d / "fitted.out"), r9_read(d / "plugin.out"));
  EXPECT_EQ(fwd, r9_read(d / "fitted.out"));
  fs::remove_all(d);
}

}  // namespace
}  // namespace test_round_nine_slips_cpp
