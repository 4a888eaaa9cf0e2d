// Units that cannot be what the columns say: see epuck2/calibrate/plausibility.hpp.
#include "epuck2/calibrate/plausibility.hpp"

#include <cmath>
#include <sstream>
#include <string>

#include "epuck2/models/kind_facts.hpp"
#include "epuck2/models/tof.hpp"
#include "epuck2/logs/output.hpp"

namespace epuck2::calibrate {

namespace {

std::string num(double v) { return logs::format_number(v, 6); }

/// The unit a value in metres was most likely written in, when `metres` is `factor` too large:
/// centimetres for a factor near 100, millimetres near 1000.
std::string likely_unit(double factor) {
  if (factor > 30 && factor < 300) return "centimetres?";
  if (factor >= 300 && factor < 3000) return "millimetres?";
  return "not metres?";
}

void check_distances(const logs::Log& log, double range_m, const char* sensor) {
  if (!log.has("distance_m")) return;
  const auto& d = log.col("distance_m");
  std::size_t worst = 0;
  for (std::size_t i = 1; i < d.size(); ++i)
    if (d[i] > d[worst]) worst = i;
  if (d.empty() || !(d[worst] > kImplausibleRangeFactor * range_m)) return;
  // The largest distance a sensor that sees to range_m is logged at is a few times its range:
  // taken as 2 x range for the unit's guess.
  throw logs::InputError(log.path, log.line_of_row[worst], log.column_of(worst, "distance_m"),
                         "distance_m reaches " + num(d[worst]) + ": " + likely_unit(d[worst] / (2 * range_m)) +
                             " (distances are in metres; the " + sensor + " sees to " + num(range_m) +
                             " m, and a distance beyond " + num(kImplausibleRangeFactor * range_m) +
                             " m is not one it was measured at)");
}

void check_obstacle(const logs::Log& log) {
  if (!log.metadata.count("obstacle_distance_m") || !log.has("tof_mm")) return;
  const double d = log.metadata_number("obstacle_distance_m");
  const double ceiling_m = models::sensors::kPluginTof.max_mm / 1000.0;
  const auto at = log.metadata_at.at("obstacle_distance_m");
  const auto& tof = log.col("tof_mm");
  const bool seen = !tof.empty() && tof[0] > models::sensors::kPluginTof.min_mm && tof[0] < models::sensors::kPluginTof.max_mm;
  if (d > kImplausibleRangeFactor * ceiling_m)
    throw logs::InputError(log.path, at.line, at.column,
                           "obstacle_distance_m is " + num(d) + ": " +
                               likely_unit(seen ? d / (tof[0] / 1000.0) : d / ceiling_m) +
                               " (distances are in metres; the ToF sees to " + num(ceiling_m) + " m)");
  if (d > ceiling_m && seen)
    throw logs::InputError(log.path, at.line, at.column,
                           "obstacle_distance_m is " + num(d) + " m, beyond the ToF's " + num(ceiling_m) +
                               " m, but tof_mm reads " + num(tof[0]) + " mm at line " +
                               std::to_string(log.line_of_row[0]) + ": " + likely_unit(d / (tof[0] / 1000.0)) +
                               " (distances are in metres)");
}

}  // namespace

void check_plausible_units(const std::vector<logs::Log>& logs) {
  for (const logs::Log& log : logs) {
    // How far the kind's sensor sees, and whether its logs give an obstacle's distance (kind_facts).
    const models::KindFacts& facts = *models::kind_facts(std::string(logs::to_string(log.kind)));
    if (facts.distances.sees_to_m > 0) check_distances(log, facts.distances.sees_to_m, facts.distances.sensor);
    for (const models::RequiredMetadata& m : facts.metadata)
      if (std::string(m.key) == "obstacle_distance_m") check_obstacle(log);
  }
}

}  // namespace epuck2::calibrate
