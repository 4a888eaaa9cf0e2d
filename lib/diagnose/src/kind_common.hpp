// Internal to the diagnosis's kinds (kind_*.cpp): the helpers every kind's problem is built with
// (the catalogue's parameters, the base model given in place of the plug-in's), and the factory
// of each kind that kinds.cpp's make_problem picks from.
#pragma once

#include <algorithm>
#include <cstdio>
#include <deque>
#include <mutex>
#include <optional>
#include <cmath>
#include <cstdint>
#include <set>
#include <type_traits>
#include <variant>

#include "epuck2/diagnose/diagnose.hpp"
#include "epuck2/fit/robust.hpp"
#include "epuck2/models/effects.hpp"
#include "epuck2/models/plugin_battery_tables.hpp"
#include "epuck2/models/sensors.hpp"
#include "problem.hpp"
#include "screening.hpp"

namespace epuck2::diagnose::detail {

namespace kinds_shared {

using namespace epuck2::fit;  // the engine (lib/fit)

namespace s = models::sensors;
namespace fx = models::effects;

/// The base model given (Options::base_model) in place of the plug-in's published one: parameter
/// j's value with its effect off, and in the published model, is the base's `v`; a start that was
/// the old neutral value moves with it.
inline void set_base(Problem& p, int j, double v) {
  fit::Parameter& q = p.params[static_cast<std::size_t>(j)];
  if (q.value == q.fallback) q.value = v;
  q.fallback = v;
  q.lower = std::min(q.lower, v);
  q.upper = std::max(q.upper, v);
  p.plugin_values[static_cast<std::size_t>(j)] = v;
}

inline int add_param(Problem& p, const std::string& name, double neutral, double start, double lower = -kInf, double upper = kInf) {
  p.params.push_back({name, start, neutral, lower, upper, false, {}});
  p.plugin_values.push_back(neutral);
  return static_cast<int>(p.params.size()) - 1;
}

/// Every parameter of a kind's catalogue effects (lib/models' registry): one per element, named
/// KEY or KEY[k], with the registry's neutral value, start and range; the kind's effects list the
/// effect with all of them (kinds narrow per-sensor effects to the sensors the logs hold).
/// [effect][parameter][element] -> index into Problem::params.
using CatalogueIndex = std::vector<std::vector<std::vector<int>>>;
inline CatalogueIndex add_catalogue(Problem& p, const fx::Catalogue& catalogue) {
  CatalogueIndex ix(catalogue.size());
  for (std::size_t id = 0; id < catalogue.size(); ++id) {
    const fx::Effect& e = catalogue[id];
    Effect effect{e.name, {}};
    for (const fx::Param& q : e.params) {
      ix[id].emplace_back();
      for (int k = 0; k < q.count; ++k) {
        const std::string name = q.count == 1 ? std::string(q.key) : std::string(q.key) + "[" + std::to_string(k) + "]";
        ix[id].back().push_back(add_param(p, name, q.neutral, q.start, q.lower, q.upper));
        p.param_units.resize(p.params.size());
        p.param_units.back() = q.unit;
        effect.params.push_back(ix[id].back().back());
      }
    }
    p.effects.push_back(effect);
  }
  return ix;
}

/// The effect of the catalogue in p.effects (added by add_catalogue).
inline Effect& effect_of(Problem& p, const fx::Catalogue& catalogue, std::size_t id) {
  for (Effect& e : p.effects)
    if (e.cause == catalogue[id].name) return e;
  throw std::logic_error("the catalogue's effect " + std::string(catalogue[id].name) + " is not in the problem");
}
inline void drop_effect(Problem& p, const fx::Catalogue& catalogue, std::size_t id) {
  p.effects.erase(std::remove_if(p.effects.begin(), p.effects.end(), [&](const Effect& e) { return e.cause == catalogue[id].name; }),
                  p.effects.end());
}

/// The kind's effect struct (lib/models) at the parameters p, through the registry's visitor.
template <class Effects, class T>
inline void fill_effects(const CatalogueIndex& ix, const T* p, Effects& e) {
  fx::for_each_param(e, [&](std::size_t id, int q, int k, auto& slot) {
    slot = p[ix[id][static_cast<std::size_t>(q)][static_cast<std::size_t>(k)]];
  });
}

/// A base model's effects (a calibration's or a diagnosis's file) as the parameters' off values.
template <class Effects>
inline void set_base_effects(Problem& p, const CatalogueIndex& ix, Effects e) {
  fx::for_each_param(e, [&](std::size_t id, int q, int k, double& v) {
    set_base(p, ix[id][static_cast<std::size_t>(q)][static_cast<std::size_t>(k)], v);
  });
}

inline std::vector<int> sensors_seen(const std::vector<double>& sensor) {
  std::set<int> seen;
  for (double v : sensor) seen.insert(static_cast<int>(v));
  return {seen.begin(), seen.end()};
}

/// A kind's problem with the base model given (Options::base_model) in place of the plug-in's:
/// it must be of the logs' kind (make_problem checks).
template <class P>
std::unique_ptr<Problem> with_base(std::unique_ptr<P> problem, const Options& options) {
  using Model = typename P::BaseModel;
  if (std::holds_alternative<Model>(options.base_model)) problem->set_base_model(std::get<Model>(options.base_model));
  return problem;
}

}  // namespace kinds_shared

// Each kind's problem over its logs (kind_ground.cpp, kind_proximity.cpp, kind_light.cpp,
// kind_camera.cpp, kind_drive.cpp, kind_battery.cpp).
std::unique_ptr<Problem> make_ground(const std::vector<logs::Log>& logs, const Options& options);
std::unique_ptr<Problem> make_proximity(const std::vector<logs::Log>& logs, const Options& options);
std::unique_ptr<Problem> make_light(const std::vector<logs::Log>& logs, const Options& options);
std::unique_ptr<Problem> make_camera(const std::vector<logs::Log>& logs, const Options& options);
std::unique_ptr<Problem> make_drive(const std::vector<logs::Log>& logs, const Options& options);
std::unique_ptr<Problem> make_battery(const std::vector<logs::Log>& logs, const Options& options);

}  // namespace epuck2::diagnose::detail
