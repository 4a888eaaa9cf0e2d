// What a simulator that runs many robots from one coefficient file needs besides the model
// (model_file.hpp): the file read once and shared, a relative name resolved beside the experiment,
// and which robot set of the file each robot uses. The ARGoS plug-in's sensors, actuator and
// battery read their files through these and model_file.hpp, so that every file is validated as
// the CLI validates it (errors at FILE:LINE:COLUMN with the JSON path, logs::InputError).
#pragma once

#include <nlohmann/json.hpp>

#include <memory>
#include <string>
#include <vector>

namespace epuck2::coefficients {

/// read_json_file, once per process and path while the file's size and modification time stay the
/// same: 50 robots reading one file share one parse, not 50.
std::shared_ptr<const nlohmann::json> shared_json_file(const std::string& path);

/// A file name as written in an experiment: absolute as is; relative, looked up beside
/// `experiment_file` first, then in the working directory; the first that exists, else the name
/// beside the experiment file.
std::string resolve_model_path(const std::string& name, const std::string& experiment_file);

/// Which of a file's robot sets a simulated robot uses (docs/argos.md, "A swarm, one controller").
struct RobotChoice {
  std::string robot;    ///< the set's id; empty: the top-level (pooled) set
  std::string warning;  ///< non-empty: to be said once (a multi-robot file read without a robot)
};
/// `attribute` is the robot asked for (empty, an id, or "auto"), `robot_map`
/// "PATTERN:ID,PATTERN:ID" ('*' matches any run of characters, the first match wins) and
/// `entity_id` the simulated robot's id. "auto": the robot_map's match, else the set named like
/// the entity; an entity without a set is an error naming it and the file's robots. No robot on a
/// file with several: the pooled set, with a warning naming the parameters that differ between
/// the robots (the file's robot_spread). Errors are logs::InputError located in the file.
RobotChoice choose_robot(const nlohmann::json& root, const std::string& path, const std::string& attribute,
                         const std::string& robot_map, const std::string& entity_id);

/// Which of a calibration file's sets the CLI runs on logs (`simulate KIND --like`, `diagnose
/// --coefficients`; docs/cli.md): `asked` is --robot ("" when not given), `log_robots` the robots
/// of the logs (logs::Log::robot: `# robot:`, a robot column, or the file stem). --robot ID: that
/// robot's set (std::invalid_argument listing the file's robots when it has none, or when its set
/// holds no fitted parameters). Else, logs of one robot that has a fitted set of its own: that set,
/// said in `note`. Else, on a file of several robots: the pooled set, with `warning` saying so and
/// naming what differs between the robots (the file's robot_spread), as ARGoS says at Init.
struct LogRobotChoice {
  std::string robot;    ///< the set's id; empty: the top-level (pooled) set
  std::string note;     ///< which set is used and why (when a robot's set is used)
  std::string warning;  ///< the pooled set of several robots is used: to be said
};
LogRobotChoice choose_robot_for_logs(const nlohmann::json& root, const std::string& path, const std::string& asked,
                                     const std::vector<std::string>& log_robots);

/// Whether the file gives a reading noise (a `noise` section at the top or in the robot's set):
/// files written before epuck2-fit measured it have none, and a simulator says so.
bool has_noise_section(const nlohmann::json& root, const std::string& robot);

/// Throws the reader's error (logs::InputError, a std::runtime_error) about the value at JSON
/// pointer `pointer` of the file `path`: FILE:LINE:COLUMN, `what`, the JSON path. For what a
/// simulator refuses beyond the reader's checks (an effect it cannot apply), without including
/// lib/logs' headers (whose names clash with ARGoS's macros).
[[noreturn]] void fail_in_file(const std::string& path, const std::string& pointer, const std::string& what);

}  // namespace epuck2::coefficients
