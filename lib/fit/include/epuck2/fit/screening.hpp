// Wild readings in static logs (proximity, light, ground, camera): a reading far from the other
// readings taken under the same conditions (same distance, intensity, sensor, grey level or LED
// position) is a glitch, not a measurement of the sensor's response. The diagnosis leaves such
// readings out before it fits anything, and lists them (docs/fitting.md).
#pragma once

#include <string>
#include <vector>

#include "epuck2/logs/log.hpp"

namespace epuck2::fit {

struct WildReading {
  std::string where;  ///< file:line
  std::string why;
};

/// A reading farther than this many robust sd (1.4826 MAD of its group, at least half the typical
/// group's and at least the floor) from its group's median is wild.
inline constexpr double kWildReadingSd = 8.0;
/// Readings under the same conditions needed to judge one of them against the others (a camera
/// takes 3 frames of an LED position; the robust sd then has a floor, so only a jump of 8 floors
/// counts).
inline constexpr std::size_t kMinReplicates = 3;

/// Flags wild values among replicates: `group[i]` is value i's group of readings taken under the
/// same conditions (-1: none, never wild here), `on_rail[i]` whether it sits on a sensor's rail.
/// A value inside the rails is wild when farther than kWildReadingSd robust sd from its group's
/// median (groups of at least kMinReplicates; the sd is the group's 1.4826 MAD, at least half the typical
/// group's and at least `floor_sd`); a railed value when it is its group's only railed one and
/// farther than half that (a stray glitch, not a sensor near its clamp). `why`, when given,
/// receives a sentence per wild value (empty for the others).
std::vector<bool> flag_wild_replicates(const std::vector<double>& values, const std::vector<int>& group,
                                       const std::vector<bool>& on_rail, double floor_sd,
                                       std::vector<std::string>* why = nullptr);

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

}  // namespace epuck2::fit
