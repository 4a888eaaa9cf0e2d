// Noise: the E-Puck2 plug-in's uniform noise, the calibrated Gaussian reading noise, and the seeded
// sources every simulation draws from.
// Header-only, standard library only (epuck2::models); units in every name, angles in radians
// unless a name says _deg. Umbrella: sensors.hpp.
#pragma once

#include <cmath>
#include <cstdint>
#include <random>

namespace epuck2::models::sensors {

/// A seedable source of uniform numbers in [0, 1) built from std::mt19937_64's bits (whose
/// output the C++ standard fixes, unlike the distributions): same seed, same numbers everywhere.
class UnitUniform {
 public:
  explicit UnitUniform(std::uint64_t seed) : engine_(seed) {}
  /// 53 random bits scaled to [0, 1).
  double operator()() { return static_cast<double>(engine_() >> 11) * 0x1.0p-53; }

 private:
  std::mt19937_64 engine_;
};

/// ARGoS's uniform noise: level * Uniform(-1, 1). A level of 0 draws nothing (the plug-in only
/// draws when noise is enabled), so the random stream is untouched when noise is off.
/// `unit` is any functor returning uniform numbers in [0, 1) (e.g. UnitUniform).
template <class UnitRandom>
double uniform_noise(UnitRandom& unit, double level) {
  if (level == 0.0) return 0.0;
  return level * (2.0 * unit() - 1.0);
}

/// No noise: the functor to pass when noise is off.
struct NoNoise {
  double operator()() const { return 0.5; }
};

/// Standard normal numbers from a UnitUniform by the Box-Muller transform, written out so that a
/// seed gives the same numbers with every standard library (std::normal_distribution's algorithm
/// is the library's choice).
class StandardNormal {
 public:
  explicit StandardNormal(std::uint64_t seed) : unit_(seed) {}
  double operator()() {
    if (has_spare_) {
      has_spare_ = false;
      return spare_;
    }
    // 1 - u lies in (0, 1]: no log of 0.
    const double r = std::sqrt(-2.0 * std::log(1.0 - unit_()));
    const double angle = 2.0 * 3.14159265358979323846 * unit_();
    spare_ = r * std::sin(angle);
    has_spare_ = true;
    return r * std::cos(angle);
  }

 private:
  UnitUniform unit_;
  double spare_ = 0.0;
  bool has_spare_ = false;
};

// ----- Gaussian noise: the calibrated reading noise (a coefficient file's `noise` section) -----

/// A Gaussian of standard deviation `sd` (any unit). An sd of 0 draws nothing.
/// `normal` is any functor returning standard normal numbers (e.g. StandardNormal).
template <class Normal>
double gaussian_noise(Normal& normal, double sd) {
  if (sd == 0.0) return 0.0;
  return sd * normal();
}

/// The reading functions (proximity_reading, ground_reading, ...) add the plug-in's
/// uniform_noise(unit, level) times their scale (below). Passed as their `unit` with level 1, this
/// makes them add a Gaussian of `sd` in the reading's units instead:
///   GaussianUnit g(normal, noise_sd_counts, kPluginNoiseScaleGround_counts);
///   ground_reading(k, grey, 1.0, g);
template <class Normal>
class GaussianUnit {
 public:
  GaussianUnit(Normal& normal, double sd, double scale) : normal_(&normal), sd_over_scale_(sd / scale) {}
  double operator()() { return (sd_over_scale_ * (*normal_)() + 1.0) / 2.0; }

 private:
  Normal* normal_;
  double sd_over_scale_;
};

/// What the plug-in multiplies its uniform noise by, in the reading's units (the plug-in's
/// source): proximity and light add it to the normalised value (x 4095 counts), ground x 1023
/// counts, the ToF x its 2 m range (2000 mm), the encoders x 32767 steps per tick.
inline constexpr double kPluginNoiseScaleProximity_counts = 4095.0;
inline constexpr double kPluginNoiseScaleLight_counts = 4095.0;
inline constexpr double kPluginNoiseScaleGround_counts = 1023.0;
inline constexpr double kPluginNoiseScaleTof_mm = 2000.0;
inline constexpr double kPluginNoiseScaleEncoder_steps = 32767.0;

/// The plug-in's uniform noise level with the variance of a Gaussian of `sd` (reading units):
/// uniform on [-L, L] has variance L^2 / 3, so L = sqrt(3) sd / scale.
inline double uniform_level_with_sd(double sd, double scale) { return std::sqrt(3.0) * sd / scale; }

}  // namespace epuck2::models::sensors
