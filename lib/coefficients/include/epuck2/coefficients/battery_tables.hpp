// The battery tables of a coefficient file (docs/coefficient-files.md): `speeds` [16 x
// {speed_cm_s, lifetime_s, cubic [d, c, b, a], linear_slope, segments [4 x {h, m, x1_s, x2_s, y1,
// y2}]}] and `simple` {static_slope_per_s, moving_slope_per_s}.
#pragma once

#include <nlohmann/json.hpp>

#include <array>
#include <limits>
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

/// One entry of `speeds`, as the readers above read it: {speed_cm_s, lifetime_s (the cubic row's
/// end_s), cubic [d, c, b, a], linear_slope, segments}, and `noise_sd` when finite (a
/// calibration's residual sd at that speed: a file without a `noise` section has their root mean
/// square as its model's noise, battery_model_from_json). Each value checked as the readers check
/// it: one they would refuse is std::domain_error, with their reason. A calibration (lib/calibrate
/// battery_json.cpp) adds its report fields (standard errors, fits, ...) around it.
/// `readable` false: only a value that is not finite is refused (JSON has none), the readers' ranges
/// are not checked: for a calibration that reports what it fitted even where no reader takes it
/// (a speed with a few rows), and says so in its warnings.
/// `index`: the entry's place in the file's `speeds`, which a refusal's JSON path names
/// (`/speeds/<index>/...`, as a reader of the whole file would).
nlohmann::json battery_speed_to_json(double speed_cm_s, const models::battery::CubicRow& cubic, double linear_slope_per_s,
                                     const std::array<models::battery::Segment, models::battery::kSegmentCount>& segments,
                                     double noise_sd = std::numeric_limits<double>::quiet_NaN(), bool readable = true,
                                     std::size_t index = 0);
/// The Simple model's `simple` section {static_slope_per_s, moving_slope_per_s}, checked alike
/// (`readable` as above).
nlohmann::json battery_simple_to_json(double static_slope_per_s, double moving_slope_per_s, bool readable = true);

/// The tables alone, as battery_tables_from_json reads them back bit for bit (a cubic row's end_s
/// is its speed's lifetime_s, as in every table the project makes or ships).
nlohmann::json battery_tables_to_json(const models::battery::Tables& t);

}  // namespace epuck2::coefficients
