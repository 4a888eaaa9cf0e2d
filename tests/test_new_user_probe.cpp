// Defects two new users' probes found (session 21): each exited 0 with a wrong number, a dropped
// value or a false sentence. Every expected value here is computed by the test from the rows it
// writes (the generator's truth), or is the docs' own formula, never taken from the code under test.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <sstream>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "cli_harness.hpp"

namespace test_new_user_probe_cpp {

using epuck2::testing::CliRun;
using epuck2::testing::slurp;
using nlohmann::json;

bool has(const std::string& text, const std::string& part) { return text.find(part) != std::string::npos; }

/// A battery run: charge = 1 - 0.7 u - 0.25 u^3 (u = t / end) every 100 s up to `end_s`, plus
/// `e` on even rows and -e on odd ones (`flip`: the other way round), at `speed` cm/s.
std::string battery_run(double speed, double end_s, double e, bool flip) {
  std::ostringstream os;
  os << "# robot: probe\ntime_s,speed_cm_s,charge\n";
  int row = 0;
  for (double t = 0; t <= end_s + 1e-9; t += 100.0, ++row) {
    const double u = t / end_s;
    const double sign = ((row % 2 == 0) != flip) ? 1.0 : -1.0;
    char line[96];
    std::snprintf(line, sizeof line, "%g,%g,%.9f\n", t, speed, 1.0 - 0.7 * u - 0.25 * u * u * u + sign * e);
    os << line;
  }
  return os.str();
}

class NewUserProbe : public epuck2::testing::CliTest {};

// docs/coefficient-files.md: a battery file's reading noise is its speeds' residual sd, a robust
// one (1.4826 x the median absolute residual). Two runs of an exact cubic, one +e/-e on alternate
// rows and the other -e/+e: the cubic goes through the mean, every residual is e in size, so the
// noise sd is 1.4826 e whether outliers are looked for or not (--least-squares used to write 0,
// and `simulate --like --noise` then added none).
TEST_F(NewUserProbe, BatteryLeastSquaresWritesTheReadingNoise) {
  const double e = 0.002;
  const std::string a = write("a.csv", battery_run(4, 9000, e, false));
  const std::string b = write("b.csv", battery_run(4, 9000, e, true));
  const std::string plain = (dir_ / "plain.json").string(), ls = (dir_ / "ls.json").string();
  ASSERT_EQ(run("battery \"" + a + "\" \"" + b + "\" -o \"" + plain + "\"").exit_code, 0);
  const CliRun r = run("battery --least-squares \"" + a + "\" \"" + b + "\" -o \"" + ls + "\"");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const double expected = 1.482602218505602 * e;
  const double sd_plain = json::parse(slurp(plain)).at("speeds").at(0).at("noise_sd").get<double>();
  const double sd_ls = json::parse(slurp(ls)).at("speeds").at(0).at("noise_sd").get<double>();
  EXPECT_NEAR(sd_plain, expected, 0.01 * expected);
  EXPECT_NEAR(sd_ls, expected, 0.01 * expected);
  // And simulate --like --noise with such a file (a reader wants every speed 0..15: two runs each)
  // adds noise: the charges differ from the noise-free ones.
  std::string all;
  for (int v = 0; v <= 15; ++v)
    for (const bool flip : {false, true})
      all += " \"" + write("s" + std::to_string(v) + (flip ? "b" : "a") + ".csv", battery_run(v, 20000 - 700 * v, e, flip)) + "\"";
  const std::string full = (dir_ / "full.json").string();
  const CliRun f = run("battery --least-squares" + all + " -o \"" + full + "\"");
  ASSERT_EQ(f.exit_code, 0) << f.err;
  const json written = json::parse(slurp(full));  // (a range-for over a temporary's member would dangle)
  ASSERT_EQ(written.at("speeds").size(), 16u);
  for (const auto& speed : written.at("speeds"))
    EXPECT_NEAR(speed.at("noise_sd").get<double>(), expected, 0.01 * expected) << speed.at("speed_cm_s");
  const CliRun quiet = run("simulate battery --like \"" + a + "\" --coefficients \"" + full + "\"");
  const CliRun noisy = run("simulate battery --like \"" + a + "\" --coefficients \"" + full + "\" --noise --seed 5");
  ASSERT_EQ(quiet.exit_code, 0) << quiet.err;
  ASSERT_EQ(noisy.exit_code, 0) << noisy.err;
  EXPECT_NE(quiet.out.substr(quiet.out.find("time_s")), noisy.out.substr(noisy.out.find("time_s")));
  EXPECT_TRUE(has(noisy.out, "and reading noise, seed 5")) << noisy.out.substr(0, 300);
}

// Two runs ending at the same time have a lifetime without a standard error because the runs
// agree, not because there is one: every place that says why names the runs as they are. With no
// run at 0 cm/s, m0 is m1 (the warning says so) and the reason is that, not "one run".
TEST_F(NewUserProbe, TwoRunsEndingTogetherAreNeverCalledOneRun) {
  const std::string a = write("a.csv", battery_run(4, 9000, 0.002, false));
  const std::string b = write("b.csv", battery_run(4, 9000, 0.002, true));
  const CliRun t = run("battery \"" + a + "\" \"" + b + "\"");
  ASSERT_EQ(t.exit_code, 0) << t.err;
  EXPECT_FALSE(has(t.out, "one run")) << t.out;
  EXPECT_TRUE(has(t.out, "9000 s (runs end together)")) << t.out;
  EXPECT_TRUE(has(t.out, "the lifetime has no standard error: the runs end at the same time")) << t.out;
  EXPECT_TRUE(has(t.out, "the static lifetime has no standard error: no run at 0 cm/s: m0 is taken as m1")) << t.out;
  EXPECT_TRUE(has(t.out, "the moving lifetimes have no standard error: at every speed the runs end at the same time")) << t.out;
  const CliRun j = run("battery --json \"" + a + "\" \"" + b + "\"");
  ASSERT_EQ(j.exit_code, 0) << j.err;
  const json r = json::parse(j.out);
  EXPECT_EQ(r.at("speeds").at(0).at("runs"), 2);
  EXPECT_TRUE(has(r.at("speeds").at(0).at("linear_slope_rounded").get<std::string>(), "the runs end at the same time"));
  EXPECT_TRUE(has(r.at("simple").at("static_rounded").get<std::string>(), "no run at 0 cm/s"));
  EXPECT_TRUE(has(r.at("simple").at("moving_rounded").get<std::string>(), "at every speed the runs end at the same time"));
  // Two runs at 0 cm/s ending together, and one run at 4 cm/s: each said as it is.
  const std::string z1 = write("z1.csv", battery_run(0, 20000, 0.002, false));
  const std::string z2 = write("z2.csv", battery_run(0, 20000, 0.002, true));
  const CliRun k = run("battery --json \"" + z1 + "\" \"" + z2 + "\" \"" + a + "\"");
  ASSERT_EQ(k.exit_code, 0) << k.err;
  const json s = json::parse(k.out);
  EXPECT_TRUE(has(s.at("simple").at("static_rounded").get<std::string>(), "the 2 runs at 0 cm/s end at the same time"))
      << s.at("simple");
  EXPECT_TRUE(has(s.at("simple").at("moving_rounded").get<std::string>(), "one run a speed")) << s.at("simple");
  EXPECT_TRUE(has(s.at("speeds").at(1).at("linear_slope_rounded").get<std::string>(), "the end of the only run's log"));
}

/// The ground log of the probe: sensor s reads offset_s + gain_s grey + e_k, e_k from a fixed
/// pattern, 10 readings a sensor at each grey 0, 0.1, ..., 1.
struct GroundRows {
  std::vector<double> grey, value;
  std::vector<int> sensor;
  std::string text;
};
GroundRows ground_rows() {
  const double offset[3] = {50, 70, 90}, gain[3] = {900, 850, 800};
  const int pattern[10] = {-3, -2, -1, 0, 1, 2, 3, -1, 1, 0};
  GroundRows g;
  g.text = "# robot: r1\ngrey,sensor,value\n";
  for (int g10 = 0; g10 <= 10; ++g10)
    for (int s = 0; s < 3; ++s)
      for (int k = 0; k < 10; ++k) {
        const double grey = g10 / 10.0, v = offset[s] + gain[s] * grey + pattern[k];
        g.grey.push_back(grey);
        g.sensor.push_back(s);
        g.value.push_back(v);
        char line[64];
        std::snprintf(line, sizeof line, "%g,%d,%g\n", grey, s, v);
        g.text += line;
      }
  return g;
}

/// The plug-in's ground model (docs/diagnose.md, reference: gain 1023, offset 0) clamped to the
/// 0..1023 register, its MSE over the rows (none of which is on a rail).
double plugin_ground_mse(const GroundRows& g) {
  double sse = 0;
  for (std::size_t i = 0; i < g.value.size(); ++i) {
    const double predicted = std::clamp(1023.0 * g.grey[i], 0.0, 1023.0);
    sse += (g.value[i] - predicted) * (g.value[i] - predicted);
  }
  return sse / static_cast<double>(g.value.size());
}

// docs/diagnose.md: `mse_plugin_reading` is the base model's MSE against its reading as
// `simulate --like` writes it, every row; the report's line 2 says it beside the expected-reading
// MSE. Here the test's own sum over the rows it wrote (3451.5 counts² by the probe's hand too).
TEST_F(NewUserProbe, TheDiagnosissPluginMseAgainstItsReadingIsTheHandSum) {
  const GroundRows g = ground_rows();
  const std::string log = write("g.csv", g.text);
  const double expected = plugin_ground_mse(g);
  EXPECT_NEAR(expected, 3451.5, 0.1);  // the probe's hand value
  const CliRun j = run("diagnose --json \"" + log + "\"");
  ASSERT_EQ(j.exit_code, 0) << j.err;
  EXPECT_NEAR(json::parse(j.out).at("mse_plugin_reading").get<double>(), expected, 1e-9 * expected);
  const CliRun t = run("diagnose \"" + log + "\"");
  ASSERT_EQ(t.exit_code, 0) << t.err;
  char number[32];
  std::snprintf(number, sizeof number, "; %.4g counts² against its reading as `simulate --like` writes it.", expected);
  EXPECT_TRUE(has(t.out, number)) << t.out.substr(0, 600);
  // And simulate --like's own rows give the same MSE (the sentence's claim).
  const CliRun sim = run("simulate ground --like \"" + log + "\"");
  ASSERT_EQ(sim.exit_code, 0) << sim.err;
  std::istringstream in(sim.out);
  double sse = 0;
  std::size_t i = 0;
  bool header = false;
  for (std::string l; std::getline(in, l);) {
    if (l.empty() || l[0] == '#') continue;
    if (!header) {
      header = true;
      ASSERT_EQ(l, "grey,sensor,value");
      continue;
    }
    const double v = std::stod(l.substr(l.rfind(',') + 1));
    sse += (g.value[i] - v) * (g.value[i] - v);
    ++i;
  }
  ASSERT_EQ(i, g.value.size());
  EXPECT_NEAR(sse / static_cast<double>(i), expected, 1e-9 * expected);
}

// The ground report's "Plug-in:" line gives the plug-in's pooled MSE on the readings inside the
// rails (it printed the fit's); the fit's is beside it. The fit's pooled MSE by hand: the fit is
// exact but for the pattern, whose mean square is (9+4+1+0+1+4+9+1+1+0)/10 = 3 (the line's two
// parameters absorb none of it: the pattern is the same at every grey and sums to 0).
TEST_F(NewUserProbe, TheGroundReportsPluginLineIsThePluginsPooledMse) {
  const GroundRows g = ground_rows();
  const std::string log = write("g.csv", g.text);
  const CliRun t = run("ground \"" + log + "\"");
  ASSERT_EQ(t.exit_code, 0) << t.err;
  char line[200];
  std::snprintf(line, sizeof line, "offset 0: pooled MSE %.1f counts² on the readings inside the rails (the fit's: 3.000 counts²)",
                plugin_ground_mse(g));
  EXPECT_TRUE(has(t.out, line)) << line << "\n" << t.out;
  const CliRun j = run("ground --json \"" + log + "\"");
  ASSERT_EQ(j.exit_code, 0) << j.err;
  EXPECT_NEAR(json::parse(j.out).at("reference_mse").at("plugin_pooled").get<double>(), plugin_ground_mse(g), 1e-9 * 3451.5);
}

// simulate --like --noise with a model that has no reading noise (the plug-in's battery) draws
// none: the output must not say it is noisy nor carry a seed, and standard error says why.
TEST_F(NewUserProbe, NoiseAskedOfAModelWithoutNoiseIsSaidNotClaimed) {
  const std::string a = write("a.csv", battery_run(4, 9000, 0.002, false));
  const CliRun quiet = run("simulate battery --like \"" + a + "\"");
  const CliRun noisy = run("simulate battery --like \"" + a + "\" --noise --seed 3");
  ASSERT_EQ(noisy.exit_code, 0) << noisy.err;
  EXPECT_EQ(quiet.out.substr(quiet.out.find("time_s")), noisy.out.substr(noisy.out.find("time_s")));
  EXPECT_TRUE(has(noisy.out, "without noise (--noise given, but the model has none)")) << noisy.out.substr(0, 300);
  EXPECT_FALSE(has(noisy.out, "# seed:")) << noisy.out.substr(0, 300);
  EXPECT_TRUE(has(noisy.err, "--noise: the model has no reading noise")) << noisy.err;
}

// A map with a load term converts voltage + offset(speed); its range is of that sum. A reading of
// 4.3624 V at 4 cm/s with offsets 0 V at 0 and 0.1 V at 10 cm/s (linear: 0.04 V at 4) is 4.4024 V,
// past the map's 4.4 V: clamped, and the warning shows both voltages.
TEST_F(NewUserProbe, AClampedVoltageWithALoadOffsetIsShownCorrected) {
  const std::string map = write("map.json", R"({"kind": "charge_map",
 "charge_map": {"form": "monotone_piecewise_linear", "knots_v": [3.0, 3.8, 4.4], "knot_charge": [0.0, 0.5, 1.0],
   "load": "per_speed", "load_speeds_cm_s": [0, 10], "load_offset_v": [0, 0.1]}}
)");
  std::string log = "# robot: m1\ntime_s,speed_cm_s,voltage_v\n";
  for (int k = 0; k < 40; ++k) {
    char line[64];
    std::snprintf(line, sizeof line, "%d,4,%.4f\n", 100 * k, 4.3624 - 0.03 * k);
    log += line;
  }
  const std::string a = write("a.csv", log), b = write("b.csv", log);
  const CliRun r = run("battery --accept-misfit --charge-map \"" + map + "\" \"" + a + "\" \"" + b + "\"");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_TRUE(has(r.err, "2 voltages outside the charge map's range 3.0000..4.4000 V (0 below, 2 above) were clamped to its end "
                        "charges (the range is of the voltage plus its load offset at the row's speed); first: "))
      << r.err;
  EXPECT_TRUE(has(r.err, "a.csv:3 (4.3624 V; 4.4024 V with the load offset at 4 cm/s)")) << r.err;
}

