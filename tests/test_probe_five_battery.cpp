// Defects a fifth new user's probe found (session 23) in the battery calibration: a run that
// starts at exactly 1.000 charge gave knots a rounding above 1, so that no reader took the file
// `battery` wrote (and the warning named the wrong table); a fitted charge map with a load term put
// its knots at the logged voltages, not the corrected ones it is a function of. Expected values
// come from the logs the test writes (their formula) and docs/coefficient-files.md's definitions.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <stdexcept>
#include <string>

#include <nlohmann/json.hpp>

#include "cli_harness.hpp"
#include "epuck2/coefficients/battery_tables.hpp"
#include "epuck2/models/plugin_battery_tables.hpp"
#include "seeded_normal.hpp"

namespace test_probe_five_battery_cpp {

using epuck2::testing::CliRun;
using epuck2::testing::slurp;
using nlohmann::json;

bool has(const std::string& text, const std::string& part) { return text.find(part) != std::string::npos; }

/// A battery log of one run at `speed` (cm/s) lasting `life` s, a row every 60 s: the charge reads
/// exactly 1.000 for the first 12 % of the run (a full gauge), then falls as
/// 1 - 0.9 x + 0.3 x^2 - 0.4 x^3 (x from 0 at the end of the flat part to 1 at `life`) with a
/// reading noise of sd 0.002, never above 1 (the probe's gen_flat.py, with the tests' own seeded
/// normal).
std::string flat_start_log(const std::string& robot, int speed, double life, epuck2::testing::Normal& noise) {
  std::string text = "# robot: " + robot + "\ntime_s,speed_cm_s,charge\n";
  const double flat = 0.12 * life;
  double c = 1.0;
  char line[96];
  for (double t = 0; t < life; t += 60) {
    if (t < flat) {
      c = 1.0;
    } else {
      const double x = (t - flat) / (life - flat);
      c = std::min(1.0, 1 - 0.9 * x + 0.3 * x * x - 0.4 * x * x * x + 0.002 * noise());
    }
    std::snprintf(line, sizeof line, "%.1f,%d,%.4f\n", t, speed, c);
    text += line;
  }
  std::snprintf(line, sizeof line, "%.1f,%d,%.4f\n", life, speed, std::max(c, 0.0));
  return text + line;
}

class ProbeFiveBattery : public epuck2::testing::CliTest {
 protected:
  /// The 32 logs (16 speeds, robots fa and fb) as command-line arguments.
  std::string flat_start_logs() {
    epuck2::testing::Normal noise(42);
    std::string args;
    for (int s = 0; s < 16; ++s)
      for (const char* robot : {"fa", "fb"}) {
        const double life = 30000 - 1500 * s + 400 * (noise.uniform() - 0.5);
        char name[32];
        std::snprintf(name, sizeof name, "flat_%02d_%s.csv", s, robot);
        args += " \"" + write(name, flat_start_log(robot, s, life, noise)) + "\"";
      }
    return args;
  }
};

// The readings of the first 12 % of every run are exactly 1.000: the Approximated model's first
// knot, at the end of that flat part, has the charge 1 (the least squares of readings all 1 is 1),
// and every knot's charge is in [0, 1], the range the readers check. Unbounded, the fit put y1 one
// to a few thousand ulps above 1 at some speeds; `battery` wrote the file with a warning and
// codegen and simulate refused it.
TEST_F(ProbeFiveBattery, AFlatStartAtFullChargeGivesAFileTheReadersTake) {
  const std::string file = (dir_ / "flat.json").string();
  const CliRun b = run("battery" + flat_start_logs() + " -o \"" + file + "\"");
  ASSERT_EQ(b.exit_code, 0) << b.err;
  EXPECT_FALSE(has(b.err, "no reader takes it")) << b.err;
  const json j = json::parse(slurp(file));
  EXPECT_TRUE(j.at("complete_tables").get<bool>());
  const json& speeds = j.at("speeds");
  ASSERT_EQ(speeds.size(), 16u);
  int held_at_full = 0;
  for (std::size_t i = 0; i < speeds.size(); ++i) {
    const json& bp = speeds.at(i).at("breakpoints");
    const double y1 = bp.at("parameters").at("y1").get<double>();
    // The knot is where the flat part ends or a little after: within 0.001 of full (hand: the
    // curve falls 0.9 per run after the flat part; the knot is within 1 % of a run from it).
    EXPECT_LE(y1, 1.0) << "speed " << i;
    EXPECT_GE(y1, 0.999) << "speed " << i;
    for (const char* k : {"y2", "y3"}) {
      EXPECT_LE(bp.at("parameters").at(k).get<double>(), 1.0) << k << " speed " << i;
      EXPECT_GE(bp.at("parameters").at(k).get<double>(), 0.0) << k << " speed " << i;
    }
    for (const json& g : speeds.at(i).at("segments")) {
      EXPECT_LE(g.at("y1").get<double>(), 1.0) << "speed " << i;
      EXPECT_LE(g.at("y2").get<double>(), 1.0) << "speed " << i;
    }
    if (y1 == 1.0) {
      ++held_at_full;
      // Held at the bound: no standard error, and said why.
      EXPECT_TRUE(bp.at("std_errors").at("y1").is_null()) << "speed " << i;
      EXPECT_TRUE(has(bp.at("std_error_why").at("y1").get<std::string>(), "upper bound")) << "speed " << i;
    }
  }
  // The case the probe met: at some speeds the free fit ended above 1 and the bound holds it.
  EXPECT_GE(held_at_full, 1);
  const CliRun c = run("codegen \"" + file + "\" -o \"" + (dir_ / "flat.hpp").string() + "\"");
  EXPECT_EQ(c.exit_code, 0) << c.err;
  const std::string profile = write("prof.csv", "time_s,speed_cm_s\n0,5\n3600,5\n");
  const CliRun s = run("simulate battery --model cubic --profile \"" + profile + "\" --coefficients \"" + file + "\"");
  EXPECT_EQ(s.exit_code, 0) << s.err;
}

// A table no reader takes is still written as fitted, with a warning that names where it is in
// the file: speeds[1] (the second speed logged), not the scratch table's speeds[0]. Speed 0 falls
// as a battery does; at 3 cm/s the charge rises from 0.2 to 0.95 (a log of a charging battery):
// its segments rise, which no reader takes.
TEST_F(ProbeFiveBattery, TheUnreadableTableWarningNamesItsPlaceInTheFile) {
  std::string args;
  for (const char* robot : {"a", "b"}) {
    std::string fall = std::string("# robot: ") + robot + "\ntime_s,speed_cm_s,charge\n";
    std::string rise = fall;
    char line[64];
    for (int i = 0; i <= 300; ++i) {
      std::snprintf(line, sizeof line, "%d,0,%.4f\n", i * 60, 1.0 - 0.95 * i / 300.0 + (robot[0] == 'a' ? 0.001 : -0.001) * (i % 2));
      fall += line;
      std::snprintf(line, sizeof line, "%d,3,%.4f\n", i * 60, 0.2 + 0.75 * i / 300.0 + (robot[0] == 'a' ? 0.001 : -0.001) * (i % 2));
      rise += line;
    }
    args += " \"" + write(std::string("fall_") + robot + ".csv", fall) + "\" \"" + write(std::string("rise_") + robot + ".csv", rise) + "\"";
  }
  const std::string file = (dir_ / "rise.json").string();
  const CliRun b = run("battery" + args + " -o \"" + file + "\"");
  ASSERT_EQ(b.exit_code, 0) << b.err;
  ASSERT_TRUE(has(b.err, "written as fitted though no reader takes it: cannot write the battery table at 3.0 cm/s")) << b.err;
  EXPECT_TRUE(has(b.err, "(at JSON path /speeds/1/")) << b.err;
  EXPECT_TRUE(has(b.err, "): speeds[1].")) << b.err;
  EXPECT_FALSE(has(b.err, "/speeds/0/")) << b.err;
  // The file has the 3 cm/s table at speeds[1], where the warning points.
  const json j = json::parse(slurp(file));
  EXPECT_EQ(j.at("speeds").at(1).at("speed_cm_s").get<double>(), 3.0);
}

// The owner's writer names the entry's index it is given: a rising linear slope at index 7 is
// refused at /speeds/7/linear_slope, as a reader of the whole file refuses it.
TEST_F(ProbeFiveBattery, TheSpeedWriterNamesTheIndexItIsGiven) {
  namespace mb = epuck2::models::battery;
  const mb::Tables plugin = mb::plugin_tables();
  mb::CubicRow q = plugin.cubic[7];
  q.end_s = plugin.lifetime_s[7];
  std::string what;
  try {
    epuck2::coefficients::battery_speed_to_json(7.0, q, 2e-4, plugin.segments[7], std::numeric_limits<double>::quiet_NaN(), true, 7);
  } catch (const std::domain_error& e) {
    what = e.what();
  }
  EXPECT_TRUE(has(what, "speeds[7].linear_slope must be negative")) << what;
  EXPECT_TRUE(has(what, "(at JSON path /speeds/7/linear_slope)")) << what;
}

/// The probe's truth map: f linear between (3.3 V, 0), (3.6, 0.3), (3.9, 0.75), (4.2, 1).
double truth_charge(double u) {
  const double x[4] = {3.3, 3.6, 3.9, 4.2}, y[4] = {0.0, 0.3, 0.75, 1.0};
  int k = u < x[1] ? 0 : (u < x[2] ? 1 : 2);
  return y[k] + (y[k + 1] - y[k]) * (u - x[k]) / (x[k + 1] - x[k]);
}

// Five runs at 0, 3, 6, 9 and 12 cm/s whose voltage sags 4 mV per cm/s: the corrected voltage
// u = voltage_v + 0.004 speed runs from 4.2 V down to 3.3 V at every speed (1 mV a row) and the
// charge is the truth map of it. The fitted map keeps the load term (the charge depends on the
// speed beyond the logged voltage) and is a function of the corrected voltage: its knots sit at
// quantiles of the corrected voltages, the first and last at their extremes
// (docs/coefficient-files.md#charge-map), i.e. at the ends of voltage_range_v. Hand: the corrected
// range is 3.3..4.2 V (each run's lowest logged voltage is 3.3 - 0.004 speed, down to 3.252 V at
// 12 cm/s), f there 0 and 1. The knots were at the logged voltages: the first at 3.252 V, below the
// map's own domain, with a charge of about -0.05 that no reading has.
TEST_F(ProbeFiveBattery, AChargeMapWithALoadTermHasItsKnotsAtTheCorrectedVoltages) {
  std::string args;
  double lowest_corrected = 1e9, highest_corrected = -1e9, lowest_logged = 1e9;
  for (int speed : {0, 3, 6, 9, 12}) {
    std::string text = "time_s,speed_cm_s,voltage_v,charge\n";
    char line[96];
    for (int i = 0; i <= 900; ++i) {
      const double u = (4200 - i) / 1000.0;
      const double v = (4200 - i - 4 * speed) / 1000.0;  // to the 0.1 mV the log holds, exactly
      std::snprintf(line, sizeof line, "%d,%d,%.4f,%.7f\n", i * 30, speed, v, truth_charge(u));
      text += line;
      lowest_corrected = std::min(lowest_corrected, v + 0.004 * speed);
      highest_corrected = std::max(highest_corrected, v + 0.004 * speed);
      lowest_logged = std::min(lowest_logged, v);
    }
    args += " \"" + write("lf_" + std::to_string(speed) + ".csv", text) + "\"";
  }
  ASSERT_NEAR(lowest_corrected, 3.3, 1e-12);
  ASSERT_NEAR(highest_corrected, 4.2, 1e-12);
  ASSERT_NEAR(lowest_logged, 3.252, 1e-12);
  const std::string file = (dir_ / "lf.json").string();
  const CliRun b = run("battery" + args + " -o \"" + file + "\"");
  ASSERT_EQ(b.exit_code, 0) << b.err;
  const json j = json::parse(slurp(file));
  const json& m = j.at("charge_map");
  ASSERT_EQ(m.at("load").get<std::string>(), "per_speed") << m.dump(1);
  // The sag recovered: 0.004 V per cm/s (to 1 mV: the map's knots are not the truth's).
  const json& offsets = m.at("load_offset_v");
  ASSERT_EQ(offsets.size(), 5u);
  for (std::size_t k = 0; k < 5; ++k) EXPECT_NEAR(offsets.at(k).get<double>(), 0.012 * static_cast<double>(k), 1e-3) << k;
  const json& knots = m.at("knots_v");
  const json& charge = m.at("knot_charge");
  const json& range = m.at("voltage_range_v");
  ASSERT_GE(knots.size(), 2u);
  // The domain: the corrected voltages' extremes (hand 3.3 and 4.2, to the offsets' error).
  EXPECT_NEAR(range.at(0).get<double>(), lowest_corrected, 1e-3);
  EXPECT_NEAR(range.at(1).get<double>(), highest_corrected, 1e-3);
  // The first and last knots at the domain's ends, not at the logged extremes.
  EXPECT_NEAR(knots.front().get<double>(), range.at(0).get<double>(), 1e-6);
  EXPECT_NEAR(knots.back().get<double>(), range.at(1).get<double>(), 1e-6);
  EXPECT_GT(knots.front().get<double>(), lowest_logged + 0.04);
  // f at the ends: the truth's 0 and 1 (to the map's misfit), no negative charge.
  EXPECT_NEAR(charge.front().get<double>(), 0.0, 0.01);
  EXPECT_NEAR(charge.back().get<double>(), 1.0, 0.01);
  EXPECT_GE(charge.front().get<double>(), -0.01);
  // The knots in between at quantiles of the corrected voltages, which are spread evenly over
  // 3.3..4.2 V here (every speed covers it at 1 mV a row): the k-th of K knots within a few mV of
  // 3.3 + 0.9 k / (K - 1).
  const std::size_t K = knots.size();
  for (std::size_t k = 0; k < K; ++k)
    EXPECT_NEAR(knots.at(k).get<double>(), 3.3 + 0.9 * static_cast<double>(k) / static_cast<double>(K - 1), 5e-3) << k;
}

}  // namespace test_probe_five_battery_cpp
