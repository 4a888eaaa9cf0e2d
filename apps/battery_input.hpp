// Shared by `battery` and `table5`: reading battery logs into runs, with the charge of
// voltage-only logs (voltage_v, no charge) computed through a voltage->charge map, and the
// speeds the logs cover and miss, by value.
//
// The map: `--charge-map FILE` when given (a battery coefficient file or a map file); otherwise
// fitted to the logs that carry both charge and voltage_v, when some do. A voltage-only log
// without either is exit 2 at its header, saying how to give a map.
#pragma once

#include <cmath>
#include <cstdio>
#include <iostream>
#include <optional>
#include <string>
#include <vector>

#include "app_support.hpp"
#include "commands.hpp"
#include "epuck2/calibrate/battery.hpp"
#include "epuck2/calibrate/charge_map.hpp"
#include "epuck2/models/battery.hpp"

namespace epuck2::app {

struct BatteryInput {
  std::vector<calibrate::BatteryRun> runs;
  std::optional<calibrate::ChargeMap> map;
  std::string map_from_file;                   ///< the --charge-map FILE, or "" when fitted here
  std::vector<calibrate::ChargeSample> map_rows;  ///< the rows the map was fitted to (fitted here)
  calibrate::ChargeConversionReport conversion;
  std::vector<std::string> warnings;
};

/// Adds --charge-map FILE (the same help text on battery and table5).
inline void add_charge_map_option(CLI::App* sub, std::string& file) {
  sub->add_option("--charge-map", file,
                  "Voltage->charge map for logs with voltage_v and no charge: a battery coefficient file with a "
                  "charge_map section (battery -o) or a map file (docs/coefficient-files.md#charge-map). Without it the map "
                  "is fitted to the logs that carry both columns")
      ->check(CLI::ExistingFile);
}

/// `fit_map`: fit the map to the logs with both columns even when no log needs it (battery writes
/// it); otherwise only when some log is voltage-only.
/// `robot`: only that robot's logs (--robot; exit 2 listing the robots when none is that one). A log
/// whose robot column names several robots is read as one run per robot (split_robot_columns).
inline BatteryInput read_battery_input(const std::string& command, const std::vector<std::string>& paths, bool skip_bad_rows,
                                       const std::string& charge_map_file, bool fit_map, const std::string& robot = "") {
  BatteryInput in;
  const auto logs =
      select_robot(split_robot_columns(command, read_logs_reporting(command, paths, logs::Kind::battery, skip_bad_rows, &in.warnings)),
                   robot);
  bool voltage_only = false;
  for (const auto& l : logs) voltage_only = voltage_only || !l.has("charge");
  if (!charge_map_file.empty()) {
    in.map = calibrate::charge_map_from_json(read_json(charge_map_file), charge_map_file);
    in.map_from_file = charge_map_file;
  } else if (fit_map || voltage_only) {
    std::vector<std::string> sources;
    in.map_rows = calibrate::charge_samples(logs, &sources);
    if (!in.map_rows.empty()) {
      const calibrate::ChargeMapFit fit = calibrate::fit_charge_map(in.map_rows, sources);
      if (fit.usable) in.map = fit.map;
      else if (voltage_only) throw NoUsableFit("the voltage->charge map for the voltage-only logs: " + fit.message);
      else in.warnings.push_back("no voltage->charge map: " + fit.message);
    }
  }
  in.runs = calibrate::battery_runs(logs, in.map ? &*in.map : nullptr, &in.conversion);
  const auto& c = in.conversion;
  if (c.below_range + c.above_range > 0) {
    char text[200];
    std::snprintf(text, sizeof text,
                  "%zu voltages outside the charge map's range %.4f..%.4f V (%zu below, %zu above) were clamped to its end "
                  "charges%s; first: ",
                  c.below_range + c.above_range, in.map->voltage_min_v, in.map->voltage_max_v, c.below_range, c.above_range,
                  !in.map->has_load() ? "" : " (the range is of the voltage plus its load offset at the row's speed)");
    in.warnings.push_back(text + c.clamped.front());  // a path of any length, whole
  }
  return in;
}

/// One line on standard error saying where the charge of voltage-only logs came from (nothing
/// when there were none).
inline void report_conversion(const std::string& command, const BatteryInput& in) {
  if (in.conversion.logs == 0) return;
  std::cerr << command << ": " << in.conversion.logs << " voltage-only logs (" << in.conversion.rows
            << " rows): charge from voltage_v through the map "
            << (in.map_from_file.empty() ? "fitted to the logs with both columns" : "of " + in.map_from_file) << '\n';
}

}  // namespace epuck2::app
