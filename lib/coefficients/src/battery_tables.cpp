// The battery tables of a coefficient file: see epuck2/coefficients/battery_tables.hpp.
#include "epuck2/coefficients/battery_tables.hpp"

#include <algorithm>
#include <cmath>

#include "epuck2/logs/json_location.hpp"
#include "epuck2/models/plugin_battery_tables.hpp"

namespace epuck2::coefficients {

namespace mb = models::battery;
using nlohmann::json;

namespace {

enum class Sign { any, positive, negative_or_zero, negative };

double number_at(const json& j, const std::string& key, const std::string& path, const std::string& where,
                 const std::string& pointer, Sign sign = Sign::any) {
  if (!j.is_object() || !j.contains(key) || !j.at(key).is_number())
    throw logs::json_file_error(path, pointer + "/" + key, where + ": expected a number '" + key + "'");
  const double v = j.at(key).get<double>();
  const std::string at = pointer + "/" + key;
  if (!std::isfinite(v)) throw logs::json_file_error(path, at, where + "." + key + " must be a finite number");
  if (sign == Sign::positive && !(v > 0))
    throw logs::json_file_error(path, at, where + "." + key + " must be positive (found " + json(v).dump() + ")");
  if (sign == Sign::negative && !(v < 0))
    throw logs::json_file_error(path, at, where + "." + key + " must be negative: a charge falls (found " + json(v).dump() + ")");
  if (sign == Sign::negative_or_zero && !(v <= 0))
    throw logs::json_file_error(path, at, where + "." + key + " must not be positive: a charge does not rise (found " +
                                              json(v).dump() + ")");
  return v;
}

}  // namespace

json battery_tables_to_json(const mb::Tables& t) {
  json speeds = json::array();
  for (std::size_t s = 0; s < mb::kSpeedCount; ++s) {
    json segs = json::array();
    for (const mb::Segment& g : t.segments[s])
      segs.push_back({{"h", g.h}, {"m", g.m}, {"x1_s", g.x1_s}, {"x2_s", g.x2_s}, {"y1", g.y1}, {"y2", g.y2}});
    const mb::CubicRow& q = t.cubic[s];
    speeds.push_back({{"speed_cm_s", static_cast<double>(s)},
                      {"lifetime_s", t.lifetime_s[s]},
                      {"cubic", {q.d, q.c, q.b, q.a}},
                      {"linear_slope", t.linear_slope_per_s[s]},
                      {"segments", segs}});
  }
  return json{{"speeds", speeds},
              {"simple", {{"static_slope_per_s", t.simple_static_slope_per_s},
                          {"moving_slope_per_s", t.simple_moving_slope_per_s}}}};
}

namespace {

/// Speed `s`'s tables from `speeds[index]` (`e`) into `t`.
void read_speed(const json& e, std::size_t s, std::size_t index, const std::string& path, mb::Tables& t) {
  const std::string where = "speeds[" + std::to_string(index) + "]";
  const std::string at = "/speeds/" + std::to_string(index);
  if (!e.contains("cubic") || !e.at("cubic").is_array() || e.at("cubic").size() != 4)
    throw logs::json_file_error(path, at + "/cubic", where + ": expected 'cubic' as [d, c, b, a]");
  const json& c = e.at("cubic");
  for (std::size_t k = 0; k < c.size(); ++k)
    if (!c.at(k).is_number() || !std::isfinite(c.at(k).get<double>()))
      throw logs::json_file_error(path, at + "/cubic/" + std::to_string(k), where + ": 'cubic' must hold finite numbers");
  const double life = number_at(e, "lifetime_s", path, where, at, Sign::positive);
  t.cubic[s] = mb::CubicRow{c.at(0).get<double>(), c.at(1).get<double>(), c.at(2).get<double>(), c.at(3).get<double>(), life};
  t.lifetime_s[s] = life;
  t.linear_slope_per_s[s] = number_at(e, "linear_slope", path, where, at, Sign::negative);
  if (!e.contains("segments") || !e.at("segments").is_array() || e.at("segments").size() != mb::kSegmentCount)
    throw logs::json_file_error(path, at + "/segments", where + ": expected 4 'segments'");
  for (std::size_t k = 0; k < mb::kSegmentCount; ++k) {
    const json& g = e.at("segments").at(k);
    const std::string gw = where + ".segments[" + std::to_string(k) + "]";
    const std::string ga = at + "/segments/" + std::to_string(k);
    t.segments[s][k] = mb::Segment{number_at(g, "h", path, gw, ga), number_at(g, "m", path, gw, ga),
                                   number_at(g, "x1_s", path, gw, ga), number_at(g, "x2_s", path, gw, ga),
                                   number_at(g, "y1", path, gw, ga), number_at(g, "y2", path, gw, ga)};
    if (!(t.segments[s][k].x1_s <= t.segments[s][k].x2_s))
      throw logs::json_file_error(path, ga + "/x2_s", gw + ": x2_s must not be before x1_s (a segment runs forward in time)");
  }
}

void read_simple(const json& j, const std::string& path, mb::Tables& t) {
  t.simple_static_slope_per_s = number_at(j.at("simple"), "static_slope_per_s", path, "simple", "/simple", Sign::negative_or_zero);
  t.simple_moving_slope_per_s = number_at(j.at("simple"), "moving_slope_per_s", path, "simple", "/simple", Sign::negative_or_zero);
}

const json& speeds_of(const json& j, const std::string& path) {
  if (!j.is_object() || !j.contains("speeds") || !j.at("speeds").is_array())
    throw logs::json_file_error(path, j.is_object() && j.contains("speeds") ? "/speeds" : "",
                                "not a battery coefficient file: expected an object with a 'speeds' array");
  return j.at("speeds");
}

}  // namespace

mb::Tables battery_tables_from_json(const json& j, const std::string& path) {
  const json& speeds = speeds_of(j, path);
  if (speeds.size() != mb::kSpeedCount)
    throw logs::json_file_error(path, "/speeds",
                                "expected 16 entries in 'speeds' (0..15 cm/s), found " + std::to_string(speeds.size()));
  mb::Tables t{};
  for (std::size_t s = 0; s < speeds.size(); ++s) {
    const std::string at = "/speeds/" + std::to_string(s);
    const double v = number_at(speeds.at(s), "speed_cm_s", path, "speeds[" + std::to_string(s) + "]", at);
    if (std::abs(v - static_cast<double>(s)) > 1e-9)
      throw logs::json_file_error(path, at + "/speed_cm_s", "speeds[" + std::to_string(s) + "]: expected speed_cm_s " + std::to_string(s));
    read_speed(speeds.at(s), s, s, path, t);
  }
  if (!j.contains("simple")) throw logs::json_file_error(path, "", "expected a 'simple' object");
  read_simple(j, path, t);
  return t;
}

mb::Tables battery_tables_from_json(const json& j, const std::string& path, TableSources& sources) {
  const json& speeds = speeds_of(j, path);
  if (speeds.empty() || speeds.size() > mb::kSpeedCount)
    throw logs::json_file_error(path, "/speeds",
                                "expected 1 to 16 entries in 'speeds' (0..15 cm/s), found " + std::to_string(speeds.size()));
  mb::Tables t = mb::plugin_tables();
  sources = TableSources{};
  for (std::size_t i = 0; i < speeds.size(); ++i) {
    const std::string where = "speeds[" + std::to_string(i) + "]";
    const std::string at = "/speeds/" + std::to_string(i);
    const double v = number_at(speeds.at(i), "speed_cm_s", path, where, at);
    if (!(v >= 0 && v < static_cast<double>(mb::kSpeedCount)) || v != std::floor(v))
      throw logs::json_file_error(path, at + "/speed_cm_s",
                                  where + ": speed_cm_s must be a whole number of cm/s in 0..15 (found " + json(v).dump() + ")");
    const int s = static_cast<int>(v);
    for (int seen : sources.fitted_speeds)
      if (seen == s) throw logs::json_file_error(path, at + "/speed_cm_s", where + ": a second table for " + std::to_string(s) + " cm/s");
    sources.fitted_speeds.push_back(s);
    read_speed(speeds.at(i), static_cast<std::size_t>(s), i, path, t);
  }
  std::sort(sources.fitted_speeds.begin(), sources.fitted_speeds.end());
  if (j.contains("simple")) {
    read_simple(j, path, t);
    sources.fitted_simple = true;
  }
  return t;
}

}  // namespace epuck2::coefficients
