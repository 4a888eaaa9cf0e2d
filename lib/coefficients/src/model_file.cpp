// A coefficient file as a model: see epuck2/coefficients/model_file.hpp. Every effect is read and
// written through lib/models' registry (effects.hpp); every base coefficient and noise channel is
// checked against the kind's facts (kind_facts.hpp).
#include "epuck2/coefficients/model_file.hpp"

#include <algorithm>
#include <cmath>
#include <fstream>
#include <limits>
#include <sstream>
#include <stdexcept>
#include <type_traits>
#include <utility>

#include "epuck2/coefficients/battery_tables.hpp"
#include "epuck2/logs/json_location.hpp"
#include "epuck2/models/effects.hpp"
#include "epuck2/models/kind_facts.hpp"

namespace epuck2::coefficients {

namespace fx = models::effects;
using nlohmann::json;

/// The battery reader, all 16 speeds (`sources` null) or some (the plug-in's elsewhere).
s::BatteryModel battery_model_from_json(const json& j, const std::string& path, const std::string& robot, TableSources* sources);

namespace {

/// A key as one token of a JSON pointer (RFC 6901: ~ and / escaped).
std::string token(const std::string& key) {
  std::string t;
  for (const char c : key) t += c == '~' ? std::string("~0") : c == '/' ? std::string("~1") : std::string(1, c);
  return t;
}

std::string number_text(double v) { return json(v).dump(); }

std::string range_text(double lo, double hi, bool open_lo, bool open_hi, const std::string& unit) {
  return std::string(open_lo ? "(" : "[") + number_text(lo) + ", " + number_text(hi) + (open_hi ? ")" : "]") +
         (unit.empty() || unit == "1" ? "" : " " + unit);
}

/// "; did you mean 'BEST'?" when a known key is close to `key` (an edit distance of at most 2, or a
/// third of its length), else "".
std::string did_you_mean(const std::string& key, const std::vector<std::string>& known) {
  std::string best;
  std::size_t best_d = std::numeric_limits<std::size_t>::max();
  for (const std::string& k : known) {
    const std::size_t d = logs::edit_distance(key, k);
    if (d < best_d) {
      best_d = d;
      best = k;
    }
  }
  return !best.empty() && best_d <= std::max<std::size_t>(2, key.size() / 3) ? "; did you mean '" + best + "'?" : "";
}

std::string joined(const std::vector<std::string>& names) {
  std::string out;
  for (const std::string& n : names) out += (out.empty() ? "" : ", ") + n;
  return out;
}

bool contains(const std::vector<std::string>& names, const std::string& key) {
  return std::find(names.begin(), names.end(), key) != names.end();
}

// The sections a reader reads (docs/coefficient-files.md, "What the readers read").
const std::vector<std::string> kReadSections{"kind", "parameters", "effects", "noise", "robots"};

// Keys a coefficient file holds for people and other tools, never read into a model
// (docs/coefficient-files.md, "Informational keys"): what the calibrations (lib/calibrate
// report_json.cpp, *_report.cpp, battery_json.cpp, apps/cmd_battery.cpp) and the diagnosis
// (lib/diagnose report_output.cpp, extended_model.cpp) write beside the model. Any other key is
// refused: a misspelt section ("efects") is an error, never a section silently skipped.
const std::vector<std::string>& informational_sections() {
  static const std::vector<std::string> keys{
      // every calibration
      "sources", "std_errors", "std_errors_corrected", "std_error_why", "fits", "statistics_conventions", "correlations",
      "censored", "outliers", "lack_of_fit", "rounded", "left_out", "warnings", "robot_spread", "units", "unit_notes", "mse",
      "observations", "reference_mse", "not_identifiable", "readings",
      // proximity, ground, camera, drive calibrations
      "mean_mse", "censored_readings", "points", "range_fit", "mse_per_sensor", "observations_per_sensor", "model", "table4",
      "steps_mse", "steps_observations", "tof_out_of_range_codes", "tof_code_dropouts", "capped_rows", "over_limit_runs", "firmware_cap",
      // battery calibration
      "models", "complete_tables", "speeds_covered_cm_s", "speeds_missing_cm_s", "speeds_other_cm_s", "charge_map",
      "charge_conversion",
      // a diagnosis (epuck2-fit diagnose -o)
      "rows", "residuals", "logs", "verdict", "most_of_the_gain", "too_few_rows", "minimum_rows", "message", "recalibrated",
      "recalibrated_uncertainty", "recalibrated_rounded", "recalibrated_uncertainty_jackknife", "jackknife_folds",
      "recalibrated_uncertainty_corrected", "recalibrated_uncertainty_why", "loss", "censored_per_rail", "fit",
      "autocorrelation", "heldout_mse_plugin", "mse_plugin_reading", "heldout_mse_recalibrated", "heldout_mse_recalibrated_why",
      "heldout_mse_final", "heldout_mse_final_why", "heldout_weighted_recalibrated", "heldout_weighted_final", "noise_sd",
      "noise_sd_why", "mse_units", "channel_noise_sd", "findings", "possible_findings", "residual_structure",
      "residual_structure_before", "effects_considered", "search", "notes", "final_base", "effects_not_in_model"};
  return keys;
}

// A robot's set (`robots.ID`, lib/calibrate report_json.cpp add_robots): what a reader reads there
// (parameters, noise; a light calibration's per_sensor) and what it does not (the rest).
const std::vector<std::string> kRobotSetKeys{"parameters", "noise", "per_sensor", "std_errors", "logs", "usable", "why",
                                             "not_identifiable"};
// A noise channel (lib/calibrate report_json.cpp): sd, per_sensor_sd and unit are read; from, n,
// groups, per_sensor_n and argos_uniform_level say how it was measured.
const std::vector<std::string> kNoiseKeys{"sd", "per_sensor_sd", "unit", "from", "n", "groups", "per_sensor_n",
                                          "argos_uniform_level"};
// A light calibration's per-sensor fit (lib/calibrate light_report.cpp): sensor and gamma are read.
const std::vector<std::string> kPerSensorKeys{"sensor", "gamma", "usable", "why", "std_error", "std_error_why", "mse",
                                              "rounded", "fit"};

/// The reading of one file: its JSON, its name, the robot asked for, and where each section is.
class Doc {
 public:
  Doc(const json& j, std::string path, std::string robot, const char* kind) : j_(j), path_(std::move(path)), robot_(std::move(robot)) {
    if (!j.is_object()) fail("", "not a JSON object (a coefficient file is one)");
    if (j.contains("kind") && (!j.at("kind").is_string() || j.at("kind").get<std::string>() != kind))
      fail("/kind", std::string("is not a ") + kind + " coefficient file (kind " + j.at("kind").dump() + ")");
    facts_ = models::kind_facts(kind);
    if (!robot_.empty()) {
      if (!j.contains("robots") || !j.at("robots").is_object() || !j.at("robots").contains(robot_)) {
        std::string known;
        if (j.contains("robots") && j.at("robots").is_object())
          for (auto it = j.at("robots").begin(); it != j.at("robots").end(); ++it) known += (known.empty() ? "" : ", ") + it.key();
        fail(j.contains("robots") ? "/robots" : "",
             "no set for robot '" + robot_ + "' (robots in the file: " + (known.empty() ? "none" : known) + ")");
      }
      robot_set_ = &j.at("robots").at(robot_);
      if (!robot_set_->is_object()) fail("/robots/" + token(robot_), "a robot's set must be an object");
    }
    check_keys();
  }

