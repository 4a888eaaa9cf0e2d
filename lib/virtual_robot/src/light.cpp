// The virtual robot's light protocol (paper section 4.1.2): PROX0 and PROX7 of a static robot
// facing a light source at 10..50 cm, for several intensities, for two robots. data/raw/light/README.md
// documents the imperfections (sensors and robots disagree, stray ambient light, noise, saturation
// with readings straddling the rail, occasional wild readings).
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
  // The rail probe: where robot 1's first sensor's latent reading, (1 - g (gamma I / d)^2) 4095 -
  // ambient, is 0 at the brightest intensity, to 0.1 mm as the lamp would be placed and measured.
  const double brightest = truth.intensities.empty() ? 0.0 : *std::max_element(truth.intensities.begin(), truth.intensities.end());
  const double gamma_1 = truth.gamma_m * (truth.robot_gamma_scale.empty() ? 1.0 : truth.robot_gamma_scale[0]);
  const double rail_d = std::round(gamma_1 * brightest * std::sqrt(truth.sensor_gain[0] / (1.0 - truth.ambient_raw / s::kProximityFullScale_raw)) * 1e4) / 1e4;
  for (std::size_t r = 0; r < truth.robot_gamma_scale.size(); ++r) {
    const double gamma = truth.gamma_m * truth.robot_gamma_scale[r];
    for (std::size_t k = 0; k < truth.intensities.size(); ++k) {
      const double intensity = truth.intensities[k];
      Gaussian noise(seed + 2000 + k + 100 * r);
      WildReadings wild(seed + 2500 + k + 100 * r, truth.wild_fraction);
      logs::LogWriter w({"distance_m", "intensity", "sensor", "value"});
      w.comment("Synthetic log recorded by epuck2-fit's virtual robot (see README.md); not a real robot.");
      w.metadata("robot", robot_id(r));
      w.metadata("seed", std::to_string(seed));
      auto record = [&](double d, int readings) {
        for (std::size_t j = 0; j < truth.sensors.size(); ++j) {
          // Eq. 2 with the sensor's own gain on the light term, then stray light and noise.
          const double sum = truth.sensor_gain[j] * s::light_contribution(gamma, intensity, d);
          for (int i = 0; i < readings; ++i) {
            const double v = (1.0 - sum) * s::kProximityFullScale_raw - truth.ambient_raw + noise() * truth.noise_raw;
            double raw = whole_count(v, s::kProximityFullScale_raw);
            double wild_raw;
            if (wild.next(0.0, s::kProximityFullScale_raw, true, &wild_raw)) raw = wild_raw;
            w.row({d, intensity, static_cast<double>(truth.sensors[j]), raw});
          }
        }
      };
      for (double d : truth.distances_m) record(d, truth.readings);
      if (truth.rail_readings > 0 && intensity == brightest) record(rail_d, truth.rail_readings);
      char name[96];
      if (r == 0) std::snprintf(name, sizeof name, "light_intensity_%.2f.csv", intensity);
      else std::snprintf(name, sizeof name, "light_intensity_%.2f_%s.csv", intensity, robot_id(r).c_str());
      files.push_back({name, w.str()});
    }
  }
  return files;
}

std::vector<GeneratedFile> light_reference_logs(std::uint64_t seed) { return light_logs(LightTruth{}, seed); }

}  // namespace epuck2::virtual_robot
