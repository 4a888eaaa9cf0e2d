// The camera calibration (field of view and image centre) as its two outputs: the human report and
// the coefficient file (docs/coefficient-files.md), from the fit's result (calibrate::fit_camera).
#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "epuck2/calibrate/report_json.hpp"
#include "epuck2/calibrate/report_text.hpp"
#include "epuck2/calibrate/sensor_reports.hpp"
#include "epuck2/calibrate/sensors.hpp"

namespace epuck2::calibrate {

namespace s = models::sensors;

namespace {

/// The ARGoS aperture's standard error, from the field of view's through the derivative.
double aperture_std_error(double fov_deg, double fov_std_error) {
  const double h = 1e-6;
  const double slope = (s::aperture_from_horizontal_fov_rad(s::deg_to_rad(fov_deg + h)) -
                        s::aperture_from_horizontal_fov_rad(s::deg_to_rad(fov_deg - h))) / (2 * s::deg_to_rad(h));
  return std::abs(slope) * fov_std_error;
}

}  // namespace

std::string report_text(const CameraFit& f) {
  Text out;
  const auto& r = f.result;
  out("Camera: px = cx - f y/x, py = cy - f z/x, f = 80 / tan(fov/2) (160x120 image)\n");
  out("%zu LED observations\n\n", f.observations.size());
  write_parameter(out, r, "fov_deg", "deg", "", "horizontal field of view");
  out("  (ARGoS aperture, the half-angle on the diagonal: %s)\n",
      fit::format_uncertain(s::rad_to_deg(s::aperture_from_horizontal_fov_rad(s::deg_to_rad(r.value("fov_deg")))),
                            aperture_std_error(r.value("fov_deg"), r.std_error("fov_deg")), "deg",
                            "follows fov_deg, which has none")
          .c_str());
  write_parameter(out, r, "cx_px", "px", "", "image centre column");
  write_parameter(out, r, "cy_px", "px", "", "image centre row");
  write_handling(out, r, "px", "  ", nullptr, /*has_rails=*/false);
  out("MSE %.3f px^2 (plug-in, 29.97 deg centred at (80, 60): %.3f px^2 on the same %zu readings, those the fit kept)\n",
      r.mse, f.plugin_mse, f.plugin_readings);
  out("Table 4 method (alpha from the pixel offset, centre taken as column 80), %zu points: mean %s (± the points' sd, "
      "not a standard error)\n",
      f.table4_points,
      fit::format_uncertain(f.table4_alpha_mean_deg, f.table4_alpha_sd_deg, "deg", "one point: no spread").c_str());
  write_noise_sections(out, {f.noise});
  return out.str();
}

s::CameraModel model_of(const CameraFit& f) {
  s::CameraModel m;
  m.base.horizontal_fov_rad = s::deg_to_rad(f.result.value("fov_deg"));
  m.base.cx_px = f.result.value("cx_px");
  m.base.cy_px = f.result.value("cy_px");
  m.base.range_m = s::kCameraRange_m;  // held
  m.noise_sd_px = f.noise.sd;
  return m;
}

std::vector<fit::ParameterEstimate> robot_estimates(const CameraFit& f) {
  std::vector<fit::ParameterEstimate> out = named_estimates(f.result);
  // The ARGoS aperture follows the field of view, its error through the derivative.
  out.emplace_back("aperture_deg", s::rad_to_deg(s::aperture_from_horizontal_fov_rad(s::deg_to_rad(f.result.value("fov_deg")))),
                   aperture_std_error(f.result.value("fov_deg"), f.result.std_error("fov_deg")));
  return out;
}

nlohmann::json coefficient_json(const CameraFit& f, const std::vector<logs::Log>& logs) {
  coefficients::CalibrationExtras extras = measured_noise({f.noise});
  extras.fov_deg = f.result.value("fov_deg");  // written as fitted (it is the model's radians exactly)
  nlohmann::json j = skeleton(owned_model([&] { return coefficients::calibration_model_json(model_of(f), extras); }), logs);
  j["units"] = {{"fov_deg", "deg"}, {"cx_px", "px"}, {"cy_px", "px"}, {"aperture_deg", "deg"}, {"width_px", "px"},
                {"height_px", "px"}, {"range_m", "m"}, {"mse", "px^2"}, {"rss", "px^2"}};
  j["unit_notes"] = {{"fov_deg", "horizontal field of view"}, {"aperture_deg", "ARGoS half-angle on the diagonal"},
                     {"width_px", "the image's size, held"}, {"height_px", "the image's size, held"},
                     {"range_m", "the camera's range, held"}};
  add_estimates(j, f.result, "", "projection", "px^2");
  for (const char* held : {"width_px", "height_px", "range_m"}) j["std_errors"][held] = 0.0;
  // The aperture is a function of the field of view: its error follows through the derivative.
  const double aperture_se = aperture_std_error(f.result.value("fov_deg"), f.result.std_error("fov_deg"));
  j["std_errors"]["aperture_deg"] = json_number(aperture_se);
  if (!std::isfinite(f.result.std_error("fov_deg"))) j["std_error_why"]["aperture_deg"] = "follows fov_deg";
  add_rounded(j, "aperture_deg", j["parameters"]["aperture_deg"].get<double>(), aperture_se,
                            "follows fov_deg, which has none");
  add_rounded(j, "width_px", s::kCameraWidth_px, 0.0, "the image's width, held");
  add_rounded(j, "height_px", s::kCameraHeight_px, 0.0, "the image's height, held");
  add_rounded(j, "range_m", s::kCameraRange_m, 0.0, "the camera's range, held");
  j["mse"] = f.result.mse;
  j["observations"] = f.observations.size();
  j["reference_mse"] = {{"plugin", f.plugin_mse}};
  j["table4"] = {{"alpha_mean_deg", f.table4_alpha_mean_deg}, {"alpha_sd_deg", f.table4_alpha_sd_deg}, {"points", f.table4_points}};
  add_noise(j, {f.noise});
  add_warnings(j, f.warnings);
  return j;
}
}  // namespace epuck2::calibrate
