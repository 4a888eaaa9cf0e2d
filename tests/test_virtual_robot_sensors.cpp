// The virtual E-Puck2's sensor logs record the imperfections of real logs (data/raw/<kind>/README.md):
// readings clipped at the rails with noise around them, occasional wild readings, a command above
// the firmware's cap, a static run, ToF out-of-range codes, two robots that differ. Each is a field
// of its Truth (virtual_robot/sensor_truth.hpp): these tests check that each appears in the
// generated logs with its documented count or fraction, that switching it off removes it, that
// generation is deterministic and that the shipped logs are a fresh generation.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <iostream>
#include <filesystem>
#include <fstream>
#include <map>
#include <set>
#include <sstream>
#include <string>
#include <vector>

#include "epuck2/logs/log.hpp"
#include "epuck2/models/sensors.hpp"
#include "epuck2/virtual_robot/reference_logs.hpp"
#include "epuck2/virtual_robot/sensor_truth.hpp"

namespace vr = epuck2::virtual_robot;
namespace s = epuck2::models::sensors;
using epuck2::logs::Kind;

namespace {

// A log as its text says (the reader rejects ToF 8190 today, so the tests read the text).
struct Table {
  std::string name;
  std::map<std::string, std::string> meta;
  std::vector<std::string> header;
  std::vector<std::vector<double>> rows;
  std::vector<int> lines;  ///< 1-based line of each row in the file
  std::size_t index(const std::string& column) const {
    const auto it = std::find(header.begin(), header.end(), column);
    if (it == header.end()) throw std::runtime_error(name + ": no column " + column);
    return static_cast<std::size_t>(it - header.begin());
  }
  std::vector<double> col(const std::string& column) const {
    const std::size_t j = index(column);
    std::vector<double> v;
    for (const auto& r : rows) v.push_back(r[j]);
    return v;
  }
};

Table read_table(const vr::GeneratedFile& f) {
  Table t;
  t.name = f.name;
  std::istringstream in(f.content);
  std::string line;
  int n = 0;
  while (std::getline(in, line)) {
    ++n;
    if (line.empty()) continue;
    if (line[0] == '#') {
      const auto colon = line.find(':');
      if (colon != std::string::npos) {
        std::string key = line.substr(1, colon - 1), value = line.substr(colon + 1);
        key.erase(0, key.find_first_not_of(' '));
        value.erase(0, value.find_first_not_of(' '));
        t.meta[key] = value;
      }
      continue;
    }
    std::vector<std::string> cells;
    std::stringstream ss(line);
    std::string cell;
    while (std::getline(ss, cell, ',')) cells.push_back(cell);
    if (t.header.empty()) {
      t.header = cells;
      continue;
    }
    std::vector<double> row;
    for (const auto& c : cells) row.push_back(std::stod(c));
    t.rows.push_back(row);
    t.lines.push_back(n);
  }
  return t;
}

std::vector<Table> tables_vrs(const std::vector<vr::GeneratedFile>& files) {
  std::vector<Table> out;
  for (const auto& f : files) out.push_back(read_table(f));
  return out;
}

const Table& by_name(const std::vector<Table>& ts, const std::string& name) {
  for (const auto& t : ts)
    if (t.name == name) return t;
  throw std::runtime_error("no file " + name);
}

bool has_file(const std::vector<vr::GeneratedFile>& files, const std::string& name) {
  return std::any_of(files.begin(), files.end(), [&](const auto& f) { return f.name == name; });
}

/// Rows whose values differ between two generations of the same protocol (same files, same rows).
std::size_t differing_rows(const std::vector<vr::GeneratedFile>& a, const std::vector<vr::GeneratedFile>& b) {
  EXPECT_EQ(a.size(), b.size());
  std::size_t n = 0;
  for (std::size_t i = 0; i < std::min(a.size(), b.size()); ++i) {
    const Table ta = read_table(a[i]), tb = read_table(b[i]);
    EXPECT_EQ(ta.name, tb.name);
    EXPECT_EQ(ta.rows.size(), tb.rows.size()) << ta.name;
    for (std::size_t k = 0; k < std::min(ta.rows.size(), tb.rows.size()); ++k) n += ta.rows[k] != tb.rows[k];
  }
  return n;
}

std::size_t total_rows(const std::vector<vr::GeneratedFile>& files) {
  std::size_t n = 0;
  for (const auto& f : files) n += read_table(f).rows.size();
  return n;
}

/// `observed` out of `n` is within 4.5 binomial standard deviations of fraction p (and, p > 0, above 0).
void expect_fraction(std::size_t observed, std::size_t n, double p, const std::string& what) {
  const double mean = p * static_cast<double>(n), sd = std::sqrt(static_cast<double>(n) * p * (1 - p));
  EXPECT_NEAR(static_cast<double>(observed), mean, 4.5 * sd + 1) << what << ": " << observed << " of " << n;
  if (p > 0) EXPECT_GT(observed, 0u) << what;
}

std::string read_bytes_vrs(const std::filesystem::path& path) {
  std::ifstream in(path, std::ios::binary);
  std::ostringstream os;
  os << in.rdbuf();
  return in ? os.str() : std::string();
}

const std::uint64_t kSeed = vr::kReferenceSeed;  // the shipped logs' seed: the README's counts

}  // namespace

