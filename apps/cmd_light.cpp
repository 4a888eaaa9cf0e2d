// epuck2-fit light LOGS...: gamma of paper Eq. 2, reading/4095 = 1 - (gamma I / d)^2, fitted to the
// unsaturated readings (paper section 4.1.2), beside the plug-in's gamma = 1/13.333 = 0.075.
#include <string>
#include <vector>

#include "epuck2/models/kind_facts.hpp"
#include "epuck2/calibrate/sensors.hpp"
#include "epuck2/plot/sensor_figures.hpp"
#include "sensor_support.hpp"

namespace epuck2::app {

namespace {

/// The fit, its checks (exit 1, or a warning under --accept-misfit), then its coefficient file.
nlohmann::json light_json(const std::vector<logs::Log>& logs, const app::sensors::SensorOptions& o, calibrate::LightFit* keep) {
  calibrate::LightFit f = calibrate::fit_light(logs, o.fit_options());
  app::sensors::require_usable(f.gamma, "light fit");
  app::sensors::require_fitting(f.gamma, "light fit", o, f.warnings);
  nlohmann::json j = calibrate::coefficient_json(f, logs);
  if (keep != nullptr) *keep = std::move(f);
  return j;
}

}  // namespace

void setup_light(CLI::App& app, Action& action) {
  app::sensors::add_sensor_command<calibrate::LightFit>(
      app, action,
      {"light", logs::Kind::light, "Calibrate the ambient light sensors: gamma of Eq. 2", "Light",
       "value: " + sensors::rail(models::kind_facts("light")->channels.front().high_rail) + " = dark, " +
           sensors::rail(models::kind_facts("light")->channels.front().low_rail) + " = saturated; both are left out of the fit."},
      light_json, plot::light_figure);
}

}  // namespace epuck2::app
