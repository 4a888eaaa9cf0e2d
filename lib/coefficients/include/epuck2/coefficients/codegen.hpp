// A model as C++ (what `epuck2-fit codegen` writes into a header): a function returning the
// kind's model (lib/models kinds.hpp) as a constant instance, every effect of the registry with
// its value (neutral ones too), the noise and the covariate effects.
#pragma once

#include <nlohmann/json.hpp>

#include <string>
#include <vector>

#include "epuck2/coefficients/model_file.hpp"
#include "epuck2/models/kinds.hpp"

namespace epuck2::coefficients {

/// `inline models::sensors::ProximityModel proximity_model() {...}` (and so on) for the model read
/// from `source` (named in its comment). Throws std::domain_error for a value that is not finite.
std::string model_to_cpp(const models::sensors::ProximityModel& m, const std::string& source);
std::string model_to_cpp(const models::sensors::LightModel& m, const std::string& source);
std::string model_to_cpp(const models::sensors::GroundModel& m, const std::string& source);
std::string model_to_cpp(const models::sensors::CameraModel& m, const std::string& source);
std::string model_to_cpp(const models::sensors::DriveModel& m, const std::string& source);
/// battery_tables() and battery_model() (the tables, the discharge model, the capacity scale, the
/// noise), with EPUCK2_FITTED_HAS_BATTERY.
std::string model_to_cpp(const models::sensors::BatteryModel& m, const std::string& source);

/// The same for a model of any kind (the overload of its type).
std::string model_to_cpp(const AnyModel& m, const std::string& source);

/// `namespace KIND { inline constexpr double KEY = value; ... }`: every numeric entry of the file's
/// `parameters` and `std_errors` (KEY_std_error) and its `mse`, as named constants. A file of one
/// of the project's kinds is validated by its reader first (model_from_json: errors as theirs), so
/// that only accepted, in-range values are written; another kind's values are written as they are.
/// A name that is no C++ identifier, or a constant declared twice, is a logs::InputError at the
/// key's FILE:LINE:COLUMN and JSON path.
std::string parameters_to_cpp(const nlohmann::json& j, const std::string& path, const std::string& kind);

/// The whole header `epuck2-fit codegen INPUTS -o OUTPUT` writes: each input's name and FNV-1a
/// 64-bit hash, the logs it was fitted from, its constants (parameters_to_cpp) and its model
/// (model_to_cpp), one file per kind. Errors are logs::InputError located in the input.
/// `warnings`, when given, receives what the header's models hold that a user should know: a
/// battery file's Cubic tables the plug-in's arithmetic never empties (models::battery::argos_cubic_stalls).
std::string header_cpp(const std::vector<std::string>& inputs, const std::string& output,
                       std::vector<std::string>* warnings = nullptr);

/// A double as C++ source that reads back to the same value (shortest round trip).
std::string cpp_number(double v);

}  // namespace epuck2::coefficients
