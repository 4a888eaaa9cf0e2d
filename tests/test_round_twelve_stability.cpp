// Correctness tests for round 12's two slips that only the byte-for-byte comparisons of
// regenerated files caught (bench/fresh-slips.md, "Round 12"): the virtual battery's stop time
// within its last tick, and the battery file's lifetime text for two runs. Expected values are
// worked by hand from the definitions in docs/, not taken from the code under test.
#include <gtest/gtest.h>

#include <cmath>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "battery_runs.hpp"
#include "epuck2/calibrate/battery.hpp"
#include "epuck2/calibrate/battery_json.hpp"
#include "epuck2/virtual_robot/battery.hpp"

namespace test_round_twelve_stability_cpp {

namespace vb = epuck2::virtual_robot::battery;

// A hand-made cell: open-circuit voltage 3.0 + 1.2 z (every knot on one line), no path
// resistance, no load pulses, 1 A drawn at every speed from 1 Ah. Its terminal voltage is then
// exactly linear in time, V(t) = 4.2 - 1.2 t / 3600, and the robot stops where V reaches the
// stop level: t* = (4.2 - stop) * 3600 / 1.2.
vb::Calibration linear_cell(double stop_v) {
  vb::Calibration c;
  c.capacity_Ah = 1.0;
  c.path_resistance_ohm = 0.0;
  for (int k = 0; k < vb::kOcvKnotCount; ++k) c.ocv_v[k] = 3.0 + 1.2 * (k * vb::kOcvKnotStep);
  c.current_a.fill(1.0);
  c.stop_voltage_v.fill(stop_v);
  c.pulse_dip_v = 0.0;
  return c;
}

vb::Run run_on(const vb::Calibration& c) {
  vb::SimulationOptions o;
  o.noise = false;
  o.log_interval_s = 10.0;
  return vb::simulate({{0.0, 0.0}}, vb::RobotParameters{}, 1, o, c);
}

TEST(RoundTwelveStability, TheBatteryStopsWhereItsVoltageCrossesTheStopLevelInsideTheLastTick) {
  // Stop at 3.6001 V: t* = 0.5999 * 3000 = 1799.7 s, 0.2 s into the 0.5-s tick 1799.5..1800 s
  // (2/5 of it; counting the fraction from the tick's other end gives 1799.8 s).
  const vb::Run r = run_on(linear_cell(3.6001));
  ASSERT_TRUE(r.stopped);
  EXPECT_NEAR(r.stop_time_s, 1799.7, 1e-6);
  ASSERT_FALSE(r.rows.empty());
  EXPECT_NEAR(r.rows.back().time_s, 1799.7, 1e-6);  // the stop row is logged at the stop
  // Stop at 3.5 V: t* = 0.7 * 3000 = 2100 s, 0.0 s into no tick: a tick's end (2099.5..2100 s).
  EXPECT_NEAR(run_on(linear_cell(3.5)).stop_time_s, 2100.0, 1e-6);
  // Stop at 3.70004 V: t* = 0.49996 * 3000 = 1499.88 s, 0.38 s into 1499.5..1500 s.
  EXPECT_NEAR(run_on(linear_cell(3.70004)).stop_time_s, 1499.88, 1e-6);
}

// A run from full to empty in 1-s rows with a small fixed wiggle (tests/battery_runs.hpp).
constexpr auto* run_of = &epuck2::testing::wiggly_battery_run;

std::string lifetime_of(const nlohmann::json& j, double speed) {
  for (const nlohmann::json& s : j.at("speeds"))
    if (s.at("speed_cm_s").get<double>() == speed) return s.at("lifetime").get<std::string>();
  ADD_FAILURE() << "no speed " << speed;
  return {};
}

TEST(RoundTwelveStability, TheLifetimeOfTwoRunsCarriesTheirStandardError) {
  // 0 cm/s: two runs ending at 100 and 120 s -> mean 110, sd sqrt(2 * 10^2 / 1) = 14.14, its
  // standard error 14.14 / sqrt(2) = 10. 5 cm/s: three runs 50, 60, 70 -> 60, sd 10, se 5.77.
  // 10 cm/s: one run (40 s): no spread, said. 15 cm/s: two runs that end together (30, 30).
  const std::vector<epuck2::calibrate::BatteryRun> runs{
      run_of(0, 100, "a"), run_of(0, 120, "b"), run_of(5, 50, "a"), run_of(5, 60, "b"), run_of(5, 70, "c"),
      run_of(10, 40, "a"), run_of(15, 30, "a"), run_of(15, 30, "b")};
  const nlohmann::json j = epuck2::calibrate::battery_fit_to_json(epuck2::calibrate::fit_battery(runs));
  EXPECT_EQ(lifetime_of(j, 0), "110 ± 10 s (mean of 2 runs' ends, standard error over runs)");
  EXPECT_EQ(lifetime_of(j, 5), "60.0 ± 5.8 s (mean of 3 runs' ends, standard error over runs)");
  EXPECT_EQ(lifetime_of(j, 10), "40 s (the end of the only run's log: no spread to estimate an error from)");
  EXPECT_EQ(lifetime_of(j, 15), "30 s (the runs end at the same time)");
}

}  // namespace test_round_twelve_stability_cpp