  [[noreturn]] void fail(const std::string& pointer, const std::string& what) const {
    throw logs::json_file_error(path_, pointer, what);
  }
  const std::string& path() const { return path_; }
  const json& root() const { return j_; }
  const models::KindFacts& facts() const { return *facts_; }

  /// The value `key` of section `section` ("parameters", "noise"): the robot's set first, then the
  /// pooled one; nullptr when neither has it. `pointer` receives where it is.
  const json* find(const char* section, const std::string& key, std::string& pointer) const {
    if (robot_set_ && robot_set_->contains(section)) {
      const json& s = robot_set_->at(section);
      if (!s.is_object()) fail("/robots/" + token(robot_) + "/" + section, std::string("`") + section + "` must be an object");
      if (s.contains(key)) {
        pointer = "/robots/" + token(robot_) + "/" + section + "/" + token(key);
        return &s.at(key);
      }
    }
    if (!j_.contains(section)) return nullptr;
    const json& s = j_.at(section);
    if (!s.is_object()) fail(std::string("/") + section, std::string("`") + section + "` must be an object");
    if (!s.contains(key)) return nullptr;
    pointer = std::string("/") + section + "/" + token(key);
    return &s.at(key);
  }
  bool has_section(const char* section) const {
    return j_.contains(section) || (robot_set_ && robot_set_->contains(section));
  }

  /// A finite number at `pointer`, named `what` in messages.
  double number(const json& v, const std::string& pointer, const std::string& what) const {
    if (!v.is_number()) fail(pointer, what + " must be a number (found " + v.dump() + ")");
    const double x = v.get<double>();
    if (!std::isfinite(x)) fail(pointer, what + " must be a finite number");
    return x;
  }
  /// `count` numbers: an array of `count`, or one number for every element.
  std::vector<double> numbers(const json& v, std::size_t count, const std::string& pointer, const std::string& what) const {
    if (v.is_number() && count >= 1) return std::vector<double>(count, number(v, pointer, what));
    if (!v.is_array() || v.size() != count)
      fail(pointer, what + " must be " + (count == 1 ? std::string("a number") : "an array of " + std::to_string(count) + " numbers") +
                        " (found " + v.dump() + ")");
    std::vector<double> out;
    for (std::size_t i = 0; i < count; ++i) out.push_back(number(v.at(i), pointer + "/" + std::to_string(i), what + "[" + std::to_string(i) + "]"));
    return out;
  }

  /// The base coefficient `key` (kind_facts' range), per element; `fallback` when absent (empty:
  /// required).
  std::vector<double> base(const std::string& key, std::size_t count, const std::vector<double>& fallback = {}) const {
    const models::BaseParam* p = facts_->base_param(key);
    // A second fit of the same coefficient (the proximity's mean_a: the means' curve) has its range.
    if (!p && key.rfind("mean_", 0) == 0) p = facts_->base_param(key.substr(5));
    std::string pointer;
    const json* v = find("parameters", key, pointer);
    if (!v) {
      if (!fallback.empty()) return fallback;
      if (!has_section("parameters")) fail("", "no `parameters` section");
      fail("/parameters", "missing parameters." + key);
    }
    std::vector<double> out = numbers(*v, count, pointer, "parameters." + key);
    if (p)
      for (std::size_t i = 0; i < out.size(); ++i) {
        const double x = out[i];
        const bool ok = (p->open_lower ? x > p->lower : x >= p->lower) && (p->open_upper ? x < p->upper : x <= p->upper);
        if (!ok)
          fail(v->is_array() ? pointer + "/" + std::to_string(i) : pointer,
               "parameters." + key + (count > 1 ? "[" + std::to_string(i) + "]" : "") + " = " + number_text(x) +
                   " is outside its physical range " + range_text(p->lower, p->upper, p->open_lower, p->open_upper, p->unit));
      }
    return out;
  }
  double base1(const std::string& key) const { return base(key, 1)[0]; }
  double base1(const std::string& key, double fallback) const { return base(key, 1, {fallback})[0]; }

  /// The reading noise of channel `c` per sensor: per_sensor_sd, else sd for every sensor, else 0
  /// (no noise section: a noiseless model). Finite, non-negative, below the channel's full scale.
  std::vector<double> noise(const models::Channel& c) const {
    const std::size_t n = static_cast<std::size_t>(c.sensors);
    std::vector<double> out(n, 0.0);
    if (!has_section("noise")) return out;
    std::string pointer;
    const json* e = find("noise", c.name, pointer);
    if (!e) return out;
    const std::string where = std::string("noise.") + c.name;
    if (!e->is_object()) fail(pointer, where + " must be an object {sd, unit, ...}");
    if (e->contains("unit") && (!e->at("unit").is_string() || e->at("unit").get<std::string>() != c.unit))
      fail(pointer + "/unit", where + ".unit must be \"" + c.unit + "\" (found " + e->at("unit").dump() + ")");
    std::string at = pointer + "/sd";
    bool per_sensor = false;
    if (n > 1 && e->contains("per_sensor_sd")) {
      // The sd over all the sensors' readings beside them (a calibration's pooled estimate): the
      // sensors' own are read, the sd checked alike.
      if (e->contains("sd")) {
        const double all = number(e->at("sd"), pointer + "/sd", where + ".sd");
        if (!(all >= 0 && all < c.full_scale))
          fail(pointer + "/sd", where + ": a reading's noise sd must lie in [0, " + number_text(c.full_scale) + ") " + c.unit + " (found " +
                                    number_text(all) + ")");
      }
      at = pointer + "/per_sensor_sd";
      out = numbers(e->at("per_sensor_sd"), n, at, where + ".per_sensor_sd");
      per_sensor = true;
    } else {
      if (!e->contains("sd")) fail(pointer, "missing " + where + ".sd");
      out.assign(n, number(e->at("sd"), at, where + ".sd"));
    }
    // A sensor's own sd out of range is refused at its entry (/per_sensor_sd/3), not at the list.
    for (std::size_t i = 0; i < n; ++i)
      if (!(out[i] >= 0 && out[i] < c.full_scale))
        fail(per_sensor ? at + "/" + std::to_string(i) : at,
             where + (per_sensor ? ".per_sensor_sd[" + std::to_string(i) + "]" : std::string()) + ": a reading's noise sd must lie in [0, " +
                 number_text(c.full_scale) + ") " + c.unit + " (found " + number_text(out[i]) + ")");
    return out;
  }

