#include "epuck2/plot/sensor_figures.hpp"
#include "epuck2/models/effects.hpp"
#include "epuck2/models/kind_facts.hpp"

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

/// A single-panel figure on the run's page: its canvas width and whether it is a paper's column
/// (titles wrapped, the legend below the plot in small type, short legend entries).
struct Sheet {
  int width = 1400;
  bool narrow = false;
  bool svg = false;  ///< drawn by the svg terminal, whose reckoning of a key's text is wider than it draws
};
Sheet page_of(const std::string& path, int default_width_px = 1400, int default_height_px = 900) {
  const int w = canvas_px(default_width_px, default_height_px).first;
  return {w, w < kNarrowCanvas_px, format_of(path) == Format::svg};
}

/// The title and the legend's place for `page`: on a narrow page no title (the caption's) and the
/// legend below the plot; on another page narrower than the figure's own canvas (two columns) the
/// title in lines of the page, and with `below_on_page` the legend below the plot too (at 17.8 cm
/// the light figure's legend, inside the plot, hid readings, and in the SVG ran over the x tics);
/// `key` otherwise.
std::string title_and_key(const Sheet& page, const std::string& title, const std::string& key, bool below_on_page = false) {
  // (the svg terminal reckons the entries 1.4 times as wide as it draws them, and set them in one
  // column of twelve rows at 8.5 cm: its columns narrowed by 6 characters to match)
  const std::string below = std::string("set key below center horizontal Left reverse samplen 2 spacing 1.0 width ") +
                            (page.svg ? "-6" : "-1") + " maxrows " + (page.narrow ? "4" : "3") + " font ',9'\n";
  if (page.width >= 1400) return "set title " + quoted(title) + " font ',13'\nset key " + key + "\n";
  if (!page.narrow)
    return "set title " + quoted(wrapped(title, page.width - 60.0, 13)) + " font ',13'\n" + (below_on_page ? below : "set key " + key + "\n");
  // A paper's column leaves the title to the figure's caption: the plot keeps the room.
  return "unset title\n" + below;
}

/// A legend entry for each robot (black, its marker) when the logs come from more than one.
std::string robot_entries(const std::vector<std::string>& names) {
  std::string out;
  if (names.size() < 2) return out;
  for (std::size_t r = 0; r < names.size(); ++r)
    out += ", NaN with points pt " + std::to_string(robot_point_type(r)) + " ps 0.9 lc rgb '#000000' title " +
           quoted("robot " + names[r]);
  return out;
}

/// The camera's two panels side by side, or one above the other on a paper's column. On a page of
/// two columns (narrower than the figure's own 1400 canvas pixels), under an overall title of
/// `title_lines` lines, with the legend in a band below.
Layout two_panels(int title_lines) {
  Layout layout;
  const std::pair<int, int> canvas = canvas_px(1400, 900);
  const double width = canvas.first, height = canvas.second;
  // Stacked on a column tall enough for panels of 110 canvas pixels; else (8.5x6cm: 23 pixels
  // each, their tics overlapping) side by side.
  if (width < kNarrowCanvas_px && (height - 265.0) / 2 < 110) {
    layout.rows = 1;
    layout.cols = 2;
    layout.left = 110.0 / width;
    layout.right = 1.0 - 15.0 / width;
    layout.top = 1.0 - 55.0 / height;  // (the svg terminal sets a title 33 pixels above its panel)
    layout.bottom = 150.0 / height;  // the x label (two lines), then the legend band (two rows)
    layout.hspace = 110.0 / width;
    return layout;
  }
  if (width < kNarrowCanvas_px) {
    layout.rows = 2;
    layout.cols = 1;
    layout.left = 110.0 / width;
    layout.right = 1.0 - 15.0 / width;
    layout.top = 1.0 - 55.0 / height;  // no overall title (the caption's): the first panel's
    layout.bottom = 125.0 / height;     // the x label, then the legend band (two rows)
    layout.vspace = 100.0 / height;     // the upper panel's x label, the lower panel's title
    return layout;
  }
  layout.rows = 1;
  layout.cols = 2;
  if (width < 1400) {  // (at 17.8x8cm the fractions below put the panels' titles on the overall
                       // title, their legends over the readings and off the canvas, the x labels below it)
    layout.left = 110.0 / width;
    layout.right = 1.0 - 15.0 / width;
    layout.top = 1.0 - (10.0 + 31.0 * title_lines + 55.0) / height;  // a 15 pt title's line: 31 pixels in the SVG
    layout.bottom = 150.0 / height;  // the x label (two lines), then the legend band (two rows)
    layout.hspace = 130.0 / width;
    return layout;
  }
  layout.top = 0.9;
  layout.bottom = 0.1;
  // Room for the tics and the y label in canvas pixels (text-sized), whatever the page's size.
  layout.left = std::max(0.07, 110.0 / width);
  layout.hspace = std::max(0.09, 130.0 / width);
  return layout;
}

}  // namespace

