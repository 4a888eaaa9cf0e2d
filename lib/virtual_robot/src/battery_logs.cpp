// The virtual robot's battery reference logs (data/raw/battery): robots a and b, each spinning in
// place at 0..15 cm/s from full charge until it stops (paper section 4.1.7's protocol).
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <string>

#include "epuck2/logs/output.hpp"
#include "epuck2/virtual_robot/battery.hpp"
#include "epuck2/virtual_robot/reference_logs.hpp"

namespace epuck2::virtual_robot {

namespace {

// Printed precision: time to 0.1 s, charge to 6 significant digits, voltage to 0.1 mV (the ADC
// resolves 1.22 mV per count; the filtered mean carries a little more). Each value is printed with
// its precision and read back, so that the log's shortest round-trip text is exactly that.
double printed(double value, const char* format, int precision) {
  char buf[64];
  std::snprintf(buf, sizeof buf, format, precision, value);
  return std::strtod(buf, nullptr);
}
constexpr int kTimeDecimals = 1;
constexpr int kChargeDigits = 6;
constexpr int kVoltageDecimals = 4;

}  // namespace

std::vector<GeneratedFile> battery_reference_logs(std::uint64_t seed) {
  namespace vb = battery;
  const vb::Calibration& cal = vb::reference_calibration();
  const vb::RobotParameters robots[2] = {vb::robot_a(), vb::robot_b()};
  const char letters[2] = {'a', 'b'};
  std::vector<GeneratedFile> files;
  for (int r = 0; r < 2; ++r) {
    for (int s = 0; s < models::battery::kSpeedCount; ++s) {
      const vb::Run run = vb::simulate_protocol(s, robots[r], vb::reference_run_seed(seed, r, s), {}, cal);
      logs::LogWriter w({"time_s", "speed_cm_s", "charge", "voltage_v"});
      w.metadata("robot", robots[r].name);
      w.metadata("source", "synthetic, epuck2-fit virtual robot (see data/raw/battery/README.md)");
      w.metadata("seed", std::to_string(seed));
      w.metadata("protocol", "spinning in place at " + std::to_string(s) + " cm/s from full charge until the robot stops");
      for (const vb::Row& row : run.rows)
        w.row({printed(row.time_s, "%.*f", kTimeDecimals), row.speed_cm_s, printed(row.charge, "%.*g", kChargeDigits),
               printed(row.voltage_v, "%.*f", kVoltageDecimals)});
      char name[64];
      std::snprintf(name, sizeof name, "robot-%c_speed-%02d.csv", letters[r], s);
      files.push_back({name, w.str()});
    }
  }
  return files;
}

}  // namespace epuck2::virtual_robot
