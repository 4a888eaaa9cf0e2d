// The screening of logs before the diagnosis fits them: see screening.hpp.
#include "screening.hpp"

#include <algorithm>
#include <cmath>
#include <map>

#include "epuck2/fit/replicates.hpp"
#include "epuck2/logs/output.hpp"
#include "epuck2/models/kind_facts.hpp"

namespace epuck2::diagnose {

namespace {

const models::KindFacts& screening_facts(logs::Kind kind) { return *models::kind_facts(std::string(logs::to_string(kind))); }

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
// Sequences (drive and battery logs), not replicates: a reading is a spike when it stands far from the line
// through its two neighbours (d_i = y_i - (y_{i-1} + y_{i+1}) / 2) compared with how far the
// run's readings usually stand (1.4826 MAD of d), by at least the kind's screening floor. Only
// rows whose conditions (the commands) repeat the previous row's are dropped, so that no command
// is lost.
std::vector<std::vector<bool>> sequence_spikes(const std::vector<logs::Log>& all, const models::KindFacts& facts,
                                               std::vector<WildReading>* dropped) {
  const models::Channel& rails = facts.channels.front();
  const char* unit = rails.unit;
  std::vector<std::vector<bool>> out;
  for (const logs::Log& log : all) {
    const std::size_t n = log.rows();
    std::vector<bool> drop(n, false);
    for (const std::string reading : facts.screening.readings) {
      const bool complete = std::all_of(facts.conditions.begin(), facts.conditions.end(), [&](const char* c) { return log.has(c); });
      if (!log.has(reading) || !complete || n < 5) continue;
      const auto& y = log.col(reading);
      auto repeats = [&](std::size_t i) {
        for (const char* c : facts.conditions)
          if (log.col(c)[i] != log.col(c)[i - 1]) return false;
        return true;
      };
      auto inside = [&](double v) { return v > rails.low_rail && v < rails.high_rail; };
      std::vector<double> d(n, 0.0), dev;
      for (std::size_t i = 1; i + 1 < n; ++i)
        if (inside(y[i - 1]) && inside(y[i]) && inside(y[i + 1])) {
          d[i] = y[i] - 0.5 * (y[i - 1] + y[i + 1]);
          dev.push_back(std::abs(d[i]));
        }
      const double sd = 1.482602218505602 * fit::median(dev);
      const double limit = std::max(fit::kWildReadingSd * sd, facts.screening.floor);
      for (std::size_t i = 1; i + 1 < n; ++i) {
        // A spike pushes its neighbours' d the other way by half as much: judge the largest first.
        if (!(std::abs(d[i]) > limit) || !repeats(i)) continue;
        if (std::abs(d[i]) < std::abs(d[i - 1]) || std::abs(d[i]) < std::abs(d[i + 1])) continue;
        drop[i] = true;
        if (dropped != nullptr)
          dropped->push_back({log.path + ":" + std::to_string(log.line_of_row[i]),
                              reading + " " + logs::format_number(y[i], 6) + " where its neighbours read " +
                                  logs::format_number(y[i - 1], 6) + " and " + logs::format_number(y[i + 1], 6) +
                                  " (a spike of " + logs::format_number(d[i], 6) + " " + unit + "; the run's typical " +
                                  logs::format_number(sd, 6) + ")"});
      }
    }
    out.push_back(std::move(drop));
  }
  return out;
}
}  // namespace

static std::vector<std::vector<bool>> wild_rows(const std::vector<logs::Log>& all, std::vector<WildReading>* dropped) {
  std::vector<std::vector<bool>> drop(all.size());
  for (std::size_t l = 0; l < all.size(); ++l) drop[l].assign(all[l].rows(), false);
  if (all.empty()) return drop;
  const models::KindFacts& facts = screening_facts(all.front().kind);
  using How = models::Screening::How;
  if (facts.screening.how == How::spikes) return sequence_spikes(all, facts, dropped);
  if (facts.screening.how != How::replicates) return drop;
  // Readings on the first channel's rails are censored, not wild.
  const models::Channel& rails = facts.channels.front();
  for (const std::string reading : facts.screening.readings) {
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
        for (const char* c : facts.conditions) key.push_back(log.has(c) ? log.col(c)[i] : 0.0);
        group.push_back(ids.emplace(key, static_cast<int>(ids.size())).first->second);
        const double x = log.col(reading)[i];
        values.push_back(x);
        on_rail.push_back(x <= rails.low_rail || x >= rails.high_rail);
        at.emplace_back(l, i);
      }
    }
    std::vector<std::string> why;
    const std::vector<bool> wild = fit::flag_wild_replicates(values, group, on_rail, facts.screening.floor, &why);
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

bool tof_code_in_view(double mm, double encoder_range_mm) {
  const double ceiling = screening_facts(logs::Kind::drive).channels.front().high_rail;
  return logs::is_tof_out_of_range(mm) && encoder_range_mm < (1.0 - kTofInViewMargin) * ceiling;
}

std::size_t readings_on_rails(const std::vector<logs::Log>& all) {
  std::size_t n = 0;
  for (const logs::Log& log : all) {
    const models::KindFacts& facts = screening_facts(log.kind);
    const models::Channel& rails = facts.channels.front();
    for (const std::string column : facts.screening.readings) {
      if (!rails.has_rails() || !log.has(column)) continue;
      for (double v : log.col(column)) n += (v <= rails.low_rail || v >= rails.high_rail) ? 1 : 0;
    }
  }
  return n;
}

}  // namespace epuck2::diagnose
