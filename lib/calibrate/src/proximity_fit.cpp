// The proximity fit (see epuck2/calibrate/sensors.hpp). Every sensor fit goes through fit_robust
// (epuck2/fit/robust.hpp): readings on a sensor's rails are censored, wild readings are left out
// and listed by file:line, parameters the logs cannot determine keep the plug-in's value.
#include <algorithm>
#include <cmath>
#include <fstream>
#include <limits>
#include <map>
#include <nlohmann/json.hpp>
#include <numeric>
#include <sstream>
#include <stdexcept>
#include <tuple>

#include "epuck2/fit/replicates.hpp"
#include "epuck2/calibrate/sensors.hpp"
#include "epuck2/models/effects.hpp"
#include "epuck2/models/saturation.hpp"
#include "epuck2/logs/json_location.hpp"
#include "sensor_fit_common.hpp"

namespace epuck2::calibrate {

using namespace epuck2::fit;  // the engine (lib/fit)
using namespace sensor_fit_detail;  // the sensor fits' shared helpers

namespace s = models::sensors;

namespace {

// Eq. 1's quadratic over the distances of `x`, parametrised by its slopes so that it cannot rise
// with distance inside [0, range]: p = {u, w, c} with u = -b (minus the slope at 0) and
// w = -(b + 2 a range) (minus the slope at the range), both >= 0; a = (u - w) / (2 range), b = -u.
struct MonotoneProximity {
  std::vector<double> x;
  double range_m;
  template <typename T>
  bool operator()(const T* p, T* out) const {
    const T a = (p[0] - p[1]) / (2.0 * range_m);
    const T abc[3] = {a, -p[0], p[2]};
    for (std::size_t i = 0; i < x.size(); ++i) out[i] = s::proximity_polynomial(abc, x[i]);
    return true;
  }
};

/// {u, w, c} -> {a, b, c} with its covariance, names a, b, c.
void to_abc(RobustFit& f, double range_m) {
  if (!f.usable) return;
  Eigen::Matrix3d M;
  M << 1 / (2 * range_m), -1 / (2 * range_m), 0, -1, 0, 0, 0, 0, 1;
  const Eigen::Vector3d uwc(f.FitResult::parameters[0].value, f.FitResult::parameters[1].value,
                            f.FitResult::parameters[2].value);
  const Eigen::Vector3d abc = M * uwc;
  const Eigen::Matrix3d cov = M * f.covariance * M.transpose();
  const char* names[3] = {"a", "b", "c"};
  // A parameter held (not identifiable) in {u, w, c} leaves its combinations without an error.
  const bool any_nan = std::any_of(f.FitResult::parameters.begin(), f.FitResult::parameters.end(),
                                   [](const ParameterEstimate& e) { return !std::isfinite(e.std_error); });
  for (int j = 0; j < 3; ++j) {
    f.FitResult::parameters[static_cast<std::size_t>(j)].name = names[j];
    f.FitResult::parameters[static_cast<std::size_t>(j)].value = abc(j);
    f.FitResult::parameters[static_cast<std::size_t>(j)].std_error =
        any_nan && j < 2 ? std::numeric_limits<double>::quiet_NaN() : std::sqrt(std::max(cov(j, j), 0.0));
  }
  f.covariance = cov;
}

std::vector<Parameter> proximity_parameters(const s::ProximityCoefficients& start) {
  const double u = -start.b_per_m, w = -(start.b_per_m + 2 * start.a_per_m2 * start.range_m);
  const double inf = std::numeric_limits<double>::infinity();
  return {{"slope_at_0", std::max(u, 0.0), u, 0.0, inf},
          {"slope_at_range", std::max(w, 0.0), w, 0.0, inf},
          {"c", start.c, start.c, -inf, inf}};
}

}  // namespace

namespace {
// A distance whose readings average under this fraction of full scale detected nothing.
constexpr double kProximityUndetectedFraction = 0.01;
// Peeling a maximum that lies far above the curve: at most this fraction of a distance's readings
// (and at least one) are passed over in the maxima fit before the point itself is left out of it.
constexpr double kProximityMaxPeelFraction = 0.02;
}  // namespace

namespace {

/// `log` with only the rows `keep` says (their file lines and cells as read).
logs::Log keep_rows(const logs::Log& log, const std::vector<bool>& keep) {
  logs::Log out = log;
  const std::size_t m = log.columns.size();
  out.line_of_row.clear();
  out.cell_start.clear();
  for (auto& [name, v] : out.numeric) v.clear();
  for (auto& [name, v] : out.text) v.clear();
  for (std::size_t i = 0; i < log.rows(); ++i) {
    if (!keep[i]) continue;
    out.line_of_row.push_back(log.line_of_row[i]);
    if (log.cell_start.size() >= (i + 1) * m)
      out.cell_start.insert(out.cell_start.end(), log.cell_start.begin() + static_cast<std::ptrdiff_t>(i * m),
                            log.cell_start.begin() + static_cast<std::ptrdiff_t>((i + 1) * m));
    for (auto& [name, v] : out.numeric) v.push_back(log.numeric.at(name)[i]);
    for (auto& [name, v] : out.text) v.push_back(log.text.at(name)[i]);
  }
  return out;
}

/// The rows facing the target (angle_deg 0, or no angle_deg column): Eq. 1 is the response of a
/// sensor facing the surface. The rows at an angle are left out of the calibration, each listed in
/// `out.left_out`, with one warning that counts them; none facing the target is bad input (exit 2).
/// `logs` itself when every row faces the target, else `facing` filled and returned.
const std::vector<logs::Log>& facing_rows(const std::vector<logs::Log>& logs, std::vector<logs::Log>& facing, ProximityFit& out) {
  std::size_t angled = 0, rows = 0;
  for (const logs::Log& log : logs) {
    rows += log.rows();
    if (!log.has("angle_deg")) continue;
    for (double a : log.col("angle_deg")) angled += a != 0.0;
  }
  if (angled == 0) return logs;
  if (angled == rows) {
    std::string files;
    for (const logs::Log& log : logs) files += (files.empty() ? "" : ", ") + log.path;
    throw logs::InputError(logs.front().path, 0, 0,
                           "no row faces the target (angle_deg 0): all " + std::to_string(rows) + " rows of " + files +
                               " are at an angle. The proximity calibration fits Eq. 1, the response of a sensor facing "
                               "the surface; log rows at angle_deg 0 (`epuck2-fit diagnose` fits the incidence angle).");
  }
  for (const logs::Log& log : logs) {
    if (!log.has("angle_deg")) {
      facing.push_back(log);
      continue;
    }
    const auto& angle = log.col("angle_deg");
    const auto& d = log.col("distance_m");
    std::vector<bool> keep(log.rows());
    for (std::size_t i = 0; i < log.rows(); ++i) {
      keep[i] = angle[i] == 0.0;
      if (!keep[i])
        out.left_out.push_back({sensor_fit_detail::where(log, i), "at an angle: angle_deg " + sensor_fit_detail::fmt(angle[i]) +
                                                                      " at " + sensor_fit_detail::fmt(d[i] * 1000) +
                                                                      " mm (the calibration takes the rows facing the target, angle_deg 0)"});
    }
    facing.push_back(keep_rows(log, keep));
  }
  out.readings += angled;
  out.warnings.push_back(std::to_string(angled) + " of " + std::to_string(rows) +
                         " rows are at an angle (angle_deg not 0): left out of the calibration, which fits Eq. 1 to the "
                         "rows facing the target (angle_deg 0); `epuck2-fit diagnose` fits the incidence angle.");
  return facing;
}

}  // namespace

ReadingNoise proximity_replicate_noise(const std::vector<logs::Log>& logs) {
  // Replicates: one log, one sensor, one distance, one incidence angle (0 without angle_deg).
  const double full = s::kProximityFullScale_raw;
  std::vector<double> nv;
  std::vector<int> ng, ns;
  std::vector<bool> nr;
  Groups<std::tuple<std::size_t, int, double, double>> groups;
  for (std::size_t l = 0; l < logs.size(); ++l) {
    const auto& d = logs[l].col("distance_m");
    const auto& v = logs[l].col("value");
    const bool has_angle = logs[l].has("angle_deg");
    for (std::size_t i = 0; i < logs[l].rows(); ++i) {
      const int sensor = sensor_of(logs[l], i);
      const double angle = has_angle ? logs[l].col("angle_deg")[i] : 0.0;
      nv.push_back(v[i]);
      ng.push_back(groups.of({l, sensor, d[i], angle}));
      ns.push_back(sensor);
      nr.push_back(v[i] <= 0 || v[i] >= full);
    }
  }
  return noise_from_replicates("proximity", "counts", kArgosNoiseScaleProximity_counts, nv, ng, nr, ns, s::kProximityCount,
                               kQuantisationSd);
}

ProximityFit fit_proximity(const std::vector<logs::Log>& all_logs, const SensorFitOptions& options,
                           const s::ProximityCoefficients& start) {
  ProximityFit out;
  std::vector<logs::Log> facing;
  const std::vector<logs::Log>& logs = facing_rows(all_logs, facing, out);
  struct Reading {
    double value;
    std::string where;
    int robot;
  };
  std::map<double, std::vector<Reading>> by_distance;
  for (const logs::Log& log : logs) {
    const auto& d = log.col("distance_m");
    const auto& v = log.col("value");
    const int robot = robot_index(out.robot_names, log.robot);
    for (std::size_t i = 0; i < log.rows(); ++i) by_distance[d[i]].push_back({v[i], where(log, i), robot});
    out.readings += log.rows();
  }
  const double full = s::kProximityFullScale_raw;
  // 1. Wild readings: far from the other readings at their distance (rails are censored
  //    information, not wild, unless one stray reading sits there alone).
  std::vector<double> values;
  std::vector<int> group;
  std::vector<bool> on_rail;
  // The screen's groups: one distance read by one robot (robots differ by more than their noise).
  std::map<std::pair<double, int>, int> group_of;
  for (const auto& [d, rs] : by_distance) {
    for (const Reading& r : rs) {
      values.push_back(r.value);
      group.push_back(group_of.emplace(std::make_pair(d, r.robot), static_cast<int>(group_of.size())).first->second);
      on_rail.push_back(r.value <= 0 || r.value >= full);
    }
  }
  std::vector<std::string> why;
  const std::vector<bool> wild =
      options.robust ? flag_wild_replicates(values, group, on_rail, 2.0, &why) : std::vector<bool>(values.size(), false);
  std::map<double, std::vector<Reading>> kept, beyond;
  // A point's min, mean and max (normalised) over `rs`.
  auto set_measured = [](ProximityPoint& p, const std::vector<Reading>& rs, double scale) {
    if (rs.empty()) return;
    double sum = 0, lo = rs.front().value, hi = rs.front().value;
    for (const Reading& r : rs) {
      sum += r.value;
      lo = std::min(lo, r.value);
      hi = std::max(hi, r.value);
    }
    p.mean = sum / static_cast<double>(rs.size()) / scale;
    p.min = lo / scale;
    p.max = hi / scale;
  };
  std::size_t k = 0;
  for (const auto& [d, rs] : by_distance) {
    ProximityPoint p;
    p.distance_m = d;
    p.readings = rs.size();
    for (const Reading& r : rs) {
      if (on_rail[k]) ++out.censored_readings;
      if (wild[k])
        out.left_out.push_back({r.where, "wild: " + why[k] + " at " + fmt(d * 1000) + " mm"});
      else
        kept[d].push_back(r);
      ++k;
    }
    std::vector<double> sum(out.robot_names.size(), 0.0), count(out.robot_names.size(), 0.0);
    for (const Reading& r : kept[d]) {
      sum[static_cast<std::size_t>(r.robot)] += r.value / full;
      count[static_cast<std::size_t>(r.robot)] += 1;
    }
    for (std::size_t b = 0; b < sum.size(); ++b)
      p.robot_mean.push_back(count[b] > 0 ? sum[b] / count[b] : std::numeric_limits<double>::quiet_NaN());
    if (d > start.range_m) {
      p.excluded_why = "beyond the sensor's range (" + fmt(start.range_m * 1000) + " mm)";
      // Left out of the fits, shown as measured (never as zeros).
      set_measured(p, kept[d], full);
      for (const Reading& r : kept[d])
        out.left_out.push_back({r.where, "beyond the range: " + fmt(r.value) + " at " + fmt(d * 1000) + " mm"});
      beyond[d] = std::move(kept[d]);
      kept[d].clear();
    }
    out.points.push_back(p);
  }

  // 1b. The range, when the logs reach beyond the model's: where the readings stop being detected
  //     (a mean under kProximityUndetectedFraction of full scale), bracketed by the distances logged.
  if (!out.points.empty() && out.points.back().distance_m > start.range_m) {
    ProximityRange& R = out.range;
    R.fitted = true;
    auto detected = [&](double d) {
      const auto& rs = d > start.range_m ? beyond[d] : kept[d];
      if (rs.empty()) return false;
      double sum = 0;
      for (const Reading& r : rs) sum += r.value;
      return sum / static_cast<double>(rs.size()) >= kProximityUndetectedFraction * full;
    };
    std::size_t last = out.points.size();  // the farthest detected distance
    for (std::size_t i = 0; i < out.points.size(); ++i)
      if (detected(out.points[i].distance_m)) last = i;
    const std::string threshold = fmt(kProximityUndetectedFraction * full, 3) + " counts";
    if (last == out.points.size()) {
      R.fitted = false;
      R.how = "no distance logged has readings detected (mean at least " + threshold + "): the range cannot be fitted";
    } else if (last + 1 == out.points.size()) {
      R.lower_bound = true;
      R.value_m = R.detected_to_m = out.points[last].distance_m;
      R.std_error_m = R.undetected_from_m = std::numeric_limits<double>::quiet_NaN();
      R.how = "at least " + fmt(R.value_m * 1000) + " mm: the readings are still detected (mean " +
              fmt(out.points[last].mean * full, 3) + " counts, at least " + threshold + ") at the farthest distance logged";
    } else {
      R.detected_to_m = out.points[last].distance_m;
      R.undetected_from_m = out.points[last + 1].distance_m;
      R.value_m = 0.5 * (R.detected_to_m + R.undetected_from_m);
      R.std_error_m = (R.undetected_from_m - R.detected_to_m) / std::sqrt(12.0);
      R.how = "between " + fmt(R.detected_to_m * 1000) + " mm (the farthest distance whose readings are detected, mean at least " +
              threshold + ") and " + fmt(R.undetected_from_m * 1000) + " mm (the next distance logged, not detected)";
    }
  }

  // 2. The maxima: peel a maximum the curve rejects (a wild high reading that escaped step 1).
  //    Only a maximum ABOVE the curve through the other distances' maxima is peeled: the next
  //    highest reading then stands for the distance in the maxima fit. The peeled reading leaves
  //    the maxima fit only; it was screened as a reading in step 1 and stays in the mean (step 3).
  //    A maximum BELOW the curve is no wild high reading: its distance is left out of the maxima
  //    fit, with a warning.
  std::map<double, std::size_t> peeled;
  std::map<double, bool> point_out;
  // Each distance's kept readings, highest first (the maxima fit takes the first not peeled).
  std::map<double, std::vector<const Reading*>> highest_first;
  for (const auto& [d, rs] : kept) {
    auto& h = highest_first[d];
    for (const Reading& r : rs) h.push_back(&r);
    std::stable_sort(h.begin(), h.end(), [](const Reading* a, const Reading* b) { return a->value > b->value; });
  }
  const std::vector<Parameter> params = proximity_parameters(start);
  for (int round = 0;; ++round) {
    std::vector<double> x;
    std::vector<Observation> obs;
    std::vector<double> dist_of_obs;
    for (ProximityPoint& p : out.points) {
      const auto& rs = kept[p.distance_m];
      if (rs.empty() || point_out[p.distance_m]) continue;
      const Reading* top = highest_first[p.distance_m][peeled[p.distance_m]];
      p.max = top->value / full;
      p.max_where = top->where;
      p.max_censoring = fit::censoring_at(top->value, 0, full);
      // Nothing detected (mean under 1 % of full scale): readings of noise around 0 say only that
      // the curve is at most this high there.
      double sum = 0;
      for (const Reading& r : rs) sum += r.value;
      if (sum / static_cast<double>(rs.size()) < kProximityUndetectedFraction * full) p.max_censoring = Censoring::at_or_below;
      x.push_back(p.distance_m);
      dist_of_obs.push_back(p.distance_m);
      obs.push_back({p.max, p.max_censoring, top->where, -1});
    }
    RobustOptions ro = robust_options(options, kQuantisationSd / full);
    out.maxima = fit_robust(MonotoneProximity{x, start.range_m}, obs, params, ro);
    if (!out.maxima.usable || !options.robust || round > 200) break;
    bool again = false;
    for (std::size_t i : out.maxima.outliers) {
      const double d = dist_of_obs[i];
      const auto& rs = kept[d];
      if (i >= out.maxima.predictions.size()) continue;
      const bool above = obs[i].value > out.maxima.predictions[i];
      if (!above) {
        point_out[d] = true;
        out.warnings.push_back("the maximum at " + fmt(d * 1000) + " mm (" + fmt(obs[i].value * full) + " counts, " +
                               obs[i].where + ") lies far below the curve through the other distances' maxima (" +
                               fmt(out.maxima.predictions[i] * full) +
                               " counts): not a wild high reading, so none is peeled; that distance is left out of the maxima fit.");
        again = true;
        continue;
      }
      const std::size_t limit = std::max<std::size_t>(1, static_cast<std::size_t>(kProximityMaxPeelFraction * static_cast<double>(rs.size())));
      if (peeled[d] >= limit || peeled[d] + 1 >= rs.size()) {
        point_out[d] = true;
        out.warnings.push_back(peeled[d] == 0 ? "the only reading at " + fmt(d * 1000) +
                                                    " mm lies far above the curve through the other distances' maxima: that "
                                                    "distance is left out of the maxima fit."
                                              : "the readings at " + fmt(d * 1000) + " mm do not fit the curve even without their " +
                                                    std::to_string(peeled[d]) + " highest: that distance is left out of the maxima fit.");
      } else {
        const Reading* top = highest_first[d][peeled[d]];
        out.left_out.push_back({top->where, "wild maximum: " + fmt(top->value) + " at " + fmt(d * 1000) +
                                                " mm, far above the curve through the other distances' maxima: left out of the "
                                                "maxima fit only (the mean keeps it)"});
        ++peeled[d];
      }
      again = true;
    }
    if (!again) break;
  }
  to_abc(out.maxima, start.range_m);

  // 3. The means, over the readings kept; a distance with readings on a rail gives a bound.
  std::vector<double> x;
  std::vector<Observation> obs;
  for (ProximityPoint& p : out.points) {
    const auto& rs = kept[p.distance_m];
    p.kept = rs.size();
    if (rs.empty()) {
      if (p.excluded_why.empty()) p.excluded_why = "no reading kept";
      continue;
    }
    p.used = true;
    double sum = 0, lo = full, hi = 0;
    bool at_top = false, at_bottom = false;
    for (const Reading& r : rs) {
      sum += r.value;
      lo = std::min(lo, r.value);
      hi = std::max(hi, r.value);
      at_top = at_top || r.value >= full;
      at_bottom = at_bottom || r.value <= 0;
    }
    p.mean = sum / static_cast<double>(rs.size()) / full;
    p.min = lo / full;
    double ss = 0;
    for (const Reading& r : rs) ss += (r.value / full - p.mean) * (r.value / full - p.mean);
    p.mean_se = rs.size() > 1 ? std::sqrt(ss / static_cast<double>(rs.size() - 1) / static_cast<double>(rs.size())) : 0.0;
    // Readings on the top rail were at least full scale: the true mean is at least this one.
    p.mean_censoring = at_top && !at_bottom ? Censoring::at_or_above
                       : at_bottom && !at_top ? Censoring::at_or_below
                                              : Censoring::none;
    if (p.mean < kProximityUndetectedFraction) p.mean_censoring = Censoring::at_or_below;
    x.push_back(p.distance_m);
    obs.push_back({p.mean, p.mean_censoring, "mean at " + fmt(p.distance_m * 1000) + " mm", -1});
  }
  // The readings were screened one by one above: a mean is not a reading to leave out.
  RobustOptions means_options = robust_options(options, kQuantisationSd / full);
  means_options.robust = false;
  out.means = fit_robust(MonotoneProximity{x, start.range_m}, obs, params, means_options);
  to_abc(out.means, start.range_m);

  // Lack of fit: both fits ran on one number per distance, but every distance has its raw
  // replicates behind it; the means are tested against them (F test), the maxima against their sd
  // (a maximum of n readings varies less than one reading: the test is on the lenient side).
  {
    const MisfitWords words{"distances", "mm", "counts", 1000.0, full};
    auto curve = [](const RobustFit& f, double d) {
      if (!f.usable) return 0.0;  // not tested below
      const double abc[3] = {f.value("a"), f.value("b"), f.value("c")};
      return s::proximity_polynomial(abc, d);
    };
    std::vector<ReplicateGroup> means_groups, maxima_groups;
    for (const ProximityPoint& p : out.points) {
      const auto& rs = kept[p.distance_m];
      if (!p.used || rs.empty()) continue;
      ReplicateGroup mg;
      mg.condition = p.distance_m;
      mg.spoilt = p.mean_censoring != Censoring::none;
      for (const Reading& r : rs) {
        mg.spoilt = mg.spoilt || r.value <= 0 || r.value >= full;
        mg.readings.push_back(r.value / full);
        mg.predictions.push_back(curve(out.means, p.distance_m));
      }
      means_groups.push_back(std::move(mg));
      ReplicateGroup xg;
      xg.condition = p.distance_m;
      xg.spoilt = point_out[p.distance_m] || p.max_censoring != Censoring::none;
      xg.readings = {p.max};
      xg.predictions = {curve(out.maxima, p.distance_m)};
      maxima_groups.push_back(std::move(xg));
    }
    if (out.means.usable) out.means.lack_of_fit = lack_of_fit(means_groups, 3 - out.means.not_identifiable.size(), words, kQuantisationSd / full);
    const LackOfFit& pure = out.means.lack_of_fit;
    if (out.maxima.usable)
      out.maxima.lack_of_fit = lack_of_fit(maxima_groups, 3 - out.maxima.not_identifiable.size(), words, kQuantisationSd / full,
                                           pure.tested ? pure.replicate_sd : 0.0, pure.tested ? pure.dof_pure : 0);
    for (RobustFit* f : {&out.maxima, &out.means}) {
      const LackOfFit& lof = f->lack_of_fit;
      if (lof.tested && lof.misfit_ratio > kMisfitWarnRatio)
        f->warnings.push_back("the curve misses the readings by " + fmt(lof.misfit_rms * full, 3) + " counts RMS, " +
                              fmt(lof.misfit_ratio, 3) + " times their replicate sd of " + fmt(lof.replicate_sd * full, 3) +
                              " counts; worst: " + lof.worst + ".");
    }
  }

  // 4. References and plausibility.
  auto reference_mse = [&](const s::ProximityCoefficients& k, bool maxima) {
    std::vector<double> r;
    const double abc[3] = {k.a_per_m2, k.b_per_m, k.c};
    for (const ProximityPoint& p : out.points) {
      if (!p.used) continue;
      const Censoring c = maxima ? p.max_censoring : p.mean_censoring;
      if (c != Censoring::none) continue;
      r.push_back((maxima ? p.max : p.mean) - std::clamp(s::proximity_polynomial(abc, p.distance_m), 0.0, 1.0));
    }
    return mse_of(r);
  };
  out.plugin_mse_maxima = reference_mse(s::kPluginProximity, true);
  out.plugin_mse_means = reference_mse(s::kPluginProximity, false);
  out.epuck1_mse_maxima = reference_mse(s::kEpuck1Proximity, true);
  out.epuck1_mse_means = reference_mse(s::kEpuck1Proximity, false);
  for (const auto* f : {&out.maxima, &out.means}) {
    const std::string which = f == &out.maxima ? "maxima fit: " : "means fit: ";
    collect(out.warnings, which, f->warnings);
    if (!f->usable) continue;
    const double abc[3] = {f->value("a"), f->value("b"), f->value("c")};
    if (s::proximity_polynomial(abc, 0.0) < 0.05)
      out.warnings.push_back(which + "the curve reads under 5 % of full scale at contact (c = " + fmt(abc[2]) +
                             "): a proximity sensor touching a surface reads near full scale.");
  }

  // 5. The reading noise: the replicates at each distance, per log and sensor (of the rows used).
  //    Without replicates each distance's mean is one reading: the means fit's residuals.
  out.noise = replicates_or_residuals(
      proximity_replicate_noise(logs),
      noise_from_residuals("proximity", "counts", kArgosNoiseScaleProximity_counts, out.means, full, s::kProximityCount));
  return out;
}

}  // namespace epuck2::calibrate
