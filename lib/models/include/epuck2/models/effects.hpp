// The catalogue of effects: every way the plug-in's models miss a real robot that the project
// can name, defined once (docs/diagnose.md, "The catalogue"). Each effect has its catalogue name,
// its meaning in one sentence, where its parameters live (the model's effect struct and a
// coefficient file's "effects" section, the file's "parameters", or folded into the base
// coefficients), and its parameters: name, unit, physical range, neutral value (the plug-in's
// model), where a fit starts, how many (one, or one per sensor) and the C++ member of the kind's
// model that holds it.
//
// The registry is what the diagnosis catalogue, the extended model, the coefficient-file reader
// and writer, codegen, the reports' units and meanings and the ARGoS plug-in iterate over: none of
// them names an effect. Adding an effect means its formula (the kind's header), its entry here,
// one line in the kind's for_each_param() below, its tests, and its line in docs/diagnose.md.
//
// Header-only, standard library only (epuck2::models).
#pragma once

#include <array>
#include <cstddef>
#include <string>
#include <vector>

#include "epuck2/models/kinds.hpp"

namespace epuck2::models::effects {

/// Where an effect's parameters live.
enum class Home {
  effects,     ///< the model's effect struct; a coefficient file's "effects": {"NAME": {key: value}},
               ///< written when not neutral
  parameters,  ///< the model's effect struct; a coefficient file's "parameters" under each
               ///< parameter's file_key, always written (a calibration fits them)
  base,        ///< a diagnosis finding folded into the kind's base coefficients; no section of its
               ///< own in a coefficient file
};

/// One parameter of an effect.
struct Param {
  const char* key;       ///< its name in the diagnosis, the reports and the file's effect object
  const char* unit;      ///< "counts", "m", "1", "cm/s", ...
  double lower;          ///< physical range, closed (a fit's bounds; a file's value outside it,
  double upper;          ///< other than the neutral one, is refused)
  double neutral;        ///< the value that leaves the model as it was
  double start;          ///< where a fit starts when the effect is switched on
  int count;             ///< 1, or one per sensor (an array; the diagnosis names element k key[k])
  const char* member;    ///< the C++ member of the kind's model that holds it ("" for Home::base)
  const char* file_key;  ///< Home::parameters: its key in a file's "parameters" ("" otherwise)
};

/// Whether `v` lies strictly between a parameter's neutral value and its physical range (a
/// neutral 0 below a range starting at 1e-3: a fitted 0.0002 is neither no effect nor one a
/// file may hold).
inline bool between_neutral_and_range(const Param& p, double v) {
  return (p.neutral < p.lower && v > p.neutral && v < p.lower) || (p.neutral > p.upper && v < p.neutral && v > p.upper);
}

/// One effect of the catalogue.
struct Effect {
  const char* name;     ///< the catalogue name
  const char* meaning;  ///< what it is, in one sentence
  Home home;
  std::vector<Param> params;

