// The virtual E-Puck2's sensors as they "really" are: the truth its reference logs are recorded
// from (data/raw/<kind>/README.md documents each imperfection and its size), and the seeded
// Gaussian noise it draws. The fits are checked against these values (tests/test_sensor_fits.cpp).
//
// These are not measured numbers: they are the synthetic robot's design, chosen from what the
// paper (section 4.1) and the e-puck2 firmware's source report.
#pragma once

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <string>
#include <vector>

#include "epuck2/models/sensors.hpp"
#include "epuck2/virtual_robot/reference_logs.hpp"

namespace epuck2::virtual_robot {

/// Standard normal numbers by Box-Muller from UnitUniform's bits: portable across standard
/// libraries (std::normal_distribution is not specified bit for bit).
class Gaussian {
 public:
  explicit Gaussian(std::uint64_t seed) : unit_(seed) {}
  double operator()() {
    if (has_spare_) {
      has_spare_ = false;
      return spare_;
    }
    double u1 = unit_();
    while (u1 <= 0.0) u1 = unit_();
    const double u2 = unit_();
    const double r = std::sqrt(-2.0 * std::log(u1));
    spare_ = r * std::sin(2.0 * models::sensors::kPi * u2);
    has_spare_ = true;
    return r * std::cos(2.0 * models::sensors::kPi * u2);
  }
  double uniform() { return unit_(); }

 private:
  models::sensors::UnitUniform unit_;
  double spare_ = 0;
  bool has_spare_ = false;
};

/// A reading rounded to a whole count and clamped to [0, full_scale]; never "-0" in a log (the
/// rounding of a small negative value is -0, which std::clamp keeps).
inline double whole_count(double v, double full_scale) {
  const double r = std::clamp(std::round(v), 0.0, full_scale);
  return r == 0.0 ? 0.0 : r;
}

/// The robots' names in the logs (`# robot: ...`): robot r (0-based) is "virtual-epuck2-<r+1>".
inline std::string robot_id(std::size_t r) { return "virtual-epuck2-" + std::to_string(r + 1); }

/// Occasional wild readings (a glitch, a reflection, a stuck register) from their own seeded
/// stream: next() draws two numbers for every reading whatever the fraction, so a fraction of 0
/// leaves every other reading exactly as it was. It is true for about `fraction` of the readings,
/// and the wild value is uniform over [lo, hi] (every whole count from lo to hi equally likely
/// when `whole`).
class WildReadings {
 public:
  WildReadings(std::uint64_t seed, double fraction) : unit_(seed), fraction_(fraction) {}
  /// Draws for the next reading: whether it is wild, and the wild value in [lo, hi].
  bool next(double lo, double hi, bool whole, double* value) {
    const double u = unit_(), w = unit_();
    *value = whole ? std::floor(lo + (hi - lo + 1.0) * w) : lo + (hi - lo) * w;
    return u < fraction_;
  }