// ----- Determinism and the shipped logs ----------------------------------------------------------

TEST(VirtualSensors, SameSeedSameBytesDifferentSeedDifferent) {
  for (Kind kind : {Kind::proximity, Kind::light, Kind::ground, Kind::camera, Kind::drive}) {
    const auto first = vr::reference_logs(kind, 7), again = vr::reference_logs(kind, 7), other = vr::reference_logs(kind, 8);
    ASSERT_EQ(first.size(), again.size());
    ASSERT_EQ(first.size(), other.size());
    for (std::size_t i = 0; i < first.size(); ++i) {
      EXPECT_EQ(first[i].name, again[i].name);
      EXPECT_EQ(first[i].content, again[i].content) << first[i].name;
      EXPECT_NE(first[i].content, other[i].content) << first[i].name;
    }
  }
}

TEST(VirtualSensors, CommittedLogsAreFresh) {
  namespace fs = std::filesystem;
  for (const char* kind : {"proximity", "light", "ground", "camera", "drive"}) {
    const auto files = vr::reference_logs(*epuck2::logs::parse_kind(kind), kSeed);
    const fs::path dir = fs::path(EPUCK2_SOURCE_DIR) / "data" / "raw" / kind;
    std::set<std::string> expected;
    for (const auto& f : files) {
      expected.insert(f.name);
      EXPECT_TRUE(read_bytes_vrs(dir / f.name) == f.content)
          << (dir / f.name) << " differs from a fresh generation: run `epuck2-fit generate " << kind << " --out-dir data/raw/" << kind << "`";
    }
    for (const auto& e : fs::directory_iterator(dir))
      if (e.path().extension() == ".csv") EXPECT_TRUE(expected.count(e.path().filename().string())) << "stale " << e.path();
  }
}

TEST(VirtualSensors, LogsWithoutToFCodesPassTheReader) {
  for (Kind kind : {Kind::proximity, Kind::light, Kind::ground, Kind::camera})
    for (const auto& f : vr::reference_logs(kind, kSeed)) EXPECT_NO_THROW(epuck2::logs::parse_log(f.content, f.name, kind)) << f.name;
  vr::DriveTruth truth;
  truth.tof_dropout_fraction = 0;
  truth.far_run_speed_cm_s = 0;
  for (const auto& f : vr::drive_logs(truth, kSeed)) EXPECT_NO_THROW(epuck2::logs::parse_log(f.content, f.name, Kind::drive)) << f.name;
}

// ----- 6. Two robots that differ --------------------------------------------------------------------

