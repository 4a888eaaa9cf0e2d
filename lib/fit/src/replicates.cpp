// Wild values among replicates: see epuck2/fit/replicates.hpp.
#include "epuck2/fit/replicates.hpp"

#include <algorithm>
#include <cmath>
#include <map>
#include <sstream>
#include "epuck2/logs/output.hpp"

namespace epuck2::fit {

double median(std::vector<double> v) {
  if (v.empty()) return 0;
  // The middle element in linear time; for an even count the largest of those below it is the
  // other middle one.
  const std::size_t mid = v.size() / 2;
  std::nth_element(v.begin(), v.begin() + static_cast<std::ptrdiff_t>(mid), v.end());
  double m = v[mid];
  if (v.size() % 2 == 0) m = 0.5 * (m + *std::max_element(v.begin(), v.begin() + static_cast<std::ptrdiff_t>(mid)));
  return m;
}

std::vector<bool> flag_wild_replicates(const std::vector<double>& values, const std::vector<int>& group,
                                       const std::vector<bool>& on_rail, double floor_sd, std::vector<std::string>* why) {
  const std::size_t n = values.size();
  std::vector<bool> wild(n, false);
  if (why != nullptr) why->assign(n, "");
  std::map<int, std::vector<std::size_t>> groups;
  for (std::size_t i = 0; i < n; ++i)
    if (group[i] >= 0) groups[group[i]].push_back(i);
  std::map<int, double> sd_of;
  // The typical spread, from the groups of at least kTypicalReplicates readings inside the rails:
  // a smaller group's MAD is far below its sd (of 3 readings, one deviation from the median is 0
  // and the MAD is the smaller of the other two), so a typical made of such groups would call
  // ordinary readings wild. With no group that large, every group of kMinReplicates counts.
  std::vector<double> sds, sds_large;
  for (const auto& [g, members] : groups) {
    std::vector<double> v;
    for (std::size_t i : members)
      if (!on_rail[i]) v.push_back(values[i]);
    if (v.size() < kMinReplicates) continue;
    const double med = median(v);
    for (double& x : v) x = std::abs(x - med);
    sd_of[g] = 1.482602218505602 * median(v);
    sds.push_back(sd_of[g]);
    if (v.size() >= kTypicalReplicates) sds_large.push_back(sd_of[g]);
  }
  const double typical = median(sds_large.empty() ? sds : sds_large);
  for (const auto& [g, members] : groups) {
    if (members.size() < kMinReplicates) continue;  // too few readings to call one of them wild
    std::vector<double> v;
    std::size_t railed = 0;
    for (std::size_t i : members) {
      v.push_back(values[i]);
      railed += on_rail[i] ? 1 : 0;
    }
    const double med = median(v);
    const double sd = std::max({sd_of.count(g) ? sd_of.at(g) : typical, 0.5 * typical, floor_sd});
    for (std::size_t i : members) {
      const double dev = std::abs(values[i] - med);
      // A railed reading is censored: the sensor read the rail or beyond, so its distance from the
      // median is the least its reading's could be. It is wild when even that least distance is
      // beyond the threshold of any reading (and it is its group's one railed reading: several are
      // a group near its clamp), never on a lower one: a reading at the rail a few sd from a group
      // near it is the sensor at its clamp, not a glitch.
      wild[i] = on_rail[i] ? railed == 1 && dev > kWildReadingSd * sd : dev > kWildReadingSd * sd;
      if (wild[i] && why != nullptr)
        (*why)[i] = logs::format_number(values[i], 6) + " where the readings under the same conditions centre on " + logs::format_number(med, 6) + " (robust sd " +
                    logs::format_number(sd, 6) + ")";
    }
  }
  return wild;
}

}  // namespace epuck2::fit
