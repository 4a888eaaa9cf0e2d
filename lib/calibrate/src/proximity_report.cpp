// The proximity calibration (Eq. 1 to the maxima and the means) as its two outputs: the human
// report and the coefficient file (docs/coefficient-files.md), from the fit's result
// (calibrate::fit_proximity).
#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "epuck2/models/kind_facts.hpp"
#include "epuck2/calibrate/report_json.hpp"
#include "epuck2/calibrate/report_text.hpp"
#include "epuck2/calibrate/sensor_reports.hpp"
#include "epuck2/calibrate/sensors.hpp"

namespace epuck2::calibrate {

namespace s = models::sensors;

std::string report_text(const ProximityFit& f) {
  Text out;
  out("Proximity sensor, paper Eq. 1: v(d) = a d^2 + b d + c (normalised 0..1), d <= 0.05 m,\n"
      "held non-increasing with distance over [0, 0.05 m] (slopes at 0 and at 0.05 m bounded at 0)\n");
  const models::Channel& proximity = models::kind_facts("proximity")->channels.front();
  out("%zu readings at %zu distances; %zu on a rail (%g or %g: censored at the distances used); %zu left out\n\n", f.readings,
      f.points.size(), f.censored_readings, proximity.low_rail, proximity.high_rail, f.left_out.size());
  out("%10s %8s %6s %8s %8s %8s  %s\n", "distance_m", "readings", "kept", "min", "mean", "max", "used");
  for (const auto& p : f.points)
    out("%10.4f %8zu %6zu %8.4f %8.4f %8.4f%s  %s\n", p.distance_m, p.readings, p.kept, p.min, p.mean, p.max,
        p.max_censoring == fit::Censoring::at_or_above   ? "+"
        : p.max_censoring == fit::Censoring::at_or_below ? "-"
                                                         : " ",
        p.used ? "yes" : ("no: " + p.excluded_why).c_str());
  out("(+: on the %g rail, at least this; -: on the %g rail, at most this; a distance not used: its readings as measured)\n",
      proximity.high_rail, proximity.low_rail);
  if (f.range.fitted && !f.range.lower_bound)
    out("Range (where the readings stop being detected): %.1f ± %.1f mm, %s; Eq. 1 keeps its 50 mm domain\n",
        f.range.value_m * 1000, f.range.std_error_m * 1000, f.range.how.c_str());
  else if (f.range.fitted)
    out("Range (where the readings stop being detected): %s; Eq. 1 keeps its 50 mm domain\n", f.range.how.c_str());
  std::size_t shown = 0;
  for (const auto& l : f.left_out)
    if (l.why.rfind("wild", 0) == 0 && shown++ < 5) out("left out: %s: %s\n", l.where.c_str(), l.why.c_str());
  auto line = [&out](const char* what, const fit::RobustFit& r, double plugin, double v1) {
    out("\n%s (%zu points):\n", what, r.observations);
    write_parameter(out, r, "a", "1/m^2");
    write_parameter(out, r, "b", "1/m");
    write_parameter(out, r, "c");
    write_handling(out, r, "(reading/4095)");
    out("  MSE %.3e (reading/4095)²   (plug-in polynomial: %.3e; E-Puck v1 298.701 d^2 - 36.8961 d + 1.08212: %.3e)\n", r.mse,
        plugin, v1);
  };
  line("Fitted to the maxima", f.maxima, f.plugin_mse_maxima, f.epuck1_mse_maxima);
  line("Fitted to the means", f.means, f.plugin_mse_means, f.epuck1_mse_means);
  out("\nPlug-in (paper, fitted to maxima): a = 197.8633, b = -30.47182, c = 1.011635\n");
  write_noise_sections(out, {f.noise});
  return out.str();
}

s::ProximityModel model_of(const ProximityFit& f, bool means) {
  const fit::RobustFit& r = means ? f.means : f.maxima;
  s::ProximityModel m;
  m.base.a_per_m2 = r.value("a");
  m.base.b_per_m = r.value("b");
  m.base.c = r.value("c");
  m.base.range_m = s::kPluginProximity.range_m;  // held: Eq. 1's domain (the detected range is `range_fit`)
  m.noise_sd_raw = per_sensor_noise<s::kProximityCount>(f.noise);
  return m;
}

std::vector<fit::ParameterEstimate> robot_estimates(const ProximityFit& f) {
  std::vector<fit::ParameterEstimate> out = named_estimates(f.maxima);
  for (auto& p : named_estimates(f.means, "mean_")) out.push_back(p);
  return out;
}

nlohmann::json coefficient_json(const ProximityFit& f, const std::vector<logs::Log>& logs) {
  nlohmann::json j = skeleton(owned_model([&] { return coefficients::calibration_model_json(model_of(f), model_of(f, true), measured_noise({f.noise})); }), logs);
  j["units"] = {{"a", "1/m^2"}, {"b", "1/m"}, {"c", "1"}, {"mean_a", "1/m^2"}, {"mean_b", "1/m"}, {"mean_c", "1"},
                {"values", "reading / 4095"}, {"range_m", "m"}, {"mse", "(reading / 4095)^2"}, {"mean_mse", "(reading / 4095)^2"},
                {"rss", "(reading / 4095)^2"}};
  add_estimates(j, f.maxima, "", "maxima", "(reading / 4095)^2");
  add_estimates(j, f.means, "mean_", "means", "(reading / 4095)^2");
  j["std_errors"]["range_m"] = 0.0;
  add_rounded(j, "range_m", s::kPluginProximity.range_m, 0.0, "the sensor's range, held: not fitted");
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
  add_left_out(j, f.left_out);
  add_noise(j, {f.noise});
  add_warnings(j, f.warnings);
  return j;
}
}  // namespace epuck2::calibrate
