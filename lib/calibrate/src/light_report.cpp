// The light calibration (gamma of Eq. 2) as its two outputs: the human report and the coefficient
// file (docs/coefficient-files.md), from the fit's result (calibrate::fit_light).
#include <cmath>
#include <cstdio>
#include <map>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "epuck2/coefficients/model_file.hpp"
#include "epuck2/models/kind_facts.hpp"
#include "epuck2/calibrate/report_json.hpp"
#include "epuck2/calibrate/report_text.hpp"
#include "epuck2/calibrate/sensor_reports.hpp"
#include "epuck2/calibrate/sensors.hpp"

namespace epuck2::calibrate {

namespace s = models::sensors;

std::string report_text(const LightFit& f) {
  Text out;
  out("Ambient light sensor, paper Eq. 2: reading/4095 = 1 - (gamma I / d)^2\n");
  const models::Channel& light = models::kind_facts("light")->channels.front();
  out("%zu readings: %zu enter the fits (%zu of them on a rail, %g = saturated or %g = dark: censored), %zu left out "
      "(no light in range)\n\n",
      f.readings, f.observations.size(), f.censored, light.low_rail, light.high_rail, f.left_out.size());
  out("All sensors together:\n");
  write_parameter(out, f.gamma, "gamma", "m");
  write_handling(out, f.gamma, "(reading/4095)");
  for (std::size_t i = 0; i < f.sensors.size(); ++i) {
    out("Sensor %d alone:\n", f.sensors[i]);
    if (!f.gamma_per_sensor[i].usable) {
      out("  no fit: %s\n", f.gamma_per_sensor[i].message.c_str());
      continue;
    }
    write_parameter(out, f.gamma_per_sensor[i], "gamma", "m");
    write_handling(out, f.gamma_per_sensor[i], "(reading/4095)");
  }
  out("Plug-in: gamma = 1/13.3333 = 0.075 m, its reading clamped to 0..4095, MSE on the readings inside the rails %.3e (reading/4095)²\n",
      f.plugin_mse);
  write_noise_sections(out, {f.noise});
  return out.str();
}

s::LightModel model_of(const LightFit& f) {
  s::LightModel m;
  m.base.gamma_m = f.gamma.value("gamma");
  m.base.range_m = s::kPluginLight.range_m;  // held
  m.noise_sd_raw = per_sensor_noise<s::kProximityCount>(f.noise);
  return m;
}

std::vector<fit::ParameterEstimate> robot_estimates(const LightFit& f) { return named_estimates(f.gamma); }

nlohmann::json coefficient_json(const LightFit& f, const std::vector<logs::Log>& logs) {
  nlohmann::json j = skeleton(owned_model([&] { return coefficients::calibration_model_json(model_of(f), measured_noise({f.noise})); }), logs);
  j["units"] = {{"gamma", "m"}, {"range_m", "m"}, {"mse", "(reading / 4095)^2"}, {"rss", "(reading / 4095)^2"}};
  j["unit_notes"] = {{"gamma", "metres per unit of the light's intensity I: Eq. 2's gamma I / d is a ratio"},
                     {"range_m", "the sensor's range, held"}};
  add_estimates(j, f.gamma, "", "gamma", "(reading / 4095)^2");
  j["std_errors"]["range_m"] = 0.0;
  add_rounded(j, "range_m", s::kPluginLight.range_m, 0.0, "the sensor's range, held: not fitted");
  j["mse"] = f.gamma.mse;
  j["observations"] = f.gamma.observations;
  j["readings"] = f.readings;
  // Each sensor's own gamma as the light model holds it (LightModel::sensor_gamma_m), written by
  // lib/coefficients' writer, which refuses what its reader would; beside it, what its fit did.
  s::LightModel model;
  for (std::size_t i = 0; i < f.sensors.size(); ++i)
    if (f.gamma_per_sensor[i].usable) model.sensor_gamma_m.at(static_cast<std::size_t>(f.sensors[i])) = f.gamma_per_sensor[i].value("gamma");
  std::map<int, nlohmann::json> written;  // sensor -> {"sensor", "gamma"}
  for (const nlohmann::json& e : coefficients::model_to_json(model).value("per_sensor", nlohmann::json::array()))
    written[e.at("sensor").get<int>()] = e;
  nlohmann::json per = nlohmann::json::array();
  for (std::size_t i = 0; i < f.sensors.size(); ++i) {
    const auto& r = f.gamma_per_sensor[i];
    if (!r.usable) {  // e.g. too few readings of this sensor: said, not written as a null gamma
      per.push_back({{"sensor", f.sensors[i]}, {"usable", false}, {"why", r.message}});
      continue;
    }
    nlohmann::json one = written.at(f.sensors[i]);
    one.update({{"usable", r.usable}, {"std_error", json_number(r.std_error("gamma"))}, {"mse", json_number(r.mse)},
                {"rounded", fit::format_uncertain(r.value("gamma"), r.std_error("gamma"), "m", std_error_reason(r, "gamma"))},
                {"fit", fit_details(r, "(reading / 4095)^2")}});
    if (!std::isfinite(r.std_error("gamma"))) one["std_error_why"] = r.usable ? std_error_reason(r, "gamma") : r.message;
    per.push_back(one);
  }
  j["per_sensor"] = per;
  j["reference_mse"] = {{"plugin", f.plugin_mse}};
  std::vector<LeftOut> left_out = f.left_out;
  add_left_out(j, left_out);
  add_noise(j, {f.noise});
  add_warnings(j, f.warnings);
  return j;
}
}  // namespace epuck2::calibrate