void proximity_figure(logs::OutputStage& stage, const std::string& path, const calibrate::ProximityFit& f) {
  const std::size_t robots = f.robot_names.size();
  std::vector<std::vector<double>> pts, per_robot;
  std::vector<std::vector<double>> left_out;  // distances left out of the fits, as measured
  double far_mm = 60;
  for (const auto& p : f.points) {
    (p.used ? pts : left_out).push_back({p.distance_m * 1000, p.min, p.mean, p.max, p.used ? 1.0 : 0.0});
    far_mm = std::max(far_mm, p.distance_m * 1000);
    // Each robot's mean at this distance, shifted sideways by 0.3 mm a robot so that they stand apart.
    for (std::size_t r = 0; r < p.robot_mean.size() && robots > 1; ++r)
      per_robot.push_back({p.distance_m * 1000 + (double(r) - 0.5 * double(robots - 1)) * 0.3, p.robot_mean[r],
                           static_cast<double>(robot_point_type(r))});
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
  const Sheet page = page_of(path);
  render(stage, path, [&](gnuplotio::Gnuplot& gp) {
    gp << datablock("pts", pts);
    gp << datablock("curves", curves);
    if (!left_out.empty()) gp << datablock("out", left_out);
    if (!per_robot.empty()) gp << datablock("robots", per_robot);
    gp << title_and_key(page, "Proximity sensor (paper Eq. 1, Fig. 4c): normalised reading against distance", "top right opaque box Left reverse");
    gp << "set xlabel 'distance to the surface (mm)'\nset ylabel "
       << quoted(page.narrow ? "reading / 4095" : "normalised reading (reading / 4095, dimensionless)") << "\n";
    gp << "set xrange [-1:" << std::ceil(far_mm + 1) << "]\nset yrange [-0.05:1.1]\nset grid lc rgb '#d8d8d8'\n";
    gp << "plot $pts using 1:3:2:4 with yerrorbars lc rgb '#999999' title " << quoted(page.narrow ? "min..max" : "readings: mean, min..max") << ", "
       << "$pts using 1:4 with points pt 7 ps 1.4 lc rgb '#d62728' title 'maxima', "
       << "$pts using 1:3 with points pt 5 ps 1.2 lc rgb '#1f77b4' title 'means', ";
    if (!left_out.empty())
      gp << "$out using 1:3:2:4 with yerrorbars pt 4 ps 1.2 lc rgb '#7f7f7f' title "
         << quoted(page.narrow ? "left out: as measured" : "left out of the fits: readings as measured") << ", ";
    if (!per_robot.empty())
      gp << "$robots using 1:2:3 with points pt variable ps 0.8 lc rgb '#ff7f0e' notitle, NaN with points pt 7 ps 0.8 lc rgb '#ff7f0e' title "
         << quoted(page.narrow ? "each robot's mean" : "each robot's mean (marker: the robot)") << ", ";
    gp << "$curves using 1:2 with lines lw 2.5 lc rgb '#d62728' title 'fit to maxima', "
       << "$curves using 1:3 with lines lw 2.5 lc rgb '#1f77b4' title 'fit to means', "
       << "$curves using 1:4 with lines lw 2 dt 2 lc rgb '#2ca02c' title "
       << quoted(page.narrow ? "plug-in" : "plug-in (197.8633, -30.47182, 1.011635)") << ", "
       << "$curves using 1:5 with lines lw 2 dt 3 lc rgb '#000000' title "
       << quoted(page.narrow ? "E-Puck v1" : "E-Puck v1 (298.701, -36.8961, 1.08212)") << robot_entries(f.robot_names) << "\n";
  });
}

void light_figure(logs::OutputStage& stage, const std::string& path, const calibrate::LightFit& f) {
  // A vector file draws at most about 1200 readings (1 in `stride` of each intensity's, in the
  // logs' order, so every robot and sensor keeps its share; the axis label says so): every one of
  // the shipped set's 3656 made a 450 KB SVG. A PNG draws them all.
  const std::size_t most = format_of(path) == Format::png ? f.observations.size() : 1200;
  const std::size_t stride = std::max<std::size_t>(1, (f.observations.size() + most - 1) / std::max<std::size_t>(1, most));
  std::map<double, std::vector<std::vector<double>>> by_intensity;
  std::map<double, std::size_t> seen;
  for (const auto& o : f.observations)
    if (seen[o.intensity]++ % stride == 0)
      by_intensity[o.intensity].push_back(
          {o.distance_m * 100, o.value_raw, double(o.sensor), static_cast<double>(robot_point_type(static_cast<std::size_t>(o.robot)))});
  const Sheet page = page_of(path);
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
    gp << title_and_key(page, "Ambient light sensor (paper Eq. 2, Fig. 5): reading against distance, per source intensity I (simulator units)",
                        "at graph 0.98,0.62 right top opaque box Left reverse samplen 3 spacing 1.15", true);
    const bool short_entries = page.width < 1400;  // a page's legend, below the plot: the short forms
    // The register's unit and rails (kind_facts); dark is the high rail.
    const models::Channel& light = models::kind_facts("light")->channels.front();
    char dark[32];
    std::snprintf(dark, sizeof dark, "%g = dark", light.high_rail);
    gp << "set xlabel "
       << quoted(stride > 1 ? "distance to the light (cm); 1 in " + std::to_string(stride) + " readings drawn"
                            : std::string("distance to the light (cm)"))
       << "\nset ylabel "
       << quoted(page.narrow ? "raw reading (" + std::string(light.unit) + ")"
                             : "raw reading (" + std::string(light.unit) + ", " + light.rails_text() + "; " + dark + ")")
       << "\n";
    gp << "set xrange [5:52]\nset yrange [-100:4200]\nset grid lc rgb '#d8d8d8'\nset samples 400\n";
    const char* colours[] = {"#1f77b4", "#d62728", "#2ca02c", "#9467bd", "#ff7f0e", "#8c564b"};
    gp << "plot ";
    k = 0;
    // Colour: the intensity; solid: the fit, dashed: the plug-in (one legend entry each, in black).
    for (const auto& [intensity, rows] : by_intensity) {
      const char* c = colours[k % 6];
      char buf[600];
      std::snprintf(buf, sizeof buf,
                    "%s$i%d using 1:2:4 with points pt variable ps 0.6 lc rgb '%s' notitle, NaN with points pt 7 ps 1 lc rgb '%s' title '%s%.2f', "
                    "$c%d using 1:2 with lines lw 2.5 lc rgb '%s' notitle, "
                    "$c%d using 1:3 with lines lw 1.5 dt (8,5) lc rgb '%s' notitle",
                    k ? ", " : "", k, c, c, short_entries ? "I = " : "readings at I = ", intensity, k, c, k, c);
      gp << buf;
      ++k;
    }
    char buf[300];
    std::snprintf(buf, sizeof buf,
                  short_entries ? ", NaN with lines lw 2.5 lc rgb 'black' title 'fit: γ = %.4f m', "
                                "NaN with lines lw 1.5 dt (8,5) lc rgb 'black' title 'plug-in: γ = 0.075 m'"
                              : ", NaN with lines lw 2.5 lc rgb 'black' title 'fit: γ = %.4f m (solid, colour of its I)', "
                                "NaN with lines lw 1.5 dt (8,5) lc rgb 'black' title 'plug-in: γ = 0.075 m (dashed)'",
                  g);
    gp << buf << robot_entries(f.robot_names);
    gp << "\n";
  });
}

