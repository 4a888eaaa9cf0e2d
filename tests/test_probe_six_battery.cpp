// Battery defects a new user's probe found (probe 6, /work/probe24): each exited 0 with a wrong
// number or without a word. Every expected value here is worked by hand or computed by the test
// from the rows it writes (the generator's truth), never taken from the code under test.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <sstream>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "cli_harness.hpp"

namespace test_probe_six_battery_cpp {

using epuck2::testing::CliRun;
using epuck2::testing::slurp;
using nlohmann::json;

bool has(const std::string& text, const std::string& part) { return text.find(part) != std::string::npos; }

class ProbeSixBattery : public epuck2::testing::CliTest {};

// ---- 13: the Approximated model's MSE is the model's as written ----------------------------

/// The polyline the two runs follow exactly: (0, 1), (250 s, 0.9), (600 s, 0.5), then slope
/// -0.0003 /s on, also past 1000 s (a run outlasting the mean lifetime reads on along it).
double polyline_truth(double t) {
  if (t <= 250) return 1.0 - 0.1 * t / 250.0;
  if (t <= 600) return 0.9 - 0.4 * (t - 250.0) / 350.0;
  return 0.5 - 0.0003 * (t - 600.0);
}

/// A run at `speed` cm/s on the polyline, a row every 10 s from 0 to `end_s`.
std::string polyline_run(int speed, double end_s) {
  std::ostringstream os;
  os << "# robot: probe6\ntime_s,speed_cm_s,charge\n";
  for (int k = 0; k * 10.0 <= end_s + 1e-9; ++k) {
    char line[96];
    std::snprintf(line, sizeof line, "%g,%d,%.12f\n", k * 10.0, speed, polyline_truth(k * 10.0));
    os << line;
  }
  return os.str();
}

// Two runs a speed, 800 s and 1200 s long: the mean lifetime L = 1000 s. Both lie exactly on
// the three-segment line, so the fitted knots are the truth's (0.25 L, 0.9), (0.6 L, 0.5) and
// y3 = 0.5 - 0.0003 * 399 = 0.3803 at L - 1 s. The model as written (docs/battery-models.md, M1..M4)
// drops to 0 at L and stays there: the 1200-s run's 21 rows at t = 1000, 1010, ..., 1200 s read
// 0.38 - 0.003 k (k = 0..20) against a model charge of 0, the other 181 rows are met exactly.
// By hand: sum (0.38 - 0.003 k)^2 = 21 * 0.1444 - 2 * 0.38 * 0.003 * 210 + 0.000009 * 2870
// = 3.0324 - 0.4788 + 0.02583 = 2.57943, over 81 + 121 = 202 rows: MSE 0.0127695. The third
// segment extended past L (charge still 0.32 at 1200 s) would give an MSE of about 0.
TEST_F(ProbeSixBattery, ApproximatedMseIsTheWrittenModelsZeroAfterTheLifetime) {
  double ss = 0;
  int n = 0;
  for (double end : {800.0, 1200.0})
    for (int k = 0; k * 10.0 <= end + 1e-9; ++k, ++n) {
      const double t = k * 10.0;
      const double model = t >= 1000.0 ? 0.0 : polyline_truth(t);  // no row falls inside M4's last second
      ss += (polyline_truth(t) - model) * (polyline_truth(t) - model);
    }
  ASSERT_EQ(n, 202);
  const double expected = ss / n;
  EXPECT_NEAR(expected, 2.57943 / 202.0, 1e-9);  // the hand value above

  std::string args;
  for (int v = 0; v <= 15; ++v)
    for (double end : {800.0, 1200.0})
      args += " \"" + write("r" + std::to_string(v) + "_" + std::to_string(static_cast<int>(end)) + ".csv", polyline_run(v, end)) + "\"";
  const std::string out = (dir_ / "b.json").string();
  const CliRun b = run("battery" + args + " -o \"" + out + "\"");
  ASSERT_EQ(b.exit_code, 0) << b.err;
  const json j = json::parse(slurp(out));
  ASSERT_EQ(j.at("speeds").size(), 16u);
  for (const auto& s : j.at("speeds")) {
    EXPECT_NEAR(s.at("lifetime_s").get<double>(), 1000.0, 1e-9);
    EXPECT_NEAR(s.at("mse").at("approximated").get<double>(), expected, 1e-6 * expected) << s.at("speed_cm_s");
  }
  EXPECT_NEAR(j.at("mse").at("approximated").get<double>(), expected, 1e-6 * expected);
  char average[64];
  std::snprintf(average, sizeof average, "approximated %.4f charge²", expected);  // 0.0128
  EXPECT_TRUE(has(b.out, average)) << b.out;

  const CliRun t5 = run("table5 --json" + args);
  ASSERT_EQ(t5.exit_code, 0) << t5.err;
  const json table = json::parse(t5.out);
  EXPECT_NEAR(table.at("analytic").at("approximated").get<double>(), expected, 1e-6 * expected);
}

}  // namespace test_probe_six_battery_cpp
