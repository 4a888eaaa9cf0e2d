// Wild readings in static logs (proximity, light, ground, camera): a reading far from the other
// readings taken under the same conditions (same distance, intensity, sensor, grey level or LED
// position) is a glitch, not a measurement of the sensor's response. The diagnosis leaves such
// readings out before it fits anything, and lists them (docs/fitting.md).
#pragma once

#include <string>
#include <vector>

#include "epuck2/fit/replicates.hpp"
#include "epuck2/logs/log.hpp"

namespace epuck2::calibrate {

struct WildReading {
  std::string where;  ///< file:line
  std::string why;
};

/// The logs without their wild readings (rows dropped whole), and what was dropped. Drive logs
/// (sequences, not replicates) lose their ToF spikes: a reading far from the line through its two
/// neighbours, on a row whose command repeats the previous one. Battery logs come back unchanged.
std::vector<logs::Log> drop_wild_readings(const std::vector<logs::Log>& logs, std::vector<WildReading>* dropped);

/// The same, in place (a long log is not copied).
void drop_wild_readings_in_place(std::vector<logs::Log>& logs, std::vector<WildReading>* dropped);

/// Readings on a sensor's rails (proximity and light 0/4095, ground 0/1023, ToF <= 20 or >= 2000
/// mm including the out-of-range codes): the censored ones.
std::size_t readings_on_rails(const std::vector<logs::Log>& logs);

/// A copy of `log` without the rows flagged in `drop`.
logs::Log without_rows(const logs::Log& log, const std::vector<bool>& drop);
/// `log` without the rows flagged in `drop`, in place.
void remove_rows(logs::Log& log, const std::vector<bool>& drop);

}  // namespace epuck2::calibrate
