// Tests written during round 13 of the fresh slips (bench/fresh-slips.md), after its GO: each
// checks a behaviour that a round-13 slip changes and that no earlier test pinned down. Expected
// values are worked by hand from docs/ and the plug-in's formulas, or are the documented option
// ranges; none is read from the code under test.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <fstream>
#include <set>
#include <sstream>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "cli_harness.hpp"
#include "epuck2/calibrate/charge_map.hpp"
#include "epuck2/fit/least_squares.hpp"
#include "epuck2/fit/readings.hpp"
#include "epuck2/coefficients/battery_tables.hpp"
#include "epuck2/models/camera.hpp"
#include "epuck2/models/light.hpp"
#include "epuck2/virtual_robot/reference_logs.hpp"
#include "epuck2/virtual_robot/sensor_truth.hpp"

namespace test_round_thirteen_cpp {

namespace fs = std::filesystem;
namespace ms = epuck2::models::sensors;
using epuck2::testing::CliRun;

// ---- lib/models: the camera's image bounds, the several-lights mean with per-sensor gains -------

TEST(RoundThirteenModels, ABlobIsOnTheImageOnlyInsideItsColumnsAndRows) {
  // 160 x 120 px (the E-Puck2's image, docs/sensor-models.md): columns 0..159, rows 0..119; a
  // position is rounded to its pixel first.
  EXPECT_TRUE(ms::camera_image_holds(80.0, 119.0));
  EXPECT_TRUE(ms::camera_image_holds(159.4, 119.4));
  EXPECT_TRUE(ms::camera_image_holds(-0.4, -0.4));
  EXPECT_FALSE(ms::camera_image_holds(80.0, 119.6));  // row 120
  EXPECT_FALSE(ms::camera_image_holds(80.0, 125.0));  // a row past the bottom, inside the width
  EXPECT_FALSE(ms::camera_image_holds(159.6, 60.0));  // column 160
  EXPECT_FALSE(ms::camera_image_holds(80.0, -0.6));
  EXPECT_FALSE(ms::camera_image_holds(-0.6, 60.0));
  // Another image size: rows bound by the height, columns by the width.
  EXPECT_TRUE(ms::camera_image_holds(300.0, 20.0, 320, 30));
  EXPECT_FALSE(ms::camera_image_holds(20.0, 30.0, 320, 30));
  EXPECT_FALSE(ms::camera_image_holds(320.0, 20.0, 320, 30));
}

TEST(RoundThirteenModels, SeveralLightsAreScaledByTheSensorsOwnGain) {
  // gamma 0.075 m: a light of intensity 1 at 0.2 m adds (0.075 / 0.2)^2 = 0.140625, at 0.3 m
  // 0.0625. Sensor 0 with gain 1.2, one light at 0.2 m: 4095 (1 - 1.2 * 0.140625) = 3403.96875.
  // Sensor 3 with gain 0.8, both lights: 4095 (1 - 0.8 * 0.203125) = 3429.5625, less the ambient
  // offset 10. A light beyond 0.5 m adds nothing.
  const ms::LightCoefficients k{0.075, 0.5};
  ms::LightEffects<double> e;
  e.gains.gain[0] = 1.2;
  e.gains.gain[3] = 0.8;
  const std::vector<ms::LightSource> one{{0.2, 1.0}}, two{{0.2, 1.0}, {0.3, 1.0}, {0.6, 1.0}};
  EXPECT_NEAR(ms::light_mean_raw(k, e, 0, one), 3403.96875, 1e-9);
  e.ambient.offset_raw = 10.0;
  EXPECT_NEAR(ms::light_mean_raw(k, e, 3, two), 3429.5625 - 10.0, 1e-9);
  // A sensor at gain 1: the plug-in's sum.
  EXPECT_NEAR(ms::light_mean_raw(k, e, 5, two), 4095.0 * (1.0 - 0.203125) - 10.0, 1e-9);
}

// ---- lib/fit: several channels in one fit, each weighted into channel 0's units ---------------

TEST(RoundThirteenFit, AChannelsErrorIsWeightedByChannelZerosSdOverItsOwn) {
  // docs/diagnose.md (drive): channel c's residuals are weighted by sd_0 / sd_c. ToF sd 2 mm,
  // encoders sd 0.5 steps: an encoder reading 1 step off weighs 1 * 2 / 0.5 = 4 (mm), a ToF
  // reading 1 mm off weighs 1.
  epuck2::fit::Channels ch(std::vector<epuck2::fit::Channel>(2));
  ch.set_noise_sd({2.0, 0.5});
  EXPECT_DOUBLE_EQ(ch.weight(0), 1.0);
  EXPECT_DOUBLE_EQ(ch.weight(1), 4.0);
  const double tof = ch.weighted_error(10.0, 11.0, 0), steps = ch.weighted_error(10.0, 11.0, 1);
  EXPECT_NEAR(std::abs(tof), 1.0, 1e-12);
  EXPECT_NEAR(std::abs(steps), 4.0, 1e-12);
  EXPECT_GT(tof * steps, 0.0);  // the same sign for the same direction of error
  EXPECT_NEAR(std::abs(ch.weighted_error(10.0, 13.0, 1)), 12.0, 1e-12);
}

TEST(RoundThirteenFit, IdentifiabilityNamesWhyEachColumnIsUndetermined) {
  // Three columns over four rows: the second is zero (the readings do not depend on it), the
  // first and third are independent: only the zero column is undetermined, for that reason.
  using Id = epuck2::fit::Identifiability;
  Eigen::MatrixXd j(4, 3);
  j << 1, 0, 1, 2, 0, -1, 3, 0, 2, 4, 0, 0;
  const Id zero = epuck2::fit::check_identifiability(j, {true, true, true});
  ASSERT_EQ(zero.undetermined.size(), 1u);
  EXPECT_EQ(zero.undetermined[0].column, 1);
  EXPECT_TRUE(zero.any(Id::Why::zero_column));
  EXPECT_FALSE(zero.any(Id::Why::condition));
  EXPECT_FALSE(zero.any(Id::Why::rank_deficient));
  // The third column twice the first, none zero: rank deficient, no zero column.
  Eigen::MatrixXd k(4, 3);
  k << 1, 5, 2, 2, 1, 4, 3, 0, 6, 4, 2, 8;
  const Id twice = epuck2::fit::check_identifiability(k, {true, true, true});
  EXPECT_FALSE(twice.determined());
  EXPECT_FALSE(twice.any(Id::Why::zero_column));
  EXPECT_TRUE(twice.any(Id::Why::rank_deficient) || twice.any(Id::Why::condition));
  // Determined: nothing is named.
  const Id fine = epuck2::fit::check_identifiability(k.leftCols(2), {true, true});
  EXPECT_TRUE(fine.determined());
  EXPECT_FALSE(fine.any(Id::Why::zero_column));
  EXPECT_FALSE(fine.any(Id::Why::rank_deficient));
}

// ---- the virtual robot's wild readings: every whole value of [lo, hi] equally likely -----------

TEST(RoundThirteenVirtualRobot, WildWholeValuesReachTheTopOfTheirRange) {
  epuck2::virtual_robot::WildReadings w(7, 1.0);
  std::vector<int> count(4, 0);
  const int n = 8000;
  for (int i = 0; i < n; ++i) {
    double v = -1;
    EXPECT_TRUE(w.next(0.0, 3.0, true, &v));  // fraction 1: every reading wild
    ASSERT_GE(v, 0.0);
    ASSERT_LE(v, 3.0);
    ASSERT_EQ(v, std::floor(v));
    ++count[static_cast<std::size_t>(v)];
  }
  // Each of 0, 1, 2, 3 a quarter of the time: 2000, binomial sd sqrt(8000 * 0.25 * 0.75) = 39;
  // 6 sd either side.
  for (int c : count) EXPECT_NEAR(c, 2000, 240);
  // Not whole: uniform in [lo, hi), mean (lo + hi) / 2.
  double sum = 0;
  for (int i = 0; i < n; ++i) {
    double v = 0;
    w.next(2.0, 5.0, false, &v);
    ASSERT_GE(v, 2.0);
    ASSERT_LT(v, 5.0);
    sum += v;
  }
  EXPECT_NEAR(sum / n, 3.5, 6 * std::sqrt(0.75 / n));
}

TEST(RoundThirteenVirtualRobot, StrayLightLowersEveryLightReading) {
  // data/raw/light/README.md: stray ambient light lowers every reading by ambient_raw counts. One
  // robot, one intensity (1), no noise, no wild readings, no rail probe, one reading a distance:
  // sensor 0 (gain 1) at 0.2 m reads round(4095 (1 - (0.075 / 0.2)^2) - 12) = round(3507.14) =
  // 3507; sensor 7 (gain 0.94) round(4095 (1 - 0.94 * 0.140625) - 12) = round(3541.69) = 3542;
  // at 0.5 m (0.0225): round(4002.86 - 12) = 3991 and round(4008.39 - 12) = 3996.
  epuck2::virtual_robot::LightTruth t;
  t.noise_raw = 0;
  t.wild_fraction = 0;
  t.rail_readings = 0;
  t.readings = 1;
  t.intensities = {1.0};
  t.robot_gamma_scale = {1.0};
  t.distances_m = {0.2, 0.5};
  const auto files = epuck2::virtual_robot::light_logs(t, 3);
  ASSERT_EQ(files.size(), 1u);
  std::vector<std::string> data;
  std::istringstream in(files[0].content);
  for (std::string line; std::getline(in, line);)
    if (!line.empty() && line[0] != '#') data.push_back(line);
  const std::vector<std::string> want{"distance_m,intensity,sensor,value", "0.2,1,0,3507", "0.2,1,7,3542", "0.5,1,0,3991",
                                      "0.5,1,7,3996"};
  EXPECT_EQ(data, want);
}

TEST(RoundThirteenVirtualRobot, TheBatteryReferenceLogsAreTwoRobotsAtEverySpeed) {
  // data/raw/battery/README.md: robots a and b, each at 0..15 cm/s: 32 logs.
  const auto files = epuck2::virtual_robot::battery_reference_logs(epuck2::virtual_robot::kReferenceSeed);
  std::set<std::string> names;
  for (const auto& f : files) names.insert(f.name);
  EXPECT_EQ(files.size(), 32u);
  for (const char* robot : {"a", "b"})
    for (int s = 0; s <= 15; ++s) {
      char name[64];
      std::snprintf(name, sizeof name, "robot-%s_speed-%02d.csv", robot, s);
      EXPECT_EQ(names.count(name), 1u) << name;
    }
}

// ---- the voltage->charge map's parameter count ------------------------------------------------

TEST(RoundThirteenChargeMap, ALoadTermAddsOneParameterPerSpeedButTheFirst) {
  // docs/battery-models.md: the load term is an offset per speed, the first speed's 0 by
  // definition, so k speeds add k - 1 parameters to the knots' charges.
  epuck2::calibrate::ChargeMap m;
  m.knots_v = {3.4, 3.5, 3.6, 3.7, 3.8, 3.9, 4.0, 4.1};
  m.knot_charge = {0, 0.1, 0.2, 0.3, 0.5, 0.7, 0.9, 1.0};
  EXPECT_EQ(m.parameters(), 8u);
  m.load_speeds_cm_s = {0, 5, 10, 15};
  m.load_offset_v = {0, -0.01, -0.02, -0.03};
  EXPECT_EQ(m.parameters(), 11u);
}

// ---- through the CLI -------------------------------------------------------------------------

class RoundThirteenCli : public epuck2::testing::CliTest {
 protected:
  static std::string q(const std::string& p) { return "\"" + p + "\""; }
  static nlohmann::json fitted(const std::string& kind) { return epuck2::testing::shipped_fitted(kind); }
  /// A CSV line's cells.
  static std::vector<std::string> cells_of(const std::string& line) {
    std::vector<std::string> cells;
    std::stringstream ls(line);
    for (std::string c; std::getline(ls, c, ',');) cells.push_back(c);
    return cells;
  }
};

TEST_F(RoundThirteenCli, TheLargestSeedTheHelpStatesIsAccepted) {
  // docs/cli.md: --seed is an unsigned 64-bit integer, 0 .. 2^64 - 1 = 18446744073709551615.
  const CliRun top = run("generate proximity --seed 18446744073709551615 -o " + q((dir_ / "top").string()));
  EXPECT_EQ(top.exit_code, 0) << top.err;
  const CliRun past = run("generate proximity --seed 18446744073709551616 -o " + q((dir_ / "past").string()));
  EXPECT_EQ(past.exit_code, 2);
  EXPECT_NE(past.err.find("out of range"), std::string::npos) << past.err;
}

TEST_F(RoundThirteenCli, AFitWithFewerThanThreeReadingsPerParameterSaysSoAndNotAtThree) {
  // docs/fitting.md: a fit with fewer than 3 readings per free parameter (the noise counted)
  // warns. The light fit has gamma and the noise: 5 readings warn, 6 do not. Readings on the
  // plug-in's curve 4095 (1 - (0.075 I / d)^2), I = 0.5, with a small fixed scatter.
  auto log_of = [&](int rows) {
    std::string t = "distance_m,intensity,sensor,value\n";
    const double d[] = {0.08, 0.1, 0.12, 0.15, 0.2, 0.25};
    for (int i = 0; i < rows; ++i) {
      const double r = 0.075 * 0.5 / d[i];
      t += std::to_string(d[i]) + ",0.5,0," + std::to_string(std::lround(4095 * (1 - r * r) + (i % 2 ? 3 : -3))) + "\n";
    }
    return write("l" + std::to_string(rows) + ".csv", t);
  };
  const CliRun five = run("light " + q(log_of(5)));
  EXPECT_EQ(five.exit_code, 0) << five.err;
  EXPECT_NE(five.err.find("only 5 readings inside the rails for 1 free parameter and the noise (fewer than 3 per parameter)"),
            std::string::npos)
      << five.err;
  const CliRun six = run("light " + q(log_of(6)));
  EXPECT_EQ(six.exit_code, 0) << six.err;
  EXPECT_EQ(six.err.find("only 6 readings inside the rails"), std::string::npos) << six.err;
}

TEST_F(RoundThirteenCli, ABatteryTableAtAFractionalSpeedIsRefused) {
  // docs/coefficient-files.md: a table's speed_cm_s is a whole number of cm/s in 0..15. The reader
  // of partial tables (one table here, the plug-in's for the other speeds: ARGoS's calibrated
  // battery reads a file so) takes 2 and refuses 2.5 at its JSON path.
  nlohmann::json j = fitted("battery");
  nlohmann::json speed = j.at("speeds").at(2);
  for (const auto& [v, ok] : {std::pair<double, bool>{2.0, true}, {2.5, false}, {15.0, true}, {16.0, false}}) {
    speed["speed_cm_s"] = v;
    j["speeds"] = nlohmann::json::array({speed});
    epuck2::coefficients::TableSources sources;
    std::string err;
    try {
      epuck2::coefficients::battery_tables_from_json(j, "b.json", sources);
    } catch (const std::exception& e) {
      err = e.what();
    }
    if (ok) {
      EXPECT_EQ(err, "") << v;
      ASSERT_EQ(sources.fitted_speeds.size(), 1u) << v;
      EXPECT_EQ(sources.fitted_speeds[0], static_cast<int>(v));
    } else {
      EXPECT_NE(err.find("speed_cm_s must be a whole number of cm/s in 0..15 (found " + nlohmann::json(v).dump() + ")"),
                std::string::npos)
          << v << ": " << err;
      EXPECT_NE(err.find("/speeds/0/speed_cm_s"), std::string::npos) << err;
    }
  }
}

TEST_F(RoundThirteenCli, AnErrorInACompactFileIsPlacedAtItsColumn) {
  // A coefficient file written on one line (no spaces): the error's column is where its value
  // starts, found here by searching the text. Numbers before it end at ',', '}' and ']'.
  nlohmann::json j = fitted("ground");
  j["parameters"]["gain"][2] = -12345.5;
  const std::string text = j.dump();
  const std::size_t at = text.find("-12345.5");
  ASSERT_NE(at, std::string::npos);
  ASSERT_NE(text.substr(0, at).find("}"), std::string::npos);  // a number closed by '}' comes first
  const std::string file = write("g.json", text);
  const CliRun r = run("codegen " + q(file) + " -o " + q((dir_ / "g.hpp").string()));
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.err.find(file + ":1:" + std::to_string(at + 1) + ": parameters.gain[2] = -12345.5"), std::string::npos)
      << r.err;
}

