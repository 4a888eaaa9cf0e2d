// Sensor fits (lib/fit sensors.hpp) recover the virtual robot's known truth
// (virtual_robot/sensor_truth.hpp) from the logs it records, within named tolerances; and the
// coefficient loaders read back what the CLI writes.
#include <gtest/gtest.h>

#include "epuck2/coefficients/model_file.hpp"

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <unistd.h>

#include "epuck2/calibrate/sensors.hpp"
#include "epuck2/logs/log.hpp"
#include "epuck2/virtual_robot/sensor_truth.hpp"

namespace fit = epuck2::fit;
namespace calibrate = epuck2::calibrate;
namespace coefficients = epuck2::coefficients;
namespace vr = epuck2::virtual_robot;
namespace s = epuck2::models::sensors;
using epuck2::logs::Kind;

namespace {

std::vector<epuck2::logs::Log> parse_fits(const std::vector<vr::GeneratedFile>& files, Kind kind) {
  std::vector<epuck2::logs::Log> logs;
  for (const auto& f : files) logs.push_back(epuck2::logs::parse_log(f.content, f.name, kind));
  return logs;
}

const std::vector<std::uint64_t> kFitsSeeds{1, 2, 3};

}  // namespace

// ----- Proximity -----------------------------------------------------------------------------

// The maxima sit on the envelope up to the symmetric noise (3 counts, the max of 720 draws about
// +2.5 sigma = 8 counts = 0.002) and the quantisation: the fitted curve stays within this of the
// envelope over the fitted range.
constexpr double kProximityEnvelopeTolerance = 0.006;

TEST(ProximityFit, MaximaRecoverTheEnvelopeAndMeansLieBelow) {
  for (std::uint64_t seed : kFitsSeeds) {
    vr::ProximityTruth truth;
    // This fit takes the maxima per distance: a wild reading (uniform over 0..4095) is the maximum
    // wherever it lands above the envelope. The plain fit is checked without them.
    truth.wild_fraction = 0;
    const auto f = calibrate::fit_proximity(parse_fits(vr::proximity_logs(truth, seed), Kind::proximity));
    ASSERT_TRUE(f.maxima.usable) << f.maxima.message;
    ASSERT_TRUE(f.means.usable) << f.means.message;
    const double m[3] = {f.maxima.value("a"), f.maxima.value("b"), f.maxima.value("c")};
    const double mm[3] = {f.means.value("a"), f.means.value("b"), f.means.value("c")};
    for (double d = 0.005; d <= 0.045; d += 0.0025) {
      const double envelope = s::proximity_response(truth.envelope, d);
      EXPECT_NEAR(s::proximity_polynomial(m, d), envelope, kProximityEnvelopeTolerance) << "seed " << seed << " d " << d;
      EXPECT_LT(s::proximity_polynomial(mm, d), s::proximity_polynomial(m, d)) << "means below maxima at " << d;
    }
    // The points: 0.005..0.045 m inside the rails; 0 m saturated (a lower bound on the curve) and
    // 0.05 m where nothing is detected (an upper bound) enter censored; beyond is out of range.
    EXPECT_EQ(f.maxima.exact, 9u);
    EXPECT_EQ(f.maxima.censored_above, 1u);
    EXPECT_EQ(f.maxima.censored_below, 1u);
    // The plug-in's polynomial is the envelope itself: its MSE on the maxima is small, on the means large.
    EXPECT_LT(f.plugin_mse_maxima, kProximityEnvelopeTolerance * kProximityEnvelopeTolerance);
    EXPECT_GT(f.plugin_mse_means, 10 * f.means.mse);
    EXPECT_GT(f.epuck1_mse_maxima, f.maxima.mse);
  }
}

// ----- Light ---------------------------------------------------------------------------------

// Per sensor, the fit should find gamma sqrt(gain): the stray light (12 counts) biases the
// normalised response by 0.003, which moves gamma by well under 1 %.
constexpr double kFitsLightGammaRelTolerance = 0.01;

TEST(LightFit, RecoversGammaPerSensor) {
  for (std::uint64_t seed : kFitsSeeds) {
    vr::LightTruth truth;
    // The plain least-squares fit is checked on one robot without wild readings: robot 2's gamma is
    // 1 % smaller (pooled, the per-sensor gammas move by 0.5 %) and a wild reading weighs as much
    // as the 2000 others.
    truth.wild_fraction = 0;
    truth.robot_gamma_scale = {1.0};
    const auto f = calibrate::fit_light(parse_fits(vr::light_logs(truth, seed), Kind::light));
    ASSERT_TRUE(f.gamma.usable) << f.gamma.message;
    ASSERT_EQ(f.sensors, (std::vector<int>{0, 7}));
    for (std::size_t j = 0; j < 2; ++j) {
      const double expected = truth.gamma_m * std::sqrt(truth.sensor_gain[j]);
      EXPECT_NEAR(f.gamma_per_sensor[j].value("gamma"), expected, kFitsLightGammaRelTolerance * expected) << "seed " << seed;
    }
    // The pooled gamma lies between the two sensors'.
    EXPECT_GT(f.gamma.value("gamma"), f.gamma_per_sensor[1].value("gamma"));
    EXPECT_LT(f.gamma.value("gamma"), f.gamma_per_sensor[0].value("gamma"));
    EXPECT_GT(f.censored, 0u);  // intensity 2 at 10 cm saturates
    EXPECT_GT(f.gamma.std_error("gamma"), 0.0);
  }
}

