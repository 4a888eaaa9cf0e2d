// Sensor calibration fits (see epuck2/calibrate/sensors.hpp): proximity, light, ground, camera, drive,
// and the loaders of the coefficient files the CLI writes. Every fit goes through fit_robust
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

#include "epuck2/calibrate/screening.hpp"
#include "epuck2/calibrate/sensors.hpp"
#include "epuck2/models/effects.hpp"
#include "epuck2/models/saturation.hpp"
#include "epuck2/logs/json_location.hpp"

namespace epuck2::calibrate {

using namespace epuck2::fit;  // the engine (lib/fit)

namespace s = models::sensors;

namespace {

double mse_of(const std::vector<double>& residuals) {
  if (residuals.empty()) return 0.0;
  double sum = 0;
  for (double r : residuals) sum += r * r;
  return sum / static_cast<double>(residuals.size());
}

std::string where(const logs::Log& log, std::size_t row) {
  return log.path + ":" + std::to_string(log.line_of_row.at(row));
}

std::string fmt(double v, int digits = 4) {
  std::ostringstream os;
  os.precision(digits);
  os << v;
  return os.str();
}

/// A reading's censoring against a sensor's two rails.
Censoring rail_of(double value, double low, double high) {
  if (value <= low) return Censoring::at_or_below;
  if (value >= high) return Censoring::at_or_above;
  return Censoring::none;
}

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

void collect(std::vector<std::string>& into, const std::string& prefix, const std::vector<std::string>& from) {
  for (const std::string& w : from) into.push_back(prefix + w);
}

RobustOptions robust_options(const SensorFitOptions& o, double noise_floor) {
  RobustOptions r;
  r.robust = o.robust;
  r.reject_sd = o.reject_sd;
  r.noise_floor = noise_floor;
  return r;
}

// The autocorrelation correction of a fit to rows of runs: the AR(1) factor from the residuals of
// the readings inside the rails that the fit kept, in row order, NaN elsewhere (a censored or
// left-out reading breaks the chain), each run its own series; and the cluster-robust errors
// with each run a cluster (fit::apply_cluster_robust).
AutocorrelationCorrection run_autocorrelation(const RobustFit& f, const std::vector<Observation>& obs,
                                              const std::vector<int>& run_of) {
  std::vector<double> e(obs.size(), std::numeric_limits<double>::quiet_NaN());
  std::vector<bool> left_out(obs.size(), false);
  for (std::size_t i : f.outliers)
    if (i < left_out.size()) left_out[i] = true;
  for (std::size_t i = 0; i < obs.size() && i < f.predictions.size(); ++i)
    if (obs[i].censoring == Censoring::none && !left_out[i]) e[i] = obs[i].value - f.predictions[i];
  AutocorrelationCorrection a = autocorrelation_correction(e, run_of);
  // Runs as clusters: every kept reading's score (censored ones too), whatever its correlation
  // with its neighbours.
  std::vector<double> r(obs.size(), std::numeric_limits<double>::quiet_NaN());
  for (std::size_t i = 0; i < obs.size() && i < f.scaled_residuals.size(); ++i)
    if (!left_out[i]) r[i] = f.scaled_residuals[i];
  apply_cluster_robust(a, f, f.jacobian, r, run_of);
  return a;
}

// No saturation on that side (models::saturate).
constexpr double kNoSaturation = std::numeric_limits<double>::infinity();

// Quantisation noise of an integer reading: 1/sqrt(12) of a count.
constexpr double kQuantisationSd = 0.28867513459481287;

/// Groups of readings under the same conditions: an id per distinct key.
template <class Key>
class Groups {
 public:
  int of(const Key& k) { return ids_.emplace(k, static_cast<int>(ids_.size())).first->second; }

