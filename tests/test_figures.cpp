// Every figure the project draws (scripts/regenerate.sh: the battery fits and lifetime, the five
// sensors, the diagnosis of every kind), drawn from the shipped logs through the real binary in
// each format the extension selects: PNG, SVG and PDF. Each must be a file of that format (its
// magic bytes), drawn without a word from gnuplot (EPUCK2_PLOT_STRICT turns any gnuplot message
// into a failed run), and, read as SVG text, carry its axes' quantities and units. Also the
// format rules of lib/plot/figure.hpp on their own.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <map>
#include <cstdlib>
#include <string>
#include <tuple>
#include <vector>

#include "cli_harness.hpp"
#include "epuck2/plot/diagnosis_figure.hpp"
#include "epuck2/plot/figure.hpp"

namespace {

namespace fs = std::filesystem;
using epuck2::testing::CliRun;
using epuck2::testing::slurp;

struct Figure {
  std::string name;                  ///< as data/fitted/plots names it
  std::string command;               ///< epuck2-fit's arguments before the figure option
  std::string option;                ///< --plot or --plot-lifetime
  std::vector<std::string> in_text;  ///< strings the SVG must hold: axis labels with units, legends
};

std::string logs_of(const std::string& kind) {
  std::vector<std::string> paths;
  for (const auto& e : fs::directory_iterator(fs::path(EPUCK2_SOURCE_DIR) / "data" / "raw" / kind))
    if (e.path().extension() == ".csv") paths.push_back(e.path().string());
  std::sort(paths.begin(), paths.end());
  std::string args;
  for (const auto& p : paths) args += " \"" + p + "\"";
  return args;
}

const std::string kFittedBattery = "\"" + std::string(EPUCK2_SOURCE_DIR) + "/data/fitted/battery.json\"";

// What each figure must say (written here from the figures' purpose, not read from the code):
// the quantity and unit of every axis, the legend entries a reader needs.
const std::vector<Figure>& figures_listed() {
  static const std::vector<Figure> f{
      {"battery_fits", "battery" + logs_of("battery"), "--plot",
       {"time (h)", "charge (fraction of full)", "simple", "linear", "cubic", "approximated", "15 cm/s", "robot virtual-e-puck2-a",
        "robot virtual-e-puck2-b"}},
      {"battery_lifetime", "battery" + logs_of("battery"), "--plot-lifetime",
       {"wheel speed (cm/s)", "lifetime (h)", "published end times"}},
      {"proximity", "proximity" + logs_of("proximity"), "--plot",
       {"distance to the surface (mm)", "normalised reading (reading / 4095, dimensionless)", "plug-in", "each robot's mean",
        "robot virtual-epuck2-1", "robot virtual-epuck2-2"}},
      {"light", "light" + logs_of("light"), "--plot",
       {"distance to the light (cm)", "raw reading (counts", "plug-in", "robot virtual-epuck2-1", "robot virtual-epuck2-2"}},
      // Two robots' logs: each robot named in the legend (its own marker), not one cloud, and its
      // points a group of their own at each grey level: robots 0.02 apart, each one's three
      // sensors within +-0.005 of its group, so that two groups (+-0.01 +- 0.005) never touch.
      {"ground", "ground" + logs_of("ground"), "--plot",
       {"grey level (fraction", "raw reading (counts, 0..1023)", "plug-in", "robot virtual-epuck2-1", "robot virtual-epuck2-2",
        "each robot's points 0.02 apart, its sensors' 0.005"}},
      {"camera", "camera" + logs_of("camera"), "--plot",
       {"column px (pixels", "row py (pixels", "dimensionless", "plug-in", "observed, robot virtual-epuck2-1",
        "observed, robot virtual-epuck2-2"}},
      // Small multiples: a panel per commanded speed (the shipped set: 2.5 to 15 cm/s, and the
      // run standing still), the encoders of every run; both robots by marker.
      {"drive", "drive" + logs_of("drive"), "--plot",
       {"2.5 cm/s: 2 runs", "5 cm/s: 5 runs", "15 cm/s: 2 runs", "standing still: 1 run", "time (s)", "ToF reading (mm)",
        "distance to the obstacle (mm)", "wheel encoders: every run", "commanded distance (mm)", "encoder steps",
        "out-of-range codes", "clipped at the rails", "the 2000 mm rail", "robot virtual-epuck2-2"}},
      // The diagnosis: one panel per measured quantity, residuals with their unit, before and
      // after in one legend; the shipped logs of two robots give the `log` verdict, whose
      // categories are labelled with the file names.
      {"diagnose_battery", "diagnose --coefficients " + kFittedBattery + logs_of("battery"), "--plot",
       {"measured − simulated (fraction of full charge)", "robot-a_speed-00.csv", "robot-b_speed-15.csv", "log (file name)",
        "before:", "after:"}},
      {"diagnose_proximity", "diagnose" + logs_of("proximity"), "--plot",
       // long_tail (length pushed to its 1 mm bound) is not written, and left out: what is left
       // depends on the distance, the covariate the figure is drawn against.
       {"measured − simulated (counts, 0..4095)", "distance to the surface (mm)", "before:", "after:"}},
      {"diagnose_light", "diagnose" + logs_of("light"), "--plot",
       {"measured − simulated (counts, 0..4095)", "light_intensity_2.00_virtual-epuck2-2.csv", "before:", "after:"}},
      {"diagnose_ground", "diagnose" + logs_of("ground"), "--plot",
       {"measured − simulated (counts, 0..1023)", "ground_virtual-epuck2-1.csv", "before:", "after:"}},
      {"diagnose_camera", "diagnose" + logs_of("camera"), "--plot",
       {"LED image column px (px)", "LED image row py (px)", "measured − simulated (px)", "before:", "after:"}},
      {"diagnose_drive", "diagnose" + logs_of("drive"), "--plot",
       {"ToF reading (mm)", "wheel encoder registers", "measured − simulated (mm)", "measured − simulated (steps)",
        "before:", "after:"}},
  };
  return f;
}

/// The real binary with EPUCK2_PLOT_STRICT set: any word from gnuplot fails the figure.
class StrictFigures : public epuck2::testing::CliTest {
 protected:
  void SetUp() override {
    CliTest::SetUp();
    ::setenv("EPUCK2_PLOT_STRICT", "1", 1);
  }
  void TearDown() override {
    ::unsetenv("EPUCK2_PLOT_STRICT");
    CliTest::TearDown();
  }
};

class Figures : public StrictFigures, public ::testing::WithParamInterface<std::tuple<std::size_t, std::string>> {};

TEST_P(Figures, AreDrawnInTheFormatTheExtensionNames) {
  const Figure& f = figures_listed()[std::get<0>(GetParam())];
  const std::string format = std::get<1>(GetParam());
  const fs::path out = dir_ / (f.name + "." + format);
  const CliRun r = run(f.command + " " + f.option + " \"" + out.string() + "\"");
  ASSERT_EQ(r.exit_code, 0) << f.name << "." << format << ": " << r.err;
  ASSERT_TRUE(fs::exists(out)) << out;
  const std::string bytes = slurp(out);
  ASSERT_GT(bytes.size(), 1000u) << out;  // a drawn figure, not an empty page
  if (format == "png") {
    EXPECT_EQ(bytes.substr(0, 8), std::string("\x89PNG\r\n\x1a\n", 8)) << out;
  } else if (format == "svg") {
    EXPECT_NE(bytes.find("<svg"), std::string::npos) << out;
    EXPECT_EQ(bytes.find("\x89PNG"), std::string::npos) << out;
    for (const std::string& text : f.in_text) EXPECT_NE(bytes.find(text), std::string::npos) << f.name << ".svg lacks '" << text << "'";
  } else {
    EXPECT_EQ(bytes.substr(0, 5), "%PDF-") << out;
  }
  EXPECT_NE(r.err.find("drew " + out.string()), std::string::npos) << r.err;
  // Nothing but the figure in the folder: no temporary left behind.
  std::size_t files = 0;
  for (const auto& e : fs::directory_iterator(dir_))
    if (e.path().filename().string().rfind("std", 0) != 0) ++files;
  EXPECT_EQ(files, 1u);
}

// The figures whose command is a whole diagnosis or battery fit of the shipped logs (each 2-4 s):
// drawn once, as SVG (whose texts are checked). The format follows the extension through one code
// path for every figure (lib/plot's terminal choice), which every other figure checks in all three;
// the diagnosis figure's terminal-specific layout is drawn as PNG and PDF by the drive's, light's,
// ground's and camera's diagnoses, the battery's pages by battery_lifetime.
bool drawn_in_svg_only(const std::string& name) {
  return name == "diagnose_battery" || name == "diagnose_proximity" || name == "battery_fits";
}

std::vector<std::tuple<std::size_t, std::string>> all_cases() {
  std::vector<std::tuple<std::size_t, std::string>> cases;
  for (std::size_t i = 0; i < figures_listed().size(); ++i)
    for (const char* format : {"png", "svg", "pdf"})
      if (!drawn_in_svg_only(figures_listed()[i].name) || std::string(format) == "svg") cases.emplace_back(i, format);
  return cases;
}

INSTANTIATE_TEST_SUITE_P(EveryFigure, Figures, ::testing::ValuesIn(all_cases()),
                         [](const ::testing::TestParamInfo<std::tuple<std::size_t, std::string>>& info) {
                           return figures_listed()[std::get<0>(info.param)].name + "_" + std::get<1>(info.param);
                         });

// ---- a paper's figure: --figure-size and --font-size ----

/// The width and height a PNG's IHDR gives (bytes 16..23, big-endian).
std::pair<unsigned, unsigned> png_size(const std::string& bytes) {
  auto be32 = [&](std::size_t at) {
    return (static_cast<unsigned>(static_cast<unsigned char>(bytes[at])) << 24) |
           (static_cast<unsigned>(static_cast<unsigned char>(bytes[at + 1])) << 16) |
           (static_cast<unsigned>(static_cast<unsigned char>(bytes[at + 2])) << 8) | static_cast<unsigned>(static_cast<unsigned char>(bytes[at + 3]));
  };
  return {be32(16), be32(20)};
}

class PaperFigures : public StrictFigures {};

// 8.5 x 6 cm, worked by hand: a PDF page of 8.5 / 2.54 * 72 = 240.94 by 170.08 pt; a PNG at
// 300 dpi of 1003.9 -> 1004 by 708.7 -> 709 px; an SVG at 96 px/in of 321.3 -> 321 by 226.8 -> 227.
TEST_F(PaperFigures, TheSizeAskedIsTheSizePrinted) {
  const std::string logs = logs_of("ground");
  for (const char* format : {"pdf", "png", "svg"}) {
    SCOPED_TRACE(format);
    const fs::path out = dir_ / (std::string("ground.") + format);
    const CliRun r = run("ground" + logs + " --plot \"" + out.string() + "\" --figure-size 8.5x6cm --font-size 8");
    ASSERT_EQ(r.exit_code, 0) << r.err;
    const std::string bytes = slurp(out);
    if (std::string(format) == "pdf") {
      const std::size_t box = bytes.find("/MediaBox [");
      ASSERT_NE(box, std::string::npos);
      double x0 = -1, y0 = -1, x1 = 0, y1 = 0;
      ASSERT_EQ(std::sscanf(bytes.c_str() + box + 11, "%lf %lf %lf %lf", &x0, &y0, &x1, &y1), 4);
      EXPECT_NEAR(x1 - x0, 240.94, 1.0);  // pdfcairo writes whole points
      EXPECT_NEAR(y1 - y0, 170.08, 1.0);
    } else if (std::string(format) == "png") {
      const auto [w, h] = png_size(bytes);
      EXPECT_EQ(w, 1004u);
      EXPECT_EQ(h, 709u);
    } else {
      EXPECT_NE(bytes.find("width=\"321\""), std::string::npos) << bytes.substr(0, 400);
      EXPECT_NE(bytes.find("height=\"227\""), std::string::npos) << bytes.substr(0, 400);
    }
  }
}

// Figures are redone at a paper's size without a word from gnuplot, and keep their axes' labels:
// the lifetime at one column's size, the diagnosis at two columns'.
TEST_F(PaperFigures, TheDiagnosisAtTwoColumnsSize) {
  const fs::path out = dir_ / "d.svg";
  const CliRun r = run("diagnose" + logs_of("ground") + " --plot \"" + out.string() + "\" --figure-size 17x12cm --font-size 8");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const std::string svg = slurp(out);
  // On a page the y label is short (the panel title says what is measured).
  // ... and the logs' names without what they share (ground_virtual-epuck2-1.csv, -2.csv: 1, 2).
  for (const char* text : {"residual (counts)", "before the findings", "after: 3 findings", "log (ground_virtual-epuck2-*.csv)", ">1<", ">2<"})
    EXPECT_NE(svg.find(text), std::string::npos) << text;
}

TEST_F(PaperFigures, LaidOutAgainAtOneColumnsSize) {
  struct Case {
    std::string command, option, label;
  };
  const std::vector<Case> cases{
      {"battery" + logs_of("battery"), "--plot-lifetime", "lifetime (h)"},
  };
  for (const auto& c : cases) {
    SCOPED_TRACE(c.command.substr(0, 20) + " " + c.option);
    const fs::path out = dir_ / "f.svg";
    const CliRun r = run(c.command + " " + c.option + " \"" + out.string() + "\" --figure-size 3.3x2.6in --font-size 8");
    ASSERT_EQ(r.exit_code, 0) << r.err;
    const std::string svg = slurp(out);
    EXPECT_NE(svg.find("width=\"317\""), std::string::npos) << svg.substr(0, 300);  // 3.3 in x 96 = 316.8
    EXPECT_NE(svg.find(c.label), std::string::npos) << c.label;
    fs::remove(out);
  }
}

TEST_F(PaperFigures, ABadSizeIsExitTwoSayingWhatWasExpected) {
  for (const char* bad : {"8.5x6", "8.5cm", "x6cm", "8.5x6ft", "0.5x0.5cm", "8,5x6cm"}) {
    SCOPED_TRACE(bad);
    const CliRun r = run("ground" + logs_of("ground") + " --plot \"" + (dir_ / "g.png").string() + "\" --figure-size " + bad);
    EXPECT_EQ(r.exit_code, 2);
    EXPECT_NE(r.err.find("--figure-size"), std::string::npos) << r.err;
    EXPECT_FALSE(fs::exists(dir_ / "g.png"));
  }
  const CliRun r = run("ground" + logs_of("ground") + " --font-size 0");
  EXPECT_EQ(r.exit_code, 2);
}

// Vector files stay small: the diagnosis of the whole drive set (thousands of residuals in
// each panel) draws at most 3000 points a series in an SVG, and says so.
TEST_F(PaperFigures, ADiagnosisSvgStaysSmall) {
  const fs::path out = dir_ / "d.svg";
  const CliRun r = run("diagnose" + logs_of("drive") + " --plot \"" + out.string() + "\"");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_LT(fs::file_size(out), 500u * 1024u);
  EXPECT_NE(slurp(out).find("drawn, means from all"), std::string::npos);  // the thinning, stated
}

// The battery reference set (32 runs, 16 panels) as an SVG: each run's readings one line, the
// SVG under 600 KB (2.2 MB when every drawn reading was a point), the thinning stated.
TEST_F(PaperFigures, ABatterySvgStaysSmallAndSaysItIsThinned) {
  const fs::path out = dir_ / "b.svg";
  const CliRun r = run("battery" + logs_of("battery") + " --plot \"" + out.string() + "\"");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_LT(fs::file_size(out), 600u * 1024u);
  EXPECT_NE(slurp(out).find("a line through ≤ 150 readings a run"), std::string::npos);
}

// The charge map of the battery reference set as an SVG: about 800 of its 38 439 logged rows
// (every 38 439 / 800 = 48th) in each panel, the SVG under 300 KB (0.9 MB with 4000 a panel),
// the thinning stated in the legend.
TEST_F(PaperFigures, AChargeMapSvgStaysSmallAndSaysItIsThinned) {
  const fs::path out = dir_ / "m.svg";
  const CliRun r = run("battery" + logs_of("battery") + " --plot-charge-map \"" + out.string() + "\"");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_LT(fs::file_size(out), 300u * 1024u);
  EXPECT_NE(slurp(out).find("logged rows, 1 in 48"), std::string::npos);
}

// The light reference set as an SVG: 3656 readings (the shipped logs' data rows), at most about
// 1200 drawn: 1 in ceil(3656 / 1200) = 4, stated on the axis; the SVG under 250 KB (450 KB when
// every reading was drawn).
TEST_F(PaperFigures, ALightSvgStaysSmallAndSaysItIsThinned) {
  const fs::path svg = dir_ / "l.svg";
  const CliRun r = run("light" + logs_of("light") + " --plot \"" + svg.string() + "\"");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_LT(fs::file_size(svg), 250u * 1024u);
  EXPECT_NE(slurp(svg).find("1 in 4 readings drawn"), std::string::npos);
}

// The drive reference set (19 runs, 1839 readings, each drawn in its speed's panel and again in
// the encoders') as an SVG: at most 25 readings a run drawn, the SVG under 300 KB (0.54 MB when
// every reading was drawn), the thinning stated; the PNG keeps every reading (no such entry).
TEST_F(PaperFigures, ADriveSvgStaysSmallAndSaysItIsThinned) {
  const fs::path out = dir_ / "d.svg";
  const CliRun r = run("drive" + logs_of("drive") + " --plot \"" + out.string() + "\"");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_LT(fs::file_size(out), 300u * 1024u);
  const std::string svg = slurp(out);
  EXPECT_NE(svg.find("at most 25 readings a run drawn"), std::string::npos);
  for (const char* text : {"ToF reading (mm)", "encoder steps", "commanded distance (mm)"})
    EXPECT_NE(svg.find(text), std::string::npos) << text;
}

/// Every `font-size="X"` of an SVG.
std::vector<double> svg_font_sizes(const std::string& svg) {
  std::vector<double> sizes;
  for (std::size_t at = svg.find("font-size=\""); at != std::string::npos; at = svg.find("font-size=\"", at + 1))
    sizes.push_back(std::atof(svg.c_str() + at + 11));
  return sizes;
}

// --font-size 8 prints at 8 pt: an SVG pixel is 1/96 in, so 8 pt = 8 / 72 * 96 = 10.67 px (worked
// by hand). The body text (tics, labels) is the most common size; the svg terminal's own scale
// (1.35 for cairo's 4/3) leaves it within 2 %.
TEST_F(PaperFigures, TheFontSizeAskedIsTheSizePrinted) {
  for (const char* pt : {"8", "10"}) {
    SCOPED_TRACE(pt);
    const fs::path out = dir_ / "g.svg";
    const CliRun r = run("ground" + logs_of("ground") + " --plot \"" + out.string() + "\" --figure-size 8.5x8cm --font-size " + pt);
    ASSERT_EQ(r.exit_code, 0) << r.err;
    const std::vector<double> sizes = svg_font_sizes(slurp(out));
    ASSERT_FALSE(sizes.empty());
    std::map<long, int> count;
    for (double s : sizes) ++count[std::lround(s * 100)];
    const auto body = std::max_element(count.begin(), count.end(), [](const auto& a, const auto& b) { return a.second < b.second; });
    EXPECT_NEAR(static_cast<double>(body->first) / 100.0, std::atof(pt) * 96.0 / 72.0, 0.02 * std::atof(pt) * 96.0 / 72.0);
    fs::remove(out);
  }
}

// At a paper's sizes every panel keeps its axes' labels and titles (read from the SVG gnuplot
// drew): the drive's small multiples and the diagnosis on one column (8.5 cm: 2 panels a row;
// before stacked over after where the page is tall enough, else side by side) and on two (17.6 cm).
TEST_F(PaperFigures, EveryPanelKeepsItsLabelsAtOneAndTwoColumns) {
  struct Case {
    std::string command, size;
    std::vector<std::string> texts;
  };
  const std::vector<Case> cases{
      {"drive" + logs_of("drive"), "8.5x14cm",
       {"2.5 cm/s, x: time (s)", "15 cm/s, x: time (s)", "standing still: 1 run", ">encoders<", "≤ 25 readings/run drawn", "ToF (mm)",
        "obstacle (mm)", "commanded (mm)", "encoder steps", "fit (7760.0 steps/m)", "robot virtual-epuck2-1"}},
      {"drive" + logs_of("drive"), "17.6x10cm", {"10 cm/s, x: time (s)", "standing still: 1 run", "encoder steps", "fit (7760.0 steps/m)"}},
      {"diagnose" + logs_of("drive"), "8.5x16cm",
       // (four panels do not stack in 16 cm: before and after side by side, the x label on two lines)
       {"before the", "after: 4 findings", "ToF residual (mm)", "encoder residual (steps)", "base model (steps)"}},
      {"diagnose" + logs_of("drive"), "17.6x12cm", {"Diagnosis of the drive logs", "residual (mm)", "before the findings"}},
      {"camera" + logs_of("camera"), "8.5x9cm", {"columns", "rows", "column px (pixels)", "row py (pixels)", "virtual-epuck2-2"}},
      {"battery" + logs_of("battery"), "17.6x14cm", {"0 cm/s, 5.48 h", "15 cm/s", "time (h)", "charge (fraction of full)"}},
  };
  for (const auto& c : cases) {
    SCOPED_TRACE(c.command.substr(0, 12) + " " + c.size);
    const fs::path out = dir_ / "p.svg";
    const CliRun r = run(c.command + " --plot \"" + out.string() + "\" --figure-size " + c.size + " --font-size 8");
    ASSERT_EQ(r.exit_code, 0) << r.err;
    const std::string svg = slurp(out);
    for (const auto& text : c.texts) EXPECT_NE(svg.find(text), std::string::npos) << text;
    fs::remove(out);
  }
}

// The battery's lifetime and charge-map figures on one column (8.5 cm at 8 pt): every axis keeps
// its label, the legend its entries (short forms), and the title is left to the caption.
TEST_F(PaperFigures, LifetimeAndChargeMapFitOneColumn) {
  const fs::path life = dir_ / "l.svg", map = dir_ / "m.svg";
  const CliRun r = run("battery" + logs_of("battery") + " --plot-lifetime \"" + life.string() + "\" --plot-charge-map \"" +
                       map.string() + "\" --figure-size 8.5x7cm --font-size 8");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const std::string l = slurp(life), m = slurp(map);
  for (const char* text : {"wheel speed (cm/s)", "lifetime (h)", "each run", "mean of the runs (± s.e.)", "published (Fig. 10b, plug-in)"})
    EXPECT_NE(l.find(text), std::string::npos) << text;
  EXPECT_EQ(l.find("Battery lifetime against wheel speed"), std::string::npos);  // the caption's
  for (const char* text : {"logged voltage (V)", "charge (1 = full)", "logged - map (1e-5)", "logged rows", "knots"})
    EXPECT_NE(m.find(text), std::string::npos) << text;
  EXPECT_EQ(m.find("Voltage -&gt; charge map"), std::string::npos);
  EXPECT_EQ(m.find("Voltage -> charge map"), std::string::npos);
  // Without a size, the titles are drawn.
  ASSERT_EQ(run("battery" + logs_of("battery") + " --plot-lifetime \"" + life.string() + "\"").exit_code, 0);
  EXPECT_NE(slurp(life).find("Battery lifetime against wheel speed"), std::string::npos);
}

// A diagnosis of two robots' logs (the shipped ground set: virtual-epuck2-1 and -2) gives each
// robot its marker, named in the legend.
TEST_F(PaperFigures, ADiagnosisOfSeveralRobotsNamesEachRobotsMarker) {
  const fs::path out = dir_ / "g.svg";
  ASSERT_EQ(run("diagnose" + logs_of("ground") + " --plot \"" + out.string() + "\"").exit_code, 0);
  const std::string svg = slurp(out);
  EXPECT_NE(svg.find("robot virtual-epuck2-1"), std::string::npos);
  EXPECT_NE(svg.find("robot virtual-epuck2-2"), std::string::npos);
}

/// Every text of an SVG (gnuplot writes each as `<g transform="translate(X,Y)" ...><text>T</text>`),
/// with where it starts.
struct SvgText {
  double x, y;
  std::string anchor, text;
};
std::vector<SvgText> svg_texts(const std::string& svg) {
  std::vector<SvgText> out;
  for (std::size_t at = svg.find("<g transform=\"translate("); at != std::string::npos;
       at = svg.find("<g transform=\"translate(", at + 1)) {
    const std::size_t end = svg.find('>', at), text = svg.find("<text>", at), close = svg.find("</text>", text);
    if (text == std::string::npos || close == std::string::npos || svg.find("<g", at + 1) < text) continue;
    SvgText t{};
    std::sscanf(svg.c_str() + at + 24, "%lf,%lf", &t.x, &t.y);
    const std::size_t a = svg.find("text-anchor=\"", at);
    if (a != std::string::npos && a < end) t.anchor = svg.substr(a + 13, svg.find('"', a + 13) - a - 13);
    t.text = svg.substr(text + 6, close - text - 6);
    out.push_back(t);
  }
  return out;
}

/// The SVG's canvas: its width and height attributes.
std::pair<double, double> svg_size(const std::string& svg) {
  const std::size_t w = svg.find("width=\""), h = svg.find("height=\"");
  return {std::atof(svg.c_str() + w + 7), std::atof(svg.c_str() + h + 8)};
}

// Issue #24: at 8.5x14cm the drive SVG's legend lost its first column ("forward", "backwards",
// "standing still"): gnuplot sized the key's columns by the svg terminal's estimate of the text,
// wider than the canvas, and centred it, so that the first column fell off the page. Every entry
// a reader needs must be drawn, and start inside the canvas (legend texts are left-aligned: a
// start at x < 0 or at x >= width is off the page).
TEST_F(PaperFigures, EveryLegendEntryIsDrawnInsideTheCanvasAtOneColumn) {
  struct Case {
    std::string name, args;
    std::vector<std::string> entries;
  };
  const std::vector<Case> cases{
      {"drive", "drive" + logs_of("drive") + " --figure-size 8.5x14cm --font-size 8",
       {"forward", "backwards", "standing still", "fit (7760.0 steps/m)", "plug-in", "the 2000 mm rail", "no-target code (2250)",
        "robot virtual-epuck2-1", "robot virtual-epuck2-2"}},
      {"battery", "battery" + logs_of("battery") + " --figure-size 8.5x12cm --font-size 8",
       {"robot virtual-e-puck2-a", "robot virtual-e-puck2-b", "simple", "linear", "cubic", "approximated"}},
      {"diagnose", "diagnose" + logs_of("ground") + " --figure-size 8.5x9cm --font-size 8",
       {"a residual before", "a residual after", "mean", "off the scale", "robot virtual-epuck2-1", "robot virtual-epuck2-2"}},
  };
  for (const auto& c : cases) {
    SCOPED_TRACE(c.name);
    const fs::path out = dir_ / (c.name + ".svg");
    const CliRun r = run(c.args + " --plot \"" + out.string() + "\"");
    ASSERT_EQ(r.exit_code, 0) << r.err;
    const std::string svg = slurp(out);
    const auto [width, height] = svg_size(svg);
    ASSERT_GT(width, 200);
    const std::vector<SvgText> texts = svg_texts(svg);
    for (const std::string& entry : c.entries) {
      const auto it = std::find_if(texts.begin(), texts.end(), [&](const SvgText& t) { return t.text == entry; });
      ASSERT_NE(it, texts.end()) << "legend entry '" << entry << "' not drawn";
      EXPECT_EQ(it->anchor, "start") << entry;
      EXPECT_GE(it->x, 0.0) << entry;
      EXPECT_LT(it->x, width) << entry;
      EXPECT_GE(it->y, 0.0) << entry;
      EXPECT_LE(it->y, height) << entry;
    }
  }
}

// A diagnosis on one column names each robot's marker (the legend used to drop them there), and
// at 8.5x6cm, where a stack of before over after left panels a few pixels high, puts the two
// side by side: both panels' titles are drawn, at the same height.
TEST_F(PaperFigures, AOneColumnDiagnosisNamesItsRobotsAndKeepsItsPanelsReadable) {
  const fs::path out = dir_ / "g.svg";
  const CliRun r = run("diagnose" + logs_of("ground") + " --figure-size 8.5x6cm --font-size 8 --plot \"" + out.string() + "\"");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const std::vector<SvgText> texts = svg_texts(slurp(out));
  auto find = [&](const std::string& text) {
    return std::find_if(texts.begin(), texts.end(), [&](const SvgText& t) { return t.text == text; });
  };
  EXPECT_NE(find("robot virtual-epuck2-1"), texts.end());
  EXPECT_NE(find("robot virtual-epuck2-2"), texts.end());
  auto starting = [&](const std::string& prefix) {  // (a small panel's title takes two lines)
    return std::find_if(texts.begin(), texts.end(), [&](const SvgText& t) { return t.text.rfind(prefix, 0) == 0; });
  };
  const auto before = starting("before the"), after = starting("after: 3 findings");
  ASSERT_NE(before, texts.end());
  ASSERT_NE(after, texts.end());
  EXPECT_LT(before->x, after->x);  // side by side: before on the left
  // (their titles' first lines: one title may have a line more, 16.5 SVG pixels at 8 pt)
  EXPECT_NEAR(before->y, after->y, 17.0);
  // 13 cm high: room to stack them, before over after, both named, the robots too (the key under
  // the figure and titles spaced as the svg terminal spaces them take the 12 cm that stacked them
  // before).
  const CliRun tall = run("diagnose" + logs_of("ground") + " --figure-size 8.5x13cm --font-size 8 --plot \"" + out.string() + "\"");
  ASSERT_EQ(tall.exit_code, 0) << tall.err;
  const std::vector<SvgText> stacked = svg_texts(slurp(out));
  auto find_in = [&](const std::string& prefix) {
    return std::find_if(stacked.begin(), stacked.end(), [&](const SvgText& t) { return t.text.rfind(prefix, 0) == 0; });
  };
  const auto b = find_in("before the"), a = find_in("after: 3 findings");
  ASSERT_NE(b, stacked.end());
  ASSERT_NE(a, stacked.end());
  EXPECT_NEAR(b->x, a->x, 1.0);
  EXPECT_LT(b->y, a->y);
  EXPECT_NE(find_in("robot virtual-epuck2-2"), stacked.end());
}

/// The width of `text` in DejaVu Sans at `font_px` pixels to the em: each character's advance,
/// in 1/2048 em, read here from DejaVuSans.ttf's hmtx table (fonts-dejavu-core 2.37) by a script
/// of the test's own, for ' ' to '~'; any other character counted as a whole em.
double dejavu_width(const std::string& text, double font_px) {
  static const int kAdvance[95] = {
      651,  821,  942,  1716, 1303, 1946, 1597, 563,  799,  799,  1024, 1716, 651,  739,  651,  690,  1303, 1303, 1303,
      1303, 1303, 1303, 1303, 1303, 1303, 1303, 690,  690,  1716, 1716, 1716, 1087, 2048, 1401, 1405, 1430, 1577, 1294,
      1178, 1587, 1540, 604,  604,  1343, 1141, 1767, 1532, 1612, 1235, 1612, 1423, 1300, 1251, 1499, 1401, 2025, 1403,
      1251, 1403, 799,  690,  799,  1716, 1024, 1024, 1255, 1300, 1126, 1300, 1260, 721,  1300, 1298, 569,  569,  1186,
      569,  1995, 1298, 1253, 1300, 1300, 842,  1067, 803,  1298, 1212, 1675, 1212, 1212, 1075, 1303, 690,  1303, 1716};
  std::string plain;  // the SVG's entities as the characters they stand for
  for (std::size_t i = 0; i < text.size(); ++i) {
    if (text[i] == '&') {
      const std::size_t semi = text.find(';', i);
      const std::string e = text.substr(i, semi - i + 1);
      plain += e == "&lt;" ? "<" : e == "&gt;" ? ">" : e == "&amp;" ? "&" : e == "&quot;" ? "\"" : e == "&apos;" ? "'" : "?";
      i = semi;
    } else {
      plain += text[i];
    }
  }
  double units = 0;
  for (unsigned char c : plain)
    if (c >= 32 && c < 127) units += kAdvance[c - 32];
    else if ((c & 0xC0) != 0x80) units += 2048;
  return units / 2048 * font_px;
}

/// Every text of a gnuplot SVG as the box it takes: its start, anchor, rotation (gnuplot writes
/// `rotate(270)` or `rotate(-90)` for a y label), size and width, from ascent (0.76 em, DejaVu
/// Sans' capitals) above the baseline to descent (0.24 em) below.
struct TextBox {
  double x0, y0, x1, y1;
  std::string text;
};
std::vector<TextBox> svg_text_boxes(const std::string& svg) {
  std::vector<TextBox> out;
  for (std::size_t at = svg.find("<g transform=\"translate("); at != std::string::npos;
       at = svg.find("<g transform=\"translate(", at + 1)) {
    const std::size_t end = svg.find('>', at), text = svg.find("<text>", at), close = svg.find("</text>", text);
    if (text == std::string::npos || close == std::string::npos || svg.find("<g", at + 1) < text) continue;
    const std::string head = svg.substr(at, end - at);
    std::string t = svg.substr(text + 6, close - text - 6);
    while (!t.empty() && t.front() == ' ') t.erase(0, 1);
    while (!t.empty() && t.back() == ' ') t.pop_back();
    if (t.empty()) continue;
    double x = 0, y = 0;
    std::sscanf(head.c_str() + 24, "%lf,%lf", &x, &y);
    const std::size_t fs_at = head.find("font-size=\"");
    const double f = fs_at == std::string::npos ? 12 : std::atof(head.c_str() + fs_at + 11);
    const std::size_t a = head.find("text-anchor=\"");
    const std::string anchor = a == std::string::npos ? "start" : head.substr(a + 13, head.find('"', a + 13) - a - 13);
    const double w = dejavu_width(t, f);
    const double from = anchor == "middle" ? -w / 2 : anchor == "end" ? -w : 0;  // along the text, from its point
    const bool upright = head.find("rotate(270)") != std::string::npos || head.find("rotate(-90)") != std::string::npos;
    if (upright) out.push_back({x - 0.76 * f, y - from - w, x + 0.24 * f, y - from, t});
    else out.push_back({x + from, y - 0.76 * f, x + from + w, y + 0.24 * f, t});
  }
  return out;
}

// Issue #24: nothing cut, nothing overlapping, in the format whose text layout is the hardest (the
// svg terminal sets lines 1.53 of their size apart, cairo 1.16). Every text of the figures whose
// layouts the page reworks, as the SVG draws it and measured in DejaVu Sans' own widths, lies
// inside the canvas (to a pixel) and overlaps no other by more than a pixel: the categorical
// diagnoses (log names on the x axis) at one column and two, the drive at both, a diagnosis of
// two quantities and the camera at one column.
TEST_F(PaperFigures, EveryTextOfAPageFigureIsOnTheCanvasAndClearOfTheOthers) {
  const std::string battery = "diagnose --coefficients " + kFittedBattery + logs_of("battery");
  const std::vector<std::pair<std::string, std::string>> cases{
      {"diagnose" + logs_of("light"), "8.5x9cm"},   {"diagnose" + logs_of("light"), "17.8x10cm"},
      {battery, "8.5x9cm"},                         {battery, "17.8x10cm"},
      {"diagnose" + logs_of("ground"), "8.5x9cm"},  {"diagnose" + logs_of("ground"), "17.8x8cm"},
      {"diagnose" + logs_of("camera"), "8.5x16cm"}, {"diagnose" + logs_of("drive"), "8.5x16cm"},
      {"drive" + logs_of("drive"), "8.5x14cm"},     {"drive" + logs_of("drive"), "17.8x10cm"},
      {"camera" + logs_of("camera"), "8.5x9cm"},
      // (the svg terminal set the proximity legend in one column of 12 rows at 8.5 cm, and the
      // light legend, inside the plot at 17.8 cm, over the x tics)
      {"proximity" + logs_of("proximity"), "8.5x7cm"}, {"light" + logs_of("light"), "8.5x7cm"},
      {"light" + logs_of("light"), "17.8x9cm"},
      // (at 17.8x8cm the camera's panel titles stood on the overall title, its legends over the
      // readings and off the canvas, its x labels below the foot)
      {"camera" + logs_of("camera"), "17.8x8cm"},
  };
  for (const auto& [command, size] : cases) {
    SCOPED_TRACE(command.substr(0, 30) + " " + size);
    const fs::path out = dir_ / "t.svg";
    const CliRun r = run(command + " --plot \"" + out.string() + "\" --figure-size " + size + " --font-size 8");
    ASSERT_EQ(r.exit_code, 0) << r.err;
    EXPECT_EQ(r.err.find("the page leaves"), std::string::npos) << r.err;  // and no warning: the page is enough
    const std::string svg = slurp(out);
    const auto [width, height] = svg_size(svg);
    const std::vector<TextBox> boxes = svg_text_boxes(svg);
    ASSERT_GT(boxes.size(), 10u);
    for (const TextBox& b : boxes) {
      EXPECT_GE(b.x0, -1.0) << "'" << b.text << "' starts left of the canvas";
      EXPECT_LE(b.x1, width + 1.0) << "'" << b.text << "' runs off the canvas's right (" << width << ")";
      EXPECT_GE(b.y0, -1.0) << "'" << b.text << "' above the canvas";
      EXPECT_LE(b.y1, height + 1.0) << "'" << b.text << "' below the canvas (" << height << ")";
    }
    for (std::size_t i = 0; i < boxes.size(); ++i)
      for (std::size_t j = i + 1; j < boxes.size(); ++j) {
        const TextBox &a = boxes[i], &b = boxes[j];
        const double over_x = std::min(a.x1, b.x1) - std::max(a.x0, b.x0), over_y = std::min(a.y1, b.y1) - std::max(a.y0, b.y0);
        EXPECT_FALSE(over_x > 1 && over_y > 1) << "'" << a.text << "' and '" << b.text << "' overlap by " << over_x << " x " << over_y;
      }
    fs::remove(out);
  }
}

/// The most common marker scale of an SVG (gnuplot draws a marker as `<use xlink:href='#gpPt…'
/// transform='translate(X,Y) scale(S)'/>`).
double common_marker_scale(const std::string& svg) {
  std::map<std::string, int> count;
  for (std::size_t at = svg.find("<use xlink:href='#gpPt"); at != std::string::npos; at = svg.find("<use xlink:href='#gpPt", at + 1)) {
    const std::size_t s = svg.find("scale(", at), end = svg.find('>', at);
    if (s < end) ++count[svg.substr(s + 6, svg.find(')', s) - s - 6)];
  }
  if (count.empty()) return 0;
  return std::atof(std::max_element(count.begin(), count.end(), [](const auto& x, const auto& y) { return x.second < y.second; })->first.c_str());
}

// On a page the SVG's markers are scaled with its text, as the PDF's are (pdfcairo's pointscale):
// the svg terminal draws a marker at its own size whatever the page, which at 8.5 cm and 8 pt
// printed the markers twice the PDF's, as tall as the text's capitals. Worked by hand: 8 pt
// against the layouts' 11 x 4/3 = 14.67 pt is a factor 0.545 on the ground figure's readings
// (to the 2 decimals the SVG writes).
TEST_F(PaperFigures, AnSvgOnAPageScalesItsMarkersWithItsText) {
  const fs::path out = dir_ / "g.svg";
  ASSERT_EQ(run("ground" + logs_of("ground") + " --plot \"" + out.string() + "\"").exit_code, 0);
  const double own = common_marker_scale(slurp(out));
  ASSERT_GT(own, 0.5);
  ASSERT_EQ(run("ground" + logs_of("ground") + " --plot \"" + out.string() + "\" --figure-size 8.5x7cm --font-size 8").exit_code, 0);
  EXPECT_NEAR(common_marker_scale(slurp(out)) / own, 8.0 / (11.0 * 4.0 / 3.0), 0.01 / own);
}

/// The texts of an SVG that read exactly `text`.
std::size_t count_texts(const std::vector<SvgText>& texts, const std::string& text) {
  return static_cast<std::size_t>(std::count_if(texts.begin(), texts.end(), [&](const SvgText& t) { return t.text == text; }));
}

// Issue #24: a diagnosis against the log at one column (8.5 cm) numbers the logs on the x axis and
// names them in a key under the figure, level, never upright. Worked by hand at 8.5 cm and 8 pt:
// the canvas is 8.5 / 2.54 x 72 x (14.67 / 8) = 442 pixels wide, two panels side by side of
// (442 - 95 - 35 - 100) / 2 = 106; the light set's 8 logs leave 13.3 pixels a log, under the
// 19.3 a number takes (9.3 for a digit of 11 pt DejaVu Sans, 10 between): every second log is
// numbered (2, 4, 6, 8), each panel. The battery set's 32 leave 3.3 pixels a log, "32" and its gap
// 28.7: every tenth (1, 10, 20, 30). The key: the light logs' shared part once, the battery's two
// runs of 16 as one entry each.
TEST_F(PaperFigures, ACategoryAxisOnAColumnIsNumberedWithItsKeyBelow) {
  const fs::path out = dir_ / "k.svg";
  CliRun r = run("diagnose" + logs_of("light") + " --plot \"" + out.string() + "\" --figure-size 8.5x9cm --font-size 8");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  std::string svg = slurp(out);
  std::vector<SvgText> texts = svg_texts(svg);
  for (const char* n : {"2", "4", "6", "8"}) EXPECT_EQ(count_texts(texts, n), 2u) << n;
  for (const char* n : {"1", "3", "5", "7"}) EXPECT_EQ(count_texts(texts, n), 0u) << n;
  EXPECT_EQ(count_texts(texts, "log (key below)"), 2u);
  EXPECT_EQ(svg.find("rotate(90)"), std::string::npos);  // no upright tic label
  EXPECT_EQ(count_texts(texts, "0.50_virtual-epuck2-2"), 0u);
  for (const char* part : {"log light_intensity_*.csv, *: 1 = 0.50,", "2 = 0.50_virtual-epuck2-2,", "8 = 2.00_virtual-epuck2-2"})
    EXPECT_NE(svg.find(part), std::string::npos) << part;
  r = run("diagnose --coefficients " + kFittedBattery + logs_of("battery") + " --plot \"" + out.string() +
          "\" --figure-size 8.5x9cm --font-size 8");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  svg = slurp(out);
  texts = svg_texts(svg);
  for (const char* n : {"1", "10", "20", "30"}) EXPECT_EQ(count_texts(texts, n), 2u) << n;
  for (const char* n : {"2", "5", "32"}) EXPECT_EQ(count_texts(texts, n), 0u) << n;
  EXPECT_NE(svg.find("1–16 = robot-a_speed-00…15.csv"), std::string::npos);
  EXPECT_NE(svg.find("17–32 = robot-b_speed-00…15.csv"), std::string::npos);
  // Two quantities (the camera's column and row, both in px): each named in its y label.
  r = run("diagnose" + logs_of("camera") + " --plot \"" + out.string() + "\" --figure-size 8.5x16cm --font-size 8");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  texts = svg_texts(slurp(out));
  EXPECT_EQ(count_texts(texts, "column residual (px)"), 2u);
  EXPECT_EQ(count_texts(texts, "row residual (px)"), 2u);
}

// Issue #24: at 8.5x14cm the drive's encoder panel title ran off the canvas. Worked by hand at
// 8 pt: the canvas 442 pixels wide (8.5 / 2.54 x 132), panels two a row between 85 and 442 - 30,
// 110 apart: (442 - 85 - 30 - 110) / 2 = 108.5 wide, the right one from 303.5 to 412, its centre
// 357.75 canvas pixels, 357.75 x 321.26 / 442 = 260.0 SVG pixels (the SVG 8.5 / 2.54 x 96 = 321
// wide). The title, centred there, ends inside the canvas.
TEST_F(PaperFigures, TheDriveEncoderPanelTitleIsInsideTheCanvasAtOneColumn) {
  const fs::path out = dir_ / "d.svg";
  const CliRun r = run("drive" + logs_of("drive") + " --plot \"" + out.string() + "\" --figure-size 8.5x14cm --font-size 8");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const std::string svg = slurp(out);
  const std::vector<TextBox> boxes = svg_text_boxes(svg);
  const auto title = std::find_if(boxes.begin(), boxes.end(), [](const TextBox& b) { return b.text == "encoders"; });
  ASSERT_NE(title, boxes.end());
  EXPECT_NEAR((title->x0 + title->x1) / 2, 260.0, 2.0);
  EXPECT_LE(title->x1, svg_size(svg).first);
  EXPECT_GE(title->x0, 0.0);
  EXPECT_NE(svg.find("≤ 25 readings/run drawn"), std::string::npos);  // the thinning, in the legend
}

// A page too short for a figure's panels says so, with the height to add: the battery's 16 speeds
// in 8.5x6cm (panels of a few millimetres) warn; in 8.5x12cm (about 12 mm each) they do not.
// The figure is drawn all the same (exit 0).
TEST_F(PaperFigures, APageTooShortForThePanelsSaysHowMuchHeightToAdd) {
  const fs::path out = dir_ / "b.png";
  CliRun r = run("battery" + logs_of("battery") + " --plot \"" + out.string() + "\" --figure-size 8.5x6cm --font-size 8");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.err.find("battery: warning: " + out.string() + ": the page leaves its"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("more height (--figure-size)"), std::string::npos) << r.err;
  r = run("battery" + logs_of("battery") + " --plot \"" + out.string() + "\" --figure-size 8.5x12cm --font-size 8");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_EQ(r.err.find("the page leaves"), std::string::npos) << r.err;
  // The figure's own size (no page) never warns.
  r = run("drive" + logs_of("drive") + " --plot \"" + out.string() + "\"");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_EQ(r.err.find("the page leaves"), std::string::npos) << r.err;
}

// Tic steps, worked by hand: [0, 22] in 3 tics: 22 / 3 = 7.3 -> 10; [-15, 17] in 3: 10.7 -> 20,
// which leaves one tic (0) inside, so 10 (-10, 0, 10); [200, 450] in 5: 50 -> 50; [0, 1] in 4:
// 0.25 -> 0.5; a degenerate range -> 1.
TEST(FigureTics, StepsAreOneTwoOrFiveTimesAPowerOfTenWithTwoTicsInside) {
  using epuck2::plot::tic_step;
  EXPECT_DOUBLE_EQ(tic_step(0, 22, 3), 10);
  EXPECT_DOUBLE_EQ(tic_step(-15, 17, 3), 10);
  EXPECT_DOUBLE_EQ(tic_step(200, 450, 5), 50);
  EXPECT_DOUBLE_EQ(tic_step(0, 1, 4), 0.5);
  EXPECT_DOUBLE_EQ(tic_step(3, 3, 4), 1);
  EXPECT_EQ(epuck2::plot::tics_that_fit(100, 40), 3);  // at least 3
  EXPECT_EQ(epuck2::plot::tics_that_fit(400, 40), 10);
}

TEST(FigureSize, ParsedInInches) {
  using epuck2::plot::parse_figure_size;
  EXPECT_NEAR(parse_figure_size("8.5x6cm").first, 8.5 / 2.54, 1e-12);
  EXPECT_NEAR(parse_figure_size("8.5x6cm").second, 6 / 2.54, 1e-12);
  EXPECT_NEAR(parse_figure_size("85X60mm").first, 85 / 25.4, 1e-12);
  EXPECT_EQ(parse_figure_size("3.5x2in"), std::make_pair(3.5, 2.0));
  for (const char* bad : {"", "x", "3x", "3x2", "3x2pt", "3.5.1x2in", "-3x2in", "50x2in"})
    EXPECT_THROW(parse_figure_size(bad), std::invalid_argument) << bad;
}

// ---- the format rules on their own (lib/plot/figure.hpp) ----

TEST(FigureFormat, TheExtensionNamesTheFormatWhateverItsCase) {
  using epuck2::plot::Format;
  using epuck2::plot::format_of;
  EXPECT_EQ(format_of("a/b/fits.png"), Format::png);
  EXPECT_EQ(format_of("FITS.PNG"), Format::png);
  EXPECT_EQ(format_of("x.svg"), Format::svg);
  EXPECT_EQ(format_of("x.Svg"), Format::svg);
  EXPECT_EQ(format_of("x.pdf"), Format::pdf);
  for (const char* bad : {"x.jpg", "x.eps", "x", "png", "x.png.txt", "x.", ".png.gz"}) EXPECT_FALSE(format_of(bad)) << bad;
  EXPECT_TRUE(epuck2::plot::why_not_a_figure("x.pdf").empty());
  const std::string why = epuck2::plot::why_not_a_figure("fits.jpg");
  for (const char* word : {"'.jpg'", ".png", ".svg", ".pdf"}) EXPECT_NE(why.find(word), std::string::npos) << why;
}

TEST(FigureFormat, AnUnknownExtensionIsRefusedBeforeAnythingIsStaged) {
  const fs::path dir = fs::temp_directory_path() / ("epuck2_fig_" + std::to_string(::getpid()));
  fs::create_directories(dir);
  bool drew = false;
  EXPECT_THROW(epuck2::plot::render((dir / "x.gif").string(), [&](gnuplotio::Gnuplot&) { drew = true; }),
               epuck2::plot::UnknownFormat);
  EXPECT_FALSE(drew);
  EXPECT_TRUE(fs::is_empty(dir));
  fs::remove_all(dir);
}

TEST(FigureFormat, AGnuplotErrorFailsTheFigureUnderStrictAndLeavesNoFile) {
  const fs::path dir = fs::temp_directory_path() / ("epuck2_fig_strict_" + std::to_string(::getpid()));
  fs::create_directories(dir);
  ::setenv("EPUCK2_PLOT_STRICT", "1", 1);
  try {
    epuck2::plot::render((dir / "x.png").string(), [](gnuplotio::Gnuplot& gp) { gp << "set no_such_setting\nplot x\n"; });
    ADD_FAILURE() << "a figure whose commands gnuplot rejects was accepted";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("gnuplot said"), std::string::npos) << e.what();
  }
  ::unsetenv("EPUCK2_PLOT_STRICT");
  EXPECT_TRUE(fs::is_empty(dir)) << "the staged figure was left behind";
  // The same figure without the error is drawn.
  epuck2::plot::render((dir / "x.svg").string(), [](gnuplotio::Gnuplot& gp) { gp << "plot x\n"; });
  EXPECT_NE(slurp(dir / "x.svg").find("<svg"), std::string::npos);
  fs::remove_all(dir);
}

