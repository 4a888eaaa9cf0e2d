// Round 4 of the fresh slips (bench/fresh-slips.md): each test's expected value is worked by hand
// in its comment or is a documented boundary, never read back from the code under test.
#include <gtest/gtest.h>

#include <cmath>
#include <memory>
#include <optional>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include <sys/wait.h>
#include <unistd.h>

#include <nlohmann/json.hpp>

#include "epuck2/calibrate/charge_map.hpp"
#include "epuck2/calibrate/reading_noise.hpp"
#include "epuck2/calibrate/report_json.hpp"
#include "../lib/diagnose/src/screening.hpp"
#include "epuck2/calibrate/sensor_reports.hpp"
#include "epuck2/calibrate/sensors.hpp"
#include "epuck2/coefficients/codegen.hpp"
#include "epuck2/coefficients/model_file.hpp"
#include "epuck2/diagnose/diagnose.hpp"
#include "epuck2/diagnose/report_output.hpp"
#include "epuck2/fit/readings.hpp"
#include "epuck2/logs/log.hpp"
#include "epuck2/models/noise.hpp"
#include "epuck2/plot/figure.hpp"
// The diagnosis's residual-structure scoring is internal to lib/diagnose (engine_detail.hpp).
#include "../lib/diagnose/src/engine_detail.hpp"

