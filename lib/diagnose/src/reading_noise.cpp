#include "epuck2/diagnose/reading_noise.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <exception>

#include "epuck2/calibrate/sensors.hpp"
#include "epuck2/diagnose/diagnose.hpp"
#include "kind_table.hpp"

namespace epuck2::diagnose {

namespace {

/// Degrees of freedom (readings less groups) a replicate sd needs to be taken over the residuals':
/// its relative standard error is about 1 / sqrt(2 dof), 10 % at 50. Fewer (logs whose conditions
/// rarely repeat: proximity rows at many incidence angles) estimate the noise worse than the final
/// model's residuals do.
constexpr std::size_t kMinReplicateDof = 200;

void keep_if_replicates(std::map<std::string, calibrate::ReadingNoise>& out, const calibrate::ReadingNoise& n) {
  if (n.usable() && n.from == "replicates" && n.n >= n.groups + kMinReplicateDof) out[n.channel] = n;
}

/// The channel a report's residual sd belongs to: its kind's, or a drive channel's name.
std::string channel_of(logs::Kind kind, const std::string& name) {
  if (name == "tof_mm") return "tof";
  if (name == "steps") return "encoder";
  if (!name.empty()) return name;
  return std::string(logs::to_string(kind));
}

}  // namespace

std::map<std::string, calibrate::ReadingNoise> replicate_noise(const std::vector<logs::Log>& logs) {
  std::map<std::string, calibrate::ReadingNoise> out;
  if (logs.empty()) return out;
  // The calibration of these logs measures the replicates exactly as a calibration file's noise;
  // logs it cannot fit have no replicate noise to give (the residuals' is used).
  try {
    const detail::KindRow* row = detail::kind_row(logs.front().kind);
    if (row && row->replicate_noise) keep_if_replicates(out, row->replicate_noise(logs));
  } catch (const std::exception&) {
    out.clear();
  }
  return out;
}

double model_noise_sd(const std::map<std::string, calibrate::ReadingNoise>& replicates, const std::string& channel,
                      double residual_sd, int sensor, bool whole) {
  double sd = residual_sd;
  const auto it = replicates.find(channel);
  if (it != replicates.end()) {
    const calibrate::ReadingNoise& n = it->second;
    // The final residuals hold the noise and whatever misfit is left: the noise is at most their
    // sd. Replicates scattering more were not taken under the same conditions (a column the
    // calibration's groups do not hold varies within them: an angle, a temperature). The cap is
    // the pooled one: the pooled replicate sd against the pooled residual sd, and each sensor's
    // own replicate sd scaled by the same factor (a noisy sensor's sd is above the pooled
    // residuals' without any misfit: capping it there would cut its noise).
    const double cap = n.sd > 0 ? std::min(1.0, residual_sd / n.sd) : 1.0;
    sd = n.sd * cap;
    const auto k = static_cast<std::size_t>(sensor);
    if (sensor >= 0 && k < n.per_sensor_sd.size() && k < n.per_sensor_n.size() && n.per_sensor_n[k] > 0 &&
        std::isfinite(n.per_sensor_sd[k]))
      sd = n.per_sensor_sd[k] * cap;
  }
  return whole ? std::sqrt(std::max(0.0, sd * sd - 1.0 / 12.0)) : sd;
}

std::vector<std::string> noise_warnings(const Report& r, const std::map<std::string, calibrate::ReadingNoise>& replicates) {
  std::vector<std::string> out;
  std::vector<NamedValue> residual = r.channel_noise_sd;
  if (residual.empty()) residual.push_back({"", r.noise_sd, 0.0});
  for (const NamedValue& v : residual) {
    const std::string channel = channel_of(r.kind, v.name);
    const auto it = replicates.find(channel);
    if (it == replicates.end() || !(it->second.sd > 0)) continue;
    const double ratio = v.value / it->second.sd;
    if (!(ratio > kImplausibleNoiseRatio)) continue;
    char buf[512];
    std::snprintf(buf, sizeof buf,
                  "%s: the final model's residuals scatter %.3g %s, %.1f times what replicate readings scatter "
                  "(%.3g %s over %zu readings): the model leaves misfit that is not reading noise. The model's "
                  "noise is the replicates' (a simulation drawing %.3g %s would add the misfit as noise)",
                  channel.c_str(), v.value, it->second.unit.c_str(), ratio, it->second.sd, it->second.unit.c_str(),
                  it->second.n, v.value, it->second.unit.c_str());
    out.push_back(buf);
  }
  return out;
}

}  // namespace epuck2::diagnose
