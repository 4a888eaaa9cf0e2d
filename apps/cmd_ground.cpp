// epuck2-fit ground LOGS...: per ground sensor, reading = offset + gain grey (grey 0 = black ..
// 1 = white), beside the plug-in's offset 0 and gain 1023 (paper section 4.1.3).
#include <string>
#include <vector>

#include "epuck2/calibrate/sensors.hpp"
#include "epuck2/models/kind_facts.hpp"
#include "epuck2/plot/sensor_figures.hpp"
#include "sensor_support.hpp"

namespace epuck2::app {

namespace {

/// The fit, its checks (exit 1, or a warning under --accept-misfit), then its coefficient file.
nlohmann::json ground_json(const std::vector<logs::Log>& logs, const app::sensors::SensorOptions& o, calibrate::GroundFit* keep) {
  calibrate::GroundFit f = calibrate::fit_ground(logs, o.fit_options());
  for (std::size_t k = 0; k < f.sensors.size(); ++k) {
    const std::string what = "ground sensor " + models::kind_facts("ground")->sensor_name(k);
    app::sensors::require_usable(f.sensors[k], what);
    app::sensors::require_fitting(f.sensors[k], what, o, f.warnings);
  }
  nlohmann::json j = calibrate::coefficient_json(f, logs);
  if (keep != nullptr) *keep = std::move(f);
  return j;
}

}  // namespace

void setup_ground(CLI::App& app, Action& action) {
  app::sensors::add_sensor_command<calibrate::GroundFit>(
      app, action,
      {"ground", logs::Kind::ground, "Calibrate the ground sensors: gain and offset per sensor", "Ground",
       "grey: 0 = black, 1 = white; sensor 0 right, 1 centre, 2 left; value " +
           models::kind_facts("ground")->channels.front().rails_text() + "."},
      ground_json, plot::ground_figure);
}

}  // namespace epuck2::app
