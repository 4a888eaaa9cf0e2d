// Noise for the calibrated sensors, drawn from ARGoS's random number generator ("argos" category,
// so an experiment's <experiment random_seed=...> fixes it).
//
// epuck2::models' reading functions add `uniform_noise(unit, level)` = level * (2 unit() - 1) at a
// sensor-specific scale (the plug-in's: x1 for proximity and light, x1023 for ground, x range for
// the ToF, x32767 for the encoders). This functor is their `unit`:
//  * uniform: unit() is Uniform[0, 1), level is the XML's noise_level: the plug-in's own noise;
//  * Gaussian: level is 1 and unit() = (g / scale + 1) / 2 with g ~ N(0, noise_sd), so that the
//    model adds exactly g, in the units the fit's noise_sd is expressed in;
//  * off: level 0, nothing drawn (the random stream is untouched).
#pragma once

#include <optional>

#include <argos3/core/utility/math/range.h>
#include <argos3/core/utility/math/rng.h>

namespace epuck2::argos_plugin {

class ArgosNoise {
 public:
  /// `enabled` is the XML's noise attribute; `sd` the file's fits.<name>.noise_sd (in the fit's
  /// units); `uniform_level` the XML's noise_level; `scale` the model's factor from a unit noise
  /// to the fit's units.
  void configure(bool enabled, std::optional<double> sd, double uniform_level, double scale) {
    gaussian_ = false;
    level_ = 0.0;
    if (!enabled) return;
    if (sd && *sd > 0) {
      gaussian_ = true;
      sd_ = *sd / scale;
      level_ = 1.0;
    } else if (uniform_level > 0) {
      level_ = uniform_level;
    }
    if (level_ > 0) rng_ = argos::CRandom::CreateRNG("argos");
  }
  double level() const { return level_; }
  bool gaussian() const { return gaussian_; }
  double operator()() {
    if (gaussian_) return (rng_->Gaussian(sd_) + 1.0) / 2.0;
    return rng_->Uniform(kUnit);
  }

 private:
  inline static const argos::CRange<argos::Real> kUnit{0.0, 1.0};
  argos::CRandom::CRNG* rng_ = nullptr;
  bool gaussian_ = false;
  double sd_ = 0.0;
  double level_ = 0.0;
};

}  // namespace epuck2::argos_plugin
