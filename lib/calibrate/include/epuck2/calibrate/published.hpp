// Figures published in the seed paper, used as references beside our own results.
#pragma once

#include "epuck2/calibrate/battery.hpp"

namespace epuck2::calibrate {

/// Paper Table 5, "Analytic" row: average MSE of the fitted functions against the robots' logs.
inline ModelMse paper_table5_analytic() { return ModelMse{0.0221, 0.0170, 0.0020, 0.0025}; }
/// Paper Table 5, "ARGoS" row: average MSE of the models run in ARGoS against the logs.
inline ModelMse paper_table5_argos() { return ModelMse{0.0216, 0.0167, 0.0019, 0.0023}; }

}  // namespace epuck2::calibrate