// ---- The second probe (session 21's, fixed in session 22) ----

/// Light logs of Eq. 2 with gamma 0.075 m and sensor 7's gain 0.94 (its own gamma 0.0727 m),
/// five readings a condition at mean + {-12, 0, 12, -5, 5} counts, distances 0.06..0.45 m, sensors
/// 0..7, at intensity `intensity`.
std::string light_rows(double intensity) {
  std::string text = "# robot: t\ndistance_m,intensity,sensor,value\n";
  for (int cm = 6; cm <= 45; ++cm) {
    const double d = cm / 100.0;
    for (int s = 0; s < 8; ++s) {
      const double g = s == 7 ? 0.94 : 1.0;
      const double r = 0.075 * intensity / d;
      const double mean = (1.0 - g * r * r) * 4095.0;
      for (const double e : {-12.0, 0.0, 12.0, -5.0, 5.0}) {
        char line[96];
        std::snprintf(line, sizeof line, "%g,%g,%d,%.0f\n", d, intensity, s, std::clamp(std::round(mean + e), 0.0, 4095.0));
        text += line;
      }
    }
  }
  return text;
}

// The diagnosis's `recalibrated` is the base refitted alone, before any finding; the final fit,
// with sensor 7's gain found, moves gamma back to the generator's 0.075 m: `final_base` and the
// text report's "Base model in the final fit" line give that one (the report printed only the
// first, and docs/diagnose.md called it the final fit's). Sensor 7 reads as a smaller gamma
// (0.075 sqrt(0.94) = 0.0727 m), so the fit of gamma alone lies between the two.
TEST_F(NewUserProbe, TheFinalBaseIsTheFinalFitsAndTheReportSaysIt) {
  const std::string a = write("l05.csv", light_rows(0.5)), b = write("l10.csv", light_rows(1.0));
  const std::string out = (dir_ / "d.json").string();
  const CliRun t = run("diagnose \"" + a + "\" \"" + b + "\" -o \"" + out + "\"");
  ASSERT_EQ(t.exit_code, 0) << t.err;
  const json d = json::parse(slurp(out));
  const double final_gamma = d.at("final_base").at("gamma_m").get<double>();
  const double alone = d.at("recalibrated").at("gamma_m").get<double>();
  EXPECT_NEAR(final_gamma, 0.075, 0.0001);
  EXPECT_GT(alone, 0.075 * std::sqrt(0.94));
  EXPECT_LT(alone, 0.075 - 0.0001);
  EXPECT_EQ(d.at("findings").at(0).at("cause"), "sensor_gain");
  char recalibrated[64], final_line[120];
  std::snprintf(recalibrated, sizeof recalibrated, "Recalibrated base model (gamma_m = %.4f", alone);
  std::snprintf(final_line, sizeof final_line, "Base model in the final fit, with the findings (the extended model's): gamma_m = %.4f",
                final_gamma);
  EXPECT_TRUE(has(t.out, recalibrated)) << recalibrated << "\n" << t.out;
  EXPECT_TRUE(has(t.out, final_line)) << final_line << "\n" << t.out;
}

