// One model type per kind of log: the base coefficients (per sensor where sensors differ), the
// effects the diagnosis found (lib/models' catalogue structs, neutral by default) and the reading
// noise, in the units the formulas take. The calibration fills them in (lib/calibrate), a
// coefficient file round-trips them (docs/coefficient-files.md), `codegen` emits them as constant
// instances (epuck2::fitted::proximity(), ...), and the simulation (`epuck2-fit simulate KIND
// --like LOG`, the ARGoS plug-in) runs them. Every formula is the one in the sensor's header.
// Every kind also carries the `covariate:NAME` effects a diagnosis found (the reading drifts with
// a logged column): a simulation that has the column adds covariate_offset() to the mean.
//
// Header-only, standard library only (epuck2::models).
#pragma once

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <optional>
#include <string>
#include <vector>

#include "epuck2/models/battery.hpp"
#include "epuck2/models/camera.hpp"
#include "epuck2/models/drive.hpp"
#include "epuck2/models/encoders.hpp"
#include "epuck2/models/ground.hpp"
#include "epuck2/models/light.hpp"
#include "epuck2/models/noise.hpp"
#include "epuck2/models/plugin_battery_tables.hpp"
#include "epuck2/models/proximity.hpp"
#include "epuck2/models/tof.hpp"

