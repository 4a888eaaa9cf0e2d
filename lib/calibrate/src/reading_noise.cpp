// The reading noise of a channel: see epuck2/calibrate/reading_noise.hpp.
#include "epuck2/calibrate/reading_noise.hpp"

#include <algorithm>
#include <map>

#include "epuck2/fit/replicates.hpp"

namespace epuck2::calibrate {

PooledSd pooled_replicate_sd(const std::vector<double>& values, const std::vector<int>& group,
                             const std::vector<bool>& on_rail, double floor_sd, double reject_sd) {
  PooledSd out;
  const std::vector<bool> wild = fit::flag_wild_replicates(values, group, on_rail, floor_sd);
  struct Group {
    std::vector<double> kept;
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
    g.kept.push_back(values[i]);
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
    for (const auto& [id, g] : groups) {
      (void)id;
      if (g.railed) {
        ++into.railed_groups;
        continue;
      }
      std::vector<double> v;
      if (std::isfinite(pooled_sd)) {
        const double med = fit::median(g.kept);
        const double limit = g.kept.size() < kSmallGroup ? reject_sd * std::max(pooled_sd, floor_sd)
                                                          : std::numeric_limits<double>::infinity();
        for (double x : g.kept) {
          if (std::abs(x - med) > limit)
            ++into.outliers;
          else
            v.push_back(x);
        }
      } else {
        v = g.kept;
      }
      if (v.size() < 2) continue;
      double mean = 0;
      for (double x : v) mean += x;
      mean /= static_cast<double>(v.size());
      for (double x : v) ss += (x - mean) * (x - mean);
      dof += v.size() - 1;
      into.n += v.size();
      ++into.groups;
    }
    into.sd = dof > 0 ? std::sqrt(ss / static_cast<double>(dof)) : std::numeric_limits<double>::quiet_NaN();
  };
  pool(std::numeric_limits<double>::quiet_NaN(), out);
  if (std::isfinite(out.sd) && reject_sd > 0) pool(out.sd, out);
  return out;
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
  const PooledSd all = pooled_replicate_sd(values, group, on_rail, floor_sd, kNoiseRejectSd);
  r.sd = all.sd;
  r.n = all.n;
  r.groups = all.groups;
  for (int s = 0; s < sensors; ++s) {
    // The sensor's own groups only: the others' readings take no part.
    std::vector<int> mine(group);
    for (std::size_t i = 0; i < mine.size(); ++i)
      if (sensor[i] != s) mine[i] = -1;
    const PooledSd one = pooled_replicate_sd(values, mine, on_rail, floor_sd, kNoiseRejectSd);
    const bool own = one.n > 0 && std::isfinite(one.sd);
    r.per_sensor_sd.push_back(own ? one.sd : all.sd);
    r.per_sensor_n.push_back(own ? one.n : 0);
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
