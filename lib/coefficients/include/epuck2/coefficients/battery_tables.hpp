// The battery tables of a coefficient file (docs/coefficient-files.md): `speeds` [16 x
// {speed_cm_s, lifetime_s, cubic [d, c, b, a], linear_slope, segments [4 x {h, m, x1_s, x2_s, y1,
// y2}]}] and `simple` {static_slope_per_s, moving_slope_per_s}.
#pragma once

#include <nlohmann/json.hpp>

#include <string>
#include <vector>

#include "epuck2/models/battery.hpp"

namespace epuck2::coefficients {

/// The four models' tables from a coefficient file; `path` names the file in errors, which say
/// where (file:line:column, JSON path) and what is wrong (logs::InputError). Every number must be
/// finite and physical: lifetimes positive, the linear and simple slopes negative (a charge falls),
/// each segment's x1_s <= x2_s.
models::battery::Tables battery_tables_from_json(const nlohmann::json& j, const std::string& path);

/// Which tables of a battery file with some speeds only are the file's.
struct TableSources {
  std::vector<int> fitted_speeds;  ///< the speeds (cm/s) whose tables are the file's, ascending
  bool fitted_simple = false;      ///< the Simple model's slopes are the file's
};
/// A battery file with tables at some speeds only (`epuck2-fit battery` on a few runs): 1 to 16
/// entries in `speeds`, each at a whole speed_cm_s in 0..15 given once, each checked as above;
/// `simple` optional. The file's tables at its speeds, the plug-in's published ones
/// (plugin_battery_tables.hpp) at the others and for `simple` when the file has none; `sources`
/// says which are which.
models::battery::Tables battery_tables_from_json(const nlohmann::json& j, const std::string& path, TableSources& sources);

/// The tables alone, as battery_tables_from_json reads them back bit for bit (a cubic row's end_s
/// is its speed's lifetime_s, as in every table the project makes or ships).
nlohmann::json battery_tables_to_json(const models::battery::Tables& t);

}  // namespace epuck2::coefficients
