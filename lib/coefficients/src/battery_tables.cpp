// The battery tables of a coefficient file: see epuck2/coefficients/battery_tables.hpp.
#include "epuck2/coefficients/battery_tables.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>
#include <tuple>
#include <vector>

#include "epuck2/logs/json_location.hpp"
#include "epuck2/logs/log.hpp"
#include "epuck2/models/kind_facts.hpp"
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

// The physical ranges of the tables (docs/coefficient-files.md, "Battery tables"). Source: the
// plug-in's published tables (models/plugin_battery_tables.hpp; paper Fig. 10 and Table 5) and the
// shipped fit (data/fitted/battery.json):
// - the longest published lifetime is 19743 s (table Q at 0 cm/s); a lifetime up to 1e6 s
//   (11.6 days, about 50 times that) is accepted, a longer one is not an E-Puck2 battery;
// - the steepest published slope is M4's final drop, -0.259 /s (15 cm/s; the shipped fit's is
//   -0.299 /s): every slope (linear, simple, a segment's m, the cubic's at 0) lies in [-1, 0] /s,
//   a charge falls, and by at most a full charge a second;
// - a charge is normalised, 1 = full: a segment's band [y2, y1] lies in [0, 1], the cubic's value
//   at 0 (d) in [0, 1.05] (the charge channel's high rail, models/kind_facts.hpp), and the cubic
//   stays within the charge channel's rails [-1, 1.05] over [0, lifetime_s].
constexpr double kMaxLifetime_s = 1e6;
constexpr double kSteepestSlope_per_s = -1.0;
constexpr double kCubicMaxAtZero = 1.05;
constexpr double kCubicLow = -1.0, kCubicHigh = 1.05;
// A segment's line h + m t passes through (x1_s, y1) and (x2_s, y2) to this much charge (the
// published tables' rounding leaves 1e-7 at most).
constexpr double kSegmentLineTolerance = 1e-6;

void fail_at(const std::string& path, const std::string& pointer, const std::string& what) {
  throw logs::json_file_error(path, pointer, what);
}

/// Refuses a key of the object `o` at `pointer` that is not in `known`.
void known_keys(const json& o, const std::vector<std::string>& known, const std::string& path, const std::string& pointer,
                const std::string& where) {
  if (!o.is_object()) fail_at(path, pointer, where + " must be an object");
  for (auto it = o.begin(); it != o.end(); ++it) {
    if (std::find(known.begin(), known.end(), it.key()) != known.end()) continue;
    // "did you mean" as the model reader's: within 2 edits, or a third of the key's length.
    std::string best;
    std::size_t best_d = std::max<std::size_t>(2, it.key().size() / 3) + 1;
    for (const std::string& k : known)
      if (const std::size_t d = logs::edit_distance(it.key(), k); d < best_d) {
        best_d = d;
        best = k;
      }
    std::string list;
    for (const std::string& k : known) list += (list.empty() ? "" : ", ") + k;
    fail_at(path, pointer + "/" + it.key(), "unknown key '" + it.key() + "' in " + where + " (it holds " + list + ")" +
                                                 (best.empty() ? "" : "; did you mean '" + best + "'?"));
  }
}

// What a speed's entry holds (lib/calibrate battery_json.cpp): the tables read, and the fit's
// statistics, standard errors and texts beside them.
const std::vector<std::string> kSpeedKeys{"speed_cm_s", "lifetime_s", "cubic", "linear_slope", "segments", "noise_sd", "runs",
                                          "observations", "lifetime_std_error_s", "lifetime_h", "lifetime", "cubic_std_errors",
                                          "cubic_std_errors_corrected", "cubic_rounded", "cubic_std_error_why",
                                          "cubic_std_errors_corrected_why", "linear_slope_std_error", "linear_slope_rounded",
                                          "free_line", "breakpoints", "mse", "fit", "outliers"};
const std::vector<std::string> kSegmentKeys{"h", "m", "x1_s", "x2_s", "y1", "y2"};
const std::vector<std::string> kSimpleKeys{"static_slope_per_s", "moving_slope_per_s", "static_std_error", "moving_std_error",
                                           "static_rounded", "moving_rounded"};

/// `v` (at `pointer`, named `what`) within [lo, hi].
void within(double v, double lo, double hi, const std::string& path, const std::string& pointer, const std::string& what,
            const std::string& unit) {
  if (!(v >= lo && v <= hi))
    fail_at(path, pointer, what + " = " + json(v).dump() + " is outside its physical range [" + json(lo).dump() + ", " + json(hi).dump() +
                               "]" + (unit.empty() ? "" : " " + unit));
}

}  // namespace

json battery_tables_to_json(const mb::Tables& t) {
  json speeds = json::array();
  for (std::size_t s = 0; s < mb::kSpeedCount; ++s) {
    mb::CubicRow q = t.cubic[s];
    q.end_s = t.lifetime_s[s];  // a row's end is its speed's lifetime in every table the project makes or ships
    speeds.push_back(battery_speed_to_json(static_cast<double>(s), q, t.linear_slope_per_s[s], t.segments[s],
                                           std::numeric_limits<double>::quiet_NaN(), true, s));
  }
  json j{{"speeds", speeds}, {"simple", battery_simple_to_json(t.simple_static_slope_per_s, t.simple_moving_slope_per_s)}};
  // What is written reads back: the reader's checks refuse at write (std::domain_error).
  try {
    battery_tables_from_json(j, "(the tables being written)");
  } catch (const logs::InputError& e) {
    throw std::domain_error(std::string("cannot write these battery tables, a reader would refuse them: ") + e.what());
  }
  return j;
}

