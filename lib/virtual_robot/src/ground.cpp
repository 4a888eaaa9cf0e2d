// The virtual robot's ground protocol (paper section 4.1.3): the three ground sensors over printed
// grey levels 0, 0.1, ..., 1 (0 = black), for two robots. data/raw/ground/README.md documents the
// imperfections (black still reflects: an offset; the sensors and robots disagree: gains; noise;
// 10-bit clamp with one sensor's white straddling the rail; occasional wild readings).
#include <algorithm>
#include <cmath>

#include "epuck2/logs/output.hpp"
#include "epuck2/models/sensors.hpp"
#include "epuck2/virtual_robot/reference_logs.hpp"
#include "epuck2/virtual_robot/sensor_truth.hpp"

namespace epuck2::virtual_robot {

std::vector<GeneratedFile> ground_logs(const GroundTruth& truth, std::uint64_t seed) {
  namespace s = models::sensors;
  std::vector<GeneratedFile> files;
  for (std::size_t r = 0; r < truth.robot_gain_scale.size(); ++r) {
    Gaussian noise(seed + 3000 + 100 * r);
    WildReadings wild(seed + 3500 + 100 * r, truth.wild_fraction);
    std::array<double, 3> gain;
    for (std::size_t k = 0; k < 3; ++k) gain[k] = truth.gain_raw[k] * truth.robot_gain_scale[r];
    // Robot 2's centre sensor: white (grey 1) at the rail.
    if (r == 1 && truth.white_rail_raw > 0) gain[1] = truth.white_rail_raw - truth.offset_raw[1];
    logs::LogWriter w({"grey", "sensor", "value"});
    w.comment("Synthetic log recorded by epuck2-fit's virtual robot (see README.md); not a real robot.");
    w.metadata("robot", robot_id(r));
    w.metadata("seed", std::to_string(seed));
    for (int g = 0; g <= truth.grey_steps; ++g) {
      const double grey = static_cast<double>(g) / truth.grey_steps;
      for (int sensor = 0; sensor < s::kGroundCount; ++sensor) {
        const double mean = s::ground_response(gain[sensor], truth.offset_raw[sensor], grey);
        for (int i = 0; i < truth.readings; ++i) {
          double raw = whole_count(mean + noise() * truth.noise_raw, s::kGroundFullScale_raw);
          double wild_raw;
          if (wild.next(0.0, s::kGroundFullScale_raw, true, &wild_raw)) raw = wild_raw;
          w.row({grey, static_cast<double>(sensor), raw});
        }
      }
    }
    files.push_back({"ground_" + robot_id(r) + ".csv", w.str()});
  }
  return files;
}

std::vector<GeneratedFile> ground_reference_logs(std::uint64_t seed) { return ground_logs(GroundTruth{}, seed); }

}  // namespace epuck2::virtual_robot
