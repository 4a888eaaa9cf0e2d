// The drive inside ARGoS (no ARGoS dependency, tested on every machine): what the calibrated
// differential steering actuator does with a command, tick by tick, and what the calibrated
// encoders and ToF read from it. The formulas are lib/models' (drive.hpp: drive_advance,
// DriveEffects); this file only turns them into what ARGoS's wheeled entity needs (the speeds the
// physics engine moves the body with during one tick) and keeps the state the sensors share.
//
//   the wheels   u = clamp(command, -max, max), max the diagnosis's speed_limit or else the
//                firmware's cap (1100 steps/s over the file's steps_per_m); then accel_limit;
//   the body     follows k times the wheels' mean speed through the lag tau (wheel_slip,
//                speed_scale): the physics engine moves it by what the lag integrates over a tick;
//   encoders     count the wheels' travel (not the body's): floor(steps_per_m x_wheel);
//   ToF          reads the body's distance delay_s ago (latency).
#pragma once

#include <array>
#include <cmath>
#include <cstddef>
#include <deque>
#include <map>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include <epuck2/models/drive.hpp>
#include <epuck2/models/encoders.hpp>

#include <nlohmann/json.hpp>

namespace epuck2::argos_plugin {

namespace ms = epuck2::models::sensors;

/// The drive part of a drive coefficient file (a calibration or a diagnosis) as ARGoS runs it.
struct DriveConfig {
  ms::DriveEffects<double> effects;  ///< speed_limit set (the fitted one or the firmware cap) unless "calibration"
  double steps_per_m = ms::kPluginStepsPerMetre;
  /// Where the speed limit comes from: the diagnosis's speed-limit finding (its registry name),
  /// "firmware", or "calibration" (none: the calibration found the encoders beat the firmware's cap).
  std::string limit_from;
};

/// Reads a drive file `root` (read from `path`; `robot`: its robot set, empty for the top level)
/// through the project's one reader (lib/coefficients: steps_per_m, slip_time_constant_s,
/// speed_limit, accel_limit, speed_scale, latency, tof_offset, tof_scale, every value checked).
/// A covariate (`covariate:NAME`) stops ARGoS at Init: ARGoS has no log column NAME. `who` names
/// the sensor or actuator in the messages. Errors are logs::InputError at FILE:LINE:COLUMN.
DriveConfig read_drive_config(const nlohmann::json& root, const std::string& path, const std::string& robot,
                              const std::string& who);
/// The same, reading the file `path`.
DriveConfig read_drive_config(const std::string& path, const std::string& who);

/// The firmware's cap in cm/s for a robot of `steps_per_m`: 1100 steps/s (the e-puck2 firmware's
/// MOTOR_SPEED_LIMIT, lib/models encoders.hpp) over steps_per_m.
inline double firmware_cap_cm_s(double steps_per_m) {
  return 100.0 * ms::kFirmwareSpeedLimit_steps_s / steps_per_m;
}

/// One robot's drive, advanced one ARGoS tick at a time under the commanded wheel speeds.
class CalibratedDrive {
 public:
  explicit CalibratedDrive(const ms::DriveEffects<double>& effects = {}) : effects_(effects) {}

  /// Advances by `h_s` under the command (cm/s) and returns the (left, right) speeds in m/s the
  /// physics engine must give the wheeled entity for the body to travel as the model says over
  /// this tick: the body's mean forward speed (its lagged travel over the tick / h) plus and minus
  /// half the wheels' difference (times speed_scale's k; the lag acts on the forward speed only,
  /// as in lib/models).
  std::array<double, 2> step(double left_cm_s, double right_cm_s, double h_s) {
    const ms::DriveState<double> before = state_;
    /* Equal commands hint at one wheel simulated for both; drive_advance takes the hint only when
       the wheels are alike too (after a turn, a stop moves each wheel from its own travel) */
    ms::drive_advance(effects_, left_cm_s, right_cm_s, h_s, state_, left_cm_s == right_cm_s);
    if (!(h_s > 0)) return {0.0, 0.0};
    const double forward = (state_.xg - before.xg) / h_s;
    const double half_diff =
        effects_.speed_scale.k * ((state_.xl - before.xl) - (state_.xr - before.xr)) / (2.0 * h_s);
    time_s_ += h_s;
    return {forward + half_diff, forward - half_diff};
  }
  const ms::DriveState<double>& state() const { return state_; }
  double time_s() const { return time_s_; }
  const ms::DriveEffects<double>& effects() const { return effects_; }
  void reset() {
    state_ = {};
    time_s_ = 0;
  }

