// Wheel encoders as the plug-in and the e-puck2 firmware keep them.
// Header-only, standard library only (epuck2::models); units in every name, angles in radians
// unless a name says _deg. Umbrella: sensors.hpp.
#pragma once

#include <cmath>
#include <vector>

#include "epuck2/models/noise.hpp"

namespace epuck2::models::sensors {

/// 1000 steps per wheel revolution over a 0.0205 m wheel radius: 1000 / (2 pi 0.0205) =
/// 7763.656 steps per metre (the plug-in's source; the source names it StepsPerCm).
inline constexpr double kPluginStepsPerMetre = 7763.656;
/// The firmware's MOTOR_SPEED_LIMIT (the plug-in's source and the e-puck2 firmware).
inline constexpr double kFirmwareSpeedLimit_steps_s = 1100.0;

struct EncoderCoefficients {
  double steps_per_m = kPluginStepsPerMetre;
};

/// One wheel's encoder register as the plug-in keeps it: a continuous count, wrapped to int16,
/// read as floor(count); partial steps are carried from tick to tick.
class Encoder {
 public:
  explicit Encoder(EncoderCoefficients k = {}) : k_(k) {}
  /// One tick: count += steps_per_m * v * dt + noise * 32767, then the int16 wrap.
  template <class UnitRandom>
  void tick(double wheel_speed_m_s, double dt_s, double noise_level, UnitRandom& unit) {
    count_ += k_.steps_per_m * wheel_speed_m_s * dt_s;
    count_ += uniform_noise(unit, noise_level) * kInt16Max;
    if (count_ >= kWrap) count_ -= 2 * kWrap;
    if (count_ < -kWrap) count_ += 2 * kWrap;
  }
  void tick(double wheel_speed_m_s, double dt_s) {
    NoNoise none;
    tick(wheel_speed_m_s, dt_s, 0.0, none);
  }
  /// The register: floor of the count (-32768..32767).
  int reading() const { return static_cast<int>(std::floor(count_)); }
  /// The register read with a noise on the reading, not on the count (the calibrated reading
  /// noise: a step counter does not drift): floor(count + noise_steps), int16-wrapped.
  int reading(double noise_steps) const {
    double r = count_ + noise_steps;
    r -= 2 * kWrap * std::floor((r + kWrap) / (2 * kWrap));
    return static_cast<int>(std::floor(r));
  }
  double count() const { return count_; }
  void set_count(double c) { count_ = c; }

 private:
  static constexpr double kInt16Max = 32767.0;  ///< the plug-in's noise scale
  static constexpr double kWrap = 32768.0;      ///< int16 range is [-32768, 32768)
  EncoderCoefficients k_;
  double count_ = 0.0;
};

/// Undoes the int16 wrap between consecutive register readings (steps moved between two samples
/// are assumed to be fewer than 32768).
inline double unwrap_steps(double previous_unwrapped, double reading) {
  const double prev_wrapped = previous_unwrapped - 65536.0 * std::floor((previous_unwrapped + 32768.0) / 65536.0);
  double delta = reading - prev_wrapped;
  if (delta > 32767.0) delta -= 65536.0;
  if (delta < -32768.0) delta += 65536.0;
  return previous_unwrapped + delta;
}

/// A register's readings unwrapped from the first, which is taken as is (the encoders read 0 at
/// time 0, docs/logs.md).
inline std::vector<double> unwrap_steps(const std::vector<double>& readings) {
  std::vector<double> out(readings.size());
  for (std::size_t i = 0; i < readings.size(); ++i) out[i] = i ? unwrap_steps(out[i - 1], readings[i]) : readings[i];
  return out;
}

}  // namespace epuck2::models::sensors
