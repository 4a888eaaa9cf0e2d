// Every number a kind's model holds, one "name value" line each (%.17g), in a fixed order: the
// base coefficients, every effect parameter (per-sensor ones element by element), the noise and
// the covariates. Written by hand from lib/models' structs (kinds.hpp), not from codegen or the
// model-file writer, so that tests/test_slip_classes.cpp can compare a model with what a program
// compiled against the header `epuck2-fit codegen` wrote returns for it: a field written with its
// sibling's value, an element dropped or every sensor given the first's shows as a differing line.
// Header-only, lib/models only: the test compiles it into a small program with the project's
// compiler (no library to link).
#pragma once

#include <cstdio>
#include <string>

#include "epuck2/models/battery.hpp"
#include "epuck2/models/effects.hpp"
#include "epuck2/models/kinds.hpp"

namespace epuck2_slip_classes_dump {

namespace sc_s = epuck2::models::sensors;
namespace sc_fx = epuck2::models::effects;

inline void sc_line(std::string& out, const std::string& name, double v) {
  char b[64];
  std::snprintf(b, sizeof b, " %.17g\n", v);
  out += name + b;
}

/// Every effect parameter, named CATALOGUE-NAME.KEY[ELEMENT].
template <class Model>
void sc_effects(std::string& out, const std::string& kind, Model m) {
  const sc_fx::Catalogue& c = sc_fx::catalogue_of(m);
  sc_fx::for_each_param(sc_fx::effects_of(m), [&](std::size_t id, int p, int k, double& v) {
    sc_line(out, kind + ".effect." + c[id].name + "." + c[id].params[static_cast<std::size_t>(p)].key + "[" + std::to_string(k) + "]", v);
  });
}

inline void sc_covariates(std::string& out, const std::string& kind, const std::vector<sc_s::CovariateEffect>& cov) {
  for (const auto& e : cov) {
    sc_line(out, kind + ".covariate." + e.column + ".slope", e.slope);
    sc_line(out, kind + ".covariate." + e.column + ".centre", e.centre);
  }
}

template <std::size_t N>
void sc_array(std::string& out, const std::string& name, const std::array<double, N>& a) {
  for (std::size_t k = 0; k < N; ++k) sc_line(out, name + "[" + std::to_string(k) + "]", a[k]);
}

inline std::string dump(const sc_s::ProximityModel& m) {
  std::string o;
  sc_line(o, "proximity.a", m.base.a_per_m2);
  sc_line(o, "proximity.b", m.base.b_per_m);
  sc_line(o, "proximity.c", m.base.c);
  sc_line(o, "proximity.range_m", m.base.range_m);
  sc_effects(o, "proximity", m);
  sc_array(o, "proximity.noise_sd", m.noise_sd_raw);
  sc_covariates(o, "proximity", m.covariates);
  return o;
}

inline std::string dump(const sc_s::LightModel& m) {
  std::string o;
  sc_line(o, "light.gamma_m", m.base.gamma_m);
  sc_line(o, "light.range_m", m.base.range_m);
  sc_effects(o, "light", m);
  sc_array(o, "light.noise_sd", m.noise_sd_raw);
  sc_covariates(o, "light", m.covariates);
  return o;
}

inline std::string dump(const sc_s::GroundModel& m) {
  std::string o;
  for (std::size_t k = 0; k < m.sensors.size(); ++k) {
    sc_line(o, "ground.gain[" + std::to_string(k) + "]", m.sensors[k].gain_raw);
    sc_line(o, "ground.offset[" + std::to_string(k) + "]", m.sensors[k].offset_raw);
  }
  sc_effects(o, "ground", m);
  sc_array(o, "ground.noise_sd", m.noise_sd_raw);
  sc_covariates(o, "ground", m.covariates);
  return o;
}

inline std::string dump(const sc_s::CameraModel& m) {
  std::string o;
  sc_line(o, "camera.fov_rad", m.base.horizontal_fov_rad);
  sc_line(o, "camera.cx_px", m.base.cx_px);
  sc_line(o, "camera.cy_px", m.base.cy_px);
  sc_line(o, "camera.range_m", m.base.range_m);
  sc_effects(o, "camera", m);
  sc_line(o, "camera.noise_sd_px", m.noise_sd_px);
  sc_covariates(o, "camera", m.covariates);
  return o;
}

inline std::string dump(const sc_s::DriveModel& m) {
  std::string o;
  sc_line(o, "drive.steps_per_m", m.steps_per_m);
  sc_effects(o, "drive", m);
  sc_line(o, "drive.tof_noise_sd_mm", m.tof_noise_sd_mm);
  sc_line(o, "drive.encoder_noise_sd_steps", m.encoder_noise_sd_steps);
  sc_covariates(o, "drive", m.covariates);
  return o;
}

inline std::string dump(const sc_s::BatteryModel& m) {
  std::string o;
  sc_line(o, "battery.model", static_cast<double>(static_cast<int>(m.model)));
  const auto& t = m.tables;
  for (std::size_t sp = 0; sp < t.cubic.size(); ++sp) {
    const std::string at = "[" + std::to_string(sp) + "]";
    const auto& q = t.cubic[sp];
    sc_line(o, "battery.cubic" + at + ".d", q.d);
    sc_line(o, "battery.cubic" + at + ".c", q.c);
    sc_line(o, "battery.cubic" + at + ".b", q.b);
    sc_line(o, "battery.cubic" + at + ".a", q.a);
    sc_line(o, "battery.cubic" + at + ".end_s", q.end_s);
    for (std::size_t k = 0; k < t.segments[sp].size(); ++k) {
      const auto& g = t.segments[sp][k];
      const std::string seg = "battery.segment" + at + "[" + std::to_string(k) + "].";
      sc_line(o, seg + "h", g.h);
      sc_line(o, seg + "m", g.m);
      sc_line(o, seg + "x1_s", g.x1_s);
      sc_line(o, seg + "x2_s", g.x2_s);
      sc_line(o, seg + "y1", g.y1);
      sc_line(o, seg + "y2", g.y2);
    }
    sc_line(o, "battery.linear_slope" + at, t.linear_slope_per_s[sp]);
    sc_line(o, "battery.lifetime_s" + at, t.lifetime_s[sp]);
  }
  sc_line(o, "battery.simple_static_slope", t.simple_static_slope_per_s);
  sc_line(o, "battery.simple_moving_slope", t.simple_moving_slope_per_s);
  sc_effects(o, "battery", m);
  sc_line(o, "battery.noise_sd", m.noise_sd);
  sc_covariates(o, "battery", m.covariates);
  return o;
}

}  // namespace epuck2_slip_classes_dump