/// Camera logs of the shipped conditions: each condition's first reading (whole px) as a centre,
/// four readings a condition at centre + {-a, +a, +a, -a} (px) and {+a, -a, +a, -a} (py), written
/// with two decimals (docs/logs.md allows fractional px). Returns the log's text.
std::string camera_rows(const std::string& shipped_text, double a) {
  std::istringstream in(shipped_text);
  std::string text = "# robot: t\nforward_m,lateral_m,vertical_m,px,py\n";
  std::string last;
  bool header = false;
  for (std::string l; std::getline(in, l);) {
    if (l.empty() || l[0] == '#') continue;
    if (!header) {
      header = true;
      continue;
    }
    std::vector<std::string> f;
    std::stringstream ls(l);
    for (std::string c; std::getline(ls, c, ',');) f.push_back(c);
    const std::string where = f[0] + "," + f[1] + "," + f[2];
    if (where == last) continue;
    last = where;
    const double px = std::stod(f[3]), py = std::stod(f[4]);
    const double sx[] = {-a, a, a, -a}, sy[] = {a, -a, a, -a};
    for (int k = 0; k < 4; ++k) {
      char line[160];
      std::snprintf(line, sizeof line, "%s,%.2f,%.2f\n", where.c_str(), px + sx[k], py + sy[k]);
      text += line;
    }
  }
  return text;
}

