// The reading noise of a sensor channel: how far one reading scatters about what the sensor would
// read without noise, in the reading's units. Every calibration measures it and every coefficient
// file holds it in its `noise` section (docs/coefficient-files.md), for the simulators that add
// noise to their readings (the ARGoS plug-in's calibrated sensors, lib/models' noise.hpp).
//
// Where the logs repeat readings under the same conditions (proximity, light, ground and camera
// protocols; the ToF while the robot stands still before it moves), the noise is the pooled
// within-group standard deviation of those replicates ("replicates"): wild readings are left out
// first (fit/replicates.hpp), then every group that still has a reading on a rail (its spread is
// clipped by the rail) and every group of one, and (a second pass) in groups of a few readings
// those farther than 4 pooled sd from their group's median. Otherwise it is the fit's residual standard
// deviation ("residuals": the robust fit's noise estimate, censored readings and outliers
// accounted for), which also holds whatever the model does not explain.
#pragma once

#include <cmath>
#include <cstddef>
#include <limits>
#include <string>
#include <vector>

#include "epuck2/calibrate/engine.hpp"
#include "epuck2/models/noise.hpp"

namespace epuck2::calibrate {

/// What the E-Puck2 ARGoS plug-in multiplies its uniform noise by, per channel (the models'
/// constants, epuck2/models/noise.hpp): proximity and light x 4095 counts, ground x 1023 counts,
/// the ToF x 2000 mm, the encoders x 32767 steps per tick.
inline constexpr double kArgosNoiseScaleProximity_counts = models::sensors::kPluginNoiseScaleProximity_counts;
inline constexpr double kArgosNoiseScaleLight_counts = models::sensors::kPluginNoiseScaleLight_counts;
inline constexpr double kArgosNoiseScaleGround_counts = models::sensors::kPluginNoiseScaleGround_counts;
inline constexpr double kArgosNoiseScaleTof_mm = models::sensors::kPluginNoiseScaleTof_mm;
inline constexpr double kArgosNoiseScaleEncoder_steps = models::sensors::kPluginNoiseScaleEncoder_steps;

/// One channel's reading noise, as a coefficient file's `noise.<channel>` holds it.
struct ReadingNoise {
  std::string channel;  ///< proximity, light, ground, tof, encoder, camera
  std::string unit;     ///< counts, mm, steps, px
  double sd = std::numeric_limits<double>::quiet_NaN();  ///< standard deviation of a reading, in `unit`
  /// One per sensor where a kind's sensors differ (proximity 8, light 8, ground 3); empty otherwise.
  /// A sensor without readings in the logs takes `sd` (per_sensor_n says 0 for it).
  std::vector<double> per_sensor_sd;
  std::vector<std::size_t> per_sensor_n;  ///< readings behind each per-sensor sd
  std::string from;       ///< "replicates" or "residuals"
  std::size_t n = 0;      ///< readings the estimate is made of
  std::size_t groups = 0; ///< replicate groups used ("replicates"; 0 for "residuals")
  /// The plug-in's noise scale for this channel (above); 0 when the plug-in has no such noise (camera).
  double argos_scale = 0;
  /// The plug-in's uniform noise level with the same variance: uniform on [-L, L] has variance
  /// L^2 / 3, so L = sqrt(3) sd / scale. NaN without a scale.
  double argos_uniform_level() const {
    return argos_scale > 0 ? models::sensors::uniform_level_with_sd(sd, argos_scale) : std::numeric_limits<double>::quiet_NaN();
  }
  bool usable() const { return std::isfinite(sd) && n > 0; }
};

/// The pooled within-group standard deviation of replicates and what it was made of.
struct PooledSd {
  double sd = std::numeric_limits<double>::quiet_NaN();
  std::size_t n = 0;       ///< readings used
  std::size_t groups = 0;  ///< groups used
  std::size_t wild = 0;    ///< readings left out as wild (fit/replicates.hpp)
  std::size_t outliers = 0;  ///< readings left out beyond reject_sd of the first pass's sd
  std::size_t railed_groups = 0;  ///< groups left out because a reading sits on a rail
};

/// Outliers among a few replicates (groups of fewer than kSmallGroup): farther than this many
/// pooled sd from their group's median.
inline constexpr double kNoiseRejectSd = 4.0;
inline constexpr std::size_t kSmallGroup = 10;

/// Pooled within-group sd: sqrt(sum over groups of sum (x - group mean)^2 / sum (n_g - 1)).
/// `group[i]` is value i's group of readings under the same conditions (-1: none, not used),
/// `on_rail[i]` whether it sits on a sensor's rail. Wild readings (flag_wild_replicates with
/// `floor_sd`) are left out, then groups with a reading on a rail; the sd is pooled over the groups
/// of two or more, then again without the readings of groups smaller than kSmallGroup farther
/// than `reject_sd` times it (at least `floor_sd`) from their group's median (0: no second pass).
PooledSd pooled_replicate_sd(const std::vector<double>& values, const std::vector<int>& group,
                             const std::vector<bool>& on_rail, double floor_sd, double reject_sd = kNoiseRejectSd);

/// A channel's noise from replicates: pooled over all sensors and per sensor (`sensor[i]`, for
/// `sensors` sensors; 0: no per-sensor entries). The readings are screened once, as
/// pooled_replicate_sd does over all the groups; each sensor's sd is pooled over its own groups from
/// the readings that screening kept, so the per-sensor counts add up to `n` (groups holding one
/// sensor each, as every caller's do).
ReadingNoise noise_from_replicates(const std::string& channel, const std::string& unit, double argos_scale,
                                   const std::vector<double>& values, const std::vector<int>& group,
                                   const std::vector<bool>& on_rail, const std::vector<int>& sensor, int sensors,
                                   double floor_sd);

/// A channel's noise from a fit's residuals: its noise sd times `to_unit` (e.g. 4095 for a fit
/// of normalised readings), over the readings it used. With `sensors` > 0 every sensor gets that
/// sd (per_sensor_n 0: no sensor's own).
ReadingNoise noise_from_residuals(const std::string& channel, const std::string& unit, double argos_scale,
                                  const RobustFit& fit, double to_unit = 1.0, int sensors = 0);

/// `replicates` when usable, else the residuals' estimate (logs without repeated readings).
inline ReadingNoise replicates_or_residuals(ReadingNoise replicates, ReadingNoise residuals) {
  return replicates.usable() ? replicates : residuals;
}

}  // namespace epuck2::calibrate
