// The voltage->charge map's figure: the rows it was fitted to (charge against the load-corrected
// voltage) and the map with its knots.
#pragma once

#include <string>
#include <vector>

#include "epuck2/calibrate/charge_map.hpp"
#include "epuck2/logs/output.hpp"

namespace epuck2::plot {

/// Stages the figure in `stage` (in place once it commits). `rows`: the rows fitted (may be empty
/// for a map given by hand: the map alone is drawn).
void charge_map_figure(logs::OutputStage& stage, const std::string& path, const std::vector<calibrate::ChargeSample>& rows,
                    const calibrate::ChargeMap& map);

}  // namespace epuck2::plot