TEST_F(RoundThirteenCli, ARangeErrorShowsWhichEndsAreOpen) {
  // docs/coefficient-files.md: the camera's range_m lies in (0, 10] m (0 refused, 10 taken).
  nlohmann::json j = fitted("camera");
  j["parameters"]["range_m"] = 0.0;
  const CliRun r = run("codegen " + q(write("c.json", j.dump(2))) + " -o " + q((dir_ / "c.hpp").string()));
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.err.find("parameters.range_m = 0.0 is outside its physical range (0.0, 10.0] m"), std::string::npos) << r.err;
  j["parameters"]["range_m"] = 10.0;
  const CliRun ten = run("codegen " + q(write("c10.json", j.dump(2))) + " -o " + q((dir_ / "c10.hpp").string()));
  EXPECT_EQ(ten.exit_code, 0) << ten.err;
}

TEST_F(RoundThirteenCli, TheDiagnosisCountsReadingsOnBothRails) {
  // docs/diagnose.md: `censored` counts the readings on a rail, 0 at or below the low one, 4095 at
  // or above the high one (proximity), after wild readings are left out. Counted here from the
  // shipped logs' value column, less the listed wild readings that sat on a rail. The shipped
  // proximity logs have readings on both rails (the 0 mm readings saturate at 4095).
  std::size_t low = 0, high = 0;
  for (const fs::path& log : epuck2::testing::shipped_logs("proximity")) {
    std::istringstream in(epuck2::testing::slurp(log));
    std::string line;
    int column = -1;
    while (std::getline(in, line)) {
      if (line.empty() || line[0] == '#') continue;
      const std::vector<std::string> cells = cells_of(line);
      if (column < 0) {
        column = static_cast<int>(std::find(cells.begin(), cells.end(), "value") - cells.begin());
        continue;
      }
      const double v = std::stod(cells.at(static_cast<std::size_t>(column)));
      low += v <= 0 ? 1 : 0;
      high += v >= 4095 ? 1 : 0;
    }
  }
  ASSERT_GT(low, 0u);
  ASSERT_GT(high, 0u);
  const CliRun r = run("diagnose --json" + shipped("proximity"));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const nlohmann::json j = nlohmann::json::parse(r.out);
  std::size_t wild_on_rail = 0;
  for (const auto& row : j.at("outliers").at("rows")) {
    const std::string t = row.get<std::string>();
    const std::size_t at = t.find(": value ");
    ASSERT_NE(at, std::string::npos) << t;
    const double v = std::stod(t.substr(at + 8));
    wild_on_rail += (v <= 0 || v >= 4095) ? 1 : 0;
  }
  EXPECT_EQ(j.at("censored").get<std::size_t>(), low + high - wild_on_rail);
}

