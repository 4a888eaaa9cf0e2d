#include "epuck2/plot/diagnosis_figure.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <map>
#include <set>
#include <sstream>

#include "epuck2/calibrate/sensors.hpp"
#include "epuck2/models/kind_facts.hpp"
#include "epuck2/plot/figure.hpp"
#include "epuck2/logs/output.hpp"

namespace epuck2::plot {

namespace {

namespace dg = epuck2::diagnose;

/// One measured quantity: its residuals (indices into the report's) and how to label them.
struct Panel {
  std::string quantity;  ///< "ToF reading"
  std::string unit;      ///< "mm"
  std::vector<std::size_t> residuals;
  std::string brief = {};  ///< "ToF": the quantity in a page's y label, where a figure has several
};

std::vector<Panel> panels_of(const dg::Report& r) {
  const std::size_t n = r.residual_before.size();
  std::vector<Panel> out;
  const models::KindFacts& facts = *models::kind_facts(std::string(logs::to_string(r.kind)));
  if (!r.residual_channel.empty()) {
    for (std::size_t c = 0; c < r.channel_noise_sd.size(); ++c) {
      const std::string& name = r.channel_noise_sd[c].name;
      if (name == "tof_mm") out.push_back({std::string(facts.channels.front().label) + " reading", facts.channels.front().unit, {}, "ToF"});
      else if (name == "steps") out.push_back({std::string(facts.channels.back().label) + " registers (left and right)", facts.channels.back().unit, {}, "encoder"});
      else out.push_back({name, "as logged", {}, name});
    }
    for (std::size_t i = 0; i < n && i < r.residual_channel.size(); ++i)
      if (r.residual_channel[i] < out.size()) out[r.residual_channel[i]].residuals.push_back(i);
  } else if (facts.readings.size() > 1) {
    // Several residuals a row, one per reading column in turn (the camera's: the LED's image
    // column, then its row), each named by the kind's facts.
    const char* unit = facts.channels.front().unit;
    for (const char* reading : facts.readings) {
      const models::ColumnWords* w = facts.words_of(reading);
      out.push_back({w ? w->words : reading, unit, {}, w ? w->brief : reading});
    }
    for (std::size_t i = 0; i < n; ++i) out[i % out.size()].residuals.push_back(i);
  } else {
    // One channel: its quantity, unit and rails from the kind's facts (a charge is a fraction of
    // the full charge, with no register behind it: Channel::axis_unit).
    const models::Channel& c = facts.channels.front();
    if (c.axis_unit) out.push_back({c.label, c.axis_unit, {}});
    else out.push_back({std::string(c.label) + " reading", std::string(c.unit) + ", " + c.rails_text(), {}});
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

Axis axis_of(const std::string& name, const dg::Report& r, const std::vector<double>& x, const std::vector<std::string>& log_names,
             const std::string& panel_unit) {
  Axis a;
  const models::KindFacts& facts = *models::kind_facts(std::string(logs::to_string(r.kind)));
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
        label = k >= 0 ? facts.sensor_name(static_cast<std::size_t>(k))
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
  static const std::map<std::string, std::string> kKnown{
      {"log_row", "row number within its log (log_row)"},
      {"speed_cm_s", "wheel speed (cm/s)"},
      {"distance_m", "distance to the surface (mm)"},
      {"time_s", "time (s)"},
      {"commanded_cm_s", "commanded wheel speed (cm/s)"},
      {"acceleration_cm_s2", "acceleration measured by the encoders (cm/s²)"},
      {"range_m", "range to the obstacle (mm)"},
      {"time_since_command_s", "time since the last command (s)"},
      {"forward_m", "LED distance ahead of the camera (mm)"},
      {"lateral_m", "LED lateral offset (mm, left > 0)"},
      {"vertical_m", "LED vertical offset (mm, up > 0)"},
      {"radius2", "squared radius in the image, (lateral² + vertical²) / forward² (dimensionless)"},
      {"grey", "grey level (fraction: 0 = black, 1 = white)"},
      {"intensity", "source intensity (simulator units; 1 = the reference source)"},
      {"angle_deg", "incidence angle (°)"},
  };
  if (const models::ColumnWords* w = facts.words_of(name)) a.label = w->words;  // the kind's own words
  else if (name == "predicted") a.label = "value the recalibrated base model simulates (" + panel_unit + ")";
  else if (name == "image_row") a.label = "LED's row in the image (px, 0 = top)";
  else if (const auto it = kKnown.find(name); it != kKnown.end()) a.label = it->second;
  else a.label = column_label(name);
  return a;
}

/// On a page, the logs' file names without what they all share ("ground_virtual-epuck2-1.csv",
/// "ground_virtual-epuck2-2.csv" -> "1", "2"), the shared part in the axis label
/// ("log (ground_virtual-epuck2-*.csv)"): tic labels short enough to stand level under a narrow panel.
void shorten_log_names(Axis& a) {
  if (a.categories.size() < 2) return;
  std::string prefix = a.categories.begin()->second, suffix = prefix;
  for (const auto& [v, label] : a.categories) {
    std::size_t k = 0;
    while (k < prefix.size() && k < label.size() && prefix[k] == label[k]) ++k;
    prefix.resize(k);
    std::size_t m = 0;
    while (m < suffix.size() && m < label.size() && suffix[suffix.size() - 1 - m] == label[label.size() - 1 - m]) ++m;
    suffix = suffix.substr(suffix.size() - m);
  }
  for (const auto& [v, label] : a.categories)
    if (label.size() <= prefix.size() + suffix.size()) return;  // a name would vanish: keep them whole
  if (prefix.size() + suffix.size() < 4) return;
  for (auto& [v, label] : a.categories) label = label.substr(prefix.size(), label.size() - prefix.size() - suffix.size());
  a.label = "log (" + prefix + "*" + suffix + ")";
}

/// The key's entries for `names` (category k+1 is names[k]): "3 = 1.00", or for a run of names
/// that differ only by a number counting up at the same place, "1–16 = a_speed-00…15".
std::vector<std::string> key_entries(const std::vector<std::string>& names) {
  struct Split {
    std::string head, digits, tail;
  };
  std::vector<Split> split;
  for (const std::string& n : names) {
    const std::size_t end = n.find_last_of("0123456789");
    if (end == std::string::npos) {
      split.push_back({n, "", ""});
      continue;
    }
    const std::size_t begin = n.find_last_not_of("0123456789", end);
    const std::size_t at = begin == std::string::npos ? 0 : begin + 1;
    split.push_back({n.substr(0, at), n.substr(at, end + 1 - at), n.substr(end + 1)});
  }
  // names[i + 1] continues names[i]'s run: the same head, tail and number width, the number one up.
  auto follows = [&](std::size_t i) {
    const Split &a = split[i], &b = split[i + 1];
    return !a.digits.empty() && a.head == b.head && a.tail == b.tail && a.digits.size() == b.digits.size() &&
           a.digits.size() < 10 && std::stol(b.digits) == std::stol(a.digits) + 1;
  };
  std::vector<std::string> out;
  for (std::size_t i = 0; i < names.size();) {
    std::size_t j = i;
    while (j + 1 < names.size() && follows(j)) ++j;
    if (j >= i + 2) {
      out.push_back(std::to_string(i + 1) + "–" + std::to_string(j + 1) + " = " + split[i].head + split[i].digits + "…" +
                    split[j].digits + split[i].tail);
      i = j + 1;
    } else {
      out.push_back(std::to_string(i + 1) + " = " + names[i]);
      ++i;
    }
  }
  return out;
}

/// `head` and `entries` in lines of at most `width_px` canvas pixels at `font_pt`, broken
/// between entries only (an entry wider than a line has a line of its own).
std::vector<std::string> key_lines(const std::string& head, const std::vector<std::string>& entries, double width_px, double font_pt) {
  std::vector<std::string> lines{head};
  for (std::size_t k = 0; k < entries.size(); ++k) {
    const std::string piece = entries[k] + (k + 1 < entries.size() ? "," : "");
    std::string& line = lines.back();
    if (line.empty() || text_px(line + " " + piece, font_pt) <= width_px) line += (line.empty() ? "" : " ") + piece;
    else lines.push_back(piece);
  }
  return lines;
}

/// A category axis on a page: level tic labels where every name fits its slot under the panel and
/// the axis label fits under it; otherwise numbers (1, 2, …; every step-th labelled where they do
/// not all fit) and a key under the figure naming each: long log names are never cut, never
/// overlap and never stand upright in a paper's column.
struct CategoryAxis {
  std::vector<std::string> tics;  ///< the label at each position 0..K-1 ("": a tic without a label)
  std::string label;              ///< the x label
  std::vector<std::string> key;   ///< the key's lines under the figure (none: the tics say it all)
};

/// The key's text size (the layouts' points) and line height (canvas pixels: 1.53 lines of text
/// a line, the svg terminal's spacing, wider than cairo's 1.16).
constexpr double kKeyFont_pt = 9, kKeyLine_px = 19;
/// A line of a panel's title (11 pt: 14.7 canvas pixels to the em) in canvas pixels, at the same spacing.
constexpr int kTitleLine_px = 23;

CategoryAxis category_axis(const Axis& full, const std::string& name, double panel_w_px, double label_font_pt, double key_w_px) {
  CategoryAxis out;
  Axis brief = full;
  if (name == "log") shorten_log_names(brief);
  const double k = static_cast<double>(std::max<std::size_t>(1, full.categories.size()));
  bool level = true;
  for (const auto& [v, label] : brief.categories) level = level && text_px(label) + 8 <= panel_w_px / k;
  // The x label: in lines of the panel's width, none of its words wider.
  std::string word;
  for (char c : brief.label + " ") {
    if (c != ' ') word += c;
    else level = level && text_px(word, label_font_pt) <= panel_w_px + 20, word.clear();
  }
  level = level && text_px(brief.label, label_font_pt) <= 2 * (panel_w_px + 20);
  if (level) {
    for (const auto& [v, label] : brief.categories) out.tics.push_back(label);
    out.label = brief.label;
    return out;
  }
  const std::string what = name == "log" ? "log" : name == "sensor" ? "sensor" : name == "axis" ? "image axis" : "measured quantity";
  out.label = what + " (key below)";
  // Numbers: all, or every step-th (1, 2 or 5 times a power of ten; from 5 on the first too:
  // 1, 5, 10, …), labelled tics at least the widest number and 10 pixels apart.
  const std::size_t n = full.categories.size();
  const double per_label = text_px(std::to_string(n)) + 10;
  auto fits = [&](std::size_t st) { return static_cast<double>(st) * panel_w_px / static_cast<double>(n) >= per_label; };
  std::size_t step = 1;
  for (std::size_t p = 1; !fits(step) && p <= n; p *= 10)
    for (std::size_t m : {1, 2, 5})
      if (!fits(step)) step = m * p;
  for (std::size_t i = 0; i < n; ++i)
    out.tics.push_back((i == 0 && step >= 5) || (i + 1) % step == 0 ? std::to_string(i + 1) : "");
  // The key: every name whole, or (shorter) the logs' shared part once and what tells them apart.
  std::vector<std::string> names, parts;
  for (const auto& [v, label] : full.categories) names.push_back(label);
  for (const auto& [v, label] : brief.categories) parts.push_back(label);
  out.key = key_lines(what + ":", key_entries(names), key_w_px, kKeyFont_pt);
  if (brief.label != full.label) {  // "log (ground_virtual-epuck2-*.csv)": the shared part in the label
    const std::string shared = brief.label.substr(brief.label.find('(') + 1, brief.label.size() - brief.label.find('(') - 2);
    std::vector<std::string> shorter = key_lines(what + " " + shared + ", *:", key_entries(parts), key_w_px, kKeyFont_pt);
    if (shorter.size() < out.key.size() && out.key.size() > 2) out.key = shorter;
  }
  return out;
}

/// The q-quantile of `v` (sorted copy).
double quantile(std::vector<double> v, double q) {
  if (v.empty()) return 0;
  const std::size_t k = std::min(v.size() - 1, static_cast<std::size_t>(q * static_cast<double>(v.size() - 1) + 0.5));
  std::nth_element(v.begin(), v.begin() + static_cast<std::ptrdiff_t>(k), v.end());
  return v[k];
}

/// A number in a title: "1.23e+04" or "0.5".
std::string num(double v) { return logs::format_number(v, 4); }

/// At most this many points of one series are drawn (the means use every residual): in a PNG,
/// and in a vector file (SVG, PDF), where every point is an element of the file.
constexpr std::size_t kMaxPoints = 20000;
constexpr std::size_t kMaxVectorPoints = 800;

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

/// "temperature_c" -> "temperature (°C)": a log column's unit from its suffix (a column in metres
/// is drawn in mm, as every distance of the figures).
std::string column_label(const std::string& name) {
  static const std::pair<const char*, const char*> kUnits[] = {
      {"_cm_s2", "cm/s²"}, {"_cm_s", "cm/s"}, {"_mm", "mm"}, {"_cm", "cm"}, {"_m", "mm"}, {"_ms", "ms"}, {"_s", "s"},
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

void diagnosis_figure(logs::OutputStage& stage, const std::string& path, const dg::Report& r,
                      const std::vector<std::string>& log_names, const std::vector<std::string>& log_robots) {
  const std::vector<Panel> panels = panels_of(r);
  const std::size_t n = r.residual_before.size();
  // Logs of several robots: each residual's robot (through the `log` covariate), a marker each.
  std::vector<std::string> robots;
  std::vector<int> marker_of(n, 7);
  for (const auto& [name, values] : r.covariates) {
    if (name != "log" || values.size() != n) continue;
    for (const auto& robot : log_robots)
      if (std::find(robots.begin(), robots.end(), robot) == robots.end()) robots.push_back(robot);
    // (Logs without a robot name are named by their file stem: a robot a log, no marker tells them apart.)
    if (robots.size() < 2 || robots.size() > 6) break;
    for (std::size_t i = 0; i < n; ++i) {
      const auto k = static_cast<std::size_t>(std::lround(values[i]));
      if (k < log_robots.size())
        marker_of[i] = robot_point_type(static_cast<std::size_t>(std::find(robots.begin(), robots.end(), log_robots[k]) - robots.begin()));
    }
    break;
  }
  if (robots.size() < 2 || robots.size() > 6) {
    robots.clear();
    std::fill(marker_of.begin(), marker_of.end(), 7);
  }
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
  // Distances in mm, as the calibration figures draw them: a covariate in metres is scaled.
  const bool metres = !cov_name.empty() && cov_name.size() > 2 && cov_name.compare(cov_name.size() - 2, 2, "_m") == 0;
  if (metres)
    for (double& v : x) v *= 1000.0;
  // A page narrower than the figure's own 1500 canvas pixels: short titles, the verdict and the
  // findings on lines of their own, the legend in two columns.
  const bool narrow = canvas_px(1500, 100).first < 1500;
  // A paper's column: no title (the caption's), the legend at the top; before and after one
  // above the other (each quantity's pair in turn) when the page is tall enough for panels of
  // 110 canvas pixels, else side by side (at 8.5x6cm a stack left panels 7 pixels high).
  const bool one_column = canvas_px(1500, 100).first < kNarrowCanvas_px;
  // Tic labels of a category on the figure's own canvas: the longest decides the room under each
  // panel (on a page, category_axis() numbers them instead, with a key under the figure).
  const Axis probe = axis_of(cov_name, r, x, log_names, panels.empty() ? "" : panels.front().unit);
  std::size_t longest = 0;
  for (const auto& [v, label] : probe.categories) longest = std::max(longest, label.size());
  const bool rotate = !narrow && probe.categorical && (longest > 6 || probe.categories.size() > 12);
  // Two columns: before the findings on the left, after them on the right, each on a y scale of
  // its own (an `unexplained` verdict's structure is often 20x smaller than what the findings
  // removed). The legend is one band under the title.
  // From the top: the two-line title (to 65 px), the legend (75-110 px), each panel's title of up
  // to two lines (just above the panel).
  // The legend: four entries and each robot's marker (named on every page: a reader must tell
  // which marker is which robot), in one row on the figure's own canvas, two columns on a page.
  const std::size_t legend_entries = 4 + robots.size();
  const int legend_rows = narrow ? static_cast<int>((legend_entries + 1) / 2) : 1;
  const int legend_top_px = one_column ? 10 : narrow ? 85 : 75;  // below the title's lines
  const int plot_h = 380, column_gap_px = 120;
  const int quantities = std::max<int>(1, static_cast<int>(panels.size()));
  // Vector files stay small: at most this many points of one series (the means use every residual).
  const std::size_t max_points = format_of(path) == Format::png ? kMaxPoints : kMaxVectorPoints;
  auto stride_of = [&](const Panel& p) { return std::max<std::size_t>(1, (p.residuals.size() + max_points - 1) / max_points); };
  // A panel's title: before or after, the quantity (on a page: in the y label), how many of its
  // residuals are drawn and how many lie beyond its scale; on a page in lines of the panel's
  // width. A column's panels side by side (`small`): what it is, then the counts on lines of their own.
  auto panel_title = [&](int side, const Panel& p, std::size_t stride, std::size_t beyond, bool small, double panel_w_px) {
    const std::string after_short = r.findings.empty() ? std::string("after: no finding")
                                                       : "after: " + std::to_string(r.findings.size()) + " finding" + (r.findings.size() == 1 ? "" : "s");
    const std::string after_name = r.findings.empty() ? "after: no finding (the same model)"
                                                      : "after: with the " + std::to_string(r.findings.size()) + " finding" +
                                                            (r.findings.size() == 1 ? "" : "s");
    std::string t = (side == 0 ? std::string("before: base model, recalibrated") : after_name) + " — " + p.quantity + " (" + p.unit +
                    "), " + std::to_string(p.residuals.size()) + " residuals";
    if (narrow) t = (side == 0 ? std::string("before the findings") : after_short) + ", " + std::to_string(p.residuals.size()) + " residuals";
    if (small) t = side == 0 ? std::string("before the findings") : after_short;
    if (small && stride > 1) t += "\n1 in " + std::to_string(stride) + " drawn";
    else if (stride > 1) t += "\n1 in " + std::to_string(stride) + " drawn, means from all";
    if (small && beyond > 0) t += "\n" + std::to_string(beyond) + " off the scale";
    else if (beyond > 0)
      t += (stride > 1 ? (narrow ? "\n" : "; ") : "\n") + std::to_string(beyond) +
           (narrow ? " off the scale, at its edge" : " beyond the y scale, drawn at its edge");
    return narrow ? wrapped(t, panel_w_px + 40) : t;
  };
  // The canvas's width (a page's, whatever its height) and the panels' margins: on a page 35
  // pixels right of the last panel, where its last x tic label ("2000", centred on the border) ends.
  const int width_px = canvas_px(1500, 100).first;
  const double right_px = narrow ? 35 : 25, hspace_px = one_column ? 100 : column_gap_px;
  // The room around the panels for panels stacked (one column) or side by side (two).
  struct Plan {
    bool small = false;       ///< a column's panels side by side: x labels in two lines of smaller text
    double panel_w_px = 0;
    CategoryAxis categories;  ///< a page's category axis: its tics and key
    int below_px = 0, gap_px = 0, top_px = 0, key_px = 0;
  };
  auto plan = [&](bool stacked) {
    Plan pl;
    pl.small = one_column && !stacked;
    const int cols = stacked ? 1 : 2;
    pl.panel_w_px = (width_px - 95.0 - right_px - (cols - 1) * hspace_px) / cols;
    if (narrow && probe.categorical) pl.categories = category_axis(probe, cov_name, pl.panel_w_px, pl.small ? 9 : 11, width_px - 20.0);
    pl.key_px = pl.categories.key.empty() ? 0 : static_cast<int>(std::lround(static_cast<double>(pl.categories.key.size()) * kKeyLine_px + 8));
    // Long tic labels stand upright (about 6.5 px a character at 9 pt, in every format). gnuplot
    // would put the x label below the room it reckons they take at the default font's width, which
    // differs from terminal to terminal: the label is placed by hand just below them instead.
    const int tics_px = rotate ? static_cast<int>(7.0 * static_cast<double>(longest)) + 14 : 22;
    // tic labels and the x label (on a page 8 pixels more: the svg terminal sets it lower)
    pl.below_px = tics_px + 32 + (pl.small ? 20 : 0) + (narrow ? 8 : 0);
    if (!narrow) {
      pl.top_px = 180;
      pl.gap_px = pl.below_px + 70;  // ... and the next panel's title (two lines)
      return pl;
    }
    // On a page, the titles' lines: the most any panel's title takes, its count off the scale
    // taken at five digits; a line of title text a line and a half high (the svg terminal's, wider
    // than cairo's 1.16).
    int lines = 1;
    for (const Panel& p : panels)
      for (int side = 0; side < 2; ++side) {
        const std::string t = panel_title(side, p, stride_of(p), 99999, pl.small, pl.panel_w_px);
        lines = std::max(lines, 1 + static_cast<int>(std::count(t.begin(), t.end(), '\n')));
      }
    const int title_px = lines * kTitleLine_px + 24;  // (the svg terminal sets the last line 33 pixels above the panel)
    pl.top_px = legend_top_px + 25 * legend_rows + title_px;
    pl.gap_px = pl.below_px + title_px + 14;
    return pl;
  };
  bool column = false;
  if (one_column) {
    const Plan st = plan(true);
    const int stacked = 2 * quantities, room = st.top_px + st.below_px + 10 + st.key_px + (stacked - 1) * st.gap_px;
    const int page_h = canvas_px(1500, room + stacked * plot_h).second;
    column = (page_h - room) / stacked >= 110;
  }
  const Plan pl = plan(column);
  const bool small_panels = pl.small;
  const int rows = column ? 2 * quantities : quantities;
  // The canvas: the figure's own size, or a page's (--figure-size), whose panels share what
  // the fixed margins leave.
  const std::pair<int, int> canvas = canvas_px(1500, pl.top_px + rows * plot_h + (rows - 1) * pl.gap_px + pl.below_px + 10 + pl.key_px);
  const int width = canvas.first, height = canvas.second;
  Layout layout;
  layout.rows = rows;
  layout.cols = column ? 1 : 2;
  layout.left = 95.0 / width;
  layout.right = 1.0 - right_px / width;
  layout.bottom = (pl.below_px + 10.0 + pl.key_px) / height;
  layout.top = 1.0 - static_cast<double>(pl.top_px) / height;
  layout.hspace = hspace_px / width;
  layout.vspace = static_cast<double>(pl.gap_px) / height;
  // Each panel's size in canvas pixels: how many tics its axes hold.
  const double panel_h_px = height * (layout.top - layout.bottom - (rows - 1) * layout.vspace) / rows;
  const double panel_w_px = width * (layout.right - layout.left - (layout.cols - 1) * layout.hspace) / layout.cols;
  check_panel_height(path, panel_h_px, rows);
  const int tics_px = rotate ? static_cast<int>(7.0 * static_cast<double>(longest)) + 14 : 22;

  std::string title = "Diagnosis of the " + std::string(logs::to_string(r.kind)) +
                      " logs: residuals (measured − simulated), before and after the findings, each on its own scale\n" +
                      verdict_line(r);
  if (narrow) {
    title = "Diagnosis of the " + std::string(logs::to_string(r.kind)) + " logs\n" + verdict_line(r);
    const std::size_t semi = title.rfind("; ");
    if (semi != std::string::npos) title.replace(semi, 2, "\n");
  }
  if (one_column) title.clear();
  render(
      stage, path,
      [&](gnuplotio::Gnuplot& gp) {
        gp << multiplot(layout, title, 14);
        gp << "set grid lc rgb '#e0e0e0'\nset xzeroaxis lt 1 lc rgb '#404040' lw 1\nunset key\n";
        int p_index = 0;
        for (const Panel& p : panels) {
          ++p_index;
          const Axis axis = axis_of(cov_name, r, x, log_names, p.unit);
          // Category positions 0..K-1.
          std::map<double, int> position;
          for (const auto& [v, label] : axis.categories) position.emplace(v, static_cast<int>(position.size()));
          auto xpos = [&](std::size_t i) {
            if (!axis.categorical) return x[i];
            const double u = std::fmod(static_cast<double>(i) * 0.6180339887498949, 1.0);  // deterministic jitter
            return position[x[i]] + 0.5 * (u - 0.5);
          };
          const std::size_t stride = stride_of(p);
          std::vector<std::size_t> order = p.residuals;
          std::sort(order.begin(), order.end(), [&](std::size_t i, std::size_t j) { return x[i] < x[j]; });
          for (int side = 0; side < 2; ++side) {
            const std::vector<double>& res = side == 0 ? r.residual_before : r.residual_after;
            const std::string colour = side == 0 ? "#d62728" : "#1f77b4", dark = side == 0 ? "#7f0000" : "#08306b";
            const std::string name = (side == 0 ? "b" : "a") + std::to_string(p_index);
            // This side's y scale: the central 99 % of its residuals, widened by 15 % on each side
            // (and reaching 0); residuals beyond it are drawn at its edge.
            std::vector<double> all;
            all.reserve(p.residuals.size());
            for (std::size_t i : p.residuals) all.push_back(res[i]);
            double lo = std::min(0.0, quantile(all, 0.005)), hi = std::max(0.0, quantile(all, 0.995));
            const double span = hi > lo ? hi - lo : std::max(1.0, std::abs(hi));
            lo -= 0.15 * span;
            hi += 0.15 * span;
            std::vector<std::vector<double>> pts, clip, mean;
            for (std::size_t k = 0; k < p.residuals.size(); k += std::max<std::size_t>(1, stride)) {
              const std::size_t i = p.residuals[k];
              if (res[i] < lo) clip.push_back({xpos(i), lo, 11});
              else if (res[i] > hi) clip.push_back({xpos(i), hi, 9});
              else pts.push_back({xpos(i), res[i], static_cast<double>(marker_of[i])});
            }
            std::size_t beyond = 0;  // every residual beyond the scale, not only those drawn
            for (std::size_t i : p.residuals) beyond += res[i] < lo || res[i] > hi;
            // Means: per category, or over equal-count bins of the covariate (by value when it
            // takes few values).
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
              double sx = 0, sy = 0;
              for (std::size_t k = start; k < end; ++k) {
                sx += x[order[k]];
                sy += res[order[k]];
              }
              const double m = static_cast<double>(end - start);
              if (axis.categorical) mean.push_back({static_cast<double>(position[x[order[start]]]), std::clamp(sy / m, lo, hi), 0.3});
              else mean.push_back({sx / m, std::clamp(sy / m, lo, hi)});
              start = end;
            }
            gp << datablock(name, pts) << datablock(name + "m", mean);
            if (!clip.empty()) gp << datablock(name + "c", clip);

            const bool small_panel = small_panels;
            // Qualified: for a non-const std::string, ADL would pick std::quoted (a better match),
            // which leaves the title's line break raw and breaks gnuplot's command line.
            gp << "set title " << plot::quoted(panel_title(side, p, stride, beyond, small_panel, panel_w_px)) << " font ',11'\n";
            // On a page, the short forms: the panel's title says what is measured.
            // (a charge's "fraction of full charge" in short: "of full charge")
            const std::string unit_short = p.unit.rfind("fraction of ", 0) == 0 ? p.unit.substr(9) : p.unit.substr(0, p.unit.find(','));
            // Several quantities (drive, camera): each named in its y label ("ToF residual (mm)").
            const std::string residual = panels.size() > 1 && !p.brief.empty() ? p.brief + " residual" : "residual";
            gp << "set ylabel " << quoted(narrow ? residual + " (" + unit_short + ")" : "measured − simulated (" + p.unit + ")") << "\n";
            if (rotate) {
              // This panel's lower border, then the tic labels' length below it.
              const int row = column ? 2 * (p_index - 1) + side + 1 : p_index;
              const int col = column ? 0 : side;
              const double panel_h = (layout.top - layout.bottom - (rows - 1) * layout.vspace) / rows;
              const double panel_w = (layout.right - layout.left - (layout.cols - 1) * layout.hspace) / layout.cols;
              const double border = layout.top - row * panel_h - (row - 1) * layout.vspace;
              const double y = border - (tics_px + 16.0) / height;
              const double xc = layout.left + col * (panel_w + layout.hspace) + panel_w / 2;
              gp << "unset xlabel\nunset label\nset label 90 " << quoted(axis.label) << " at screen " << num(xc) << "," << num(y)
                 << " center front\n";
            } else {
              const std::string xlabel = narrow && cov_name == "predicted" ? "simulated by the base model (" + unit_short + ")"
                                         : narrow && axis.categorical ? pl.categories.label
                                                                      : axis.label;
              // A small panel: the label in lines of its width, a size smaller.
              gp << "set xlabel " << quoted(small_panel ? wrapped(xlabel, panel_w_px + 20, 9) : xlabel) << (small_panel ? " font ',9'" : "") << "\n";
            }
            gp << "set yrange [" << num(lo) << ":" << num(hi) << "]\nset ytics " << num(tic_step(lo, hi, tics_that_fit(panel_h_px, 40)))
               << "\n";
            if (axis.categorical) {
              gp << "set xrange [-0.6:" << static_cast<double>(axis.categories.size()) - 0.4 << "]\n";
              std::string tics = "set xtics (";
              for (const auto& [v, label] : axis.categories) {
                // A page's: the numbers (an unlabelled tic where they skip) or the short names.
                const int at = position[v];
                const std::string shown = narrow ? pl.categories.tics[static_cast<std::size_t>(at)] : label;
                tics += (tics.back() == '(' ? "" : ", ") + quoted(shown) + " " + std::to_string(at) + (narrow && shown.empty() ? " 1" : "");
              }
              gp << tics << ")" << (rotate ? " rotate by 90 right font ',9'" : "") << "\nset grid noxtics\n";
            } else {
              gp << "set xrange [*:*]\nset grid xtics\n";
              if (narrow && !p.residuals.empty()) {  // about 4 tics: a page's panel is narrow for 6-digit labels
                double xmin = x[p.residuals.front()], xmax = xmin;
                for (std::size_t i : p.residuals) {
                  xmin = std::min(xmin, x[i]);
                  xmax = std::max(xmax, x[i]);
                }
                const double pad = 0.02 * (xmax - xmin) + (xmax > xmin ? 0.0 : 1.0);
                gp << "set xrange [" << num(xmin - pad) << ":" << num(xmax + pad) << "]\nset xtics "
                   << num(tic_step(xmin, xmax, std::min(5, tics_that_fit(panel_w_px, 85)))) << " norotate\n";
              } else {
                gp << "set xtics autofreq norotate\n";
              }
            }
            const std::string ps = pts.size() > 3000 ? "0.35" : "0.6";
            gp << "plot $" << name << " using 1:2:3 with points pt variable ps " << ps << " lc rgb '#99" << colour.substr(1) << "' notitle";
            if (axis.categorical)
              gp << ", $" << name << "m using 1:2:3 with xerrorbars pt 7 ps 0.9 lw 3 lc rgb '" << dark << "' notitle";
            else
              gp << ", $" << name << "m using 1:2 with linespoints lw 2.5 pt 5 ps 0.8 lc rgb '" << dark << "' notitle";
            if (!clip.empty()) gp << ", $" << name << "c using 1:2:3 with points pt variable ps 1.1 lc rgb '" << colour << "' notitle";
            gp << "\n";
          }
        }
        // The legend, once, under the title.
        gp << "unset label\n";
        std::vector<std::string> entries{"NaN with points pt 7 ps 0.8 lc rgb '#d62728' title 'a residual before'",
                           "NaN with points pt 7 ps 0.8 lc rgb '#1f77b4' title 'a residual after'",
                           std::string("NaN with linespoints lw 2.5 pt 5 lc rgb '#404040' title ") +
                               (probe.categorical ? (one_column ? "'mean'" : "'mean per category'") : one_column ? "'mean'" : narrow ? "'mean per bin'" : "'mean per bin of the x axis'"),
                           narrow ? "NaN with points pt 9 ps 1.1 lc rgb 'black' title 'off the scale'"
                                  : "NaN with points pt 9 ps 1.1 lc rgb 'black' title 'beyond the y scale, at its edge'"};
        for (std::size_t k = 0; k < robots.size(); ++k)
          entries.push_back("NaN with points pt " + std::to_string(robot_point_type(k)) + " ps 0.9 lc rgb '#404040' title " + quoted("robot " + robots[k]));
        gp << legend_band(one_column ? 0.01 : layout.left, one_column ? 0.99 : layout.right, 1.0 - (legend_top_px + 25.0 * legend_rows) / height,
                          1.0 - static_cast<double>(legend_top_px) / height, entries, 10, legend_rows);
        // A page's category key, under the panels' x labels: a line each, left-aligned (gnuplot
        // centres a label's line on its point), drawn by one more empty plot.
        if (!pl.categories.key.empty()) {
          gp << "unset key\n";
          const std::size_t n = pl.categories.key.size();
          for (std::size_t k = 0; k < n; ++k)
            gp << "set label " << 100 + k << " " << quoted(pl.categories.key[k]) << " at screen " << num(10.0 / width) << ","
               << num((8.0 + (static_cast<double>(n - 1 - k) + 0.5) * kKeyLine_px) / height) << " left front font '," << kKeyFont_pt << "'\n";
          gp << "plot NaN notitle\nunset label\n";
        }
        gp << "unset multiplot\n";
      },
      width, height);
}

}  // namespace epuck2::plot
