// Round 20 of the fresh slips (bench/fresh-slips.md): a test for each survivor's behaviour, written
// during the round's run (after its GO: not in the run that scores it). Every expected value comes
// from the docs, is counted by the test from the inputs it builds, or is worked by hand in the
// comment beside it, never from the code under test.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <memory>
#include <sstream>
#include <string>
#include <vector>

#include <Eigen/Dense>

#include "cli_harness.hpp"
#include "epuck2/fit/fit_curve.hpp"
#include "epuck2/fit/least_squares.hpp"
#include "epuck2/coefficients/model_sets.hpp"
#include "epuck2/diagnose/diagnose.hpp"
#include "epuck2/logs/log.hpp"
#include "../lib/diagnose/src/problem.hpp"

#include <nlohmann/json.hpp>

namespace test_round_twenty_cpp {

namespace fit = epuck2::fit;
using epuck2::testing::CliRun;
using epuck2::testing::slurp;

bool has(const std::string& text, const std::string& part) { return text.find(part) != std::string::npos; }

class RoundTwentyCli : public epuck2::testing::CliTest {};

struct Line {
  static constexpr int kParameters = 2;
  template <typename T>
  T operator()(const T* p, double x) const {
    return p[0] + p[1] * x;
  }
};

struct Quadratic {
  static constexpr int kParameters = 3;
  template <typename T>
  T operator()(const T* p, double x) const {
    return p[0] + p[1] * x + p[2] * x * x;
  }
};

// ---- lib/fit: a parameter held at a bound is said to be on the side it is on ----

// y = 1 + 2x exactly. With the slope bounded below by 2.5 it ends on that lower bound; bounded
// above by 1.5, on the upper one (docs/fitting.md: "ended on its lower/upper bound, where it is
// held: no standard error").
TEST(RoundTwentyFit, AParameterOnItsBoundIsSaidOnTheRightSide) {
  const std::vector<double> x{0, 1, 2, 3}, y{1, 3, 5, 7};
  std::vector<fit::Parameter> low{{"a", 0.0}, {"b", 3.0}};
  low[1].lower = 2.5;
  const fit::FitResult l = fit::fit_curve(Line{}, x, y, low);
  ASSERT_TRUE(l.usable) << l.message;
  EXPECT_NEAR(l.value("b"), 2.5, 1e-9);
  EXPECT_EQ(l.parameters[1].std_error_why, "ended on its lower bound, where it is held: no standard error");
  // The intercept for slope 2.5: mean(y - 2.5 x) = 4 - 2.5 * 1.5 = 0.25.
  EXPECT_NEAR(l.value("a"), 0.25, 1e-9);
  std::vector<fit::Parameter> high{{"a", 0.0}, {"b", 0.0}};
  high[1].upper = 1.5;
  const fit::FitResult h = fit::fit_curve(Line{}, x, y, high);
  ASSERT_TRUE(h.usable) << h.message;
  EXPECT_EQ(h.parameters[1].std_error_why, "ended on its upper bound, where it is held: no standard error");
}

// ---- lib/fit: a fit with as many residuals as parameters has no noise to estimate ----

// fit_curve refuses fewer than k + 1 observations before any covariance; the covariance step itself
// (set_covariance, which every fit of the engine ends with: the sensor fits' robust passes, the
// camera's, the drive's) must still say why when it is handed as many residuals as estimable
// parameters: n - k = 0 leaves no degree of freedom for the noise. A 3 x 3 Jacobian (the quadratic
// through x = 0, 1, 2) and a 2 x 2 one; with one row more, errors exist and no reason is left.
TEST(RoundTwentyFit, AnExactlyDeterminedFitSaysItHasNoDegreeOfFreedom) {
  const auto covariance_of = [](const std::vector<std::string>& names, const Eigen::MatrixXd& jacobian) {
    fit::FitResult r;
    for (const auto& n : names) r.parameters.emplace_back(n, 1.0, std::nan(""), "");
    r.usable = true;
    r.rss = 0.25;
    fit::set_covariance(r, jacobian, std::vector<bool>(names.size(), true));
    return r;
  };
  Eigen::MatrixXd q(3, 3);
  q << 1, 0, 0, 1, 1, 1, 1, 2, 4;
  for (const auto& p : covariance_of({"c0", "c1", "c2"}, q).parameters)
    EXPECT_EQ(p.std_error_why, "undefined: 3 residuals for 3 estimable parameters leave no degree of freedom to estimate the noise")
        << p.name;
  Eigen::MatrixXd l(2, 2);
  l << 1, 0, 1, 1;
  for (const auto& p : covariance_of({"a", "b"}, l).parameters)
    EXPECT_EQ(p.std_error_why, "undefined: 2 residuals for 2 estimable parameters leave no degree of freedom to estimate the noise")
        << p.name;
  Eigen::MatrixXd m(3, 2);
  m << 1, 0, 1, 1, 1, 2;
  for (const auto& p : covariance_of({"a", "b"}, m).parameters) {
    EXPECT_TRUE(p.std_error > 0) << p.name;
    EXPECT_EQ(p.std_error_why, "") << p.name;
  }
  // And fit_curve, which refuses such a fit earlier, says so (docs/fitting.md).
  const fit::FitResult refused = fit::fit_curve(Quadratic{}, {0, 1, 2}, {1, 2, 5}, {{"c0", 0.0}, {"c1", 0.0}, {"c2", 0.0}});
  EXPECT_FALSE(refused.usable);
  EXPECT_EQ(refused.message, "too few observations (3) for 3 parameters");
}

// ---- lib/calibrate: the light's plug-in MSE is over the readings inside the rails ----

// docs/coefficient-files.md: the light report's `reference_mse.plugin` is the plug-in's gamma =
// 0.075 on the readings inside the rails (0 and 4095 are rails: a reading there says only that
// the light is at least that bright). A light of intensity 1 read with gamma 0.08 (8 sensors,
// readings truth + -3, 0, 3): at 3 and 5 cm every reading is 0 (1 - (0.08 / d)^2 < 0), left out;
// the test sums ((v - 4095 clamp01(1 - (0.075 / d)^2)) / 4095)^2 over the others itself.
TEST_F(RoundTwentyCli, TheLightsPluginMseLeavesOutTheReadingsOnTheRails) {
  std::string text = "# robot: r\ndistance_m,intensity,sensor,value\n";
  double sse = 0;
  std::size_t inside = 0;
  for (const double d : {0.03, 0.05, 0.1, 0.15, 0.2, 0.3, 0.4})
    for (int s = 0; s < 8; ++s)
      for (const int e : {-3, 0, 3}) {
        const double truth = 4095.0 * std::clamp(1.0 - (0.08 / d) * (0.08 / d), 0.0, 1.0);
        const double v = truth > 0 ? std::clamp(std::round(truth) + e, 0.0, 4095.0) : 0.0;
        char line[64];
        std::snprintf(line, sizeof line, "%g,1,%d,%g\n", d, s, v);
        text += line;
        if (v > 0 && v < 4095) {
          const double plugin = 4095.0 * std::clamp(1.0 - (0.075 / d) * (0.075 / d), 0.0, 1.0);
          sse += (v - plugin) / 4095.0 * (v - plugin) / 4095.0;
          ++inside;
        }
      }
  ASSERT_EQ(inside, 120u);  // 5 distances x 8 sensors x 3
  const std::string log = write("l.csv", text);
  const CliRun r = run("light --json \"" + log + "\"");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NEAR(nlohmann::json::parse(r.out).at("reference_mse").at("plugin").get<double>(), sse / 120.0, 1e-12);
}

// ---- lib/coefficients: a null noise section gives no noise ----

// model_sets.hpp: has_noise_section says whether a file gives a reading noise. `"noise": null`
// gives none (the readers refuse it in a file; the function is asked of whatever JSON it is handed,
// and a simulator would otherwise take a file without noise for one with measured noise).
TEST(RoundTwentyCoefficients, ANullNoiseSectionIsNoNoise) {
  namespace co = epuck2::coefficients;
  using nlohmann::json;
  EXPECT_FALSE(co::has_noise_section(json::parse(R"({"noise": null})"), ""));
  EXPECT_FALSE(co::has_noise_section(json::parse(R"({"robots": {"A": {"noise": null}}})"), "A"));
  EXPECT_TRUE(co::has_noise_section(json::parse(R"({"noise": {"ground": {"sd": 2}}})"), ""));
}

// ---- the CLI's outputs: the special paths docs/cli.md names ----

// docs/cli.md: `-o` takes `-`, /dev/stdout, /dev/stderr and /proc/self/fd/N as the streams they
// name, written in place. The coefficient file (its "kind" line) must land on that stream only.
TEST_F(RoundTwentyCli, OutputToDevStderrAndProcSelfFdOneLandOnTheirStreams) {
  const std::string logs = shipped("ground");
  const CliRun e = run("ground" + logs + " -o /dev/stderr");
  ASSERT_EQ(e.exit_code, 0) << e.err.substr(0, 500);
  EXPECT_TRUE(has(e.err, "\"kind\": \"ground\"")) << e.err.substr(0, 500);
  EXPECT_FALSE(has(e.out, "\"kind\"")) << e.out.substr(0, 500);
  const CliRun o = run("ground" + logs + " -o /proc/self/fd/1");
  ASSERT_EQ(o.exit_code, 0) << o.err.substr(0, 500);
  EXPECT_TRUE(has(o.out, "\"kind\": \"ground\"")) << o.out.substr(0, 500);
  EXPECT_FALSE(has(o.err, "\"kind\"")) << o.err.substr(0, 500);
  // Standard output a pipe (as in `epuck2-fit ground LOGS -o /proc/self/fd/1 | jq`): descriptor 1
  // is standard output, so it holds the one file and no report (docs/cli.md, as for /dev/fd/1).
  for (const char* path : {"/proc/self/fd/1", "/dev/fd/1", "/dev/stdout"}) {
    const CliRun piped = run("ground" + logs + " -o " + path + " 2>/dev/null | cat");
    ASSERT_EQ(piped.exit_code, 0) << path;
    EXPECT_FALSE(has(piped.out, "Ground sensors")) << path << ": " << piped.out.substr(0, 300);
    EXPECT_EQ(nlohmann::json::parse(piped.out).at("kind"), "ground") << path;
  }
  const CliRun t = run("ground" + logs + " -o /proc/self/fd/2");
  ASSERT_EQ(t.exit_code, 0) << t.err.substr(0, 500);
  EXPECT_TRUE(has(t.err, "\"kind\": \"ground\"")) << t.err.substr(0, 500);
  EXPECT_FALSE(has(t.out, "\"kind\"")) << t.out.substr(0, 500);
}

// A number option's range is of finite numbers: "nan" compares false both ways and would pass a
// plain lo <= v <= hi test (docs/cli.md: --dt in [0.001, 10]).
TEST_F(RoundTwentyCli, ANanTickIsRefused) {
  for (const char* v : {"nan", "NaN", "inf"}) {
    const CliRun r = run(std::string("table5 --dt ") + v + shipped("battery"));
    EXPECT_EQ(r.exit_code, 2) << v;
    EXPECT_TRUE(has(r.err, "--dt: ")) << r.err;
    EXPECT_TRUE(has(r.err, "is out of range: allowed a finite number in [0.001, 10]")) << r.err;
  }
}

// ---- lib/calibrate: the camera's fewest observations ----

// Two LED positions give 4 pixel readings for 3 parameters (fov, cx, cy): the fit is made, and
// through the docs' pinhole (docs/diagnose.md's camera model: px = cx - f lateral / forward,
// py = cy - f vertical / forward, f = (W/2) / tan(fov/2), W = 160) it is exact: the LED at
// vertical 0 reads py = cy = 58; at vertical -0.035 m, 0.2 m ahead, py - cy = 50 = f 0.175, so
// f = 285.714 px; px = 154 = cx + f 0.25 gives cx = 82.571; fov = 2 atan(80 / f) = 31.2845 deg.
// One position (2 readings) is refused, naming the count.
TEST_F(RoundTwentyCli, ACameraFitOfTwoObservationsIsMadeAndExact) {
  const std::string two = write("two.csv", "# robot: r\nforward_m,lateral_m,vertical_m,px,py\n0.2,-0.05,-0.035,154,108\n0.2,-0.05,0,154,58\n");
  const CliRun r = run("camera --json \"" + two + "\"");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const auto p = nlohmann::json::parse(r.out).at("parameters");
  const double f = 50.0 / 0.175, pi = std::acos(-1.0);
  EXPECT_NEAR(p.at("cy_px").get<double>(), 58.0, 1e-6);
  EXPECT_NEAR(p.at("cx_px").get<double>(), 154.0 - 0.25 * f, 1e-4);
  EXPECT_NEAR(p.at("fov_deg").get<double>(), 2.0 * std::atan(80.0 / f) * 180.0 / pi, 1e-4);
  const std::string one = write("one.csv", "# robot: r\nforward_m,lateral_m,vertical_m,px,py\n0.2,-0.05,-0.035,154,108\n");
  const CliRun o = run("camera \"" + one + "\"");
  EXPECT_EQ(o.exit_code, 1);
  EXPECT_TRUE(has(o.err, "too few camera observations (1) for 3 parameters and their noise")) << o.err;
}

// simulate --like copies a log's numeric columns and says when it leaves text columns out: one
// text column is said as two are.
TEST_F(RoundTwentyCli, SimulateSaysItLeavesOutEvenOneTextColumn) {
  std::string text = "# robot: r\ngrey,sensor,value,note\n";
  for (int g = 0; g <= 10; ++g)
    for (int s = 0; s < 3; ++s) text += std::to_string(g / 10.0) + "," + std::to_string(s) + ",500,ok\n";
  const std::string log = write("g.csv", text);
  const CliRun r = run("simulate ground --like \"" + log + "\"");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_TRUE(has(r.err, "simulate: text columns of " + log + " are not copied (only numeric columns are)")) << r.err;
  EXPECT_TRUE(has(r.out, "grey,sensor,value\n")) << r.out.substr(0, 300);
}

// ---- lib/diagnose: a one-channel kind's misfit is not called its noise ----

// A ground log whose curve has a wiggle no catalogue effect describes (30 sin(6 pi grey) counts)
// and replicates scattering by the pattern -2, -1, 0, 1, 2 twice: their sd is sqrt(20 / 9) = 1.49
// counts over 21 greys x 3 sensors x 10 = 630 readings. The final model misses by about the
// wiggle's rms (21 counts), far over twice that: the diagnosis must say its residuals are not
// reading noise (docs/diagnose.md), as it does for the drive's and camera's channels.
TEST_F(RoundTwentyCli, AOneChannelDiagnosisWarnsWhenItsMisfitIsNotNoise) {
  std::string text = "# robot: r\ngrey,sensor,value\n";
  const int pattern[10] = {-2, -1, 0, 1, 2, -2, -1, 0, 1, 2};
  const double pi = std::acos(-1.0);
  for (int g20 = 0; g20 <= 20; ++g20)
    for (int s = 0; s < 3; ++s)
      for (int k = 0; k < 10; ++k) {
        const double g = g20 / 20.0;
        char line[64];
        std::snprintf(line, sizeof line, "%g,%d,%.3f\n", g, s, 50 + 900 * g + 30 * std::sin(6 * pi * g) + pattern[k]);
        text += line;
      }
  const std::string log = write("wiggle.csv", text);
  const CliRun r = run("diagnose --json \"" + log + "\"");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  bool warned = false;
  const nlohmann::json report = nlohmann::json::parse(r.out);
  for (const auto& w : report.at("warnings"))
    warned = warned || (has(w.get<std::string>(), "ground: the final model's residuals scatter ") &&
                        has(w.get<std::string>(), "times what replicate readings scatter (1.49 counts over 630 readings)"));
  EXPECT_TRUE(warned) << r.out.substr(0, 400);
}

// docs/diagnose.md: incidence_angle is looked for when every log has `angle_deg` and the angle
// varies or is not 0. One tilt throughout (60 deg: cos 0.5) counts; an angle of 0 throughout does not.
TEST_F(RoundTwentyCli, OneTiltThroughoutIsEnoughToLookForTheIncidenceEffect) {
  const std::string source = slurp(std::string(EPUCK2_SOURCE_DIR) + "/data/raw/proximity/proximity_virtual-epuck2-1.csv");
  const auto with_angle = [&](const std::string& angle) {
    std::istringstream in(source);
    std::string out;
    bool header = false;
    for (std::string l; std::getline(in, l);) {
      if (l.empty() || l[0] == '#') out += l + "\n";
      else if (!header) { out += l + ",angle_deg\n"; header = true; }
      else out += l + "," + angle + "\n";
    }
    return write("p" + angle + ".csv", out);
  };
  const auto considered = [&](const std::string& log) {
    const CliRun r = run("diagnose --json \"" + log + "\"");
    EXPECT_EQ(r.exit_code, 0) << r.err;
    const nlohmann::json report = nlohmann::json::parse(r.out);
    for (const auto& e : report.at("effects_considered"))
      if (e == "incidence_angle") return true;
    return false;
  };
  EXPECT_TRUE(considered(with_angle("60")));
  EXPECT_FALSE(considered(with_angle("0")));
}

// ---- lib/diagnose: the near field's rows include those at the base model's range ----

// docs/diagnose.md: a long tail that carries most of the modelled reading within the base model's
// range (d <= range_m, 0.05 m for the plug-in's model) is the near-field curve's shape, and the
// reason counts those rows. Rows at 30, 40, 50 and 60 mm with a tail of 8000 exp(-d / 1 m) counts
// (lifting every reading to the full scale): the rows within d <= 0.05 m are 3, the one at 50 mm
// included; the one at 60 mm is beyond.
TEST(RoundTwentyDiagnose, TheNearFieldCountsTheRowsAtTheRangeItself) {
  namespace dd = epuck2::diagnose::detail;
  const std::vector<epuck2::logs::Log> logs{epuck2::logs::parse_log(
      "distance_m,sensor,value\n0.03,0,3500\n0.04,0,3000\n0.05,0,2000\n0.06,0,1000\n", "p.csv", epuck2::logs::Kind::proximity)};
  std::string why;
  const std::unique_ptr<dd::Problem> p = dd::make_problem(logs, epuck2::diagnose::Options{}, why);
  ASSERT_TRUE(p) << why;
  std::vector<double> values;
  for (const auto& q : p->params) values.push_back(q.fallback);
  for (const auto& e : p->effects)
    if (e.cause == "long_tail") {
      values[static_cast<std::size_t>(e.params.at(0))] = 8000.0;  // amplitude, counts
      values[static_cast<std::size_t>(e.params.at(1))] = 1.0;     // length, m
    }
  const auto id = p->identify("long_tail", values, Eigen::MatrixXd());
  ASSERT_TRUE(id.has_value());
  EXPECT_EQ(id->cause, "near_field_curve");
  EXPECT_TRUE(has(id->why, "within the base model's range (d <= 0.05 m, 3 rows)")) << id->why;
}

}  // namespace test_round_twenty_cpp
