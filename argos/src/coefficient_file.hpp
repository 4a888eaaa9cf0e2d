// Reading the project's coefficient files (data/fitted/<kind>.json, written by epuck2-fit) inside
// the ARGoS plug-in. Only the few fields the run-time models need are read here; the formulas
// themselves are epuck2::models'. No ARGoS dependency: errors are std::runtime_error whose message
// starts with the file's path, which the sensors turn into ARGoS exceptions at Init.
#pragma once

#include <cstddef>
#include <memory>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include <epuck2/models/battery.hpp>
#include <epuck2/models/plugin_battery_tables.hpp>

namespace epuck2::argos_plugin {

/// One channel of a coefficient file's `noise` section (docs/coefficient-files.md): the reading
/// noise the calibration measured, in the reading's units.
struct ReadingNoise {
  std::string channel;                ///< proximity, light, ground, tof, encoder, camera
  double sd = 0;                      ///< standard deviation of a reading, in `unit`
  std::string unit;                   ///< counts, mm, steps, px
  std::vector<double> per_sensor_sd;  ///< one per sensor where sensors differ; empty otherwise
  std::string from;                   ///< replicates or residuals
  double n = 0;                       ///< readings the estimate is made of
  /// Each of `count` sensors' sd: per_sensor_sd when the file has it, else sd for every sensor.
  std::vector<double> sd_per_sensor(std::size_t count) const {
    return per_sensor_sd.size() == count ? per_sensor_sd : std::vector<double>(count, sd);
  }
};

/// A sensor coefficient file: `parameters` {name: number or array}, optional `std_errors`,
/// optional `noise` {channel: {sd, unit, per_sensor_sd, from, n, argos_uniform_level}} and optional
/// `robots` {ID: {parameters, std_errors, noise}}.
class CoefficientFile {
 public:
  /// Loads `path` and checks that its `kind` (when present) is one of `kinds`. With a non-empty
  /// `robot`, the file's `robots.<robot>` set overrides the top-level parameters (and it is an
  /// error if the file has no such robot).
  static CoefficientFile load(const std::string& path, const std::vector<std::string>& kinds,
                              const std::string& robot = "");

  const std::string& path() const { return path_; }
  /// The robot set asked for (empty: the top level).
  const std::string& robot() const { return robot_; }
  const nlohmann::json& root() const { return *root_; }

  bool has(const std::string& name) const;
  /// A scalar parameter; an error when missing or not a number.
  double scalar(const std::string& name) const;
  /// A scalar parameter, or `fallback` when the file does not have it.
  double scalar_or(const std::string& name, double fallback) const;
  /// A per-sensor parameter: an array of `count` numbers, or one number used for every sensor.
  std::vector<double> per_sensor(const std::string& name, std::size_t count) const;
  /// Whether the file has a `noise` section (files written before it have none).
  bool has_noise() const { return noise_.is_object(); }
  /// `noise.<channel>` (the robot's set first), checked: `sd` a non-negative number, `unit` equal
  /// to `unit`, `per_sensor_sd` (when present) `sensors` non-negative numbers. std::nullopt when
  /// the file has no `noise` section; an error when the section lacks the channel.
  std::optional<ReadingNoise> noise(const std::string& channel, const std::string& unit, std::size_t sensors) const;
  /// The extended model's `effects` (a diagnosis file; the robot's set merged over the top level):
  /// {name: {parameter: number}}; an empty object for a calibration file.
  const nlohmann::json& effects() const { return effects_; }
  /// An error naming the file (and robot): what the calibrated sensors throw.
  [[noreturn]] void fail(const std::string& what) const;

 private:
  std::string path_;
  std::string robot_;
  std::shared_ptr<const nlohmann::json> root_;  ///< shared by every sensor that loads the file
  nlohmann::json parameters_;  ///< top level, with the robot's set merged over it
  nlohmann::json noise_;       ///< top level, with the robot's set merged over it (per channel)
  nlohmann::json effects_ = nlohmann::json::object();  ///< top level, the robot's set merged over it
};

/// Which of a file's robot sets an ARGoS robot uses (docs/argos.md, "A swarm, one controller").
struct RobotChoice {
  std::string robot;    ///< the set's id; empty: the top-level (pooled) set
  std::string warning;  ///< non-empty: to be said at Init (a multi-robot file read without robot=)
};
/// `attribute` is the XML's robot= (empty, an id, or "auto"), `robot_map` its robot_map=
/// ("PATTERN:ID,PATTERN:ID", '*' matching any run of characters, the first match wins) and
/// `entity_id` the ARGoS robot's id. "auto": the robot_map's match, else the set named like the
/// entity; an entity without a set is an error naming it and the file's robots. No robot= on a
/// file with several robots: the pooled set, with a warning naming the parameters that differ
/// between the robots (the file's robot_spread).
RobotChoice choose_robot(const nlohmann::json& root, const std::string& path, const std::string& attribute,
                         const std::string& robot_map, const std::string& entity_id);

/// A battery coefficient file (a calibration, `battery -o`, or a battery diagnosis, `diagnose -o`;
/// the layout lib/fit's battery_json.cpp writes: `speeds` [{speed_cm_s, cubic [d,c,b,a],
/// lifetime_s, linear_slope, segments [4 x {h,m,x1_s,x2_s,y1,y2}]}], `simple` {static_slope_per_s,
/// moving_slope_per_s}, and a diagnosis's `battery_model` and `effects.capacity_scale.k`).
struct BatteryFile {
  /// The file's table at each speed it has, the plug-in's at the others (and the plug-in's
  /// Simple slopes when the file has no `simple`).
  epuck2::models::battery::Tables tables;
  std::vector<int> fitted_speeds;  ///< the speeds (cm/s) whose tables are the file's, ascending
  bool fitted_simple = false;      ///< the Simple model's slopes are the file's
  std::optional<epuck2::models::battery::Model> model;  ///< battery_model, when the file names one
  double capacity_k = 1.0;         ///< effects.capacity_scale.k (1: none)
};
/// Reads a battery file: 1 to 16 speeds (whole cm/s, 0..15, each once); any effect other than
/// capacity_scale is an error naming it (ARGoS cannot apply it).
BatteryFile load_battery_file(const std::string& path);
/// The same, read once per process and file (while the file stays the same) and shared: 50 robots
/// with the calibrated battery model step through one copy of the tables, not 50.
std::shared_ptr<const BatteryFile> shared_battery_file(const std::string& path);

/// Every file is parsed once per process and path (while its size and modification time stay the
/// same): 50 robots with a calibrated sensor share one parse of the file, not 50.
std::shared_ptr<const nlohmann::json> parse_coefficient_file(const std::string& path);

/// A coefficient file name as written in the XML: environment variables expanded by the caller;
/// a relative name is looked up next to the experiment file first, then in the working
/// directory. Returns the first that exists, else the name relative to the experiment file.
std::string resolve_coefficient_path(const std::string& name, const std::string& experiment_file);

}  // namespace epuck2::argos_plugin
