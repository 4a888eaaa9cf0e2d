// Defects a sixth new user's probe found (session 24): the diagnosis's per-sensor noise cut at the
// pooled residual sd, a sub-pixel camera log simulated with whole-pixel rounding on top of its
// measured noise, the ToF's dropouts counted as readings on a rail, and the reference sensor of
// sensor_offset. Expected values come from the logs the tests write, computed here.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <fstream>
#include <map>
#include <sstream>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "cli_harness.hpp"
#include "seeded_normal.hpp"

namespace test_probe_six_cpp {

using epuck2::testing::CliRun;
using epuck2::testing::slurp;
using nlohmann::json;

bool has(const std::string& text, const std::string& part) { return text.find(part) != std::string::npos; }

class ProbeSix : public epuck2::testing::CliTest {};

/// The numeric column `name` of a CSV text (comment lines skipped).
std::vector<double> column(const std::string& text, const std::string& name) {
  std::istringstream in(text);
  std::string line;
  std::vector<std::string> head;
  std::vector<double> out;
  int k = -1;
  while (std::getline(in, line)) {
    if (line.empty() || line[0] == '#') continue;
    std::vector<std::string> cells;
    std::stringstream ss(line);
    std::string c;
    while (std::getline(ss, c, ',')) cells.push_back(c);
    if (head.empty()) {
      head = cells;
      for (std::size_t i = 0; i < head.size(); ++i)
        if (head[i] == name) k = static_cast<int>(i);
      continue;
    }
    if (k >= 0 && static_cast<std::size_t>(k) < cells.size()) out.push_back(std::stod(cells[static_cast<std::size_t>(k)]));
  }
  return out;
}

// Ground, one robot: reading = 40 + 983 grey + N(0, sd_s), rounded, sd 3, 6 and 12 counts for
// sensors 0, 1, 2, twenty readings at each of 19 greys. The diagnosis's noise per sensor is each
// sensor's replicate sd less the rounding's 1/12 count^2; sensor 2's was cut at the pooled final
// residual sd (about 7.8, the root mean square of the three) though nothing is misfit.
TEST_F(ProbeSix, TheDiagnosisKeepsANoisySensorsOwnNoise) {
  epuck2::testing::Normal normal(20261129);
  const double sd[3] = {3, 6, 12};
  std::string text = "# robot: g1\ngrey,sensor,value\n";
  std::map<std::pair<int, int>, std::vector<double>> groups;
  char line[64];
  for (int g = 1; g < 20; ++g)
    for (int s = 0; s < 3; ++s)
      for (int r = 0; r < 20; ++r) {
        const double v = std::round(40 + 983 * g / 20.0 + sd[s] * normal());
        groups[{s, g}].push_back(v);
        std::snprintf(line, sizeof line, "%.2f,%d,%.0f\n", g / 20.0, s, v);
        text += line;
      }
  const std::string log = write("psd.csv", text);
  const std::string out = (dir_ / "psd.json").string();
  const CliRun r = run("diagnose \"" + log + "\" -o \"" + out + "\"");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const json j = json::parse(slurp(out));
  const json& per = j.at("noise").at("ground").at("per_sensor_sd");
  for (int s = 0; s < 3; ++s) {
    double ss = 0;
    std::size_t n = 0, g = 0;
    for (const auto& [key, v] : groups) {
      if (key.first != s) continue;
      double mean = 0;
      for (double x : v) mean += x / static_cast<double>(v.size());
      for (double x : v) ss += (x - mean) * (x - mean);
      n += v.size();
      ++g;
    }
    const double hand = std::sqrt(ss / static_cast<double>(n - g) - 1.0 / 12.0);
    EXPECT_NEAR(per.at(s).get<double>(), hand, 0.03 * hand) << "sensor " << s << ": " << per.dump();
  }
  // Sensor 2's own noise, about 12 (the truth), not the pooled residuals' 7.8.
  EXPECT_GT(per.at(2).get<double>(), 10.5) << per.dump();
}

// A camera log whose px and py hold decimals (a blob's centroid) is simulated in sub-pixels: with
// --noise the positions scatter about the noiseless ones by the file's noise sd, 0.3 px here, not
// by sqrt(0.3^2 + 1/12) = 0.416 px (the whole-pixel rounding added on top).
TEST_F(ProbeSix, ASubPixelCameraLogIsSimulatedWithoutRoundingOnTopOfItsNoise) {
  json model = epuck2::testing::shipped_fitted("camera");
  model["noise"]["camera"]["sd"] = 0.3;
  model.erase("robots");  // the pooled set, whichever robot the log names
  model.erase("robot_spread");
  const std::string file = write("cam.json", model.dump());
  // The shipped log's rows, each position given a decimal (+0.25 px).
  const std::string shipped = slurp(epuck2::testing::shipped_logs("camera").front().string());
  std::istringstream in(shipped);
  std::string line, text;
  bool header = false;
  while (std::getline(in, line)) {
    if (line.empty() || line[0] == '#' || !header) {
      header = header || (!line.empty() && line[0] != '#');
      text += line + "\n";
      continue;
    }
    const auto c3 = line.find(',', line.find(',', line.find(',') + 1) + 1), c4 = line.find(',', c3 + 1);
    text += line.substr(0, c4) + ".25," + line.substr(c4 + 1) + ".25\n";
  }
  const std::string log = write("sub.csv", text);
  const CliRun quiet = run("simulate camera --like \"" + log + "\" --coefficients \"" + file + "\" -o \"" + (dir_ / "q.csv").string() + "\"");
  ASSERT_EQ(quiet.exit_code, 0) << quiet.err;
  const CliRun noisy = run("simulate camera --like \"" + log + "\" --coefficients \"" + file + "\" --noise --seed 7 -o \"" +
                           (dir_ / "n.csv").string() + "\"");
  ASSERT_EQ(noisy.exit_code, 0) << noisy.err;
  const std::string q = slurp((dir_ / "q.csv").string()), n = slurp((dir_ / "n.csv").string());
  double ss = 0;
  std::size_t count = 0, fractional = 0;
  for (const char* axis : {"px", "py"}) {
    const std::vector<double> a = column(q, axis), b = column(n, axis);
    ASSERT_EQ(a.size(), b.size());
    for (std::size_t i = 0; i < a.size(); ++i) {
      ss += (b[i] - a[i]) * (b[i] - a[i]);
      fractional += b[i] != std::floor(b[i]);
      ++count;
    }
  }
  ASSERT_GT(count, 500u);
  const double scatter = std::sqrt(ss / static_cast<double>(count));
  // 0.3 px to within 3 standard errors of an sd from ~1600 draws (1.8 % each), far from 0.416.
  EXPECT_NEAR(scatter, 0.3, 0.3 * 0.06) << scatter;
  EXPECT_GT(fractional, count / 2) << "the simulated positions are whole pixels";
}

// A camera log of whole pixels is still simulated as the camera's register: whole pixels.
TEST_F(ProbeSix, AWholePixelCameraLogIsStillSimulatedInWholePixels) {
  const std::string log = epuck2::testing::shipped_logs("camera").front().string();
  const CliRun noisy = run("simulate camera --like \"" + log + "\" --noise --seed 7 -o \"" + (dir_ / "n.csv").string() + "\"");
  ASSERT_EQ(noisy.exit_code, 0) << noisy.err;
  const std::string n = slurp((dir_ / "n.csv").string());
  for (const char* axis : {"px", "py"})
    for (double v : column(n, axis)) ASSERT_EQ(v, std::floor(v)) << axis;
}

/// A straight drive run at 5 cm/s from 0.3 m: rows every 0.1 s for 4 s, encoders at the plug-in's
/// 7763.656 steps/m (rounded), ToF = 1000 (0.3 - travel) mm rounded; the rows in `codes` read 8190
/// (no target) though the obstacle is 100-300 mm away.
std::string drive_log(const std::vector<int>& codes) {
  std::string text = "# robot: d1\n# obstacle_distance_m: 0.3\ntime_s,left_speed_cm_s,right_speed_cm_s,left_steps,right_steps,tof_mm\n";
  char line[128];
  for (int i = 0; i <= 40; ++i) {
    const double t = 0.1 * i, travel = 0.05 * t;
    const long steps = std::lround(travel * 7763.656);
    long tof = std::lround(1000 * (0.3 - travel));
    for (int c : codes) tof = c == i ? 8190 : tof;
    std::snprintf(line, sizeof line, "%.1f,5,5,%ld,%ld,%ld\n", t, steps, steps, tof);
    text += line;
  }
  return text;
}

// The diagnosis leaves out a "no target" code where the encoders put the obstacle in view: it is a
// dropout, listed under outliers, and not counted among the readings on a rail (none here: every
// other reading lies between 100 and 300 mm, inside 20..2000).
TEST_F(ProbeSix, TheDiagnosisListsToFDropoutsAndDoesNotCountThemOnARail) {
  const std::string log = write("d.csv", drive_log({10, 25}));
  const std::string out = (dir_ / "d.json").string();
  const CliRun r = run("diagnose \"" + log + "\" -o \"" + out + "\"");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const json j = json::parse(slurp(out));
  EXPECT_EQ(j.at("censored").get<int>(), 0) << j.dump().substr(0, 400);
  // Rows 10 and 25 are the file's lines 14 and 29 (three lines before the first row).
  std::vector<std::string> rows = j.at("outliers").at("rows").get<std::vector<std::string>>();
  ASSERT_EQ(rows.size(), 2u) << j.at("outliers").dump();
  EXPECT_TRUE(has(rows[0], log + ":14: a ToF \"no target\" code (8190)")) << rows[0];
  EXPECT_TRUE(has(rows[1], log + ":29: ")) << rows[1];
  EXPECT_FALSE(has(r.out, "Readings on a sensor's rails")) << r.out;
}

// The drive calibration censors the codes at the ceiling and its robust fit leaves out those the
// curve puts in view: the report says how many of the codes it left out as dropouts.
TEST_F(ProbeSix, TheDriveReportSaysWhichCodesItLeftOutAsDropouts) {
  const std::string log = write("d.csv", drive_log({10, 25, 33}));
  const std::string out = (dir_ / "d.json").string();
  const CliRun r = run("drive \"" + log + "\" -o \"" + out + "\"");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_TRUE(has(r.out, "3 codes >= 8190, of which 3 left out as dropouts: the fitted curve puts the obstacle in view there"))
      << r.out;
  const json j = json::parse(slurp(out));
  EXPECT_EQ(j.at("tof_code_dropouts").get<int>(), 3);
  EXPECT_EQ(j.at("tof_out_of_range_codes").get<int>(), 3);
}

// A run without slip (the ToF follows the encoders exactly): the fitted lag lands between 0 (no
// slip) and the 1 ms a lag may be in a file; the calibration was refused as unwritable. It is
// written as 0, no slip, and said.
TEST_F(ProbeSix, ASlipLagBelowAMillisecondIsWrittenAsNoSlip) {
  const std::string log = write("d.csv", drive_log({}));
  const std::string out = (dir_ / "d.json").string();
  const CliRun r = run("drive \"" + log + "\" -o \"" + out + "\"");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const json j = json::parse(slurp(out));
  const double tau = j.at("parameters").at("slip_time_constant_s").get<double>();
  if (tau != 0.0) {
    EXPECT_GE(tau, 1e-3) << "a lag a file may not hold";
  } else {
    bool said = false;
    for (const json& w : j.at("warnings")) said = said || has(w.get<std::string>(), "no slip these logs resolve; written as 0 (no slip)");
    EXPECT_TRUE(said) << j.at("warnings").dump();
  }
  // simulate runs the file (a reader takes it).
  const CliRun s = run("simulate drive --like \"" + log + "\" --coefficients \"" + out + "\"");
  EXPECT_EQ(s.exit_code, 0) << s.err;
}

// The reference of sensor_offset is the lowest-numbered sensor logged, whatever order the rows
// come in (docs/diagnose.md): sensor 2's rows first, sensors 1 and 2 reading 15 and 30 counts
// over sensor 0 at black; offsets[1] and offsets[2] are those differences, sensor 0's is null.
TEST_F(ProbeSix, SensorOffsetIsRelativeToTheLowestNumberedSensor) {
  epuck2::testing::Normal normal(31);
  std::string text = "# robot: g2\ngrey,sensor,value\n";
  char line[64];
  const double offset[3] = {30, 45, 60};
  for (int s : {2, 0, 1})
    for (int g = 0; g <= 10; ++g)
      for (int r = 0; r < 10; ++r) {
        const double v = std::round(offset[s] + (1023 - offset[s]) * g / 10.0 + 3 * normal());
        std::snprintf(line, sizeof line, "%.1f,%d,%.0f\n", g / 10.0, s, std::min(1023.0, v));
        text += line;
      }
  const std::string log = write("so.csv", text);
  const std::string out = (dir_ / "so.json").string();
  const CliRun r = run("diagnose \"" + log + "\" --effects sensor_offset,black_offset -o \"" + out + "\"");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const json j = json::parse(slurp(out));
  const json* found = nullptr;
  for (const json& f : j.at("findings"))
    if (f.at("cause") == "sensor_offset") found = &f;
  ASSERT_NE(found, nullptr) << j.at("findings").dump();
  const json& o = found->at("parameters").at("offsets");
  EXPECT_TRUE(o.at(0).is_null()) << o.dump();
  EXPECT_NEAR(o.at(1).get<double>(), 15.0, 2.0) << o.dump();
  EXPECT_NEAR(o.at(2).get<double>(), 30.0, 2.0) << o.dump();
}



namespace round_twenty_two {

// Round 22's survivor (bench/fresh-slips.md): the drive diagnosis leaves out a ToF spike only when
// it stands more than 8 robust sd of the run's deviations from the line through its neighbours
// AND more than the 50 mm floor (docs/fitting.md, "Wild readings"). A run whose ToF steps 5 mm a
// row with a +-1 mm wobble (typical deviation about 1.5 mm: 8 sd about 12 mm) and two bumps: +20 mm
// at row 15 (beyond 8 sd, under the floor: kept) and +70 mm at row 30 (beyond both: left out).
TEST_F(ProbeSix, ADriveSpikeMustClearTheFloorAsWellAsEightSd) {
  std::string text = "# robot: d1\n# obstacle_distance_m: 0.3\ntime_s,left_speed_cm_s,right_speed_cm_s,left_steps,right_steps,tof_mm\n";
  char line[128];
  for (int i = 0; i <= 40; ++i) {
    const double t = 0.1 * i, travel = 0.05 * t;
    const long steps = std::lround(travel * 7763.656);
    long tof = std::lround(1000 * (0.3 - travel)) + (i % 3) - 1;
    if (i == 15) tof += 20;
    if (i == 30) tof += 70;
    std::snprintf(line, sizeof line, "%.1f,5,5,%ld,%ld,%ld\n", t, steps, steps, tof);
    text += line;
  }
  const std::string log = write("spikes.csv", text);
  const std::string out = (dir_ / "s.json").string();
  const CliRun r = run("diagnose \"" + log + "\" -o \"" + out + "\"");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const json j = json::parse(slurp(out));
  const std::vector<std::string> rows = j.at("outliers").at("rows").get<std::vector<std::string>>();
  ASSERT_EQ(rows.size(), 1u) << j.at("outliers").dump();
  EXPECT_TRUE(has(rows[0], log + ":34: tof_mm")) << rows[0];  // row 30: three lines before the first row
}

}  // namespace round_twenty_two
}  // namespace test_probe_six_cpp
