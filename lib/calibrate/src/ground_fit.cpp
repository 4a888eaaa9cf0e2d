// The ground fit (see epuck2/calibrate/sensors.hpp; the shared conventions: proximity_fit.cpp).
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
struct GroundLine {
  std::vector<double> grey;
  template <typename T>
  bool operator()(const T* p, T* out) const {
    for (std::size_t i = 0; i < grey.size(); ++i) out[i] = s::ground_response(p[0], p[1], grey[i]);
    return true;
  }
};
}  // namespace

GroundFit fit_ground(const std::vector<logs::Log>& logs, const SensorFitOptions& options) {
  GroundFit out;
  const double full = s::kGroundFullScale_raw;
  std::array<std::vector<Observation>, s::kGroundCount> obs;
  for (const logs::Log& log : logs) {
    const auto& g = log.col("grey");
    const auto& sen = log.col("sensor");
    const auto& v = log.col("value");
    out.readings += log.rows();
    const int robot = robot_index(out.robot_names, log.robot);
    for (std::size_t i = 0; i < log.rows(); ++i) {
      const auto k = static_cast<std::size_t>(sen[i]);
      const Censoring c = fit::censoring_at(v[i], 0, full);
      if (c != Censoring::none) ++out.censored;
      out.grey[k].push_back(g[i]);
      out.value_raw[k].push_back(v[i]);
      out.robot[k].push_back(robot);
      // Replicates: the same grey level (to a tenth of a percent).
      obs[k].push_back({v[i], c, where(log, i), static_cast<int>(std::lround(g[i] * 1000)), robot});
    }
  }
  double rss = 0, plugin_rss = 0;
  std::size_t n = 0, plugin_n = 0;
  const double inf = std::numeric_limits<double>::infinity();
  for (std::size_t k = 0; k < static_cast<std::size_t>(s::kGroundCount); ++k) {
    if (obs[k].empty()) {
      out.sensors[k].message = "no readings of this sensor";
      continue;
    }
    // Gains positive (white reflects more than black); the offset is what black reads.
    out.sensors[k] = fit_robust(GroundLine{out.grey[k]}, obs[k],
                                {{"gain", s::kPluginGround.gain_raw, s::kPluginGround.gain_raw, 1e-9, inf},
                                 {"offset", s::kPluginGround.offset_raw, s::kPluginGround.offset_raw, -inf, inf}},
                                robust_options(options, kQuantisationSd));
    collect(out.warnings, "sensor " + std::to_string(k) + ": ", out.sensors[k].warnings);
    if (out.sensors[k].usable) {
      rss += out.sensors[k].rss;
      n += out.sensors[k].exact;
    }
    std::vector<double> r;
    for (std::size_t i = 0; i < out.grey[k].size(); ++i)
      if (obs[k][i].censoring == Censoring::none)
        r.push_back(out.value_raw[k][i] - s::ground_response(s::kPluginGround.gain_raw, s::kPluginGround.offset_raw, out.grey[k][i]));
    out.plugin_mse[k] = mse_of(r);
    for (const double e : r) plugin_rss += e * e;
    plugin_n += r.size();
  }
  out.mse = n ? rss / static_cast<double>(n) : 0.0;
  out.plugin_mse_pooled = plugin_n ? plugin_rss / static_cast<double>(plugin_n) : 0.0;

  // The reading noise: the replicates of each log, sensor and grey level (to a tenth of a percent).
  std::vector<double> nv;
  std::vector<int> ng, ns;
  std::vector<bool> nr;
  Groups<std::tuple<std::size_t, int, long>> groups;
  for (std::size_t l = 0; l < logs.size(); ++l) {
    const auto& g = logs[l].col("grey");
    const auto& v = logs[l].col("value");
    for (std::size_t i = 0; i < logs[l].rows(); ++i) {
      const int sensor = sensor_of(logs[l], i);
      nv.push_back(v[i]);
      ng.push_back(groups.of({l, sensor, std::lround(g[i] * 1000)}));
      ns.push_back(sensor);
      nr.push_back(v[i] <= 0 || v[i] >= full);
    }
  }
  // Without replicates: the three sensors' fits' residuals, pooled.
  RobustFit pooled;
  pooled.usable = n > 0;
  pooled.noise_sd = n ? std::sqrt(rss / static_cast<double>(n)) : 0.0;
  pooled.observations = n;
  out.noise = replicates_or_residuals(
      noise_from_replicates("ground", "counts", kArgosNoiseScaleGround_counts, nv, ng, nr, ns, s::kGroundCount,
                            kQuantisationSd),
      noise_from_residuals("ground", "counts", kArgosNoiseScaleGround_counts, pooled, 1.0, s::kGroundCount));
  return out;
}

}  // namespace epuck2::calibrate
