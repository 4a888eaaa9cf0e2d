// Geometry of the E-Puck2 as the plug-in builds it: sensor positions, body and wheels, units.
// Header-only, standard library only (epuck2::models); units in every name, angles in radians
// unless a name says _deg. Umbrella: sensors.hpp.
#pragma once

#include <array>

namespace epuck2::models::sensors {

inline constexpr int kProximityCount = 8;
inline constexpr int kGroundCount = 3;
/// Proximity and light sensor angles, index 0..7, from the plug-in's source (docs/logs.md;
/// index 0 front-right, clockwise, negative = right side). The paper's Table 3 lists 15, 50, 90,
/// 150, 210, 270, 310, 345 degrees instead.
inline constexpr std::array<double, kProximityCount> kProximityAngles_deg{-17, -50, -90, -150, 150, 90, 50, 17};
inline constexpr double kProximityRingRadius_m = 0.036;   ///< the plug-in's source
inline constexpr double kProximityElevation_m = 0.043;    ///< the plug-in's source
inline constexpr double kBodyRadius_m = 0.035;            ///< the plug-in's source
inline constexpr double kInterWheel_m = 0.053;            ///< the plug-in's source
inline constexpr double kWheelRadius_m = 0.0205;          ///< the plug-in's source
/// ToF sensor position in the robot frame (the plug-in's source).
inline constexpr std::array<double, 3> kTofPosition_m{0.032, 0.0, 0.036};
/// Ground sensors (x, y) in the robot frame, index 0 = right, 1 = centre, 2 = left (reference
/// section 1; docs/logs.md for the index order).
inline constexpr std::array<std::array<double, 2>, kGroundCount> kGroundPositions_m{
    {{0.03, -0.009}, {0.03, 0.0}, {0.03, 0.009}}};

inline constexpr double kPi = 3.14159265358979323846;
inline constexpr double deg_to_rad(double deg) { return deg * (kPi / 180.0); }
inline constexpr double rad_to_deg(double rad) { return rad * (180.0 / kPi); }

}  // namespace epuck2::models::sensors
