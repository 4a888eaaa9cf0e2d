#include "epuck2/calibrate/report_json.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <map>

#include "epuck2/calibrate/no_usable_fit.hpp"

namespace epuck2::calibrate {

using nlohmann::json;

json json_number(double v) { return std::isfinite(v) ? json(v) : json(nullptr); }

json statistics_json(const fit::FitStatistics& s, const std::string& rss_unit) {
  json j{{"n", s.n},
         {"free_parameters", s.k},
         {"rss", json_number(s.rss)},
         {"mse", json_number(s.mse)},
         {"reduced_chi2", json_number(s.reduced_chi2)},
         {"r2", json_number(s.r2)},
         {"aic", json_number(s.aic)},
         {"bic", json_number(s.bic)},
         {"rss_unit", rss_unit}};
  if (!std::isfinite(s.r2)) j["r2_why"] = "the data do not vary: there is no variance to explain";
  if (!std::isfinite(s.reduced_chi2)) j["reduced_chi2_why"] = "no degree of freedom left (n <= k)";
  if (!std::isfinite(s.aic)) j["aic_why"] = s.n == 0 ? "no residual" : fit::kInformationCriteriaUndefined;
  if (!std::isfinite(s.bic)) j["bic_why"] = s.n == 0 ? "no residual" : fit::kInformationCriteriaUndefined;
  return j;
}

json statistics_conventions_json(const char* n_convention) {
  return {{"n", n_convention},
          {"reduced_chi2", fit::kReducedChi2Convention},
          {"aic", fit::kAicConvention},
          {"bic", fit::kBicConvention},
          {"correlations", "pairs with |r| > 0.1 (lmfit), r = cov(a, b) / (se_a se_b)"}};
}

json correlations_json(const std::vector<fit::Correlation>& c, const std::string& prefix) {
  json a = json::array();
  for (const auto& x : c) a.push_back({{"a", prefix + x.a}, {"b", prefix + x.b}, {"r", json_number(x.r)}});
  return a;
}

json autocorrelation_json(const fit::AutocorrelationCorrection& a) {
  json j{{"computed", a.computed}, {"method", a.method.empty() ? std::string(fit::kAutocorrelationMethod) : a.method},
         {"cluster_robust", a.cluster_robust}};
  if (a.computed) {
    j["rho"] = json_number(a.rho);
    j["n"] = a.n;
    j["n_eff"] = json_number(a.n_eff);
    j["factor"] = json_number(a.factor);
  } else {
    j["why"] = a.why_not;
  }
  j["series"] = a.series;
  if (!a.cluster_robust) j["cluster_robust_why_not"] = a.cluster_why_not;
  return j;
}

fit::FitStatistics robust_statistics(const fit::RobustFit& r) {
  return fit::fit_statistics(r.kept_exact, r.free_parameters, r.rss, r.r2);
}

// ----- the sensor coefficient file's shape --------------------------------------------------

std::vector<std::string> robots_of(const std::vector<logs::Log>& all) {
  std::vector<std::string> names;
  for (const auto& l : all)
    if (std::find(names.begin(), names.end(), l.robot) == names.end()) names.push_back(l.robot);
  return names;
}

json skeleton(const json& model, const std::vector<logs::Log>& logs) {
  std::vector<std::string> sources;
  for (const auto& l : logs) sources.push_back(l.path);
  json j = model;
  j["std_errors"] = json::object();
  j["sources"] = sources;
  return j;
}

json owned_model(const std::function<json()>& write) {
  try {
    return write();
  } catch (const std::domain_error& e) {
    throw NoUsableFit(std::string("the fitted model cannot be written: ") + e.what());
  }
}

coefficients::CalibrationExtras measured_noise(const std::vector<ReadingNoise>& channels) {
  coefficients::CalibrationExtras x;
  for (const auto& c : channels) {
    if (!c.usable())
      throw NoUsableFit(c.channel + " reading noise: no reading to measure it from (" +
                        (c.from == "replicates" ? "no group of two or more readings under the same conditions inside the rails"
                                                : "the fit it comes from is not usable") +
                        ")");
    x.pooled_sd[c.channel] = c.sd;
  }
  return x;
}

void append(json& j, const std::string& key, const json& v) {
  if (!j.contains(key)) j[key] = json::array();
  j[key].push_back(v);
}

json fit_details(const fit::RobustFit& r, const std::string& rss_unit,
                 const fit::AutocorrelationCorrection* autocorrelation) {
  json d = statistics_json(robust_statistics(r), rss_unit);
  d["method"] = r.method;
  d["observations"] = r.observations;
  d["inside_rails"] = r.exact;
  d["censored"] = {{"at_or_below", r.censored_below}, {"at_or_above", r.censored_above}};
  d["censored_kept"] = {{"at_or_below", r.kept_censored_below}, {"at_or_above", r.kept_censored_above}};
  d["outliers"] = r.outliers.size();
  d["noise_sd"] = json_number(r.noise_sd);
  if (!std::isfinite(r.r2)) d["r2_why"] = "the readings inside the rails do not vary: there is no variance to explain";
  d["log_likelihood"] = json_number(r.log_likelihood);
  d["aic_likelihood"] = json_number(r.aic);
  d["bic_likelihood"] = json_number(r.bic);
  d["correlations"] = correlations_json(fit::correlations(r));
  if (autocorrelation != nullptr) d["autocorrelation"] = autocorrelation_json(*autocorrelation);
  if (r.lack_of_fit.tested)
    d["lack_of_fit"] = {{"reduced_chi2", json_number(r.lack_of_fit.reduced_chi2)}, {"p_value", json_number(r.lack_of_fit.p_value)},
                        {"replicate_sd", json_number(r.lack_of_fit.replicate_sd)}, {"groups", r.lack_of_fit.groups},
                        {"dof_lack", r.lack_of_fit.dof_lack}, {"dof_pure", r.lack_of_fit.dof_pure},
                        {"misfit_rms", json_number(r.lack_of_fit.misfit_rms)}, {"misfit_ratio", json_number(r.lack_of_fit.misfit_ratio)},
                        {"worst", r.lack_of_fit.worst}, {"robots", r.lack_of_fit.robots}};
  else
    d["lack_of_fit"] = {{"tested", false}, {"why", r.lack_of_fit.why_not}};
  return d;
}

void add_aggregates(json& j, const fit::RobustFit& r, const std::string& key, const std::string& prefix,
                    const std::string& rss_unit, const fit::AutocorrelationCorrection* autocorrelation) {
  for (const auto& n : r.not_identifiable) append(j, "not_identifiable", prefix + n);
  j["fits"][key] = fit_details(r, rss_unit, autocorrelation);
  if (!j.contains("statistics_conventions")) j["statistics_conventions"] = statistics_conventions_json();
  if (!j.contains("correlations")) j["correlations"] = json::array();
  for (const auto& c : correlations_json(fit::correlations(r), prefix)) j["correlations"].push_back(c);
  // Only the parameters with a standard error to correct (the others' reasons: std_error_why).
  if (autocorrelation != nullptr)
    for (const auto& p : r.parameters)
      if (std::isfinite(autocorrelation->std_error(p.name)))
        j["std_errors_corrected"][prefix + p.name] = autocorrelation->std_error(p.name);
  j["censored"] = j.value("censored", std::size_t{0}) + r.censored();
  if (!j.contains("outliers")) j["outliers"] = {{"count", 0}, {"rows", json::array()}};
  j["outliers"]["count"] = j["outliers"]["count"].get<std::size_t>() + r.outlier_where.size();
  for (const auto& w : r.outlier_where) j["outliers"]["rows"].push_back(w);
  if (r.lack_of_fit.tested) j["lack_of_fit"][key] = j["fits"][key]["lack_of_fit"];
}

std::string std_error_reason(const fit::RobustFit& r, const std::string& name) {
  const auto why = r.std_error_why.find(name);
  if (why != r.std_error_why.end()) return why->second;
  for (const auto& p : r.parameters)
    if (p.name == name && !p.std_error_why.empty()) return p.std_error_why;
  return "the covariance could not be computed";
}

std::string unit_of(const json& j, const std::string& name) {
  if (!j.contains("units")) return "";
  const std::string base = name.substr(0, name.find('['));  // gain[0]: the unit of gain
  for (const std::string& key : {name, base})
    if (j["units"].contains(key) && j["units"][key].is_string()) return j["units"][key].get<std::string>();
  return "";
}

void add_rounded(json& j, const std::string& name, double value, double std_error, const std::string& why) {
  const std::string unit = unit_of(j, name);
  j["rounded"][name] = fit::format_uncertain(value, std_error, unit == "1" ? "" : unit, why);  // a ratio: no unit
}

void add_estimates(json& j, const fit::RobustFit& r, const std::string& prefix,
                   const std::string& key, const std::string& rss_unit,
                   const fit::AutocorrelationCorrection* autocorrelation) {
  for (const auto& p : r.parameters) {
    j["std_errors"][prefix + p.name] = json_number(p.std_error);
    const bool has_error = std::isfinite(p.std_error) && p.std_error > 0;
    if (!std::isfinite(p.std_error)) j["std_error_why"][prefix + p.name] = std_error_reason(r, p.name);
    add_rounded(j, prefix + p.name, p.value, p.std_error,
                has_error ? "" : std::isfinite(p.std_error) ? "held fixed" : std_error_reason(r, p.name));
  }
  add_aggregates(j, r, key, prefix, rss_unit, autocorrelation);
}

void add_left_out(json& j, const std::vector<LeftOut>& rows) {
  if (!j.contains("outliers")) j["outliers"] = {{"count", 0}, {"rows", json::array()}};
  json list = json::array();
  for (const auto& r : rows) {
    list.push_back({{"where", r.where}, {"why", r.why}});
    if (r.why.rfind("wild", 0) == 0) {
      j["outliers"]["count"] = j["outliers"]["count"].get<std::size_t>() + 1;
      j["outliers"]["rows"].push_back(r.where);
    }
  }
  j["left_out"] = {{"count", rows.size()}, {"rows", list}};
}

void add_noise(json& j, const std::vector<ReadingNoise>& channels) {
  (void)measured_noise(channels);  // each channel measured
  for (const auto& c : channels) {
    // sd, per_sensor_sd and unit: the owner's, from the model (skeleton).
    json& e = j.at("noise").at(c.channel);
    e["from"] = c.from;
    e["n"] = c.n;
    if (c.from == "replicates") e["groups"] = c.groups;
    if (!c.per_sensor_sd.empty()) e["per_sensor_n"] = c.per_sensor_n;
    if (c.argos_scale > 0) e["argos_uniform_level"] = c.argos_uniform_level();
  }
}

void add_warnings(json& j, const std::vector<std::string>& warnings) {
  if (!j.contains("warnings")) j["warnings"] = json::array();
  for (const auto& w : warnings) j["warnings"].push_back(w);
}

std::vector<fit::ParameterEstimate> named_estimates(const fit::FitResult& r, const std::string& prefix, const std::string& suffix) {
  std::vector<fit::ParameterEstimate> out = r.parameters;
  for (auto& p : out) p.name = prefix + p.name + suffix;
  return out;
}

namespace {
std::string strip_period(std::string s) {
  while (!s.empty() && (s.back() == '.' || s.back() == ' ')) s.pop_back();
  return s;
}
}  // namespace

void add_robots(json& j, const std::vector<logs::Log>& all,
                const std::function<RobotCalibration(const std::vector<logs::Log>&)>& fit_logs) {
  const std::vector<std::string> names = robots_of(all);
  if (names.size() < 2) return;
  const std::string kind = j.at("kind").get<std::string>();
  std::vector<fit::FitResult> fits;  // one per usable robot: its fitted parameters, as named in the file
  std::vector<std::pair<std::string, std::string>> unfitted;  // a robot without a set of its own, and why
  for (const auto& name : names) {
    std::vector<logs::Log> mine;
    std::vector<std::string> files;
    for (const auto& l : all)
      if (l.robot == name) {
        mine.push_back(l);
        files.push_back(l.path);
      }
    RobotCalibration r;
    try {
      r = fit_logs(mine);
    } catch (const NoUsableFit& e) {
      coefficients::add_robot_set(j, kind, name, {{"logs", files}, {"usable", false}, {"why", e.what()}});
      unfitted.emplace_back(name, e.what());
      continue;
    }
    // The robot's model sections as the owner wrote them for its file; its report beside them.
    json set = {{"logs", files}, {"usable", true}, {"parameters", r.file.at("parameters")}, {"std_errors", r.file.at("std_errors")}};
    if (r.file.contains("noise")) set["noise"] = r.file.at("noise");
    // Light: the robot's own per-sensor gammas, fitted to its rows (the pooled file's are the
    // pool's, and describe no robot).
    if (r.file.contains("per_sensor")) set["per_sensor"] = r.file.at("per_sensor");
    if (r.file.contains("not_identifiable")) set["not_identifiable"] = r.file.at("not_identifiable");
    try {
      coefficients::add_robot_set(j, kind, name, set);
    } catch (const std::domain_error& e) {
      // A robot's set that no reader would take is not written: the robot has no usable set.
      coefficients::add_robot_set(j, kind, name, {{"logs", files}, {"usable", false}, {"why", e.what()}});
      unfitted.emplace_back(name, e.what());
      continue;
    }
    fits.emplace_back();
    fits.back().usable = true;
    fits.back().parameters = std::move(r.estimates);
  }
  // A robot without a set of its own is said (its logs still count in the pooled fit), and so is
  // a comparison that cannot be made.
  for (const auto& [name, why] : unfitted) {
    std::string what = strip_period(why);
    append(j, "warnings",
           "robot " + name + " has no set of its own (" + what + "): its logs count only in the pooled fit, and " +
               (fits.size() < 2 ? "the robots were not compared (" + std::to_string(fits.size()) + " of " +
                                      std::to_string(names.size()) + " robots have a set of their own)."
                                : "it is left out of the robots' comparison."));
  }
  // Every parameter any robot's fit has, by name (the file's order: alphabetical), compared over the
  // robots whose fit has it with a standard error.
  std::map<std::string, std::vector<fit::ParameterEstimate>> by_parameter;
  for (const fit::FitResult& f : fits)
    for (const auto& p : f.parameters) by_parameter[p.name].push_back(p);
  json spread = json::array();
  for (const auto& [name, values] : by_parameter) {
    std::vector<fit::FitResult> one(values.size());
    std::vector<const fit::FitResult*> ptrs;
    for (std::size_t i = 0; i < values.size(); ++i) {
      one[i].usable = true;
      one[i].parameters = {values[i]};
      ptrs.push_back(&one[i]);
    }
    for (const fit::RobotSpread& s : fit::robot_spread(ptrs)) {
      spread.push_back({{"parameter", name}, {"spread_sd", json_number(s.spread_sd)}, {"q", json_number(s.q)}, {"dof", s.dof},
                        {"p_value", json_number(s.p_value)}, {"exceeds_uncertainty", s.exceeds}});
      if (s.exceeds) {
        char buf[300];
        std::snprintf(buf, sizeof buf,
                      "the robots differ in %s beyond their own uncertainties (sd between robots %.4g, Q = %.3g, p = %.2g): "
                      "the pooled value describes no robot; use `robots` or --robot ID.",
                      name.c_str(), s.spread_sd, s.q, s.p_value);
        append(j, "warnings", std::string(buf));
      }
    }
  }
  j["robot_spread"] = spread;
}

}  // namespace epuck2::calibrate
