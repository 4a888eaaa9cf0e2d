// A model as C++: see epuck2/coefficients/codegen.hpp. The effects' lines come from the registry
// (lib/models effects.hpp: each parameter's C++ member), so a new effect needs nothing here.
#include "epuck2/coefficients/codegen.hpp"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <fstream>
#include <map>
#include <set>
#include <sstream>
#include <stdexcept>
#include <vector>

#include "epuck2/logs/json_location.hpp"
#include "epuck2/logs/log.hpp"
#include "epuck2/logs/output.hpp"
#include "epuck2/models/kind_facts.hpp"
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

std::uint64_t fnv1a64(const std::string& bytes) {
  std::uint64_t h = 1469598103934665603ull;
  for (unsigned char c : bytes) {
    h ^= c;
    h *= 1099511628211ull;
  }
  return h;
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

/// `FILE:LINE:COLUMN` error about the value at JSON pointer `pointer` of the file `path`.
[[noreturn]] void refuse(const std::string& path, const std::string& pointer, const std::string& what) {
  throw logs::json_file_error(path, pointer, what);
}

std::string token(const std::string& key) {
  std::string t;
  for (const char c : key) t += c == '~' ? std::string("~0") : c == '/' ? std::string("~1") : std::string(1, c);
  return t;
}

}  // namespace

std::string parameters_to_cpp(const nlohmann::json& j, const std::string& path, const std::string& kind) {
  // A file of one of the project's kinds is read (validated) first: only what its reader accepts
  // is written, every key known and every value in its range.
  if (models::kind_facts(kind) != nullptr) (void)model_from_json(kind, j, path);
  std::ostringstream os;
  os << "namespace " << kind << " {\n";
  // Every constant's name, with the parameter it comes from and where: two of the same name (a
  // parameter named `mse`, or `x_std_error` beside x's standard error) would not compile.
  std::map<std::string, std::pair<std::string, std::string>> emitted;  // name -> (from, JSON pointer)
  auto declare = [&](const std::string& name, const std::string& from, const std::string& pointer) {
    const auto [it, fresh] = emitted.emplace(name, std::make_pair(from, pointer));
    if (!fresh)
      refuse(path, pointer, "the constant '" + kind + "::" + name + "' would be declared twice (from " + it->second.first + " at " +
                                (it->second.second.empty() ? std::string("/") : it->second.second) + " and from " + from + ")");
  };
  for (const char* section : {"parameters", "std_errors"}) {
    if (!j.contains(section)) {
      if (std::string(section) == "parameters") refuse(path, "", "expected a 'parameters' object");
      continue;
    }
    const nlohmann::json& p = j.at(section);
    if (!p.is_object()) refuse(path, std::string("/") + section, std::string("'") + section + "' must be an object");
    const std::string suffix = std::string(section) == "std_errors" ? "_std_error" : "";
    for (const auto& [key, value] : p.items()) {
      const std::string pointer = std::string("/") + section + "/" + token(key);
      const std::string problem = identifier_problem(key);
      if (!problem.empty()) refuse(path, pointer, std::string(section) + ": the name '" + key + "' " + problem);
      const std::string from = std::string(section) + "." + key;
      if (value.is_number()) {
        declare(key + suffix, from, pointer);
        os << "inline constexpr double " << key << suffix << " = " << cpp_number(value.get<double>()) << ";\n";
      } else if (value.is_array() && !value.empty() && std::all_of(value.begin(), value.end(), [](const auto& v) { return v.is_number(); })) {
        declare(key + suffix, from, pointer);
        os << "inline constexpr std::array<double, " << value.size() << "> " << key << suffix << "{";
        for (std::size_t i = 0; i < value.size(); ++i) os << (i ? ", " : "") << cpp_number(value.at(i).get<double>());
        os << "};\n";
      }
    }
  }
  if (j.contains("mse") && j.at("mse").is_number()) {
    declare("mse", "mse", "/mse");
    os << "inline constexpr double mse = " << cpp_number(j.at("mse").get<double>()) << ";\n";
  }
  os << "}  // namespace " << kind << "\n";
  return os.str();
}

