// Shared files, paths and robot sets: see epuck2/coefficients/model_sets.hpp.
#include "epuck2/coefficients/model_sets.hpp"

#include <algorithm>
#include <filesystem>
#include <stdexcept>
#include <map>
#include <mutex>
#include <sstream>

#include "epuck2/coefficients/model_file.hpp"
#include "epuck2/logs/json_location.hpp"

namespace epuck2::coefficients {

namespace fs = std::filesystem;
using nlohmann::json;

namespace {

struct CachedFile {
  std::uintmax_t size = 0;
  fs::file_time_type modified{};
  std::shared_ptr<const json> root;
};

/// `text` matches `pattern`, '*' standing for any run of characters.
bool glob_match(const char* pattern, const char* text) {
  if (*pattern == '\0') return *text == '\0';
  if (*pattern == '*') return glob_match(pattern + 1, text) || (*text != '\0' && glob_match(pattern, text + 1));
  return *text == *pattern && glob_match(pattern + 1, text + 1);
}

std::string robot_list(const json& robots) {
  std::string known;
  if (robots.is_object())
    for (auto it = robots.begin(); it != robots.end(); ++it) known += (known.empty() ? "" : ", ") + it.key();
  return known.empty() ? "none" : known;
}

/// A robot's set that a calibration fitted (an object with parameters; not {"usable": false, "why"}).
bool fitted_set(const json& set) {
  return set.is_object() && set.contains("parameters") && !(set.contains("usable") && set.at("usable") == false);
}

/// "PATH holds N robots (a, b) and WHY: using the pooled set, which describes no robot; the robots
/// differ ... in P (spread sd S). HOW": what a reader of the pooled set of several robots says.
std::string pooled_set_warning(const json& root, const std::string& path, const std::string& why, const std::string& how) {
  const json robots = root.value("robots", json::object());
  std::string differ;
  for (const json& e : root.value("robot_spread", json::array()))
    if (e.is_object() && e.value("exceeds_uncertainty", false) && e.contains("parameter") && e.at("parameter").is_string() &&
        e.contains("spread_sd") && e.at("spread_sd").is_number()) {
      std::ostringstream os;
      os << e.at("parameter").get<std::string>() << " (spread sd " << e.at("spread_sd").get<double>() << ")";
      differ += (differ.empty() ? "" : ", ") + os.str();
    }
  return path + " holds " + std::to_string(robots.size()) + " robots (" + robot_list(robots) + ") and " + why +
         ": using the pooled set, which describes no robot" +
         (differ.empty() ? std::string(" (the robots agree within their uncertainties)")
                         : "; the robots differ beyond their uncertainties in " + differ) +
         ". " + how;
}

}  // namespace

std::shared_ptr<const json> shared_json_file(const std::string& path) {
  static std::mutex mutex;
  static std::map<std::string, CachedFile> cache;
  std::error_code ec_size, ec_time;
  const std::uintmax_t size = fs::file_size(path, ec_size);
  const fs::file_time_type modified = fs::last_write_time(path, ec_time);
  const bool stat_ok = !ec_size && !ec_time;
  std::lock_guard<std::mutex> lock(mutex);
  if (stat_ok) {
    const auto it = cache.find(path);
    if (it != cache.end() && it->second.size == size && it->second.modified == modified) return it->second.root;
  }
  auto root = std::make_shared<const json>(read_json_file(path));
  if (!root->is_object()) throw logs::json_file_error(path, "", "not a coefficient file (expected a JSON object)");
  if (stat_ok) cache[path] = CachedFile{size, modified, root};
  return root;
}

std::string resolve_model_path(const std::string& name, const std::string& experiment_file) {
  const fs::path p(name);
  if (p.is_absolute()) return name;
  std::error_code ec;
  const fs::path beside = fs::path(experiment_file).parent_path() / p;
  if (!experiment_file.empty() && fs::exists(beside, ec)) return beside.lexically_normal().string();
  if (fs::exists(p, ec)) return name;
  return experiment_file.empty() ? name : beside.lexically_normal().string();
}

RobotChoice choose_robot(const json& root, const std::string& path, const std::string& attribute,
                         const std::string& robot_map, const std::string& entity_id) {
  RobotChoice c;
  const json robots = root.is_object() ? root.value("robots", json::object()) : json::object();
  const std::string at = root.is_object() && root.contains("robots") ? "/robots" : "";
  if (!robot_map.empty() && attribute != "auto")
    throw logs::json_file_error(path, at, "robot_map is used only with robot=\"auto\"");
  if (attribute == "auto") {
    if (!robot_map.empty()) {
      std::istringstream in(robot_map);
      std::string item;
      while (std::getline(in, item, ',')) {
        const auto colon = item.rfind(':');
        if (colon == std::string::npos || colon == 0 || colon + 1 == item.size())
          throw logs::json_file_error(path, at, "robot_map entry '" + item + "' is not PATTERN:ROBOT_ID");
        if (glob_match(item.substr(0, colon).c_str(), entity_id.c_str())) {
          c.robot = item.substr(colon + 1);
          return c;
        }
      }
      throw logs::json_file_error(path, at, "robot=\"auto\": no robot_map pattern matches the entity '" + entity_id +
                                                "' (robot_map \"" + robot_map + "\")");
    }
    if (robots.is_object() && robots.contains(entity_id)) {
      c.robot = entity_id;
      return c;
    }
    throw logs::json_file_error(path, at, "robot=\"auto\": the entity '" + entity_id + "' has no robot set in the file (robots: " +
                                              robot_list(robots) +
                                              "); name the sets after the entities or give robot_map=\"PATTERN:ROBOT_ID,...\"");
  }
  c.robot = attribute;
  if (!attribute.empty() || !robots.is_object() || robots.size() < 2) return c;
  c.warning = pooled_set_warning(root, path, "no robot= is given", "robot=\"ID\" or robot=\"auto\" uses a robot's own set");
  return c;
}

LogRobotChoice choose_robot_for_logs(const json& root, const std::string& path, const std::string& asked,
                                     const std::vector<std::string>& log_robots) {
  LogRobotChoice c;
  const json robots = root.is_object() ? root.value("robots", json::object()) : json::object();
  if (!asked.empty()) {
    if (!robots.is_object() || !robots.contains(asked))
      throw std::invalid_argument("--robot " + asked + ": " + path + " has no set of that robot (its robots: " + robot_list(robots) +
                                  ")");
    if (!fitted_set(robots.at(asked)))
      throw std::invalid_argument("--robot " + asked + ": " + path + "'s set of that robot holds no fitted parameters (" +
                                  robots.at(asked).value("why", std::string("not fitted")) + "); its robots: " + robot_list(robots));
    c.robot = asked;
    c.note = "using " + path + "'s set robots." + asked + " (--robot " + asked + ")";
    return c;
  }
  std::vector<std::string> distinct;
  for (const std::string& r : log_robots)
    if (std::find(distinct.begin(), distinct.end(), r) == distinct.end()) distinct.push_back(r);
  if (distinct.size() == 1 && robots.is_object() && robots.contains(distinct.front()) && fitted_set(robots.at(distinct.front()))) {
    c.robot = distinct.front();
    c.note = "using " + path + "'s set robots." + c.robot + ", the log's robot's own (--robot ID asks for another)";
    return c;
  }
  if (!robots.is_object() || robots.size() < 2) return c;
  std::string whose;
  if (distinct.size() == 1)
    whose = "the log's robot " + distinct.front() + " has no fitted set of its own";
  else {
    whose = "the logs are of " + std::to_string(distinct.size()) + " robots (";
    for (std::size_t i = 0; i < distinct.size(); ++i) whose += (i ? ", " : "") + distinct[i];
    whose += ")";
  }
  c.warning = pooled_set_warning(root, path, whose, "--robot ID uses a robot's own set");
  return c;
}

bool has_noise_section(const json& root, const std::string& robot) {
  if (!root.is_object()) return false;
  if (root.contains("noise") && !root.at("noise").is_null()) return true;
  if (robot.empty() || !root.contains("robots") || !root.at("robots").is_object() || !root.at("robots").contains(robot))
    return false;
  const json& r = root.at("robots").at(robot);
  return r.is_object() && r.contains("noise") && !r.at("noise").is_null();
}

void fail_in_file(const std::string& path, const std::string& pointer, const std::string& what) {
  throw logs::json_file_error(path, pointer, what);
}

}  // namespace epuck2::coefficients
