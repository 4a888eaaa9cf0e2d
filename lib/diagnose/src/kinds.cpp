// The kinds' base models and catalogue effects for the diagnosis (docs/diagnose.md, "The
// catalogue"), each written once, templated on the scalar, over every row of the logs. Every
// effect is a parameter set whose neutral values give back the base model, so that the engine
// switches effects on by freeing their parameters.
// Each kind in its own file (kind_ground.cpp, kind_proximity.cpp, kind_light.cpp, kind_camera.cpp,
// kind_drive.cpp, kind_battery.cpp; their shared helpers: kind_common.hpp); here, the choice of
// the kind's problem for the logs, and the table of what the diagnosis does per kind
// (kind_table.hpp).
#include "kind_table.hpp"

#include "epuck2/coefficients/model_file.hpp"
#include "kind_common.hpp"

namespace epuck2::diagnose {

using namespace epuck2::fit;  // the engine (lib/fit)

namespace detail {

namespace {

/// A kind's extended model (extended_model.hpp) as a coefficient file.
template <auto Extended>
nlohmann::json extended_json(const Report& r, std::vector<std::string>* left_out, const ModelInputs& inputs) {
  return coefficients::model_to_json(Extended(r, left_out, inputs));
}

}  // namespace

const KindRow* kind_row(logs::Kind kind) {
  // The reading noise between replicates is what the kind's calibration measures (lib/calibrate).
  using Logs = std::vector<logs::Log>;
  static const KindRow rows[] = {
      {logs::Kind::ground, make_ground, extended_json<extended_ground>,
       [](const Logs& l) { return calibrate::fit_ground(l).noise; }},
      // The proximity's replicates are one distance and one incidence angle: every row counts here
      // (the calibration takes those facing the target only).
      {logs::Kind::proximity, make_proximity, extended_json<extended_proximity>, calibrate::proximity_replicate_noise},
      {logs::Kind::light, make_light, extended_json<extended_light>,
       [](const Logs& l) { return calibrate::fit_light(l).noise; }},
      {logs::Kind::camera, make_camera, extended_json<extended_camera>,
       [](const Logs& l) { return calibrate::fit_camera(l).noise; }},
      // The drive's replicates need no fit (on a 1M-row log the fits took most of the diagnosis's
      // time and memory).
      {logs::Kind::drive, make_drive, extended_json<extended_drive>, calibrate::drive_tof_replicate_noise},
      {logs::Kind::battery, make_battery, extended_json<extended_battery>, nullptr},
  };
  for (const KindRow& row : rows)
    if (row.kind == kind) return &row;
  return nullptr;
}

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
  const KindRow* row = kind_row(kind);
  if (!row) {
    why = "diagnose does not support the kind '" + std::string(logs::to_string(kind)) + "' yet";
    return nullptr;
  }
  std::unique_ptr<Problem> p = row->make(logs, options);
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

bool supported(logs::Kind kind) { return detail::kind_row(kind) != nullptr; }

}  // namespace epuck2::diagnose