  /// The parameter `key`, or nullptr.
  const Param* param(const std::string& key) const {
    for (const Param& p : params)
      if (key == p.key) return &p;
    return nullptr;
  }
  /// Whether `value` of parameter p is one a model may hold: its neutral value, or in its range.
  static bool admissible(const Param& p, double value) {
    return value == p.neutral || (value >= p.lower && value <= p.upper);
  }
};

/// A kind's catalogue, in the order of the kind's handles below.
using Catalogue = std::vector<Effect>;

namespace s = sensors;

// ----- proximity (sensors 0..7) ------------------------------------------------------------------

namespace proximity {
enum : std::size_t { ambient_offset, sensor_gain, long_tail, incidence_angle, saturation, count };
}

inline const Catalogue& proximity_catalogue() {
  static const Catalogue c{
      {"ambient_offset", "ambient light shifts every reading by the same amount", Home::effects,
       {{"offset", "counts", -s::kProximityFullScale_raw, s::kProximityFullScale_raw, 0.0, 10.0, 1,
         "effects.ambient.offset_raw", ""}}},
      {"sensor_gain", "the sensors disagree: each has its own gain", Home::effects,
       {{"gains", "1", 0.05, 20.0, 1.0, 1.0, s::kProximityCount, "effects.gains.gain", ""}}},
      {"long_tail", "the sensor still responds beyond the model's cut-off", Home::effects,
       {{"amplitude", "counts", 0.0, 20.0 * s::kProximityFullScale_raw, 0.0, 200.0, 1, "effects.tail.amplitude_raw", ""},
        {"length_m", "m", 0.001, 1.0, 0.02, 0.02, 1, "effects.tail.length_m", ""}}},
      {"incidence_angle", "readings fall as the surface tilts away from the sensor", Home::effects,
       {{"k", "1", 0.0, 50.0, 0.0, 1.0, 1, "effects.incidence.k", ""}}},
      {"saturation", "readings saturate below full scale", Home::effects,
       {{"level", "counts", 1.0, 1e9, 1e9, 4000.0, 1, "effects.saturation.level_raw", ""}}},
  };
  return c;
}

/// f(effect, parameter, element, value) over every parameter of the proximity effects' struct.
template <class T, class F>
void for_each_param(s::ProximityEffects<T>& e, F&& f) {
  f(proximity::ambient_offset, 0, 0, e.ambient.offset_raw);
  for (int k = 0; k < s::kProximityCount; ++k) f(proximity::sensor_gain, 0, k, e.gains.gain[static_cast<std::size_t>(k)]);
  f(proximity::long_tail, 0, 0, e.tail.amplitude_raw);
  f(proximity::long_tail, 1, 0, e.tail.length_m);
  f(proximity::incidence_angle, 0, 0, e.incidence.k);
  f(proximity::saturation, 0, 0, e.saturation.level_raw);
}

// ----- light (sensors 0..7) ----------------------------------------------------------------------

namespace light {
enum : std::size_t { ambient_offset, falloff_exponent, sensor_gain, count };
}

inline const Catalogue& light_catalogue() {
  static const Catalogue c{
      {"ambient_offset", "ambient light shifts every reading by the same amount", Home::effects,
       {{"offset", "counts", -s::kProximityFullScale_raw, s::kProximityFullScale_raw, 0.0, 10.0, 1,
         "effects.ambient.offset_raw", ""}}},
      {"falloff_exponent", "the reading does not fall with the square of the distance", Home::effects,
       {{"exponent", "1", 0.2, 10.0, 2.0, 2.0, 1, "effects.falloff.exponent", ""}}},
      {"sensor_gain", "the sensors disagree: each has its own gain", Home::effects,
       {{"gains", "1", 0.05, 20.0, 1.0, 1.0, s::kProximityCount, "effects.gains.gain", ""}}},
  };
  return c;
}

template <class T, class F>
void for_each_param(s::LightEffects<T>& e, F&& f) {
  f(light::ambient_offset, 0, 0, e.ambient.offset_raw);
  f(light::falloff_exponent, 0, 0, e.falloff.exponent);
  for (int k = 0; k < s::kProximityCount; ++k) f(light::sensor_gain, 0, k, e.gains.gain[static_cast<std::size_t>(k)]);
}

// ----- ground (sensors 0..2) ---------------------------------------------------------------------
// black_offset, white_level, sensor_gain and sensor_offset change each sensor's own black offset
// and gain (the base coefficients): sensor s has the black offset B_s + o_s and the gain
// G_s (level - o_s) / 1023 g_s with o_s = offset + offsets[s] (B_s, G_s: the base's).

namespace ground {
enum : std::size_t { black_offset, white_level, sensor_gain, nonlinear_response, sensor_offset, count };
}

inline const Catalogue& ground_catalogue() {
  static const Catalogue c{
      {"black_offset", "black still reflects: readings over black sit above 0", Home::base,
       {{"offset", "counts", -s::kGroundFullScale_raw, s::kGroundFullScale_raw, 0.0, 20.0, 1, "", ""}}},
      {"white_level", "white reads a different level than the model's full scale", Home::base,
       {{"level", "counts", 1.0, 4.0 * s::kGroundFullScale_raw, s::kGroundFullScale_raw, s::kGroundFullScale_raw, 1, "", ""}}},
      {"sensor_gain", "the sensors disagree: each has its own gain", Home::base,
       {{"gains", "1", 0.05, 5.0, 1.0, 1.0, s::kGroundCount, "", ""}}},
      {"nonlinear_response", "the reading is not proportional to the grey level", Home::effects,
       {{"exponent", "1", 0.05, 20.0, 1.0, 1.0, 1, "effects.exponent", ""}}},
      {"sensor_offset", "each sensor reads its own level over black", Home::base,
       {{"offsets", "counts", -s::kGroundFullScale_raw, s::kGroundFullScale_raw, 0.0, 0.0, s::kGroundCount, "", ""}}},
  };
  return c;
}

template <class T, class F>
void for_each_param(s::GroundNonlinear<T>& e, F&& f) {
  f(ground::nonlinear_response, 0, 0, e.exponent);
}

// ----- camera ------------------------------------------------------------------------------------
// principal_offset moves the base's image centre (cx, cy) by (dx, dy) pixels from the image's.

namespace camera {
enum : std::size_t { principal_offset, radial_distortion, distortion_k2, distortion_k3, count };
}

inline const Catalogue& camera_catalogue() {
  static const Catalogue c{
      {"principal_offset", "the optical axis is off the image centre", Home::base,
       {{"dx_px", "px", -s::kCameraWidth_px, s::kCameraWidth_px, 0.0, 0.0, 1, "", ""},
        {"dy_px", "px", -s::kCameraHeight_px, s::kCameraHeight_px, 0.0, 0.0, 1, "", ""}}},
      {"radial_distortion", "the lens bends points away from (or towards) the centre", Home::effects,
       {{"k1", "1", -10.0, 10.0, 0.0, 0.0, 1, "distortion.k1", ""}}},
      {"distortion_k2", "the lens's radial distortion has a fourth-order term: positions scale by 1 + ... + k2 r^4",
       Home::effects, {{"k2", "1", -100.0, 100.0, 0.0, 0.0, 1, "distortion.k2", ""}}},
      {"distortion_k3", "the lens's radial distortion has a sixth-order term: positions scale by 1 + ... + k3 r^6",
       Home::effects, {{"k3", "1", -1000.0, 1000.0, 0.0, 0.0, 1, "distortion.k3", ""}}},
  };
  return c;
}

template <class T, class F>
void for_each_param(s::CameraRadialDistortion<T>& e, F&& f) {
  f(camera::radial_distortion, 0, 0, e.k1);
  f(camera::distortion_k2, 0, 0, e.k2);
  f(camera::distortion_k3, 0, 0, e.k3);
}

// ----- drive -------------------------------------------------------------------------------------

namespace drive {
enum : std::size_t { speed_limit, accel_limit, wheel_slip, speed_scale, latency, tof_offset, tof_scale, count };
}

inline const Catalogue& drive_catalogue() {
  static const Catalogue c{
      {"speed_limit", "the wheels do not turn faster than a limit, whatever the command", Home::effects,
       {{"max_cm_s", "cm/s", 0.1, s::kDriveNoLimit, s::kDriveNoLimit, 14.0, 1, "effects.speed_limit.max_cm_s", ""}}},
      {"accel_limit", "the wheels reach a new command only gradually: their acceleration is limited", Home::effects,
       {{"accel_cm_s2", "cm/s^2", 0.5, s::kDriveNoLimit, s::kDriveNoLimit, 40.0, 1, "effects.accel_limit.accel_cm_s2", ""}}},
      {"wheel_slip", "the robot's speed over the ground trails the wheels while it accelerates", Home::parameters,
       {{"tau_s", "s", 1e-3, 10.0, 0.0, 0.1, 1, "effects.slip.tau_s", "slip_time_constant_s"}}},
      {"speed_scale", "the robot covers a different distance than its wheels turn (worn or mis-sized wheels)", Home::effects,
       {{"k", "1", 0.2, 5.0, 1.0, 1.0, 1, "effects.speed_scale.k", ""}}},
      {"latency", "the ToF reading describes an earlier moment than its time stamp", Home::effects,
       {{"delay_s", "s", 0.0, 5.0, 0.0, 0.05, 1, "effects.latency.delay_s", ""}}},
      {"tof_offset", "the ToF reads a constant amount off at every range", Home::parameters,
       {{"offset_mm", "mm", -500.0, 500.0, 0.0, 0.0, 1, "effects.tof_offset.offset_mm", "tof_offset_mm"}}},
      {"tof_scale", "the ToF reading is off in proportion to the range", Home::parameters,
       {{"k", "1", 0.5, 2.0, 1.0, 1.0, 1, "effects.tof_scale.k", "tof_scale"}}},
  };
  return c;
}

template <class T, class F>
void for_each_param(s::DriveEffects<T>& e, F&& f) {
  f(drive::speed_limit, 0, 0, e.speed_limit.max_cm_s);
  f(drive::accel_limit, 0, 0, e.accel_limit.accel_cm_s2);
  f(drive::wheel_slip, 0, 0, e.slip.tau_s);
  f(drive::speed_scale, 0, 0, e.speed_scale.k);
  f(drive::latency, 0, 0, e.latency.delay_s);
  f(drive::tof_offset, 0, 0, e.tof_offset.offset_mm);
  f(drive::tof_scale, 0, 0, e.tof_scale.k);
}

// ----- battery -----------------------------------------------------------------------------------

namespace battery {
enum : std::size_t { capacity_scale, count };
}

inline const Catalogue& battery_catalogue() {
  static const Catalogue c{
      {"capacity_scale", "the battery holds a different charge than the calibration batteries", Home::effects,
       {{"k", "1", 0.05, 20.0, 1.0, 1.0, 1, "capacity.k", ""}}},
  };
  return c;
}

template <class F>
void for_each_param(models::battery::CapacityScale& e, F&& f) {
  f(battery::capacity_scale, 0, 0, e.k);
}

// ----- by kind -----------------------------------------------------------------------------------

/// The effect struct of a kind's model (what for_each_param visits).
inline s::ProximityEffects<double>& effects_of(s::ProximityModel& m) { return m.effects; }
inline s::LightEffects<double>& effects_of(s::LightModel& m) { return m.effects; }
inline s::GroundNonlinear<double>& effects_of(s::GroundModel& m) { return m.effects; }
inline s::CameraRadialDistortion<double>& effects_of(s::CameraModel& m) { return m.distortion; }
inline s::DriveEffects<double>& effects_of(s::DriveModel& m) { return m.effects; }
inline models::battery::CapacityScale& effects_of(s::BatteryModel& m) { return m.capacity; }

inline const Catalogue& catalogue_of(const s::ProximityModel&) { return proximity_catalogue(); }
inline const Catalogue& catalogue_of(const s::LightModel&) { return light_catalogue(); }
inline const Catalogue& catalogue_of(const s::GroundModel&) { return ground_catalogue(); }
inline const Catalogue& catalogue_of(const s::CameraModel&) { return camera_catalogue(); }
inline const Catalogue& catalogue_of(const s::DriveModel&) { return drive_catalogue(); }
inline const Catalogue& catalogue_of(const s::BatteryModel&) { return battery_catalogue(); }

/// A kind's name and its catalogue.
struct KindCatalogue {
  const char* kind;
  const Catalogue& (*catalogue)();
};

/// Every kind with its catalogue, in the order the logs' kinds are listed: the one dispatch from a
/// kind's name to its catalogue.
inline const std::array<KindCatalogue, 6>& kind_catalogues() {
  static const std::array<KindCatalogue, 6> k{{{"ground", ground_catalogue},
                                               {"proximity", proximity_catalogue},
                                               {"light", light_catalogue},
                                               {"camera", camera_catalogue},
                                               {"drive", drive_catalogue},
                                               {"battery", battery_catalogue}}};
  return k;
}

/// The catalogue of the kind named `kind` ("proximity", ...); nullptr for another name.
inline const Catalogue* catalogue(const std::string& kind) {
  for (const KindCatalogue& k : kind_catalogues())
    if (kind == k.kind) return &k.catalogue();
  return nullptr;
}

/// The effect `name` of a catalogue, or nullptr.
inline const Effect* find(const Catalogue& c, const std::string& name) {
  for (const Effect& e : c)
    if (name == e.name) return &e;
  return nullptr;
}

/// The key in a coefficient file's "parameters" of parameter p of effect `id` (Home::parameters:
/// what a calibration fits, e.g. the drive's ToF scale).
inline const char* file_key(const Catalogue& c, std::size_t id, std::size_t p = 0) { return c[id].params[p].file_key; }

/// The kinds that have a catalogue, in the order the logs' kinds are listed.
inline const std::array<const char*, 6>& kinds() {
  static const std::array<const char*, 6> k = [] {
    std::array<const char*, 6> names{};
    for (std::size_t i = 0; i < names.size(); ++i) names[i] = kind_catalogues()[i].kind;
    return names;
  }();
  return k;
}

/// `covariate:NAME` (every kind): the reading drifts with a logged column (kinds.hpp
/// CovariateEffect). Not in a catalogue: its name carries the column.
inline constexpr const char* kCovariatePrefix = "covariate:";
inline constexpr const char* kCovariateMeaning = "the reading drifts with a logged quantity";

}  // namespace epuck2::models::effects
