// Runs a discharge model over a speed profile of a robot spinning in place (the paper's battery
// protocol: one wheel forward, one backward, each at the profile's speed), at a fixed tick.
//
// Behaviour::argos_compatible also reproduces what ARGoS 3 feeds the plug-in (reference
// section 3, "Observed when the plug-in runs in ARGoS 3"):
//  * tick 1 is charged before the robot moves: a wheel command takes effect one tick after the
//    controller issues it, so tick k (k >= 2) runs the command in effect at time (k - 2) dt;
//  * on the first tick after a change of command the robot turns only 0.9 new + 0.1 old as far
//    (the physics engine's sub-steps), e.g. 6.30 cm/s on the way to 7;
//  * the plug-in derives the distance from the rotation: angle * 0.0265f.
// Behaviour::corrected runs tick k at the command in effect at its start, (k - 1) dt, exactly.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <stdexcept>
#include <vector>

#include "epuck2/models/battery.hpp"

namespace epuck2::models::battery {

struct ProfilePoint {
  double time_s = 0;
  double speed_cm_s = 0;  ///< wheel speed magnitude; holds until the next point's time
};

struct ChargeSample {
  double time_s = 0;
  double charge = 0;
};

/// The commanded speed at time t: the last profile point whose time is <= t (0 before the first).
inline double commanded_speed_cm_s(const std::vector<ProfilePoint>& profile, double t_s) {
  double v = 0;
  constexpr double kTimeSlack_s = 1e-9;  // tick times are k*dt in floating point
  for (const ProfilePoint& p : profile) {
    if (p.time_s <= t_s + kTimeSlack_s) v = p.speed_cm_s;
    else break;
  }
  return v;
}

/// Walks a profile forwards in time: the command in effect at non-decreasing query times, in
/// amortised constant time per query.
class ProfileCursor {
 public:
  explicit ProfileCursor(const std::vector<ProfilePoint>& profile) : profile_(profile) {}
  double speed_at(double t_s) {
    constexpr double kTimeSlack_s = 1e-9;  // tick times are k*dt in floating point
    while (next_ < profile_.size() && profile_[next_].time_s <= t_s + kTimeSlack_s) {
      speed_ = profile_[next_].speed_cm_s;
      ++next_;
    }
    return speed_;
  }

 private:
  const std::vector<ProfilePoint>& profile_;
  std::size_t next_ = 0;
  double speed_ = 0;
};

/// Samples reserved up front: a profile's end says how long the simulation may run, not how long
/// it does (it stops when the battery is empty), so the rest grows as it goes.
inline constexpr std::size_t kReservedSamples = std::size_t{1} << 16;

/// Charge from `start_charge` at time 0, one sample after each tick, until the profile's last
/// time or an empty battery (the last sample then reads 0). Throws std::invalid_argument when
/// `dt_s` is not a finite number > 0 or the profile holds more than 2^53 ticks of it.
inline std::vector<ChargeSample> simulate_discharge(Model model, Behaviour behaviour,
                                                    const Tables& tables,
                                                    const std::vector<ProfilePoint>& profile,
                                                    double dt_s = 0.1, double start_charge = 1.0) {
  std::vector<ChargeSample> out;
  if (!(dt_s > 0) || !std::isfinite(dt_s))
    throw std::invalid_argument("simulate_discharge: the tick must be a finite number of seconds > 0");
  if (profile.empty()) return out;
  const double end_s = profile.back().time_s;
  // The tick count as a double first: a cast of a value beyond size_t's range is undefined.
  const double last_tick = std::floor(end_s / dt_s + 1e-9);
  if (!(last_tick <= 9007199254740992.0))
    throw std::invalid_argument("simulate_discharge: the profile holds more than 2^53 ticks");
  const auto ticks = last_tick > 0 ? static_cast<std::uint64_t>(last_tick) : std::uint64_t{0};
  out.reserve(static_cast<std::size_t>(std::min<std::uint64_t>(ticks + 1, kReservedSamples)));
  out.push_back({0.0, start_charge});
  double charge = start_charge;
  double previous_cmd_m_s = 0;   // ARGoS: the wheel command of the previous tick
  ProfileCursor cursor(profile);
  corrected::CubicHints hints;  // the corrected Cubic's root searches, carried tick to tick
  for (std::uint64_t k = 1; k <= ticks && charge > 0; ++k) {
    double delta_pos_m = 0;
    if (behaviour == Behaviour::argos_compatible) {
      double wheel_m_s = 0;
      if (k >= 2) {
        const double cmd_m_s = cursor.speed_at(static_cast<double>(k - 2) * dt_s) / 100.0;
        wheel_m_s = (cmd_m_s != previous_cmd_m_s) ? 0.9 * cmd_m_s + 0.1 * previous_cmd_m_s : cmd_m_s;
        previous_cmd_m_s = cmd_m_s;
      }
      // The body spins in place by wheel * dt / half-axle; the plug-in turns the angle back into
      // wheel travel with the float literal 0.0265f.
      const double delta_angle_rad = wheel_m_s * dt_s / kHalfAxle_m;
      delta_pos_m = delta_angle_rad * kHalfAxleFloat_m;
    } else {
      delta_pos_m = cursor.speed_at(static_cast<double>(k - 1) * dt_s) / 100.0 * dt_s;
    }
    charge = step(model, behaviour, tables, charge, delta_pos_m, dt_s, hints);
    out.push_back({static_cast<double>(k) * dt_s, charge});
  }
  return out;
}

}  // namespace epuck2::models::battery
