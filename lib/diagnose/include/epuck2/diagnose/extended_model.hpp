// The model a diagnosis ends with, as a coefficient file: the base model's parameters in the
// final joint fit (or the base the diagnosis started from, for kinds without free base
// parameters), every finding that lib/models can represent as an effect, and the final
// residual noise. `diagnose -o` writes it into its report, so that the report doubles as a
// coefficient file for `simulate KIND --like`, `codegen` and the ARGoS plug-in
// (lib/calibrate model_file.hpp).
#pragma once

#include <nlohmann/json.hpp>

#include <string>
#include <vector>

#include "epuck2/diagnose/diagnose.hpp"
#include "epuck2/models/kinds.hpp"

namespace epuck2::diagnose {

/// The extended model of a report, for the kinds lib/models has a model type of (proximity,
/// light, ground, camera, drive). `left_out` receives the findings no model type represents
/// (`covariate:` effects: a column the simulation does not know). Throws std::invalid_argument for
/// other kinds.
models::sensors::ProximityModel extended_proximity(const Report& r, std::vector<std::string>* left_out = nullptr);
models::sensors::LightModel extended_light(const Report& r, std::vector<std::string>* left_out = nullptr);
models::sensors::GroundModel extended_ground(const Report& r, std::vector<std::string>* left_out = nullptr);
models::sensors::CameraModel extended_camera(const Report& r, std::vector<std::string>* left_out = nullptr);
models::sensors::DriveModel extended_drive(const Report& r, std::vector<std::string>* left_out = nullptr);

/// {"kind", "parameters", "effects", "noise"} of the report's extended model (calibrate::
/// model_to_json), plus "effects_not_in_model" when some finding cannot be represented; an empty
/// object for kinds without a model type (battery).
nlohmann::json extended_model_json(const Report& r);

}  // namespace epuck2::diagnose
