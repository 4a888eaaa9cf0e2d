// epuck2-fit proximity LOGS...: paper Eq. 1's quadratic fitted to the per-distance maxima and
// means of the readings (normalised by 4095, d <= 0.05 m), beside the plug-in's and the E-Puck
// (v1) polynomials (paper section 4.1.1, Fig. 4c).
#include <cstdio>

#include "epuck2/calibrate/sensors.hpp"
#include "epuck2/plot/sensor_figures.hpp"
#include "sensor_support.hpp"

namespace epuck2::app {

namespace {

namespace s = models::sensors;

void print_proximity_report(const calibrate::ProximityFit& f) {
  std::printf("Proximity sensor, paper Eq. 1: v(d) = a d^2 + b d + c (normalised 0..1), d <= 0.05 m,\n"
              "held non-increasing with distance over [0, 0.05 m] (slopes at 0 and at 0.05 m bounded at 0)\n");
  std::printf("%zu readings at %zu distances; %zu on a rail (0 or 4095, censored); %zu left out\n\n", f.readings,
              f.points.size(), f.censored_readings, f.left_out.size());
  std::printf("%10s %8s %6s %8s %8s %8s  %s\n", "distance_m", "readings", "kept", "min", "mean", "max", "used");
  for (const auto& p : f.points)
    std::printf("%10.4f %8zu %6zu %8.4f %8.4f %8.4f%s  %s\n", p.distance_m, p.readings, p.kept, p.min, p.mean, p.max,
                p.max_censoring == fit::Censoring::at_or_above   ? "+"
                : p.max_censoring == fit::Censoring::at_or_below ? "-"
                                                                 : " ",
                p.used ? "yes" : ("no: " + p.excluded_why).c_str());
  std::printf("(+: on the 4095 rail, at least this; -: on the 0 rail, at most this; a distance not used: its readings as measured)\n");
  if (f.range.fitted && !f.range.lower_bound)
    std::printf("Range (where the readings stop being detected): %.1f ± %.1f mm, %s; Eq. 1 keeps its 50 mm domain\n",
                f.range.value_m * 1000, f.range.std_error_m * 1000, f.range.how.c_str());
  else if (f.range.fitted)
    std::printf("Range (where the readings stop being detected): %s; Eq. 1 keeps its 50 mm domain\n", f.range.how.c_str());
  std::size_t shown = 0;
  for (const auto& l : f.left_out)
    if (l.why.rfind("wild", 0) == 0 && shown++ < 5) std::printf("left out: %s: %s\n", l.where.c_str(), l.why.c_str());
  auto line = [](const char* what, const fit::RobustFit& r, double plugin, double v1) {
    std::printf("\n%s (%zu points):\n", what, r.observations);
    app::sensors::print_parameter(r, "a", "1/m^2");
    app::sensors::print_parameter(r, "b", "1/m");
    app::sensors::print_parameter(r, "c");
    app::sensors::print_handling(r, "(reading/4095)");
    std::printf("  MSE %.3e (reading/4095)²   (plug-in polynomial: %.3e; E-Puck v1 298.701 d^2 - 36.8961 d + 1.08212: %.3e)\n", r.mse,
                plugin, v1);
  };
  line("Fitted to the maxima", f.maxima, f.plugin_mse_maxima, f.epuck1_mse_maxima);
  line("Fitted to the means", f.means, f.plugin_mse_means, f.epuck1_mse_means);
  std::printf("\nPlug-in (paper, fitted to maxima): a = 197.8633, b = -30.47182, c = 1.011635\n");
  app::sensors::print_noise_and_warnings({f.noise}, f.warnings);
}

nlohmann::json proximity_json(const std::vector<logs::Log>& logs, const app::sensors::SensorOptions& o, calibrate::ProximityFit* keep) {
  calibrate::ProximityFit f = calibrate::fit_proximity(logs, o.fit_options());
  app::sensors::require_usable(f.maxima, "proximity fit to the maxima");
  app::sensors::require_usable(f.means, "proximity fit to the means");
  app::sensors::require_fitting(f.maxima, "proximity fit to the maxima", o, f.warnings);
  app::sensors::require_fitting(f.means, "proximity fit to the means", o, f.warnings);
  nlohmann::json j = app::sensors::skeleton("proximity", logs);
  j["units"] = {{"a", "1/m^2"}, {"b", "1/m"}, {"c", "1"}, {"mean_a", "1/m^2"}, {"mean_b", "1/m"}, {"mean_c", "1"},
                {"values", "reading / 4095"}, {"range_m", "m"}, {"mse", "(reading / 4095)^2"}, {"mean_mse", "(reading / 4095)^2"},
                {"rss", "(reading / 4095)^2"}};
  app::sensors::add_parameters(j, f.maxima, "", "maxima", "(reading / 4095)");
  app::sensors::add_parameters(j, f.means, "mean_", "means", "(reading / 4095)");
  j["parameters"]["range_m"] = s::kPluginProximity.range_m;
  j["std_errors"]["range_m"] = 0.0;
  app::sensors::add_rounded(j, "range_m", s::kPluginProximity.range_m, 0.0, "the sensor's range, held: not fitted");
  j["mse"] = f.maxima.mse;
  j["mean_mse"] = f.means.mse;
  j["observations"] = f.maxima.observations;
  j["readings"] = f.readings;
  j["censored_readings"] = f.censored_readings;
  j["reference_mse"] = {{"plugin_maxima", f.plugin_mse_maxima}, {"plugin_means", f.plugin_mse_means},
                        {"epuck1_maxima", f.epuck1_mse_maxima}, {"epuck1_means", f.epuck1_mse_means}};
  nlohmann::json points = nlohmann::json::array();
  auto rail = [](fit::Censoring c) {
    return c == fit::Censoring::at_or_above ? "at_or_above" : c == fit::Censoring::at_or_below ? "at_or_below" : "none";
  };
  for (const auto& p : f.points) {
    points.push_back({{"distance_m", p.distance_m}, {"max", p.max}, {"mean", p.mean}, {"min", p.min},
                      {"readings", p.readings}, {"kept", p.kept}, {"used", p.used}, {"max_censoring", rail(p.max_censoring)},
                      {"mean_censoring", rail(p.mean_censoring)}});
    if (!p.used) points.back()["left_out_why"] = p.excluded_why;  // its values are the readings as measured
  }
  j["points"] = points;
  if (f.range.fitted) {
    nlohmann::json r = {{"value_m", f.range.value_m}, {"lower_bound", f.range.lower_bound}, {"detected_to_m", f.range.detected_to_m},
                        {"how", f.range.how}};
    // A lower bound has no bracket's far end and no standard error: absent, not NaN.
    if (!f.range.lower_bound) {
      r["std_error_m"] = f.range.std_error_m;
      r["undetected_from_m"] = f.range.undetected_from_m;
    }
    j["range_fit"] = r;
  }
  app::sensors::add_left_out(j, f.left_out);
  app::sensors::add_noise(j, {f.noise});
  app::sensors::add_warnings(j, f.warnings);
  if (keep != nullptr) *keep = std::move(f);
  return j;
}

}  // namespace

void setup_proximity(CLI::App& app, Action& action) {
  app::sensors::add_sensor_command<calibrate::ProximityFit>(
      app, action,
      {"proximity", logs::Kind::proximity, "Calibrate the proximity sensors: Eq. 1 fitted to the maxima and to the means", "Proximity",
       "Optional: angle_deg (incidence angle). value: 0 = nothing detected, 4095 = touching."},
      proximity_json, print_proximity_report, plot::proximity_figure);
}

}  // namespace epuck2::app
