// Noise for the calibrated sensors, drawn from ARGoS's random number generator ("argos" category,
// so an experiment's <experiment random_seed=...> fixes it).
//
// epuck2::models' reading functions add `uniform_noise(unit, level)` = level * (2 unit() - 1) at a
// sensor-specific scale (the plug-in's: x4095 counts for proximity and light, whose noise is added
// to the normalised value, x1023 for ground, x range for the ToF, x32767 for the encoders). This
// class gives each sensor its `level` and its `unit` functor:
//  * Gaussian (the coefficient file's measured reading noise): level is 1 and unit() =
//    (g / scale + 1) / 2 with g ~ N(0, sd), so that the model adds exactly g, in the reading's
//    units (counts, mm, steps);
//  * uniform: unit() is Uniform[0, 1) and level the plug-in's noise_level: the plug-in's own noise
//    (a uniform on [-L, L] times the scale, variance (L scale)^2 / 3);
//  * off: level 0, nothing drawn (the random stream is untouched).
#pragma once

#include <cmath>
#include <cstddef>
#include <vector>

#include <argos3/core/utility/math/range.h>
#include <argos3/core/utility/math/rng.h>

namespace epuck2::argos_plugin {

class ArgosNoise {
 public:
  /// One sensor's source of unit numbers (what the models call `unit`).
  class Unit {
   public:
    double operator()() {
      if (gaussian_) return (rng_->Gaussian(sd_) + 1.0) / 2.0;
      return rng_->Uniform(kUnit);
    }

   private:
    friend class ArgosNoise;
    inline static const argos::CRange<argos::Real> kUnit{0.0, 1.0};
    argos::CRandom::CRNG* rng_ = nullptr;
    bool gaussian_ = false;
    double sd_ = 0.0;  ///< in the model's unit noise (the reading's sd / scale)
  };

  /// No noise for `sensors` sensors.
  void off(std::size_t sensors) {
    units_.assign(sensors, Unit{});
    levels_.assign(sensors, 0.0);
    gaussian_ = false;
  }
  /// Gaussian noise of sd[i] (the reading's units) on sensor i; `scale` is the model's factor from
  /// a unit noise to the reading's units.
  void gaussian(const std::vector<double>& sd, double scale) {
    off(sd.size());
    gaussian_ = true;
    for (std::size_t i = 0; i < sd.size(); ++i) {
      if (!(sd[i] > 0)) continue;
      units_[i].gaussian_ = true;
      units_[i].sd_ = sd[i] / scale;
      units_[i].rng_ = rng();
      levels_[i] = 1.0;
    }
  }
  /// The plug-in's uniform noise of level[i] on sensor i.
  void uniform(const std::vector<double>& level) {
    off(level.size());
    for (std::size_t i = 0; i < level.size(); ++i) {
      if (!(level[i] > 0)) continue;
      units_[i].rng_ = rng();
      levels_[i] = level[i];
    }
  }

  double level(std::size_t i) const { return levels_[i]; }
  Unit& unit(std::size_t i) { return units_[i]; }
  bool gaussian() const { return gaussian_; }
  /// Whether any sensor draws noise.
  bool any() const {
    for (double l : levels_)
      if (l > 0) return true;
    return false;
  }

 private:
  /// One generator per sensor object, created only when it draws (as the plug-in's sensors do).
  argos::CRandom::CRNG* rng() {
    if (rng_ == nullptr) rng_ = argos::CRandom::CreateRNG("argos");
    return rng_;
  }
  argos::CRandom::CRNG* rng_ = nullptr;
  std::vector<Unit> units_;
  std::vector<double> levels_;
  bool gaussian_ = false;
};

}  // namespace epuck2::argos_plugin
