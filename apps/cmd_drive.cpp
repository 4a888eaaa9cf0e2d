// epuck2-fit drive LOGS...: encoder steps per metre (steps against the commanded distance, paper
// section 4.1.5) and the ToF's scale and offset (ToF against the obstacle distance minus the
// travelled distance, section 4.1.4), with the wheel slip as a first-order lag of the body behind
// the wheels.
#include <string>
#include <vector>

#include "epuck2/logs/log.hpp"
#include "epuck2/logs/output.hpp"
#include "epuck2/models/kind_facts.hpp"
#include "epuck2/models/effects.hpp"
#include "epuck2/calibrate/sensors.hpp"
#include "epuck2/plot/sensor_figures.hpp"
#include "sensor_support.hpp"

namespace epuck2::app {

namespace {

/// The fit, its checks (exit 1, or a warning under --accept-misfit), then its coefficient file.
nlohmann::json drive_json(const std::vector<logs::Log>& logs, const app::sensors::SensorOptions& o, calibrate::DriveFit* keep) {
  calibrate::DriveFit f = calibrate::fit_drive(logs, o.fit_options());
  app::sensors::require_usable(f.steps, "encoder fit");
  app::sensors::require_usable(f.tof, "ToF fit");
  app::sensors::require_fitting(f.steps, "encoder fit", o, f.warnings);
  app::sensors::require_fitting(f.tof, "ToF fit", o, f.warnings);
  nlohmann::json j = calibrate::coefficient_json(f, logs);
  if (keep != nullptr) *keep = std::move(f);
  return j;
}

}  // namespace

void setup_drive(CLI::App& app, Action& action) {
  app::sensors::add_sensor_command<calibrate::DriveFit>(
      app, action,
      {"drive", logs::Kind::drive, "Calibrate encoders and ToF from straight runs towards/away from an obstacle", "Drive",
       "Required metadata: '# obstacle_distance_m: D' (m, at time 0). tof_mm " +
           models::kind_facts("drive")->channels.front().rails_text() + ", or >= " +
           logs::format_number(logs::kTofOutOfRangeCode_mm) +
           " (the VL53L0X's no target in range: the fit censors it as beyond the 2000 mm rail, as a reading "
           "on that rail; one where the fitted curve puts the obstacle in view is a dropout, left out and listed)."},
      drive_json, plot::drive_figure);
}

}  // namespace epuck2::app
