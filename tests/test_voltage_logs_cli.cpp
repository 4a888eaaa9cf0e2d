// Voltage-only battery logs through the real binary: `battery` and `table5` take logs with
// voltage_v and no charge through a voltage->charge map (given with --charge-map, or fitted to the
// logs of the same call that carry both columns), and reproduce the charge-based fits.
//
// Tolerances. Lifetimes are the runs' last times, which the conversion does not touch: equal.
// The MSEs: a voltage-only copy's charge differs from the logged one by the map's error on each
// row, e, at most 7e-5 on the shipped logs (the voltage is printed to 0.1 mV, i.e. 6.25e-5 in
// charge units at the firmware's 0.8 V per unit; the charge to 6 significant digits, 5e-7; the
// fitted line's own error is a few 1e-6 over 38 471 rows). For a model whose curve does not
// depend on the charge (Simple, Linear: lifetimes only) the triangle inequality bounds the change
// of the root mean square error by e; for a least-squares fit (Cubic, Approximated) too, as the
// minimum over the same curves moves by at most e. So |MSE' - MSE| <= e (2 sqrt(MSE) + e): about
// 6e-6 for a cubic MSE of 0.002, 0.3 % of it. (e bounds the root mean square of the conversion
// error; a row clamped at the map's range adds to it, see the seed-7 test.)
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>

#include "cli_harness.hpp"

using epuck2::testing::CliRun;
using epuck2::testing::slurp;
namespace fs = std::filesystem;

namespace {

constexpr double kConversionError = 7e-5;  // see the file's comment
/// |MSE' - MSE| allowed when the converted charge is off by at most e (root mean square) per speed.
double mse_tolerance(double mse, double e = kConversionError) { return e * (2.0 * std::sqrt(mse) + e); }

class VoltageLogsCli : public epuck2::testing::CliTest {
 protected:
  static std::vector<fs::path> csvs(const fs::path& dir) {
    std::vector<fs::path> files;
    for (const auto& e : fs::directory_iterator(dir))
      if (e.path().extension() == ".csv") files.push_back(e.path());
    std::sort(files.begin(), files.end());
    return files;
  }
  static std::string args(const std::vector<fs::path>& files) {
    std::string a;
    for (const auto& f : files) a += " \"" + f.string() + "\"";
    return a;
  }
  static fs::path shipped_dir() { return fs::path(EPUCK2_SOURCE_DIR) / "data" / "raw" / "battery"; }
  /// Copies of `files` into `to` without their charge column (comments and metadata kept).
  std::vector<fs::path> voltage_only(const std::vector<fs::path>& files, const std::string& to) {
    fs::create_directories(dir_ / to);
    std::vector<fs::path> out;
    for (const auto& f : files) {
      std::istringstream in(slurp(f));
      std::string line, text;
      int charge = -1;
      while (std::getline(in, line)) {
        if (line.empty() || line[0] == '#') {
          text += line + "\n";
          continue;
        }
        std::vector<std::string> cells;
        std::stringstream ss(line);
        for (std::string c; std::getline(ss, c, ',');) cells.push_back(c);
        if (charge < 0) charge = static_cast<int>(std::find(cells.begin(), cells.end(), "charge") - cells.begin());
        std::string kept;
        for (std::size_t k = 0; k < cells.size(); ++k)
          if (static_cast<int>(k) != charge) kept += (kept.empty() ? "" : ",") + cells[k];
        text += kept + "\n";
      }
      EXPECT_GE(charge, 0) << f;
      out.push_back(dir_ / to / f.filename());
      std::ofstream(out.back()) << text;
    }
    return out;
  }
  /// Every speed's lifetime equal, every model's MSE (per speed and averaged) within tolerance.
  static void expect_same_fit(const nlohmann::json& a, const nlohmann::json& b, double e = kConversionError) {
    ASSERT_EQ(a.at("speeds").size(), b.at("speeds").size());
    for (std::size_t s = 0; s < a.at("speeds").size(); ++s) {
      const auto& x = a.at("speeds")[s];
      const auto& y = b.at("speeds")[s];
      EXPECT_EQ(x.at("speed_cm_s"), y.at("speed_cm_s"));
      EXPECT_EQ(x.at("lifetime_s").get<double>(), y.at("lifetime_s").get<double>()) << x.at("speed_cm_s");
      EXPECT_EQ(x.at("observations"), y.at("observations"));
      for (const char* m : {"simple", "linear", "cubic", "approximated"}) {
        const double mse = x.at("mse").at(m).get<double>();
        EXPECT_NEAR(y.at("mse").at(m).get<double>(), mse, mse_tolerance(mse, e)) << m << " at " << x.at("speed_cm_s");
      }
    }
    for (const char* m : {"simple", "linear", "cubic", "approximated"}) {
      const double mse = a.at("mse").at(m).get<double>();
      EXPECT_NEAR(b.at("mse").at(m).get<double>(), mse, mse_tolerance(mse, e)) << m;
    }
  }
};

}  // namespace