 private:
  models::sensors::UnitUniform unit_;
  double fraction_;
};

// ----- Proximity (paper section 4.1.1) ---------------------------------------------------------
struct ProximityTruth {
  /// The upper envelope of the readings: the paper's polynomial fitted to the maxima.
  models::sensors::ProximityCoefficients envelope = models::sensors::kPluginProximity;
  /// Per-robot gain on the envelope (two robots disagree).
  std::array<double, 2> robot_gain{1.00, 0.97};
  /// Readings scatter below the envelope: minus |N(0,1)| * (floor + slope * envelope), normalised.
  double scatter_floor = 0.012;
  double scatter_slope = 0.06;
  /// Symmetric electronic noise, raw counts (one sigma).
  double noise_raw = 3.0;
  std::vector<double> distances_m{0.000, 0.005, 0.010, 0.015, 0.020, 0.025, 0.030,
                                  0.035, 0.040, 0.045, 0.050, 0.055, 0.060};
  int readings_per_distance = 360;  ///< about 24 readings/s for 15 s (paper section 4.1.1)
  int sensor = 0;                   ///< PROX0, the front-right sensor the paper used
  /// Rails: at the first this many of distances_m (the nearest: 0 mm) the receiver saturates, whatever the
  /// robot's gain: the latent reading is the rail (4095) plus the electronic noise only (no
  /// scatter), then clipped, so about half the readings land on 4095 and half just inside.
  /// 0 disables (the envelope, clamped to 1, minus scatter, as at every other distance).
  int saturated_distances = 1;
  /// Wild readings: this fraction of the readings is replaced by a value uniform over 0..4095
  /// (WildReadings, own stream). 0 disables.
  double wild_fraction = 0.002;
};

// ----- Light (paper section 4.1.2) -------------------------------------------------------------
struct LightTruth {
  double gamma_m = 0.075;                       ///< paper section 4.1.2
  std::array<int, 2> sensors{0, 7};             ///< PROX0 and PROX7 as in the paper
  std::array<double, 2> sensor_gain{1.00, 0.94};  ///< multiplies (gamma I / d)^2: sensors disagree
  double ambient_raw = 12.0;                    ///< stray light lowers every reading (counts)
  double noise_raw = 15.0;                      ///< one sigma, counts
  std::vector<double> distances_m{0.10, 0.15, 0.20, 0.25, 0.30, 0.35, 0.40, 0.45, 0.50};
  std::vector<double> intensities{0.5, 1.0, 1.5, 2.0};
  int readings = 24;
  /// Two robots differ: robot r's gamma is gamma_m * robot_gamma_scale[r] (robot 2's is 1 % smaller,
  /// 0.07425 m). Robot 1 writes light_intensity_I.csv, robot r > 1 light_intensity_I_<robot>.csv.
  /// One element: one robot.
  std::vector<double> robot_gamma_scale{1.00, 0.99};
  /// Rails: this many extra readings per robot and sensor in the brightest intensity's file, at the
  /// distance (to 0.1 mm) where robot 1's first sensor's latent reading is the rail 0, so about half
  /// of that sensor's land on 0 and half just inside. 0 disables.
  int rail_readings = 48;
  /// Wild readings: this fraction replaced by a value uniform over 0..4095 (own stream). 0 disables.
  double wild_fraction = 0.002;
};

// ----- Ground (paper section 4.1.3) -------------------------------------------------------------
struct GroundTruth {
  /// Black still reflects (offset) and the three sensors disagree (gain); index 0 right, 1 centre, 2 left.
  std::array<double, 3> offset_raw{62.0, 48.0, 75.0};
  std::array<double, 3> gain_raw{905.0, 940.0, 870.0};
  double noise_raw = 5.0;  ///< one sigma, counts
  int grey_steps = 10;     ///< grey = 0, 0.1, ..., 1
  int readings = 40;
  /// Two robots differ: robot r's gains are gain_raw * robot_gain_scale[r] (robot 2's 2 % higher),
  /// same offsets. Robot r writes ground_<robot>.csv. One element: one robot.
  std::vector<double> robot_gain_scale{1.00, 1.02};
  /// Rails: robot 2's centre sensor (offset 48) has the gain that brings its white (grey 1) latent
  /// reading to this value, 1023 = the rail (gain 975 instead of 940 x 1.02 = 958.8), so about half
  /// its white readings land on 1023 and half just inside. 0 disables. The black rail is not
  /// modelled: every offset stays 48..75 counts (10..15 noise sd) above 0, see README.md.
  double white_rail_raw = 1023.0;
  /// Wild readings: this fraction replaced by a value uniform over 0..1023 (own stream). 0 disables.
  double wild_fraction = 0.002;
};

// ----- Camera (paper section 4.1.6) -------------------------------------------------------------
struct CameraTruth {
  double horizontal_fov_deg = 30.8;  ///< the paper's robot mean (Table 4)
  double cx_px = 81.6;               ///< optical axis off the image centre (80, 60)
  double cy_px = 57.9;
  double pixel_noise_px = 0.5;       ///< blob centroid jitter, one sigma, then rounded to a pixel
  std::vector<double> depths_m{0.20, 0.35, 0.50, 0.70, 0.90};
  int columns = 9;  ///< LED positions across the field of view per depth
  int rows = 3;     ///< heights per depth
  int frames = 3;   ///< images per LED position
  /// Two robots differ: robot r's optical axis column is cx_px + robot_cx_shift_px[r] (robot 2's
  /// at 82.1). Robot r writes camera_<robot>.csv. One element: one robot.
  std::vector<double> robot_cx_shift_px{0.0, 0.5};
  /// Wild readings: the blob detector locks onto a reflection in this fraction of the frames: the
  /// centroid is uniform over the image (px 0..159, py 0..119, whole pixels; own stream). 0 disables.
  double wild_fraction = 0.01;
};

// ----- Drive: encoders and ToF (paper sections 4.1.4 and 4.1.5) --------------------------------
struct DriveTruth {
  double obstacle_distance_m = 0.30;  ///< paper section 4.1.4
  std::vector<double> speeds_cm_s{2.5, 5.0, 7.5, 10.0, 12.5, 15.0};
  double toward_travel_m = 0.22;      ///< stop 8 cm before the obstacle (commanded travel)
  double away_travel_m = 0.50;
  double pause_s = 1.0;               ///< standing still before and after
  double steps_per_m = models::sensors::kPluginStepsPerMetre;  ///< nominal 41 mm wheel
  double speed_limit_steps_s = models::sensors::kFirmwareSpeedLimit_steps_s;
  double slip_time_constant_s = 0.12;  ///< ground speed lags the wheels (first order)
  double tof_scale = 0.985;
  double tof_offset_mm = 9.0;
  double tof_noise_mm = 2.0;           ///< one sigma at 0 m ...
  double tof_noise_per_m_mm = 3.0;     ///< ... plus this much per metre of range
  double sample_period_s = 0.1;        ///< ~10 Hz over Wi-Fi ...
  double sample_jitter_s = 0.02;       ///< ... +- this (uniform; paper section 4.1.5)
  double physics_step_s = 0.001;
  /// Above the cap: speeds_cm_s holds 15 cm/s, which the host sends as 1165 steps/s and the
  /// firmware caps at speed_limit_steps_s (1100 = 14.17 cm/s).
  ///
  /// Two robots differ: robot r's wheels travel 1/steps_per_m_scale[r] of the nominal distance per
  /// step (robot 2's true steps_per_m is 0.5 % higher, 7802.47: a wheel 0.2 mm smaller) while its host
  /// still converts commands with steps_per_m. Robot 1 runs speeds_cm_s and the extra runs below;
  /// robot r > 1 runs other_robot_speeds_cm_s, both directions, drive_*_<robot>.csv. One element: one robot.
  std::vector<double> steps_per_m_scale{1.000, 1.005};
  std::vector<double> other_robot_speeds_cm_s{5.0, 10.0};
  /// Static run: robot 1 stands still (all commands 0) this long, drive_static.csv. 0 disables.
  double static_run_s = 10.0;
  /// Rail at the ToF floor: a run that starts 11.2 mm from the obstacle (`# obstacle_distance_m:
  /// 0.0112`), where the latent ToF reading is the 20 mm floor ((20 - tof_offset_mm) / tof_scale),
  /// stands still there for floor_run_pause_s (about half the readings on 20), then drives away at
  /// this speed for floor_run_travel_m, drive_away_floor_SS.S_cm_s.csv. 0 disables.
  double floor_run_speed_cm_s = 5.0;
  double floor_run_pause_s = 3.0;
  double floor_run_travel_m = 0.10;
  /// Out of range, and the rail at 2000 mm: a run away from the obstacle at this speed for
  /// far_run_travel_m, drive_away_far_SS.S_cm_s.csv. Beyond tof_range_m the VL53L0X finds no target
  /// and reports tof_out_of_range_mm; within it readings clamp at 2000 (the latent reading is 2000 at
  /// 2.021 m, 2077 at 2.10 m). 0 disables.
  double far_run_speed_cm_s = 10.0;
  double far_run_travel_m = 2.0;
  double tof_range_m = 2.10;
  double tof_out_of_range_mm = 8190.0;
  /// Dropouts: this fraction of the ToF readings reads tof_out_of_range_mm (own stream). 0 disables.
  double tof_dropout_fraction = 0.002;
  /// Wild readings: this fraction of the ToF readings is uniform over 20..2000 mm (own stream). 0 disables.
  double tof_wild_fraction = 0.002;
};

// The protocols with a given truth (the *_reference_logs functions use the defaults above).
std::vector<GeneratedFile> proximity_logs(const ProximityTruth& truth, std::uint64_t seed);
std::vector<GeneratedFile> light_logs(const LightTruth& truth, std::uint64_t seed);
std::vector<GeneratedFile> ground_logs(const GroundTruth& truth, std::uint64_t seed);
std::vector<GeneratedFile> camera_logs(const CameraTruth& truth, std::uint64_t seed);
std::vector<GeneratedFile> drive_logs(const DriveTruth& truth, std::uint64_t seed);

}  // namespace epuck2::virtual_robot