void ground_figure(logs::OutputStage& stage, const std::string& path, const calibrate::GroundFit& f) {
  const Sheet page = page_of(path);
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
    // Sideways, so that each robot's cluster stands apart from the others at every grey level (the
    // levels lie 0.1 apart): one robot: the sensors 0.006 apart; several: the robots 0.02 apart
    // (closer when there are more than four, all within 0.07), each robot's sensors 0.005 apart
    // inside its own group.
    const double sensor_step = robots > 1 ? 0.005 : 0.006;
    const double robot_step = robots > 1 ? std::min(0.02, 0.06 / double(robots - 1)) : 0.0;
    for (std::size_t k = 0; k < f.sensors.size(); ++k) {
      std::vector<std::vector<double>> rows;
      for (std::size_t i = 0; i < f.grey[k].size(); ++i) {
        const int robot = i < f.robot[k].size() ? f.robot[k][i] : 0;
        const double shift = (double(k) - 1) * sensor_step + (double(robot) - 0.5 * double(robots - 1)) * robot_step;
        rows.push_back({f.grey[k][i] + shift, f.value_raw[k][i],
                        static_cast<double>(robot_point_type(static_cast<std::size_t>(robot)))});
      }
      gp << datablock("s" + std::to_string(k), rows);
    }
    gp << title_and_key(page, "Ground sensors (paper section 4.1.3): reading against the grey level of the floor",
                        "top left opaque box Left reverse");
    char steps[200];
    if (robots > 1)
      std::snprintf(steps, sizeof steps, page.narrow ? "robots %.3g apart, sensors %.3g" : "each robot's points %.3g apart, its sensors' %.3g",
                    robot_step, sensor_step);
    else
      std::snprintf(steps, sizeof steps, page.narrow ? "sensors %.3g apart" : "each sensor's points %.3g apart", sensor_step);
    gp << "set xlabel "
       << quoted(page.narrow ? wrapped(std::string("grey level (0 black, 1 white; shifted: ") + steps + ")", page.width - 120)
                             : std::string("grey level (fraction: 0 = black, 1 = white; shifted sideways: ") + steps + ")")
       << "\n";
    const models::KindFacts& ground = *models::kind_facts("ground");
    const std::string unit = ground.channels.front().unit;
    gp << "set ylabel "
       << quoted(page.narrow ? "raw reading (" + unit + ")" : "raw reading (" + unit + ", " + ground.channels.front().rails_text() + ")")
       << "\n";
    gp << "set xrange [-0.03:1.03]\nset yrange [-20:1060]\nset grid lc rgb '#d8d8d8'\n";
    const char* colours[] = {"#d62728", "#2ca02c", "#1f77b4"};
    gp << "plot ";
    for (std::size_t k = 0; k < f.sensors.size(); ++k) {
      char buf[500];
      std::snprintf(buf, sizeof buf,
                    "$s%zu using 1:2:3 with points pt variable ps 0.5 lc rgb '%s' notitle, "
                    "$lines using 1:%zu with lines lw 2.5 lc rgb '%s' title 'sensor %s, fit: %.1f + %.1f grey', ",
                    k, colours[k], k + 2, colours[k], ground.sensor_name(k).c_str(), f.sensors[k].value("offset"),
                    f.sensors[k].value("gain"));
      gp << buf;
    }
    gp << "$lines using 1:" << f.sensors.size() + 2 << " with lines lw 2 dt 2 lc rgb '#000000' title 'plug-in: 1023 grey'"
       << robot_entries(f.robot_names) << "\n";
  });
}

