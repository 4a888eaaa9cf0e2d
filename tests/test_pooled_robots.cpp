// Pooled fits over several robots (probe 5, defect 02): a reading is judged wild against its own
// robot's replicates, not against every robot's readings under the same conditions (whose spread
// is the robots' difference, not the noise); the lack-of-fit test of a pooled fit says that its
// groups span the robots. The logs are written here with a known truth: robot A reads 1000 grey,
// robot B 700 grey, each reading at +{-2, -1, 0, 0, 1, 2} counts; one of A's readings is 100
// counts off (50 of A's own robust sd, a third of the two robots' gap).
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <string>

#include <nlohmann/json.hpp>

#include "cli_harness.hpp"

namespace test_pooled_robots_cpp {

using epuck2::testing::CliRun;
using epuck2::testing::slurp;
using nlohmann::json;

bool has(const std::string& text, const std::string& part) { return text.find(part) != std::string::npos; }

class PooledRobots : public epuck2::testing::CliTest {};

constexpr int kNoise[] = {-2, -1, 0, 0, 1, 2};

/// A ground log of `robot` (gain `gain`, offset 0) for greys 0.1 .. 0.9 and the three sensors.
/// When `wild_line` is given, the reading of sensor 0 at grey 0.5 with noise +2 reads 100 more,
/// and *wild_line is set to its line number (1-based, the file's own lines).
std::string ground_log(const std::string& robot, int gain, int* wild_line = nullptr) {
  std::string text = "# robot: " + robot + "\ngrey,sensor,value\n";
  int line = 2;
  char buf[64];
  for (int g = 1; g <= 9; ++g)
    for (int s = 0; s < 3; ++s)
      for (int e : kNoise) {
        int v = gain * g / 10 + e;
        ++line;
        if (wild_line != nullptr && g == 5 && s == 0 && e == 2) {
          v += 100;
          *wild_line = line;
        }
        std::snprintf(buf, sizeof buf, "0.%d,%d,%d\n", g, s, v);
        text += buf;
      }
  return text;
}

TEST_F(PooledRobots, AGroundReadingFarFromItsOwnRobotsReplicatesIsWildInThePooledFit) {
  int wild = 0;
  const std::string a = write("a.csv", ground_log("A", 1000, &wild));
  const std::string b = write("b.csv", ground_log("B", 700));
  ASSERT_GT(wild, 0);
  const std::string out = (dir_ / "g.json").string();
  const CliRun r = run("ground \"" + a + "\" \"" + b + "\" -o \"" + out + "\"");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const json j = json::parse(slurp(out));
  // A's group at grey 0.5 reads 498, 499, 500, 500, 501, 602: 602 is 101.5 counts from its median
  // (far beyond 8 robust sd, whose floor is 2.3 counts). With B's six readings (348 .. 352) in the
  // same group its median would be 425 and its MAD 75.5 (8 robust sd: 895): kept.
  const std::string where = a + ":" + std::to_string(wild);
  int listed = 0;
  for (const json& w : j.at("outliers").at("rows")) listed += w.get<std::string>() == where;
  EXPECT_EQ(listed, 1) << j.at("outliers").dump();
  EXPECT_EQ(j.at("outliers").at("count").get<int>(), 1) << j.at("outliers").dump();
  // The pooled line through both robots: gain 850 (their mean; the same readings at each grey),
  // offset 0, to the noise's rounding.
  EXPECT_NEAR(j.at("parameters").at("gain").at(0).get<double>(), 850.0, 1.0) << j.at("parameters").dump();
  // The pooled lack-of-fit groups pool both robots, and say so.
  EXPECT_EQ(j.at("lack_of_fit").at("sensor_0").at("robots").get<int>(), 2) << j.at("lack_of_fit").dump();
  // Their sd is the robots' spread: at grey g the readings are 100 g +- 150 g: about 150 g (g =
  // 0.1 .. 0.9: pooled over the groups, sqrt(mean((150 g)^2) * 12/11) ~ 90), far above the 1.4 of one robot.
  EXPECT_GT(j.at("lack_of_fit").at("sensor_1").at("replicate_sd").get<double>(), 50.0);
  EXPECT_TRUE(has(r.out, "(the groups pool 2 robots: this sd holds their differences beside the reading noise")) << r.out;
  EXPECT_TRUE(has(r.out, "under the same conditions and robot judged against their replicates only")) << r.out;
  // Each robot's own set is tested within that robot: its groups do not pool robots.
  const json& own = j.at("robots").at("A");
  ASSERT_TRUE(own.value("usable", false)) << own.dump();
}

TEST_F(PooledRobots, OneRobotsLackOfFitDoesNotSayItPoolsRobots) {
  const std::string a = write("a.csv", ground_log("A", 1000));
  const std::string out = (dir_ / "g.json").string();
  const CliRun r = run("ground \"" + a + "\" -o \"" + out + "\"");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const json j = json::parse(slurp(out));
  EXPECT_EQ(j.at("lack_of_fit").at("sensor_0").at("robots").get<int>(), 1) << j.at("lack_of_fit").dump();
  EXPECT_FALSE(has(r.out, "the groups pool")) << r.out;
  EXPECT_FALSE(has(r.out, "conditions and robot judged")) << r.out;
  // One robot, noise +{-2, -1, 0, 0, 1, 2}: the replicate sd is sqrt(10 / 5) = 1.414 in every group.
  EXPECT_NEAR(j.at("lack_of_fit").at("sensor_0").at("replicate_sd").get<double>(), std::sqrt(2.0), 1e-9);
}

/// A proximity log of `robot`: every sensor reads scale * {3600, 3000, 2200, 1500, 1100, 800} at
/// 10, 20, .., 60 mm, +{-2, -1, 0, 0, 1, 2}; with `wild_line`, sensor 3's reading at 20 mm with
/// noise +2 reads 1000 less.
std::string proximity_log(const std::string& robot, double scale, int* wild_line = nullptr) {
  std::string text = "# robot: " + robot + "\ndistance_m,sensor,value\n";
  int line = 2;
  char buf[64];
  const int at[] = {3600, 3000, 2200, 1500, 1100, 800};
  for (int d = 0; d < 6; ++d)
    for (int s = 0; s < 8; ++s)
      for (int e : kNoise) {
        int v = static_cast<int>(std::lround(scale * at[d])) + e;
        ++line;
        if (wild_line != nullptr && d == 1 && s == 3 && e == 2) {
          v -= 1000;
          *wild_line = line;
        }
        std::snprintf(buf, sizeof buf, "0.0%d,%d,%d\n", d + 1, s, v);
        text += buf;
      }
  return text;
}

TEST_F(PooledRobots, AProximityReadingFarFromItsOwnRobotsReplicatesIsLeftOut) {
  int wild = 0;
  const std::string a = write("pa.csv", proximity_log("A", 1.0, &wild));
  const std::string b = write("pb.csv", proximity_log("B", 2.0 / 3.0));
  const std::string out = (dir_ / "p.json").string();
  const CliRun r = run("proximity \"" + a + "\" \"" + b + "\" -o \"" + out + "\"");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const json j = json::parse(slurp(out));
  // At 20 mm A's 48 readings centre on 3000 (robust sd at most 2.3, the floor), and its reading
  // 3002 - 1000 = 2002 sits 998 counts below them. Pooled with B's 48 readings around 2000, the
  // group's median would be about 2500 and its MAD about 500 (8 robust sd: 5900): kept.
  const std::string where = a + ":" + std::to_string(wild);
  int listed = 0;
  for (const json& l : j.at("left_out").at("rows")) listed += l.at("where").get<std::string>() == where;
  EXPECT_EQ(listed, 1) << j.at("left_out").dump();
}

}  // namespace test_pooled_robots_cpp
