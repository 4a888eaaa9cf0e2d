// What each calibrated part of the ARGoS plug-in applies of its kind's effects, stated with the
// registry's handles (lib/models effects.hpp), never by name, and the refusal at Init of a
// coefficient file with a non-neutral effect that ARGoS would read and then ignore (issue #19):
// lib/coefficients reads every effect of the catalogue, so an effect added to lib/models that no
// part runs would otherwise reach ARGoS as a value nobody uses.
//
// A part applies an effect when its reading (or its wheels) runs the effect's formula with the
// file's value. Checked by reading each part's Update (2026-11-26):
//   proximity  ms::mean_raw(ProximityModel, sensor, distance, cos): lib/models' whole formula, the
//              cosine of incidence from the surface hit, the rays stretched to the long tail's reach;
//   light      ms::mean_raw(LightModel, sensor, lights): the whole formula;
//   ground     ms::mean_raw(GroundModel, sensor, grey): the nonlinear response; the other ground
//              effects are folded into each sensor's offset and gain by the reader;
//   camera     ms::mean_px(CameraModel, ...): the three radial terms; the principal offset is
//              folded into the image centre by the reader;
//   wheels     CalibratedDrive::step, lib/models' drive_advance on the file's DriveEffects: speed
//              limit, acceleration limit, slip, speed scale (the calibrated differential_steering;
//              the encoders count those wheels);
//   ToF        ms::tof_reading_mm with the file's scale and offset, DelayLine for the latency;
//   battery    the capacity scale (time runs 1/k as fast).
// No ARGoS dependency: tested by test_argos_calibrated_drive on every machine.
#pragma once

#include <algorithm>
#include <cstddef>
#include <string>
#include <vector>

#include <epuck2/coefficients/model_sets.hpp>
#include <epuck2/models/effects.hpp>

#include <nlohmann/json.hpp>

namespace epuck2::argos_plugin {

namespace fx = epuck2::models::effects;

/// The effects of one kind's catalogue a part applies, by handle.
using Applied = std::vector<std::size_t>;

inline const Applied& proximity_applies() {
  static const Applied a{fx::proximity::ambient_offset, fx::proximity::sensor_gain, fx::proximity::long_tail,
                         fx::proximity::incidence_angle, fx::proximity::saturation};
  return a;
}
inline const Applied& light_applies() {
  static const Applied a{fx::light::ambient_offset, fx::light::falloff_exponent, fx::light::sensor_gain};
  return a;
}
inline const Applied& ground_applies() {
  static const Applied a{fx::ground::black_offset, fx::ground::white_level, fx::ground::sensor_gain,
                         fx::ground::nonlinear_response, fx::ground::sensor_offset};
  return a;
}
inline const Applied& camera_applies() {
  static const Applied a{fx::camera::principal_offset, fx::camera::radial_distortion, fx::camera::distortion_k2,
                         fx::camera::distortion_k3};
  return a;
}
/// The calibrated differential_steering's wheels (and so the encoders and the body the ToF sees).
inline const Applied& wheels_apply() {
  static const Applied a{fx::drive::speed_limit, fx::drive::accel_limit, fx::drive::wheel_slip, fx::drive::speed_scale};
  return a;
}
/// The calibrated ToF's own.
inline const Applied& tof_applies() {
  static const Applied a{fx::drive::tof_offset, fx::drive::tof_scale, fx::drive::latency};
  return a;
}
/// What ARGoS applies of a drive file: the wheels' and the ToF's (each part reads the whole file).
inline const Applied& drive_applies() {
  static const Applied a = [] {
    Applied u = wheels_apply();
    u.insert(u.end(), tof_applies().begin(), tof_applies().end());
    return u;
  }();
  return a;
}
inline const Applied& battery_applies() {
  static const Applied a{fx::battery::capacity_scale};
  return a;
}

/// "a, b and c": the names of `applied` in catalogue `c`, from the registry.
inline std::string applied_names(const fx::Catalogue& c, const Applied& applied) {
  std::string out;
  for (std::size_t i = 0; i < applied.size(); ++i)
    out += std::string(i == 0 ? "" : i + 1 == applied.size() ? " and " : ", ") + c[applied[i]].name;
  return out;
}

/// Stops at Init (logs::InputError at FILE:LINE:COLUMN of the value, with the JSON path) when model
/// `m`, read from `root` (file `path`, robot set `robot`), holds a non-neutral value of an effect
/// that `applied` lacks: `who` (e.g. "the calibrated epuck2_tof") would ignore it.
template <class Model>
void refuse_unapplied(Model m, const Applied& applied, const nlohmann::json& root, const std::string& path,
                      const std::string& robot, const std::string& who) {
  const fx::Catalogue& c = fx::catalogue_of(m);
  fx::for_each_param(fx::effects_of(m), [&](std::size_t id, int p, int, double& value) {
    const fx::Param& q = c[id].params[static_cast<std::size_t>(p)];
    if (value == q.neutral || std::find(applied.begin(), applied.end(), id) != applied.end()) return;
    std::string pointer = "/effects/" + std::string(c[id].name);
    std::string where = "effects." + std::string(c[id].name);
    if (c[id].home == fx::Home::parameters) {
      pointer = "/parameters/" + std::string(q.file_key);
      where = "parameters." + std::string(q.file_key) + " (" + c[id].name + ")";
      if (!robot.empty() && root.contains("robots") && root.at("robots").contains(robot) &&
          root.at("robots").at(robot).contains("parameters") && root.at("robots").at(robot).at("parameters").contains(q.file_key))
        pointer = "/robots/" + robot + pointer;
    }
    coefficients::fail_in_file(path, pointer,
                               where + ": " + who + " does not apply it in ARGoS: a file whose " + c[id].name +
                                   " is not neutral (" + q.key + " = " + std::to_string(value) +
                                   ") would run without it; ARGoS applies " + applied_names(c, applied) +
                                   " (simulate --like runs every effect)");
  });
}

}  // namespace epuck2::argos_plugin