TEST_F(RoundThirteenCli, TheDriveDiagnosisRSquaredDoesNotMoveWithTheToFsLevel) {
  // docs/diagnose.md: R^2 measures each channel's readings about their own channel's mean. Move
  // the obstacle 0.1 m farther and every ToF reading 100 mm up: the base model's ToF predictions
  // move with them (obstacle minus travel), the residuals and the noise are unchanged, and each
  // channel's spread about its own mean is unchanged, so every R^2 stays (to rounding). The
  // encoders' spread measured about any other level would move it. The shipped drive logs whose
  // ToF stays inside its 20..2000 mm rails after the shift (no rail, no code, either way).
  const fs::path a = dir_ / "a", b = dir_ / "b";
  fs::create_directories(a);
  fs::create_directories(b);
  std::size_t used = 0;
  for (const fs::path& log : epuck2::testing::shipped_logs("drive")) {
    const std::string name = log.filename().string();
    std::istringstream in(epuck2::testing::slurp(log));
    std::string line, shifted, original;
    int column = -1;
    bool inside = true;
    while (std::getline(in, line)) {
      original += line + "\n";
      if (line.rfind("# obstacle_distance_m:", 0) == 0) {
        const double d = std::stod(line.substr(22));
        shifted += "# obstacle_distance_m: " + std::to_string(d + 0.1) + "\n";
        continue;
      }
      if (line.empty() || line[0] == '#') {
        shifted += line + "\n";
        continue;
      }
      std::vector<std::string> cells = cells_of(line);
      if (column < 0) {
        column = static_cast<int>(std::find(cells.begin(), cells.end(), "tof_mm") - cells.begin());
        shifted += line + "\n";
        continue;
      }
      const double tof = std::stod(cells.at(static_cast<std::size_t>(column)));
      inside = inside && tof > 20 && tof + 100 < 2000;
      cells[static_cast<std::size_t>(column)] = std::to_string(static_cast<long>(tof) + 100);
      std::string row;
      for (std::size_t k = 0; k < cells.size(); ++k) row += (k ? "," : "") + cells[k];
      shifted += row + "\n";
    }
    if (!inside) continue;
    ++used;
    std::ofstream(a / name) << original;
    std::ofstream(b / name) << shifted;
  }
  ASSERT_GE(used, 10u);
  auto diagnose = [&](const fs::path& d) {
    std::string args = "diagnose --json";
    std::vector<std::string> files;
    for (const auto& e : fs::directory_iterator(d)) files.push_back(e.path().string());
    std::sort(files.begin(), files.end());
    for (const auto& f : files) args += " " + q(f);
    const CliRun r = run(args);
    EXPECT_EQ(r.exit_code, 0) << r.err;
    return nlohmann::json::parse(r.out);
  };
  const nlohmann::json ja = diagnose(a), jb = diagnose(b);
  for (const char* fit : {"recalibrated", "final"}) {
    const double ra = ja.at("fit").at(fit).at("r2").get<double>(), rb = jb.at("fit").at(fit).at("r2").get<double>();
    EXPECT_NEAR(ra, rb, 1e-12) << fit;
    EXPECT_NEAR(ja.at("fit").at(fit).at("rss").get<double>(), jb.at("fit").at(fit).at("rss").get<double>(),
                1e-6 * ja.at("fit").at(fit).at("rss").get<double>())  // the final fit converges to ~1e-7
        << fit;
    EXPECT_LT(ra, 1.0) << fit;
  }
}

