// What the figures draw, checked against what they claim to draw. tests/test_figures.cpp checks
// that each figure is drawn, in its format, with its axes and legend; this file checks its data:
// the gnuplot script the real binary sends (kept with EPUCK2_PLOT_SCRIPT_DIR, docs/cli.md
// "Figures") is read back, and
//   - every plotted reading is a row of the logs (read here from the CSV text), in the panel or
//     series of its own intensity, sensor or speed;
//   - every curve is the paper's formula (written here from the reference's statement of it) with
//     the coefficients the same run reports in its JSON, or the plug-in's published constants;
//   - the battery lifetime figure's runs, means and standard errors are the logs' end times, worked
//     here, and its published end times the paper's (Fig. 10).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <map>
#include <set>
#include <sstream>
#include <string>
#include <vector>

#include <sys/wait.h>
#include <unistd.h>

#include <nlohmann/json.hpp>

namespace test_figure_data_cpp {
namespace {

namespace fs = std::filesystem;
using nlohmann::json;
using Rows = std::vector<std::vector<double>>;

/// A gnuplot script as the binary sent it: its datablocks by name, and the inline ('-') data blocks
/// of its plot commands in order.
std::vector<double> numbers(const std::string& line) {
  std::vector<double> out;
  std::istringstream in(line);
  std::string word;
  while (in >> word) out.push_back(std::strtod(word.c_str(), nullptr));
  return out;
}

/// One element of a plot command: what it draws ($name, '-' or NaN for a legend entry), the
/// columns it takes (`using`, 1:2 when absent), its style (after `with`) and its title ("" for
/// notitle).
struct Element {
  std::string source;
  std::vector<int> columns{1, 2};
  std::string style, title;
};
struct Script {
  std::map<std::string, Rows> blocks;
  std::vector<Rows> inline_blocks;
  std::vector<std::vector<Element>> plots;  // each plot command's elements
};

/// The elements of a `plot` line: split at the commas outside quotes and parentheses.
std::vector<Element> elements_of(const std::string& line) {
  std::vector<std::string> parts;
  std::string cur;
  int depth = 0;
  char quote = 0;
  for (std::size_t i = 5; i < line.size(); ++i) {
    const char c = line[i];
    if (quote) {
      if (c == quote) quote = 0;
    } else if (c == '\'' || c == '"') {
      quote = c;
    } else if (c == '(') {
      ++depth;
    } else if (c == ')') {
      --depth;
    } else if (c == ',' && depth == 0) {
      parts.push_back(cur);
      cur.clear();
      continue;
    }
    cur += c;
  }
  parts.push_back(cur);
  std::vector<Element> out;
  for (std::string p : parts) {
    while (!p.empty() && p.front() == ' ') p.erase(0, 1);
    Element e;
    e.source = p.substr(0, p.find(' '));
    if (const std::size_t u = p.find(" using "); u != std::string::npos && u < p.find(" with ")) {
      e.columns.clear();
      std::string spec = p.substr(u + 7, p.find(' ', u + 7) - (u + 7));
      std::replace(spec.begin(), spec.end(), ':', ' ');
      for (double v : numbers(spec)) e.columns.push_back(static_cast<int>(v));
    }
    const std::size_t w = p.find(" with ");
    std::size_t t = p.find(" title ");
    const std::size_t nt = p.find(" notitle");
    const std::size_t style_end = std::min(t, nt);
    if (w != std::string::npos) e.style = p.substr(w + 6, style_end == std::string::npos ? std::string::npos : style_end - (w + 6));
    if (t != std::string::npos) e.title = p.substr(t + 8, p.size() - (t + 8) - 1);  // inside its quotes
    out.push_back(e);
  }
  return out;
}

/// The element of `plot` whose title contains `title` (or is `title`, with `whole`); exactly one
/// must.
const Element& titled(const std::vector<Element>& plot, const std::string& title, bool whole = false) {
  const Element* found = nullptr;
  for (const auto& e : plot)
    if (whole ? e.title == title : e.title.find(title) != std::string::npos) {
      EXPECT_EQ(found, nullptr) << "two series titled '" << title << "'";
      found = &e;
    }
  EXPECT_NE(found, nullptr) << "no series titled '" << title << "'";
  static const Element none;
  return found ? *found : none;
}

Script read_script(const fs::path& p) {
  std::ifstream in(p);
  EXPECT_TRUE(in.good()) << p;
  Script s;
  std::string line;
  while (std::getline(in, line)) {
    if (line.size() > 1 && line[0] == '$' && line.find(" << EOD") != std::string::npos) {
      const std::string name = line.substr(1, line.find(' ') - 1);
      Rows rows;
      while (std::getline(in, line) && line != "EOD") rows.push_back(numbers(line));
      s.blocks[name] = rows;
    } else if (line.rfind("plot ", 0) == 0) {
      s.plots.push_back(elements_of(line));
      std::size_t inl = 0;
      for (std::size_t at = line.find("'-'"); at != std::string::npos; at = line.find("'-'", at + 3)) ++inl;
      for (std::size_t b = 0; b < inl; ++b) {
        Rows rows;
        while (std::getline(in, line) && line != "e") rows.push_back(numbers(line));
        s.inline_blocks.push_back(rows);
      }
    }
  }
  return s;
}

/// A log's data rows by column name (comment lines '#' skipped).
struct Csv {
  std::vector<std::string> header;
  Rows rows;
  std::size_t col(const std::string& name) const {
    const auto it = std::find(header.begin(), header.end(), name);
    EXPECT_NE(it, header.end()) << name;
    return static_cast<std::size_t>(it - header.begin());
  }
};

Csv read_csv(const fs::path& p) {
  std::ifstream in(p);
  Csv c;
  std::string line;
  while (std::getline(in, line)) {
    if (line.empty() || line[0] == '#') continue;
    std::replace(line.begin(), line.end(), ',', ' ');
    if (c.header.empty()) {
      std::istringstream words(line);
      std::string w;
      while (words >> w) c.header.push_back(w);
    } else {
      c.rows.push_back(numbers(line));
    }
  }
  return c;
}

std::vector<fs::path> logs_of(const std::string& kind) {
  std::vector<fs::path> out;
  for (const auto& e : fs::directory_iterator(fs::path(EPUCK2_SOURCE_DIR) / "data/raw" / kind))
    if (e.path().extension() == ".csv") out.push_back(e.path());
  std::sort(out.begin(), out.end());
  return out;
}

/// Runs `epuck2-fit ARGS` with the figure scripts kept in `dir`; the JSON report (-o) is returned.
json run_fit(const fs::path& dir, const std::string& kind, const std::string& plots) {
  std::string cmd = "EPUCK2_PLOT_SCRIPT_DIR='" + dir.string() + "' '" EPUCK2_FIT_EXE "' " + kind;
  for (const auto& p : logs_of(kind)) cmd += " '" + p.string() + "'";
  cmd += " --json -o '" + (dir / "report.json").string() + "' " + plots + " >/dev/null 2>'" + (dir / "stderr.txt").string() + "'";
  const int rc = std::system(cmd.c_str());
  EXPECT_EQ(rc, 0) << cmd;
  std::ifstream in(dir / "report.json");
  return json::parse(in);
}

class FigureData : public ::testing::Test {
 protected:
  void SetUp() override {
    char tmpl[] = "/tmp/epuck2-figure-data-XXXXXX";
    ASSERT_NE(::mkdtemp(tmpl), nullptr);
    dir_ = tmpl;
  }
  void TearDown() override {
    std::error_code ec;
    fs::remove_all(dir_, ec);
  }
  fs::path dir_;
};

/// The 0-based index of the y column `e` draws from `block`.
std::size_t y_of(const Element& e, const std::string& block) {
  EXPECT_EQ(e.source, "$" + block) << e.title;
  EXPECT_GE(e.columns.size(), 2u) << e.title;
  return e.columns.size() >= 2 ? static_cast<std::size_t>(e.columns[1] - 1) : 0;
}

constexpr double kDatablockDigits = 1e-9;  // datablocks carry 10 significant digits

void expect_near_rel(double want, double got, const std::string& what) {
  EXPECT_NEAR(got, want, 2 * kDatablockDigits * std::max(1.0, std::abs(want))) << what;
}

// ---- proximity: paper Eq. 1, the reading / 4095 = clamp01(a d^2 + b d + c) within the range ----

double eq1(double a, double b, double c, double range_m, double d) {
  if (d > range_m) return 0.0;
  return std::clamp(a * d * d + b * d + c, 0.0, 1.0);
}

TEST_F(FigureData, ProximityCurvesAreEq1WithTheReportedAndThePublishedCoefficients) {
  const json r = run_fit(dir_, "proximity", "--plot '" + (dir_ / "p.png").string() + "'");
  const Script s = read_script(dir_ / "p.png.gp");
  const json& k = r["parameters"];
  const Rows& curves = s.blocks.at("curves");
  ASSERT_GE(curves.size(), 100u);
  EXPECT_EQ(curves.front()[0], 0.0);
  EXPECT_NEAR(curves.back()[0], 50.0, 1e-9);
  // Each curve found by its legend entry: what is drawn under a title is what the title says.
  ASSERT_EQ(s.plots.size(), 1u);
  const auto& plot = s.plots[0];
  const std::size_t maxima = y_of(titled(plot, "fit to maxima"), "curves"), means = y_of(titled(plot, "fit to means"), "curves"),
                    plugin = y_of(titled(plot, "plug-in"), "curves"), v1 = y_of(titled(plot, "E-Puck v1"), "curves");
  for (const auto& row : curves) {
    ASSERT_EQ(row.size(), 5u);
    const double d = row[0] / 1000.0;
    expect_near_rel(eq1(k["a"], k["b"], k["c"], k["range_m"], d), row.at(maxima), "fit to maxima at " + std::to_string(row[0]));
    expect_near_rel(eq1(k["mean_a"], k["mean_b"], k["mean_c"], k["range_m"], d), row.at(means), "fit to means");
    // The plug-in's (reference: 197.8633, -30.47182, 1.011635, range 0.05 m) and the E-Puck v1's.
    expect_near_rel(eq1(197.8633, -30.47182, 1.011635, 0.05, d), row.at(plugin), "plug-in");
    expect_near_rel(eq1(298.701, -36.8961, 1.08212, 0.05, d), row.at(v1), "E-Puck v1");
  }
  // The points titled maxima and means: the $pts columns of the max and the mean (distance, min,
  // mean, max; checked against the logs below).
  EXPECT_EQ(y_of(titled(plot, "maxima", true), "pts"), 3u);
  EXPECT_EQ(y_of(titled(plot, "means", true), "pts"), 2u);
}

// Each distance's point: the readings at that distance / 4095 (every sensor, every log) less the
// fit's outliers: where the report keeps them all, their min, mean and max exactly; else within.
TEST_F(FigureData, ProximityPointsAreTheLogsReadingsAtEachDistance) {
  const json r = run_fit(dir_, "proximity", "--plot '" + (dir_ / "p.png").string() + "'");
  const Script s = read_script(dir_ / "p.png.gp");
  std::map<long, std::vector<double>> at;  // key: distance in micrometres
  for (const auto& p : logs_of("proximity")) {
    const Csv c = read_csv(p);
    for (const auto& row : c.rows) at[std::lround(row[c.col("distance_m")] * 1e6)].push_back(row[c.col("value")] / 4095.0);
  }
  Rows drawn = s.blocks.at("pts");
  if (s.blocks.count("out")) drawn.insert(drawn.end(), s.blocks.at("out").begin(), s.blocks.at("out").end());
  ASSERT_EQ(drawn.size(), at.size()) << "one point per logged distance";
  std::size_t exact = 0;
  for (const auto& row : drawn) {
    ASSERT_EQ(row.size(), 5u);
    const auto it = at.find(std::lround(row[0] * 1000.0));
    ASSERT_NE(it, at.end()) << "a point at " << row[0] << " mm, a distance no log has";
    const std::vector<double>& v = it->second;
    const double lo = *std::min_element(v.begin(), v.end()), hi = *std::max_element(v.begin(), v.end());
    double mean = 0;
    for (double x : v) mean += x;
    mean /= static_cast<double>(v.size());
    EXPECT_LE(row[1], row[2]);
    EXPECT_LE(row[2], row[3]);
    EXPECT_GE(row[1], lo - 1e-9);
    EXPECT_LE(row[3], hi + 1e-9);
    // The report's point at that distance: how many it kept.
    for (const auto& p : r["points"])
      if (std::lround(p["distance_m"].get<double>() * 1e6) == it->first && p["kept"] == p["readings"]) {
        ++exact;
        expect_near_rel(lo, row[1], "min at " + std::to_string(row[0]));
        expect_near_rel(mean, row[2], "mean at " + std::to_string(row[0]));
        expect_near_rel(hi, row[3], "max at " + std::to_string(row[0]));
        EXPECT_EQ(row[4], 1.0);
      }
  }
  EXPECT_GE(exact, 3u) << "the shipped logs have distances without a wild reading";
}

// ---- light: paper Eq. 2, 4095 (1 - (gamma I / d)^2) within 0.5 m, clamped to [0, 4095] ----

double eq2(double gamma_m, double intensity, double d) {
  if (d > 0.5) return 4095.0;
  const double x = gamma_m * intensity / d;
  return std::clamp(4095.0 * (1.0 - x * x), 0.0, 4095.0);
}

TEST_F(FigureData, LightReadingsAreTheLogsRowsOfTheirIntensityAndTheCurvesEq2) {
  const json r = run_fit(dir_, "light", "--plot '" + (dir_ / "l.png").string() + "'");
  const Script s = read_script(dir_ / "l.png.gp");
  std::map<double, std::multiset<std::pair<long, long>>> rows;  // intensity: (distance in um, value)
  std::size_t total = 0;
  for (const auto& p : logs_of("light")) {
    const Csv c = read_csv(p);
    for (const auto& row : c.rows) {
      rows[row[c.col("intensity")]].insert({std::lround(row[c.col("distance_m")] * 1e6), std::lround(row[c.col("value")])});
      ++total;
    }
  }
  ASSERT_EQ(rows.size(), 4u);
  const double gamma = r["parameters"]["gamma"];
  std::size_t k = 0, drawn = 0;
  for (const auto& [intensity, logged] : rows) {  // the blocks in increasing intensity
    const std::string i = "i" + std::to_string(k), c = "c" + std::to_string(k);
    ASSERT_TRUE(s.blocks.count(i) && s.blocks.count(c)) << k;
    std::multiset<std::pair<long, long>> left = logged;
    for (const auto& row : s.blocks.at(i)) {
      const auto it = left.find({std::lround(row[0] * 1e4), std::lround(row[1])});
      ASSERT_NE(it, left.end()) << "I = " << intensity << ": a reading (" << row[0] << " cm, " << row[1]
                                << ") that is not a row of its logs";
      left.erase(it);
      ++drawn;
    }
    // docs/cli.md: the fit solid, the plug-in dashed (`dt`), in the intensity's colour; the
    // intensity's legend entry names it.
    std::size_t fit = 0, plugin = 0, lines = 0;
    std::string colour;
    for (const auto& e : s.plots.at(0))
      if (e.source == "$" + c) {
        ++lines;
        (e.style.find(" dt ") != std::string::npos ? plugin : fit) = y_of(e, c);
      } else if (e.source == "$" + i) {
        colour = e.style.substr(e.style.find("lc rgb"));
      }
    ASSERT_EQ(lines, 2u);
    char name[32];
    std::snprintf(name, sizeof name, "I = %.2f", intensity);
    const Element& entry = titled(s.plots.at(0), name);
    EXPECT_EQ(entry.source, "NaN");
    EXPECT_NE(entry.style.find(colour), std::string::npos) << name << " is not drawn in its readings' colour";
    for (const auto& row : s.blocks.at(c)) {
      expect_near_rel(eq2(gamma, intensity, row[0] / 100.0), row.at(fit), "fit at I " + std::to_string(intensity));
      expect_near_rel(eq2(1.0 / 13.3333333333333, intensity, row[0] / 100.0), row.at(plugin), "plug-in");
    }
    ++k;
  }
  // A PNG draws every reading the fit used: all but its outliers.
  EXPECT_LE(drawn, total);
  EXPECT_GE(static_cast<double>(drawn), 0.97 * static_cast<double>(total));
}

// ---- ground: each sensor's line offset + gain grey, the plug-in's 1023 grey ----

// The readings are drawn shifted sideways (the axis label says by how much): with two robots,
// sensor k's by (k - 1) 0.005 and robot r's by (r - 1/2) 0.02; each robot has its marker.
TEST_F(FigureData, GroundReadingsAreEachSensorsRowsAndTheLinesTheReportedOnes) {
  const json r = run_fit(dir_, "ground", "--plot '" + (dir_ / "g.png").string() + "'");
  const Script s = read_script(dir_ / "g.png.gp");
  // (sensor, robot): (grey in 1e-6, value); the robots in the logs' order.
  std::map<std::pair<int, int>, std::multiset<std::pair<long, long>>> rows;
  int robot = 0;
  for (const auto& p : logs_of("ground")) {
    const Csv c = read_csv(p);
    for (const auto& row : c.rows)
      rows[{static_cast<int>(row[c.col("sensor")]), robot}].insert({std::lround(row[c.col("grey")] * 1e6), std::lround(row[c.col("value")])});
    ++robot;
  }
  ASSERT_EQ(robot, 2);
  ASSERT_EQ(rows.size(), 6u);
  std::map<int, int> robot_of_marker;
  for (int sensor = 0; sensor < 3; ++sensor) {
    const Rows& drawn = s.blocks.at("s" + std::to_string(sensor));
    EXPECT_GE(static_cast<double>(drawn.size()), 0.97 * static_cast<double>(rows[{sensor, 0}].size() + rows[{sensor, 1}].size()));
    for (const auto& row : drawn) {
      bool found = false;
      for (int rb = 0; rb < 2 && !found; ++rb) {
        const double shift = (sensor - 1) * 0.005 + (rb - 0.5) * 0.02;
        auto& left = rows[{sensor, rb}];
        const auto it = left.find({std::lround((row[0] - shift) * 1e6), std::lround(row[1])});
        if (it == left.end()) continue;
        left.erase(it);
        found = true;
        const auto m = robot_of_marker.emplace(static_cast<int>(row[2]), rb).first;
        EXPECT_EQ(m->second, rb) << "one marker, two robots";
      }
      ASSERT_TRUE(found) << "sensor " << sensor << ": (" << row[0] << ", " << row[1] << ") is not one of its rows, shifted";
    }
  }
  EXPECT_EQ(robot_of_marker.size(), 2u);
  const json& k = r["parameters"];
  const Rows& lines = s.blocks.at("lines");
  ASSERT_GE(lines.size(), 2u);
  std::size_t column[3];
  for (int sensor = 0; sensor < 3; ++sensor) {
    const Element& e = titled(s.plots.at(0), "sensor " + std::to_string(sensor) + " (");
    column[sensor] = y_of(e, "lines");
    // The title's numbers: the sensor's offset and gain to 0.1.
    char want[64];
    std::snprintf(want, sizeof want, "fit: %.1f + %.1f grey", k["offset"][sensor].get<double>(), k["gain"][sensor].get<double>());
    EXPECT_NE(e.title.find(want), std::string::npos) << e.title << " (expected " << want << ")";
    // Its readings drawn in its colour.
    for (const auto& d : s.plots.at(0))
      if (d.source == "$s" + std::to_string(sensor)) EXPECT_NE(e.style.find(d.style.substr(d.style.find("lc rgb"), 17)), std::string::npos);
  }
  const std::size_t plugin = y_of(titled(s.plots.at(0), "plug-in"), "lines");
  for (const auto& row : lines) {
    ASSERT_EQ(row.size(), 5u);
    for (int sensor = 0; sensor < 3; ++sensor)
      expect_near_rel(k["offset"][sensor].get<double>() + k["gain"][sensor].get<double>() * row[0], row.at(column[sensor]),
                      "sensor " + std::to_string(sensor) + " at grey " + std::to_string(row[0]));
    expect_near_rel(1023.0 * row[0], row.at(plugin), "plug-in");
  }
  EXPECT_EQ(lines.front()[0], 0.0);
  EXPECT_EQ(lines.back()[0], 1.0);
}

// ---- camera: the pinhole of the reference, column = cx - (W/2) (lateral/forward) / tan(fov/2),
// row = cy - (W/2) (vertical/forward) / tan(fov/2) (square pixels); the plug-in's fov
// 2 atan(0.8 tan 18.5 deg) = 29.97 deg, centre (80, 60) ----

TEST_F(FigureData, CameraObservationsAreTheLogsAndTheCurvesThePinhole) {
  const json r = run_fit(dir_, "camera", "--plot '" + (dir_ / "c.png").string() + "'");
  const Script s = read_script(dir_ / "c.png.gp");
  std::multiset<std::vector<long>> logged;
  for (const auto& p : logs_of("camera")) {
    const Csv c = read_csv(p);
    for (const auto& row : c.rows) {
      const double fwd = row[c.col("forward_m")];
      logged.insert({std::lround(row[c.col("lateral_m")] / fwd * 1e9), std::lround(row[c.col("px")]),
                     std::lround(row[c.col("vertical_m")] / fwd * 1e9), std::lround(row[c.col("py")])});
    }
  }
  const json& k = r["parameters"];
  const double pi = std::acos(-1.0);
  const double t_fit = std::tan(k["fov_deg"].get<double>() * pi / 360.0);
  const double t_plugin = 0.8 * std::tan(18.5 * pi / 180.0);
  const Rows& obs = s.blocks.at("obs");
  // The column panel, then the row panel; in each the series titled fit and plug-in, and the
  // observations (notitle, the legend's entries name the robots).
  ASSERT_EQ(s.plots.size(), 2u);
  const std::size_t fit_col = y_of(titled(s.plots[0], "fit", true), "obs"), plugin_col = y_of(titled(s.plots[0], "plug-in"), "obs");
  const std::size_t fit_row = y_of(titled(s.plots[1], "fit", true), "obs"), plugin_row = y_of(titled(s.plots[1], "plug-in"), "obs");
  EXPECT_EQ(s.plots[0][0].columns[0], 1);
  EXPECT_EQ(s.plots[0][0].columns[1], 2);
  EXPECT_EQ(s.plots[1][0].columns[0], 5);
  EXPECT_EQ(s.plots[1][0].columns[1], 6);
  for (const auto* plot : {&s.plots[0], &s.plots[1]})
    for (const auto& e : *plot)
      if (e.source == "$obs") EXPECT_EQ(e.columns[0], plot == &s.plots[0] ? 1 : 5) << "an x that is not the panel's";
  EXPECT_GE(static_cast<double>(obs.size()), 0.97 * static_cast<double>(logged.size()));
  for (const auto& row : obs) {
    ASSERT_GE(row.size(), 8u);
    // The datablock's 10 digits: the ratios to 1e-9 relative.
    bool found = false;
    for (long dl : {-1L, 0L, 1L})
      for (long dv : {-1L, 0L, 1L}) {
        const auto it = logged.find({std::lround(row[0] * 1e9) + dl, std::lround(row[1]), std::lround(row[4] * 1e9) + dv, std::lround(row[5])});
        if (it != logged.end() && !found) {
          logged.erase(it);
          found = true;
        }
      }
    EXPECT_TRUE(found) << "(" << row[0] << ", " << row[1] << ", " << row[4] << ", " << row[5] << ") is not a row of the logs";
    expect_near_rel(k["cx_px"].get<double>() - 80.0 * row[0] / t_fit, row.at(fit_col), "fitted column");
    expect_near_rel(80.0 - 80.0 * row[0] / t_plugin, row.at(plugin_col), "plug-in column");
    expect_near_rel(k["cy_px"].get<double>() - 80.0 * row[4] / t_fit, row.at(fit_row), "fitted row");
    expect_near_rel(60.0 - 80.0 * row[4] / t_plugin, row.at(plugin_row), "plug-in row");
  }
}

// ---- drive: the ToF readings and the encoders as logged; the ToF response scale d + offset and
// the plug-in's d, both clamped to the sensor's rails [20, 2000] mm; the encoders' steps per
// metre, fitted and the plug-in's 1000 / (2 pi 0.0205 m) = 7763.656 (the reference) ----

TEST_F(FigureData, DriveReadingsAreTheLogsRowsAndTheResponsesTheReportedOnes) {
  const json r = run_fit(dir_, "drive", "--plot '" + (dir_ / "d.png").string() + "'");
  const Script s = read_script(dir_ / "d.png.gp");
  const json& k = r["parameters"];
  const double scale = k["tof_scale"], offset = k["tof_offset_mm"], spm = k["steps_per_m"];
  // Every run's drawn rows: time, reading (NaN for an out-of-range code, then drawn at 2250 mm in
  // column 7), ..., steps (column 5): a log's rows, in order.
  std::vector<Csv> logs;
  for (const auto& p : logs_of("drive")) logs.push_back(read_csv(p));
  std::size_t runs = 0, codes = 0;
  for (const auto& [name, rows] : s.blocks) {
    if (name.size() < 2 || name[0] != 'r' || name.find_first_not_of("0123456789", 1) != std::string::npos) continue;
    ++runs;
    bool matched = false;
    for (const Csv& c : logs) {
      std::size_t at = 0, hits = 0;
      for (const auto& row : rows) {
        while (at < c.rows.size() && std::lround(c.rows[at][c.col("time_s")] * 1000) != std::lround(row[0] * 1000)) ++at;
        if (at == c.rows.size()) break;
        const double tof = c.rows[at][c.col("tof_mm")];
        const bool code = tof >= 8190;
        const bool same_reading = code ? (std::isnan(row[1]) && row[6] == 2250.0) : (row[1] == tof && std::isnan(row[6]));
        const double steps = 0.5 * (c.rows[at][c.col("left_steps")] + c.rows[at][c.col("right_steps")]);
        if (!same_reading || std::abs(row[4] - steps) > 0.5) break;
        codes += code;
        ++hits;
        ++at;
      }
      if (hits == rows.size()) {
        matched = true;
        break;
      }
    }
    EXPECT_TRUE(matched) << "$" << name << " is not a log's rows (time, ToF, steps)";
  }
  EXPECT_EQ(runs, logs.size());
  EXPECT_GT(codes, 0u) << "the shipped drive logs have out-of-range codes";
  // The standing-still panel's responses and the encoders' lines, each by its style: the fit
  // solid, the plug-in dashed.
  auto by_style = [&](const std::string& block, bool dashed) {
    for (const auto& plot : s.plots)
      for (const auto& e : plot)
        if (e.source == "$" + block && (e.style.find(" dt ") != std::string::npos) == dashed) return y_of(e, block);
    ADD_FAILURE() << "no " << (dashed ? "dashed" : "solid") << " line of $" << block;
    return std::size_t{0};
  };
  const std::size_t still_fit = by_style("still", false), still_plugin = by_style("still", true);
  ASSERT_GE(s.blocks.at("still").size(), 10u);
  for (const auto& row : s.blocks.at("still")) {
    expect_near_rel(std::clamp(scale * row[0] + offset, 20.0, 2000.0), row.at(still_fit), "fitted ToF at " + std::to_string(row[0]));
    expect_near_rel(std::clamp(row[0], 20.0, 2000.0), row.at(still_plugin), "plug-in ToF");
  }
  const std::size_t steps_fit = by_style("steps", false), steps_plugin = by_style("steps", true);
  ASSERT_GE(s.blocks.at("steps").size(), 2u);
  for (const auto& row : s.blocks.at("steps")) {
    expect_near_rel(spm * row[0] / 1000.0, row.at(steps_fit), "fitted steps at " + std::to_string(row[0]) + " mm");
    expect_near_rel(7763.656 * row[0] / 1000.0, row.at(steps_plugin), "plug-in steps");
  }
}

// ---- battery ----

struct BatteryRun {
  double speed = 0;
  std::vector<double> t, charge, voltage;
};
std::vector<BatteryRun> battery_runs() {
  std::vector<BatteryRun> out;
  for (const auto& p : logs_of("battery")) {
    const Csv c = read_csv(p);
    BatteryRun r;
    r.speed = c.rows.front()[c.col("speed_cm_s")];
    for (const auto& row : c.rows) {
      r.t.push_back(row[c.col("time_s")]);
      r.charge.push_back(row[c.col("charge")]);
      r.voltage.push_back(row[c.col("voltage_v")]);
    }
    out.push_back(r);
  }
  return out;
}

// Lifetime: each run's last logged time (the logs end at the stop, data/raw/battery/README.md),
// the mean of a speed's runs and its standard error sd / sqrt(n), and the paper's end times.
TEST_F(FigureData, TheLifetimeFigureIsTheLogsEndTimesTheirMeansAndThePublishedOnes) {
  const fs::path stage = dir_;
  run_fit(stage, "battery", "--plot-lifetime '" + (dir_ / "life.png").string() + "'");
  const Script s = read_script(dir_ / "life.png.gp");
  ASSERT_EQ(s.inline_blocks.size(), 3u);
  const std::vector<BatteryRun> runs = battery_runs();
  std::multiset<std::pair<long, long>> ends;  // (speed in 0.01 cm/s, end in ms)
  std::map<long, std::vector<double>> by_speed;
  for (const auto& r : runs) {
    ends.insert({std::lround(r.speed * 100), std::lround(r.t.back() * 1000)});
    by_speed[std::lround(r.speed * 100)].push_back(r.t.back() / 3600.0);
  }
  ASSERT_EQ(s.inline_blocks[0].size(), runs.size());
  for (const auto& row : s.inline_blocks[0]) {
    const auto it = ends.find({std::lround(row[0] * 100), std::lround(row[1] * 3600 * 1000)});
    ASSERT_NE(it, ends.end()) << "a run at " << row[0] << " cm/s ending at " << row[1] << " h: no log";
    ends.erase(it);
  }
  ASSERT_EQ(s.inline_blocks[1].size(), by_speed.size());
  for (const auto& row : s.inline_blocks[1]) {
    const std::vector<double>& h = by_speed.at(std::lround(row[0] * 100));
    double mean = 0, ss = 0;
    for (double x : h) mean += x;
    mean /= static_cast<double>(h.size());
    for (double x : h) ss += (x - mean) * (x - mean);
    const double se = h.size() > 1 ? std::sqrt(ss / static_cast<double>(h.size() - 1) / static_cast<double>(h.size())) : 0.0;
    EXPECT_NEAR(row[1], mean, 1e-9) << row[0] << " cm/s";
    EXPECT_NEAR(row[2], se, 1e-9) << row[0] << " cm/s";
  }
  // Paper Fig. 10's end times (the reference's, to their 2 decimals: the plug-in's tables hold
  // 19743.4806580544 ...), s.
  const double published[16] = {19743.48, 16021.85, 12856.62, 11142.83, 9166.25, 9355.34, 9202.55, 9729.11,
                                9897.89,  10356.66, 11057.34, 11638.03, 12765.53, 13055.41, 13228.29, 12957.47};
  ASSERT_EQ(s.inline_blocks[2].size(), 16u);
  for (int k = 0; k < 16; ++k) {
    EXPECT_EQ(s.inline_blocks[2][k][0], k);
    EXPECT_NEAR(s.inline_blocks[2][k][1], published[k] / 3600.0, 0.006 / 3600.0) << k << " cm/s";
  }
}

// The fits figure: per speed (increasing), the four models then the logs. The models worked here
// from the report's coefficients: simple 1 + slope t (the static slope at 0 cm/s, else the moving
// one), linear 1 + slope t, both floored at 0; cubic d + c t + b t^2 + a t^3 (the report's
// `cubic`, constant term first); approximated the line through (0, 1), (x1, y1), (x2, y2),
// (lifetime - 1 s, y3). The logs' points are each run's rows of that speed.
TEST_F(FigureData, TheBatteryFitsFigureDrawsTheReportedModelsAndTheLogsRows) {
  const json r = run_fit(dir_, "battery", "--plot '" + (dir_ / "fits.png").string() + "'");
  const Script s = read_script(dir_ / "fits.png.gp");
  const json& speeds = r["speeds"];
  ASSERT_EQ(s.inline_blocks.size(), 5 * speeds.size());
  const std::vector<BatteryRun> runs = battery_runs();
  for (std::size_t i = 0; i < speeds.size(); ++i) {
    const json& sp = speeds[i];
    const double v = sp["speed_cm_s"], life = sp["lifetime_s"];
    const double simple = v == 0 ? r["simple"]["static_slope_per_s"].get<double>() : r["simple"]["moving_slope_per_s"].get<double>();
    const double linear = sp["linear_slope"];
    const json& cu = sp["cubic"];
    const json& bp = sp["breakpoints"]["parameters"];
    const double x[4] = {0.0, bp["x1_s"], bp["x2_s"], life - 1.0}, y[4] = {1.0, bp["y1"], bp["y2"], bp["y3"]};
    // Which curve is which: the style of the legend's entry for the model.
    const char* names[4] = {"simple", "linear", "cubic", "approximated"};
    ASSERT_GE(s.plots.size(), speeds.size());
    ASSERT_EQ(s.plots[i].size(), 5u);
    for (int m = 0; m < 4; ++m) {
      const Element* entry = nullptr;
      for (const auto& plot : s.plots)
        for (const auto& e : plot)
          if (e.source == "NaN" && e.title.rfind(names[m], 0) == 0) entry = &e;
      ASSERT_NE(entry, nullptr) << names[m];
      const Element& drawn = s.plots[i][static_cast<std::size_t>(m)];
      EXPECT_EQ(drawn.source, "'-'");
      EXPECT_EQ(drawn.style, entry->style) << v << " cm/s: the " << names[m] << " curve is drawn in another model's style";
      const Rows& c = s.inline_blocks[5 * i + static_cast<std::size_t>(m)];
      ASSERT_GE(c.size(), 100u);
      EXPECT_NEAR(c.back()[0], life / 3600.0, 1e-9);
      for (const auto& row : c) {
        const double t = row[0] * 3600.0;
        double want = 0;
        if (m == 0) want = std::max(0.0, 1.0 + simple * t);
        if (m == 1) want = std::max(0.0, 1.0 + linear * t);
        if (m == 2) want = cu[0].get<double>() + cu[1].get<double>() * t + cu[2].get<double>() * t * t + cu[3].get<double>() * t * t * t;
        if (m == 3) {
          if (t > x[3]) continue;  // (beyond the last knot: extrapolated, not checked)
          int seg = t <= x[1] ? 0 : t <= x[2] ? 1 : 2;
          want = y[seg] + (y[seg + 1] - y[seg]) * (t - x[seg]) / (x[seg + 1] - x[seg]);
        }
        EXPECT_NEAR(row[1], want, 1e-9) << v << " cm/s, model " << m << ", t " << t;
      }
    }
    // The logs: every drawn point a row of a run at this speed; each run ends its line with NaN.
    std::multiset<std::pair<long, long>> logged;
    std::size_t n_runs = 0;
    for (const auto& run : runs)
      if (std::lround(run.speed * 100) == std::lround(v * 100)) {
        ++n_runs;
        for (std::size_t k = 0; k < run.t.size(); ++k) logged.insert({std::lround(run.t[k] * 1000), std::lround(run.charge[k] * 1e6)});
      }
    ASSERT_EQ(n_runs, sp["runs"].get<std::size_t>());
    std::size_t nans = 0, points = 0;
    for (const auto& row : s.inline_blocks[5 * i + 4]) {
      if (std::isnan(row[0])) {
        ++nans;
        continue;
      }
      const auto it = logged.find({std::lround(row[0] * 3600 * 1000), std::lround(row[1] * 1e6)});
      ASSERT_NE(it, logged.end()) << v << " cm/s: (" << row[0] << " h, " << row[1] << ") is not a row of its runs";
      logged.erase(it);
      ++points;
    }
    EXPECT_EQ(nans, n_runs);
    EXPECT_GE(points, 100 * n_runs);
    EXPECT_LE(points, 400 * n_runs);
  }
}

// The charge map (the shipped set's map has no load term): the line is the map's linear
// interpolation between its reported knots, the knots are drawn where they are, every drawn row
// is a logged (voltage, charge), and every residual is that row's charge minus the line.
TEST_F(FigureData, TheChargeMapFigureDrawsTheLogsRowsTheMapAndTheirDifference) {
  const json r = run_fit(dir_, "battery", "--plot-charge-map '" + (dir_ / "map.png").string() + "'");
  const Script s = read_script(dir_ / "map.png.gp");
  ASSERT_EQ(s.inline_blocks.size(), 4u);
  const json& m = r["charge_map"];
  ASSERT_EQ(m["load"], "none");
  const std::vector<double> kv = m["knots_v"], kc = m["knot_charge"];
  auto f = [&](double v) {
    const double lo = m["voltage_range_v"][0], hi = m["voltage_range_v"][1];
    v = std::clamp(v, lo, hi);
    std::size_t k = 0;
    while (k + 2 < kv.size() && v > kv[k + 1]) ++k;
    return kc[k] + (kc[k + 1] - kc[k]) * (v - kv[k]) / (kv[k + 1] - kv[k]);
  };
  std::multiset<std::pair<long, long>> logged;
  for (const auto& run : battery_runs())
    for (std::size_t k = 0; k < run.t.size(); ++k) logged.insert({std::lround(run.voltage[k] * 1e4), std::lround(run.charge[k] * 1e6)});
  const Rows& pts = s.inline_blocks[0];
  // At most about 4000 in a PNG (docs/cli.md): every k-th of the 38 471 rows, k = 38 471 / 4000 = 9.
  const std::size_t n = m["observations"];
  const std::size_t stride = std::max<std::size_t>(1, n / 4000);
  EXPECT_EQ(pts.size(), (n + stride - 1) / stride);
  for (const auto& row : pts) {
    const auto it = logged.find({std::lround(row[0] * 1e4), std::lround(row[1] * 1e6)});
    ASSERT_NE(it, logged.end()) << "(" << row[0] << " V, " << row[1] << ") is not a logged row";
  }
  for (const auto& row : s.inline_blocks[1]) EXPECT_NEAR(row[1], f(row[0]), 1e-12) << row[0] << " V";
  ASSERT_EQ(s.inline_blocks[2].size(), kv.size());
  for (std::size_t k = 0; k < kv.size(); ++k) {
    EXPECT_EQ(s.inline_blocks[2][k][0], kv[k]);
    EXPECT_EQ(s.inline_blocks[2][k][1], kc[k]);
  }
  const Rows& resid = s.inline_blocks[3];
  ASSERT_EQ(resid.size(), pts.size());
  for (std::size_t i = 0; i < pts.size(); ++i) {
    EXPECT_EQ(resid[i][0], pts[i][0]);
    EXPECT_NEAR(resid[i][1], pts[i][1] - f(pts[i][0]), 1e-12) << pts[i][0] << " V";
  }
}

// A map with a load term (docs/coefficient-files.md: charge = f(voltage_v + load_offset_v(speed)),
// load_offset_v linear between load_speeds_cm_s, the end values beyond them): the shipped runs with
// their voltage lowered by 2 mV per cm/s (a sag under load, 30 mV at 15 cm/s), which the map must
// take as a load term. Every drawn row stands at its corrected voltage, and its residual is its
// charge minus f at that voltage -- each row at its own speed.
TEST_F(FigureData, AChargeMapWithALoadTermDrawsEachRowAtItsOwnSpeedsCorrection) {
  std::string cmd = "EPUCK2_PLOT_SCRIPT_DIR='" + dir_.string() + "' '" EPUCK2_FIT_EXE "' battery";
  std::vector<BatteryRun> runs;
  for (const auto& p : logs_of("battery")) {
    std::ifstream in(p);
    std::ofstream out(dir_ / p.filename());
    std::string line;
    bool header = false;
    BatteryRun run;
    while (std::getline(in, line)) {
      if (line.empty() || line[0] == '#') {
        out << line << "\n";
        continue;
      }
      if (!header) {
        ASSERT_EQ(line, "time_s,speed_cm_s,charge,voltage_v");
        header = true;
        out << line << "\n";
        continue;
      }
      std::replace(line.begin(), line.end(), ',', ' ');
      const std::vector<double> r = numbers(line);
      const double v = r[3] - 0.002 * std::abs(r[1]);
      char row[128];
      std::snprintf(row, sizeof row, "%.17g,%.17g,%.17g,%.6f\n", r[0], r[1], r[2], v);
      out << row;
      run.speed = r[1];
      run.t.push_back(r[0]);
      run.charge.push_back(r[2]);
      run.voltage.push_back(std::strtod(row + std::string(row).rfind(',') + 1, nullptr));
    }
    runs.push_back(run);
    cmd += " '" + (dir_ / p.filename()).string() + "'";
  }
  cmd += " --json -o '" + (dir_ / "r.json").string() + "' --plot-charge-map '" + (dir_ / "map.png").string() + "' >/dev/null 2>&1";
  ASSERT_EQ(std::system(cmd.c_str()), 0) << cmd;
  std::ifstream in(dir_ / "r.json");
  const json m = json::parse(in)["charge_map"];
  ASSERT_EQ(m["load"], "per_speed") << m.dump();
  const std::vector<double> kv = m["knots_v"], kc = m["knot_charge"], ls = m["load_speeds_cm_s"], lo = m["load_offset_v"];
  ASSERT_EQ(ls.size(), lo.size());
  auto offset = [&](double speed) {
    const double s = std::abs(speed);
    if (s <= ls.front()) return lo.front();
    if (s >= ls.back()) return lo.back();
    std::size_t k = 0;
    while (s > ls[k + 1]) ++k;
    return lo[k] + (lo[k + 1] - lo[k]) * (s - ls[k]) / (ls[k + 1] - ls[k]);
  };
  // The sag: at 15 cm/s about 30 mV more than at rest.
  EXPECT_NEAR(offset(15) - offset(0), 0.030, 0.003);
  auto f = [&](double x) {
    x = std::clamp(x, m["voltage_range_v"][0].get<double>(), m["voltage_range_v"][1].get<double>());
    std::size_t k = 0;
    while (k + 2 < kv.size() && x > kv[k + 1]) ++k;
    return kc[k] + (kc[k + 1] - kc[k]) * (x - kv[k]) / (kv[k + 1] - kv[k]);
  };
  // charge in 1e-6 -> the rows' (voltage, speed)
  std::multimap<long, std::pair<double, double>> rows_of;
  for (const auto& run : runs)
    for (std::size_t k = 0; k < run.t.size(); ++k) rows_of.insert({std::lround(run.charge[k] * 1e6), {run.voltage[k], run.speed}});
  const Script s = read_script(dir_ / "map.png.gp");
  ASSERT_EQ(s.inline_blocks.size(), 4u);
  const Rows& pts = s.inline_blocks[0];
  const Rows& resid = s.inline_blocks[3];
  ASSERT_EQ(pts.size(), resid.size());
  std::size_t moving = 0;
  for (std::size_t i = 0; i < pts.size(); ++i) {
    // The drawn x is voltage + offset(speed): find the logged row whose charge it carries and whose
    // voltage + its speed's offset is that x.
    bool found = false;
    const auto range = rows_of.equal_range(std::lround(pts[i][1] * 1e6));
    for (auto it = range.first; it != range.second; ++it) {
      const auto [v, speed] = it->second;
      if (std::abs(v + offset(speed) - pts[i][0]) > 1e-9) continue;
      found = true;
      moving += speed != 0;
      EXPECT_EQ(resid[i][0], pts[i][0]);
      EXPECT_NEAR(resid[i][1], pts[i][1] - f(v + offset(speed)), 1e-12) << v << " V at " << speed << " cm/s";
      break;
    }
    ASSERT_TRUE(found) << "(" << pts[i][0] << ", " << pts[i][1] << ") is no logged row at its speed's corrected voltage";
  }
  EXPECT_GT(moving, pts.size() / 2);
}

TEST_F(FigureData, AScriptFolderThatIsNotAFolderStopsTheRun) {
  const std::string cmd = "EPUCK2_PLOT_SCRIPT_DIR='" + (dir_ / "missing").string() + "' '" EPUCK2_FIT_EXE "' ground " +
                          logs_of("ground").front().string() + " --plot '" + (dir_ / "g.png").string() + "' >/dev/null 2>'" +
                          (dir_ / "err.txt").string() + "'";
  const int rc = std::system(cmd.c_str());
  EXPECT_EQ(WEXITSTATUS(rc), 2);
  std::ifstream in(dir_ / "err.txt");
  const std::string err((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  EXPECT_NE(err.find("EPUCK2_PLOT_SCRIPT_DIR"), std::string::npos) << err;
  EXPECT_FALSE(fs::exists(dir_ / "g.png"));
}

}  // namespace
}  // namespace test_figure_data_cpp