void camera_figure(logs::OutputStage& stage, const std::string& path, const calibrate::CameraFit& f) {
  const double fov = s::deg_to_rad(f.result.value("fov_deg")), cx = f.result.value("cx_px"), cy = f.result.value("cy_px");
  const auto plugin = s::plugin_camera();
  const Sheet page = page_of(path);
  std::vector<std::vector<double>> rows;
  for (const auto& o : f.observations) {
    double mx, my, qx, qy;
    s::camera_projection(fov, cx, cy, s::kCameraWidth_px, o.forward_m, o.lateral_m, o.vertical_m, &mx, &my);
    s::camera_projection(plugin.horizontal_fov_rad, plugin.cx_px, plugin.cy_px, s::kCameraWidth_px, o.forward_m, o.lateral_m,
                         o.vertical_m, &qx, &qy);
    // Each robot its own marker and colour (columns 9 and 10: gnuplot's pt and rgb variables).
    static const int kColours[] = {0x1f77b4, 0xff7f0e, 0x2ca02c, 0x9467bd, 0x8c564b, 0xe377c2};
    const auto robot = static_cast<std::size_t>(o.robot);
    rows.push_back({o.lateral_m / o.forward_m, o.px, mx, qx, o.vertical_m / o.forward_m, o.py, my, qy,
                    static_cast<double>(robot_point_type(robot)), static_cast<double>(kColours[robot % 6])});
  }
  std::string robots_legend;  // each robot's marker and colour, named
  for (std::size_t r = 0; r < f.robot_names.size() && f.robot_names.size() > 1; ++r) {
    static const char* kNames[] = {"#1f77b4", "#ff7f0e", "#2ca02c", "#9467bd", "#8c564b", "#e377c2"};
    robots_legend += ", NaN with points pt " + std::to_string(robot_point_type(r)) + " ps 0.8 lc rgb '" + kNames[r % 6] +
                     "' title " + quoted((page.narrow ? "" : "observed, robot ") + f.robot_names[r]);
  }
  const std::string observed = robots_legend.empty() ? " pt 7 ps 0.8 lc rgb '#1f77b4' title 'observed'" : " pt variable ps 0.8 lc rgb variable notitle";
  render(stage, path, [&](gnuplotio::Gnuplot& gp) {
    gp << datablock("obs", rows);
    // A page narrower than the figure's canvas: the title in lines of the page, the legend in a band below.
    const bool banded = page.width < 1400;
    const std::string title = wrapped("Camera (paper section 4.1.6): where the LED appears in the image against its direction",
                                      banded ? page.width - 40.0 : 1e9, 15);
    const Layout layout = two_panels(1 + static_cast<int>(std::count(title.begin(), title.end(), '\n')));
    gp << multiplot(layout, page.narrow ? "" : title);
    // Each panel's size in canvas pixels: its tics, and whether its x label needs two lines.
    const std::pair<int, int> canvas = canvas_px(1400, 900);
    const double panel_w = canvas.first * (layout.right - layout.left - (layout.cols - 1) * layout.hspace) / layout.cols;
    const double panel_h = canvas.second * (layout.top - layout.bottom - (layout.rows - 1) * layout.vspace) / layout.rows;
    // Side by side on a column: the labels' short forms in lines of the panel's width.
    const bool small = page.narrow && layout.cols == 2;
    auto xlabel = [&](const std::string& text) {
      if (banded && !small) return quoted(wrapped(text, panel_w + 40));
      if (!small) return quoted(text);
      return quoted(wrapped(text.substr(0, text.find(" (tangent")) + (text.find("left") != std::string::npos ? " (left > 0)" : " (up > 0)"), panel_w + 40));
    };
    // The x tics: as many as the panel's width holds, over the directions observed.
    auto xtics = [&](std::size_t column) {
      double lo = 0, hi = 0;
      for (const auto& row : rows) {
        lo = std::min(lo, row[column]);
        hi = std::max(hi, row[column]);
      }
      char buf[160];
      // (the range not widened to the next tic: it was, to ±0.4, for directions within ±0.25)
      std::snprintf(buf, sizeof buf, "set autoscale xfix\nset offsets graph 0.05, graph 0.05, 0, 0\nset xtics %g\n",
                    tic_step(lo, hi, small ? 2 : tics_that_fit(panel_w, 55)));
      return std::string(buf);
    };
    check_panel_height(path, panel_h, layout.rows);
    const std::string yticks = "set ytics " + std::to_string(static_cast<int>(tic_step(0, 160, tics_that_fit(panel_h, 35)))) + "\n";
    gp << "set grid lc rgb '#d8d8d8'\n";
    // A paper's column: the legend in a band under the panels.
    gp << (banded ? "unset key\n" : "set key top right opaque box Left reverse\n");
    gp << "set title 'columns' font ',12'\n";
    gp << "set xlabel " << xlabel(page.narrow ? "lateral / forward (tangent, left > 0)" : "lateral / forward (tangent of the horizontal angle, dimensionless; left > 0)") << "\n";
    gp << "set ylabel " << quoted(page.narrow ? "column px (pixels)" : "column px (pixels, 0..159)") << "\nset yrange [-5:165]\n" << yticks << xtics(0);
    gp << "plot $obs using 1:2" << (robots_legend.empty() ? "" : ":9:10") << " with points" << observed << ", "
       << "$obs using 1:3 with lines lw 2.5 lc rgb '#d62728' title 'fit', "
       << "$obs using 1:4 with lines lw 2 dt (8,5) lc rgb '#000000' title "
       << quoted(page.narrow ? "plug-in" : "plug-in (29.97° field of view, centre 80)") << robots_legend << "\n";
    gp << "set title 'rows' font ',12'\n";
    gp << "set xlabel " << xlabel(page.narrow ? "vertical / forward (tangent, up > 0)" : "vertical / forward (tangent of the vertical angle, dimensionless; up > 0)") << "\n";
    gp << "set ylabel " << quoted(page.narrow ? "row py (pixels)" : "row py (pixels, 0..119)") << "\nset yrange [-5:125]\n" << yticks << xtics(4);
    gp << "plot $obs using 5:6" << (robots_legend.empty() ? "" : ":9:10") << " with points" << observed << ", "
       << "$obs using 5:7 with lines lw 2.5 lc rgb '#d62728' title 'fit', "
       << "$obs using 5:8 with lines lw 2 dt (8,5) lc rgb '#000000' title 'plug-in (centre 60)'" << robots_legend << "\n";
    if (banded) {
      std::vector<std::string> entries{"NaN with lines lw 2.5 lc rgb '#d62728' title 'fit'",
                                       "NaN with lines lw 2 dt (8,5) lc rgb '#000000' title 'plug-in'"};
      if (robots_legend.empty()) entries.insert(entries.begin(), "NaN with points pt 7 ps 0.8 lc rgb '#1f77b4' title 'observed'");
      std::size_t at = 0;  // each robot's entry, from the panels' list
      while ((at = robots_legend.find(", NaN", at)) != std::string::npos) {
        const std::size_t next = robots_legend.find(", NaN", at + 1);
        entries.push_back(robots_legend.substr(at + 2, next == std::string::npos ? std::string::npos : next - at - 2));
        at += 1;
      }
      const double height = canvas_px(1400, 900).second;
      gp << legend_band(0.02, 0.98, 0.0, 60.0 / height, entries, 9, 2);
    }
    gp << "unset multiplot\n";
  });
}