TEST(FigureFormat, QuotedTextReachesGnuplotAsWritten) {
  using epuck2::plot::quoted;
  EXPECT_EQ(quoted("drive_away_05.0_cm_s.csv"), "\"drive_away_05.0_cm_s.csv\"");
  EXPECT_EQ(quoted("a \"b\" c\\d"), "\"a \\\"b\\\" c\\\\d\"");
  EXPECT_EQ(quoted("line 1\nline 2"), "\"line 1\\nline 2\"");
  EXPECT_EQ(quoted(std::string("bell\a")), "\"bell?\"");
}

TEST(DiagnosisFigureAxis, EachUnitSuffixNamesItsUnit) {
  // docs/logs.md's column-naming rule: a covariate column's unit is its name's suffix. The longer
  // suffix wins where one ends another (_cm_s2 / _cm_s / _s, _ms / _s, _mm / _m, _cm / _m), and a
  // column in metres is drawn in mm, as every distance of the figures.
  const std::pair<const char*, const char*> cases[] = {
      {"accel_cm_s2", "accel (cm/s²)"},   {"speed_cm_s", "speed (cm/s)"},     {"gap_mm", "gap (mm)"},
      {"gap_cm", "gap (cm)"},             {"height_m", "height (mm)"},        {"lag_ms", "lag (ms)"},
      {"elapsed_s", "elapsed (s)"},       {"heading_deg", "heading (°)"},     {"heading_rad", "heading (rad)"},
      {"board_temp_c", "board temp (°C)"}, {"cell_k", "cell (K)"},            {"supply_v", "supply (V)"},
      {"motor_a", "motor (A)"},           {"pwm_hz", "pwm (Hz)"},             {"humidity_pct", "humidity (%)"},
      {"blob_px", "blob (px)"},           {"humidity", "humidity (as logged: no unit in its name)"},
      {"_m", "_m (as logged: no unit in its name)"}};
  for (const auto& [name, label] : cases) EXPECT_EQ(epuck2::plot::column_label(name), label) << name;
}

}  // namespace
