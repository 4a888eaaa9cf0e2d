// Proximity sensors: paper Eq. 1 as the plug-in computes it.
// Header-only, standard library only (epuck2::models); units in every name, angles in radians
// unless a name says _deg. Umbrella: sensors.hpp.
#pragma once

#include <algorithm>
#include <array>
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

// ---------------------------------------------------------------------------------------------
// What the plug-in's Eq. 1 misses: the diagnosis catalogue's effects (docs/diagnose.md), one
// parameter struct each, every one neutral at its default (the plug-in's model). Templated on the
// scalar: the diagnosis fits them with Jets, the simulation and plug-ins run them in double.
// ---------------------------------------------------------------------------------------------

/// ambient_offset: every reading is raised by offset_raw (counts), at every distance.
template <typename T = double>
struct ProximityAmbientOffset {
  T offset_raw = T(0.0);
};
/// sensor_gain: sensor s reads gain[s] times the base response.
template <typename T = double>
struct ProximitySensorGain {
  std::array<T, kProximityCount> gain{T(1.0), T(1.0), T(1.0), T(1.0), T(1.0), T(1.0), T(1.0), T(1.0)};
};
/// long_tail: the sensor still responds beyond the ray's cut-off: + amplitude_raw exp(-d / length_m).
template <typename T = double>
struct ProximityLongTail {
  T amplitude_raw = T(0.0);
  T length_m = T(0.02);
};
/// incidence_angle: a surface seen at an angle theta from the sensor's axis reflects cos(theta)^k.
template <typename T = double>
struct ProximityIncidence {
  T k = T(0.0);
};
/// saturation: readings never exceed level_raw (counts).
template <typename T = double>
struct ProximitySaturation {
  T level_raw = T(1e9);  ///< neutral: above any reading
};

/// Every effect of the catalogue at once (each neutral by default).
template <typename T = double>
struct ProximityEffects {
  ProximityAmbientOffset<T> ambient;
  ProximitySensorGain<T> gains;
  ProximityLongTail<T> tail;
  ProximityIncidence<T> incidence;
  ProximitySaturation<T> saturation;
};

/// The long tail's contribution in counts at distance d; 0 when there was no hit (d infinite or
/// NaN, as proximity_response and kinds.hpp's mean_raw take it), the limit of exp(-d/length) and
/// of its derivatives (a Jet's -inf / length would carry 0 * inf = NaN derivatives).
template <typename T>
T proximity_tail_raw(const ProximityLongTail<T>& e, double distance_m) {
  using std::exp;
  if (!std::isfinite(distance_m)) return T(0.0);
  return e.amplitude_raw * exp(-distance_m / e.length_m);
}

/// cos(theta)^k for cos(theta) >= 0 from the data (0 at grazing incidence and beyond, and no log
/// of 0 in the derivative), except at the neutral k = 0: 1 at every angle, the plug-in's model,
/// which has no angle (cos^0 = 1; the base model is evaluated with the logged angle too).
template <typename T>
T proximity_incidence_factor(const ProximityIncidence<T>& e, double cos_incidence) {
  using std::exp;
  if (!(cos_incidence > 0)) return e.k == T(0.0) ? T(1.0) : T(0.0);
  if (cos_incidence == 1.0) return T(1.0);
  return exp(e.k * std::log(cos_incidence));
}

/// The mean reading in counts before the sensor's clamp to [0, 4095] and its rounding: the plug-in's
/// 4095 clamp01(a d^2 + b d + c) for d <= range (else 0), with the catalogue's effects:
///   min(gain_s cos(theta)^k 4095 clamp01(poly) [d <= range] + offset + amplitude exp(-d/length), level).
/// `abc` = {a_per_m2, b_per_m, c}; `cos_incidence` = 1 for a surface facing the sensor.
template <typename T>
T proximity_mean_raw(const T* abc, double range_m, const ProximityEffects<T>& e, int sensor, double distance_m,
                     double cos_incidence = 1.0) {
  using std::fmax;
  using std::fmin;
  T v = e.ambient.offset_raw + proximity_tail_raw(e.tail, distance_m);
  if (distance_m <= range_m) {
    const T poly = fmin(fmax(proximity_polynomial(abc, distance_m), T(0.0)), T(1.0));
    v += e.gains.gain[static_cast<std::size_t>(sensor)] * proximity_incidence_factor(e.incidence, cos_incidence) *
         kProximityFullScale_raw * poly;
  }
  return fmin(v, e.saturation.level_raw);
}

/// A reading's mean in counts from the model's coefficients and effects (double).
inline double proximity_mean_raw(const ProximityCoefficients& k, const ProximityEffects<double>& e, int sensor,
                                 double distance_m, double cos_incidence = 1.0) {
  const double abc[3] = {k.a_per_m2, k.b_per_m, k.c};
  return proximity_mean_raw(abc, k.range_m, e, sensor, distance_m, cos_incidence);
}

}  // namespace epuck2::models::sensors