 private:
  ms::DriveEffects<double> effects_;
  ms::DriveState<double> state_;
  double time_s_ = 0;
};

/// A step register that counts a wheel's travel: floor(steps_per_m x) (int16-wrapped), with the
/// calibrated reading noise drawn only when the count moved. A register standing still reads
/// exactly what it read before: a real robot's step count does not flicker.
class StepRegister {
 public:
  explicit StepRegister(double steps_per_m = ms::kPluginStepsPerMetre) : steps_per_m_(steps_per_m) {}
  /// The reading after the wheel has travelled `wheel_m` in all; `noise_steps` is drawn by the
  /// caller only when moved() says the count changed.
  int read(double wheel_m, double noise_steps = 0.0) {
    const double count = steps_per_m_ * wheel_m;
    if (count == last_count_ && has_read_) return last_reading_;
    has_read_ = true;
    last_count_ = count;
    const double f = count == 0.0 ? 0.0 : std::floor(count + noise_steps);
    last_reading_ = static_cast<int>(f - 65536.0 * std::floor((f + 32768.0) / 65536.0));
    return last_reading_;
  }
  /// Whether the count at `wheel_m` differs from the one last read (a noise draw is due).
  bool moved(double wheel_m) const { return !has_read_ || steps_per_m_ * wheel_m != last_count_; }
  void reset() {
    has_read_ = false;
    last_count_ = 0;
    last_reading_ = 0;
  }

 private:
  double steps_per_m_;
  bool has_read_ = false;
  double last_count_ = 0;
  int last_reading_ = 0;
};

/// The ToF's latency: the distances the ray measured, tick by tick, read back delay_s later
/// (linear between ticks; before the first tick, the first distance). A missing distance (no
/// obstacle in range) is kept as such and returned when the delayed time falls on it.
class DelayLine {
 public:
  explicit DelayLine(double delay_s = 0) : delay_s_(delay_s) {}
  std::optional<double> push_and_read(double time_s, std::optional<double> distance_m) {
    if (!(delay_s_ > 0)) return distance_m;
    past_.push_back({time_s, distance_m});
    const double when = time_s - delay_s_;
    while (past_.size() > 2 && past_[1].first <= when) past_.pop_front();
    if (when <= past_.front().first || past_.size() == 1) return past_.front().second;
    const auto& a = past_[0];
    const auto& b = past_[1];
    if (!a.second || !b.second) return (when - a.first) < (b.first - when) ? a.second : b.second;
    const double w = (when - a.first) / (b.first - a.first);
    return *a.second + w * (*b.second - *a.second);
  }
  void reset() { past_.clear(); }

 private:
  double delay_s_;
  std::deque<std::pair<double, std::optional<double>>> past_;
};

/// The drives of the robots in a simulation, by robot entity: the calibrated actuator creates a
/// robot's drive at SetRobot, the calibrated encoders and ToF of that robot find it at Init
/// (ARGoS sets up a controller's actuators before its sensors).
class DriveRegistry {
 public:
  static std::shared_ptr<CalibratedDrive> create(const void* robot, const ms::DriveEffects<double>& effects) {
    auto d = std::make_shared<CalibratedDrive>(effects);
    std::lock_guard<std::mutex> lock(mutex());
    map()[robot] = d;
    return d;
  }
  /// The robot's calibrated drive, or nullptr when its actuator is not the calibrated one.
  static std::shared_ptr<CalibratedDrive> find(const void* robot) {
    std::lock_guard<std::mutex> lock(mutex());
    const auto it = map().find(robot);
    return it == map().end() ? nullptr : it->second.lock();
  }

 private:
  static std::mutex& mutex() {
    static std::mutex m;
    return m;
  }
  static std::map<const void*, std::weak_ptr<CalibratedDrive>>& map() {
    static std::map<const void*, std::weak_ptr<CalibratedDrive>> m;
    return m;
  }
};

}  // namespace epuck2::argos_plugin
