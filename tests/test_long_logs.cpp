// Long logs read and diagnosed without changing a number (bench/README.md, "Scale (1M rows)"):
// each shortcut checked against the computation it stands for, written here apart from it.
//  - the battery diagnosis keeps its simulations by capacity scale, simulates only the rows a
//    screening fit asks for and steps k +- h side by side: its residuals are the discharge
//    stepped row by row in this file, bit for bit, at the recalibrated and at the fitted scale;
//  - the drive diagnosis's replicate ToF noise comes without fit_drive's fits: it is
//    fit_drive(logs).tof_noise (from replicates), also where the firmware's cap decides which
//    rows stand still;
//  - the log reader keeps a cell as a place in the file's text: a mid-size log reads back the
//    values written, and a bad cell far down is still located;
//  - the drive diagnosis builds its residual-structure covariates after the last fit, from the
//    registers its residuals kept: they are the ones this file computes from the logs' columns.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <random>
#include <sstream>
#include <string>
#include <vector>

#include "epuck2/calibrate/sensors.hpp"
#include "epuck2/diagnose/diagnose.hpp"
#include "epuck2/logs/log.hpp"
#include "epuck2/models/battery.hpp"
#include "epuck2/models/plugin_battery_tables.hpp"
// The drive's problem (make_problem, its covariates) is the library's own, not in its public headers.
#include "../lib/diagnose/src/problem.hpp"