std::string header_cpp(const std::vector<std::string>& inputs, const std::string& output, std::vector<std::string>* warnings) {
  std::ostringstream body;
  std::ostringstream head;
  head << "// GENERATED by `epuck2-fit codegen";
  for (const auto& in : inputs) head << ' ' << in;
  // Regenerated by the same command (scripts/regenerate.sh runs it for data/fitted).
  head << " -o " << output << "`: do not edit; regenerate with the same command.\n";
  std::ostringstream fitted_from;  // the logs each coefficient file says it was fitted to (`sources`)
  std::map<std::string, std::string> kinds;  // kind -> its file
  for (const auto& in : inputs) {
    std::ifstream f(in, std::ios::binary);
    if (!f) throw logs::InputError(in, 0, 0, "cannot open the file for reading");
    std::stringstream ss;
    ss << f.rdbuf();
    char hash[32];
    std::snprintf(hash, sizeof hash, "%016llx", static_cast<unsigned long long>(fnv1a64(ss.str())));
    head << "// source: " << in << " fnv1a64 " << hash << "\n";
    const nlohmann::json j = read_json_file(in);
    if (!j.is_object() || !j.contains("kind") || !j.at("kind").is_string())
      refuse(in, j.is_object() && j.contains("kind") ? "/kind" : "", "not a coefficient file: expected an object with a string 'kind'");
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
    if (!problem.empty()) refuse(in, "/kind", "the kind '" + kind + "' " + problem);
    // One file per kind: a second would define the same namespace's constants (or the battery
    // tables) twice.
    const auto [first, fresh] = kinds.emplace(kind, in);
    if (!fresh) refuse(in, "/kind", "a second coefficient file of kind '" + kind + "' (the first is " + first->second + "): give one file per kind");
    body << "\n// ---- " << kind << " (" << in << ") ----\n";
    try {
      // The model of one of the project's kinds, read (validated) once; a kind the project has no
      // model of: its parameters alone, as named constants.
      const models::KindFacts* facts = models::kind_facts(kind);
      if (facts == nullptr || !facts->base.empty()) body << parameters_to_cpp(j, in, kind);
      if (facts != nullptr) {
        const AnyModel model = model_from_json(kind, j, in);
        body << model_to_cpp(model, in);
        // Tables the plug-in's own arithmetic cannot run: said, as `battery` said when it wrote them.
        if (const auto* battery = std::get_if<models::sensors::BatteryModel>(&model); battery != nullptr && warnings != nullptr)
          if (const auto stalls = mb::argos_cubic_stalls(battery->tables); !stalls.empty())
            warnings->push_back(in + ": " + mb::argos_cubic_stall_text(stalls));
      }
    } catch (const logs::InputError&) {
      throw;
    } catch (const std::runtime_error& e) {
      refuse(in, "", e.what());  // a value C++ cannot hold: the file it came from
    } catch (const std::domain_error& e) {
      refuse(in, "", e.what());
    }
  }
  std::ostringstream out;
  out << head.str();
  out << "// Coefficients fitted by epuck2-fit from these logs:\n" << fitted_from.str();
  out << "#pragma once\n\n#include <array>\n\n#include \"epuck2/models/battery.hpp\"\n#include \"epuck2/models/kinds.hpp\"\n\nnamespace epuck2::fitted {\n";
  out << body.str();
  out << "\n}  // namespace epuck2::fitted\n";
  return out.str();
}

namespace {
}  // namespace

std::string model_to_cpp(const AnyModel& m, const std::string& source) {
  return std::visit([&](const auto& model) { return model_to_cpp(model, source); }, m);
}

std::string model_to_cpp(const s::ProximityModel& m, const std::string& source) {
  (void)model_to_json(m);  // what the header holds reads as a coefficient file: the readers' checks refuse the rest
  std::ostringstream os;
  os << "/// The proximity model of " << source << ": base, effects, reading noise (counts).\n"
     << "inline models::sensors::ProximityModel proximity_model() {\n  models::sensors::ProximityModel m;\n"
     << "  m.base = {" << cpp_number(m.base.a_per_m2) << ", " << cpp_number(m.base.b_per_m) << ", " << cpp_number(m.base.c) << ", "
     << cpp_number(m.base.range_m) << "};\n"
     << effects_code(m) << "  m.noise_sd_raw = " << array_of(m.noise_sd_raw) << ";\n" << close(covariates_code(m.covariates));
  return os.str();
}

