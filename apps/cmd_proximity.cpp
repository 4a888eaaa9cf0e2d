// epuck2-fit proximity LOGS...: paper Eq. 1's quadratic fitted to the per-distance maxima and
// means of the readings (normalised by 4095, d <= 0.05 m), beside the plug-in's and the E-Puck
// (v1) polynomials (paper section 4.1.1, Fig. 4c).
#include <string>
#include <vector>

#include "epuck2/models/kind_facts.hpp"
#include "epuck2/calibrate/sensors.hpp"
#include "epuck2/plot/sensor_figures.hpp"
#include "sensor_support.hpp"

namespace epuck2::app {

namespace {

/// The fit, its checks (exit 1, or a warning under --accept-misfit), then its coefficient file.
nlohmann::json proximity_json(const std::vector<logs::Log>& logs, const app::sensors::SensorOptions& o, calibrate::ProximityFit* keep) {
  calibrate::ProximityFit f = calibrate::fit_proximity(logs, o.fit_options());
  app::sensors::require_usable(f.maxima, "proximity fit to the maxima");
  app::sensors::require_usable(f.means, "proximity fit to the means");
  app::sensors::require_fitting(f.maxima, "proximity fit to the maxima", o, f.warnings);
  app::sensors::require_fitting(f.means, "proximity fit to the means", o, f.warnings);
  nlohmann::json j = calibrate::coefficient_json(f, logs);
  if (keep != nullptr) *keep = std::move(f);
  return j;
}

}  // namespace

void setup_proximity(CLI::App& app, Action& action) {
  app::sensors::add_sensor_command<calibrate::ProximityFit>(
      app, action,
      {"proximity", logs::Kind::proximity, "Calibrate the proximity sensors: Eq. 1 fitted to the maxima and to the means", "Proximity",
       "Optional: angle_deg (incidence angle). value: " + sensors::rail(models::kind_facts("proximity")->channels.front().low_rail) +
           " = nothing detected, " + sensors::rail(models::kind_facts("proximity")->channels.front().high_rail) + " = touching."},
      proximity_json, plot::proximity_figure);
}

}  // namespace epuck2::app