  /// Every entry of "effects" into the model's effect struct `e` through the registry, and the
  /// covariate:NAME entries into `covariates`.
  template <class Effects>
  void effects(const fx::Catalogue& catalogue, Effects& e, std::vector<models::sensors::CovariateEffect>& covariates) const {
    // Effects whose home is "parameters" are read there first.
    for (std::size_t id = 0; id < catalogue.size(); ++id) {
      const fx::Effect& effect = catalogue[id];
      if (effect.home != fx::Home::parameters) continue;
      for (std::size_t p = 0; p < effect.params.size(); ++p) {
        const fx::Param& param = effect.params[p];
        std::string pointer;
        const json* v = find("parameters", param.file_key, pointer);
        if (!v) continue;  // neutral
        set(e, id, p, numbers(*v, static_cast<std::size_t>(param.count), pointer, std::string("parameters.") + param.file_key), pointer,
            std::string("parameters.") + param.file_key);
      }
    }
    if (!j_.contains("effects")) return;
    const json& section = j_.at("effects");
    if (!section.is_object()) fail("/effects", "`effects` must be an object");
    const std::string prefix = fx::kCovariatePrefix;
    for (auto it = section.begin(); it != section.end(); ++it) {
      const std::string& name = it.key();
      const json& value = it.value();
      const std::string pointer = "/effects/" + token(name);
      const std::string where = "effects." + name;
      if (!value.is_object()) fail(pointer, where + " must be an object");
      if (name.rfind(prefix, 0) == 0) {
        if (name.size() == prefix.size()) fail(pointer, where + ": the effect names no column");
        for (auto k = value.begin(); k != value.end(); ++k)
          if (k.key() != "slope" && k.key() != "centre")
            fail(pointer + "/" + token(k.key()), where + " has no parameter '" + k.key() + "' (it has: slope, centre)");
        auto need = [&](const char* key) {
          if (!value.contains(key)) fail(pointer, "missing " + where + "." + key);
          return number(value.at(key), pointer + "/" + key, where + "." + key);
        };
        covariates.push_back({name.substr(prefix.size()), need("slope"), need("centre")});
        continue;
      }
      const fx::Effect* effect = fx::find(catalogue, name);
      if (!effect) fail(pointer, unknown_effect(catalogue, name));
      if (effect->home == fx::Home::base)
        fail(pointer, "'" + name + "' is not an effect a model file holds: a diagnosis folds it into the base coefficients "
                                   "(`parameters`)");
      const std::size_t id = static_cast<std::size_t>(effect - catalogue.data());
      std::string names;
      for (const fx::Param& p : effect->params) names += (names.empty() ? "" : ", ") + std::string(p.key);
      for (auto k = value.begin(); k != value.end(); ++k)
        if (!effect->param(k.key())) fail(pointer + "/" + token(k.key()), where + " has no parameter '" + k.key() + "' (it has: " + names + ")");
      for (std::size_t p = 0; p < effect->params.size(); ++p) {
        const fx::Param& param = effect->params[p];
        if (!value.contains(param.key)) fail(pointer, "missing " + where + "." + param.key);
        const std::string at = pointer + "/" + token(param.key);
        set(e, id, p, numbers(value.at(param.key), static_cast<std::size_t>(param.count), at, where + "." + param.key), at,
            where + "." + param.key);
      }
    }
  }

  /// Every key of `parameters` a file of this kind may hold: the base coefficients, the
  /// parameter-home effects' file keys (registry), the kind's own (kind_facts' file_parameters).
  std::vector<std::string> parameter_keys() const {
    std::vector<std::string> keys;
    for (const models::BaseParam& p : facts_->base) keys.emplace_back(p.key);
    for (const fx::Effect& e : *fx::catalogue(facts_->name))
      if (e.home == fx::Home::parameters)
        for (const fx::Param& p : e.params) keys.emplace_back(p.file_key);
    for (const char* k : facts_->file_parameters)
      if (!contains(keys, k)) keys.emplace_back(k);
    return keys;
  }

 private:
  /// Refuses what no reader reads and no writer writes (an unknown key anywhere but `effects`,
  /// whose names effects() checks against the registry), in the file and in every robot's set.
  void check_keys() const {
    std::vector<std::string> top = kReadSections;
    top.insert(top.end(), facts_->file_sections.begin(), facts_->file_sections.end());
    std::vector<std::string> known = top;
    known.insert(known.end(), informational_sections().begin(), informational_sections().end());
    for (auto it = j_.begin(); it != j_.end(); ++it)
      if (!contains(known, it.key()))
        fail("/" + token(it.key()), "unknown section '" + it.key() + "' in a " + facts_->name + " coefficient file (the sections read: " +
                                        joined(top) + "; the informational ones are listed in docs/coefficient-files.md)" +
                                        did_you_mean(it.key(), known));
    check_set(j_, "");
    if (!j_.contains("robots")) return;
    const json& robots = j_.at("robots");
    if (!robots.is_object()) fail("/robots", "`robots` must be an object {ID: a robot's set}");
    for (auto it = robots.begin(); it != robots.end(); ++it) {
      const std::string at = "/robots/" + token(it.key());
      if (!it.value().is_object()) fail(at, "a robot's set must be an object");
      for (auto k = it.value().begin(); k != it.value().end(); ++k)
        if (!contains(kRobotSetKeys, k.key()) ||
            (k.key() == "per_sensor" && std::find(facts_->file_sections.begin(), facts_->file_sections.end(),
                                                   std::string_view("per_sensor")) == facts_->file_sections.end()))
          fail(at + "/" + token(k.key()), "unknown key '" + k.key() + "' in robot " + it.key() + "'s set (a robot's set holds " +
                                              joined(kRobotSetKeys) + (k.key() == "effects" ? "; effects are the file's, at the top" : "") +
                                              ")" + did_you_mean(k.key(), kRobotSetKeys));
      check_set(it.value(), at);
    }
  }

  /// The parameters, std_errors and noise of the file (`at` "") or of a robot's set (`at` its pointer).
  void check_set(const json& set, const std::string& at) const {
    const std::vector<std::string> keys = parameter_keys();
    for (const char* section : {"parameters", "std_errors"}) {
      if (!set.contains(section)) continue;
      const json& p = set.at(section);
      const std::string ps = at + "/" + section;
      if (!p.is_object()) fail(ps, std::string("`") + section + "` must be an object");
      for (auto it = p.begin(); it != p.end(); ++it) {
        if (!contains(keys, it.key()))
          fail(ps + "/" + token(it.key()), "unknown parameter '" + it.key() + "' in `" + section + "` of a " + facts_->name +
                                               " coefficient file (its parameters: " + (keys.empty() ? std::string("none") : joined(keys)) +
                                               ")" + did_you_mean(it.key(), keys));
        if (std::string(section) == "std_errors") check_std_error(it.value(), ps + "/" + token(it.key()), it.key());
      }
    }
    if (!set.contains("noise")) return;
    const json& n = set.at("noise");
    if (!n.is_object()) fail(at + "/noise", "`noise` must be an object");
    std::vector<std::string> channels;
    for (const models::Channel& c : facts_->channels) channels.emplace_back(c.name);
    for (auto it = n.begin(); it != n.end(); ++it) {
      const std::string cp = at + "/noise/" + token(it.key());
      if (!contains(channels, it.key()))
        fail(cp, "unknown noise channel '" + it.key() + "' for a " + facts_->name + " model (its channels: " + joined(channels) + ")" +
                     did_you_mean(it.key(), channels));
      if (!it.value().is_object()) fail(cp, "noise." + it.key() + " must be an object {sd, unit, ...}");
      for (auto k = it.value().begin(); k != it.value().end(); ++k)
        if (!contains(kNoiseKeys, k.key()))
          fail(cp + "/" + token(k.key()), "unknown key '" + k.key() + "' in noise." + it.key() + " (a channel holds " + joined(kNoiseKeys) +
                                              ")" + did_you_mean(k.key(), kNoiseKeys));
    }
  }