TEST_F(VoltageLogsCli, AVoltageOnlyCopyOfTheShippedLogsReproducesTheChargeFit) {
  const auto shipped = csvs(shipped_dir());
  ASSERT_EQ(shipped.size(), 32u);
  const std::string full = (dir_ / "battery.json").string();
  const CliRun a = run("battery" + args(shipped) + " -o \"" + full + "\"");
  ASSERT_EQ(a.exit_code, 0) << a.err;
  const auto with_charge = nlohmann::json::parse(slurp(full));
  ASSERT_TRUE(with_charge.contains("charge_map"));
  EXPECT_EQ(with_charge.at("charge_map").at("load"), "none");
  EXPECT_EQ(with_charge.at("charge_map").at("sources").size(), 32u);
  EXPECT_LT(with_charge.at("charge_map").at("residual_sd").get<double>(), 1e-4);

  const auto volts = voltage_only(shipped, "volts");
  const CliRun b = run("battery" + args(volts) + " --charge-map \"" + full + "\" --json");
  ASSERT_EQ(b.exit_code, 0) << b.err;
  EXPECT_NE(b.err.find("32 voltage-only logs (38471 rows): charge from voltage_v through the map of " + full), std::string::npos) << b.err;
  const auto from_voltage = nlohmann::json::parse(b.out);
  EXPECT_EQ(from_voltage.at("charge_conversion").at("rows"), 38471);
  EXPECT_EQ(from_voltage.at("charge_conversion").at("clamped_below_range"), 0);
  EXPECT_EQ(from_voltage.at("charge_conversion").at("clamped_above_range"), 0);
  EXPECT_EQ(from_voltage.at("charge_map").at("from_file"), full);
  expect_same_fit(with_charge, from_voltage);

  // table5: the same Table 5 (analytic) within the same tolerance.
  const CliRun t1 = run("table5" + args(shipped) + " --json");
  const CliRun t2 = run("table5" + args(volts) + " --charge-map \"" + full + "\" --json");
  ASSERT_EQ(t1.exit_code, 0) << t1.err;
  ASSERT_EQ(t2.exit_code, 0) << t2.err;
  const auto j1 = nlohmann::json::parse(t1.out), j2 = nlohmann::json::parse(t2.out);
  for (const char* m : {"simple", "linear", "cubic", "approximated"}) {
    const double mse = j1.at("analytic").at(m).get<double>();
    EXPECT_NEAR(j2.at("analytic").at(m).get<double>(), mse, mse_tolerance(mse)) << m;
  }
  EXPECT_EQ(j2.at("charge_conversion").at("logs"), 32);
}

