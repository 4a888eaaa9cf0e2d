// The model a diagnosis ends with, as a coefficient file: the base model's parameters in the
// final joint fit (or the base the diagnosis started from, for kinds without free base
// parameters), every finding that lib/models can represent as an effect, and the final
// residual noise. `diagnose -o` writes it into its report, so that the report doubles as a
// coefficient file for `simulate KIND --like`, `codegen` and the ARGoS plug-in
// (lib/calibrate model_file.hpp).
#pragma once

#include <nlohmann/json.hpp>

#include <map>
#include <optional>
#include <string>
#include <vector>

#include "epuck2/diagnose/diagnose.hpp"
#include "epuck2/diagnose/reading_noise.hpp"
#include "epuck2/models/kinds.hpp"

namespace epuck2::diagnose {

/// What an extended model needs besides the report: the mean of every numeric extra column over
/// the diagnosed rows (the centre of a `covariate:NAME` effect, reading = base + slope (NAME -
/// centre)), and for battery logs the discharge model and tables the diagnosis ran.
struct ModelInputs {
  std::map<std::string, double> column_means;
  models::battery::Model battery_model = models::battery::Model::cubic;
  std::optional<models::battery::Tables> battery_tables;  ///< none: the plug-in's (as Options)
  double battery_capacity_k = 1.0;                         ///< the base's capacity scale (as Options)
  /// Each channel's noise from the logs' replicates (reading_noise.hpp): the model's noise where
  /// present, else the final model's residuals.
  std::map<std::string, calibrate::ReadingNoise> replicate_noise;
  /// Whether every reading of the logs (the kind's reading columns, lib/models kind_facts.hpp) is a
  /// whole number: only then does the model's noise leave out the rounding's 1/12 unit^2 (a camera
  /// log may give px to 0.01, docs/logs.md: its scatter holds no rounding to take off).
  bool whole_readings = true;
};

/// The inputs of a diagnosis of `logs` under `options` (taken before the logs go to diagnose()):
/// the mean over all rows of every numeric extra column that every log has. (The diagnosis
/// centres on the mean over its residuals: the same rows less the wild readings it leaves out,
/// and for drive logs the ToF and encoder residuals; a column that does not follow the
/// experiment, such as a temperature, has the same mean over either to within its scatter.)
ModelInputs model_inputs(const std::vector<logs::Log>& logs, const Options& options);

/// The extended model of a report, one per kind (lib/models kinds.hpp). `left_out` receives the
/// findings no model type represents (a `covariate:NAME` whose column has no mean in `inputs`).
/// Throws std::invalid_argument when the report is of another kind.
models::sensors::ProximityModel extended_proximity(const Report& r, std::vector<std::string>* left_out = nullptr,
                                                   const ModelInputs& inputs = {});
models::sensors::LightModel extended_light(const Report& r, std::vector<std::string>* left_out = nullptr,
                                           const ModelInputs& inputs = {});
models::sensors::GroundModel extended_ground(const Report& r, std::vector<std::string>* left_out = nullptr,
                                             const ModelInputs& inputs = {});
models::sensors::CameraModel extended_camera(const Report& r, std::vector<std::string>* left_out = nullptr,
                                             const ModelInputs& inputs = {});
models::sensors::DriveModel extended_drive(const Report& r, std::vector<std::string>* left_out = nullptr,
                                           const ModelInputs& inputs = {});
/// The discharge model and tables of `inputs`, capacity_scale's k, the residual noise.
models::sensors::BatteryModel extended_battery(const Report& r, std::vector<std::string>* left_out = nullptr,
                                               const ModelInputs& inputs = {});

/// {"kind", "parameters" (battery: "battery_model", "speeds", "simple"), "effects", "noise"} of
/// the report's extended model (coefficients::model_to_json), plus "effects_not_in_model" when some
/// finding cannot be represented.
nlohmann::json extended_model_json(const Report& r, const ModelInputs& inputs = {});

}  // namespace epuck2::diagnose