  /// A standard error: a non-negative, finite number, or null (written where it is undefined).
  void check_std_error(const json& v, const std::string& pointer, const std::string& key) const {
    if (v.is_null()) return;
    if (v.is_array()) {
      for (std::size_t i = 0; i < v.size(); ++i)
        if (!v.at(i).is_null()) check_std_error(v.at(i), pointer + "/" + std::to_string(i), key + "[" + std::to_string(i) + "]");
      return;
    }
    const double x = number(v, pointer, "std_errors." + key);
    if (!(x >= 0)) fail(pointer, "std_errors." + key + " = " + number_text(x) + " must not be negative (a standard error)");
  }

  std::string unknown_effect(const fx::Catalogue& catalogue, const std::string& name) const {
    std::vector<std::string> known;
    for (const fx::Effect& e : catalogue)
      if (e.home != fx::Home::base) known.emplace_back(e.name);
    return "unknown effect '" + name + "' for a " + facts_->name + " model (the effects a " + facts_->name +
           " model file holds: " + joined(known) + ", and covariate:COLUMN)" + did_you_mean(name, known);
  }

  /// Element values of parameter p of effect `id`, checked against the registry's range.
  template <class Effects>
  void set(Effects& e, std::size_t id, std::size_t p, const std::vector<double>& values, const std::string& pointer,
           const std::string& what) const {
    fx::for_each_param(e, [&](std::size_t eid, int pid, int k, double& slot) {
      if (eid != id || static_cast<std::size_t>(pid) != p) return;
      const double v = values[static_cast<std::size_t>(k)];
      const fx::Param& param = catalogue_param(id, p);
      if (!fx::Effect::admissible(param, v))
        fail(values.size() > 1 ? pointer + "/" + std::to_string(k) : pointer,
             what + (values.size() > 1 ? "[" + std::to_string(k) + "]" : "") + " = " + number_text(v) +
                 " is outside its physical range " + range_text(param.lower, param.upper, false, false, param.unit) +
                 " (neutral " + number_text(param.neutral) + ")");
      slot = v;
    });
  }
  const fx::Param& catalogue_param(std::size_t id, std::size_t p) const {
    return (*fx::catalogue(facts_->name))[id].params[p];
  }

