// The reading noise every calibration measures (lib/calibrate reading_noise.hpp): the pooled
// within-group sd on hand-computed data, and on the virtual robot's logs recorded with a known
// noise (virtual_robot/sensor_truth.hpp: each kind's noise_raw / pixel_noise_px / tof_noise_mm is
// the sd of a seeded Gaussian added before the reading is rounded to a whole count) the calibrated
// sd within 10 % of that truth. The truth of a rounded reading is sqrt(sd^2 + 1/12): the rounding
// to whole counts adds a uniform error of variance 1/12 (Sheppard).
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <string>
#include <vector>

#include "epuck2/calibrate/reading_noise.hpp"
#include "epuck2/calibrate/sensors.hpp"
#include "epuck2/logs/log.hpp"
#include "epuck2/virtual_robot/sensor_truth.hpp"

namespace calibrate = epuck2::calibrate;
namespace vr = epuck2::virtual_robot;
using epuck2::logs::Kind;

namespace {

std::vector<epuck2::logs::Log> parse_noise(const std::vector<vr::GeneratedFile>& files, Kind kind) {
  std::vector<epuck2::logs::Log> logs;
  for (const auto& f : files) logs.push_back(epuck2::logs::parse_log(f.content, f.name, kind));
  return logs;
}

/// The truth of a reading rounded to a whole unit: the Gaussian's variance plus the rounding's 1/12.
double rounded(double sd) { return std::sqrt(sd * sd + 1.0 / 12.0); }

constexpr double kTolerance = 0.10;  // the calibrated sd within 10 % of the truth

const std::vector<std::uint64_t> kNoiseSeeds{1, 2, 3};

}  // namespace

// ----- The estimator on numbers worked by hand -----------------------------------------------

TEST(PooledReplicateSd, HandComputed) {
  // Group 0: 1, 2, 3 (mean 2, squares 1 + 0 + 1 = 2, 2 dof); group 1: 10, 14 (mean 12, squares
  // 4 + 4 = 8, 1 dof); group 2: a single reading (no dof). Pooled: sqrt(10 / 3).
  const std::vector<double> v{1, 2, 3, 10, 14, 7};
  const std::vector<int> g{0, 0, 0, 1, 1, 2};
  const std::vector<bool> rail(v.size(), false);
  const calibrate::PooledSd p = calibrate::pooled_replicate_sd(v, g, rail, 0.0);
  EXPECT_NEAR(p.sd, std::sqrt(10.0 / 3.0), 1e-12);
  EXPECT_EQ(p.n, 5u);
  EXPECT_EQ(p.groups, 2u);
}

TEST(PooledReplicateSd, GroupsOnARailAndWildReadingsAreLeftOut) {
  // Group 0 (five readings, one on the rail 0): left out whole, its spread is clipped. Group 1:
  // 100, 101, 99, 100, 100, 101, 99, 100 and one wild 400 (far beyond 8 robust sd): left out.
  // What remains: group 1 without the wild one, squares 0+1+1+0+0+1+1+0 = 4 over 7 dof.
  std::vector<double> v{0, 3, 5, 2, 4, 100, 101, 99, 100, 100, 101, 99, 100, 400};
  std::vector<int> g{0, 0, 0, 0, 0, 1, 1, 1, 1, 1, 1, 1, 1, 1};
  std::vector<bool> rail(v.size(), false);
  rail[0] = true;
  const calibrate::PooledSd p = calibrate::pooled_replicate_sd(v, g, rail, 0.0);
  EXPECT_NEAR(p.sd, std::sqrt(4.0 / 7.0), 1e-12);
  EXPECT_EQ(p.n, 8u);
  EXPECT_EQ(p.wild, 1u);
  EXPECT_EQ(p.railed_groups, 1u);
}

