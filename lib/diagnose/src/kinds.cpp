// The kinds' base models and catalogue effects for the diagnosis (docs/diagnose.md, "The
// catalogue"), each written once, templated on the scalar, over every row of the logs. Every
// effect is a parameter set whose neutral values give back the base model, so that the engine
// switches effects on by freeing their parameters.
// Each kind in its own file (kind_ground.cpp, kind_proximity.cpp, kind_light.cpp, kind_camera.cpp,
// kind_drive.cpp, kind_battery.cpp; their shared helpers: kind_common.hpp); here, the choice of
// the kind's problem for the logs.
#include "kind_common.hpp"

namespace epuck2::diagnose {

using namespace epuck2::fit;  // the engine (lib/fit)

namespace detail {

std::unique_ptr<Problem> make_problem(const std::vector<logs::Log>& logs, const Options& options, std::string& why) {
  const logs::Kind kind = logs.front().kind;
  for (const auto& l : logs)
    if (l.kind != kind) {
      why = "the logs are not all of one kind";
      return nullptr;
    }
  if (options.base_model.index() != 0 && base_model_kind(options.base_model) != kind) {
    why = std::string("the base model given is of the kind ") + std::string(logs::to_string(base_model_kind(options.base_model))) +
          ", the logs of the kind " + std::string(logs::to_string(kind));
    return nullptr;
  }
  std::unique_ptr<Problem> p;
  switch (kind) {
    case logs::Kind::ground: p = make_ground(logs, options); break;
    case logs::Kind::proximity: p = make_proximity(logs, options); break;
    case logs::Kind::light: p = make_light(logs, options); break;
    case logs::Kind::camera: p = make_camera(logs, options); break;
    case logs::Kind::drive: p = make_drive(logs, options); break;
    case logs::Kind::battery: p = make_battery(logs, options); break;
    default:
      why = "diagnose does not support the kind '" + std::string(logs::to_string(kind)) + "' yet";
      return nullptr;
  }
  // The kinds' optional columns of docs/logs.md are inputs of the model (angle_deg) or a
  // consequence of the measured quantity (voltage_v), never `covariate:` candidates.
  add_common_covariates(*p, logs, {"angle_deg", "voltage_v"});
  // Per-residual vectors grew by push_back (up to twice their size): give the slack back before
  // the fits, which run beside them.
  p->y.shrink_to_fit();
  p->row.shrink_to_fit();
  p->channel.shrink_to_fit();
  for (auto& c : p->covariates) c.second.shrink_to_fit();
  for (auto& c : p->extra_columns) c.second.shrink_to_fit();
  return p;
}

}  // namespace detail

std::string finding_meaning(const std::string& cause) {
  if (cause == "near_field_curve")
    return "the reading's curve within the sensor's range has another shape than the model's quadratic";
  return cause;
}

bool supported(logs::Kind kind) {
  switch (kind) {
    case logs::Kind::ground:
    case logs::Kind::proximity:
    case logs::Kind::light:
    case logs::Kind::camera:
    case logs::Kind::drive:
    case logs::Kind::battery: return true;
  }
  return false;
}

}  // namespace epuck2::diagnose
