// Time-of-flight distance sensor as the plug-in computes it.
// Header-only, standard library only (epuck2::models); units in every name, angles in radians
// unless a name says _deg. Umbrella: sensors.hpp.
#pragma once

#include <algorithm>
#include <cmath>
#include <optional>

#include "epuck2/models/noise.hpp"

namespace epuck2::models::sensors {

struct TofCoefficients {
  double range_m = 2.0;       ///< the plug-in's source: one 2.0 m ray
  double min_mm = 20.0;       ///< VL53L0X minimum (the plug-in's source and the e-puck2 firmware)
  double max_mm = 2000.0;     ///< the plug-in's source
  double scale = 1.0;         ///< measured = scale * true distance + offset (plug-in: 1, 0)
  double offset_mm = 0.0;
};
inline constexpr TofCoefficients kPluginTof{};
/// The VL53L0X's "no target in range" code: a tof_mm reading at or above it is no distance
/// (ST's VL53L0X API reports 8190 or 8191 when the signal is too weak; docs/logs.md, drive).
inline constexpr double kTofOutOfRangeCode_mm = 8190;

/// The noiseless reading in mm before rounding: scale * 1000 d + offset. What a fit adjusts.
template <typename T>
T tof_response_mm(const T& scale, const T& offset_mm, const T& distance_m) {
  return scale * distance_m * 1000.0 + offset_mm;
}

/// The plug-in's reading: hit distance (range if no hit) + noise * range, in mm rounded, clamped
/// to [20, 2000]. With non-default scale/offset the response is scale * d + offset first.
template <class UnitRandom>
int tof_reading_mm(const TofCoefficients& k, std::optional<double> hit_distance_m, double noise_level, UnitRandom& unit) {
  const double d_m = hit_distance_m && *hit_distance_m <= k.range_m ? *hit_distance_m : k.range_m;
  const double reading_m = tof_response_mm(k.scale, k.offset_mm, d_m) / 1000.0 + uniform_noise(unit, noise_level) * k.range_m;
  return static_cast<int>(std::clamp(std::round(reading_m * 1000.0), k.min_mm, k.max_mm));
}
inline int tof_reading_mm(const TofCoefficients& k, std::optional<double> hit_distance_m) {
  NoNoise none;
  return tof_reading_mm(k, hit_distance_m, 0.0, none);
}

}  // namespace epuck2::models::sensors
