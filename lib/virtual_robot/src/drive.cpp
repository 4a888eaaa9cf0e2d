// The virtual robot's drive protocol (paper sections 4.1.4 and 4.1.5): a straight run at one of six
// speeds towards an obstacle 30 cm ahead of the ToF sensor, and one away from it, logging the
// commands, both encoder registers and the ToF reading at about 10 Hz. data/raw/drive/README.md
// documents the imperfections (firmware speed limit and integer steps/s, wheel slip as a lag of
// the ground speed behind the wheels, ToF scale, offset and noise, irregular sampling).
#include <algorithm>
#include <cmath>
#include <cstdio>

#include "epuck2/logs/output.hpp"
#include "epuck2/models/sensors.hpp"
#include "epuck2/virtual_robot/reference_logs.hpp"
#include "epuck2/virtual_robot/sensor_truth.hpp"

namespace epuck2::virtual_robot {

namespace {

// One run. direction +1 towards the obstacle, -1 away from it.
GeneratedFile drive_run(const DriveTruth& truth, double speed_cm_s, int direction, std::uint64_t seed) {
  namespace s = models::sensors;
  Gaussian noise(seed);
  const double travel_m = direction > 0 ? truth.toward_travel_m : truth.away_travel_m;
  // The host converts the command to the firmware's integer steps/s; the firmware caps it.
  const double command_steps_s =
      std::min(std::round(speed_cm_s / 100.0 * truth.steps_per_m), truth.speed_limit_steps_s) * direction;
  const double target_steps = travel_m * truth.steps_per_m;

  logs::LogWriter w({"time_s", "left_speed_cm_s", "right_speed_cm_s", "left_steps", "right_steps", "tof_mm"});
  w.comment("Synthetic log recorded by epuck2-fit's virtual robot (see README.md); not a real robot.");
  w.metadata("robot", "virtual-epuck2-1");
  w.metadata("obstacle_distance_m", logs::format_number(truth.obstacle_distance_m));
  w.metadata("commanded_speed_cm_s", logs::format_number(speed_cm_s * direction));
  w.metadata("seed", std::to_string(seed));

  double t = 0, steps = 0;      // exact step count (both wheels alike)
  double ground_speed = 0, ground_m = 0;  // the body's travel, lagging the wheels
  double command_cm_s = 0;      // what the host sends: the logged command
  double rate_steps_s = 0;      // what the firmware drives
  enum class Phase { before, moving, after } phase = Phase::before;
  double phase_end = truth.pause_s;
  double next_sample = 0;
  const double lag = truth.slip_time_constant_s;
  for (int guard = 0; guard < 10'000'000; ++guard) {
    if (t >= next_sample - 1e-12) {
      // The host's control loop runs at each sample: read the sensors, then decide the command.
      if (phase == Phase::before && t >= phase_end) phase = Phase::moving;
      if (phase == Phase::moving && std::abs(steps) >= target_steps) {
        phase = Phase::after;
        phase_end = t + truth.pause_s;
      }
      if (phase == Phase::after && t >= phase_end) break;
      command_cm_s = phase == Phase::moving ? speed_cm_s * direction : 0.0;
      rate_steps_s = phase == Phase::moving ? command_steps_s : 0.0;
      const double true_distance_m = truth.obstacle_distance_m - ground_m;
      const double sigma_mm = truth.tof_noise_mm + truth.tof_noise_per_m_mm * true_distance_m;
      const double tof = std::clamp(std::round(s::tof_response_mm(truth.tof_scale, truth.tof_offset_mm, true_distance_m) +
                                               noise() * sigma_mm),
                                    20.0, 2000.0);
      // The firmware counts whole steps; the register is 16-bit.
      const double wrapped = std::floor(steps) - 65536.0 * std::floor((std::floor(steps) + 32768.0) / 65536.0);
      w.row({std::round(t * 1e4) / 1e4, command_cm_s, command_cm_s, wrapped, wrapped, tof});
      next_sample = t + truth.sample_period_s + truth.sample_jitter_s * (2.0 * noise.uniform() - 1.0);
      next_sample = std::round(next_sample / truth.physics_step_s) * truth.physics_step_s;
    }
    // Physics step: the wheels turn at the commanded rate; the body follows with a first-order lag
    // (integrated exactly over the step).
    const double dt = truth.physics_step_s;
    const double wheel_speed = rate_steps_s / truth.steps_per_m;
    const double decay = std::exp(-dt / lag);
    ground_m += wheel_speed * dt + (ground_speed - wheel_speed) * lag * (1.0 - decay);
    ground_speed = wheel_speed + (ground_speed - wheel_speed) * decay;
    steps += rate_steps_s * dt;
    t += dt;
  }
  char name[96];
  std::snprintf(name, sizeof name, "drive_%s_%04.1f_cm_s.csv", direction > 0 ? "toward" : "away", speed_cm_s);
  return {name, w.str()};
}

}  // namespace

std::vector<GeneratedFile> drive_logs(const DriveTruth& truth, std::uint64_t seed) {
  std::vector<GeneratedFile> files;
  std::uint64_t k = 0;
  for (double v : truth.speeds_cm_s)
    for (int direction : {+1, -1}) files.push_back(drive_run(truth, v, direction, seed + 5000 + k++));
  return files;
}

std::vector<GeneratedFile> drive_reference_logs(std::uint64_t seed) { return drive_logs(DriveTruth{}, seed); }

}  // namespace epuck2::virtual_robot