TEST(PooledReplicateSd, AFewReplicatesLoseAReadingBeyondFourPooledSd) {
  // 20 groups of 3 readings {0, 1, 0} (squares 2/3 each) and one group {50, 50, 53} (squares 6):
  // the first pass pools sqrt((40/3 + 6) / 42) = 0.678; 53 lies 3 from its group's median 50,
  // 4.4 of those (the 8-robust-sd rule, with its floor of 0.5 here, calls wild only beyond 4):
  // the second pass leaves it out.
  std::vector<double> v;
  std::vector<int> g;
  for (int k = 0; k < 20; ++k)
    for (double x : {0.0, 1.0, 0.0}) v.push_back(x), g.push_back(k);
  for (double x : {50.0, 50.0, 53.0}) v.push_back(x), g.push_back(20);
  const std::vector<bool> rail(v.size(), false);
  const calibrate::PooledSd p = calibrate::pooled_replicate_sd(v, g, rail, 0.5);
  // Without it: 20 groups of squares 2/3 and {50, 50} with none, over 40 + 1 dof.
  EXPECT_NEAR(p.sd, std::sqrt(20 * (2.0 / 3.0) / 41.0), 1e-12);
  EXPECT_EQ(p.outliers, 1u);
  // Without the second pass the 53 stays: squares 6 more, 42 dof.
  EXPECT_NEAR(calibrate::pooled_replicate_sd(v, g, rail, 0.5, 0.0).sd, std::sqrt((20 * (2.0 / 3.0) + 6.0) / 42.0), 1e-12);
}

TEST(ReadingNoise, UniformLevelHasTheSameVariance) {
  calibrate::ReadingNoise n;
  n.sd = 41.0;
  n.argos_scale = 4095.0;
  // Uniform on [-L, L] x 4095 has variance (4095 L)^2 / 3 = 41^2.
  const double l = n.argos_uniform_level();
  EXPECT_NEAR(4095.0 * l / std::sqrt(3.0), 41.0, 1e-12);
  n.argos_scale = 0;
  EXPECT_TRUE(std::isnan(n.argos_uniform_level()));
}

// ----- Each calibration on logs with a known reading noise -----------------------------------

TEST(CalibratedReadingNoise, ProximityFromItsReplicates) {
  for (std::uint64_t seed : kNoiseSeeds) {
    // The readings scatter only by the electronic noise (no scatter below the envelope), 40 counts.
    vr::ProximityTruth truth;
    truth.scatter_floor = 0;
    truth.scatter_slope = 0;
    truth.noise_raw = 40.0;
    const auto f = calibrate::fit_proximity(parse_noise(vr::proximity_logs(truth, seed), Kind::proximity));
    const calibrate::ReadingNoise& n = f.noise;
    EXPECT_EQ(n.channel, "proximity");
    EXPECT_EQ(n.unit, "counts");
    EXPECT_EQ(n.from, "replicates");
    EXPECT_NEAR(n.sd, rounded(40.0), kTolerance * rounded(40.0)) << "seed " << seed;
    ASSERT_EQ(n.per_sensor_sd.size(), 8u);
    EXPECT_EQ(n.per_sensor_sd[truth.sensor], n.sd);  // the logs hold one sensor
    EXPECT_EQ(n.per_sensor_n[truth.sensor], n.n);
    EXPECT_EQ(n.per_sensor_n[3], 0u);
    // 0 mm saturates (half the readings on 4095) and 50 mm detects nothing (readings on 0): those
    // groups are left out, 9 distances x 2 robots remain.
    EXPECT_EQ(n.groups, 18u) << "seed " << seed;
  }
}

TEST(CalibratedReadingNoise, LightFromItsReplicatesPerSensor) {
  for (std::uint64_t seed : kNoiseSeeds) {
    vr::LightTruth truth;  // 15 counts, two sensors, two robots, rails and wild readings
    const auto f = calibrate::fit_light(parse_noise(vr::light_logs(truth, seed), Kind::light));
    const calibrate::ReadingNoise& n = f.noise;
    EXPECT_EQ(n.unit, "counts");
    EXPECT_EQ(n.from, "replicates");
    EXPECT_NEAR(n.sd, rounded(truth.noise_raw), kTolerance * rounded(truth.noise_raw)) << "seed " << seed;
    ASSERT_EQ(n.per_sensor_sd.size(), 8u);
    for (int sensor : truth.sensors) {
      EXPECT_GT(n.per_sensor_n[static_cast<std::size_t>(sensor)], 500u);
      EXPECT_NEAR(n.per_sensor_sd[static_cast<std::size_t>(sensor)], rounded(truth.noise_raw), kTolerance * rounded(truth.noise_raw));
    }
  }
}

