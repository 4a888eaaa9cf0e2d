// epuck2-fit light LOGS...: gamma of paper Eq. 2, reading/4095 = 1 - (gamma I / d)^2, fitted to the
// unsaturated readings (paper section 4.1.2), beside the plug-in's gamma = 1/13.333 = 0.075.
#include <cstdio>

#include "epuck2/calibrate/sensors.hpp"
#include "epuck2/plot/sensor_figures.hpp"
#include "sensor_support.hpp"

namespace epuck2::app {

namespace {

namespace s = models::sensors;

void print_light_report(const calibrate::LightFit& f) {
  std::printf("Ambient light sensor, paper Eq. 2: reading/4095 = 1 - (gamma I / d)^2\n");
  std::printf("%zu readings: %zu enter the fits (%zu of them on a rail, 0 = saturated or 4095 = dark: censored), %zu left out "
              "(no light in range)\n\n",
              f.readings, f.observations.size(), f.censored, f.left_out.size());
  std::printf("All sensors together:\n");
  app::sensors::print_parameter(f.gamma, "gamma", "m");
  app::sensors::print_handling(f.gamma, "(reading/4095)");
  for (std::size_t i = 0; i < f.sensors.size(); ++i) {
    std::printf("Sensor %d alone:\n", f.sensors[i]);
    if (!f.gamma_per_sensor[i].usable) {
      std::printf("  no fit: %s\n", f.gamma_per_sensor[i].message.c_str());
      continue;
    }
    app::sensors::print_parameter(f.gamma_per_sensor[i], "gamma", "m");
    app::sensors::print_handling(f.gamma_per_sensor[i], "(reading/4095)");
  }
  std::printf("Plug-in: gamma = 1/13.3333 = 0.075 m, MSE on the readings inside the rails %.3e (reading/4095)²\n", f.plugin_mse);
  app::sensors::print_noise_and_warnings({f.noise}, f.warnings);
}

nlohmann::json light_json(const std::vector<logs::Log>& logs, const app::sensors::SensorOptions& o, calibrate::LightFit* keep) {
  calibrate::LightFit f = calibrate::fit_light(logs, o.fit_options());
  app::sensors::require_usable(f.gamma, "light fit");
  app::sensors::require_fitting(f.gamma, "light fit", o, f.warnings);
  nlohmann::json j = app::sensors::skeleton("light", logs);
  j["units"] = {{"gamma", "m"}, {"range_m", "m"}, {"mse", "(reading / 4095)^2"}, {"rss", "(reading / 4095)^2"}};
  j["unit_notes"] = {{"gamma", "metres per unit of the light's intensity I: Eq. 2's gamma I / d is a ratio"},
                     {"range_m", "the sensor's range, held"}};
  app::sensors::add_parameters(j, f.gamma, "", "gamma", "(reading / 4095)");
  j["parameters"]["range_m"] = s::kPluginLight.range_m;
  j["std_errors"]["range_m"] = 0.0;
  app::sensors::add_rounded(j, "range_m", s::kPluginLight.range_m, 0.0, "the sensor's range, held: not fitted");
  j["mse"] = f.gamma.mse;
  j["observations"] = f.gamma.observations;
  j["readings"] = f.readings;
  nlohmann::json per = nlohmann::json::array();
  for (std::size_t i = 0; i < f.sensors.size(); ++i) {
    const auto& r = f.gamma_per_sensor[i];
    if (!r.usable) {  // e.g. too few readings of this sensor: said, not written as a null gamma
      per.push_back({{"sensor", f.sensors[i]}, {"usable", false}, {"why", r.message}});
      continue;
    }
    nlohmann::json one = {{"sensor", f.sensors[i]}, {"usable", r.usable}, {"gamma", app::sensors::number(r.value("gamma"))},
                          {"std_error", app::sensors::number(r.std_error("gamma"))}, {"mse", app::sensors::number(r.mse)},
                          {"rounded", fit::format_uncertain(r.value("gamma"), r.std_error("gamma"), "m",
                                                            app::sensors::std_error_reason(r, "gamma"))},
                          {"fit", app::sensors::fit_details(r, "(reading / 4095)")}};
    if (!std::isfinite(r.std_error("gamma"))) one["std_error_why"] = r.usable ? app::sensors::std_error_reason(r, "gamma") : r.message;
    per.push_back(one);
  }
  j["per_sensor"] = per;
  j["reference_mse"] = {{"plugin", f.plugin_mse}};
  std::vector<calibrate::LeftOut> left_out = f.left_out;
  app::sensors::add_left_out(j, left_out);
  app::sensors::add_noise(j, {f.noise});
  app::sensors::add_warnings(j, f.warnings);
  if (keep != nullptr) *keep = std::move(f);
  return j;
}

}  // namespace

void setup_light(CLI::App& app, Action& action) {
  app::sensors::add_sensor_command<calibrate::LightFit>(
      app, action,
      {"light", logs::Kind::light, "Calibrate the ambient light sensors: gamma of Eq. 2", "Light",
       "value: 4095 = dark, 0 = saturated; both are left out of the fit."},
      light_json, print_light_report, plot::light_figure);
}

}  // namespace epuck2::app