 private:
  std::map<Key, int> ids_;
};

/// A sensor index from a log's `sensor` column (0 when the log has none).
int sensor_of(const logs::Log& log, std::size_t row) {
  return log.has("sensor") ? static_cast<int>(log.col("sensor")[row]) : 0;
}

}  // namespace

// ================================================================================================
// Proximity
// ================================================================================================

namespace {
// A distance whose readings average under this fraction of full scale detected nothing.
constexpr double kProximityUndetectedFraction = 0.01;
// Peeling a maximum that the curve rejects: at most this fraction of a distance's readings (and
// at least one) are taken away before the point itself is left out.
constexpr double kProximityMaxPeelFraction = 0.02;
}  // namespace

ProximityFit fit_proximity(const std::vector<logs::Log>& logs, const SensorFitOptions& options,
                           const s::ProximityCoefficients& start) {
  ProximityFit out;
  struct Reading {
    double value;
    std::string where;
  };
  std::map<double, std::vector<Reading>> by_distance;
  for (const logs::Log& log : logs) {
    const auto& d = log.col("distance_m");
    const auto& v = log.col("value");
    for (std::size_t i = 0; i < log.rows(); ++i) by_distance[d[i]].push_back({v[i], where(log, i)});
    out.readings += log.rows();
  }
  const double full = s::kProximityFullScale_raw;
  // 1. Wild readings: far from the other readings at their distance (rails are censored
  //    information, not wild, unless one stray reading sits there alone).
  std::vector<double> values;
  std::vector<int> group;
  std::vector<bool> on_rail;
  std::map<double, int> group_of;
  for (const auto& [d, rs] : by_distance) {
    const int g = static_cast<int>(group_of.size());
    group_of[d] = g;
    for (const Reading& r : rs) {
      values.push_back(r.value);
      group.push_back(g);
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

  // 2. The maxima: peel a maximum the curve rejects (a wild reading that escaped step 1).
  std::map<double, std::size_t> peeled;
  std::map<double, bool> point_out;
  const std::vector<Parameter> params = proximity_parameters(start);
  for (int round = 0;; ++round) {
    std::vector<double> x;
    std::vector<Observation> obs;
    std::vector<double> dist_of_obs;
    for (ProximityPoint& p : out.points) {
      auto& rs = kept[p.distance_m];
      if (rs.empty() || point_out[p.distance_m]) continue;
      const auto top = std::max_element(rs.begin(), rs.end(), [](const Reading& a, const Reading& b) { return a.value < b.value; });
      p.max = top->value / full;
      p.max_where = top->where;
      p.max_censoring = rail_of(top->value, 0, full);
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
      auto& rs = kept[d];
      const std::size_t limit = std::max<std::size_t>(1, static_cast<std::size_t>(kProximityMaxPeelFraction * static_cast<double>(rs.size() + peeled[d])));
      if (peeled[d] >= limit) {
        point_out[d] = true;
        out.warnings.push_back("the readings at " + fmt(d * 1000) + " mm do not fit the curve even without their " +
                               std::to_string(peeled[d]) + " highest: that distance is left out of the maxima fit.");
      } else {
        const auto top = std::max_element(rs.begin(), rs.end(), [](const Reading& a, const Reading& b) { return a.value < b.value; });
        out.left_out.push_back({top->where, "wild: " + fmt(top->value) + " at " + fmt(d * 1000) +
                                                " mm, far above the curve through the other distances' maxima"});
        rs.erase(top);
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

  // 5. The reading noise: the replicates at each distance, per log and sensor.
  {
    std::vector<double> nv;
    std::vector<int> ng, ns;
    std::vector<bool> nr;
    Groups<std::tuple<std::size_t, int, double>> groups;
    for (std::size_t l = 0; l < logs.size(); ++l) {
      const auto& d = logs[l].col("distance_m");
      const auto& v = logs[l].col("value");
      for (std::size_t i = 0; i < logs[l].rows(); ++i) {
        const int sensor = sensor_of(logs[l], i);
        nv.push_back(v[i]);
        ng.push_back(groups.of({l, sensor, d[i]}));
        ns.push_back(sensor);
        nr.push_back(v[i] <= 0 || v[i] >= full);
      }
    }
    // Without replicates each distance's mean is one reading: the means fit's residuals.
    out.noise = replicates_or_residuals(
        noise_from_replicates("proximity", "counts", kArgosNoiseScaleProximity_counts, nv, ng, nr, ns, s::kProximityCount,
                              kQuantisationSd),
        noise_from_residuals("proximity", "counts", kArgosNoiseScaleProximity_counts, out.means, full, s::kProximityCount));
  }
  return out;
}

// ================================================================================================
// Light
// ================================================================================================

namespace {
// Eq. 2 for one light: y = 1 - g (gamma I / d)^2 over the observations' x = I / d (per metre),
// saturated at 0 before the noise (a phototransistor in bright light reads 0 plus its noise, not
// the -4700 counts of the unclamped curve; lib/models saturation.hpp). The register's rail at 0 is
// the Tobit censoring of fit_robust: together, the mean of a reading is
// E[clamp(clamp(model) + noise)].
struct LightCurve {
  std::vector<double> intensity_per_m;
  template <typename T>
  bool operator()(const T* gamma_m, T* out) const {
    for (std::size_t i = 0; i < intensity_per_m.size(); ++i)
      out[i] = models::saturate(s::light_response(gamma_m[0], intensity_per_m[i], 1.0), 0.0, kNoSaturation);
    return true;
  }
};

RobustFit fit_gamma(const std::vector<LightObservation>& obs_in, const SensorFitOptions& options, int sensor) {
  const double full = s::kProximityFullScale_raw;
  std::vector<double> x;
  std::vector<Observation> obs;
  std::map<std::tuple<int, double, double>, int> groups;
  for (const LightObservation& o : obs_in) {
    if (sensor >= 0 && o.sensor != sensor) continue;
    x.push_back(o.intensity / o.distance_m);
    const auto key = std::make_tuple(o.sensor, o.distance_m, o.intensity);
    const int group = groups.emplace(key, static_cast<int>(groups.size())).first->second;
    obs.push_back({std::clamp(o.value_raw / full, 0.0, 1.0), rail_of(o.value_raw, 0, full), o.where, group});
  }
  const double inf = std::numeric_limits<double>::infinity();
  return fit_robust(LightCurve{x}, obs, {{"gamma", s::kPluginLight.gamma_m, s::kPluginLight.gamma_m, 1e-9, inf}},
                    robust_options(options, kQuantisationSd / full));
}
}  // namespace

LightFit fit_light(const std::vector<logs::Log>& logs, const SensorFitOptions& options) {
  LightFit out;
  std::map<int, bool> seen;
  for (const logs::Log& log : logs) {
    const auto& d = log.col("distance_m");
    const auto& in = log.col("intensity");
    const auto& sen = log.col("sensor");
    const auto& v = log.col("value");
    out.readings += log.rows();
    for (std::size_t i = 0; i < log.rows(); ++i) {
      // A light out of range or of no intensity leaves the reading dark whatever gamma is.
      if (!(d[i] > 0) || d[i] > s::kPluginLight.range_m) {
        out.left_out.push_back({where(log, i), "light beyond the sensor's range (0.5 m)"});
        continue;
      }
      if (!(in[i] > 0)) {
        out.left_out.push_back({where(log, i), "no light (intensity 0)"});
        continue;
      }
      const int sensor = static_cast<int>(sen[i]);
      seen[sensor] = true;
      if (v[i] <= 0 || v[i] >= s::kProximityFullScale_raw) ++out.censored;
      out.observations.push_back({d[i], in[i], sensor, v[i], where(log, i)});
    }
  }
  out.gamma = fit_gamma(out.observations, options, -1);
  collect(out.warnings, "pooled gamma: ", out.gamma.warnings);
  for (const auto& [sensor, yes] : seen) {
    (void)yes;
    out.sensors.push_back(sensor);
    out.gamma_per_sensor.push_back(fit_gamma(out.observations, options, sensor));
    collect(out.warnings, "sensor " + std::to_string(sensor) + ": ", out.gamma_per_sensor.back().warnings);
  }
  std::vector<double> r;
  for (const LightObservation& o : out.observations)
    if (o.value_raw > 0 && o.value_raw < s::kProximityFullScale_raw)
      r.push_back(o.value_raw / s::kProximityFullScale_raw - s::light_response(s::kPluginLight.gamma_m, o.intensity, o.distance_m));
  out.plugin_mse = mse_of(r);

  // The reading noise: the replicates of each log, sensor, distance and intensity (a light out of
  // range or off included: the sensor's dark reading is a reading too).
  std::vector<double> nv;
  std::vector<int> ng, ns;
  std::vector<bool> nr;
  Groups<std::tuple<std::size_t, int, double, double>> groups;
  for (std::size_t l = 0; l < logs.size(); ++l) {
    const auto& d = logs[l].col("distance_m");
    const auto& in = logs[l].col("intensity");
    const auto& v = logs[l].col("value");
    for (std::size_t i = 0; i < logs[l].rows(); ++i) {
      const int sensor = sensor_of(logs[l], i);
      nv.push_back(v[i]);
      ng.push_back(groups.of({l, sensor, d[i], in[i]}));
      ns.push_back(sensor);
      nr.push_back(v[i] <= 0 || v[i] >= s::kProximityFullScale_raw);
    }
  }
  out.noise = replicates_or_residuals(
      noise_from_replicates("light", "counts", kArgosNoiseScaleLight_counts, nv, ng, nr, ns, s::kProximityCount,
                            kQuantisationSd),
      noise_from_residuals("light", "counts", kArgosNoiseScaleLight_counts, out.gamma, s::kProximityFullScale_raw,
                           s::kProximityCount));
  return out;
}

// ================================================================================================
// Ground
// ================================================================================================

namespace {
struct GroundLine {
  std::vector<double> grey;
  template <typename T>
  bool operator()(const T* p, T* out) const {
    for (std::size_t i = 0; i < grey.size(); ++i) out[i] = s::ground_response(p[0], p[1], grey[i]);
    return true;
  }
};
}  // namespace

GroundFit fit_ground(const std::vector<logs::Log>& logs, const SensorFitOptions& options) {
  GroundFit out;
  const double full = s::kGroundFullScale_raw;
  std::array<std::vector<Observation>, s::kGroundCount> obs;
  for (const logs::Log& log : logs) {
    const auto& g = log.col("grey");
    const auto& sen = log.col("sensor");
    const auto& v = log.col("value");
    out.readings += log.rows();
    const auto named = std::find(out.robot_names.begin(), out.robot_names.end(), log.robot);
    const int robot = static_cast<int>(named - out.robot_names.begin());
    if (named == out.robot_names.end()) out.robot_names.push_back(log.robot);
    for (std::size_t i = 0; i < log.rows(); ++i) {
      const auto k = static_cast<std::size_t>(sen[i]);
      const Censoring c = rail_of(v[i], 0, full);
      if (c != Censoring::none) ++out.censored;
      out.grey[k].push_back(g[i]);
      out.value_raw[k].push_back(v[i]);
      out.robot[k].push_back(robot);
      // Replicates: the same grey level (to a tenth of a percent).
      obs[k].push_back({v[i], c, where(log, i), static_cast<int>(std::lround(g[i] * 1000))});
    }
  }
  double rss = 0;
  std::size_t n = 0;
  const double inf = std::numeric_limits<double>::infinity();
  for (std::size_t k = 0; k < static_cast<std::size_t>(s::kGroundCount); ++k) {
    if (obs[k].empty()) {
      out.sensors[k].message = "no readings of this sensor";
      continue;
    }
    // Gains positive (white reflects more than black); the offset is what black reads.
    out.sensors[k] = fit_robust(GroundLine{out.grey[k]}, obs[k],
                                {{"gain", s::kPluginGround.gain_raw, s::kPluginGround.gain_raw, 1e-9, inf},
                                 {"offset", s::kPluginGround.offset_raw, s::kPluginGround.offset_raw, -inf, inf}},
                                robust_options(options, kQuantisationSd));
    collect(out.warnings, "sensor " + std::to_string(k) + ": ", out.sensors[k].warnings);
    if (out.sensors[k].usable) {
      rss += out.sensors[k].rss;
      n += out.sensors[k].exact;
    }
    std::vector<double> r;
    for (std::size_t i = 0; i < out.grey[k].size(); ++i)
      if (obs[k][i].censoring == Censoring::none)
        r.push_back(out.value_raw[k][i] - s::ground_response(s::kPluginGround.gain_raw, s::kPluginGround.offset_raw, out.grey[k][i]));
    out.plugin_mse[k] = mse_of(r);
  }
  out.mse = n ? rss / static_cast<double>(n) : 0.0;

  // The reading noise: the replicates of each log, sensor and grey level (to a tenth of a percent).
  std::vector<double> nv;
  std::vector<int> ng, ns;
  std::vector<bool> nr;
  Groups<std::tuple<std::size_t, int, long>> groups;
  for (std::size_t l = 0; l < logs.size(); ++l) {
    const auto& g = logs[l].col("grey");
    const auto& v = logs[l].col("value");
    for (std::size_t i = 0; i < logs[l].rows(); ++i) {
      const int sensor = sensor_of(logs[l], i);
      nv.push_back(v[i]);
      ng.push_back(groups.of({l, sensor, std::lround(g[i] * 1000)}));
      ns.push_back(sensor);
      nr.push_back(v[i] <= 0 || v[i] >= full);
    }
  }
  // Without replicates: the three sensors' fits' residuals, pooled.
  RobustFit pooled;
  pooled.usable = n > 0;
  pooled.noise_sd = n ? std::sqrt(rss / static_cast<double>(n)) : 0.0;
  pooled.observations = n;
  out.noise = replicates_or_residuals(
      noise_from_replicates("ground", "counts", kArgosNoiseScaleGround_counts, nv, ng, nr, ns, s::kGroundCount,
                            kQuantisationSd),
      noise_from_residuals("ground", "counts", kArgosNoiseScaleGround_counts, pooled, 1.0, s::kGroundCount));
  return out;
}

// ================================================================================================
// Camera
// ================================================================================================

namespace {
// px and py of every observation (2 per LED sighting), p = {fov_deg, cx_px, cy_px}:
// px = cx - f y / x, py = cy - f z / x, f = (W/2) / tan(fov/2).
struct CameraModel {
  std::vector<CameraObservation> obs;
  template <typename T>
  bool operator()(const T* p, T* out) const {
    for (std::size_t i = 0; i < obs.size(); ++i)
      s::camera_projection(T(s::deg_to_rad(1.0)) * p[0], p[1], p[2], s::kCameraWidth_px, obs[i].forward_m, obs[i].lateral_m,
                           obs[i].vertical_m, &out[2 * i], &out[2 * i + 1]);
    return true;
  }
};
}  // namespace

CameraFit fit_camera(const std::vector<logs::Log>& logs, const SensorFitOptions& options) {
  CameraFit out;
  std::vector<Observation> obs;
  std::map<std::tuple<double, double, double>, int> groups;
  for (const logs::Log& log : logs) {
    const auto& x = log.col("forward_m");
    const auto& y = log.col("lateral_m");
    const auto& z = log.col("vertical_m");
    const auto& px = log.col("px");
    const auto& py = log.col("py");
    for (std::size_t i = 0; i < log.rows(); ++i) {
      out.observations.push_back({x[i], y[i], z[i], px[i], py[i], where(log, i)});
      const int g = groups.emplace(std::make_tuple(x[i], y[i], z[i]), static_cast<int>(groups.size())).first->second;
      obs.push_back({px[i], Censoring::none, where(log, i), 2 * g});
      obs.push_back({py[i], Censoring::none, where(log, i), 2 * g + 1});
    }
  }
  const s::CameraCoefficients plugin = s::plugin_camera();
  if (out.observations.size() < 2) {
    out.result.message = "too few camera observations (" + std::to_string(out.observations.size()) +
                         ") for 3 parameters and their noise";
    return out;
  }
  const double fov = s::rad_to_deg(plugin.horizontal_fov_rad);
  const double inf = std::numeric_limits<double>::infinity();
  // The field of view lies within (0, 180) degrees.
  out.result = fit_robust(CameraModel{out.observations}, obs,
                          {{"fov_deg", fov, fov, 1e-3, 179.9},
                           {"cx_px", plugin.cx_px, plugin.cx_px, -inf, inf},
                           {"cy_px", plugin.cy_px, plugin.cy_px, -inf, inf}},
                          robust_options(options, kQuantisationSd));
  collect(out.warnings, "", out.result.warnings);

  std::vector<double> r, alphas;
  for (const auto& o : out.observations) {
    double mx, my;
    s::camera_projection(plugin.horizontal_fov_rad, plugin.cx_px, plugin.cy_px, s::kCameraWidth_px, o.forward_m,
                         o.lateral_m, o.vertical_m, &mx, &my);
    r.push_back(o.px - mx);
    r.push_back(o.py - my);
    const double offset = o.px - s::kCameraWidth_px / 2.0;
    if (std::abs(offset) > s::kCameraWidth_px / 4.0 && o.lateral_m != 0.0)
      alphas.push_back(s::rad_to_deg(s::alpha_from_pixel_offset_rad(o.forward_m, o.lateral_m, offset)));
  }
  out.plugin_mse = mse_of(r);
  out.table4_points = alphas.size();
  if (!alphas.empty()) {
    const double mean = std::accumulate(alphas.begin(), alphas.end(), 0.0) / static_cast<double>(alphas.size());
    double ss = 0;
    for (double a : alphas) ss += (a - mean) * (a - mean);
    out.table4_alpha_mean_deg = mean;
    out.table4_alpha_sd_deg = alphas.size() > 1 ? std::sqrt(ss / static_cast<double>(alphas.size() - 1)) : 0.0;
  }

  // The reading noise: the frames of each LED position, px and py each their own group, pooled.
  // Blobs have no rail (a blob off the image is not seen). The plug-in's camera draws no noise:
  // no ARGoS scale.
  std::vector<double> nv;
  std::vector<int> ng, ns;
  std::vector<bool> nr;
  Groups<std::tuple<std::size_t, double, double, double, int>> frames;
  for (std::size_t l = 0; l < logs.size(); ++l) {
    const auto& x = logs[l].col("forward_m");
    const auto& y = logs[l].col("lateral_m");
    const auto& z = logs[l].col("vertical_m");
    const auto& px = logs[l].col("px");
    const auto& py = logs[l].col("py");
    for (std::size_t i = 0; i < logs[l].rows(); ++i)
      for (int axis = 0; axis < 2; ++axis) {
        nv.push_back(axis == 0 ? px[i] : py[i]);
        ng.push_back(frames.of({l, x[i], y[i], z[i], axis}));
        ns.push_back(0);
        nr.push_back(false);
      }
  }
  out.noise = replicates_or_residuals(noise_from_replicates("camera", "px", 0.0, nv, ng, nr, ns, 0, kQuantisationSd),
                                      noise_from_residuals("camera", "px", 0.0, out.result));
  return out;
}

// ================================================================================================
// Drive
// ================================================================================================

DriveRun drive_run_from_log(const logs::Log& log) {
  DriveRun run;
  run.path = log.path;
  run.obstacle_distance_m = log.metadata_number("obstacle_distance_m");
  const auto& t = log.col("time_s");
  const auto& vl = log.col("left_speed_cm_s");
  const auto& vr = log.col("right_speed_cm_s");
  const auto& sl = log.col("left_steps");
  const auto& sr = log.col("right_steps");
  const auto& tof = log.col("tof_mm");
  const std::vector<double> ul = s::unwrap_steps(sl), ur = s::unwrap_steps(sr);
  const double cap = kFirmwareSpeedLimit_m_s;
  for (std::size_t i = 0; i < log.rows(); ++i) {
    run.time_s.push_back(t[i]);
    run.line.push_back(log.line_of_row.at(i));
    // The firmware runs a wheel commanded above its limit at the limit.
    const double l = std::clamp(vl[i] / 100.0, -cap, cap), r = std::clamp(vr[i] / 100.0, -cap, cap);
    if (l != vl[i] / 100.0 || r != vr[i] / 100.0) {
      run.over_speed_limit = true;
      ++run.capped_rows;
    }
    run.command_m_s.push_back(0.5 * (l + r));
    run.command_uncapped_m_s.push_back(0.5 * (vl[i] + vr[i]) / 100.0);
    run.steps.push_back(0.5 * (ul[i] + ur[i]));
    run.tof_mm.push_back(tof[i]);
  }
  return run;
}

namespace {
// Encoder steps against the commanded distance: the register's mean after that travel
// (lib/models encoder_mean_steps: steps_per_m x - 1/2, the mean of floor(steps_per_m x)).
struct StepsLine {
  std::vector<double> distance_m;
  template <typename T>
  bool operator()(const T* p, T* out) const {
    for (std::size_t i = 0; i < distance_m.size(); ++i) out[i] = s::encoder_mean_steps(p[0], distance_m[i]);
    return true;
  }
};

// The ToF of every row of every run: latent = scale 1000 (D - g) + offset, g the encoders'
// wheel travel lagged by tau (lagged_travel_m); p = {tof_offset_mm, tof_scale, slip_time_constant_s}.
struct TofModel {
  const std::vector<DriveRun>* runs;
  double steps_per_m;
  template <typename T>
  bool operator()(const T* p, T* out) const {
    std::size_t i = 0;
    for (const DriveRun& run : *runs) {
      const std::vector<T> travel = lagged_travel_m(run, steps_per_m, p[2]);
      for (std::size_t k = 0; k < run.time_s.size(); ++k)
        out[i++] = s::tof_response_mm(p[1], p[0], T(run.obstacle_distance_m) - travel[k]);
    }
    return true;
  }
};
}  // namespace

DriveFit fit_drive(const std::vector<logs::Log>& logs, const SensorFitOptions& options) {
  DriveFit out;
  for (const logs::Log& log : logs) {
    out.runs.push_back(drive_run_from_log(log));
    if (out.runs.back().over_speed_limit) out.over_limit_runs.push_back(log.path);
    out.capped_rows += out.runs.back().capped_rows;
  }
  const double nominal = s::kPluginStepsPerMetre;

  // 1. Steps per metre: encoder steps against the commanded distance (a command holds until the
  //    next row), commands above the firmware's limit taken as the limit -- unless the encoders
  //    say the wheels ran faster (the cap tested by the BIC, DriveFit::cap_kept).
  std::vector<double> x, x_uncapped;
  std::vector<Observation> obs;
  std::vector<int> run_of;  // per row: its run (the residuals' series)
  for (const DriveRun& run : out.runs) {
    double commanded_m = 0, uncapped_m = 0;
    for (std::size_t k = 0; k < run.time_s.size(); ++k) {
      run_of.push_back(static_cast<int>(&run - out.runs.data()));
      x.push_back(commanded_m);
      x_uncapped.push_back(uncapped_m);
      obs.push_back({run.steps[k], Censoring::none, run.path + ":" + std::to_string(run.line[k]), -1});
      if (k + 1 < run.time_s.size()) {
        commanded_m += run.command_m_s[k] * (run.time_s[k + 1] - run.time_s[k]);
        uncapped_m += run.command_uncapped_m_s[k] * (run.time_s[k + 1] - run.time_s[k]);
      }
    }
  }
  out.steps_rows = x.size();
  // Within +-20 % of the nominal 41 mm wheel; steps are whole numbers.
  const std::vector<fit::Parameter> steps_params{{"steps_per_m", nominal, nominal, 0.8 * nominal, 1.2 * nominal}};
  out.steps = fit_robust(StepsLine{x}, obs, steps_params, robust_options(options, kQuantisationSd));
  if (out.capped_rows > 0) {
    RobustFit uncapped = fit_robust(StepsLine{x_uncapped}, obs, steps_params, robust_options(options, kQuantisationSd));
    // Each model's BIC over every row (the same rows, one parameter each): n ln(RSS/n) + ln n.
    auto bic = [&](const RobustFit& f, const std::vector<double>& d) {
      if (!f.usable) return std::numeric_limits<double>::infinity();
      const double k = f.value("steps_per_m");
      double rss = 0;
      for (std::size_t i = 0; i < d.size(); ++i) {
        const double r = obs[i].value - s::encoder_mean_steps(k, d[i]);
        rss += r * r;
      }
      const double n = static_cast<double>(d.size());
      return n * std::log(std::max(rss, 1e-300) / n) + std::log(n);
    };
    out.cap_tested = true;
    out.bic_capped = bic(out.steps, x);
    out.bic_uncapped = bic(uncapped, x_uncapped);
    if (out.bic_uncapped <= out.bic_capped - kCapBicMargin) {
      out.cap_kept = false;
      out.steps = std::move(uncapped);
      for (DriveRun& run : out.runs) run.command_m_s = run.command_uncapped_m_s;
    }
  }
  collect(out.warnings, "steps per metre: ", out.steps.warnings);
  if (out.steps.usable) out.steps_autocorrelation = run_autocorrelation(out.steps, obs, run_of);
  const double steps_per_m = out.steps.usable ? out.steps.value("steps_per_m") : nominal;

  // 2. ToF offset and scale with the slip lag, from every row of every run: readings at the
  //    sensor's floor (20 mm) or ceiling (2000 mm, and the out-of-range codes >= 8190) censored.
  std::vector<Observation> tobs;
  std::vector<double> plugin_r;
  for (const DriveRun& run : out.runs) {
    const std::vector<double> enc_travel = lagged_travel_m(run, nominal, 0.0);
    for (std::size_t k = 0; k < run.time_s.size(); ++k) {
      const double mm = run.tof_mm[k];
      const TofReading read = read_tof(mm);  // as the diagnosis reads it
      Observation o = read.observation;
      o.where = run.path + ":" + std::to_string(run.line[k]);
      if (read.no_target_code) ++out.tof_out_of_range_codes;
      if (o.censoring == Censoring::none)
        plugin_r.push_back(mm - s::tof_response_mm(1.0, 0.0, run.obstacle_distance_m - enc_travel[k]));  // the plug-in's
      if (o.censoring != Censoring::none) ++out.tof_censored;
      tobs.push_back(o);
    }
  }
  out.tof_rows = tobs.size();
  out.plugin_tof_mse = mse_of(plugin_r);
  // Scale within a factor of two of a true range; the lag between none and 2 s. Declared order
  // decides what a log that cannot tell them apart keeps: the scale and the lag before the offset.
  out.tof = fit_robust(TofModel{&out.runs, steps_per_m}, tobs,
                       {{"tof_offset_mm", 0.0, s::kPluginTof.offset_mm, -500.0, 500.0},
                        {models::effects::file_key(models::effects::drive_catalogue(), models::effects::drive::tof_scale), 1.0, s::kPluginTof.scale, 0.5, 2.0},
                        {"slip_time_constant_s", 0.05, 0.0, 0.0, 2.0}},
                       robust_options(options, kQuantisationSd));
  collect(out.warnings, "ToF: ", out.tof.warnings);
  if (out.tof.usable) out.tof_autocorrelation = run_autocorrelation(out.tof, tobs, run_of);
  if (!out.over_limit_runs.empty() && out.cap_kept)
    out.warnings.push_back(std::to_string(out.capped_rows) + " rows command more than the firmware's limit (" +
                           fmt(kFirmwareSpeedLimit_m_s * 100) + " cm/s): taken as the limit, which is what the robot does (the " +
                           "encoders agree: BIC " + fmt(out.bic_capped) + " with the cap, " + fmt(out.bic_uncapped) + " without).");
  if (!out.cap_kept)
    out.warnings.push_back(std::to_string(out.capped_rows) + " rows command more than the firmware's limit (" +
                           fmt(kFirmwareSpeedLimit_m_s * 100) + " cm/s), and the encoders say the wheels ran faster: BIC " +
                           fmt(out.bic_uncapped) + " as commanded against " + fmt(out.bic_capped) +
                           " with the cap; the wheels exceed the firmware's limit and are fitted as they run.");

  // 3. The reading noise. ToF: the readings of each run while the robot stands still before it
  //    first moves (no command yet, the encoders unchanged) are replicates: the body has not moved
  //    (after a move it may still be settling, see the slip lag). With fewer than
  //    kMinStillReadings of them, the ToF fit's residuals. Encoders: the steps fit's residuals.
  {
    std::vector<double> nv;
    std::vector<int> ng, ns;
    std::vector<bool> nr;
    for (std::size_t r = 0; r < out.runs.size(); ++r) {
      const DriveRun& run = out.runs[r];
      for (std::size_t k = 0; k < run.time_s.size(); ++k) {
        if (run.command_m_s[k] != 0.0 || run.steps[k] != run.steps[0]) break;
        nv.push_back(run.tof_mm[k]);
        ng.push_back(static_cast<int>(r));
        ns.push_back(0);
        nr.push_back(run.tof_mm[k] <= s::kPluginTof.min_mm || run.tof_mm[k] >= s::kPluginTof.max_mm);
      }
    }
    out.tof_noise = noise_from_replicates("tof", "mm", kArgosNoiseScaleTof_mm, nv, ng, nr, ns, 0, kQuantisationSd);
    if (!(out.tof_noise.n >= kMinStillReadings) || !std::isfinite(out.tof_noise.sd))
      out.tof_noise = noise_from_residuals("tof", "mm", kArgosNoiseScaleTof_mm, out.tof);
    out.encoder_noise = noise_from_residuals("encoder", "steps", kArgosNoiseScaleEncoder_steps, out.steps);
  }
  return out;
}

}  // namespace epuck2::calibrate
