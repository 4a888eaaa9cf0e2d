// The light fit (see epuck2/calibrate/sensors.hpp; the shared conventions: proximity_fit.cpp).
#include <algorithm>
#include <cmath>
#include <fstream>
#include <limits>
#include <map>
#include <nlohmann/json.hpp>
#include <numeric>
#include <sstream>
#include <stdexcept>
#include <tuple>

#include "epuck2/fit/replicates.hpp"
#include "epuck2/calibrate/sensors.hpp"
#include "epuck2/models/effects.hpp"
#include "epuck2/models/saturation.hpp"
#include "epuck2/logs/json_location.hpp"
#include "sensor_fit_common.hpp"

namespace epuck2::calibrate {

using namespace epuck2::fit;  // the engine (lib/fit)
using namespace sensor_fit_detail;  // the sensor fits' shared helpers

namespace s = models::sensors;

namespace {

// No saturation on that side (models::saturate).
constexpr double kNoSaturation = std::numeric_limits<double>::infinity();

}  // namespace

namespace {
// Eq. 2 for one light: y = 1 - g (gamma I / d)^2 over the observations' x = I / d (per metre),
// saturated at 0 before the noise (a phototransistor in bright light reads 0 plus its noise, not
// the -4700 counts of the unclamped curve; lib/models saturation.hpp). The register's rail at 0 is
// the Tobit censoring of fit_robust: together, the mean of a reading is
// E[clamp(clamp(model) + noise)].
struct LightCurve {
  std::vector<double> intensity_per_m;
  template <typename T>
  bool operator()(const T* gamma_m, T* out) const {
    for (std::size_t i = 0; i < intensity_per_m.size(); ++i)
      out[i] = models::saturate(s::light_response(gamma_m[0], intensity_per_m[i], 1.0), 0.0, kNoSaturation);
    return true;
  }
};

RobustFit fit_gamma(const std::vector<LightObservation>& obs_in, const SensorFitOptions& options, int sensor) {
  const double full = s::kProximityFullScale_raw;
  std::vector<double> x;
  std::vector<Observation> obs;
  std::map<std::tuple<int, double, double>, int> groups;
  for (const LightObservation& o : obs_in) {
    if (sensor >= 0 && o.sensor != sensor) continue;
    x.push_back(o.intensity / o.distance_m);
    const auto key = std::make_tuple(o.sensor, o.distance_m, o.intensity);
    const int group = groups.emplace(key, static_cast<int>(groups.size())).first->second;
    obs.push_back({std::clamp(o.value_raw / full, 0.0, 1.0), fit::censoring_at(o.value_raw, 0, full), o.where, group, o.robot});
  }
  const double inf = std::numeric_limits<double>::infinity();
  return fit_robust(LightCurve{x}, obs, {{"gamma", s::kPluginLight.gamma_m, s::kPluginLight.gamma_m, 1e-9, inf}},
                    robust_options(options, kQuantisationSd / full));
}
}  // namespace

LightFit fit_light(const std::vector<logs::Log>& logs, const SensorFitOptions& options) {
  LightFit out;
  std::map<int, bool> seen;
  for (const logs::Log& log : logs) {
    const auto& d = log.col("distance_m");
    const auto& in = log.col("intensity");
    const auto& sen = log.col("sensor");
    const auto& v = log.col("value");
    out.readings += log.rows();
    const int robot = robot_index(out.robot_names, log.robot);
    for (std::size_t i = 0; i < log.rows(); ++i) {
      // A light out of range or of no intensity leaves the reading dark whatever gamma is.
      if (!(d[i] > 0) || d[i] > s::kPluginLight.range_m) {
        out.left_out.push_back({where(log, i), "light beyond the sensor's range (0.5 m)"});
        continue;
      }
      if (!(in[i] > 0)) {
        out.left_out.push_back({where(log, i), "no light (intensity 0)"});
        continue;
      }
      const int sensor = static_cast<int>(sen[i]);
      seen[sensor] = true;
      if (v[i] <= 0 || v[i] >= s::kProximityFullScale_raw) ++out.censored;
      out.observations.push_back({d[i], in[i], sensor, v[i], where(log, i), robot});
    }
  }
  out.gamma = fit_gamma(out.observations, options, -1);
  collect(out.warnings, "pooled gamma: ", out.gamma.warnings);
  for (const auto& [sensor, yes] : seen) {
    (void)yes;
    out.sensors.push_back(sensor);
    out.gamma_per_sensor.push_back(fit_gamma(out.observations, options, sensor));
    collect(out.warnings, "sensor " + std::to_string(sensor) + ": ", out.gamma_per_sensor.back().warnings);
  }
  // The plug-in's MSE as the plug-in reads: 1 - (0.075 I / d)^2 clamped to [0, 1] (Eq. 2, the
  // reading clamped to the register's 0..4095), on the readings inside the rails as the fit's. The
  // unclamped curve is thousands of counts below 0 in bright light, where the plug-in reads 0.
  std::vector<double> r;
  for (const LightObservation& o : out.observations)
    if (o.value_raw > 0 && o.value_raw < s::kProximityFullScale_raw)
      r.push_back(o.value_raw / s::kProximityFullScale_raw -
                  std::clamp(s::light_response(s::kPluginLight.gamma_m, o.intensity, o.distance_m), 0.0, 1.0));
  out.plugin_mse = mse_of(r);

  // The reading noise: the replicates of each log, sensor, distance and intensity (a light out of
  // range or off included: the sensor's dark reading is a reading too).
  std::vector<double> nv;
  std::vector<int> ng, ns;
  std::vector<bool> nr;
  Groups<std::tuple<std::size_t, int, double, double>> groups;
  for (std::size_t l = 0; l < logs.size(); ++l) {
    const auto& d = logs[l].col("distance_m");
    const auto& in = logs[l].col("intensity");
    const auto& v = logs[l].col("value");
    for (std::size_t i = 0; i < logs[l].rows(); ++i) {
      const int sensor = sensor_of(logs[l], i);
      nv.push_back(v[i]);
      ng.push_back(groups.of({l, sensor, d[i], in[i]}));
      ns.push_back(sensor);
      nr.push_back(v[i] <= 0 || v[i] >= s::kProximityFullScale_raw);
    }
  }
  out.noise = replicates_or_residuals(
      noise_from_replicates("light", "counts", kArgosNoiseScaleLight_counts, nv, ng, nr, ns, s::kProximityCount,
                            kQuantisationSd),
      noise_from_residuals("light", "counts", kArgosNoiseScaleLight_counts, out.gamma, s::kProximityFullScale_raw,
                           s::kProximityCount));
  return out;
}

}  // namespace epuck2::calibrate
