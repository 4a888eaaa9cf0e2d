// The battery coefficient file (data/fitted/battery.json): what `epuck2-fit battery -o` writes and
// what codegen, simulate and table5 read back. Layout in docs/coefficient-files.md (`speeds` with
// speed_cm_s, lifetime_s, cubic [d, c, b, a], linear_slope, segments, mse; `mse` averages) plus
// every standard error and fit statistic.
#pragma once

#include <nlohmann/json.hpp>
#include <string>

#include "epuck2/calibrate/battery.hpp"

namespace epuck2::calibrate {

nlohmann::json battery_fit_to_json(const BatteryFit& fit);

/// The four models' tables from a coefficient file; `path` names the file in errors, which say
/// which entry is missing or wrong (InputError).
models::battery::Tables battery_tables_from_json(const nlohmann::json& j, const std::string& path);

}  // namespace epuck2::calibrate
