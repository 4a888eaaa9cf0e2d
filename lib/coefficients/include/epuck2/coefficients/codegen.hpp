// A model as C++ (what `epuck2-fit codegen` writes into a header): a function returning the
// kind's model (lib/models kinds.hpp) as a constant instance, every effect of the registry with
// its value (neutral ones too), the noise and the covariate effects.
#pragma once

#include <string>

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

/// A double as C++ source that reads back to the same value (shortest round trip).
std::string cpp_number(double v);

}  // namespace epuck2::coefficients
