// A reading that saturates before its noise: the expected value of
//   reading = clamp(clamp(model, saturation_lo, saturation_hi) + noise, rail_lo, rail_hi)
// with noise ~ N(0, sigma^2). The inner clamp is the sensor's physics (a phototransistor that
// saturates at 0 in bright light, a proximity sensor at full scale in contact); the outer one is
// the register's rails. A saturated sensor still carries its noise: a light sensor in bright light
// reads 0 plus noise, clipped at 0 by its register (half the readings 0, half a few counts). The
// calibration fits (lib/calibrate) and the diagnosis (lib/diagnose) use these formulas, written
// once here (docs/fitting.md, "Saturated readings").
// Header-only, standard library only (epuck2::models); templated on the scalar (Jets in the fits).
#pragma once

#include <cmath>
#include <limits>
#include <type_traits>

namespace epuck2::models {

/// The value of a scalar: itself, or a Jet's value (`.a`), without depending on Ceres.
template <typename T>
double scalar_value(const T& x) {
  if constexpr (std::is_arithmetic_v<T>)
    return static_cast<double>(x);
  else
    return scalar_value(x.a);
}

/// The sensor's physical saturation: the model clamped to [lo, hi] (±inf: no saturation there).
template <typename T>
T saturate(const T& model, double lo, double hi) {
  using std::fmax;
  using std::fmin;
  T out = model;
  if (std::isfinite(lo)) out = fmax(out, T(lo));
  if (std::isfinite(hi)) out = fmin(out, T(hi));
  return out;
}

/// E[clamp(mu + e, lo, hi)] for e ~ N(0, sigma^2): the mean of a clamped noisy reading, smooth in
/// mu, so that readings at a clamp are fitted without bias (for hi - lo >> sigma). With
/// X ~ N(mu, sigma^2): E[clamp(X)] = mu + E[max(0, lo - X)] - E[max(0, X - hi)], and
/// E[max(0, lo - X)] = sigma (z Phi(z) + phi(z)), z = (lo - mu) / sigma (the normal's partial
/// expectation).
template <typename T>
T expected_clamp(const T& mu, double lo, double hi, double sigma) {
  using std::erfc;
  using std::exp;
  constexpr double kInvSqrt2 = 0.70710678118654752440;
  constexpr double kInvSqrt2Pi = 0.39894228040143267794;
  // Beyond 9 sigma from both clamps the correction is below 1e-20 sigma: the mean itself.
  constexpr double kFar = 9.0;
  const double m = scalar_value(mu);
  if (!(m - lo < kFar * sigma) && !(hi - m < kFar * sigma)) return mu;
  // Beyond 9 sigma outside one clamp (and far from the other), the reading is that clamp.
  if (lo - m > kFar * sigma && hi - m > kFar * sigma) return T(lo);
  if (m - hi > kFar * sigma && m - lo > kFar * sigma) return T(hi);
  T out = mu;
  if (std::isfinite(lo)) {
    const T z = (lo - mu) / sigma;
    out += sigma * (z * (0.5 * erfc(-z * kInvSqrt2)) + kInvSqrt2Pi * exp(-0.5 * z * z));
  }
  if (std::isfinite(hi)) {
    const T z = (mu - hi) / sigma;
    out -= sigma * (z * (0.5 * erfc(-z * kInvSqrt2)) + kInvSqrt2Pi * exp(-0.5 * z * z));
  }
  return out;
}

/// E[clamp(clamp(model, saturation_lo, saturation_hi) + e, rail_lo, rail_hi)], e ~ N(0, sigma^2):
/// the mean reading of a sensor that saturates before its noise.
template <typename T>
T expected_saturated_reading(const T& model, double saturation_lo, double saturation_hi, double rail_lo, double rail_hi,
                             double sigma) {
  return expected_clamp(saturate(model, saturation_lo, saturation_hi), rail_lo, rail_hi, sigma);
}

}  // namespace epuck2::models
