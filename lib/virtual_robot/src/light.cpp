// The virtual robot's light protocol (paper section 4.1.2): PROX0 and PROX7 of one static robot
// facing a light source at 10..50 cm, for several intensities. data/raw/light/README.md documents
// the imperfections (sensors disagree, stray ambient light, noise, saturation).
#include <algorithm>
#include <cmath>
#include <cstdio>

#include "epuck2/logs/output.hpp"
#include "epuck2/models/sensors.hpp"
#include "epuck2/virtual_robot/reference_logs.hpp"
#include "epuck2/virtual_robot/sensor_truth.hpp"

namespace epuck2::virtual_robot {

std::vector<GeneratedFile> light_logs(const LightTruth& truth, std::uint64_t seed) {
  namespace s = models::sensors;
  std::vector<GeneratedFile> files;
  for (std::size_t k = 0; k < truth.intensities.size(); ++k) {
    const double intensity = truth.intensities[k];
    Gaussian noise(seed + 2000 + k);
    logs::LogWriter w({"distance_m", "intensity", "sensor", "value"});
    w.comment("Synthetic log recorded by epuck2-fit's virtual robot (see README.md); not a real robot.");
    w.metadata("robot", "virtual-epuck2-1");
    w.metadata("seed", std::to_string(seed));
    for (double d : truth.distances_m) {
      for (std::size_t j = 0; j < truth.sensors.size(); ++j) {
        // Eq. 2 with the sensor's own gain on the light term, then stray light and noise.
        const double sum = truth.sensor_gain[j] * s::light_contribution(truth.gamma_m, intensity, d);
        for (int i = 0; i < truth.readings; ++i) {
          const double v = (1.0 - sum) * s::kProximityFullScale_raw - truth.ambient_raw + noise() * truth.noise_raw;
          const double raw = std::clamp(std::round(v), 0.0, s::kProximityFullScale_raw);
          w.row({d, intensity, static_cast<double>(truth.sensors[j]), raw});
        }
      }
    }
    char name[64];
    std::snprintf(name, sizeof name, "light_intensity_%.2f.csv", intensity);
    files.push_back({name, w.str()});
  }
  return files;
}

std::vector<GeneratedFile> light_reference_logs(std::uint64_t seed) { return light_logs(LightTruth{}, seed); }

}  // namespace epuck2::virtual_robot
