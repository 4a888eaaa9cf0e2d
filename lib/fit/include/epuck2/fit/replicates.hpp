// Wild values among replicates: a value far from the other values taken under the same
// conditions is a glitch, not a measurement. Used by the robust engine (robust.hpp) and by the
// log screening of lib/diagnose (src/screening.hpp).
#pragma once

#include <cstddef>
#include <string>
#include <vector>

namespace epuck2::fit {

/// A reading farther than this many robust sd (1.4826 MAD of its group, at least half the typical
/// group's and at least the floor) from its group's median is wild.
inline constexpr double kWildReadingSd = 8.0;
/// Readings under the same conditions needed to judge one of them against the others (a camera
/// takes 3 frames of an LED position; the robust sd then has a floor, so only a jump of 8 floors
/// counts).
inline constexpr std::size_t kMinReplicates = 3;
/// Fewest readings inside the rails for a group's MAD to count in the typical spread (a smaller
/// group's MAD lies far below its sd).
inline constexpr std::size_t kTypicalReplicates = 5;

/// Flags wild values among replicates: `group[i]` is value i's group of readings taken under the
/// same conditions (-1: none, never wild here), `on_rail[i]` whether it sits on a sensor's rail.
/// A value inside the rails is wild when farther than kWildReadingSd robust sd from its group's
/// median (groups of at least kMinReplicates; the sd is the group's 1.4826 MAD, at least half the typical
/// group's -- the median MAD of the groups of at least kTypicalReplicates readings inside the rails,
/// of every group when none is that large -- and at least `floor_sd`); a railed value (censored: at or beyond the rail, so at least
/// as far as the rail) when it is its group's only railed one and the rail itself is farther than
/// that (a stray glitch, not a sensor near its clamp). `why`, when given,
/// receives a sentence per wild value (empty for the others).
/// The median of `values` (the mean of the two middle ones for an even count); 0 for none.
double median(std::vector<double> values);

std::vector<bool> flag_wild_replicates(const std::vector<double>& values, const std::vector<int>& group,
                                       const std::vector<bool>& on_rail, double floor_sd,
                                       std::vector<std::string>* why = nullptr);

}  // namespace epuck2::fit
