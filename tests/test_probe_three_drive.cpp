// Defects a new user's probe found (session 23) in the drive calibration and what reads its file:
// the plug-in's reference MSE over other rows than the fit's, the firmware's cap reckoned with the
// plug-in's steps per metre instead of the fitted one, `simulate drive --like` and `codegen` that
// ignored the cap, encoder noise on a wheel standing still, a legend that named 1000 steps/m, and
// docs/help that disagreed with the code. Expected values come from the logs the tests write (the
// firmware's 1100 steps/s, the encoders' floor, the plug-in's 1000 (D - steps / 7763.656) mm),
// computed here row by row.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <set>
#include <sstream>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "cli_harness.hpp"
#include "epuck2/logs/log.hpp"

namespace test_probe_three_drive_cpp {

using epuck2::testing::CliRun;
using epuck2::testing::slurp;
using nlohmann::json;
namespace fs = std::filesystem;

bool has(const std::string& text, const std::string& part) { return text.find(part) != std::string::npos; }

constexpr double kCapStepsPerSecond = 1100.0;  // the e-puck2 firmware's MOTOR_SPEED_LIMIT
constexpr double kPluginStepsPerMetre = 7763.656;

/// A straight run written by hand: a row about every 0.1 s (0.1 s + a fixed -0.02..0.02 s pattern,
/// as a host's loop over Wi-Fi logs them: the counts' fractions vary), both wheels commanded `cm_s` of each
/// segment; the encoders count `steps_per_m` steps per metre of command, at most 1100 steps/s (the
/// firmware), floor of the count; the ToF reads round(1000 (D - count / steps_per_m)) plus a
/// -2..2 mm pattern; `tof_at` replaces the reading of the rows it names, `tof_plus` adds to it.
struct HandRun {
  double steps_per_m = kPluginStepsPerMetre;
  double obstacle_m = 0.5;
  std::vector<std::pair<double, int>> segments;  // {cm/s, rows}
  std::vector<std::pair<int, double>> tof_at;     // {row, reading}
  std::vector<std::pair<int, double>> tof_plus;   // {row, mm added}
  // Filled by text():
  std::vector<double> time_s, command_cm_s, steps, tof;
  std::vector<int> line;

