// Calibrating the sensors from raw logs (docs/logs.md) with Ceres: proximity (paper Eq. 1
// fitted to the per-distance maxima and means, section 4.1.1), ambient light (Eq. 2's gamma,
// section 4.1.2), ground (gain and offset per sensor, section 4.1.3), camera (horizontal field of
// view and image centre, section 4.1.6 and Table 4), drive (encoder steps per metre and the ToF's
// scale and offset, with the wheel slip as a first-order lag, sections 4.1.4 and 4.1.5).
//
// Every fit evaluates the model functions of epuck2/models/sensors.hpp (the very code the
// simulator runs) through fit_curve or a Ceres cost functor, and returns FitResults that say
// whether they are usable; nothing here throws for numerical trouble. The loaders at the end read
// the coefficient files the CLI writes (data/fitted/<kind>.json) back into the models' structs.
#pragma once

#include <array>
#include <string>
#include <vector>

#include "epuck2/fit/least_squares.hpp"
#include "epuck2/logs/log.hpp"
#include "epuck2/models/sensors.hpp"

namespace epuck2::fit {

// ----- Proximity -------------------------------------------------------------------------------

/// Readings at one distance, normalised by 4095.
struct ProximityPoint {
  double distance_m = 0;
  double max = 0, mean = 0, min = 0;
  std::size_t readings = 0;
  bool used = false;        ///< within range and neither saturated nor undetected
  std::string excluded_why;  ///< empty when used
};

struct ProximityFit {
  std::vector<ProximityPoint> points;  ///< one per distance, ascending
  FitResult maxima;                    ///< a, b, c of Eq. 1 fitted to the per-distance maxima
  FitResult means;                     ///< the same fitted to the per-distance means
  double plugin_mse_maxima = 0, plugin_mse_means = 0;  ///< the plug-in's polynomial on the same points
  double epuck1_mse_maxima = 0, epuck1_mse_means = 0;  ///< the E-Puck (v1) polynomial on the same points
  std::size_t readings = 0;
};

/// The points (d <= range) whose maximum is 4095 (saturated) or whose mean is below this fraction
/// of full scale (nothing detected) carry only an inequality and are left out of the fits.
inline constexpr double kProximityUndetectedFraction = 0.01;

ProximityFit fit_proximity(const std::vector<logs::Log>& logs,
                           const models::sensors::ProximityCoefficients& start = models::sensors::kPluginProximity);

// ----- Light -----------------------------------------------------------------------------------

struct LightObservation {
  double distance_m = 0, intensity = 0;
  int sensor = 0;
  double value_raw = 0;
};

struct LightFit {
  std::vector<LightObservation> observations;  ///< the readings used (unsaturated, not dark)
  FitResult gamma;                             ///< one gamma_m for all sensors
  std::vector<int> sensors;                    ///< sensors seen, ascending
  std::vector<FitResult> gamma_per_sensor;     ///< same order as `sensors`
  double plugin_mse = 0;                       ///< the plug-in's gamma = 0.075 on the same readings (normalised units)
  std::size_t readings = 0, censored = 0;
};

LightFit fit_light(const std::vector<logs::Log>& logs);

// ----- Ground ----------------------------------------------------------------------------------

struct GroundFit {
  std::array<FitResult, models::sensors::kGroundCount> sensors;  ///< gain_raw, offset_raw per sensor
  std::array<std::vector<double>, models::sensors::kGroundCount> grey, value_raw;  ///< data used
  std::array<double, models::sensors::kGroundCount> plugin_mse{};  ///< gain 1023, offset 0
  double mse = 0;  ///< pooled over the three sensors
  std::size_t readings = 0, censored = 0;
};

GroundFit fit_ground(const std::vector<logs::Log>& logs);

// ----- Camera ----------------------------------------------------------------------------------

struct CameraObservation {
  double forward_m = 0, lateral_m = 0, vertical_m = 0, px = 0, py = 0;
};

struct CameraFit {
  std::vector<CameraObservation> observations;
  FitResult result;        ///< fov_deg (horizontal), cx_px, cy_px; residuals in pixels (px and py)
  double plugin_mse = 0;   ///< the plug-in's 29.97 deg centred camera on the same points (px^2)
  /// The paper's Table 4 method, applied to each observation far from the centre column (more
  /// than a quarter width away) with the centre taken as W/2 = 80: mean and spread of alpha.
  double table4_alpha_mean_deg = 0, table4_alpha_sd_deg = 0;
  std::size_t table4_points = 0;
};

CameraFit fit_camera(const std::vector<logs::Log>& logs);

// ----- Drive: encoders and ToF -----------------------------------------------------------------

struct DriveRun {
  std::string path;
  double obstacle_distance_m = 0;
  std::vector<double> time_s, command_m_s, steps, tof_mm;  ///< steps unwrapped, mean of both wheels
  bool over_speed_limit = false;  ///< some command exceeds the firmware's limit
};

struct DriveFit {
  std::vector<DriveRun> runs;
  FitResult steps;   ///< steps_per_m: encoder steps against the commanded distance
  FitResult tof;     ///< tof_scale, tof_offset_mm, slip_time_constant_s
  double plugin_tof_mse = 0;  ///< the plug-in's ToF (scale 1, offset 0, no slip) on the same rows, mm^2
  std::size_t steps_rows = 0, tof_rows = 0, tof_censored = 0;
  std::vector<std::string> excluded_from_steps;  ///< runs over the firmware's speed limit
};

/// The firmware's speed limit in m/s: MOTOR_SPEED_LIMIT / the plug-in's steps per metre.
inline constexpr double kFirmwareSpeedLimit_m_s =
    models::sensors::kFirmwareSpeedLimit_steps_s / models::sensors::kPluginStepsPerMetre;

DriveRun drive_run_from_log(const logs::Log& log);
DriveFit fit_drive(const std::vector<logs::Log>& logs);

/// Ground travel (m) at each row of a run: the wheel travel from the encoders (steps / steps_per_m,
/// constant speed between rows) followed by a first-order lag of time constant tau_s, integrated
/// exactly between rows. Templated for the fit; used by the plots too.
template <typename T>
std::vector<T> lagged_travel_m(const DriveRun& run, double steps_per_m, const T& tau_s) {
  using std::exp;
  std::vector<T> out(run.time_s.size(), T(0.0));
  T speed(0.0), travel(0.0);
  for (std::size_t k = 0; k + 1 < run.time_s.size(); ++k) {
    out[k] = travel;
    const double dt = run.time_s[k + 1] - run.time_s[k];
    if (!(dt > 0)) continue;
    const double wheel = (run.steps[k + 1] - run.steps[k]) / steps_per_m / dt;
    const T decay = exp(-dt / tau_s);
    travel += wheel * dt + (speed - wheel) * tau_s * (1.0 - decay);
    speed = wheel + (speed - wheel) * decay;
  }
  if (!out.empty()) out.back() = travel;
  return out;
}

// ----- Coefficient files (data/fitted/<kind>.json, written by `epuck2-fit KIND -o`) -----------
// Each reads `parameters` with .at(); a missing key or a wrong type throws std::runtime_error
// naming the file and the key.

models::sensors::ProximityCoefficients load_proximity_coefficients(const std::string& path);
models::sensors::LightCoefficients load_light_coefficients(const std::string& path);
std::array<models::sensors::GroundCoefficients, models::sensors::kGroundCount> load_ground_coefficients(const std::string& path);
models::sensors::CameraCoefficients load_camera_coefficients(const std::string& path);
struct DriveCoefficients {
  models::sensors::EncoderCoefficients encoder;
  models::sensors::TofCoefficients tof;
  double slip_time_constant_s = 0;
};
DriveCoefficients load_drive_coefficients(const std::string& path);

}  // namespace epuck2::fit
