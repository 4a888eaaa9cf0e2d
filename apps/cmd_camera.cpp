// epuck2-fit camera LOGS...: the camera's horizontal field of view and image centre from where LEDs
// of known position appear in the 160x120 image (pinhole with square pixels, as the plug-in's
// projection), and the paper's Table 4 method (alpha from a pixel offset at a known geometry).
#include <cstdio>

#include "epuck2/fit/sensors.hpp"
#include "epuck2/plot/png.hpp"
#include "sensor_support.hpp"

namespace epuck2::app {

namespace {

namespace s = models::sensors;

void print_report(const fit::CameraFit& f) {
  const auto& r = f.result;
  std::printf("Camera: px = cx - f y/x, py = cy - f z/x, f = 80 / tan(fov/2) (160x120 image)\n");
  std::printf("%zu LED observations\n\n", f.observations.size());
  std::printf("horizontal field of view fov_deg = %.3f +- %.3f deg\n", r.value("fov_deg"), r.std_error("fov_deg"));
  std::printf("  (ARGoS aperture on the diagonal: %.3f deg)\n",
              s::rad_to_deg(s::aperture_from_horizontal_fov_rad(s::deg_to_rad(r.value("fov_deg")))));
  std::printf("image centre cx_px = %.2f +- %.2f, cy_px = %.2f +- %.2f\n", r.value("cx_px"), r.std_error("cx_px"),
              r.value("cy_px"), r.std_error("cy_px"));
  std::printf("MSE %.3f px^2 (plug-in, 29.97 deg centred at (80, 60): %.3f px^2)\n", r.mse, f.plugin_mse);
  std::printf("Table 4 method (alpha from the pixel offset, centre taken as column 80), %zu points: %.2f +- %.2f deg\n",
              f.table4_points, f.table4_alpha_mean_deg, f.table4_alpha_sd_deg);
}

void draw(logs::OutputStage& stage, const std::string& path, const fit::CameraFit& f) {
  const double fov = s::deg_to_rad(f.result.value("fov_deg")), cx = f.result.value("cx_px"), cy = f.result.value("cy_px");
  const auto plugin = s::plugin_camera();
  std::vector<std::vector<double>> rows;
  for (const auto& o : f.observations) {
    double mx, my, qx, qy;
    s::camera_projection(fov, cx, cy, s::kCameraWidth_px, o.forward_m, o.lateral_m, o.vertical_m, &mx, &my);
    s::camera_projection(plugin.horizontal_fov_rad, plugin.cx_px, plugin.cy_px, s::kCameraWidth_px, o.forward_m, o.lateral_m,
                         o.vertical_m, &qx, &qy);
    rows.push_back({o.lateral_m / o.forward_m, o.px, mx, qx, o.vertical_m / o.forward_m, o.py, my, qy});
  }
  plot::render_png(stage, path, [&](gnuplotio::Gnuplot& gp) {
    gp << app::sensors::datablock("obs", rows);
    gp << "set multiplot layout 1,2 title 'Camera (paper section 4.1.6): pixel against the LED direction'\n";
    gp << "set grid\nset key top right\n";
    gp << "set xlabel 'lateral / forward (left > 0)'\nset ylabel 'column px'\nset yrange [-5:165]\n";
    gp << "plot $obs using 1:2 with points pt 7 ps 0.8 lc rgb '#1f77b4' title 'observed', "
       << "$obs using 1:3 with lines lw 2.5 lc rgb '#d62728' title 'fit', "
       << "$obs using 1:4 with lines lw 2 dt 2 lc rgb '#000000' title 'plug-in (29.97 deg, centre 80)'\n";
    gp << "set xlabel 'vertical / forward (up > 0)'\nset ylabel 'row py'\nset yrange [-5:125]\n";
    gp << "plot $obs using 5:6 with points pt 7 ps 0.8 lc rgb '#1f77b4' title 'observed', "
       << "$obs using 5:7 with lines lw 2.5 lc rgb '#d62728' title 'fit', "
       << "$obs using 5:8 with lines lw 2 dt 2 lc rgb '#000000' title 'plug-in (centre 60)'\n";
    gp << "unset multiplot\n";
  });
}

int run_camera(const app::sensors::SensorOptions& o) {
  const auto logs = logs::read_logs(o.logs, logs::Kind::camera);
  const fit::CameraFit f = fit::fit_camera(logs);
  app::sensors::require_usable(f.result, "camera fit");
  nlohmann::json j = app::sensors::skeleton("camera", o.logs);
  app::sensors::add_parameters(j, f.result);
  j["parameters"]["aperture_deg"] = s::rad_to_deg(s::aperture_from_horizontal_fov_rad(s::deg_to_rad(f.result.value("fov_deg"))));
  j["parameters"]["width_px"] = s::kCameraWidth_px;
  j["parameters"]["height_px"] = s::kCameraHeight_px;
  j["parameters"]["range_m"] = s::kCameraRange_m;
  j["mse"] = f.result.mse;
  j["observations"] = f.observations.size();
  j["units"] = {{"fov_deg", "degrees, horizontal"}, {"aperture_deg", "ARGoS half-angle on the diagonal"}, {"mse", "px^2"}};
  j["reference_mse"] = {{"plugin", f.plugin_mse}};
  j["table4"] = {{"alpha_mean_deg", f.table4_alpha_mean_deg}, {"alpha_sd_deg", f.table4_alpha_sd_deg}, {"points", f.table4_points}};
  return app::sensors::finish("camera", o, j, [&] { print_report(f); }, [&](logs::OutputStage& stage, const std::string& path) { draw(stage, path, f); });
}

}  // namespace

void setup_camera(CLI::App& app, Action& action) {
  auto o = std::make_shared<app::sensors::SensorOptions>();
  CLI::App* sub = app.add_subcommand("camera", "Calibrate the camera: horizontal field of view and image centre");
  app::sensors::add_common_options(sub, *o, "Camera");
  sub->callback([o, &action] { action = [o] { return run_camera(*o); }; });
}

}  // namespace epuck2::app