namespace epuck2::models::sensors {

/// A reading with Gaussian noise of standard deviation sd_raw, rounded and clamped to [lo, hi]
/// (the sensor's register). `normal` returns standard normal numbers (StandardNormal); sd 0
/// draws nothing.
template <class Normal>
int noisy_register(double mean_raw, double sd_raw, double lo, double hi, Normal& normal) {
  const double noise = sd_raw > 0 ? sd_raw * normal() : 0.0;
  return static_cast<int>(std::clamp(std::round(mean_raw + noise), lo, hi));
}

// ----- covariate:NAME, every kind -------------------------------------------------------------

/// `covariate:NAME` (docs/diagnose.md): the reading drifts with a logged quantity, reading = base
/// + slope (x - centre), x the row's value of the column `column` (e.g. temperature_c), centre the
/// mean of that column over the rows the slope was fitted on. In the reading's units (counts, px,
/// ToF mm, charge) per unit of the column.
struct CovariateEffect {
  std::string column;
  double slope = 0;
  double centre = 0;
};

/// The covariate effects' sum on one row: `value_of(column)` returns the row's value of a column.
template <class ValueOf>
double covariate_offset(const std::vector<CovariateEffect>& effects, ValueOf&& value_of) {
  double sum = 0;
  for (const CovariateEffect& e : effects) sum += e.slope * (value_of(e.column) - e.centre);
  return sum;
}

// ----- proximity -------------------------------------------------------------------------------

struct ProximityModel {
  ProximityCoefficients base = kPluginProximity;  ///< Eq. 1 (per-sensor differences: effects.gains)
  ProximityEffects<double> effects;
  std::array<double, kProximityCount> noise_sd_raw{};  ///< reading noise per sensor, counts
  std::vector<CovariateEffect> covariates;             ///< counts per unit of each column
};

/// The mean reading (counts, before the clamp and the rounding). `distance_m` = nullopt: no hit.
inline double mean_raw(const ProximityModel& m, int sensor, std::optional<double> distance_m,
                       double cos_incidence = 1.0) {
  return proximity_mean_raw(m.base, m.effects, sensor,
                            distance_m ? *distance_m : std::numeric_limits<double>::infinity(), cos_incidence);
}
/// The register: the mean (saturated, docs/diagnose.md) with noise, rounded, clamped to [0, 4095].
/// `covariate_raw`: the covariate effects' sum on the row (covariate_offset), added to the mean.
template <class Normal>
int reading(const ProximityModel& m, int sensor, std::optional<double> distance_m, double cos_incidence,
            Normal& normal, double covariate_raw = 0.0) {
  return noisy_register(mean_raw(m, sensor, distance_m, cos_incidence) + covariate_raw,
                        m.noise_sd_raw[static_cast<std::size_t>(sensor)], 0.0, kProximityFullScale_raw, normal);
}

// ----- light -----------------------------------------------------------------------------------

struct LightModel {
  LightCoefficients base = kPluginLight;  ///< Eq. 2: the pooled gamma (every sensor's, but those below)
  /// A light calibration's per-sensor fits (the file's `per_sensor[i].gamma`, m): sensor s's own
  /// gamma in place of base.gamma_m; an empty entry (the neutral value) takes the pooled one.
  std::array<std::optional<double>, kProximityCount> sensor_gamma_m{};
  LightEffects<double> effects;
  std::array<double, kProximityCount> noise_sd_raw{};  ///< reading noise per sensor, counts
  std::vector<CovariateEffect> covariates;             ///< counts per unit of each column
};

/// Sensor s's gamma (m): its own fit where the model has one, else the pooled base.gamma_m.
inline double light_gamma_m(const LightModel& m, int sensor) {
  return m.sensor_gamma_m[static_cast<std::size_t>(sensor)].value_or(m.base.gamma_m);
}
/// Sensor s's gamma over the pooled one (exactly 1 where it has none): what the diagnosis holds
/// while it recalibrates the pooled gamma (lib/diagnose kind_light.cpp).
inline double light_gamma_ratio(const LightModel& m, int sensor) { return light_gamma_m(m, sensor) / m.base.gamma_m; }
/// The model with its pooled gamma recalibrated to gamma_m, each sensor's own gamma moved with it
/// (gamma_m times its ratio: the diagnosis's extended model, lib/diagnose extended_model.cpp).
inline LightModel with_pooled_gamma(LightModel m, double gamma_m) {
  for (std::size_t k = 0; k < m.sensor_gamma_m.size(); ++k)
    if (m.sensor_gamma_m[k]) m.sensor_gamma_m[k] = gamma_m * light_gamma_ratio(m, static_cast<int>(k));
  m.base.gamma_m = gamma_m;
  return m;
}
/// Eq. 2's coefficients as sensor s sees them: the base with its own gamma.
inline LightCoefficients light_coefficients(const LightModel& m, int sensor) {
  LightCoefficients k = m.base;
  k.gamma_m = light_gamma_m(m, sensor);
  return k;
}

inline double mean_raw(const LightModel& m, int sensor, double intensity, double distance_m) {
  return light_mean_raw(light_coefficients(m, sensor), m.effects, sensor, intensity, distance_m);
}
/// Several lights at once (`lights`: LightSource), as a simulator sees them.
template <class Lights>
double mean_raw(const LightModel& m, int sensor, const Lights& lights) {
  return light_mean_raw(light_coefficients(m, sensor), m.effects, sensor, lights);
}
/// `covariate_raw`: the covariate effects' sum on the row (covariate_offset), added to the mean.
template <class Normal>
int reading(const LightModel& m, int sensor, double intensity, double distance_m, Normal& normal,
            double covariate_raw = 0.0) {
  return noisy_register(mean_raw(m, sensor, intensity, distance_m) + covariate_raw,
                        m.noise_sd_raw[static_cast<std::size_t>(sensor)], 0.0, kProximityFullScale_raw, normal);
}

// ----- ground ----------------------------------------------------------------------------------

struct GroundModel {
  /// Per sensor: offset over black and gain (white minus black), counts. The plug-in: 0 and 1023.
  std::array<GroundCoefficients, kGroundCount> sensors{kPluginGround, kPluginGround, kPluginGround};
  GroundNonlinear<double> effects;
  std::array<double, kGroundCount> noise_sd_raw{};  ///< reading noise per sensor, counts
  std::vector<CovariateEffect> covariates;          ///< counts per unit of each column
};

/// `grey` in [0, 1] (0 black).
inline double mean_raw(const GroundModel& m, int sensor, double grey) {
  return ground_mean_raw(m.sensors[static_cast<std::size_t>(sensor)], m.effects, grey);
}
/// `covariate_raw`: the covariate effects' sum on the row (covariate_offset), added to the mean.
template <class Normal>
int reading(const GroundModel& m, int sensor, double grey, Normal& normal, double covariate_raw = 0.0) {
  return noisy_register(mean_raw(m, sensor, grey) + covariate_raw, m.noise_sd_raw[static_cast<std::size_t>(sensor)], 0.0,
                        kGroundFullScale_raw, normal);
}

// ----- camera ----------------------------------------------------------------------------------

struct CameraModel {
  CameraCoefficients base = plugin_camera();  ///< field of view in radians, centre in pixels
  CameraRadialDistortion<double> distortion;
  double noise_sd_px = 0;  ///< pixel noise of an LED's image position (each axis)
  std::vector<CovariateEffect> covariates;  ///< px per unit of each column, on both axes
};

/// The image position (px, py) of a point in the camera frame, before rounding.
inline std::array<double, 2> mean_px(const CameraModel& m, double forward_m, double lateral_m, double vertical_m) {
  std::array<double, 2> p{};
  camera_projection(m.base.horizontal_fov_rad, m.base.cx_px, m.base.cy_px, m.base.width_px, forward_m, lateral_m,
                    vertical_m, &p[0], &p[1], m.distortion);
  return p;
}
/// The reported pixel: rounded, with the noise, not clamped (whether an LED beyond the image edge
/// is seen at all is camera_image_holds's). `covariate_px`: the covariate effects' sum on the row
/// (covariate_offset), added to both axes as the diagnosis fits it.
template <class Normal>
std::array<int, 2> reading(const CameraModel& m, double forward_m, double lateral_m, double vertical_m, Normal& normal,
                           double covariate_px = 0.0) {
  const auto p = mean_px(m, forward_m, lateral_m, vertical_m);
  const double big = std::numeric_limits<int>::max() / 2.0;
  return {noisy_register(p[0] + covariate_px, m.noise_sd_px, -big, big, normal),
          noisy_register(p[1] + covariate_px, m.noise_sd_px, -big, big, normal)};
}

// ----- drive -----------------------------------------------------------------------------------

struct DriveModel {
  double steps_per_m = kPluginStepsPerMetre;
  TofCoefficients tof = kPluginTof;  ///< range and rails; its scale and offset are effects' tof_scale/tof_offset
  DriveEffects<double> effects;
  double tof_noise_sd_mm = 0;       ///< ToF reading noise, mm
  double encoder_noise_sd_steps = 0;  ///< encoder register noise, steps
  std::vector<CovariateEffect> covariates;  ///< ToF mm per unit of each column (the encoders: none)
  /// The e-puck2 firmware's cap: a wheel turns at most 1100 steps/s, 100 x 1100 / steps_per_m cm/s
  /// of command, where effects.speed_limit is neutral. A calibration file's drive has it (its
  /// `firmware_cap`, unless `kept` is false: the encoders beat the cap); a diagnosis's cap is its
  /// speed_limit; the plug-in's published model has none (it runs a 20 cm/s command at 20 cm/s).
  bool firmware_cap = false;
};

/// The effects as the drive runs them: the model's, with the firmware's cap (100 x 1100 /
/// steps_per_m cm/s) as the speed limit where the model has that cap and no speed_limit of its own.
inline DriveEffects<double> effects_as_run(const DriveModel& m) {
  DriveEffects<double> e = m.effects;
  if (m.firmware_cap && !(e.speed_limit.max_cm_s < kDriveLimitOn))
    e.speed_limit.max_cm_s = 100.0 * kFirmwareSpeedLimit_steps_s / m.steps_per_m;
  return e;
}

/// A drive simulated row by row: the commands hold from one row to the next (zero-order hold),
/// the effects act as in the diagnosis (exactly integrated, no time step), the ToF reads at t -
/// delay, the encoders count floor(steps_per_m x) wrapped to int16.
class DriveSimulation {
 public:
  DriveSimulation(const DriveModel& m, double obstacle_m) : m_(m), obstacle_m_(obstacle_m) { m_.effects = effects_as_run(m); }

