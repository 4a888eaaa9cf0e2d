// Session 8 of the slip classes (bench/fresh-slips.md, "Classes closed (session 8)"; issue #22
// item 6): the classes that round 7's slips fell in, covered where they still held. Every expected
// value is worked by hand in the test, recomputed from the rows by another route (the written
// model run by `simulate --like` over the log, the log's own time column), or a relation between
// sibling fields that a documented formula fixes (docs/coefficient-files.md's statistics table,
// docs/diagnose.md's noise). File-local names carry the prefix c8 (one unity program).
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <map>
#include <Eigen/Dense>
#include <nlohmann/json.hpp>
#include <random>
#include <regex>
#include <set>
#include <sstream>
#include <string>
#include <vector>

#include <sys/wait.h>
#include <unistd.h>

#include "cli_harness.hpp"
#include "epuck2/calibrate/reading_noise.hpp"
#include "epuck2/fit/report.hpp"
#include "epuck2/models/kinds.hpp"
#include "epuck2/models/simulate_log.hpp"

namespace {

namespace c8fs = std::filesystem;
using c8json = nlohmann::json;

// ----- helpers ------------------------------------------------------------------------------

c8fs::path c8_scratch(const std::string& name) {
  const c8fs::path p = c8fs::temp_directory_path() / ("epuck2_c8_" + name + "_" + std::to_string(::getpid()));
  c8fs::remove_all(p);
  c8fs::create_directories(p);
  return p;
}


/// Runs `args` (after the CLI's path) from the source folder; standard output and error into
/// files of `dir`; the exit code.
int c8_cli(const std::string& args, const c8fs::path& dir, std::string* out = nullptr) {
  const c8fs::path o = dir / "stdout.txt", e = dir / "stderr.txt";
  const std::string cmd = "cd '" + std::string(EPUCK2_SOURCE_DIR) + "' && '" + std::string(EPUCK2_FIT_EXE) + "' " + args + " > '" +
                          o.string() + "' 2> '" + e.string() + "'";
  const int status = std::system(cmd.c_str());
  if (out) *out = epuck2::testing::slurp(o);
  return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

/// A CSV's data rows with their line numbers in the file ('#' lines and the header skipped).
std::vector<std::pair<std::size_t, std::map<std::string, double>>> c8_rows(const std::string& text) {
  std::istringstream in(text);
  std::string line;
  std::vector<std::string> names;
  std::vector<std::pair<std::size_t, std::map<std::string, double>>> out;
  for (std::size_t ln = 1; std::getline(in, line); ++ln) {
    if (line.empty() || line[0] == '#') continue;
    std::vector<std::string> cells;
    std::stringstream ss(line);
    std::string cell;
    while (std::getline(ss, cell, ',')) cells.push_back(cell);
    if (names.empty()) {
      names = cells;
      continue;
    }
    std::map<std::string, double> row;
    for (std::size_t k = 0; k < names.size() && k < cells.size(); ++k) row[names[k]] = std::stod(cells[k]);
    out.emplace_back(ln, row);
  }
  return out;
}

/// A CSV's columns by name, '#' lines skipped (the tool's comments and metadata).
std::map<std::string, std::vector<double>> c8_csv(const std::string& text) {
  std::map<std::string, std::vector<double>> cols;
  for (const auto& [line, row] : c8_rows(text))
    for (const auto& [name, value] : row) cols[name].push_back(value);
  return cols;
}

/// A ground log written by hand: 3 sensors, offsets 40, 25, 15 and gains 900, 950, 1000 over the
/// grey level to the power 1.6 (the catalogue's nonlinear_response), 21 grey levels 0 .. 1, 6
/// readings each with the deviations +2, -2, +1, -1, +3, -3 about the rounded mean (sd sqrt(28/6)
/// about it, sqrt(28/5) with one degree per group taken); rows in a seeded shuffle.
std::string c8_ground_log() {
  const double offset[3] = {40, 25, 15}, gain[3] = {900, 950, 1000};
  const double dev[6] = {2, -2, 1, -1, 3, -3};
  std::vector<std::string> rows;
  for (int s = 0; s < 3; ++s)
    for (int k = 0; k <= 20; ++k)
      for (int r = 0; r < 6; ++r) {
        const double grey = 0.05 * k;
        std::ostringstream row;
        row << grey << "," << s << "," << std::round(offset[s] + gain[s] * std::pow(grey, 1.6)) + dev[r];
        rows.push_back(row.str());
      }
  std::mt19937 rng(11);
  std::shuffle(rows.begin(), rows.end(), rng);
  std::string text = "grey,sensor,value\n";
  for (const std::string& r : rows) text += r + "\n";
  return text;
}

/// Checks one statistics block against docs/coefficient-files.md's formulas from its own n, k and
/// RSS: MSE = RSS/n, reduced chi2 = RSS/(n - k), AIC = n ln(RSS/n) + 2k, BIC = n ln(RSS/n) + k ln n.
void c8_expect_statistics(const c8json& s, const std::string& where) {
  const double n = s["n"].get<double>(), k = s["free_parameters"].get<double>(), rss = s["rss"].get<double>();
  ASSERT_GT(n, k) << where;
  ASSERT_GT(rss, 0.0) << where;
  const double tol = 1e-9;
  EXPECT_NEAR(s["mse"].get<double>(), rss / n, tol * rss / n) << where;
  EXPECT_NEAR(s["reduced_chi2"].get<double>(), rss / (n - k), tol * rss / (n - k)) << where;
  const double ll = n * std::log(rss / n);
  EXPECT_NEAR(s["aic"].get<double>(), ll + 2 * k, 1e-9 * std::abs(ll) + 1e-9) << where;
  EXPECT_NEAR(s["bic"].get<double>(), ll + k * std::log(n), 1e-9 * std::abs(ll) + 1e-9) << where;
}

// ----- class A: every numeric field of the diagnosis report ----------------------------------

// A diagnosis of the hand-made ground log (binary, `--json` and `-o`): every statistics block
// (recalibrated, final, each finding's) follows from its own n, k and RSS; n is the log's 378
// rows; R^2 is 1 - RSS / sum (y - mean y)^2 with the sum from the log; fit.final is the written
// model's: `simulate ground --like` with the extended model gives back, row by row, an MSE equal
// to fit.final.mse, and with the plug-in's model (the ground base has no free parameter:
// docs/diagnose.md) fit.recalibrated.mse. The findings chain: each one's held-out MSE after is
// the next one's before, the first's before is heldout_mse_recalibrated, the last's after
// heldout_mse_final, each lower; the last finding's fit is fit.final. noise_sd is the final
// model's residual sd; the file's noise is the final residuals' with the rounding's 1/12 taken out
// (docs/diagnose.md: at most that, and below the replicates' 28/5 - 1/12 here).
TEST(ClassesEightDiagnosisReport, EveryFitFieldFollowsFromTheRowsAndTheWrittenModel) {
  const c8fs::path dir = c8_scratch("dreport");
  const std::string text = c8_ground_log();
  {
    std::ofstream f(dir / "g.csv");
    f << text;
  }
  const std::string log = "'" + (dir / "g.csv").string() + "'";
  std::string out;
  ASSERT_EQ(c8_cli("diagnose " + log + " --json -o '" + (dir / "ext.json").string() + "'", dir, &out), 0) << epuck2::testing::slurp(dir / "stderr.txt");
  const c8json j = c8json::parse(out);
  ASSERT_GE(j["findings"].size(), 2u) << out;
  const c8json& rec = j["fit"]["recalibrated"];
  const c8json& fin = j["fit"]["final"];
  c8_expect_statistics(rec, "fit.recalibrated");
  c8_expect_statistics(fin, "fit.final");
  for (const c8json& f : j["findings"]) c8_expect_statistics(f["fit"], "finding " + f["cause"].get<std::string>());

  // n and R^2 from the log itself.
  const auto y = c8_csv(text).at("value");
  ASSERT_EQ(y.size(), 378u);
  double mean = 0, ss = 0;
  for (double v : y) mean += v / y.size();
  for (double v : y) ss += (v - mean) * (v - mean);
  for (const c8json* s : {&rec, &fin}) {
    EXPECT_EQ((*s)["n"].get<std::size_t>(), y.size());
    EXPECT_NEAR((*s)["r2"].get<double>(), 1 - (*s)["rss"].get<double>() / ss, 1e-9);
  }

  // base and final differ, and the final fits better.
  EXPECT_GT(fin["free_parameters"].get<int>(), rec["free_parameters"].get<int>());
  EXPECT_LT(fin["rss"].get<double>(), 0.01 * rec["rss"].get<double>());
  EXPECT_DOUBLE_EQ(j["findings"].back()["fit"]["rss"].get<double>(), fin["rss"].get<double>());

  // the written model over the rows (simulate without noise: the expected readings).
  auto mse_of = [&](const std::string& coefficients) {
    const c8fs::path sim = dir / "sim.csv";
    EXPECT_EQ(c8_cli("simulate ground --like " + log + coefficients + " -o '" + sim.string() + "'", dir), 0) << epuck2::testing::slurp(dir / "stderr.txt");
    const auto p = c8_csv(epuck2::testing::slurp(sim)).at("value");
    EXPECT_EQ(p.size(), y.size());
    double s = 0;
    for (std::size_t i = 0; i < std::min(p.size(), y.size()); ++i) s += (y[i] - p[i]) * (y[i] - p[i]);
    return s / y.size();
  };
  const double written = mse_of(" --coefficients '" + (dir / "ext.json").string() + "'");
  EXPECT_NEAR(fin["mse"].get<double>(), written, 1e-6 * written);
  EXPECT_LT(written, 2.0 * 28.0 / 6.0);  // the deviations' own 28/6 and the fit's slack
  const double plugin = mse_of("");
  EXPECT_NEAR(rec["mse"].get<double>(), plugin, 1e-9 * plugin);

  // the findings' held-out MSEs, chained.
  double before = j["heldout_mse_recalibrated"].get<double>();
  for (const c8json& f : j["findings"]) {
    EXPECT_DOUBLE_EQ(f["heldout_mse_before"].get<double>(), before) << f["cause"];
    EXPECT_LT(f["heldout_mse_after"].get<double>(), before) << f["cause"];
    before = f["heldout_mse_after"].get<double>();
  }
  EXPECT_DOUBLE_EQ(j["heldout_mse_final"].get<double>(), before);
  EXPECT_LT(j["heldout_mse_final"].get<double>(), 2.0 * 28.0 / 6.0);

  // the noise.
  EXPECT_NEAR(j["noise_sd"].get<double>(), std::sqrt(fin["mse"].get<double>()), 1e-6);
  const double sd = j["noise"]["ground"]["sd"].get<double>();
  EXPECT_NEAR(sd * sd, fin["mse"].get<double>() - 1.0 / 12.0, 1e-6);
  EXPECT_LT(sd * sd, 28.0 / 5.0 - 1.0 / 12.0);
  c8fs::remove_all(dir);
}


// Every kind, on the first shipped log of each: every statistics block of the diagnosis report
// (recalibrated, final, each finding's) follows from its own n, k and RSS by the documented
// formulas; where a finding is kept the final fit has more free parameters and a smaller RSS than
// the recalibrated one, and the last finding's fit is the final one (where no possible finding
// stayed in the search's model). The held-out MSEs chain
// (each finding's before is the one before it's after, from heldout_mse_recalibrated to
// heldout_mse_final) where every finding is judged on the same rows' MSE: light, ground, camera,
// drive (its ToF channel) and battery (proximity's findings are judged on the censored
// likelihood's rows, not chained). For light and camera (no rail reached) the written model,
// run by `simulate --like` over the log, gives back fit.final's RSS and n over the rows that the
// report does not list as wild (`outliers.rows`, file:line), on the kind's reading columns.
TEST(ClassesEightDiagnosisReport, EveryKindsFitBlocksFollowFromTheirRowsAndTheWrittenModel) {
  const c8fs::path dir = c8_scratch("kinds");
  struct Kind {
    std::string kind, log;
    std::vector<std::string> readings;  // empty: no written-model check
    bool chained;
  };
  const std::vector<Kind> kinds = {{"proximity", "data/raw/proximity/proximity_virtual-epuck2-1.csv", {}, false},
                                   {"light", "data/raw/light/light_intensity_0.50.csv", {"value"}, true},
                                   {"ground", "data/raw/ground/ground_virtual-epuck2-1.csv", {}, true},
                                   {"camera", "data/raw/camera/camera_virtual-epuck2-1.csv", {"px", "py"}, true},
                                   {"drive", "data/raw/drive/drive_away_02.5_cm_s.csv", {}, true},
                                   {"battery", "data/raw/battery/robot-a_speed-00.csv", {}, true}};
  for (const Kind& k : kinds) {
    SCOPED_TRACE(k.kind);
    const c8fs::path ext = dir / (k.kind + ".json");
    std::string out;
    ASSERT_EQ(c8_cli("diagnose " + k.log + " --json -o '" + ext.string() + "'", dir, &out), 0) << epuck2::testing::slurp(dir / "stderr.txt");
    const c8json j = c8json::parse(out);
    const c8json& rec = j["fit"]["recalibrated"];
    const c8json& fin = j["fit"]["final"];
    c8_expect_statistics(rec, "fit.recalibrated");
    c8_expect_statistics(fin, "fit.final");
    for (const c8json& f : j["findings"]) c8_expect_statistics(f["fit"], "finding " + f["cause"].get<std::string>());
    ASSERT_FALSE(j["findings"].empty()) << "the shipped logs hold the virtual robot's imperfections";
    EXPECT_GT(fin["free_parameters"].get<int>(), rec["free_parameters"].get<int>());
    EXPECT_LT(fin["rss"].get<double>(), rec["rss"].get<double>());
    EXPECT_EQ(fin["n"], rec["n"]);
    // (a possible, not determined finding is in the search's model at later steps but not in
    // the final one: docs/diagnose.md; the shipped proximity log keeps a long_tail so)
    if (j["possible_findings"].empty()) EXPECT_DOUBLE_EQ(j["findings"].back()["fit"]["rss"].get<double>(), fin["rss"].get<double>());
    if (k.chained) {
      double before = j["heldout_mse_recalibrated"].get<double>();
      for (const c8json& f : j["findings"]) {
        EXPECT_NEAR(f["heldout_mse_before"].get<double>(), before, 1e-6 * before) << f["cause"];
        before = f["heldout_mse_after"].get<double>();
      }
      EXPECT_NEAR(j["heldout_mse_final"].get<double>(), before, 1e-6 * before);
    }
    if (k.readings.empty()) continue;
    std::set<std::size_t> wild;
    const std::regex at(":([0-9]+):");
    for (const c8json& r : j["outliers"]["rows"]) {
      std::smatch m;
      const std::string text = r.get<std::string>();
      ASSERT_TRUE(std::regex_search(text, m, at)) << text;
      wild.insert(std::stoul(m[1]));
    }
    const c8fs::path sim = dir / (k.kind + "_sim.csv");
    ASSERT_EQ(c8_cli("simulate " + k.kind + " --like " + k.log + " --coefficients '" + ext.string() + "' -o '" + sim.string() + "'", dir), 0)
        << epuck2::testing::slurp(dir / "stderr.txt");
    const auto measured = c8_rows(epuck2::testing::slurp(c8fs::path(EPUCK2_SOURCE_DIR) / k.log));
    const auto simulated = c8_rows(epuck2::testing::slurp(sim));
    ASSERT_EQ(measured.size(), simulated.size());
    double rss = 0;
    std::size_t n = 0;
    for (std::size_t i = 0; i < measured.size(); ++i) {
      if (wild.count(measured[i].first)) continue;
      for (const std::string& c : k.readings) {
        const double d = measured[i].second.at(c) - simulated[i].second.at(c);
        rss += d * d;
        ++n;
      }
    }
    EXPECT_EQ(n, fin["n"].get<std::size_t>());
    EXPECT_NEAR(rss, fin["rss"].get<double>(), 1e-6 * rss);
  }
  c8fs::remove_all(dir);
}

// The two exceptions to the chain that docs/diagnose.md states, on the shipped log that shows both:
// a pair accepted together shares one step (both findings give the pair's before and after), and
// with the drive's two channels a finding's before is the model without it refitted under the
// noise weights it re-estimated, within 1e-4 of the previous after. Every other link is exact.
TEST(ClassesEightDiagnosisReport, AChainBreaksOnlyWhereTheDocsSay) {
  const c8fs::path dir = c8_scratch("pairchain");
  std::string out;
  ASSERT_EQ(c8_cli("diagnose data/raw/drive/drive_away_10.0_cm_s.csv --json", dir, &out), 0) << epuck2::testing::slurp(dir / "stderr.txt");
  const c8json j = c8json::parse(out);
  const c8json& fs = j["findings"];
  ASSERT_GE(fs.size(), 2u);
  double before = j["heldout_mse_recalibrated"].get<double>();
  std::size_t pairs = 0;
  for (std::size_t i = 0; i < fs.size(); ++i) {
    const c8json& f = fs[i];
    SCOPED_TRACE(f["cause"].get<std::string>());
    EXPECT_NEAR(f["heldout_mse_before"].get<double>(), before, 1e-4 * before);
    EXPECT_LT(f["heldout_mse_after"].get<double>(), f["heldout_mse_before"].get<double>());
    const std::string with = f.value("accepted_with", std::string());
    if (!with.empty()) {
      ASSERT_LT(i + 1, fs.size()) << "a pair's second finding follows its first";
      const c8json& g = fs[i + 1];
      EXPECT_EQ(g["cause"].get<std::string>(), with);
      EXPECT_EQ(g["accepted_with"].get<std::string>(), f["cause"].get<std::string>());
      EXPECT_EQ(g["heldout_mse_before"].get<double>(), f["heldout_mse_before"].get<double>());
      EXPECT_EQ(g["heldout_mse_after"].get<double>(), f["heldout_mse_after"].get<double>());
      ++pairs;
      ++i;
    }
    before = f["heldout_mse_after"].get<double>();
  }
  EXPECT_EQ(pairs, 1u) << "the shipped log's ToF offset and speed scale are found together";
  EXPECT_EQ(j["heldout_mse_final"].get<double>(), before);
  c8fs::remove_all(dir);
}

// ----- class D/A: derived numbers and units of the battery file -------------------------------

// The battery file's lifetime at each speed from the logs' own time columns (docs/coefficient-
// files.md): lifetime_s the mean of the runs' last times, lifetime_std_error_s their standard
// error (sample sd / sqrt(runs)), lifetime_h = lifetime_s / 3600, linear_slope = -1 / lifetime_s
// (1/s) with its error se / lifetime^2, runs the number of logs at that speed.
TEST(ClassesEightBatteryFile, LifetimesAndLinearSlopesFromTheLogsTimeColumns) {
  const c8fs::path dir = c8_scratch("battery");
  std::map<double, std::vector<double>> ends;  // speed -> each run's last time
  for (const auto& e : c8fs::directory_iterator(c8fs::path(EPUCK2_SOURCE_DIR) / "data/raw/battery")) {
    if (e.path().extension() != ".csv") continue;
    const auto cols = c8_csv(epuck2::testing::slurp(e.path()));
    ends[cols.at("speed_cm_s").front()].push_back(cols.at("time_s").back());
  }
  ASSERT_GE(ends.size(), 2u);
  ASSERT_EQ(c8_cli("battery data/raw/battery/*.csv -o '" + (dir / "b.json").string() + "'", dir), 0) << epuck2::testing::slurp(dir / "stderr.txt");
  const c8json j = c8json::parse(epuck2::testing::slurp(dir / "b.json"));
  ASSERT_EQ(j["speeds"].size(), ends.size());
  for (const c8json& s : j["speeds"]) {
    const double speed = s["speed_cm_s"].get<double>();
    ASSERT_EQ(ends.count(speed), 1u) << speed;
    const std::vector<double>& t = ends[speed];
    double mean = 0, ss = 0;
    for (double v : t) mean += v / t.size();
    for (double v : t) ss += (v - mean) * (v - mean);
    const double se = t.size() > 1 ? std::sqrt(ss / (t.size() - 1)) / std::sqrt(double(t.size())) : 0.0;
    EXPECT_EQ(s["runs"].get<std::size_t>(), t.size()) << speed;
    EXPECT_NEAR(s["lifetime_s"].get<double>(), mean, 1e-9 * mean) << speed;
    EXPECT_NEAR(s["lifetime_h"].get<double>(), mean / 3600.0, 1e-9 * mean / 3600.0) << speed;
    EXPECT_NEAR(s["lifetime_std_error_s"].get<double>(), se, 1e-9 * mean) << speed;
    EXPECT_NEAR(s["linear_slope"].get<double>(), -1.0 / mean, 1e-9 / mean) << speed;
    EXPECT_NEAR(s["linear_slope_std_error"].get<double>(), se / (mean * mean), 1e-6 * se / (mean * mean) + 1e-18) << speed;
  }
  c8fs::remove_all(dir);
}

// The camera file's standard errors in their units (degrees for fov_deg, px for the centre),
// recomputed by another route: docs/coefficient-files.md's pinhole, px = cx - f lateral/forward,
// py = cy - f vertical/forward, f = 80 / tan(fov/2), differentiated by central differences in
// degrees and pixels at the file's parameters over the rows the file does not list as outliers;
// se = sqrt(s^2 (J^T J)^-1), s^2 the projection fit's reduced chi^2 (its noise sd squared). Within
// 1 % (the file leaves out single readings, the test their rows). A derivative taken per radian
// and written per degree is 57.3 times off.
TEST(ClassesEightCameraFile, StandardErrorsInDegreesAndPixelsByFiniteDifferences) {
  const c8fs::path dir = c8_scratch("camera");
  const std::string log = "data/raw/camera/camera_virtual-epuck2-1.csv";
  ASSERT_EQ(c8_cli("camera " + log + " -o '" + (dir / "c.json").string() + "'", dir), 0) << epuck2::testing::slurp(dir / "stderr.txt");
  const c8json j = c8json::parse(epuck2::testing::slurp(dir / "c.json"));
  std::set<std::size_t> wild;
  for (const c8json& r : j["outliers"]["rows"]) {
    const std::string t = r.get<std::string>();
    wild.insert(std::stoul(t.substr(t.rfind(':') + 1)));
  }
  const double pi = std::acos(-1.0);
  const Eigen::Vector3d p0(j["parameters"]["fov_deg"].get<double>(), j["parameters"]["cx_px"].get<double>(),
                           j["parameters"]["cy_px"].get<double>());
  auto project = [&](const Eigen::Vector3d& p, double fwd, double lat, double vert) {
    const double f = 80.0 / std::tan(p[0] * pi / 180.0 / 2.0);
    return Eigen::Vector2d(p[1] - f * lat / fwd, p[2] - f * vert / fwd);
  };
  Eigen::Matrix3d jtj = Eigen::Matrix3d::Zero();
  std::size_t rows = 0;
  for (const auto& [line, r] : c8_rows(epuck2::testing::slurp(c8fs::path(EPUCK2_SOURCE_DIR) / log))) {
    if (wild.count(line)) continue;
    Eigen::Matrix<double, 2, 3> g;
    for (int k = 0; k < 3; ++k) {
      Eigen::Vector3d a = p0, b = p0;
      a[k] += 1e-4;
      b[k] -= 1e-4;
      g.col(k) = (project(a, r.at("forward_m"), r.at("lateral_m"), r.at("vertical_m")) -
                  project(b, r.at("forward_m"), r.at("lateral_m"), r.at("vertical_m"))) / 2e-4;
    }
    jtj += g.transpose() * g;
    ++rows;
  }
  ASSERT_GT(rows, 300u);
  const double s2 = j["fits"]["projection"]["reduced_chi2"].get<double>();
  const Eigen::Matrix3d cov = s2 * jtj.inverse();
  const char* names[3] = {"fov_deg", "cx_px", "cy_px"};
  for (int k = 0; k < 3; ++k) {
    const double want = std::sqrt(cov(k, k));
    EXPECT_NEAR(j["std_errors"][names[k]].get<double>(), want, 0.01 * want) << names[k];
  }
  c8fs::remove_all(dir);
}

// The drive file's numbers in their documented units (docs/coefficient-files.md), from the logs by
// hand: steps_per_m against each moving run's encoder slope over its second half, steps per
// second over the commanded speed in m/s (runs at most 12.5 cm/s: 15 is above the firmware's
// cap), within 0.2 % each and 0.1 % on their mean; the ToF's scale and offset (mm) against the
// readings standing before a run first moves, tof_mm = scale 1000 (D - 0) + offset with D the
// log's obstacle_distance_m: their mean misfit within 1 mm (the noise's ~3.7 mm over ~100 rows);
// capped_rows the rows whose command, either wheel, exceeds the firmware's 1100 steps/s (14.17
// cm/s), over_limit_runs the runs holding one.
TEST(ClassesEightDriveFile, StepsPerMetreAndTofLineInTheirUnitsFromTheLogs) {
  const c8fs::path dir = c8_scratch("drive");
  ASSERT_EQ(c8_cli("drive data/raw/drive/*.csv -o '" + (dir / "d.json").string() + "'", dir), 0) << epuck2::testing::slurp(dir / "stderr.txt");
  const c8json j = c8json::parse(epuck2::testing::slurp(dir / "d.json"));
  const double steps_per_m = j["parameters"]["steps_per_m"].get<double>();
  const double scale = j["parameters"]["tof_scale"].get<double>(), offset = j["parameters"]["tof_offset_mm"].get<double>();
  double slopes = 0, misfit = 0;
  std::size_t runs = 0, still = 0, capped = 0, capped_runs = 0;
  const double cap_cm_s = 1100.0 / 7763.656 * 100.0;  // the firmware's 1100 steps/s at the plug-in's steps/m
  for (const auto& e : c8fs::directory_iterator(c8fs::path(EPUCK2_SOURCE_DIR) / "data/raw/drive")) {
    if (e.path().extension() != ".csv") continue;
    const std::string text = epuck2::testing::slurp(e.path());
    const std::size_t at = text.find("# obstacle_distance_m: ");
    ASSERT_NE(at, std::string::npos) << e.path();
    const double d_m = std::stod(text.substr(at + 23));
    const auto rows = c8_rows(text);
    std::vector<std::map<std::string, double>> moving;
    bool moved = false;
    std::size_t over = 0;
    for (const auto& [line, r] : rows) {
      (void)line;
      if (std::max(std::abs(r.at("left_speed_cm_s")), std::abs(r.at("right_speed_cm_s"))) > cap_cm_s) ++over;
      moved = moved || r.at("left_speed_cm_s") != 0 || r.at("right_speed_cm_s") != 0;
      if (!moved && r.at("tof_mm") < 8190) {
        misfit += r.at("tof_mm") - (scale * 1000.0 * d_m + offset);
        ++still;
      }
      if (r.at("left_speed_cm_s") != 0) moving.push_back(r);
    }
    capped += over;
    capped_runs += over > 0;
    if (moving.size() < 10 || std::abs(moving.front().at("left_speed_cm_s")) > 12.5) continue;
    const auto& a = moving[moving.size() / 2];
    const auto& b = moving.back();
    const double slope = (b.at("left_steps") - a.at("left_steps")) / (b.at("time_s") - a.at("time_s")) / (a.at("left_speed_cm_s") / 100.0);
    EXPECT_NEAR(slope, steps_per_m, 0.002 * steps_per_m) << e.path();
    slopes += slope;
    ++runs;
  }
  ASSERT_GE(runs, 10u);
  ASSERT_GE(still, 50u);
  EXPECT_NEAR(slopes / runs, steps_per_m, 0.001 * steps_per_m);
  EXPECT_NEAR(misfit / still, 0.0, 1.0);
  EXPECT_EQ(j["capped_rows"].get<std::size_t>(), capped);
  EXPECT_EQ(j["over_limit_runs"].size(), capped_runs);
  EXPECT_GT(capped, 0u);
  c8fs::remove_all(dir);
}

// ----- class E: `simulate --like` with noise, every kind ---------------------------------------

/// A log's columns as simulated_readings reads a log.
struct C8Log {
  std::map<std::string, std::vector<double>> c;
  double obstacle_m = 1.0;
  bool has(const std::string& k) const { return c.count(k) != 0; }
  const std::vector<double>& col(const std::string& k) const { return c.at(k); }
  std::size_t rows() const { return c.begin()->second.size(); }
  double metadata_number(const std::string&) const { return obstacle_m; }
};

/// Every draw the same number of standard deviations: with +1 each noisy reading is its own
/// sensor's mean plus its own sensor's noise sd, rounded.
struct C8ConstantNormal {
  double z = 1.0;
  double operator()() { return z; }
};

// Ground with noise: sensor s reads round(offset_s + gain_s grey^1.6 + sd_s) (each draw +1 sd),
// clamped to 0..1023, by hand: offsets 40, 25, 15, gains 900, 950, 1000, sds 2, 5, 9; rows in the
// sensor order 2, 0, 1, 1, 2, 0 at grey levels that differ.
TEST(ClassesEightSimulateLikeNoisy, GroundEachSensorFollowsItsOwnLineAndNoise) {
  namespace s = epuck2::models::sensors;
  s::GroundModel m;
  const double offset[3] = {40, 25, 15}, gain[3] = {900, 950, 1000}, sd[3] = {2, 5, 9};
  for (int k = 0; k < 3; ++k) {
    m.sensors[k].offset_raw = offset[k];
    m.sensors[k].gain_raw = gain[k];
    m.noise_sd_raw[k] = sd[k];
  }
  m.effects.exponent = 1.6;
  C8Log log;
  log.c["sensor"] = {2, 0, 1, 1, 2, 0};
  log.c["grey"] = {0.3, 0.7, 0.45, 0.9, 0.1, 0.25};
  C8ConstantNormal one;
  const std::vector<double> cov(6, 0.0);
  const auto out = s::simulated_readings(m, log, cov, true, one);
  ASSERT_EQ(out.size(), 6u);
  for (std::size_t i = 0; i < 6; ++i) {
    const int k = static_cast<int>(log.c["sensor"][i]);
    const double want = std::round(offset[k] + gain[k] * std::pow(log.c["grey"][i], 1.6) + sd[k]);
    EXPECT_EQ(out[i].at(0), want) << "row " << i << " sensor " << k;
  }
}

// Light with noise: sensor s reads round(4095 (1 - g_s (gamma_s I / d)^2) - offset + sd_s), by
// hand: per-sensor gammas 0.06, 0.08, 0.1 (sensors 0..2), gains 0.9, 1.0, 1.1, ambient offset 12,
// sds 3, 6, 11; distance and intensity differ on every row (their swap changes the ratio).
TEST(ClassesEightSimulateLikeNoisy, LightEachSensorFollowsItsOwnGammaGainAndNoise) {
  namespace s = epuck2::models::sensors;
  s::LightModel m;
  const double gamma[3] = {0.06, 0.08, 0.1}, g[3] = {0.9, 1.0, 1.1}, sd[3] = {3, 6, 11};
  for (int k = 0; k < 3; ++k) {
    m.sensor_gamma_m[k] = gamma[k];
    m.effects.gains.gain[k] = g[k];
    m.noise_sd_raw[k] = sd[k];
  }
  m.effects.ambient.offset_raw = 12.0;
  C8Log log;
  log.c["sensor"] = {1, 2, 0, 2, 0, 1};
  log.c["distance_m"] = {0.2, 0.35, 0.15, 0.25, 0.3, 0.12};
  log.c["intensity"] = {0.5, 1.2, 0.8, 0.7, 1.5, 0.4};
  C8ConstantNormal one;
  const std::vector<double> cov(6, 0.0);
  const auto out = s::simulated_readings(m, log, cov, true, one);
  ASSERT_EQ(out.size(), 6u);
  for (std::size_t i = 0; i < 6; ++i) {
    const int k = static_cast<int>(log.c["sensor"][i]);
    const double r = gamma[k] * log.c["intensity"][i] / log.c["distance_m"][i];
    const double want = std::clamp(std::round(4095.0 * (1 - g[k] * r * r) - 12.0 + sd[k]), 0.0, 4095.0);
    EXPECT_EQ(out[i].at(0), want) << "row " << i << " sensor " << k;
  }
}

// Proximity with noise: with draws +1 and -1 sd, sensor s's two readings differ by 2 sd_s (to the
// rounding's 1 count), sds 10, 40, 90 for sensors 0..2 (rows in another order); with draw 0 each
// reading is the noiseless expected reading of its own row rounded, at distances and angles that
// differ (gains 0.8, 1.0, 1.25 per sensor, so that a sibling's sensor index shows; the incidence
// effect on, k = 2, so that the angle does).
TEST(ClassesEightSimulateLikeNoisy, ProximityEachSensorDrawsItsOwnNoiseAtItsOwnDistance) {
  namespace s = epuck2::models::sensors;
  s::ProximityModel m;
  const double sd[3] = {10, 40, 90}, g[3] = {0.8, 1.0, 1.25};
  for (int k = 0; k < 3; ++k) {
    m.noise_sd_raw[k] = sd[k];
    m.effects.gains.gain[k] = g[k];
  }
  m.effects.incidence.k = 2.0;  // the angle matters: cos^2 of it
  C8Log log;
  log.c["sensor"] = {2, 0, 1, 0, 2, 1};
  log.c["distance_m"] = {0.01, 0.02, 0.015, 0.03, 0.012, 0.025};
  log.c["angle_deg"] = {0, 20, 40, 10, 30, 0};
  const std::vector<double> cov(6, 0.0);
  C8ConstantNormal up{1.0}, down{-1.0}, zero{0.0};
  const auto hi = s::simulated_readings(m, log, cov, true, up);
  const auto lo = s::simulated_readings(m, log, cov, true, down);
  const auto mid = s::simulated_readings(m, log, cov, true, zero);
  const auto exact = s::simulated_readings(m, log, cov, false, zero);
  for (std::size_t i = 0; i < 6; ++i) {
    const int k = static_cast<int>(log.c["sensor"][i]);
    ASSERT_GT(exact[i][0], 2 * sd[2]) << "row " << i << ": the fixture must sit off the rails";
    ASSERT_LT(exact[i][0], 4095 - 2 * sd[2]) << "row " << i;
    EXPECT_NEAR(hi[i][0] - lo[i][0], 2 * sd[k], 1.0) << "row " << i << " sensor " << k;
    EXPECT_EQ(mid[i][0], std::round(exact[i][0])) << "row " << i;
  }
  // the fixture's power: the rows' expected readings all differ, and each row at an angle reads
  // otherwise than it would facing the surface
  C8Log facing = log;
  facing.c["angle_deg"] = std::vector<double>(6, 0.0);
  const auto straight = s::simulated_readings(m, facing, cov, false, zero);
  for (std::size_t i = 0; i < 6; ++i)
    if (log.c["angle_deg"][i] != 0) EXPECT_GT(std::abs(straight[i][0] - exact[i][0]), 2.0) << "row " << i;
  for (std::size_t a = 0; a < 6; ++a)
    for (std::size_t b = a + 1; b < 6; ++b) EXPECT_GT(std::abs(exact[a][0] - exact[b][0]), 2.0) << a << " " << b;
}

// Camera with noise: each axis is its own mean plus the noise (px and py are not swapped, every
// draw +1 sd = 2 px), the LED positions asymmetric so that px != py and forward, lateral and
// vertical differ; with draw 0 the rounded noiseless position.
TEST(ClassesEightSimulateLikeNoisy, CameraEachAxisFollowsItsOwnPosition) {
  namespace s = epuck2::models::sensors;
  s::CameraModel m;
  m.noise_sd_px = 2.0;
  C8Log log;
  log.c["forward_m"] = {0.3, 0.5, 0.4};
  log.c["lateral_m"] = {0.05, -0.08, 0.02};
  log.c["vertical_m"] = {-0.03, 0.04, 0.06};
  const std::vector<double> cov(3, 0.0);
  C8ConstantNormal up{1.0}, zero{0.0};
  const auto hi = s::simulated_readings(m, log, cov, true, up);
  const auto mid = s::simulated_readings(m, log, cov, true, zero);
  const auto exact = s::simulated_readings(m, log, cov, false, zero);
  for (std::size_t i = 0; i < 3; ++i) {
    ASSERT_EQ(exact[i].size(), 2u) << "row " << i << " must be seen";
    ASSERT_GT(std::abs(exact[i][0] - exact[i][1]), 5.0) << "row " << i;
    for (int a = 0; a < 2; ++a) {
      EXPECT_EQ(mid[i].at(a), std::round(exact[i][a])) << "row " << i << " axis " << a;
      EXPECT_EQ(hi[i].at(a), std::round(exact[i][a] + 2.0)) << "row " << i << " axis " << a;
    }
  }
}

// Drive with noise: the ToF's draw is in mm (sd 7 mm), the encoders' in steps (sd 0.4): every draw
// +1 sd moves the ToF by 7 mm (to the rounding) against the noiseless run, never by 0.4; both
// wheels commanded differently (8 and 3 cm/s), each encoder within a step of its noiseless count.
TEST(ClassesEightSimulateLikeNoisy, DriveToFAndEncodersDrawTheirOwnNoise) {
  namespace s = epuck2::models::sensors;
  s::DriveModel m;
  m.tof_noise_sd_mm = 7.0;
  m.encoder_noise_sd_steps = 0.4;
  C8Log log;
  log.obstacle_m = 0.5;
  for (int i = 0; i <= 10; ++i) {
    log.c["time_s"].push_back(0.1 * i);
    log.c["left_speed_cm_s"].push_back(8.0);
    log.c["right_speed_cm_s"].push_back(3.0);
  }
  const std::vector<double> cov(11, 0.0);
  C8ConstantNormal up{1.0}, zero{0.0};
  const auto hi = s::simulated_readings(m, log, cov, true, up);
  const auto exact = s::simulated_readings(m, log, cov, false, zero);
  ASSERT_GT(exact.back()[0], exact.back()[1] + 100) << "the left wheel must have turned further";
  for (std::size_t i = 1; i < 11; ++i) {
    EXPECT_NEAR(hi[i][2] - exact[i][2], 7.0, 1.0) << "row " << i;
    EXPECT_NEAR(hi[i][0], exact[i][0], 1.0) << "row " << i;
    EXPECT_NEAR(hi[i][1], exact[i][1], 1.0) << "row " << i;
  }
}

// Battery with noise: the charge is the mean plus noise_sd times the draw, not rounded: +1 sd of
// 0.004 is 0.004 above the noiseless charge on every row below the bound 1.05.
TEST(ClassesEightSimulateLikeNoisy, BatteryChargeMovesByItsOwnNoise) {
  namespace s = epuck2::models::sensors;
  s::BatteryModel m;
  m.noise_sd = 0.004;
  C8Log log;
  log.c["time_s"] = {0, 600, 1200, 1800};
  log.c["speed_cm_s"] = {5, 5, 5, 5};
  log.c["charge"] = {0.9, 0.85, 0.8, 0.75};
  const std::vector<double> cov(4, 0.0);
  C8ConstantNormal up{1.0}, zero{0.0};
  const auto hi = s::simulated_readings(m, log, cov, true, up);
  const auto exact = s::simulated_readings(m, log, cov, false, zero);
  for (std::size_t i = 0; i < 4; ++i) {
    ASSERT_LT(exact[i][0], 1.05 - 0.004) << "row " << i;
    EXPECT_NEAR(hi[i][0] - exact[i][0], 0.004, 1e-12) << "row " << i;
  }
}

// Through the binary, the file's noise per sensor: a ground log written by hand whose sensors
// scatter by +-2, +-3, +-8 counts (20 readings at each of 11 grey levels: replicate sd d sqrt(20/19)
// = 2.052, 3.078, 8.208), calibrated (`ground -o`), then `simulate ground --like --noise --seed 3`
// and without noise: each sensor's simulated readings scatter about the noiseless ones by its own
// sd (within 20 %: 220 draws each, and the rounding) and centre on them (within 4 sd / sqrt(220)).
TEST(ClassesEightSimulateLikeNoisy, GroundThroughTheBinaryEachSensorDrawsItsOwnFilesNoise) {
  const c8fs::path dir = c8_scratch("gnoise");
  const double offset[3] = {30, 10, 20}, gain[3] = {700, 850, 990}, dev[3] = {2, 3, 8};
  {
    std::ofstream f(dir / "g.csv");
    f << "grey,sensor,value\n";
    for (int k = 0; k <= 10; ++k)
      for (int s = 0; s < 3; ++s)
        for (int r = 0; r < 20; ++r) f << 0.1 * k << "," << s << "," << std::round(offset[s] + gain[s] * 0.1 * k) + (r % 2 ? dev[s] : -dev[s]) << "\n";
  }
  const std::string log = "'" + (dir / "g.csv").string() + "'", file = "'" + (dir / "g.json").string() + "'";
  ASSERT_EQ(c8_cli("ground " + log + " -o " + file, dir), 0) << epuck2::testing::slurp(dir / "stderr.txt");
  ASSERT_EQ(c8_cli("simulate ground --like " + log + " --coefficients " + file + " --noise --seed 3 -o '" + (dir / "n.csv").string() + "'", dir), 0)
      << epuck2::testing::slurp(dir / "stderr.txt");
  ASSERT_EQ(c8_cli("simulate ground --like " + log + " --coefficients " + file + " -o '" + (dir / "e.csv").string() + "'", dir), 0)
      << epuck2::testing::slurp(dir / "stderr.txt");
  const auto noisy = c8_csv(epuck2::testing::slurp(dir / "n.csv")), exact = c8_csv(epuck2::testing::slurp(dir / "e.csv"));
  ASSERT_EQ(noisy.at("value").size(), 660u);
  ASSERT_EQ(exact.at("value").size(), 660u);
  for (int s = 0; s < 3; ++s) {
    std::vector<double> d;
    for (std::size_t i = 0; i < 660; ++i)
      if (noisy.at("sensor")[i] == s) d.push_back(noisy.at("value")[i] - exact.at("value")[i]);
    ASSERT_EQ(d.size(), 220u);
    double mean = 0, ss = 0;
    for (double v : d) mean += v / d.size();
    for (double v : d) ss += (v - mean) * (v - mean);
    const double want = dev[s] * std::sqrt(20.0 / 19.0);
    EXPECT_NEAR(std::sqrt(ss / (d.size() - 1)), want, 0.2 * want) << "sensor " << s;
    EXPECT_NEAR(mean, 0.0, 4 * want / std::sqrt(220.0)) << "sensor " << s;
  }
  c8fs::remove_all(dir);
}

// ----- class C: the reading noise's group sizes, at the limits ----------------------------------

/// 50 groups of two readings -1, +1 (each 2 counts^2 about its mean, 1 degree), a lone reading
/// 1000 (a group of one: no spread, never pooled) and a test group `t`; the pooled sd.
epuck2::calibrate::PooledSd c8_pooled_with(const std::vector<double>& t) {
  std::vector<double> v;
  std::vector<int> g;
  for (int k = 0; k < 50; ++k) {
    v.insert(v.end(), {-1.0, 1.0});
    g.insert(g.end(), {k, k});
  }
  v.push_back(1000.0);
  g.push_back(50);
  for (double x : t) {
    v.push_back(x);
    g.push_back(51);
  }
  return epuck2::calibrate::pooled_replicate_sd(v, g, std::vector<bool>(v.size(), false), 0.0);
}

// reading_noise.hpp: groups of two or more are pooled; a reading farther than 4 pooled sd from its
// group's median is left out only in groups of fewer than kSmallGroup = 10 readings. A group of 9
// (-1 x4, +1 x4, 10): the first pass pools (100 + 96.89) / 58 (sd 1.842), the 10 sits 9 from the
// median 1, beyond 4 x 1.842 = 7.37: left out, leaving (100 + 8) / (50 + 7) over 108 readings. A
// group of exactly 10 (-1 x4, 0, +1 x4, 10) keeps it: (100 + 98) / (50 + 9), 110 readings. Neither
// 10 is wild (8 robust sd: 1.4826 x MAD 2 and 1 from the medians 1 and 0.5: 23.7 and 11.9 > 9).
TEST(ClassesEightBoundaries, ReadingNoiseSmallGroupIsBelowTenAndPairsArePooled) {
  const auto nine = c8_pooled_with({-1, -1, -1, -1, 1, 1, 1, 1, 10});
  EXPECT_EQ(nine.outliers, 1u);
  EXPECT_EQ(nine.groups, 51u);
  EXPECT_EQ(nine.n, 108u);
  EXPECT_NEAR(nine.sd, std::sqrt(108.0 / 57.0), 1e-12);
  const auto ten = c8_pooled_with({-1, -1, -1, -1, 0, 1, 1, 1, 1, 10});
  EXPECT_EQ(ten.outliers, 0u);
  EXPECT_EQ(ten.wild, 0u);
  EXPECT_EQ(ten.groups, 51u);
  EXPECT_EQ(ten.n, 110u);
  EXPECT_NEAR(ten.sd, std::sqrt(198.0 / 59.0), 1e-12);
}

// fit/report.hpp: the cluster-robust errors need at least kMinClusters = 5 runs. One parameter
// (a mean: every Jacobian entry 1), runs of two rows with residuals d_c, d_c, d = 1, -2, 3, -1, -1:
// s_c = 2 d_c = 2, -4, 6, -2, -2, sum of s_c^2 = 64, (J^T J)^-1 = 1/10, so V = 64/100 x 5/4 = 0.8 and
// the error sqrt(0.8) = 0.894427 (above the covariance's 0.001). With the first four runs only, not
// cluster-robust: the covariance's 0.001 (AR(1) not computed: factor 1) and a reason naming 4 runs.
TEST(ClassesEightBoundaries, ClusterRobustErrorsFromExactlyFiveRuns) {
  auto run_with = [](int runs) {
    const double d[5] = {1, -2, 3, -1, -1};
    epuck2::fit::FitResult fit;
    fit.parameters.emplace_back("mean", 0.0, 0.001);
    std::vector<double> residuals;
    std::vector<int> run;
    for (int c = 0; c < runs; ++c)
      for (int r = 0; r < 2; ++r) {
        residuals.push_back(d[c]);
        run.push_back(c);
      }
    const Eigen::MatrixXd jacobian = Eigen::MatrixXd::Ones(static_cast<Eigen::Index>(residuals.size()), 1);
    epuck2::fit::AutocorrelationCorrection a;
    epuck2::fit::apply_cluster_robust(a, fit, jacobian, residuals, run);
    return a;
  };
  const auto five = run_with(5);
  EXPECT_TRUE(five.cluster_robust) << five.cluster_why_not;
  ASSERT_EQ(five.std_errors.size(), 1u);
  EXPECT_NEAR(five.std_errors[0], std::sqrt(0.8), 1e-12);
  const auto four = run_with(4);
  EXPECT_FALSE(four.cluster_robust);
  ASSERT_EQ(four.std_errors.size(), 1u);
  EXPECT_DOUBLE_EQ(four.std_errors[0], 0.001);
  EXPECT_NE(four.cluster_why_not.find("4 runs"), std::string::npos) << four.cluster_why_not;
}

/// A drive log written by hand: `still` rows standing (ToF 297, 303 alternating about the obstacle
/// at 0.3 m, encoders 0), then 4 s at 5 cm/s on both wheels, the encoders at floor(7763.656 x) of
/// the commanded travel x and the ToF at 1000 (0.3 - x) +- 1 mm.
std::string c8_drive_log(int still) {
  std::ostringstream out;
  out << "# obstacle_distance_m: 0.3\ntime_s,left_speed_cm_s,right_speed_cm_s,left_steps,right_steps,tof_mm\n";
  int row = 0;
  for (int i = 0; i < still; ++i, ++row) out << 0.1 * row << ",0,0,0,0," << (i % 2 ? 303 : 297) << "\n";
  for (int k = 0; k < 40; ++k, ++row) {
    const double x = 0.05 * 0.1 * k;
    const long steps = static_cast<long>(std::floor(7763.656 * x));
    out << 0.1 * row << ",5,5," << steps << "," << steps << "," << std::lround(1000 * (0.3 - x)) + (k % 2 ? 1 : -1) << "\n";
  }
  return out.str();
}

// drive_fit: the ToF's noise comes from the readings standing before a run moves when there are at
// least kMinStillReadings = 30 of them. Exactly 30 (15 at 297, 15 at 303): from the replicates, n
// 30, one group, sd sqrt(15 x 9 x 2 / 29) = sqrt(270/29) = 3.0513; 29: from the ToF fit's residuals.
TEST(ClassesEightBoundaries, DriveToFNoiseFromExactlyThirtyStandingReadings) {
  const c8fs::path dir = c8_scratch("still");
  for (int still : {30, 29}) {
    SCOPED_TRACE(still);
    const c8fs::path log = dir / ("still" + std::to_string(still) + ".csv");
    {
      std::ofstream f(log);
      f << c8_drive_log(still);
    }
    const c8fs::path out = dir / "d.json";
    ASSERT_EQ(c8_cli("drive '" + log.string() + "' -o '" + out.string() + "'", dir), 0) << epuck2::testing::slurp(dir / "stderr.txt");
    const c8json tof = c8json::parse(epuck2::testing::slurp(out))["noise"]["tof"];
    if (still == 30) {
      EXPECT_EQ(tof["from"], "replicates") << tof.dump();
      EXPECT_EQ(tof["n"].get<int>(), 30);
      EXPECT_EQ(tof["groups"].get<int>(), 1);
      EXPECT_NEAR(tof["sd"].get<double>(), std::sqrt(270.0 / 29.0), 1e-9);
    } else {
      EXPECT_EQ(tof["from"], "residuals") << tof.dump();
    }
  }
  c8fs::remove_all(dir);
}

}  // namespace