// This file's `using namespace` stays in its own named namespace, so it opens nothing to the
// files compiled after it in the same unity unit (tests/CMakeLists.txt).
namespace test_long_logs_cpp {
namespace {

using namespace epuck2;
namespace mb = models::battery;

std::string g17(double v) {
  char b[40];
  std::snprintf(b, sizeof b, "%.17g", v);
  return b;
}

// The corrected Cubic with the plug-in's tables, capacity scale k, stepped row by row from a full
// charge (docs/diagnose.md, "battery": a speed holds from its row to the next).
std::vector<double> discharge(const std::vector<double>& t, double speed_cm_s, double k) {
  const mb::Tables tables = mb::plugin_tables();
  std::vector<double> c(t.size());
  double charge = 1.0;
  for (std::size_t i = 0; i < t.size(); ++i) {
    c[i] = charge;
    if (i + 1 < t.size()) {
      const double dt = t[i + 1] - t[i];
      charge = mb::corrected::step(mb::Model::cubic, tables, charge, speed_cm_s / 100.0 * dt / k, dt / k);
    }
  }
  return c;
}

TEST(LongLogs, BatteryResidualsAreTheDischargeSteppedRowByRow) {
  // 30 000 rows: more than the 20 000 residuals above which candidates are screened on the
  // leading ones. A battery 8 % larger than the tables' (capacity_scale 1.08), reading noise 0.01.
  constexpr std::size_t kRows = 30000;
  constexpr double kSpeed = 5, kTrueScale = 1.08;
  const double life = mb::plugin_tables().lifetime_s[5] * kTrueScale;
  std::vector<double> t(kRows);
  for (std::size_t i = 0; i < kRows; ++i) t[i] = std::round(10.0 * life * static_cast<double>(i) / kRows) / 10.0;
  const std::vector<double> truth = discharge(t, kSpeed, kTrueScale);
  std::mt19937_64 rng(20261125);
  std::normal_distribution<double> noise(0.0, 0.01);
  std::ostringstream csv;
  csv << "time_s,speed_cm_s,charge\n";
  std::vector<double> y(kRows);
  for (std::size_t i = 0; i < kRows; ++i) {
    y[i] = std::stod(g17(std::min(1.05, truth[i] + noise(rng))));
    csv << g17(t[i]) << "," << kSpeed << "," << g17(y[i]) << "\n";
  }
  const diagnose::Report r = diagnose::diagnose({logs::parse_log(csv.str(), "battery.csv")});
  ASSERT_EQ(r.verdict_name(), "capacity_scale");
  const double k = r.findings.front().parameters.front().value;
  EXPECT_NEAR(k, kTrueScale, 0.01);
  // Every row but the last (the moment the robot stopped) is a residual: reading - model.
  const std::vector<double> base = discharge(t, kSpeed, 1.0), fitted = discharge(t, kSpeed, k);
  ASSERT_EQ(r.residual_before.size(), kRows - 1);
  ASSERT_EQ(r.residual_after.size(), kRows - 1);
  std::size_t differ_before = 0, differ_after = 0;
  for (std::size_t i = 0; i + 1 < kRows; ++i) {
    differ_before += r.residual_before[i] != y[i] - base[i];
    differ_after += r.residual_after[i] != y[i] - fitted[i];
  }
  EXPECT_EQ(differ_before, 0u);
  EXPECT_EQ(differ_after, 0u);
}

// A drive log: `still` rows standing (commands `left`/`right`, the encoders unchanged, the ToF
// at the obstacle's distance plus noise), then `moving` rows at `speed` cm/s towards it.
logs::Log drive_log_long(int still, double left, double right, std::uint64_t seed, double speed = 5, double obstacle_m = 0.6,
                    int moving = 100) {
  std::mt19937_64 rng(seed);
  std::normal_distribution<double> noise(0.0, 3.0);
  std::ostringstream csv;
  csv << "# obstacle_distance_m: " << obstacle_m << "\ntime_s,left_speed_cm_s,right_speed_cm_s,left_steps,right_steps,tof_mm\n";
  double x = 0;
  for (int i = 0; i < still + moving; ++i) {
    const bool standing = i < still;
    const double t = 0.1 * i;
    if (!standing && i > still) x += speed / 100.0 * 0.1;
    const long steps = std::lround(x * 7763.656);
    csv << g17(t) << "," << (standing ? left : speed) << "," << (standing ? right : speed) << "," << steps << "," << steps << ","
        << std::lround(1000.0 * (obstacle_m - x) + noise(rng)) << "\n";
  }
  return logs::parse_log(csv.str(), "drive.csv", logs::Kind::drive);
}

void expect_same_noise(const calibrate::ReadingNoise& got, const calibrate::ReadingNoise& calibration) {
  EXPECT_EQ(got.from, calibration.from);
  EXPECT_EQ(got.sd, calibration.sd);
  EXPECT_EQ(got.n, calibration.n);
  EXPECT_EQ(got.groups, calibration.groups);
}

TEST(LongLogs, DriveReplicateNoiseWithoutTheFitsIsTheCalibrations) {
  // Two runs standing 40 and 50 rows before they move.
  const std::vector<logs::Log> logs{drive_log_long(40, 0, 0, 1), drive_log_long(50, 0, 0, 2)};
  const calibrate::ReadingNoise calibration = calibrate::fit_drive(logs).tof_noise;
  ASSERT_EQ(calibration.from, "replicates");
  ASSERT_EQ(calibration.n, 90u);  // (minus wild readings: none in N(0, 3 mm) noise)
  expect_same_noise(calibrate::drive_tof_replicate_noise(logs), calibration);
}

TEST(LongLogs, DriveReplicateNoiseWhereTheCapDecidesIsTheCalibrations) {
  // Standing with the wheels commanded 20 and -16 cm/s: both beyond the firmware's 15.5 cm/s,
  // so capped their mean is 0 (standing), as logged it is 2 cm/s (moving): which one holds is
  // fit_drive's steps fit's to say, and the shortcut asks it.
  const std::vector<logs::Log> logs{drive_log_long(40, 20, -16, 3)};
  ASSERT_EQ(calibrate::fit_drive(logs).tof_noise.from, "replicates");  // the encoders say it stood: the cap is kept
  expect_same_noise(calibrate::drive_tof_replicate_noise(logs), calibrate::fit_drive(logs).tof_noise);
}

TEST(LongLogs, WhereTheWheelsRunBeyondTheCapNothingStoodStill) {
  // Standing commanded 16 and -15.5 cm/s (capped: a mean of 0; as logged 0.25 cm/s), then moving
  // at 30 cm/s with the encoders counting 30 cm/s: the steps fit drops the cap, so the first row
  // already moves and the calibration's ToF noise comes from its residuals. Taking the capped
  // commands without asking the fit would give 40 replicates.
  const std::vector<logs::Log> logs{drive_log_long(40, 16, -15.5, 5, 30, 1.9, 30)};
  const calibrate::DriveFit calibration = calibrate::fit_drive(logs);
  ASSERT_FALSE(calibration.cap_kept);
  ASSERT_EQ(calibration.tof_noise.from, "residuals");
  EXPECT_FALSE(calibrate::drive_tof_replicate_noise(logs).usable());
}

TEST(LongLogs, TooFewStillReadingsGiveNoReplicateNoise) {
  // 10 still rows (fewer than kMinStillReadings): the calibration's noise is the fit's residuals'.
  const std::vector<logs::Log> logs{drive_log_long(10, 0, 0, 4)};
  ASSERT_EQ(calibrate::fit_drive(logs).tof_noise.from, "residuals");
  EXPECT_FALSE(calibrate::drive_tof_replicate_noise(logs).usable());
}

TEST(LongLogs, AMidSizeLogReadsBackTheValuesWrittenAndLocatesABadCell) {
  constexpr int kRows = 50000;
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  std::vector<double> grey(kRows), value(kRows), extra(kRows);
  std::ostringstream csv;
  csv << "\xEF\xBB\xBF# robot: r1\r\ngrey , Sensor,value,temperature_c,note,\r\n";
  for (int i = 0; i < kRows; ++i) {
    grey[i] = u(rng);
    value[i] = std::floor(1023 * u(rng));
    extra[i] = 20 + 10 * u(rng);
    csv << " " << g17(grey[i]) << "\t," << i % 3 << "," << g17(value[i]) << "," << g17(extra[i]) << ",n" << i << ",\r\n";
  }
  const std::string text = csv.str();
  const logs::Log log = logs::parse_log(text, "ground.csv");
  ASSERT_EQ(log.kind, logs::Kind::ground);
  ASSERT_EQ(log.rows(), static_cast<std::size_t>(kRows));
  EXPECT_EQ(log.robot, "r1");
  EXPECT_EQ(log.col("grey"), grey);
  EXPECT_EQ(log.col("value"), value);
  EXPECT_EQ(log.col("temperature_c"), extra);
  EXPECT_EQ(log.text.at("note").at(kRows - 1), "n" + std::to_string(kRows - 1));
  EXPECT_EQ(log.line_of_row.at(kRows - 1), kRows + 2);
  EXPECT_EQ(log.column_of(kRows - 1, "sensor"), 2 + static_cast<int>(g17(grey[kRows - 1]).size()) + 2);

  // Row 40 000's value (line 40 002) spoiled: the error names that line and the cell's column.
  const int bad = 40000;
  const std::string row_start = " " + g17(grey[bad - 1]) + "\t," + std::to_string((bad - 1) % 3) + ",";
  const std::size_t at = text.find("\r\n" + row_start) + 2;
  ASSERT_NE(at, std::string::npos + 2);
  std::string spoiled = text;
  spoiled.insert(at + row_start.size(), "x");
  try {
    logs::parse_log(spoiled, "ground.csv");
    FAIL() << "a bad cell was read";
  } catch (const logs::InputError& e) {
    EXPECT_EQ(e.line(), bad + 2);
    EXPECT_EQ(e.column(), static_cast<int>(row_start.size()) + 1);
    EXPECT_NE(e.message().find("column 'value': expected a number, got 'x" + g17(value[bad - 1]) + "'"), std::string::npos)
        << e.message();
  }
}

}  // namespace

namespace {

// A drive log's CSV: per row the commands and the two registers as given.
struct DriveRow {
  double t, left_cmd, right_cmd;
  long left_steps, right_steps, tof;
};
logs::Log drive_rows(const std::vector<DriveRow>& rows, const std::string& name) {
  std::ostringstream csv;
  csv << "# obstacle_distance_m: 0.6\ntime_s,left_speed_cm_s,right_speed_cm_s,left_steps,right_steps,tof_mm\n";
  for (const DriveRow& r : rows)
    csv << g17(r.t) << "," << g17(r.left_cmd) << "," << g17(r.right_cmd) << "," << r.left_steps << "," << r.right_steps << "," << r.tof << "\n";
  return logs::parse_log(csv.str(), name, logs::Kind::drive);
}

// A 16-bit register's readings unwrapped from the first (the step between two readings is the
// one within half the register's range).
std::vector<double> unwrapped(const std::vector<long>& reading) {
  std::vector<double> out(reading.size());
  for (std::size_t i = 0; i < reading.size(); ++i) {
    if (i == 0) {
      out[i] = static_cast<double>(reading[i]);
      continue;
    }
    long d = (reading[i] - reading[i - 1]) % 65536;
    if (d > 32767) d -= 65536;
    if (d < -32768) d += 65536;
    out[i] = out[i - 1] + static_cast<double>(d);
  }
  return out;
}

}  // namespace

TEST(LongLogs, DriveCovariatesBuiltAfterTheFitsAreTheLogsOwn) {
  constexpr double kStepsPerMetre = 7763.656;  // the plug-in's encoder (docs/diagnose.md, drive)
  // Log 1, commands unlike on the two wheels: its registers start at 32700 and wrap past 32767
  // (int16), then one wheel at a time (the other register unchanged), then standing; two ToF
  // "no target" codes (dropouts: the obstacle is in view). Log 2, both wheels commanded alike at 0.1 cm/s (under a
  // step a row): the registers often unchanged, the right one the left one's or one above it.
  std::vector<DriveRow> one, two;
  double xl = 0, xr = 0;
  for (int i = 0; i < 120; ++i) {
    const double vl = i < 30 ? 4 : i < 60 ? 3 : 0, vr = i < 30 ? 4 : i < 60 ? 0 : i < 90 ? 5 : 0;
    auto int16 = [](long v) { return (v + 32768) % 65536 - 32768; };
    const long sl = 32700 + static_cast<long>(std::floor(xl * kStepsPerMetre)), sr = 32700 + static_cast<long>(std::floor(xr * kStepsPerMetre));
    const long tof = i == 40 || i == 95 ? 8191 : std::lround(1000.0 * (0.6 - 0.5 * (xl + xr)));
    one.push_back({0.1 * i, vl, vr, int16(sl), int16(sr), tof});
    xl += vl / 100.0 * 0.1;
    xr += vr / 100.0 * 0.1;
  }
  double x = 0;
  for (int i = 0; i < 100; ++i) {
    const double v = i < 80 ? 0.1 : 0;
    two.push_back({5.0 + 0.1 * i, v, v, static_cast<long>(std::floor(x * kStepsPerMetre)),
                   static_cast<long>(std::floor(x * kStepsPerMetre + 0.5)), std::lround(1000.0 * (0.6 - x))});
    x += v / 100.0 * 0.1;
  }
  const std::vector<logs::Log> logs{drive_rows(one, "one.csv"), drive_rows(two, "two.csv")};
  std::string why;
  const auto p = diagnose::detail::make_problem(logs, diagnose::Options{}, why);
  ASSERT_NE(p, nullptr) << why;
  // Before: only the covariates every kind shares.
  std::vector<std::string> names;
  for (const auto& c : p->covariates) names.push_back(c.first);
  EXPECT_EQ(names, (std::vector<std::string>{"log_row", "log"}));
  p->add_late_covariates();
  p->add_late_covariates();  // once only
  names.clear();
  for (const auto& c : p->covariates) names.push_back(c.first);
  ASSERT_EQ(names, (std::vector<std::string>{"time_s", "commanded_cm_s", "speed_cm_s", "acceleration_cm_s2", "distance_m", "range_m",
                                             "time_since_command_s", "channel", "log_row", "log"}));

  // Expected, from the logs' columns: per row, and each residual's channel (0 ToF, 1 left
  // register, 2 right register: a register only where it changed since the previous row, the
  // right one not where the commands are alike throughout and it equals the left one).
  std::vector<std::vector<double>> per_row(7);
  std::vector<double> channel;
  std::size_t right_kept_as_previous = 0, right_kept_as_left = 0;
  for (const auto& rows : {one, two}) {
    const std::size_t n = rows.size();
    std::vector<long> sl, sr;
    bool alike = true;
    for (const DriveRow& r : rows) {
      sl.push_back(r.left_steps);
      sr.push_back(r.right_steps);
      alike = alike && r.left_cmd == r.right_cmd;
    }
    const std::vector<double> ul = unwrapped(sl), ur = unwrapped(sr);
    std::vector<double> m(n);
    for (std::size_t i = 0; i < n; ++i) m[i] = 0.5 * (ul[i] + ur[i]) / kStepsPerMetre;
    auto t = [&](std::size_t i) { return rows[i].t; };
    auto slope = [&](std::size_t a, std::size_t b) { return b > a && t(b) > t(a) ? (m[b] - m[a]) / (t(b) - t(a)) : 0.0; };
    double since = 0;
    for (std::size_t i = 0; i < n; ++i) {
      const std::size_t a = i > 0 ? i - 1 : 0, b = std::min(i + 1, n - 1), a2 = i > 1 ? i - 2 : 0, b2 = std::min(i + 2, n - 1);
      const double dist = a == i || b == i ? m[i] : m[a] + (m[b] - m[a]) * (t(i) - t(a)) / (t(b) - t(a));
      const double span = 0.5 * (t(b) + t(b2)) - 0.5 * (t(a2) + t(a));
      if (i > 0 && (rows[i].left_cmd != rows[i - 1].left_cmd || rows[i].right_cmd != rows[i - 1].right_cmd)) since = t(i);
      const double row_values[7] = {t(i), 0.5 * (rows[i].left_cmd + rows[i].right_cmd), 100.0 * slope(a, b),
                                    span > 0 ? 100.0 * (slope(b, b2) - slope(a2, a)) / span : 0.0, dist, 0.6 - dist, t(i) - since};
      for (int k = 0; k < 7; ++k) per_row[static_cast<std::size_t>(k)].push_back(row_values[k]);
      if (rows[i].tof != 8191) channel.push_back(0);
      if (i == 0 || ul[i] != ul[i - 1]) channel.push_back(1);
      const bool as_left = alike && ur[i] == ul[i], as_previous = i > 0 && ur[i] == ur[i - 1];
      if (!as_left && !as_previous) channel.push_back(2);
      right_kept_as_left += as_left && i > 0 && ur[i] != ur[i - 1] ? 1 : 0;
      right_kept_as_previous += !as_left && as_previous ? 1 : 0;
    }
  }
  // Both ways a right register leaves the residuals occur, and a wrap: the test reaches them.
  EXPECT_GT(right_kept_as_left, 3u);
  EXPECT_GT(right_kept_as_previous, 3u);
  EXPECT_LT(one[20].left_steps, -30000);

  ASSERT_EQ(p->rows, one.size() + two.size());
  for (std::size_t k = 0; k < 7; ++k) {
    ASSERT_TRUE(p->is_per_row(k)) << names[k];
    ASSERT_EQ(p->covariates[k].second.size(), p->rows) << names[k];
    for (std::size_t i = 0; i < p->rows; ++i)
      EXPECT_NEAR(p->covariates[k].second[i], per_row[k][i], 1e-12 * (1.0 + std::abs(per_row[k][i]))) << names[k] << " row " << i;
  }
  EXPECT_FALSE(p->is_per_row(7));
  EXPECT_EQ(p->covariates[7].second, channel);
  EXPECT_TRUE(p->is_per_row(8));
  EXPECT_TRUE(p->is_per_row(9));
}
}  // namespace test_long_logs_cpp
