// The virtual robot's proximity protocol (paper section 4.1.1): two static robots, PROX0 facing a
// white surface at 0..60 mm, about 24 readings/s for 15 s per distance. data/raw/proximity/README.md
// documents the imperfections (readings scatter below the envelope, robots disagree, noise, the
// receiver saturates at 0 mm, occasional wild readings).
#include <algorithm>
#include <cmath>

#include "epuck2/logs/output.hpp"
#include "epuck2/models/sensors.hpp"
#include "epuck2/virtual_robot/reference_logs.hpp"
#include "epuck2/virtual_robot/sensor_truth.hpp"

namespace epuck2::virtual_robot {

std::vector<GeneratedFile> proximity_logs(const ProximityTruth& truth, std::uint64_t seed) {
  namespace s = models::sensors;
  std::vector<GeneratedFile> files;
  for (std::size_t r = 0; r < truth.robot_gain.size(); ++r) {
    Gaussian noise(seed + 1000 * (r + 1));
    WildReadings wild(seed + 1000 * (r + 1) + 700, truth.wild_fraction);
    logs::LogWriter w({"time_s", "distance_m", "sensor", "value"});
    const std::string robot = robot_id(r);
    w.comment("Synthetic log recorded by epuck2-fit's virtual robot (see README.md); not a real robot.");
    w.metadata("robot", robot);
    w.metadata("surface", "white cardboard");
    w.metadata("seed", std::to_string(seed));
    long k = 0;
    const double period_s = 15.0 / truth.readings_per_distance;
    for (std::size_t j = 0; j < truth.distances_m.size(); ++j) {
      const double d = truth.distances_m[j];
      const double envelope = s::proximity_response(truth.envelope, d) * truth.robot_gain[r];
      // The nearest distances saturate the receiver: the rail plus the electronic noise.
      const bool saturated = static_cast<int>(j) < truth.saturated_distances;
      for (int i = 0; i < truth.readings_per_distance; ++i) {
        double v;
        if (saturated) {
          v = 1.0 + noise() * truth.noise_raw / s::kProximityFullScale_raw;
        } else {
          const double scatter = std::abs(noise()) * (truth.scatter_floor + truth.scatter_slope * envelope);
          v = (envelope > 0 ? envelope - scatter : 0.0) + noise() * truth.noise_raw / s::kProximityFullScale_raw;
        }
        // The firmware reports max(0, delta - offset) (the e-puck2 firmware), on 12 bits.
        double raw = whole_count(v * s::kProximityFullScale_raw, s::kProximityFullScale_raw);
        double wild_raw;
        if (wild.next(0.0, s::kProximityFullScale_raw, true, &wild_raw)) raw = wild_raw;
        const double t = std::round(static_cast<double>(k++) * period_s * 1e6) / 1e6;  // microseconds
        w.row({t, d, static_cast<double>(truth.sensor), raw}, 0);
      }
    }
    files.push_back({"proximity_" + robot + ".csv", w.str()});
  }
  return files;
}

std::vector<GeneratedFile> proximity_reference_logs(std::uint64_t seed) { return proximity_logs(ProximityTruth{}, seed); }

}  // namespace epuck2::virtual_robot