TEST(VirtualSensors, EveryLogNamesItsRobotAndEachKindHasTwo) {
  for (Kind kind : {Kind::proximity, Kind::light, Kind::ground, Kind::camera, Kind::drive}) {
    std::set<std::string> robots;
    for (const auto& t : tables_vrs(vr::reference_logs(kind, kSeed))) {
      ASSERT_TRUE(t.meta.count("robot")) << t.name;
      robots.insert(t.meta.at("robot"));
      if (t.meta.at("robot") != "virtual-epuck2-1")
        EXPECT_NE(t.name.find(t.meta.at("robot")), std::string::npos) << "robot 2's files carry its name: " << t.name;
    }
    EXPECT_EQ(robots, (std::set<std::string>{"virtual-epuck2-1", "virtual-epuck2-2"}));
  }
  // Battery logs name theirs too.
  std::set<std::string> battery;
  for (const auto& t : tables_vrs(vr::battery_reference_logs(kSeed))) battery.insert(t.meta.at("robot"));
  EXPECT_EQ(battery.size(), 2u);
  // One element: one robot.
  vr::LightTruth light;
  light.robot_gamma_scale = {1.0};
  vr::GroundTruth ground;
  ground.robot_gain_scale = {1.0};
  vr::CameraTruth camera;
  camera.robot_cx_shift_px = {0.0};
  vr::DriveTruth drive;
  drive.steps_per_m_scale = {1.0};
  for (const auto& files : {vr::light_logs(light, kSeed), vr::ground_logs(ground, kSeed), vr::camera_logs(camera, kSeed),
                            vr::drive_logs(drive, kSeed)})
    for (const auto& t : tables_vrs(files)) EXPECT_EQ(t.meta.at("robot"), "virtual-epuck2-1") << t.name;
}

TEST(VirtualSensors, RobotsDifferByTheDocumentedAmounts) {
  auto mean_where = [](const Table& t, const std::map<std::string, double>& where, const std::string& column) {
    double sum = 0;
    int n = 0;
    for (const auto& r : t.rows) {
      bool ok = true;
      for (const auto& [c, v] : where) ok = ok && std::abs(r[t.index(c)] - v) < 1e-9;
      if (ok) sum += r[t.index(column)], ++n;
    }
    EXPECT_GT(n, 0);
    return sum / n;
  };
  {  // Light: robot 2's gamma 1 % smaller: at 10 cm, intensity 1, sensor 0 it reads (0.5625 - 0.5513) 4095 = 46 counts more.
    vr::LightTruth truth;
    truth.wild_fraction = 0;
    const auto ts = tables_vrs(vr::light_logs(truth, kSeed));
    const std::map<std::string, double> at{{"distance_m", 0.10}, {"sensor", 0}};
    const double diff = mean_where(by_name(ts, "light_intensity_1.00_virtual-epuck2-2.csv"), at, "value") -
                        mean_where(by_name(ts, "light_intensity_1.00.csv"), at, "value");
    const double expected = truth.sensor_gain[0] * s::kProximityFullScale_raw *
                            (s::light_contribution(truth.gamma_m, 1.0, 0.10) -
                             s::light_contribution(truth.gamma_m * truth.robot_gamma_scale[1], 1.0, 0.10));
    EXPECT_NEAR(diff, expected, 12.0);  // 4 standard errors of the difference of two means of 24 (15 counts each)
    EXPECT_NEAR(truth.gamma_m * truth.robot_gamma_scale[1], 0.07425, 1e-12);
  }
  {  // Ground: robot 2's gains 2 % higher (sensor 0 white: +18 counts); its centre sensor's gain 975.
    vr::GroundTruth truth;
    truth.wild_fraction = 0;
    const auto ts = tables_vrs(vr::ground_logs(truth, kSeed));
    const Table &a = by_name(ts, "ground_virtual-epuck2-1.csv"), &b = by_name(ts, "ground_virtual-epuck2-2.csv");
    const std::map<std::string, double> white0{{"grey", 1.0}, {"sensor", 0}}, half1{{"grey", 0.5}, {"sensor", 1}};
    EXPECT_NEAR(mean_where(b, white0, "value") - mean_where(a, white0, "value"), 0.02 * truth.gain_raw[0], 5.0);
    EXPECT_NEAR(mean_where(b, half1, "value") - mean_where(a, half1, "value"), 0.5 * (975.0 - truth.gain_raw[1]), 5.0);
  }
  {  // Camera: robot 2's optical axis 0.5 px to the right: every centroid moves by 0.5 px before rounding.
    vr::CameraTruth truth;
    truth.wild_fraction = 0;
    const auto ts = tables_vrs(vr::camera_logs(truth, kSeed));
    const auto a = by_name(ts, "camera_virtual-epuck2-1.csv").col("px"), b = by_name(ts, "camera_virtual-epuck2-2.csv").col("px");
    ASSERT_EQ(a.size(), b.size());
    double diff = 0;
    for (std::size_t i = 0; i < a.size(); ++i) diff += (b[i] - a[i]) / static_cast<double>(a.size());
    EXPECT_NEAR(diff, 0.5, 0.12);  // 0.5 px noise and rounding over ~400 frames: standard error 0.04 px
  }
  {  // Drive: robot 2's true steps/m 0.5 % higher: after the 0.5 m away run it is 2.5 mm nearer than
     // its encoders say at the host's steps/m (no ToF noise; the body has caught up with the wheels).
    vr::DriveTruth truth;
    truth.tof_noise_mm = truth.tof_noise_per_m_mm = 0;
    truth.tof_wild_fraction = truth.tof_dropout_fraction = 0;
    truth.other_robot_speeds_cm_s = {10.0};
    const auto ts = tables_vrs(vr::drive_logs(truth, kSeed));
    for (const char* name : {"drive_away_10.0_cm_s.csv", "drive_away_10.0_cm_s_virtual-epuck2-2.csv"}) {
      const Table& t = by_name(ts, name);
      const double scale = t.meta.at("robot") == "virtual-epuck2-1" ? 1.0 : truth.steps_per_m_scale[1];
      const double travel_mm = -t.col("left_steps").back() / (truth.steps_per_m * scale) * 1000.0;
      EXPECT_NEAR(t.col("tof_mm").back(), truth.tof_scale * (truth.obstacle_distance_m * 1000.0 + travel_mm) + truth.tof_offset_mm, 0.6)
          << name;
    }
    EXPECT_NEAR(truth.away_travel_m * 1000.0 * (1 - 1 / truth.steps_per_m_scale[1]), 2.5, 0.02);
  }
}

