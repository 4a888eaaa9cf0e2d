// Defects a third new user's probe found (session 22) in what every sensor report and file says:
// each exited 0 with a false count or a mislabelled unit. Expected values come from the logs the
// test writes (the generator's truth) and from docs/coefficient-files.md's definitions.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <sstream>
#include <string>

#include <nlohmann/json.hpp>

#include "cli_harness.hpp"

namespace test_probe_three_cpp {

using epuck2::testing::CliRun;
using epuck2::testing::slurp;
using nlohmann::json;

bool has(const std::string& text, const std::string& part) { return text.find(part) != std::string::npos; }

std::size_t count(const std::string& text, const std::string& part) {
  std::size_t n = 0;
  for (std::size_t at = text.find(part); at != std::string::npos; at = text.find(part, at + part.size())) ++n;
  return n;
}

/// A ground log of robot `robot`: reading = offset + 800 grey (counts) for greys 0, 0.1, .., 1 and
/// the three sensors, five readings each at +{-2, -1, 0, 1, 2} counts.
std::string ground_log(const std::string& robot, double offset) {
  std::string text = "# robot: " + robot + "\ngrey,sensor,value\n";
  for (int g = 0; g <= 10; ++g)
    for (int s = 0; s < 3; ++s)
      for (int e = -2; e <= 2; ++e) {
        char line[64];
        std::snprintf(line, sizeof line, "%.1f,%d,%.0f\n", g / 10.0, s, offset + 80.0 * g + e);
        text += line;
      }
  return text;
}

class ProbeThree : public epuck2::testing::CliTest {};

// Two robots whose black offsets differ by 30 counts (readings scatter 1.6 counts): the robots'
// comparison warns that they differ. The report's count of warnings counts every warning printed
// on standard error and held in the JSON; it counted only the fit's own and left the robots' out
// (ground printed no count at all).
TEST_F(ProbeThree, TheReportCountsEveryWarningItsFileHolds) {
  const std::string a = write("a.csv", ground_log("r1", 60)), b = write("b.csv", ground_log("r2", 90));
  const CliRun t = run("ground \"" + a + "\" \"" + b + "\"");
  ASSERT_EQ(t.exit_code, 0) << t.err;
  const std::size_t printed = count(t.err, "ground: warning: ");
  EXPECT_GE(count(t.err, "the robots differ in"), 1u) << t.err;
  ASSERT_GE(printed, 1u);
  EXPECT_TRUE(has(t.out, "\n" + std::to_string(printed) + " warnings (on standard error and in the JSON)\n")) << t.out;
  const CliRun j = run("ground --json \"" + a + "\" \"" + b + "\"");
  ASSERT_EQ(j.exit_code, 0) << j.err;
  const json file = json::parse(j.out);
  EXPECT_EQ(file.at("warnings").size(), printed);
  // One robot: nothing to warn about, no count line.
  const CliRun one = run("ground \"" + a + "\"");
  ASSERT_EQ(one.exit_code, 0) << one.err;
  EXPECT_EQ(count(one.err, "warning:"), 0u) << one.err;
  EXPECT_FALSE(has(one.out, "warnings (on standard error")) << one.out;
}

// docs/coefficient-files.md, "Fit statistics": `rss_unit` is "the RSS's unit (the reading's unit
// squared)", as the file's `units.rss` and the battery's and diagnosis's files give it. Each
// sensor file's fits carried the reading's unit itself.
TEST_F(ProbeThree, EveryFitsRssUnitIsTheReadingsUnitSquared) {
  const struct {
    const char* kind;
    const char* fit;
    const char* unit;
  } cases[] = {{"ground", "sensor_0", "counts^2"},           {"ground", "sensor_2", "counts^2"},
               {"light", "gamma", "(reading / 4095)^2"},      {"proximity", "maxima", "(reading / 4095)^2"},
               {"proximity", "means", "(reading / 4095)^2"},  {"camera", "projection", "px^2"},
               {"drive", "steps", "steps^2"},                 {"drive", "tof", "mm^2"}};
  for (const auto& c : cases) {
    const json file = epuck2::testing::shipped_fitted(c.kind);
    EXPECT_EQ(file.at("fits").at(c.fit).at("rss_unit").get<std::string>(), c.unit) << c.kind << " " << c.fit;
  }
  // And a fit run now (not only the shipped files): ground of the test's own log.
  const std::string a = write("a.csv", ground_log("r1", 60));
  const CliRun j = run("ground --json \"" + a + "\"");
  ASSERT_EQ(j.exit_code, 0) << j.err;
  const json file = json::parse(j.out);
  EXPECT_EQ(file.at("fits").at("sensor_1").at("rss_unit").get<std::string>(), "counts^2");
  EXPECT_EQ(file.at("units").at("rss").get<std::string>(), "counts^2");
}

// The proximity report's header counts the readings on a rail, those beyond the range (left out,
// never fitted) among them: it called them all censored. The plug-in's curve (a = 197.8633,
// b = -30.47182, c = 1.011635) at 0..60 mm in 5 mm steps, 8 sensors, five readings each at
// +{-20, -10, 0, 10, 20} counts, clamped to 0..4095: at 0 mm it reads 4142.6 (all 40 on the 4095
// rail), at 50 mm -71 (all 40 on 0), at 55 and 60 mm below 0 too (80 on 0, beyond the 50 mm
// range); 45 mm reads 168. So 160 on a rail, 80 of them at the distances the fits use.
TEST_F(ProbeThree, TheProximityHeaderSaysWhichRailReadingsAreCensored) {
  std::string text = "# robot: t\ndistance_m,sensor,value\n";
  std::size_t on_rail = 0;
  for (int mm5 = 0; mm5 <= 12; ++mm5) {
    const double d = mm5 * 0.005;
    const double v = (197.8633 * d * d - 30.47182 * d + 1.011635) * 4095.0;
    for (int s = 0; s < 8; ++s)
      for (int e = -20; e <= 20; e += 10) {
        const double r = std::min(4095.0, std::max(0.0, std::round(v + e)));
        if (r == 0.0 || r == 4095.0) ++on_rail;
        char line[64];
        std::snprintf(line, sizeof line, "%.3f,%d,%.0f\n", d, s, r);
        text += line;
      }
  }
  ASSERT_EQ(on_rail, 160u);
  const std::string log = write("p.csv", text);
  const CliRun t = run("proximity --accept-misfit \"" + log + "\"");
  ASSERT_EQ(t.exit_code, 0) << t.err;
  EXPECT_TRUE(has(t.out, "520 readings at 13 distances; 160 on a rail (0 or 4095: censored at the distances used); ")) << t.out;
  const CliRun j = run("proximity --accept-misfit --json \"" + log + "\"");
  ASSERT_EQ(j.exit_code, 0) << j.err;
  EXPECT_EQ(json::parse(j.out).at("censored_readings").get<std::size_t>(), 160u);
}

}  // namespace test_probe_three_cpp
