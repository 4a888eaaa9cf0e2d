#include "epuck2/plot/battery_figures.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <tuple>

#include "epuck2/models/plugin_battery_tables.hpp"
#include "epuck2/plot/figure.hpp"

namespace epuck2::plot {

namespace mb = models::battery;

namespace {
// The four models, each with its own colour, dash pattern and point type, so that they stay
// apart where they overlap (Simple and Linear coincide at 0 cm/s, Cubic and Approximated nearly
// everywhere) and in grey print; their markers at different intervals, so that they do not
// stack.
struct ModelStyle {
  const char* title;
  const char* style;
};
constexpr ModelStyle kStyles[] = {
    {"simple (two slopes)", "lw 2 lc rgb '#d62728' dt (14,7) pt 4 ps 1.1 pi 75"},
    {"linear (1 → 0 over the lifetime)", "lw 2 lc rgb '#1f77b4' dt (4,5) pt 6 ps 1.1 pi 62"},
    {"cubic", "lw 2.5 lc rgb '#2ca02c' dt 1 pt 7 ps 0.8 pi 50"},
    {"approximated (piecewise linear)", "lw 2 lc rgb '#9467bd' dt (12,5,2,5) pt 9 ps 1.2 pi 43"},
};
}  // namespace

void battery_fits_figure(logs::OutputStage& stage, const std::string& path, const std::vector<calibrate::BatteryRun>& runs,
                         const calibrate::BatteryFit& f) {
  const int n = static_cast<int>(f.speeds.size());
  int cols = n <= 4 ? std::max(n, 1) : 4;
  int rows = (n + cols - 1) / cols;
  // At least 1300 x 600: the title and the one-row legend fit over one or two speeds' panels.
  const std::pair<int, int> canvas = canvas_px(std::max(450 * cols + 100, 1300), std::max(330 * rows + 170, 600));
  const int width = canvas.first, height = canvas.second;
  // Narrower than 1700 pixels, the legend takes three rows and the title its short form; on a
  // paper's column (narrower than kNarrowCanvas_px) no title (the caption's) and the legend in
  // two columns.
  const bool narrow = width < 1700;
  const bool one_column = width < kNarrowCanvas_px;
  const bool paged = page().width_in > 0 || page().font_pt > 0;  // --figure-size or --font-size
  std::size_t robot_count = 0;
  {
    std::vector<std::string> seen;
    for (const auto& r : runs)
      if (std::find(seen.begin(), seen.end(), r.robot) == seen.end()) seen.push_back(r.robot);
    robot_count = seen.size() > 1 ? seen.size() : 0;
  }
  const int one_column_legend_rows = static_cast<int>((5 + robot_count + 1) / 2);
  // A page (--figure-size, --font-size): the columns that give the panels the most room (the
  // smaller of their width and 1.6 times their height), so that 16 speeds on a short page are
  // not one column of panels a few pixels high; each panel keeps room for its tics.
  if (paged) {
    double best = -1;
    for (int c = 1; c <= std::min(n, 6); ++c) {
      const int r = (n + c - 1) / c;
      const double top = one_column ? 10.0 + 25.0 * one_column_legend_rows + 35.0 : 160.0;
      // Panels touching (tics and labels on the outer ones alone, the speed inside each panel).
      const double w = (width - 135.0 - (c - 1) * 12.0) / c, h = (height - top - 75.0 - (r - 1) * 12.0) / r;
      if (std::min(w, 1.6 * h) > best) {
        best = std::min(w, 1.6 * h);
        cols = c;
      }
    }
  }
  rows = (n + cols - 1) / cols;
  // On a page, several rows of panels share their axes (small multiples): the time's tics under
  // the lowest panel of each column, the charge's left of the first, the speed and lifetime
  // written inside each panel; 16 speeds' titles and tics took all of a 10 cm page's height.
  const bool shared_axes = paged && rows > 1;
  const double top_px = one_column ? 10.0 + 25.0 * one_column_legend_rows + (shared_axes ? 10.0 : 35.0)
                        : shared_axes ? 115.0
                        : narrow && rows * cols == n ? 160.0 : narrow ? 115.0 : 135.0;  // narrow: the legend may stack
  Layout layout;
  layout.rows = rows;
  layout.cols = cols;
  layout.left = (narrow ? 115.0 : 60.0) / width;
  layout.right = 1.0 - 20.0 / width;
  layout.bottom = (narrow ? 75.0 : 50.0) / height;
  layout.top = 1.0 - top_px / height;  // the title, then the legend (two rows at most), then the first row's titles
  layout.hspace = (shared_axes ? 12.0 : 95.0) / width;
  layout.vspace = (shared_axes ? 12.0 : 85.0) / height;
  // Every panel on one time axis: to the longest run or lifetime, so that speeds compare at a glance.
  double t_max_h = 0;
  for (const auto& r : runs)
    if (!r.time_s.empty()) t_max_h = std::max(t_max_h, r.time_s.back() / 3600.0);
  for (const auto& s : f.speeds) t_max_h = std::max(t_max_h, s.lifetime_s / 3600.0);
  // Vector files stay small: every drawn point is an element of an SVG (400 a run made a 2.2 MB
  // SVG of the reference set); there, each run's readings (at most 150) are one thin line, and
  // the curves 150 samples; the legend says so.
  const bool vector = format_of(path) != Format::png;
  const std::size_t per_run = vector ? 150 : 400;
  const int curve_samples = vector ? 150 : 300;
  // Logs of several robots: each robot its marker (PNG) or its colour (a vector file's lines).
  std::vector<std::string> robots;
  for (const auto& r : runs)
    if (std::find(robots.begin(), robots.end(), r.robot) == robots.end()) robots.push_back(r.robot);
  static const int kRobotColours[] = {0x707070, 0xc07830, 0x5f8fbf, 0x8c564b};
  static const char* kRobotColourNames[] = {"#707070", "#c07830", "#5f8fbf", "#8c564b"};
  render(
      stage, path,
      [&](gnuplotio::Gnuplot& gp) {
        gp << multiplot(layout, one_column ? "" : narrow ? "Battery discharge per wheel speed" : "Battery discharge per wheel speed: the logs and the four fitted models");
        const double panel_w_px = width * (layout.right - layout.left - (cols - 1) * layout.hspace) / cols;
        const double panel_h_px = height * (layout.top - layout.bottom - (rows - 1) * layout.vspace) / rows;
        check_panel_height(path, panel_h_px, rows);
        char xrange[64];
        std::snprintf(xrange, sizeof xrange, "set xrange [0:%.4g]\n", t_max_h > 0 ? 1.02 * t_max_h : 1.0);
        // Tics as many as a panel holds (gnuplot's own crowded on a page's small panels).
        gp << "set grid lc rgb '#dddddd'\nset yrange [0:1.05]\nset ytics " << (narrow ? tic_step(0, 1, tics_that_fit(panel_h_px, 35)) : 0.25)
           << "\n" << xrange << "set xtics " << tic_step(0, t_max_h > 0 ? t_max_h : 1.0, std::min(6, tics_that_fit(panel_w_px, 45)))
           << "\nset key off\n";
        for (int i = 0; i < n; ++i) {
          // Axis labels once: the charge on the first column, the time under each column's last panel.
          if (shared_axes)  // one charge label, on the middle row, for all the rows
            gp << (i == (rows / 2) * cols ? "set ylabel 'charge (fraction of full)' offset 1.5,0\n" : "unset ylabel\n");
          else
          gp << (i % cols == 0 ? (narrow && rows > 2 ? "set ylabel 'charge (of full)' offset 1.5,0\n" : "set ylabel 'charge (fraction of full)' offset 1.5,0\n")
                               : "unset ylabel\n");
          gp << (i + cols >= n ? "set xlabel 'time (h)' offset 0,0.5\n" : "unset xlabel\n");
          if (shared_axes)
            gp << (i + cols >= n ? "set format x '% g'\n" : "set format x ''\n") << (i % cols == 0 ? "set format y '% g'\n" : "set format y ''\n");
          const calibrate::SpeedFit& s = f.speeds[static_cast<std::size_t>(i)];
          std::vector<std::tuple<double, double, double, double>> pts;  // time, charge, marker, colour
          for (const auto& r : runs) {
            if (std::lround(r.speed_cm_s * 100) != std::lround(s.speed_cm_s * 100)) continue;
            const std::size_t stride = std::max<std::size_t>(1, (r.time_s.size() + per_run - 1) / per_run);
            const auto robot = static_cast<std::size_t>(std::find(robots.begin(), robots.end(), r.robot) - robots.begin());
            for (std::size_t k = 0; k < r.time_s.size(); k += stride)
              pts.emplace_back(r.time_s[k] / 3600.0, r.charge[k], robot_point_type(robot), kRobotColours[robot % 4]);
            pts.emplace_back(std::nan(""), std::nan(""), 7, 0x707070);  // the line of one run ends
          }
          std::vector<std::vector<std::tuple<double, double>>> curves(4);
          const int kSamples = curve_samples;
          for (int k = 0; k <= kSamples; ++k) {
            const double t = s.lifetime_s * k / kSamples;
            int m = 0;
            for (mb::Model model : mb::kAllModels)
              curves[static_cast<std::size_t>(m++)].emplace_back(t / 3600.0, calibrate::analytic_charge(s, f, model, t));
          }
          char title[128];
          std::snprintf(title, sizeof title, "%g cm/s: lifetime %.2f h, %zu run%s", s.speed_cm_s, s.lifetime_s / 3600.0, s.runs,
                        s.runs == 1 ? "" : "s");
          if (panel_w_px < 200)  // a small panel: speed and lifetime
            std::snprintf(title, sizeof title, "%g cm/s, %.2f h", s.speed_cm_s, s.lifetime_s / 3600.0);
          else if (narrow && n > 1)  // a page: the short form
            std::snprintf(title, sizeof title, "%g cm/s: %.2f h, %zu run%s", s.speed_cm_s, s.lifetime_s / 3600.0, s.runs,
                          s.runs == 1 ? "" : "s");
          if (shared_axes) {  // the speed and lifetime inside the panel, top right
            std::snprintf(title, sizeof title, "%g cm/s, %.2f h", s.speed_cm_s, s.lifetime_s / 3600.0);
            // On a panel too narrow for it to stand clear of the curves (a column's: about 100
            // canvas pixels, the label 90), speed over lifetime in the top right corner, where
            // every speed's discharge has left the charge below one half.
            const bool two_lines = text_px(title, 9) > 0.6 * panel_w_px;
            if (two_lines) std::snprintf(title, sizeof title, "%g cm/s\n%.2f h", s.speed_cm_s, s.lifetime_s / 3600.0);
            gp << "unset title\nset label 1 " << quoted(title) << " at graph 0.97," << (two_lines ? "0.8" : "0.9") << " right front font ',9'\n";
          } else {
            gp << "set title " << quoted(title) << " font ',11' offset 0,-0.3\n";
          }
          // The models first, the logs over them: the readings stay visible where the curves lie.
          gp << "plot ";
          for (const auto& st : kStyles) gp << (&st == kStyles ? "" : ", ") << "'-' with linespoints " << st.style << " notitle";
          gp << (vector ? ", '-' using 1:2:4 with lines lw 0.8 lc rgb variable notitle\n"
                        : ", '-' using 1:2:3:4 with points pt variable ps 0.3 lc rgb variable notitle\n");
          for (const auto& c : curves) gp.send1d(c);
          gp.send1d(pts);
        }
        // One legend for all panels, across the top under the overall title.
        // On a narrow page the entries' first words alone (the long forms are in docs/cli.md).
        std::vector<std::string> entries{
            vector ? std::string("NaN with lines lw 1 lc rgb '#707070' title ") +
                         quoted(narrow ? "logs (a line a run)" : "logs (a line through ≤ 150 readings a run)")
                   : std::string("NaN with points pt 7 ps 1 lc rgb '#707070' title ") +
                         quoted(narrow ? "logs (≤ 400 readings a run)" : "logs (at most 400 readings a run drawn)")};
        for (std::size_t r = 0; r < robots.size() && robots.size() > 1; ++r)
          entries.push_back(vector ? std::string("NaN with lines lw 2 lc rgb '") + kRobotColourNames[r % 4] + "' title " + quoted("robot " + robots[r])
                                   : "NaN with points pt " + std::to_string(robot_point_type(r)) + " ps 1 lc rgb '" + kRobotColourNames[r % 4] +
                                         "' title " + quoted("robot " + robots[r]));
        for (const auto& st : kStyles) {
          const std::string name = st.title;
          entries.push_back(std::string("NaN with linespoints ") + st.style + " title " +
                            quoted(narrow ? name.substr(0, name.find(' ')) : name));
        }
        // A narrow page with empty panel slots at the end: the legend fills them.
        const int empty = rows * cols - n;
        if (narrow && !one_column && !shared_axes && empty > 0) {
          const double panel_w = (layout.right - layout.left - (cols - 1) * layout.hspace) / cols;
          const double panel_h = (layout.top - layout.bottom - (rows - 1) * layout.vspace) / rows;
          gp << legend_band(layout.left + (cols - empty) * (panel_w + layout.hspace), layout.right, layout.bottom,
                            layout.bottom + panel_h, entries, 11, static_cast<int>(entries.size()));
        } else if (one_column) {
          gp << legend_band(0.01, 0.99, 0.0, 1.0 - 10.0 / height, entries, 10, one_column_legend_rows);
        } else if (shared_axes) {
          gp << legend_band(0.02, 0.98, 0.0, 1.0 - 45.0 / height, entries, 10, 2);
        } else {
          gp << legend_band(0.02, 0.98, 1.0 - (top_px - 40.0) / height, 1.0 - 42.0 / height, entries, 11, 2);
        }
        gp << "unset multiplot\n";
      },
      width, height);
}

void battery_lifetime_figure(logs::OutputStage& stage, const std::string& path, const std::vector<calibrate::BatteryRun>& runs,
                             const calibrate::BatteryFit& f) {
  // A paper's column (narrower than 1200 of the canvas's pixels, as the drive figure's): no title
  // (the caption's), the legend in short entries below the panel, a tic every 3 cm/s.
  const std::pair<int, int> canvas = canvas_px(1200, 800);
  const bool narrow = canvas.first < 1200;
  render(
      stage, path,
      [&](gnuplotio::Gnuplot& gp) {
        std::vector<std::tuple<double, double>> each;
        for (const auto& r : runs) each.emplace_back(r.speed_cm_s, r.lifetime_s / 3600.0);
        std::vector<std::tuple<double, double, double>> mean;
        for (const auto& s : f.speeds) mean.emplace_back(s.speed_cm_s, s.lifetime_s / 3600.0, s.lifetime_std_error_s / 3600.0);
        std::vector<std::tuple<double, double>> published;
        const mb::Tables& pt = mb::plugin_tables();
        for (int s = 0; s < mb::kSpeedCount; ++s) published.emplace_back(s, pt.lifetime_s[static_cast<std::size_t>(s)] / 3600.0);
        if (!narrow) gp << "set title 'Battery lifetime against wheel speed (robot spinning in place)' font ',14'\n";
        gp << "set xlabel 'wheel speed (cm/s)'\nset ylabel 'lifetime (h)'\nset grid lc rgb '#dddddd'\n";
        gp << (narrow ? "set key below left Left reverse maxcols 1\n" : "set key bottom right box opaque\n");
        gp << "set xrange [-0.5:15.5]\nset yrange [0:*]\nset xtics " << (narrow ? 3 : 1) << "\n";
        gp << "plot '-' with points pt 7 ps 1.2 lc rgb '#999999' title 'each run', "
              "'-' with yerrorlines pt 5 ps 1.2 lw 2 lc rgb '#1f77b4' title "
           << (narrow ? "'mean of the runs (± s.e.)'" : "'mean of the runs (± standard error)'")
           << ", '-' with linespoints dt (8,5) pt 6 ps 1.4 lw 2 lc rgb '#d62728' title "
           << (narrow ? "'published (Fig. 10b, plug-in)'" : "'published end times (paper Fig. 10b, plug-in tables)'") << "\n";
        gp.send1d(each);
        gp.send1d(mean);
        gp.send1d(published);
      },
      canvas.first, canvas.second);
}

}  // namespace epuck2::plot
