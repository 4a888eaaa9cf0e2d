// Noise: the E-Puck2 plug-in's uniform noise, and the seeded sources every simulation draws from.
// Header-only, standard library only (epuck2::models); units in every name, angles in radians
// unless a name says _deg. Umbrella: sensors.hpp.
#pragma once

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

}  // namespace epuck2::models::sensors
