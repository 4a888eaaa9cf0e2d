// Models of every kind built from a stream of numbers rather than read from a file: what the
// coefficient file's writer (lib/coefficients model_to_json) meets when a diagnosis or a program
// makes a model. Shared by the libFuzzer target fuzz_coefficients (numbers from the fuzz bytes)
// and the unit test StrictFiles.BuiltModelsAreWrittenAndReadBackOrRefused (numbers from a seeded
// generator).
//
// The property (issue #22 item 5): model_to_json writes the model and a reader reads it back to
// the same JSON, or model_to_json refuses it (std::domain_error). Anything else is a finding.
#pragma once

#include <nlohmann/json.hpp>

#include <stdexcept>
#include <string>

#include "epuck2/coefficients/model_file.hpp"
#include "epuck2/models/effects.hpp"

namespace epuck2::fuzzing {

namespace s = models::sensors;

/// Every number of the model that a file holds, each replaced by `next(its current value)` (the
/// plug-in's model first: `next` may keep a value, change it a little or put a wild one).
template <class Next>
void build(s::ProximityModel& m, Next& next) {
  for (double* v : {&m.base.a_per_m2, &m.base.b_per_m, &m.base.c, &m.base.range_m}) *v = next(*v);
  for (double& v : m.noise_sd_raw) v = next(v);
}
template <class Next>
void build(s::LightModel& m, Next& next) {
  for (double* v : {&m.base.gamma_m, &m.base.range_m}) *v = next(*v);
  m.sensor_gamma_m[3] = next(m.base.gamma_m);  // a calibration's own gamma for one sensor
  for (double& v : m.noise_sd_raw) v = next(v);
}
template <class Next>
void build(s::GroundModel& m, Next& next) {
  for (auto& g : m.sensors) {
    g.gain_raw = next(g.gain_raw);
    g.offset_raw = next(g.offset_raw);
  }
  for (double& v : m.noise_sd_raw) v = next(v);
}
template <class Next>
void build(s::CameraModel& m, Next& next) {
  for (double* v : {&m.base.horizontal_fov_rad, &m.base.cx_px, &m.base.cy_px, &m.base.range_m, &m.noise_sd_px}) *v = next(*v);
}
template <class Next>
void build(s::DriveModel& m, Next& next) {
  for (double* v : {&m.steps_per_m, &m.tof_noise_sd_mm, &m.encoder_noise_sd_steps}) *v = next(*v);
}
template <class Next>
void build(s::BatteryModel& m, Next& next) {
  auto& t = m.tables;
  for (std::size_t k = 0; k < t.cubic.size(); ++k) {
    for (double* v : {&t.cubic[k].d, &t.cubic[k].c, &t.cubic[k].b, &t.cubic[k].a, &t.lifetime_s[k], &t.linear_slope_per_s[k]}) *v = next(*v);
    t.cubic[k].end_s = t.lifetime_s[k];  // as every table the project makes (battery_tables.hpp)
    for (auto& g : t.segments[k])
      for (double* v : {&g.h, &g.m, &g.x1_s, &g.x2_s, &g.y1, &g.y2}) *v = next(*v);
  }
  t.simple_static_slope_per_s = next(t.simple_static_slope_per_s);
  t.simple_moving_slope_per_s = next(t.simple_moving_slope_per_s);
  m.noise_sd = next(m.noise_sd);
}

/// The plug-in's model of type Model, every number (effects' too) from `next`.
template <class Model, class Next>
Model built_model(Next& next) {
  Model m = std::get<Model>(coefficients::plugin_model(coefficients::kind_of(Model{})));
  build(m, next);
  models::effects::for_each_param(models::effects::effects_of(m), [&](std::size_t, int, int, double& v) { v = next(v); });
  return m;
}

enum class RoundTrip { refused, equal, differs, unreadable };

/// Writes `m`, reads it back with `from_json` and writes that again; `why` says what went wrong.
template <class Model, class FromJson>
RoundTrip write_and_read_back(const Model& m, FromJson from_json, std::string& why) {
  nlohmann::json written;
  try {
    written = coefficients::model_to_json(m);
  } catch (const std::domain_error& e) {
    why = e.what();
    return RoundTrip::refused;
  }
  try {
    const Model back = from_json(written, std::string("round-trip.json"), std::string());
    if (coefficients::model_to_json(back) == written) return RoundTrip::equal;
    why = "read back differs from what was written: " + written.dump();
    return RoundTrip::differs;
  } catch (const std::exception& e) {
    why = std::string("what was written does not read back (") + e.what() + "): " + written.dump();
    return RoundTrip::unreadable;
  }
}

}  // namespace epuck2::fuzzing