  /// The readings at time t under the command that held since the previous call (the first call
  /// is time 0 of the run: nothing has moved), then the command that holds from t.
  /// `tof_covariate_mm`: the covariate effects' sum on the row (covariate_offset), added to the
  /// ToF's mean as the diagnosis fits it.
  struct Readings {
    int tof_mm = 0;
    int left_steps = 0, right_steps = 0;
  };
  template <class Normal>
  Readings sample(double time_s, double left_cm_s, double right_cm_s, Normal& normal, double tof_covariate_mm = 0.0) {
    if (started_) advance_to(time_s);
    started_ = true;
    history_.push_back({time_s, state_});
    commands_.push_back({left_cm_s, right_cm_s});
    Readings r;
    const double xg = delayed_travel(time_s);
    const double tof = drive_tof_mean_mm(m_.effects, obstacle_m_, xg) + tof_covariate_mm;
    r.tof_mm = noisy_register(tof, m_.tof_noise_sd_mm, m_.tof.min_mm, m_.tof.max_mm, normal);
    r.left_steps = encoder_register(registers_[0], state_.xl, normal);
    r.right_steps = encoder_register(registers_[1], state_.xr, normal);
    return r;
  }

 private:
  struct Past {
    double time_s;
    DriveState<double> state;
  };
  void advance_to(double time_s) {
    const auto& c = commands_.back();
    drive_advance(m_.effects, c[0], c[1], time_s - history_.back().time_s, state_);
  }
  /// The body's travel at t - delay: the state at the last sample before then, advanced.
  double delayed_travel(double time_s) const {
    const double when = time_s - m_.effects.latency.delay_s;
    if (m_.effects.latency.delay_s <= 0) return state_.xg;
    if (when < history_.front().time_s) return 0.0;
    std::size_t k = history_.size() - 1;
    while (k > 0 && history_[k].time_s > when) --k;
    DriveState<double> at = history_[k].state;
    drive_advance(m_.effects, commands_[k][0], commands_[k][1], when - history_[k].time_s, at);
    return at.xg;
  }
  /// A wheel's register as last read: a register standing still reads exactly what it read before
  /// (a step count does not flicker), as the calibrated encoders in ARGoS keep it.
  struct Register {
    bool has_read = false;
    double count = 0;
    int reading = 0;
  };
  /// floor(steps_per_m x + noise), int16-wrapped; the noise drawn only when the count moved since
  /// the register was last read, and none while the wheel has not left 0 (docs/logs.md: the
  /// encoders read 0 at time 0).
  template <class Normal>
  int encoder_register(Register& reg, double wheel_m, Normal& normal) const {
    const double count = m_.steps_per_m * wheel_m;
    if (reg.has_read && count == reg.count) return reg.reading;
    reg.has_read = true;
    reg.count = count;
    const double noise = m_.encoder_noise_sd_steps > 0 ? m_.encoder_noise_sd_steps * normal() : 0.0;
    const double f = count == 0.0 ? 0.0 : std::floor(count + noise);
    reg.reading = static_cast<int>(f - 65536.0 * std::floor((f + 32768.0) / 65536.0));  // int16 wrap
    return reg.reading;
  }

