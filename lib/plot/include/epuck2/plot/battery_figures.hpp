// Battery figures for a paper: the logs with the four fitted models per speed (small multiples),
// and lifetime against speed (the paper's Fig. 10b) beside the published end times.
#pragma once

#include <string>
#include <vector>

#include "epuck2/fit/battery.hpp"

namespace epuck2::plot {

void battery_fits_png(const std::string& path, const std::vector<fit::BatteryRun>& runs, const fit::BatteryFit& fit);
void battery_lifetime_png(const std::string& path, const std::vector<fit::BatteryRun>& runs, const fit::BatteryFit& fit);

}  // namespace epuck2::plot
