// Both sides of branches that a branch-coverage run (gcovr --branches over the whole suite,
// session 19) showed taken one way only: a guard that no input ever tripped, or always tripped.
// Each test builds the input for the side no test reached, with expected values worked by hand
// (in the comment beside them), from the plug-in's published tables, or computed independently
// (a numerical integral), never from the code under test.
#include <gtest/gtest.h>

#include <array>
#include <filesystem>
#include <fstream>
#include <cmath>
#include <limits>
#include <sstream>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "cli_harness.hpp"
#include "epuck2/models/battery.hpp"
#include "epuck2/models/saturation.hpp"

namespace test_branch_sides_cpp {

namespace mb = epuck2::models::battery;
namespace fs = std::filesystem;

// The corrected approximated model picks the segment whose band holds the charge; a charge above
// the first band takes the first segment (the plug-in's quirk takes the last, M4: that side is
// tested in test_battery_models.cpp). Bands by hand: M1 1.0..0.8, M2 0.8..0.5, M3 0.5..0.2, M4 0.2..0.
TEST(BranchSides, TheCorrectedSegmentAboveTheFirstBandIsTheFirst) {
  std::array<mb::Segment, mb::kSegmentCount> segs{};
  const double top[4] = {1.0, 0.8, 0.5, 0.2}, bottom[4] = {0.8, 0.5, 0.2, 0.0};
  for (int k = 0; k < 4; ++k) {
    segs[static_cast<std::size_t>(k)].y1 = top[k];
    segs[static_cast<std::size_t>(k)].y2 = bottom[k];
    segs[static_cast<std::size_t>(k)].m = -(k + 1) * 1e-4;  // told apart by their slopes too
  }
  EXPECT_EQ(&mb::corrected::segment_for(segs, 1.2), &segs[0]);     // above M1's band
  EXPECT_EQ(&mb::corrected::segment_for(segs, 1.0000001), &segs[0]);
  EXPECT_EQ(&mb::corrected::segment_for(segs, 1.0), &segs[0]);     // M1's top
  EXPECT_EQ(&mb::corrected::segment_for(segs, 0.8), &segs[0]);     // the shared edge: the higher band first
  EXPECT_EQ(&mb::corrected::segment_for(segs, 0.7999999), &segs[1]);
  EXPECT_EQ(&mb::corrected::segment_for(segs, 0.35), &segs[2]);
  EXPECT_EQ(&mb::corrected::segment_for(segs, 0.1), &segs[3]);     // M4's band (the loop stops before it)
  EXPECT_EQ(&mb::corrected::segment_for(segs, -0.05), &segs[3]);   // below every band
}

// E[clamp(X, lo, hi)] for X ~ N(mu, sigma^2) with one side open (lo = -inf or hi = +inf): only the
// finite clamp's correction. Expected: the integral of clamp(x) times the normal density by the
// trapezoid rule on [mu - 12 sigma, mu + 12 sigma] with 200 001 points (not the closed form the
// code uses).
double clamp_mean_by_integral(double mu, double lo, double hi, double sigma) {
  const int n = 200000;
  const double a = mu - 12 * sigma, b = mu + 12 * sigma, h = (b - a) / n;
  double sum = 0;
  for (int i = 0; i <= n; ++i) {
    const double x = a + h * i;
    const double c = std::min(std::max(x, lo), hi);
    const double w = (i == 0 || i == n) ? 0.5 : 1.0;
    sum += w * c * std::exp(-0.5 * (x - mu) * (x - mu) / (sigma * sigma));
  }
  return sum * h / (sigma * std::sqrt(2 * M_PI));
}

TEST(BranchSides, AClampOpenOnOneSideCorrectsOnlyTheOther) {
  const double inf = std::numeric_limits<double>::infinity();
  const double sigma = 10;
  for (double mu : {-15.0, 0.0, 8.0, 30.0}) {
    // a lower rail at 0 only (a reading that cannot go below 0, nothing above)
    EXPECT_NEAR(epuck2::models::expected_clamp(mu, 0.0, inf, sigma), clamp_mean_by_integral(mu, 0.0, inf, sigma), 1e-6) << mu;
    // an upper rail at 20 only
    EXPECT_NEAR(epuck2::models::expected_clamp(mu, -inf, 20.0, sigma), clamp_mean_by_integral(mu, -inf, 20.0, sigma), 1e-6) << mu;
  }
  // At the rail the correction is sigma phi(0) = 3.989 (by hand): mean 0 clamped at 0 from below.
  EXPECT_NEAR(epuck2::models::expected_clamp(0.0, 0.0, inf, sigma), 10 * 0.3989422804, 1e-9);
  EXPECT_NEAR(epuck2::models::expected_clamp(20.0, -inf, 20.0, sigma), 20 - 10 * 0.3989422804, 1e-9);
  // saturate: an infinite side clamps nothing there.
  EXPECT_EQ(epuck2::models::saturate(-5.0, -inf, 3.0), -5.0);
  EXPECT_EQ(epuck2::models::saturate(7.0, -inf, 3.0), 3.0);
  EXPECT_EQ(epuck2::models::saturate(7.0, 1.0, inf), 7.0);
  EXPECT_EQ(epuck2::models::saturate(-7.0, 1.0, inf), 1.0);
}

// `simulate battery --like LOG --battery-model M` runs model M (docs/cli.md), not the file's: a
// log at 5 cm/s, the plug-in's tables. Linear: charge(t) = 1 + L[5] t with L[5] = -1.068908673e-04
// /s (the plug-in's published slope = -1/lifetime): at 2000 s, 0.786218. Simple: the moving slope
// M1 = -8.699123633e-05 /s: 0.826018. The default is the file's, the plug-in's cubic: the same as
// --battery-model cubic, and not the other two (the cubic's own values: test_model_loop.cpp).
class BranchSidesCli : public epuck2::testing::CliTest {};

TEST_F(BranchSidesCli, SimulateLikeRunsTheBatteryModelItIsGiven) {
  const std::string log = write("b.csv", "time_s,speed_cm_s,charge\n0,5,0.99\n1000,5,0.9\n2000,5,0.8\n");
  auto charge_at_2000 = [&](const std::string& extra) {
    const epuck2::testing::CliRun r = run("simulate battery --like \"" + log + "\" --coefficients plugin" + extra);
    EXPECT_EQ(r.exit_code, 0) << extra << "\n" << r.err;
    std::istringstream in(r.out);
    std::string line, last;
    while (std::getline(in, line))
      if (!line.empty() && line[0] != '#') last = line;
    return std::stod(last.substr(last.rfind(',') + 1));
  };
  const double t = 2000;
  EXPECT_NEAR(charge_at_2000(" --battery-model linear"), 1 - 1.068908673e-04 * t, 1e-3);
  EXPECT_NEAR(charge_at_2000(" --battery-model simple"), 1 - 8.699123633e-05 * t, 1e-3);
  const double cubic = charge_at_2000(" --battery-model cubic");
  EXPECT_EQ(charge_at_2000(""), cubic);
  EXPECT_GT(std::abs(cubic - (1 - 1.068908673e-04 * t)), 0.05);
  EXPECT_GT(std::abs(cubic - (1 - 8.699123633e-05 * t)), 0.05);
}

// A long gap between a log's rows is simulated as the short steps a dense log has (docs/cli.md,
// "simulate battery --like"): with rows only at 0 and 2000 s, the charge at 2000 s is the one with
// a row every 10 s, for every model; and the cubic (found by this test: the one step of 2000 s
// ran the start transient's initial slope for 2000 s, 0.572 instead of 0.690) lies on the
// published 5 cm/s curve there, 0.9603929712 - 1.9429015609e-04 t + 3.4602913169e-08 t^2
// - 2.5372952124e-12 t^3 = 0.689926 at t = 2000 (by hand), within the firmware filter's start
// (a few seconds of slope 1.9e-4: < 1e-3).
TEST_F(BranchSidesCli, ALongGapBetweenRowsIsSimulatedAsShortSteps) {
  std::string dense = "time_s,speed_cm_s,charge\n";
  for (int t = 0; t <= 2000; t += 10) dense += std::to_string(t) + ",5," + (t == 0 ? "0.99" : "0.8") + "\n";
  const std::string dense_log = write("dense.csv", dense);
  const std::string sparse_log = write("sparse.csv", "time_s,speed_cm_s,charge\n0,5,0.99\n2000,5,0.8\n");
  const std::string three_log = write("three.csv", "time_s,speed_cm_s,charge\n0,5,0.99\n1000,5,0.9\n2000,5,0.8\n");
  auto last_charge = [&](const std::string& log, const std::string& model) {
    const epuck2::testing::CliRun r =
        run("simulate battery --like \"" + log + "\" --coefficients plugin --battery-model " + model);
    EXPECT_EQ(r.exit_code, 0) << model << "\n" << r.err;
    std::istringstream in(r.out);
    std::string line, last;
    while (std::getline(in, line))
      if (!line.empty() && line[0] != '#') last = line;
    return std::stod(last.substr(last.rfind(',') + 1));
  };
  for (const char* model : {"simple", "linear", "cubic", "approximated"}) {
    const double d = last_charge(dense_log, model);
    EXPECT_NEAR(last_charge(sparse_log, model), d, 1e-9) << model;
    EXPECT_NEAR(last_charge(three_log, model), d, 1e-9) << model;
  }
  const double t = 2000;
  EXPECT_NEAR(last_charge(sparse_log, "cubic"),
              0.9603929712 - 1.9429015609e-04 * t + 3.4602913169e-08 * t * t - 2.5372952124e-12 * t * t * t, 1e-3);
  EXPECT_NEAR(last_charge(three_log, "cubic"),
              0.9603929712 - 1.9429015609e-04 * t + 3.4602913169e-08 * t * t - 2.5372952124e-12 * t * t * t, 1e-3);
}

// A voltage-only log through a charge map (`battery --charge-map`): every voltage outside the
// map's range is clamped and counted, and the report lists where the first 10 are (docs/coefficient-files.md:
// clamped_rows, "the first 10"). 12 rows at 4.6 V (above any cell's 4.2 V) and 3 at 2.9 V (below
// the power-off threshold): 12 above, 3 below, 10 listed, the file's first 10 data lines (the test
// counts the lines it wrote).
TEST_F(BranchSidesCli, EveryClampedVoltageIsCountedAndTheFirstTenListed) {
  const fs::path shipped = fs::path(EPUCK2_SOURCE_DIR) / "data" / "raw" / "battery" / "robot-a_speed-05.csv";
  std::istringstream in(epuck2::testing::slurp(shipped));
  std::string line, text;
  int line_no = 0, data_rows = 0;
  std::vector<int> high_lines;
  while (std::getline(in, line)) {
    ++line_no;
    if (line.empty() || line[0] == '#') {
      text += line + "\n";
      continue;
    }
    std::vector<std::string> c;
    std::stringstream cells(line);
    for (std::string cell; std::getline(cells, cell, ',');) c.push_back(cell);
    ASSERT_EQ(c.size(), 4u) << line;  // time_s,speed_cm_s,charge,voltage_v
    if (c[0] == "time_s") {
      text += "time_s,speed_cm_s,voltage_v\n";
      continue;
    }
    std::string v = c[3];
    if (data_rows < 12) {
      v = "4.6";
      high_lines.push_back(line_no);
    } else if (data_rows >= 100 && data_rows < 103) {
      v = "2.9";
    }
    ++data_rows;
    text += c[0] + "," + c[1] + "," + v + "\n";
  }
  const std::string log = write("v5.csv", text);
  const std::string map = (fs::path(EPUCK2_SOURCE_DIR) / "data" / "fitted" / "battery.json").string();
  const epuck2::testing::CliRun r = run("battery \"" + log + "\" --charge-map \"" + map + "\" --json");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const nlohmann::json j = nlohmann::json::parse(r.out);
  const nlohmann::json c = j.at("charge_conversion");
  EXPECT_EQ(c.at("clamped_above_range"), 12);
  EXPECT_EQ(c.at("clamped_below_range"), 3);
  ASSERT_EQ(c.at("clamped_rows").size(), 10u) << c.dump();
  for (std::size_t k = 0; k < 10; ++k)
    EXPECT_EQ(c.at("clamped_rows").at(k).get<std::string>(), log + ":" + std::to_string(high_lines[k]) + " (4.6000 V)");
  EXPECT_NE(r.err.find("15 voltages outside the charge map's range"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("(3 below, 12 above)"), std::string::npos) << r.err;
}

// A proximity curve that reads under 5 % of full scale at contact (c < 0.05) is said to be
// implausible (a sensor touching a surface reads near full scale); one at 8 % is not. Readings
// 4095 c (1 - d / 0.05)^2 by hand, c = 0.03 and 0.08, six a distance 0..50 mm, noise sd 2 counts
// (seeded).
TEST_F(BranchSidesCli, AProximityCurveFaintAtContactIsSaidToBe) {
  auto log_for = [&](double c, const std::string& name) {
    std::string text = "# robot: weak-sensor\ntime_s,distance_m,sensor,value\n";
    std::uint64_t state = 3;
    auto unit = [&] { state = state * 6364136223846793005ULL + 1442695040888963407ULL; return ((state >> 11) + 0.5) / 9007199254740992.0; };
    double t = 0;
    for (int i = 0; i <= 10; ++i) {
      const double d = i * 0.005, v = c * (1 - d / 0.05) * (1 - d / 0.05);
      for (int k = 0; k < 6; ++k) {
        const double noise = 2 * std::sqrt(-2 * std::log(unit())) * std::cos(2 * M_PI * unit());
        const long reading = std::lround(std::clamp(4095 * v + noise, 0.0, 4095.0));
        text += std::to_string(t) + "," + std::to_string(d) + ",0," + std::to_string(reading) + "\n";
        t += 0.05;
      }
    }
    return write(name, text);
  };
  const epuck2::testing::CliRun faint = run("proximity \"" + log_for(0.03, "faint.csv") + "\"");
  for (const char* fit : {"maxima fit", "means fit"})
    EXPECT_NE(faint.err.find(std::string(fit) + ": the curve reads under 5 % of full scale at contact (c = 0.0"), std::string::npos)
        << fit << "\n" << faint.err;
  const epuck2::testing::CliRun fair = run("proximity \"" + log_for(0.08, "fair.csv") + "\"");
  EXPECT_EQ(fair.err.find("under 5 % of full scale at contact"), std::string::npos) << fair.err;
}

// diagnose --coefficients fitted names its base as the compiled-in fitted battery tables; plugin
// (or none) as the plug-in's model with the coefficients given (docs/diagnose.md).
TEST_F(BranchSidesCli, TheDiagnosisNamesTheBaseItWasGiven) {
  const std::string log = "\"" + (fs::path(EPUCK2_SOURCE_DIR) / "data" / "raw" / "battery" / "robot-a_speed-05.csv").string() + "\"";
  const epuck2::testing::CliRun fitted = run("diagnose " + log + " --coefficients fitted");
  ASSERT_EQ(fitted.exit_code, 0) << fitted.err;
  EXPECT_NE(fitted.out.find("The plug-in's model with the CLI's compiled-in fitted battery tables, before recalibration"),
            std::string::npos) << fitted.out;
  const epuck2::testing::CliRun plugin = run("diagnose " + log + " --coefficients plugin");
  ASSERT_EQ(plugin.exit_code, 0) << plugin.err;
  EXPECT_NE(plugin.out.find("The plug-in's model with the coefficients given, before recalibration"), std::string::npos) << plugin.out;
}

}  // namespace test_branch_sides_cpp