// ----- Ground --------------------------------------------------------------------------------

// 440 readings per sensor with 5-count noise: the standard error of the gain is about 0.4 count
// and of the offset 0.3; 2.5 counts is over 5 standard errors.
constexpr double kGroundTolerance_raw = 2.5;

TEST(GroundFit, RecoversGainAndOffsetPerSensor) {
  for (std::uint64_t seed : kFitsSeeds) {
    vr::GroundTruth truth;
    // The plain least-squares fit is checked on one robot without wild readings: robot 2's gains
    // are 2 % higher (pooled, 9 counts) and a wild reading moves a line by several counts.
    truth.wild_fraction = 0;
    truth.robot_gain_scale = {1.0};
    const auto f = calibrate::fit_ground(parse_fits(vr::ground_logs(truth, seed), Kind::ground));
    for (std::size_t k = 0; k < 3; ++k) {
      ASSERT_TRUE(f.sensors[k].usable) << f.sensors[k].message;
      EXPECT_NEAR(f.sensors[k].value("gain"), truth.gain_raw[k], kGroundTolerance_raw) << "seed " << seed << " sensor " << k;
      EXPECT_NEAR(f.sensors[k].value("offset"), truth.offset_raw[k], kGroundTolerance_raw) << "seed " << seed << " sensor " << k;
      EXPECT_LT(f.sensors[k].std_error("gain"), kGroundTolerance_raw / 3);
      // The noise variance is 25 counts^2, plus 1/12 for the rounding.
      EXPECT_NEAR(f.sensors[k].mse, truth.noise_raw * truth.noise_raw + 1.0 / 12, 5.0);
      EXPECT_GT(f.plugin_mse[k], 20 * f.sensors[k].mse);  // 760..2400 against 25 counts^2
    }
  }
}

// ----- Camera --------------------------------------------------------------------------------

// Pixel noise 0.5 px then rounding over ~400 points: the field of view's standard error is
// about 0.02 deg and the centre's 0.04 px.
constexpr double kCameraFovTolerance_deg = 0.1;
constexpr double kCameraCentreTolerance_px = 0.25;

TEST(CameraFit, RecoversFieldOfViewAndCentre) {
  for (std::uint64_t seed : kFitsSeeds) {
    vr::CameraTruth truth;
    // The plain least-squares fit is checked on one robot without centroids jumping to reflections
    // (robot 2's optical axis is 0.5 px to the right; a jump costs up to 80 px).
    truth.wild_fraction = 0;
    truth.robot_cx_shift_px = {0.0};
    const auto f = calibrate::fit_camera(parse_fits(vr::camera_logs(truth, seed), Kind::camera));
    ASSERT_TRUE(f.result.usable) << f.result.message;
    EXPECT_NEAR(f.result.value("fov_deg"), truth.horizontal_fov_deg, kCameraFovTolerance_deg) << "seed " << seed;
    EXPECT_NEAR(f.result.value("cx_px"), truth.cx_px, kCameraCentreTolerance_px) << "seed " << seed;
    EXPECT_NEAR(f.result.value("cy_px"), truth.cy_px, kCameraCentreTolerance_px) << "seed " << seed;
    EXPECT_GT(f.plugin_mse, 4 * f.result.mse);
    EXPECT_GT(f.table4_points, 0u);
  }
}

// ----- Drive ---------------------------------------------------------------------------------

// The host rounds each command to whole steps/s (2.5 cm/s = 194.09 -> 194 steps/s: -0.05 %),
// which the fit to commanded distance absorbs: 0.1 % covers it.
constexpr double kStepsPerMetreRelTolerance = 0.001;
constexpr double kTofScaleTolerance = 0.005;
constexpr double kTofOffsetTolerance_mm = 1.5;
constexpr double kSlipTimeConstantRelTolerance = 0.25;

