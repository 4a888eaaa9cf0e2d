// The reading noise of a channel: see epuck2/calibrate/reading_noise.hpp.
#include "epuck2/calibrate/reading_noise.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>

#include "epuck2/fit/replicates.hpp"

namespace epuck2::calibrate {

namespace {

/// Adds a group's squared deviations from its own mean to `ss`, and its n - 1 to `dof`.
void add_group(const std::vector<double>& v, double& ss, std::size_t& dof) {
  double mean = 0;
  for (double x : v) mean += x;
  mean /= static_cast<double>(v.size());
  for (double x : v) ss += (x - mean) * (x - mean);
  dof += v.size() - 1;
}

/// pooled_replicate_sd, with `used[i]` set for each reading the final sd is made of (after the
/// wild readings, the railed groups, the groups of one and the second pass's outliers are left out).
PooledSd screen_and_pool(const std::vector<double>& values, const std::vector<int>& group, const std::vector<bool>& on_rail,
                         double floor_sd, double reject_sd, std::vector<bool>& used) {
  PooledSd out;
  const std::vector<bool> wild = fit::flag_wild_replicates(values, group, on_rail, floor_sd);
  struct Group {
    std::vector<std::size_t> kept;  // indices into values
    bool railed = false;
  };
  std::map<int, Group> groups;
  for (std::size_t i = 0; i < values.size(); ++i) {
    if (group[i] < 0) continue;
    if (wild[i]) {
      ++out.wild;
      continue;
    }
    Group& g = groups[group[i]];
    g.kept.push_back(i);
    g.railed = g.railed || on_rail[i];
  }
  // Two passes: the pooled sd, then, in groups of fewer than kSmallGroup readings, without the
  // readings farther than reject_sd pooled sd from their group's median: among a few replicates a
  // wild reading moves the group's own spread too much for flag_wild_replicates to see it. Larger
  // groups keep every reading that rule kept (their tails are the noise: cutting them at 4 sd
  // would shrink a skewed noise's sd).
  auto pool = [&](double pooled_sd, PooledSd& into) {
    double ss = 0;
    std::size_t dof = 0;
    into.n = into.groups = into.railed_groups = into.outliers = 0;
    used.assign(values.size(), false);
    for (const auto& [id, g] : groups) {
      (void)id;
      if (g.railed) {
        ++into.railed_groups;
        continue;
      }
      std::vector<std::size_t> v;
      if (std::isfinite(pooled_sd)) {
        std::vector<double> kept;
        for (std::size_t i : g.kept) kept.push_back(values[i]);
        const double med = fit::median(kept);
        const double limit = g.kept.size() < kSmallGroup ? reject_sd * std::max(pooled_sd, floor_sd)
                                                          : std::numeric_limits<double>::infinity();
        for (std::size_t i : g.kept) {
          if (std::abs(values[i] - med) > limit)
            ++into.outliers;
          else
            v.push_back(i);
        }
      } else {
        v = g.kept;
      }
      if (v.size() < 2) continue;
      std::vector<double> x;
      for (std::size_t i : v) x.push_back(values[i]);
      add_group(x, ss, dof);
      into.n += v.size();
      ++into.groups;
      for (std::size_t i : v) used[i] = true;
    }
    into.sd = dof > 0 ? std::sqrt(ss / static_cast<double>(dof)) : std::numeric_limits<double>::quiet_NaN();
  };
  pool(std::numeric_limits<double>::quiet_NaN(), out);
  if (std::isfinite(out.sd) && reject_sd > 0) pool(out.sd, out);
  return out;
}

}  // namespace

PooledSd pooled_replicate_sd(const std::vector<double>& values, const std::vector<int>& group,
                             const std::vector<bool>& on_rail, double floor_sd, double reject_sd) {
  std::vector<bool> used;
  return screen_and_pool(values, group, on_rail, floor_sd, reject_sd, used);
}

ReadingNoise noise_from_replicates(const std::string& channel, const std::string& unit, double argos_scale,
                                   const std::vector<double>& values, const std::vector<int>& group,
                                   const std::vector<bool>& on_rail, const std::vector<int>& sensor, int sensors,
                                   double floor_sd) {
  ReadingNoise r;
  r.channel = channel;
  r.unit = unit;
  r.from = "replicates";
  r.argos_scale = argos_scale;
  // Screened once: the pooled sd and every sensor's are made of the same readings, so the
  // sensors' counts add up to the pooled one (a sensor's groups screened on their own would judge
  // a reading against that sensor's spread alone and keep or leave out other readings).
  std::vector<bool> used;
  const PooledSd all = screen_and_pool(values, group, on_rail, floor_sd, kNoiseRejectSd, used);
  r.sd = all.sd;
  r.n = all.n;
  r.groups = all.groups;
  // Each sensor's sd: within its own groups (a group and a sensor; the callers' groups hold one
  // sensor each), over the readings used above.
  std::map<std::pair<int, int>, std::vector<double>> own;
  for (std::size_t i = 0; i < values.size(); ++i)
    if (used[i]) own[{sensor[i], group[i]}].push_back(values[i]);
  for (int s = 0; s < sensors; ++s) {
    double ss = 0;
    std::size_t dof = 0, n = 0;
    for (const auto& [key, v] : own) {
      if (key.first != s || v.size() < 2) continue;
      add_group(v, ss, dof);
      n += v.size();
    }
    const bool mine = n > 0 && dof > 0;
    r.per_sensor_sd.push_back(mine ? std::sqrt(ss / static_cast<double>(dof)) : all.sd);
    r.per_sensor_n.push_back(mine ? n : 0);
  }
  return r;
}

ReadingNoise noise_from_residuals(const std::string& channel, const std::string& unit, double argos_scale,
                                  const RobustFit& fit, double to_unit, int sensors) {
  ReadingNoise r;
  r.channel = channel;
  r.unit = unit;
  r.from = "residuals";
  r.argos_scale = argos_scale;
  if (fit.usable) {
    r.sd = fit.noise_sd * to_unit;
    r.n = fit.observations;
  }
  r.per_sensor_sd.assign(static_cast<std::size_t>(sensors), r.sd);
  r.per_sensor_n.assign(static_cast<std::size_t>(sensors), 0);
  return r;
}

}  // namespace epuck2::calibrate
