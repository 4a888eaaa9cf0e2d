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

#include "epuck2/calibrate/engine.hpp"
#include "epuck2/calibrate/reading_noise.hpp"
#include "epuck2/fit/least_squares.hpp"
#include "epuck2/fit/report.hpp"
#include "epuck2/fit/robust.hpp"
#include "epuck2/logs/log.hpp"
#include "epuck2/models/sensors.hpp"

namespace epuck2::calibrate {

/// How the sensor fits treat the readings (docs/fitting.md): robust with outliers left out, or
/// plain least squares; readings on a rail are censored either way.
struct SensorFitOptions {
  bool robust = true;
  double reject_sd = 4.0;
};

/// A reading left out of a fit, and why (listed by file:line in the reports).
struct LeftOut {
  std::string where;  ///< file:line
  std::string why;
};

// ----- Proximity -------------------------------------------------------------------------------

/// Readings at one distance, normalised by 4095.
struct ProximityPoint {
  double distance_m = 0;
  /// Over the readings kept (not wild); at a distance left out of the fits (beyond the range),
  /// over its readings that are not wild, as measured, with `excluded_why`. `max` is the maximum
  /// the maxima fit takes: the highest kept reading not peeled (a reading far above the curve
  /// through the other distances' maxima leaves the maxima fit only; `mean` and `kept` keep it).
  double max = 0, mean = 0, min = 0;
  std::size_t readings = 0;           ///< all readings at this distance
  std::size_t kept = 0;               ///< readings kept (not wild)
  bool used = false;                  ///< within range: enters both fits
  Censoring max_censoring = Censoring::none;   ///< the maximum sits on a rail
  Censoring mean_censoring = Censoring::none;  ///< some reading sits on a rail: the mean is a bound
  double mean_se = 0;                 ///< standard error of the mean (replicates)
  std::string max_where;              ///< file:line of the maximum
  std::string excluded_why;           ///< empty when used
  /// The mean of each robot's kept readings (normalised, like `mean`), indexed as
  /// ProximityFit::robot_names; NaN for a robot with none here. What the figure tells apart.
  std::vector<double> robot_mean;
};

/// The proximity range (where the sensor stops detecting), from logs that reach beyond the
/// model's: bracketed by the farthest distance whose readings are detected (mean at least 1 % of
/// full scale) and the next distance logged, where they are not.
struct ProximityRange {
  bool fitted = false;       ///< the logs reach beyond the model's range
  bool lower_bound = false;  ///< still detected at the farthest distance logged: the range is at least that
  double value_m = 0;        ///< the bracket's middle (or the lower bound)
  double std_error_m = 0;    ///< the bracket's width / sqrt(12) (uniform within it); NaN for a lower bound
  double detected_to_m = 0, undetected_from_m = 0;  ///< the bracket (undetected_from_m NaN for a lower bound)
  std::string how;           ///< in words, for the report and the JSON
};

struct ProximityFit {
  std::vector<ProximityPoint> points;  ///< one per distance, ascending
  ProximityRange range;                ///< the range fitted from the logs (reported; Eq. 1 keeps its 0.05 m domain)
  std::vector<std::string> robot_names;  ///< the logs' `robot`, in the order first met
  RobustFit maxima;                    ///< a, b, c of Eq. 1 fitted to the per-distance maxima
  RobustFit means;                     ///< the same fitted to the per-distance means
  double plugin_mse_maxima = 0, plugin_mse_means = 0;  ///< the plug-in's polynomial on the same points
  double epuck1_mse_maxima = 0, epuck1_mse_means = 0;  ///< the E-Puck (v1) polynomial on the same points
  std::size_t readings = 0;
  std::size_t censored_readings = 0;   ///< readings on a rail (0 or 4095)
  std::vector<LeftOut> left_out;       ///< wild readings and readings beyond the range
  std::vector<std::string> warnings;   ///< plausibility and what the fits said
  /// Reading noise in counts, from the replicates at each distance (per log and sensor, of the
  /// rows facing the target: proximity_replicate_noise), per sensor (8).
  ReadingNoise noise;
};

/// Fits Eq. 1 with the curve held non-increasing over [0, range] (b <= 0 and b + 2 a range <= 0):
/// parametrised by the slopes at 0 and at the range, both bounded at 0. Eq. 1 is the response
/// facing the target: rows at an angle (angle_deg not 0) are left out (listed in `left_out`, one
/// warning counts them); logs without a row at angle_deg 0 throw logs::InputError (exit 2).
ProximityFit fit_proximity(const std::vector<logs::Log>& logs, const SensorFitOptions& options = {},
                           const models::sensors::ProximityCoefficients& start = models::sensors::kPluginProximity);

/// The proximity reading noise between replicates ("replicates"; not usable() without a group of
/// two readings): the readings of one log and sensor at one distance and one incidence angle
/// (angle_deg, 0 where the log has none). One definition for the calibration (its rows facing the
/// target) and the diagnosis (every row; lib/diagnose kinds.cpp).
ReadingNoise proximity_replicate_noise(const std::vector<logs::Log>& logs);

// ----- Light -----------------------------------------------------------------------------------

struct LightObservation {
  double distance_m = 0, intensity = 0;
  int sensor = 0;
  double value_raw = 0;
  std::string where;
  int robot = 0;  ///< an index into LightFit::robot_names
};

struct LightFit {
  std::vector<LightObservation> observations;  ///< the readings that enter the fits (rails included)
  RobustFit gamma;                             ///< one gamma for all sensors
  std::vector<int> sensors;                    ///< sensors seen, ascending
  std::vector<std::string> robot_names;        ///< the logs' `robot`, in the order first met
  std::vector<RobustFit> gamma_per_sensor;     ///< same order as `sensors`
  double plugin_mse = 0;                       ///< the plug-in's gamma = 0.075 on the readings inside the rails (normalised units)
  std::size_t readings = 0, censored = 0;      ///< all readings; readings on a rail (0 or 4095)
  std::vector<LeftOut> left_out;               ///< beyond the range, no light
  std::vector<std::string> warnings;
  /// Reading noise in counts, from the replicates (per log, sensor, distance and intensity), per
  /// sensor (8).
  ReadingNoise noise;
};

LightFit fit_light(const std::vector<logs::Log>& logs, const SensorFitOptions& options = {});

// ----- Ground ----------------------------------------------------------------------------------

/// (The ground sensors' names, as the reports and the figures give them: kind_facts("ground").)

struct GroundFit {
  std::array<RobustFit, models::sensors::kGroundCount> sensors;  ///< gain_raw, offset_raw per sensor
  std::array<std::vector<double>, models::sensors::kGroundCount> grey, value_raw;  ///< readings (rails included)
  /// Each reading's robot, an index into robot_names (the logs' `robot`, in the order first met):
  /// what the figure tells apart.
  std::array<std::vector<int>, models::sensors::kGroundCount> robot;
  std::vector<std::string> robot_names;
  std::array<double, models::sensors::kGroundCount> plugin_mse{};  ///< gain 1023, offset 0
  double plugin_mse_pooled = 0;  ///< the plug-in's on every reading inside the rails, the three sensors pooled
  double mse = 0;  ///< the fit's, pooled over the three sensors
  std::size_t readings = 0, censored = 0;
  std::vector<std::string> warnings;
  /// Reading noise in counts, from the replicates (per log, sensor and grey level), per sensor (3).
  ReadingNoise noise;
};

GroundFit fit_ground(const std::vector<logs::Log>& logs, const SensorFitOptions& options = {});

// ----- Camera ----------------------------------------------------------------------------------

struct CameraObservation {
  double forward_m = 0, lateral_m = 0, vertical_m = 0, px = 0, py = 0;
  std::string where;
  int robot = 0;  ///< an index into CameraFit::robot_names
};

struct CameraFit {
  std::vector<CameraObservation> observations;
  std::vector<std::string> robot_names;  ///< the logs' `robot`, in the order first met
  RobustFit result;        ///< fov_deg (horizontal), cx_px, cy_px; residuals in pixels (px and py)
  /// The plug-in's 29.97 deg centred camera on the readings the fit's MSE is over (px and py of
  /// the points, less those left out as wild: plugin_readings of them), px^2.
  double plugin_mse = 0;
  std::size_t plugin_readings = 0;
  /// The paper's Table 4 method, applied to each observation far from the centre column (more
  /// than a quarter width away) with the centre taken as W/2 = 80: mean and spread of alpha.
  double table4_alpha_mean_deg = 0, table4_alpha_sd_deg = 0;
  std::size_t table4_points = 0;
  std::vector<std::string> warnings;
  /// Reading noise of a blob's px and py together, in pixels, from the frames of each LED position.
  ReadingNoise noise;
};

CameraFit fit_camera(const std::vector<logs::Log>& logs, const SensorFitOptions& options = {});

// ----- Drive: encoders and ToF -----------------------------------------------------------------

struct DriveRun {
  std::string path;
  std::string robot;  ///< the log's `robot` (the figure tells robots apart)
  double obstacle_distance_m = 0;
  std::vector<double> time_s, command_m_s, steps, tof_mm;  ///< steps unwrapped, mean of both wheels
  std::vector<double> command_uncapped_m_s;                ///< the commands as logged (command_m_s: capped)
  std::vector<double> left_cm_s, right_cm_s;               ///< each wheel's command as logged
  std::vector<int> line;                                   ///< source line of each row
  bool over_speed_limit = false;  ///< some command exceeds the firmware's limit (taken as the limit)
  std::size_t capped_rows = 0;    ///< rows whose command was above the limit
};

struct DriveFit {
  std::vector<DriveRun> runs;
  RobustFit steps;   ///< steps_per_m: encoder steps against the commanded distance (commands capped)
  RobustFit tof;     ///< tof_offset_mm, tof_scale, slip_time_constant_s
  /// The plug-in's ToF (scale 1, offset 0, no slip) on the rows the ToF fit's MSE is over (inside
  /// the rails, not left out as wild: plugin_tof_rows of them), mm^2.
  double plugin_tof_mse = 0;
  std::size_t plugin_tof_rows = 0;
  /// The firmware's cap in m/s of command: 1100 steps/s over the fitted steps_per_m (the plug-in's
  /// 7763.656 when the steps fit is not usable); commands above it are capped_rows.
  double cap_m_s = 0;
  std::size_t steps_rows = 0, tof_rows = 0, tof_censored = 0, tof_out_of_range_codes = 0, capped_rows = 0;
  /// Out-of-range codes the ToF fit left out: censored at the ceiling, but the curve puts the
  /// obstacle in view there (dropouts of the sensor; among the fit's outliers).
  std::size_t tof_code_dropouts = 0;
  std::vector<std::string> over_limit_runs;  ///< runs with a command above the firmware's limit
  /// With commands above the firmware's limit, the cap is tested, not assumed: the steps fit with
  /// the commands capped and as logged, each BIC over every row (n ln(RSS/n) + ln n). The cap is
  /// kept unless the uncapped model's BIC is lower by kCapBicMargin or more: then the wheels run
  /// faster than the firmware's limit, the runs' commands are taken as logged, and a warning says so.
  bool cap_tested = false, cap_kept = true;
  double bic_capped = 0, bic_uncapped = 0;
  std::vector<std::string> warnings;
  /// Rows of a run are a time series: the residuals of each fit are autocorrelated within a run,
  /// and its standard errors need this correction (epuck2/fit/report.hpp).
  fit::AutocorrelationCorrection steps_autocorrelation, tof_autocorrelation;
  /// ToF reading noise in mm: from the readings while the robot stands still before it first
  /// moves in a run (replicates), else from the ToF fit's residuals.
  ReadingNoise tof_noise;
  /// Encoder reading noise in steps: the steps fit's residuals about the commanded travel (a
  /// step counter has no replicates that vary).
  ReadingNoise encoder_noise;
};

/// Readings standing still (before a run's first move) needed to take the ToF's reading noise from
/// them rather than from the fit's residuals.
inline constexpr std::size_t kMinStillReadings = 30;

/// The firmware's speed limit in m/s: MOTOR_SPEED_LIMIT / the plug-in's steps per metre.
inline constexpr double kFirmwareSpeedLimit_m_s =
    models::sensors::kFirmwareSpeedLimit_steps_s / models::sensors::kPluginStepsPerMetre;

/// "Very strong" evidence on the BIC scale (Kass and Raftery 1995): the uncapped model must beat
/// the firmware's cap by this much before the cap is dropped.
inline constexpr double kCapBicMargin = 10.0;

/// A drive log's rows; commands above the firmware's limit are taken as the limit (what the robot
/// does; fit_drive tests it), the logged ones kept in command_uncapped_m_s.
DriveRun drive_run_from_log(const logs::Log& log);
/// Sets a run's command_m_s, over_speed_limit and capped_rows from its wheels' commands, each
/// clamped to +-cap (m/s): what the firmware runs.
void cap_commands(DriveRun& run, double cap);
DriveFit fit_drive(const std::vector<logs::Log>& logs, const SensorFitOptions& options = {});
/// fit_drive(logs).tof_noise when it comes from replicates (the readings standing still before
/// each run's first move), without the fits where they cannot change it (the diagnosis asks for
/// nothing else); a ReadingNoise that is not usable() when fit_drive's would come from the
/// residuals (fewer than kMinStillReadings still readings).
ReadingNoise drive_tof_replicate_noise(const std::vector<logs::Log>& logs);

/// Ground travel (m) at each row of a run: the wheel travel from the encoders (steps / steps_per_m,
/// constant speed between rows) followed by a first-order lag of time constant tau_s, integrated
/// exactly between rows (tau_s = 0: no lag). Templated for the fit; used by the plots too.
template <typename T>
std::vector<T> lagged_travel_m(const DriveRun& run, double steps_per_m, const T& tau_s) {
  std::vector<double> wheel_m(run.steps.size());
  for (std::size_t k = 0; k < wheel_m.size(); ++k) wheel_m[k] = run.steps[k] / steps_per_m;
  std::vector<T> out(run.time_s.size(), T(0.0));
  models::sensors::DriveWheelSlip<T> slip;
  slip.tau_s = tau_s;
  models::sensors::lagged_body_travel_m(slip, run.time_s, wheel_m, out.data());
  return out;
}

// A coefficient file as a model: lib/coefficients (epuck2/coefficients/model_file.hpp), the one
// reader.

}  // namespace epuck2::calibrate
