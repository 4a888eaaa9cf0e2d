// The ground calibration (gain and offset per sensor) as its two outputs: the human report and the
// coefficient file (docs/coefficient-files.md), from the fit's result (calibrate::fit_ground).
#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "epuck2/calibrate/report_json.hpp"
#include "epuck2/calibrate/report_text.hpp"
#include "epuck2/calibrate/sensor_reports.hpp"
#include "epuck2/calibrate/sensors.hpp"
#include "epuck2/models/kind_facts.hpp"

namespace epuck2::calibrate {

std::string report_text(const GroundFit& f) {
  Text out;
  const models::KindFacts& ground = *models::kind_facts("ground");
  out("Ground sensors: reading = offset + gain * grey (grey 0 = black, 1 = white)\n");
  out("%zu readings, %zu on the %g/%g rails (censored)\n\n", f.readings, f.censored, ground.channels.front().low_rail,
      ground.channels.front().high_rail);
  out("%-11s %-26s %-26s %10s %12s\n", "sensor", "gain (counts)", "offset (counts)", "MSE", "plug-in MSE");
  for (std::size_t k = 0; k < f.sensors.size(); ++k) {
    const auto& r = f.sensors[k];
    out("%-11s %-26s %-26s %10.3f %12.1f\n", ground.sensor_name(k).c_str(),
        fit::format_uncertain(r.value("gain"), r.std_error("gain"), "", std_error_reason(r, "gain")).c_str(),
        fit::format_uncertain(r.value("offset"), r.std_error("offset"), "", std_error_reason(r, "offset")).c_str(),
        r.mse, f.plugin_mse[k]);
  }
  out("(MSE in counts²)\n");
  for (std::size_t k = 0; k < f.sensors.size(); ++k) {
    out("\nSensor %s:\n", ground.sensor_name(k).c_str());
    write_parameter(out, f.sensors[k], "gain", "counts");
    write_parameter(out, f.sensors[k], "offset", "counts");
    write_handling(out, f.sensors[k], "counts");
  }
  out("\nPlug-in: gain 1023 (grey 0..255 * 4.011764706), offset 0: pooled MSE %.1f counts² on the readings inside the "
      "rails (the fit's: %.3f counts²)\n",
      f.plugin_mse_pooled, f.mse);
  write_noise_sections(out, {f.noise});
  return out.str();
}

models::sensors::GroundModel model_of(const GroundFit& f) {
  models::sensors::GroundModel m;
  for (std::size_t k = 0; k < f.sensors.size(); ++k) m.sensors[k] = {f.sensors[k].value("gain"), f.sensors[k].value("offset")};
  m.noise_sd_raw = per_sensor_noise<models::sensors::kGroundCount>(f.noise);
  return m;
}

std::vector<fit::ParameterEstimate> robot_estimates(const GroundFit& f) {
  std::vector<fit::ParameterEstimate> out;
  for (std::size_t k = 0; k < f.sensors.size(); ++k)
    for (auto& p : named_estimates(f.sensors[k], "", "[" + std::to_string(k) + "]")) out.push_back(p);
  return out;
}

nlohmann::json coefficient_json(const GroundFit& f, const std::vector<logs::Log>& logs) {
  nlohmann::json j = skeleton(owned_model([&] { return coefficients::calibration_model_json(model_of(f), measured_noise({f.noise})); }), logs);
  j["units"] = {{"gain", "counts"}, {"offset", "counts"}, {"mse", "counts^2"}, {"rss", "counts^2"}};
  j["unit_notes"] = {{"gain", "raw counts from black to white (grey 0 to 1)"}, {"offset", "raw counts over black"}};
  nlohmann::json correlations = nlohmann::json::array();
  nlohmann::json gain_se = nlohmann::json::array(), offset_se = nlohmann::json::array(), mse = nlohmann::json::array(),
                 n = nlohmann::json::array();
  std::size_t observations = 0;
  for (std::size_t k = 0; k < f.sensors.size(); ++k) {
    const auto& r = f.sensors[k];
    gain_se.push_back(json_number(r.std_error("gain")));
    offset_se.push_back(json_number(r.std_error("offset")));
    for (const char* name : {"gain", "offset"})
      if (!std::isfinite(r.std_error(name)))
        j["std_error_why"][std::string(name) + "[" + std::to_string(k) + "]"] = std_error_reason(r, name);
    mse.push_back(r.mse);
    n.push_back(r.observations);
    observations += r.observations;
    add_aggregates(j, r, "sensor_" + std::to_string(k), "sensor_" + std::to_string(k) + ".", "counts^2");
    // Named as in `parameters`: gain[k], offset[k].
    const std::string index = "[" + std::to_string(k) + "]";
    for (const auto& c : fit::correlations(r)) correlations.push_back({{"a", c.a + index}, {"b", c.b + index}, {"r", c.r}});
    for (const char* name : {"gain", "offset"})
      add_rounded(j, name + index, r.value(name), r.std_error(name), std_error_reason(r, name));
  }
  j["correlations"] = correlations;
  j["std_errors"]["gain"] = gain_se;
  j["std_errors"]["offset"] = offset_se;
  j["mse"] = f.mse;
  j["mse_per_sensor"] = mse;
  j["observations"] = observations;
  j["observations_per_sensor"] = n;
  j["readings"] = f.readings;
  j["model"] = "value_raw = offset + gain * grey, grey in [0, 1], sensors 0 right, 1 centre, 2 left";
  j["reference_mse"] = {{"plugin", f.plugin_mse}, {"plugin_pooled", f.plugin_mse_pooled}};
  add_noise(j, {f.noise});
  add_warnings(j, f.warnings);
  return j;
}
}  // namespace epuck2::calibrate