TEST_F(VoltageLogsCli, TheShippedMapConvertsLogsOfAnotherSeed) {
  // Logs the map never saw (the virtual robot with seed 7): the charge fit of their voltage-only
  // copies matches the fit of their own charge column.
  const CliRun g = run("generate battery --seed 7 --out \"" + (dir_ / "seed7").string() + "\"");
  ASSERT_EQ(g.exit_code, 0) << g.err;
  const std::string map = (dir_ / "map.json").string();
  ASSERT_EQ(run("battery" + args(csvs(shipped_dir())) + " -o \"" + map + "\"").exit_code, 0);
  const auto seven = csvs(dir_ / "seed7");
  const CliRun a = run("battery" + args(seven) + " --json");
  const CliRun b = run("battery" + args(voltage_only(seven, "seed7_volts")) + " --charge-map \"" + map + "\" --json");
  ASSERT_EQ(a.exit_code, 0) << a.err;
  ASSERT_EQ(b.exit_code, 0) << b.err;
  const auto jb = nlohmann::json::parse(b.out);
  // Seed 7 reaches voltages the shipped logs did not (its noise differs): those are clamped to
  // the map's ends and counted. At most 2, each at most 2.5 mV beyond the range, i.e. off by at
  // most 3.1e-3 in charge; among the 1500 rows or more of a speed, two such rows add at most
  // 3.1e-3 sqrt(2 / 1500) = 1.1e-4 to the root mean square error of the conversion: e = 2e-4.
  const auto conv = jb.at("charge_conversion");
  const auto range = jb.at("charge_map").at("voltage_range_v");
  EXPECT_LE(conv.at("clamped_below_range").get<int>() + conv.at("clamped_above_range").get<int>(), 2) << conv.dump();
  for (const auto& row : conv.at("clamped_rows")) {
    const std::string text = row.get<std::string>();  // "file:line (4.2365 V)"
    const double v = std::stod(text.substr(text.rfind('(') + 1));
    EXPECT_LE(std::max(range[0].get<double>() - v, v - range[1].get<double>()), 2.5e-3) << text;
  }
  for (const auto& s : jb.at("speeds")) EXPECT_GE(s.at("observations").get<int>(), 1500);
  expect_same_fit(nlohmann::json::parse(a.out), jb, 2e-4);
}

TEST_F(VoltageLogsCli, AVoltageOnlyLogWithoutAMapIsExit2SayingHowToGiveOne) {
  const auto volts = voltage_only({shipped_dir() / "robot-a_speed-04.csv"}, "v");
  for (const char* command : {"battery", "table5"}) {
    const CliRun r = run(std::string(command) + args(volts));
    EXPECT_EQ(r.exit_code, 2) << command;
    // The header's line (line 5, after four metadata lines), column 1.
    EXPECT_NE(r.err.find(volts[0].string() + ":5:1: no 'charge' column, only 'voltage_v'"), std::string::npos) << r.err;
    EXPECT_NE(r.err.find("--charge-map FILE"), std::string::npos) << r.err;
    EXPECT_EQ(r.out, "") << command;
  }
  // diagnose compares charges: it says so at the header too.
  const CliRun d = run("diagnose" + args(volts));
  EXPECT_EQ(d.exit_code, 2);
  EXPECT_NE(d.err.find(volts[0].string() + ":5:1: no 'charge' column, only 'voltage_v': diagnose compares"), std::string::npos) << d.err;
}

TEST_F(VoltageLogsCli, LogsWithBothColumnsGiveTheMapForTheVoltageOnlyOnesInTheSameCall) {
  std::vector<fs::path> a, b;
  for (const auto& f : csvs(shipped_dir())) (f.filename().string().rfind("robot-a", 0) == 0 ? a : b).push_back(f);
  const auto b_volts = voltage_only(b, "b");
  std::vector<fs::path> mixed = a;
  mixed.insert(mixed.end(), b_volts.begin(), b_volts.end());
  const CliRun r = run("battery" + args(mixed) + " --json");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.err.find("16 voltage-only logs"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("fitted to the logs with both columns"), std::string::npos) << r.err;
  const auto j = nlohmann::json::parse(r.out);
  EXPECT_EQ(j.at("charge_map").at("sources").size(), 16u);  // robot a's logs only
  expect_same_fit(nlohmann::json::parse(run("battery" + args(csvs(shipped_dir())) + " --json").out), j);
}

