// LEDs: paper Table 2 and their positions on the ring.
// Header-only, standard library only (epuck2::models); units in every name, angles in radians
// unless a name says _deg. Umbrella: sensors.hpp.
#pragma once

#include <array>
#include <cmath>
#include <string_view>

#include "epuck2/models/geometry.hpp"

namespace epuck2::models::sensors {

enum class LedColour { red, rgb, green };
inline constexpr std::string_view to_string(LedColour c) {
  switch (c) {
    case LedColour::red: return "red";
    case LedColour::rgb: return "rgb";
    case LedColour::green: return "green";
  }
  return "?";
}

struct Led {
  int number = 0;        ///< 1..10 as in Table 2
  LedColour colour = LedColour::red;
  bool on_ring = false;  ///< LEDs 1..8: on the ring at angle_deg; 9 and 10: no position given
  double angle_deg = 0;  ///< ring angle (LEDs 1..8)
};
inline constexpr double kLedRingRadius_m = 0.037;   ///< the plug-in's source
inline constexpr double kLedElevation_m = 0.048;    ///< the plug-in's source
/// Paper Table 2: 1..8 around the ring at 0, 45, ..., 315 deg (RED, RGB alternating), 9 the front
/// LED (red), 10 the body LED (green). The reference gives no position for 9 and 10.
inline constexpr std::array<Led, 10> kLeds{{{1, LedColour::red, true, 0},
                                            {2, LedColour::rgb, true, 45},
                                            {3, LedColour::red, true, 90},
                                            {4, LedColour::rgb, true, 135},
                                            {5, LedColour::red, true, 180},
                                            {6, LedColour::rgb, true, 225},
                                            {7, LedColour::red, true, 270},
                                            {8, LedColour::rgb, true, 315},
                                            {9, LedColour::red, false, 0},
                                            {10, LedColour::green, false, 0}}};

/// A ring LED's position in its robot's frame (x forward, y left, z up).
inline std::array<double, 3> led_position_m(const Led& led) {
  const double a = deg_to_rad(led.angle_deg);
  return {kLedRingRadius_m * std::cos(a), kLedRingRadius_m * std::sin(a), kLedElevation_m};
}

}  // namespace epuck2::models::sensors