// ----- 1. Rails -----------------------------------------------------------------------------------

TEST(VirtualSensors, ProximitySaturatesAtZeroMillimetresAboutHalfOnTheRail) {
  vr::ProximityTruth truth;
  truth.wild_fraction = 0;
  for (int on : {1, 0}) {
    truth.saturated_distances = on;
    for (const auto& t : tables_vrs(vr::proximity_logs(truth, kSeed))) {
      std::size_t rail = 0, n = 0, near = 0;
      for (const auto& r : t.rows) {
        if (r[t.index("distance_m")] != 0.0) continue;
        ++n;
        rail += r[t.index("value")] == 4095;
        near += r[t.index("value")] >= 4095 - 5 * truth.noise_raw;
      }
      ASSERT_EQ(n, static_cast<std::size_t>(truth.readings_per_distance));
      if (on) {
        expect_fraction(rail, n, 0.5, t.name + " on the rail");
        EXPECT_EQ(near, n) << t.name << ": the others just inside";
      } else {
        EXPECT_LT(rail, n / 20) << t.name;  // envelope minus scatter: rarely the rail (robot 2 never)
      }
    }
  }
}

TEST(VirtualSensors, LightStraddlesTheZeroRail) {
  vr::LightTruth truth;
  truth.wild_fraction = 0;
  // The documented probe distance: 0.075 x 2 x sqrt(1 / (1 - 12/4095)) = 0.1502 m.
  const double d = 0.1502;
  for (int readings : {48, 0}) {
    truth.rail_readings = readings;
    const auto ts = tables_vrs(vr::light_logs(truth, kSeed));
    const Table& t = by_name(ts, "light_intensity_2.00.csv");
    std::size_t rail = 0, n = 0, inside = 0;
    for (const auto& r : t.rows) {
      if (std::abs(r[t.index("distance_m")] - d) > 1e-9 || r[t.index("sensor")] != 0) continue;
      ++n;
      rail += r[t.index("value")] == 0;
      inside += r[t.index("value")] > 0 && r[t.index("value")] <= 5 * truth.noise_raw;
    }
    EXPECT_EQ(n, static_cast<std::size_t>(readings));
    if (readings) {
      expect_fraction(rail, n, 0.5, "light on the rail");
      EXPECT_EQ(rail + inside, n);
    }
  }
}

