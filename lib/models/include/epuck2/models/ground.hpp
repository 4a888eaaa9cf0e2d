// Ground sensors as the plug-in computes them.
// Header-only, standard library only (epuck2::models); units in every name, angles in radians
// unless a name says _deg. Umbrella: sensors.hpp.
#pragma once

#include <algorithm>
#include <cmath>

#include "epuck2/models/noise.hpp"
#include "epuck2/models/geometry.hpp"

namespace epuck2::models::sensors {

/// value = offset + gain * grey, grey in [0, 1] (0 = black). The plug-in has offset 0 and gain
/// 1023: it multiplies a 0..255 grey level by 4.011764706 = 1023/255 (the plug-in's source).
struct GroundCoefficients {
  double gain_raw = 1023.0;   ///< reading of white minus reading of black, raw counts
  double offset_raw = 0.0;    ///< reading over black (the paper's residual detections)
};
inline constexpr GroundCoefficients kPluginGround{};
inline constexpr double kGroundFullScale_raw = 1023.0;        ///< 10-bit reading (reference 2.3)
inline constexpr double kPluginGroundPerGreyLevel = 4.011764706;  ///< the plug-in's source

/// The noiseless response to a grey level in [0, 1]. What a fit adjusts.
template <typename T>
T ground_response(const T& gain_raw, const T& offset_raw, double grey) {
  return offset_raw + gain_raw * grey;
}

/// The plug-in's reading from a 0..255 grey level: grey * 4.011764706 + noise * 1023, rounded,
/// clamped to [0, 1023] (the plug-in's source).
template <class UnitRandom>
int ground_reading_plugin(double grey_level_0_255, double noise_level, UnitRandom& unit) {
  const double v = grey_level_0_255 * kPluginGroundPerGreyLevel + uniform_noise(unit, noise_level) * kGroundFullScale_raw;
  return static_cast<int>(std::clamp(std::round(v), 0.0, kGroundFullScale_raw));
}
inline int ground_reading_plugin(double grey_level_0_255) {
  NoNoise none;
  return ground_reading_plugin(grey_level_0_255, 0.0, none);
}

/// The reading from a grey in [0, 1] with given coefficients: offset + gain * grey + noise * 1023,
/// rounded, clamped. With kPluginGround it equals ground_reading_plugin(grey * 255) up to the
/// rounding of 4.011764706 against 1023/255.
template <class UnitRandom>
int ground_reading(const GroundCoefficients& k, double grey, double noise_level, UnitRandom& unit) {
  const double v = ground_response(k.gain_raw, k.offset_raw, grey) + uniform_noise(unit, noise_level) * kGroundFullScale_raw;
  return static_cast<int>(std::clamp(std::round(v), 0.0, kGroundFullScale_raw));
}
inline int ground_reading(const GroundCoefficients& k, double grey) {
  NoNoise none;
  return ground_reading(k, grey, 0.0, none);
}

// ---------------------------------------------------------------------------------------------
// What the plug-in's 1023 grey misses: the diagnosis catalogue's effects (docs/diagnose.md) and
// the per-sensor black offsets of real robots. A sensor's response is
//   offset_raw + gain_raw grey^exponent
// with offset_raw its reading over black (black_offset), offset_raw + gain_raw its reading over
// white (white_level, sensor_gain: one white level per sensor) and exponent the nonlinear_response
// (1: linear). The plug-in: offset 0, gain 1023, exponent 1 for every sensor.
// ---------------------------------------------------------------------------------------------

/// nonlinear_response: grey^exponent in place of grey.
template <typename T = double>
struct GroundNonlinear {
  T exponent = T(1.0);
};

/// The mean reading in counts before the clamp to [0, 1023] and the rounding.
template <typename T>
T ground_mean_raw(const T& offset_raw, const T& gain_raw, const GroundNonlinear<T>& e, double grey) {
  using std::exp;
  // grey^exponent for grey >= 0 from the data: 0 for grey 0 and 1 for grey 1 (no log of 0, and
  // d/dexponent = ln 1 = 0), else grey grey^(exponent - 1), whose second factor is exp(0) = 1
  // exactly at the neutral exponent 1: the reading is then ground_response's offset + gain grey
  // bit for bit, in every scalar. The exponent's derivative is grey^p ln(grey) as before.
  if (!(grey > 0)) return ground_response(gain_raw, offset_raw, 0.0);
  if (grey == 1.0) return ground_response(gain_raw, offset_raw, 1.0);
  return offset_raw + gain_raw * grey * exp((e.exponent - T(1.0)) * std::log(grey));
}

inline double ground_mean_raw(const GroundCoefficients& k, const GroundNonlinear<double>& e, double grey) {
  return ground_mean_raw(k.offset_raw, k.gain_raw, e, grey);
}

}  // namespace epuck2::models::sensors
