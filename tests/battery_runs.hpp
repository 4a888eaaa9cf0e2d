// Hand-made battery runs for tests of the battery fit: a known lifetime, a known shape.
#pragma once

#include <cmath>
#include <string>

#include "epuck2/calibrate/battery.hpp"

namespace epuck2::testing {

/// A run from full to empty in 1-s rows, charge 1 - t / lifetime plus a small fixed wiggle
/// 0.002 sin(1.3 t) (never an outlier), at one speed, ending at `lifetime` seconds.
inline calibrate::BatteryRun wiggly_battery_run(double speed, double lifetime, const std::string& robot) {
  calibrate::BatteryRun r;
  r.path = robot + "_" + std::to_string(speed) + ".csv";
  r.robot = robot;
  r.speed_cm_s = speed;
  r.lifetime_s = lifetime;
  for (int t = 0; t <= static_cast<int>(lifetime); ++t) {
    r.time_s.push_back(t);
    r.charge.push_back(1.0 - t / lifetime + 0.002 * std::sin(1.3 * t));
    r.line.push_back(t + 2);
  }
  r.profile = {{0.0, speed}};
  return r;
}

}  // namespace epuck2::testing