TEST(VirtualSensors, GroundWhiteOfRobotTwosCentreSensorStraddlesTheRail) {
  vr::GroundTruth truth;
  truth.wild_fraction = 0;
  for (double rail : {1023.0, 0.0}) {
    truth.white_rail_raw = rail;
    const auto ts = tables_vrs(vr::ground_logs(truth, kSeed));
    for (const auto& t : ts) {
      std::size_t on = 0, n = 0, low = 0;
      for (const auto& r : t.rows) {
        on += r[t.index("value")] == 1023;
        low += r[t.index("value")] == 0;
        if (r[t.index("grey")] == 1.0 && r[t.index("sensor")] == 1) ++n;
      }
      EXPECT_EQ(low, 0u) << t.name << ": no black rail (offsets 48..75 counts)";
      if (rail > 0 && t.meta.at("robot") == "virtual-epuck2-2") expect_fraction(on, n, 0.5, t.name + " white on the rail");
      else EXPECT_EQ(on, 0u) << t.name;
    }
  }
}

TEST(VirtualSensors, ToFReachesItsFloorAndItsCeilingThenReportsOutOfRange) {
  vr::DriveTruth truth;
  truth.tof_wild_fraction = truth.tof_dropout_fraction = 0;
  const auto files = vr::drive_logs(truth, kSeed);
  const auto ts = tables_vrs(files);
  {  // The floor run stands 11.2 mm from the obstacle first: about half the readings on 20 mm.
    const Table& t = by_name(ts, "drive_away_floor_05.0_cm_s.csv");
    EXPECT_EQ(t.meta.at("obstacle_distance_m"), "0.0112");
    const auto tof = t.col("tof_mm"), time = t.col("time_s");
    std::size_t rail = 0, n = 0;
    for (std::size_t k = 0; k < tof.size(); ++k) {
      if (time[k] >= truth.floor_run_pause_s) break;
      ++n;
      rail += tof[k] == 20;
      EXPECT_LE(tof[k], 20 + 4 * truth.tof_noise_mm) << "line " << t.lines[k];
    }
    EXPECT_GE(n, 25u);
    expect_fraction(rail, n, 0.5, "ToF on the 20 mm floor");
  }
  {  // The far run: readings on 2000 before the target is lost, then 8190 to the end.
    const Table& t = by_name(ts, "drive_away_far_10.0_cm_s.csv");
    const auto tof = t.col("tof_mm");
    EXPECT_GE(std::count(tof.begin(), tof.end(), 2000.0), 5);  // 2.021..2.10 m at 10 cm/s
    const auto first_code = std::find(tof.begin(), tof.end(), 8190.0);
    ASSERT_NE(first_code, tof.end());
    EXPECT_TRUE(std::all_of(first_code, tof.end(), [](double v) { return v == 8190.0; }));
    EXPECT_GT(tof.end() - first_code, 20);  // the last 0.25 m at 10 cm/s and the 1 s pause
  }
  // Off: no floor run, no far run, and no reading on a rail or out of range anywhere.
  truth.floor_run_speed_cm_s = 0;
  truth.far_run_speed_cm_s = 0;
  const auto off = vr::drive_logs(truth, kSeed);
  EXPECT_EQ(off.size(), files.size() - 2);
  for (const auto& t : tables_vrs(off))
    for (double v : t.col("tof_mm")) ASSERT_TRUE(v > 20 && v < 2000) << t.name << " " << v;
}