namespace {

/// Speed `s`'s tables from `speeds[index]` (`e`) into `t`.
void read_speed(const json& e, std::size_t s, std::size_t index, const std::string& path, mb::Tables& t) {
  const std::string where = "speeds[" + std::to_string(index) + "]";
  const std::string at = "/speeds/" + std::to_string(index);
  known_keys(e, kSpeedKeys, path, at, where);
  if (!e.contains("cubic") || !e.at("cubic").is_array() || e.at("cubic").size() != 4)
    throw logs::json_file_error(path, at + "/cubic", where + ": expected 'cubic' as [d, c, b, a]");
  const json& c = e.at("cubic");
  for (std::size_t k = 0; k < c.size(); ++k)
    if (!c.at(k).is_number() || !std::isfinite(c.at(k).get<double>()))
      throw logs::json_file_error(path, at + "/cubic/" + std::to_string(k), where + ": 'cubic' must hold finite numbers");
  const double life = number_at(e, "lifetime_s", path, where, at, Sign::positive);
  within(life, 0, kMaxLifetime_s, path, at + "/lifetime_s", where + ".lifetime_s", "s");
  t.cubic[s] = mb::CubicRow{c.at(0).get<double>(), c.at(1).get<double>(), c.at(2).get<double>(), c.at(3).get<double>(), life};
  within(t.cubic[s].d, 0, kCubicMaxAtZero, path, at + "/cubic/0", where + ".cubic[0] (d, the charge at 0 s)", "charge");
  within(t.cubic[s].c, kSteepestSlope_per_s, -kSteepestSlope_per_s, path, at + "/cubic/1", where + ".cubic[1] (c, the slope at 0 s)",
         "1/s");
  for (int i = 0; i <= 64; ++i) {
    const double ts = life * i / 64.0;
    const double p[4] = {t.cubic[s].d, t.cubic[s].c, t.cubic[s].b, t.cubic[s].a};
    const double q = mb::cubic_charge(p, ts);
    if (!(q >= kCubicLow && q <= kCubicHigh))
      fail_at(path, at + "/cubic", where + ".cubic: the charge it gives at " + json(ts).dump() + " s, " + json(q).dump() +
                                       ", is outside the charge's range [-1, 1.05] (over 0 to lifetime_s)");
  }
  t.lifetime_s[s] = life;
  t.linear_slope_per_s[s] = number_at(e, "linear_slope", path, where, at, Sign::negative);
  within(t.linear_slope_per_s[s], kSteepestSlope_per_s, -1.0 / kMaxLifetime_s, path, at + "/linear_slope", where + ".linear_slope", "1/s");
  if (!e.contains("segments") || !e.at("segments").is_array() || e.at("segments").size() != mb::kSegmentCount)
    throw logs::json_file_error(path, at + "/segments", where + ": expected 4 'segments'");
  for (std::size_t k = 0; k < mb::kSegmentCount; ++k) {
    const json& g = e.at("segments").at(k);
    const std::string gw = where + ".segments[" + std::to_string(k) + "]";
    const std::string ga = at + "/segments/" + std::to_string(k);
    known_keys(g, kSegmentKeys, path, ga, gw);
    const mb::Segment seg{number_at(g, "h", path, gw, ga),    number_at(g, "m", path, gw, ga),
                          number_at(g, "x1_s", path, gw, ga), number_at(g, "x2_s", path, gw, ga),
                          number_at(g, "y1", path, gw, ga),   number_at(g, "y2", path, gw, ga)};
    t.segments[s][k] = seg;
    if (!(seg.x1_s <= seg.x2_s))
      throw logs::json_file_error(path, ga + "/x2_s", gw + ": x2_s must not be before x1_s (a segment runs forward in time)");
    within(seg.x1_s, 0, kMaxLifetime_s, path, ga + "/x1_s", gw + ".x1_s", "s");
    within(seg.x2_s, 0, kMaxLifetime_s, path, ga + "/x2_s", gw + ".x2_s", "s");
    within(seg.y1, 0, 1, path, ga + "/y1", gw + ".y1", "charge");
    within(seg.y2, 0, 1, path, ga + "/y2", gw + ".y2", "charge");
    within(seg.m, kSteepestSlope_per_s, 0, path, ga + "/m", gw + ".m (the slope; a charge does not rise)", "1/s");
    if (!(seg.y2 <= seg.y1))
      fail_at(path, ga + "/y2", gw + ": y2 = " + json(seg.y2).dump() + " is above y1 = " + json(seg.y1).dump() +
                                    " (the charge at x2_s, after x1_s): a charge does not rise");
    // The line h + m t through the segment's ends (the approximated model steps along it).
    for (const auto& [x, y, key] : {std::tuple<double, double, const char*>{seg.x1_s, seg.y1, "y1"}, {seg.x2_s, seg.y2, "y2"}})
      if (!(std::abs(seg.h + seg.m * x - y) <= kSegmentLineTolerance))
        fail_at(path, ga + "/h", gw + ": its line h + m t gives " + json(seg.h + seg.m * x).dump() + " at " + json(x).dump() + " s, not " +
                                     key + " = " + json(y).dump() + " (h is the line's charge at 0 s)");
  }
}

void read_simple(const json& j, const std::string& path, mb::Tables& t) {
  known_keys(j.at("simple"), kSimpleKeys, path, "/simple", "simple");
  t.simple_static_slope_per_s = number_at(j.at("simple"), "static_slope_per_s", path, "simple", "/simple", Sign::negative_or_zero);
  t.simple_moving_slope_per_s = number_at(j.at("simple"), "moving_slope_per_s", path, "simple", "/simple", Sign::negative_or_zero);
  within(t.simple_static_slope_per_s, kSteepestSlope_per_s, 0, path, "/simple/static_slope_per_s", "simple.static_slope_per_s", "1/s");
  within(t.simple_moving_slope_per_s, kSteepestSlope_per_s, 0, path, "/simple/moving_slope_per_s", "simple.moving_slope_per_s", "1/s");
}

const json& speeds_of(const json& j, const std::string& path) {
  if (!j.is_object() || !j.contains("speeds") || !j.at("speeds").is_array())
    throw logs::json_file_error(path, j.is_object() && j.contains("speeds") ? "/speeds" : "",
                                "not a battery coefficient file: expected an object with a 'speeds' array");
  return j.at("speeds");
}

}  // namespace