std::string model_to_cpp(const s::LightModel& m, const std::string& source) {
  (void)model_to_json(m);  // what the header holds reads as a coefficient file: the readers' checks refuse the rest
  std::ostringstream os;
  os << "/// The light model of " << source << ": base, effects, reading noise (counts).\n"
     << "inline models::sensors::LightModel light_model() {\n  models::sensors::LightModel m;\n"
     << "  m.base.gamma_m = " << cpp_number(m.base.gamma_m) << ";\n  m.base.range_m = " << cpp_number(m.base.range_m) << ";\n";
  for (std::size_t k = 0; k < m.sensor_gamma_m.size(); ++k)  // a calibration's per-sensor fits; the others take base.gamma_m
    if (m.sensor_gamma_m[k]) os << "  m.sensor_gamma_m[" << k << "] = " << cpp_number(*m.sensor_gamma_m[k]) << ";\n";
  os << effects_code(m) << "  m.noise_sd_raw = " << array_of(m.noise_sd_raw) << ";\n" << close(covariates_code(m.covariates));
  return os.str();
}

std::string model_to_cpp(const s::GroundModel& m, const std::string& source) {
  (void)model_to_json(m);  // what the header holds reads as a coefficient file: the readers' checks refuse the rest
  std::ostringstream os;
  os << "/// The ground model of " << source << ": per-sensor gain and black offset, effects, reading noise (counts).\n"
     << "inline models::sensors::GroundModel ground_model() {\n  models::sensors::GroundModel m;\n";
  for (std::size_t k = 0; k < m.sensors.size(); ++k)
    os << "  m.sensors[" << k << "] = {" << cpp_number(m.sensors[k].gain_raw) << ", " << cpp_number(m.sensors[k].offset_raw) << "};\n";
  os << effects_code(m) << "  m.noise_sd_raw = " << array_of(m.noise_sd_raw) << ";\n" << close(covariates_code(m.covariates));
  return os.str();
}

std::string model_to_cpp(const s::CameraModel& m, const std::string& source) {
  (void)model_to_json(m);  // what the header holds reads as a coefficient file: the readers' checks refuse the rest
  std::ostringstream os;
  os << "/// The camera model of " << source << " (field of view in radians), distortion, pixel noise.\n"
     << "inline models::sensors::CameraModel camera_model() {\n  models::sensors::CameraModel m;\n"
     << "  m.base.horizontal_fov_rad = " << cpp_number(m.base.horizontal_fov_rad) << ";\n"
     << "  m.base.cx_px = " << cpp_number(m.base.cx_px) << ";\n  m.base.cy_px = " << cpp_number(m.base.cy_px) << ";\n"
     << (m.base.range_m != s::kCameraRange_m ? "  m.base.range_m = " + cpp_number(m.base.range_m) + ";\n" : std::string())
     << effects_code(m) << "  m.noise_sd_px = " << cpp_number(m.noise_sd_px) << ";\n" << close(covariates_code(m.covariates));
  return os.str();
}

std::string model_to_cpp(const s::DriveModel& file_model, const std::string& source) {
  // The wheels as the model runs them: the file's cap (the firmware's 1100 steps/s over its
  // steps_per_m, where it has no speed_limit of its own) is the header's speed_limit.
  s::DriveModel m = file_model;
  m.effects = s::effects_as_run(file_model);
  const bool firmware = m.effects.speed_limit.max_cm_s != file_model.effects.speed_limit.max_cm_s;
  (void)model_to_json(m);  // what the header holds reads as a coefficient file: the readers' checks refuse the rest
  std::ostringstream os;
  os << "/// The drive model of " << source << ": encoders, effects, ToF and encoder noise"
     << (firmware ? std::string("; ") + fx::drive_catalogue()[fx::drive::speed_limit].name +
                        " the firmware's cap,\n/// 1100 steps/s over steps_per_m"
                  : std::string())
     << ".\n"
     << "inline models::sensors::DriveModel drive_model() {\n  models::sensors::DriveModel m;\n"
     << "  m.steps_per_m = " << cpp_number(m.steps_per_m) << ";\n"
     << effects_code(m) << "  m.tof_noise_sd_mm = " << cpp_number(m.tof_noise_sd_mm) << ";\n"
     << "  m.encoder_noise_sd_steps = " << cpp_number(m.encoder_noise_sd_steps) << ";\n" << close(covariates_code(m.covariates));
  return os.str();
}

std::string model_to_cpp(const s::BatteryModel& m, const std::string& source) {
  (void)model_to_json(m);  // what the header holds reads as a coefficient file: the readers' checks refuse the rest
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