  DriveModel m_;
  double obstacle_m_;
  bool started_ = false;
  DriveState<double> state_;
  std::array<Register, 2> registers_{};
  std::vector<Past> history_;
  std::vector<std::array<double, 2>> commands_;
};

// ----- battery ---------------------------------------------------------------------------------

struct BatteryModel {
  battery::Model model = battery::Model::cubic;          ///< the discharge model (paper Appendix)
  battery::Tables tables = battery::plugin_tables();     ///< its coefficient tables per speed
  battery::CapacityScale capacity;                       ///< capacity_scale (docs/diagnose.md)
  double noise_sd = 0;                                   ///< charge reading noise (normalised charge)
  std::vector<CovariateEffect> covariates;               ///< charge per unit of each column
};

/// A charge reading at or above this at a run's first row is the full charge the run starts
/// from, seen through the reading's noise (docs/logs.md: a discharge run starts fully charged).
inline constexpr double kBatteryStartsFull = 0.9;

/// The longest step of the row-by-row simulation: a row interval longer than this is run as
/// equal steps of at most this length. The corrected models' step arithmetic is exact only for
/// short steps: the cubic's start transient runs at the curve's initial slope for the whole step
/// (over 10 s the published curves bend by < 4e-6, b dt^2), and the approximated model keeps the
/// segment of the step's start. Without it, a log with rows 2000 s apart read 0.12 below the curve
/// at 2000 s. 10 s: a row interval of the shipped logs is one step, as before.
inline constexpr double kBatteryLongestStep_s = 10.0;
/// At most this many steps a row interval (a gap of 1e7 s and more: steps longer than 10 s).
inline constexpr double kBatteryMostSteps = 1e6;

/// The charge of a discharge log row by row, as the diagnosis simulates it (docs/diagnose.md,
/// "battery"): the corrected behaviour with the capacity scale, one step per row interval (a
/// speed holds from its row to the next; the robot spins in place, each wheel at that speed),
/// split into equal steps of at most kBatteryLongestStep_s when longer,
/// from a full charge when the first reading is >= kBatteryStartsFull, else from that reading.
/// A repeated time stamp is a step of no length. `time_s` and `speed_cm_s` have one entry a row.
/// For N capacity scales `k` at once (m.capacity is not used): out[s][i] is row i's charge with
/// k[s], the same numbers as N runs one after the other, stepped side by side so that the
/// processor overlaps the N independent chains of steps (the diagnosis's central difference).
template <std::size_t N, class Times, class Speeds>
void battery_mean_charges(const BatteryModel& m, const std::array<double, N>& k, const Times& time_s,
                          const Speeds& speed_cm_s, double first_reading, const std::array<double*, N>& out) {
  const std::size_t n = time_s.size();
  std::array<double, N> charge;
  charge.fill(first_reading >= kBatteryStartsFull ? 1.0 : first_reading);
  for (std::size_t i = 0; i < n; ++i) {
    for (std::size_t s = 0; s < N; ++s) out[s][i] = charge[s];
    if (i + 1 == n) break;
    const double dt = time_s[i + 1] - time_s[i];
    if (dt == 0) continue;
    const double steps = dt > kBatteryLongestStep_s ? std::min(std::ceil(dt / kBatteryLongestStep_s), kBatteryMostSteps) : 1.0;
    const double step_s = steps == 1.0 ? dt : dt / steps;
    const double distance_m = std::abs(speed_cm_s[i]) / 100.0 * step_s;
    for (double j = 0; j < steps; ++j) {
      for (std::size_t s = 0; s < N; ++s)
        charge[s] = battery::step(m.model, m.tables, battery::CapacityScale{k[s]}, charge[s], distance_m, step_s);
      bool all_empty = true;  // an empty battery stays empty: the rest of a long gap changes nothing
      for (std::size_t s = 0; s < N; ++s) all_empty = all_empty && charge[s] <= 0;
      if (all_empty) break;
    }
  }
}

/// The same with the model's own capacity scale.
template <class Times, class Speeds>
std::vector<double> battery_mean_charge(const BatteryModel& m, const Times& time_s, const Speeds& speed_cm_s,
                                        double first_reading) {
  std::vector<double> out(time_s.size());
  battery_mean_charges<1>(m, {m.capacity.k}, time_s, speed_cm_s, first_reading, {out.data()});
  return out;
}

/// A charge reading: the mean plus the covariate effects' sum on the row (covariate_offset) and
/// Gaussian noise of noise_sd, bounded as a log holds a normalised charge ([-1, 1.05],
/// docs/logs.md); not rounded (a charge is no register).
template <class Normal>
double charge_reading(const BatteryModel& m, double mean_charge, Normal& normal, double covariate = 0.0) {
  const double noise = m.noise_sd > 0 ? m.noise_sd * normal() : 0.0;
  return std::clamp(mean_charge + covariate + noise, -1.0, 1.05);
}

}  // namespace epuck2::models::sensors
