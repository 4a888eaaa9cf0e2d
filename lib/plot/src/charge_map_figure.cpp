#include "epuck2/plot/charge_map_figure.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <tuple>
#include <utility>

#include "epuck2/plot/figure.hpp"

namespace epuck2::plot {

void charge_map_figure(logs::OutputStage& stage, const std::string& path, const std::vector<calibrate::ChargeSample>& rows,
                    const calibrate::ChargeMap& map) {
  // A paper's column (narrower than 1200 of the canvas's pixels): the panels stacked as always, no
  // title (the caption's), the legend below the map's panel.
  const std::pair<int, int> canvas = canvas_px(1200, 900);
  const bool narrow = canvas.first < 1200;
  render(
      stage, path,
      [&](gnuplotio::Gnuplot& gp) {
        // At most about 4000 rows drawn (every k-th): the cloud's shape, not every point; in a
        // vector file (SVG, PDF), where each is an element, about 800 (the reference set's SVG was
        // 0.9 MB with 4000 in each panel), and the legend says so.
        std::vector<std::tuple<double, double>> pts;
        const std::size_t most = format_of(path) == Format::png ? 4000 : 800;
        const std::size_t stride = std::max<std::size_t>(1, rows.size() / most);
        for (std::size_t i = 0; i < rows.size(); i += stride)
          pts.emplace_back(rows[i].voltage_v + calibrate::load_offset_v(map, rows[i].speed_cm_s), rows[i].charge);
        if (pts.empty()) pts.emplace_back(map.knots_v.front(), map.knot_charge.front());
        std::vector<std::tuple<double, double>> line, knots;
        constexpr int kSamples = 400;
        for (int k = 0; k <= kSamples; ++k) {
          const double v = map.voltage_min_v + (map.voltage_max_v - map.voltage_min_v) * k / kSamples;
          line.emplace_back(v, calibrate::convert_voltage(map, v - calibrate::load_offset_v(map, 0.0), 0.0).charge);
        }
        for (std::size_t k = 0; k < map.knots_v.size(); ++k)
          if (map.knots_v[k] >= map.voltage_min_v - 1e-12 && map.knots_v[k] <= map.voltage_max_v + 1e-12)
            knots.emplace_back(map.knots_v[k], map.knot_charge[k]);
        if (knots.empty()) knots.push_back(line.front());
        char title[200];
        if (std::isfinite(map.residual_sd))
          std::snprintf(title, sizeof title, "Voltage -> charge map: %zu knots, load term %s, residual sd %.2g (%zu rows)",
                        map.knots_v.size(), map.has_load() ? "per speed" : "none", map.residual_sd, map.observations);
        else
          std::snprintf(title, sizeof title, "Voltage -> charge map: %zu knots, load term %s", map.knots_v.size(),
                        map.has_load() ? "per speed" : "none");
        // Below: the residuals, logged charge minus the map, where the rows' scatter shows.
        std::vector<std::tuple<double, double>> resid;
        for (std::size_t i = 0; i < rows.size(); i += stride)
          resid.emplace_back(rows[i].voltage_v + calibrate::load_offset_v(map, rows[i].speed_cm_s),
                             rows[i].charge - calibrate::convert_voltage(map, rows[i].voltage_v, rows[i].speed_cm_s).charge);
        const std::string xlabel = map.has_load() ? "logged voltage + load offset (V)" : "logged voltage (V)";
        if (narrow) gp << "set multiplot\n";
        else gp << "set multiplot layout 2,1 title '" << title << "' font ',13' noenhanced\n";
        gp << "set xlabel '" << (narrow ? std::string() : xlabel) << "' noenhanced\n";  // a column: once, under the residuals
        gp << "set ylabel 'charge (1 = full)'\nset grid\n" << (narrow ? "set key below horizontal Left reverse width -2\n" : "set key top left\n");
        gp << (narrow ? "set size 1,0.6\nset origin 0,0.4\n" : "set size 1,0.62\nset origin 0,0.33\n");
        // (a column's legend shows the rows' marker at a size it can be seen: 0.3 was a dot)
        gp << "plot '-' with points pt 7 ps 0.3 lc rgb '#b0b0b0' "
           << (narrow ? "notitle, NaN with points pt 7 ps 0.8 lc rgb '#b0b0b0' title " : "title ")
           << quoted(stride > 1 && format_of(path) != Format::png ? "logged rows, 1 in " + std::to_string(stride) : std::string("logged rows"))
           << ", "
           << "'-' with lines lw 2 lc rgb '#e41a1c' title 'map', "
              "'-' with points pt 6 ps 1.5 lw 2 lc rgb '#377eb8' title 'knots'\n";
        gp.send1d(pts);
        gp.send1d(line);
        gp.send1d(knots);
        // A column's residual axis in units of 1e-5 (its tics would overlap as 2.0e-05, 4.0e-05, ...).
        const double unit = narrow ? 1e5 : 1.0;
        if (narrow) for (auto& r : resid) std::get<1>(r) *= unit;
        gp << (narrow ? "set size 1,0.4\n" : "set size 1,0.33\n") << "set origin 0,0\nset key off\n"
           << (narrow ? "set ylabel 'logged - map (1e-5)'\nset format y '%g'\nset ytics 6\nset xlabel '" + xlabel + "' noenhanced\n"
                      : std::string("set ylabel 'logged - map (charge, 1 = full)'\nset format y '%.1e'\n"));
        if (resid.empty()) resid.emplace_back(map.voltage_min_v, 0.0);
        gp << "plot '-' with points pt 7 ps 0.3 lc rgb '#555555' notitle, 0 with lines lc rgb '#e41a1c' notitle\n";
        gp.send1d(resid);
        gp << "unset multiplot\n";
      },
      canvas.first, canvas.second);
}

}  // namespace epuck2::plot
