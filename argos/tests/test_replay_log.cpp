// The --like replay's log handling (argos/experiments/src/replay_log.*), without ARGoS: which
// columns a replay keeps, copies and fills, what it refuses, and the text it writes. Expected
// strings are written out by hand from docs/argos.md's description of the replay.
#include <cstdio>
#include <fstream>
#include <string>

#include <gtest/gtest.h>

#include "../experiments/src/replay_log.hpp"
#include "epuck2/logs/log.hpp"

namespace {

namespace ar = epuck2::argos_replay;

std::string write(const std::string& name, const std::string& text) {
  const std::string path = ::testing::TempDir() + name;
  std::ofstream(path) << text;
  return path;
}

TEST(ArgosReplayLog, GroundKeepsEveryColumnAndFillsTheReading) {
  const std::string path = write("replay_ground.csv", "# robot: r1\n# seed: 7\n# protocol: old\ngrey,sensor,value\n0.5,2,511\n1,0,1000\n");
  const ar::ReplayLog r = ar::read_replay_log(path, "ground");
  ASSERT_EQ(r.rows(), 2u);
  EXPECT_EQ(r.columns, (std::vector<std::string>{"grey", "sensor", "value"}));
  EXPECT_EQ(r.readings, (std::vector<std::string>{"value"}));
  EXPECT_EQ(ar::replay_head(r, "argos-epuck2", "P"),
            "# robot: argos-epuck2\n# seed: 7\n# replayed_from: " + path + "\n# protocol: P\ngrey,sensor,value\n");
  EXPECT_EQ(ar::replay_row(r, 0, {{"value", "498"}}), "0.5,2,498\n");
  EXPECT_EQ(ar::replay_row(r, 1, {{"value", "1023"}}), "1,0,1023\n");
  EXPECT_THROW(ar::replay_row(r, 0, {}), std::logic_error);  // a reading ARGoS did not give
}

TEST(ArgosReplayLog, ProximityCopiesTimeAndAngle) {
  const std::string path = write("replay_prox.csv", "time_s,distance_m,sensor,value,angle_deg\n0.25,0.005,3,3539,30\n");
  const ar::ReplayLog r = ar::read_replay_log(path, "proximity");
  EXPECT_EQ(r.columns, (std::vector<std::string>{"time_s", "distance_m", "sensor", "value", "angle_deg"}));
  EXPECT_EQ(ar::replay_row(r, 0, {{"value", "12"}}), "0.25,0.005,3,12,30\n");
}

TEST(ArgosReplayLog, AConditionArgosCannotSetIsRefusedAtTheHeader) {
  const std::string path = write("replay_temp.csv", "# robot: r\ngrey,sensor,value,temperature_c\n0.5,1,500,31\n");
  try {
    ar::read_replay_log(path, "ground");
    FAIL() << "a temperature_c column was accepted";
  } catch (const epuck2::logs::InputError& e) {
    EXPECT_EQ(e.line(), 2);
    EXPECT_NE(e.message().find("column 'temperature_c': ARGoS has no way to set it"), std::string::npos) << e.what();
  }
}

TEST(ArgosReplayLog, BatteryDropsTheVoltageAndAVoltageOnlyLogGetsACharge) {
  const ar::ReplayLog both = ar::read_replay_log(write("replay_bat.csv", "time_s,speed_cm_s,charge,voltage_v\n0,5,1,4.2\n10,5,0.99,4.19\n"), "battery");
  EXPECT_EQ(both.columns, (std::vector<std::string>{"time_s", "speed_cm_s", "charge"}));
  EXPECT_EQ(ar::replay_row(both, 1, {{"charge", "0.98"}}), "10,5,0.98\n");
  const ar::ReplayLog volts = ar::read_replay_log(write("replay_volts.csv", "time_s,speed_cm_s,voltage_v\n0,5,4.2\n"), "battery");
  EXPECT_EQ(volts.columns, (std::vector<std::string>{"time_s", "speed_cm_s", "charge"}));
  EXPECT_EQ(ar::replay_row(volts, 0, {{"charge", "1"}}), "0,5,1\n");
}

TEST(ArgosReplayLog, DriveReadsItsObstacleDistanceAndFillsThreeReadings) {
  const std::string path = write("replay_drive.csv",
                                 "# obstacle_distance_m: 0.3\ntime_s,left_speed_cm_s,right_speed_cm_s,left_steps,right_steps,tof_mm\n"
                                 "0,0,0,0,0,300\n0.1,5,5,3,3,298\n");
  const ar::ReplayLog r = ar::read_replay_log(path, "drive");
  EXPECT_DOUBLE_EQ(r.obstacle_distance_m, 0.3);
  EXPECT_EQ(r.readings, (std::vector<std::string>{"left_steps", "right_steps", "tof_mm"}));
  EXPECT_EQ(ar::replay_row(r, 1, {{"left_steps", "4"}, {"right_steps", "5"}, {"tof_mm", "297"}}), "0.1,5,5,4,5,297\n");
  // Without its obstacle distance a drive log is refused as epuck2-fit refuses it.
  EXPECT_THROW(ar::read_replay_log(write("replay_drive_bad.csv", "time_s,left_speed_cm_s,right_speed_cm_s,left_steps,right_steps,tof_mm\n0,0,0,0,0,300\n"),
                                   "drive"),
               epuck2::logs::InputError);
}

TEST(ArgosReplayLog, ALogOfAnotherKindIsRefused) {
  EXPECT_THROW(ar::read_replay_log(write("replay_wrong.csv", "grey,sensor,value\n0.5,1,500\n"), "camera"), epuck2::logs::InputError);
}

}  // namespace
