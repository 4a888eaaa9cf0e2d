#include "epuck2/plot/battery_figures.hpp"

#include <cmath>
#include <cstdio>
#include <map>
#include <tuple>

#include "epuck2/models/plugin_battery_tables.hpp"
#include "epuck2/plot/png.hpp"

namespace epuck2::plot {

namespace mb = models::battery;

void battery_fits_png(logs::OutputStage& stage, const std::string& path, const std::vector<calibrate::BatteryRun>& runs, const calibrate::BatteryFit& f) {
  const int n = static_cast<int>(f.speeds.size());
  const int cols = n <= 4 ? n : 4;
  const int rows = (n + cols - 1) / cols;
  render_png(
      stage, path,
      [&](gnuplotio::Gnuplot& gp) {
        gp << "set multiplot layout " << rows << "," << cols
           << " title 'Battery discharge: logs (grey) and the four fitted models' font ',14'\n";
        gp << "set key off\nset grid lc rgb '#dddddd'\nset yrange [0:1.05]\nset xtics font ',8'\nset ytics 0.25 font ',8'\n";
        gp << "set lmargin 5\nset rmargin 1\nset tmargin 2\nset bmargin 2\n";
        for (int i = 0; i < n; ++i) {
          const calibrate::SpeedFit& s = f.speeds[static_cast<std::size_t>(i)];
          std::vector<std::tuple<double, double>> pts;
          for (const auto& r : runs) {
            if (std::lround(r.speed_cm_s * 100) != std::lround(s.speed_cm_s * 100)) continue;
            const std::size_t stride = std::max<std::size_t>(1, r.time_s.size() / 400);
            for (std::size_t k = 0; k < r.time_s.size(); k += stride) pts.emplace_back(r.time_s[k] / 3600.0, r.charge[k]);
          }
          std::vector<std::vector<std::tuple<double, double>>> curves(4);
          constexpr int kSamples = 300;
          for (int k = 0; k <= kSamples; ++k) {
            const double t = s.lifetime_s * k / kSamples;
            int m = 0;
            for (mb::Model model : mb::kAllModels)
              curves[static_cast<std::size_t>(m++)].emplace_back(t / 3600.0, calibrate::analytic_charge(s, f, model, t));
          }
          char title[96];
          std::snprintf(title, sizeof title, "%g cm/s  (lifetime %.2f h, %zu runs)", s.speed_cm_s, s.lifetime_s / 3600.0, s.runs);
          gp << "set title '" << title << "' font ',10'\n";
          if (i == 0) {
            gp << "set key top right font ',8' samplen 2\n";
          } else {
            gp << "set key off\n";
          }
          gp << "set xlabel 'hours' font ',8' offset 0,0.8\n";
          gp << "plot '-' with points pt 7 ps 0.25 lc rgb '#b0b0b0' title 'logs', "
                "'-' with lines lw 1.5 lc rgb '#e41a1c' title 'simple', "
                "'-' with lines lw 1.5 lc rgb '#377eb8' title 'linear', "
                "'-' with lines lw 2 lc rgb '#4daf4a' title 'cubic', "
                "'-' with lines lw 1.5 dt 2 lc rgb '#984ea3' title 'approximated'\n";
          gp.send1d(pts);
          for (const auto& c : curves) gp.send1d(c);
        }
        gp << "unset multiplot\n";
      },
      1800, 1400);
}

void battery_lifetime_png(logs::OutputStage& stage, const std::string& path, const std::vector<calibrate::BatteryRun>& runs, const calibrate::BatteryFit& f) {
  render_png(
      stage, path,
      [&](gnuplotio::Gnuplot& gp) {
        std::vector<std::tuple<double, double>> each;
        for (const auto& r : runs) each.emplace_back(r.speed_cm_s, r.lifetime_s / 3600.0);
        std::vector<std::tuple<double, double, double>> mean;
        for (const auto& s : f.speeds) mean.emplace_back(s.speed_cm_s, s.lifetime_s / 3600.0, s.lifetime_std_error_s / 3600.0);
        std::vector<std::tuple<double, double>> published;
        const mb::Tables& pt = mb::plugin_tables();
        for (int s = 0; s < mb::kSpeedCount; ++s) published.emplace_back(s, pt.lifetime_s[static_cast<std::size_t>(s)] / 3600.0);
        gp << "set title 'Battery lifetime against speed (robot spinning in place)' font ',14'\n";
        gp << "set xlabel 'wheel speed (cm/s)'\nset ylabel 'lifetime (h)'\nset grid\nset key top right\n";
        gp << "set xrange [-0.5:15.5]\nset yrange [0:*]\n";
        gp << "plot '-' with points pt 7 ps 1.2 lc rgb '#999999' title 'each run', "
              "'-' with yerrorlines pt 5 ps 1.2 lw 2 lc rgb '#377eb8' title 'mean of runs (+- standard error)', "
              "'-' with linespoints dt 2 pt 6 lw 1.5 lc rgb '#e41a1c' title 'published end times (paper Fig. 10b, plug-in tables)'\n";
        gp.send1d(each);
        gp.send1d(mean);
        gp.send1d(published);
      },
      1200, 800);
}

}  // namespace epuck2::plot
