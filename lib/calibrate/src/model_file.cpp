// A coefficient file as a model: see epuck2/calibrate/model_file.hpp.
#include "epuck2/calibrate/model_file.hpp"

#include <cmath>
#include <stdexcept>

#include "epuck2/calibrate/battery_json.hpp"

namespace epuck2::calibrate {

namespace s = models::sensors;
using nlohmann::json;

namespace {

[[noreturn]] void fail(const std::string& path, const std::string& what) {
  throw std::runtime_error(path + ": " + what);
}

const json& section(const json& j, const char* name, const std::string& path) {
  if (!j.is_object()) fail(path, "not a JSON object (a coefficient file is one)");
  if (!j.contains(name)) fail(path, std::string("no `") + name + "` section");
  const json& v = j.at(name);
  if (!v.is_object()) fail(path, std::string("`") + name + "` must be an object");
  return v;
}

double number(const json& obj, const std::string& key, const std::string& where, const std::string& path) {
  if (!obj.contains(key)) fail(path, "missing " + where + "." + key);
  const json& v = obj.at(key);
  if (!v.is_number() || !std::isfinite(v.get<double>())) fail(path, where + "." + key + " must be a finite number");
  return v.get<double>();
}

double number_or(const json& obj, const std::string& key, double fallback, const std::string& where,
                 const std::string& path) {
  return obj.contains(key) ? number(obj, key, where, path) : fallback;
}

template <std::size_t N>
std::array<double, N> numbers(const json& obj, const std::string& key, const std::string& where, const std::string& path) {
  if (!obj.contains(key)) fail(path, "missing " + where + "." + key);
  const json& v = obj.at(key);
  if (!v.is_array() || v.size() != N)
    fail(path, where + "." + key + " must be an array of " + std::to_string(N) + " numbers");
  std::array<double, N> out{};
  for (std::size_t i = 0; i < N; ++i) {
    if (!v.at(i).is_number() || !std::isfinite(v.at(i).get<double>()))
      fail(path, where + "." + key + "[" + std::to_string(i) + "] must be a finite number");
    out[i] = v.at(i).get<double>();
  }
  return out;
}

/// The effect `name` of the file's `effects` section, or nullptr when absent (neutral).
const json* effect(const json& j, const char* name, const std::string& path) {
  if (!j.contains("effects")) return nullptr;
  const json& e = j.at("effects");
  if (!e.is_object()) fail(path, "`effects` must be an object");
  if (!e.contains(name)) return nullptr;
  if (!e.at(name).is_object()) fail(path, std::string("effects.") + name + " must be an object");
  return &e.at(name);
}

/// A channel's reading noise sd per sensor (N > 0) from noise.<channel>: per_sensor_sd when
/// present, else sd for every sensor, else 0 (no noise section: a noiseless model).
template <std::size_t N>
std::array<double, N> noise_sd(const json& j, const char* channel, const std::string& path) {
  std::array<double, N> out{};
  if (!j.contains("noise")) return out;
  const json& n = j.at("noise");
  if (!n.is_object()) fail(path, "`noise` must be an object");
  if (!n.contains(channel)) return out;
  const json& c = n.at(channel);
  const std::string where = std::string("noise.") + channel;
  if (!c.is_object()) fail(path, where + " must be an object");
  if (N > 1 && c.contains("per_sensor_sd")) {
    out = numbers<N>(c, "per_sensor_sd", where, path);
  } else {
    out.fill(number(c, "sd", where, path));
  }
  for (double v : out)
    if (v < 0) fail(path, where + ": a noise sd must not be negative");
  return out;
}

void check_kind(const json& j, const char* kind, const std::string& path) {
  if (!j.is_object()) fail(path, "not a JSON object (a coefficient file is one)");
  if (j.contains("kind") && (!j.at("kind").is_string() || j.at("kind").get<std::string>() != kind))
    fail(path, std::string("is not a ") + kind + " coefficient file (kind " + j.at("kind").dump() + ")");
}

template <std::size_t N>
json noise_json(const std::array<double, N>& sd, const char* unit) {
  json c;
  double sum = 0;
  bool same = true;
  for (double v : sd) {
    sum += v * v;
    same = same && v == sd[0];
  }
  c["sd"] = same ? sd[0] : std::sqrt(sum / static_cast<double>(N));
  if (!same) c["per_sensor_sd"] = sd;
  c["unit"] = unit;
  return c;
}

/// The `covariate:NAME` effects of the file: {"slope": .., "centre": ..} each.
std::vector<s::CovariateEffect> covariates_from_json(const json& j, const std::string& path) {
  std::vector<s::CovariateEffect> out;
  if (!j.contains("effects")) return out;
  const json& e = j.at("effects");
  if (!e.is_object()) fail(path, "`effects` must be an object");
  const std::string prefix = "covariate:";
  for (const auto& [key, value] : e.items()) {
    if (key.rfind(prefix, 0) != 0) continue;
    const std::string where = "effects." + key;
    if (key.size() == prefix.size()) fail(path, where + ": the effect names no column");
    if (!value.is_object()) fail(path, where + " must be an object");
    out.push_back({key.substr(prefix.size()), number(value, "slope", where, path), number(value, "centre", where, path)});
  }
  return out;
}

void covariates_to_json(const std::vector<s::CovariateEffect>& covariates, json& effects) {
  for (const auto& c : covariates) effects["covariate:" + c.column] = {{"slope", c.slope}, {"centre", c.centre}};
}

template <std::size_t N>
bool all_one(const std::array<double, N>& g) {
  for (double v : g)
    if (v != 1.0) return false;
  return true;
}

}  // namespace

// ----- proximity -----

s::ProximityModel proximity_model_from_json(const json& j, const std::string& path) {
  check_kind(j, "proximity", path);
  const json& p = section(j, "parameters", path);
  s::ProximityModel m;
  m.base.a_per_m2 = number(p, "a", "parameters", path);
  m.base.b_per_m = number(p, "b", "parameters", path);
  m.base.c = number(p, "c", "parameters", path);
  m.base.range_m = number_or(p, "range_m", m.base.range_m, "parameters", path);
  if (const json* e = effect(j, "ambient_offset", path)) m.effects.ambient.offset_raw = number(*e, "offset", "effects.ambient_offset", path);
  if (const json* e = effect(j, "sensor_gain", path)) m.effects.gains.gain = numbers<s::kProximityCount>(*e, "gains", "effects.sensor_gain", path);
  if (const json* e = effect(j, "long_tail", path)) {
    m.effects.tail.amplitude_raw = number(*e, "amplitude", "effects.long_tail", path);
    m.effects.tail.length_m = number(*e, "length_m", "effects.long_tail", path);
    if (!(m.effects.tail.length_m > 0)) fail(path, "effects.long_tail.length_m must be positive");
  }
  if (const json* e = effect(j, "incidence_angle", path)) m.effects.incidence.k = number(*e, "k", "effects.incidence_angle", path);
  if (const json* e = effect(j, "saturation", path)) m.effects.saturation.level_raw = number(*e, "level", "effects.saturation", path);
  m.covariates = covariates_from_json(j, path);
  m.noise_sd_raw = noise_sd<s::kProximityCount>(j, "proximity", path);
  return m;
}

json model_to_json(const s::ProximityModel& m) {
  json j;
  j["kind"] = "proximity";
  j["parameters"] = {{"a", m.base.a_per_m2}, {"b", m.base.b_per_m}, {"c", m.base.c}, {"range_m", m.base.range_m}};
  json e = json::object();
  const s::ProximityEffects<double> neutral;
  if (m.effects.ambient.offset_raw != neutral.ambient.offset_raw) e["ambient_offset"] = {{"offset", m.effects.ambient.offset_raw}};
  if (!all_one(m.effects.gains.gain)) e["sensor_gain"] = {{"gains", m.effects.gains.gain}};
  if (m.effects.tail.amplitude_raw != neutral.tail.amplitude_raw)
    e["long_tail"] = {{"amplitude", m.effects.tail.amplitude_raw}, {"length_m", m.effects.tail.length_m}};
  if (m.effects.incidence.k != neutral.incidence.k) e["incidence_angle"] = {{"k", m.effects.incidence.k}};
  if (m.effects.saturation.level_raw != neutral.saturation.level_raw) e["saturation"] = {{"level", m.effects.saturation.level_raw}};
  covariates_to_json(m.covariates, e);
  j["effects"] = e;
  j["noise"] = {{"proximity", noise_json(m.noise_sd_raw, "counts")}};
  return j;
}

// ----- light -----

s::LightModel light_model_from_json(const json& j, const std::string& path) {
  check_kind(j, "light", path);
  const json& p = section(j, "parameters", path);
  s::LightModel m;
  m.base.gamma_m = number(p, "gamma", "parameters", path);
  if (!(m.base.gamma_m > 0)) fail(path, "parameters.gamma must be positive");
  m.base.range_m = number_or(p, "range_m", m.base.range_m, "parameters", path);
  if (const json* e = effect(j, "ambient_offset", path)) m.effects.ambient.offset_raw = number(*e, "offset", "effects.ambient_offset", path);
  if (const json* e = effect(j, "falloff_exponent", path)) m.effects.falloff.exponent = number(*e, "exponent", "effects.falloff_exponent", path);
  if (const json* e = effect(j, "sensor_gain", path)) m.effects.gains.gain = numbers<s::kProximityCount>(*e, "gains", "effects.sensor_gain", path);
  m.covariates = covariates_from_json(j, path);
  m.noise_sd_raw = noise_sd<s::kProximityCount>(j, "light", path);
  return m;
}

json model_to_json(const s::LightModel& m) {
  json j;
  j["kind"] = "light";
  j["parameters"] = {{"gamma", m.base.gamma_m}, {"range_m", m.base.range_m}};
  json e = json::object();
  const s::LightEffects<double> neutral;
  if (m.effects.ambient.offset_raw != neutral.ambient.offset_raw) e["ambient_offset"] = {{"offset", m.effects.ambient.offset_raw}};
  if (m.effects.falloff.exponent != neutral.falloff.exponent) e["falloff_exponent"] = {{"exponent", m.effects.falloff.exponent}};
  if (!all_one(m.effects.gains.gain)) e["sensor_gain"] = {{"gains", m.effects.gains.gain}};
  covariates_to_json(m.covariates, e);
  j["effects"] = e;
  j["noise"] = {{"light", noise_json(m.noise_sd_raw, "counts")}};
  return j;
}

// ----- ground -----

s::GroundModel ground_model_from_json(const json& j, const std::string& path) {
  check_kind(j, "ground", path);
  const json& p = section(j, "parameters", path);
  s::GroundModel m;
  const auto gain = numbers<s::kGroundCount>(p, "gain", "parameters", path);
  const auto offset = numbers<s::kGroundCount>(p, "offset", "parameters", path);
  for (std::size_t k = 0; k < m.sensors.size(); ++k) m.sensors[k] = {gain[k], offset[k]};
  if (const json* e = effect(j, "nonlinear_response", path)) {
    m.effects.exponent = number(*e, "exponent", "effects.nonlinear_response", path);
    if (!(m.effects.exponent > 0)) fail(path, "effects.nonlinear_response.exponent must be positive");
  }
  m.covariates = covariates_from_json(j, path);
  m.noise_sd_raw = noise_sd<s::kGroundCount>(j, "ground", path);
  return m;
}

json model_to_json(const s::GroundModel& m) {
  json j;
  j["kind"] = "ground";
  std::array<double, s::kGroundCount> gain{}, offset{};
  for (std::size_t k = 0; k < m.sensors.size(); ++k) {
    gain[k] = m.sensors[k].gain_raw;
    offset[k] = m.sensors[k].offset_raw;
  }
  j["parameters"] = {{"gain", gain}, {"offset", offset}};
  json e = json::object();
  if (m.effects.exponent != 1.0) e["nonlinear_response"] = {{"exponent", m.effects.exponent}};
  covariates_to_json(m.covariates, e);
  j["effects"] = e;
  j["noise"] = {{"ground", noise_json(m.noise_sd_raw, "counts")}};
  return j;
}

// ----- camera -----

s::CameraModel camera_model_from_json(const json& j, const std::string& path) {
  check_kind(j, "camera", path);
  const json& p = section(j, "parameters", path);
  s::CameraModel m;
  const double fov_deg = number(p, "fov_deg", "parameters", path);
  if (!(fov_deg > 0 && fov_deg < 180)) fail(path, "parameters.fov_deg must lie in (0, 180) degrees");
  m.base.horizontal_fov_rad = s::deg_to_rad(fov_deg);
  m.base.cx_px = number(p, "cx_px", "parameters", path);
  m.base.cy_px = number(p, "cy_px", "parameters", path);
  if (const json* e = effect(j, "radial_distortion", path)) m.distortion.k1 = number(*e, "k1", "effects.radial_distortion", path);
  m.covariates = covariates_from_json(j, path);
  m.noise_sd_px = noise_sd<1>(j, "camera", path)[0];
  return m;
}

json model_to_json(const s::CameraModel& m) {
  json j;
  j["kind"] = "camera";
  j["parameters"] = {{"fov_deg", s::rad_to_deg(m.base.horizontal_fov_rad)}, {"cx_px", m.base.cx_px}, {"cy_px", m.base.cy_px}};
  json e = json::object();
  if (m.distortion.k1 != 0.0) e["radial_distortion"] = {{"k1", m.distortion.k1}};
  covariates_to_json(m.covariates, e);
  j["effects"] = e;
  j["noise"] = {{"camera", noise_json(std::array<double, 1>{m.noise_sd_px}, "px")}};
  return j;
}

// ----- drive -----

s::DriveModel drive_model_from_json(const json& j, const std::string& path) {
  check_kind(j, "drive", path);
  const json& p = section(j, "parameters", path);
  s::DriveModel m;
  m.steps_per_m = number(p, "steps_per_m", "parameters", path);
  if (!(m.steps_per_m > 0)) fail(path, "parameters.steps_per_m must be positive");
  m.effects.tof_offset.offset_mm = number(p, "tof_offset_mm", "parameters", path);
  m.effects.tof_scale.k = number(p, "tof_scale", "parameters", path);
  m.effects.slip.tau_s = number_or(p, "slip_time_constant_s", 0.0, "parameters", path);
  if (m.effects.slip.tau_s < 0) fail(path, "parameters.slip_time_constant_s must not be negative");
  if (const json* e = effect(j, "speed_limit", path)) m.effects.speed_limit.max_cm_s = number(*e, "max_cm_s", "effects.speed_limit", path);
  if (const json* e = effect(j, "accel_limit", path)) m.effects.accel_limit.accel_cm_s2 = number(*e, "accel_cm_s2", "effects.accel_limit", path);
  if (const json* e = effect(j, "speed_scale", path)) m.effects.speed_scale.k = number(*e, "k", "effects.speed_scale", path);
  if (const json* e = effect(j, "latency", path)) {
    m.effects.latency.delay_s = number(*e, "delay_s", "effects.latency", path);
    if (m.effects.latency.delay_s < 0) fail(path, "effects.latency.delay_s must not be negative");
  }
  m.covariates = covariates_from_json(j, path);
  m.tof_noise_sd_mm = noise_sd<1>(j, "tof", path)[0];
  m.encoder_noise_sd_steps = noise_sd<1>(j, "encoder", path)[0];
  return m;
}

json model_to_json(const s::DriveModel& m) {
  json j;
  j["kind"] = "drive";
  j["parameters"] = {{"steps_per_m", m.steps_per_m},
                     {"tof_offset_mm", m.effects.tof_offset.offset_mm},
                     {"tof_scale", m.effects.tof_scale.k},
                     {"slip_time_constant_s", m.effects.slip.tau_s}};
  json e = json::object();
  const s::DriveEffects<double> neutral;
  if (m.effects.speed_limit.max_cm_s != neutral.speed_limit.max_cm_s) e["speed_limit"] = {{"max_cm_s", m.effects.speed_limit.max_cm_s}};
  if (m.effects.accel_limit.accel_cm_s2 != neutral.accel_limit.accel_cm_s2)
    e["accel_limit"] = {{"accel_cm_s2", m.effects.accel_limit.accel_cm_s2}};
  if (m.effects.speed_scale.k != neutral.speed_scale.k) e["speed_scale"] = {{"k", m.effects.speed_scale.k}};
  if (m.effects.latency.delay_s != neutral.latency.delay_s) e["latency"] = {{"delay_s", m.effects.latency.delay_s}};
  covariates_to_json(m.covariates, e);
  j["effects"] = e;
  j["noise"] = {{"tof", noise_json(std::array<double, 1>{m.tof_noise_sd_mm}, "mm")},
                {"encoder", noise_json(std::array<double, 1>{m.encoder_noise_sd_steps}, "steps")}};
  return j;
}

// ----- battery -----

s::BatteryModel battery_model_from_json(const json& j, const std::string& path) {
  check_kind(j, "battery", path);
  s::BatteryModel m;
  m.tables = battery_tables_from_json(j, path);
  if (j.contains("battery_model")) {
    const json& name = j.at("battery_model");
    if (!name.is_string() || !models::battery::parse_model(name.get<std::string>(), m.model))
      fail(path, "battery_model must be one of simple, linear, cubic, approximated (found " + name.dump() + ")");
  }
  if (const json* e = effect(j, "capacity_scale", path)) {
    m.capacity.k = number(*e, "k", "effects.capacity_scale", path);
    if (!(m.capacity.k > 0)) fail(path, "effects.capacity_scale.k must be positive");
  }
  m.covariates = covariates_from_json(j, path);
  if (j.contains("noise")) {
    m.noise_sd = noise_sd<1>(j, "charge", path)[0];
  } else {
    // A calibration file (`epuck2-fit battery -o`) has each speed's residual sd (`noise_sd`):
    // their root mean square.
    double sum = 0;
    int n = 0;
    for (const json& speed : j.at("speeds"))
      if (speed.contains("noise_sd") && speed.at("noise_sd").is_number() && std::isfinite(speed.at("noise_sd").get<double>())) {
        sum += speed.at("noise_sd").get<double>() * speed.at("noise_sd").get<double>();
        ++n;
      }
    m.noise_sd = n > 0 ? std::sqrt(sum / n) : 0.0;
  }
  return m;
}

json model_to_json(const s::BatteryModel& m) {
  json j = battery_tables_to_json(m.tables);
  j["kind"] = "battery";
  j["battery_model"] = std::string(models::battery::to_string(m.model));
  json e = json::object();
  if (m.capacity.k != 1.0) e["capacity_scale"] = {{"k", m.capacity.k}};
  covariates_to_json(m.covariates, e);
  j["effects"] = e;
  j["noise"] = {{"charge", noise_json(std::array<double, 1>{m.noise_sd}, "charge")}};
  return j;
}

}  // namespace epuck2::calibrate
