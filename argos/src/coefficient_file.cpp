#include "coefficient_file.hpp"

#include <epuck2/models/effects.hpp>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <map>
#include <mutex>
#include <sstream>

namespace epuck2::argos_plugin {

namespace fs = std::filesystem;
namespace mb = epuck2::models::battery;
using nlohmann::json;

namespace {

json parse_file_uncached(const std::string& path) {
  std::ifstream in(path);
  if (!in) throw std::runtime_error(path + ": cannot open the coefficient file");
  try {
    json j;
    in >> j;
    if (!j.is_object()) throw std::runtime_error(path + ": not a coefficient file (expected a JSON object)");
    return j;
  } catch (const json::parse_error& e) {
    throw std::runtime_error(path + ": not JSON: " + e.what());
  }
}

struct CachedFile {
  std::uintmax_t size = 0;
  fs::file_time_type modified{};
  std::shared_ptr<const json> root;
};

}  // namespace

std::shared_ptr<const json> parse_coefficient_file(const std::string& path) {
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
  auto root = std::make_shared<const json>(parse_file_uncached(path));
  if (stat_ok) cache[path] = CachedFile{size, modified, root};
  return root;
}

namespace {

/// `over`'s members replace `base`'s (one level deep).
json merged(json base, const json& over) {
  if (!base.is_object()) base = json::object();
  if (over.is_object())
    for (auto it = over.begin(); it != over.end(); ++it) base[it.key()] = it.value();
  return base;
}

std::string join(const std::vector<std::string>& v) {
  std::string s;
  for (const auto& x : v) s += (s.empty() ? "" : " or ") + x;
  return s;
}

}  // namespace

CoefficientFile CoefficientFile::load(const std::string& path, const std::vector<std::string>& kinds,
                                      const std::string& robot) {
  CoefficientFile f;
  f.path_ = path;
  f.robot_ = robot;
  f.root_ = parse_coefficient_file(path);
  const json& root = *f.root_;
  if (root.contains("kind")) {
    const json& k = root.at("kind");
    bool ok = false;
    for (const auto& want : kinds) ok = ok || (k.is_string() && k.get<std::string>() == want);
    if (!ok) f.fail("a '" + (k.is_string() ? k.get<std::string>() : k.dump()) + "' file, expected " + join(kinds));
  }
  if (!root.contains("parameters") || !root.at("parameters").is_object())
    f.fail("no 'parameters' object");
  f.parameters_ = root.at("parameters");
  if (root.contains("noise")) {
    if (!root.at("noise").is_object()) f.fail("'noise' must be an object {channel: {sd, unit, ...}}");
    f.noise_ = root.at("noise");
  }
  if (root.contains("effects") && !root.at("effects").is_null()) {
    if (!root.at("effects").is_object()) f.fail("'effects' must be an object {effect: {parameter: number}}");
    f.effects_ = root.at("effects");
  }
  if (!robot.empty()) {
    const json robots = root.value("robots", json::object());
    if (!robots.is_object() || !robots.contains(robot)) {
      std::string known;
      if (robots.is_object())
        for (auto it = robots.begin(); it != robots.end(); ++it) known += (known.empty() ? "" : ", ") + it.key();
      f.fail("no coefficients for robot '" + robot + "' (robots in the file: " + (known.empty() ? "none" : known) + ")");
    }
    const json& r = robots.at(robot);
    f.parameters_ = merged(f.parameters_, r.value("parameters", json::object()));
    if (r.contains("noise") && r.at("noise").is_object()) f.noise_ = merged(f.noise_, r.at("noise"));
    if (r.contains("effects") && r.at("effects").is_object()) f.effects_ = merged(f.effects_, r.at("effects"));
  }
  return f;
}

void CoefficientFile::fail(const std::string& what) const {
  throw std::runtime_error(path_ + (robot_.empty() ? "" : " (robot " + robot_ + ")") + ": " + what);
}

bool CoefficientFile::has(const std::string& name) const { return parameters_.contains(name); }

double CoefficientFile::scalar(const std::string& name) const {
  if (!parameters_.contains(name)) fail("missing parameter '" + name + "'");
  const json& v = parameters_.at(name);
  if (!v.is_number()) fail("parameter '" + name + "' must be a number, found " + v.dump());
  return v.get<double>();
}

double CoefficientFile::scalar_or(const std::string& name, double fallback) const {
  return has(name) ? scalar(name) : fallback;
}

std::vector<double> CoefficientFile::per_sensor(const std::string& name, std::size_t count) const {
  if (!parameters_.contains(name)) fail("missing parameter '" + name + "'");
  const json& v = parameters_.at(name);
  if (v.is_number()) return std::vector<double>(count, v.get<double>());
  if (!v.is_array() || v.size() != count)
    fail("parameter '" + name + "' must be a number or an array of " + std::to_string(count) + " numbers, found " + v.dump());
  std::vector<double> out;
  for (const json& x : v) {
    if (!x.is_number()) fail("parameter '" + name + "' must hold numbers, found " + x.dump());
    out.push_back(x.get<double>());
  }
  return out;
}

std::optional<ReadingNoise> CoefficientFile::noise(const std::string& channel, const std::string& unit,
                                                   std::size_t sensors) const {
  if (!noise_.is_object()) return std::nullopt;
  const std::string where = "noise." + channel;
  if (!noise_.contains(channel)) fail("the 'noise' section has no '" + channel + "' entry");
  const json& e = noise_.at(channel);
  if (!e.is_object()) fail(where + " must be an object {sd, unit, ...}");
  ReadingNoise r;
  r.channel = channel;
  if (!e.contains("sd") || !e.at("sd").is_number() || !(e.at("sd").get<double>() >= 0))
    fail(where + ".sd must be a non-negative number");
  r.sd = e.at("sd").get<double>();
  if (!e.contains("unit") || !e.at("unit").is_string() || e.at("unit").get<std::string>() != unit)
    fail(where + ".unit must be \"" + unit + "\", found " + (e.contains("unit") ? e.at("unit").dump() : "none"));
  r.unit = unit;
  if (e.contains("per_sensor_sd")) {
    const json& v = e.at("per_sensor_sd");
    if (!v.is_array() || v.size() != sensors)
      fail(where + ".per_sensor_sd must be an array of " + std::to_string(sensors) + " numbers, found " + v.dump());
    for (const json& x : v) {
      if (!x.is_number() || !(x.get<double>() >= 0)) fail(where + ".per_sensor_sd must hold non-negative numbers, found " + x.dump());
      r.per_sensor_sd.push_back(x.get<double>());
    }
  }
  if (e.contains("from") && e.at("from").is_string()) r.from = e.at("from").get<std::string>();
  if (e.contains("n") && e.at("n").is_number()) r.n = e.at("n").get<double>();
  return r;
}

namespace {

double number_at(const json& o, const char* key, const std::string& path, const std::string& where) {
  if (!o.is_object() || !o.contains(key) || !o.at(key).is_number())
    throw std::runtime_error(path + ": " + where + ": missing number '" + key + "'");
  return o.at(key).get<double>();
}

}  // namespace

BatteryFile load_battery_file(const std::string& path) {
  const json& j = *parse_coefficient_file(path);
  if (j.contains("kind") && j.at("kind") != "battery")
    throw std::runtime_error(path + ": a '" + (j.at("kind").is_string() ? j.at("kind").get<std::string>() : j.at("kind").dump()) +
                             "' file, expected battery");
  if (!j.contains("speeds") || !j.at("speeds").is_array() || j.at("speeds").empty())
    throw std::runtime_error(path + ": not a battery coefficient file: expected an object with a 'speeds' array of 1 to 16 entries");
  const json& speeds = j.at("speeds");
  if (speeds.size() > mb::kSpeedCount)
    throw std::runtime_error(path + ": expected at most 16 entries in 'speeds' (0..15 cm/s), found " + std::to_string(speeds.size()));
  BatteryFile f;
  f.tables = mb::plugin_tables();  // the plug-in's where the file has no table
  for (std::size_t k = 0; k < speeds.size(); ++k) {
    const json& e = speeds.at(k);
    const std::string where = "speeds[" + std::to_string(k) + "]";
    const double v = number_at(e, "speed_cm_s", path, where);
    const double whole = std::round(v);
    if (std::abs(v - whole) > 1e-9 || whole < 0 || whole >= static_cast<double>(mb::kSpeedCount))
      throw std::runtime_error(path + ": " + where + ": speed_cm_s must be a whole number of cm/s in 0..15, found " + e.at("speed_cm_s").dump());
    const auto s = static_cast<std::size_t>(whole);
    if (std::find(f.fitted_speeds.begin(), f.fitted_speeds.end(), static_cast<int>(s)) != f.fitted_speeds.end())
      throw std::runtime_error(path + ": " + where + ": a second table for " + std::to_string(s) + " cm/s");
    f.fitted_speeds.push_back(static_cast<int>(s));
    if (!e.contains("cubic") || !e.at("cubic").is_array() || e.at("cubic").size() != 4)
      throw std::runtime_error(path + ": " + where + ": expected 'cubic' as [d, c, b, a]");
    const json& c = e.at("cubic");
    for (const json& x : c)
      if (!x.is_number()) throw std::runtime_error(path + ": " + where + ": 'cubic' must hold numbers");
    const double life = number_at(e, "lifetime_s", path, where);
    f.tables.cubic[s] = mb::CubicRow{c.at(0).get<double>(), c.at(1).get<double>(), c.at(2).get<double>(),
                                     c.at(3).get<double>(), life};
    f.tables.lifetime_s[s] = life;
    f.tables.linear_slope_per_s[s] = number_at(e, "linear_slope", path, where);
    if (!e.contains("segments") || !e.at("segments").is_array() || e.at("segments").size() != mb::kSegmentCount)
      throw std::runtime_error(path + ": " + where + ": expected 4 'segments'");
    for (std::size_t k2 = 0; k2 < mb::kSegmentCount; ++k2) {
      const json& g = e.at("segments").at(k2);
      const std::string gw = where + ".segments[" + std::to_string(k2) + "]";
      f.tables.segments[s][k2] = mb::Segment{number_at(g, "h", path, gw),    number_at(g, "m", path, gw),
                                             number_at(g, "x1_s", path, gw), number_at(g, "x2_s", path, gw),
                                             number_at(g, "y1", path, gw),   number_at(g, "y2", path, gw)};
    }
  }
  std::sort(f.fitted_speeds.begin(), f.fitted_speeds.end());
  if (j.contains("simple")) {
    f.tables.simple_static_slope_per_s = number_at(j.at("simple"), "static_slope_per_s", path, "simple");
    f.tables.simple_moving_slope_per_s = number_at(j.at("simple"), "moving_slope_per_s", path, "simple");
    f.fitted_simple = true;
  }
  if (j.contains("battery_model")) {
    mb::Model m{};
    if (!j.at("battery_model").is_string() || !mb::parse_model(j.at("battery_model").get<std::string>(), m))
      throw std::runtime_error(path + ": battery_model must be simple, linear, cubic or approximated, found " +
                               j.at("battery_model").dump());
    f.model = m;
  }
  const char* capacity_scale = epuck2::models::effects::battery_catalogue()[epuck2::models::effects::battery::capacity_scale].name;
  if (j.contains("effects") && j.at("effects").is_object()) {
    for (auto it = j.at("effects").begin(); it != j.at("effects").end(); ++it) {
      if (it.key() == capacity_scale) continue;
      throw std::runtime_error(path + ": effects." + it.key() + ": the calibrated battery cannot apply it in ARGoS" +
                               (it.key().rfind("covariate:", 0) == 0 ? ": it needs the log column '" + it.key().substr(10) +
                                                                           "', which ARGoS does not have"
                                                                     : std::string(": not a battery effect (the battery's is ") + capacity_scale + ")"));
    }
    if (j.at("effects").contains(capacity_scale)) {
      f.capacity_k = number_at(j.at("effects").at(capacity_scale), "k", path, std::string("effects.") + capacity_scale);
      if (!(f.capacity_k > 0)) throw std::runtime_error(path + ": effects." + capacity_scale + ".k must be positive");
    }
  }
  return f;
}

std::shared_ptr<const BatteryFile> shared_battery_file(const std::string& path) {
  struct Entry {
    std::shared_ptr<const json> root;  ///< the parse the tables were read from
    std::shared_ptr<const BatteryFile> file;
  };
  static std::mutex mutex;
  static std::map<std::string, Entry> cache;
  const std::shared_ptr<const json> root = parse_coefficient_file(path);
  std::lock_guard<std::mutex> lock(mutex);
  const auto it = cache.find(path);
  if (it != cache.end() && it->second.root == root) return it->second.file;
  auto file = std::make_shared<const BatteryFile>(load_battery_file(path));
  cache[path] = Entry{root, file};
  return file;
}

namespace {

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

}  // namespace

RobotChoice choose_robot(const json& root, const std::string& path, const std::string& attribute,
                         const std::string& robot_map, const std::string& entity_id) {
  RobotChoice c;
  const json robots = root.value("robots", json::object());
  if (!robot_map.empty() && attribute != "auto")
    throw std::runtime_error(path + ": robot_map is used only with robot=\"auto\"");
  if (attribute == "auto") {
    if (!robot_map.empty()) {
      std::istringstream in(robot_map);
      std::string item;
      while (std::getline(in, item, ',')) {
        const auto colon = item.rfind(':');
        if (colon == std::string::npos || colon == 0 || colon + 1 == item.size())
          throw std::runtime_error(path + ": robot_map entry '" + item + "' is not PATTERN:ROBOT_ID");
        if (glob_match(item.substr(0, colon).c_str(), entity_id.c_str())) {
          c.robot = item.substr(colon + 1);
          return c;
        }
      }
      throw std::runtime_error(path + ": robot=\"auto\": no robot_map pattern matches the entity '" + entity_id +
                               "' (robot_map \"" + robot_map + "\")");
    }
    if (robots.is_object() && robots.contains(entity_id)) {
      c.robot = entity_id;
      return c;
    }
    throw std::runtime_error(path + ": robot=\"auto\": the entity '" + entity_id +
                             "' has no robot set in the file (robots: " + robot_list(robots) +
                             "); name the sets after the entities or give robot_map=\"PATTERN:ROBOT_ID,...\"");
  }
  c.robot = attribute;
  if (!attribute.empty() || !robots.is_object() || robots.size() < 2) return c;
  // The pooled set of several robots: say so, with what differs between them.
  std::string differ;
  for (const json& e : root.value("robot_spread", json::array()))
    if (e.is_object() && e.value("exceeds_uncertainty", false) && e.contains("parameter") && e.contains("spread_sd")) {
      std::ostringstream os;
      os << e.at("parameter").get<std::string>() << " (spread sd " << e.at("spread_sd").get<double>() << ")";
      differ += (differ.empty() ? "" : ", ") + os.str();
    }
  c.warning = path + " holds " + std::to_string(robots.size()) + " robots (" + robot_list(robots) +
              ") and no robot= is given: using the pooled set, which describes no robot" +
              (differ.empty() ? std::string(" (the robots agree within their uncertainties)")
                              : "; the robots differ beyond their uncertainties in " + differ) +
              ". robot=\"ID\" or robot=\"auto\" uses a robot's own set";
  return c;
}

std::string resolve_coefficient_path(const std::string& name, const std::string& experiment_file) {
  const fs::path p(name);
  if (p.is_absolute()) return name;
  std::error_code ec;
  const fs::path beside = fs::path(experiment_file).parent_path() / p;
  if (!experiment_file.empty() && fs::exists(beside, ec)) return beside.lexically_normal().string();
  if (fs::exists(p, ec)) return name;
  return experiment_file.empty() ? name : beside.lexically_normal().string();
}

}  // namespace epuck2::argos_plugin
