// epuck2-fit ground LOGS...: per ground sensor, reading = offset + gain grey (grey 0 = black ..
// 1 = white), beside the plug-in's offset 0 and gain 1023 (paper section 4.1.3).
#include <cstdio>

#include "epuck2/calibrate/sensors.hpp"
#include "epuck2/plot/sensor_figures.hpp"
#include "sensor_support.hpp"

namespace epuck2::app {

namespace {

void print_ground_report(const calibrate::GroundFit& f) {
  std::printf("Ground sensors: reading = offset + gain * grey (grey 0 = black, 1 = white)\n");
  std::printf("%zu readings, %zu on the 0/1023 rails (censored)\n\n", f.readings, f.censored);
  std::printf("%-11s %-26s %-26s %10s %12s\n", "sensor", "gain (counts)", "offset (counts)", "MSE", "plug-in MSE");
  for (std::size_t k = 0; k < f.sensors.size(); ++k) {
    const auto& r = f.sensors[k];
    std::printf("%-11s %-26s %-26s %10.3f %12.1f\n", calibrate::kGroundSensorNames[k],
                fit::format_uncertain(r.value("gain"), r.std_error("gain"), "", app::sensors::std_error_reason(r, "gain")).c_str(),
                fit::format_uncertain(r.value("offset"), r.std_error("offset"), "", app::sensors::std_error_reason(r, "offset")).c_str(),
                r.mse, f.plugin_mse[k]);
  }
  std::printf("(MSE in counts²)\n");
  for (std::size_t k = 0; k < f.sensors.size(); ++k) {
    std::printf("\nSensor %s:\n", calibrate::kGroundSensorNames[k]);
    app::sensors::print_parameter(f.sensors[k], "gain", "counts");
    app::sensors::print_parameter(f.sensors[k], "offset", "counts");
    app::sensors::print_handling(f.sensors[k], "counts");
  }
  std::printf("\nPlug-in: gain 1023 (grey 0..255 * 4.011764706), offset 0. Pooled MSE %.3f counts²\n", f.mse);
  app::sensors::print_noise_and_warnings({f.noise}, f.warnings);
}

nlohmann::json ground_json(const std::vector<logs::Log>& logs, const app::sensors::SensorOptions& o, calibrate::GroundFit* keep) {
  calibrate::GroundFit f = calibrate::fit_ground(logs, o.fit_options());
  nlohmann::json j = app::sensors::skeleton("ground", logs);
  j["units"] = {{"gain", "counts"}, {"offset", "counts"}, {"mse", "counts^2"}, {"rss", "counts^2"}};
  j["unit_notes"] = {{"gain", "raw counts from black to white (grey 0 to 1)"}, {"offset", "raw counts over black"}};
  nlohmann::json correlations = nlohmann::json::array();
  nlohmann::json gain = nlohmann::json::array(), offset = nlohmann::json::array(), gain_se = nlohmann::json::array(),
                 offset_se = nlohmann::json::array(), mse = nlohmann::json::array(), n = nlohmann::json::array();
  std::size_t observations = 0;
  for (std::size_t k = 0; k < f.sensors.size(); ++k) {
    const auto& r = f.sensors[k];
    app::sensors::require_usable(r, std::string("ground sensor ") + calibrate::kGroundSensorNames[k]);
    app::sensors::require_fitting(r, std::string("ground sensor ") + calibrate::kGroundSensorNames[k], o, f.warnings);
    gain.push_back(r.value("gain"));
    offset.push_back(r.value("offset"));
    gain_se.push_back(app::sensors::number(r.std_error("gain")));
    offset_se.push_back(app::sensors::number(r.std_error("offset")));
    for (const char* name : {"gain", "offset"})
      if (!std::isfinite(r.std_error(name)))
        j["std_error_why"][std::string(name) + "[" + std::to_string(k) + "]"] = app::sensors::std_error_reason(r, name);
    mse.push_back(r.mse);
    n.push_back(r.observations);
    observations += r.observations;
    app::sensors::add_aggregates(j, r, "sensor_" + std::to_string(k), "sensor_" + std::to_string(k) + ".", "counts");
    // Named as in `parameters`: gain[k], offset[k].
    const std::string index = "[" + std::to_string(k) + "]";
    for (const auto& c : fit::correlations(r)) correlations.push_back({{"a", c.a + index}, {"b", c.b + index}, {"r", c.r}});
    for (const char* name : {"gain", "offset"})
      app::sensors::add_rounded(j, name + index, r.value(name), r.std_error(name), app::sensors::std_error_reason(r, name));
  }
  j["correlations"] = correlations;
  j["parameters"]["gain"] = gain;
  j["parameters"]["offset"] = offset;
  j["std_errors"]["gain"] = gain_se;
  j["std_errors"]["offset"] = offset_se;
  j["mse"] = f.mse;
  j["mse_per_sensor"] = mse;
  j["observations"] = observations;
  j["observations_per_sensor"] = n;
  j["readings"] = f.readings;
  j["model"] = "value_raw = offset + gain * grey, grey in [0, 1], sensors 0 right, 1 centre, 2 left";
  j["reference_mse"] = {{"plugin", f.plugin_mse}};
  app::sensors::add_noise(j, {f.noise});
  app::sensors::add_warnings(j, f.warnings);
  if (keep != nullptr) *keep = std::move(f);
  return j;
}

}  // namespace

void setup_ground(CLI::App& app, Action& action) {
  app::sensors::add_sensor_command<calibrate::GroundFit>(
      app, action,
      {"ground", logs::Kind::ground, "Calibrate the ground sensors: gain and offset per sensor", "Ground",
       "grey: 0 = black, 1 = white; sensor 0 right, 1 centre, 2 left; value 0..1023."},
      ground_json, print_ground_report, plot::ground_figure);
}

}  // namespace epuck2::app
