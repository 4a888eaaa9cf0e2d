// The virtual robot's ground protocol (paper section 4.1.3): the three ground sensors over printed
// grey levels 0, 0.1, ..., 1 (0 = black). data/raw/ground/README.md documents the imperfections
// (black still reflects: an offset; the sensors disagree: per-sensor gains; noise; 10-bit clamp).
#include <algorithm>
#include <cmath>

#include "epuck2/logs/output.hpp"
#include "epuck2/models/sensors.hpp"
#include "epuck2/virtual_robot/reference_logs.hpp"
#include "epuck2/virtual_robot/sensor_truth.hpp"

namespace epuck2::virtual_robot {

std::vector<GeneratedFile> ground_logs(const GroundTruth& truth, std::uint64_t seed) {
  namespace s = models::sensors;
  Gaussian noise(seed + 3000);
  logs::LogWriter w({"grey", "sensor", "value"});
  w.comment("Synthetic log recorded by epuck2-fit's virtual robot (see README.md); not a real robot.");
  w.metadata("robot", "virtual-epuck2-1");
  w.metadata("seed", std::to_string(seed));
  for (int g = 0; g <= truth.grey_steps; ++g) {
    const double grey = static_cast<double>(g) / truth.grey_steps;
    for (int sensor = 0; sensor < s::kGroundCount; ++sensor) {
      const double mean = s::ground_response(truth.gain_raw[sensor], truth.offset_raw[sensor], grey);
      for (int i = 0; i < truth.readings; ++i) {
        const double raw = std::clamp(std::round(mean + noise() * truth.noise_raw), 0.0, s::kGroundFullScale_raw);
        w.row({grey, static_cast<double>(sensor), raw});
      }
    }
  }
  return {{"ground_virtual-epuck2-1.csv", w.str()}};
}

std::vector<GeneratedFile> ground_reference_logs(std::uint64_t seed) { return ground_logs(GroundTruth{}, seed); }

}  // namespace epuck2::virtual_robot
