// The virtual E-Puck2's sensors as they "really" are: the truth its reference logs are recorded
// from (data/raw/<kind>/README.md documents each imperfection and its size), and the seeded
// Gaussian noise it draws. The fits are checked against these values (tests/test_sensor_fits.cpp).
//
// These are not measured numbers: they are the synthetic robot's design, chosen from what the
// paper (section 4.1) and the e-puck2 firmware's source report.
#pragma once

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
};

// ----- Ground (paper section 4.1.3) -------------------------------------------------------------
struct GroundTruth {
  /// Black still reflects (offset) and the three sensors disagree (gain); index 0 right, 1 centre, 2 left.
  std::array<double, 3> offset_raw{62.0, 48.0, 75.0};
  std::array<double, 3> gain_raw{905.0, 940.0, 870.0};
  double noise_raw = 5.0;  ///< one sigma, counts
  int grey_steps = 10;     ///< grey = 0, 0.1, ..., 1
  int readings = 40;
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
};

// The protocols with a given truth (the *_reference_logs functions use the defaults above).
std::vector<GeneratedFile> proximity_logs(const ProximityTruth& truth, std::uint64_t seed);
std::vector<GeneratedFile> light_logs(const LightTruth& truth, std::uint64_t seed);
std::vector<GeneratedFile> ground_logs(const GroundTruth& truth, std::uint64_t seed);
std::vector<GeneratedFile> camera_logs(const CameraTruth& truth, std::uint64_t seed);
std::vector<GeneratedFile> drive_logs(const DriveTruth& truth, std::uint64_t seed);

}  // namespace epuck2::virtual_robot