std::string drive_fit_legend(double steps_per_m, bool narrow) {
  char text[96];
  if (narrow) std::snprintf(text, sizeof text, "fit (%.1f steps/m)", steps_per_m);
  else std::snprintf(text, sizeof text, "fit (%.3f steps/m), clipped at the rails", steps_per_m);
  return text;
}

std::string drive_plugin_legend(bool narrow) {
  char text[96];
  if (narrow) return "plug-in";
  std::snprintf(text, sizeof text, "plug-in (%.3f steps/m, no slip)", s::kPluginStepsPerMetre);
  return text;
}

void drive_figure(logs::OutputStage& stage, const std::string& path, const calibrate::DriveFit& f) {
  const double spm = f.steps.value("steps_per_m");
  const double scale = f.tof.value(models::effects::file_key(models::effects::drive_catalogue(), models::effects::drive::tof_scale)), offset = f.tof.value("tof_offset_mm"), tau = f.tof.value("slip_time_constant_s");
  constexpr double kOutOfRangeCode_mm = logs::kTofOutOfRangeCode_mm, kCodeRow_mm = 2250;
  const models::Channel& tof = models::kind_facts("drive")->channels.front();  // its rails
  char rail_mm[16];
  std::snprintf(rail_mm, sizeof rail_mm, "%g", tof.high_rail);
  const double kNaN = std::numeric_limits<double>::quiet_NaN();
  // The curves as the sensor reports them: clamped to its rails (20 and 2000 mm), never drawn
  // above the 2000 mm a reading cannot exceed.
  auto on_rails = [](double mm) { return std::clamp(mm, s::kPluginTof.min_mm, s::kPluginTof.max_mm); };

  // Small multiples: one panel per commanded speed (as logged, to 0.1 cm/s; both directions and
  // every robot in it), the ToF against time; the runs standing still in one panel against the
  // obstacle's distance (time says nothing there); the encoders of every run in the last panel,
  // against the commanded distance (steps_per_m is their slope).
  std::vector<std::string> robots;
  std::map<long, std::vector<std::size_t>> by_speed;  // speed in mm/s -> runs
  std::vector<std::size_t> still;
  std::vector<int> direction(f.runs.size(), 0), robot_of(f.runs.size(), 0);
  for (std::size_t r = 0; r < f.runs.size(); ++r) {
    const auto& run = f.runs[r];
    double top = 0;
    for (double c : run.command_uncapped_m_s)
      if (std::abs(c) > std::abs(top)) top = c;
    direction[r] = top > 0 ? 1 : top < 0 ? -1 : 0;
    const auto named = std::find(robots.begin(), robots.end(), run.robot);
    robot_of[r] = static_cast<int>(named - robots.begin());
    if (named == robots.end()) robots.push_back(run.robot);
    const long mm_s = std::lround(std::abs(top) * 1000);
    if (mm_s == 0) still.push_back(r);
    else by_speed[mm_s].push_back(r);
  }
  const std::size_t panels = by_speed.size() + (still.empty() ? 0 : 1) + 1;
  // The canvas: 4 panels a row on the figure's own 1600 pixels, fewer on a page narrower.
  const int default_cols = static_cast<int>(std::min<std::size_t>(4, panels));
  const int default_rows = static_cast<int>((panels + static_cast<std::size_t>(default_cols) - 1) / static_cast<std::size_t>(default_cols));
  const std::pair<int, int> canvas = canvas_px(1600, 190 + default_rows * 330);
  const int width = canvas.first, height = canvas.second;
  // A page narrower than 1200 of its canvas pixels (two columns at 8 pt: 915): short titles and
  // labels, no overall title (the caption's), the legend in short entries.
  const bool narrow = width < 1200;
  // Panels at least 200 canvas pixels wide (a two-column page holds 4 a row, one column 2).
  const int cols = std::max(1, std::min(default_cols, (width - 40) / 200));
  const int rows = static_cast<int>((panels + static_cast<std::size_t>(cols) - 1) / static_cast<std::size_t>(cols));
  // Vector files stay small: every drawn reading is an element of an SVG (all 1800 of the
  // reference set, each drawn in its speed's panel and again in the encoders', made a 0.5 MB SVG);
  // there, at most 25 rows a run (every stride-th, and the last), and the legend says so. The
  // curves go through the same rows: a run's fit is smooth on that scale.
  const bool vector = format_of(path) != Format::png;
  const std::size_t per_run = vector ? 25 : std::numeric_limits<std::size_t>::max();
  std::size_t thinned = 0;
  for (const auto& run : f.runs) thinned += run.time_s.size() > per_run;

  // The legend's entries, in as many columns as fit across.
  std::size_t codes = 0;
  for (const auto& run : f.runs)
    for (double mm : run.tof_mm) codes += mm >= kOutOfRangeCode_mm;
  const std::size_t entry_count = 5 + (still.empty() ? 0 : 1) + (codes > 0 ? 1 : 0) + (robots.size() > 1 ? robots.size() : 0) + (thinned > 0 ? 1 : 0);
  // (gnuplot gives every column the longest entry's width and drops a column that overflows.)
  const std::size_t legend_cols = std::max<std::size_t>(1, static_cast<std::size_t>(width) / (narrow ? 210 : 440));
  const int legend_rows = static_cast<int>((entry_count + legend_cols - 1) / legend_cols);
  // From the top: the title (none on a paper's column: the caption's), the legend, the first
  // panels' titles. Between rows: the tics, the x label (none on a column's time panels: their
  // titles say "time (s)"), the next titles.
  // (a column's titles 48 pixels: the svg terminal sets a title's line 33 pixels above its panel)
  const double top_px = (narrow ? 10.0 : 60.0) + legend_rows * 22.0 + (narrow ? 48.0 : 35.0);
  Layout layout;
  layout.rows = rows;
  layout.cols = cols;
  // (the svg terminal reckons the tics' "2000" wider than it draws, and leaves out a y label that
  // its reckoning puts left of the canvas: at 70 pixels the SVG lost the ToF panels' labels)
  layout.left = 85.0 / width;
  // (a column's: 30 pixels, which its right panels' titles, wider than the panels, reach into)
  layout.right = 1.0 - (narrow ? 30.0 : 15.0) / width;
  layout.bottom = 60.0 / height;
  layout.top = 1.0 - top_px / height;
  layout.hspace = (narrow ? 110.0 : 105.0) / width;  // the encoders' 6-digit tics and their label
  layout.vspace = (narrow ? 85.0 : 100.0) / height;  // (the svg terminal's titles stand 33 pixels above their panel)
  const double panel_px = (height * (layout.top - layout.bottom) - (rows - 1) * height * layout.vspace) / rows;
  const std::string tof_label = narrow ? "ToF (mm)" : "ToF reading (mm)";
  const double panel_w_px = (width * (layout.right - layout.left) - (cols - 1) * width * layout.hspace) / cols;
  check_panel_height(path, panel_px, rows);

  const char* kToward = "#1f77b4";  // forward, toward the obstacle
  const char* kAway = "#2ca02c";    // backwards
  const char* kStill = "#7f7f7f";
  auto colour = [&](std::size_t r) { return direction[r] > 0 ? kToward : direction[r] < 0 ? kAway : kStill; };
  render(
      stage, path,
      [&](gnuplotio::Gnuplot& gp) {
        // Every run's rows: time, reading (NaN for a code), fit, plug-in, steps, commanded steps,
        // the code's row, the robot's marker, the commanded distance (mm), the obstacle (mm).
        for (std::size_t r = 0; r < f.runs.size(); ++r) {
          const auto& run = f.runs[r];
          const std::vector<double> travel = calibrate::lagged_travel_m(run, spm, tau);
          const std::vector<double> enc = calibrate::lagged_travel_m(run, s::kPluginStepsPerMetre, 0.0);
          std::vector<std::vector<double>> rows_of_run;
          double commanded = 0;
          const std::size_t stride = std::max<std::size_t>(1, (run.time_s.size() + per_run - 1) / per_run);
          for (std::size_t k = 0; k < run.time_s.size(); ++k) {
            const bool drawn = k % stride == 0 || k + 1 == run.time_s.size();  // a vector file: every stride-th row, and the last
            if (!drawn) {
              if (k + 1 < run.time_s.size()) commanded += run.command_m_s[k] * (run.time_s[k + 1] - run.time_s[k]);
              continue;
            }
            // The VL53L0X's out-of-range codes (>= 8190) are no distance: drawn apart, at the top.
            const bool code = run.tof_mm[k] >= kOutOfRangeCode_mm;
            rows_of_run.push_back({run.time_s[k], code ? kNaN : run.tof_mm[k],
                                   on_rails(s::tof_response_mm(scale, offset, run.obstacle_distance_m - travel[k])),
                                   on_rails(s::tof_response_mm(1.0, 0.0, run.obstacle_distance_m - enc[k])), run.steps[k],
                                   spm * commanded, code ? kCodeRow_mm : kNaN,
                                   static_cast<double>(robot_point_type(static_cast<std::size_t>(robot_of[r]))), commanded * 1000,
                                   run.obstacle_distance_m * 1000});
            if (k + 1 < run.time_s.size()) commanded += run.command_m_s[k] * (run.time_s[k + 1] - run.time_s[k]);
          }
          gp << datablock("r" + std::to_string(r), rows_of_run);
        }
        const std::string title = "Drive runs (paper sections 4.1.4 and 4.1.5): the time-of-flight sensor per commanded speed, and the wheel encoders";
        gp << multiplot(layout, narrow ? "" : title, 14);
        gp << "set grid lc rgb '#e0e0e0'\nunset key\n";
        // The 2000 mm rail, dotted: no reading (and no curve) lies above it.
        const std::string rail = std::string("set arrow 1 from graph 0, first ") + rail_mm + " to graph 1, first " + rail_mm +
                                 " nohead dt 3 lc rgb '#808080'\n";
        int index = 0;
        auto axes_labels = [&](const std::string& x, const std::string& y) {
          // The ToF's y label on each row's first panel, the encoders' on theirs; the x label on
          // every panel (their axes differ).
          gp << "set xlabel " << quoted(x) << " offset 0,0.3\n";
          gp << (index % cols == 0 || y != tof_label ? "set ylabel " + quoted(y) + (y == tof_label ? " offset 1,0\n" : "\n")
                                                     : std::string("unset ylabel\n"));
          ++index;
        };
        for (const auto& [mm_s, runs] : by_speed) {
          char t[96];
          std::snprintf(t, sizeof t, "%g cm/s: %zu run%s", static_cast<double>(mm_s) / 10.0,
                        runs.size(), runs.size() == 1 ? "" : "s");
          if (narrow) std::snprintf(t, sizeof t, "%g cm/s, x: time (s)", static_cast<double>(mm_s) / 10.0);
          gp << "set title " << quoted(t) << " font ',11'\n";
          axes_labels(narrow ? "" : "time (s)", tof_label);
          // Tics as many as the panel's width holds (gnuplot's own crowded "0 2 4 6 8 101214").
          double t_end = 0;
          for (std::size_t r : runs)
            if (!f.runs[r].time_s.empty()) t_end = std::max(t_end, f.runs[r].time_s.back());
          gp << rail << "set yrange [0:2400]\nset xrange [0:" << 1.02 * std::max(1.0, t_end) << "]\nset ytics " << (panel_px < 150 ? 1000 : 500) << "\nset xtics "
             << tic_step(0, std::max(1.0, t_end), std::min(6, tics_that_fit(panel_w_px, 45))) << "\n";
          std::string plot = "plot ";
          for (std::size_t r : runs) {
            const std::string d = "$r" + std::to_string(r);
            plot += (plot.size() > 5 ? ", " : "") + d + " using 1:2:8 with points pt variable ps 0.5 lc rgb '" + colour(r) +
                    "' notitle, " + d + " using 1:7 with points pt 9 ps 0.8 lc rgb '#ff7f0e' notitle";
          }
          for (std::size_t r : runs)  // the curves over the readings
            plot += ", $r" + std::to_string(r) + " using 1:3 with lines lw 1.5 lc rgb '#d62728' notitle, $r" + std::to_string(r) +
                    " using 1:4 with lines lw 1.2 dt 2 lc rgb '#000000' notitle";
          gp << plot << "\n";
        }
        if (!still.empty()) {
          gp << "set title " << quoted("standing still: " + std::to_string(still.size()) + " run" + (still.size() == 1 ? "" : "s")) << " font ',11'\n";
          axes_labels(narrow ? "obstacle (mm)" : "distance to the obstacle (mm)", tof_label);
          // Readings spread sideways by their time (±20 mm over the run) so that they do not stack.
          double lo = 1e300, hi = -1e300;
          for (std::size_t r : still) {
            lo = std::min(lo, f.runs[r].obstacle_distance_m * 1000);
            hi = std::max(hi, f.runs[r].obstacle_distance_m * 1000);
          }
          const double pad = std::max(100.0, 0.2 * (hi - lo));
          std::vector<std::vector<double>> line;  // the fitted response and the plug-in's, without travel
          for (double mm : samples(lo - pad, hi + pad, 100))
            line.push_back({mm, on_rails(s::tof_response_mm(scale, offset, mm / 1000)), on_rails(s::tof_response_mm(1.0, 0.0, mm / 1000))});
          gp << datablock("still", line);
          double ylo = 1e300, yhi = -1e300;  // the readings' range: as many tics as the panel holds
          for (std::size_t r : still)
            for (double mm : f.runs[r].tof_mm)
              if (mm < kOutOfRangeCode_mm) {
                ylo = std::min(ylo, mm);
                yhi = std::max(yhi, mm);
              }
          for (const auto& row : line) {
            ylo = std::min({ylo, row[1], row[2]});
            yhi = std::max({yhi, row[1], row[2]});
          }
          gp << "unset arrow 1\nset xrange [" << lo - pad << ":" << hi + pad << "]\nset yrange [*:*]\nset ytics "
             << tic_step(ylo, yhi, tics_that_fit(panel_px, 35)) << "\nset xtics " << tic_step(lo - pad, hi + pad, tics_that_fit(panel_w_px, 60))
             << "\n";
          std::string plot = "plot $still using 1:2 with lines lw 2 lc rgb '#d62728' notitle, $still using 1:3 with lines lw 1.5 dt 2 lc rgb '#000000' notitle";
          for (std::size_t r : still) {
            const double span = std::max(1e-9, f.runs[r].time_s.empty() ? 1.0 : f.runs[r].time_s.back());
            char spread[64];
            std::snprintf(spread, sizeof spread, "($10 + 40 * ($1 / %.6g - 0.5))", span);
            plot += ", $r" + std::to_string(r) + " using " + spread + ":2:8 with points pt variable ps 0.4 lc rgb '" + kStill + "' notitle";
          }
          gp << plot << "\n";
        }
        gp << "unset arrow 1\n";
        // (a column's panel is about 120 canvas pixels wide: its title one word, the thinning in the legend)
        gp << "set title " << quoted(narrow ? "encoders" : "wheel encoders: every run") << " font ',11'\n";
        axes_labels(narrow ? "commanded (mm)" : "commanded distance (mm)", "encoder steps");
        gp << "set xrange [*:*]\nset yrange [*:*]\n";
        {
          std::string plot = "plot $steps using 1:2 with lines lw 2 lc rgb '#d62728' notitle, $steps using 1:3 with lines lw 1.5 dt 2 lc rgb '#000000' notitle";
          for (std::size_t r = 0; r < f.runs.size(); ++r)
            plot += ", $r" + std::to_string(r) + " using 9:5:8 with points pt variable ps 0.5 lc rgb '" + colour(r) + "' notitle";
          double lo = 0, hi = 0;
          for (const auto& run : f.runs) {
            double c = 0;
            for (std::size_t k = 0; k + 1 < run.time_s.size(); ++k) {
              c += run.command_m_s[k] * (run.time_s[k + 1] - run.time_s[k]);
              lo = std::min(lo, c * 1000);
              hi = std::max(hi, c * 1000);
            }
          }
          gp << datablock("steps", {{lo, spm * lo / 1000, s::kPluginStepsPerMetre * lo / 1000}, {hi, spm * hi / 1000, s::kPluginStepsPerMetre * hi / 1000}});
          // The ranges by hand: runs that stand still alone leave every point at 0 (an empty range).
          double ylo = std::min({0.0, spm * lo / 1000, s::kPluginStepsPerMetre * lo / 1000});
          double yhi = std::max({0.0, spm * hi / 1000, s::kPluginStepsPerMetre * hi / 1000});
          for (const auto& run : f.runs)
            for (double v : run.steps) {
              ylo = std::min(ylo, v);
              yhi = std::max(yhi, v);
            }
          const double xpad = std::max(1.0, 0.03 * (hi - lo)), ypad = std::max(1.0, 0.03 * (yhi - ylo));
          gp << "set xrange [" << lo - xpad << ":" << hi + xpad << "]\nset yrange [" << ylo - ypad << ":" << yhi + ypad << "]\n";
          // (on a column's panel, 110 pixels wide, "-2000" and "-1000" touched at three tics: there
          // a tic every 50 canvas pixels at most, two at least)
          gp << "set xtics " << tic_step(lo, hi, narrow ? std::max(2, static_cast<int>(panel_w_px / 50)) : tics_that_fit(panel_w_px, 70)) << "\nset ytics " << tic_step(ylo, yhi, tics_that_fit(panel_px, 35)) << "\n";
          gp << plot << "\n";
        }
        std::vector<std::string> entries{
            std::string("NaN with points pt 7 ps 0.8 lc rgb '") + kToward + "' title " + (narrow ? "'forward'" : "'forward (toward the obstacle)'"),
            std::string("NaN with points pt 7 ps 0.8 lc rgb '") + kAway + "' title " + (narrow ? "'backwards'" : "'backwards (away)'"),
            std::string("NaN with lines lw 2 lc rgb '#d62728' title ") + quoted(drive_fit_legend(spm, narrow)),
            std::string("NaN with lines lw 1.5 dt 2 lc rgb '#000000' title ") + quoted(drive_plugin_legend(narrow)),
            std::string("NaN with lines dt 3 lc rgb '#808080' title 'the ") + rail_mm + " " + tof.unit + " rail'"};
        if (thinned > 0)
          entries.push_back(std::string("NaN with dots lc rgb '#ffffff' title ") +
                            (narrow ? "'≤ 25 readings/run drawn'" : "'at most 25 readings a run drawn (every n-th)'"));
        if (!still.empty()) entries.insert(entries.begin() + 2, std::string("NaN with points pt 7 ps 0.8 lc rgb '") + kStill + "' title 'standing still'");
        if (codes > 0)
          entries.push_back(narrow ? "NaN with points pt 9 ps 1 lc rgb '#ff7f0e' title 'no-target code (2250)'"
                                   : "NaN with points pt 9 ps 1 lc rgb '#ff7f0e' title 'out-of-range codes (≥ " +
                                         std::to_string(static_cast<int>(kOutOfRangeCode_mm)) + "), drawn at 2250 mm'");
        for (std::size_t r = 0; r < robots.size() && robots.size() > 1; ++r)
          entries.push_back("NaN with points pt " + std::to_string(robot_point_type(r)) + " ps 0.9 lc rgb '#000000' title " + quoted("robot " + robots[r]));
        const double band_top = 1.0 - (narrow ? 10.0 : 55.0) / height;
        gp << legend_band(0.01, 0.99, band_top - legend_rows * 22.0 / height, band_top, entries, narrow ? 9 : 10, legend_rows);
        gp << "unset multiplot\n";
      },
      width, height);
}

}  // namespace epuck2::plot
