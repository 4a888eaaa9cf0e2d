// The model a diagnosis ends with: see epuck2/diagnose/extended_model.hpp.
#include "epuck2/diagnose/extended_model.hpp"

#include <algorithm>
#include <cmath>
#include <map>
#include <stdexcept>

#include "epuck2/coefficients/model_file.hpp"
#include "epuck2/models/effects.hpp"
#include "epuck2/models/kind_facts.hpp"
#include "kind_table.hpp"

namespace epuck2::diagnose {

namespace s = models::sensors;
namespace fx = models::effects;

namespace {

constexpr const char* kCovariate = fx::kCovariatePrefix;

/// Every parameter of the report by name: the base's (final joint fit) and each finding's, keyed
/// "cause.name" for findings (catalogue names repeat across causes: drive's two `k`).
struct Values {
  std::map<std::string, double> base;
  std::map<std::string, std::map<std::string, double>> effect;
  bool has(const std::string& cause) const { return effect.count(cause) != 0; }
  /// The parameter `name` of the finding of effect `cause`; `neutral` when there is no such
  /// finding. A finding without the parameter is an error (a misspelt name, never a silent
  /// default).
  double at(const std::string& cause, const std::string& name, double neutral) const {
    const auto e = effect.find(cause);
    if (e == effect.end()) return neutral;
    const auto v = e->second.find(name);
    if (v == e->second.end()) {
      std::string known;
      for (const auto& [k, x] : e->second) known += (known.empty() ? "" : ", ") + k;
      throw std::logic_error("the finding " + cause + " has no parameter '" + name + "' (it has: " + known + ")");
    }
    return v->second;
  }
  /// The same for a parameter a finding may lack (a sensor's gain: the reference sensor's and
  /// those the logs do not hold are not fitted).
  double optional_at(const std::string& cause, const std::string& name, double neutral) const {
    const auto e = effect.find(cause);
    if (e == effect.end()) return neutral;
    const auto v = e->second.find(name);
    return v == e->second.end() ? neutral : v->second;
  }
  double base_or(const std::string& name, double fallback) const {
    const auto v = base.find(name);
    return v == base.end() ? fallback : v->second;
  }
};

Values values_of(const Report& r, std::vector<std::string>* left_out, const fx::Catalogue& catalogue) {
  Values v;
  for (const NamedValue& p : r.final_base.empty() ? r.recalibrated : r.final_base) v.base[p.name] = p.value;
  for (const Finding& f : r.findings) {
    if (f.cause.rfind(kCovariate, 0) == 0) continue;  // covariates(), below
    // The formula the finding carries (a renamed finding keeps its effect's).
    const std::string& effect = f.effect.empty() ? f.cause : f.effect;
    const bool ok = fx::find(catalogue, effect) != nullptr;
    if (!ok) {
      if (left_out) left_out->push_back(f.cause);
      continue;
    }
    for (const NamedValue& p : f.parameters) v.effect[effect][p.name] = p.value;
  }
  return v;
}

/// The noise of one reading of `channel` per sensor (reading_noise.hpp: the replicates', else the
/// final model's residuals, less the rounding's 1/12 unit^2 when the logs' readings are whole
/// numbers of their unit, ModelInputs::whole_readings).
template <std::size_t N>
std::array<double, N> noise_per_sensor(const ModelInputs& inputs, const std::string& channel, double residual_sd) {
  std::array<double, N> sd{};
  for (std::size_t k = 0; k < N; ++k) sd[k] = model_noise_sd(inputs.replicate_noise, channel, residual_sd, static_cast<int>(k), inputs.whole_readings);
  return sd;
}

/// The report's `covariate:NAME` findings, centred on the column's mean in `inputs` (left out
/// without one).
std::vector<s::CovariateEffect> covariates(const Report& r, const ModelInputs& inputs, std::vector<std::string>* left_out) {
  std::vector<s::CovariateEffect> out;
  const std::string prefix = kCovariate;
  for (const Finding& f : r.findings) {
    if (f.cause.rfind(prefix, 0) != 0) continue;
    const std::string column = f.cause.substr(prefix.size());
    const auto mean = inputs.column_means.find(column);
    const auto slope = std::find_if(f.parameters.begin(), f.parameters.end(), [](const NamedValue& p) { return p.name == "slope"; });
    if (mean == inputs.column_means.end() || slope == f.parameters.end()) {
      if (left_out) left_out->push_back(f.cause);
      continue;
    }
    out.push_back({column, slope->value, mean->second});
  }
  return out;
}

/// The base model's covariate effects with the report's found ones: a column found again takes
/// the new slope and centre (the diagnosis does not simulate a base model's covariate terms, so a
/// base's drift shows up again as a finding), the others stay.
std::vector<s::CovariateEffect> merged(std::vector<s::CovariateEffect> base, const std::vector<s::CovariateEffect>& found) {
  for (const s::CovariateEffect& f : found) {
    auto same = std::find_if(base.begin(), base.end(), [&](const s::CovariateEffect& b) { return b.column == f.column; });
    if (same != base.end()) *same = f;
    else base.push_back(f);
  }
  return base;
}

void require(const Report& r, logs::Kind kind) {
  if (r.kind != kind) throw std::invalid_argument("the report is not of this kind");
}

/// The base model the report was diagnosed against: the one given, else the plug-in's.
template <class Model>
Model base_of(const Report& r) {
  return std::holds_alternative<Model>(r.base_model) ? std::get<Model>(r.base_model) : Model{};
}

/// "gains[3]" of a finding, per sensor (the reference sensor, not fitted, and sensors the logs do
/// not hold keep the base's gain).
template <std::size_t N>
std::array<double, N> gains(const Values& v, const std::string& cause, const std::string& key, const std::array<double, N>& base) {
  std::array<double, N> g = base;
  for (std::size_t k = 0; k < N; ++k) g[k] = v.optional_at(cause, key + "[" + std::to_string(k) + "]", base[k]);
  return g;
}

/// Every finding of an effect that lives in the model's effect struct, through the registry: its
/// parameters (KEY, or KEY[k] per sensor: a sensor the finding does not fit keeps the base's).
template <class Model>
void apply_findings(const Values& v, Model& m) {
  const fx::Catalogue& catalogue = fx::catalogue_of(m);
  fx::for_each_param(fx::effects_of(m), [&](std::size_t id, int q, int k, double& slot) {
    const fx::Effect& e = catalogue[id];
    const fx::Param& p = e.params[static_cast<std::size_t>(q)];
    if (p.count == 1) slot = v.at(e.name, p.key, slot);
    else slot = v.optional_at(e.name, std::string(p.key) + "[" + std::to_string(k) + "]", slot);
  });
}

}  // namespace

s::ProximityModel extended_proximity(const Report& r, std::vector<std::string>* left_out, const ModelInputs& inputs) {
  require(r, logs::Kind::proximity);
  s::ProximityModel m = base_of<s::ProximityModel>(r);
  const Values v = values_of(r, left_out, fx::catalogue_of(m));
  m.base.a_per_m2 = v.base_or("a", m.base.a_per_m2);
  m.base.b_per_m = v.base_or("b", m.base.b_per_m);
  m.base.c = v.base_or("c", m.base.c);
  apply_findings(v, m);
  m.covariates = merged(m.covariates, covariates(r, inputs, left_out));
  m.noise_sd_raw = noise_per_sensor<s::kProximityCount>(inputs, "proximity", r.noise_sd);
  return m;
}

s::LightModel extended_light(const Report& r, std::vector<std::string>* left_out, const ModelInputs& inputs) {
  require(r, logs::Kind::light);
  s::LightModel m = base_of<s::LightModel>(r);
  const Values v = values_of(r, left_out, fx::catalogue_of(m));
  // The recalibrated pooled gamma; a calibration's per-sensor gammas move with it (kind_light.cpp).
  m = s::with_pooled_gamma(m, v.base_or("gamma_m", m.base.gamma_m));
  apply_findings(v, m);
  m.covariates = merged(m.covariates, covariates(r, inputs, left_out));
  m.noise_sd_raw = noise_per_sensor<s::kProximityCount>(inputs, "light", r.noise_sd);
  return m;
}

s::GroundModel extended_ground(const Report& r, std::vector<std::string>* left_out, const ModelInputs& inputs) {
  require(r, logs::Kind::ground);
  s::GroundModel m = base_of<s::GroundModel>(r);
  const fx::Catalogue& c = fx::catalogue_of(m);
  const Values v = values_of(r, left_out, c);
  // The catalogue's effects relative to each sensor's base (B_s over black, G_s from black to
  // white; the plug-in's 0 and 1023): sensor s has the black offset B_s + o_s and the gain
  // G_s (level - o_s) / 1023 g_s, o_s = offset + offsets[s] (the diagnosis's ground model,
  // kinds.cpp).
  const fx::Effect& black_offset = c[fx::ground::black_offset];
  const fx::Effect& white_level = c[fx::ground::white_level];
  const fx::Effect& sensor_gain = c[fx::ground::sensor_gain];
  const fx::Effect& sensor_offset = c[fx::ground::sensor_offset];
  const double offset = v.at(black_offset.name, black_offset.params[0].key, black_offset.params[0].neutral);
  const double level = v.at(white_level.name, white_level.params[0].key, white_level.params[0].neutral);
  std::array<double, s::kGroundCount> ones;
  ones.fill(sensor_gain.params[0].neutral);
  const auto g = gains<s::kGroundCount>(v, sensor_gain.name, sensor_gain.params[0].key, ones);
  for (std::size_t k = 0; k < m.sensors.size(); ++k) {
    const double black = offset + v.optional_at(sensor_offset.name, std::string(sensor_offset.params[0].key) + "[" + std::to_string(k) + "]",
                                                sensor_offset.params[0].neutral);
    m.sensors[k] = {m.sensors[k].gain_raw * (level - black) / s::kGroundFullScale_raw * g[k], m.sensors[k].offset_raw + black};
  }
  apply_findings(v, m);
  m.covariates = merged(m.covariates, covariates(r, inputs, left_out));
  m.noise_sd_raw = noise_per_sensor<s::kGroundCount>(inputs, "ground", r.noise_sd);
  return m;
}

s::CameraModel extended_camera(const Report& r, std::vector<std::string>* left_out, const ModelInputs& inputs) {
  require(r, logs::Kind::camera);
  s::CameraModel m = base_of<s::CameraModel>(r);
  const fx::Catalogue& c = fx::catalogue_of(m);
  const Values v = values_of(r, left_out, c);
  const fx::Effect& principal = c[fx::camera::principal_offset];
  m.base.horizontal_fov_rad = s::deg_to_rad(v.base_or("fov_deg", s::rad_to_deg(m.base.horizontal_fov_rad)));
  m.base.cx_px = s::kCameraWidth_px / 2.0 + v.at(principal.name, principal.params[0].key, m.base.cx_px - s::kCameraWidth_px / 2.0);
  m.base.cy_px = s::kCameraHeight_px / 2.0 + v.at(principal.name, principal.params[1].key, m.base.cy_px - s::kCameraHeight_px / 2.0);
  apply_findings(v, m);
  m.covariates = merged(m.covariates, covariates(r, inputs, left_out));
  m.noise_sd_px = model_noise_sd(inputs.replicate_noise, "camera", r.noise_sd, -1, inputs.whole_readings);
  return m;
}

s::DriveModel extended_drive(const Report& r, std::vector<std::string>* left_out, const ModelInputs& inputs) {
  require(r, logs::Kind::drive);
  s::DriveModel m = base_of<s::DriveModel>(r);
  const Values v = values_of(r, left_out, fx::catalogue_of(m));
  apply_findings(v, m);
  double tof_residual_sd = r.noise_sd;
  for (const NamedValue& c : r.channel_noise_sd) {
    if (c.name == "tof_mm") tof_residual_sd = c.value;
    if (c.name == "steps") m.encoder_noise_sd_steps = model_noise_sd(inputs.replicate_noise, "encoder", c.value, -1, inputs.whole_readings);
  }
  m.tof_noise_sd_mm = model_noise_sd(inputs.replicate_noise, "tof", tof_residual_sd, -1, inputs.whole_readings);
  m.covariates = merged(m.covariates, covariates(r, inputs, left_out));
  return m;
}

s::BatteryModel extended_battery(const Report& r, std::vector<std::string>* left_out, const ModelInputs& inputs) {
  require(r, logs::Kind::battery);
  s::BatteryModel m;
  const Values v = values_of(r, left_out, fx::catalogue_of(m));
  m.model = inputs.battery_model;
  if (inputs.battery_tables) m.tables = *inputs.battery_tables;
  m.capacity.k = inputs.battery_capacity_k;
  apply_findings(v, m);
  m.noise_sd = r.noise_sd;  // a charge is not rounded: no register's share to take out
  m.covariates = merged(m.covariates, covariates(r, inputs, left_out));
  return m;
}

ModelInputs model_inputs(const std::vector<logs::Log>& logs, const Options& options) {
  ModelInputs in;
  in.battery_model = options.battery_model;
  in.battery_tables = options.battery_tables;
  in.battery_capacity_k = options.battery_capacity_k;
  if (logs.empty()) return in;
  in.replicate_noise = replicate_noise(logs);
  if (const models::KindFacts* facts = models::kind_facts(std::string(logs::to_string(logs.front().kind)))) {
    for (const auto& log : logs)
      for (const char* column : facts->readings)
        if (log.has(column))
          for (double x : log.col(column))
            if (std::isfinite(x) && x != std::round(x)) in.whole_readings = false;
  }
  for (const std::string& name : logs.front().extra_numeric_columns()) {
    double sum = 0;
    std::size_t n = 0;
    bool everywhere = true;
    for (const auto& log : logs) {
      if (!log.has(name)) {
        everywhere = false;
        break;
      }
      for (double x : log.col(name)) sum += x;
      n += log.rows();
    }
    if (everywhere && n > 0) in.column_means[name] = sum / static_cast<double>(n);
  }
  return in;
}

nlohmann::json extended_model_json(const Report& r, const ModelInputs& inputs) {
  std::vector<std::string> left_out;
  nlohmann::json j;
  if (const detail::KindRow* row = detail::kind_row(r.kind)) j = row->extended(r, &left_out, inputs);
  if (!left_out.empty()) j["effects_not_in_model"] = left_out;
  return j;
}

}  // namespace epuck2::diagnose
