// The virtual robot's drive protocol (paper sections 4.1.4 and 4.1.5): a straight run at one of six
// speeds towards an obstacle 30 cm ahead of the ToF sensor, and one away from it, logging the
// commands, both encoder registers and the ToF reading at about 10 Hz. data/raw/drive/README.md
// documents the imperfections (firmware speed limit and integer steps/s, wheel slip as a lag of
// the ground speed behind the wheels, ToF scale, offset and noise, irregular sampling, ToF rails,
// out-of-range codes and wild readings, a static run, a second robot with smaller wheels).
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>

#include "epuck2/logs/output.hpp"
#include "epuck2/models/sensors.hpp"
#include "epuck2/virtual_robot/reference_logs.hpp"
#include "epuck2/virtual_robot/sensor_truth.hpp"

namespace epuck2::virtual_robot {

namespace {

// One run of one robot.
struct RunSpec {
  double speed_cm_s = 0;  ///< commanded, >= 0
  int direction = +1;     ///< +1 towards the obstacle, -1 away from it
  double travel_m = 0;    ///< commanded travel (encoder distance at the host's steps/m)
  double pause_before_s = 0, pause_after_s = 0;
  double wheel_scale = 1;  ///< the robot's true steps/m over the host's
  double obstacle_m = 0;   ///< the obstacle's distance from the ToF sensor at the start
  std::string robot;
  std::string name;
};

GeneratedFile drive_run(const DriveTruth& truth, const RunSpec& run, std::uint64_t seed) {
  namespace s = models::sensors;
  Gaussian noise(seed);
  WildReadings wild(seed + 7919, truth.tof_wild_fraction);
  WildReadings dropout(seed + 15838, truth.tof_dropout_fraction);
  const double speed_cm_s = run.speed_cm_s;
  const int direction = run.direction;
  // The host converts the command to the firmware's integer steps/s; the firmware caps it.
  const double command_steps_s =
      std::min(std::round(speed_cm_s / 100.0 * truth.steps_per_m), truth.speed_limit_steps_s) * direction;
  const double target_steps = run.travel_m * truth.steps_per_m;
  const double true_steps_per_m = truth.steps_per_m * run.wheel_scale;

  logs::LogWriter w({"time_s", "left_speed_cm_s", "right_speed_cm_s", "left_steps", "right_steps", "tof_mm"});
  w.comment("Synthetic log recorded by epuck2-fit's virtual robot (see README.md); not a real robot.");
  w.metadata("robot", run.robot);
  w.metadata("obstacle_distance_m", logs::format_number(run.obstacle_m));
  w.metadata("commanded_speed_cm_s", logs::format_number(speed_cm_s * direction));
  w.metadata("seed", std::to_string(seed));

  double t = 0, steps = 0;      // exact step count (both wheels alike)
  double ground_speed = 0, ground_m = 0;  // the body's travel, lagging the wheels
  double command_cm_s = 0;      // what the host sends: the logged command
  double rate_steps_s = 0;      // what the firmware drives
  enum class Phase { before, moving, after } phase = Phase::before;
  double phase_end = run.pause_before_s;
  double next_sample = 0;
  const double lag = truth.slip_time_constant_s;
  for (int guard = 0; guard < 10'000'000; ++guard) {
    if (t >= next_sample - 1e-12) {
      // The host's control loop runs at each sample: read the sensors, then decide the command.
      if (phase == Phase::before && t >= phase_end) phase = Phase::moving;
      if (phase == Phase::moving && std::abs(steps) >= target_steps) {
        phase = Phase::after;
        phase_end = t + run.pause_after_s;
      }
      if (phase == Phase::after && t >= phase_end) break;
      command_cm_s = phase == Phase::moving ? speed_cm_s * direction : 0.0;
      rate_steps_s = phase == Phase::moving ? command_steps_s : 0.0;
      const double true_distance_m = run.obstacle_m - ground_m;
      const double sigma_mm = truth.tof_noise_mm + truth.tof_noise_per_m_mm * true_distance_m;
      double tof = std::clamp(std::round(s::tof_response_mm(truth.tof_scale, truth.tof_offset_mm, true_distance_m) +
                                         noise() * sigma_mm),
                              20.0, 2000.0);
      // No target within range: the VL53L0X's out-of-range code.
      if (true_distance_m > truth.tof_range_m) tof = truth.tof_out_of_range_mm;
      double wild_mm, unused;
      if (wild.next(20.0, 2000.0, true, &wild_mm)) tof = wild_mm;
      if (dropout.next(0.0, 1.0, false, &unused)) tof = truth.tof_out_of_range_mm;
      // The firmware counts whole steps; the register is 16-bit.
      const double wrapped = std::floor(steps) - 65536.0 * std::floor((std::floor(steps) + 32768.0) / 65536.0);
      w.row({std::round(t * 1e4) / 1e4, command_cm_s, command_cm_s, wrapped, wrapped, tof});
      next_sample = t + truth.sample_period_s + truth.sample_jitter_s * (2.0 * noise.uniform() - 1.0);
      next_sample = std::round(next_sample / truth.physics_step_s) * truth.physics_step_s;
    }
    // Physics step: the wheels turn at the commanded rate; the body follows with a first-order lag
    // (integrated exactly over the step).
    const double dt = truth.physics_step_s;
    const double wheel_speed = rate_steps_s / true_steps_per_m;
    s::body_lag_piece(s::DriveWheelSlip<double>{lag}, wheel_speed, 0.0, dt, ground_m, ground_speed);
    steps += rate_steps_s * dt;
    t += dt;
  }
  return {run.name, w.str()};
}

std::string run_name(const char* what, double speed_cm_s, const std::string& suffix) {
  char name[128];
  std::snprintf(name, sizeof name, "drive_%s_%04.1f_cm_s%s.csv", what, speed_cm_s, suffix.c_str());
  return name;
}

}  // namespace

std::vector<GeneratedFile> drive_logs(const DriveTruth& truth, std::uint64_t seed) {
  std::vector<GeneratedFile> files;
  for (std::size_t r = 0; r < truth.steps_per_m_scale.size(); ++r) {
    RunSpec run;
    run.robot = robot_id(r);
    run.wheel_scale = truth.steps_per_m_scale[r];
    run.obstacle_m = truth.obstacle_distance_m;
    run.pause_before_s = run.pause_after_s = truth.pause_s;
    const std::string suffix = r == 0 ? "" : "_" + run.robot;
    const std::vector<double>& speeds = r == 0 ? truth.speeds_cm_s : truth.other_robot_speeds_cm_s;
    std::uint64_t k = 5000 + 200 * r;
    for (double v : speeds) {
      for (int direction : {+1, -1}) {
        run.speed_cm_s = v;
        run.direction = direction;
        run.travel_m = direction > 0 ? truth.toward_travel_m : truth.away_travel_m;
        run.name = run_name(direction > 0 ? "toward" : "away", v, suffix);
        files.push_back(drive_run(truth, run, seed + k++));
      }
    }
    if (r != 0) continue;
    // Robot 1's extra runs.
    if (truth.static_run_s > 0) {
      RunSpec still = run;
      still.speed_cm_s = 0;
      still.direction = +1;
      still.travel_m = 0;
      still.pause_before_s = truth.static_run_s;
      still.pause_after_s = 0;
      still.name = "drive_static.csv";
      files.push_back(drive_run(truth, still, seed + 5100));
    }
    if (truth.floor_run_speed_cm_s > 0) {
      // Start against the obstacle, where the latent ToF reading is the 20 mm floor (to 0.1 mm, as
      // a user would place the robot and measure), stand still, then drive away.
      RunSpec floor = run;
      floor.obstacle_m = std::round((20.0 - truth.tof_offset_mm) / truth.tof_scale * 10.0) / 1e4;
      floor.speed_cm_s = truth.floor_run_speed_cm_s;
      floor.direction = -1;
      floor.travel_m = truth.floor_run_travel_m;
      floor.pause_before_s = truth.floor_run_pause_s;
      floor.name = run_name("away_floor", floor.speed_cm_s, "");
      files.push_back(drive_run(truth, floor, seed + 5101));
    }
    if (truth.far_run_speed_cm_s > 0) {
      RunSpec far = run;
      far.speed_cm_s = truth.far_run_speed_cm_s;
      far.direction = -1;
      far.travel_m = truth.far_run_travel_m;
      far.name = run_name("away_far", far.speed_cm_s, "");
      files.push_back(drive_run(truth, far, seed + 5102));
    }
  }
  return files;
}

std::vector<GeneratedFile> drive_reference_logs(std::uint64_t seed) { return drive_logs(DriveTruth{}, seed); }

}  // namespace epuck2::virtual_robot