// ----- 2. Wild readings, 5. dropouts --------------------------------------------------------------

// The shipped logs' wild readings (README.md's counts): rows that change when the fraction is 0.
TEST(VirtualSensors, WildReadingsHaveTheDocumentedCountsAndFractions) {
  {
    vr::ProximityTruth on, off;
    off.wild_fraction = 0;
    EXPECT_EQ(differing_rows(vr::proximity_logs(on, kSeed), vr::proximity_logs(off, kSeed)), 17u);
    on.wild_fraction = 0.05;
    const auto files = vr::proximity_logs(on, kSeed);
    expect_fraction(differing_rows(files, vr::proximity_logs(off, kSeed)), total_rows(files), 0.05 * 4095 / 4096, "proximity");
    // Without them, nothing reads above the noise where the sensor sees nothing (0.05 m and beyond).
    for (const auto& t : tables_vrs(vr::proximity_logs(off, kSeed)))
      for (const auto& r : t.rows)
        if (r[t.index("distance_m")] >= 0.05) ASSERT_LE(r[t.index("value")], 5 * off.noise_raw) << t.name;
  }
  {
    vr::LightTruth on, off;
    off.wild_fraction = 0;
    EXPECT_EQ(differing_rows(vr::light_logs(on, kSeed), vr::light_logs(off, kSeed)), 13u);
    on.wild_fraction = 0.05;
    const auto files = vr::light_logs(on, kSeed);
    expect_fraction(differing_rows(files, vr::light_logs(off, kSeed)), total_rows(files), 0.05, "light");
  }
  {
    vr::GroundTruth on, off;
    off.wild_fraction = 0;
    EXPECT_EQ(differing_rows(vr::ground_logs(on, kSeed), vr::ground_logs(off, kSeed)), 10u);
    on.wild_fraction = 0.05;
    const auto files = vr::ground_logs(on, kSeed);
    expect_fraction(differing_rows(files, vr::ground_logs(off, kSeed)), total_rows(files), 0.05, "ground");
  }
  {
    vr::CameraTruth on, off;
    off.wild_fraction = 0;
    EXPECT_EQ(differing_rows(vr::camera_logs(on, kSeed), vr::camera_logs(off, kSeed)), 8u);
    on.wild_fraction = 0.05;
    const auto files = vr::camera_logs(on, kSeed);
    expect_fraction(differing_rows(files, vr::camera_logs(off, kSeed)), total_rows(files), 0.05, "camera");
  }
  {
    vr::DriveTruth on, off;
    off.tof_wild_fraction = 0;
    EXPECT_EQ(differing_rows(vr::drive_logs(on, kSeed), vr::drive_logs(off, kSeed)), 4u);
    on.tof_wild_fraction = 0.05;
    on.tof_dropout_fraction = off.tof_dropout_fraction = 0;
    on.far_run_speed_cm_s = off.far_run_speed_cm_s = 0;  // its 8190s hide wild readings
    const auto files = vr::drive_logs(on, kSeed);
    expect_fraction(differing_rows(files, vr::drive_logs(off, kSeed)), total_rows(files), 0.05, "ToF wild");
  }
}

TEST(VirtualSensors, ToFDropoutsReadTheOutOfRangeCode) {
  vr::DriveTruth truth;
  truth.far_run_speed_cm_s = 0;  // its own 8190s are not dropouts
  auto codes = [](const std::vector<vr::GeneratedFile>& files) {
    std::size_t n = 0;
    for (const auto& t : tables_vrs(files))
      for (double v : t.col("tof_mm")) n += v == 8190;
    return n;
  };
  EXPECT_EQ(codes(vr::drive_logs(truth, kSeed)), 1u);  // README.md
  truth.tof_dropout_fraction = 0.05;
  const auto files = vr::drive_logs(truth, kSeed);
  expect_fraction(codes(files), total_rows(files), 0.05, "dropouts");
  truth.tof_dropout_fraction = 0;
  EXPECT_EQ(codes(vr::drive_logs(truth, kSeed)), 0u);
}

