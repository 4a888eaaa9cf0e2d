// Logs whose every cell is in range but whose numbers cannot be in the units the columns say:
// distances written in cm or mm, an obstacle farther than the ToF can see although the ToF sees
// it (docs/fitting.md#implausible-units). Fitted, they would give a calibration of nonsense (a
// proximity tail above full scale, a ToF offset stuck on its bound): they stop the run instead.
#pragma once

#include <vector>

#include "epuck2/logs/log.hpp"

namespace epuck2::calibrate {

/// A distance beyond a sensor's physical range by this factor is not in metres.
inline constexpr double kImplausibleRangeFactor = 10.0;

/// Throws logs::InputError (file, line, column, the column's name, the value, and the likely
/// unit, "centimetres?") at the first implausible value:
/// - proximity: `distance_m` beyond 10 x the sensor's 0.05 m ray (0.5 m);
/// - light: `distance_m` beyond 10 x the plug-in's 0.5 m light range (5 m);
/// - drive: `obstacle_distance_m` beyond 10 x the ToF's 2000 mm, or beyond 2000 mm while the
///   first row's ToF reads the obstacle inside its rails.
void check_plausible_units(const std::vector<logs::Log>& logs);

}  // namespace epuck2::calibrate
