// The battery calibration as text and the charge conversion as JSON, beside their results
// (battery.hpp, charge_map.hpp); the battery coefficient file itself is battery_json.hpp's.
#pragma once

#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "epuck2/calibrate/battery.hpp"
#include "epuck2/calibrate/charge_map.hpp"

namespace epuck2::calibrate {

/// The human report of `epuck2-fit battery`: every speed's four models with their errors and
/// statistics, the simple model, the averages, the wild readings, the speeds missing from the
/// tables and the warnings. `robust` (Huber) and `reject_sd` (0: every reading kept) say how the
/// fits treated the readings.
std::string report_text(const BatteryFit& f, bool robust, double reject_sd);

/// The voltage->charge map in words: where it comes from (`map_from_file`, "" when fitted to the
/// logs with both columns), its knots, load offsets and residuals, and what it converted (`c`).
std::string charge_map_text(const ChargeMap& m, const std::string& map_from_file, const ChargeConversionReport& c);

/// The paper's Table 5 for a set of logs: per discharge model, the average MSE of the fitted
/// functions against the logs (`analytic`), of the runtime models run every `tick_s` over the
/// logged speeds with the fitted tables (`simulated`: plug-in compatible arithmetic, as the
/// paper's ARGoS runs; `simulated_corrected`: the corrected behaviour), with the plug-in's
/// published tables, and the paper's published values (published.hpp).
struct Table5 {
  std::size_t logs = 0;
  std::size_t speeds = 0;
  double tick_s = 0.1;
  SpeedCoverage coverage;
  ModelMse analytic, simulated, simulated_corrected, plugin_tables_simulated, published_analytic, published_argos;
  /// The fitted Cubic tables the plug-in's arithmetic never empties at tick_s
  /// (models::battery::argos_cubic_stalls): the `simulated` Cubic cell runs a battery stuck there.
  std::vector<models::battery::ArgosCubicStall> argos_cubic_stalls;
};

/// Table 5 of `runs`, fitted as `f` (which must have its tables: f.tables), from `logs` logs.
Table5 table5(const std::vector<BatteryRun>& runs, const BatteryFit& f, std::size_t logs, double tick_s);

/// `epuck2-fit table5 --json` (docs/battery-models.md): the MSEs per model and source, the speeds
/// covered, and the ratios to the published values.
nlohmann::json table5_json(const Table5& t);

/// `epuck2-fit table5`'s table and ratios.
std::string table5_text(const Table5& t);

/// A Table 5 report's closing line on the voltage-only logs converted through the map
/// (`map_from_file` "" when it was fitted to the logs with both columns); "" when none was.
std::string charge_conversion_text(const ChargeConversionReport& c, const std::string& map_from_file, double map_residual_sd);

/// A JSON report's `charge_conversion`: the voltage-only logs converted through the map and the
/// rows clamped to its range (null when no log was converted).
nlohmann::json charge_conversion_json(const ChargeConversionReport& c, const std::string& map_from_file);

}  // namespace epuck2::calibrate
