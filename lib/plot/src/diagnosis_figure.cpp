#include "epuck2/plot/diagnosis_figure.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <map>
#include <set>
#include <sstream>

#include "epuck2/calibrate/sensors.hpp"
#include "epuck2/plot/figure.hpp"

namespace epuck2::plot {

namespace {

namespace dg = epuck2::diagnose;

/// One measured quantity: its residuals (indices into the report's) and how to label them.
struct Panel {
  std::string quantity;  ///< "ToF reading"
  std::string unit;      ///< "mm"
  std::vector<std::size_t> residuals;
};

std::vector<Panel> panels_of(const dg::Report& r) {
  const std::size_t n = r.residual_before.size();
  std::vector<Panel> out;
  if (!r.residual_channel.empty()) {
    for (std::size_t c = 0; c < r.channel_noise_sd.size(); ++c) {
      const std::string& name = r.channel_noise_sd[c].name;
      if (name == "tof_mm") out.push_back({"ToF reading", "mm", {}});
      else if (name == "steps") out.push_back({"wheel encoder registers (left and right)", "steps", {}});
      else out.push_back({name, "as logged", {}});
    }
    for (std::size_t i = 0; i < n && i < r.residual_channel.size(); ++i)
      if (r.residual_channel[i] < out.size()) out[r.residual_channel[i]].residuals.push_back(i);
  } else if (r.kind == logs::Kind::camera) {
    // Two residuals a row: the LED's column, then its row in the image.
    out = {{"LED image column px", "px", {}}, {"LED image row py", "px", {}}};
    for (std::size_t i = 0; i < n; ++i) out[i % 2].residuals.push_back(i);
  } else {
    switch (r.kind) {
      case logs::Kind::battery: out.push_back({"charge", "fraction of full charge", {}}); break;
      case logs::Kind::ground: out.push_back({"ground sensor reading", "counts, 0..1023", {}}); break;
      case logs::Kind::proximity: out.push_back({"proximity reading", "counts, 0..4095", {}}); break;
      case logs::Kind::light: out.push_back({"light sensor reading", "counts, 0..4095", {}}); break;
      default: out.push_back({"reading", "as logged", {}}); break;
    }
    for (std::size_t i = 0; i < n; ++i) out[0].residuals.push_back(i);
  }
  out.erase(std::remove_if(out.begin(), out.end(), [](const Panel& p) { return p.residuals.empty(); }), out.end());
  return out;
}

/// A covariate's axis: its label (quantity and unit) and, for a category, the label of each
/// value.
struct Axis {
  std::string label;
  bool categorical = false;
  std::map<double, std::string> categories;  ///< value -> tic label, in order
};

/// "temperature_c" -> "temperature (°C)": a log column's unit from its suffix.
std::string column_label(const std::string& name) {
  static const std::pair<const char*, const char*> kUnits[] = {
      {"_cm_s2", "cm/s²"}, {"_cm_s", "cm/s"}, {"_mm", "mm"}, {"_cm", "cm"}, {"_m", "m"}, {"_ms", "ms"}, {"_s", "s"},
      {"_deg", "°"},       {"_rad", "rad"},   {"_c", "°C"},  {"_k", "K"},   {"_v", "V"}, {"_a", "A"},   {"_hz", "Hz"},
      {"_pct", "%"},       {"_px", "px"}};
  for (const auto& [suffix, unit] : kUnits) {
    const std::string s = suffix;
    if (name.size() > s.size() && name.compare(name.size() - s.size(), s.size(), s) == 0) {
      std::string quantity = name.substr(0, name.size() - s.size());
      std::replace(quantity.begin(), quantity.end(), '_', ' ');
      return quantity + " (" + unit + ")";
    }
  }
  return name + " (as logged: no unit in its name)";
}

Axis axis_of(const std::string& name, const dg::Report& r, const std::vector<double>& x, const std::vector<std::string>& log_names,
             const std::string& panel_unit) {
  Axis a;
  std::set<double> values(x.begin(), x.end());
  if (name == "log" || name == "sensor" || name == "axis" || name == "channel") {
    a.categorical = true;
    for (double v : values) {
      const auto k = static_cast<long>(std::lround(v));
      std::string label;
      if (name == "log") {
        label = k >= 0 && static_cast<std::size_t>(k) < log_names.size()
                    ? std::filesystem::path(log_names[static_cast<std::size_t>(k)]).filename().string()
                    : "log " + std::to_string(k);
      } else if (name == "sensor") {
        label = r.kind == logs::Kind::ground && k >= 0 && k < 3 ? calibrate::kGroundSensorNames[static_cast<std::size_t>(k)]
                                                                : std::to_string(k);
      } else if (name == "axis") {
        label = k == 0 ? "px (column)" : k == 1 ? "py (row)" : std::to_string(k);
      } else {
        label = k == 0 ? "ToF" : k == 1 ? "left encoder" : k == 2 ? "right encoder" : std::to_string(k);
      }
      a.categories[v] = label;
    }
    a.label = name == "log"      ? "log (file name)"
              : name == "sensor" ? "sensor (id)"
              : name == "axis"   ? "image axis (px: image column, py: image row)"
                                 : "measured quantity (channel)";
    return a;
  }
  const bool drive = r.kind == logs::Kind::drive;
  static const std::map<std::string, std::string> kKnown{
      {"log_row", "row number within its log (log_row)"},
      {"time_s", "time (s)"},
      {"commanded_cm_s", "commanded wheel speed (cm/s)"},
      {"acceleration_cm_s2", "acceleration measured by the encoders (cm/s²)"},
      {"range_m", "range to the obstacle (m)"},
      {"time_since_command_s", "time since the last command (s)"},
      {"forward_m", "LED distance ahead of the camera (m)"},
      {"lateral_m", "LED lateral offset (m, left > 0)"},
      {"vertical_m", "LED vertical offset (m, up > 0)"},
      {"radius2", "squared radius in the image, (lateral² + vertical²) / forward² (dimensionless)"},
      {"grey", "grey level (fraction: 0 = black, 1 = white)"},
      {"intensity", "source intensity (simulator units; 1 = the reference source)"},
      {"angle_deg", "incidence angle (°)"},
  };
  if (name == "speed_cm_s") a.label = drive ? "speed measured by the encoders (cm/s)" : "wheel speed (cm/s)";
  else if (name == "distance_m")
    a.label = drive ? "distance travelled from the start (m; negative: backwards)" : r.kind == logs::Kind::light ? "distance to the light (m)" : "distance to the surface (m)";
  else if (name == "predicted") a.label = "value the recalibrated base model simulates (" + panel_unit + ")";
  else if (const auto it = kKnown.find(name); it != kKnown.end()) a.label = it->second;
  else a.label = column_label(name);
  return a;
}

/// The q-quantile of `v` (sorted copy).
double quantile(std::vector<double> v, double q) {
  if (v.empty()) return 0;
  const std::size_t k = std::min(v.size() - 1, static_cast<std::size_t>(q * static_cast<double>(v.size() - 1) + 0.5));
  std::nth_element(v.begin(), v.begin() + static_cast<std::ptrdiff_t>(k), v.end());
  return v[k];
}

/// A number in a title: "1.23e+04" or "0.5".
std::string num(double v) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.4g", v);
  return buf;
}

/// At most this many points of one series are drawn (the means use every residual).
constexpr std::size_t kMaxPoints = 20000;

std::string verdict_line(const dg::Report& r) {
  std::string line = "verdict: " + r.verdict_name();
  if (r.verdict == dg::Verdict::unexplained && !r.structure_after.empty())
    line += " (the residuals" + (r.structure_after.front().channel.empty() ? std::string() : " of " + r.structure_after.front().channel) +
            " still depend on " + r.structure_after.front().covariate + ")";
  std::string findings;
  for (const auto& f : r.findings) findings += (findings.empty() ? "" : ", ") + f.cause;
  line += findings.empty() ? "; no finding" : "; findings: " + findings;
  return line;
}

}  // namespace

