// Defects a fourth new user's probe found (session 23): the light's plug-in MSE on the unclamped
// curve, a robot's light set read with the pooled per-sensor gammas, a railed reading near its
// clamp called wild, and `table5 --charge-map` printing "residual sd nan" for a map written by
// hand. Every expected value is computed here from the rows the test writes (the generator's
// truth) or from the docs' formulas, never taken from the code under test.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <functional>
#include <sstream>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "cli_harness.hpp"
#include "epuck2/coefficients/model_file.hpp"
#include "epuck2/fit/replicates.hpp"
#include "epuck2/models/kinds.hpp"

namespace test_probe_four_cpp {

using epuck2::testing::CliRun;
using epuck2::testing::slurp;
using nlohmann::json;

bool has(const std::string& text, const std::string& part) { return text.find(part) != std::string::npos; }

struct LightRow {
  double distance_m, intensity;
  int sensor;
  double value;
};

std::string light_text(const std::string& robot, const std::vector<LightRow>& rows) {
  std::string text = "# robot: " + robot + "\ndistance_m,intensity,sensor,value\n";
  for (const LightRow& r : rows) {
    char line[96];
    std::snprintf(line, sizeof line, "%.4f,%.3f,%d,%.0f\n", r.distance_m, r.intensity, r.sensor, r.value);
    text += line;
  }
  return text;
}

/// Eq. 2 without noise, in counts: 4095 (1 - (gamma I / d)^2), unclamped.
double eq2_raw(double gamma_m, double intensity, double distance_m) {
  const double r = gamma_m * intensity / distance_m;
  return 4095.0 * (1.0 - r * r);
}

/// Readings of sensors 0..7, sensor s with gamma `gamma_of(s)`, at 0.15..0.40 m and intensities 1
/// and 0.5, five replicates each at +{-2, -1, 0, 1, 2} counts around the rounded curve.
std::vector<LightRow> light_rows(const std::function<double(int)>& gamma_of) {
  std::vector<LightRow> rows;
  for (int s = 0; s < 8; ++s)
    for (double d : {0.15, 0.20, 0.25, 0.30, 0.40})
      for (double in : {1.0, 0.5})
        for (int e = -2; e <= 2; ++e) rows.push_back({d, in, s, std::round(eq2_raw(gamma_of(s), in, d)) + e});
  return rows;
}

class ProbeFour : public epuck2::testing::CliTest {};

// docs/coefficient-files.md: `reference_mse.plugin` is the plug-in's gamma = 0.075 (1/13.3333333333333,
// the plug-in's source) on the readings inside the rails, its reading clamped as the plug-in's:
// 1 - (0.075 I / d)^2 clamped to 0..1. A light at 5 cm of intensity 1 puts the unclamped curve at
// 1 - 2.25 = -1.25 (5119 counts below the rail): a reading of 12 counts there (the plug-in reads 0)
// was a misfit of 1.25 in the plug-in's MSE, now of 12/4095.
TEST_F(ProbeFour, LightPluginMseIsTheClampedPluginsReading) {
  std::vector<LightRow> rows = light_rows([](int) { return 0.08; });
  for (double v : {3.0, 7.0, 12.0, 0.0, 0.0}) rows.push_back({0.05, 1.0, 0, v});  // bright: the plug-in reads 0
  for (double v : {20.0, 5.0, 0.0}) rows.push_back({0.06, 1.0, 1, v});
  const std::string log = write("bright.csv", light_text("r", rows));
  const CliRun r = run("light --json \"" + log + "\"");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const json j = json::parse(r.out);
  const double gamma = 1.0 / 13.3333333333333;
  double sum = 0, unclamped_sum = 0;
  std::size_t n = 0;
  for (const LightRow& row : rows) {
    if (!(row.value > 0 && row.value < 4095)) continue;  // on a rail: censored, not in the MSE
    const double curve = 1.0 - std::pow(gamma * row.intensity / row.distance_m, 2);
    const double e = row.value / 4095.0 - std::clamp(curve, 0.0, 1.0);
    const double u = row.value / 4095.0 - curve;
    sum += e * e;
    unclamped_sum += u * u;
    ++n;
  }
  const double expected = sum / static_cast<double>(n);
  ASSERT_GT(unclamped_sum / static_cast<double>(n), 10 * expected);  // the two differ: the case tests something
  const double got = j.at("reference_mse").at("plugin").get<double>();
  EXPECT_NEAR(got, expected, 1e-9 * expected) << "unclamped would be " << unclamped_sum / static_cast<double>(n);
  // The report prints the same number, and says the reading is clamped.
  const CliRun t = run("light \"" + log + "\"");
  ASSERT_EQ(t.exit_code, 0) << t.err;
  char line[160];
  std::snprintf(line, sizeof line, "its reading clamped to 0..4095, MSE on the readings inside the rails %.3e", expected);
  EXPECT_TRUE(has(t.out, line)) << t.out << "\nexpected: " << line;
}

// A light file of two robots: each robot's set holds that robot's own per-sensor gammas, fitted to
// its rows, and a reader asked for a robot (ARGoS's robot="ID", the library's light_model_from_json
// with the robot) reads them; it read the file's pooled per-sensor gammas, so that choosing a robot
// changed nothing for light. Robot A's sensor s has gamma 0.060 + 0.002 s, robot B's 0.090 +
// 0.002 s; the readings scatter 1.4 counts, so each fit lands within 1e-4 m of its truth.
TEST_F(ProbeFour, LightRobotSetsHoldEachRobotsOwnSensorGammas) {
  auto gamma_a = [](int s) { return 0.060 + 0.002 * s; };
  auto gamma_b = [](int s) { return 0.090 + 0.002 * s; };
  const std::string a = write("a.csv", light_text("A", light_rows(gamma_a)));
  const std::string b = write("b.csv", light_text("B", light_rows(gamma_b)));
  const std::string file = (dir_ / "light.json").string();
  // --accept-misfit: each robot's one gamma misses its sensors' own (what per_sensor is for).
  const CliRun r = run("light --accept-misfit \"" + a + "\" \"" + b + "\" -o \"" + file + "\"");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const json j = json::parse(slurp(file));
  ASSERT_TRUE(j.at("robots").at("A").contains("per_sensor")) << j.at("robots").at("A").dump();
  namespace s = epuck2::models::sensors;
  const s::LightModel pooled = epuck2::coefficients::light_model_from_json(j, file);
  const s::LightModel ma = epuck2::coefficients::light_model_from_json(j, file, "A");
  const s::LightModel mb = epuck2::coefficients::light_model_from_json(j, file, "B");
  for (int k = 0; k < 8; ++k) {
    EXPECT_NEAR(s::light_gamma_m(ma, k), gamma_a(k), 1e-4) << "sensor " << k;
    EXPECT_NEAR(s::light_gamma_m(mb, k), gamma_b(k), 1e-4) << "sensor " << k;
    // The pooled per-sensor gamma lies between the robots': neither robot's.
    EXPECT_GT(std::abs(s::light_gamma_m(pooled, k) - gamma_a(k)), 0.01) << "sensor " << k;
    // What each robot's set simulates: its own curve, e.g. at 0.2 m and intensity 1.
    EXPECT_NEAR(s::mean_raw(ma, k, 1.0, 0.2), eq2_raw(gamma_a(k), 1.0, 0.2), 2.0) << "sensor " << k;
    EXPECT_NEAR(s::mean_raw(mb, k, 1.0, 0.2), eq2_raw(gamma_b(k), 1.0, 0.2), 2.0) << "sensor " << k;
  }
  // Robot A's set matches robot A fitted alone (`--robot A`), sensor by sensor.
  const std::string alone = (dir_ / "a_alone.json").string();
  ASSERT_EQ(run("light --accept-misfit --robot A \"" + a + "\" \"" + b + "\" -o \"" + alone + "\"").exit_code, 0);
  const s::LightModel own = epuck2::coefficients::light_model_from_json(json::parse(slurp(alone)), alone);
  for (int k = 0; k < 8; ++k) EXPECT_NEAR(s::light_gamma_m(ma, k), s::light_gamma_m(own, k), 1e-12) << "sensor " << k;
  // A robot's set written without a list reads the robot's gamma on every sensor, never the file's
  // pooled per-sensor ones.
  json bare = j;
  bare["robots"]["A"].erase("per_sensor");
  const s::LightModel plain = epuck2::coefficients::light_model_from_json(bare, file, "A");
  for (int k = 0; k < 8; ++k) EXPECT_EQ(s::light_gamma_m(plain, k), plain.base.gamma_m) << "sensor " << k;
  EXPECT_NEAR(plain.base.gamma_m, j.at("robots").at("A").at("parameters").at("gamma").get<double>(), 1e-15);
}

// docs/fitting.md: a railed reading is censored (at or beyond its rail), so it is wild only when it
// is its group's one railed reading and even its distance to the median is beyond the 8 robust sd
// any reading is judged by. Groups of five readings scattering about 10 counts (robust sd 8.9: the
// typical group's), and one group just below the dark rail, {4068, 4072, 4073, 4074, 4095}: its
// inside readings' robust sd is 1.48, floored at half the typical, 4.45; the 4095 is 22 counts from
// the median 4073, 2.2 of the groups' true sd (about 1.9 above its group's mean): 4.9 floored sd,
// past the railed readings' old threshold of 4, not wild. A reading 200 counts (20 sd) from its
// group, inside the rails, is still wild.
TEST_F(ProbeFour, ARailedReadingNearItsClampIsNotWild) {
  std::vector<double> values;
  std::vector<int> group;
  std::vector<bool> on_rail;
  for (int g = 0; g < 12; ++g)
    for (double e : {-13.0, -6.0, 0.0, 6.0, 13.0}) {
      values.push_back(2000.0 + 100.0 * g + e + (g == 3 && e == 13.0 ? 200.0 : 0.0));
      group.push_back(g);
      on_rail.push_back(false);
    }
  const std::size_t wild_one = 3 * 5 + 4;
  for (double v : {4068.0, 4072.0, 4073.0, 4074.0, 4095.0}) {
    values.push_back(v);
    group.push_back(12);
    on_rail.push_back(v >= 4095.0);
  }
  const std::size_t railed = values.size() - 1;
  const std::vector<bool> wild = epuck2::fit::flag_wild_replicates(values, group, on_rail, 0.2886751345948129);
  EXPECT_FALSE(wild[railed]);
  EXPECT_TRUE(wild[wild_one]);
  EXPECT_EQ(std::count(wild.begin(), wild.end(), true), 1);
  // A stray 4095 in a group far from the rail is still wild.
  std::vector<double> far = values;
  far[railed - 1] = 3000.0;
  far[railed - 2] = 3004.0;
  far[railed - 3] = 2996.0;
  far[railed - 4] = 3010.0;
  EXPECT_TRUE(epuck2::fit::flag_wild_replicates(far, group, on_rail, 0.2886751345948129)[railed]);

  // The same through the light fit: the group just below the rail at 0.21 m and intensity 0.2
  // (Eq. 2 at gamma 0.075: 4074.1 counts), the others 10 counts of scatter about the plug-in's curve.
  std::vector<LightRow> rows;
  for (int s = 0; s < 8; ++s)
    for (double d : {0.15, 0.20, 0.25, 0.30})
      for (double e : {-13.0, -6.0, 0.0, 6.0, 13.0}) rows.push_back({d, 1.0, s, std::round(eq2_raw(0.075, 1.0, d)) + e});
  rows[4].value += 200.0;  // sensor 0 at 0.15 m: 20 sd from its group
  for (double v : {4068.0, 4072.0, 4073.0, 4074.0, 4095.0}) rows.push_back({0.21, 0.2, 0, v});
  const std::string log = write("near_rail.csv", light_text("r", rows));
  const CliRun r = run("light --json \"" + log + "\"");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const json j = json::parse(r.out);
  // Rows start at line 3 (the robot's line, the header).
  const std::string wild_at = log + ":" + std::to_string(3 + 4), railed_at = log + ":" + std::to_string(3 + rows.size() - 1);
  std::vector<std::string> outliers;
  for (const json& w : j.at("outliers").at("rows")) outliers.push_back(w.get<std::string>());
  EXPECT_NE(std::find(outliers.begin(), outliers.end(), wild_at), outliers.end()) << j.at("outliers").dump();
  EXPECT_EQ(std::find(outliers.begin(), outliers.end(), railed_at), outliers.end()) << j.at("outliers").dump();
}

// docs/coefficient-files.md, "Charge map": a map written by hand has no residual sd (`null` with a
// `_why`). `table5 --charge-map` printed "(residual sd nan)"; it says the file's map has none. The
// JSON's `charge_map.residual_sd` is null with its reason, not a number.
TEST_F(ProbeFour, Table5HandWrittenChargeMapPrintsNoNan) {
  const std::string map = write("map.json",
                                R"({"kind": "charge_map", "charge_map": {"form": "monotone_piecewise_linear", )"
                                R"("knots_v": [3.5, 4.2], "knot_charge": [0.1, 1.0]}})");
  // Voltage-only runs at every speed 0..15 cm/s (Table 5 needs them all), 4.2 V down to 3.55 V.
  std::string log;
  for (int speed = 0; speed <= 15; ++speed) {
    std::string text = "# robot: r\ntime_s,speed_cm_s,voltage_v\n";
    const double end_s = 20000.0 - 600.0 * speed;
    for (int k = 0; k <= 20; ++k) {
      char line[96];
      std::snprintf(line, sizeof line, "%g,%d,%.4f\n", end_s * k / 20.0, speed, 4.2 - 0.65 * std::pow(k / 20.0, 1.3));
      text += line;
    }
    log += (log.empty() ? "" : "\" \"") + write("volts_" + std::to_string(speed) + ".csv", text);
  }
  const CliRun t = run("table5 --charge-map \"" + map + "\" \"" + log + "\"");
  ASSERT_EQ(t.exit_code, 0) << t.err;
  EXPECT_FALSE(has(t.out, "nan")) << t.out;
  EXPECT_TRUE(has(t.out, "through the voltage->charge map of " + map + " (no residual sd: the file's map has none)")) << t.out;
  const CliRun j = run("table5 --json --charge-map \"" + map + "\" \"" + log + "\"");
  ASSERT_EQ(j.exit_code, 0) << j.err;
  EXPECT_FALSE(has(j.out, "nan")) << j.out;
  const json file = json::parse(j.out);
  EXPECT_TRUE(file.at("charge_map").at("residual_sd").is_null());
  EXPECT_TRUE(file.at("charge_map").contains("residual_sd_why"));
  // The battery report says nothing of a residual sd for that map either (no nan).
  const CliRun b = run("battery --charge-map \"" + map + "\" \"" + log + "\"");
  ASSERT_EQ(b.exit_code, 0) << b.err;
  EXPECT_FALSE(has(b.out, "nan")) << b.out;
  EXPECT_FALSE(has(b.out, "residual sd nan")) << b.out;
}

}  // namespace test_probe_four_cpp