// docs/diagnose.md, "The noise of the extended model": the rounding's 1/12 px² is taken off only
// readings that are whole numbers. Fractional readings (a = 0.37 px: each condition's four
// readings have the sample sd a sqrt(4/3) = 0.4272 px in both columns) keep the replicates' sd;
// the same logs with a = 1 (whole readings) have theirs less 1/12 px². The diagnosis took the
// 1/12 off both.
TEST_F(NewUserProbe, TheRoundingIsTakenOffOnlyWholeReadings) {
  const auto logs = epuck2::testing::shipped_logs("camera");
  ASSERT_FALSE(logs.empty());
  const std::string shipped = slurp(logs.front());
  for (const double a : {0.37, 1.0}) {
    const std::string log = write("c" + std::to_string(a) + ".csv", camera_rows(shipped, a));
    const std::string d = (dir_ / "d.json").string(), c = (dir_ / "c.json").string();
    const CliRun diag = run("diagnose \"" + log + "\" -o \"" + d + "\"");
    ASSERT_EQ(diag.exit_code, 0) << diag.err;
    const CliRun cal = run("camera --accept-misfit \"" + log + "\" -o \"" + c + "\"");
    ASSERT_EQ(cal.exit_code, 0) << cal.err;
    const double replicates = a * std::sqrt(4.0 / 3.0);
    const double calibrated = json::parse(slurp(c)).at("noise").at("camera").at("sd").get<double>();
    EXPECT_NEAR(calibrated, replicates, 1e-3 * replicates) << a;
    const double diagnosed = json::parse(slurp(d)).at("noise").at("camera").at("sd").get<double>();
    const double expected = a == 1.0 ? std::sqrt(replicates * replicates - 1.0 / 12.0) : replicates;
    EXPECT_NEAR(diagnosed, expected, 1e-3 * expected) << a;
  }
}

}  // namespace test_new_user_probe_cpp
