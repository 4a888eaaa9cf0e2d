// The virtual robot records what its README says it records. Each kind's logs are generated afresh
// (`epuck2-fit generate KIND`, through the real binary, at the default seed and at another), and
// simple statistics of them, worked here -- medians per setting (robust to the wild readings the
// README announces), rates, spreads -- are compared with the truth as data/raw/<kind>/README.md
// states it, its numbers copied into this file from the README's tables. The README is the
// generator's specification; VirtualSensors.CommittedLogsAreFresh only checks that the shipped logs
// are today's generation, whatever it is.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>
#include <tuple>
#include <string>
#include <vector>

#include <unistd.h>

namespace test_generator_truth_cpp {
namespace {

namespace fs = std::filesystem;

struct Log {
  std::string name;
  std::map<std::string, std::string> meta;  // "# key: value"
  std::vector<std::string> header;
  std::vector<std::vector<double>> rows;
  std::size_t col(const std::string& c) const {
    const auto it = std::find(header.begin(), header.end(), c);
    EXPECT_NE(it, header.end()) << name << ": no column " << c;
    return static_cast<std::size_t>(it - header.begin());
  }
};

Log read_log(const fs::path& p) {
  Log l;
  l.name = p.filename().string();
  std::ifstream in(p);
  std::string line;
  while (std::getline(in, line)) {
    if (line.empty()) continue;
    if (line[0] == '#') {
      const std::size_t colon = line.find(": ");
      if (colon != std::string::npos && line.size() > 2) l.meta[line.substr(2, colon - 2)] = line.substr(colon + 2);
      continue;
    }
    std::replace(line.begin(), line.end(), ',', ' ');
    std::istringstream words(line);
    if (l.header.empty()) {
      std::string w;
      while (words >> w) l.header.push_back(w);
    } else {
      std::vector<double> row;
      std::string w;
      while (words >> w) row.push_back(std::strtod(w.c_str(), nullptr));
      l.rows.push_back(row);
    }
  }
  return l;
}

double median(std::vector<double> v) {
  EXPECT_FALSE(v.empty());
  if (v.empty()) return NAN;
  std::sort(v.begin(), v.end());
  const std::size_t n = v.size();
  return n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}

/// A robust standard deviation: 1.4826 x the median absolute deviation.
double mad_sd(const std::vector<double>& v) {
  const double m = median(v);
  std::vector<double> d;
  for (double x : v) d.push_back(std::abs(x - m));
  return 1.4826 * median(d);
}

/// The logs `generate KIND --seed SEED` writes, each with its robot's index (0 for
/// virtual-epuck2-1).
std::vector<Log> generate(const std::string& kind, unsigned long seed) {
  char tmpl[] = "/tmp/epuck2-generator-truth-XXXXXX";
  EXPECT_NE(::mkdtemp(tmpl), nullptr);
  const fs::path dir = tmpl;
  const std::string cmd = "'" EPUCK2_FIT_EXE "' generate " + kind + " --seed " + std::to_string(seed) + " --out-dir '" +
                          dir.string() + "' >/dev/null 2>&1";
  EXPECT_EQ(std::system(cmd.c_str()), 0) << cmd;
  std::vector<Log> out;
  std::vector<fs::path> files;
  for (const auto& e : fs::directory_iterator(dir))
    if (e.path().extension() == ".csv") files.push_back(e.path());
  std::sort(files.begin(), files.end());
  for (const auto& f : files) out.push_back(read_log(f));
  std::error_code ec;
  fs::remove_all(dir, ec);
  EXPECT_FALSE(out.empty()) << kind;
  return out;
}

int robot_of(const Log& l) {
  const std::string r = l.meta.count("robot") ? l.meta.at("robot") : "";
  EXPECT_TRUE(r == "virtual-epuck2-1" || r == "virtual-epuck2-2") << l.name << ": robot '" << r << "'";
  return r == "virtual-epuck2-2" ? 1 : 0;
}

constexpr unsigned long kSeeds[] = {20241121UL, 77UL};

// ---- ground: value = offset_s + gain_s x grey (robot 2: gains x 1.02, its centre sensor's 975),
// N(0, 5), rounded and clamped to [0, 1023] ----
TEST(GeneratorTruth, GroundIsOffsetPlusGainTimesGrey) {
  const double offset[3] = {62, 48, 75}, gain[3] = {905, 940, 870};
  for (unsigned long seed : kSeeds) {
    const std::vector<Log> logs = generate("ground", seed);
    ASSERT_EQ(logs.size(), 2u);
    std::vector<double> residuals;
    for (const Log& l : logs) {
      const int r = robot_of(l);
      std::map<std::pair<int, long>, std::vector<double>> at;  // (sensor, grey x 1000)
      for (const auto& row : l.rows)
        at[{static_cast<int>(row[l.col("sensor")]), std::lround(row[l.col("grey")] * 1000)}].push_back(row[l.col("value")]);
      EXPECT_EQ(at.size(), 33u) << l.name << ": 3 sensors x 11 grey levels";
      for (const auto& [key, v] : at) {
        const int s = key.first;
        const double grey = static_cast<double>(key.second) / 1000.0;
        const double g = r == 1 && s == 1 ? 975.0 : gain[s] * (r == 1 ? 1.02 : 1.0);
        const double truth = std::clamp(offset[s] + g * grey, 0.0, 1023.0);
        EXPECT_EQ(v.size(), 40u) << l.name;
        // The median of 40 readings of sd 5: within 3 counts (about 3.8 of its standard errors).
        EXPECT_NEAR(median(v), truth, 3.0) << l.name << " sensor " << s << " grey " << grey << " seed " << seed;
        if (truth < 1000)
          for (double x : v) residuals.push_back(x - (offset[s] + g * grey));
      }
    }
    EXPECT_NEAR(mad_sd(residuals), std::sqrt(25.0 + 1.0 / 12.0), 0.5) << "noise N(0, 5) and the rounding, seed " << seed;
  }
}

// ---- light: reading = (1 - g_s (gamma_r I / d)^2) 4095 - 12, N(0, 15), rounded and clamped;
// gamma 0.075 m (robot 2: 0.99 of it), g_0 = 1.00, g_7 = 0.94; sensors 0 and 7; 24 readings a
// distance (48 at the rail probe) ----
TEST(GeneratorTruth, LightIsEq2WithTheSensorsGainsAndTheStrayLight) {
  for (unsigned long seed : kSeeds) {
    const std::vector<Log> logs = generate("light", seed);
    ASSERT_EQ(logs.size(), 8u);
    std::vector<double> residuals;
    std::map<double, int> files_of_intensity;
    for (const Log& l : logs) {
      const int r = robot_of(l);
      const double gamma = 0.075 * (r == 1 ? 0.99 : 1.0);
      std::map<std::tuple<int, double, long>, std::vector<double>> at;  // (sensor, I, d in um)
      for (const auto& row : l.rows)
        at[{static_cast<int>(row[l.col("sensor")]), row[l.col("intensity")], std::lround(row[l.col("distance_m")] * 1e6)}].push_back(
            row[l.col("value")]);
      for (const auto& [key, v] : at) {
        const auto [s, intensity, d_um] = key;
        ++files_of_intensity[intensity];
        ASSERT_TRUE(s == 0 || s == 7) << l.name << ": sensor " << s;
        const double d = static_cast<double>(d_um) / 1e6;
        const double x = gamma * intensity / d;
        const double latent = (1.0 - (s == 0 ? 1.0 : 0.94) * x * x) * 4095.0 - 12.0;
        // The median of 24 readings of sd 15: within 16 counts (its standard error is
        // 1.2533 x 15 / sqrt 24 = 3.8: 4.2 of them, over 288 settings); the stray light's 12 counts
        // are checked on the mean of all residuals below.
        EXPECT_NEAR(median(v), std::clamp(latent, 0.0, 4095.0), 16.0) << l.name << " sensor " << s << " d " << d << " seed " << seed;
        EXPECT_TRUE(v.size() == 24u || v.size() == 48u) << l.name;
        if (latent > 60 && latent < 4035)
          for (double y : v) residuals.push_back(y - latent);
      }
    }
    EXPECT_EQ(files_of_intensity.size(), 4u);
    EXPECT_NEAR(mad_sd(residuals), 15.0, 1.0) << "noise N(0, 15), seed " << seed;
    // Their mean (the wild readings, 0.2 %, left out beyond 6 sd): 0 within 1.5 counts (about 6
    // standard errors of the mean of some 2000 readings; the stray light is 12).
    double mean = 0;
    std::size_t n = 0;
    for (double e : residuals)
      if (std::abs(e) < 90) {
        mean += e;
        ++n;
      }
    EXPECT_NEAR(mean / static_cast<double>(n), 0.0, 1.5) << "seed " << seed;
  }
}

// ---- camera: a pinhole of 30.8 deg horizontal field of view, centre (81.6, 57.9) (robot 2's
// column 82.1), square pixels: px = cx - 80 (lateral / forward) / tan(15.4 deg), py = cy - 80
// (vertical / forward) / tan(15.4 deg); jitter N(0, 0.5 px), rounded; 3 frames a position ----
TEST(GeneratorTruth, CameraIsThePinholeOfTheReadme) {
  const double pi = std::acos(-1.0), t = std::tan(15.4 * pi / 180.0);
  for (unsigned long seed : kSeeds) {
    const std::vector<Log> logs = generate("camera", seed);
    ASSERT_EQ(logs.size(), 2u);
    for (const Log& l : logs) {
      const int r = robot_of(l);
      const double cx = r == 1 ? 82.1 : 81.6, cy = 57.9;
      EXPECT_EQ(l.rows.size(), 405u) << l.name;
      std::size_t far = 0;
      std::vector<double> dx;
      for (const auto& row : l.rows) {
        const double f = row[l.col("forward_m")];
        const double px = cx - 80.0 * row[l.col("lateral_m")] / f / t, py = cy - 80.0 * row[l.col("vertical_m")] / f / t;
        if (std::abs(row[l.col("px")] - px) > 2.5 || std::abs(row[l.col("py")] - py) > 2.5) {
          ++far;  // a wild frame (1 %)
          continue;
        }
        dx.push_back(row[l.col("px")] - px);
      }
      EXPECT_LE(far, 12u) << l.name << ": more frames off the pinhole than the README's 1 % wild ones, seed " << seed;
      double mean = 0;
      for (double v : dx) mean += v;
      mean /= static_cast<double>(dx.size());
      // The centre to 0.1 px (the mean of about 400 jitters of sd 0.58: se 0.03).
      EXPECT_NEAR(mean, 0.0, 0.1) << l.name << " seed " << seed;
    }
  }
}

// ---- proximity: readings / 4095 below the envelope gain_r x clamp01(197.8633 d^2 - 30.47182 d +
// 1.011635) (0 beyond 0.05 m; robot 2's gain 0.97) by |N(0,1)| (0.012 + 0.06 envelope), plus
// N(0, 3 counts); at 0 mm the rail 4095 + N(0, 3), clipped ----
TEST(GeneratorTruth, ProximityLiesBelowTheEnvelopeByTheReadmesScatter) {
  const double e_abs = std::sqrt(2.0 / std::acos(-1.0));  // E|N(0,1)|
  for (unsigned long seed : kSeeds) {
    const std::vector<Log> logs = generate("proximity", seed);
    ASSERT_EQ(logs.size(), 2u);
    for (const Log& l : logs) {
      const int r = robot_of(l);
      std::map<long, std::vector<double>> at;  // d in um
      for (const auto& row : l.rows) at[std::lround(row[l.col("distance_m")] * 1e6)].push_back(row[l.col("value")] / 4095.0);
      EXPECT_EQ(at.size(), 13u) << l.name << ": 0, 5, ..., 60 mm";
      for (const auto& [d_um, v] : at) {
        const double d = static_cast<double>(d_um) / 1e6;
        EXPECT_EQ(v.size(), 360u) << l.name;
        if (d_um == 0) {
          EXPECT_GE(median(v), 4092.0 / 4095.0) << l.name << ": the rail at 0 mm";
          continue;
        }
        const double env = (r == 1 ? 0.97 : 1.0) * (d > 0.05 ? 0.0 : std::clamp(197.8633 * d * d - 30.47182 * d + 1.011635, 0.0, 1.0));
        // The median of env - |N| w, w = 0.012 + 0.06 env (the envelope's or the robot's: 0.1 %
        // apart): env - 0.6745 w; its standard error about 1.25 x 0.6 w / sqrt(360).
        const double w = 0.012 + 0.06 * env;
        if (env > 0.03) {
          EXPECT_NEAR(median(v), env - 0.6745 * w, 0.004) << l.name << " d " << d << " seed " << seed;
          double mean = 0;
          std::vector<double> kept;
          for (double x : v)
            if (x <= env + 0.01 && x >= env - 6 * w) kept.push_back(x);  // the wild readings left out
          for (double x : kept) mean += x;
          mean /= static_cast<double>(kept.size());
          EXPECT_NEAR(mean, env - e_abs * w, 0.004) << l.name << " d " << d << " seed " << seed;
          EXPECT_GE(kept.size(), 350u);
        } else {
          EXPECT_LE(median(v), env + 4.0 / 4095.0) << l.name << " d " << d;
        }
      }
    }
  }
}

// ---- drive: commands converted to whole steps/s with 7763.656 steps/m, capped at 1100 steps/s;
// the encoders count the steps sent; the ToF reads 0.985 x distance + 9 mm, N(0, 2 mm + 3 mm/m);
// the obstacle 0.3 m ahead (the log's header); rows every 0.1 s +- 0.02 s ----
TEST(GeneratorTruth, DriveEncodersCountTheCommandedStepsAndTheToFIsScaledAndOffset) {
  for (unsigned long seed : kSeeds) {
    const std::vector<Log> logs = generate("drive", seed);
    ASSERT_EQ(logs.size(), 19u);
    std::size_t moving_runs = 0;
    std::vector<double> standing;  // ToF minus the truth, standing before the first command
    for (const Log& l : logs) {
      robot_of(l);
      ASSERT_TRUE(l.meta.count("obstacle_distance_m")) << l.name;
      const double obstacle_mm = std::strtod(l.meta.at("obstacle_distance_m").c_str(), nullptr) * 1000.0;
      const std::size_t t = l.col("time_s"), cl = l.col("left_speed_cm_s"), sl = l.col("left_steps"), sr = l.col("right_steps"),
                        tof = l.col("tof_mm");
      for (std::size_t i = 1; i < l.rows.size(); ++i) {
        const double dt = l.rows[i][t] - l.rows[i - 1][t];
        // (the times are logged to the millisecond: each of the two ends rounded by up to 0.5 ms)
        EXPECT_GE(dt, 0.08 - 0.001 - 1e-9) << l.name << " row " << i;
        EXPECT_LE(dt, 0.12 + 0.001 + 1e-9) << l.name << " row " << i;
      }
      // Standing before the first command: the ToF at the obstacle.
      std::size_t first = 0;
      while (first < l.rows.size() && l.rows[first][cl] == 0) ++first;
      const double truth = std::clamp(0.985 * obstacle_mm + 9.0, 20.0, 2000.0);
      for (std::size_t i = 0; i < first && i < l.rows.size(); ++i) {
        EXPECT_EQ(l.rows[i][sl], 0.0);
        if (l.rows[i][tof] < 8190 && truth > 25) standing.push_back((l.rows[i][tof] - truth) / (2.0 + 3.0 * obstacle_mm / 1000.0));
      }
      if (first == l.rows.size()) continue;  // the static run
      ++moving_runs;
      // The first command's rate, whole steps/s, capped: the encoders count it from the row it was sent.
      const double cmd = l.rows[first][cl];
      const double rate = std::min(1100.0, std::round(std::abs(cmd) / 100.0 * 7763.656)) * (cmd < 0 ? -1 : 1);
      for (std::size_t i = first; i < l.rows.size() && l.rows[i][cl] == cmd; ++i) {
        const double want = rate * (l.rows[i][t] - l.rows[first][t]);
        EXPECT_NEAR(l.rows[i][sl], want, 1.0 + 1e-6) << l.name << " row " << i << " seed " << seed;
        EXPECT_EQ(l.rows[i][sl], l.rows[i][sr]) << l.name << ": both wheels alike";
      }
    }
    EXPECT_EQ(moving_runs, 18u);
    ASSERT_GE(standing.size(), 150u);
    double mean = 0, ss = 0;
    for (double z : standing) mean += z;
    mean /= static_cast<double>(standing.size());
    for (double z : standing) ss += (z - mean) * (z - mean);
    // In units of the README's noise sd: mean 0 (+- 0.25, whole-mm rounding included), sd 1 (+- 15 %).
    EXPECT_NEAR(mean, 0.0, 0.25) << "seed " << seed;
    EXPECT_NEAR(std::sqrt(ss / static_cast<double>(standing.size() - 1)), 1.0, 0.15) << "seed " << seed;
  }
}

}  // namespace
}  // namespace test_generator_truth_cpp