namespace {

using nlohmann::json;
namespace c = epuck2::calibrate;
namespace co = epuck2::coefficients;
namespace f = epuck2::fit;
namespace l = epuck2::logs;
namespace s = epuck2::models::sensors;

/// What `fn` throws, or "" when it does not throw.
template <class F>
std::string error_of(F&& fn) {
  try {
    fn();
  } catch (const std::exception& e) {
    return e.what();
  }
  return "";
}

// ----- the one censored residual: a reading exactly on a rail is censored -----

TEST(RoundFourReadings, AReadingExactlyOnEitherRailIsCensored) {
  // The ground register's rails 0 and 1023 (docs/fitting.md: a reading on a rail is censored).
  EXPECT_EQ(f::censoring_at(0.0, 0.0, 1023.0), f::Censoring::at_or_below);
  EXPECT_EQ(f::censoring_at(1023.0, 0.0, 1023.0), f::Censoring::at_or_above);
  EXPECT_EQ(f::censoring_at(1.0, 0.0, 1023.0), f::Censoring::none);
  EXPECT_EQ(f::censoring_at(1022.0, 0.0, 1023.0), f::Censoring::none);
}

// ----- the calibration report: each rail's count under its own name -----

TEST(RoundFourReports, AFitsCensoredCountsKeepTheirRails) {
  f::RobustFit r;
  r.usable = true;
  r.censored_below = 2;  // two readings at or below the low rail
  r.censored_above = 5;  // five at or above the high one
  r.kept_censored_below = 1;
  r.kept_censored_above = 4;
  const json d = c::fit_details(r, "counts");
  EXPECT_EQ(d.at("censored").at("at_or_below").get<int>(), 2);
  EXPECT_EQ(d.at("censored").at("at_or_above").get<int>(), 5);
  EXPECT_EQ(d.at("censored_kept").at("at_or_below").get<int>(), 1);
  EXPECT_EQ(d.at("censored_kept").at("at_or_above").get<int>(), 4);
}

TEST(RoundFourReports, GroundFileKeepsEachSensorsGainAndOffsetErrorsApart) {
  // Three sensors whose gain and offset errors all differ: gain ± 2, 3, 4; offset ± 0.25, 0.5, 0.75.
  c::GroundFit g;
  for (std::size_t k = 0; k < 3; ++k) {
    f::RobustFit& r = g.sensors[k];
    r.usable = true;
    r.observations = 10;
    r.parameters = {{"gain", 1000.0 + k, 2.0 + k}, {"offset", 40.0 + k, 0.25 * (k + 1)}};
  }
  g.noise.channel = "ground";
  g.noise.unit = "counts";
  g.noise.from = "replicates";
  g.noise.sd = 1.0;
  g.noise.n = 30;
  const json j = c::coefficient_json(g, {});
  for (std::size_t k = 0; k < 3; ++k) {
    EXPECT_DOUBLE_EQ(j.at("std_errors").at("gain").at(k).get<double>(), 2.0 + k) << k;
    EXPECT_DOUBLE_EQ(j.at("std_errors").at("offset").at(k).get<double>(), 0.25 * (k + 1)) << k;
    EXPECT_DOUBLE_EQ(j.at("parameters").at("offset").at(k).get<double>(), 40.0 + k) << k;
  }
}

// ----- the model-file validator and the kinds' facts -----

json camera_file(double cx, double cy) {
  return {{"kind", "camera"}, {"parameters", {{"fov_deg", 60.0}, {"cx_px", cx}, {"cy_px", cy}}}};
}

TEST(RoundFourModelFile, TheImageCentreRowLiesInsideTheImagesHeight) {
  // The camera image is 160 x 120 px (the plug-in's source, lib/models camera.hpp): a row centre of
  // 120 is on the edge, 130 is
  // below the image, while both are inside its width.
  EXPECT_EQ(error_of([] { co::camera_model_from_json(camera_file(80, 119.5), "cam.json"); }), "");
  EXPECT_EQ(error_of([] { co::camera_model_from_json(camera_file(80, 120), "cam.json"); }), "");
  const std::string e = error_of([] { co::camera_model_from_json(camera_file(80, 130), "cam.json"); });
  EXPECT_NE(e.find("cy_px"), std::string::npos) << e;
  EXPECT_NE(e.find("/parameters/cy_px"), std::string::npos) << e;
  // The column centre's range is the width: 150 is inside, 161 is not.
  EXPECT_EQ(error_of([] { co::camera_model_from_json(camera_file(150, 60), "cam.json"); }), "");
  EXPECT_NE(error_of([] { co::camera_model_from_json(camera_file(161, 60), "cam.json"); }), "");
}

TEST(RoundFourModelFile, ALightSensorsOwnGammaOfZeroIsRefused) {
  // gamma's range is (0, 10] m, open at 0 (docs/coefficient-files.md): per_sensor's gammas too.
  const json base = {{"kind", "light"}, {"parameters", {{"gamma", 0.075}}}};
  json zero = base, small = base;
  zero["per_sensor"] = json::array({{{"sensor", 3}, {"gamma", 0.0}}});
  small["per_sensor"] = json::array({{{"sensor", 3}, {"gamma", 1e-3}}});
  const std::string e = error_of([&] { co::light_model_from_json(zero, "light.json"); });
  EXPECT_NE(e.find("per_sensor[0].gamma"), std::string::npos) << e;
  const s::LightModel m = co::light_model_from_json(small, "light.json");
  EXPECT_DOUBLE_EQ(s::light_gamma_m(m, 3), 1e-3);
  EXPECT_DOUBLE_EQ(s::light_gamma_m(m, 2), 0.075);
}

// ----- codegen: the Simple model's two slopes -----

TEST(RoundFourCodegen, SimpleModelsStaticAndMovingSlopesKeepTheirOwnValues) {
  s::BatteryModel m;
  m.tables.simple_static_slope_per_s = -0.25;
  m.tables.simple_moving_slope_per_s = -0.5;
  for (std::size_t sp = 0; sp < m.tables.lifetime_s.size(); ++sp) {
    m.tables.lifetime_s[sp] = 1000.0;
    m.tables.cubic[sp].end_s = 1000.0;
    m.tables.linear_slope_per_s[sp] = -0.001;
  }
  const std::string code = co::model_to_cpp(m, "a test");
  EXPECT_NE(code.find("t.simple_static_slope_per_s = -0.25;"), std::string::npos) << code;
  EXPECT_NE(code.find("t.simple_moving_slope_per_s = -0.5;"), std::string::npos) << code;
}

// ----- the voltage->charge map read from a file without its voltage range -----

TEST(RoundFourChargeMap, WithoutAVoltageRangeTheKnotsAreTheRange) {
  // Knots 3.0, 3.5, 4.0 V at charges 0, 0.4, 1 (docs/coefficient-files.md#charge-map: without
  // voltage_range_v the map's range is its knots'): 3.75 V -> 0.4 + 0.5 * 0.6 = 0.7, inside;
  // 4.2 V -> 1, clamped above; 2.9 V -> 0, clamped below.
  const json file = {{"charge_map",
                      {{"form", c::kChargeMapForm}, {"knots_v", {3.0, 3.5, 4.0}}, {"knot_charge", {0.0, 0.4, 1.0}}}}};
  const c::ChargeMap m = c::charge_map_from_json(file, "map.json");
  const c::ChargeConversion mid = c::convert_voltage(m, 3.75, 0.0);
  EXPECT_NEAR(mid.charge, 0.7, 1e-12);
  EXPECT_EQ(mid.side, 0);
  const c::ChargeConversion high = c::convert_voltage(m, 4.2, 0.0);
  EXPECT_NEAR(high.charge, 1.0, 1e-12);
  EXPECT_EQ(high.side, 1);
  const c::ChargeConversion low = c::convert_voltage(m, 2.9, 0.0);
  EXPECT_NEAR(low.charge, 0.0, 1e-12);
  EXPECT_EQ(low.side, -1);
}

// ----- the reading noise between replicates -----

TEST(RoundFourReadingNoise, AGroupWithARailedReadingAnywhereIsLeftOut) {
  // Group 0: 500, 502 (mean 501, squares 1 + 1 = 2, one degree of freedom). Group 1: 1023 on the
  // ground's high rail first, then 1022 and 1021: railed, left out whatever its last reading.
  // Pooled sd sqrt(2 / 1); the groups' slip (group 1 kept) would give sqrt((2 + 2) / 3).
  const std::vector<double> v{500, 502, 1023, 1022, 1021};
  const std::vector<int> g{0, 0, 1, 1, 1};
  const std::vector<bool> rail{false, false, true, false, false};
  // The floor 1 count (a calibration's quantisation floor) keeps every reading from being wild:
  // group 1's robust sd is at least 1, its railed reading 1 count from the median 1022.
  const c::PooledSd p = c::pooled_replicate_sd(v, g, rail, 1.0, 0.0);
  EXPECT_EQ(p.wild, 0u);
  EXPECT_EQ(p.railed_groups, 1u);
  EXPECT_EQ(p.groups, 1u);
  EXPECT_EQ(p.n, 2u);
  EXPECT_NEAR(p.sd, std::sqrt(2.0), 1e-12);
}

TEST(RoundFourReadingNoise, ArgosUniformLevelHasTheGaussiansVariance) {
  // Uniform on [-L, L] has variance L^2 / 3 (integral of x^2 / (2L) over [-L, L]); for an sd of
  // 6 counts on the proximity's unit noise of 4095 counts, L = 6 sqrt(3) / 4095 = 10.392305 / 4095
  // = 0.00253780.
  const double level = s::uniform_level_with_sd(6.0, 4095.0);
  EXPECT_NEAR(level * level * 4095.0 * 4095.0 / 3.0, 36.0, 1e-9);
  EXPECT_NEAR(level, 0.00253780, 1e-8);
  // Numerically, the variance of an evenly spaced uniform sample over [-L, L] (in counts).
  const double L = level * 4095.0;
  double ss = 0;
  const int n = 200000;
  for (int i = 0; i < n; ++i) {
    const double x = -L + 2 * L * (i + 0.5) / n;
    ss += x * x;
  }
  EXPECT_NEAR(std::sqrt(ss / n), 6.0, 1e-6);
}

// ----- simulate --like: a noiseless ground reading clamped at the ground's own full scale -----

/// Runs the CLI with `args`, returns its standard output (standard error to /dev/null) and exit code.
std::string run_cli(const std::string& args, int& code) {
  const std::string cmd = std::string(EPUCK2_FIT_EXE) + " " + args + " 2>/dev/null";
  FILE* p = popen(cmd.c_str(), "r");
  std::string out;
  char buf[4096];
  std::size_t n = 0;
  while ((n = fread(buf, 1, sizeof buf, p)) > 0) out.append(buf, n);
  const int status = pclose(p);
  code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  return out;
}

TEST(RoundFourSimulateLike, GroundReadingsClampAtTheGroundsFullScale) {
  // A ground model with gain 2000 counts and offset 0 on every sensor (inside gain's (0, 4092]):
  // grey 1 means 2000, which the 10-bit register reads as its rail 1023; grey 0.25 means 500
  // (docs/logs.md: the ground's value is 0..1023).
  namespace fs = std::filesystem;
  const fs::path dir = fs::temp_directory_path() / ("epuck2_round_four_" + std::to_string(::getpid()));
  fs::create_directories(dir);
  std::ofstream(dir / "ground.csv") << "grey,sensor,value\n1,0,1023\n0.25,1,500\n";
  std::ofstream(dir / "model.json")
      << R"({"kind": "ground", "parameters": {"gain": [2000, 2000, 2000], "offset": [0, 0, 0]}})";
  int code = -1;
  const std::string out = run_cli("simulate ground --like " + (dir / "ground.csv").string() + " --coefficients " +
                                      (dir / "model.json").string(),
                                  code);
  fs::remove_all(dir);
  ASSERT_EQ(code, 0) << out;
  std::vector<double> values;
  std::istringstream lines(out);
  std::string line;
  bool header = false;
  while (std::getline(lines, line)) {
    if (line.empty() || line[0] == '#') continue;
    if (!header) {
      header = true;
      ASSERT_EQ(line, "grey,sensor,value");
      continue;
    }
    values.push_back(std::stod(line.substr(line.rfind(',') + 1)));
  }
  ASSERT_EQ(values.size(), 2u) << out;
  EXPECT_DOUBLE_EQ(values[0], 1023.0) << out;
  EXPECT_DOUBLE_EQ(values[1], 500.0) << out;
}

// ----- the residual structure: a channel's floor in its own units, weighted like its residuals -----

/// Two channels of residuals (the drive's ToF in mm and encoders in steps) with no model: only
/// what structure() reads (channel, names, floors, covariates).
struct TwoChannels : epuck2::diagnose::detail::Problem {
  void mean(const double*, double*, std::size_t) const override {}
  void mean(const epuck2::diagnose::detail::Jet*, epuck2::diagnose::detail::Jet*, std::size_t) const override {}
  void mean(const epuck2::diagnose::detail::ShortJet*, epuck2::diagnose::detail::ShortJet*, std::size_t) const override {}
  void mean(const epuck2::diagnose::detail::PairJet*, epuck2::diagnose::detail::PairJet*, std::size_t) const override {}
};

TEST(RoundFourResidualStructure, AChannelsFloorIsInItsOwnUnits) {
  // Noise sd 3 mm (ToF, channel 0) and 0.3 steps (encoders, channel 1): a step residual is
  // reported in channel 0's units times 3 / 0.3 = 10. The encoders' floor is 0.5 steps
  // (kind_drive.cpp), 5 in channel 0's units. 40 encoder residuals of +-0.3 steps (+-3 weighted)
  // that follow a covariate exactly explain all their variance (binned means +-3, RMS size 3):
  // 0.3 steps is below the half-step floor, not significant. At +-0.8 steps (+-8 weighted) it is.
  auto score = [](double steps) {
    TwoChannels p;
    p.channel_names = {"tof_mm", "steps"};
    p.channel_min_structure = {0.0, 0.5};
    std::vector<double> x, r;
    for (int i = 0; i < 40; ++i) {
      p.channel.push_back(1);
      x.push_back(i % 2);
      r.push_back((i % 2 ? 1.0 : -1.0) * steps * 10.0);
      // ToF residuals without structure: alternating in a pattern the covariate does not follow.
      p.channel.push_back(0);
      x.push_back(i % 2);
      r.push_back((i / 2) % 2 ? 1.0 : -1.0);
    }
    p.covariates.emplace_back("u", x);
    const auto out = epuck2::diagnose::engine_detail::structure(p, r, std::vector<double>(r.size(), 0.0), 0.05, {3.0, 0.3});
    for (const auto& c : out)
      if (c.covariate == "u") return c;
    return epuck2::diagnose::CovariateScore{};
  };
  const auto small = score(0.3);
  EXPECT_EQ(small.channel, "steps");
  EXPECT_NEAR(small.size, 3.0, 1e-9);
  EXPECT_FALSE(small.significant);
  const auto large = score(0.8);
  EXPECT_EQ(large.channel, "steps");
  EXPECT_NEAR(large.size, 8.0, 1e-9);
  EXPECT_TRUE(large.significant);
}

// ----- the naming step: a long tail's share of the reading as the sensor reports it -----

/// Whether the proximity kind names a long tail of `amplitude` counts and length 1 m the
/// near-field curve on rows at `distances` (every other parameter at its neutral or plug-in value;
/// with `flat_c`, the base quadratic a = b = 0, c = flat_c instead of the plug-in's).
std::optional<std::string> tail_named(const std::string& distances_csv, std::optional<double> flat_c = std::nullopt) {
  namespace dd = epuck2::diagnose::detail;
  const std::vector<l::Log> logs{l::parse_log("distance_m,sensor,value\n" + distances_csv, "p.csv", l::Kind::proximity)};
  std::string why;
  const std::unique_ptr<dd::Problem> p = dd::make_problem(logs, epuck2::diagnose::Options{}, why);
  std::vector<double> values;
  for (const auto& q : p->params)
    values.push_back(!flat_c ? q.fallback : q.name == "a" || q.name == "b" ? 0.0 : q.name == "c" ? *flat_c : q.fallback);
  for (const auto& e : p->effects)
    if (e.cause == "long_tail") {
      values[static_cast<std::size_t>(e.params.at(0))] = 8000.0;  // amplitude, counts
      values[static_cast<std::size_t>(e.params.at(1))] = 1.0;     // length, m
    }
  const auto id = p->identify("long_tail", values, Eigen::MatrixXd());
  if (!id) return std::nullopt;
  return id->cause;
}

TEST(RoundFourIdentify, ALongTailsShareIsCountedUpToTheFullScale) {
  // The plug-in's curve (lib/models proximity.hpp kPluginProximity, the paper's Eq. 1)
  // 4095 (197.8633 d^2 - 30.47182 d + 1.011635): 3539.0 counts at 5 mm and
  // 2975.9 at 10 mm. A tail of 8000 exp(-d / 1 m) lifts both past the full scale 4095: as the
  // sensor reports them it adds 4095 - 3539.0 = 556.0 and 4095 - 2975.9 = 1119.1 counts, a share
  // (556.0 + 1119.1) / (2 x 4095) = 0.20 of the reading, not more than half: it extends the curve
  // (not renamed). Unclipped it would be 7960 + 7920 counts, a share of 1.94.
  EXPECT_EQ(tail_named("0.005,0,3500\n0.01,0,3000\n"), std::nullopt);
  // At 30 and 40 mm the curve gives 1128.4 and 447.7 counts: the tail adds 2966.6 and 3647.3 as
  // reported, a share 0.81 > 0.5: it replaces the near-field curve.
  EXPECT_EQ(tail_named("0.03,0,3500\n0.04,0,3000\n"), std::optional<std::string>("near_field_curve"));
}

// The cut itself: a tail that carries exactly half of the reading within the range is not more
// than half, so it extends the curve. Base quadratic a = b = 0, c = 0.5 (lib/models
// proximity_mean_raw: 4095 x 0.5 = 2047.5 counts exactly, every effect neutral); a tail of
// 8000 exp(-d / 1 m) lifts the reading past the full scale, so as reported it adds
// 4095 - 2047.5 = 2047.5 counts of 4095: a share of exactly 0.5, all of it exact in doubles. With
// c = 0.4999 the base gives 2047.09 and the tail 2047.91 > 2047.5: more than half, renamed.
TEST(RoundFourIdentify, ATailOfExactlyHalfTheReadingExtendsTheCurve) {
  EXPECT_EQ(tail_named("0.02,0,4095\n", 0.5), std::nullopt);
  EXPECT_EQ(tail_named("0.02,0,4095\n", 0.4999), std::optional<std::string>("near_field_curve"));
}

// ----- the firmware cap's uncapped command: the wheels' mean -----

TEST(RoundFourFirmwareCap, TheUncappedCommandIsTheWheelsMean) {
  // Left 20 cm/s, right 10 cm/s: the body's command (0.20 + 0.10) / 2 = 0.15 m/s as logged; the
  // cap (kFirmwareSpeedLimit_m_s, about 0.129 m/s) brings the left to the limit: (cap + 0.10) / 2.
  const std::string log =
      "# obstacle_distance_m: 1.5\n"
      "time_s,left_speed_cm_s,right_speed_cm_s,left_steps,right_steps,tof_mm\n"
      "0,20,10,0,0,1500\n"
      "1,-6,-2,100,100,1400\n";
  const c::DriveRun run = c::drive_run_from_log(l::parse_log(log, "drive.csv", l::Kind::drive));
  ASSERT_EQ(run.command_uncapped_m_s.size(), 2u);
  EXPECT_NEAR(run.command_uncapped_m_s[0], 0.15, 1e-12);
  EXPECT_NEAR(run.command_uncapped_m_s[1], -0.04, 1e-12);
  EXPECT_NEAR(run.command_m_s[0], 0.5 * (c::kFirmwareSpeedLimit_m_s + 0.10), 1e-12);
  EXPECT_NEAR(run.command_m_s[1], -0.04, 1e-12);
  EXPECT_EQ(run.capped_rows, 1u);
}

// ----- the ToF's no-target codes: in view only well inside the sensor's range -----

TEST(RoundFourTofCodes, ACodeIsADropoutOnlyInsideTheRangeLessItsMargin) {
  // Ceiling 2000 mm, margin 10 % (screening.hpp kTofInViewMargin): a code while the encoders put
  // the obstacle at 1700 mm is a dropout; at 1900 mm, and at 2100 mm, it is not (the target may
  // lie beyond what the sensor sees).
  EXPECT_TRUE(epuck2::diagnose::tof_code_in_view(8190, 1700));
  EXPECT_FALSE(epuck2::diagnose::tof_code_in_view(8190, 1900));
  EXPECT_FALSE(epuck2::diagnose::tof_code_in_view(8190, 2100));
  EXPECT_FALSE(epuck2::diagnose::tof_code_in_view(1500, 1700));  // a reading, not a code
}

// ----- the log reader: the sensor ranges and the columns of errors -----

TEST(RoundFourLogReader, SensorIndicesStopAtTheLastSensor) {
  // Proximity: sensors 0..7; ground: 0..2 (docs/logs.md).
  EXPECT_EQ(error_of([] { l::parse_log("distance_m,sensor,value\n0.01,7,3000\n", "p.csv"); }), "");
  const std::string p = error_of([] { l::parse_log("distance_m,sensor,value\n0.01,8,3000\n", "p.csv"); });
  EXPECT_NE(p.find("p.csv:2:6"), std::string::npos) << p;
  EXPECT_EQ(error_of([] { l::parse_log("grey,sensor,value\n0.5,2,500\n", "g.csv"); }), "");
  const std::string g = error_of([] { l::parse_log("grey,sensor,value\n0.5,3,500\n", "g.csv"); });
  EXPECT_NE(g.find("g.csv:2:5"), std::string::npos) << g;
}

TEST(RoundFourLogReader, AnErrorNamesTheCellsFirstCharacterCountingFromOne) {
  // Line 3 "0.02,x,12": the cell x starts at the 6th character.
  const std::string e = error_of([] { l::parse_log("distance_m,sensor,value\n0.01,1,10\n0.02,x,12\n", "p.csv"); });
  EXPECT_NE(e.find("p.csv:3:6:"), std::string::npos) << e;
  // The first cell starts at column 1: "abc,1,10".
  const std::string first = error_of([] { l::parse_log("distance_m,sensor,value\nabc,1,10\n", "p.csv"); });
  EXPECT_NE(first.find("p.csv:2:1:"), std::string::npos) << first;
}

// ----- the figures' legend band: each column's key at its own left edge -----

TEST(RoundFourFigures, EachLegendColumnsKeyStandsAtItsOwnLeftEdge) {
  // Two entries in one row: two columns of equal titles, each half of the band 0.1..0.9: keys at
  // x = 0.1 and 0.5.
  const std::string band = epuck2::plot::legend_band(0.1, 0.9, 0.0, 0.95,
                                                     {"NaN with lines title 'aaaa'", "NaN with lines title 'bbbb'"}, 10, 1);
  EXPECT_NE(band.find("set key at screen 0.1000,0.9500"), std::string::npos) << band;
  EXPECT_NE(band.find("set key at screen 0.5000,0.9500"), std::string::npos) << band;
}


// ----- the diagnosis report: the largest of a value's standard errors is the one it carries -----

TEST(RoundFourDiagnosisReport, TheLargestStandardErrorIsTheOneReported) {
  // gamma 0.08 m with a covariance error of 0.001 m and a jackknife error four times larger: the
  // report rounds to the jackknife's and names it first (docs/diagnose.md), the covariance's beside.
  namespace d = epuck2::diagnose;
  d::Report r;
  r.kind = l::Kind::light;
  r.rows = r.residuals = 100;
  d::NamedValue v("gamma", 0.08, 0.001);
  v.std_error_jackknife = 0.004;
  r.recalibrated = {v};
  const std::string text = d::report_text(r, "The plug-in's model");
  // (Errors print with two significant digits: 0.0040, 0.0010.)
  EXPECT_NE(text.find("gamma = 0.0800 ± 0.0040 m (jackknife over the held-out folds; covariance ± 0.0010)"), std::string::npos)
      << text;
  // And the other way round: a covariance error above the jackknife's is the one reported.
  r.recalibrated[0].std_error = 0.01;
  const std::string other = d::report_text(r, "The plug-in's model");
  EXPECT_NE(other.find("gamma = 0.080 ± 0.010 m (covariance; jackknife over the held-out folds ± 0.0040)"), std::string::npos)
      << other;
}

}  // namespace