TEST_F(RoundThirteenCli, TheStaticSpeedCountsAsCovered) {
  // docs/cli.md (battery): the speeds covered are those of 0..15 cm/s with a log; 0 cm/s (the
  // robot at rest) is one of them. Logs at 0 and 1 cm/s: covered 0, 1; missing 2..15; no other.
  const std::string logs = " " + q((fs::path(EPUCK2_SOURCE_DIR) / "data/raw/battery/robot-a_speed-00.csv").string()) + " " +
                           q((fs::path(EPUCK2_SOURCE_DIR) / "data/raw/battery/robot-a_speed-01.csv").string());
  const CliRun r = run("battery --json" + logs);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const nlohmann::json j = nlohmann::json::parse(r.out);
  EXPECT_EQ(j.at("speeds_covered_cm_s"), nlohmann::json({0, 1}));
  EXPECT_EQ(j.at("speeds_missing_cm_s"), nlohmann::json({2, 3, 4, 5, 6, 7, 8, 9, 10, 11, 12, 13, 14, 15}));
  EXPECT_TRUE(j.at("speeds_other_cm_s").empty()) << j.at("speeds_other_cm_s");
  const CliRun t = run("battery" + logs);
  EXPECT_NE(t.out.find("speeds covered (cm/s): 0, 1"), std::string::npos) << t.out;
}

}  // namespace test_round_thirteen_cpp
