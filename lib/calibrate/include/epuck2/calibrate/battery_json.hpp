// The battery coefficient file (data/fitted/battery.json): what `epuck2-fit battery -o` writes and
// what codegen, simulate and table5 read back. Layout in docs/coefficient-files.md (`speeds` with
// speed_cm_s, lifetime_s, cubic [d, c, b, a], linear_slope, segments, mse; `mse` averages) plus
// every standard error and fit statistic.
#pragma once

#include <nlohmann/json.hpp>
#include <string>

#include "epuck2/calibrate/battery.hpp"

namespace epuck2::calibrate {

/// `robust` and `reject_sd`: how the fits treated the readings (fit_battery's options), for the
/// file's `method`.
nlohmann::json battery_fit_to_json(const BatteryFit& fit, bool robust = false, double reject_sd = kBatteryRejectSd);

/// The four models' tables from a coefficient file; `path` names the file in errors, which say
/// which entry is missing or wrong (InputError).
models::battery::Tables battery_tables_from_json(const nlohmann::json& j, const std::string& path);

/// The tables alone, as battery_tables_from_json reads them back bit for bit (a cubic row's end_s
/// is its speed's lifetime_s, as in every table the project makes or ships): {"speeds": [16 x
/// {speed_cm_s, lifetime_s, cubic [d, c, b, a], linear_slope, segments}], "simple":
/// {static_slope_per_s, moving_slope_per_s}} (what a battery model file carries).
nlohmann::json battery_tables_to_json(const models::battery::Tables& t);

}  // namespace epuck2::calibrate