TEST_F(VoltageLogsCli, VoltagesOutsideTheMapAreClampedAndCountedAndSpeedsOutsideItsLoadTermRefused) {
  // A map by hand: the firmware's line over 3.5..4.2 V, with a load term defined at 0..5 cm/s.
  const std::string map = write("map.json", R"({"kind": "charge_map", "charge_map": {"form": "monotone_piecewise_linear",
    "knots_v": [3.5, 4.2], "knot_charge": [0.125, 1.0], "load_speeds_cm_s": [0, 5], "load_offset_v": [0, 0]}})");
  const std::string log = write("v.csv", "time_s,speed_cm_s,voltage_v\n0,3,4.25\n10,3,4.1\n20,3,3.9\n30,3,3.8\n40,3,3.7\n50,3,3.6\n60,3,3.45\n");
  const CliRun r = run("battery \"" + log + "\" --charge-map \"" + map + "\" --json");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.err.find("2 voltages outside the charge map's range 3.5000..4.2000 V (1 below, 1 above) were clamped"), std::string::npos)
      << r.err;
  EXPECT_NE(r.err.find(log + ":2 (4.2500 V)"), std::string::npos) << r.err;
  const auto j = nlohmann::json::parse(r.out);
  EXPECT_EQ(j.at("charge_conversion").at("clamped_above_range"), 1);
  EXPECT_EQ(j.at("charge_conversion").at("clamped_below_range"), 1);
  // 7 rows for the cubic's 4 parameters and the approximated model's 5: said, not hidden.
  bool weak = false;
  for (const auto& w : j.at("warnings")) weak = weak || w.get<std::string>().find("barely determined") != std::string::npos;
  EXPECT_TRUE(weak) << j.at("warnings").dump();

  const std::string fast = write("fast.csv", "time_s,speed_cm_s,voltage_v\n0,7,4.1\n10,7,4.0\n");
  const CliRun f = run("battery \"" + fast + "\" --charge-map \"" + map + "\"");
  EXPECT_EQ(f.exit_code, 2);
  EXPECT_NE(f.err.find(fast + ":2:3: column 'speed_cm_s': speed 7 cm/s is outside the charge map's load term (0..5 cm/s)"),
            std::string::npos)
      << f.err;
}

TEST_F(VoltageLogsCli, AFileWithoutAChargeMapIsExit2NamingIt) {
  const std::string not_a_map = write("x.json", "{\n  \"kind\": \"battery\"\n}\n");
  const auto volts = voltage_only({shipped_dir() / "robot-a_speed-04.csv"}, "v");
  const CliRun r = run("battery" + args(volts) + " --charge-map \"" + not_a_map + "\"");
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.err.find(not_a_map + ":1:1: no 'charge_map' section"), std::string::npos) << r.err;
}

TEST_F(VoltageLogsCli, ThePlotOfTheMapIsDrawn) {
  const std::string png = (dir_ / "map.png").string();
  const CliRun r = run("battery \"" + (shipped_dir() / "robot-a_speed-04.csv").string() + "\" \"" +
                       (shipped_dir() / "robot-b_speed-04.csv").string() + "\" --plot-charge-map \"" + png + "\"");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_GT(fs::file_size(png), 1000u);
  // With no map at all (no voltage_v anywhere), asking for its plot is a bad usage.
  const std::string plain = write("c.csv", "time_s,speed_cm_s,charge\n0,3,1\n10,3,0.99\n20,3,0.98\n30,3,0.97\n40,3,0.96\n50,3,0.95\n60,3,0.9\n");
  const CliRun n = run("battery \"" + plain + "\" --plot-charge-map \"" + (dir_ / "none.png").string() + "\"");
  EXPECT_EQ(n.exit_code, 2) << n.err;
  EXPECT_FALSE(fs::exists(dir_ / "none.png"));
}

