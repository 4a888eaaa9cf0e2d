// epuck2-fit camera LOGS...: the camera's horizontal field of view and image centre from where LEDs
// of known position appear in the 160x120 image (pinhole with square pixels, as the plug-in's
// projection), and the paper's Table 4 method (alpha from a pixel offset at a known geometry).
#include <string>
#include <vector>

#include "epuck2/calibrate/sensors.hpp"
#include "epuck2/plot/sensor_figures.hpp"
#include "sensor_support.hpp"

namespace epuck2::app {

namespace {

/// The fit, its checks (exit 1, or a warning under --accept-misfit), then its coefficient file.
nlohmann::json camera_json(const std::vector<logs::Log>& logs, const app::sensors::SensorOptions& o, calibrate::CameraFit* keep) {
  calibrate::CameraFit f = calibrate::fit_camera(logs, o.fit_options());
  app::sensors::require_usable(f.result, "camera fit");
  app::sensors::require_fitting(f.result, "camera fit", o, f.warnings);
  nlohmann::json j = calibrate::coefficient_json(f, logs);
  if (keep != nullptr) *keep = std::move(f);
  return j;
}

}  // namespace

void setup_camera(CLI::App& app, Action& action) {
  app::sensors::add_sensor_command<calibrate::CameraFit>(
      app, action,
      {"camera", logs::Kind::camera, "Calibrate the camera: horizontal field of view and image centre", "Camera",
       "px 0..159 from the left, py 0..119 from the top; lateral_m > 0 to the left."},
      camera_json, plot::camera_figure);
}

}  // namespace epuck2::app
