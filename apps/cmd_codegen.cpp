// epuck2-fit codegen COEFFICIENT_FILES... -o HEADER: the C++ header of fitted coefficients that
// the runtime model library compiles in (data/fitted/include/epuck2/fitted/coefficients.hpp).
// Its first lines name every source file and its FNV-1a 64-bit hash; a test regenerates it and
// fails when the committed copy differs.
#include <algorithm>
#include <cctype>
#include <cstdio>
#include <fstream>
#include <iostream>
#include <map>
#include <set>
#include <sstream>

#include "app_support.hpp"
#include "epuck2/calibrate/model_file.hpp"
#include "epuck2/logs/json_location.hpp"
#include "commands.hpp"
#include "epuck2/calibrate/battery_json.hpp"
#include "epuck2/logs/output.hpp"

namespace epuck2::app {

namespace {
namespace mb = models::battery;

struct CodegenOptions {
  std::vector<std::string> inputs;
  std::string output;
};

std::uint64_t fnv1a64(const std::string& bytes) {
  std::uint64_t h = 1469598103934665603ull;
  for (unsigned char c : bytes) {
    h ^= c;
    h *= 1099511628211ull;
  }
  return h;
}

std::string num(double v) { return logs::format_number(v); }

/// A key as one token of a JSON pointer (RFC 6901: ~ and / escaped).
std::string pointer_token(const std::string& key) {
  std::string t;
  for (const char c : key) t += c == '~' ? std::string("~0") : c == '/' ? std::string("~1") : std::string(1, c);
  return t;
}

bool is_identifier(const std::string& s) {
  if (s.empty() || std::isdigit(static_cast<unsigned char>(s[0]))) return false;
  for (char c : s)
    if (!(std::isalnum(static_cast<unsigned char>(c)) || c == '_')) return false;
  return true;
}

// C++ keywords and alternative tokens (C++20's included: the header may be compiled as C++20).
const std::set<std::string>& keywords() {
  static const std::set<std::string> k{
      "alignas", "alignof", "and", "and_eq", "asm", "auto", "bitand", "bitor", "bool", "break", "case", "catch", "char",
      "char8_t", "char16_t", "char32_t", "class", "compl", "concept", "const", "consteval", "constexpr", "constinit",
      "const_cast", "continue", "co_await", "co_return", "co_yield", "decltype", "default", "delete", "do", "double",
      "dynamic_cast", "else", "enum", "explicit", "export", "extern", "false", "float", "for", "friend", "goto", "if",
      "inline", "int", "long", "mutable", "namespace", "new", "noexcept", "not", "not_eq", "nullptr", "operator", "or",
      "or_eq", "private", "protected", "public", "register", "reinterpret_cast", "requires", "return", "short",
      "signed", "sizeof", "static", "static_assert", "static_cast", "struct", "switch", "template", "this",
      "thread_local", "throw", "true", "try", "typedef", "typeid", "typename", "union", "unsigned", "using",
      "virtual", "void", "volatile", "wchar_t", "while", "xor", "xor_eq"};
  return k;
}

// Names the generated header itself uses unqualified where a kind's namespace or a constant of
// that name would be found first (`std::array`, `models::battery::Tables`), and lower-case
// macros of the standard headers it includes.
const std::set<std::string>& taken_names() {
  static const std::set<std::string> t{"std", "models", "epuck2", "fitted", "battery_tables", "assert", "errno", "offsetof",
                                       "setjmp", "va_arg", "va_copy", "va_end", "va_start", "stdin", "stdout",
                                       "stderr", "math_errhandling"};
  return t;
}

/// Why `name` cannot be a C++ name in the generated header ("" when it can): [A-Za-z_][A-Za-z0-9_]*,
/// not a keyword, not reserved (a double underscore, or an underscore and a capital first), not
/// a name the header relies on, not all capitals (the macros' convention: NULL, EOF, NAN).
std::string identifier_problem(const std::string& name) {
  if (!is_identifier(name)) return "is not a C++ identifier ([A-Za-z_][A-Za-z0-9_]*)";
  if (keywords().count(name)) return "is a C++ keyword";
  if (name.find("__") != std::string::npos || (name.size() > 1 && name[0] == '_' && std::isupper(static_cast<unsigned char>(name[1]))))
    return "is reserved to the implementation (a double underscore, or an underscore and a capital)";
  if (taken_names().count(name)) return "would hide a name the generated header uses (std, models, ...) or a macro";
  if (std::none_of(name.begin(), name.end(), [](char c) { return std::islower(static_cast<unsigned char>(c)); }))
    return "is all capitals, the convention of macros (NULL, EOF, NAN): a macro of that name breaks the header";
  return "";
}

void emit_battery(std::ostringstream& os, const nlohmann::json& j, const std::string& path) {
  const mb::Tables t = calibrate::battery_tables_from_json(j, path);
  os << "#define EPUCK2_FITTED_HAS_BATTERY 1\n\n";
  os << "/// The four discharge models' tables fitted from " << path << ".\n";
  os << "inline const models::battery::Tables& battery_tables() {\n";
  os << "  static const models::battery::Tables tables = [] {\n";
  os << "    models::battery::Tables t{};\n";
  for (int s = 0; s < mb::kSpeedCount; ++s) {
    const auto& q = t.cubic[static_cast<std::size_t>(s)];
    os << "    // " << s << " cm/s\n";
    os << "    t.cubic[" << s << "] = {" << num(q.d) << ", " << num(q.c) << ", " << num(q.b) << ", " << num(q.a) << ", "
       << num(q.end_s) << "};\n";
    for (int k = 0; k < mb::kSegmentCount; ++k) {
      const auto& g = t.segments[static_cast<std::size_t>(s)][static_cast<std::size_t>(k)];
      os << "    t.segments[" << s << "][" << k << "] = {" << num(g.h) << ", " << num(g.m) << ", " << num(g.x1_s) << ", "
         << num(g.x2_s) << ", " << num(g.y1) << ", " << num(g.y2) << "};\n";
    }
    os << "    t.linear_slope_per_s[" << s << "] = " << num(t.linear_slope_per_s[static_cast<std::size_t>(s)]) << ";\n";
    os << "    t.lifetime_s[" << s << "] = " << num(t.lifetime_s[static_cast<std::size_t>(s)]) << ";\n";
  }
  os << "    t.simple_static_slope_per_s = " << num(t.simple_static_slope_per_s) << ";\n";
  os << "    t.simple_moving_slope_per_s = " << num(t.simple_moving_slope_per_s) << ";\n";
  os << "    return t;\n  }();\n  return tables;\n}\n";
}

// The battery as a model (kinds.hpp BatteryModel): the tables above, the discharge model, the
// capacity scale a diagnosis found (1 for a calibration) and the charge reading's noise.
std::string covariates_code(const std::vector<models::sensors::CovariateEffect>& covariates);

void emit_battery_model(std::ostringstream& os, const nlohmann::json& j, const std::string& path) {
  const models::sensors::BatteryModel m = calibrate::battery_model_from_json(j, path);
  os << "\n/// The battery model of " << path << ": the discharge model, the tables above, the capacity scale and the\n"
     << "/// charge reading's noise.\n"
     << "inline models::sensors::BatteryModel battery_model() {\n  models::sensors::BatteryModel m;\n"
     << "  m.model = models::battery::Model::" << mb::to_string(m.model) << ";\n"
     << "  m.tables = battery_tables();\n"
     << "  m.capacity.k = " << num(m.capacity.k) << ";\n"
     << "  m.noise_sd = " << num(m.noise_sd) << ";\n" << covariates_code(m.covariates) << "  return m;\n}\n";
}

// Any other kind: every numeric entry of "parameters" (and "std_errors") as a named constant.
void emit_parameters(std::ostringstream& os, const nlohmann::json& j, const std::string& path, const std::string& kind) {
  os << "namespace " << kind << " {\n";
  // Every constant's name, with the parameter it comes from: two of the same name (a parameter
  // named `mse`, or `x_std_error` beside x's standard error) would not compile.
  std::map<std::string, std::string> emitted;
  auto declare = [&](const std::string& name, const std::string& from) {
    const auto [it, fresh] = emitted.emplace(name, from);
    if (!fresh)
      throw logs::InputError(path, 0, 0, "the constant '" + kind + "::" + name + "' would be declared twice (from " +
                                             it->second + " and from " + from + ")");
  };
  for (const char* section : {"parameters", "std_errors"}) {
    if (!j.contains(section)) {
      if (std::string(section) == "parameters")
        throw logs::json_file_error(path, "", "expected a 'parameters' object");
      continue;
    }
    const nlohmann::json& p = j.at(section);
    if (!p.is_object()) throw logs::json_file_error(path, std::string("/") + section, std::string("'") + section + "' must be an object");
    const std::string suffix = std::string(section) == "std_errors" ? "_std_error" : "";
    for (const auto& [key, value] : p.items()) {
      const std::string problem = identifier_problem(key);
      if (!problem.empty())
        throw logs::json_file_error(path, std::string("/") + section + "/" + pointer_token(key),
                                    std::string(section) + ": the name '" + key + "' " + problem);
      const std::string from = std::string(section) + "." + key;
      if (value.is_number()) {
        declare(key + suffix, from);
        os << "inline constexpr double " << key << suffix << " = " << num(value.get<double>()) << ";\n";
      } else if (value.is_array() && !value.empty() && std::all_of(value.begin(), value.end(), [](const auto& v) { return v.is_number(); })) {
        declare(key + suffix, from);
        os << "inline constexpr std::array<double, " << value.size() << "> " << key << suffix << "{";
        for (std::size_t i = 0; i < value.size(); ++i) os << (i ? ", " : "") << num(value.at(i).get<double>());
        os << "};\n";
      }
    }
  }
  if (j.contains("mse") && j.at("mse").is_number()) {
    declare("mse", "mse");
    os << "inline constexpr double mse = " << num(j.at("mse").get<double>()) << ";\n";
  }
  os << "}  // namespace " << kind << "\n";
}

template <std::size_t N>
std::string array_of(const std::array<double, N>& a) {
  std::string s = "{";
  for (std::size_t i = 0; i < N; ++i) s += (i ? ", " : "") + num(a[i]);
  return s + "}";
}

/// `  m.covariates = {{"NAME", slope, centre}, ...};` for a model with covariate:NAME effects
/// (nothing for one without: the calibration files' headers are unchanged).
std::string covariates_code(const std::vector<models::sensors::CovariateEffect>& covariates) {
  if (covariates.empty()) return "";
  std::string out = "  m.covariates = {";
  for (std::size_t i = 0; i < covariates.size(); ++i) {
    std::string name;
    for (char ch : covariates[i].column) {
      if (ch == '"' || ch == '\\') name += '\\';
      name += ch;
    }
    out += std::string(i ? ", " : "") + "{\"" + name + "\", " + num(covariates[i].slope) + ", " + num(covariates[i].centre) + "}";
  }
  return out + "};\n";
}

/// The kind's model (lib/models kinds.hpp) as a function returning a constant instance, in the
/// units the model takes (radians for the camera's field of view), read from the file by the same
/// reader `simulate --like` uses (lib/calibrate model_file).
void emit_model(std::ostringstream& os, const nlohmann::json& j, const std::string& path, const std::string& kind) {
  namespace s = models::sensors;
  auto model_error = [&](const std::exception& e) { return logs::json_file_error(path, "", e.what()); };
  try {
    if (kind == "proximity") {
      const s::ProximityModel m = calibrate::proximity_model_from_json(j, path);
      const auto& e = m.effects;
      os << "/// The proximity model of " << path << ": base, effects, reading noise (counts).\n"
         << "inline models::sensors::ProximityModel proximity_model() {\n  models::sensors::ProximityModel m;\n"
         << "  m.base = {" << num(m.base.a_per_m2) << ", " << num(m.base.b_per_m) << ", " << num(m.base.c) << ", " << num(m.base.range_m) << "};\n"
         << "  m.effects.ambient.offset_raw = " << num(e.ambient.offset_raw) << ";\n"
         << "  m.effects.gains.gain = " << array_of(e.gains.gain) << ";\n"
         << "  m.effects.tail.amplitude_raw = " << num(e.tail.amplitude_raw) << ";\n"
         << "  m.effects.tail.length_m = " << num(e.tail.length_m) << ";\n"
         << "  m.effects.incidence.k = " << num(e.incidence.k) << ";\n"
         << "  m.effects.saturation.level_raw = " << num(e.saturation.level_raw) << ";\n"
         << "  m.noise_sd_raw = " << array_of(m.noise_sd_raw) << ";\n" << covariates_code(m.covariates) << "  return m;\n}\n";
    } else if (kind == "light") {
      const s::LightModel m = calibrate::light_model_from_json(j, path);
      os << "/// The light model of " << path << ": base, effects, reading noise (counts).\n"
         << "inline models::sensors::LightModel light_model() {\n  models::sensors::LightModel m;\n"
         << "  m.base.gamma_m = " << num(m.base.gamma_m) << ";\n  m.base.range_m = " << num(m.base.range_m) << ";\n"
         << "  m.effects.ambient.offset_raw = " << num(m.effects.ambient.offset_raw) << ";\n"
         << "  m.effects.falloff.exponent = " << num(m.effects.falloff.exponent) << ";\n"
         << "  m.effects.gains.gain = " << array_of(m.effects.gains.gain) << ";\n"
         << "  m.noise_sd_raw = " << array_of(m.noise_sd_raw) << ";\n" << covariates_code(m.covariates) << "  return m;\n}\n";
    } else if (kind == "ground") {
      const s::GroundModel m = calibrate::ground_model_from_json(j, path);
      os << "/// The ground model of " << path << ": per-sensor gain and black offset, effects, reading noise (counts).\n"
         << "inline models::sensors::GroundModel ground_model() {\n  models::sensors::GroundModel m;\n";
      for (std::size_t k = 0; k < m.sensors.size(); ++k)
        os << "  m.sensors[" << k << "] = {" << num(m.sensors[k].gain_raw) << ", " << num(m.sensors[k].offset_raw) << "};\n";
      os << "  m.effects.exponent = " << num(m.effects.exponent) << ";\n"
         << "  m.noise_sd_raw = " << array_of(m.noise_sd_raw) << ";\n" << covariates_code(m.covariates) << "  return m;\n}\n";
    } else if (kind == "camera") {
      const s::CameraModel m = calibrate::camera_model_from_json(j, path);
      os << "/// The camera model of " << path << " (field of view in radians), distortion, pixel noise.\n"
         << "inline models::sensors::CameraModel camera_model() {\n  models::sensors::CameraModel m;\n"
         << "  m.base.horizontal_fov_rad = " << num(m.base.horizontal_fov_rad) << ";\n"
         << "  m.base.cx_px = " << num(m.base.cx_px) << ";\n  m.base.cy_px = " << num(m.base.cy_px) << ";\n"
         << "  m.distortion.k1 = " << num(m.distortion.k1) << ";\n"
         << "  m.noise_sd_px = " << num(m.noise_sd_px) << ";\n" << covariates_code(m.covariates) << "  return m;\n}\n";
    } else if (kind == "drive") {
      const s::DriveModel m = calibrate::drive_model_from_json(j, path);
      const auto& e = m.effects;
      os << "/// The drive model of " << path << ": encoders, effects, ToF and encoder noise.\n"
         << "inline models::sensors::DriveModel drive_model() {\n  models::sensors::DriveModel m;\n"
         << "  m.steps_per_m = " << num(m.steps_per_m) << ";\n"
         << "  m.effects.speed_limit.max_cm_s = " << num(e.speed_limit.max_cm_s) << ";\n"
         << "  m.effects.accel_limit.accel_cm_s2 = " << num(e.accel_limit.accel_cm_s2) << ";\n"
         << "  m.effects.slip.tau_s = " << num(e.slip.tau_s) << ";\n"
         << "  m.effects.speed_scale.k = " << num(e.speed_scale.k) << ";\n"
         << "  m.effects.latency.delay_s = " << num(e.latency.delay_s) << ";\n"
         << "  m.effects.tof_offset.offset_mm = " << num(e.tof_offset.offset_mm) << ";\n"
         << "  m.effects.tof_scale.k = " << num(e.tof_scale.k) << ";\n"
         << "  m.tof_noise_sd_mm = " << num(m.tof_noise_sd_mm) << ";\n"
         << "  m.encoder_noise_sd_steps = " << num(m.encoder_noise_sd_steps) << ";\n" << covariates_code(m.covariates) << "  return m;\n}\n";
    }
  } catch (const logs::InputError&) {
    throw;
  } catch (const std::runtime_error& e) {
    throw model_error(e);
  }
}

int run_codegen(const CodegenOptions& o) {
  std::ostringstream body;
  std::ostringstream head;
  head << "// GENERATED by `epuck2-fit codegen";
  for (const auto& in : o.inputs) head << ' ' << in;
  // Regenerated by the same command (scripts/regenerate.sh runs it for data/fitted).
  head << " -o " << o.output << "`: do not edit; regenerate with the same command.\n";
  std::ostringstream fitted_from;  // the logs each coefficient file says it was fitted to (`sources`)
  std::map<std::string, std::string> kinds;  // kind -> its file
  for (const auto& in : o.inputs) {
    std::ifstream f(in, std::ios::binary);
    if (!f) throw logs::InputError(in, 0, 0, "cannot open the file for reading");
    std::stringstream ss;
    ss << f.rdbuf();
    char hash[32];
    std::snprintf(hash, sizeof hash, "%016llx", static_cast<unsigned long long>(fnv1a64(ss.str())));
    head << "// source: " << in << " fnv1a64 " << hash << "\n";
    const nlohmann::json j = read_json(in);
    if (!j.is_object() || !j.contains("kind") || !j.at("kind").is_string())
      throw logs::json_file_error(in, j.is_object() && j.contains("kind") ? "/kind" : "",
                                  "not a coefficient file: expected an object with a string 'kind'");
    const std::string kind = j.at("kind").get<std::string>();
    fitted_from << "// " << kind << " (" << in << ") fitted from";
    // A calibration's file names its logs in `sources`, a diagnosis's in `logs`.
    const char* const list = j.contains("sources") ? "sources" : "logs";
    if (j.contains(list) && j.at(list).is_array() && !j.at(list).empty()) {
      for (const auto& src : j.at(list))
        if (src.is_string()) fitted_from << ' ' << logs::escape_control(src.get<std::string>());
    } else {
      fitted_from << " logs it does not name (no `sources` or `logs`)";
    }
    fitted_from << "\n";
    const std::string problem = identifier_problem(kind);
    if (!problem.empty()) throw logs::json_file_error(in, "/kind", "the kind '" + kind + "' " + problem);
    // One file per kind: a second would define the same namespace's constants (or the battery
    // tables) twice.
    const auto [first, fresh] = kinds.emplace(kind, in);
    if (!fresh)
      throw logs::json_file_error(in, "/kind", "a second coefficient file of kind '" + kind + "' (the first is " + first->second +
                                                   "): give one file per kind");
    body << "\n// ---- " << kind << " (" << in << ") ----\n";
    if (kind == "battery") {
      emit_battery(body, j, in);
      emit_battery_model(body, j, in);
    } else {
      emit_parameters(body, j, in, kind);
      emit_model(body, j, in, kind);
    }
  }
  std::ostringstream out;
  out << head.str();
  out << "// Coefficients fitted by epuck2-fit from these logs:\n" << fitted_from.str();
  out << "#pragma once\n\n#include <array>\n\n#include \"epuck2/models/battery.hpp\"\n#include \"epuck2/models/kinds.hpp\"\n\nnamespace epuck2::fitted {\n";
  out << body.str();
  out << "\n}  // namespace epuck2::fitted\n";
  logs::write_file_atomically(o.output, out.str());
  std::cerr << "codegen: wrote " << o.output << '\n';
  return 0;
}
}  // namespace

void setup_codegen(CLI::App& app, Action& action) {
  auto o = std::make_shared<CodegenOptions>();
  CLI::App* sub = app.add_subcommand("codegen", "Write the C++ header of fitted coefficients compiled into lib/models");
  sub->add_option("files", o->inputs, "Coefficient files (JSON) written by the fitting subcommands")->required()->check(CLI::ExistingFile);
  sub->add_option("-o,--output", o->output, "The header to write (atomically)")->type_name("FILE")->required()->check(output_file());
  sub->callback([o, &action] { action = [o] { return run_codegen(*o); }; });
}

}  // namespace epuck2::app