// table5's text report of voltage-only logs ends with the conversion's line: how many logs went
// through which map, the map's residual sd, and how many readings fell outside the map's voltage
// range (clamped to its ends). Counted here from the logs and the map file: the voltage-only
// copies of the virtual robot's seed-7 logs, with one reading pushed 10 mV above the map's range
// and four 10 mV below it (the seed-7 logs themselves fall outside at most twice: the counts differ).
TEST_F(VoltageLogsCli, Table5TextSaysWhichMapAndHowManyReadingsWereClampedCountedFromTheLogs) {
  ASSERT_EQ(run("generate battery --seed 7 --out \"" + (dir_ / "seed7").string() + "\"").exit_code, 0);
  const std::string map = (dir_ / "map.json").string();
  ASSERT_EQ(run("battery" + args(csvs(shipped_dir())) + " -o \"" + map + "\"").exit_code, 0);
  const auto m = nlohmann::json::parse(slurp(map)).at("charge_map");
  const double lo = m.at("voltage_range_v")[0].get<double>(), hi = m.at("voltage_range_v")[1].get<double>();
  const auto volts = voltage_only(csvs(dir_ / "seed7"), "t5_volts");
  ASSERT_EQ(volts.size(), 32u);
  // Push the 3rd data row of the first log above the range, the 5th to 8th of the second below.
  auto push = [&](const fs::path& f, std::vector<int> rows, double v) {
    std::istringstream in(slurp(f));
    std::string line, text;
    int data = -1;  // -1: the header not yet read
    while (std::getline(in, line)) {
      if (!line.empty() && line[0] != '#') {
        if (data >= 0 && std::find(rows.begin(), rows.end(), data) != rows.end()) {
          const std::size_t comma = line.rfind(',');
          char cell[32];
          std::snprintf(cell, sizeof cell, "%.4f", v);
          line = line.substr(0, comma + 1) + cell;
        }
        ++data;
      }
      text += line + "\n";
    }
    std::ofstream(f) << text;
  };
  ASSERT_EQ(slurp(volts[0]).find("voltage_v") != std::string::npos, true);
  push(volts[0], {3}, hi + 0.01);
  push(volts[1], {5, 6, 7, 8}, lo - 0.01);
  // Count the readings outside [lo, hi] from the files (the voltage is the last column).
  int below = 0, above = 0;
  for (const auto& f : volts) {
    std::istringstream in(slurp(f));
    std::string line;
    bool header = false;
    while (std::getline(in, line)) {
      if (line.empty() || line[0] == '#') continue;
      if (!header) {
        ASSERT_EQ(line.substr(line.rfind(',') + 1), "voltage_v") << f;
        header = true;
        continue;
      }
      const double v = std::stod(line.substr(line.rfind(',') + 1));
      below += v < lo;
      above += v > hi;
    }
  }
  ASSERT_GE(below, 4);
  ASSERT_NE(below, above);
  ASSERT_GE(above, 1);
  const CliRun t = run("table5" + args(volts) + " --charge-map \"" + map + "\"");
  ASSERT_EQ(t.exit_code, 0) << t.err;
  char sd[32];
  std::snprintf(sd, sizeof sd, "%.3g", m.at("residual_sd").get<double>());
  const std::string want = "Charge of 32 voltage-only logs from voltage_v through the voltage->charge map of " + map +
                           " (residual sd " + sd + "); clamped to its range: " + std::to_string(below) + " below, " +
                           std::to_string(above) + " above.";
  EXPECT_NE(t.out.find(want), std::string::npos) << "expected: " << want << "\n" << t.out;
  // The JSON report counts the same.
  const CliRun j = run("table5" + args(volts) + " --charge-map \"" + map + "\" --json");
  ASSERT_EQ(j.exit_code, 0) << j.err;
  const auto c = nlohmann::json::parse(j.out).at("charge_conversion");
  EXPECT_EQ(c.at("clamped_below_range").get<int>(), below);
  EXPECT_EQ(c.at("clamped_above_range").get<int>(), above);
  EXPECT_EQ(c.at("logs").get<int>(), 32);
}