TEST(CalibratedReadingNoise, GroundFromItsReplicatesPerSensor) {
  for (std::uint64_t seed : kNoiseSeeds) {
    for (double sd : {5.0, 20.0}) {
      vr::GroundTruth truth;
      truth.noise_raw = sd;
      const auto f = calibrate::fit_ground(parse_noise(vr::ground_logs(truth, seed), Kind::ground));
      const calibrate::ReadingNoise& n = f.noise;
      EXPECT_EQ(n.unit, "counts");
      EXPECT_EQ(n.from, "replicates");
      EXPECT_NEAR(n.sd, rounded(sd), kTolerance * rounded(sd)) << "seed " << seed << " sd " << sd;
      ASSERT_EQ(n.per_sensor_sd.size(), 3u);
      for (std::size_t k = 0; k < 3; ++k) {
        EXPECT_GT(n.per_sensor_n[k], 500u);
        EXPECT_NEAR(n.per_sensor_sd[k], rounded(sd), kTolerance * rounded(sd)) << "sensor " << k;
      }
    }
  }
}

TEST(CalibratedReadingNoise, CameraFromItsFrames) {
  for (std::uint64_t seed : kNoiseSeeds) {
    for (double sd : {0.5, 1.5}) {
      vr::CameraTruth truth;  // 3 frames per LED position, 1 % wild frames
      truth.pixel_noise_px = sd;
      const auto f = calibrate::fit_camera(parse_noise(vr::camera_logs(truth, seed), Kind::camera));
      const calibrate::ReadingNoise& n = f.noise;
      EXPECT_EQ(n.unit, "px");
      EXPECT_EQ(n.from, "replicates");
      EXPECT_TRUE(n.per_sensor_sd.empty());
      EXPECT_NEAR(n.sd, rounded(sd), kTolerance * rounded(sd)) << "seed " << seed << " sd " << sd;
    }
  }
}

TEST(CalibratedReadingNoise, TofFromTheReadingsBeforeTheRobotMoves) {
  for (std::uint64_t seed : kNoiseSeeds) {
    vr::DriveTruth truth;
    truth.tof_noise_mm = 4.0;  // the same at every range
    truth.tof_noise_per_m_mm = 0.0;
    const auto f = calibrate::fit_drive(parse_noise(vr::drive_logs(truth, seed), Kind::drive));
    const calibrate::ReadingNoise& n = f.tof_noise;
    EXPECT_EQ(n.unit, "mm");
    EXPECT_EQ(n.from, "replicates");
    EXPECT_GE(n.n, calibrate::kMinStillReadings);
    EXPECT_NEAR(n.sd, rounded(4.0), kTolerance * rounded(4.0)) << "seed " << seed;
    // The encoders have no replicates that vary: their noise is the steps fit's residual sd.
    EXPECT_EQ(f.encoder_noise.unit, "steps");
    EXPECT_EQ(f.encoder_noise.from, "residuals");
    EXPECT_EQ(f.encoder_noise.sd, f.steps.noise_sd);
  }
}

TEST(CalibratedReadingNoise, WithoutReplicatesTheResidualsAreTheNoise) {
  // One reading per distance: nothing repeats, the means fit's residuals (normalised, x 4095)
  // are the reading noise.
  vr::ProximityTruth truth;
  truth.scatter_floor = 0;
  truth.scatter_slope = 0;
  truth.noise_raw = 40.0;
  truth.readings_per_distance = 1;
  truth.wild_fraction = 0;
  truth.distances_m.clear();
  for (int k = 0; k <= 120; ++k) truth.distances_m.push_back(0.005 + 0.0003 * k);  // 5 .. 41 mm
  truth.saturated_distances = 0;
  // One robot's log (the fit pools the distances of every log: two robots' readings would be a
  // mean of two).
  const auto f = calibrate::fit_proximity({parse_noise(vr::proximity_logs(truth, 7), Kind::proximity).at(0)});
  ASSERT_TRUE(f.means.usable);
  EXPECT_EQ(f.noise.from, "residuals");
  EXPECT_NEAR(f.noise.sd, f.means.noise_sd * 4095.0, 1e-9);
  EXPECT_NEAR(f.noise.sd, rounded(40.0), 0.15 * rounded(40.0));
  EXPECT_EQ(f.noise.per_sensor_n, std::vector<std::size_t>(8, 0));
}