void diagnosis_figure(logs::OutputStage& stage, const std::string& path, const dg::Report& r,
                      const std::vector<std::string>& log_names) {
  const std::vector<Panel> panels = panels_of(r);
  const std::size_t n = r.residual_before.size();
  // The covariate: the one the diagnosis chose for the figure, else the residual's index.
  std::string cov_name = "log_row";
  std::vector<double> x;
  if (!r.covariates.empty() && r.covariates.front().second.size() == n) {
    cov_name = r.covariates.front().first;
    x = r.covariates.front().second;
  } else {
    cov_name = "residual";
    x.resize(n);
    for (std::size_t i = 0; i < n; ++i) x[i] = static_cast<double>(i);
  }
  // Tic labels of a category: the longest decides the room under each panel.
  const Axis probe = axis_of(cov_name, r, x, log_names, panels.empty() ? "" : panels.front().unit);
  std::size_t longest = 0;
  for (const auto& [v, label] : probe.categories) longest = std::max(longest, label.size());
  const bool rotate = probe.categorical && (longest > 6 || probe.categories.size() > 12);
  const int rows = std::max<int>(1, static_cast<int>(panels.size()));
  const int width = 1500, plot_h = 400, top_px = 110, key_px = 400;
  // Long tic labels stand upright (about 6.5 px a character at 9 pt, in every format). gnuplot
  // would put the x label below the room it reckons they take at the default font's width, which
  // differs from terminal to terminal: the label is placed by hand just below them instead.
  const int tics_px = rotate ? static_cast<int>(7.0 * static_cast<double>(longest)) + 14 : 22;
  const int below_px = tics_px + 32;  // tic labels and the x label
  const int gap_px = below_px + 45;   // ... and the next panel's title
  const int height = top_px + rows * plot_h + (rows - 1) * gap_px + below_px + 10;
  Layout layout;
  layout.rows = rows;
  layout.cols = 1;
  layout.left = 95.0 / width;
  layout.right = 1.0 - static_cast<double>(key_px) / width;
  layout.bottom = (below_px + 10.0) / height;
  layout.top = 1.0 - static_cast<double>(top_px) / height;
  layout.hspace = 0.0;
  layout.vspace = static_cast<double>(gap_px) / height;

  const std::string title = "Diagnosis of the " + std::string(logs::to_string(r.kind)) +
                            " logs: residuals (measured − simulated) before and after the findings\n" + verdict_line(r);
  render(
      stage, path,
      [&](gnuplotio::Gnuplot& gp) {
        gp << multiplot(layout, title, 14);
        gp << "set grid lc rgb '#e0e0e0'\nset xzeroaxis lt 1 lc rgb '#404040' lw 1\n";
        gp << "set key outside right top vertical Left reverse samplen 2 spacing 1.15 font ',10'\n";
        int p_index = 0;
        for (const Panel& p : panels) {
          const std::string b = "b" + std::to_string(p_index), a = "a" + std::to_string(p_index);
          ++p_index;
          const Axis axis = axis_of(cov_name, r, x, log_names, p.unit);
          // One y scale for before and after: the central 99 % of both, widened by 15 % on each
          // side (and reaching 0); residuals beyond it are drawn at its edge.
          std::vector<double> all;
          all.reserve(2 * p.residuals.size());
          for (std::size_t i : p.residuals) {
            all.push_back(r.residual_before[i]);
            all.push_back(r.residual_after[i]);
          }
          double lo = std::min(0.0, quantile(all, 0.005)), hi = std::max(0.0, quantile(all, 0.995));
          const double span = hi > lo ? hi - lo : std::max(1.0, std::abs(hi));
          lo -= 0.15 * span;
          hi += 0.15 * span;
          // Category positions 0..K-1.
          std::map<double, int> position;
          for (const auto& [v, label] : axis.categories) position.emplace(v, static_cast<int>(position.size()));
          auto xpos = [&](std::size_t i, double side) {
            if (!axis.categorical) return x[i];
            const double u = std::fmod(static_cast<double>(i) * 0.6180339887498949, 1.0);  // deterministic jitter
            return position[x[i]] + side + 0.28 * (u - 0.5);
          };
          const std::size_t stride = (p.residuals.size() + kMaxPoints - 1) / kMaxPoints;
          std::vector<std::vector<double>> pts_b, pts_a, clip_b, clip_a;
          for (std::size_t k = 0; k < p.residuals.size(); k += std::max<std::size_t>(1, stride)) {
            const std::size_t i = p.residuals[k];
            for (int which = 0; which < 2; ++which) {
              const double y = which == 0 ? r.residual_before[i] : r.residual_after[i];
              const double xi = xpos(i, axis.categorical ? (which == 0 ? -0.2 : 0.2) : 0.0);
              auto& pts = which == 0 ? pts_b : pts_a;
              auto& clip = which == 0 ? clip_b : clip_a;
              if (y < lo) clip.push_back({xi, lo, 11});
              else if (y > hi) clip.push_back({xi, hi, 9});
              else pts.push_back({xi, y});
            }
          }
          std::size_t beyond = 0;  // every residual beyond the scale, not only those drawn
          for (std::size_t i : p.residuals)
            beyond += (r.residual_before[i] < lo || r.residual_before[i] > hi) + (r.residual_after[i] < lo || r.residual_after[i] > hi);
          // Means: per category, or over equal-count bins of the covariate (by value when it
          // takes few values).
          std::vector<std::vector<double>> mean_b, mean_a;
          {
            std::vector<std::size_t> order = p.residuals;
            std::sort(order.begin(), order.end(), [&](std::size_t i, std::size_t j) { return x[i] < x[j]; });
            std::set<double> distinct;
            for (std::size_t i : order) {
              distinct.insert(x[i]);
              if (distinct.size() > 40) break;
            }
            const bool by_value = axis.categorical || distinct.size() <= 40;
            const std::size_t bins = 30;
            std::size_t start = 0;
            for (std::size_t bin = 0; start < order.size(); ++bin) {
              std::size_t end = start + 1;
              if (by_value) {
                while (end < order.size() && x[order[end]] == x[order[start]]) ++end;
              } else {
                end = std::max(end, (bin + 1) * order.size() / bins);
                while (end < order.size() && x[order[end]] == x[order[end - 1]]) ++end;  // ties stay together
              }
              double sx = 0, sb = 0, sa = 0;
              for (std::size_t k = start; k < end; ++k) {
                sx += x[order[k]];
                sb += r.residual_before[order[k]];
                sa += r.residual_after[order[k]];
              }
              const double m = static_cast<double>(end - start);
              if (axis.categorical) {
                const double c = position[x[order[start]]];
                mean_b.push_back({c - 0.2, std::clamp(sb / m, lo, hi), 0.17});
                mean_a.push_back({c + 0.2, std::clamp(sa / m, lo, hi), 0.17});
              } else {
                mean_b.push_back({sx / m, std::clamp(sb / m, lo, hi)});
                mean_a.push_back({sx / m, std::clamp(sa / m, lo, hi)});
              }
              start = end;
            }
          }
          gp << datablock(b, pts_b) << datablock(a, pts_a) << datablock(b + "m", mean_b) << datablock(a + "m", mean_a);
          if (!clip_b.empty()) gp << datablock(b + "c", clip_b);
          if (!clip_a.empty()) gp << datablock(a + "c", clip_a);

          std::string panel_title = p.quantity + " (" + p.unit + "), " + std::to_string(p.residuals.size()) + " residuals";
          if (stride > 1) panel_title += "; 1 in " + std::to_string(stride) + " drawn, means from all";
          gp << "set title " << quoted(panel_title) << " font ',12'\n";
          gp << "set ylabel " << quoted("measured − simulated (" + p.unit + ")") << "\n";
          if (rotate) {
            // This panel's lower border, then the tic labels' length below it.
            const double panel_h = (layout.top - layout.bottom - (rows - 1) * layout.vspace) / rows;
            const double border = layout.top - p_index * panel_h - (p_index - 1) * layout.vspace;
            const double y = border - (tics_px + 16.0) / height;
            gp << "unset xlabel\nset label 90 " << quoted(axis.label) << " at screen " << num((layout.left + layout.right) / 2)
               << "," << num(y) << " center front\n";
          } else {
            gp << "set xlabel " << quoted(axis.label) << "\n";
          }
          gp << "set yrange [" << num(lo) << ":" << num(hi) << "]\n";
          if (axis.categorical) {
            gp << "set xrange [-0.6:" << static_cast<double>(axis.categories.size()) - 0.4 << "]\n";
            std::string tics = "set xtics (";
            for (const auto& [v, label] : axis.categories)
              tics += (tics.back() == '(' ? "" : ", ") + quoted(label) + " " + std::to_string(position[v]);
            gp << tics << ")" << (rotate ? " rotate by 90 right font ',9'" : "") << "\nset grid noxtics\n";
          } else {
            gp << "set xrange [*:*]\nset xtics autofreq norotate\nset grid xtics\n";
          }
          const bool many = pts_b.size() > 3000;
          const std::string ps = many ? "0.35" : "0.6";
          gp << "plot $" << b << " using 1:2 with points pt 7 ps " << ps
             << " lc rgb '#99d62728' title 'before: base model, recalibrated', "
             << "$" << a << " using 1:2 with points pt 7 ps " << ps << " lc rgb '#991f77b4' title "
             << quoted(r.findings.empty() ? "after: no finding (the same model)"
                                          : "after: with the " + std::to_string(r.findings.size()) + " finding" +
                                                (r.findings.size() == 1 ? "" : "s"));
          if (axis.categorical) {
            gp << ", $" << b << "m using 1:2:3 with xerrorbars pt 7 ps 0.9 lw 3 lc rgb '#7f0000' title 'before: mean per category'"
               << ", $" << a << "m using 1:2:3 with xerrorbars pt 5 ps 0.9 lw 3 lc rgb '#08306b' title 'after: mean per category'";
          } else {
            gp << ", $" << b << "m using 1:2 with linespoints dt (9,5) lw 2.5 pt 6 ps 1 lc rgb '#7f0000' title 'before: mean per bin'"
               << ", $" << a << "m using 1:2 with linespoints dt 1 lw 2.5 pt 5 ps 0.8 lc rgb '#08306b' title 'after: mean per bin'";
          }
          // Residuals beyond the y range: triangles at its edge, in their series' colour; one
          // legend entry (a black sample) for both.
          if (!clip_b.empty())
            gp << ", $" << b << "c using 1:2:3 with points pt variable ps 1.1 lc rgb '#d62728' notitle";
          if (!clip_a.empty())
            gp << ", $" << a << "c using 1:2:3 with points pt variable ps 1.1 lc rgb '#1f77b4' notitle";
          if (beyond > 0)
            gp << ", NaN with points pt 9 ps 1.1 lc rgb 'black' title "
               << quoted("beyond the y range, at its edge: " + std::to_string(beyond));
          gp << "\n";
        }
        gp << "unset multiplot\n";
      },
      width, height);
}

}  // namespace epuck2::plot
