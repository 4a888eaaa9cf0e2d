// Battery figures for a paper: the logs with the four fitted models per speed (small multiples),
// and lifetime against speed (the paper's Fig. 10b) beside the published end times. The format
// follows the file name's extension (epuck2/plot/figure.hpp).
#pragma once

#include <string>
#include <vector>

#include "epuck2/calibrate/battery.hpp"
#include "epuck2/logs/output.hpp"

namespace epuck2::plot {

/// Both stage the figure in `stage` (in place once it commits).
void battery_fits_figure(logs::OutputStage& stage, const std::string& path, const std::vector<calibrate::BatteryRun>& runs,
                         const calibrate::BatteryFit& fit);
void battery_lifetime_figure(logs::OutputStage& stage, const std::string& path, const std::vector<calibrate::BatteryRun>& runs,
                             const calibrate::BatteryFit& fit);

}  // namespace epuck2::plot