TEST(DriveFit, RecoversStepsPerMetreTofAndSlip) {
  vr::DriveTruth truth;
  // The reader rejects ToF 8190 today (out of range: the far run and the dropouts), and the plain
  // least-squares fit is checked on one robot without wild ToF readings (robot 2's wheels move its
  // ToF scale by 0.5 %; a wild reading costs up to 2 m).
  truth.tof_dropout_fraction = 0;
  truth.far_run_speed_cm_s = 0;
  truth.tof_wild_fraction = 0;
  truth.steps_per_m_scale = {1.0};
  const auto f = calibrate::fit_drive(parse_fits(vr::drive_logs(truth, 1), Kind::drive));
  ASSERT_TRUE(f.steps.usable) << f.steps.message;
  ASSERT_TRUE(f.tof.usable) << f.tof.message;
  EXPECT_NEAR(f.steps.value("steps_per_m"), truth.steps_per_m, kStepsPerMetreRelTolerance * truth.steps_per_m);
  // The two 15 cm/s runs exceed 1100 steps/s: their commands are taken as the limit.
  EXPECT_EQ(f.over_limit_runs.size(), 2u);
  EXPECT_GT(f.capped_rows, 0u);
  EXPECT_NEAR(f.tof.value("tof_scale"), truth.tof_scale, kTofScaleTolerance);
  EXPECT_NEAR(f.tof.value("tof_offset_mm"), truth.tof_offset_mm, kTofOffsetTolerance_mm);
  EXPECT_NEAR(f.tof.value("slip_time_constant_s"), truth.slip_time_constant_s,
              kSlipTimeConstantRelTolerance * truth.slip_time_constant_s);
  EXPECT_GT(f.plugin_tof_mse, 4 * f.tof.mse);
}

TEST(DriveFit, UnwrapsTheSixteenBitRegisters) {
  // A run long enough to wrap: 6 m at 10 cm/s = 46582 steps (truth without noise in the counts).
  vr::DriveTruth truth;
  truth.speeds_cm_s = {10.0};
  truth.away_travel_m = 6.0;
  truth.toward_travel_m = 0.1;
  truth.obstacle_distance_m = 0.3;
  // The reader rejects ToF 8190 today (out of range: the far run, the dropouts, and this 6 m run
  // beyond the ToF's 2.1 m).
  truth.tof_dropout_fraction = 0;
  truth.far_run_speed_cm_s = 0;
  truth.tof_range_m = 1e9;
  const auto logs = parse_fits(vr::drive_logs(truth, 4), Kind::drive);
  const calibrate::DriveRun away = calibrate::drive_run_from_log(logs.at(1));
  EXPECT_LT(away.steps.back(), -40000.0);  // past -32768 without a jump
  for (std::size_t k = 1; k < away.steps.size(); ++k) EXPECT_LT(std::abs(away.steps[k] - away.steps[k - 1]), 200.0);
}

// ----- Coefficient files ---------------------------------------------------------------------

TEST(SensorCoefficientFiles, LoadBackWhatTheCliWrites) {
  namespace fs = std::filesystem;
  const fs::path dir = fs::temp_directory_path() / ("epuck2_sensor_coeffs_" + std::to_string(::getpid()));
  fs::create_directories(dir);
  auto write = [&](const std::string& name, const std::string& text) {
    std::ofstream(dir / name) << text;
    return (dir / name).string();
  };
  const auto p = coefficients::read_model_file<s::ProximityModel>(write("p.json", R"({"kind":"proximity","parameters":{"a":1.5,"b":-2,"c":0.9}})"));
  EXPECT_EQ(p.base.a_per_m2, 1.5);
  EXPECT_EQ(p.base.b_per_m, -2);
  EXPECT_EQ(p.base.c, 0.9);
  EXPECT_EQ(coefficients::read_model_file<s::LightModel>(write("l.json", R"({"kind":"light","parameters":{"gamma":0.07}})")).base.gamma_m, 0.07);
  const auto g = coefficients::read_model_file<s::GroundModel>(
      write("g.json", R"({"kind":"ground","parameters":{"gain":[900,910,920],"offset":[1,2,3]}})"));
  EXPECT_EQ(g.sensors[2].gain_raw, 920);
  EXPECT_EQ(g.sensors[1].offset_raw, 2);
  const auto c = coefficients::read_model_file<s::CameraModel>(write("c.json", R"({"kind":"camera","parameters":{"fov_deg":30,"cx_px":81,"cy_px":59}})"));
  EXPECT_NEAR(c.base.horizontal_fov_rad, s::deg_to_rad(30), 1e-15);
  const auto d = coefficients::read_model_file<s::DriveModel>(
      write("d.json", R"({"kind":"drive","parameters":{"steps_per_m":7700,"tof_scale":0.99,"tof_offset_mm":5}})"));
  EXPECT_EQ(d.steps_per_m, 7700);
  EXPECT_EQ(d.effects.tof_offset.offset_mm, 5);
  EXPECT_EQ(d.effects.tof_scale.k, 0.99);
  // Missing key, wrong kind: errors naming the file.
  try {
    coefficients::read_model_file<s::LightModel>(write("bad.json", R"({"kind":"light","parameters":{}})"));
    FAIL() << "expected an error";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("bad.json"), std::string::npos) << e.what();
  }
  EXPECT_THROW(coefficients::read_model_file<s::LightModel>(write("kind.json", R"({"kind":"ground","parameters":{"gamma":1}})")),
               std::runtime_error);
  fs::remove_all(dir);
}
