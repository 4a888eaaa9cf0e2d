// The battery coefficient file (data/fitted/battery.json): what `epuck2-fit battery -o` writes and
// what codegen, simulate and table5 read back. Layout in docs/coefficient-files.md (`speeds` with
// speed_cm_s, lifetime_s, cubic [d, c, b, a], linear_slope, segments, mse; `mse` averages) plus
// every standard error and fit statistic.
#pragma once

#include <nlohmann/json.hpp>
#include <string>

#include "epuck2/calibrate/battery.hpp"
#include "epuck2/coefficients/battery_tables.hpp"

namespace epuck2::calibrate {

/// `robust` and `reject_sd`: how the fits treated the readings (fit_battery's options), for the
/// file's `method`. The tables are written by the file's owner (lib/coefficients
/// battery_speed_to_json, battery_simple_to_json), which checks them as its readers do; tables a
/// reader would refuse (a speed fitted to a few rows) are still written as fitted, the report of
/// what the logs gave, and `warnings` says which and that no reader takes the file.
nlohmann::json battery_fit_to_json(const BatteryFit& fit, bool robust = false, double reject_sd = kBatteryRejectSd);

// The tables alone (battery_tables_from_json, battery_tables_to_json) belong to the coefficient
// file's owner: epuck2/coefficients/battery_tables.hpp.

}  // namespace epuck2::calibrate