  std::string text() {
    time_s.clear(), command_cm_s.clear(), steps.clear(), tof.clear(), line.clear();
    char head[160];
    std::snprintf(head, sizeof head, "# robot: hand\n# obstacle_distance_m: %.6g\n", obstacle_m);
    std::string out = std::string(head) + "time_s,left_speed_cm_s,right_speed_cm_s,left_steps,right_steps,tof_mm\n";
    double count = 0;
    int row = 0;
    double t = 0;
    for (const auto& [cm_s, rows] : segments)
      for (int k = 0; k < rows; ++k, ++row) {
        const double s = std::floor(count + 1e-9);
        double mm = std::round(1000.0 * (obstacle_m - count / steps_per_m)) + ((row * 7) % 5 - 2);
        for (const auto& [at, reading] : tof_at)
          if (at == row) mm = reading;
        for (const auto& [at, plus] : tof_plus)
          if (at == row) mm += plus;
        time_s.push_back(t), command_cm_s.push_back(cm_s), steps.push_back(s), tof.push_back(mm), line.push_back(row + 4);
        char r[160];
        std::snprintf(r, sizeof r, "%.3f,%g,%g,%.0f,%.0f,%.0f\n", t, cm_s, cm_s, s, s, mm);
        out += r;
        // This row's command holds until the next row: the wheels' steps per second, capped.
        const double dt = 0.1 + 0.004 * ((row * 37) % 11 - 5);
        const double rate = std::min(std::abs(cm_s) / 100.0 * steps_per_m, kCapStepsPerSecond);
        count += (cm_s < 0 ? -rate : rate) * dt;
        t += dt;
      }
    return out;
  }
};

class ProbeThreeDrive : public epuck2::testing::CliTest {
 protected:
  json fit_json(const std::string& log, const std::string& extra = "") {
    const CliRun r = run("drive --json " + extra + " \"" + log + "\"");
    EXPECT_EQ(r.exit_code, 0) << r.err;
    return r.exit_code == 0 ? json::parse(r.out) : json::object();
  }
};

// 1. The report's "plug-in" MSE is over the rows the fit's MSE is over: inside the rails (no
// out-of-range code >= 8190) and not left out as wild. Before, the wild row the fit leaves out
// counted in the plug-in's MSE and made the plug-in look worse than it is on the same rows.
TEST_F(ProbeThreeDrive, ThePluginMseIsOverTheRowsTheFitKept) {
  HandRun h;
  h.obstacle_m = 0.5;
  h.segments = {{0, 10}, {10, 40}, {0, 10}};
  h.tof_at = {{20, 8190}, {21, 8190}, {22, 8191}};
  h.tof_plus = {{30, 600}};  // a wild reading: 600 mm off
  const std::string wild = h.text();
  const std::string log = write("d.csv", wild);
  const json j = fit_json(log);
  ASSERT_TRUE(j.contains("reference_mse"));
  std::set<int> left_out;
  for (const auto& w : j.at("outliers").at("rows")) {
    const std::string s = w.get<std::string>();
    if (s.rfind(log + ":", 0) == 0) left_out.insert(std::stoi(s.substr(log.size() + 1)));
  }
  ASSERT_TRUE(left_out.count(h.line[30])) << "the wild row is left out: " << j.at("outliers").dump();
  double rss = 0;
  std::size_t n = 0;
  for (std::size_t k = 0; k < h.tof.size(); ++k) {
    if (h.tof[k] <= 20 || h.tof[k] >= 2000 || left_out.count(h.line[k])) continue;
    const double plugin = 1000.0 * (h.obstacle_m - h.steps[k] / kPluginStepsPerMetre);
    rss += (h.tof[k] - plugin) * (h.tof[k] - plugin);
    ++n;
  }
  ASSERT_EQ(n, j.at("fits").at("tof").at("n").get<std::size_t>());
  EXPECT_EQ(j.at("reference_mse").at("plugin_tof_rows").get<std::size_t>(), n);
  EXPECT_NEAR(j.at("reference_mse").at("plugin_tof").get<double>(), rss / static_cast<double>(n), 1e-9 * rss / static_cast<double>(n));
  EXPECT_EQ(j.at("tof_out_of_range_codes").get<int>(), 3);
  const CliRun t = run("drive \"" + log + "\"");
  ASSERT_EQ(t.exit_code, 0) << t.err;
  char said[96];
  std::snprintf(said, sizeof said, ": %.3f mm^2 on the same %zu rows", rss / static_cast<double>(n), n);
  EXPECT_TRUE(has(t.out, said)) << said << "\n" << t.out;
}

// A robot whose encoders count 9000 steps per metre of command (16 % above the plug-in's), 5 and
// 15 cm/s: 15 cm/s asks 1350 steps/s, the firmware runs 1100. The cap in m/s of command is 1100 /
// 9000 = 0.1222 m/s, not the plug-in's 1100 / 7763.656 = 0.1417 m/s.
HandRun fast_counting_robot() {
  HandRun h;
  h.steps_per_m = 9000;
  h.obstacle_m = 0.8;
  h.segments = {{0, 10}, {5, 30}, {15, 30}, {0, 10}};
  return h;
}

// 2. The firmware's cap is 1100 steps/s over the FITTED steps per metre, in the file and in the
// report. Before, it was reckoned with the plug-in's 7763.656: the 15 cm/s rows were predicted at
// 9000 x 0.1417 = 1275 steps/s instead of 1100, and the file held no cap in m/s.
TEST_F(ProbeThreeDrive, TheFirmwareCapIsReckonedWithTheFittedStepsPerMetre) {
  HandRun h = fast_counting_robot();
  const std::string log = write("fast.csv", h.text());
  const json j = fit_json(log);
  ASSERT_TRUE(j.contains("parameters"));
  const double k = j.at("parameters").at("steps_per_m").get<double>();
  EXPECT_NEAR(k, 9000.0, 2.0);  // the encoders' own count, the capped rows at 1100 steps/s
  ASSERT_TRUE(j.contains("firmware_cap") && j.at("firmware_cap").contains("limit_m_s")) << j.dump().substr(0, 400);
  EXPECT_NEAR(j.at("firmware_cap").at("limit_m_s").get<double>(), kCapStepsPerSecond / k, 1e-12);
  EXPECT_NEAR(j.at("firmware_cap").at("limit_m_s").get<double>(), 1100.0 / 9000.0, 3e-5);
  EXPECT_TRUE(j.at("firmware_cap").at("kept").get<bool>());
  EXPECT_EQ(j.at("capped_rows").get<int>(), 30);
  // The capped rows fit as well as the others: no outlier among them.
  EXPECT_EQ(j.at("fits").at("steps").at("outliers").get<int>(), 0);
  const CliRun t = run("drive \"" + log + "\"");
  ASSERT_EQ(t.exit_code, 0) << t.err;
  char said[96];
  std::snprintf(said, sizeof said, "1100 / steps_per_m = %.3f cm/s taken as that limit: 30 rows", 100 * kCapStepsPerSecond / k);
  EXPECT_TRUE(has(t.out, said)) << said << "\n" << t.out;
}

// The simulated run of `log` (simulate drive --like, `extra` options), read back.
epuck2::logs::Log simulated(epuck2::testing::CliTest& /*unused*/, const fs::path& dir, const std::string& log,
                            const std::string& extra) {
  const std::string out = (dir / "sim.csv").string();
  const std::string cmd = std::string("\"") + EPUCK2_FIT_EXE + "\" simulate drive --like \"" + log + "\" " + extra + " -o \"" + out +
                          "\" 2>\"" + (dir / "sim_err.txt").string() + "\"";
  EXPECT_EQ(std::system(cmd.c_str()), 0) << cmd << "\n" << slurp(dir / "sim_err.txt");
  return epuck2::logs::read_log(out);
}

// 3. simulate --like and codegen apply the file's cap: 1100 steps/s over the file's steps_per_m
// (9000: 12.222 cm/s). A 15 cm/s command moves each wheel 1100 steps a second, the body 1100 /
// 9000 m a second; the ToF (scale 1, offset 0, no slip) reads 1000 (D - x). Before, the wheels
// ran the 15 cm/s (1350 steps/s) and codegen wrote speed_limit 1e+06. A file whose calibration
// found the wheels beat the cap (firmware_cap.kept false) runs them as commanded, as does a file
// without firmware_cap (a diagnosis: its cap is its speed_limit effect).
TEST_F(ProbeThreeDrive, SimulateAndCodegenApplyTheFilesCap) {
  HandRun h;
  h.obstacle_m = 0.8;
  h.segments = {{0, 5}, {15, 20}, {0, 5}};
  const std::string log = write("run.csv", h.text());
  const std::string base = R"("kind":"drive","parameters":{"steps_per_m":9000,"tof_scale":1,"tof_offset_mm":0,"slip_time_constant_s":0})";
  const std::string capped = write("cap.json", "{" + base + R"(,"firmware_cap":{"kept":true}})");
  const std::string uncapped = write("nocap.json", "{" + base + R"(,"firmware_cap":{"kept":false}})");
  const epuck2::logs::Log sim = simulated(*this, dir_, log, "--coefficients \"" + capped + "\"");
  ASSERT_EQ(sim.rows(), h.time_s.size());
  for (std::size_t i = 0; i < sim.rows(); ++i) {
    // Seconds at the cap before this row: rows 5..24 command 15 cm/s, each until the next row.
    const double at_cap_s = h.time_s[std::min<std::size_t>(std::max<std::size_t>(i, 5), 25)] - h.time_s[5];
    const double steps = kCapStepsPerSecond * at_cap_s;
    EXPECT_NEAR(sim.col("left_steps")[i], steps, 1.0) << "row " << i;
    EXPECT_NEAR(sim.col("right_steps")[i], steps, 1.0) << "row " << i;
    EXPECT_NEAR(sim.col("tof_mm")[i], 1000.0 * (0.8 - steps / 9000.0), 1.0) << "row " << i;
  }
  const epuck2::logs::Log free = simulated(*this, dir_, log, "--coefficients \"" + uncapped + "\"");
  EXPECT_NEAR(free.col("left_steps")[25], 9000 * 0.15 * (h.time_s[25] - h.time_s[5]), 1.0);  // at 15 cm/s
  const std::string bare = write("bare.json", "{" + base + "}");
  const epuck2::logs::Log diagnosis_like = simulated(*this, dir_, log, "--coefficients \"" + bare + "\"");
  EXPECT_NEAR(diagnosis_like.col("left_steps")[25], 9000 * 0.15 * (h.time_s[25] - h.time_s[5]), 1.0);
  // codegen: the header's speed_limit is the cap.
  const CliRun g = run("codegen \"" + capped + "\" -o -");
  ASSERT_EQ(g.exit_code, 0) << g.err;
  const std::string key = "m.effects.speed_limit.max_cm_s = ";
  const std::size_t at = g.out.find(key);
  ASSERT_NE(at, std::string::npos) << g.out;
  EXPECT_NEAR(std::stod(g.out.substr(at + key.size())), 100.0 * 1100.0 / 9000.0, 1e-9) << g.out.substr(at, 80);
  const CliRun gf = run("codegen \"" + uncapped + "\" -o -");
  ASSERT_EQ(gf.exit_code, 0) << gf.err;
  const std::size_t at_free = gf.out.find(key);
  ASSERT_NE(at_free, std::string::npos);
  EXPECT_GE(std::stod(gf.out.substr(at_free + key.size())), 1e5);  // no cap: the neutral limit
  // The shipped header holds the shipped file's cap.
  const json shipped = epuck2::testing::shipped_fitted("drive");
  const std::string header = slurp(fs::path(EPUCK2_SOURCE_DIR) / "data" / "fitted" / "include" / "epuck2" / "fitted" / "coefficients.hpp");
  const std::size_t drive = header.find("drive_model()");
  ASSERT_NE(drive, std::string::npos);
  const std::size_t cap_at = header.find(key, drive);
  ASSERT_NE(cap_at, std::string::npos);
  EXPECT_NEAR(std::stod(header.substr(cap_at + key.size())), 100.0 * shipped.at("firmware_cap").at("limit_m_s").get<double>(), 1e-9);
  EXPECT_NEAR(std::stod(header.substr(cap_at + key.size())), 110000.0 / shipped.at("parameters").at("steps_per_m").get<double>(), 1e-9);
}

// 4. simulate --noise: a wheel that does not move reads a constant count. Rows 0-9 stand still
// (command 0, nothing moved: the registers read 0); rows 10-19 drive at 5 cm/s; from row 21 the
// wheels have not moved since row 20 (its command, 0, holds), so rows 21-29 read row 20's count.
// Before, every row drew the encoder noise afresh (sd 3 steps: the still rows flickered).
TEST_F(ProbeThreeDrive, AStillWheelReadsAConstantCountWithNoise) {
  HandRun h;
  h.segments = {{0, 10}, {5, 10}, {0, 10}};
  const std::string log = write("still.csv", h.text());
  const std::string file = write("noisy.json", R"({"kind":"drive","parameters":{"steps_per_m":7763.656,"tof_scale":1,"tof_offset_mm":0,)"
                                              R"("slip_time_constant_s":0},"noise":{"tof":{"sd":2,"unit":"mm"},"encoder":{"sd":3,"unit":"steps"}}})");
  const epuck2::logs::Log sim = simulated(*this, dir_, log, "--coefficients \"" + file + "\" --noise --seed 7");
  ASSERT_EQ(sim.rows(), 30u);
  for (const char* wheel : {"left_steps", "right_steps"}) {
    const auto& c = sim.col(wheel);
    for (std::size_t i = 0; i < 10; ++i) EXPECT_EQ(c[i], 0.0) << wheel << " row " << i;
    for (std::size_t i = 21; i < 30; ++i) EXPECT_EQ(c[i], c[20]) << wheel << " row " << i;
    // The moving rows do get the noise: some differ from the noiseless floor(steps_per_m x).
    int differ = 0;
    for (std::size_t i = 11; i <= 20; ++i) differ += c[i] != std::floor(kPluginStepsPerMetre * 0.05 * (h.time_s[i] - h.time_s[10]) + 1e-9);
    EXPECT_GT(differ, 0) << wheel;
  }
}

// 5. drive --plot: the legend names the fitted steps per metre (and the plug-in's 7763.656), not
// "1000 steps/m" whatever the fit.
TEST_F(ProbeThreeDrive, ThePlotLegendNamesTheFittedStepsPerMetre) {
  HandRun h = fast_counting_robot();
  const std::string log = write("fast.csv", h.text());
  const json j = fit_json(log);
  ASSERT_TRUE(j.contains("parameters"));
  const std::string cmd = "EPUCK2_PLOT_SCRIPT_DIR='" + dir_.string() + "' '" EPUCK2_FIT_EXE "' drive '" + log + "' --plot '" +
                          (dir_ / "p.svg").string() + "' >/dev/null 2>'" + (dir_ / "err.txt").string() + "'";
  ASSERT_EQ(std::system(cmd.c_str()), 0) << slurp(dir_ / "err.txt");
  const std::string script = slurp(dir_ / "p.svg.gp");
  ASSERT_FALSE(script.empty());
  char fitted[64];
  std::snprintf(fitted, sizeof fitted, "fit (%.3f steps/m)", j.at("parameters").at("steps_per_m").get<double>());
  EXPECT_TRUE(has(script, fitted)) << fitted;
  EXPECT_TRUE(has(script, "plug-in (7763.656 steps/m, no slip)"));
  EXPECT_FALSE(has(script, "1000 steps/m"));
}

// 6. Docs and help. `drive --help` names the ToF's no-target codes (>= 8190) as the fit takes
// them (censored beyond 2000 mm); the top-level `censored` is every reading on a rail, as the file
// writes it (the sum of the fits' censored counts; those the final fits kept: censored_kept), and
// docs/coefficient-files.md says so; data/raw/drive/README.md quotes the shipped file's numbers and
// no longer says the reader refuses 8190.
TEST_F(ProbeThreeDrive, DocsAndHelpSayWhatTheCodeDoes) {
  const CliRun help = run("drive --help");
  ASSERT_EQ(help.exit_code, 0) << help.err;
  EXPECT_TRUE(has(help.out, "8190")) << help.out;
  EXPECT_TRUE(has(help.out, "no target")) << help.out;

  HandRun h;
  h.obstacle_m = 0.5;
  h.segments = {{0, 10}, {10, 40}, {0, 10}};
  h.tof_at = {{3, 2000}, {20, 8190}, {45, 20}, {46, 20}};
  const std::string log = write("rails.csv", h.text());
  std::size_t on_rails = 0;
  for (double mm : h.tof) on_rails += mm <= 20 || mm >= 2000;
  ASSERT_EQ(on_rails, 4u);
  const json j = fit_json(log, "--accept-misfit");
  ASSERT_TRUE(j.contains("censored"));
  std::size_t in_fits = 0;
  for (const auto& [name, f] : j.at("fits").items())
    in_fits += f.at("censored").at("at_or_below").get<std::size_t>() + f.at("censored").at("at_or_above").get<std::size_t>();
  EXPECT_EQ(j.at("censored").get<std::size_t>(), on_rails);
  EXPECT_EQ(j.at("censored").get<std::size_t>(), in_fits);
  const std::string docs = slurp(fs::path(EPUCK2_SOURCE_DIR) / "docs" / "coefficient-files.md");
  EXPECT_TRUE(has(docs, "| `censored` | integer | every reading on a sensor's rail")) << "docs/coefficient-files.md";

  const std::string readme = slurp(fs::path(EPUCK2_SOURCE_DIR) / "data" / "raw" / "drive" / "README.md");
  EXPECT_FALSE(has(readme, "rejects ToF 8190"));
  EXPECT_FALSE(has(readme, "cannot read the logs"));
  const json shipped = epuck2::testing::shipped_fitted("drive");
  for (const char* p : {"steps_per_m", "tof_scale", "tof_offset_mm", "slip_time_constant_s"})
    EXPECT_TRUE(has(readme, shipped.at("rounded").at(p).get<std::string>())) << p << ": " << shipped.at("rounded").at(p);
  std::size_t rows = 0, files = 0;
  for (const auto& p : epuck2::testing::shipped_logs("drive")) {
    ++files;
    rows += epuck2::logs::read_log(p.string()).rows();
  }
  EXPECT_TRUE(has(readme, "(" + std::to_string(files) + " files, " + std::to_string(rows) + " rows)"));
  char cap[64];
  std::snprintf(cap, sizeof cap, "%.3f cm/s", 100 * shipped.at("firmware_cap").at("limit_m_s").get<double>());
  EXPECT_TRUE(has(readme, cap)) << cap;
}

}  // namespace test_probe_three_drive_cpp
