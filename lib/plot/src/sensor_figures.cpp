#include "epuck2/plot/sensor_figures.hpp"
#include "epuck2/models/effects.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <map>
#include <vector>

#include "epuck2/plot/figure.hpp"

namespace epuck2::plot {

namespace {

namespace s = models::sensors;

/// n + 1 evenly spaced values from `from` to `to`: where a curve of lib/models is sampled (the
/// figures draw lib/models' formulas, never a copy of them in gnuplot's language).
std::vector<double> samples(double from, double to, int n) {
  std::vector<double> x;
  for (int i = 0; i <= n; ++i) x.push_back(from + (to - from) * i / n);
  return x;
}

/// The camera's and the drive's two panels side by side.
Layout two_panels() {
  Layout layout;
  layout.rows = 1;
  layout.cols = 2;
  layout.top = 0.9;
  layout.bottom = 0.1;
  // Room for the tics and the y label in canvas pixels (text-sized), whatever the page's size.
  const double width = canvas_px(1400, 900).first;
  layout.left = std::max(0.07, 110.0 / width);
  layout.hspace = std::max(0.09, 130.0 / width);
  return layout;
}

}  // namespace

void proximity_figure(logs::OutputStage& stage, const std::string& path, const calibrate::ProximityFit& f) {
  std::vector<std::vector<double>> pts;
  std::vector<std::vector<double>> left_out;  // distances left out of the fits, as measured
  double far_mm = 60;
  for (const auto& p : f.points) {
    (p.used ? pts : left_out).push_back({p.distance_m * 1000, p.min, p.mean, p.max, p.used ? 1.0 : 0.0});
    far_mm = std::max(far_mm, p.distance_m * 1000);
  }
  // Eq. 1's normalised response (lib/models proximity_response) of each curve, on 0..50 mm.
  const s::ProximityCoefficients kmax{f.maxima.value("a"), f.maxima.value("b"), f.maxima.value("c"), s::kPluginProximity.range_m};
  const s::ProximityCoefficients kmean{f.means.value("a"), f.means.value("b"), f.means.value("c"), s::kPluginProximity.range_m};
  std::vector<std::vector<double>> curves;
  for (double mm : samples(0.0, 50.0, 500)) {
    const double d = mm / 1000.0;
    curves.push_back({mm, s::proximity_response(kmax, d), s::proximity_response(kmean, d),
                      s::proximity_response(s::kPluginProximity, d), s::proximity_response(s::kEpuck1Proximity, d)});
  }
  render(stage, path, [&](gnuplotio::Gnuplot& gp) {
    gp << datablock("pts", pts);
    gp << datablock("curves", curves);
    if (!left_out.empty()) gp << datablock("out", left_out);
    gp << "set title 'Proximity sensor (paper Eq. 1, Fig. 4c): normalised reading against distance' font ',13'\n";
    gp << "set xlabel 'distance to the surface (mm)'\nset ylabel 'normalised reading (reading / 4095, dimensionless)'\n";
    gp << "set xrange [-1:" << std::ceil(far_mm + 1) << "]\nset yrange [-0.05:1.1]\nset grid lc rgb '#d8d8d8'\nset key top right opaque box Left reverse\n";
    gp << "plot $pts using 1:3:2:4 with yerrorbars lc rgb '#999999' title 'readings: mean, min..max', "
       << "$pts using 1:4 with points pt 7 ps 1.4 lc rgb '#d62728' title 'maxima', "
       << "$pts using 1:3 with points pt 5 ps 1.2 lc rgb '#1f77b4' title 'means', "
       << (left_out.empty() ? "" : "$out using 1:3:2:4 with yerrorbars pt 4 ps 1.2 lc rgb '#7f7f7f' title 'left out of the fits: readings as measured', ")
       << "$curves using 1:2 with lines lw 2.5 lc rgb '#d62728' title 'fit to maxima', "
       << "$curves using 1:3 with lines lw 2.5 lc rgb '#1f77b4' title 'fit to means', "
       << "$curves using 1:4 with lines lw 2 dt 2 lc rgb '#2ca02c' title 'plug-in (197.8633, -30.47182, 1.011635)', "
       << "$curves using 1:5 with lines lw 2 dt 3 lc rgb '#000000' title 'E-Puck v1 (298.701, -36.8961, 1.08212)'\n";
  });
}

void light_figure(logs::OutputStage& stage, const std::string& path, const calibrate::LightFit& f) {
  std::map<double, std::vector<std::vector<double>>> by_intensity;
  for (const auto& o : f.observations) by_intensity[o.intensity].push_back({o.distance_m * 100, o.value_raw, double(o.sensor)});
  const double g = f.gamma.value("gamma");
  // Eq. 2's raw reading (lib/models light_mean_raw, no effects) for the fit's and the plug-in's
  // gamma at each intensity, on 5..52 cm.
  auto eq2 = [](double gamma_m, double intensity, double distance_m) {
    const s::LightCoefficients k{gamma_m, s::kPluginLight.range_m};
    return std::clamp(s::light_mean_raw(k, s::LightEffects<double>{}, 0, intensity, distance_m), 0.0, s::kProximityFullScale_raw);
  };
  render(stage, path, [&](gnuplotio::Gnuplot& gp) {
    int k = 0;
    for (const auto& [i, rows] : by_intensity) {
      std::vector<std::vector<double>> curve;
      for (double cm : samples(5.0, 52.0, 470)) curve.push_back({cm, eq2(g, i, cm / 100.0), eq2(s::kPluginLight.gamma_m, i, cm / 100.0)});
      gp << datablock("i" + std::to_string(k), rows);
      gp << datablock("c" + std::to_string(k), curve);
      ++k;
    }
    gp << "set title 'Ambient light sensor (paper Eq. 2, Fig. 5): reading against distance, per source intensity I (simulator units)' font ',13'\n";
    gp << "set xlabel 'distance to the light (cm)'\nset ylabel 'raw reading (counts, 0..4095; 4095 = dark)'\n";
    gp << "set xrange [5:52]\nset yrange [-100:4200]\nset grid lc rgb '#d8d8d8'\nset samples 400\n";
    gp << "set key at graph 0.98,0.62 right top opaque box Left reverse samplen 3 spacing 1.15\n";
    const char* colours[] = {"#1f77b4", "#d62728", "#2ca02c", "#9467bd", "#ff7f0e", "#8c564b"};
    gp << "plot ";
    k = 0;
    // Colour: the intensity; solid: the fit, dashed: the plug-in (one legend entry each, in black).
    for (const auto& [intensity, rows] : by_intensity) {
      const char* c = colours[k % 6];
      char buf[600];
      std::snprintf(buf, sizeof buf,
                    "%s$i%d using 1:2 with points pt 7 ps 0.6 lc rgb '%s' title 'readings at I = %.2f', "
                    "$c%d using 1:2 with lines lw 2.5 lc rgb '%s' notitle, "
                    "$c%d using 1:3 with lines lw 1.5 dt (8,5) lc rgb '%s' notitle",
                    k ? ", " : "", k, c, intensity, k, c, k, c);
      gp << buf;
      ++k;
    }
    char buf[300];
    std::snprintf(buf, sizeof buf,
                  ", NaN with lines lw 2.5 lc rgb 'black' title 'fit: γ = %.4f m (solid, colour of its I)', "
                  "NaN with lines lw 1.5 dt (8,5) lc rgb 'black' title 'plug-in: γ = 0.075 m (dashed)'",
                  g);
    gp << buf;
    gp << "\n";
  });
}

void ground_figure(logs::OutputStage& stage, const std::string& path, const calibrate::GroundFit& f) {
  render(stage, path, [&](gnuplotio::Gnuplot& gp) {
    // Each sensor's fitted line and the plug-in's (lib/models ground_response), on grey 0..1.
    std::vector<std::vector<double>> lines;
    for (double grey : samples(0.0, 1.0, 100)) {
      std::vector<double> row{grey};
      for (std::size_t k = 0; k < f.sensors.size(); ++k)
        row.push_back(s::ground_response(f.sensors[k].value("gain"), f.sensors[k].value("offset"), grey));
      row.push_back(s::ground_response(s::kPluginGround.gain_raw, s::kPluginGround.offset_raw, grey));
      lines.push_back(row);
    }
    gp << datablock("lines", lines);
    // Several robots: each robot its own marker (filled circle, open square, open triangle, ...)
    // in its sensor's colour, so that one robot's black cluster is not taken for another's.
    const std::size_t robots = std::max<std::size_t>(1, f.robot_names.size());
    static const int kMarkers[] = {7, 4, 8, 6, 12, 10};
    for (std::size_t k = 0; k < f.sensors.size(); ++k) {
      std::vector<std::vector<double>> rows;
      for (std::size_t i = 0; i < f.grey[k].size(); ++i) {
        const int robot = i < f.robot[k].size() ? f.robot[k][i] : 0;
        // Sideways: 0.006 between sensors, 0.002 between robots (each robot's cluster its own column).
        const double shift = (double(k) - 1) * 0.006 + (robots > 1 ? (robot - 0.5 * double(robots - 1)) * 0.002 : 0.0);
        rows.push_back({f.grey[k][i] + shift, f.value_raw[k][i],
                        static_cast<double>(kMarkers[static_cast<std::size_t>(robot) % 6])});
      }
      gp << datablock("s" + std::to_string(k), rows);
    }
    gp << "set title 'Ground sensors (paper section 4.1.3): reading against the grey level of the floor' font ',13'\n";
    gp << "set xlabel 'grey level (fraction: 0 = black, 1 = white; each sensor''s points shifted sideways by 0.006, each robot''s by 0.002)'\n";
    gp << "set ylabel 'raw reading (counts, 0..1023)'\n";
    gp << "set xrange [-0.03:1.03]\nset yrange [-20:1060]\nset grid lc rgb '#d8d8d8'\nset key top left opaque box Left reverse\n";
    const char* colours[] = {"#d62728", "#2ca02c", "#1f77b4"};
    gp << "plot ";
    for (std::size_t k = 0; k < f.sensors.size(); ++k) {
      char buf[500];
      std::snprintf(buf, sizeof buf,
                    "$s%zu using 1:2:3 with points pt variable ps 0.5 lc rgb '%s' notitle, "
                    "NaN with points pt 7 ps 1 lc rgb '%s' title 'sensor %s', "
                    "$lines using 1:%zu with lines lw 2.5 lc rgb '%s' title 'fit: %.1f + %.1f grey', ",
                    k, colours[k], colours[k], calibrate::kGroundSensorNames[k], k + 2, colours[k], f.sensors[k].value("offset"),
                    f.sensors[k].value("gain"));
      gp << buf;
    }
    gp << "$lines using 1:" << f.sensors.size() + 2 << " with lines lw 2 dt 2 lc rgb '#000000' title 'plug-in: 1023 grey'";
    if (robots > 1)
      for (std::size_t r = 0; r < robots; ++r)
        gp << ", NaN with points pt " << kMarkers[r % 6] << " ps 0.9 lc rgb '#000000' title " << plot::quoted("robot " + f.robot_names[r]);
    gp << "\n";
  });
}

void camera_figure(logs::OutputStage& stage, const std::string& path, const calibrate::CameraFit& f) {
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
  render(stage, path, [&](gnuplotio::Gnuplot& gp) {
    gp << datablock("obs", rows);
    gp << multiplot(two_panels(), "Camera (paper section 4.1.6): where the LED appears in the image against its direction");
    gp << "set grid lc rgb '#d8d8d8'\nset key top right opaque box Left reverse\n";
    gp << "set title 'columns' font ',12'\n";
    gp << "set xlabel 'lateral / forward (tangent of the horizontal angle, dimensionless; left > 0)'\n";
    gp << "set ylabel 'column px (pixels, 0..159)'\nset yrange [-5:165]\n";
    gp << "plot $obs using 1:2 with points pt 7 ps 0.8 lc rgb '#1f77b4' title 'observed', "
       << "$obs using 1:3 with lines lw 2.5 lc rgb '#d62728' title 'fit', "
       << "$obs using 1:4 with lines lw 2 dt (8,5) lc rgb '#000000' title 'plug-in (29.97° field of view, centre 80)'\n";
    gp << "set title 'rows' font ',12'\n";
    gp << "set xlabel 'vertical / forward (tangent of the vertical angle, dimensionless; up > 0)'\n";
    gp << "set ylabel 'row py (pixels, 0..119)'\nset yrange [-5:125]\n";
    gp << "plot $obs using 5:6 with points pt 7 ps 0.8 lc rgb '#1f77b4' title 'observed', "
       << "$obs using 5:7 with lines lw 2.5 lc rgb '#d62728' title 'fit', "
       << "$obs using 5:8 with lines lw 2 dt (8,5) lc rgb '#000000' title 'plug-in (centre 60)'\n";
    gp << "unset multiplot\n";
  });
}

void drive_figure(logs::OutputStage& stage, const std::string& path, const calibrate::DriveFit& f) {
  const double spm = f.steps.value("steps_per_m");
  const double scale = f.tof.value(models::effects::file_key(models::effects::drive_catalogue(), models::effects::drive::tof_scale)), offset = f.tof.value("tof_offset_mm"), tau = f.tof.value("slip_time_constant_s");
  constexpr double kOutOfRangeCode_mm = 8190, kCodeRow_mm = 2250;
  const double kNaN = std::numeric_limits<double>::quiet_NaN();
  std::size_t codes = 0;
  render(stage, path, [&](gnuplotio::Gnuplot& gp) {
    std::string plot_tof = "plot ", plot_steps = "plot ";
    for (std::size_t r = 0; r < f.runs.size(); ++r) {
      const auto& run = f.runs[r];
      const std::vector<double> travel = calibrate::lagged_travel_m(run, spm, tau);
      const std::vector<double> enc = calibrate::lagged_travel_m(run, s::kPluginStepsPerMetre, 0.0);
      std::vector<std::vector<double>> rows;
      double commanded = 0;
      for (std::size_t k = 0; k < run.time_s.size(); ++k) {
        // The VL53L0X's out-of-range codes (>= 8190) are no distance: drawn apart, at the top.
        const bool code = run.tof_mm[k] >= kOutOfRangeCode_mm;
        // The curves as the sensor reports them: clamped to its rails (20 and 2000 mm), never
        // drawn above the 2000 mm a reading cannot exceed.
        auto on_rails = [](double mm) { return std::clamp(mm, s::kPluginTof.min_mm, s::kPluginTof.max_mm); };
        rows.push_back({run.time_s[k], code ? kNaN : run.tof_mm[k],
                        on_rails(s::tof_response_mm(scale, offset, run.obstacle_distance_m - travel[k])),
                        on_rails(s::tof_response_mm(1.0, 0.0, run.obstacle_distance_m - enc[k])), run.steps[k], spm * commanded,
                        code ? kCodeRow_mm : kNaN});
        codes += code;
        if (k + 1 < run.time_s.size()) commanded += run.command_m_s[k] * (run.time_s[k + 1] - run.time_s[k]);
      }
      gp << datablock("r" + std::to_string(r), rows);
      const std::string first = r == 0 ? "" : ", ";
      const std::string d = "$r" + std::to_string(r);
      plot_tof += first + d + " using 1:2 with points pt 7 ps 0.4 lc rgb '#1f77b4' " + (r ? "notitle" : "title 'ToF readings'") +
                  ", " + d + " using 1:3 with lines lw 2 lc rgb '#d62728' " + (r ? "notitle" : "title 'fit (scale, offset, slip lag), on the rails'") +
                  ", " + d + " using 1:4 with lines lw 1.5 dt 2 lc rgb '#000000' " + (r ? "notitle" : "title 'plug-in: 1000 (D - encoder travel)'");
      plot_steps += first + d + " using 1:5 with points pt 7 ps 0.4 lc rgb '#2ca02c' " + (r ? "notitle" : "title 'encoder steps'") +
                    ", " + d + " using 1:6 with lines lw 1.5 lc rgb '#d62728' " + (r ? "notitle" : "title 'fitted steps/m × commanded distance'");
    }
    for (std::size_t r = 0; r < f.runs.size() && codes > 0; ++r)
      plot_tof += ", $r" + std::to_string(r) + " using 1:7 with points pt 9 ps 0.8 lc rgb '#ff7f0e' " +
                  (r ? "notitle" : "title 'out-of-range codes (≥ 8190), drawn at 2250 mm'");
    gp << multiplot(two_panels(), "Drive runs (paper sections 4.1.4 and 4.1.5), all runs overlaid");
    // The legend above the readings (the 2000 mm rail, the codes drawn at 2250 mm).
    gp << "set grid lc rgb '#d8d8d8'\nset key top left opaque box Left reverse\nset xlabel 'time since the start of the run (s)'\n";
    gp << "set title 'time-of-flight sensor' font ',12'\nset ylabel 'ToF reading (mm)'\nset yrange [0:2800]\n";
    gp << plot_tof << "\n";
    gp << "set title 'wheel encoders' font ',12'\nset ylabel 'encoder register, unwrapped (steps)'\nset yrange [*:*]\n";
    gp << "set key bottom left\n";
    gp << plot_steps << "\n";
    gp << "unset multiplot\n";
  });
}

}  // namespace epuck2::plot
