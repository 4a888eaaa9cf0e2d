// epuck2-fit codegen COEFFICIENT_FILES... -o HEADER: the C++ header of fitted coefficients that
// the runtime model library compiles in (data/fitted/include/epuck2/fitted/coefficients.hpp).
// Its first lines name every source file and its FNV-1a 64-bit hash; a test regenerates it and
// fails when the committed copy differs.
#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <iostream>
#include <map>
#include <set>
#include <sstream>

#include "app_support.hpp"
#include "epuck2/coefficients/model_file.hpp"
#include "epuck2/logs/json_location.hpp"
#include "commands.hpp"
#include "epuck2/coefficients/codegen.hpp"
#include "epuck2/logs/output.hpp"
#include "epuck2/models/kind_facts.hpp"

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

/// A number as C++ source. A NaN or an infinity is never written (the header would not compile,
/// or would compile a model that reads NaN): a runtime_error, which the file's reading turns into
/// an error naming the file.
std::string num(double v) {
  if (!std::isfinite(v))
    throw std::runtime_error("a coefficient evaluates to " + logs::format_number(v) + ", not a finite number; no header was written");
  return logs::format_number(v);
}

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

/// The kind's model (lib/models kinds.hpp) as a function returning a constant instance, in the
/// units the model takes (radians for the camera's field of view), read and written by the
/// coefficient file's owner (lib/coefficients), the same reader `simulate --like` uses.
/// A kind that has no model (not one of kind_facts'): its parameters alone.
void emit_model(std::ostringstream& os, const nlohmann::json& j, const std::string& path, const std::string& kind) {
  if (models::kind_facts(kind) == nullptr) return;
  try {
    os << coefficients::model_to_cpp(coefficients::model_from_json(kind, j, path), path);
  } catch (const std::domain_error& e) {
    throw logs::json_file_error(path, "", e.what());
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
    try {
      // A kind whose base model has named coefficients (not the battery's tables): them too.
      const models::KindFacts* facts = models::kind_facts(kind);
      if (facts == nullptr || !facts->base.empty()) emit_parameters(body, j, in, kind);
      emit_model(body, j, in, kind);
    } catch (const logs::InputError&) {
      throw;
    } catch (const std::runtime_error& e) {
      throw logs::json_file_error(in, "", e.what());  // num()'s refusal: the file it came from
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
  sub->add_option("-o,--output", o->output, "The header to write (atomically; -: to standard output)")->type_name("FILE")->required()->check(output_file());
  sub->callback([o, &action] { action = [o] { return run_codegen(*o); }; });
}

}  // namespace epuck2::app
