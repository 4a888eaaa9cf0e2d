// Ambient light: paper Eq. 2 as the plug-in computes it.
// Header-only, standard library only (epuck2::models); units in every name, angles in radians
// unless a name says _deg. Umbrella: sensors.hpp.
#pragma once

#include <algorithm>
#include <array>
#include <cmath>

#include "epuck2/models/noise.hpp"
#include "epuck2/models/proximity.hpp"

namespace epuck2::models::sensors {

struct LightCoefficients {
  /// Eq. 2's gamma (m per intensity unit): each light adds (gamma I)^2 / d^2. The plug-in divides
  /// I by 13.3333333333333 (the plug-in's source), i.e. gamma = 0.075 (paper section 4.1.2).
  double gamma_m = 1.0 / 13.3333333333333;
  double range_m = 0.50;  ///< lights farther than this are ignored (the plug-in's source)
};
inline constexpr LightCoefficients kPluginLight{};

/// One light's contribution (gamma I / d)^2 to the normalised sum. What a fit adjusts.
template <typename T>
T light_contribution(const T& gamma_m, double intensity, double distance_m) {
  const T r = gamma_m * intensity / distance_m;
  return r * r;
}

/// Normalised reading without noise for one light: 1 - (gamma I / d)^2, the quantity Eq. 2
/// clamps (not clamped here: the fit uses it on unsaturated readings).
template <typename T>
T light_response(const T& gamma_m, double intensity, double distance_m) {
  return T(1.0) - light_contribution(gamma_m, intensity, distance_m);
}

/// A light as one sensor sees it: distance and intensity (occlusion is the caller's business).
struct LightSource {
  double distance_m = 0;
  double intensity = 0;
};

/// The plug-in's reading 0..4095 (4095 = dark): sum over lights with I > 0 within range of
/// (I/13.333)^2/d^2, + noise, reading = round((1 - sum) * 4095) clamped to [0, 4095].
template <class Lights, class UnitRandom>
int light_reading(const LightCoefficients& k, const Lights& lights, double noise_level, UnitRandom& unit) {
  double sum = 0.0;
  for (const LightSource& l : lights)
    if (l.intensity > 0 && l.distance_m <= k.range_m) sum += light_contribution(k.gamma_m, l.intensity, l.distance_m);
  sum += uniform_noise(unit, noise_level);
  return static_cast<int>(std::clamp(std::round((1.0 - sum) * kProximityFullScale_raw), 0.0, kProximityFullScale_raw));
}
inline int light_reading(const LightCoefficients& k, double intensity, double distance_m) {
  NoNoise none;
  const std::array<LightSource, 1> one{{{distance_m, intensity}}};
  return light_reading(k, one, 0.0, none);
}

// ---------------------------------------------------------------------------------------------
// What the plug-in's Eq. 2 misses: the diagnosis catalogue's effects (docs/diagnose.md), one
// parameter struct each, neutral by default. Templated on the scalar (Jets in the diagnosis).
// ---------------------------------------------------------------------------------------------

/// ambient_offset: ambient light lowers every reading by offset_raw (counts).
template <typename T = double>
struct LightAmbientOffset {
  T offset_raw = T(0.0);
};
/// falloff_exponent: (gamma I / d)^exponent in place of the square.
template <typename T = double>
struct LightFalloff {
  T exponent = T(2.0);
};
/// sensor_gain: sensor s sees gain[s] times the light.
template <typename T = double>
struct LightSensorGain {
  std::array<T, kProximityCount> gain{T(1.0), T(1.0), T(1.0), T(1.0), T(1.0), T(1.0), T(1.0), T(1.0)};
};
template <typename T = double>
struct LightEffects {
  LightAmbientOffset<T> ambient;
  LightFalloff<T> falloff;
  LightSensorGain<T> gains;
};

/// The mean reading in counts before the clamp to [0, 4095] and the rounding, for one light:
///   4095 (1 - gain_s (gamma I / d)^exponent) - offset for d <= range and I > 0, else 4095 - offset
/// (the plug-in's Eq. 2 with every effect neutral).
template <typename T>
T light_mean_raw(const T& gamma_m, double range_m, const LightEffects<T>& e, int sensor, double intensity,
                 double distance_m) {
  using std::exp;
  using std::log;
  T v(kProximityFullScale_raw);
  if (distance_m <= range_m && intensity > 0) {
    const T ratio = gamma_m * intensity / distance_m;
    // ratio^exponent as ratio^2 ratio^(exponent - 2): at the neutral exponent 2 the second factor
    // is exp(0) = 1 exactly, so the reading is light_response's 1 - ratio^2 bit for bit (in every
    // scalar: the arithmetic stays in T); the exponent's derivative is ratio^p ln(ratio) as before.
    const T power = ratio * ratio * exp((e.falloff.exponent - T(2.0)) * log(ratio));
    v = T(kProximityFullScale_raw) * (T(1.0) - e.gains.gain[static_cast<std::size_t>(sensor)] * power);
  }
  return v - e.ambient.offset_raw;
}

inline double light_mean_raw(const LightCoefficients& k, const LightEffects<double>& e, int sensor, double intensity,
                             double distance_m) {
  return light_mean_raw(k.gamma_m, k.range_m, e, sensor, intensity, distance_m);
}

/// The mean reading in counts for several lights (LightSource), as the plug-in sums them: each
/// light within range and of positive intensity adds (gamma I / d)^exponent,
///   4095 (1 - gain_s sum) - offset;
/// for one light light_mean_raw's value bit for bit, for none 4095 - offset.
template <class Lights>
double light_mean_raw(const LightCoefficients& k, const LightEffects<double>& e, int sensor, const Lights& lights) {
  double sum = 0.0;
  for (const LightSource& l : lights)
    if (l.distance_m <= k.range_m && l.intensity > 0) {
      const double ratio = k.gamma_m * l.intensity / l.distance_m;
      sum += ratio * ratio * std::exp((e.falloff.exponent - 2.0) * std::log(ratio));
    }
  return kProximityFullScale_raw * (1.0 - e.gains.gain[static_cast<std::size_t>(sensor)] * sum) - e.ambient.offset_raw;
}

}  // namespace epuck2::models::sensors
