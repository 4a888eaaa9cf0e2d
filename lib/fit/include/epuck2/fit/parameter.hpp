// The one parameter type of every fit in the project: the least-squares engine (fit_curve), the
// robust and censored fit (fit_robust) and the diagnosis's joint fits all take parameters as
// `Parameter`s, with their names, bounds, documented fallback and fixed flag, and find them by
// name through `index_of`, which throws on a name it does not know (a typo is an error, never a
// NaN or a silent default).
#pragma once

#include <cstddef>
#include <limits>
#include <stdexcept>
#include <string>
#include <vector>

namespace epuck2::fit {

/// One parameter: name (with its unit), start, documented fallback, bounds, held or free.
struct Parameter {
  std::string name;
  double value = 0;  ///< start; the estimate after the fit
  /// The documented default (the plug-in's value) kept when the logs do not determine it. For
  /// the diagnosis: the value at which its effect is off (the plug-in's, for a base parameter).
  double fallback = std::numeric_limits<double>::quiet_NaN();
  double lower = -std::numeric_limits<double>::infinity();
  double upper = std::numeric_limits<double>::infinity();
  bool fixed = false;  ///< held by the caller at `value` (not an identifiability decision)
  /// More starting points, tried besides `value` where a search is multi-start (the diagnosis: a
  /// parameter whose cost has flat regions, as a speed limit above every command).
  std::vector<double> other_starts = {};
};

/// A free parameter starting at `start`, without bounds or fallback.
inline Parameter free_parameter(std::string name, double start) {
  Parameter p;
  p.name = std::move(name);
  p.value = start;
  return p;
}

/// A parameter held at `value`.
inline Parameter fixed_parameter(std::string name, double value) {
  Parameter p = free_parameter(std::move(name), value);
  p.fixed = true;
  return p;
}

/// Free parameters called `names`, starting at `starts` (the same length; std::invalid_argument
/// otherwise): for callers that hold a model's names and starts as lists (NIST's files).
inline std::vector<Parameter> free_parameters(const std::vector<std::string>& names, const std::vector<double>& starts) {
  if (names.size() != starts.size())
    throw std::invalid_argument(std::to_string(names.size()) + " parameter names for " + std::to_string(starts.size()) + " starts");
  std::vector<Parameter> out;
  for (std::size_t j = 0; j < names.size(); ++j) out.push_back(free_parameter(names[j], starts[j]));
  return out;
}

/// "a, b, c": the names, for messages.
inline std::string names_of(const std::vector<Parameter>& parameters) {
  std::string out;
  for (const Parameter& p : parameters) out += (out.empty() ? "" : ", ") + p.name;
  return out;
}

/// The index of the parameter called `name`; std::out_of_range naming it and the known ones when
/// there is none.
inline std::size_t index_of(const std::vector<Parameter>& parameters, const std::string& name) {
  for (std::size_t j = 0; j < parameters.size(); ++j)
    if (parameters[j].name == name) return j;
  throw std::out_of_range("no parameter named '" + name + "' (the parameters are: " + names_of(parameters) + ")");
}

/// The start (or estimate) of every parameter, in order.
inline std::vector<double> values_of(const std::vector<Parameter>& parameters) {
  std::vector<double> v;
  v.reserve(parameters.size());
  for (const Parameter& p : parameters) v.push_back(p.value);
  return v;
}

}  // namespace epuck2::fit
