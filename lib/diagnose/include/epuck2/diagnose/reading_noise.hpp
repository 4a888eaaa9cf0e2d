// The noise a diagnosis writes into its extended model: the noise of one reading, never the
// base model's misfit. Where the logs repeat readings under the same conditions it is what the
// calibration of those logs measures from the replicates (lib/calibrate reading_noise.hpp: the
// same groups, rails and wild readings); otherwise the final extended model's residuals.
#pragma once

#include <map>
#include <string>
#include <vector>

#include "epuck2/calibrate/reading_noise.hpp"
#include "epuck2/logs/log.hpp"

namespace epuck2::diagnose {

struct Report;

/// Each channel's noise measured from the logs' replicates, by channel (proximity, light, ground,
/// camera, tof): the calibration of the same logs, its `noise` when it came from replicates.
/// Empty for a kind without replicates (battery, the encoders) or logs the calibration cannot fit.
std::map<std::string, calibrate::ReadingNoise> replicate_noise(const std::vector<logs::Log>& logs);

/// The noise sd of one reading of `channel` for the extended model: the replicates' (`sensor` >=
/// 0: that sensor's own where it has readings) but at most `residual_sd`, the final model's
/// residual sd (replicates scattering more vary in a condition the groups do not hold), else
/// `residual_sd`;
/// either less the rounding's 1/12 unit^2 when `whole` (readings that are whole counts, px, mm or
/// steps: the simulation rounds too).
double model_noise_sd(const std::map<std::string, calibrate::ReadingNoise>& replicates, const std::string& channel,
                      double residual_sd, int sensor = -1, bool whole = true);

/// A warning for each channel whose final residuals scatter more than kImplausibleNoiseRatio times
/// its replicates: the extended model leaves misfit that is not reading noise (the file's noise is
/// the replicates').
inline constexpr double kImplausibleNoiseRatio = 2.0;
std::vector<std::string> noise_warnings(const Report& r, const std::map<std::string, calibrate::ReadingNoise>& replicates);

}  // namespace epuck2::diagnose