// ----- 3. Above the cap, 4. static run ----------------------------------------------------------

TEST(VirtualSensors, OneSpeedIsAboveTheFirmwaresCap) {
  const double cap_cm_s = s::kFirmwareSpeedLimit_steps_s / s::kPluginStepsPerMetre * 100.0;  // 14.17
  std::set<std::string> above;
  for (const auto& t : tables_vrs(vr::drive_reference_logs(kSeed)))
    for (double v : t.col("left_speed_cm_s"))
      if (std::abs(v) > cap_cm_s) above.insert(t.name);
  EXPECT_EQ(above, (std::set<std::string>{"drive_away_15.0_cm_s.csv", "drive_toward_15.0_cm_s.csv"}));
}

TEST(VirtualSensors, StaticRunStandsStillThroughout) {
  vr::DriveTruth truth;
  const auto files = vr::drive_logs(truth, kSeed);
  ASSERT_TRUE(has_file(files, "drive_static.csv"));
  const Table t = tables_vrs(files)[std::find_if(files.begin(), files.end(), [](const auto& f) { return f.name == "drive_static.csv"; }) - files.begin()];
  EXPECT_EQ(t.meta.at("commanded_speed_cm_s"), "0");
  for (const char* c : {"left_speed_cm_s", "right_speed_cm_s", "left_steps", "right_steps"})
    for (double v : t.col(c)) ASSERT_EQ(v, 0.0) << c;
  EXPECT_GE(t.col("time_s").back(), truth.static_run_s - 2 * (truth.sample_period_s + truth.sample_jitter_s));
  EXPECT_GT(t.rows.size(), 80u);
  truth.static_run_s = 0;
  EXPECT_FALSE(has_file(vr::drive_logs(truth, kSeed), "drive_static.csv"));
}

// ----- The README's line lists -------------------------------------------------------------------

// EPUCK2_LIST_WILD=1 prints file:line of every wild reading and dropout in the shipped logs (the
// rows that change when the fraction is 0), as data/raw/<kind>/README.md lists them.
TEST(VirtualSensors, ListWildLinesWhenAsked) {
  if (!std::getenv("EPUCK2_LIST_WILD")) GTEST_SKIP() << "set EPUCK2_LIST_WILD=1 to list the wild readings' lines";
  auto list = [](const char* what, const std::vector<vr::GeneratedFile>& on, const std::vector<vr::GeneratedFile>& off) {
    for (std::size_t i = 0; i < on.size(); ++i) {
      const Table a = read_table(on[i]), b = read_table(off[i]);
      for (std::size_t k = 0; k < a.rows.size(); ++k)
        if (a.rows[k] != b.rows[k]) {
          std::cout << what << " " << a.name << ":" << a.lines[k] << " ";
          for (double v : a.rows[k]) std::cout << v << ",";
          std::cout << " (otherwise " << b.rows[k].back() << ")\n";
        }
    }
  };
  vr::ProximityTruth p;
  p.wild_fraction = 0;
  list("wild", vr::proximity_logs({}, kSeed), vr::proximity_logs(p, kSeed));
  vr::LightTruth l;
  l.wild_fraction = 0;
  list("wild", vr::light_logs({}, kSeed), vr::light_logs(l, kSeed));
  vr::GroundTruth g;
  g.wild_fraction = 0;
  list("wild", vr::ground_logs({}, kSeed), vr::ground_logs(g, kSeed));
  vr::CameraTruth c;
  c.wild_fraction = 0;
  list("wild", vr::camera_logs({}, kSeed), vr::camera_logs(c, kSeed));
  vr::DriveTruth d;
  d.tof_wild_fraction = 0;
  list("wild", vr::drive_logs({}, kSeed), vr::drive_logs(d, kSeed));
  vr::DriveTruth d2;
  d2.tof_dropout_fraction = 0;
  list("dropout", vr::drive_logs({}, kSeed), vr::drive_logs(d2, kSeed));
}