  const json& j_;
  std::string path_;
  std::string robot_;
  const json* robot_set_ = nullptr;
  const models::KindFacts* facts_ = nullptr;
};

template <std::size_t N>
std::array<double, N> to_array(const std::vector<double>& v) {
  std::array<double, N> a{};
  for (std::size_t i = 0; i < N; ++i) a[i] = v[i];
  return a;
}

void require_finite(double v, const std::string& what) {
  if (!std::isfinite(v)) throw std::domain_error("cannot write " + what + ": it is not finite (" + number_text(v) + ")");
}

/// The effects section and the parameters-home effects of a model, through the registry: an
/// effect is written when any of its values is not neutral.
template <class Model>
void write_effects(Model m, json& parameters, json& effects) {
  const fx::Catalogue& catalogue = fx::catalogue_of(m);
  std::vector<std::vector<json>> values(catalogue.size());  // [effect][param]: a number or an array
  for (std::size_t id = 0; id < catalogue.size(); ++id) values[id].resize(catalogue[id].params.size());
  std::vector<bool> active(catalogue.size(), false);
  fx::for_each_param(fx::effects_of(m), [&](std::size_t id, int p, int /*element: in order*/, double& v) {
    const fx::Param& param = catalogue[id].params[static_cast<std::size_t>(p)];
    require_finite(v, std::string("effects.") + catalogue[id].name + "." + param.key);
    if (v != param.neutral) active[id] = true;
    json& slot = values[id][static_cast<std::size_t>(p)];
    if (param.count == 1) slot = v;
    else {
      if (!slot.is_array()) slot = json::array();
      slot.push_back(v);
    }
  });
  for (std::size_t id = 0; id < catalogue.size(); ++id) {
    const fx::Effect& e = catalogue[id];
    if (e.home == fx::Home::parameters) {
      for (std::size_t p = 0; p < e.params.size(); ++p) parameters[e.params[p].file_key] = values[id][p];
    } else if (e.home == fx::Home::effects && active[id]) {
      json o = json::object();
      for (std::size_t p = 0; p < e.params.size(); ++p) o[e.params[p].key] = values[id][p];
      effects[e.name] = o;
    }
  }
  for (const auto& c : m.covariates) {
    require_finite(c.slope, "the covariate effect " + c.column + "'s slope");
    require_finite(c.centre, "the covariate effect " + c.column + "'s centre");
    effects[std::string(fx::kCovariatePrefix) + c.column] = {{"slope", c.slope}, {"centre", c.centre}};
  }
}

template <class Model>
json with_common(const char* kind, json parameters, const Model& m) {
  json j;
  j["kind"] = kind;
  json effects = json::object();
  write_effects(m, parameters, effects);
  for (auto it = parameters.begin(); it != parameters.end(); ++it)
    if (it.value().is_number()) require_finite(it.value().get<double>(), std::string("parameters.") + it.key());
  j["parameters"] = parameters;
  j["effects"] = effects;
  return j;
}

template <std::size_t N>
std::vector<double> vec(const std::array<double, N>& a) {
  return {a.begin(), a.end()};
}

/// `read(robot)`, the model asked for, after reading every other set of the file too (the pooled
/// one and each robot's): a file that one of its sets makes invalid is refused whichever set is
/// read, so that the CLI (the pooled set) and ARGoS (a robot's) refuse the same files.
template <class Read>
auto every_set(const json& j, const std::string& robot, const Read& read) {
  if (j.is_object() && j.contains("robots") && j.at("robots").is_object()) {
    if (!robot.empty()) read(std::string());
    for (auto it = j.at("robots").begin(); it != j.at("robots").end(); ++it)
      if (it.key() != robot) read(it.key());
  }
  return read(robot);
}

/// The model `m` written as `j`, read back by `read` (the readers' validation): a value the reader
/// would refuse is refused at write, std::domain_error with the reader's reason, so that what is
/// written always reads back.
template <class Read>
json readable(json j, const Read& read) {
  try {
    read(j, std::string("(the model being written)"), std::string());
  } catch (const logs::InputError& e) {
    throw std::domain_error(std::string("cannot write this model, a reader would refuse it: ") + e.what());
  }
  return j;
}

/// A model's sections `j` (model_to_json's) as a calibration file holds them (`c` non-null): no
/// empty `effects` section, and each channel of `c->pooled_sd` with that sd, beside each sensor's
/// (`per_sensor_sd`, the model's) for a channel of several sensors; a channel of one sensor has its
/// model's sd alone, which the calibration's must then be.
json as_calibration(json j, const CalibrationExtras* c) {
  if (c == nullptr) return j;
  if (j.contains("effects") && j.at("effects").empty()) j.erase("effects");
  const models::KindFacts& facts = *models::kind_facts(j.at("kind").get<std::string>());
  for (const auto& [name, sd] : c->pooled_sd) {
    const models::Channel* channel = nullptr;
    for (const models::Channel& ch : facts.channels)
      if (name == ch.name) channel = &ch;
    if (channel == nullptr || !j.at("noise").contains(name))
      throw std::domain_error("cannot write the noise of '" + name + "': a " + facts.name + " model has no such channel");
    json& e = j["noise"][name];
    if (channel->sensors > 1) {
      if (!e.contains("per_sensor_sd")) e["per_sensor_sd"] = std::vector<double>(static_cast<std::size_t>(channel->sensors), e.at("sd").get<double>());
      require_finite(sd, "noise." + name + ".sd");
      e["sd"] = sd;
    } else if (!(sd == e.at("sd").get<double>())) {
      throw std::domain_error("cannot write noise." + name + ".sd = " + number_text(sd) + ": the model's is " + e.at("sd").dump() +
                              " (a channel of one sensor has one sd, the model's)");
    }
  }
  return j;
}

// The camera's range: positive, at most 10 m, ten times the plug-in's 1 m (models/camera.hpp
// kCameraRange_m; paper 4.1.6), beyond which an LED is far below a pixel of a 160 px image.
constexpr double kCameraMaxRange_m = 10.0;

/// What the camera's calibration holds fixed or derives (range_m, width_px, height_px,
/// aperture_deg), each checked when present.
void camera_extras(const Doc& d, const s::CameraModel& m) {
  std::string at;
  if (d.find("parameters", "range_m", at) && !(m.base.range_m > 0 && m.base.range_m <= kCameraMaxRange_m))
    d.fail(at, "parameters.range_m = " + number_text(m.base.range_m) + " is outside its physical range " +
                   range_text(0, kCameraMaxRange_m, true, false, "m"));
  if (const json* v = d.find("parameters", "width_px", at); v && d.number(*v, at, "parameters.width_px") != s::kCameraWidth_px)
    d.fail(at, "parameters.width_px = " + v->dump() + " is not the E-Puck2 camera's image width, " + std::to_string(s::kCameraWidth_px) +
                   " px (the model's image; cx_px is checked against it)");
  if (const json* v = d.find("parameters", "height_px", at); v && d.number(*v, at, "parameters.height_px") != s::kCameraHeight_px)
    d.fail(at, "parameters.height_px = " + v->dump() + " is not the E-Puck2 camera's image height, " + std::to_string(s::kCameraHeight_px) +
                   " px (the model's image; cy_px is checked against it)");
  if (const json* v = d.find("parameters", "aperture_deg", at)) {
    // Derived from fov_deg by the calibration (lib/calibrate camera_report.cpp): the two must agree.
    const double a = d.number(*v, at, "parameters.aperture_deg");
    const double expected = s::rad_to_deg(s::aperture_from_horizontal_fov_rad(m.base.horizontal_fov_rad));
    if (!(std::abs(a - expected) <= 1e-6 * std::max(1.0, expected)))
      d.fail(at, "parameters.aperture_deg = " + number_text(a) + " does not match fov_deg (its half-angle on the image diagonal is " +
                     number_text(expected) + " deg); the aperture follows the field of view, write fov_deg alone");
  }
}

}  // namespace

json noise_json(const std::vector<double>& sd, const std::string& unit) {
  json c;
  double sum = 0, top = 0;
  bool same = true;
  for (double v : sd) {
    if (!(v >= 0) || !std::isfinite(v)) throw std::domain_error("cannot write a noise sd of " + number_text(v) + " " + unit);
    sum += v * v;
    top = std::max(top, v);
    same = same && v == sd[0];
  }
  double rms = std::sqrt(sum / static_cast<double>(sd.size()));
  if (!std::isfinite(rms)) {  // the squares overflowed: the same root mean square, scaled
    double scaled = 0;
    for (double v : sd) scaled += (v / top) * (v / top);
    rms = top * std::sqrt(scaled / static_cast<double>(sd.size()));
  }
  c["sd"] = same ? sd[0] : rms;
  if (!same) c["per_sensor_sd"] = sd;
  c["unit"] = unit;
  return c;
}

std::vector<std::string> robot_ids(const json& j) {
  std::vector<std::string> out;
  if (j.is_object() && j.contains("robots") && j.at("robots").is_object())
    for (auto it = j.at("robots").begin(); it != j.at("robots").end(); ++it) out.push_back(it.key());
  return out;
}

// ----- proximity -----

s::ProximityModel proximity_model_from_json(const json& j, const std::string& path, const std::string& robot) {
  return proximity_model_from_json(j, path, robot, ProximityCurve::maxima);
}

s::ProximityModel proximity_model_from_json(const json& j, const std::string& path, const std::string& robot,
                                            ProximityCurve curve) {
  return every_set(j, robot, [&](const std::string& r) {
    const Doc d(j, path, r, "proximity");
    const std::string prefix = curve == ProximityCurve::means ? "mean_" : "";
    s::ProximityModel m;
    m.base.a_per_m2 = d.base1(prefix + "a");
    m.base.b_per_m = d.base1(prefix + "b");
    m.base.c = d.base1(prefix + "c");
    m.base.range_m = d.base1("range_m", m.base.range_m);
    // The other curve, where the file has it: in the same ranges whichever curve is read.
    const std::string other = curve == ProximityCurve::means ? "" : "mean_";
    for (const char* k : {"a", "b", "c"}) {
      std::string at;
      if (d.find("parameters", other + k, at)) d.base1(other + k);
    }
    d.effects(fx::proximity_catalogue(), m.effects, m.covariates);
    m.noise_sd_raw = to_array<s::kProximityCount>(d.noise(d.facts().channels[0]));
    return m;
  });
}

namespace {
json write_model(const s::ProximityModel& m, const CalibrationExtras* c) {
  json j = with_common("proximity", {{"a", m.base.a_per_m2}, {"b", m.base.b_per_m}, {"c", m.base.c}, {"range_m", m.base.range_m}}, m);
  j["noise"] = {{"proximity", noise_json(vec(m.noise_sd_raw), "counts")}};
  return readable(as_calibration(j, c), [](const json& w, const std::string& p, const std::string& r) { return proximity_model_from_json(w, p, r); });
}
}  // namespace

json model_to_json(const s::ProximityModel& m) { return write_model(m, nullptr); }

// ----- light -----

namespace {

/// A light calibration's per-sensor fits into `m.sensor_gamma_m`: the `per_sensor` entries
/// ({"sensor": 0..7, "gamma"}), each in gamma's physical range; a sensor without an entry, or
/// whose entry says it could not be fitted ({"usable": false, "why"}), keeps the set's gamma. A
/// robot's set reads its own list (`robots.ID.per_sensor`) and never the file's: the file's are the
/// pooled robots' fits, which would override the robot's own gamma on every sensor they list; a
/// robot's set without a list reads its gamma on every sensor.
void read_sensor_gammas(const Doc& d, const json& j, const std::string& robot, s::LightModel& m) {
  std::string pointer = "/per_sensor";
  const json* list = j.contains("per_sensor") ? &j.at("per_sensor") : nullptr;
  if (!robot.empty()) {
    const json& set = j.at("robots").at(robot);
    list = set.contains("per_sensor") ? &set.at("per_sensor") : nullptr;
    pointer = "/robots/" + token(robot) + "/per_sensor";
  }
  if (!list) return;
  if (!list->is_array()) d.fail(pointer, "per_sensor must be an array of {\"sensor\", \"gamma\"}");
  const models::BaseParam& range = *d.facts().base_param("gamma");
  for (std::size_t i = 0; i < list->size(); ++i) {
    const json& e = list->at(i);
    const std::string at = pointer + "/" + std::to_string(i);
    const std::string what = "per_sensor[" + std::to_string(i) + "]";
    if (!e.is_object() || !e.contains("sensor"))
      d.fail(at, what + " must be an object with \"sensor\" and \"gamma\"");
    for (auto k = e.begin(); k != e.end(); ++k)
      if (!contains(kPerSensorKeys, k.key()))
        d.fail(at + "/" + token(k.key()), "unknown key '" + k.key() + "' in " + what + " (a sensor's fit holds " + joined(kPerSensorKeys) +
                                              ")" + did_you_mean(k.key(), kPerSensorKeys));
    const double k = d.number(e.at("sensor"), at + "/sensor", what + ".sensor");
    if (!(k >= 0 && k < static_cast<double>(s::kProximityCount)) || k != std::floor(k))
      d.fail(at + "/sensor", what + ".sensor must be a light sensor's number, 0 to 7 (found " + number_text(k) + ")");
    // A sensor the calibration could not fit ({"usable": false, "why"}) keeps the common gamma.
    if (e.contains("usable") && e.at("usable") == false && !e.contains("gamma")) continue;
    if (!e.contains("gamma")) d.fail(at, what + " must be an object with \"sensor\" and \"gamma\"");
    const double g = d.number(e.at("gamma"), at + "/gamma", what + ".gamma");
    if (!(g > range.lower && g <= range.upper))
      d.fail(at + "/gamma", what + ".gamma = " + number_text(g) + " is outside its physical range " +
                                range_text(range.lower, range.upper, range.open_lower, range.open_upper, range.unit));
    if (m.sensor_gamma_m[static_cast<std::size_t>(k)])
      d.fail(at + "/sensor", what + ".sensor: sensor " + number_text(k) + " has an entry already (one per sensor)");
    m.sensor_gamma_m[static_cast<std::size_t>(k)] = g;
  }
}

}  // namespace

s::LightModel light_model_from_json(const json& j, const std::string& path, const std::string& robot) {
  return every_set(j, robot, [&](const std::string& r) {
    const Doc d(j, path, r, "light");
    s::LightModel m;
    m.base.gamma_m = d.base1("gamma");
    m.base.range_m = d.base1("range_m", m.base.range_m);
    read_sensor_gammas(d, j, r, m);  // the per-sensor fits, checked by every reader alike
    d.effects(fx::light_catalogue(), m.effects, m.covariates);
    m.noise_sd_raw = to_array<s::kProximityCount>(d.noise(d.facts().channels[0]));
    return m;
  });
}

namespace {
json write_model(const s::LightModel& m, const CalibrationExtras* c) {
  json j = with_common("light", {{"gamma", m.base.gamma_m}, {"range_m", m.base.range_m}}, m);
  json per = json::array();
  for (std::size_t k = 0; k < m.sensor_gamma_m.size(); ++k)
    if (m.sensor_gamma_m[k]) {
      require_finite(*m.sensor_gamma_m[k], "per_sensor[" + std::to_string(per.size()) + "].gamma");
      per.push_back({{"sensor", k}, {"gamma", *m.sensor_gamma_m[k]}});
    }
  if (!per.empty()) j["per_sensor"] = per;
  j["noise"] = {{"light", noise_json(vec(m.noise_sd_raw), "counts")}};
  return readable(as_calibration(j, c), [](const json& w, const std::string& p, const std::string& r) { return light_model_from_json(w, p, r); });
}
}  // namespace

json model_to_json(const s::LightModel& m) { return write_model(m, nullptr); }

// ----- ground -----

s::GroundModel ground_model_from_json(const json& j, const std::string& path, const std::string& robot) {
  return every_set(j, robot, [&](const std::string& r) {
    const Doc d(j, path, r, "ground");
    s::GroundModel m;
    const auto gain = d.base("gain", s::kGroundCount);
    const auto offset = d.base("offset", s::kGroundCount);
    for (std::size_t k = 0; k < m.sensors.size(); ++k) m.sensors[k] = {gain[k], offset[k]};
    d.effects(fx::ground_catalogue(), m.effects, m.covariates);
    m.noise_sd_raw = to_array<s::kGroundCount>(d.noise(d.facts().channels[0]));
    return m;
  });
}

namespace {
json write_model(const s::GroundModel& m, const CalibrationExtras* c) {
  std::array<double, s::kGroundCount> gain{}, offset{};
  for (std::size_t k = 0; k < m.sensors.size(); ++k) {
    gain[k] = m.sensors[k].gain_raw;
    offset[k] = m.sensors[k].offset_raw;
    require_finite(gain[k], "parameters.gain");
    require_finite(offset[k], "parameters.offset");
  }
  json j = with_common("ground", {{"gain", gain}, {"offset", offset}}, m);
  j["noise"] = {{"ground", noise_json(vec(m.noise_sd_raw), "counts")}};
  return readable(as_calibration(j, c), [](const json& w, const std::string& p, const std::string& r) { return ground_model_from_json(w, p, r); });
}
}  // namespace

json model_to_json(const s::GroundModel& m) { return write_model(m, nullptr); }

// ----- camera -----

s::CameraModel camera_model_from_json(const json& j, const std::string& path, const std::string& robot) {
  return every_set(j, robot, [&](const std::string& r) {
    const Doc d(j, path, r, "camera");
    s::CameraModel m;
    m.base.horizontal_fov_rad = s::deg_to_rad(d.base1("fov_deg"));
    m.base.cx_px = d.base1("cx_px");
    m.base.cy_px = d.base1("cy_px");
    m.base.range_m = d.base1("range_m", m.base.range_m);
    camera_extras(d, m);
    d.effects(fx::camera_catalogue(), m.distortion, m.covariates);
    m.noise_sd_px = d.noise(d.facts().channels[0])[0];
    return m;
  });
}

/// A number of degrees that a reader turns back into exactly `rad` (deg_to_rad is a rounded
/// product, so rad_to_deg(rad) may read back an ulp off): rad_to_deg(rad) when it does, else the
/// nearest within 8 ulps that does; false when none does.
bool exact_degrees(double rad, double& deg) {
  deg = s::rad_to_deg(rad);
  if (s::deg_to_rad(deg) == rad) return true;
  for (int k = 1; k <= 8; ++k)
    for (const double toward : {std::numeric_limits<double>::infinity(), -std::numeric_limits<double>::infinity()}) {
      double x = deg;
      for (int i = 0; i < k; ++i) x = std::nextafter(x, toward);
      if (s::deg_to_rad(x) == rad) {
        deg = x;
        return true;
      }
    }
  return false;
}

/// The field of view written so that what is read back writes the same text again: the degrees
/// that read back to `rad` exactly, or, for radians no number of degrees gives, those of the
/// nearest radians one does (the model read back then differs from `rad` by an ulp).
double degrees_that_read_back(double rad) {
  double deg;
  if (exact_degrees(rad, deg) || exact_degrees(s::deg_to_rad(s::rad_to_deg(rad)), deg)) return deg;
  return s::rad_to_deg(rad);
}

namespace {
json write_model(const s::CameraModel& m, const CalibrationExtras* c) {
  if (m.base.width_px != s::kCameraWidth_px || m.base.height_px != s::kCameraHeight_px)
    throw std::domain_error("cannot write a camera model of a " + std::to_string(m.base.width_px) + "x" + std::to_string(m.base.height_px) +
                            " px image: a coefficient file's camera is the E-Puck2's, " + std::to_string(s::kCameraWidth_px) + "x" +
                            std::to_string(s::kCameraHeight_px) + " px");
  double fov_deg = degrees_that_read_back(m.base.horizontal_fov_rad);
  if (c != nullptr && std::isfinite(c->fov_deg)) {
    // The calibration's own degrees, when they are the model's radians exactly.
    if (!(s::deg_to_rad(c->fov_deg) == m.base.horizontal_fov_rad))
      throw std::domain_error("cannot write fov_deg = " + number_text(c->fov_deg) + ": it is not the model's field of view (" +
                              number_text(m.base.horizontal_fov_rad) + " rad)");
    fov_deg = c->fov_deg;
  }
  json parameters = {{"fov_deg", fov_deg}, {"cx_px", m.base.cx_px}, {"cy_px", m.base.cy_px}};
  if (m.base.range_m != s::kCameraRange_m || c != nullptr) parameters["range_m"] = m.base.range_m;  // the plug-in's 1 m when absent
  if (c != nullptr) {
    // What a calibration holds fixed (the image) or derives (ARGoS's aperture), each checked by the reader.
    parameters["width_px"] = s::kCameraWidth_px;
    parameters["height_px"] = s::kCameraHeight_px;
    parameters["aperture_deg"] = s::rad_to_deg(s::aperture_from_horizontal_fov_rad(m.base.horizontal_fov_rad));
  }
  json j = with_common("camera", parameters, m);
  j["noise"] = {{"camera", noise_json({m.noise_sd_px}, "px")}};
  return readable(as_calibration(j, c), [](const json& w, const std::string& p, const std::string& r) { return camera_model_from_json(w, p, r); });
}
}  // namespace

json model_to_json(const s::CameraModel& m) { return write_model(m, nullptr); }

// ----- drive -----

bool firmware_cap_refuted(const json& j) {
  if (!j.is_object() || !j.contains("firmware_cap")) return false;
  const json& cap = j.at("firmware_cap");
  return cap.is_object() && cap.contains("kept") && cap.at("kept") == false;
}

s::DriveModel drive_model_from_json(const json& j, const std::string& path, const std::string& robot) {
  return every_set(j, robot, [&](const std::string& r) {
    const Doc d(j, path, r, "drive");
    s::DriveModel m;
    m.steps_per_m = d.base1("steps_per_m");
    d.effects(fx::drive_catalogue(), m.effects, m.covariates);
    m.tof_noise_sd_mm = d.noise(d.facts().channels[0])[0];
    m.encoder_noise_sd_steps = d.noise(d.facts().channels[1])[0];
    // A calibration's robot runs under the e-puck2 firmware's cap (1100 steps/s over its
    // steps_per_m): its `firmware_cap` (drive -o writes it), unless the calibration found the
    // wheels beat it (`kept` false). A diagnosis's cap is its speed_limit effect.
    m.firmware_cap = j.is_object() && j.contains("firmware_cap") && j.at("firmware_cap").is_object() && !firmware_cap_refuted(j);
    return m;
  });
}

namespace {
json write_model(const s::DriveModel& m, const CalibrationExtras* c) {
  json j = with_common("drive", {{"steps_per_m", m.steps_per_m}}, m);
  j["noise"] = {{"tof", noise_json({m.tof_noise_sd_mm}, "mm")}, {"encoder", noise_json({m.encoder_noise_sd_steps}, "steps")}};
  return readable(as_calibration(j, c), [](const json& w, const std::string& p, const std::string& r) { return drive_model_from_json(w, p, r); });
}
}  // namespace

json model_to_json(const s::DriveModel& m) { return write_model(m, nullptr); }

// ----- battery -----

s::BatteryModel battery_model_from_json(const json& j, const std::string& path, const std::string& robot) {
  return battery_model_from_json(j, path, robot, nullptr);
}

s::BatteryModel battery_model_from_json(const json& j, const std::string& path, const std::string& robot, TableSources& sources) {
  return battery_model_from_json(j, path, robot, &sources);
}

s::BatteryModel battery_model_from_json(const json& j, const std::string& path, const std::string& robot, TableSources* sources) {
  const Doc d(j, path, robot, "battery");
  s::BatteryModel m;
  m.tables = sources ? battery_tables_from_json(j, path, *sources) : battery_tables_from_json(j, path);
  if (j.contains("battery_model")) {
    const json& name = j.at("battery_model");
    if (!name.is_string() || !models::battery::parse_model(name.get<std::string>(), m.model))
      d.fail("/battery_model", "battery_model must be one of simple, linear, cubic, approximated (found " + name.dump() + ")");
  }
  d.effects(fx::battery_catalogue(), m.capacity, m.covariates);
  if (d.has_section("noise")) {
    m.noise_sd = d.noise(d.facts().channels[0])[0];
  } else {
    // A calibration file (`epuck2-fit battery -o`) has each speed's residual sd (`noise_sd`):
    // their root mean square.
    double sum = 0;
    int n = 0;
    const models::Channel& charge = d.facts().channels[0];
    for (std::size_t i = 0; i < j.at("speeds").size(); ++i) {
      const json& speed = j.at("speeds").at(i);
      if (!speed.contains("noise_sd") || speed.at("noise_sd").is_null()) continue;  // null: not measured
      const std::string at = "/speeds/" + std::to_string(i) + "/noise_sd";
      const double sd = d.number(speed.at("noise_sd"), at, "speeds[" + std::to_string(i) + "].noise_sd");
      if (!(sd >= 0 && sd < charge.full_scale))
        d.fail(at, "speeds[" + std::to_string(i) + "].noise_sd: a reading's noise sd must lie in [0, " + number_text(charge.full_scale) +
                       ") charge (found " + number_text(sd) + ")");
      sum += sd * sd;
      ++n;
    }
    m.noise_sd = n > 0 ? std::sqrt(sum / n) : 0.0;
  }
  return m;
}

json model_to_json(const s::BatteryModel& m) {
  json j = battery_tables_to_json(m.tables);
  for (const auto& speed : j.at("speeds"))
    for (const auto& [k, v] : speed.items())
      if (v.is_number()) require_finite(v.get<double>(), "the battery tables");
  j["kind"] = "battery";
  j["battery_model"] = std::string(models::battery::to_string(m.model));
  json parameters = json::object(), effects = json::object();
  write_effects(m, parameters, effects);
  j["effects"] = effects;
  j["noise"] = {{"charge", noise_json({m.noise_sd}, "charge")}};
  return readable(j, [](const json& w, const std::string& p, const std::string& r) { return battery_model_from_json(w, p, r); });
}

// ----- a calibration's file -----

json calibration_model_json(const s::ProximityModel& maxima, const s::ProximityModel& means, const CalibrationExtras& extras) {
  json j = write_model(maxima, &extras);
  // The second curve: Eq. 1 fitted to the means (ProximityCurve::means reads it).
  j["parameters"]["mean_a"] = means.base.a_per_m2;
  j["parameters"]["mean_b"] = means.base.b_per_m;
  j["parameters"]["mean_c"] = means.base.c;
  for (const char* k : {"mean_a", "mean_b", "mean_c"}) require_finite(j["parameters"][k].get<double>(), std::string("parameters.") + k);
  return readable(j, [](const json& w, const std::string& p, const std::string& r) {
    return proximity_model_from_json(w, p, r, ProximityCurve::means);
  });
}
json calibration_model_json(const s::LightModel& m, const CalibrationExtras& extras) { return write_model(m, &extras); }
json calibration_model_json(const s::GroundModel& m, const CalibrationExtras& extras) { return write_model(m, &extras); }
json calibration_model_json(const s::CameraModel& m, const CalibrationExtras& extras) { return write_model(m, &extras); }
json calibration_model_json(const s::DriveModel& m, const CalibrationExtras& extras) { return write_model(m, &extras); }

void add_robot_set(json& j, const std::string& kind, const std::string& id, const json& set) {
  const bool had_robots = j.contains("robots");
  const json before = had_robots && j.at("robots").contains(id) ? j.at("robots").at(id) : json();
  j["robots"][id] = set;
  try {
    (void)model_from_json(kind, j, "(the file being written)", id);
  } catch (const logs::InputError& e) {
    // Left as it was.
    if (!before.is_null()) j["robots"][id] = before;
    else if (had_robots) j["robots"].erase(id);
    else j.erase("robots");
    throw std::domain_error("cannot write robot " + id + "'s set, a reader would refuse it: " + e.what());
  }
}

std::optional<double> camera_range_m(const json& j, const std::string& path, const std::string& robot) {
  const s::CameraModel m = camera_model_from_json(j, path, robot);  // every value checked
  const Doc d(j, path, robot, "camera");
  std::string at;
  if (!d.find("parameters", "range_m", at)) return std::nullopt;
  return m.base.range_m;
}

// ----- from a file -----

json read_json_file(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw logs::InputError(path, 0, 0, "cannot open the file for reading");
  std::stringstream ss;
  ss << in.rdbuf();
  const std::string text = ss.str();
  try {
    return json::parse(text);
  } catch (const json::parse_error& e) {
    // e.byte is the 1-based offset of the character where parsing failed.
    const logs::SourcePos at = logs::position_of(text, e.byte > 0 ? e.byte - 1 : 0);
    throw logs::InputError(path, at.line, at.column, std::string("invalid JSON: ") + e.what());
  } catch (const json::exception& e) {
    // E.g. a number too large for a double (1e999): nlohmann says what, not where.
    const logs::SourcePos at = logs::locate_json_overflow(text);
    throw logs::InputError(path, at.line, at.column,
                           std::string("invalid JSON: ") + e.what() + (at.line > 0 ? " (a number too large for a double)" : ""));
  }
}

namespace {

// One reader per model type, so that read_model_file is written once.
s::ProximityModel from_json(const json& j, const std::string& path, const std::string& robot, s::ProximityModel*) {
  return proximity_model_from_json(j, path, robot);
}
s::LightModel from_json(const json& j, const std::string& path, const std::string& robot, s::LightModel*) {
  return light_model_from_json(j, path, robot);
}
s::GroundModel from_json(const json& j, const std::string& path, const std::string& robot, s::GroundModel*) {
  return ground_model_from_json(j, path, robot);
}
s::CameraModel from_json(const json& j, const std::string& path, const std::string& robot, s::CameraModel*) {
  return camera_model_from_json(j, path, robot);
}
s::DriveModel from_json(const json& j, const std::string& path, const std::string& robot, s::DriveModel*) {
  return drive_model_from_json(j, path, robot);
}
s::BatteryModel from_json(const json& j, const std::string& path, const std::string& robot, s::BatteryModel*) {
  return battery_model_from_json(j, path, robot);
}

// The kind of each model type: the one table from a kind's name to its model type.
const char* model_kind(s::ProximityModel*) { return "proximity"; }
const char* model_kind(s::LightModel*) { return "light"; }
const char* model_kind(s::GroundModel*) { return "ground"; }
const char* model_kind(s::CameraModel*) { return "camera"; }
const char* model_kind(s::DriveModel*) { return "drive"; }
const char* model_kind(s::BatteryModel*) { return "battery"; }

/// out = make(static_cast<Model*>(nullptr)) for the model type of the kind `kind`; false when no
/// model type is of that kind.
template <class Make, std::size_t... I>
bool make_of_kind(const std::string& kind, AnyModel& out, const Make& make, std::index_sequence<I...>) {
  return ((kind == model_kind(static_cast<std::variant_alternative_t<I, AnyModel>*>(nullptr)) &&
           (out = make(static_cast<std::variant_alternative_t<I, AnyModel>*>(nullptr)), true)) ||
          ...);
}
template <class Make>
AnyModel make_of_kind(const std::string& kind, const Make& make) {
  AnyModel out;
  if (!make_of_kind(kind, out, make, std::make_index_sequence<std::variant_size_v<AnyModel>>{}))
    throw std::invalid_argument("no model of the kind '" + kind + "'");
  return out;
}

}  // namespace

std::string kind_of(const AnyModel& m) {
  return std::visit([](const auto& model) { return std::string(model_kind(static_cast<std::decay_t<decltype(model)>*>(nullptr))); }, m);
}

AnyModel model_from_json(const std::string& kind, const json& j, const std::string& path, const std::string& robot) {
  return make_of_kind(kind, [&](auto* type) -> AnyModel { return from_json(j, path, robot, type); });
}

AnyModel plugin_model(const std::string& kind) {
  return make_of_kind(kind, [](auto* type) -> AnyModel { return std::remove_pointer_t<decltype(type)>{}; });
}

template <class Model>
Model read_model_file(const std::string& path, const std::string& robot) {
  return from_json(read_json_file(path), path, robot, static_cast<Model*>(nullptr));
}
template s::ProximityModel read_model_file<s::ProximityModel>(const std::string&, const std::string&);
template s::LightModel read_model_file<s::LightModel>(const std::string&, const std::string&);
template s::GroundModel read_model_file<s::GroundModel>(const std::string&, const std::string&);
template s::CameraModel read_model_file<s::CameraModel>(const std::string&, const std::string&);
template s::DriveModel read_model_file<s::DriveModel>(const std::string&, const std::string&);
template s::BatteryModel read_model_file<s::BatteryModel>(const std::string&, const std::string&);

}  // namespace epuck2::coefficients