json battery_speed_to_json(double speed_cm_s, const mb::CubicRow& cubic, double linear_slope_per_s,
                           const std::array<mb::Segment, mb::kSegmentCount>& segments, double noise_sd, bool readable,
                           std::size_t index) {
  json segs = json::array();
  for (const mb::Segment& g : segments)
    segs.push_back({{"h", g.h}, {"m", g.m}, {"x1_s", g.x1_s}, {"x2_s", g.x2_s}, {"y1", g.y1}, {"y2", g.y2}});
  json e{{"speed_cm_s", speed_cm_s},
         {"lifetime_s", cubic.end_s},
         {"cubic", {cubic.d, cubic.c, cubic.b, cubic.a}},
         {"linear_slope", linear_slope_per_s},
         {"segments", segs}};
  const std::string where = "the battery table at " + json(speed_cm_s).dump() + " cm/s";
  if (!std::isfinite(speed_cm_s) || speed_cm_s < 0) throw std::domain_error("cannot write " + where + ": its speed is not a speed");
  if (!readable) {
    for (const double v : {cubic.end_s, cubic.d, cubic.c, cubic.b, cubic.a, linear_slope_per_s})
      if (!std::isfinite(v)) throw std::domain_error("cannot write " + where + ": a value is not finite");
    for (const mb::Segment& g : segments)
      for (const double v : {g.h, g.m, g.x1_s, g.x2_s, g.y1, g.y2})
        if (!std::isfinite(v)) throw std::domain_error("cannot write " + where + ": a segment's value is not finite");
    if (std::isfinite(noise_sd)) e["noise_sd"] = noise_sd;
    return e;
  }
  if (std::isfinite(noise_sd)) {
    // The charge channel's noise, as battery_model_from_json checks a speed's noise_sd.
    const double full_scale = models::kind_facts("battery")->channels.front().full_scale;
    if (!(noise_sd >= 0 && noise_sd < full_scale))
      throw std::domain_error("cannot write " + where + ": its noise_sd " + json(noise_sd).dump() + " is not a reading's noise sd, in [0, " +
                              json(full_scale).dump() + ") charge");
    e["noise_sd"] = noise_sd;
  } else if (!std::isnan(noise_sd)) {
    throw std::domain_error("cannot write " + where + ": its noise_sd is not finite");
  }
  try {
    mb::Tables scratch{};
    read_speed(e, 0, index, "(the battery table being written)", scratch);
  } catch (const logs::InputError& x) {
    throw std::domain_error("cannot write " + where + ", a reader would refuse it: " + x.what());
  }
  return e;
}

json battery_simple_to_json(double static_slope_per_s, double moving_slope_per_s, bool readable) {
  const json j{{"simple", {{"static_slope_per_s", static_slope_per_s}, {"moving_slope_per_s", moving_slope_per_s}}}};
  if (!readable) {
    if (!std::isfinite(static_slope_per_s) || !std::isfinite(moving_slope_per_s))
      throw std::domain_error("cannot write the Simple model's slopes: a slope is not finite");
    return j.at("simple");
  }
  try {
    mb::Tables scratch{};
    read_simple(j, "(the Simple model being written)", scratch);
  } catch (const logs::InputError& x) {
    throw std::domain_error(std::string("cannot write the Simple model's slopes, a reader would refuse them: ") + x.what());
  }
  return j.at("simple");
}

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
