// Wild readings in static logs: see epuck2/calibrate/screening.hpp.
#include "epuck2/calibrate/screening.hpp"
#include "epuck2/models/kind_facts.hpp"

#include <algorithm>
#include <cmath>
#include <map>

#include "epuck2/fit/replicates.hpp"
#include "epuck2/logs/output.hpp"
#include "epuck2/models/tof.hpp"

namespace epuck2::calibrate {

using namespace epuck2::fit;  // the engine (lib/fit)

namespace {

struct Rule {
  std::vector<std::string> conditions;  ///< columns that define "the same conditions"
  std::vector<std::string> readings;    ///< columns screened
  double low = -1e300, high = 1e300;    ///< rails (readings on them are censored, not wild)
  double floor = 2.0;                   ///< smallest robust sd (a few counts of quantisation)
};

/// The kind's first channel (lib/models kind_facts.hpp): its rails.
const models::Channel& channel_of(logs::Kind kind, std::size_t k = 0) {
  return models::kind_facts(std::string(logs::to_string(kind)))->channels.at(k);
}

bool rule_for(logs::Kind kind, Rule* r) {
  const auto rails = [&](Rule rule) {
    const models::Channel& c = channel_of(kind);
    if (std::isfinite(c.low_rail)) rule.low = c.low_rail;
    if (std::isfinite(c.high_rail)) rule.high = c.high_rail;
    return rule;
  };
  switch (kind) {
    case logs::Kind::proximity: *r = rails({{"distance_m", "sensor", "angle_deg"}, {"value"}, -1e300, 1e300, 2.0}); return true;
    case logs::Kind::light: *r = rails({{"distance_m", "intensity", "sensor"}, {"value"}, -1e300, 1e300, 2.0}); return true;
    case logs::Kind::ground: *r = rails({{"grey", "sensor"}, {"value"}, -1e300, 1e300, 2.0}); return true;
    case logs::Kind::camera: *r = rails({{"forward_m", "lateral_m", "vertical_m"}, {"px", "py"}, -1e300, 1e300, 1.0}); return true;
    default: return false;
  }
}

}  // namespace

void remove_rows(logs::Log& log, const std::vector<bool>& drop) {
  const std::size_t n = log.rows(), m = log.columns.size();
  if (std::find(drop.begin(), drop.end(), true) == drop.end()) return;
  for (auto& [name, col] : log.numeric) {
    std::size_t k = 0;
    for (std::size_t i = 0; i < n; ++i)
      if (!drop[i]) col[k++] = col[i];
    col.resize(k);
  }
  for (auto& [name, col] : log.text) {
    std::size_t k = 0;
    for (std::size_t i = 0; i < n; ++i)
      if (!drop[i]) col[k++] = col[i];
    col.resize(k);
  }
  std::size_t k = 0, c = 0;
  for (std::size_t i = 0; i < n; ++i) {
    if (drop[i]) continue;
    log.line_of_row[k++] = log.line_of_row[i];
    for (std::size_t j = 0; j < m && i * m + j < log.cell_start.size(); ++j) log.cell_start[c++] = log.cell_start[i * m + j];
  }
  log.line_of_row.resize(k);
  log.cell_start.resize(std::min(c, log.cell_start.size()));
}

logs::Log without_rows(const logs::Log& log, const std::vector<bool>& drop) {
  logs::Log out = log;
  remove_rows(out, drop);
  return out;
}

namespace {
// Drive logs are sequences, not replicates: a ToF reading is a spike when it stands far from the
// line through its two neighbours (d_i = tof_i - (tof_{i-1} + tof_{i+1}) / 2) compared with how
// far the run's readings usually stand (1.4826 MAD of d), by at least kSpikeFloor_mm. Only rows
// whose command repeats the previous row's are dropped, so that no command is lost.
constexpr double kSpikeFloor_mm = 50.0;

std::vector<std::vector<bool>> tof_spikes(const std::vector<logs::Log>& all, std::vector<WildReading>* dropped) {
  std::vector<std::vector<bool>> out;
  for (const logs::Log& log : all) {
    const std::size_t n = log.rows();
    std::vector<bool> drop(n, false);
    if (log.has("tof_mm") && log.has("left_speed_cm_s") && log.has("right_speed_cm_s") && n >= 5) {
      const auto& tof = log.col("tof_mm");
      const auto& cl = log.col("left_speed_cm_s");
      const auto& cr = log.col("right_speed_cm_s");
      const models::Channel& tof_rails = channel_of(logs::Kind::drive);
      auto inside = [&](double v) { return v > tof_rails.low_rail && v < tof_rails.high_rail; };
      std::vector<double> d(n, 0.0), dev;
      for (std::size_t i = 1; i + 1 < n; ++i)
        if (inside(tof[i - 1]) && inside(tof[i]) && inside(tof[i + 1])) {
          d[i] = tof[i] - 0.5 * (tof[i - 1] + tof[i + 1]);
          dev.push_back(std::abs(d[i]));
        }
      const double sd = 1.482602218505602 * fit::median(dev);
      const double limit = std::max(kWildReadingSd * sd, kSpikeFloor_mm);
      for (std::size_t i = 1; i + 1 < n; ++i) {
        // A spike pushes its neighbours' d the other way by half as much: judge the largest first.
        if (!(std::abs(d[i]) > limit) || cl[i] != cl[i - 1] || cr[i] != cr[i - 1]) continue;
        if (std::abs(d[i]) < std::abs(d[i - 1]) || std::abs(d[i]) < std::abs(d[i + 1])) continue;
        drop[i] = true;
        if (dropped != nullptr)
          dropped->push_back({log.path + ":" + std::to_string(log.line_of_row[i]),
                              "tof_mm " + logs::format_number(tof[i], 6) + " where its neighbours read " +
                                  logs::format_number(tof[i - 1], 6) + " and " + logs::format_number(tof[i + 1], 6) +
                                  " (a spike of " + logs::format_number(d[i], 6) + " mm; the run's typical " +
                                  logs::format_number(sd, 6) + ")"});
      }
    }
    out.push_back(std::move(drop));
  }
  return out;
}
}  // namespace

std::vector<std::vector<bool>> wild_rows(const std::vector<logs::Log>& all, std::vector<WildReading>* dropped) {
  std::vector<std::vector<bool>> drop(all.size());
  for (std::size_t l = 0; l < all.size(); ++l) drop[l].assign(all[l].rows(), false);
  if (all.empty()) return drop;
  if (all.front().kind == logs::Kind::drive) return tof_spikes(all, dropped);
  Rule rule;
  if (!rule_for(all.front().kind, &rule)) return drop;
  for (const std::string& reading : rule.readings) {
    // One group per combination of the conditions' values, over all logs.
    std::map<std::vector<double>, int> ids;
    std::vector<double> values;
    std::vector<int> group;
    std::vector<bool> on_rail;
    std::vector<std::pair<std::size_t, std::size_t>> at;
    for (std::size_t l = 0; l < all.size(); ++l) {
      const logs::Log& log = all[l];
      if (!log.has(reading)) continue;
      for (std::size_t i = 0; i < log.rows(); ++i) {
        std::vector<double> key;
        for (const std::string& c : rule.conditions) key.push_back(log.has(c) ? log.col(c)[i] : 0.0);
        group.push_back(ids.emplace(key, static_cast<int>(ids.size())).first->second);
        const double x = log.col(reading)[i];
        values.push_back(x);
        on_rail.push_back(x <= rule.low || x >= rule.high);
        at.emplace_back(l, i);
      }
    }
    std::vector<std::string> why;
    const std::vector<bool> wild = flag_wild_replicates(values, group, on_rail, rule.floor, &why);
    for (std::size_t k = 0; k < values.size(); ++k) {
      if (!wild[k] || drop[at[k].first][at[k].second]) continue;
      drop[at[k].first][at[k].second] = true;
      if (dropped != nullptr)
        dropped->push_back({all[at[k].first].path + ":" + std::to_string(all[at[k].first].line_of_row[at[k].second]),
                            reading + " " + why[k]});
    }
  }
  return drop;
}

std::vector<logs::Log> drop_wild_readings(const std::vector<logs::Log>& all, std::vector<WildReading>* dropped) {
  const std::vector<std::vector<bool>> drop = wild_rows(all, dropped);
  std::vector<logs::Log> out;
  for (std::size_t l = 0; l < all.size(); ++l) out.push_back(without_rows(all[l], drop[l]));
  return out;
}

void drop_wild_readings_in_place(std::vector<logs::Log>& all, std::vector<WildReading>* dropped) {
  const std::vector<std::vector<bool>> drop = wild_rows(all, dropped);
  for (std::size_t l = 0; l < all.size(); ++l) remove_rows(all[l], drop[l]);
}

TofReading read_tof(double mm) {
  namespace s = models::sensors;
  TofReading r{{mm, Censoring::none, "", -1}, logs::is_tof_out_of_range(mm)};
  if (mm <= s::kPluginTof.min_mm) r.observation = {s::kPluginTof.min_mm, Censoring::at_or_below, "", -1};
  else if (mm >= s::kPluginTof.max_mm) r.observation = {s::kPluginTof.max_mm, Censoring::at_or_above, "", -1};
  return r;
}

bool tof_code_in_view(double mm, double encoder_range_mm) {
  const double ceiling = models::sensors::kPluginTof.max_mm;
  return logs::is_tof_out_of_range(mm) && encoder_range_mm < (1.0 - kTofInViewMargin) * ceiling;
}

std::size_t readings_on_rails(const std::vector<logs::Log>& all) {
  std::size_t n = 0;
  for (const logs::Log& log : all) {
    auto count = [&](const std::string& column, double low, double high) {
      if (!log.has(column)) return;
      for (double v : log.col(column)) n += (v <= low || v >= high) ? 1 : 0;
    };
    switch (log.kind) {
      case logs::Kind::proximity:
      case logs::Kind::light:
      case logs::Kind::ground: count("value", channel_of(log.kind).low_rail, channel_of(log.kind).high_rail); break;
      case logs::Kind::drive: count("tof_mm", channel_of(log.kind).low_rail, channel_of(log.kind).high_rail); break;
      default: break;
    }
  }
  return n;
}

}  // namespace epuck2::calibrate
