#include "replay_log.hpp"

#include <algorithm>
#include <cstdio>
#include <stdexcept>

#include <epuck2/logs/log.hpp>
#include <epuck2/models/kind_facts.hpp>

namespace epuck2::argos_replay {

namespace {

namespace el = epuck2::logs;

/// Per kind: the columns ARGoS sets up from (conditions), the ones it writes (readings) and the
/// measured ones its model does not simulate (dropped): the kind's facts (lib/models
/// kind_facts.hpp), which `simulate --like` reads too.
struct KindColumns {
  std::vector<std::string> conditions, readings, dropped;
};

KindColumns columns_of(el::Kind kind) {
  const epuck2::models::KindFacts& f = *epuck2::models::kind_facts(std::string(el::to_string(kind)));
  return {{f.conditions.begin(), f.conditions.end()}, {f.readings.begin(), f.readings.end()}, {f.not_simulated.begin(), f.not_simulated.end()}};
}

bool contains(const std::vector<std::string>& v, const std::string& s) { return std::find(v.begin(), v.end(), s) != v.end(); }

}  // namespace

std::string replay_number(double v, int digits) {
  char buf[64];
  std::snprintf(buf, sizeof buf, "%.*g", digits, v);
  return buf;
}

ReplayLog read_replay_log(const std::string& path, const std::string& kind_name) {
  const auto kind = el::parse_kind(kind_name);
  if (!kind) throw std::invalid_argument("argos replay: unknown kind '" + kind_name + "'");
  ReplayLog r;
  const KindColumns k = columns_of(*kind);
  el::Log log = el::read_log(path, *kind);
  r.path = log.path;
  r.metadata = log.metadata;
  r.numeric = std::move(log.numeric);
  r.text = std::move(log.text);
  r.line_of_row = std::move(log.line_of_row);
  if (*kind == el::Kind::drive) r.obstacle_distance_m = log.metadata_number("obstacle_distance_m");
  for (const std::string& c : log.columns) {
    const bool text_robot = c == "robot" && r.text.count(c);
    if (contains(k.conditions, c) || contains(k.readings, c) || c == "time_s" || text_robot) {
      r.columns.push_back(c);
      continue;
    }
    if (contains(k.dropped, c)) continue;
    throw el::InputError(path, log.header_line, 0,
                         "column '" + c + "': ARGoS has no way to set it, so it cannot replay these rows as the robot "
                         "ran them (replay a copy of the log without the column)");
  }
  for (const std::string& c : k.readings)
    if (contains(r.columns, c)) r.readings.push_back(c);
  if (r.readings.empty())  // a voltage-only battery log: ARGoS writes its charge
    for (const std::string& c : k.readings) {
      r.columns.push_back(c);
      r.readings.push_back(c);
    }
  return r;
}

std::string replay_head(const ReplayLog& r, const std::string& robot, const std::string& protocol) {
  std::string out = "# robot: " + robot + "\n";
  for (const auto& [key, value] : r.metadata)
    if (key != "robot" && key != "protocol" && key != "replayed_from") out += "# " + key + ": " + value + "\n";
  out += "# replayed_from: " + r.path + "\n# protocol: " + protocol + "\n";
  for (std::size_t i = 0; i < r.columns.size(); ++i) out += (i ? "," : "") + r.columns[i];
  return out + "\n";
}

std::string replay_row(const ReplayLog& r, std::size_t row, const std::map<std::string, std::string>& readings) {
  std::string out;
  for (std::size_t i = 0; i < r.columns.size(); ++i) {
    const std::string& c = r.columns[i];
    if (i) out += ',';
    if (contains(r.readings, c)) {
      const auto it = readings.find(c);
      if (it == readings.end()) throw std::logic_error("argos replay: no reading for column '" + c + "'");
      out += it->second;
    } else if (r.numeric.count(c)) {
      out += replay_number(r.numeric.at(c)[row]);
    } else {
      out += r.text.at(c)[row];
    }
  }
  return out + "\n";
}

}  // namespace epuck2::argos_replay
