// A model as C++: see epuck2/coefficients/codegen.hpp. The effects' lines come from the registry
// (lib/models effects.hpp: each parameter's C++ member), so a new effect needs nothing here.
#include "epuck2/coefficients/codegen.hpp"

#include <cmath>
#include <sstream>
#include <stdexcept>
#include <vector>

#include "epuck2/logs/output.hpp"
#include "epuck2/models/effects.hpp"

namespace epuck2::coefficients {

namespace s = models::sensors;
namespace fx = models::effects;
namespace mb = models::battery;

std::string cpp_number(double v) {
  if (!std::isfinite(v)) throw std::domain_error("cannot write a value that is not finite into C++ (" + logs::format_number(v) + ")");
  return logs::format_number(v);
}

namespace {

template <std::size_t N>
std::string array_of(const std::array<double, N>& a) {
  std::string s = "{";
  for (std::size_t i = 0; i < N; ++i) s += (i ? ", " : "") + cpp_number(a[i]);
  return s + "}";
}

/// `  m.covariates = {{"NAME", slope, centre}, ...};` for a model with covariate:NAME effects
/// (nothing for one without).
std::string covariates_code(const std::vector<s::CovariateEffect>& covariates) {
  if (covariates.empty()) return "";
  std::string out = "  m.covariates = {";
  for (std::size_t i = 0; i < covariates.size(); ++i) {
    std::string name;
    for (char ch : covariates[i].column) {
      if (ch == '"' || ch == '\\') name += '\\';
      name += ch;
    }
    out += std::string(i ? ", " : "") + "{\"" + name + "\", " + cpp_number(covariates[i].slope) + ", " +
           cpp_number(covariates[i].centre) + "}";
  }
  return out + "};\n";
}

/// `  m.MEMBER = value;` for every parameter of the model's effects, in the registry's order
/// (neutral values too: the header states the whole model).
template <class Model>
std::string effects_code(Model m) {
  const fx::Catalogue& catalogue = fx::catalogue_of(m);
  std::vector<std::vector<std::vector<double>>> values(catalogue.size());
  for (std::size_t id = 0; id < catalogue.size(); ++id) values[id].resize(catalogue[id].params.size());
  fx::for_each_param(fx::effects_of(m), [&](std::size_t id, int p, int, double& v) {
    values[id][static_cast<std::size_t>(p)].push_back(v);
  });
  std::string out;
  for (std::size_t id = 0; id < catalogue.size(); ++id) {
    const fx::Effect& e = catalogue[id];
    if (e.home == fx::Home::base) continue;
    for (std::size_t p = 0; p < e.params.size(); ++p) {
      const std::vector<double>& v = values[id][p];
      out += std::string("  m.") + e.params[p].member + " = ";
      if (e.params[p].count == 1) {
        out += cpp_number(v.at(0));
      } else {
        out += "{";
        for (std::size_t i = 0; i < v.size(); ++i) out += (i ? ", " : "") + cpp_number(v[i]);
        out += "}";
      }
      out += ";\n";
    }
  }
  return out;
}

std::string close(const std::string& covariates) { return covariates + "  return m;\n}\n"; }

}  // namespace

std::string model_to_cpp(const AnyModel& m, const std::string& source) {
  return std::visit([&](const auto& model) { return model_to_cpp(model, source); }, m);
}

std::string model_to_cpp(const s::ProximityModel& m, const std::string& source) {
  std::ostringstream os;
  os << "/// The proximity model of " << source << ": base, effects, reading noise (counts).\n"
     << "inline models::sensors::ProximityModel proximity_model() {\n  models::sensors::ProximityModel m;\n"
     << "  m.base = {" << cpp_number(m.base.a_per_m2) << ", " << cpp_number(m.base.b_per_m) << ", " << cpp_number(m.base.c) << ", "
     << cpp_number(m.base.range_m) << "};\n"
     << effects_code(m) << "  m.noise_sd_raw = " << array_of(m.noise_sd_raw) << ";\n" << close(covariates_code(m.covariates));
  return os.str();
}

std::string model_to_cpp(const s::LightModel& m, const std::string& source) {
  std::ostringstream os;
  os << "/// The light model of " << source << ": base, effects, reading noise (counts).\n"
     << "inline models::sensors::LightModel light_model() {\n  models::sensors::LightModel m;\n"
     << "  m.base.gamma_m = " << cpp_number(m.base.gamma_m) << ";\n  m.base.range_m = " << cpp_number(m.base.range_m) << ";\n"
     << effects_code(m) << "  m.noise_sd_raw = " << array_of(m.noise_sd_raw) << ";\n" << close(covariates_code(m.covariates));
  return os.str();
}

std::string model_to_cpp(const s::GroundModel& m, const std::string& source) {
  std::ostringstream os;
  os << "/// The ground model of " << source << ": per-sensor gain and black offset, effects, reading noise (counts).\n"
     << "inline models::sensors::GroundModel ground_model() {\n  models::sensors::GroundModel m;\n";
  for (std::size_t k = 0; k < m.sensors.size(); ++k)
    os << "  m.sensors[" << k << "] = {" << cpp_number(m.sensors[k].gain_raw) << ", " << cpp_number(m.sensors[k].offset_raw) << "};\n";
  os << effects_code(m) << "  m.noise_sd_raw = " << array_of(m.noise_sd_raw) << ";\n" << close(covariates_code(m.covariates));
  return os.str();
}

std::string model_to_cpp(const s::CameraModel& m, const std::string& source) {
  std::ostringstream os;
  os << "/// The camera model of " << source << " (field of view in radians), distortion, pixel noise.\n"
     << "inline models::sensors::CameraModel camera_model() {\n  models::sensors::CameraModel m;\n"
     << "  m.base.horizontal_fov_rad = " << cpp_number(m.base.horizontal_fov_rad) << ";\n"
     << "  m.base.cx_px = " << cpp_number(m.base.cx_px) << ";\n  m.base.cy_px = " << cpp_number(m.base.cy_px) << ";\n"
     << effects_code(m) << "  m.noise_sd_px = " << cpp_number(m.noise_sd_px) << ";\n" << close(covariates_code(m.covariates));
  return os.str();
}

std::string model_to_cpp(const s::DriveModel& m, const std::string& source) {
  std::ostringstream os;
  os << "/// The drive model of " << source << ": encoders, effects, ToF and encoder noise.\n"
     << "inline models::sensors::DriveModel drive_model() {\n  models::sensors::DriveModel m;\n"
     << "  m.steps_per_m = " << cpp_number(m.steps_per_m) << ";\n"
     << effects_code(m) << "  m.tof_noise_sd_mm = " << cpp_number(m.tof_noise_sd_mm) << ";\n"
     << "  m.encoder_noise_sd_steps = " << cpp_number(m.encoder_noise_sd_steps) << ";\n" << close(covariates_code(m.covariates));
  return os.str();
}

std::string model_to_cpp(const s::BatteryModel& m, const std::string& source) {
  std::ostringstream os;
  const mb::Tables& t = m.tables;
  os << "#define EPUCK2_FITTED_HAS_BATTERY 1\n\n";
  os << "/// The four discharge models' tables fitted from " << source << ".\n";
  os << "inline const models::battery::Tables& battery_tables() {\n";
  os << "  static const models::battery::Tables tables = [] {\n";
  os << "    models::battery::Tables t{};\n";
  for (int sp = 0; sp < mb::kSpeedCount; ++sp) {
    const auto& q = t.cubic[static_cast<std::size_t>(sp)];
    os << "    // " << sp << " cm/s\n";
    os << "    t.cubic[" << sp << "] = {" << cpp_number(q.d) << ", " << cpp_number(q.c) << ", " << cpp_number(q.b) << ", "
       << cpp_number(q.a) << ", " << cpp_number(q.end_s) << "};\n";
    for (int k = 0; k < mb::kSegmentCount; ++k) {
      const auto& g = t.segments[static_cast<std::size_t>(sp)][static_cast<std::size_t>(k)];
      os << "    t.segments[" << sp << "][" << k << "] = {" << cpp_number(g.h) << ", " << cpp_number(g.m) << ", "
         << cpp_number(g.x1_s) << ", " << cpp_number(g.x2_s) << ", " << cpp_number(g.y1) << ", " << cpp_number(g.y2) << "};\n";
    }
    os << "    t.linear_slope_per_s[" << sp << "] = " << cpp_number(t.linear_slope_per_s[static_cast<std::size_t>(sp)]) << ";\n";
    os << "    t.lifetime_s[" << sp << "] = " << cpp_number(t.lifetime_s[static_cast<std::size_t>(sp)]) << ";\n";
  }
  os << "    t.simple_static_slope_per_s = " << cpp_number(t.simple_static_slope_per_s) << ";\n";
  os << "    t.simple_moving_slope_per_s = " << cpp_number(t.simple_moving_slope_per_s) << ";\n";
  os << "    return t;\n  }();\n  return tables;\n}\n";
  os << "\n/// The battery model of " << source << ": the discharge model, the tables above, the capacity scale and the\n"
     << "/// charge reading's noise.\n"
     << "inline models::sensors::BatteryModel battery_model() {\n  models::sensors::BatteryModel m;\n"
     << "  m.model = models::battery::Model::" << mb::to_string(m.model) << ";\n"
     << "  m.tables = battery_tables();\n"
     << effects_code(m) << "  m.noise_sd = " << cpp_number(m.noise_sd) << ";\n" << close(covariates_code(m.covariates));
  return os.str();
}

}  // namespace epuck2::coefficients
