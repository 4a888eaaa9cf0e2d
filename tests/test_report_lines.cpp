// The text reports' lines that say which way a choice went, or that a count reached its limit,
// each checked on both sides against what the test counts itself: a scan of the product code
// (session 20) found these lines quoted by no test. The text report is written apart from the JSON
// (lib/calibrate *_report.cpp against report_json.cpp, battery_json.cpp): each line is compared
// with the JSON's number, and the JSON's number with the test's own computation where it can be
// done from the log.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <functional>
#include <sstream>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "cli_harness.hpp"

namespace test_report_lines_cpp {

namespace fs = std::filesystem;
using epuck2::testing::CliRun;
using epuck2::testing::slurp;
using nlohmann::json;

bool has(const std::string& text, const std::string& part) { return text.find(part) != std::string::npos; }

std::string printed(const char* format, double v) {
  char b[64];
  std::snprintf(b, sizeof b, format, v);
  return b;
}

std::vector<std::string> lines_of(const std::string& text) {
  std::vector<std::string> out;
  std::istringstream in(text);
  for (std::string l; std::getline(in, l);) out.push_back(l);
  return out;
}

fs::path raw(const std::string& kind, const std::string& file) { return fs::path(EPUCK2_SOURCE_DIR) / "data" / "raw" / kind / file; }

/// A copy of a shipped battery log with `edit` applied to each data row's cells (index from 0).
std::string edited_battery_log(const std::string& file, const std::function<void(std::size_t, std::vector<std::string>&)>& edit) {
  std::istringstream in(slurp(raw("battery", file)));
  std::string line, text;
  bool header = false;
  std::size_t row = 0;
  while (std::getline(in, line)) {
    if (line.empty() || line[0] == '#' || !header) {
      header = header || (!line.empty() && line[0] != '#');
      text += line + "\n";
      continue;
    }
    std::vector<std::string> c;
    std::stringstream cells(line);
    for (std::string cell; std::getline(cells, cell, ',');) c.push_back(cell);
    edit(row++, c);
    for (std::size_t k = 0; k < c.size(); ++k) text += (k ? "," : "") + c[k];
    text += "\n";
  }
  return text;
}

class ReportLines : public epuck2::testing::CliTest {};

// "Average MSE over speeds": the plain mean of each model's per-speed MSE (docs/fitting.md, Table
// 5's "average MSE"), computed here from the JSON's speeds; the text prints it to 4 decimals.
TEST_F(ReportLines, TheBatterysAverageMseIsTheMeanOverSpeeds) {
  const std::string logs = " \"" + raw("battery", "robot-a_speed-05.csv").string() + "\" \"" +
                           raw("battery", "robot-a_speed-06.csv").string() + "\" \"" + raw("battery", "robot-b_speed-09.csv").string() + "\"";
  const CliRun j = run("battery" + logs + " --json");
  ASSERT_EQ(j.exit_code, 0) << j.err;
  const CliRun t = run("battery" + logs);
  ASSERT_EQ(t.exit_code, 0) << t.err;
  const json r = json::parse(j.out);
  ASSERT_EQ(r.at("speeds").size(), 3u);
  std::string line = "Average MSE over speeds:";
  for (const std::string m : {"simple", "linear", "cubic", "approximated"}) {
    double sum = 0;
    for (std::size_t s = 0; s < 3; ++s) sum += r.at("speeds").at(s).at("mse").at(m).get<double>();
    EXPECT_NEAR(r.at("mse").at(m).get<double>(), sum / 3.0, 1e-15) << m;
    line += std::string(m == "simple" ? " " : ", ") + m + " " + printed("%.4f", sum / 3.0);
  }
  EXPECT_TRUE(has(t.out, line + " charge²")) << line << "\n" << t.out;
}

// Wild battery readings: counted on the report's line with their rule (6 robust sd from the speed's
// cubic, docs/fitting.md), the first three of a speed listed; --least-squares keeps every one.
// Four readings of charge 0.05 planted where the log reads about 0.9 to 0.5 (rows 50, 150, 250, 350).
TEST_F(ReportLines, TheBatterysWildReadingsAreCountedAndThreeAreListed) {
  const std::string log = write("wild.csv", edited_battery_log("robot-a_speed-05.csv", [](std::size_t row, std::vector<std::string>& c) {
                                  if (row == 50 || row == 150 || row == 250 || row == 350) c[2] = "0.05";
                                }));
  const CliRun j = run("battery \"" + log + "\" --json");
  ASSERT_EQ(j.exit_code, 0) << j.err;
  const json r = json::parse(j.out);
  const json& outliers = r.at("speeds").at(0).at("outliers");
  ASSERT_EQ(outliers.size(), 4u) << outliers.dump();
  // The data rows 50, 150, 250, 350 are on lines 52 + the metadata lines before the header.
  const CliRun t = run("battery \"" + log + "\"");
  ASSERT_EQ(t.exit_code, 0) << t.err;
  EXPECT_TRUE(has(t.out, "Readings left out as wild (more than 6 robust sd from their speed's cubic; --least-squares keeps them): 4\n"))
      << t.out;
  std::vector<std::string> listed;
  for (const std::string& l : lines_of(t.out))
    if (l.rfind("  5.00 cm/s: ", 0) == 0) listed.push_back(l.substr(13));
  ASSERT_EQ(listed.size(), 3u) << t.out;
  for (std::size_t i = 0; i < 3; ++i) EXPECT_EQ(listed[i], outliers.at(i).get<std::string>());
  EXPECT_TRUE(has(listed[0], log)) << listed[0];

  const CliRun ls = run("battery \"" + log + "\" --least-squares");
  ASSERT_EQ(ls.exit_code, 0) << ls.err;
  EXPECT_TRUE(has(ls.out, "\nEvery reading kept (--least-squares)\n")) << ls.out;
  EXPECT_FALSE(has(ls.out, "left out as wild")) << ls.out;
  EXPECT_FALSE(has(ls.out, "  5.00 cm/s: ")) << ls.out;
}

// A speed off the 0..15 cm/s grid is named on its own line (and in the JSON): covered by a run, but
// not one of the tables' speeds, which still miss 5.
TEST_F(ReportLines, ABatterySpeedOffTheGridIsNamed) {
  const std::string log = write("s55.csv", edited_battery_log("robot-a_speed-05.csv", [](std::size_t, std::vector<std::string>& c) {
                                  c[1] = "5.5";
                                }));
  const std::string six = raw("battery", "robot-a_speed-06.csv").string();
  const CliRun t = run("battery \"" + log + "\" \"" + six + "\"");
  ASSERT_EQ(t.exit_code, 0) << t.err;
  EXPECT_TRUE(has(t.out, "\n  speeds covered (cm/s): 5.5, 6\n  speeds missing (cm/s): 0, 1, 2, 3, 4, 5, 7,")) << t.out;
  EXPECT_TRUE(has(t.out, "\n  speeds other than 0..15 (cm/s): 5.5\n")) << t.out;
  const CliRun j = run("battery \"" + log + "\" \"" + six + "\" --json");
  ASSERT_EQ(j.exit_code, 0) << j.err;
  const json r = json::parse(j.out);
  EXPECT_EQ(r.at("speeds_other_cm_s"), json::array({5.5}));
  EXPECT_EQ(r.at("speeds_covered_cm_s"), json::array({5.5, 6}));
  EXPECT_EQ(r.at("complete_tables"), false);
  // On the grid only: no such line.
  const CliRun grid = run("battery \"" + raw("battery", "robot-a_speed-05.csv").string() + "\" \"" + six + "\"");
  ASSERT_EQ(grid.exit_code, 0) << grid.err;
  EXPECT_FALSE(has(grid.out, "speeds other than")) << grid.out;
}

// The proximity report's two blocks are the fits they name: "Fitted to the maxima (N points)" with
// the JSON's maxima fit (its observations, its MSE to the 4 digits the text prints), the means'
// likewise; the two differ on the shipped logs, so a swap shows.
TEST_F(ReportLines, EachProximityBlockIsTheFitItNames) {
  std::string logs;
  for (const auto& p : epuck2::testing::shipped_logs("proximity")) logs += " \"" + p.string() + "\"";
  const CliRun j = run("proximity" + logs + " --json");
  ASSERT_EQ(j.exit_code, 0) << j.err;
  const CliRun t = run("proximity" + logs);
  ASSERT_EQ(t.exit_code, 0) << t.err;
  const json fits = json::parse(j.out).at("fits");
  ASSERT_NE(printed("%.3e", fits.at("maxima").at("mse").get<double>()), printed("%.3e", fits.at("means").at("mse").get<double>()));
  const std::vector<std::string> lines = lines_of(t.out);
  for (const std::string which : {"maxima", "means"}) {
    const json& f = fits.at(which);
    const std::string title = std::string(which == "maxima" ? "Fitted to the maxima (" : "Fitted to the means (") +
                              std::to_string(f.at("observations").get<std::size_t>()) + " points):";
    std::size_t at = lines.size();
    for (std::size_t i = 0; i < lines.size(); ++i)
      if (lines[i] == title) at = i;
    ASSERT_LT(at, lines.size()) << title << "\n" << t.out;
    std::string mse_line;
    for (std::size_t i = at + 1; i < lines.size() && mse_line.empty(); ++i)
      if (lines[i].rfind("  MSE ", 0) == 0) mse_line = lines[i];
    EXPECT_EQ(mse_line.rfind("  MSE " + printed("%.3e", f.at("mse").get<double>()) + " (reading/4095)²", 0), 0u) << which << ": " << mse_line;
  }
}

// The ground report's table: row k is sensor k (its name, docs/models.md: 0 right, 1 centre, 2
// left), with that sensor's MSE and plug-in MSE from the JSON; the plug-in MSE is also computed
// here from the logs: reading − 1023 grey over the readings inside the 0/1023 rails.
TEST_F(ReportLines, EachGroundTableRowIsItsSensor) {
  std::string logs;
  std::vector<double> sum(3, 0.0);
  std::vector<std::size_t> n(3, 0);
  for (const auto& p : epuck2::testing::shipped_logs("ground")) {
    logs += " \"" + p.string() + "\"";
    std::istringstream in(slurp(p));
    std::vector<std::string> header;
    for (std::string l; std::getline(in, l);) {
      if (l.empty() || l[0] == '#') continue;
      std::vector<std::string> c;
      std::stringstream cells(l);
      for (std::string cell; std::getline(cells, cell, ',');) c.push_back(cell);
      if (header.empty()) {
        header = c;
        continue;
      }
      double grey = 0, value = 0;
      int sensor = 0;
      for (std::size_t k = 0; k < c.size(); ++k) {
        if (header[k] == "grey") grey = std::stod(c[k]);
        if (header[k] == "value") value = std::stod(c[k]);
        if (header[k] == "sensor") sensor = std::stoi(c[k]);
      }
      if (value <= 0 || value >= 1023) continue;
      sum[sensor] += (value - 1023 * grey) * (value - 1023 * grey);
      ++n[sensor];
    }
  }
  const CliRun j = run("ground" + logs + " --json");
  ASSERT_EQ(j.exit_code, 0) << j.err;
  const CliRun t = run("ground" + logs);
  ASSERT_EQ(t.exit_code, 0) << t.err;
  const json r = json::parse(j.out);
  const std::vector<std::string> names{"0 (right)", "1 (centre)", "2 (left)"};
  const std::vector<std::string> lines = lines_of(t.out);
  for (std::size_t k = 0; k < 3; ++k) {
    ASSERT_GT(n[k], 0u);
    const double plugin = sum[k] / static_cast<double>(n[k]);
    EXPECT_NEAR(r.at("reference_mse").at("plugin").at(k).get<double>(), plugin, 1e-9 * plugin) << k;
    std::string row;
    for (const auto& l : lines)
      if (l.rfind(names[k], 0) == 0 && has(l, "±")) row = l;
    ASSERT_FALSE(row.empty()) << names[k] << "\n" << t.out;
    std::vector<std::string> words;
    std::istringstream all(row);
    for (std::string w; all >> w;) words.push_back(w);
    ASSERT_GE(words.size(), 2u);
    EXPECT_EQ(words[words.size() - 1], printed("%.1f", plugin)) << row;
    EXPECT_EQ(words[words.size() - 2], printed("%.3f", r.at("mse_per_sensor").at(k).get<double>())) << row;
  }
}

}  // namespace test_report_lines_cpp
