// Proximity sensors: paper Eq. 1 as the plug-in computes it.
// Header-only, standard library only (epuck2::models); units in every name, angles in radians
// unless a name says _deg. Umbrella: sensors.hpp.
#pragma once

#include <algorithm>
#include <cmath>
#include <optional>

#include "epuck2/models/noise.hpp"
#include "epuck2/models/geometry.hpp"

namespace epuck2::models::sensors {

/// The response v(d) = a d^2 + b d + c (normalised to 0..1) for d <= range, else 0.
struct ProximityCoefficients {
  double a_per_m2 = 0;
  double b_per_m = 0;
  double c = 0;
  double range_m = 0.05;  ///< the plug-in's source: the ray is 0.05 m long
};

/// The E-Puck2 plug-in's polynomial, fitted by the paper to the maxima (paper section 4.1.1;
/// the plug-in's source).
inline constexpr ProximityCoefficients kPluginProximity{197.8633, -30.47182, 1.011635, 0.05};
/// The E-Puck (v1) polynomial (Garattoni and Francesca; paper section 4.1.1; reference 2.1).
inline constexpr ProximityCoefficients kEpuck1Proximity{298.701, -36.8961, 1.08212, 0.05};
/// Full scale of a proximity and light reading: 12-bit ADC (the plug-in's source).
inline constexpr double kProximityFullScale_raw = 4095.0;

/// The polynomial of Eq. 1 without its clamp: p = {a, b, c}. What a fit adjusts.
template <typename T>
T proximity_polynomial(const T* abc, double distance_m) {
  return (abc[0] * distance_m + abc[1]) * distance_m + abc[2];
}

/// Normalised response without noise: clamp01(poly(d)) for d <= range, else 0.
inline double proximity_response(const ProximityCoefficients& k, double distance_m) {
  if (!(distance_m <= k.range_m)) return 0.0;  // also no hit (NaN/inf)
  const double abc[3] = {k.a_per_m2, k.b_per_m, k.c};
  return std::clamp(proximity_polynomial(abc, distance_m), 0.0, 1.0);
}

/// The plug-in's reading 0..4095: clamp01(poly(d)) (0 beyond range or no hit), + noise, then
/// round(v * 4095) clamped to [0, 4095]. `distance_m` = std::nullopt when the ray hit nothing.
template <class UnitRandom>
int proximity_reading(const ProximityCoefficients& k, std::optional<double> distance_m, double noise_level,
                      UnitRandom& unit) {
  double v = distance_m ? proximity_response(k, *distance_m) : 0.0;
  v += uniform_noise(unit, noise_level);
  return static_cast<int>(std::clamp(std::round(v * kProximityFullScale_raw), 0.0, kProximityFullScale_raw));
}
inline int proximity_reading(const ProximityCoefficients& k, std::optional<double> distance_m) {
  NoNoise none;
  return proximity_reading(k, distance_m, 0.0, none);
}

}  // namespace epuck2::models::sensors
