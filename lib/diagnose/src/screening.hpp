// Internal to the diagnosis: the screening of logs before anything is fitted (docs/fitting.md,
// "Wild readings"). Its only user is the diagnosis (search.cpp, kind_drive.cpp); what the kinds
// differ in (which columns set the conditions, which are screened, the rails, the floor) is their
// facts' (lib/models kind_facts.hpp: KindFacts::conditions, KindFacts::screening, the channels).
//
// Wild readings in static logs (proximity, light, ground, camera): a reading far from the other
// readings taken under the same conditions (same distance, intensity, sensor, grey level or LED
// position) is a glitch, not a measurement of the sensor's response. The diagnosis leaves such
// readings out before it fits anything, and lists them.
#pragma once

#include <string>
#include <vector>

#include "epuck2/logs/log.hpp"

namespace epuck2::diagnose {

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
/// mm including the out-of-range codes): the censored ones, among the screened readings.
std::size_t readings_on_rails(const std::vector<logs::Log>& logs);

/// A "no target" code (logs::is_tof_out_of_range) where the target is in view: the range the
/// encoders give (obstacle distance minus the travel at the nominal steps per metre) is inside the
/// ToF's ceiling by more than kTofInViewMargin of it. Such a code is a dropout, not a reading
/// beyond the ceiling: the diagnosis leaves it out before anything is fitted (the calibration's
/// robust fit leaves it out too: its curve puts it far on the wrong side of its rail).
inline constexpr double kTofInViewMargin = 0.1;
bool tof_code_in_view(double mm, double encoder_range_mm);

/// A copy of `log` without the rows flagged in `drop`.
logs::Log without_rows(const logs::Log& log, const std::vector<bool>& drop);
/// `log` without the rows flagged in `drop`, in place.
void remove_rows(logs::Log& log, const std::vector<bool>& drop);

}  // namespace epuck2::diagnose
